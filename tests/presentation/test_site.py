"""The static site (``registry site``), tested on the files and in a real headless Chromium.

One database is built per module: the three seed cases, a renamed case (its old id is an
alias), two cases in Hamiltonian form (so(3,1), and kappa a parameter), and a hostile case
whose title, notes, citation, DOI, URL and topic carry markup and quotes; audited in this
process, with a recorded search of Zhukovsky's gyrostat. The site is built twice
(byte-identical, and once more in another process) and served from 127.0.0.1 by
``http.server``.

In the browser (Debian's ``chromium`` and ``chromedriver``, driven by Selenium): the index
and case pages load, every MathML formula renders with a non-zero size, the filters change
the visible rows (and with scripts off the full table shows), an alias page redirects, a
crawl from the index reaches every page of the site and finds no broken link (each link's
target fetched from the server, each anchor found), and no injected script runs. A
screenshot of a case page is kept in ``test-artifacts/`` (ignored by git; its path is
printed). Every internal link of every page is also checked on the files. Under
``REGISTRY_CI`` a missing Chromium fails these tests instead of skipping them.
"""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import urllib.request
from functools import partial
from html.parser import HTMLParser
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from types import SimpleNamespace
from urllib.parse import unquote, urlparse

import pytest
import sympy as sp
from click.testing import CliRunner

import registry
from registry.cli import main
from registry.language.casefile import parse_case_text
from registry.model import ExponentOptions, ExponentResult
from registry.presentation import site
from registry.presentation.site import bracket
from tests.helpers.samples import (
    AFFINE,
    CASES,
    FAMILIES,
    HAMILTONIAN,
    SEED,
    TEST_DATA,
    YEHIA_B,
    ZHUKOVSKY,
)

ROOT = Path(__file__).resolve().parents[2]
ARTIFACTS = ROOT / "test-artifacts"
CHROMIUM = os.environ.get("REGISTRY_CHROMIUM", "/usr/bin/chromium")
CHROMEDRIVER = os.environ.get("REGISTRY_CHROMEDRIVER", "/usr/bin/chromedriver")
RENAMED = "zhukovsky-1885-renamed-gyrostat"
SO31 = "test-kovalevskaya-so31"  # Hamiltonian form, kappa = -1
SO4 = "test-kovalevskaya-so4"  # Hamiltonian form, kappa a parameter
#: the heavy top (2, 3, 4), (1, 2, a): minutes over Q(a), a witness at one a in a second
WITNESSED = TEST_DATA / "exponents" / "heavy-top-centre-a.toml"
HOSTILE_ID = "hostile-2024-markup"
#: A family whose special set (Sretenskii's gyrostat) is the affine torque at some values.
GYROSTATS = "goryachev-chaplygin-gyrostat"
GYROSTATS_SEARCH = dict(
    degree=3,
    weights={"M": 1, "gamma": 2},
    on=["M1*gamma1 + M2*gamma2 + M3*gamma3 + k1*gamma1 + k2*gamma2 + k3*gamma3 = 0"],
    free=["k1", "k2", "k3"],
)
PAYLOAD = "<script>window.__pwned = 1</script>"
HOSTILE = f'''id = "{HOSTILE_ID}"
title = "Evil {PAYLOAD} \\"quoted\\" & 'single' <img src=x onerror=\\"window.__pwned=2\\">"
topic = "<b>bold topic</b>"
notes = "Notes </pre>{PAYLOAD}<!-- and a comment"

[source]
citation = "A. B. Author, Journal of {PAYLOAD} 1 (2024) 1-2"
authors = ["A. B. Author"]
year = 2024
locator = "p. 1 \\"<i>\\""
doi = "10.1000/\\"><script>window.__pwned=3</script>"
url = "javascript:window.__pwned=4"

[parameters]
c = "positive"

[system]
inertia = ["1", "1", "2"]
potential = "c*gamma3"

[[claims]]
label = "I1"
kind = "integral"
expression = "M3"
notes = "{PAYLOAD}"
'''


