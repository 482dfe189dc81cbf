"""``rastercheck bench``: throughput of the oracle and the built-ins against Pillow, side by side.

Workloads (fixed seeds, 1024 x 1024):

- W1: 10,000 random triangles of mean area about 50 px;
- W2: 100 triangles of about 100,000 px each.

Pillow's ``ImageDraw.polygon``, one call per triangle, is the in-run yardstick: every
figure is reported as a ratio to it, measured in the same process, so the numbers compare
across machines. Cold start (numba compilation or cache load) is timed separately.

Beside the single-sample oracle, the oracles of the other coverage kinds: the exact area
(``oracle_area``) and the exact 4x and 8x multisample coverage (``oracle_msaa4``,
``oracle_msaa8``), with the anti-aliased fills of cairo and skia as their peers
(``cairo_aa_fill``, ``skia_aa_fill``: the libraries alone, each triangle filled into one
8-bit surface, no read-back -- the least they can cost), when installed.

Path workloads (fixed seeds, 512 x 512; :func:`path_workloads`), each under both fill rules:

- P1-nonzero, P1-evenodd: 1,000 {10/3} stars (10 vertices, one self-intersecting contour
  each; random centres, radii 4 to 40 px and rotations);
- P2-nonzero, P2-evenodd: one closed wiggly curve of 100,000 vertices that winds twice
  around the centre (self-intersecting: where the two turns overlap nonzero and even-odd
  part).
- P3-nonzero, P3-evenodd: 1,000 glyph-like outlines (an "o": a ring of 24 short edges,
  its counter wound against it, and a bar overlapping both, as variable fonts overlap
  contours; heights 6 to 30 px).

The exact area oracle of paths (``oracle_area``, :func:`harness.oracle.path_area.path_area_coverage`)
against the libraries' anti-aliased path fills (``cairo_aa_path``: cairo's default
anti-aliasing; ``skia_aa_path``: ``drawPath`` with ``AntiAlias=True``), likewise.

The exact winding oracle (``oracle``, :func:`harness.oracle.coverage.exact_coverage` on the path
scene) against the aliased path fills of the libraries, each path filled in one call into
one 8-bit surface, no read-back: Pillow's ``ImageDraw.polygon`` (the yardstick again;
even-odd, whatever the rule asked), cairo (``cairo_fill``: ``ANTIALIAS_NONE``, the scene's
fill rule), skia (``skia_fill``: ``drawPath`` without anti-aliasing, the scene's fill type)
and scikit-image (``skimage_polygon``: ``draw.polygon``, even-odd); and each rasterizer
that takes the scene (:func:`harness.contract.protocol.takes`). A library's time includes handing it the
vertices through its Python binding, as for the triangle peers.

Line workloads (fixed seeds, 1024 x 1024; :func:`line_workloads`), width 1:

- L1: 100,000 short segments (lengths 2 to 16 px, random directions);
- L2: 1,000 long segments (end points anywhere on the screen, at least 256 px apart).

Every segment stays inside the viewport (no peer clips). The exact line oracles, one per
rule (``oracle_diamond_exit``, ``oracle_bresenham``, ``oracle_rectangle``:
:func:`harness.oracle.coverage.exact_coverage` under ``Convention(line=...)``), against the aliased
line drawers of the libraries, each segment one call into one 8-bit image, no read-back:
Pillow's ``ImageDraw.line`` (the yardstick: integer Bresenham between the end points
truncated to pixels), scikit-image's ``draw.line`` (``skimage_line``: Bresenham between the
pixels whose centres are nearest the end points, the pixels set by a fancy index) -- on
these workloads both draw exactly the Bresenham oracle's pixels --, cairo's hairline
(``cairo_line``: width 1, ``ANTIALIAS_NONE``, each segment stroked: nearly the rectangle
oracle's) and skia's (``skia_hairline``: ``drawLine`` with stroke width 0, no
anti-aliasing: nearest the diamond-exit oracle's), when installed; and each rasterizer
that takes lines. Rates are in segments per second.

Anti-aliased stroke workloads (fixed seeds, 512 x 512; :func:`stroke_workloads`), butt caps:

- S1: 1,000 segments of lengths 4 to 64 px in random directions, width 1.5;
- S2: the same at width 4.

The exact stroke-area oracle (``oracle_area``, :func:`harness.oracle.area_lines.line_area_coverage`
under :data:`STROKE_ORACLE`) against the libraries' anti-aliased strokes, each segment one
call into one 8-bit surface, no read-back: cairo (``cairo_aa_stroke``: its default
anti-aliasing) and skia (``skia_aa_stroke``: ``drawLine`` with ``AntiAlias=True``), when
installed; Pillow's aliased ``ImageDraw.line`` at the width rounded is the yardstick.

Every contender is measured in a forked process of its own, each call within a time limit
(``--timeout``; see the section on isolation below): a crash, a hang, a raise or an answer
that is no coverage is that contender's row (:attr:`Measurement.fault`), and the others go
on. The clock times the drawing call alone, in that process, as it did in one.

The campaign workload (``rastercheck bench --campaign``; :func:`run_campaign_bench`): a
campaign (:func:`harness.campaign.coordinator.run_campaign`) of a fixed scene budget on a built-in
reference (``pineda_topleft``: it passes, so nothing is shrunk) over every fuzz family it
takes, first on a ``LocalCluster`` of one worker process, then of two
(:func:`harness.campaign.cluster.local_cluster`, as a campaign starts by default): end-to-end checked
primitives per second (generation, the isolated rasterize calls, every check against the
exact oracle, the coordinator merging and saving the state) per worker, and the speed-up
from one worker to two. The workers are started and warmed (the harness imported, the
kernels loaded, one scene of each family checked) before the clock starts: the figure is
a campaign's steady state, which is what a long one runs in.

Here the measuring (each contender in a process of its own), the table and the JSON; the
workloads are :mod:`harness.cli.bench_workloads`, the library peers
:mod:`harness.cli.bench_peers`, the campaign workload :mod:`harness.cli.bench_campaign`
(their public names re-exported here), the command :mod:`harness.cli.bench_command`.
"""

