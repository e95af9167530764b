"""Running work elsewhere: the only room of the package that starts processes.

The number of jobs, the one loop a child serves calls with, parent-death handling,
killable local workers, the child interpreters of Dask tasks, mapping with a grace period
and results back in order, and time budgets. The audit, the discovery and the survey
use it and own no process code (``tests/test_layers.py``). Builds on the model and the
errors only.
"""
