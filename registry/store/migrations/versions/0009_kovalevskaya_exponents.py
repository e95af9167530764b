"""Kovalevskaya exponents recorded with the case: ``registry exponents --record`` and the
survey store each analysis of a case version (its balances, exponents, Yoshida's degrees,
the Painlevé test and the statement, as the JSON document of docs/json-output.md) in the
new table ``exponents``, one row per analysis, never overwritten. Nothing stored before
changes.

Revision ID: 0009
Revises: 0008
"""

import sqlalchemy as sa
from alembic import op

revision = "0009"
down_revision = "0008"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "exponents",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("case_pk", sa.Integer(), sa.ForeignKey("cases.id"), nullable=False),
        sa.Column("options", sa.JSON(), nullable=False),
        sa.Column("options_key", sa.Text(), nullable=False),
        sa.Column("code_version", sa.Text(), nullable=False),
        sa.Column("started_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("seconds", sa.Float(), nullable=False),
        sa.Column("decided", sa.Boolean(), nullable=False),
        sa.Column("homogeneous", sa.Boolean(), nullable=False),
        sa.Column("all_integer", sa.Boolean(), nullable=False),
        sa.Column("all_rational", sa.Boolean(), nullable=False),
        sa.Column("passes", sa.Boolean(), nullable=False),
        sa.Column("degrees", sa.JSON(), nullable=False),
        sa.Column("balances", sa.Integer(), nullable=False),
        sa.Column("statement", sa.Text(), nullable=False),
        sa.Column("document", sa.JSON(), nullable=False),
    )
    op.create_index("ix_exponents_case_pk", "exponents", ["case_pk"])
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="9"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