def _renamed_zhukovsky() -> str:
    """Zhukovsky's gyrostat under a new id, listing its seed id as an alias."""
    text = (CASES / f"{ZHUKOVSKY}.toml").read_text(encoding="utf-8")
    text = re.sub(r'^id = "[^"]+"', f'id = "{RENAMED}"', text, count=1, flags=re.M)
    return text.replace(f'id = "{RENAMED}"', f'id = "{RENAMED}"\naliases = ["{ZHUKOVSKY}"]', 1)


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> SimpleNamespace:
    """The database, and the site built twice from it into two folders."""
    folder = tmp_path_factory.mktemp("site")
    db = folder / "registry.sqlite"
    with registry.open(db) as reg:
        reg.add(*(CASES / f"{c}.toml" for c in SEED if c != ZHUKOVSKY))
        reg.add(HAMILTONIAN / "kovalevskaya-so31.toml", HAMILTONIAN / "kovalevskaya-so4.toml")
        for name, text in ((RENAMED, _renamed_zhukovsky()), (HOSTILE_ID, HOSTILE)):
            reg.add_case(parse_case_text(text, f"{name}.toml"))
        reg.audit(jobs=1)
        reg.survey([RENAMED], jobs=1)
        reg.analyse_exponents(SO4, record=True)
        reg.analyse_exponents(WITNESSED, budget=8, record=True, jobs=1)  # out of time
        reg.analyse_exponents(HOSTILE_ID, free=["c"], record=True, jobs=1)
        reg.add(FAMILIES / "lagrange-lam.toml")  # two parameters: generic series not computed
        reg.analyse_exponents("family-lagrange-lam", free=["lam", "z"], record=True, jobs=1)
        reg.identify([RENAMED, AFFINE], jobs=1)
        reg.discover(FAMILIES / f"{GYROSTATS}.toml", **GYROSTATS_SEARCH, record=True, jobs=1)
        first = reg.site(folder / "one")
        reg.site(folder / "two")
        cases = reg.cases()
        verdicts = reg.verdicts()
        claims = reg.claims()
    return SimpleNamespace(
        db=db,
        site=folder / "one",
        other=folder / "two",
        written=first,
        cases=cases,
        verdicts=verdicts,
        claims=claims,
    )


def _tree(folder: Path) -> dict[str, bytes]:
    return {
        p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file()
    }


# ------------------------------------------------------------------ the files


def test_two_builds_are_byte_identical(built):
    one, two = _tree(built.site), _tree(built.other)
    assert one.keys() == two.keys()
    assert [name for name in one if one[name] != two[name]] == []
    assert sorted(one) == sorted(p.relative_to(built.site).as_posix() for p in built.written)


def test_every_case_has_its_permanent_page_downloads_and_alias_redirect(built):
    ids = list(built.cases["case"])
    family = f"family-{GYROSTATS}"  # recorded by its search, with its special set
    recorded = {family, f"{family}-where-k1-0-k2-0"}
    lagrange = "family-lagrange-lam"
    witnessed = "test-heavy-top-centre-a"
    expected = {*SEED, RENAMED, HOSTILE_ID, SO31, SO4, lagrange, witnessed, *recorded}
    assert set(ids) == expected - {ZHUKOVSKY}
    for case_id in ids:
        for ext in ("html", "toml", "audit.json", "m", "mpl", "py"):
            assert (built.site / "cases" / f"{case_id}.{ext}").is_file(), (case_id, ext)
    redirect = (built.site / "cases" / f"{ZHUKOVSKY}.html").read_text(encoding="utf-8")
    assert f'content="0; url={RENAMED}.html"' in redirect
    for page in ("index.html", "searches.html", "classifications.html", "corrections.html",
                 "topics/index.html"):  # fmt: skip
        assert (built.site / page).is_file()


class _Links(HTMLParser):
    """Every href and src of a page, and its element ids; tags left open or closed wrong."""

    VOID = {"meta", "img", "br", "hr", "link", "input", "source", "mspace", "none"}

    def __init__(self) -> None:
        super().__init__()
        self.links: list[str] = []
        self.ids: set[str] = set()
        self.open: list[str] = []
        self.errors: list[str] = []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("href", "src") and value is not None:
                self.links.append(value)
            if name == "id" and value:
                self.ids.add(value)
        if tag not in self.VOID:
            self.open.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)
        if tag not in self.VOID:
            self.open.pop()

    def handle_endtag(self, tag):
        if not self.open or self.open.pop() != tag:
            self.errors.append(f"</{tag}> at {self.getpos()}")


