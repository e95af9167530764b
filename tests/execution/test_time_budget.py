"""Time budgets: the timer interrupts Python code and is lifted afterwards, and a check
that runs out of time is inconclusive within its budget."""

import signal
import time
from dataclasses import replace

import pytest
import sympy as sp

from registry import Verdict, audit_case, load_case
from registry.execution.time_budget import AGAIN, BudgetExceeded, TimeBudget, time_limit
from registry.model import Expression
from tests.helpers.clocks import HANG, cpu_bound
from tests.helpers.samples import CASES


def test_time_limit_interrupts_python_code():
    # the timer counts wall-clock time, during which the loop uses at most as much CPU time
    with cpu_bound(1.5), pytest.raises(BudgetExceeded):
        with time_limit(0.3):
            while True:
                pass


def test_a_budget_run_out_inside_a_c_extensions_callback_is_still_a_budget_exceeded():
    # CPython reports an exception raised in Python code a C extension called back
    # (symengine asking a sympy object for its parts) as a SystemError caused by it
    with pytest.raises(BudgetExceeded):
        with time_limit(5):
            try:
                raise BudgetExceeded
            except BudgetExceeded as err:
                raise SystemError("returned a result with an exception set") from err
    # any other SystemError is left as it is
    with pytest.raises(SystemError, match="a bug elsewhere"):
        with time_limit(5):
            raise SystemError("a bug elsewhere")


def test_a_budget_exceeded_swallowed_inside_the_block_still_ends_it_so():
    # sympy catches Exception around some C callbacks: a BudgetExceeded arriving there as
    # a SystemError is swallowed and the computation goes on past its time
    finished = []
    with cpu_bound(1.5), pytest.raises(BudgetExceeded):
        with time_limit(0.1):
            try:
                while True:
                    pass
            except BudgetExceeded as err:  # what sympy's except Exception does to it
                swallowed = SystemError("returned a result with an exception set")
                swallowed.__cause__ = err
            finished.append(True)
    assert finished == [True]


def test_a_signal_python_dropped_comes_again_until_the_block_ends():
    """A signal that lands in a garbage collector's weakref callback is printed and
    dropped by Python (SQLAlchemy's ``_collection_gced`` once swallowed the 1 s budget of
    an audit check, which then ran past 20 s of CPU time). Here the first interrupt is
    dropped by hand; the timer comes again and ends the block within a second."""
    dropped = []
    begun = time.monotonic()
    with cpu_bound(5), pytest.raises(BudgetExceeded):
        with time_limit(0.1):
            while time.monotonic() - begun < 30:
                if dropped:
                    continue
                try:
                    sum(range(1000))
                except BudgetExceeded:
                    dropped.append(True)  # what Python does in a weakref callback
    assert dropped == [True] and time.monotonic() - begun < 0.1 + AGAIN + 0.5


def test_a_cleanup_on_the_way_out_is_not_cut_short_by_the_signal_that_comes_again():
    """A worker pool stops its processes in a ``finally`` as the BudgetExceeded passes
    through: the signal that comes again every AGAIN seconds leaves that alone."""
    cleaned = []
    with cpu_bound(5), pytest.raises(BudgetExceeded):
        with time_limit(0.05):
            try:
                while True:
                    pass
            finally:
                begun = time.monotonic()
                while time.monotonic() - begun < 2 * AGAIN + 0.2:
                    pass
                cleaned.append(True)
    assert cleaned == [True]


def test_a_budget_spent_before_the_block_begins_leaves_no_timer_behind():
    """A budget of 1e-9 s fires before the block's first line: the block still ends in
    BudgetExceeded and its timer, which fires again until the block ends, is stopped."""
    handler = signal.getsignal(signal.SIGALRM)
    for _ in range(20):
        with pytest.raises(BudgetExceeded):
            with time_limit(1e-9):
                while True:
                    pass
        assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
        assert signal.getsignal(signal.SIGALRM) is handler


def test_time_limit_is_lifted_afterwards():
    handler = signal.getsignal(signal.SIGALRM)
    with time_limit(5):
        assert signal.getitimer(signal.ITIMER_REAL)[0] > 0
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)  # no stray alarm
    assert signal.getsignal(signal.SIGALRM) is handler
    # the same after a block that ran out of time
    with cpu_bound(10), pytest.raises(BudgetExceeded):
        with time_limit(0.05):
            assert signal.getitimer(signal.ITIMER_REAL)[0] > 0
            while True:
                pass
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
    assert signal.getsignal(signal.SIGALRM) is handler


