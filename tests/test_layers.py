"""The direction of imports between the package's layers, checked on the source.

Every module is parsed with ``ast`` (imports inside functions and under
``TYPE_CHECKING`` count too), relative imports are resolved, and each import of the
package is checked against the rules below. The mathematics never imports the case
language, the audit, the store or the presentation; the store never imports the
mathematics or the audit; nothing but the command line's own modules imports it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import registry

PACKAGE = Path(registry.__file__).resolve().parent

BASE = {"model", "errors", "dynamics", "expression", "settings"}
#: What each layer (a folder, or a module at the top) may import, besides itself.
ALLOWED: dict[str, set[str]] = {
    "expression": set(),
    "dynamics": {"expression"},
    "model": {"dynamics", "expression"},
    "errors": set(),
    "settings": {"errors"},
    "version": set(),
    # a Dask cluster must run this code version (``executor.open_executor``)
    "execution": BASE | {"version"},
    "mathematics": BASE,
    "language": BASE | {"mathematics"},
    "audit": BASE | {"mathematics", "language", "execution"},
    "discovery": BASE | {"mathematics", "language", "audit", "execution"},
    "store": BASE | {"language"},
    # the command line talks only to the facade (and reads the settings, names the errors)
    "cli": {"api", "errors", "settings"},
}
#: Layers that may import anything but these.
FORBIDDEN: dict[str, set[str]] = {
    # presentation renders the data it is given: the facade (api) gathers it
    "presentation": {"api", "runs", "cli", "__main__", "__init__"},
    # the runs hold the facade's policies; the facade delegates to them, not back
    "runs": {"api", "cli", "__main__", "__init__"},
    "api": {"cli", "__main__", "__init__"},
    "__main__": set(),
    "__init__": {"cli", "__main__"},
}


def layer_of(module: str) -> str:
    """The layer of a module of the package: its folder, or itself at the top
    (``registry`` alone is the package's ``__init__``)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def module_name(path: Path, package: Path) -> str:
    relative = path.relative_to(package.parent).with_suffix("")
    parts = relative.parts[:-1] if relative.name == "__init__" else relative.parts
    return ".".join(parts)


def imports_of(path: Path, package: Path) -> list[tuple[int, str]]:
    """(line, absolute module name) of every import of the package in one file."""
    name = module_name(path, package)
    is_package = path.name == "__init__.py"
    here = name.split(".") if is_package else name.split(".")[:-1]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - node.level + 1]
                module = ".".join([*base, node.module] if node.module else base)
            else:
                module = node.module or ""
            for alias in node.names:  # from a package: a submodule, or a name of it
                sub = f"{module}.{alias.name}"
                found.append((node.lineno, sub if _is_module(sub, package) else module))
    root = package.name
    kept = [(line, m) for line, m in found if m == root or m.startswith(root + ".")]
    return list(dict.fromkeys(kept))


def _is_module(name: str, package: Path) -> bool:
    """Whether ``name`` (``registry.x.y``) is a module or package of the package."""
    path = package.parent.joinpath(*name.split("."))
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


def violations(package: Path) -> list[str]:
    """Every import that breaks the rules, as 'file:line imports module (why)'."""
    problems = []
    for path in sorted(package.rglob("*.py")):
        source = module_name(path, package)
        mine = layer_of(source)
        for line, target in imports_of(path, package):
            theirs = layer_of(target)
            if theirs == mine:
                continue
            if mine in ALLOWED:
                allowed = ALLOWED[mine]
                if theirs in allowed:
                    continue
                why = f"{mine} may import only {', '.join(sorted(allowed | {mine}))}"
            elif theirs in FORBIDDEN.get(mine, set()):
                why = f"{mine} must not import {theirs}"
            else:
                continue
            where = path.relative_to(package.parent).as_posix()
            problems.append(f"{where}:{line} imports {target} ({why})")
    return problems


def test_every_import_goes_in_an_allowed_direction():
    assert violations(PACKAGE) == []


#: Modules that start processes, and the functions of ``os`` that do.
PROCESS_MODULES = ("multiprocessing", "subprocess", "concurrent.futures")
PROCESS_CALLS = ("fork", "forkpty", "system", "popen", "spawn", "posix_spawn", "exec")


