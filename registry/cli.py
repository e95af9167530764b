"""The ``registry`` command: a thin layer over the facade, ``registry.api``.

Each command opens the database, calls one facade function and prints what it returns;
the command line imports nothing else of the package but the settings and the errors
(``tests/test_layers.py``). User errors print one line per problem, starting ``Error:``,
and exit with status 1; ``--debug`` shows the traceback instead.
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from functools import wraps
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import click

from . import settings
from .errors import DatabaseMissingError, RegistryError, printable

if TYPE_CHECKING:
    from .api import Registry

#: The overall verdicts of a claim (``model.Verdict``), spelled out here so that
#: ``registry --help`` need not import sympy; tests/test_cli.py checks they agree.
VERDICTS = ("verified", "refuted", "inconclusive", "error")


def _report(err: Exception) -> None:
    """Print an error as lines starting ``Error:``, one per problem."""
    for line in str(err).splitlines() or [type(err).__name__]:
        click.echo(f"Error: {line}", err=True)


def _user_errors(fn):
    """Turn a RegistryError into ``Error: ...`` lines and exit status 1 (unless --debug)."""

    @wraps(fn)
    def wrapper(*args, **kwargs):
        ctx = click.get_current_context()
        try:
            return fn(*args, **kwargs)
        except (RegistryError, OSError) as err:
            if ctx.obj and ctx.obj.get("debug"):
                raise
            if isinstance(err, OSError) and not isinstance(err, RegistryError):
                err = RegistryError(_os_message(err))
            _report(err)
            ctx.exit(1)

    return wrapper


def _os_message(err: OSError) -> str:
    """An operating-system failure (a file that cannot be read or written) in one line."""
    where = f" {str(err.filename)!r}" if err.filename else ""
    return f"cannot use{where}: {err.strerror or err}"


class _Group(click.Group):
    """The command group, with click's own usage errors as one ``Error:`` line, exit 1."""

    def main(self, *args, **kwargs):
        kwargs.update(standalone_mode=False, prog_name="registry")  # also for python -m
        try:
            code = super().main(*args, **kwargs)
        except click.exceptions.Abort:
            click.echo("Error: interrupted", err=True)
            sys.exit(130)
        except click.ClickException as err:
            hint = ""
            if isinstance(err, click.UsageError) and err.ctx is not None:
                hint = f" (see: {err.ctx.command_path} --help)"
            click.echo(f"Error: {err.format_message()}{hint}", err=True)
            sys.exit(1)
        sys.exit(code if isinstance(code, int) else 0)


def _registry(create: bool = False) -> Registry:
    """The registry named by --db; only ``add`` creates a database that does not exist."""
    ctx = click.get_current_context()
    if "registry" not in ctx.obj:
        from .api import open_registry

        reg = ctx.with_resource(open_registry(settings.database(ctx.obj["db"]), create=create))
        if reg.upgraded_from is not None:
            click.echo(_upgraded(reg), err=True)
        ctx.obj["registry"] = reg
    return ctx.obj["registry"]


def _every_case(verb: str, unit: str, case_ids: tuple[str, ...], options: dict) -> Any:
    """``reg.<verb>`` over the named cases (default: every case), with ``jobs`` and
    ``scheduler`` checked first, a bar counting each ``unit`` done, and Ctrl-C or SIGTERM
    ending it between records: what ``survey`` and ``identify`` share."""
    from .api import check_where

    check_where(options["jobs"], options["scheduler"])
    reg = _registry()
    with _counting_bar(unit) as progress, reg.interruptible():
        return getattr(reg, verb)(list(case_ids) or None, progress=progress, **options)


def _registry_for(target: str, record: bool) -> Registry | None:
    """The registry a command on "a case file or a stored case's id" needs: none for a
    file handled without --record (no database is needed, and none is created)."""
    if record or not Path(target).is_file():
        return _registry(create=True)
    return _existing_registry()


def _names(text: str) -> tuple[str, ...]:
    """A comma-separated list of names (``--free a,b``), blanks dropped."""
    return tuple(name.strip() for name in text.split(",") if name.strip())


def _existing_registry() -> Registry | None:
    """The registry named by --db if it exists (None otherwise): nothing is created."""
    try:
        return _registry(create=False)
    except DatabaseMissingError:
        return None


def _upgraded(reg: Registry) -> str:
    """What a schema upgrade did, and where the copy made before it is (an SQLite file's;
    on a database server, backing up is the administrator's job)."""
    done = f"Upgraded database {reg.location!r} from schema revision {reg.upgraded_from}"
    if reg.backup is not None:
        return f"{done}; the copy made before is {str(reg.backup)!r}"
    return (
        f"{done} in one transaction; no copy was made before (back up a PostgreSQL "
        "database with pg_dump)"
    )


