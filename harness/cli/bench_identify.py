"""``rastercheck bench --kinds identify``: how long ``rastercheck identify`` takes on each
built-in rasterizer mode, grouped by kind, against the goal of :data:`IDENTIFY_GOAL` seconds
(issue 35).

Each mode is identified in a fresh Python process of its own (``sys.executable``, this
process's environment), as a user runs ``rastercheck identify <spec>``: the clock starts
once the command's module is imported (the interpreter's start-up and ``harness``'s own
import are not identify's) and stops when the card is printed and the declared convention
judged (:func:`harness.cli.identify._identify_card`, its output swallowed). So it counts the
probes' own imports, the numba kernels loaded from their on-disk cache, the worker process
that runs the rasterizer and every probe and oracle call. ``identify_seconds`` is the part
spent in :func:`harness.identify.fingerprint.identify_isolated` (the fingerprint alone: what
``rastercheck run``'s ``--identify`` and the atlas pay per mode); ``cpu_seconds`` the
processor time of that process and its workers over the same span (steadier than the wall
clock on a shared machine). The best of ``repeats`` fresh processes is kept.

``cold_seconds``: the same in a process whose numba cache directory starts empty
(``NUMBA_CACHE_DIR``: every kernel compiled), measured for the first mode of each kind
only (compiling takes seconds per kernel); NaN for the others.

The kind of a mode (:func:`kind_of`): ``multisample`` or ``area`` for a rasterizer whose
answers carry sample indices or alphas (the coverage kind identify saw), else ``lines``
(it takes only lines), ``points`` (only points), ``paths`` (it takes paths) or
``triangles``.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

__all__ = ["IDENTIFY_GOAL", "IdentifyMeasurement", "run_identify_bench", "format_identify_table", "identify_summary",
           "kind_of", "IDENTIFY_KINDS"]

# seconds: issue 35's goal for one built-in rasterizer mode
IDENTIFY_GOAL = 2.0
# the kinds, in the order the table lists them
IDENTIFY_KINDS = ("triangles", "paths", "lines", "multisample", "area", "points")

# What the fresh process runs: identify one mode as the command does, timed from the
# command's module imported to the card printed; one JSON line on stdout.
_CHILD = r"""
import argparse, contextlib, io, json, resource, sys, time

def cpu():
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime

import harness.cli.identify as command
import harness.identify.fingerprint as fingerprint_module

seen = {}
original = fingerprint_module.identify_isolated

def timed(*args, **kwargs):
    start = time.perf_counter()
    found = original(*args, **kwargs)
    seen["identify_seconds"] = time.perf_counter() - start
    seen["coverage_kind"] = found.coverage_kind
    seen["exact"] = bool(found.exact)
    seen["calls"] = found.calls.calls if found.calls is not None else 0
    return found

fingerprint_module.identify_isolated = timed
args = argparse.Namespace(spec=sys.argv[1], seed=int(sys.argv[2]), timeout=float(sys.argv[3]), json=None)
cpu_start, start = cpu(), time.perf_counter()
with contextlib.redirect_stdout(io.StringIO()):
    code = command._identify_card(args)