def process_starts(package: Path) -> list[str]:
    """Every place outside ``execution/`` that could start a process: an import of
    multiprocessing, subprocess or concurrent.futures, or os.fork, os.system, os.spawn*,
    os.posix_spawn*, os.exec*, as 'file:line what'."""
    found = []
    for path in sorted(package.rglob("*.py")):
        if layer_of(module_name(path, package)) == "execution":
            continue
        where = path.relative_to(package.parent).as_posix()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = []
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level:
                names = [node.module or ""]
            for name in names:
                if any(name == m or name.startswith(m + ".") for m in PROCESS_MODULES):
                    found.append(f"{where}:{node.lineno} imports {name}")
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id == "os"
                and node.attr.startswith(PROCESS_CALLS)
            ):
                found.append(f"{where}:{node.lineno} uses os.{node.attr}")
    return found


def test_only_the_execution_layer_starts_processes():
    assert process_starts(PACKAGE) == []


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("import multiprocessing as mp\n", "imports multiprocessing"),
        ("from concurrent.futures import ProcessPoolExecutor\n", "imports concurrent.futures"),
        ("def f():\n    import subprocess\n", "imports subprocess"),
        ("import os\npid = os.fork()\n", "uses os.fork"),
        ("import os\nos.execv('x', [])\n", "uses os.execv"),
    ],
)
def test_a_process_started_outside_the_execution_layer_is_named(tmp_path, text, expected):
    package = tmp_path / "registry"
    for folder in ("audit", "execution"):
        (package / folder).mkdir(parents=True)
        (package / folder / "__init__.py").write_text("")
    (package / "__init__.py").write_text("")
    (package / "audit" / "bad.py").write_text(text)
    (package / "execution" / "fine.py").write_text(text)
    (problem,) = process_starts(package)
    assert problem.startswith("registry/audit/bad.py:") and problem.endswith(expected)


def cycles(package: Path) -> list[list[str]]:
    """The import circles among the package's modules (strongly connected components of
    more than one module, or a module importing itself), each sorted."""
    graph: dict[str, set[str]] = {}
    for path in sorted(package.rglob("*.py")):
        graph[module_name(path, package)] = {m for _, m in imports_of(path, package)}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(node: str) -> None:  # Tarjan's algorithm
        index[node] = low[node] = len(index)
        stack.append(node)
        for other in graph[node]:
            if other not in graph:
                continue
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            component = []
            while True:
                other = stack.pop()
                component.append(other)
                if other == node:
                    break
            if len(component) > 1 or node in graph[node]:
                found.append(sorted(component))

    for node in graph:
        if node not in index:
            visit(node)
    return found


def test_the_import_graph_has_no_circle():
    assert cycles(PACKAGE) == []


def test_a_circle_of_imports_is_found(tmp_path):
    package = tmp_path / "registry"
    (package / "mathematics").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "mathematics" / "__init__.py").write_text("")
    (package / "mathematics" / "a.py").write_text("from .b import f\n")
    (package / "mathematics" / "b.py").write_text("def g():\n    from .c import h\n")
    (package / "mathematics" / "c.py").write_text("from . import a\n")
    assert cycles(package) == [
        ["registry.mathematics.a", "registry.mathematics.b", "registry.mathematics.c"]
    ]


def test_every_folder_of_the_package_is_a_known_layer():
    folders = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()}
    assert folders <= set(ALLOWED) | set(FORBIDDEN)
    modules = {p.stem for p in PACKAGE.glob("*.py")}
    assert modules <= set(ALLOWED) | set(FORBIDDEN)


