"""Systems on any phase space, what a verified check adds, and drift curves as data.

* ``cases.form``: the fields of a system given on a state of its own, as written
  (``variables``, ``equations``, ``bracket`` entries, ``definitions``); NULL for the
  reference paper's forms without definitions, which every row stored before this
  revision is (those forms did not exist).
* ``check_results.detail``: what a verified check adds for people (a relation's
  cofactor); "" for every earlier row.
* ``drift_curves``: the trajectory the audit integrates for a refuted claim (times, the
  changes of I and of H), stored with its run so that a report draws it without
  integrating anything.

Revision ID: 0008
Revises: 0007
"""

import sqlalchemy as sa
from alembic import op

revision = "0008"
down_revision = "0007"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column("cases", sa.Column("form", sa.JSON(none_as_null=True), nullable=True))
    op.add_column(
        "check_results", sa.Column("detail", sa.Text(), nullable=False, server_default="")
    )
    op.create_table(
        "drift_curves",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("run_id", sa.Integer(), sa.ForeignKey("audit_runs.id"), nullable=False),
        sa.Column("case_pk", sa.Integer(), sa.ForeignKey("cases.id"), nullable=False),
        sa.Column("claim_id", sa.Integer(), sa.ForeignKey("claims.id"), nullable=False),
        sa.Column("t", sa.JSON(), nullable=False),
        sa.Column("di", sa.JSON(), nullable=False),
        sa.Column("dh", sa.JSON(), nullable=False),
    )
    op.create_index("ix_drift_curves_run_id", "drift_curves", ["run_id"])
    op.create_index("ix_drift_curves_case_pk", "drift_curves", ["case_pk"])
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="8"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
