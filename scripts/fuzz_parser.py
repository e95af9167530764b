"""Coverage-guided fuzzing of the case-file reader and the expression language.

Runs ``registry.language.casefile.parse_case_text`` and
``registry.language.parser.parse_expression`` on ``--runs`` inputs made by libFuzzer
(through atheris) from a seed corpus: the catalog's case files (``data/cases/**/*.toml``),
the hostile files of ``tests/test_hostile.py`` (its ``HOSTILE`` corpus), every
expression of the catalog and the hostile pieces the tests insert (``TOKENS``,
``PAYLOADS``). An input's first byte chooses the target (even: a case file, odd: an
expression, read in a namespace that declares every parameter and function of the
catalog); the rest is the text, decoded as UTF-8 with invalid bytes kept as lone
surrogates (which the reader must refuse cleanly too).

The property, for every input:

* it loads (a ``Case``, a sympy expression), or it is refused with a
  ``CaseFormatError`` whose message is one line per problem, each starting with the
  file's name, naming the field (only whole-file problems such as invalid TOML have
  none) and at most 400 characters, or with an ``ExpressionError`` of one line that
  quotes the text;
* never another exception (a traceback); never more than ``--time-limit`` seconds of
  processor time (a ``SIGPROF`` timer stops the input and records it; libFuzzer's own
  ``-timeout`` is a wall-clock backstop); never more than ``--memory-mb`` MiB of address
  space beyond what the fuzzing process had after its imports (``RLIMIT_AS`` is set in
  the fuzzing child, so an allocation past it is a ``MemoryError``, recorded); no text
  is run as code (``eval``/``exec`` of text and ``os.system`` are trapped);
* nothing stored: the fuzzer imports only ``registry.language`` (and what it needs),
  never touches a database or the store, and checks at the end that neither
  ``registry.store`` nor SQLAlchemy was ever imported in the fuzzing process.

Why atheris: it drives libFuzzer, which keeps the inputs that reach new code of the
reader (the TOML pre-scan, tomllib, every field check and the expression walker are
instrumented for branch coverage) and mutates those further, with a dictionary of the
language's tokens. The parser's interesting inputs are deep in that code (a valid
TOML table with one expression that passes the text checks and breaks a later one),
which random or grammar-drawn text reaches far less often without that feedback;
Hypothesis with grammars already runs in the suite (``tests/test_hostile.py``), so this
adds what it lacks. atheris ships a wheel for this Python (3.11, manylinux); where it
does not install, the script says so and stops (the Hypothesis property tests remain).

The fuzzing runs in a child process (this script with ``--child``), so that the
address-space limit and a crash of libFuzzer do not take the report with them; a child
stopped early (a libFuzzer timeout or out-of-memory kill) is recorded as a finding and
the fuzzing goes on in a new child until ``--runs`` inputs have run. Each finding's
input is saved in ``OUT/findings/`` (the first three of each kind).

Usage (the documented run: 100,000 inputs in about 2 minutes, some 800 inputs/s on one
core of a quiet machine, 500/s on a loaded one)::

    python scripts/fuzz_parser.py --runs 100000 --out /tmp/fuzz

What it found (issue 34): error lines of up to 800 characters, as the message's quote of
a text was cut before it was escaped (a lone surrogate or a line separator shows as six
characters, an emoji as ten); the cut now counts the escapes, and
``tests/test_hostile.py`` keeps each such file (category ``fuzz``).

Exit status 0 when nothing was found, 1 when something was (listed), 2 when the
fuzzer could not run.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import subprocess
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: Longest input libFuzzer makes (bytes); the catalog's files are at most about 2 KB.
MAX_LEN = 8192
#: Longest error line accepted, in characters (texts are quoted cut to 80).
MAX_LINE = 400
#: Problems without a field: about the whole file, the count of those not listed, or an
#: unknown key at the top (the key is the field).
WHOLE_FILE = re.compile(
    r"invalid TOML: |the file |the text is not valid Unicode |not a regular file|"
    r"cannot read the file |\d+ more problems? not listed|unknown key "
)
#: The name the case texts are parsed under (it must start each error line).
FILE = "fuzz.toml"
#: Inputs saved per kind of finding.
KEEP = 3


# ------------------------------------------------------------------ the parent


def main(argv: list[str] | None = None) -> int:
    args = arguments().parse_args(argv)
    if args.child:
        return child(args)
    try:
        import atheris  # noqa: F401
    except ImportError as err:
        print(f"atheris is not installed ({err}); pip install atheris", file=sys.stderr)
        return 2
    out = Path(args.out)
    (out / "findings").mkdir(parents=True, exist_ok=True)
    seeds = write_seeds(out / "seeds")
    tokens = write_dictionary(out / "tokens.dict")
    corpus = out / "corpus"
    corpus.mkdir(exist_ok=True)
    print(f"{seeds} seed inputs, {tokens} dictionary tokens; {args.runs} runs", flush=True)

    started, done, children, stops = time.monotonic(), 0, 0, []
    while done < args.runs and children < args.max_children:
        children += 1
        ran, stop = run_child(args, out, corpus, args.runs - done, args.seed + children)
        done += ran
        if stop:
            stops.append(stop)
        if ran == 0:  # it could not start: another child would fail the same way
            stops.append("the fuzzing child ran no input")
            break
    seconds = time.monotonic() - started
    return report(out, done, seconds, children, stops)


def arguments() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=100_000, help="inputs to run")
    parser.add_argument("--out", default="fuzz-out", help="folder for corpus and findings")
    parser.add_argument("--seed", type=int, default=1, help="libFuzzer's random seed")
    parser.add_argument(
        "--time-limit", type=float, default=2.0, help="CPU seconds allowed per input"
    )
    parser.add_argument(
        "--memory-mb", type=int, default=2048, help="address space allowed (MiB, after imports)"
    )
    parser.add_argument("--max-children", type=int, default=20, help=argparse.SUPPRESS)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("libfuzzer", nargs="*", help=argparse.SUPPRESS)
    return parser


def run_child(args, out: Path, corpus: Path, runs: int, seed: int) -> tuple[int, str | None]:
    """Fuzz ``runs`` inputs in a child; (inputs run, why it stopped early or None)."""
    stats = out / "stats.json"
    stats.unlink(missing_ok=True)
    command = [
        sys.executable, __file__, "--child", "--out", str(out),
        "--time-limit", str(args.time_limit), "--memory-mb", str(args.memory_mb), "--",
        f"-runs={runs}", f"-seed={seed}", f"-max_len={MAX_LEN}",
        f"-timeout={max(30, int(10 * args.time_limit))}", "-rss_limit_mb=0",
        f"-dict={out / 'tokens.dict'}", f"-artifact_prefix={out / 'findings'}/",
        "-use_value_profile=1", "-print_final_stats=1", "-print_pcs=0",
        str(corpus), str(out / "seeds"),
    ]  # fmt: skip
    log = out / "libfuzzer.log"
    with log.open("a", encoding="utf-8") as stream:
        done = subprocess.run(command, stdout=stream, stderr=subprocess.STDOUT, cwd=ROOT)
    text = log.read_text(encoding="utf-8", errors="replace")
    finished = re.findall(r"Done (\d+) runs in \d+ second", text)
    counted = json.loads(stats.read_text())["inputs"] if stats.exists() else 0
    if done.returncode == 0 and finished:
        return int(finished[-1]), None
    tail = text.strip().splitlines()[-3:]
    return counted, f"fuzzing child stopped (status {done.returncode}): {' / '.join(tail)}"


def write_seeds(folder: Path) -> int:
    """The seed corpus: catalog files, hostile files, expressions and hostile pieces."""
    sys.path.insert(0, str(ROOT))
    from registry.language.casefile import parse_case_text
    from tests import test_hostile

    folder.mkdir(parents=True, exist_ok=True)
    inputs: list[bytes] = []
    files = sorted((ROOT / "data" / "cases").rglob("*.toml"))
    for path in files:
        inputs.append(b"\x00" + path.read_bytes())
    for content, _ in test_hostile.HOSTILE.values():
        data = content.encode("utf-8", "surrogatepass") if isinstance(content, str) else content
        inputs.append(b"\x00" + data[:MAX_LEN])
    texts = set(test_hostile.TOKENS) | set(test_hostile.PAYLOADS)
    for path in files:
        case = parse_case_text(path.read_text(encoding="utf-8"))
        system = case.system
        exprs = [*system.inertia, system.potential, *system.torque, system.kappa]
        exprs += [system.hamiltonian] if system.hamiltonian is not None else []
        for claim in case.claims:
            exprs += [claim.expression, *claim.on]
        texts |= {e.text for e in exprs}
    for text in sorted(texts):
        inputs.append(b"\x01" + text.encode("utf-8", "surrogatepass")[:MAX_LEN])
    for data in inputs:
        (folder / hashlib.sha1(data).hexdigest()).write_bytes(data)
    return len(set(inputs))


#: libFuzzer's dictionary: the format's keys and values, the language's names and
#: operators, and pieces the hostile tests use.
TOKENS = [
    "id", "title", "topic", "aliases", "notes", "[source]", "citation", "doi", "authors",
    "year", "journal", "locator", "[parameters]", "[functions]", "[system]", "inertia",
    "potential", "torque", "hamiltonian", "kappa", "[[claims]]", "label", "kind",
    "expression", "on", "provenance", "integral", "casimir", "positive", "real",
    "nonzero", "integer", "literature", "discovered", "M1", "M2", "M3", "gamma1",
    "gamma2", "gamma3", "s", "pi", "E", "sqrt(", "exp(", "log(", "sin(", "cos(", "tan(",
    "asin(", "atan(", "sinh(", "cosh(", "diff(", "**", "*", "/", "+", "-", "(", ")",
    " = ", "\"", "'", '"""', "[", "]", "{", "}", ",", ".", "#", "\n", "1e", "0x",
    "inf", "nan", "true", "1979-05-27", "\\u", "__", "lambda", "^",
    # characters shown escaped in messages (each takes up to ten characters there)
    "\u2028", "\U0001f600", "\u0430", "\u202e", "\x1b", "\\U0001F600", "\\ud800",
]  # fmt: skip


