"""Old import paths of modules that moved into the layer folders, still importable.

Before the package's layers became folders, every module sat at its top
(``registry.zero``, ``registry.storage``, ...). Notebooks that import those paths
keep working: ``install`` (called by ``registry/__init__.py``) puts a finder on
``sys.meta_path`` that answers each old path with a stand-in module, with a
DeprecationWarning naming the new place. The stand-in looks every name up in the
new modules, in order (several where the old module was split), under its new
name where it was renamed (``registry.budget.Budget`` is ``TimeBudget``); a name
found in none of them raises AttributeError saying where the contents went.

One old module, ``registry.audit``, gave its name to a folder: its names
(``registry.audit.audit_case``, ...) are answered by that package's own
``__getattr__``, with the same warning (they are in ``audit.case_audit`` now).

The package's own code and tests never use these paths.
"""

from __future__ import annotations

import functools
import importlib
import importlib.abc
import importlib.machinery
import sys
import types
import warnings

#: Each old module path and the modules its contents moved to, searched in this order.
MOVED: dict[str, tuple[str, ...]] = {
    "registry.mechanics": ("registry.mathematics.mechanics",),
    "registry.fast": ("registry.mathematics.symengine_bridge",),
    "registry.certified": ("registry.mathematics.certified_evaluation",),
    "registry.zero": (
        "registry.mathematics.zero_test",
        "registry.mathematics.sampling",
        "registry.mathematics.normal_form",
    ),
    "registry.families": ("registry.mathematics.families", "registry.mathematics.potentials"),
    "registry.conditions": ("registry.mathematics.parameter_conditions",),
    "registry.expressions": (
        "registry.language.parser",
        "registry.language.printer",
        "registry.language.limits",
    ),
    "registry.casefile": ("registry.language.casefile",),
    "registry.export": ("registry.language.case_writer",),
    "registry.checks": ("registry.audit.checks", "registry.mathematics.case_mechanics"),
    "registry.corrections": ("registry.audit.repairs",),
    "registry.numeric": ("registry.audit.numeric_evidence",),
    "registry.budget": ("registry.audit.time_budget",),
    "registry.workers": ("registry.audit.worker_pool",),
    "registry.storage": (
        "registry.store.database",
        "registry.store.tables",
        "registry.store.conversions",
        "registry.store.engine",
        "registry.store.frames",
        "registry.store.integrity",
        "registry.store.processes",
    ),
    "registry.migrate": ("registry.store.migrate",),
    "registry.integrity": ("registry.store.integrity",),
    "registry.report": ("registry.presentation.verdict_table", "registry.presentation.audit_json"),
    "registry.reports": (
        "registry.presentation.report_content",
        "registry.presentation.report_writers",
        "registry.presentation.latex",
    ),
    "registry.sharing": ("registry.presentation.data_export", "registry.presentation.bibtex"),
    "registry.plots": ("registry.presentation.plots",),
    "registry.display": ("registry.presentation.notebook",),
}

#: Names that changed on the way: old module path -> {old name: new name}.
RENAMED: dict[str, dict[str, str]] = {
    "registry.zero": {  # private names other modules imported, public now
        "_sample_point": "sample_point",
        "_concrete_functions": "concrete_functions",
        "_substitute_functions": "substitute_functions",
        "_radical_bases": "radical_bases",
        "_Atoms": "Atoms",
        "_numerator": "numerator",
        "_reduce_radical": "reduce_radical",
    },
    "registry.expressions": {"Budget": "ParseBudget"},
    "registry.checks": {"Mechanics": "CaseMechanics"},
    "registry.budget": {"Budget": "TimeBudget"},
    "registry.storage": {
        "_configure_sqlite": "configure_sqlite",
        "_guarded": "guarded",
        "_resolve": "resolve",
        "_case_row": "case_row",
        "_claim_row": "claim_row",
        "_newest_versions": "newest_versions",
        "_process_started": "process_started",
        "_process_gone": "process_gone",
    },
}


#: Old names whose behaviour is now an option of a new function:
#: (old module path, name) -> (new module, function, its keyword arguments).
OPTIONS: dict[tuple[str, str], tuple[str, str, dict]] = {
    ("registry.sharing", "latex_escape"): (
        "registry.presentation.latex",
        "escape",
        {"balanced": True},
    ),
}