def _where(what: str):
    """The --jobs and --scheduler options of a command whose work runs in worker processes
    or on a Dask cluster: the same meaning and default in every command."""

    def options(fn):
        fn = click.option(
            "--scheduler",
            metavar="ADDRESS",
            default=None,
            help=f"{what} on a Dask cluster: a scheduler's address (tcp://HOST:PORT) or "
            "scheduler file (FILE.json), or local:N to start N local Dask worker processes "
            f"for this command (default: ${settings.SCHEDULER_ENV}; --jobs overrides the "
            "variable).",
        )(fn)
        return click.option(
            "--jobs",
            type=click.IntRange(min=1),
            default=None,
            help=f"{what} in N worker processes (default: one per core; 1: in this process).",
        )(fn)

    return options


def _print_version(ctx: click.Context, param: click.Parameter, value: bool) -> None:
    """``registry --version``: the release and the code version runs are recorded with."""
    if not value or ctx.resilient_parsing:
        return
    from .api import version

    click.echo(version())
    ctx.exit(0)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.option(
    "--db",
    metavar="PATH|URL",
    default=None,
    help=f"Database file or SQLAlchemy URL (default: ${settings.DB_ENV}, else "
    f"{settings.DEFAULT_DB.as_posix()}).",
)
@click.option("--debug", is_flag=True, help="Show tracebacks instead of one-line errors.")
@click.option(
    "-V",
    "--version",
    is_flag=True,
    expose_value=False,
    is_eager=True,
    callback=_print_version,
    help="Show the package's version and the digest of its code, and exit.",
)
@click.pass_context
def main(ctx: click.Context, db: str | None, debug: bool) -> None:
    """The registry of rigid-body integrability claims.

    Example: registry add data/cases && registry audit
    """
    ctx.ensure_object(dict)
    ctx.obj.update(db=db, debug=debug)  # None: the default (api.default_target), when opened


@main.command()
@click.argument("paths", nargs=-1, required=True, type=click.Path(exists=True))
@_user_errors
def add(paths: tuple[str, ...]) -> None:
    """Load case files (or folders of them) into the registry.

    Each file is stored whole or not at all; a refused file is reported with
    every problem found, and the others are still added.

    Example: registry add data/cases
    """
    results = _registry(create=True).add(*paths)
    refused = [r for r in results if r.status == "refused"]
    for r in results:
        if r.status != "refused":
            click.echo(f"{r.status:12} {r.case} (version {r.version})  {printable(r.path)}")
    counts = Counter(r.status for r in results)
    tally = ", ".join(f"{counts[s]} {s}" for s in ("added", "new version", "unchanged", "refused"))
    click.echo(f"{len(results)} file(s): {tally}")
    for r in refused:
        _report(r.error or RegistryError(f"{r.path}: refused"))
    if refused:
        sys.exit(1)


