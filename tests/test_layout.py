"""The package's layout stays walkable: every module with logic has a test file named
after it, and the module map of docs/development.md names every module (and nothing else)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import registry

PACKAGE = Path(registry.__file__).resolve().parent
ROOT = PACKAGE.parent
TESTS = ROOT / "tests"
#: The page whose "Module map" lists every module of the package.
MAP_PAGE = ROOT / "docs" / "development.md"

#: Modules with logic but no test file of their own, and why (paths under registry/).
EXEMPT = {
    "__init__.py": "re-exports the public API; tests/test_api.py tests it through them",
    "__main__.py": "only calls the CLI; tests/test_cli.py runs `python -m registry`",
    "store/migrations/": "Alembic's revisions; tests/store/test_migrate.py runs every one",
}


def modules() -> list[str]:
    """Every module of the package, as a path under registry/ (POSIX)."""
    return sorted(
        p.relative_to(PACKAGE).as_posix()
        for p in PACKAGE.rglob("*.py")
        if "__pycache__" not in p.parts
    )


def has_logic(path: str) -> bool:
    """Whether a module holds more than its docstring."""
    body = ast.parse((PACKAGE / path).read_text(encoding="utf-8")).body
    docstring = (
        body[:1] and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)
    )
    return len(body) > (1 if docstring else 0)


def exempt(path: str) -> str | None:
    return next(
        (
            why
            for where, why in EXEMPT.items()
            if path == where or (where.endswith("/") and path.startswith(where))
        ),
        None,
    )


def test_every_module_with_logic_has_a_test_file_named_after_it():
    test_files = {p.name for p in TESTS.rglob("test_*.py")}
    missing = [
        path
        for path in modules()
        if has_logic(path)
        and not exempt(path)
        and f"test_{Path(path).stem.lstrip('_')}.py" not in test_files
    ]
    assert missing == []


def test_every_exemption_is_still_needed():
    for where in EXEMPT:
        matching = [
            m for m in modules() if m == where or where.endswith("/") and m.startswith(where)
        ]
        assert matching, f"{where} is exempt but no longer exists"
        if not where.endswith("/"):
            assert has_logic(where), f"{where} has no logic left: drop its exemption"


def test_test_file_names_are_unique():
    names = [p.name for p in TESTS.rglob("test_*.py")]
    assert len(names) == len(set(names))  # one name, one place to look


def imported_modules(path: Path) -> set[str]:
    """The modules a file imports (absolute names; relative imports resolved)."""
    package = ".".join(path.relative_to(ROOT).with_suffix("").parts[:-1])
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = package.rsplit(".", node.level - 1)[0] if node.level else ""
            name = ".".join(p for p in (base, node.module or "") if p)
            found |= {name} | {f"{name}.{alias.name}" for alias in node.names}
    return found


def test_no_test_module_imports_another_or_a_conftest():
    for path in sorted(TESTS.rglob("*.py")):
        for name in imported_modules(path):
            last = name.rsplit(".", 1)[-1]
            assert not last.startswith("test_") and last != "conftest", (
                f"{path.relative_to(ROOT)} imports {name}: shared code goes to tests/helpers/"
            )


def module_map() -> list[str]:
    """The entries of the module map as paths under registry/ (folders end in /)."""
    page = MAP_PAGE.read_text(encoding="utf-8")
    section = page.split("## Module map", 1)[1]
    block = re.search(r"```text\n(.*?)```", section, re.S).group(1)
    entries, folders = [], []  # folders: (indent, name) of the enclosing folders
    for line in block.splitlines():
        if not line.strip():
            continue
        indent = len(line) - len(line.lstrip())
        name = line.split()[0]
        while folders and folders[-1][0] >= indent:
            folders.pop()
        path = "".join(f for _, f in folders[1:]) + name  # folders[0] is registry/
        if name != "registry/":
            entries.append(path)
        if name.endswith("/"):
            folders.append((indent, name))
    return entries


def named_by(path: str) -> str:
    """How the map names a module: a package by its folder, a revision by its folder."""
    if path.startswith("store/migrations/versions/"):
        return "store/migrations/versions/"
    if path.endswith("/__init__.py"):
        return path.removesuffix("__init__.py")
    return path


def test_the_module_map_names_every_module_once():
    entries = module_map()
    assert len(entries) == len(set(entries)), "a module is listed twice"
    assert sorted({named_by(m) for m in modules()}) == sorted(entries)


def test_every_line_of_the_module_map_says_what_the_module_holds():
    page = MAP_PAGE.read_text(encoding="utf-8")
    block = re.search(r"## Module map.*?```text\n(.*?)```", page, re.S).group(1)
    for line in block.splitlines()[1:]:
        assert len(line.split(maxsplit=1)) == 2, f"no description: {line!r}"
        assert len(line) <= 100, f"too long: {line!r}"