def write_dictionary(path: Path) -> int:
    """libFuzzer's dictionary file: one quoted token a line, other bytes as \\xNN."""

    def escaped(token: str) -> str:
        plain = lambda c: " " <= c <= "~" and c not in '"\\'  # noqa: E731
        return "".join(c if plain(c) else "".join(f"\\x{b:02x}" for b in c.encode()) for c in token)

    path.write_text("".join(f'"{escaped(t)}"\n' for t in TOKENS), encoding="ascii")
    return len(TOKENS)


def report(out: Path, inputs: int, seconds: float, children: int, stops: list[str]) -> int:
    """Print what was found; 0 when nothing was, 1 otherwise."""
    kinds: dict[str, dict] = {}
    for line in (
        (out / "findings.jsonl").read_text().splitlines()
        if (out / "findings.jsonl").exists()
        else []
    ):
        found = json.loads(line)
        entry = kinds.setdefault(found["kind"], {**found, "count": 0})
        entry["count"] += 1
    rate = inputs / seconds if seconds else 0.0
    print(
        f"{inputs} inputs in {seconds:.0f} s ({rate:.0f} inputs/s), {children} fuzzing "
        f"process(es); corpus {len(list((out / 'corpus').iterdir()))} inputs"
    )
    for stop in stops:
        print(f"stopped: {stop}")
    if not kinds:
        print("found: nothing (every input loaded or was refused with a clean message)")
    for kind, found in sorted(kinds.items()):
        print(f"found {found['count']}x {kind}: {found['detail']} (input: {found['file']})")
    return 1 if kinds or stops else 0