def _parsed(path: Path) -> _Links:
    parser = _Links()
    parser.feed(path.read_text(encoding="utf-8"))
    parser.close()
    return parser


def test_every_internal_link_of_every_page_resolves_and_tags_balance(built):
    pages = sorted(built.site.rglob("*.html"))
    assert len(pages) > 10
    broken, unbalanced, external = [], [], set()
    for page in pages:
        found = _parsed(page)
        if found.errors or found.open:
            unbalanced.append((page.name, found.errors[:3], found.open[:3]))
        for link in found.links:
            parts = urlparse(link)
            if parts.scheme or link.startswith("//"):
                external.add(parts.scheme)
                continue
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if not target.is_file():
                broken.append((page.relative_to(built.site).as_posix(), link))
            elif parts.fragment and target.suffix == ".html":
                if parts.fragment not in _parsed(target).ids:
                    broken.append((page.name, link))
    assert broken == []
    assert unbalanced == []
    assert external <= {"https"}  # DOI links; never javascript:


def test_hostile_text_is_escaped_everywhere(built):
    ours = {"index.html": 2}  # the JSON index and site.js
    for page in built.site.rglob("*.html"):
        text = page.read_text(encoding="utf-8")
        name = page.relative_to(built.site).as_posix()
        assert text.count("<script") == ours.get(name, 0), name
        assert "<img src=x" not in text and "<b>bold" not in text, name
        assert 'href="javascript:' not in text, name
    case_page = (built.site / "cases" / f"{HOSTILE_ID}.html").read_text(encoding="utf-8")
    assert "&lt;script&gt;window.__pwned = 1&lt;/script&gt;" in case_page
    assert 'href="javascript:' not in case_page
    assert 'href="https://doi.org/10.1000/%22%3E%3Cscript%3E' in case_page  # quoted DOI
    index = json.loads((built.site / "index.json").read_text(encoding="utf-8"))
    (row,) = [r for r in index if r["id"] == HOSTILE_ID]
    assert PAYLOAD in row["title"]  # data kept as it is, escaped where it is written


def test_downloads_reload_parse_and_evaluate(built, tmp_path):
    case_dir = built.site / "cases"
    toml = case_dir / f"{YEHIA_B}.toml"
    result = CliRunner().invoke(main, ["--db", str(tmp_path / "r.sqlite"), "add", str(toml)])
    assert result.exit_code == 0, result.output
    with registry.open(tmp_path / "r.sqlite") as reg, registry.open(built.db) as original:
        assert reg.case(YEHIA_B).content_hash == original.case(YEHIA_B).content_hash
        case = original.case(YEHIA_B)
    document = json.loads((case_dir / f"{YEHIA_B}.audit.json").read_text(encoding="utf-8"))
    (entry,) = document["cases"]
    assert entry["case"] == YEHIA_B and entry["claims"][0]["verdict"] == "refuted"
    namespace: dict = {}
    code = (case_dir / f"{YEHIA_B}.py").read_text(encoding="utf-8")
    exec(compile(code, f"{YEHIA_B}.py", "exec"), namespace)  # the site's own file
    assert namespace["claims"]["I2"] == case.claims[0].expression.expr
    for got, want in zip(namespace["torque"], case.system.torque_exprs, strict=True):
        assert sp.expand(got - want) == 0
    math = (case_dir / f"{YEHIA_B}.m").read_text(encoding="utf-8")
    assert 'caseId = "yehia-2003-kovalevskaya-b";' in math
    assert "claims = <|" in math and "pC" in math  # C is a Mathematica built-in: renamed


def test_case_page_shows_verdicts_witness_corrections_history_and_citations(built):
    page = (built.site / "cases" / f"{YEHIA_B}.html").read_text(encoding="utf-8")
    for text in (
        "witness point",
        "Corrected Casimir",
        "Corrected torque",
        "The claim holds when",
        "Version history",
        "@misc{registry:yehia-2003-kovalevskaya-b,",
        "@article{yehia2003,",
    ):
        assert text in page, text
    assert page.count("<math") > 10
    assert "e(3)" in page
    renamed = (built.site / "cases" / f"{RENAMED}.html").read_text(encoding="utf-8")
    assert "Newest search for integrals" in renamed and "No search recorded" not in renamed
    assert f'<a href="{ZHUKOVSKY}.html">{ZHUKOVSKY}</a>' in renamed


