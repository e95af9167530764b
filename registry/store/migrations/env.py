"""Alembic environment: migrations run on the connection ``registry.migrate`` hands over,
inside its write transaction, with batch mode so that SQLite can alter tables."""

from alembic import context

from registry.store.tables import Base

context.configure(
    connection=context.config.attributes["connection"],
    target_metadata=Base.metadata,
    render_as_batch=True,
)
with context.begin_transaction():
    context.run_migrations()