# ------------------------------------------------------------------- the child


class InputTimeout(BaseException):
    """An input ran past the time limit (raised by the SIGPROF handler)."""


def child(args) -> int:
    import resource
    import signal

    import atheris

    with atheris.instrument_imports(include=["registry.language", "tomllib"]):
        from registry.errors import CaseFormatError, ExpressionError
        from registry.language import casefile, parser
        from registry.model import Case

    namespace = catalog_namespace(casefile)
    out = Path(args.out)
    findings = out / "findings.jsonl"
    state = {"inputs": 0, "kept": {}}

    def on_timer(signum, frame):
        raise InputTimeout()

    signal.signal(signal.SIGPROF, on_timer)
    size = int(re.search(r"VmSize:\s+(\d+) kB", Path("/proc/self/status").read_text())[1])
    limit = size * 1024 + args.memory_mb * 2**20
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    trap_code_execution()

    def found(kind: str, detail: str, data: bytes) -> None:
        kept = state["kept"].setdefault(kind, 0)
        name = f"{re.sub(r'[^a-z0-9]+', '-', kind.lower())[:60]}-{hashlib.sha1(data).hexdigest()}"
        if kept < KEEP:
            (out / "findings" / name).write_bytes(data)
            state["kept"][kind] = kept + 1
        with findings.open("a", encoding="utf-8") as stream:
            stream.write(json.dumps({"kind": kind, "detail": detail[:500], "file": name}) + "\n")

    def one_input(data: bytes) -> None:
        state["inputs"] += 1
        if state["inputs"] % 500 == 0:
            write_stats(out, state["inputs"])
        expression = bool(data[:1]) and data[0] & 1 == 1
        text = data[1:].decode("utf-8", "surrogateescape")
        start = time.process_time()
        signal.setitimer(signal.ITIMER_PROF, args.time_limit)
        try:
            if expression:
                problem = check_expression(text, namespace, parser, ExpressionError)
            else:
                problem = check_case(text, casefile, Case, CaseFormatError)
        except InputTimeout:
            problem = ("hang", f"more than {args.time_limit:g} s of processor time")
        except MemoryError:
            problem = ("memory", f"more than {args.memory_mb} MiB of address space")
        except Exception as err:  # noqa: BLE001 - every other exception is a finding
            problem = crash(err)
        finally:
            signal.setitimer(signal.ITIMER_PROF, 0)
        spent = time.process_time() - start
        if problem is None and spent > args.time_limit:
            problem = ("hang", f"{spent:.1f} s of processor time")
        if problem is not None:
            target = "expression" if expression else "case file"
            found(f"{target}: {problem[0]}", problem[1], data)

    atheris.Setup([sys.argv[0], *args.libfuzzer], one_input)
    import atexit

    atexit.register(lambda: write_stats(out, state["inputs"]))
    atheris.Fuzz()
    return 0