def _exponents_section(built, case_id: str) -> str:
    page = (built.site / "cases" / f"{case_id}.html").read_text(encoding="utf-8")
    return html.unescape(page[page.index('id="exponents"') : page.index('id="history"')])


def test_a_case_page_shows_its_newest_kovalevskaya_analysis(built):
    section = _exponents_section(built, SO4)
    assert re.search(
        r"Analysis \d+ of version 1, weights M = 1, gamma = 2 \(the field is not "
        r"weighted-homogeneous: its leading part is analysed\)\.",
        section,
    )
    # two families of balances along M2 (-1, 0, 1, 2, 3, 4), two isolated ones
    assert section.count("(a family of dimension 1, along M2)") == 2
    assert section.count("<code>-1, 0, 1, 2, 3, 4</code>") == 2
    assert section.count("<code>-1, -1, 2, 2, 3, 4</code>") == 2
    assert section.count("every condition holds") == 4
    degrees = "Degrees Yoshida's theorem allows: 1, 2, 3, 4. Painlevé (ARS) test: passes."
    assert degrees in section
    assert "applied to the leading part" in section  # the statement, as strong as Yoshida's
    assert "With the newest search" not in section  # no search of this case
    other = _exponents_section(built, YEHIA_B)
    assert "No Kovalevskaya analysis recorded for this case." in other


def test_a_family_s_generic_painleve_test_comes_from_its_stratification(built):
    """Lagrange's tops with lam and z free: the family's own analysis computes no series
    with two parameters, but the stratification passes on the whole space; the balances
    say that their own series was not computed (the page once read "fails")."""
    section = _exponents_section(built, "family-lagrange-lam")
    assert "Painlevé (ARS) test for generic values: passes." in section
    assert section.count("no series computed for this balance") == 2
    assert "every condition holds" not in section
    # both stratifications, each set with its exponents and the catalog's cases it is
    assert "Sets where the Painlevé (ARS) test passes (1 strata analysed; complete: yes)" in section
    assert "Sets where every exponent is in ½ℤ (1 strata analysed; complete: yes)" in section
    rows = re.findall(r"<tr><th scope=\"row\">(.*?)</tr>", section, flags=re.S)
    sets = [r for r in rows if r.startswith("<code>every value</code>")]
    assert len(sets) == 2 and "(lam, z free) [integer]" in sets[1]
    assert all("<code>-1, 0, 1, 2, 3, 4 (2 balances)</code>" in r for r in sets)
    for row in sets:  # compared with the catalog: the cases it is, each linked to its page
        named = re.findall(r'<a href="([^"]+)\.html">\1</a>', row.rsplit("<td>", 1)[1])
        assert named and set(named) <= set(built.cases["case"])


def test_a_long_balance_is_elided_on_the_page_and_shown_whole_on_request():
    """A family's generic point over Q(p) can run to pages (Schottky's so(4) body:
    50 000 characters): the table shows which symbols each coordinate involves, and a
    disclosure holds the whole point, and a long failing condition."""
    long = " + ".join(f"{k}*theta**{k}*kappa" for k in range(1, 80))
    balance = {
        "point": {"M1": long, "M2": "0"}, "root_of": "theta**2 - kappa = 0",
        "exponents": ["-1", "2"], "integer": True, "rational": True, "dimension": 0,
        "along": [], "painleve": {"compatible": True, "resonances": []},
    }  # fmt: skip

    def page(balance: dict, passes: bool | None = True) -> dict:
        document = {"weights": {"M": 1}, "balances": [balance], "painleve": {"passes": passes}}
        result = ExponentResult("demo", "h", ExponentOptions((("M", 1),)), document)
        return site._exponents(site.ExponentEntry(1, 1, result))

    shown = page(balance)
    (b,) = shown["balances"]
    assert b["point"] == f"M1 = <an expression in kappa, theta: {len(long)} characters>, M2 = 0"
    assert b["whole"] == [f"M1 = {long}, M2 = 0"]
    assert b["root_of"] == "theta**2 - kappa = 0"  # short: shown as it is
    assert shown["painleve"] == "passes"
    condition = {"order": 2, "conditions": [f"{long} = 0"], "missing": 0}
    (b,) = page({**balance, "painleve": {"compatible": False, "resonances": [condition]}})[
        "balances"
    ]
    elided = f"<an expression in kappa, theta: {len(long) + 4} characters>"
    assert b["failing"] == [f"resonance 2: condition fails: {elided}"]
    assert b["whole"] == [f"M1 = {long}, M2 = 0", f"{long} = 0"]
    assert page(balance, passes=None)["painleve"] == "not made"


