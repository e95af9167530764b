"""``registry exponents`` (docs/cli.md; its JSON: docs/json-output.md and the contract's
section "Kovalevskaya exponents"): the document's keys and types, the text, a file
analysed without a database, a stored case recorded and reused, a family on worker
processes, and each user error as one ``Error:`` line naming the file, field and text."""

from __future__ import annotations

import json

from click.testing import CliRunner

import registry
from registry.cli import main
from tests.helpers.samples import CASES, CLASSICAL, TEST_DATA

KOVALEVSKAYA = str(CLASSICAL / "kovalevskaya-top.toml")
EXPONENTS = TEST_DATA / "exponents"


def run(*args: str):
    return CliRunner().invoke(main, list(args))


def test_the_json_has_the_contract_keys_with_their_types(tmp_path):
    result = run("--db", str(tmp_path / "none.sqlite"), "exponents", KOVALEVSKAYA, "--json")
    assert result.exit_code == 0, result.output
    d = json.loads(result.stdout)
    assert d["case"] == "test-kovalevskaya-top"
    assert d["weights"] == {"M": 1, "gamma": 2}  # by vector, as --weights names them
    assert d["homogeneous"] is True and d["free"] == []
    first = d["balances"][0]
    assert set(first["point"]) == {"M1", "M2", "M3", "gamma1", "gamma2", "gamma3"}
    assert first["exponents"] == ["-1", "0", "1", "2", "3", "4"]
    assert first["integer"] is True and first["rational"] is True
    assert d["all_integer"] is True and d["degrees"] == [1, 2, 3, 4]
    assert d["painleve"]["passes"] is True and d["painleve"]["conditions"] == []
    assert "Yoshida" in d["statement"] and isinstance(d["seconds"], float)
    assert not (tmp_path / "none.sqlite").exists()  # a file needs no database


def test_the_text_names_each_balance_and_the_verdicts():
    result = run("exponents", KOVALEVSKAYA)
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[0] == "test-kovalevskaya-top: Kovalevskaya exponents (weights M=1,gamma=2)"
    assert "    exponents: -1, 0, 1, 2, 3, 4 (integers)" in lines
    assert "degrees (Yoshida): 1, 2, 3, 4" in lines
    assert "Painlevé (ARS) test: passes" in lines


def test_a_logarithmic_branch_is_reported_with_its_condition():
    path = str(EXPONENTS / "log-branch.toml")
    result = run("exponents", path, "--weights", "x=1,y=3,z=2", "--json")
    assert result.exit_code == 0, result.output
    d = json.loads(result.stdout)
    assert d["painleve"]["passes"] is False
    assert d["painleve"]["conditions"][0]["condition"] == "-f4**2 = 0"


def test_a_stored_case_is_recorded_then_reused(tmp_path):
    db = str(tmp_path / "r.sqlite")
    assert run("--db", db, "add", KOVALEVSKAYA).exit_code == 0
    first = run("--db", db, "exponents", "test-kovalevskaya-top", "--record")
    assert first.exit_code == 0, first.output
    assert first.stdout.splitlines()[-1] == "recorded as analysis 1"
    again = run("--db", db, "exponents", "test-kovalevskaya-top", "--json")
    d = json.loads(again.stdout)
    assert d["analysis"] == 1 and d["reused"] is True


def test_a_family_runs_its_candidates_in_worker_processes():
    path = str(TEST_DATA / "families" / "symmetric-top-n.toml")
    result = run("exponents", path, "--free", "n", "--jobs", "2", "--json")
    assert result.exit_code == 0, result.output
    d = json.loads(result.stdout)
    assert d["free"] == ["n"]
    assert [s["when"] for s in d["special"]][:3] == [["n = 1"], ["n = 2"], ["n = 4"]]
    assert d["complete"]["integer"] is True


def test_several_free_parameters_list_the_sets_where_the_test_passes_on_workers():
    """Two free parameters on two worker processes: the text lists the sets where the
    Painlevé test passes (Lagrange's top and the spherical top) and says it is complete."""
    path = str(TEST_DATA / "families" / "heavy-top-c-x0.toml")
    result = run("exponents", path, "--free", "c,x0", "--jobs", "2", "--budget", "120")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("Painlevé (ARS) test passes"))
    end = lines.index("complete: yes", start)  # complete: every other value fails
    found = [line.strip() for line in lines[start + 1 : end] if not line.startswith("      ")]
    assert found == ["c = 1 (x0 free)", "x0 = 0 (c free)"]


