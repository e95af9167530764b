"""Identification with the catalog (issue 33): ``discoveries.same_as`` holds, for each
set of values a search found integrals on, the catalog cases it is the same system as
(case id, parameter values, transformation, the claims its integrals equal), as JSON;
"[]" for every earlier row (they were not identified). Nothing else changes.

Revision ID: 0010
Revises: 0009
"""

import sqlalchemy as sa
from alembic import op

revision = "0010"
down_revision = "0009"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column(
        "discoveries", sa.Column("same_as", sa.JSON(), nullable=False, server_default="[]")
    )
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="10"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
