"""``rastercheck atlas``: every installed real library in every mode, identified and run
through the quick suite, on one page (``atlas.html``) with its JSON twin (``atlas.json``),
beside the run report the page links every cell to.

Steps, each reusing a command's own machinery: ``run`` over the real adapters
(:data:`harness.engine.registry.real_adapters`; every one identified, ``--jobs`` of them
side by side, each in a worker process of its own, so that a library that hangs or crashes
costs its own calls only); each adapter's drawings of the suite's still scenes compared
with the others' (:mod:`harness.diagnose.alike`); the version of each library, asked in a
process of its own where the adapter learns it only once it draws (Mesa's GL_VERSION); the
upstream bug scripts (``rasterizers/real/upstream``) copied beside the page.

Exit codes: 0 the atlas is written (failing checks are its content, not an error), 2 a
usage error, 130 interrupted (what finished is written as a partial run report).
"""

from __future__ import annotations

import argparse
import ast
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

from harness.cli.common import UsageError, _skipped

__all__ = ["add_atlas_parser", "upstream_scripts"]

UPSTREAM = Path(__file__).resolve().parents[2] / "rasterizers" / "real" / "upstream"
_VERSION_PROBE = """
import sys
from harness.contract.scenes import Scene
from harness.engine.registry import load
r = load(sys.argv[1])
r.rasterize(Scene(4, 4, [[[0.5, 0.5], [3.5, 0.5], [0.5, 3.5]]]))
print(getattr(r, "library_version", ""))
"""


def upstream_scripts(folder: Path = UPSTREAM) -> list[dict[str, str]]:
    """The upstream bug scripts: per script its library (what its docstring's first paragraph
    names before its colon, "cairo: ..."), its file name and that first paragraph (the
    bug in a sentence)."""
    out = []
    for path in sorted(folder.glob("*.py")) if folder.is_dir() else []:
        if path.name.startswith("_"):
            continue
        try:
            doc = ast.get_docstring(ast.parse(path.read_text())) or ""
        except (OSError, SyntaxError, ValueError):
            doc = ""
        title = " ".join(doc.strip().split("\n\n")[0].split()) if doc.strip() else path.stem
        library, said, _ = title.partition(":")
        out.append({"library": library.strip() if said else path.stem.split("_")[0], "script": f"upstream/{path.name}",
                    "title": title})
    return out


def _versions(rasterizers: list[Any], timeout: float) -> dict[str, str]:
    """The library version of each adapter that learns it only when it draws, asked in a
    process of its own (one small triangle drawn); "" when that fails."""
    from harness.contract.protocol import library_of

    out = {}
    for r in rasterizers:
        if library_of(r)[1]:
            continue
        try:
            done = subprocess.run([sys.executable, "-c", _VERSION_PROBE, r.name], capture_output=True, text=True,
                                  timeout=timeout)
            out[r.name] = done.stdout.strip().splitlines()[-1] if done.returncode == 0 and done.stdout.strip() else ""
        except (OSError, subprocess.TimeoutExpired):
            out[r.name] = ""
    return out


def _still_cases(suite_name: str, seed: int, globs: list[str] | None) -> list[Any]:
    """The suite's still cases of the atlas's kinds (those ``globs`` match, when given),
    compared across adapters."""
    import fnmatch

    from cases.suites import suite
    from harness.contract.case import Case
    from harness.results.atlas import ATLAS_KINDS

    return [c for c in suite(suite_name, seed) if isinstance(c, Case) and c.scene.kind in ATLAS_KINDS
            and (not globs or any(fnmatch.fnmatchcase(c.id, g) for g in globs))]


def _atlas(args: argparse.Namespace) -> int:
    from harness.cli.run import Interrupted, _execute, _interrupted, _write_outputs
    from harness.diagnose.alike import draw_all, pairs
    from harness.engine.registry import real_adapters
    from harness.report.atlas_page import write_atlas_page
    from harness.results.atlas import atlas_document, write_atlas_json

    specs = args.rasterizer or real_adapters()
    if not specs:
        raise UsageError("no real-library adapter is registered (pip install -e . registers them)")
    out = Path(args.out)
    run_args = argparse.Namespace(
        rasterizer=specs, suite=args.suite, seed=args.seed, jobs=args.jobs, timeout=args.timeout, out=str(out),
        json=str(out / "results.json"), junit=None, no_fingerprints=False, case=args.case, check=None, skip=None, shard=None,
        rerun=0, max_seconds=None, causes=0, resume=False, tolerant=True)
    start = time.perf_counter()
    try:
        rasterizers, results, seconds, fingerprints = _execute(run_args, journal=True)
    except Interrupted as stopped:
        return _interrupted(run_args, stopped)
    missing = dict(_skipped)
    _write_outputs(run_args, rasterizers, results, seconds, fingerprints, quiet=True)
    print(f"atlas: the suite and identify done in {seconds:.0f} s; comparing drawings", file=sys.stderr)
    cases = _still_cases(args.suite, args.seed, args.case)
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:  # each draws in a worker process of its own
        drawings = list(pool.map(lambda r: draw_all(r, cases, args.timeout), rasterizers))
    versions = _versions(rasterizers, args.timeout)
    upstream = upstream_scripts()
    if upstream:
        (out / "upstream").mkdir(parents=True, exist_ok=True)
        for u in upstream:
            shutil.copyfile(UPSTREAM / Path(u["script"]).name, out / u["script"])
    from cases.suites import suite

    document = atlas_document(rasterizers, results, fingerprints, suite(args.suite, args.seed), pairs(drawings),
                              missing=missing, upstream=upstream, versions=versions, suite=args.suite, seed=args.seed,
                              seconds=time.perf_counter() - start)
    write_atlas_json(out / "atlas.json", document)
    page = write_atlas_page(out, document)
    adapters = sum(len(lib["adapters"]) for lib in document["libraries"])
    print(f"atlas: {page} ({len(document['libraries'])} libraries, {adapters} modes, {len(missing)} not installed; "
          f"{document['seconds']:.0f} s); JSON: {out / 'atlas.json'}")
    return 0


def add_atlas_parser(sub: Any, jobs: Any, seconds: Any, path: Any) -> None:
    """The ``atlas`` subcommand (its types are main's: ``jobs`` a positive int, ``seconds`` a
    positive number of seconds, ``path`` an output path)."""
    import os

    atlas = sub.add_parser("atlas", help="every installed real library in every mode, identified and judged, on one page",
                           description="Identify every installed real-library adapter and run the quick suite on it, "
                                       "compare their drawings, and write atlas.html and atlas.json beside the run report.")
    atlas.add_argument("--rasterizer", action="append", metavar="SPEC",
                       help="only these adapters (default every registered real-library adapter)")
    atlas.add_argument("--suite", default="quick", help="quick or full (default quick)")
    atlas.add_argument("--seed", type=int, default=0)
    atlas.add_argument("--case", action="append", metavar="GLOB", help="only cases whose id matches (repeatable)")
    atlas.add_argument("--jobs", type=jobs, default=os.cpu_count() or 1,
                       help="adapters identified and checked side by side (default: one per core)")
    atlas.add_argument("--timeout", type=seconds, default=60.0, help="the most seconds one rasterize call may take")
    atlas.add_argument("--out", type=path, default=str(Path("reports") / "atlas"), help="folder (default reports/atlas)")
    atlas.set_defaults(func=_atlas)
