"""Code the test modules share (no test module imports another): sample cases and case
files, database targets and the throwaway PostgreSQL server, Dask clusters, processes
watched through /proc, independent numeric checks, parsing in a test namespace."""
