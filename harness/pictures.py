"""Pictures for the report: animations of motion sequences, as GIF data URIs (Pillow)."""

from __future__ import annotations

import base64
import io
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from harness.api import Coverage

__all__ = ["motion_animation", "LEGEND"]

LEGEND = {
    "covered": (150, 150, 150),
    "oracle only (missing)": (90, 60, 200),
    "extra": (220, 60, 60),
    "flicker or backward jump": (255, 200, 0),
    "texel swim": (230, 0, 230),
}
MAX_FRAMES = 48
MAX_SIDE = 64  # pixels of the viewport shown: a window around the evidence


def _texel_colours(ids: NDArray) -> NDArray:
    rng = np.random.default_rng(7)
    palette = rng.integers(60, 230, size=(4096, 3))
    return palette[ids % 4096]


def motion_animation(coverages: list[Coverage], oracles: list[Coverage], width: int, height: int,
                     marks: list[dict[str, Any]] | None = None, texels: int | None = None, scale: int = 6) -> str:
    """An animated GIF (data URI) of the sequence: coverage (or texel ids when textured)
    against the oracle, with the evidence's frames, pixels and rows marked.

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
        want = oracles[f].counts(width, height) > 0
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
        images.append(Image.fromarray(np.ascontiguousarray(crop)).resize(((wx1 - wx0) * scale, (wy1 - wy0) * scale), Image.NEAREST))
    buffer = io.BytesIO()
    images[0].save(buffer, format="GIF", save_all=True, append_images=images[1:], duration=80, loop=0)
    return "data:image/gif;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")
