"""A case version records its system in both forms: ``cases.hamiltonian`` (H as the
case file gives it, NULL in the inertia form) and ``cases.kappa`` (the bracket's
parameter as written; "0", e(3), by default). Rows stored before this revision get
both from the ``[system]`` table of the case text they keep (read as TOML, nothing
evaluated): cases of revisions 0001-0003 predate the Hamiltonian form and get NULL
and "0".

Revision ID: 0007
Revises: 0006
"""

import tomllib

import sqlalchemy as sa
from alembic import op

revision = "0007"
down_revision = "0006"
branch_labels = None
depends_on = None


def _system(text: str) -> dict:
    """The ``[system]`` table of a stored case text ({} if it has none)."""
    try:
        system = tomllib.loads(text).get("system", {})
    except tomllib.TOMLDecodeError:  # verify-db names such a row; nothing to copy here
        return {}
    return system if isinstance(system, dict) else {}


def upgrade() -> None:
    op.add_column("cases", sa.Column("hamiltonian", sa.Text(), nullable=True))
    op.add_column("cases", sa.Column("kappa", sa.Text(), nullable=False, server_default="0"))
    cases = sa.table(
        "cases",
        sa.column("id", sa.Integer()),
        sa.column("text", sa.Text()),
        sa.column("hamiltonian", sa.Text()),
        sa.column("kappa", sa.Text()),
    )
    bind = op.get_bind()
    for pk, text in bind.execute(sa.select(cases.c.id, cases.c.text)).all():
        system = _system(text or "")
        hamiltonian, kappa = system.get("hamiltonian"), system.get("kappa")
        values = {}
        if isinstance(hamiltonian, str):
            values["hamiltonian"] = hamiltonian
        if isinstance(kappa, bool):  # a case the parser refuses never got stored
            pass
        elif isinstance(kappa, str):
            values["kappa"] = kappa
        elif isinstance(kappa, int | float):  # as the case parser writes a TOML number
            values["kappa"] = str(kappa) if isinstance(kappa, int) else repr(kappa)
        if values:
            bind.execute(cases.update().where(cases.c.id == pk).values(**values))
    meta = sa.table("meta", sa.column("key", sa.Text()), sa.column("value", sa.Text()))
    op.execute(meta.update().where(meta.c.key == "schema_version").values(value="7"))


def downgrade() -> None:
    raise NotImplementedError("restore the backup copy made before the upgrade")