@main.command()
@click.option("--case", "case_ids", multiple=True, metavar="ID", help="Audit only this case.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON (docs/json-output.md).")
@click.option("--fresh", is_flag=True, help="Recompute instead of reusing stored results.")
@_where("Audit the cases")
@click.option(
    "--budget",
    "check_budget",
    type=click.FloatRange(min=0, min_open=True),
    default=None,
    help=f"Seconds allowed to each check (default ${settings.BUDGET_ENV}, else "
    f"{settings.DEFAULT_CHECK_SECONDS:g}).",
)
@click.option(
    "--corrections-budget",
    "corrections_budget",
    type=click.FloatRange(min=0, min_open=True),
    default=None,
    help="Seconds allowed to the corrections and conditions of each case "
    f"(default ${settings.CORRECTIONS_BUDGET_ENV}, else "
    f"{settings.DEFAULT_CORRECTIONS_SECONDS:g}).",
)
@click.option(
    "--numeric",
    is_flag=True,
    help="Add numerical evidence: drift of each claim along trajectories started on "
    "exactly the claim's level set (its 'on' equations, nothing added).",
)
@click.option(
    "--strict",
    is_flag=True,
    help="Implies --numeric; exit with status 1 when the numbers contradict a claim's "
    "integral verdict (the drift speaks of conservation, never of the Casimir property).",
)
@_user_errors
def audit(
    case_ids: tuple[str, ...],
    as_json: bool,
    fresh: bool,
    jobs: int | None,
    scheduler: str | None,
    check_budget: float | None,
    corrections_budget: float | None,
    numeric: bool,
    strict: bool,
) -> None:
    """Re-check every claim of every case (or the named ones) and store the run.

    Unchanged cases reuse the results stored by the same code version; --fresh
    recomputes them. A check that runs out of time is inconclusive.

    \b
    Numerical evidence (--numeric, --strict) follows these rules; the verdicts
    never change because of the numbers:
    - the drift of I is compared with the claim's integral verdict, whatever its
      kind: a true integral claimed as a Casimir (integral verified, casimir
      refuted) has a flat drift, and that agrees;
    - trajectories start on the set where the symbols decided, the claim's 'on'
      equations and nothing else (no |gamma| = 1 added);
    - drifts are relative to the size of the terms of the expression at the
      start (the sum of their absolute values): a relation that vanishes on its
      set, sampled at large momenta, is judged by the size of its terms;
    - on a level set the flow is proven to keep (invariant verified), each
      trajectory is projected back onto the set after every step (Gauss-Newton
      on the 'on' equations), so a repelling set does not throw it off; the
      departure (largest relative residual of the equations) is recorded;
    - a trajectory whose departure exceeds 1e-8 has left the set and is not
      compared; if none stayed, numeric.reason says so, and nothing is
      contradicted: --strict fails only where the numbers contradict the symbols
      on trajectories that stayed on the set;
    - where the numbers stand on a smaller set (one instance of a family's
      functions, said in the output), a flat drift cannot contradict a refutation.

    \b
    On a Dask cluster (--scheduler, or $REGISTRY_SCHEDULER; --jobs overrides the
    variable): each case is audited in a child process of a Dask worker under the
    same budgets, a case whose worker dies is audited again on another, and the
    results are those of the local workers, case by case.

    Example: registry audit --case yehia-2003-kovalevskaya-b --json
    """
    from .api import check_where, time_budget

    check_where(jobs, scheduler)
    reg = _registry()
    total = reg.count_cases(list(case_ids) or None)
    quiet = as_json or not sys.stderr.isatty()
    bar = _progress_bar(total=total, unit="case", disable=quiet)

    def progress(case_id: str) -> None:
        bar.set_postfix_str(case_id, refresh=False)
        bar.update()

    budget = time_budget(check_budget, corrections_budget)
    try:
        with reg.interruptible():
            report = reg.audit(
                case_ids or None,
                fresh=fresh,
                jobs=jobs,
                budget=budget,
                numeric=numeric or strict,
                progress=progress,
                scheduler=scheduler,
            )
    finally:
        bar.close()
    for event in report.events:
        click.echo(f"note: {event}", err=True)
    if as_json:
        click.echo(json.dumps(report.document(), indent=2, ensure_ascii=False))
    else:
        click.echo(report.table())
    contradicted = report.contradicted()
    if strict and contradicted:
        click.echo(
            f"Error: numerical evidence contradicts the verdict of {', '.join(contradicted)}",
            err=True,
        )
        sys.exit(1)


def _weights(text: str | None) -> dict[str, int] | None:
    """``M=1,gamma=2`` as {"M": 1, "gamma": 2} (None: not given); a click error names what
    is wrong. Which vectors the case's state has is the search's to check."""
    if text is None:
        return None
    found: dict[str, int] = {}
    for part in text.split(","):
        name, _, value = part.partition("=")
        name = name.strip()
        if not name.isidentifier() or not value.strip().isdigit() or int(value) < 1:
            raise click.BadParameter(
                f"{text!r}: expected VECTOR=<positive integer>,... (M=1,gamma=2)",
                param_hint="--weights",
            )
        if name in found:
            raise click.BadParameter(f"{text!r}: {name} given twice", param_hint="--weights")
        found[name] = int(value)
    return found


