"""Motion sequences: the same geometry over frames that move it a tiny step at a time.

Translations by 1/16, 1/64 and 1/256 px along x, y and a diagonal over two pixels, slow
rotations (0.01 to 0.1 degrees a frame) about an arbitrary point, and slow zooms, applied
to single triangles, fans, grids and projected trimesh meshes. Textured variants carry
per-vertex (u, v) on a T x T texel grid, including perspective quads seen at grazing angles
(``w`` differs per vertex). Translations by dyadic steps of lattice geometry stay exact.

Anti-aliased paths and lines (issue 34, :func:`aa_motion_cases`): frames that are path
scenes -- a glyph-like outline (a "D" of flattened curves, its counter and an overlapping
stem contour) and a pentagram, translated by 1/64 px and rotated slowly -- and line scenes
-- segments sliding by 1/64 px -- for the popping check under area coverage (and jaggy
under a sample rule). Kept apart from :func:`motion_cases`, whose frames are triangles.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from cases.meshes import _rotation, _shapes, project
from cases.partitions import fan, grid
from cases.paths import glyph_d, star
from harness.contract.case import MotionCase
from harness.contract.scenes import LineScene, PathScene, Scene

__all__ = ["MotionCase", "motion_cases", "aa_motion_cases", "translate", "rotate", "zoom"]


def translate(positions: NDArray, step: tuple[float, float], count: int) -> list[NDArray]:
    """Frames moved by ``k * step``, k = 0 .. count-1 (exact for dyadic steps and input)."""
    return [positions + k * np.asarray(step) for k in range(count)]


def rotate(positions: NDArray, centre: NDArray, degrees: float, count: int) -> list[NDArray]:
    frames = []
    for k in range(count):
        a = np.radians(degrees * k)
        r = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        frames.append((positions - centre) @ r.T + centre)
    return frames


def zoom(positions: NDArray, centre: NDArray, rate: float, count: int) -> list[NDArray]:
    return [(positions - centre) * (1.0 + rate) ** k + centre for k in range(count)]


def _textured_quad(size: int, grazing: bool) -> tuple[NDArray, NDArray, NDArray | None]:
    """Two triangles of a square with (u, v) at its corners; seen at a grazing angle the
    square recedes, and w grows with depth."""
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    if not grazing:
        corners = np.array([[4.25, 5.5], [size - 5.0, 4.75], [size - 4.5, size - 6.25], [5.0, size - 4.0]])
        w = None
    else:
        # a floor seen from just above it: the far edge is narrow, and w is its depth
        depth = np.array([1.0, 1.0, 6.0, 6.0])
        x_world = np.array([-1.0, 1.0, 1.0, -1.0])
        y_world = np.array([1.0, 1.0, 1.0, 1.0]) * 0.35
        sx = x_world / depth
        sy = y_world / depth
        corners = np.stack([(sx + 1) / 2 * size, (1 - sy) / 2 * size - size / 3], axis=-1)
        corners[:, 1] = size - corners[:, 1]
        w = depth
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    return corners[faces], uv[faces], (None if w is None else w[faces])


def motion_cases(seed: int, full: bool = False, meshes: bool = True) -> list[MotionCase]:
    """The motion family for a suite (``full`` adds longer and finer sweeps). Without
    ``meshes``, only the plain geometries' (the single triangle, the fan and the grid: the
    same cases as with them, and no trimesh import), not the tall sliver, the projected
    mesh or the textured sequences."""
    rng = np.random.default_rng(seed)
    cases: list[MotionCase] = []
    size = 24

    def add(name: str, frames: list[NDArray], attributes: NDArray | None = None, w: NDArray | None = None,
            texels: int | None = None, viewport: int = size) -> None:
        scenes = tuple(Scene(viewport, viewport, f, attributes, w) for f in frames)
        cases.append(MotionCase(f"motion/{name}", scenes, texels, w is not None))

    triangle = np.array([[[3.25, 2.5], [17.5, 6.75], [7.75, 19.5]]])  # on a 1/4 lattice
    fan_tris, _ = fan(8, np.array([11.5, 11.5]), 8.0, rng)
    grid_tris = grid(3, 3.0, 18.0, "lattice", "mixed", rng)
    steps = (1 / 16, 1 / 64, 1 / 256) if full else (1 / 16, 1 / 64)
    for name, geometry in (("triangle", triangle), ("fan-8", fan_tris), ("grid-3x3", grid_tris)):
        for step in steps:
            count = int(2 / step) + 1  # two pixels of travel
            for axis, direction in (("x", (step, 0.0)), ("y", (0.0, step)), ("diagonal", (step, step))):
                if name != "triangle" and step != 1 / 16 and axis != "diagonal":
                    continue  # the finer steps on every geometry only along the diagonal
                add(f"{name}/translate-{axis}-1/{int(1 / step)}", translate(geometry, direction, count))
        for degrees in ((0.01, 0.05, 0.1) if full else (0.05,)):
            add(f"{name}/rotate-{degrees:g}deg", rotate(geometry, rng.uniform(6, 14, 2), degrees, 120))
        add(f"{name}/zoom-0.1pct", zoom(geometry, rng.uniform(8, 12, 2), 0.001, 100))
    if not meshes:  # the plain geometries' cases drew from rng first: they are the same either way
        return cases
    # a tall sliver far right on a large screen: two thousand rows down each long edge,
    # where single-precision stepping drifts by a visible fraction of a pixel
    tall = np.array([[[1500.25, 0.75], [1530.5, 2040.25], [1509.75, 2046.5]]])
    scenes = tuple(Scene(1600, 2048, f) for f in translate(tall, (1 / 64, 0.0), 129))
    cases.append(MotionCase("motion/tall-triangle/translate-x-1/64", scenes))
    # a projected mesh, sliding and turning
    screen, _, _ = project(_shapes()["icosphere"], _rotation(rng), 3.0, size=size)
    add("icosphere/translate-diagonal-1/16", translate(screen, (1 / 16, 1 / 16), 33))
    add("icosphere/rotate-0.02deg", rotate(screen, np.array([12.3, 11.7]), 0.02, 60))
    # textured sequences: an affine quad and a perspective floor at a grazing angle
    for texels in ((8, 64, 256) if full else (8, 64)):
        quad, uv, _ = _textured_quad(size, grazing=False)
        add(f"textured-{texels}/quad/translate-x-1/64", translate(quad, (1 / 64, 0.0), 129), uv, texels=texels)
        add(f"textured-{texels}/quad/translate-diagonal-1/16", translate(quad, (1 / 16, 1 / 16), 33), uv, texels=texels)
    floor, uv, w = _textured_quad(32, grazing=True)
    add("textured-64/perspective-floor/translate-x-1/64", translate(floor, (1 / 64, 0.0), 129), uv, w, texels=64, viewport=32)
    add("textured-256/perspective-floor/still", [floor], uv, w, texels=256, viewport=32)
    return cases


def aa_motion_cases(seed: int, full: bool = False) -> list[MotionCase]:
    """Motion of anti-aliased paths and lines: ``motion/path-<shape>/<movement>/<rule>``
    (frames: path scenes) and ``motion/aa-lines/<movement>/w<width>`` (frames: line
    scenes). The quick suite: the glyph sliding diagonally by 1/64 px over half a pixel,
    the pentagram turning by 0.05 degrees a frame, and three segments sliding by 1/64 px;
    the full suite adds the other axes, two pixels of travel, finer and coarser turns, the
    even-odd rule and other widths."""
    rng = np.random.default_rng(seed + 34)
    size = 32
    cases: list[MotionCase] = []
    shapes = {"glyph-d": glyph_d(rng.uniform(4, 5, 2), 23.0, 10), "star-5-2": [star(5, 2, rng.uniform(15, 17, 2), 12.5, 0.3)]}
    count = 129 if full else 33  # two pixels of travel at 1/64, or half a pixel

    def add_path(name: str, movement: str, frames: list[NDArray], sizes: NDArray, rule: str) -> None:
        scenes: tuple[Any, ...] = tuple(PathScene(size, size, f, sizes, np.zeros(sizes.size, dtype=np.int64), rule)
                                        for f in frames)
        cases.append(MotionCase(f"motion/path-{name}/{movement}/{rule}", scenes))

    for name, contours in shapes.items():
        vertices = np.concatenate(contours)
        sizes = np.array([c.shape[0] for c in contours], dtype=np.int64)
        centre = vertices.mean(axis=0) + rng.uniform(-1, 1, 2)
        for rule in (("nonzero", "evenodd") if full else ("nonzero",)):
            moves = [("translate-diagonal-1/64", translate(vertices, (1 / 64, 1 / 64), count))]
            if full:
                moves += [("translate-x-1/64", translate(vertices, (1 / 64, 0.0), count)),
                          ("translate-y-1/64", translate(vertices, (0.0, 1 / 64), count))]
            for degrees in ((0.01, 0.05, 0.1) if full else (0.05,)):
                moves.append((f"rotate-{degrees:g}deg", rotate(vertices, centre, degrees, 120 if full else 40)))
            for movement, frames in moves:
                if not full and (name, movement) not in (("glyph-d", "translate-diagonal-1/64"), ("star-5-2", "rotate-0.05deg")):
                    continue
                add_path(name, movement, frames, sizes, rule)
    # segments: shallow, steep and diagonal, ends off the lattice
    a = np.array([[3.3, 5.2], [6.1, 3.4], [4.2, 27.1]])
    b = np.array([[28.7, 11.9], [11.4, 28.6], [27.3, 6.2]])
    for width in ((0.5, 1.0, 2.5) if full else (1.0,)):
        for movement, step in ((("slide-x-1/64", (1 / 64, 0.0)), ("slide-y-1/64", (0.0, 1 / 64)),
                                ("slide-diagonal-1/64", (1 / 64, 1 / 64))) if full else (("slide-x-1/64", (1 / 64, 0.0)),)):
            lines: tuple[Any, ...] = tuple(LineScene.from_segments(size, size, a + k * np.asarray(step), b + k * np.asarray(step),
                                                                   width) for k in range(count))
            cases.append(MotionCase(f"motion/aa-lines/{movement}/w{width:g}", lines))
    return cases
