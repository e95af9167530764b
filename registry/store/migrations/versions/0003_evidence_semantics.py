"""Numeric evidence records which symbolic verdict it was compared with and whether it
stands on a smaller set than the claim's; derived facts carry a verdict of the one
vocabulary (verified, refuted, inconclusive, error) or none.

Evidence stored before this revision was compared with the verdict of the check its
claim's kind names, so those rows get that kind as ``compared_with``; the markers
``unverified`` and ``""`` of the corrections table become ``inconclusive`` and NULL.

Revision ID: 0003
Revises: 0002
"""

import sqlalchemy as sa
from alembic import op

revision = "0003"
down_revision = "0002"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("evidence") as batch:
        batch.add_column(
            sa.Column("compared_with", sa.Text(), nullable=False, server_default="integral")
        )
        batch.add_column(sa.Column("narrowed", sa.Text(), nullable=False, server_default=""))
    evidence = sa.table("evidence", sa.column("claim_id"), sa.column("compared_with"))
    claims = sa.table("claims", sa.column("id"), sa.column("kind"))
    kind = sa.select(claims.c.kind).where(claims.c.id == evidence.c.claim_id).scalar_subquery()
    op.execute(evidence.update().values(compared_with=kind))

    with op.batch_alter_table("corrections") as batch:
        batch.alter_column("verdict", existing_type=sa.Text(), nullable=True)
    corrections = sa.table("corrections", sa.column("verdict", sa.Text()))
    op.execute(corrections.update().where(corrections.c.verdict == "").values(verdict=None))
    op.execute(
        corrections.update()
        .where(corrections.c.verdict == "unverified")
        .values(verdict="inconclusive")
    )
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="3"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
