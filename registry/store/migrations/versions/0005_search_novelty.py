"""Searches say which integrals they found are new and which are the case's own claims
again: ``discoveries.status`` holds, per integral, ``new`` or ``rediscovered`` with the
claims it equals, the known integrals it is taken modulo and the identity;
``searches.claims`` the claims proven integrals and counted as known, and
``searches.claims_complete`` whether they span every integral of the ansatz beyond
the known ones. Searches stored before this revision decided none of it: their rows
get an empty list and false.

Revision ID: 0005
Revises: 0004
"""

import sqlalchemy as sa
from alembic import op

revision = "0005"
down_revision = "0004"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column(
        "discoveries", sa.Column("status", sa.JSON(), nullable=False, server_default="[]")
    )
    op.add_column("searches", sa.Column("claims", sa.JSON(), nullable=False, server_default="[]"))
    op.add_column(
        "searches",
        sa.Column("claims_complete", sa.Boolean(), nullable=False, server_default=sa.false()),
    )
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="5"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