from __future__ import annotations

import json
import math
import multiprocessing
import os
import platform
import signal
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image

from harness.cli.bench_identify import IdentifyMeasurement
from harness.cli.bench_peers import (
    _library_peers,
    _line_peers,
    _path_peers,
    _pillow,
    _pillow_lines,
    _pillow_paths,
    _pillow_strokes,
    _stroke_peers,
    _Surface,
    _unmeasured,
    missing_peers,
)
from harness.cli.bench_workloads import (
    Workload,
    line_workloads,
    long_segments,
    path_workloads,
    short_segments,
    stars,
    stroke_workloads,
    wiggly_outline,
    workloads,
)
from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import model_named
from harness.contract.protocol import coverage_kind_of, takes
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene
from harness.engine.isolation import _exit_with_parent, describe, span_limit
from harness.engine.registry import builtins, load
from harness.kinds import PATHS
from harness.oracle.coverage import RECENT_ANSWERS, exact_coverage

__all__ = ["Workload", "workloads", "path_workloads", "line_workloads", "stroke_workloads", "short_segments",
           "long_segments", "stars", "wiggly_outline", "run_bench", "STROKE_ORACLE", "format_table", "LINE_ORACLES",
           "DEFAULT_TIMEOUT", "failures_by_contender", "Measurement", "write_json", "missing_peers", "CampaignMeasurement"]


DEFAULT_TIMEOUT = 60.0  # seconds one call of a contender may take (``--timeout``; as ``run``'s)


@dataclass(frozen=True, slots=True)
class Measurement:
    """One contender on one workload. ``triangles_per_second`` is primitives per second:
    paths for a path workload, segments for a line workload (``unit``).

    ``fault`` says why nothing was measured ("crashed (signal 11, SIGSEGV)", "timed out
    after 60 s", "raised ValueError: ...", "no coverage ..."; the figures are then NaN);
    ``note`` what was not counted of a measured answer (malformed spans)."""

    workload: str
    contender: str
    cold_seconds: float
    seconds: float
    triangles_per_second: float
    ratio_to_pillow: float
    pixels: int
    unit: str = "triangles"
    description: str = ""
    fault: str = ""
    note: str = ""