def test_a_case_page_shows_a_failure_witnessed_at_rational_values(built):
    """The analysis over Q(a) ran out of time; the page says the test fails for generic
    values, by which balance, with its long coordinates behind a disclosure."""
    section = _exponents_section(built, "test-heavy-top-centre-a")
    assert "Painlevé (ARS) test for generic values: fails, by a simple balance at a = " in section
    assert "those not rational, at one root theta, approximately" in section
    assert "<details><summary>in full</summary><code>M1 = " in section
    assert "fails for generic values of a" in section  # the statement
    assert "Degrees Yoshida's theorem allows" not in section  # nothing generic is claimed


def test_a_witnessed_failure_is_shown_with_its_balance_and_its_long_parts_elided():
    """An analysis out of time with a witness (``exponent_witness``): the page says the
    test fails for generic values, at which values, and shows the balance there."""
    long = " + ".join(f"{k}*theta**{k}" for k in range(1, 80))
    witness = {
        "values": {"a": "6/7"}, "point": {"M1": "theta", "M2": "0"},
        "root_of": "theta**2 + 3 = 0", "exponents": ["-1", f"root of lambda**2 + {long}"],
        "rational": ["-1"], "not_rational": 1, "approximate": ["0.5 - 1.2*I"],
    }  # fmt: skip
    document = {
        "weights": {"M": 1}, "decided": False, "reason": "time budget exceeded (8 s)",
        "balances": [], "painleve": {"passes": False}, "witness": witness,
    }  # fmt: skip
    result = ExponentResult("demo", "h", ExponentOptions((("M", 1),)), document)
    shown = site._exponents(site.ExponentEntry(1, 1, result))
    assert shown["painleve"] == "fails" and not shown["decided"]
    w = shown["witness"]
    assert (w["at"], w["point"], w["root_of"]) == (
        "a = 6/7",
        "M1 = theta, M2 = 0",
        "theta**2 + 3 = 0",
    )
    assert w["exponents"].startswith("-1, <an expression in lambda, of, root, theta: ")
    assert w["whole"] == [f"-1, root of lambda**2 + {long}"]
    assert w["approximate"] == "0.5 - 1.2*I"
    bare = {k: v for k, v in document.items() if k != "witness"}  # no witness: not made
    without = site._exponents(
        site.ExponentEntry(1, 1, ExponentResult("d", "h", result.options, bare))
    )
    assert without["witness"] is None and without["painleve"] == "not made"


def _same_system_section(built, case_id: str) -> str:
    page = (built.site / "cases" / f"{case_id}.html").read_text(encoding="utf-8")
    return html.unescape(page[page.index('id="same-system"') : page.index('id="exponents"')])


def test_a_case_page_names_the_catalog_cases_that_are_the_same_system(built):
    renamed = _same_system_section(built, RENAMED)  # Zhukovsky's gyrostat: an affine torque
    assert f'<a href="{AFFINE}.html">{AFFINE}</a>, at A = A, B = B, C = C, T11 = 0' in renamed
    affine = _same_system_section(built, AFFINE)
    assert "No other case of the catalog was found to be this system" in affine
    assert f'Cases that are this system at some of its values: <a href="{RENAMED}.html">' in affine
    never = _same_system_section(built, YEHIA_B)
    assert "Not identified with the catalog yet" in never