@pytest.mark.parametrize(
    ("file", "text", "expected"),
    [
        (
            "mathematics/bad.py",
            "from ..store import tables\n",
            "mathematics may import only dynamics, errors, expression, mathematics, model",
        ),
        (
            "mathematics/bad.py",
            "def f():\n    from registry.presentation import latex\n",
            "mathematics may import only dynamics, errors, expression, mathematics, model",
        ),
        ("store/bad.py", "from ..audit.checks import CHECKS\n", "store may import only"),
        ("store/bad.py", "from .. import cli\n", "store may import only"),
        ("presentation/bad.py", "from ..cli import main\n", "presentation must not import cli"),
        (
            "presentation/bad.py",
            "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from ..api import Registry\n",
            "presentation must not import api",
        ),
        ("api.py", "import registry.cli\n", "api must not import cli"),
        (
            "cli.py",
            "from .presentation.verdict_table import verdict_table\n",
            "cli may import only api, cli, errors, settings",
        ),
    ],
)
def test_a_wrong_import_is_named_with_its_file_and_rule(tmp_path, file, text, expected):
    package = tmp_path / "registry"
    for folder in ("mathematics", "store", "presentation", "audit"):
        (package / folder).mkdir(parents=True)
        (package / folder / "__init__.py").write_text("")
    (package / "__init__.py").write_text("")
    (package / file).write_text(text)
    (problem,) = violations(package)
    assert problem.startswith(f"registry/{file}:")
    assert expected in problem


def test_relative_imports_resolve_to_the_module_they_name(tmp_path):
    package = tmp_path / "registry"
    (package / "audit").mkdir(parents=True)
    (package / "model.py").write_text("")
    (package / "audit" / "__init__.py").write_text("from . import checks\nfrom .. import model\n")
    (package / "audit" / "checks.py").write_text("from ..mathematics.zero_test import decide\n")
    assert imports_of(package / "audit" / "__init__.py", package) == [
        (1, "registry.audit.checks"),
        (2, "registry.model"),
    ]
    assert imports_of(package / "audit" / "checks.py", package) == [
        (1, "registry.mathematics.zero_test")
    ]


#: The fields of the forms a case file may give its system in (``model.System``).
FORM_FIELDS = {
    "inertia",
    "inertia_exprs",
    "potential",
    "torque",
    "torque_exprs",
    "hamiltonian",
    "hamiltonian_form",
    "kappa",
    "kappa_expr",
    "variables",
    "equations",
    "bracket",
    "definitions",
}
#: Where the forms are known: the case language builds the ``Dynamics`` every other layer
#: reads; the model declares the forms.
FORM_AWARE = {"language", "model"}


def form_inspections(package: Path) -> list[str]:
    """Every place outside the case language that reads a field of the form a case file
    gave its system in (``case.system.inertia``, ``x.system.hamiltonian``, ...) or imports
    ``model.System``, as 'file:line what'."""
    found = []
    for path in sorted(package.rglob("*.py")):
        if layer_of(module_name(path, package)) in FORM_AWARE:
            continue
        where = path.relative_to(package.parent).as_posix()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Attribute)
                and node.attr in FORM_FIELDS
                and isinstance(node.value, ast.Attribute)
                and node.value.attr == "system"
            ):
                found.append(f"{where}:{node.lineno} reads .system.{node.attr}")
            elif isinstance(node, ast.ImportFrom) and any(a.name == "System" for a in node.names):
                if (node.module or "").endswith("model"):
                    found.append(f"{where}:{node.lineno} imports model.System")
    return found


def test_only_the_case_language_knows_the_form_of_a_system():
    """The audit, discovery, numeric evidence, the store and presentation read the case's
    ``Dynamics`` and ask what it has; none of them branches on the file's form."""
    assert form_inspections(PACKAGE) == []


def test_reading_a_form_field_outside_the_language_is_named(tmp_path):
    package = tmp_path / "registry"
    for folder in ("audit", "language"):
        (package / folder).mkdir(parents=True)
        (package / folder / "__init__.py").write_text("")
    (package / "__init__.py").write_text("")
    text = "def f(case):\n    return case.system.hamiltonian is None\n"
    (package / "audit" / "bad.py").write_text(text)
    (package / "language" / "fine.py").write_text(text)
    (package / "audit" / "worse.py").write_text("from ..model import Case, System\n")
    assert form_inspections(package) == [
        "registry/audit/bad.py:2 reads .system.hamiltonian",
        "registry/audit/worse.py:1 imports model.System",
    ]