def test_an_inner_block_ends_no_later_than_the_enclosing_one():
    # an inner budget of 30 s inside an outer one of 0.3 s: the outer one's time counts
    with cpu_bound(3), pytest.raises(BudgetExceeded):
        with time_limit(0.3):
            with time_limit(30):
                assert signal.getitimer(signal.ITIMER_REAL)[0] <= 0.3
                while True:
                    pass
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_the_enclosing_timer_goes_on_after_an_inner_block():
    # an inner block that ends (at once, or caught running out of the outer time) leaves
    # the outer one's timer running: before, its end switched the outer limit off
    with cpu_bound(3), pytest.raises(BudgetExceeded):
        with time_limit(0.3):
            with time_limit(0.1):
                pass
            assert 0 < signal.getitimer(signal.ITIMER_REAL)[0] <= 0.3
            while True:
                pass
    with cpu_bound(3), pytest.raises(BudgetExceeded):
        with time_limit(0.3):
            try:
                with time_limit(30):
                    while True:
                        pass
            except BudgetExceeded:  # a stage that records "not decided" and goes on
                pass
            end = time.monotonic() + 0.5
            while time.monotonic() < end:  # interrupted, or the block ends so at its end
                pass
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_a_processor_time_limit_counts_this_process_and_is_lifted_afterwards():
    handler = signal.getsignal(signal.SIGPROF)
    with cpu_bound(10), pytest.raises(BudgetExceeded):
        with time_limit(0.2, cpu=True):
            assert signal.getitimer(signal.ITIMER_PROF)[0] > 0
            assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)  # not the wall clock
            while True:
                pass
    assert signal.getitimer(signal.ITIMER_PROF) == (0.0, 0.0)
    assert signal.getsignal(signal.SIGPROF) is handler


def test_an_expression_crafted_to_take_forever_ends_inconclusive_within_its_budget():
    case = load_case(CASES / "zhukovsky-gyrostat.toml")
    g1, g2, g3 = sp.symbols("gamma1 gamma2 gamma3", real=True)
    k1 = case.parameters["k1"]
    linear = g1 + g2 + g3 + k1 + 1
    # identically zero, so no probe refutes it, but a proof must expand two powers
    # of five-variable polynomials into ~10**5 terms each
    zero = linear**40 - sp.expand(linear**2) ** 20
    expr = case.claims[0].expression.expr + zero
    claim = replace(case.claims[0], expression=Expression("crafted", expr))
    # two checks of 1 s, the corrections' 1 s and the cheap checks: seconds of CPU time, where
    # the proof without its budget would take minutes
    with cpu_bound(20):
        audit = audit_case(
            replace(case, claims=(claim,)), budget=TimeBudget(check=1.0, corrections=1.0)
        )
    for check in ("integral", "casimir"):
        result = audit.result(check, claim.label)
        assert result.verdict is Verdict.INCONCLUSIVE
        assert result.reason == "time budget exceeded (1 s)"
        # the reason names the 1 s budget; the audit's own wall-clock figure says that the
        # alarm stopped the check (on a busy machine it may come seconds late, after a
        # long call into C returns), not after the minutes the proof would take
        assert result.seconds < HANG


def test_a_workers_deadline_covers_every_check_the_corrections_and_a_margin():
    budget = TimeBudget(check=2.0, corrections=5.0, margin=1.0)
    assert budget.case_deadline(10) == 2.0 * 10 + 5.0 + 1.0
    assert TimeBudget() == TimeBudget(check=5.0, corrections=20.0, margin=10.0)


def test_the_default_budgets_may_come_from_the_environment(monkeypatch):
    from registry.errors import SettingError
    from registry.execution.time_budget import default_budget

    assert default_budget({}) == TimeBudget()
    both = {"REGISTRY_BUDGET": " 60 ", "REGISTRY_CORRECTIONS_BUDGET": "300"}
    assert default_budget(both) == TimeBudget(check=60.0, corrections=300.0)
    for bad in ("abc", "0", "-1", "inf", "nan"):
        with pytest.raises(SettingError) as caught:
            default_budget({"REGISTRY_CORRECTIONS_BUDGET": bad})
        assert str(caught.value) == (
            f"$REGISTRY_CORRECTIONS_BUDGET must be a positive number of seconds, not {bad!r} "
            "(unset it for the built-in default)"
        )
    # an audit given no budget takes the environment's; one given a budget keeps it
    case = load_case(CASES / "yehia-2003-kovalevskaya-b.toml")
    monkeypatch.setenv("REGISTRY_CORRECTIONS_BUDGET", "1e-9")
    cut = audit_case(case, checks=["integral"], corrections=True)
    assert cut.family.reason == "corrections: time budget exceeded (1e-09 s)"
    kept = audit_case(
        case, checks=["integral"], corrections=True, budget=TimeBudget(corrections=600)
    )
    assert kept.family.name == "psi-gamma-grad-phi"  # found, with time to do it
