"""Numeric evidence on a level set records how far its trajectories left the set:
``evidence.departure`` (the largest relative residual of the set's equations where the
drift was measured; NULL for a claim without a level set), ``evidence.projected``
(whether the trajectories were projected back onto the set after each step) and
``evidence.reason`` (why the drift was not compared with the verdict, if it was not).
Evidence stored before this revision was never projected and always compared: its rows
get NULL, false and "".

Revision ID: 0006
Revises: 0005
"""

import sqlalchemy as sa
from alembic import op

revision = "0006"
down_revision = "0005"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column("evidence", sa.Column("departure", sa.Float(), nullable=True))
    op.add_column(
        "evidence",
        sa.Column("projected", sa.Boolean(), nullable=False, server_default=sa.false()),
    )
    op.add_column("evidence", sa.Column("reason", sa.Text(), nullable=False, server_default=""))
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="6"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
