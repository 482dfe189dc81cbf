"""The README's pictures of the conventions' rules (section "Conventions"): one picture per
rule, each drawn by the exact oracle (:func:`harness.oracle.coverage.exact_coverage`).

    python docs/rule_pictures.py [OUT_DIR]      # default: docs/rules/

Each picture is the pixel grid with the scene's primitives outlined in black (as given: thin
grey; as the convention receives and snaps them: black), the pixels the rule draws in blue
(drawn twice: dark violet), and, in orange frames, the pixels where the rule and plain centre
sampling with top-left ties (``Convention()``, on the same input) part. A picture may print
each pixel's covered area (the threshold rules). Prints, per picture, how many pixels it
draws and how many differ from centre sampling. Pillow draws the PNGs.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from harness.contract.conventions import Convention, LineRule  # noqa: E402
from harness.contract.scenes import AnyScene, LineScene, Scene  # noqa: E402
from harness.oracle.area import exact_area  # noqa: E402
from harness.oracle.coverage import exact_coverage  # noqa: E402

CELL = 34  # picture pixels per pixel
MARGIN = 8
COLOURS = {"background": (255, 255, 255), "grid": (205, 205, 205), "once": (96, 142, 214), "twice": (88, 40, 130),
           "differs": (240, 150, 40), "given": (150, 150, 150), "shape": (20, 20, 20), "centre": (200, 60, 60),
           "text": (40, 40, 40)}


@dataclass(frozen=True)
class Panel:
    """One picture: ``scene`` drawn under ``convention``, its pixels compared with those of
    ``baseline`` (None: centre sampling, top-left ties, on the same input and line rule);
    ``areas``: print each pixel's covered area (one-triangle scenes)."""

    name: str
    scene: AnyScene
    convention: Convention
    areas: bool = False
    baseline: Convention | None = None


def _triangles(points: list[list[tuple[float, float]]], width: int, height: int) -> Scene:
    return Scene(width, height, np.array(points, dtype=np.float64))


PANELS: tuple[Panel, ...] = (
    # input precision: vertices rounded to whole pixels (pygame) before anything else
    Panel("input-integer", _triangles([[(0.7, 0.6), (6.6, 1.4), (2.3, 5.8)]], 8, 7), Convention(input="integer"),
          baseline=Convention()),
    # coverage rules decided on the pixel's square
    Panel("area-threshold", _triangles([[(0.3, 0.2), (6.8, 1.7), (1.7, 6.1)]], 8, 7),
          Convention(coverage="area-threshold"), areas=True),
    Panel("conservative-over", _triangles([[(0.3, 0.2), (6.8, 1.7), (1.7, 6.1)]], 8, 7),
          Convention(coverage="conservative-over")),
    Panel("conservative-under", _triangles([[(0.3, 0.2), (6.8, 1.7), (1.7, 6.1)]], 8, 7),
          Convention(coverage="conservative-under")),
    # closed: two triangles sharing a diagonal through pixel centres both draw its samples
    Panel("closed", _triangles([[(0.5, 0.5), (6.5, 0.5), (6.5, 6.5)], [(0.5, 0.5), (6.5, 6.5), (0.5, 6.5)]], 7, 7),
          Convention(coverage="closed")),
    # dropout control: a sliver between pixel centres still draws (FreeType mono, smart mode)
    Panel("dropout", _triangles([[(0.25, 1.75), (7.75, 3.2), (7.75, 3.4)]], 8, 5),
          Convention(coverage="closed", input="fixed6", dropout="smart-no-stubs-stepped6"),
          baseline=Convention(coverage="closed", input="fixed6", dropout="none-stepped6")),
    # the rules read from libraries' sources
    Panel("agg-cover", _triangles([[(0.3, 0.2), (6.8, 1.7), (1.7, 6.1)]], 8, 7),
          Convention(coverage="agg-cover", input="fixed8-toward-zero"), areas=True, baseline=Convention()),
    Panel("inclusive-scanline", _triangles([[(0.7, 0.6), (6.6, 1.4), (2.3, 5.8)]], 8, 7),
          Convention(coverage="inclusive-scanline", input="integer-toward-zero"), baseline=Convention()),
    Panel("skia-hairline", LineScene.from_segments(10, 6, [(1.25, 0.875)], [(8.25, 4.375)]),
          Convention(line=LineRule("skia-hairline")), baseline=Convention()),
    Panel("qt-cosmetic", LineScene.from_segments(10, 6, [(1.25, 0.875)], [(8.25, 4.375)]),
          Convention(line=LineRule("qt-cosmetic")), baseline=Convention()),
    Panel("llvmpipe-rectangle", LineScene.from_segments(10, 6, [(1.25, 0.875)], [(8.25, 4.375)]),
          Convention(subpixel_bits=8, line=LineRule("llvmpipe-rectangle")), baseline=Convention(subpixel_bits=8)),
    # Vulkan's non-strict lines
    Panel("parallelogram", LineScene.from_segments(10, 6, [(1.25, 0.875)], [(8.25, 4.375)]),
          Convention(line=LineRule("parallelogram")), baseline=Convention()),
)