#: Old names that are used differently now: looked up through the old path, each raises
#: AttributeError saying what to use instead.
CHANGED: dict[tuple[str, str], str] = {
    ("registry.report", "verdict_table"): (
        "the verdict table is made from the audit's outcomes now: "
        "registry.presentation.verdict_table.verdict_table(report.outcomes(), report.run)"
    ),
    ("registry.report", "disagreements"): (
        "use registry.presentation.verdict_table.disagreements(report.outcomes())"
    ),
    ("registry.report", "audit_document"): (
        "use report.document(), or registry.presentation.audit_json.audit_document("
        "run, report.outcomes())"
    ),
    ("registry.report", "case_document"): (
        "use registry.presentation.audit_json.case_document(outcome) with an outcome of "
        "registry.audit.outcome.case_outcome(audit, case, version)"
    ),
    ("registry.reports", "diff_runs"): (
        "use Registry.diff(run_a, run_b), which returns VerdictChange objects"
    ),
    ("registry.reports", "diff_table"): (
        "use registry.presentation.verdict_table.diff_table(reg.diff(run_a, run_b), run_a, run_b)"
    ),
}


def new_places(old: str) -> str:
    """Where the contents of the old module ``old`` went, for messages."""
    places = MOVED[old]
    if len(places) == 1:
        return places[0]
    return ", ".join(places[:-1]) + " and " + places[-1]


class MovedModule(types.ModuleType):
    """The stand-in for an old module path: its attributes are those of the new modules."""

    def __init__(self, name: str):
        super().__init__(name, f"Moved: {name} is now {new_places(name)}.")
        self.__moved_to__ = MOVED[name]
        self.__renamed__ = RENAMED.get(name, {})

    def __getattr__(self, attr: str):
        if attr == "__all__":
            return sorted({n for m in self._modules() for n in _public(m)} | set(self.__renamed__))
        if attr.startswith("__") and attr.endswith("__"):
            raise AttributeError(attr)
        if (self.__name__, attr) in CHANGED:
            raise AttributeError(
                f"{self.__name__}.{attr} has changed: {CHANGED[self.__name__, attr]}"
            )
        if (self.__name__, attr) in OPTIONS:
            module, function, options = OPTIONS[self.__name__, attr]
            return functools.partial(getattr(importlib.import_module(module), function), **options)
        wanted = self.__renamed__.get(attr, attr)
        for module in self._modules():
            if hasattr(module, wanted):
                return getattr(module, wanted)
        raise AttributeError(
            f"module {self.__name__!r} has no attribute {attr!r}: {self.__name__} moved to "
            f"{new_places(self.__name__)}, where there is no {wanted!r} either"
        )

    def __repr__(self) -> str:
        return f"<module {self.__name__!r} (moved to {new_places(self.__name__)})>"

    def __dir__(self) -> list[str]:
        return sorted(set(super().__dir__()) | set(self.__all__))

    def _modules(self) -> list[types.ModuleType]:
        return [importlib.import_module(target) for target in self.__moved_to__]


def _public(module: types.ModuleType) -> list[str]:
    names = getattr(module, "__all__", None)
    return list(names) if names is not None else [n for n in vars(module) if n[0] != "_"]


class _OldPaths(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds and loads the old module paths (and nothing else)."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname not in MOVED:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec):
        return MovedModule(spec.name)

    def exec_module(self, module) -> None:
        name = module.__name__
        warnings.warn(
            f"{name} has moved: import it from {new_places(name)}",
            DeprecationWarning,
            stacklevel=_importer(),
        )


def _importer() -> int:
    """The stack level of the code that imported an old path, for ``warnings.warn``
    called in ``exec_module``: past this module, the package's ``__getattr__`` and
    ``importlib.import_module``. The warnings machinery does not count the frames of
    importlib's bootstrap, so neither does this."""
    import importlib as machinery

    skipped = {__file__, sys.modules["registry"].__file__, machinery.__file__}
    frame, level = sys._getframe(2), 1  # the frame that called exec_module
    while frame is not None:
        name = frame.f_code.co_filename
        internal = "importlib" in name and "_bootstrap" in name
        if not internal:
            if name not in skipped:
                return level + 1
            level += 1
        frame = frame.f_back
    return level


_FINDER = _OldPaths()


def install() -> None:
    """Answer the old module paths (once per process; the first finder asked)."""
    if _FINDER not in sys.meta_path:
        sys.meta_path.insert(0, _FINDER)


def old_module(name: str) -> types.ModuleType:
    """``registry.<name>`` for an old top-level module name (``registry.zero``), imported
    on first use: ``registry.zero.decide`` works without ``import registry.zero``."""
    full = f"registry.{name}"
    if full not in MOVED:
        raise AttributeError(f"module 'registry' has no attribute {name!r}")
    return importlib.import_module(full)
