"""Time and size of the static site and of the HTML report of the catalog.

Loads the catalog into a database (a temporary one unless --db is given), surveys and
audits it (stored results are reused), then times, each --repeat times (best counts):
the Markdown report (the baseline: the same content, formulas in LaTeX), the HTML report
without and with drift plots (formulas as MathML; the plots drawn from the curves the audit
stored, once with an empty image cache and once reading the images the first drew), and
the static site (two builds, which must be byte-identical). Prints seconds, ratios to the
baseline and sizes. Times on a shared machine are noisy; the ratios, measured in the same
run, are what to compare.

Usage: python scripts/bench_site.py [--db PATH|URL] [--repeat N]
"""

from __future__ import annotations

import argparse
import filecmp
import os
import sys
import tempfile
import time
from pathlib import Path

import registry

ROOT = Path(__file__).resolve().parents[1]


def best(repeat: int, fn):
    """The best wall-clock time of ``repeat`` calls, and the last result."""
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return min(times), result


def folder_size(folder: Path) -> tuple[int, int]:
    files = [p for p in folder.rglob("*") if p.is_file()]
    return len(files), sum(p.stat().st_size for p in files)


def identical(a: Path, b: Path) -> bool:
    names = sorted(p.relative_to(a).as_posix() for p in a.rglob("*") if p.is_file())
    others = sorted(p.relative_to(b).as_posix() for p in b.rglob("*") if p.is_file())
    if names != others:
        return False
    _, mismatch, errors = filecmp.cmpfiles(a, b, names, shallow=False)
    return not mismatch and not errors


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", default=None)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        db = args.db or str(scratch / "catalog.sqlite")
        with registry.open(db) as reg:
            reg.add(ROOT / "data" / "cases")
            reg.survey()
            reg.audit()
            n = len(reg.cases())
            base, md = best(args.repeat, lambda: reg.report(fmt="md", plots=False))
            bare, html = best(args.repeat, lambda: reg.report(fmt="html", plots=False))
            # the drift images in an empty cache folder: the first report draws them all
            os.environ["REGISTRY_CACHE"] = str(scratch / "cache")
            drawn, full = best(1, lambda: reg.report(fmt="html", plots=True))
            cached, again = best(args.repeat, lambda: reg.report(fmt="html", plots=True))
            site, _ = best(args.repeat, lambda: reg.site(scratch / "site"))
            reg.site(scratch / "again")
        same = identical(scratch / "site", scratch / "again")
        files, size = folder_size(scratch / "site")
    print(f"catalog: {n} cases")
    print(f"report md (baseline)      {base:7.2f} s  {len(md.encode()) / 1e3:8.0f} kB")
    print(
        f"report html, no plots     {bare:7.2f} s  {len(html.encode()) / 1e3:8.0f} kB"
        f"  ({bare / base:.2f} x baseline)"
    )
    print(
        f"report html, drift plots  {drawn:7.2f} s  {len(full.encode()) / 1e3:8.0f} kB"
        f"  ({drawn / base:.2f} x baseline; one run, {full.count('<img')} plots drawn)"
    )
    print(
        f"  again, images cached    {cached:7.2f} s  {len(again.encode()) / 1e3:8.0f} kB"
        f"  ({cached / base:.2f} x baseline; the same file: {full == again})"
    )
    print(
        f"site                      {site:7.2f} s  {size / 1e3:8.0f} kB in {files} files"
        f"  ({site / base:.2f} x baseline); two builds byte-identical: {same}"
    )
    return 0 if same and full == again else 1


if __name__ == "__main__":
    sys.exit(main())