def test_the_sets_with_half_integer_exponents_name_goryachev_chaplygins_plane(tmp_path):
    """Moments (1, 1, 1/4), centre anywhere: the text lists where every exponent is in
    (1/2)Z, Goryachev and Chaplygin's z0 = 0 marked half-integer beside Lagrange's axis;
    with both lists complete the grid of small values is not searched, and the statement
    says where the exponents leave (1/2)Z."""
    path = str(TEST_DATA / "families" / "goryachev-chaplygin-moments-centre.toml")
    none = str(tmp_path / "none.sqlite")  # no registry: the sets are not named
    result = run("--db", none, "exponents", path, "--free", "x0,y0,z0", "--budget", "120")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("every exponent in (1/2)Z"))
    end = lines.index("complete: yes", start)
    found = [line.strip() for line in lines[start + 1 : end] if not line.startswith("      ")]
    assert found == ["z0 = 0 (x0, y0 free) [half-integer]", "x0 = 0, y0 = 0 (z0 free) [integer]"]
    plane = lines[start + 2 : next(i for i in range(start + 2, end) if "x0 = 0, y0" in lines[i])]
    assert any("exponents -1, -1/2, 3/2, 2, 3, 4" in line for line in plane)
    statement = " ".join(result.stdout.split())
    assert "some exponent half an odd integer on: z0 = 0 (x0, y0 free)" in statement
    assert "outside these sets some exponent is not in (1/2)Z" in statement
    assert "small values not searched one by one" in statement
    d = json.loads(run("--db", none, "exponents", path, "--free", "x0,y0,z0", "--json").stdout)
    assert d["special"] == [] and d["half_integer_sets"]["complete"]
    assert all("same_as" not in s for s in d["half_integer_sets"]["sets"])
    assert [s["when"] for s in d["painleve_sets"]["passing"]] == [["x0 = 0", "y0 = 0"]]
    empty = tmp_path / "empty.sqlite"  # a registry without cases names none either
    registry.open(empty).close()
    assert empty.exists()
    text = run("--db", str(empty), "exponents", path, "--free", "x0,y0,z0").stdout
    assert "catalog" not in text and "z0 = 0 (x0, y0 free) [half-integer]" in text


def test_with_a_registry_each_set_found_is_named_by_the_cases_it_is(tmp_path):
    """With Goryachev and Chaplygin's and Lagrange's tops stored, the plane z0 = 0 of the
    family with moments (1, 1, 1/4) is the same system as the first (its centre rotated
    onto the first axis and scaled) and not the second, and Lagrange's axis the second."""
    db = str(tmp_path / "r.sqlite")
    tops = [
        CASES / "goryachev-chaplygin-1900.toml",
        CASES / "heavy-top/lagrange-1788-heavy-top.toml",
    ]
    assert run("--db", db, "add", *map(str, tops)).exit_code == 0
    path = str(TEST_DATA / "families" / "goryachev-chaplygin-moments-centre.toml")
    result = run("--db", db, "exponents", path, "--free", "x0,y0,z0", "--json")
    assert result.exit_code == 0, result.output
    d = json.loads(result.stdout)
    named = {tuple(s["when"]): s["same_as"] for s in d["half_integer_sets"]["sets"]}
    assert named == {
        ("z0 = 0",): ["goryachev-chaplygin-1900"],
        ("x0 = 0", "y0 = 0"): ["lagrange-1788-heavy-top"],
    }
    (axis,) = d["painleve_sets"]["passing"]
    assert axis["same_as"] == ["lagrange-1788-heavy-top"]
    text = run("--db", db, "exponents", path, "--free", "x0,y0,z0").stdout
    assert "      same as goryachev-chaplygin-1900" in text.splitlines()


def test_user_errors_are_one_line_each_naming_file_field_and_text():
    result = run("exponents", KOVALEVSKAYA, "--weights", "omega=1", "--free", "q")
    assert result.exit_code == 1
    assert result.stderr.splitlines() == [
        f"Error: {KOVALEVSKAYA}: --weights: names a vector the case's state does not have "
        "(its vectors: M, gamma): 'omega'",
        f"Error: {KOVALEVSKAYA}: --free: names a parameter the case does not declare (its "
        "parameters: c): 'q'",
    ]
    broken = str(EXPONENTS / "non-polynomial.toml")
    result = run("exponents", broken)
    assert result.exit_code == 1
    assert [line.split(": ")[2] for line in result.stderr.splitlines()] == ["dM1/dt", "dM2/dt"]
    result = run("exponents", KOVALEVSKAYA, "--weights", "M=one")
    assert result.exit_code == 1
    assert result.stderr.startswith("Error: Invalid value for --weights: 'M=one'")
    result = run("exponents", KOVALEVSKAYA, "--jobs", "2", "--scheduler", "local:1")
    assert result.exit_code == 1 and "not both" in result.stderr


def test_the_text_fits_the_terminal():
    result = CliRunner().invoke(
        main, ["exponents", KOVALEVSKAYA], env={"COLUMNS": "60"}, catch_exceptions=False
    )
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert max(map(len, lines)) <= 60
    assert "degrees (Yoshida): 1, 2, 3, 4" in lines
    text = " ".join(line.strip() for line in lines)
    assert "every compatibility condition holds): necessary for the Painlevé property" in text