def test_the_classifications_page_shows_each_family_s_sets_identified(built):
    page = (built.site / "classifications.html").read_text(encoding="utf-8")
    section = page.split('<section id="search-', 1)[1].split("</section>", 1)[0]
    assert "family-goryachev-chaplygin-gyrostat" in section
    assert "3 free parameters (k1, k2, k3)" in section and "Complete: yes." in section
    assert "<caption>1 special sets</caption>" in section
    (row,) = re.findall(r"<tr>\n<th scope=\"row\">.*?</tr>", section, flags=re.S)
    assert f'<a href="cases/{AFFINE}.html">{AFFINE}</a>' in row
    assert "<td>1 of 1</td>" in row  # Sretenskii's integral: no case of this site claims it
    assert "k1 = 0" in html.unescape(row) and "M1**2*M3" in html.unescape(row)


def test_a_family_s_analysis_shows_its_special_sets_and_their_completeness(built):
    section = _exponents_section(built, HOSTILE_ID)
    assert ", free c." in section and "(generic values of c)" in section
    assert "Painlevé (ARS) test for generic values: passes." in section
    rows = re.findall(r"<tr><td>(\w+)</td><th scope=\"row\"><code>([^<]*)</code></th>", section)
    assert rows == [("integer", "every value"), ("rational", "every value")]
    assert "Complete: integer yes, half-integer yes, rational yes." in section


def test_a_surveyed_case_s_analysis_is_combined_with_its_newest_search(built):
    """The survey analysed Zhukovsky's gyrostat beside its search; with every parameter
    generic the analysis may run out of its short budget: either way the page says what
    the two halves prove together, and no more."""
    section = _exponents_section(built, RENAMED)
    assert "Analysis " in section and "With the newest search: " in section
    combined = section[section.index("With the newest search: ") :]
    assert combined.startswith("With the newest search: Nothing is stated beyond degree") or (
        "Yoshida" in combined
    )


def test_bracket_names_follow_the_sign_of_kappa(built):
    assert bracket(parse_case_text(HOSTILE, "h.toml"))[0] == "e(3)"
    index = {r["id"]: r for r in json.loads((built.site / "index.json").read_text())}
    assert index[SO31]["bracket"] == "so(3,1)"
    assert index[SO4]["bracket"] == "by the sign of kappa"  # kappa is a real parameter
    assert index[YEHIA_B]["bracket"] == "e(3)"
    page = (built.site / "cases" / f"{SO31}.html").read_text(encoding="utf-8")
    assert "so(3,1) (kappa = -1 &lt; 0)" in page
    assert '<code class="source">H = ' in page and '<code class="source">kappa = -1' in page
    assert '<code class="source">A = ' not in page  # a Hamiltonian, no moments


def test_a_build_in_another_process_is_byte_identical(built, tmp_path):
    """Another interpreter, with another hash seed, writes the same bytes."""
    out = tmp_path / "elsewhere"
    env = {**os.environ, "PYTHONHASHSEED": "12345"}
    command = [sys.executable, "-m", "registry", "--db", str(built.db), "site", "-o", str(out)]
    subprocess.run(command, env=env, check=True, capture_output=True, timeout=600)
    one, other = _tree(built.site), _tree(out)
    assert one.keys() == other.keys()
    assert [name for name in one if one[name] != other[name]] == []


def test_cli_site_prints_the_folder_and_its_counts(built, tmp_path):
    out = tmp_path / "cli-site"
    args = ["--db", str(built.db), "site", "-o", str(out), "--base-url", "https://x.org/reg"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert re.fullmatch(rf"{re.escape(str(out))}: \d+ files, \d+ pages\n", result.output)
    page = (out / "cases" / f"{YEHIA_B}.html").read_text(encoding="utf-8")
    assert f'<link rel="canonical" href="https://x.org/reg/cases/{YEHIA_B}.html">' in page
    assert f"url = {{https://x.org/reg/cases/{YEHIA_B}.html}}" in page


# ------------------------------------------------------------------ the browser


@pytest.fixture(scope="module")
def server(built):
    """The first build served over HTTP from 127.0.0.1 (a free port)."""
    handler = partial(_QuietHandler, directory=str(built.site))
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}/"
    httpd.shutdown()
    httpd.server_close()