@dataclass(frozen=True, slots=True)
class CampaignMeasurement:
    """One campaign of the fixed scene budget on ``workers`` local worker processes.

    ``seconds`` runs from the first batch sent to the last one merged (the coordinator's
    own clock, :class:`harness.campaign.state.ProgressEvent`); ``startup_seconds`` is what
    starting and warming the workers took before it. ``primitives`` are those checked
    (triangles, and every frame's of a motion sequence); ``per_worker`` is
    ``primitives_per_second / workers``; ``speedup`` the primitives per second against
    the first measurement's (one worker); ``runs`` the seconds of every run of this
    count (the measurement is the fastest); ``breakdown`` the milliseconds per scene of
    each part of the work (:func:`harness.cli.bench_campaign.per_scene_breakdown`);
    ``cores`` the cores its processes were held to (0: free to use every one)."""

    workload: str
    contender: str
    workers: int
    scenes: int
    primitives: int
    findings: int
    seconds: float
    startup_seconds: float
    scenes_per_second: float
    primitives_per_second: float
    per_worker: float
    speedup: float
    unit: str = "primitives"
    description: str = ""
    runs: tuple[float, ...] = ()
    failed_calls: int = 0
    breakdown: dict[str, float] = field(default_factory=dict)
    cores: int = 0


# The oracles of each coverage kind the bench measures.
ORACLES: dict[str, Convention] = {
    "oracle": Convention(),
    "oracle_area": Convention(coverage="area"),
    "oracle_msaa4": Convention(samples=4),
    "oracle_msaa8": Convention(samples=8),
}


# The line oracles the bench measures: one per rule, width 1.
LINE_ORACLES: dict[str, Convention] = {
    "oracle_diamond_exit": Convention(line="diamond-exit"),
    "oracle_bresenham": Convention(line="bresenham"),
    "oracle_rectangle": Convention(line="rectangle"),
}


# The exact stroke-area oracle the anti-aliased stroke workloads measure (butt caps).
STROKE_ORACLE = Convention(coverage="area", line=LineRule("rectangle", cap="butt"))


def _pixels(result: object) -> int:
    """Pixels drawn (Pillow and the library fills: pixels set; rasterizers: fragments,
    one per sample for multisample coverage)."""
    if isinstance(result, Image.Image):
        return int(np.count_nonzero(np.asarray(result)))
    if isinstance(result, np.ndarray):
        return int(np.count_nonzero(result))
    if isinstance(result, _Surface):
        return int(np.count_nonzero(result.read()))
    return int(result.n_pixels)  # type: ignore[attr-defined]


def _time(fn: Callable[[], object], budget: float, count: Callable[[object], int] = _pixels,
          heard: Callable[[float, object], None] | None = None) -> tuple[float, float, int, int]:
    """(cold seconds, best seconds, pixels, warm runs): only the drawing call is timed.

    Warm repeats run while the next one fits in the ``budget`` (at least one -- the cold
    call pays for compilation and is no throughput -- at most 50): the budget caps the
    time of the repeats, not only their count. ``count`` turns the cold call's answer into
    its pixels; ``heard`` hears each call's seconds and answer (outside the clock) as soon
    as it is made: the isolated contender's heartbeat (:func:`_serve_contender`)."""
    start = time.perf_counter()
    result = fn()
    cold = time.perf_counter() - start
    pixels = count(result)
    if heard is not None:
        heard(cold, result)
    best = float("inf")
    runs = 0
    deadline = time.perf_counter() + budget
    while runs < 50:
        left = deadline - time.perf_counter()
        if runs >= 1 and best > left:
            break  # the next repeat would overrun the budget
        start = time.perf_counter()
        again = fn()
        seconds = time.perf_counter() - start
        best = min(best, seconds)
        runs += 1
        if heard is not None:
            heard(seconds, again)
    return cold, best, pixels, runs


def _line_contenders(scene: LineScene) -> list[tuple[str, Callable[[], object]]]:
    contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow_lines, scene))]
    contenders += [(label, partial(exact_coverage, scene, convention)) for label, convention in LINE_ORACLES.items()]
    contenders += [(label, partial(draw, scene)) for label, draw in _line_peers()]
    return contenders


def _stroke_contenders(scene: LineScene) -> list[tuple[str, Callable[[], object]]]:
    contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow_strokes, scene)),
                                                          ("oracle_area", partial(exact_coverage, scene, STROKE_ORACLE))]
    contenders += [(label, partial(draw, scene)) for label, draw in _stroke_peers()]
    return contenders


def _path_contenders(scene: PathScene) -> list[tuple[str, Callable[[], object]]]:
    contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow_paths, scene)),
                                                          ("oracle", partial(exact_coverage, scene, ORACLES["oracle"])),
                                                          ("oracle_area", partial(exact_coverage, scene, ORACLES["oracle_area"]))]
    contenders += [(label, partial(fill, scene)) for label, fill in _path_peers() if not _unmeasured(label, scene)]
    return contenders