@main.command()
@click.argument("target", metavar="FILE|ID")
@click.option(
    "--degree",
    type=click.IntRange(min=1),
    default=4,
    show_default=True,
    help="Largest weighted degree of the ansatz.",
)
@click.option(
    "--weights",
    "weights_text",
    default=None,
    metavar="VECTOR=W,...",
    help="Weights of the state's vectors (default: their own; M=1,gamma=2 for the "
    "reference paper's state; a vector not named keeps its default).",
)
@click.option(
    "--on",
    "on",
    multiple=True,
    metavar='"LHS = RHS"',
    help="Integrals on this level set (repeatable, as in claims.on).",
)
@click.option(
    "--free",
    "free_text",
    default="",
    metavar="P,Q",
    help="Parameters whose special values are sought (the others stay generic).",
)
@click.option(
    "--relations",
    is_flag=True,
    help="Search invariant relations F = 0 (Darboux polynomials, dF/dt = K F) instead.",
)
@click.option(
    "--measure",
    is_flag=True,
    help="Search invariant measures rho = prod F_i**a_i over the Darboux polynomials among "
    "the factors of the field (Jacobi's last multiplier) instead.",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON (docs/json-output.md).")
@click.option(
    "--record",
    is_flag=True,
    help="Store the search; its integrals become claims the next audit decides.",
)
@click.option("--fresh", is_flag=True, help="Search again instead of reusing a stored search.")
@click.option(
    "--budget",
    "seconds",
    type=click.FloatRange(min=0, min_open=True),
    default=settings.DEFAULT_SEARCH_SECONDS,
    show_default=True,
    help="Seconds the whole search may take; then what is proven is reported.",
)
@_where("Search the candidate parameter values")
@_user_errors
def discover(
    target: str,
    degree: int,
    weights_text: str,
    on: tuple[str, ...],
    free_text: str,
    relations: bool,
    measure: bool,
    as_json: bool,
    record: bool,
    fresh: bool,
    seconds: float,
    jobs: int | None,
    scheduler: str | None,
) -> None:
    """Search a case (a case file or a stored case's id) for first integrals.

    Finds every polynomial integral of weighted degree <= --degree beyond the known
    ones (H, |gamma|^2, the torque's Casimir; on so(4), so(3,1) kappa|M|^2 + |gamma|^2
    and M.gamma), and, for a family, every set of values of the --free parameters
    (kappa among them, if the case names it) where more exist. Each integral is proven by the
    audit's zero test; "complete" means that no other special values exist for this
    ansatz. Stored searches of the same case version and options are reused.

    Example: registry discover tests/data/families/heavy-top-lam.toml --degree 4 --free lam
    """
    from .api import check_where

    check_where(jobs, scheduler)
    weights = _weights(weights_text)
    free = _names(free_text)
    if measure:
        is_file = Path(target).is_file()
        _measures(target, is_file, as_json, relations or record or bool(free) or bool(on))
        return
    reg = _registry_for(target, record)
    options: dict[str, Any] = dict(
        degree=degree,
        weights=weights,
        on=on,
        free=free,
        relations=relations,
        budget=seconds,
        jobs=jobs,
        scheduler=scheduler,
    )
    with _counting_bar("set", quiet=as_json) as progress:
        if reg is None:
            from .api import discover_file

            report = discover_file(target, progress=progress, **options)
        else:
            with reg.interruptible():
                report = reg.discover(
                    target, record=record, fresh=fresh, progress=progress, **options
                )
    for event in report.events:
        click.echo(f"note: {event}", err=True)
    if as_json:
        click.echo(json.dumps(report.document(), indent=2, ensure_ascii=False))
        return
    click.echo(report.text())
    if report.reused:
        click.echo(f"(reused stored search {report.number}; --fresh searches again)")
    elif report.number is not None:
        click.echo(f"recorded as search {report.number}")
    for case_id in report.derived:
        click.echo(f"  derived case {case_id}: its integrals are claims for the next audit")


def _measures(target: str, is_file: bool, as_json: bool, other_options: bool) -> None:
    """``discover --measure``: the invariant densities of a case file or a stored case."""
    from .api import find_measures, measure_text
    from .errors import UsageError

    if other_options:
        raise UsageError(
            "--measure searches densities on its own: it takes none of --relations, --record, "
            "--free or --on (a density found is added to the case as a claim of kind 'measure')"
        )
    if is_file:
        found = find_measures(target)
    else:
        reg = _existing_registry()
        if reg is None:
            raise UsageError(f"{target!r} is neither a case file nor a stored case")
        with reg:
            found = reg.measures(target)
    if as_json:
        click.echo(json.dumps(found.as_dict(), indent=2, ensure_ascii=False))
    else:
        click.echo(measure_text(found))


@main.command()
@click.option("--case", "case_ids", multiple=True, metavar="ID", help="Search only this case.")
@click.option("--fresh", is_flag=True, help="Search again instead of reusing stored searches.")
@click.option(
    "--budget",
    "seconds",
    type=click.FloatRange(min=0, min_open=True),
    default=settings.DEFAULT_SURVEY_SECONDS,
    show_default=True,
    help="Seconds each search may take; then what is proven is recorded.",
)
@_where("Search, one task per search,")
@_user_errors
def survey(
    case_ids: tuple[str, ...],
    fresh: bool,
    jobs: int | None,
    seconds: float,
    scheduler: str | None,
) -> None:
    """Record a search of every case (or the named ones) at the degree its claims reach.

    \b
    Each case is searched for polynomial integrals beyond H and the bracket's
    Casimirs (|gamma|^2 and the torque's Casimir; on so(4), so(3,1) kappa|M|^2 + |gamma|^2
    and M.gamma):
    - up to the largest weighted degree of its claims (at least 2), with weights
      M=1,gamma=1 for a potential of degree >= 2 in gamma, else M=1,gamma=2 (for a
      case that gives H or kappa, the weights that make its field homogeneous, else
      M=1,gamma=1);
    - on the whole phase space, and on each level set its claims are stated on.
    A system that is not polynomial is recorded as not searched, with the reason.
    What a search finds becomes a claim that the next audit decides; searches
    recorded by this code version are reused. List them with: registry searches

    Example: registry survey --case kovalevskaya-1889-heavy-top
    """
    options = dict(fresh=fresh, budget=seconds, jobs=jobs, scheduler=scheduler)
    reports = _every_case("survey", "search", case_ids, options)
    from .api import survey_text

    if reports:
        click.echo(survey_text(reports))
    fresh_ones = sum(not r.reused for r in reports)
    undecided = sum(not r.search.decided for r in reports)
    click.echo(
        f"{len(reports)} search(es): {fresh_ones} recorded, {len(reports) - fresh_ones} "
        f"reused; {undecided} not decided (see their statements)"
    )


@main.command()
@click.option("--case", "case_ids", multiple=True, metavar="ID", help="Identify only this case.")
@click.option("--fresh", is_flag=True, help="Compare again instead of reusing stored results.")
@click.option(
    "--budget",
    "seconds",
    type=click.FloatRange(min=0, min_open=True),
    default=settings.DEFAULT_IDENTIFY_SECONDS,
    show_default=True,
    help="Seconds each case's comparisons may take; the cases left are named.",
)
@click.option("--json", "as_json", is_flag=True, help="Print a JSON list, one object per case.")
@_where("Compare, one task per case,")
@_user_errors
def identify(
    case_ids: tuple[str, ...],
    fresh: bool,
    seconds: float,
    as_json: bool,
    jobs: int | None,
    scheduler: str | None,
) -> None:
    """Record which catalog cases each case (or the named ones) is the same system as.

    \b
    Two cases are the same system when one's vector field is the other's at some
    values of the other's parameters, after scaling time and each vector, permuting
    and changing the signs of the axes, rotating about an axis of symmetry, or
    shifting M -> M + f(gamma) (adding Casimirs to H changes no field). Each match
    is checked exactly; finding none proves nothing. Results are recorded and shown
    by `registry cases`, `reg.identifications()` and the site.

    Example: registry identify --case kovalevskaya-1889-heavy-top
    """
    from .api import identify_text

    options = dict(fresh=fresh, budget=seconds, jobs=jobs, scheduler=scheduler)
    found = _every_case("identify", "case", case_ids, options)
    if as_json:
        click.echo(json.dumps([f.as_dict() for f in found], indent=2, ensure_ascii=False))
        return
    click.echo(identify_text(found))
    same = sum(bool(f.same_as) for f in found)
    click.echo(
        f"{len(found)} case(s): {same} the same system as some other case; "
        f"{sum(not f.complete for f in found)} not compared with every case"
    )


@main.command()
@click.option("--case", "case_id", default=None, metavar="ID", help="Searches of this case only.")
@click.option(
    "--long", "long_", is_flag=True, help="Each search's result in one sentence, in full."
)
@click.option(
    "--json",
    "as_json",
    is_flag=True,
    help="Print the searches as a JSON list of search documents (docs/json-output.md).",
)
@_user_errors
def searches(case_id: str | None, long_: bool, as_json: bool) -> None:
    """List the recorded integral searches, oldest first: one line each with the case,
    the ansatz (degree, weights, level set, free parameters), whether the search is
    complete, and its result in short.

    Example: registry searches --case kovalevskaya-1889-heavy-top --long
    """
    reg = _registry()
    if as_json:
        documents = reg.search_documents(case_id)
        click.echo(json.dumps(documents, indent=2, ensure_ascii=False))
        return
    click.echo(reg.searches_text(case_id, long=long_))


@main.command()
@click.argument("target", metavar="FILE|ID")
@click.option(
    "--weights",
    "weights_text",
    default=None,
    metavar="VECTOR=W,...",
    help="Weights of the state's vectors (default: the grading that makes the field "
    "homogeneous, else their own: M=1,gamma=2 for the reference paper's state).",
)
@click.option(
    "--free",
    "free_text",
    default="",
    metavar="P,Q",
    help="Parameters whose special values are sought (every other parameter of the field "
    "must be free too).",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON (docs/json-output.md).")
@click.option("--record", is_flag=True, help="Store the analysis with the case version.")
@click.option(
    "--fresh",
    is_flag=True,
    help="Analyse again instead of reusing a stored analysis (one that ran out of a smaller "
    "--budget is analysed again anyway).",
)
@click.option(
    "--budget",
    "seconds",
    type=click.FloatRange(min=0, min_open=True),
    default=settings.DEFAULT_EXPONENT_SECONDS,
    show_default=True,
    help="Seconds the whole analysis may take; past them nothing is established, except "
    "that a system with parameters (a family's generic members) may be shown to fail the "
    "Painlevé test at generic values by a witness at rational ones, sought in the last "
    "quarter, 10 s at most (with "
    "local worker processes a single system is analysed in one, stopped a few seconds "
    "past them; with --jobs 1 or --scheduler in this process, where a long step in FLINT "
    "ends first).",
)
@_where("Analyse the candidate parameter values")
@_user_errors
def exponents(
    target: str,
    weights_text: str | None,
    free_text: str,
    as_json: bool,
    record: bool,
    fresh: bool,
    seconds: float,
    jobs: int | None,
    scheduler: str | None,
) -> None:
    """Kovalevskaya exponents of a case (a case file or a stored case's id).

    Splits the field into weighted-homogeneous parts (the leading part is used, and
    said so, where the field is not homogeneous), finds every balance x = c t^(-w)
    (complex ones too, algebraic numbers exact), its exponents, the weighted degrees
    Yoshida's theorem leaves for first integrals, and the Painlevé (ARS) test. With
    --free, the parameter values where every exponent is an integer, half an integer
    or rational, each with its own analysis. The statement says only what the cited
    theorems prove. A file analysed without --record needs no database.

    Example: registry exponents data/cases/heavy-top/kovalevskaya-1889-heavy-top.toml
    """
    from .api import check_where

    check_where(jobs, scheduler)
    weights = _weights(weights_text)
    free = _names(free_text)
    reg = _registry_for(target, record)
    options: dict[str, Any] = dict(
        weights=weights, free=free, budget=seconds, jobs=jobs, scheduler=scheduler
    )
    if reg is None:
        from .api import analyse_exponents

        report = analyse_exponents(target, **options)
    else:
        with reg.interruptible():
            report = reg.analyse_exponents(target, record=record, fresh=fresh, **options)
    for event in report.events:
        click.echo(f"note: {event}", err=True)
    if as_json:
        click.echo(json.dumps(report.document(), indent=2, ensure_ascii=False))
        return
    click.echo(report.text())
    if report.reused:
        click.echo(f"(reused stored analysis {report.number}; --fresh analyses again)")
    elif report.number is not None:
        click.echo(f"recorded as analysis {report.number}")


def _progress_bar(**options: Any) -> Any:
    """A tqdm bar on stderr, without tqdm's monitor thread: the local pool forks its
    workers from this process, and a fork is safe only where no other thread runs."""
    from tqdm import tqdm

    tqdm.monitor_interval = 0
    return tqdm(file=sys.stderr, leave=False, **options)


@contextmanager
def _counting_bar(unit: str, quiet: bool = False) -> Iterator:
    """A progress bar on stderr (none when it is not a terminal, or ``quiet``), as the
    callback (done, total, what) that searches report to."""
    disable = quiet or not sys.stderr.isatty()
    bar = _progress_bar(total=0, unit=unit, disable=disable)

    def progress(done: int, total: int, where: str) -> None:
        bar.total = total
        bar.n = done
        bar.set_postfix_str(where, refresh=True)

    try:
        yield progress
    finally:
        bar.close()


def _years(text: str | None) -> int | tuple[int, int] | None:
    """``1889`` or ``1880-1900`` (inclusive)."""
    if text is None:
        return None
    first, _, last = text.partition("-")
    if not first.strip().isdigit() or (last and not last.strip().isdigit()):
        raise click.BadParameter(f"{text!r}: expected a year or a range like 1880-1900")
    return (int(first), int(last)) if last else int(first)


@main.command()
@click.option("--source", default=None, help="Text in the citation, title or journal.")
@click.option("--author", default=None, help="Text in an author's name.")
@click.option("--year", "year_text", default=None, metavar="YEAR|FROM-TO", help="Year or range.")
@click.option("--topic", default=None, help="A topic (free rigid body, heavy top, gyrostat, ...).")
@click.option("--family", default=None, help="The torque's family (constant, affine, ...).")
@click.option(
    "--verdict",
    type=click.Choice(VERDICTS),
    default=None,
    help="Cases with a claim of this verdict (in its newest audit).",
)
@_user_errors
def cases(
    source: str | None,
    author: str | None,
    year_text: str | None,
    topic: str | None,
    family: str | None,
    verdict: str | None,
) -> None:
    """List the cases in the registry (latest versions), with their sources.

    Filters combine: --source, --author, --year, --topic, --family, --verdict.

    Example: registry cases --author Kowalevski --year 1880-1900
    """
    text = _registry().cases_text(
        source=source,
        author=author,
        year=_years(year_text),
        topic=topic,
        family=family,
        verdict=verdict,
    )
    click.echo(text)


@main.command()
@click.option("--run", type=int, default=None, help="Verdicts of this run (default: newest).")
@_user_errors
def verdicts(run: int | None) -> None:
    """List the newest verdict of every check and claim.

    Example: registry verdicts --run 3
    """
    click.echo(_registry().verdicts_text(run))


@main.command()
@click.option("--run", type=int, default=None, help="Corrections of this run (default: newest).")
@_user_errors
def corrections(run: int | None) -> None:
    """List torque families, re-checked corrections and parameter conditions.

    Example: registry corrections --run 3
    """
    click.echo(_registry().corrections_text(run))


@main.command()
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["csv", "json", "parquet"]),
    default=None,
    help="Write the tables cases, claims, verdicts, all_results, corrections and runs.",
)
@click.option("--bibtex", is_flag=True, help="Write the sources of the cases as BibTeX.")
@click.option(
    "-o",
    "--output",
    type=click.Path(),
    default=None,
    help="Folder for the tables (default ./export); file for --bibtex (default: standard output).",
)
@_user_errors
def export(fmt: str | None, bibtex: bool, output: str | None) -> None:
    """Publish the registry: its tables as data files, or its sources as BibTeX.

    Example: registry export --format parquet -o export
    """
    if (fmt is None) == (not bibtex):
        raise click.UsageError("give exactly one of --format and --bibtex")
    if fmt is not None:
        for path in _registry().export(output or "export", fmt):
            click.echo(str(path))
        return
    text = _registry().bibtex()
    if output is None:
        click.echo(text, nl=False)
    else:
        Path(output).write_text(text, encoding="utf-8")
        click.echo(output)


