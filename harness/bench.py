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
"""

from __future__ import annotations

from functools import partial

import json
import os
import platform
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from harness.api import Scene
from harness.conventions import Convention
from harness.oracle import exact_coverage
from harness.registry import builtins, load
from cases.scenes import random_triangles

__all__ = ["Workload", "workloads", "run_bench", "format_table"]

SIZE = 1024


@dataclass(frozen=True, slots=True)
class Workload:
    name: str
    description: str
    scene: Scene
    mean_area: float


@dataclass(frozen=True, slots=True)
class Measurement:
    workload: str
    contender: str
    cold_seconds: float
    seconds: float
    triangles_per_second: float
    ratio_to_pillow: float
    pixels: int


def workloads(scale: float = 1.0) -> list[Workload]:
    """W1 and W2; ``scale`` < 1 shrinks the triangle counts (for smoke tests)."""
    out = []
    for name, count, area, seed in (("W1", 10_000, 50.0, 1), ("W2", 100, 100_000.0, 2)):
        n = max(1, int(count * scale))
        positions = random_triangles(n, area, SIZE, seed)
        p = positions
        areas = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
        out.append(Workload(name, f"{n} triangles, mean area {areas.mean():,.0f} px", Scene(SIZE, SIZE, positions), float(areas.mean())))
    return out


def _pillow(scene: Scene) -> Image.Image:
    image = Image.new("L", (scene.width, scene.height), 0)
    draw = ImageDraw.Draw(image)
    # Pillow puts pixel centres at integers: shift by half a pixel to draw the same triangles.
    for tri in (scene.positions - 0.5).tolist():
        draw.polygon([tuple(v) for v in tri], fill=255)
    return image


def _cairo_aa(scene: Scene) -> np.ndarray:
    """cairo's anti-aliased fill (``ANTIALIAS_DEFAULT``) of each triangle into one A8 surface."""
    import cairo

    surface = cairo.ImageSurface(cairo.FORMAT_A8, scene.width, scene.height)
    context = cairo.Context(surface)
    for (ax, ay), (bx, by), (cx, cy) in scene.positions.tolist():
        context.move_to(ax, ay)
        context.line_to(bx, by)
        context.line_to(cx, cy)
        context.close_path()
        context.fill()
    surface.flush()
    return np.frombuffer(surface.get_data(), dtype=np.uint8)


def _skia_aa(scene: Scene) -> np.ndarray:
    """skia's anti-aliased path fill of each triangle into one 8-bit alpha surface."""
    import skia

    surface = skia.Surface.MakeRaster(skia.ImageInfo.MakeA8(scene.width, scene.height))
    canvas = surface.getCanvas()
    paint = skia.Paint(AntiAlias=True)
    for (ax, ay), (bx, by), (cx, cy) in scene.positions.tolist():
        path = skia.Path()
        path.moveTo(ax, ay)
        path.lineTo(bx, by)
        path.lineTo(cx, cy)
        path.close()
        canvas.drawPath(path, paint)
    return np.asarray(surface.makeImageSnapshot().toarray())


def _library_peers() -> list[tuple[str, Callable[[Scene], object]]]:
    """The anti-aliased library fills that are installed here."""
    peers: list[tuple[str, Callable[[Scene], object]]] = []
    for label, module, fill in (("cairo_aa_fill", "cairo", _cairo_aa), ("skia_aa_fill", "skia", _skia_aa)):
        try:
            __import__(module)
        except Exception:  # noqa: BLE001 - not installed (or broken): no peer, the table says which ran
            continue
        peers.append((label, fill))
    return peers


# The oracles of each coverage kind the bench measures.
ORACLES: dict[str, Convention] = {
    "oracle": Convention(),
    "oracle_area": Convention(coverage="area"),
    "oracle_msaa4": Convention(samples=4),
    "oracle_msaa8": Convention(samples=8),
}


def _pixels(result: object) -> int:
    """Pixels drawn (Pillow and the library fills: pixels set; rasterizers: fragments,
    one per sample for multisample coverage)."""
    if isinstance(result, Image.Image):
        return int(np.count_nonzero(np.asarray(result)))
    if isinstance(result, np.ndarray):
        return int(np.count_nonzero(result))
    return int(result.n_pixels)  # type: ignore[attr-defined]


def _time(fn: Callable[[], object], budget: float) -> tuple[float, float, int, int]:
    """(cold seconds, best seconds, pixels, warm runs): only the drawing call is timed.

    Warm repeats run while the next one fits in the ``budget`` (at least one -- the cold
    call pays for compilation and is no throughput -- at most 50): the budget caps the
    time of the repeats, not only their count."""
    start = time.perf_counter()
    result = fn()
    cold = time.perf_counter() - start
    pixels = _pixels(result)
    best = float("inf")
    runs = 0
    deadline = time.perf_counter() + budget
    while runs < 50:
        left = deadline - time.perf_counter()
        if runs >= 1 and best > left:
            break  # the next repeat would overrun the budget
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
        runs += 1
    return cold, best, pixels, runs


def run_bench(names: list[str] | None = None, scale: float = 1.0, budget: float = 1.0,
              progress: Callable[[str], None] | None = None) -> list[Measurement]:
    """Measure Pillow, the oracle and each rasterizer on W1 and W2 in this process;
    ``progress`` hears a line before and after each contender."""
    names = names if names is not None else builtins()
    rasterizers = [load(n) for n in names]
    results = []
    peers = _library_peers()
    for work in workloads(scale):
        contenders: list[tuple[str, Callable[[], object]]] = [("pillow", partial(_pillow, work.scene))]
        contenders += [(label, partial(exact_coverage, work.scene, convention)) for label, convention in ORACLES.items()]
        contenders += [(label, partial(fill, work.scene)) for label, fill in peers]
        for r in rasterizers:
            contenders.append((r.name, partial(r.rasterize, work.scene)))
        pillow_rate = None
        for label, fn in contenders:
            if progress is not None:
                progress(f"{work.name} {label}: measuring ...")
            cold, seconds, pixels, runs = _time(fn, budget)
            if progress is not None:
                progress(f"{work.name} {label}: best {seconds * 1e3:.1f} ms of {runs} warm runs (cold {cold:.2f} s)")
            rate = len(work.scene) / seconds
            if pillow_rate is None:
                pillow_rate = rate
            results.append(Measurement(work.name, label, cold, seconds, rate, rate / pillow_rate, pixels))
    return results


def format_table(results: list[Measurement], descriptions: dict[str, str]) -> str:
    lines = []
    for work in dict.fromkeys(m.workload for m in results):
        lines.append(f"{work}: {descriptions.get(work, '')}")
        lines.append(f"  {'contender':<18}{'triangles/s':>14}{'x Pillow':>10}{'best ms':>10}{'cold s':>9}{'pixels':>11}")
        for m in (m for m in results if m.workload == work):
            lines.append(
                f"  {m.contender:<18}{m.triangles_per_second:>14,.0f}{m.ratio_to_pillow:>10.2f}"
                f"{m.seconds * 1e3:>10.2f}{m.cold_seconds:>9.2f}{m.pixels:>11,}"
            )
    return "\n".join(lines)


def write_json(results: list[Measurement], path: Path) -> None:
    from harness.files import atomic_write_text

    payload = {
        "schema": 1,
        "machine": {"platform": platform.platform(), "python": platform.python_version(), "cpus": os.cpu_count()},
        "date": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "results": [asdict(m) for m in results],
    }
    atomic_write_text(path, json.dumps(payload, indent=2))
