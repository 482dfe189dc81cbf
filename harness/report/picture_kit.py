"""The shared parts of the report's pictures (:mod:`harness.report.pictures`): the colours,
one meaning each across every picture (the legends), the raster helpers (PNG data URIs,
windows, heat maps, oracle diffs), the samples of a pattern drawn in a window
(:class:`Samples`), and where a failure's evidence points (its offending pixels)."""

from __future__ import annotations

import base64
import io
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from PIL import Image

from harness.checks import Result
from harness.checks.records import Drawing
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene
from harness.oracle.coverage import exact_coverage

__all__ = ["LEGEND", "HEAT_LEGEND", "DIFF_LEGEND", "CROP_LEGEND", "ALPHA_LEGEND", "SAMPLE_LEGEND", "PATH_LEGEND", "LINE_LEGEND", "heatmap",
           "oracle_diff", "window_around", "svg_pattern", "Samples", "sample_hits"]


def _oracles(drawing: Drawing, scenes: list[Any]) -> tuple[Coverage, ...] | None:
    """The oracle of each scene: the check's, when it computed one; else computed now
    (given a convention); None without a convention."""
    if drawing.oracles is not None:
        return drawing.oracles
    if drawing.convention is None:
        return None
    return tuple(exact_coverage(scene, drawing.convention) for scene in scenes)


def _offending_rows(evidence: dict[str, Any]) -> list[dict[str, Any]]:
    """The rows of ``evidence["pixels"]`` (dicts with ``x`` and ``y``) that are offending:
    all but those that say they are within tolerance (``over`` False: accuracy lists its
    worst pixels, and those of them within tolerance are not wrong); accuracy's
    ``off_level`` rows when no other is.

    >>> _offending_rows({"pixels": [{"x": 1, "y": 2, "over": True}, {"x": 3, "y": 4, "over": False}]})
    [{'x': 1, 'y': 2, 'over': True}]
    """
    rows = [p for p in evidence.get("pixels") or () if isinstance(p, dict) and "x" in p and "y" in p]
    wrong = [p for p in rows if p.get("over") is not False]
    if not wrong and rows:
        wrong = [p for p in evidence.get("off_level") or () if isinstance(p, dict) and "x" in p and "y" in p]
    return wrong


def _focus(result: Result) -> list[tuple[int, int]]:
    """The offending pixels a failure names, first the most telling."""
    e = result.evidence
    if "pixels" in e and e["pixels"] and isinstance(e["pixels"][0], dict):
        return [(int(p["x"]), int(p["y"])) for p in _offending_rows(e)]
    if "blame" in e:
        return [(int(b["pixel"][0]), int(b["pixel"][1])) for b in e["blame"]]
    for key in ("strays", "pixels"):
        if e.get(key):
            return [(int(p[0]), int(p[1])) for p in e[key]]
    for key in ("rotate-vertices", "flip-winding", "permute-triangles", "translate", *_PATH_ROWS):
        if e.get(key):
            return [(int(p[1]), int(p[2])) for p in e[key]]
    return []


# Evidence lists of [path, x, y] rows on path scenes: the triangulation check's and the
# invariance check's path variants (harness.checks.paths, harness.checks.invariance).
_PATH_ROWS = ("path_only", "triangles_only", "triangulation_double_hits", "rotate-start-vertex", "reverse-every-contour",
              "reverse-one-contour", "reorder-contours", "permute-paths")


HEAT_LEGEND = {"not hit": (255, 255, 255), "hit once": (198, 219, 239), "hit twice or more": (8, 69, 148),
               "hole (inside, not hit)": (37, 37, 37), "stray (outside, hit)": (0, 170, 190)}


DIFF_LEGEND = {"both": (161, 217, 155), "missing (oracle only)": (215, 40, 40), "extra (rasterizer only)": (250, 140, 30),
               "near tie": (255, 225, 0)}


# the animations say "missing" and "extra" in the diff's colours
LEGEND = {
    "covered": (150, 150, 150),
    "oracle only (missing)": DIFF_LEGEND["missing (oracle only)"],
    "extra": DIFF_LEGEND["extra (rasterizer only)"],
    "flicker or backward jump": (120, 60, 220),
    "texel swim": (230, 0, 230),
}