@main.command("export-case")
@click.argument("case_id")
@click.option("--claim", default=None, metavar="LABEL", help="The claim whose correction to use.")
@click.option(
    "--kind",
    type=click.Choice(["torque", "casimir"]),
    default="torque",
    show_default=True,
    help="torque: corrected torque, claim kept; casimir: same torque, derived Casimir.",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    default=None,
    help="Write to this file instead of standard output.",
)
@_user_errors
def export_case(case_id: str, claim: str | None, kind: str, output: str | None) -> None:
    """Write a corrected case, from the newest audit, as a new case file.

    Example: registry export-case yehia-2003-kovalevskaya-b --claim I2 -o fixed.toml
    """
    text = _registry().export_case(case_id, claim, kind)
    if output is None:
        click.echo(text, nl=False)
    else:
        with open(output, "w", encoding="utf-8") as f:
            f.write(text)
        click.echo(f"wrote {output}", err=True)


@main.command()
@click.argument("case_id")
@click.argument("claim")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    default=None,
    help="PNG file to write (default: drift-CASE-CLAIM.png).",
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the start point.")
@_user_errors
def plot(case_id: str, claim: str, output: str | None, seed: int) -> None:
    """Plot I(t) - I(0) and H(t) - H(0) of a claim along one integrated trajectory.

    Example: registry plot yehia-2003-kovalevskaya-b I2 -o I2.png
    """
    path = _registry().plot(case_id, claim, output or f"drift-{case_id}-{claim}.png", seed)
    click.echo(str(path))