def _triangle_contenders(scene: Scene) -> list[tuple[str, Callable[[], object]]]:
    contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow, scene))]
    contenders += [(label, partial(exact_coverage, scene, convention)) for label, convention in ORACLES.items()]
    contenders += [(label, partial(fill, scene)) for label, fill in _library_peers()]
    return contenders


# The bench's contenders per scene kind: Pillow, the oracles, the kind's library peers.
_CONTENDERS: dict[str, Callable[[Any], list[tuple[str, Callable[[], object]]]]] = {
    "triangles": _triangle_contenders, "paths": _path_contenders, "lines": _line_contenders}


def _fixed_contenders(work: Workload) -> list[tuple[str, Callable[[], object]]]:
    """Pillow first (the yardstick), the oracles, then the library peers of the workload's
    scene kind (an anti-aliased stroke workload's: the stroke-area oracle and the
    libraries' anti-aliased strokes)."""
    if work.anti_aliased:
        return _stroke_contenders(work.scene)  # type: ignore[arg-type]
    return _CONTENDERS[work.scene.kind](work.scene)


def _contenders(work: Workload, rasterizers: list[Any]) -> list[tuple[str, Callable[[], object]]]:
    """Pillow first (the yardstick), the oracles, the library peers, then each rasterizer
    that takes the workload's scene."""
    scene = work.scene
    return _fixed_contenders(work) + [(r.name, partial(r.rasterize, scene)) for r in rasterizers if _measured_on(r, work)]


def _measured_on(rasterizer: Any, work: Workload) -> bool:
    """Whether a rasterizer is measured on a workload: it takes the scene, and for an
    anti-aliased stroke workload it anti-aliases (area coverage: an aliased line drawer
    is no peer of a wide anti-aliased stroke, and most draw width 1 only)."""
    return takes(rasterizer, work.scene) and (not work.anti_aliased or model_named(coverage_kind_of(rasterizer)).alphas)


# -- isolation: every contender measured in a process of its own -------------------------------
#
# A rasterizer under bench is a plugin: it may raise, answer garbage, segfault, end its
# process or never answer. Every contender -- Pillow, the oracles, the library peers and the
# rasterizers alike -- is therefore measured in a forked process of its own (one per
# contender, kept from workload to workload so that kernels compiled or loaded by its first
# call stay loaded, as they did in one process; replaced after a crash or a timeout), each of
# its calls within the time limit (``--timeout``). The child runs the very timing loop the
# bench ran in its own process (:func:`_time`: the clock around the drawing call alone, a
# cold call first, then the warm repeats within the budget) and reports each call as it
# ends, so the figures and their ratios to Pillow are measured as before: the process's
# start-up, the pipe and the checks of an answer are outside the clock, and the parent
# waits idle while a child measures.
#
# Not :class:`harness.engine.isolation.Worker` itself: a Worker sends each scene and gets each
# answer back as a Coverage, while the library peers draw into surfaces that cannot cross
# a pipe (cairo's, skia's) and are counted where they were drawn. A rasterizer's answer is
# checked as a Worker's is (a Coverage, within :func:`harness.engine.isolation.span_limit` spans,
# tidied: :meth:`harness.contract.coverage.Coverage.tidy`), outside the clock, and its exceptions are
# described as the Worker's (:func:`harness.engine.isolation.describe`).


class _Unusable(Exception):
    """A contender's answer that is no measurement (its text is the row's fault)."""


def _one_line(text: str, most: int = 200) -> str:
    """``text`` on one line, at most ``most`` characters."""
    flat = " ".join(text.split())
    return flat if len(flat) <= most else flat[: most - 3] + "..."


