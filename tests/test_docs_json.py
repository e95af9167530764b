"""docs/json-output.md, the contract of the JSON that scripts read, stays true.

Each JSON example on the page is the output of the command named in the marker before
it (``<!-- output of: registry audit --case ID --json -->``). The test runs that command
on the catalog's case in a folder and database of its own, and checks key by key that
every key the example shows exists in the real output, with the same JSON type, at the
same place; and that every key the real output has is named on the page (in backticks),
so a key added to the output without a word in the contract fails here.

To refresh the examples after a change of the output: ``python -m tests.test_docs_json``
prints each marked command's output now, to paste over the page's.
"""

from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import pytest

from tests.helpers.docs import DOCS, blocks, catalog_file, prepare, run
from tests.helpers.processes import registry_command

PAGE = DOCS / "json-output.md"
MARK = re.compile(r"output of: (?P<command>registry .*)")

#: Objects whose keys are data, not part of the shape: a witness point's coordinates
#: and parameters, the concrete functions of a family's refutation, the weights of a
#: state's vectors and the leading part's components (named as the case names them), a
#: catalog case's parameter values and its variables under a transformation.
DATA_KEYED = {"point", "functions", "weights", "leading", "values", "transformation"}


def examples() -> list[tuple[str, str]]:
    """(command, JSON text) of every JSON example, in the page's order."""
    found = []
    for block in blocks(PAGE):
        if block.lang != "json":
            continue
        marked = MARK.fullmatch(block.marker)
        assert marked, f"{block.where}: a JSON example must name the command that printed it"
        found.append((marked["command"], block.text))
    return found


EXAMPLES = examples()


def real_output(command: str, folder: Path) -> dict:
    """The output of ``command`` (``registry ...``) run in ``folder``: the cases named by
    ``--case`` are added from the catalog first, into a database of the folder's own
    (and surveyed, for ``registry searches``)."""
    env = prepare(folder)
    db = Path(env["REGISTRY_DB"])
    words = shlex.split(command)
    cases = [words[i + 1] for i, w in enumerate(words) if w == "--case"]
    if cases:
        files = [str(catalog_file(c)) for c in cases]
        added = run(registry_command(db, "add", *files), folder, env)
        assert added.returncode == 0, added.stdout
    if words[1] == "searches":  # the recorded searches: the survey records them first
        survey = [a for c in cases for a in ("--case", c)]
        surveyed = run(registry_command(db, "survey", "--jobs", "1", *survey), folder, env)
        assert surveyed.returncode == 0, surveyed.stdout
    done = run(registry_command(db, *words[1:]), folder, env, merge=False)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def json_type(value: object) -> str:
    return {dict: "object", list: "array", str: "string", bool: "boolean", int: "integer"}.get(
        type(value), "null" if value is None else "number"
    )


def differences(shown: object, real: object, where: str = "$") -> list[str]:
    """Where ``real`` lacks a key of ``shown``, or holds a value of another type."""
    if json_type(shown) != json_type(real):
        return [f"{where}: {json_type(shown)} in the doc, {json_type(real)} in the output"]
    found = []
    if isinstance(shown, dict):
        for key, value in shown.items():
            if key not in real:
                found.append(f"{where}.{key}: in the doc, not in the output")
            else:
                found += differences(value, real[key], f"{where}.{key}")
    elif isinstance(shown, list) and shown:
        if not real:
            return [f"{where}: an empty array in the output, not in the doc"]
        for i, (a, b) in enumerate(zip(shown, real, strict=False)):
            found += differences(a, b, f"{where}[{i}]")
    return found


def keys(value: object) -> set[str]:
    """Every key of a JSON value, at any depth (not those of data-keyed objects)."""
    if isinstance(value, dict):
        inner = [keys(v) for k, v in value.items() if k not in DATA_KEYED]
        return set(value).union(*inner)
    if isinstance(value, list):
        return set().union(*map(keys, value))
    return set()


def test_the_page_has_its_examples():
    commands = [c for c, _ in EXAMPLES]
    assert any(c.startswith("registry audit ") for c in commands)
    assert any(c.startswith("registry discover ") for c in commands)
    assert any(c.startswith("registry searches ") for c in commands)
    assert all(c.endswith(" --json") or " --json " in c for c in commands)


@pytest.mark.parametrize(("command", "text"), EXAMPLES, ids=[c for c, _ in EXAMPLES])
def test_every_key_of_the_example_is_in_the_real_output(command, text, tmp_path):
    shown = json.loads(text)
    real = real_output(command, tmp_path)
    assert differences(shown, real) == []
    page = PAGE.read_text(encoding="utf-8")
    undocumented = sorted(k for k in keys(real) if f"`{k}`" not in page)
    assert undocumented == [], "keys of the output that the page does not name"


def test_the_comparison_can_fail():
    """A key renamed, a type changed, an array emptied: each is found."""
    real = {"run": 1, "cases": [{"case": "x", "checks": {"jacobi": "verified"}}]}
    assert differences(real, real) == []
    assert differences({"runs": 1}, real) == ["$.runs: in the doc, not in the output"]
    assert differences({"run": "1"}, real) == ["$.run: string in the doc, integer in the output"]
    shown = {"cases": [{"checks": {"jacobi": "verified"}}]}
    assert differences(shown, {"cases": []}) == [
        "$.cases: an empty array in the output, not in the doc"
    ]
    assert keys(real) == {"run", "cases", "case", "checks", "jacobi"}


if __name__ == "__main__":  # python -m tests.test_docs_json: the examples as printed now
    import tempfile

    for command, _ in EXAMPLES:
        with tempfile.TemporaryDirectory() as folder:
            print(f"<!-- output of: {command} -->")
            print("```json")
            print(json.dumps(real_output(command, Path(folder)), indent=2, ensure_ascii=False))
            print("```\n")
