"""Old import paths (``registry.zero``, ``registry.storage``, ...) still import, with a
DeprecationWarning naming the new place; the package itself never uses them."""

from __future__ import annotations

import ast
import importlib
import sys
import warnings
from pathlib import Path

import pytest

import registry
from registry import _moved

ROOT = Path(registry.__file__).resolve().parents[1]

#: Names looked up through old paths, and what they must be.
OLD_NAMES = [
    ("registry.mechanics", "poisson_tensor", "registry.mathematics.mechanics", "poisson_tensor"),
    ("registry.fast", "ENABLED", "registry.mathematics.symengine_bridge", "ENABLED"),
    ("registry.certified", "evaluate", "registry.mathematics.certified_evaluation", "evaluate"),
    ("registry.zero", "decide", "registry.mathematics.zero_test", "decide"),
    ("registry.zero", "Domain", "registry.mathematics.zero_test", "Domain"),
    ("registry.zero", "sample_points", "registry.mathematics.sampling", "sample_points"),
    ("registry.zero", "_sample_point", "registry.mathematics.sampling", "sample_point"),
    ("registry.zero", "prove_zero", "registry.mathematics.normal_form", "prove_zero"),
    ("registry.zero", "_Atoms", "registry.mathematics.normal_form", "Atoms"),
    ("registry.families", "recognise", "registry.mathematics.families", "recognise"),
    (
        "registry.families",
        "tangential_potential",
        "registry.mathematics.potentials",
        "tangential_potential",
    ),
    (
        "registry.conditions",
        "parameter_conditions",
        "registry.mathematics.parameter_conditions",
        "parameter_conditions",
    ),
    ("registry.expressions", "parse_expression", "registry.language.parser", "parse_expression"),
    ("registry.expressions", "to_text", "registry.language.printer", "to_text"),
    ("registry.expressions", "MAX_NODES", "registry.language.limits", "MAX_NODES"),
    ("registry.expressions", "Budget", "registry.language.limits", "ParseBudget"),
    ("registry.casefile", "load_case", "registry.language.casefile", "load_case"),
    ("registry.casefile", "MAX_CLAIMS", "registry.language.casefile", "MAX_CLAIMS"),
    (
        "registry.export",
        "corrected_case_text",
        "registry.language.case_writer",
        "corrected_case_text",
    ),
    ("registry.checks", "CHECKS", "registry.audit.checks", "CHECKS"),
    ("registry.checks", "Mechanics", "registry.mathematics.case_mechanics", "CaseMechanics"),
    ("registry.corrections", "repairs", "registry.audit.repairs", "repairs"),
    ("registry.numeric", "claim_drift", "registry.audit.numeric_evidence", "claim_drift"),
    ("registry.budget", "time_limit", "registry.audit.time_budget", "time_limit"),
    ("registry.budget", "Budget", "registry.audit.time_budget", "TimeBudget"),
    ("registry.workers", "audit_in_workers", "registry.audit.worker_pool", "audit_in_workers"),
    ("registry.storage", "Store", "registry.store.database", "Store"),
    ("registry.storage", "BUSY_TIMEOUT", "registry.store.engine", "BUSY_TIMEOUT"),
    ("registry.storage", "Base", "registry.store.tables", "Base"),
    ("registry.storage", "storage_error", "registry.store.engine", "storage_error"),
    ("registry.storage", "_configure_sqlite", "registry.store.engine", "configure_sqlite"),
    ("registry.migrate", "head", "registry.store.migrate", "head"),
    ("registry.integrity", "verify", "registry.store.integrity", "verify"),
    ("registry.report", "result_document", "registry.presentation.audit_json", "result_document"),
    ("registry.reports", "build_report", "registry.presentation.report_content", "build_report"),
    ("registry.reports", "FORMATS", "registry.presentation.report_writers", "FORMATS"),
    ("registry.sharing", "read_table", "registry.presentation.data_export", "read_table"),
    ("registry.sharing", "bibtex", "registry.presentation.bibtex", "bibtex"),
    ("registry.plots", "drift_plot", "registry.presentation.plots", "drift_plot"),
    ("registry.display", "case_html", "registry.presentation.notebook", "case_html"),
]


#: What the module registry.audit held before it became a folder.
OLD_AUDIT_NAMES = set(registry.audit._OLD_NAMES)


