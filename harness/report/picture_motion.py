"""Pictures of motion failures: the sequence as an animation with its offending pixels
marked (:func:`motion_animation`), and the per-frame series as a plot (:func:`series_plot`,
matplotlib imported when one is drawn)."""

from __future__ import annotations

import base64
import io
import textwrap
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from harness.contract.coverage import Coverage
from harness.report.picture_kit import LEGEND

__all__ = ["motion_animation", "series_plot", "series_label", "SERIES"]


MAX_FRAMES = 48


MAX_SIDE = 64  # pixels of the viewport shown: a window around the evidence


def _texel_colours(ids: NDArray) -> NDArray:
    rng = np.random.default_rng(7)
    palette = rng.integers(60, 230, size=(4096, 3))
    return palette[ids % 4096]


def motion_animation(coverages: list[Coverage], oracles: list[Coverage] | None, width: int, height: int,
                     marks: list[dict[str, Any]] | None = None, texels: int | None = None, scale: int = 6) -> str:
    """An animated GIF (data URI) of the sequence: coverage (or texel ids when textured)
    against the oracle (none without a convention), with the evidence's frames, pixels and
    rows marked.

    Frames beyond ``MAX_FRAMES`` are sampled evenly; marked frames are always kept.
    """
    marks = marks or []
    count = len(coverages)
    # a window of at most MAX_SIDE x MAX_SIDE pixels around the first mark, or the coverage
    xs = [int(m.get("x", m.get("column", 0))) for m in marks]
    ys = [int(m.get("y", m.get("row", 0))) for m in marks]
    if not xs:
        t, x, y = coverages[0].pixels()
        xs, ys = (x.tolist() or [0]), (y.tolist() or [0])
    cx = int(np.clip(xs[0], 0, width - 1)) if marks else (min(xs) + max(xs)) // 2
    cy = int(np.clip(ys[0], 0, height - 1)) if marks else (min(ys) + max(ys)) // 2
    wx0 = int(np.clip(cx - MAX_SIDE // 2, 0, max(width - MAX_SIDE, 0)))
    wy0 = int(np.clip(cy - MAX_SIDE // 2, 0, max(height - MAX_SIDE, 0)))
    wx1, wy1 = min(wx0 + MAX_SIDE, width), min(wy0 + MAX_SIDE, height)
    keep = set(np.linspace(0, count - 1, min(count, MAX_FRAMES)).astype(int).tolist())
    keep |= {int(m["frame"]) for m in marks if "frame" in m and int(m["frame"]) < count}
    images = []
    for f in sorted(keep):
        got = coverages[f].counts(width, height) > 0
        want = oracles[f].counts(width, height) > 0 if oracles is not None else got
        rgb = np.full((height, width, 3), 255, dtype=np.uint8)
        if texels and coverages[f].attributes is not None and coverages[f].attributes.shape[0] == coverages[f].n_pixels:
            t, x, y = coverages[f].pixels()
            ok = (x >= 0) & (x < width) & (y >= 0) & (y < height)
            uv = np.nan_to_num(coverages[f].attributes[ok, :2] * texels).astype(np.int64)
            rgb[y[ok], x[ok]] = _texel_colours(uv[:, 0] * 131 + uv[:, 1])
        else:
            rgb[got] = LEGEND["covered"]
        rgb[want & ~got] = LEGEND["oracle only (missing)"]
        rgb[got & ~want] = LEGEND["extra"]
        for m in marks:
            if int(m.get("frame", -1)) != f:
                continue
            if "x" in m and "y" in m:
                rgb[int(m["y"]) % height, int(m["x"]) % width] = LEGEND["texel swim" if "axis" in m or "texel" in m else "flicker or backward jump"]
            elif "row" in m and "column" in m:
                rgb[int(m["row"]) % height, min(max(int(m["column"]), 0), width - 1)] = LEGEND["flicker or backward jump"]
        crop = rgb[wy0:wy1, wx0:wx1]
        images.append(Image.fromarray(np.ascontiguousarray(crop)).resize(((wx1 - wx0) * scale, (wy1 - wy0) * scale), Image.Resampling.NEAREST))
    buffer = io.BytesIO()
    images[0].save(buffer, format="GIF", save_all=True, append_images=images[1:], duration=80, loop=0)
    return "data:image/gif;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


# series name -> (what it counts, unit): the motion checks' evidence["series"]
SERIES = {
    "changed_pixels": ("pixels that changed", "pixels"),
    "oracle_changed_pixels": ("pixels the oracle changed", "pixels"),
    "backward_jumps": ("backward jumps", "span ends"),
    "mismatches": ("texel mismatches", "pixels"),
    "max_uv_error_texels": ("largest u, v error", "texels"),
    # popping: the worst pixel's alpha, exact area and declared model, frame by frame
    "alpha": ("the rasterizer's alpha", "alpha"),
    "area": ("the exact area", "alpha"),
    "oracle": ("the declared model's alpha", "alpha"),
}


def series_label(name: str) -> tuple[str, str]:
    """What a per-frame series counts and its unit; an unknown name is read from its
    suffix (``_pixels``, ``_texels``), else counted.

    >>> series_label("max_uv_error_texels"), series_label("stray_pixels"), series_label("flips")
    (('largest u, v error', 'texels'), ('stray', 'pixels'), ('flips', 'count'))
    """
    if name in SERIES:
        return SERIES[name]
    for unit in ("pixels", "texels"):
        if name.endswith("_" + unit):
            return name[: -len(unit) - 1].replace("_", " "), unit
    return name.replace("_", " "), "count"


def series_plot(series: dict[str, list[float]]) -> str:
    """Per-frame metric series as a PNG data URI (matplotlib, Agg): one panel per unit,
    frames along x, the metric and its unit along y, a legend naming each series.
    Non-finite values are left out of the line (the legend says how many). A fixed
    layout and fast PNG compression keep it near a tenth of a second."""
    from matplotlib.figure import Figure  # the presentation's own import: the engine never pays for it
    from matplotlib.ticker import MaxNLocator

    panels: dict[str, list[tuple[str, NDArray]]] = {}
    for name, values in series.items():
        label, unit = series_label(name)
        panels.setdefault(unit, []).append((label, np.asarray(values, dtype=float).ravel()))
    dpi, panel, legend, axis = 80, 110, 24, 44  # px: a panel's height, a legend's above it, the x axis's below
    height = len(panels) * (panel + legend) + axis
    figure = Figure(figsize=(512 / dpi, height / dpi), dpi=dpi)
    figure.subplots_adjust(left=90 / 512, right=1 - 12 / 512, top=1 - legend / height, bottom=axis / height,
                           hspace=legend / panel)
    axes = figure.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for ax, (unit, lines) in zip(axes, panels.items()):
        for label, v in lines:
            finite = np.isfinite(v)
            lost = int((~finite).sum())
            ax.plot(np.arange(v.size), np.where(finite, v, np.nan), marker="." if v.size <= 40 else None,
                    linewidth=1.2, label=label + (f" ({lost} non-finite frames not drawn)" if lost else ""))
        ax.set_ylabel(textwrap.fill(lines[0][0], 16) + f"\n({unit})" if len(lines) == 1 else unit, fontsize=9)
        finite_values = np.concatenate([v[np.isfinite(v)] for _, v in lines])
        whole = bool(np.array_equal(finite_values, np.round(finite_values)))
        ax.yaxis.set_major_locator(MaxNLocator(nbins=4, integer=whole))
        if whole and (not finite_values.size or finite_values.min() >= 0):  # counts: from 0, at least to 1
            top = max(1.0, float(finite_values.max()) if finite_values.size else 1.0)
            ax.set_ylim(-0.05 * top, 1.08 * top)
        ax.tick_params(labelsize=8)
        ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=len(lines), frameon=False,
                  borderaxespad=0.1)
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("frame", fontsize=9)
    axes[-1].xaxis.set_major_locator(MaxNLocator(integer=True))
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", pil_kwargs={"compress_level": 1})
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")