@main.command("list-checks")
def list_checks() -> None:
    """List the mathematical checks the audit runs, each with the statement it tests.

    (registry verify-db verifies the database instead.)

    Example: registry list-checks
    """
    from .api import checks_text

    click.echo(checks_text())


@main.command()
@click.option("--run", type=int, default=None, help="Report on this run (default: newest).")
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["md", "html", "tex"]),
    default="md",
    show_default=True,
    help="Markdown, one self-contained HTML file, or a LaTeX fragment to \\input.",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    default=None,
    help="Write to this file (default: report.<format> in the current directory).",
)
@click.option(
    "--plots/--no-plots",
    default=True,
    help="Drift plots of refuted claims (PNG next to the file; embedded in HTML).",
)
@click.option(
    "--diff",
    type=(int, int),
    default=None,
    metavar="RUN_A RUN_B",
    help="Instead of a report, list the verdicts that changed between two runs.",
)
@_user_errors
def report(
    run: int | None, fmt: str, output: str | None, plots: bool, diff: tuple[int, int] | None
) -> None:
    """Write a report of one audit run: systems, claims, verdicts, residuals, corrections.

    Prints the path of the file written. With --diff, prints the verdicts that
    changed between two runs instead ("no changes" when none).

    Example: registry report --format html -o audit.html
    """
    from .api import diff_text

    reg = _registry()
    if diff is not None:
        click.echo(diff_text(reg.diff(*diff), *diff))
        return
    path = Path(output or f"report.{fmt}")
    path.parent.mkdir(parents=True, exist_ok=True)
    text = reg.report(run, fmt, out_dir=path.parent, plots=plots)
    path.write_text(text, encoding="utf-8")
    click.echo(str(path))