def _counted(answer: object, scene: AnyScene) -> tuple[int, str]:
    """A rasterizer's first answer on ``scene``: its fragments once tidied (malformed spans
    not counted) and what was not counted, in words ("" when nothing); :class:`_Unusable`
    when it is no Coverage or holds more than :func:`span_limit` spans."""
    if not isinstance(answer, Coverage):
        raise _Unusable(f"no coverage (rasterize returned {type(answer).__name__}, not a harness.Coverage)")
    if len(answer) > span_limit(scene):
        raise _Unusable(f"garbage: an answer of {len(answer):,} spans ({len(scene):,} {scene.noun}s on "
                        f"{scene.height:,} rows need at most {span_limit(scene):,})")
    usable, flaws = answer.tidy(scene)
    if usable is answer:
        return int(usable.n_pixels), ""
    kinds = {kind: len(spans) for kind, spans in flaws.items() if kind != "repeated_pixels" and len(spans)}
    return int(usable.n_pixels), "not counted: " + ", ".join(f"{n:,} span{'s' if n > 1 else ''} {kind.replace('_', ' ')}"
                                                             for kind, n in kinds.items())


def _measure_here(fn: Callable[[], object], scene: AnyScene, budget: float, plugin: bool,
                  send: Callable[[tuple[Any, ...]], None]) -> tuple[Any, ...]:
    """In the contender's process: :func:`_time` on ``fn``, ``("call", seconds)`` sent
    after each call; ``("done", cold, best, pixels, runs, note)`` or ``("fault", text)``.
    A rasterizer's answers (``plugin``) must be Coverages, the first within the span limit."""
    notes: list[str] = []

    def count(answer: object) -> int:
        if not plugin:
            return _pixels(answer)
        pixels, note = _counted(answer, scene)
        notes.append(note)
        return pixels

    def heard(seconds: float, answer: object) -> None:
        if plugin and not isinstance(answer, Coverage):
            raise _Unusable(f"no coverage on a warm run (rasterize returned {type(answer).__name__}, not a harness.Coverage)")
        send(("call", seconds))

    try:
        with RECENT_ANSWERS.off():  # the oracles' repeats are timed computing, not looked up
            cold, best, pixels, runs = _time(fn, budget, count, heard)
    except _Unusable as exc:
        return ("fault", str(exc))
    except BaseException as exc:  # noqa: B036 - a plugin's KeyboardInterrupt or SystemExit is its failure
        return ("fault", f"raised {describe(exc)}")
    return ("done", cold, best, pixels, runs, notes[0] if notes else "")


