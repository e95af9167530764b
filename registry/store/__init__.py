"""The store: the registry database (SQLAlchemy): its tables, the conversion of rows to
and from domain objects, the engine and its errors, the store's reads and writes,
DataFrame queries, schema migrations and ``registry verify-db``.

The database never does algebra: it imports the domain model and the case language,
never the mathematics, the audit or the presentation (``tests/test_layers.py``). A new
storage backend is one more engine here.
"""