ALPHA_LEGEND = {"exact (white)": (255, 255, 255), "too much alpha (full red: the scale)": (200, 30, 30),
                "too little alpha (full blue: the scale)": (30, 80, 200), "stray (outside the region, alpha > 0)": (0, 0, 0)}


_DRAWN = "drawn by the rasterizer (crops, and the left picture of a repro; anti-aliased: shaded by its alpha)"


_CONVENTION = "covered by the convention (the right picture of a repro; anti-aliased: shaded by its alpha)"


CROP_LEGEND = {_DRAWN: (200, 200, 200), _CONVENTION: (230, 205, 140),
               "offending pixel (outlined)": (221, 0, 0), "triangle (outlined)": (0, 80, 200),
               "region of a partition (dotted; every pixel wholly inside it must be hit)": (0, 130, 100)}


_REGION = list(CROP_LEGEND)[-1]


# multisample and supersampled pictures: each sample of the convention's pattern in each
# pixel, over CROP_LEGEND's pixels
# The most samples one repro panel draws (a dot or ring each): 16 a pixel keep a 12 px
# crop, 64 (a 16x4 grid) a 6 px one.
SAMPLE_BUDGET = 2400


SAMPLE_LEGEND = {"sample covered (dot)": (25, 25, 25), "sample not covered (ring)": (140, 140, 140),
                 "sample where the rasterizer and the convention differ (thick ring)": (221, 0, 0),
                 "alpha of an offending pixel (anti-aliased; k/N: k of the N samples)": (0, 40, 170)}
_HIT, _MISS, _DIFFERS, _ALPHA = SAMPLE_LEGEND


# path crops and repros, over CROP_LEGEND's pixels and marks: the fill is the outline's
# colour at PATH_FILL_OPACITY (its swatch: that over white)
PATH_FILL_OPACITY = 0.16


_PATH_COLOUR: tuple[int, int, int] = (120, 40, 170)


_OTHER_PATH_COLOUR: tuple[int, int, int] = (150, 120, 60)


def _faint(rgb: tuple[int, int, int]) -> tuple[int, int, int]:
    """``rgb`` at PATH_FILL_OPACITY over white."""
    r, g, b = (round(255 - PATH_FILL_OPACITY * (255 - c)) for c in rgb)
    return r, g, b


PATH_LEGEND = {
    "the numbered path (outlined; arrows: each edge's direction; ring: each contour's first vertex)": _PATH_COLOUR,
    "where its fill rule fills it (faint)": _faint(_PATH_COLOUR),
    "other paths (dashed outline; their arrows and rings likewise)": _OTHER_PATH_COLOUR,
    "where their fill rule fills them (faint)": _faint(_OTHER_PATH_COLOUR),
    "winding number of the pixel's sample: the rule fills it (bold)": (10, 10, 10),
    "winding number of the pixel's sample: the rule leaves it": (135, 135, 135),
}
_FILLED, _LEFT = list(PATH_LEGEND)[-2:]


# line crops and repros: the pixels in DIFF_LEGEND's colours (crops; without an oracle, and
# in repros, CROP_LEGEND's), the marks in CROP_LEGEND's, the vectors in these
LINE_LEGEND = {
    "the segment the failure names (thick; its number at its middle, an arrowhead for its direction; dotted: its "
    "rectangle, for rectangular lines)": (0, 100, 40),
    "other segments (a strip's segments joined; numbered and dotted likewise; a ring at each end point that is no "
    "joint)": (95, 95, 95),
    "joint: a vertex where one segment ends and the next starts": (255, 0, 150),
    "diamond test area of an offending pixel, diamond-exit rule (solid: the edges and corners it includes; dashed, "
    "hollow: those it excludes)": (160, 60, 0),
    "how many segments drew the pixel, where more than one did": (120, 0, 0),
}
_NAMED_SEGMENT, _OTHER_SEGMENT, _JOINT, _DIAMOND, _HITS = LINE_LEGEND


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*rgb)