@main.command()
@click.option(
    "-o",
    "--output",
    type=click.Path(file_okay=False),
    default="site",
    show_default=True,
    help="Folder to write the site into (created if need be).",
)
@click.option(
    "--base-url",
    default="",
    metavar="URL",
    help="Where the site will be served (https://example.org/registry/): each page's "
    "canonical address and the url of a case's BibTeX entry. Links are relative either way.",
)
@_user_errors
def site(output: str, base_url: str) -> None:
    """Write the registry as a static web site: an index with filters, a page per case
    (cases/ID.html, with downloads for Mathematica, Maple and Python), pages per source
    and topic, the searches and the corrections. The same registry gives byte-identical
    files. Prints the folder and how many files it holds.

    Example: registry site -o site && python -m http.server -d site
    """
    written = _registry().site(output, base_url)
    pages = sum(p.suffix == ".html" for p in written)
    click.echo(f"{output}: {len(written)} files, {pages} pages")


@main.command()
@click.option("--host", default="127.0.0.1", show_default=True, help="Address to listen on.")
@click.option("--port", type=int, default=8001, show_default=True, help="Port to listen on.")
@_user_errors
def serve(host: str, port: int) -> None:
    """Browse an SQLite registry live in Datasette (the optional extra 'serve'): every
    table described, any read-only SQL, and canned queries (refuted claims, cases by
    source, the verdicts of a case, what the searches establish). Ctrl-C stops it.

    Example: registry serve --port 8001
    """
    _registry().serve(host, port)


