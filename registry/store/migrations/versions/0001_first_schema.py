"""The first released schema (registry 0.1.0): cases, claims, runs, results, corrections.

Frozen here as it was released; later revisions change it. Databases created
before migrations existed carry ``schema_version = 1`` in ``meta`` and are
stamped with this revision before they are upgraded.

Revision ID: 0001
Revises:
"""

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None

_WHEN = sa.DateTime(timezone=True)

LATEST_VERDICTS = """
CREATE VIEW latest_verdicts AS SELECT ranked."case", ranked.version, ranked.claim,
ranked."check", ranked.verdict, ranked.method, ranked.reason, ranked.residual,
ranked.witness, ranked.run, ranked.seconds, ranked.reused, ranked.result
FROM (SELECT cases.case_id AS "case", cases.version AS version, claims.label AS claim,
check_results."check" AS "check", check_results.verdict AS verdict,
check_results.method AS method, check_results.reason AS reason,
check_results.residual AS residual, check_results.witness AS witness,
check_results.run_id AS run, check_results.seconds AS seconds,
check_results.reused AS reused, check_results.id AS result,
row_number() OVER (PARTITION BY cases.case_id, claims.label, check_results."check"
ORDER BY check_results.run_id DESC, check_results.id DESC) AS rn
FROM check_results JOIN cases ON check_results.case_pk = cases.id
LEFT OUTER JOIN claims ON check_results.claim_id = claims.id
WHERE cases.version = (SELECT max(newer.version) AS max_1 FROM cases AS newer
WHERE newer.case_id = cases.case_id)) AS ranked
WHERE ranked.rn = 1
"""


def _per_run(name: str, *columns: sa.Column) -> None:
    """A table of rows belonging to one run and one case version."""
    op.create_table(
        name,
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("run_id", sa.Integer(), sa.ForeignKey("audit_runs.id"), nullable=False),
        sa.Column("case_pk", sa.Integer(), sa.ForeignKey("cases.id"), nullable=False),
        *columns,
    )
    op.create_index(f"ix_{name}_case_pk", name, ["case_pk"])
    op.create_index(f"ix_{name}_run_id", name, ["run_id"])


def upgrade() -> None:
    op.create_table(
        "meta",
        sa.Column("key", sa.Text(), primary_key=True),
        sa.Column("value", sa.Text(), nullable=False),
    )
    op.create_table(
        "sources",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("citation", sa.Text(), nullable=False),
        sa.Column("doi", sa.Text(), nullable=False),
        sa.UniqueConstraint("citation", "doi"),
    )
    op.create_table(
        "audit_runs",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("started_at", _WHEN, nullable=False),
        sa.Column("finished_at", _WHEN, nullable=True),
        sa.Column("status", sa.Text(), nullable=False),
        sa.Column("code_version", sa.Text(), nullable=False),
        sa.Column("sympy_version", sa.Text(), nullable=False),
        sa.Column("python_version", sa.Text(), nullable=False),
        sa.Column("options", sa.JSON(), nullable=False),
    )
    op.create_table(
        "cases",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("case_id", sa.Text(), nullable=False),
        sa.Column("version", sa.Integer(), nullable=False),
        sa.Column("title", sa.Text(), nullable=False),
        sa.Column("source_id", sa.Integer(), sa.ForeignKey("sources.id"), nullable=False),
        sa.Column("locator", sa.Text(), nullable=False),
        sa.Column("notes", sa.Text(), nullable=False),
        sa.Column("content_hash", sa.Text(), nullable=False),
        sa.Column("text", sa.Text(), nullable=False),
        sa.Column("path", sa.Text(), nullable=True),
        sa.Column("inertia", sa.JSON(), nullable=False),
        sa.Column("potential", sa.Text(), nullable=False),
        sa.Column("torque", sa.JSON(), nullable=False),
        sa.Column("parameters", sa.JSON(), nullable=False),
        sa.Column("functions", sa.JSON(), nullable=False),
        sa.Column("added_at", _WHEN, nullable=False),
        sa.UniqueConstraint("case_id", "version"),
    )
    op.create_table(
        "claims",
        sa.Column("id", sa.Integer(), primary_key=True),
        sa.Column("case_pk", sa.Integer(), sa.ForeignKey("cases.id"), nullable=False),
        sa.Column("position", sa.Integer(), nullable=False),
        sa.Column("label", sa.Text(), nullable=False),
        sa.Column("kind", sa.Text(), nullable=False),
        sa.Column("expression", sa.Text(), nullable=False),
        sa.Column("on", sa.JSON(), nullable=False),
        sa.Column("locator", sa.Text(), nullable=False),
        sa.UniqueConstraint("case_pk", "label"),
    )
    claim = sa.Column("claim_id", sa.Integer(), sa.ForeignKey("claims.id"), nullable=True)
    _per_run(
        "check_results",
        claim,
        sa.Column("check", sa.Text(), nullable=False),
        sa.Column("verdict", sa.Text(), nullable=False),
        sa.Column("method", sa.Text(), nullable=False),
        sa.Column("reason", sa.Text(), nullable=False),
        sa.Column("residual", sa.Text(), nullable=True),
        sa.Column("witness", sa.JSON(), nullable=True),
        sa.Column("seconds", sa.Float(), nullable=False),
        sa.Column("reused", sa.Boolean(), server_default=sa.false(), nullable=False),
    )
    _per_run(
        "corrections",
        sa.Column("claim_id", sa.Integer(), sa.ForeignKey("claims.id"), nullable=True),
        sa.Column("kind", sa.Text(), nullable=False),
        sa.Column("expression", sa.Text(), nullable=True),
        sa.Column("method", sa.Text(), nullable=False),
        sa.Column("verdict", sa.Text(), nullable=False),
        sa.Column("payload", sa.JSON(), nullable=False),
    )
    _per_run(
        "evidence",
        sa.Column("claim_id", sa.Integer(), sa.ForeignKey("claims.id"), nullable=False),
        sa.Column("drift", sa.Float(), nullable=True),
        sa.Column("floor", sa.Float(), nullable=True),
        sa.Column("runs", sa.Integer(), nullable=False),
        sa.Column("contradicts", sa.Boolean(), nullable=False),
        sa.Column("note", sa.Text(), nullable=False),
    )
    op.execute(LATEST_VERDICTS)
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.bulk_insert(meta, [{"key": "schema_version", "value": "1"}])


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