def _png(rgb: NDArray, scale: int) -> str:
    image = Image.fromarray(np.ascontiguousarray(rgb)).resize((rgb.shape[1] * scale, rgb.shape[0] * scale), Image.Resampling.NEAREST)
    buffer = io.BytesIO()
    image.save(buffer, format="PNG")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def window_around(x: int, y: int, width: int, height: int, side: int) -> tuple[int, int, int, int]:
    """A side x side window of the viewport centred near (x, y)."""
    x0 = int(np.clip(x - side // 2, 0, max(width - side, 0)))
    y0 = int(np.clip(y - side // 2, 0, max(height - side, 0)))
    return x0, y0, min(x0 + side, width), min(y0 + side, height)


def heatmap(counts: NDArray, holes: NDArray | None = None, strays: NDArray | None = None,
            window: tuple[int, int, int, int] | None = None) -> str:
    """Hit counts per pixel as a PNG data URI: white 0, pale blue 1, dark blue 2+, near-black
    holes, teal strays (colours in HEAT_LEGEND)."""
    rgb = np.full(counts.shape + (3,), 255, dtype=np.uint8)
    rgb[counts == 1] = HEAT_LEGEND["hit once"]
    rgb[counts >= 2] = HEAT_LEGEND["hit twice or more"]
    if holes is not None:
        rgb[holes] = HEAT_LEGEND["hole (inside, not hit)"]
    if strays is not None:
        rgb[strays] = HEAT_LEGEND["stray (outside, hit)"]
    if window is not None:
        x0, y0, x1, y1 = window
        rgb = rgb[y0:y1, x0:x1]
    return _png(rgb, max(1, 384 // max(rgb.shape)))


def oracle_diff(width: int, height: int, got: NDArray, want: NDArray, pixels: list[dict[str, Any]],
                window: tuple[int, int, int, int] | None = None) -> str:
    """dEQP-style diff as a PNG data URI: both green, missing red, extra orange, near-tie
    yellow (colours in DIFF_LEGEND)."""
    rgb = np.full((height, width, 3), 255, dtype=np.uint8)
    rgb[got & want] = DIFF_LEGEND["both"]
    rgb[want & ~got] = DIFF_LEGEND["missing (oracle only)"]
    rgb[got & ~want] = DIFF_LEGEND["extra (rasterizer only)"]
    for p in pixels:
        x, y = int(p["x"]), int(p["y"])
        if 0 <= x < width and 0 <= y < height:
            kind = "near tie" if p.get("near_tie") else ("missing (oracle only)" if p["kind"] == "missing" else "extra (rasterizer only)")
            rgb[y, x] = DIFF_LEGEND[kind]
    if window is not None:
        x0, y0, x1, y1 = window
        rgb = rgb[y0:y1, x0:x1]
    return _png(rgb, max(1, 384 // max(rgb.shape)))


@dataclass(frozen=True, slots=True)
class Samples:
    """The samples of a window drawn in its pixels (SAMPLE_LEGEND).

    Parameters
    ----------
    offsets : (S, 2) float64
        The pattern: each sample's position in its pixel.
    hits : (rows, cols, S) bool
        Which samples of each pixel of the window are covered.
    differs : (rows, cols, S) bool or None
        The samples where the rasterizer and the convention disagree (ringed thick).
    """

    offsets: NDArray[np.float64]
    hits: NDArray[np.bool_]
    differs: NDArray[np.bool_] | None = None


def sample_hits(scene: AnyScene, convention: Convention, window: tuple[int, int, int, int],
                coverage: Coverage | None = None, only: list[int] | None = None) -> NDArray[np.bool_]:
    """(rows, cols, S) bool: which samples of the convention's pattern each pixel of the
    window has covered: by ``coverage`` (a multisample answer, its sample indices the
    pattern's), else by the convention itself (its exact oracle, sample by sample: for a
    supersampled area convention too); by the primitives ``only`` when given.

    >>> from harness.contract.scenes import Scene
    >>> square = Scene(2, 1, [[[0, 0], [1, 0], [0, 1]]])
    >>> sample_hits(square, Convention(samples=4), (0, 0, 2, 1))[0].astype(int).tolist()
    [[1, 0, 1, 0], [0, 0, 0, 0]]
    """
    x0, y0, x1, y1 = window
    count = convention.n_samples
    out = np.zeros((y1 - y0, x1 - x0, count), dtype=bool)
    for k in range(count):
        layer = coverage.layer(k) if coverage is not None else exact_coverage(scene, convention.at_sample(k))
        out[..., k] = _of(layer, only).counts(scene.width, scene.height)[y0:y1, x0:x1] > 0
    return out


def _of(coverage: Coverage, only: list[int] | None) -> Coverage:
    """The coverage of the primitives ``only`` (all of it for None)."""
    return coverage if only is None else coverage.take(np.flatnonzero(np.isin(coverage.primitive, only)))


def _svg_samples(samples: Samples, window: tuple[int, int, int, int], scale: float) -> list[str]:
    """Each sample of each pixel of the window: a dot where covered, a ring where not, a
    thick red ring around those where the rasterizer and the convention differ."""
    x0, y0, _, _ = window
    count = samples.offsets.shape[0]
    r = min(0.09, max(1.2 / scale, 0.35 / math.sqrt(count) / 2))
    thin = 'vector-effect="non-scaling-stroke"'
    hit, miss, red = _hex(SAMPLE_LEGEND[_HIT]), _hex(SAMPLE_LEGEND[_MISS]), _hex(SAMPLE_LEGEND[_DIFFERS])
    out = []
    for (j, i, k), covered in np.ndenumerate(samples.hits):
        cx, cy = x0 + i + float(samples.offsets[k, 0]), y0 + j + float(samples.offsets[k, 1])
        if covered:
            out.append(f'<circle cx="{cx:.6g}" cy="{cy:.6g}" r="{r:.4f}" fill="{hit}"/>')
        else:
            out.append(f'<circle cx="{cx:.6g}" cy="{cy:.6g}" r="{r * 0.8:.4f}" fill="none" stroke="{miss}" stroke-width="1" {thin}/>')
        if samples.differs is not None and samples.differs[j, i, k]:
            out.append(f'<circle cx="{cx:.6g}" cy="{cy:.6g}" r="{r * 1.9:.4f}" fill="none" stroke="{red}" stroke-width="2" {thin}>'
                       f'<title>sample {k} of pixel ({x0 + i}, {y0 + j}): {"covered" if covered else "not covered"} here, '
                       f'the other way in the other picture</title></circle>')
    return out


def svg_pattern(offsets: tuple[tuple[float, float], ...], side: int = 160) -> str:
    """A multisample pattern as an SVG data URI: one pixel square, its 1/16 px grid, the
    centre marked, and each sample as a numbered dot (y down, as on screen).

    >>> svg_pattern(((0.375, 0.125), (0.875, 0.375))).startswith("data:image/svg+xml;base64,")
    True
    """
    thin = 'vector-effect="non-scaling-stroke"'
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{side}" height="{side}" viewBox="-0.08 -0.08 1.16 1.16">',
             '<rect x="0" y="0" width="1" height="1" fill="white" stroke="#333" stroke-width="1.5" ' + thin + '/>']
    parts.extend(f'<line x1="{k / 16:g}" y1="0" x2="{k / 16:g}" y2="1" stroke="#ddd" stroke-width="0.5" {thin}/>'
                 f'<line x1="0" y1="{k / 16:g}" x2="1" y2="{k / 16:g}" stroke="#ddd" stroke-width="0.5" {thin}/>'
                 for k in range(1, 16))
    parts.append('<circle cx="0.5" cy="0.5" r="0.012" fill="#999"/>')
    blue = _hex(CROP_LEGEND["triangle (outlined)"])
    for index, (x, y) in enumerate(offsets):
        parts.append(f'<circle cx="{x:.6g}" cy="{y:.6g}" r="0.025" fill="{blue}"/>'
                     f'<text x="{x + 0.03:.6g}" y="{y - 0.02:.6g}" font-size="0.07" font-family="sans-serif">{index}</text>')
    parts.append("</svg>")
    return "data:image/svg+xml;base64," + base64.b64encode("".join(parts).encode()).decode("ascii")