def write_stats(out: Path, inputs: int) -> None:
    """How many inputs this child ran, and whether the store was ever imported."""
    stored = sorted(m for m in sys.modules if m.startswith(("registry.store", "sqlalchemy")))
    part = out / "stats.json.part"
    part.write_text(json.dumps({"inputs": inputs, "store_modules": stored}))
    part.replace(out / "stats.json")
    if stored:  # the property "nothing stored" is broken: say it loudly
        raise SystemExit(f"the fuzzer imported the store: {', '.join(stored)}")


def catalog_namespace(casefile):
    """Every parameter and function that the catalog's cases declare, in one namespace."""
    parameters, functions = {}, {}
    for path in sorted((ROOT / "data" / "cases").rglob("*.toml")):
        case = casefile.parse_case_text(path.read_text(encoding="utf-8"))
        for name, symbol in case.parameters.items():
            parameters.setdefault(name, symbol)
        for name, function in case.functions.items():
            functions.setdefault(name, function)
    from registry.language.parser import Namespace

    return Namespace(parameters, functions)


def check_case(text: str, casefile, case_type, error_type) -> tuple[str, str] | None:
    """None when the text loads or is refused cleanly; else (kind, detail)."""
    try:
        loaded = casefile.parse_case_text(text, FILE)
    except error_type as err:
        lines = str(err).splitlines()
        if not err.problems or len(lines) != len(err.problems):
            return "message", f"{len(err.problems)} problems in {len(lines)} lines: {lines[:3]}"
        for line, problem in zip(lines, err.problems, strict=True):
            if not line.startswith(f"{FILE}: ") or len(line) > MAX_LINE:
                return "message", f"badly formed line {line[:200]!r}"
            if not problem.field and not WHOLE_FILE.match(problem.message):
                return "message", f"a problem without a field: {line[:200]!r}"
        return None
    if not isinstance(loaded, case_type):
        return "result", f"parse_case_text returned {type(loaded).__name__}"
    return None


def check_expression(text: str, namespace, parser, error_type) -> tuple[str, str] | None:
    try:
        value = parser.parse_expression(text, namespace)
    except error_type as err:
        message = str(err)
        if err.text != text or not err.message:
            return "message", f"the error does not quote the text: {message[:200]!r}"
        if "\n" in message or len(message) > MAX_LINE:
            return "message", f"not one short line: {message[:200]!r}"
        return None
    import sympy

    if not isinstance(value, sympy.Expr):
        return "result", f"parse_expression returned {type(value).__name__}"
    return None


def crash(err: BaseException) -> tuple[str, str]:
    """(kind, detail) of an unexpected exception: its type and where in our code or
    tomllib it was raised (the innermost such frame)."""
    frames = traceback.extract_tb(err.__traceback__)
    ours = [f for f in frames if "/registry/" in f.filename or "/tomllib/" in f.filename]
    where = ours[-1] if ours else (frames[-1] if frames else None)
    at = f"{Path(where.filename).name}:{where.lineno}" if where else "?"
    last = frames[-1] if frames else None
    inner = f" (raised in {Path(last.filename).name}:{last.lineno})" if last else ""
    return f"{type(err).__name__} at {at}", f"{str(err)[:300]}{inner}"


def trap_code_execution() -> None:
    """Make ``eval``/``exec`` of text and ``os.system`` fail loudly (a finding)."""
    import builtins

    real = {name: getattr(builtins, name) for name in ("eval", "exec")}

    def guarded(name):
        def run(source, *args, **kwargs):
            if isinstance(source, str | bytes):
                raise AssertionError(f"{name} of text was called")
            return real[name](source, *args, **kwargs)

        return run

    def no_system(*args, **kwargs):
        raise AssertionError("os.system was called")

    builtins.eval = guarded("eval")
    builtins.exec = guarded("exec")
    os.system = no_system


if __name__ == "__main__":
    sys.exit(main())
