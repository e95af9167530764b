"""The code version (``registry/version.py``): the release and a digest of every source,
and ``registry --version`` / ``-V`` printing them; the release agrees with
``pyproject.toml``, ``CITATION.cff`` and the changelog (docs/development.md, Releasing:
``pyproject.toml`` gives the newest released version)."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

import registry
from registry.cli import main
from registry.version import code_version, release, source_digest

ROOT = Path(registry.__file__).resolve().parent.parent
#: A release's heading in the changelog: ``## [0.1.0] - 2026-11-26``.
RELEASE = re.compile(r"\[(?P<version>\d+\.\d+\.\d+)\] - (?P<date>\d{4}-\d{2}-\d{2})")
#: The sections a version may have (Keep a Changelog 1.1.0), each at most once.
SECTIONS = {"Added", "Changed", "Deprecated", "Removed", "Fixed", "Security"}


def changelog() -> list[tuple[str, list[str]]]:
    """(heading, its ### section titles) of every ``##`` version of CHANGELOG.md."""
    versions: list[tuple[str, list[str]]] = []
    for line in (ROOT / "CHANGELOG.md").read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            versions.append((line[3:], []))
        elif line.startswith("### "):
            assert versions, f"a section before any version: {line!r}"
            versions[-1][1].append(line[4:])
    return versions


def newest_release() -> tuple[str, str]:
    """(version, date) of the newest release in the changelog."""
    found = RELEASE.fullmatch(changelog()[1][0])
    assert found, changelog()[1][0]
    return found["version"], found["date"]


def test_the_changelog_has_unreleased_then_each_release_newest_first():
    (unreleased, _), *releases = changelog()
    assert unreleased == "[Unreleased]"
    assert releases, "no released version"
    found = [RELEASE.fullmatch(heading) for heading, _ in releases]
    assert all(found), [h for (h, _), f in zip(releases, found, strict=True) if not f]
    numbers = [tuple(map(int, f["version"].split("."))) for f in found if f]
    dates = [f["date"] for f in found if f]
    assert numbers == sorted(set(numbers), reverse=True)
    assert dates == sorted(dates, reverse=True)


def test_each_version_has_each_kind_of_section_once():
    for heading, sections in changelog():
        assert set(sections) <= SECTIONS, heading
        assert len(sections) == len(set(sections)), f"{heading}: {sections}"


def test_pyproject_citation_and_the_installed_package_give_the_newest_release():
    version, date = newest_release()
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert project["version"] == version
    assert (str(citation["version"]), str(citation["date-released"])) == (version, date)
    # what registry --version prints (reinstall after changing pyproject.toml's version)
    assert release() == version


def _package_copy(tmp_path: Path) -> Path:
    """A copy of the package's sources (no compiled files) to edit."""
    import shutil

    source = Path(registry.__file__).parent
    copy = tmp_path / "registry"
    shutil.copytree(source, copy, ignore=shutil.ignore_patterns("__pycache__"))
    return copy


def test_code_version_digests_every_source_of_the_package():
    version = code_version()
    digest = source_digest(Path(registry.__file__).parent)
    assert version.endswith("+" + digest[:12])


def test_editing_a_module_in_a_sub_package_changes_the_code_version(tmp_path):
    copy = _package_copy(tmp_path)
    before = source_digest(copy)
    nested = sorted(p for p in copy.rglob("*.py") if p.parent != copy)
    assert nested, "the package has no sub-package"
    for module in nested:
        original = module.read_bytes()
        module.write_bytes(original + b"\n# edited\n")
        assert source_digest(copy) != before, module
        module.write_bytes(original)
    assert source_digest(copy) == before


def test_compiled_files_and_other_files_do_not_change_the_code_version(tmp_path):
    copy = _package_copy(tmp_path)
    before = source_digest(copy)
    (copy / "__pycache__").mkdir(exist_ok=True)
    (copy / "__pycache__" / "api.cpython-311.pyc").write_bytes(b"compiled")
    (copy / "notes.txt").write_text("not code", encoding="utf-8")
    assert source_digest(copy) == before


def test_moving_a_module_changes_the_code_version(tmp_path):
    copy = _package_copy(tmp_path)
    before = source_digest(copy)
    (copy / "elsewhere").mkdir()
    (copy / "model.py").rename(copy / "elsewhere" / "model.py")
    assert source_digest(copy) != before


@pytest.mark.parametrize("flag", ["--version", "-V"])
def test_the_version_option_prints_the_release_and_the_code_digest(flag):
    result = CliRunner().invoke(main, [flag])
    assert result.exit_code == 0, result.output
    digest = source_digest(Path(registry.__file__).parent)[:12]
    assert result.output == f"registry {release()} (code digest {digest})\n"
    assert code_version() == f"{release()}+{digest}"


def test_the_version_option_works_without_a_database(tmp_path):
    missing = tmp_path / "nowhere" / "registry.sqlite"
    done = subprocess.run(
        [sys.executable, "-m", "registry", "--db", str(missing), "-V"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(f"registry {release()} (code digest ")
    assert not missing.parent.exists()
