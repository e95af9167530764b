"""A registry with a row in every table, built from code, and every row of a registry
read as data: for the tests of copying (``tests/store/test_copying.py``) and of
upgrades from every schema revision (``tests/store/test_migrate.py``)."""

from __future__ import annotations

from pathlib import Path

from sqlalchemy import select

import registry
from registry.language.casefile import parse_case_text
from registry.store.tables import Base
from tests.helpers.databases import connection
from tests.helpers.samples import AFFINE, CASES, FAMILIES, SEED, ZHUKOVSKY, case_file

#: A case in the Hamiltonian form on so(3,1) (kappa -1): revision 0007 reads H and kappa
#: from the stored text of such a case.
SO31 = CASES / "so4" / "komarov-1990-so31-kovalevskaya.toml"


def full_registry(path: Path) -> Path:
    """An SQLite registry holding rows in every table: the seed cases and one in the
    Hamiltonian form, a second version of one, a renamed case with an alias, two
    recorded searches (a generic integral attached as a claim, derived cases), a recorded
    Kovalevskaya analysis, two identifications, an audit with corrections, and a numerical
    one (evidence).
    About 15 s of work."""
    with registry.open(path) as reg:
        reg.add(*(case_file(c) for c in SEED), FAMILIES / "lagrange-lam.toml", SO31)
        text = case_file(ZHUKOVSKY).read_text(encoding="utf-8")
        changed = text.replace('title = "', 'title = "Second version: ', 1)
        reg.add_case(parse_case_text(changed, "zhukovsky-v2.toml"))
        renamed = case_file(AFFINE).read_text(encoding="utf-8")
        renamed = renamed.replace(
            f'id = "{AFFINE}"', 'id = "affine-renamed"\naliases = ["affine-old-name"]', 1
        )
        reg.add_case(parse_case_text(renamed, "affine-renamed.toml"))
        reg.discover("family-lagrange-lam", degree=2, free=["lam"], record=True)
        reg.discover(FAMILIES / "heavy-top-lam.toml", degree=3, free=["lam"], record=True)
        reg.analyse_exponents("family-lagrange-lam", record=True)
        reg.identify([ZHUKOVSKY, "family-lagrange-lam"], jobs=1)
        reg.audit(jobs=1)
        reg.audit([ZHUKOVSKY, "family-lagrange-lam"], jobs=1, numeric=True, fresh=True)
    return path


def registry_rows(target: str | Path) -> dict[str, list[dict]]:
    """Every row of every registry table, in id order, read through the registry's
    column types (JSON as the values it holds, times as aware UTC datetimes, booleans as
    booleans), so that two backends holding the same data give equal rows."""
    with connection(target) as conn:
        return {
            t.name: [
                dict(r._mapping) for r in conn.execute(select(t).order_by(*t.primary_key.columns))
            ]
            for t in Base.metadata.sorted_tables
        }