def _serve_contender(calls: dict[str, tuple[Callable[[], object], AnyScene]], plugin: bool,  # pragma: no cover - the child's
                     conn: Any) -> None:
    """The child of :class:`_Isolated`: for each workload asked (its name and the budget),
    :func:`_measure_here` on the call of that workload."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    _exit_with_parent()
    while True:
        try:
            work, budget = conn.recv()
        except (EOFError, OSError):
            return
        fn, scene = calls[work]
        conn.send(_measure_here(fn, scene, budget, plugin, conn.send))


def _exit_fault(code: int | None) -> str:
    """A contender's process that ended without answering, in words.

    >>> _exit_fault(-11), _exit_fault(0)
    ('crashed (signal 11, SIGSEGV)', 'its process exited with code 0 without answering')
    """
    if code is not None and code < 0:
        try:
            name = f", {signal.Signals(-code).name}"
        except ValueError:
            name = ""
        return f"crashed (signal {-code}{name})"
    return f"its process exited with code {code} without answering"


class _Isolated:
    """One contender in a forked process of its own (started at its first workload,
    replaced after a crash or a timeout), each call within ``timeout`` seconds.

    Parameters
    ----------
    calls : dict
        ``{workload name: (the call, its scene)}``, inherited by the child (nothing is sent
        but the workload's name).
    plugin : bool
        The contender is a rasterizer: its answer must be a Coverage within the span limit.
    timeout : float
        The most seconds one call may take.
    """

    def __init__(self, calls: dict[str, tuple[Callable[[], object], AnyScene]], plugin: bool, timeout: float) -> None:
        self.calls = calls
        self.plugin = plugin
        self.timeout = timeout
        self._context = multiprocessing.get_context("fork")
        self._process: Any = None
        self._conn: Any = None

    def _start(self) -> None:
        self._conn, child = self._context.Pipe()
        self._process = self._context.Process(target=_serve_contender, args=(self.calls, self.plugin, child), daemon=True)
        self._process.start()
        child.close()

    def measure(self, work: str, budget: float) -> tuple[Any, ...]:
        """``("done", cold, best, pixels, runs, note)`` or ``("fault", text)`` of the
        contender on ``work``."""
        if self._process is None:
            self._start()
        try:
            self._conn.send((work, budget))
        except OSError:
            return self._died()
        while True:
            try:
                if not self._conn.poll(self.timeout):
                    self.close()
                    return ("fault", f"timed out after {self.timeout:g} s")
                message = self._conn.recv()
            except (EOFError, OSError):
                return self._died()
            if message[0] != "call":
                return tuple(message)

    def _died(self) -> tuple[str, str]:
        self._process.join(5)
        code = self._process.exitcode
        self.close()
        return ("fault", _exit_fault(code))

    def close(self) -> None:
        """End the contender's process (a new one starts at the next workload)."""
        if self._process is None:
            return
        if self._process.is_alive():
            self._process.kill()
        self._process.join(5)
        self._conn.close()
        self._process = self._conn = None


def run_bench(names: list[str] | None = None, scale: float = 1.0, budget: float = 1.0,
              progress: Callable[[str], None] | None = None, paths: bool = True, lines: bool = True,
              triangles: bool = True, timeout: float = DEFAULT_TIMEOUT, strokes: bool = False) -> list[Measurement]:
    """Measure Pillow, the oracle and each rasterizer on W1 and W2 (with ``triangles``),
    then (with ``paths``) Pillow, the winding oracle, the library path fills and each
    path-taking rasterizer on the path workloads, then (with ``lines``) Pillow, the three
    line oracles, the library line drawers and each line-taking rasterizer on the line
    workloads, then (with ``strokes``; the command measures them unless ``--kinds`` leaves
    them out) Pillow, the exact stroke-area oracle, the libraries' anti-aliased strokes and
    each anti-aliasing (area coverage) line-taking rasterizer on the stroke workloads,
    each contender in a process of its own, each call within ``timeout`` seconds;
    ``progress`` hears a line before and after each contender.

    A contender that crashes, hangs, raises or answers garbage on a workload is that
    workload's row (:attr:`Measurement.fault`) and the others go on; a workload whose
    Pillow failed has no ratios (NaN)."""
    from harness.engine.registry import distinct_names

    names = names if names is not None else builtins()
    rasterizers: list[Any] = distinct_names([load(n) for n in names])  # a path or line scene only to those that take it
    chosen = ((workloads(scale) if triangles else []) + (path_workloads(scale) if paths else [])
              + (line_workloads(scale) if lines else []) + (stroke_workloads(scale) if strokes else []))
    # each contender's calls, by workload: the key of a rasterizer is its place (a name of its
    # own may be any, "pillow" or "oracle" too)
    lineup: list[list[tuple[str, str, bool]]] = []  # per workload: (key, label, plugin)
    calls: dict[str, dict[str, tuple[Callable[[], object], AnyScene]]] = {}
    for work in chosen:
        entries = [(label, label, False, fn) for label, fn in _fixed_contenders(work)]
        entries += [(f"rasterizer {k}", r.name, True, partial(r.rasterize, work.scene)) for k, r in enumerate(rasterizers)
                    if _measured_on(r, work)]
        lineup.append([(key, label, plugin) for key, label, plugin, _ in entries])
        for key, _, _, fn in entries:
            calls.setdefault(key, {})[work.name] = (fn, work.scene)
    last = {key: k for k, row in enumerate(lineup) for key, _, _ in row}
    isolated: dict[str, _Isolated] = {}
    results = []
    nan = float("nan")
    try:
        for k, (work, row) in enumerate(zip(chosen, lineup)):
            unit = f"{work.scene.noun}s"  # triangles, paths, segments
            if progress is not None and PATHS.owns(work.scene):
                for label, _ in _path_peers():
                    if _unmeasured(label, work.scene):
                        progress(f"{work.name} {label}: {_unmeasured(label, work.scene)}")
            pillow_rate = nan
            for place, (key, label, plugin) in enumerate(row):
                if progress is not None:
                    progress(f"{work.name} {label}: measuring ...")
                if key not in isolated:
                    isolated[key] = _Isolated(calls[key], plugin, timeout)
                contender = isolated[key]
                answer = contender.measure(work.name, budget)
                if last[key] == k:
                    contender.close()
                if answer[0] == "fault":
                    fault = _one_line(answer[1])
                    if progress is not None:
                        progress(f"{work.name} {label}: {fault}")
                    results.append(Measurement(work.name, label, nan, nan, nan, nan, 0, unit, work.description, fault=fault))
                    continue
                _, cold, seconds, pixels, runs, note = answer
                if progress is not None:
                    progress(f"{work.name} {label}: best {seconds * 1e3:.1f} ms of {runs} warm runs (cold {cold:.2f} s)")
                rate = len(work.scene) / seconds
                if place == 0:
                    pillow_rate = rate
                results.append(Measurement(work.name, label, cold, seconds, rate, rate / pillow_rate, pixels, unit,
                                           work.description, note=note))
    finally:
        for contender in isolated.values():
            contender.close()
    return results


def failures_by_contender(results: Sequence[Measurement]) -> dict[str, str]:
    """One line per contender that failed on some workload: its faults and where, and
    whether anything of it was measured.

    >>> from dataclasses import replace
    >>> bad = Measurement("W1", "mine", 0, 0, 0, 0, 0, fault="raised ValueError: no")
    >>> failures_by_contender([bad, replace(bad, workload="W2")])
    {'mine': 'nothing measured: raised ValueError: no (W1, W2)'}
    """
    out = {}
    for contender in dict.fromkeys(m.contender for m in results if m.fault):
        mine = [m for m in results if m.contender == contender]
        by_fault: dict[str, list[str]] = {}
        for m in mine:
            if m.fault:
                by_fault.setdefault(m.fault, []).append(m.workload)
        said = "; ".join(f"{fault} ({', '.join(works)})" for fault, works in by_fault.items())
        measured = [m.workload for m in mine if not m.fault]
        out[contender] = (f"{said}; measured on {', '.join(measured)}" if measured else f"nothing measured: {said}")
    return out


def _figure(value: float, spec: str) -> str:
    """``value`` formatted by ``spec``, or ``-`` when it is not a number."""
    return format(value, spec) if math.isfinite(value) else "-"


def format_table(results: list[Measurement], descriptions: dict[str, str]) -> str:
    """One block per workload: each contender's rate, ratio to Pillow, best and cold time
    and pixels, or why it has none; a workload missing from ``descriptions`` is described
    by its measurements."""
    lines = []
    for work in dict.fromkeys(m.workload for m in results):
        mine = [m for m in results if m.workload == work]
        lines.append(f"{work}: {descriptions.get(work) or mine[0].description}")
        lines.append(f"  {'contender':<18}{mine[0].unit + '/s':>14}{'x Pillow':>10}{'best ms':>10}{'cold s':>9}{'pixels':>11}")
        for m in mine:
            if m.fault:
                lines.append(f"  {m.contender:<18}  {m.fault}")
                continue
            lines.append(
                f"  {m.contender:<18}{m.triangles_per_second:>14,.0f}{_figure(m.ratio_to_pillow, '>10.2f'):>10}"
                f"{m.seconds * 1e3:>10.2f}{m.cold_seconds:>9.2f}{m.pixels:>11,}" + (f"   ({m.note})" if m.note else "")
            )
    return "\n".join(lines)


def _finite(row: dict[str, Any]) -> dict[str, Any]:
    """``row`` with every non-finite float as None (JSON has no NaN)."""
    return {k: None if isinstance(v, float) and not math.isfinite(v) else v for k, v in row.items()}


def write_json(results: Sequence[Measurement | CampaignMeasurement | IdentifyMeasurement], path: Path,
               summary: dict[str, Any] | None = None, not_measured: dict[str, str] | None = None) -> None:
    """The measurements as JSON (schema 1), with the machine and the date; ``summary``
    (e.g. the campaign's speed-up, :func:`campaign_summary`) goes in as ``"summary"``,
    the peers not measured, with why (:func:`missing_peers`), as ``"not_measured"``, and
    the rows of contenders that failed (their ``fault``) as ``"failed"``, not among the
    ``"results"``."""
    from harness.results.files import atomic_write_text

    payload: dict[str, Any] = {
        "schema": 1,
        "machine": {"platform": platform.platform(), "python": platform.python_version(), "cpus": os.cpu_count()},
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "results": [_finite(asdict(m)) for m in results if not getattr(m, "fault", "")],
    }
    failed = [{"workload": m.workload, "contender": m.contender, "fault": m.fault} for m in results
              if isinstance(m, (Measurement, IdentifyMeasurement)) and m.fault]
    if failed:
        payload["failed"] = failed
    if summary is not None:
        payload["summary"] = summary
    if not_measured:
        payload["not_measured"] = not_measured
    atomic_write_text(path, json.dumps(payload, indent=2))