def _outlines(scene: AnyScene, convention: Convention) -> tuple[list[NDArray[np.float64]], list[NDArray[np.float64]]]:
    """The primitives' outlines as given and as the convention sees them (snapped): for a
    segment, its centre line, and under the parallelogram rule the parallelogram (the
    segment moved by half a pixel either way along its minor axis)."""
    if isinstance(scene, LineScene):
        a, b = scene.segments()
        lines = convention.for_lines()
        given = [np.array([p, q]) for p, q in zip(a, b)]
        snapped = [np.array([p, q]) for p, q in zip(lines.snap(a), lines.snap(b))]
        if convention.line.rule == "parallelogram":
            for p, q in zip(lines.snap(a), lines.snap(b)):
                minor = np.array([0.0, 0.5]) if abs(q[0] - p[0]) >= abs(q[1] - p[1]) else np.array([0.5, 0.0])
                snapped.append(np.array([p - minor, q - minor, q + minor, p + minor]))
        return given, snapped
    return list(scene.positions), list(convention.snap(scene.positions))


def counts(scene: AnyScene, convention: Convention) -> NDArray[np.int32]:
    """How many primitives draw each pixel, (height, width)."""
    return np.asarray(exact_coverage(scene, convention).counts(scene.width, scene.height))


def draw(panel: Panel) -> tuple[Image.Image, int, int]:
    """The picture, the pixels drawn and the pixels where the rule and centre sampling part."""
    scene, convention = panel.scene, panel.convention
    drawn = counts(scene, convention)
    baseline = panel.baseline or Convention(input=convention.input, line=convention.line)
    centre = counts(scene, baseline)
    differs = (drawn > 0) != (centre > 0)
    w, h = scene.width, scene.height
    image = Image.new("RGB", (2 * MARGIN + w * CELL, 2 * MARGIN + h * CELL), COLOURS["background"])
    pen = ImageDraw.Draw(image)

    def at(x: float, y: float) -> tuple[float, float]:
        return MARGIN + x * CELL, MARGIN + y * CELL

    for j in range(h):
        for i in range(w):
            box = (*at(i, j), *at(i + 1, j + 1))
            fill = {0: COLOURS["background"], 1: COLOURS["once"]}.get(int(drawn[j, i]), COLOURS["twice"])
            pen.rectangle(box, fill=fill, outline=COLOURS["grid"])
            if differs[j, i]:
                pen.rectangle((box[0] + 2, box[1] + 2, box[2] - 2, box[3] - 2), outline=COLOURS["differs"], width=3)
            cx, cy = at(i + 0.5, j + 0.5)
            pen.ellipse((cx - 1.5, cy - 1.5, cx + 1.5, cy + 1.5), fill=COLOURS["centre"])
            if panel.areas and isinstance(scene, Scene):
                area = exact_area(convention.snap(scene.positions)[0], i, j)
                if area > 0:
                    text = ("1" if area == 1 else ">.99" if area > 0.99 else "<.01" if area < 0.01
                            else f"{float(area):.2f}".lstrip("0"))
                    pen.text((box[0] + 3, box[1] + 2), text, fill=COLOURS["text"] if not drawn[j, i] else (255, 255, 255))
    given, snapped = _outlines(scene, convention)
    for shape in given:
        pen.line([at(*p) for p in [*shape, shape[0]]], fill=COLOURS["given"], width=1)
    for shape in snapped:
        pen.line([at(*p) for p in [*shape, shape[0]]], fill=COLOURS["shape"], width=2)
    return image, int((drawn > 0).sum()), int(differs.sum())


def main(argv: list[str]) -> int:
    out = Path(argv[0]) if argv else Path(__file__).resolve().parent / "rules"
    out.mkdir(parents=True, exist_ok=True)
    for panel in PANELS:
        image, n, off = draw(panel)
        image.save(out / f"{panel.name}.png")
        print(f"{panel.name}: {n} pixels drawn, {off} where it and centre sampling part")
    return 0



if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