seen.update(seconds=time.perf_counter() - start, cpu_seconds=cpu() - cpu_start, exit=code)
from harness.contract.protocol import scene_kinds_of
from harness.engine.registry import load
seen["scene_kinds"] = list(scene_kinds_of(load(sys.argv[1])))
print("IDENTIFY-BENCH " + json.dumps(seen))
"""


@dataclass(frozen=True, slots=True)
class IdentifyMeasurement:
    """``rastercheck identify`` on one rasterizer mode (see the module docstring): the best
    ``seconds`` of ``repeats`` fresh processes, with that run's ``identify_seconds`` (the
    fingerprint alone), ``cpu_seconds`` and rasterizer ``calls``; ``cold_seconds`` with
    every kernel compiled (NaN when not measured); ``within_goal``: ``seconds`` under
    :data:`IDENTIFY_GOAL`. ``fault`` says why nothing was measured (the figures are then NaN)."""

    workload: str
    contender: str
    kind: str
    seconds: float
    identify_seconds: float
    cpu_seconds: float
    cold_seconds: float
    calls: int
    exact: bool
    within_goal: bool
    runs: tuple[float, ...] = ()
    goal_seconds: float = IDENTIFY_GOAL
    unit: str = "seconds"
    description: str = "rastercheck identify <spec>: seconds per built-in mode, in a fresh process"
    fault: str = ""


def kind_of(coverage_kind: str, scene_kinds: Sequence[str]) -> str:
    """The kind a mode is counted under (:data:`IDENTIFY_KINDS`).

    >>> kind_of("multisample", ["triangles"]), kind_of("single", ["lines"]), kind_of("single", ["triangles", "paths"])
    ('multisample', 'lines', 'paths')
    """
    from harness.contract.coverage_models import SINGLE

    if coverage_kind != SINGLE.coverage_kind:  # multisample or area coverage: counted under its own kind
        return coverage_kind
    kinds = set(scene_kinds)
    if kinds == {"lines"}:
        return "lines"
    if kinds == {"points"}:
        return "points"
    return "paths" if "paths" in kinds else "triangles"


def _identify_once(name: str, seed: int, timeout: float, cold: bool) -> dict[str, Any]:
    """One fresh process identifying ``name``: its JSON line, or ``{"fault": ...}``."""
    env = dict(os.environ)
    with tempfile.TemporaryDirectory(prefix="rastercheck-cold-numba-") as empty:
        if cold:
            env["NUMBA_CACHE_DIR"] = empty  # every kernel compiled anew, the real cache untouched
        try:
            done = subprocess.run([sys.executable, "-c", _CHILD, name, str(seed), str(timeout)], env=env,
                                  capture_output=True, text=True, timeout=max(600.0, 10 * timeout))
        except subprocess.TimeoutExpired:
            return {"fault": f"timed out after {max(600.0, 10 * timeout):g} s"}
    for line in done.stdout.splitlines():
        if line.startswith("IDENTIFY-BENCH "):
            found: dict[str, Any] = json.loads(line.removeprefix("IDENTIFY-BENCH "))
            return found
    said = (done.stderr.strip().splitlines() or [f"exit {done.returncode}"])[-1]
    return {"fault": f"no measurement (exit {done.returncode}): {said}"[:300]}


def run_identify_bench(names: Sequence[str] | None = None, *, repeats: int = 2, cold: bool = True, seed: int = 0,
                       timeout: float = 60.0, progress: Callable[[str], None] | None = None) -> list[IdentifyMeasurement]:
    """Identify each mode (``names``; default every built-in, :func:`harness.engine.registry.builtins`)
    ``repeats`` times, each in a fresh process, and (``cold``) the first mode of each kind
    once more with an empty numba cache. Ordered by kind (:data:`IDENTIFY_KINDS`), then name."""
    from harness.engine.registry import builtins

    measured: list[IdentifyMeasurement] = []
    for name in (list(names) if names else builtins()):
        runs = [_identify_once(name, seed, timeout, cold=False) for _ in range(max(1, repeats))]
        good = [r for r in runs if "fault" not in r]
        if not good:
            nan = math.nan
            measured.append(IdentifyMeasurement("identify", name, "unknown", nan, nan, nan, nan, 0, False, False,
                                                fault=runs[0]["fault"]))
            if progress is not None:
                progress(f"identify {name}: {runs[0]['fault']}")
            continue
        best = min(good, key=lambda r: float(r["seconds"]))
        kind = kind_of(str(best["coverage_kind"]), best["scene_kinds"])
        measured.append(IdentifyMeasurement(
            "identify", name, kind, float(best["seconds"]), float(best["identify_seconds"]), float(best["cpu_seconds"]),
            math.nan, int(best["calls"]), bool(best["exact"]), float(best["seconds"]) < IDENTIFY_GOAL,
            tuple(round(float(r["seconds"]), 4) for r in good)))
        if progress is not None:
            progress(f"identify {name} ({kind}): {best['seconds']:.2f} s (fingerprint {best['identify_seconds']:.2f} s, "
                     f"{best['calls']} calls)")
    ordered = sorted(measured, key=lambda m: (IDENTIFY_KINDS.index(m.kind) if m.kind in IDENTIFY_KINDS
                                              else len(IDENTIFY_KINDS), m.contender))
    if cold:
        firsts: dict[str, int] = {}
        for k, m in enumerate(ordered):
            if not m.fault:
                firsts.setdefault(m.kind, k)
        for k in firsts.values():
            m = ordered[k]
            run = _identify_once(m.contender, seed, timeout, cold=True)
            if "fault" not in run:
                from dataclasses import replace

                ordered[k] = replace(m, cold_seconds=float(run["seconds"]))
                if progress is not None:
                    progress(f"identify {m.contender}: cold (every kernel compiled) {run['seconds']:.1f} s")
    return ordered


def identify_summary(results: Sequence[IdentifyMeasurement]) -> dict[str, Any]:
    """Per kind: the modes, the slowest and the median seconds, and whether every mode is
    under the goal; and overall (``"all"``)."""
    out: dict[str, Any] = {"goal_seconds": IDENTIFY_GOAL}
    groups = {kind: [m for m in results if m.kind == kind and not m.fault]
              for kind in dict.fromkeys(m.kind for m in results if not m.fault)}
    for kind, ms in [*groups.items(), ("all", [m for m in results if not m.fault])]:
        if not ms:
            continue
        seconds = sorted(m.seconds for m in ms)
        out[kind] = {"modes": [m.contender for m in ms], "max_seconds": round(seconds[-1], 3),
                     "median_seconds": round(seconds[len(seconds) // 2], 3),
                     "max_identify_seconds": round(max(m.identify_seconds for m in ms), 3),
                     "max_cpu_seconds": round(max(m.cpu_seconds for m in ms), 3),
                     "within_goal": all(m.within_goal for m in ms)}
    out["failed"] = [m.contender for m in results if m.fault]
    return out


def format_identify_table(results: Sequence[IdentifyMeasurement]) -> str:
    """One block per kind: each mode's seconds (best of its fresh processes), the
    fingerprint's part, the processor time, the cold figure where measured, the calls, and
    the slowest of the kind against the goal."""
    lines = [f"identify: rastercheck identify <spec> per built-in mode, in a fresh process (goal: under {IDENTIFY_GOAL:g} s)"]
    lines.append(f"  {'mode':<22}{'kind':<13}{'s':>7}{'identify s':>12}{'cpu s':>8}{'cold s':>8}{'calls':>7}  goal")
    for kind in dict.fromkeys(m.kind for m in results):
        mine = [m for m in results if m.kind == kind]
        for m in mine:
            if m.fault:
                lines.append(f"  {m.contender:<22}{m.kind:<13}  {m.fault}")
                continue
            cold = f"{m.cold_seconds:8.1f}" if math.isfinite(m.cold_seconds) else f"{'-':>8}"
            lines.append(f"  {m.contender:<22}{m.kind:<13}{m.seconds:7.2f}{m.identify_seconds:12.2f}{m.cpu_seconds:8.2f}"
                         f"{cold}{m.calls:>7}  {'ok' if m.within_goal else 'OVER'}")
        good = [m for m in mine if not m.fault]
        if good:
            worst = max(good, key=lambda m: m.seconds)
            lines.append(f"  {'slowest of ' + kind + ': ' + worst.contender:<35}{worst.seconds:7.2f}")
    return "\n".join(lines)
