"""The code version (``registry/version.py``): the release and a digest of every source,
and ``registry --version`` / ``-V`` printing them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

import registry
from registry.cli import main
from registry.version import code_version, release, source_digest


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
