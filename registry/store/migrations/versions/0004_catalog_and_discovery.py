"""The literature catalog and integral discovery.

Sources carry their structured citation (authors, year, title, journal or book,
volume, issue, pages, url), cases their topic and earlier ids (``case_aliases``),
claims their notes and provenance (literature or discovered); ``searches`` and
``discoveries`` record integral searches and what they found. Existing rows keep
their values; the new columns start empty.

Revision ID: 0004
Revises: 0003
"""

import sqlalchemy as sa
from alembic import op

revision = "0004"
down_revision = "0003"
branch_labels = None
depends_on = None

_WHEN = sa.DateTime(timezone=True)

_SOURCE_TEXTS = ("title", "journal", "booktitle", "publisher", "volume", "issue", "pages", "url")


def upgrade() -> None:
    # plain added columns: no table is rebuilt, so no row that others point to moves
    op.add_column("sources", sa.Column("authors", sa.JSON(), nullable=False, server_default="[]"))
    op.add_column("sources", sa.Column("year", sa.Integer(), nullable=True))
    for name in _SOURCE_TEXTS:
        op.add_column("sources", sa.Column(name, sa.Text(), nullable=False, server_default=""))
    op.add_column("cases", sa.Column("topic", sa.Text(), nullable=False, server_default=""))
    op.create_table(
        "case_aliases",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("case_pk", sa.Integer(), sa.ForeignKey("cases.id"), nullable=False),
        sa.Column("alias", sa.Text(), nullable=False),
    )
    op.create_index("ix_case_aliases_case_pk", "case_aliases", ["case_pk"])
    op.create_index("ix_case_aliases_alias", "case_aliases", ["alias"])
    op.create_table(
        "searches",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("case_pk", sa.Integer(), sa.ForeignKey("cases.id"), nullable=False),
        sa.Column("options", sa.JSON(), nullable=False),
        sa.Column("options_key", sa.Text(), nullable=False),
        sa.Column("code_version", sa.Text(), nullable=False),
        sa.Column("started_at", _WHEN, nullable=False),
        sa.Column("seconds", sa.Float(), nullable=False),
        sa.Column("complete", sa.Boolean(), nullable=False),
        sa.Column("coverage", sa.JSON(), nullable=False),
        sa.Column("known", sa.JSON(), nullable=False),
        sa.Column("dimensions", sa.JSON(), nullable=False),
        sa.Column("method", sa.Text(), nullable=False),
        sa.Column("statement", sa.Text(), nullable=False),
    )
    op.create_index("ix_searches_case_pk", "searches", ["case_pk"])
    op.create_table(
        "discoveries",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("search_id", sa.Integer(), sa.ForeignKey("searches.id"), nullable=False),
        sa.Column("position", sa.Integer(), nullable=False),
        sa.Column("when", sa.JSON(), nullable=False),
        sa.Column("extra", sa.Integer(), nullable=False),
        sa.Column("integrals", sa.JSON(), nullable=False),
        sa.Column("casimir", sa.JSON(), nullable=False),
        sa.Column("derived_case_pk", sa.Integer(), sa.ForeignKey("cases.id"), nullable=True),
    )
    op.create_index("ix_discoveries_search_id", "discoveries", ["search_id"])
    # claims.search_id names the search that attached a claim; it is checked by
    # `registry check` rather than by a foreign key, which SQLite could only add by
    # rebuilding the claims table that results point to
    op.add_column("claims", sa.Column("notes", sa.Text(), nullable=False, server_default=""))
    op.add_column(
        "claims", sa.Column("provenance", sa.Text(), nullable=False, server_default="literature")
    )
    op.add_column("claims", sa.Column("search_id", sa.Integer(), nullable=True))
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="4"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
