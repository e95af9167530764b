"""The Painlevé test's third verdict: ``exponents.passes`` may be NULL, where the test was
not made (an undecided analysis, or integer exponents whose Laurent series was not
computed: a family's generic members with several parameters). Before, such rows held
false, which read as "fails". Each stored analysis's column is read again from its own
document; nothing else changes.

Revision ID: 0012
Revises: 0011
"""

import sqlalchemy as sa
from alembic import op

revision = "0012"
down_revision = "0011"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("exponents") as batch:
        batch.alter_column("passes", existing_type=sa.Boolean(), nullable=True)
    exponents = sa.table(
        "exponents",
        sa.column("id", sa.Integer()),
        sa.column("decided", sa.Boolean()),
        sa.column("passes", sa.Boolean()),
        sa.column("document", sa.JSON()),
    )
    conn = op.get_bind()
    rows = conn.execute(sa.select(exponents.c.id, exponents.c.decided, exponents.c.document))
    not_made = [
        row.id
        for row in rows
        if not row.decided or (row.document.get("painleve") or {}).get("passes") is None
    ]
    if not_made:
        op.execute(exponents.update().where(exponents.c.id.in_(not_made)).values(passes=None))
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="12"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
