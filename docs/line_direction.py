"""The README's picture of the direction of travel (section "Lines"): one segment of slope
1/2 between pixel centres, drawn from a to b and from b to a by the exact oracle, under
Bresenham walked as given (top row) and walked from the end point with smaller x, as
textbook plotLine does (bottom row).

    python docs/line_direction.py [OUT]        # default: docs/line-direction.png

Each panel is the pixel grid: drawn pixels blue, those the other column's drawing lacks
orange; the segment in black from its start (green) to its end (red). Walked as given,
the decision variable's ties (every other column) step towards the end point, so the two
drawings differ; walked from the smaller x, both are the same. Prints how many pixels
each pair differs in. numpy and the standard library only (zlib writes the PNG).
"""

from __future__ import annotations

import struct
import sys
import zlib
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from harness.contract.conventions import Convention, LineRule  # noqa: E402
from harness.contract.scenes import LineScene  # noqa: E402
from harness.oracle.coverage import exact_coverage  # noqa: E402

WIDTH, HEIGHT = 12, 7  # pixels per panel
CELL = 22  # picture pixels per pixel
GAP = 14
A, B = (1.5, 1.5), (9.5, 5.5)  # slope 1/2 from centre to centre: a tie at every other step
RULES = (("as given", LineRule("bresenham")), ("from the smaller x", LineRule("bresenham", direction="smaller-x")))
COLOURS = {"background": (255, 255, 255), "grid": (205, 205, 205), "drawn": (96, 142, 214), "differs": (240, 150, 40),
           "segment": (20, 20, 20), "start": (40, 170, 70), "end": (215, 50, 50)}


def drawn(rule: LineRule, a: tuple[float, float], b: tuple[float, float]) -> set[tuple[int, int]]:
    """The pixels (x, y) the oracle draws for segment a -> b under ``rule``."""
    scene = LineScene.from_segments(WIDTH, HEIGHT, [a], [b])
    _, x, y = exact_coverage(scene, Convention(line=rule)).pixels()
    return set(zip(x.tolist(), y.tolist()))


def _disc(image: NDArray[np.uint8], cx: float, cy: float, radius: float, colour: tuple[int, int, int]) -> None:
    yy, xx = np.mgrid[0:image.shape[0], 0:image.shape[1]]
    image[(xx + 0.5 - cx) ** 2 + (yy + 0.5 - cy) ** 2 <= radius**2] = colour


def panel(pixels: set[tuple[int, int]], other: set[tuple[int, int]], start: tuple[float, float],
          end: tuple[float, float]) -> NDArray[np.uint8]:
    """One panel, (HEIGHT * CELL + 1, WIDTH * CELL + 1, 3) uint8."""
    image = np.full((HEIGHT * CELL + 1, WIDTH * CELL + 1, 3), COLOURS["background"], dtype=np.uint8)
    for x, y in pixels:
        image[y * CELL:(y + 1) * CELL, x * CELL:(x + 1) * CELL] = COLOURS["drawn" if (x, y) in other else "differs"]
    image[::CELL, :] = COLOURS["grid"]
    image[:, ::CELL] = COLOURS["grid"]
    t = np.linspace(0.0, 1.0, 4 * CELL * WIDTH)
    px = (start[0] + t * (end[0] - start[0])) * CELL
    py = (start[1] + t * (end[1] - start[1])) * CELL
    for dx in (-1, 0):
        for dy in (-1, 0):
            image[np.clip(py.astype(int) + dy, 0, image.shape[0] - 1), np.clip(px.astype(int) + dx, 0, image.shape[1] - 1)] = \
                COLOURS["segment"]
    _disc(image, start[0] * CELL, start[1] * CELL, CELL * 0.28, COLOURS["start"])
    _disc(image, end[0] * CELL, end[1] * CELL, CELL * 0.28, COLOURS["end"])
    return image


def picture() -> tuple[NDArray[np.uint8], dict[str, int]]:
    """The 2 x 2 panels (rows: the rules; columns: a -> b, b -> a) and, per rule, how many
    pixels the two drawings differ in."""
    rows, differ = [], {}
    for label, rule in RULES:
        forward, backward = drawn(rule, A, B), drawn(rule, B, A)
        differ[label] = len(forward ^ backward)
        left, right = panel(forward, backward, A, B), panel(backward, forward, B, A)
        rows.append(np.concatenate([left, np.full((left.shape[0], GAP, 3), 255, np.uint8), right], axis=1))
    gap = np.full((GAP, rows[0].shape[1], 3), 255, np.uint8)
    body = np.concatenate([rows[0], gap, rows[1]], axis=0)
    framed = np.full((body.shape[0] + 2 * GAP, body.shape[1] + 2 * GAP, 3), 255, np.uint8)
    framed[GAP:-GAP, GAP:-GAP] = body
    return framed, differ


def png(image: NDArray[np.uint8]) -> bytes:
    """An 8-bit RGB PNG of ``image`` (H, W, 3)."""
    height, width, _ = image.shape

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + image[row].tobytes() for row in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main(argv: list[str]) -> int:
    out = Path(argv[0]) if argv else Path(__file__).resolve().parent / "line-direction.png"
    image, differ = picture()
    out.write_bytes(png(image))
    for label, count in differ.items():
        print(f"walked {label}: a -> b and b -> a differ in {count} pixels")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