@main.command()
@_user_errors
def runs() -> None:
    """List the audit runs.

    Example: registry runs
    """
    click.echo(_registry().runs_text())


@main.command("verify-db")
@_user_errors
def verify_db() -> None:
    """Verify the database: schema, SQLite integrity and foreign keys (on PostgreSQL,
    the foreign keys by query), that every stored case text matches its hash and
    re-parses, and every stored expression.

    Exits with status 1 when a problem is found.

    Example: registry verify-db
    """
    reg = _registry()
    found = reg.verify_db()
    click.echo(f"database {reg.location!r}, schema revision {found.revision}")
    click.echo(", ".join(f"{n} {name}" for name, n in found.counts.items()))
    click.echo(f"engine: {found.engine}")
    for note in found.notes:
        click.echo(f"note: {note}")
    for problem in found.problems:
        click.echo(f"problem: {problem}")
    if found.problems:
        click.echo(f"Error: {len(found.problems)} problem(s) found in the database", err=True)
        sys.exit(1)
    click.echo("ok: integrity, foreign keys, hashes and every stored expression")


@main.command("copy")
@click.option("--to", "to", metavar="PATH|URL", default=None, help="Copy this registry into DB.")
@click.option(
    "--from", "from_", metavar="PATH|URL", default=None, help="Copy DB into this registry."
)
@_user_errors
def copy_registry(to: str | None, from_: str | None) -> None:
    """Copy a whole registry (every table, ids and history) into a new SQLite file or an
    empty database, from SQLite or PostgreSQL to either.

    The copy is one transaction, checked before it is committed (verify-db's checks,
    and every table's rows and every case hash against the source's): interrupted or
    refused, it leaves the target as it was. The target must be new or empty. This is
    how a registry moves from its SQLite file to a group's PostgreSQL server, and how a
    server is backed up (--to backup.sqlite) and restored (--from backup.sqlite into an
    empty database).

    Example: registry --db data/registry.sqlite copy --to postgresql+psycopg://me@db/registry

    Example: registry --db postgresql+psycopg://me@db/registry copy --from backup.sqlite
    """
    if (to is None) == (from_ is None):
        raise click.UsageError("give exactly one of --to DB and --from DB")
    ctx = click.get_current_context()
    if to is not None:
        source, target = _registry(), to
    else:
        from .api import open_registry

        source = ctx.with_resource(open_registry(from_, create=False))
        target = settings.database(ctx.obj["db"])
    done = source.copy_to(target)
    click.echo(
        f"copied {done.source!r} into {done.target!r} in {done.seconds:.1f} s: {done.described()}"
    )
    click.echo(
        f"verified before the commit: schema revision {done.verification.revision}, "
        "integrity, foreign keys, hashes and every stored expression; the rows of every "
        f"table and the hashes of the {done.case_versions} case versions equal the source's"
    )


@main.command()
@click.option("--reader", "reader", metavar="ROLE", default=None, help="Let ROLE browse and query.")
@click.option(
    "--writer", "writer", metavar="ROLE", default=None, help="Let ROLE also add, audit, search."
)
@click.option("--revoke", "revoke", metavar="ROLE", default=None, help="Take both back from ROLE.")
@click.option(
    "--print-sql", is_flag=True, help="Print the SQL for an administrator instead of running it."
)
@_user_errors
def grant(reader: str | None, writer: str | None, revoke: str | None, print_sql: bool) -> None:
    """Give a role on the PostgreSQL server read or write access to this registry.

    A reader may run every reading command (cases, verdicts, searches, report, export);
    a writer may also add, audit, survey and record searches. Neither may change the
    schema: only the owner of the registry's tables upgrades it, and only the owner (or
    a superuser) may grant. The role must exist on the server.

    Example: registry --db postgresql+psycopg://maintainer@db/registry grant --reader student
    """
    levels: tuple[tuple[Literal["reader", "writer"] | None, str | None], ...] = (
        ("reader", reader),
        ("writer", writer),
        (None, revoke),
    )
    given = [(lvl, r) for lvl, r in levels if r]
    if len(given) != 1:
        raise click.UsageError("give exactly one of --reader ROLE, --writer ROLE, --revoke ROLE")
    ((level, role),) = given
    statements = _registry().grant(role, level, run=not print_sql)
    if print_sql:
        click.echo("\n".join(f"{sql};" for sql in statements))
        return
    what = {"reader": "may now read", "writer": "may now read and write", None: "may no longer use"}
    click.echo(f"role {role!r} {what[level]} the registry ({len(statements)} statements run)")
