"""Alembic migrations of the registry database (run through ``registry.migrate``)."""