class _QuietHandler(SimpleHTTPRequestHandler):
    def log_message(self, *args):  # no request log on the test's output
        pass


def _chrome(tmp_path_factory, javascript: bool = True):
    """A headless Chromium with a fresh profile, driven by the distribution's driver."""
    if not (shutil.which(CHROMIUM) and shutil.which(CHROMEDRIVER)):
        if os.environ.get("REGISTRY_CI"):
            pytest.fail(
                f"Chromium ({CHROMIUM}) and chromedriver ({CHROMEDRIVER}) are required in CI"
            )
        pytest.skip("no Chromium or chromedriver (apt-get install chromium chromium-driver)")
    from selenium import webdriver

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in (
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--window-size=1280,1600",
        f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}",
    ):
        options.add_argument(flag)
    if not javascript:
        options.add_experimental_option(
            "prefs", {"profile.managed_default_content_settings.javascript": 2}
        )
    return webdriver.Chrome(options=options, service=webdriver.ChromeService(CHROMEDRIVER))


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    driver = _chrome(tmp_path_factory)
    yield driver
    driver.quit()


def _visible_rows(driver) -> list[str]:
    return driver.execute_script(
        "return Array.from(document.querySelectorAll('tr[data-case]'))"
        ".filter(r => !r.hidden && r.offsetParent !== null).map(r => r.dataset.case)"
    )


def test_the_index_lists_every_case_and_its_filters_change_the_rows(built, server, browser):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import Select

    browser.get(server + "index.html")
    everything = sorted(built.cases["case"])
    assert sorted(_visible_rows(browser)) == everything
    form = browser.find_element(By.ID, "filters")
    assert form.is_displayed()

    refuted = sorted(
        {
            row.case
            for row in built.claims.itertuples()
            for v in built.verdicts.itertuples()
            if v.case == row.case and v.claim == row.label and v.check == row.kind
            and v.verdict == "refuted"
        }
    )  # fmt: skip
    assert refuted and len(refuted) < len(everything)
    Select(browser.find_element(By.ID, "f-verdict")).select_by_value("refuted")
    assert sorted(_visible_rows(browser)) == refuted
    assert browser.find_element(By.ID, "shown").text == (
        f"{len(refuted)} of {len(everything)} cases shown."
    )
    browser.find_element(By.CSS_SELECTOR, "button[type=reset]").click()
    assert sorted(_visible_rows(browser)) == everything

    browser.find_element(By.ID, "f-text").send_keys("kovalevskaya")
    assert _visible_rows(browser) == [SO31, SO4, YEHIA_B]  # by id, and titles
    browser.find_element(By.ID, "f-text").send_keys("-b")
    assert _visible_rows(browser) == [YEHIA_B]
    browser.find_element(By.CSS_SELECTOR, "button[type=reset]").click()
    browser.find_element(By.ID, "f-year-from").send_keys("2020")
    assert _visible_rows(browser) == [HOSTILE_ID]  # the only source from 2020 on
    browser.find_element(By.CSS_SELECTOR, "button[type=reset]").click()
    browser.find_element(By.ID, "f-author").send_keys("yehia")
    assert _visible_rows(browser) == [YEHIA_B]
    browser.find_element(By.CSS_SELECTOR, "button[type=reset]").click()
    topic = built.cases.set_index("case").loc[YEHIA_B, "topic"]
    Select(browser.find_element(By.ID, "f-topic")).select_by_value(topic)
    expected = sorted(built.cases[built.cases["topic"] == topic]["case"])
    assert sorted(_visible_rows(browser)) == expected
    browser.find_element(By.CSS_SELECTOR, "button[type=reset]").click()
    Select(browser.find_element(By.ID, "f-bracket")).select_by_value("so(3,1)")
    assert _visible_rows(browser) == [SO31]
    assert browser.execute_script("return window.__pwned === undefined")


def test_with_scripts_off_the_index_shows_the_full_table(built, server, tmp_path_factory):
    driver = _chrome(tmp_path_factory, javascript=False)
    try:
        from selenium.webdriver.common.by import By

        driver.get(server + "index.html")
        rows = driver.find_elements(By.CSS_SELECTOR, "tr[data-case]")
        assert sorted(r.get_attribute("data-case") for r in rows) == sorted(built.cases["case"])
        assert all(r.is_displayed() for r in rows)
        assert not driver.find_element(By.ID, "filters").is_displayed()  # needs the script
    finally:
        driver.quit()


