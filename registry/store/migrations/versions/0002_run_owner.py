"""Audit runs record the process running them, so that a run whose process died
(killed, power cut) is found on the next start and marked ``interrupted``.

Revision ID: 0002
Revises: 0001
"""

import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("audit_runs") as batch:
        batch.add_column(sa.Column("host", sa.Text(), nullable=True))
        batch.add_column(sa.Column("pid", sa.Integer(), nullable=True))
        # the process's start time as the kernel reports it: tells a live run from
        # a dead one whose pid has been reused
        batch.add_column(sa.Column("pid_started", sa.Text(), nullable=True))
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="2"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