def fresh_import(name: str, monkeypatch) -> tuple[object, list[warnings.WarningMessage]]:
    """Import ``name`` as if for the first time; return it and the warnings raised."""
    monkeypatch.delitem(sys.modules, name, raising=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(name)
    return module, caught


@pytest.mark.parametrize("old", sorted(_moved.MOVED))
def test_every_old_path_imports_with_a_warning_naming_the_new_place(old, monkeypatch):
    module, caught = fresh_import(old, monkeypatch)
    deprecations = [w for w in caught if issubclass(w.category, DeprecationWarning)]
    assert len(deprecations) == 1
    message = str(deprecations[0].message)
    assert message.startswith(f"{old} has moved: import it from ")
    for new in _moved.MOVED[old]:
        assert new in message
        importlib.import_module(new)  # every new place exists
    assert deprecations[0].filename == __file__  # the warning points at the importing line


@pytest.mark.parametrize(("old", "name", "new", "new_name"), OLD_NAMES)
def test_names_are_found_through_the_old_path(old, name, new, new_name, monkeypatch):
    module, _ = fresh_import(old, monkeypatch)
    assert getattr(module, name) is getattr(importlib.import_module(new), new_name)


def test_from_import_of_an_old_path_works_and_warns(monkeypatch):
    monkeypatch.delitem(sys.modules, "registry.zero", raising=False)
    monkeypatch.delattr(registry, "zero", raising=False)
    with pytest.warns(DeprecationWarning, match=r"registry\.zero has moved"):
        from registry.zero import decide
    from registry.mathematics.zero_test import decide as new

    assert decide is new


def test_an_old_module_is_an_attribute_of_the_package(monkeypatch):
    monkeypatch.delitem(sys.modules, "registry.families", raising=False)
    monkeypatch.delattr(registry, "families", raising=False)
    with pytest.warns(DeprecationWarning):
        found = registry.families.recognise
    from registry.mathematics.families import recognise

    assert found is recognise


@pytest.mark.parametrize("name", ["audit_case", "failed_case", "DEFAULT_BUDGET", "CASE_CHECKS"])
def test_the_old_audit_module_s_names_are_found_in_the_audit_package(name):
    from registry.audit import case_audit

    with pytest.warns(DeprecationWarning, match=rf"registry\.audit\.{name} has moved") as caught:
        found = getattr(registry.audit, name)
    assert found is getattr(case_audit, name)
    assert caught[0].filename == __file__
    with pytest.warns(DeprecationWarning):
        exec(f"from registry.audit import {name}", {})


def test_the_audit_package_s_own_modules_are_not_old_names():
    from registry.audit import repairs

    assert repairs.__name__ == "registry.audit.repairs"
    with pytest.raises(AttributeError, match="has no attribute 'no_such_name'"):
        registry.audit.no_such_name  # noqa: B018


def test_an_old_function_that_became_an_option_keeps_its_behaviour(monkeypatch):
    module, _ = fresh_import("registry.sharing", monkeypatch)
    from registry.presentation import latex

    assert module.latex_escape("{x}_1") == latex.escape("{x}_1", balanced=True)
    assert module.latex_escape("{x}") == r"\textbraceleft{}x\textbraceright{}"


@pytest.mark.parametrize(("old", "name"), sorted(_moved.CHANGED))
def test_a_name_used_differently_now_says_what_to_use(old, name, monkeypatch):
    module, _ = fresh_import(old, monkeypatch)
    with pytest.raises(AttributeError) as caught:
        getattr(module, name)
    assert str(caught.value) == f"{old}.{name} has changed: {_moved.CHANGED[old, name]}"


def test_an_unknown_name_says_where_the_contents_went(monkeypatch):
    module, _ = fresh_import("registry.zero", monkeypatch)
    with pytest.raises(AttributeError) as caught:
        module.no_such_name  # noqa: B018
    assert str(caught.value) == (
        "module 'registry.zero' has no attribute 'no_such_name': registry.zero moved to "
        f"{_moved.new_places('registry.zero')}, where there is no 'no_such_name' either"
    )


def test_an_unknown_module_of_the_package_is_still_an_attribute_error():
    with pytest.raises(AttributeError, match="has no attribute 'no_such_module'"):
        registry.no_such_module  # noqa: B018
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("registry.no_such_module")


def test_star_import_and_dir_list_the_new_modules_names(monkeypatch):
    module, _ = fresh_import("registry.zero", monkeypatch)
    assert {"decide", "Domain", "ZeroTest"} <= set(module.__all__)
    assert "decide" in dir(module)
    namespace: dict = {}
    exec("from registry.zero import *", namespace)
    assert namespace["decide"] is module.decide


def _imported_modules(path: Path) -> set[str]:
    """The absolute names of the modules a file imports (relative imports resolved)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = None
    if ROOT / "registry" in path.parents:
        package = ".".join(path.relative_to(ROOT).with_suffix("").parts[:-1])
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*parts, base] if base else parts)
            found.add(base)
            found.update(f"{base}.{alias.name}" for alias in node.names)
            if base == "registry.audit":  # the old module's names, now in case_audit
                found.update(a.name for a in node.names if a.name in OLD_AUDIT_NAMES)
    return found


def test_the_package_tests_and_scripts_never_use_an_old_path():
    files = [
        *(ROOT / "registry").rglob("*.py"),
        *(ROOT / "tests").rglob("*.py"),
        *(ROOT / "scripts").rglob("*.py"),
    ]
    users = {
        f"{path.relative_to(ROOT)} imports {name}"
        for path in files
        if path.name != "test_moved.py"
        for name in _imported_modules(path)
        if name in _moved.MOVED or name in OLD_AUDIT_NAMES
    }
    assert not users


def test_doctests_and_the_readme_never_use_an_old_path():
    import re

    old = re.compile(r"\b(" + "|".join(re.escape(m) for m in _moved.MOVED) + r")\b")
    examples = [
        (path, line)
        for path in (ROOT / "registry").rglob("*.py")
        for line in path.read_text(encoding="utf-8").splitlines()
        if line.lstrip().startswith(">>>")
    ]
    examples += [
        (ROOT / "README.md", line) for line in (ROOT / "README.md").read_text().splitlines()
    ]
    users = [
        f"{path.relative_to(ROOT)}: {line.strip()}" for path, line in examples if old.search(line)
    ]
    assert not users