def test_case_pages_render_their_mathml_and_keep_a_screenshot(built, server, browser):
    for case_id in (YEHIA_B, RENAMED, HOSTILE_ID):
        browser.get(server + f"cases/{case_id}.html")
        sizes = browser.execute_script(
            "return Array.from(document.querySelectorAll('math')).map(m => {"
            " const r = m.getBoundingClientRect(); return [r.width, r.height]; })"
        )
        assert len(sizes) >= 6, case_id
        assert all(w > 0 and h > 0 for w, h in sizes), case_id
        # MathML laid out as math: a fraction is taller than a line of text
        assert browser.execute_script("return window.__pwned === undefined"), case_id
    browser.get(server + f"cases/{YEHIA_B}.html")
    heights = browser.execute_script(
        "return Array.from(document.querySelectorAll('math mfrac'))"
        ".map(f => f.getBoundingClientRect().height)"
    )
    line = browser.execute_script(
        "return parseFloat(getComputedStyle(document.querySelector('p')).lineHeight)"
    )
    assert heights and max(heights) > line
    ARTIFACTS.mkdir(exist_ok=True)
    shot = ARTIFACTS / f"site-{YEHIA_B}.png"
    assert browser.save_screenshot(str(shot))
    assert shot.read_bytes().startswith(b"\x89PNG")
    print(f"screenshot: {shot}")


def test_the_browser_reaches_every_page_from_the_index_and_no_link_is_broken(
    built, server, browser
):
    """A crawl in the browser: every page reachable from the index is loaded, has one
    h1 and a language, and every link on it (pages, downloads, anchors) is served."""
    from selenium.webdriver.common.by import By

    browser.get(server + f"cases/{ZHUKOVSKY}.html")  # the alias: redirected
    assert browser.current_url == server + f"cases/{RENAMED}.html"
    pages, queue, served = set(), [server + "index.html"], set()
    while queue:
        page = queue.pop()
        if page in pages:
            continue
        pages.add(page)
        browser.get(page)
        assert browser.current_url == page, page  # no redirect, no error page
        assert len(browser.find_elements(By.TAG_NAME, "h1")) == 1, page
        assert browser.find_element(By.TAG_NAME, "html").get_attribute("lang") == "en"
        links = {a.get_attribute("href") for a in browser.find_elements(By.CSS_SELECTOR, "a[href]")}
        for href in sorted(h for h in links if h.startswith(server)):
            target, _, fragment = href.partition("#")
            if fragment and target == page:
                assert browser.find_elements(By.ID, fragment), href
            if target not in served:
                with urllib.request.urlopen(target) as response:  # noqa: S310 - our server
                    assert response.status == 200, target
                served.add(target)
            if target.endswith(".html") and not target.endswith(f"/{ZHUKOVSKY}.html"):
                queue.append(target)
    on_disk = {
        server + p.relative_to(built.site).as_posix()
        for p in built.site.rglob("*.html")
        if p.name != f"{ZHUKOVSKY}.html"  # the redirect, checked above
    }
    assert pages == on_disk  # every page is reachable, and every reachable page exists


def test_any_backend_gives_the_same_site(db_target, tmp_path):
    """The seed cases on this module's backend (SQLite, then PostgreSQL) and on an SQLite
    file give the same files and the same index (times of adding and of each check aside,
    which differ between two audits)."""
    trees = []
    for target in (db_target, tmp_path / "reference.sqlite"):
        with registry.open(target) as reg:
            reg.add(*(CASES / f"{c}.toml" for c in SEED))
            reg.audit(jobs=1)
            reg.site(tmp_path / str(len(trees)))
        trees.append(_tree(tmp_path / str(len(trees))))
    assert trees[0].keys() == trees[1].keys()
    assert trees[0]["index.json"] == trees[1]["index.json"]
    for case_id in SEED:
        for ext in ("toml", "py", "m", "mpl"):
            name = f"cases/{case_id}.{ext}"
            assert trees[0][name] == trees[1][name], name
