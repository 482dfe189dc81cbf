"""Fuzz scenes for campaigns: small generated scenes, each regenerable alone from
``(family, seed, index)``.

:func:`generate` draws scene ``index`` of a family from its own generator,
``np.random.default_rng([FAMILY_CODE[family], seed, index])``: no scene depends on another,
so a failure found on any worker after hours replays on a laptop from its three numbers,
and scenes ``start .. start + count - 1`` can be handed out in any order. Ids are
``<suite family>/fuzz/<family>/<seed>/<index>`` (:func:`scene_id`): a fuzz case belongs to
the suite family it stands for (:data:`SUITE_FAMILY`; ``Case.family`` is the id's first
part), so the checks gated on a family (invariance, triangulation, degenerate) judge it as
they judge that family's suite cases.

Each family reuses its suite family's building blocks with the scene's own generator:

- ``lattice``: :func:`cases.scenes.lattice_triangles` on the 1, 1/2 .. 1/256 px lattices
  (vertices on pixel centres and corners, edges through samples: ties on purpose), or
  sub-pixel triangles around pixel centres on the 1/16 lattice; first, four tie probes
  (right triangles whose every vertex and edge midpoint is a pixel centre, each mirrored:
  every kind of tie, owned and not, in every scene). Exact in any arithmetic.
- ``float``: :func:`cases.scenes.random_triangles` of random sizes, unconstrained
  vertices, or lattice triangles nudged by about a micro-pixel (near ties).
- ``partitions``: exact planar partitions (:mod:`cases.partitions`: grids, fans, sliver
  fans, strips, Delaunay triangulations) with their outline as ``region``, windings mixed.
- ``meshes``: small closed trimesh shapes (built once per process, trimesh imported on
  first use) seen by a perspective camera (``closed``), or cut by the near plane.
- ``degenerate``: two ordinary triangles and a few bad ones: zero area, epsilon heights
  and widths, slivers, huge coordinates (10**k and 2**k px, ``refusable``), off-screen,
  non-finite; or a screen-covering pair of huge triangles (a partition).
- ``motion``: a triangle, fan or grid translated by 1/16 .. 1/256 px, turned or zoomed
  over a short sequence (8 .. 25 frames, :mod:`cases.motion`); some textured, some a
  perspective floor at a grazing angle, some a tall sliver on a 1600 x 2048 screen (where
  single-precision stepping drifts).
- ``paths``: star polygons, rings, overlapping polygons, random contours, spikes and
  doubled vertices under a random fill rule; quad-grid partitions (:mod:`cases.paths`).
- ``lines``: fans in every octant, lattice, float, near-tie and sub-pixel segments,
  polylines (walks, spirals, zig-zags, stars) and bad segments (:mod:`cases.lines`).
- ``tall``: one to three triangles over 2,048 px tall at x past 1,024 px on a screen
  1,152 px wide and 2,064 .. 2,560 tall (:func:`cases.scenes.tall_triangles`), where an
  edge stepped down the rows in float32 drifts by a tenth of a pixel.
- ``winding``: one path of a triangle or rectangle traced N times over (N either side of
  128, 256, 32,768 and 65,536, where 8- and 16-bit winding counters wrap or saturate, or
  anywhere from 2 to 300) and one to three other such contours traced once to three
  times, each wound either way, on the 1/4 or 1/2 px lattice or not, under a random fill
  rule, on an 8 or 16 px screen (:func:`cases.paths.wound`).

Scenes are small (mostly 3 .. 64 primitives -- meshes up to 120 -- in a 24 .. 64 px
viewport; the tall triangles and the tall motion sliver excepted, and the deep-winding
paths' up to 262,000 vertices) so that a campaign checks hundreds a second per
worker; generating one takes 0.3 .. 1.3 ms.

>>> case = generate("lattice", 0, 7)
>>> case.id, case.lattice, case == generate("lattice", 0, 7)
('lattice/fuzz/lattice/0/7', True, False)
>>> bool((case.scene.positions == generate("lattice", 0, 7).scene.positions).all())
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from cases import lines as line_shapes
from cases.partitions import _mix_windings, delaunay, fan, grid, sliver_fan, strip
from cases.paths import _on_lattice as _path_lattice
from cases.paths import _random_contours, quad_grid, rectangle, regular, star, wound
from cases.scenes import lattice_triangles, random_triangles, tall_triangles
from harness.contract.case import Case, MotionCase
from harness.contract.scenes import LineScene, PathScene, Scene

__all__ = ["FAMILIES", "FAMILY_CODE", "SUITE_FAMILY", "generate", "scene_id", "scene_point", "primitives", "REFUSABLE_FROM"]

FAMILIES: tuple[str, ...] = ("lattice", "float", "partitions", "meshes", "degenerate", "motion", "paths", "lines", "tall",
                             "winding")
# The first word of each scene's seed sequence: fixed forever (a new family takes a new
# code), so that adding a family never changes another family's scenes.
FAMILY_CODE: dict[str, int] = {"lattice": 1, "float": 2, "partitions": 3, "meshes": 4, "degenerate": 5, "motion": 6,
                               "paths": 7, "lines": 8, "tall": 9, "winding": 10}
# The suite family each fuzz family stands for: the checks gated on a case's family
# (invariance, triangulation, degenerate) know the suites' names, and a fuzz case's own
# family (``Case.family``, the id's first part) is ``fuzz``.
SUITE_FAMILY: dict[str, str] = {"lattice": "lattice", "float": "float", "partitions": "watertight", "meshes": "mesh",
                                "degenerate": "degenerate", "motion": "motion", "paths": "paths", "lines": "lines",
                                "tall": "float", "winding": "paths"}
# |coordinate| from which a primitive may be refused (ValueError naming it), as in the suites
REFUSABLE_FROM = 1e6

Positions = NDArray[np.float64]


def generate(family: str, seed: int, index: int) -> Case | MotionCase:
    """Scene ``index`` of ``family`` for ``seed``: the same whenever and wherever it is
    drawn (only these three numbers decide it), id :func:`scene_id`.

    Raises ValueError naming the family when it is unknown, and naming the argument when
    ``seed`` or ``index`` is not a non-negative integer.

    >>> generate("partitions", 3, 0).id
    'watertight/fuzz/partitions/3/0'
    >>> generate("cubes", 0, 0)  # doctest: +NORMALIZE_WHITESPACE
    Traceback (most recent call last):
    ...
    ValueError: unknown fuzz family 'cubes': choose one of lattice, float, partitions, meshes, degenerate, motion, paths, lines,
    tall, winding
    """
    build = _BUILDERS.get(family) if isinstance(family, str) else None
    if build is None:
        raise ValueError(f"unknown fuzz family {family!r}: choose one of {', '.join(FAMILIES)}")
    for name, value in (("seed", seed), ("index", index)):
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < 0:
            raise ValueError(f"fuzz scene {name} must be a non-negative integer, not {value!r}")
    rng = np.random.default_rng([FAMILY_CODE[family], int(seed), int(index)])
    return build(scene_id(family, int(seed), int(index)), rng)


def scene_id(family: str, seed: int, index: int) -> str:
    """The id of fuzz scene (family, seed, index): ``<suite family>/fuzz/<family>/<seed>/<index>``."""
    return f"{SUITE_FAMILY[family]}/fuzz/{family}/{seed}/{index}"


def scene_point(case_id: str) -> tuple[str, int, int] | None:
    """(family, seed, index) of a fuzz scene's id, None for any other id.

    >>> scene_point("watertight/fuzz/partitions/3/0"), scene_point("lattice/bits-0")
    (('partitions', 3, 0), None)
    """
    parts = case_id.split("/")
    if len(parts) != 5 or parts[1] != "fuzz" or parts[2] not in FAMILY_CODE or not (parts[3].isdigit() and parts[4].isdigit()):
        return None
    return parts[2], int(parts[3]), int(parts[4])


def primitives(case: Case | MotionCase) -> int:
    """How many primitives a check of the case looks at: triangles, paths or segments;
    a motion case's every frame counted.

    >>> primitives(generate("motion", 0, 0)) % len(generate("motion", 0, 0).frames[0])
    0
    """
    if isinstance(case, MotionCase):
        return sum(len(frame) for frame in case.frames)
    return len(case.scene)


# -- helpers ---------------------------------------------------------------------------------


def _seed(rng: np.random.Generator) -> int:
    """An integer seed for the building blocks that take one, drawn from the scene's rng."""
    return int(rng.integers(2**62))


def _on_lattice(coordinates: NDArray, bits: int = 8) -> bool:
    """Whether every coordinate is finite, below 2**12 in magnitude and a multiple of
    2**-bits: float arithmetic on such scenes is exact (``Case.lattice``)."""
    c = np.asarray(coordinates, dtype=np.float64)
    with np.errstate(invalid="ignore", over="ignore"):
        scaled = c * 2.0**bits
        return bool(np.isfinite(c).all() and (np.abs(c) < 2.0**12).all() and (scaled == np.round(scaled)).all())


def _choice(rng: np.random.Generator, options: tuple[Any, ...], weights: tuple[float, ...] | None = None) -> Any:
    """One of ``options`` (by index: options may be tuples)."""
    p = None if weights is None else np.asarray(weights, dtype=np.float64) / sum(weights)
    return options[int(rng.choice(len(options), p=p))]


def _refusable(coordinates: NDArray) -> tuple[int, ...]:
    """Primitives (first axis) with a finite coordinate of magnitude REFUSABLE_FROM or more
    and no non-finite one."""
    flat = np.asarray(coordinates, dtype=np.float64).reshape(coordinates.shape[0], -1)
    with np.errstate(invalid="ignore"):
        big = np.isfinite(flat).all(axis=1) & (np.abs(flat) >= REFUSABLE_FROM).any(axis=1)
    return tuple(int(k) for k in np.flatnonzero(big))


# -- triangles -------------------------------------------------------------------------------

LATTICE_SIZE = 32


def _tie_probes(rng: np.random.Generator, pairs: int) -> Positions:
    """(2 * pairs, 3, 2): right triangles with their corner on a pixel centre and legs of
    2, 4 or 6 px along the axes, each with its mirror image through the corner: the
    midpoint of every edge -- horizontal, vertical and slanted, on either side of its
    triangle (owned by any tie rule and not) -- is a pixel centre, and so is every
    vertex. Ties of every kind in every scene."""
    corner = np.floor(rng.uniform(7, LATTICE_SIZE - 7, size=(pairs, 2))) + 0.5
    legs = 2.0 * rng.integers(1, 4, size=(pairs, 2)) * rng.choice([-1.0, 1.0], size=(pairs, 2))
    out = []
    for sign in (1.0, -1.0):
        x_leg, y_leg = corner.copy(), corner.copy()
        x_leg[:, 0] += sign * legs[:, 0]
        y_leg[:, 1] += sign * legs[:, 1]
        out.append(np.stack([corner, x_leg, y_leg], axis=1))
    return np.concatenate(out)


def _lattice(case_id: str, rng: np.random.Generator) -> Case:
    if rng.random() < 0.8:
        bits = int(_choice(rng, (0, 1, 2, 3, 4, 8), (3, 2, 3, 1, 2, 1)))
        tris = lattice_triangles(int(rng.integers(8, 45)), LATTICE_SIZE, bits, _seed(rng))
    else:
        # sub-pixel triangles around pixel centres, offsets on the 1/16 lattice
        count = int(rng.integers(16, 61))
        centres = np.floor(rng.uniform(1, LATTICE_SIZE - 1, size=(count, 1, 2))) + 0.5
        tris = centres + rng.integers(-12, 13, size=(count, 3, 2)) / 16
    # the probes first: evidence lists the first triangles' deviations
    tris = np.concatenate([_tie_probes(rng, 2), tris])
    return Case(case_id, Scene(LATTICE_SIZE, LATTICE_SIZE, tris), lattice=True)


def _float(case_id: str, rng: np.random.Generator) -> Case:
    size = int(_choice(rng, (32, 64)))
    mode = rng.random()
    count = int(rng.integers(8, 49))
    if mode < 0.5:
        tris = random_triangles(count, float(np.exp(rng.uniform(np.log(0.5), np.log(size * size / 8)))), size, _seed(rng))
    elif mode < 0.75:
        tris = rng.uniform(-2.0, size + 2.0, size=(count, 3, 2))
    else:
        # lattice triangles nudged by about a micro-pixel: samples just off the edges
        amount = float(_choice(rng, (2e-6, 1e-9, 1e-12)))
        lattice = lattice_triangles(count, size, int(_choice(rng, (0, 1, 2, 4))), _seed(rng))
        tris = lattice + rng.uniform(-amount, amount, (count, 3, 2))
    return Case(case_id, Scene(size, size, tris), lattice=_on_lattice(tris))


PARTITION_SIZE = 64  # what cases.partitions' strip and delaunay draw on


def _partitions(case_id: str, rng: np.random.Generator) -> Case:
    kind = _choice(rng, ("grid", "fan", "sliver-fan", "strip", "delaunay"), (4, 3, 1, 1, 2))
    if kind == "grid":
        cells = int(rng.integers(2, 7))
        where = _choice(rng, (0.0, 0.5, 0.25, float(rng.uniform(0, 1))))  # lines on corners, centres, samples, anywhere
        lo = float(rng.integers(1, 9)) + where
        hi = lo + cells * float(_choice(rng, (4, 6, 8, 10, float(rng.uniform(3, 9)))))
        hi = min(hi, PARTITION_SIZE - 1.0)
        jitter = _choice(rng, ("none", "lattice", "float"))
        tris = grid(cells, lo, hi, jitter, _choice(rng, ("main", "anti", "mixed")), rng)
        region = rectangle(lo, lo, hi, hi)
    elif kind in ("fan", "sliver-fan"):
        centre = _choice(rng, (np.array([31.5, 31.5]), np.array([32.0, 32.0]), rng.uniform(24, 40, 2)))
        build = fan if kind == "fan" else sliver_fan
        tris, region = build(int(rng.integers(4, 25)), centre, float(rng.uniform(8, 28)), rng)
    elif kind == "strip":
        top = float(_choice(rng, (float(rng.integers(4, 28)) + 0.5, float(rng.uniform(4, 28)))))
        tris, region = strip(2 * int(rng.integers(3, 13)), top, top + float(rng.uniform(4, 30)), rng)
    else:
        tris, region = delaunay(int(rng.integers(8, 31)), rng, bool(rng.random() < 0.5))
    tris = _mix_windings(np.asarray(tris, dtype=np.float64), rng)
    return Case(case_id, Scene(PARTITION_SIZE, PARTITION_SIZE, tris), lattice=_on_lattice(tris),
                region=np.asarray(region, dtype=np.float64))


MESH_SIZE = 48


@cache
def _mesh_shapes() -> tuple[tuple[str, Any], ...]:
    """Small closed meshes, built once per process (trimesh is imported here, not when
    this module is: it takes over a second)."""
    import trimesh

    return (
        ("box", trimesh.creation.box()),
        ("icosahedron", trimesh.creation.icosphere(subdivisions=0)),
        ("icosphere", trimesh.creation.icosphere(subdivisions=1)),
        ("cylinder", trimesh.creation.cylinder(radius=0.5, height=1.5, sections=10)),
        ("capsule", trimesh.creation.capsule(height=1.0, radius=0.4, count=[6, 6])),
        ("torus", trimesh.creation.torus(major_radius=1.0, minor_radius=0.35, major_sections=10, minor_sections=6)),
    )


def _meshes(case_id: str, rng: np.random.Generator) -> Case:
    from cases.meshes import _rotation, project

    shapes = _mesh_shapes()
    _, mesh = shapes[int(rng.integers(len(shapes)))]
    rotation = _rotation(rng)
    if rng.random() < 0.8:
        # wholly in front of the camera (the farthest vertex is sqrt(3) from the centre)
        screen, _, _ = project(mesh, rotation, float(rng.uniform(2.2, 4.0)), size=MESH_SIZE)
        return Case(case_id, Scene(MESH_SIZE, MESH_SIZE, screen), closed=True)
    # the near plane cuts it: open, only the convention-bound checks apply
    screen, w, _ = project(mesh, rotation, float(rng.uniform(0.15, 0.6)), size=MESH_SIZE)
    return Case(case_id, Scene(MESH_SIZE, MESH_SIZE, screen, attributes=w[..., None], w=w), refusable=_refusable(screen))


DEGENERATE_SIZE = 32
ULP = float(np.spacing(10.5))


def _bad_triangle(rng: np.random.Generator, huge: bool) -> Positions:
    """One degenerate or hostile triangle, (3, 2): a huge one, or one of the other kinds."""
    size = DEGENERATE_SIZE
    kind = "huge" if huge else _choice(rng, ("zero-area", "epsilon", "sliver", "on-samples", "offscreen", "non-finite"),
                                       (3, 3, 2, 2, 1, 1))
    if kind == "zero-area":
        p = np.floor(rng.uniform(2, size - 2, 2)) + _choice(rng, (0.0, 0.5))
        d = rng.integers(-6, 7, 2) / _choice(rng, (1.0, 2.0, 4.0))
        steps = np.sort(rng.integers(-3, 4, 3)).astype(np.float64)
        shape = _choice(rng, ("collinear", "repeated", "point"))
        if shape == "repeated":
            steps[1] = steps[0]
        elif shape == "point":
            steps[:] = 0.0
        collinear: Positions = p + steps[:, None] * d
        return collinear
    if kind == "epsilon":
        # a long edge through sample points (along a row, a column or a diagonal), the third
        # vertex a tiny step off it, on either side
        eps = float(_choice(rng, (1e-8, 1e-12, ULP, 2.0 ** -int(rng.integers(10, 50)))) * _choice(rng, (1.0, -1.0)))
        c = np.floor(rng.uniform(4, size - 4, 2)) + 0.5
        reach = float(rng.integers(3, 12))
        axis = _choice(rng, ("row", "column", "diagonal"))
        if axis == "row":
            return np.array([[c[0] - reach, c[1]], [c[0] + reach, c[1]], [c[0] + rng.uniform(-2, 2), c[1] + eps]])
        if axis == "column":
            return np.array([[c[0], c[1] - reach], [c[0], c[1] + reach], [c[0] + eps, c[1] + rng.uniform(-2, 2)]])
        return np.array([[c[0] - reach, c[1] - reach], [c[0] + reach, c[1] + reach], [c[0] + eps, c[1] - eps]])
    if kind == "sliver":
        a = rng.uniform(1, size - 1, 2)
        b = a + rng.uniform(-20, 20, 2)
        return np.array([a, b, a + (b - a) * 0.5 + [float(_choice(rng, (1e-3, 1e-6, 1e-9))), 0.0]])
    if kind == "on-samples":
        on_samples: Positions = np.floor(rng.uniform(1, size - 1, (3, 2))) + _choice(rng, (0.0, 0.5))
        return on_samples
    if kind == "huge":
        big = float(_choice(rng, (10.0 ** int(rng.integers(4, 40)), 2.0 ** int(rng.integers(12, 1024)),
                                  10.0 ** int(rng.integers(40, 308)))))
        shape = _choice(rng, ("sliver", "wedge", "far"))
        if shape == "sliver":
            return np.array([[-big, rng.uniform(4, 16)], [big, rng.uniform(16, 28)], [rng.uniform(4, 28), rng.uniform(12, 20)]])
        if shape == "wedge":
            return np.array([[-big, rng.uniform(2, 10)], [big, rng.uniform(2, 10)], rng.uniform(12, 30, 2)])
        return np.array([rng.uniform(0, size, 2), rng.uniform(0, size, 2),
                         [big * _choice(rng, (1.0, -1.0)), rng.uniform(0, size)]])
    if kind == "offscreen":
        p = rng.uniform(-size, 2 * size, (3, 2))
        return p
    p = rng.uniform(0, size, (3, 2))
    p[int(rng.integers(3)), int(rng.integers(2))] = _choice(rng, (np.nan, np.inf, -np.inf))
    return p


def _degenerate(case_id: str, rng: np.random.Generator) -> Case:
    size = DEGENERATE_SIZE
    if rng.random() < 0.1:
        # a screen-covering pair from far away: a partition of the square of side 2*big
        big = float(_choice(rng, (10.0 ** int(rng.integers(3, 40)), 2.0 ** int(rng.integers(10, 1023)))))
        pair = np.array([[[-big, -big], [big, -big], [-big, big]], [[big, -big], [big, big], [-big, big]]])
        square = rectangle(-big, -big, big, big)
        return Case(case_id, Scene(size, size, pair), refusable=_refusable(pair), region=square)
    anchors = random_triangles(2, float(rng.uniform(10, 60)), size, _seed(rng))
    # huge triangles in scenes of their own: a rasterizer may refuse one (a skip of the
    # whole scene), which must not hide the other kinds
    huge = bool(rng.random() < 0.25)
    bad = np.array([_bad_triangle(rng, huge) for _ in range(int(rng.integers(1, 4 if huge else 7)))])
    tris = np.concatenate([anchors, bad])
    return Case(case_id, Scene(size, size, tris), lattice=_on_lattice(tris), refusable=_refusable(tris))


MOTION_SIZE = 24


def _motion(case_id: str, rng: np.random.Generator) -> MotionCase:
    from cases.motion import _textured_quad, rotate, translate, zoom

    size = MOTION_SIZE
    kind = _choice(rng, ("triangle", "fan", "grid", "textured", "perspective", "tall"), (8, 4, 4, 2, 1, 1))
    if kind == "perspective":
        # a floor seen at a grazing angle, textured: w differs per vertex
        floor, uv, w = _textured_quad(32, grazing=True)
        count = int(rng.integers(8, 26))
        scenes = tuple(Scene(32, 32, f, uv, w) for f in translate(floor, (float(_choice(rng, (1 / 64, 1 / 16))), 0.0), count))
        return MotionCase(case_id, scenes, int(_choice(rng, (64, 256))), True)
    if kind == "tall":
        # a tall sliver far right on a large screen: two thousand rows down each long edge,
        # where single-precision stepping drifts by a visible fraction of a pixel
        x = float(rng.integers(1000, 1500)) + float(_choice(rng, (0.25, 0.5, 0.75)))
        tall = np.array([[[x, 0.75], [x + float(rng.integers(16, 40)) + 0.5, 2040.25],
                          [x + float(rng.integers(4, 14)) + 0.75, 2046.5]]])
        scenes = tuple(Scene(1600, 2048, f) for f in translate(tall, (1 / 64, 0.0), int(rng.integers(17, 34))))
        return MotionCase(case_id, scenes)
    attributes, texels = None, None
    if kind == "triangle":
        # on the 1/4 lattice, at least a pixel in area (twice the area: |cross| >= 2)
        geometry = np.array([[[3.0, 3.0], [12.0, 4.0], [5.0, 12.0]]])
        for _ in range(16):
            drawn = np.round(rng.uniform(2, size - 6, (1, 3, 2)) * 4) / 4
            (ax, ay), (bx, by), (cx, cy) = drawn[0]
            if abs((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)) >= 2.0:
                geometry = drawn
                break
    elif kind == "fan":
        geometry, _ = fan(int(rng.integers(4, 9)), np.floor(rng.uniform(9, 13, 2)) + _choice(rng, (0.0, 0.5)),
                          float(rng.uniform(4, 8)), rng)
    elif kind == "grid":
        geometry = grid(2, 3.0, float(_choice(rng, (15.0, 17.0, 18.5))), "lattice", "mixed", rng)
    else:
        lo, hi = rng.uniform(3, 6, 2), rng.uniform(size - 8, size - 4, 2)
        corners = np.array([lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]])
        faces = np.array([[0, 1, 2], [0, 2, 3]])
        uv = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
        geometry, attributes, texels = corners[faces], uv[faces], int(_choice(rng, (8, 64)))
    movement = _choice(rng, ("translate", "rotate", "zoom"), (3, 1, 1))
    if movement == "translate":
        step = float(_choice(rng, (1 / 16, 1 / 64, 1 / 256)))
        direction = _choice(rng, ((step, 0.0), (0.0, step), (step, step), (-step, step)))
        frames = translate(geometry, direction, int(rng.integers(8, 26)))
    elif movement == "rotate":
        frames = rotate(geometry, rng.uniform(6, 18, 2), float(rng.uniform(0.01, 0.2)), int(rng.integers(8, 21)))
    else:
        frames = zoom(geometry, rng.uniform(8, 16, 2), float(rng.uniform(0.0005, 0.005)), int(rng.integers(8, 21)))
    scenes = tuple(Scene(size, size, f, attributes) for f in frames)
    return MotionCase(case_id, scenes, texels)


# -- paths -----------------------------------------------------------------------------------

PATH_SIZE = 32
_STARS = tuple((n, k) for n in range(5, 13) for k in range(2, (n + 1) // 2) if math.gcd(n, k) == 1)


def _paths(case_id: str, rng: np.random.Generator) -> Case:
    size = PATH_SIZE
    rule = _choice(rng, ("nonzero", "evenodd"))
    scale = _choice(rng, (4, 2, None))  # on the 1/4 or 1/2 lattice, or floats

    def placed(contour: Positions) -> Positions:
        return _path_lattice(contour, scale) if scale else contour

    def centre() -> Positions:
        return rng.uniform(size / 2 - 3, size / 2 + 3, 2)

    kind = _choice(rng, ("star", "ring", "overlap", "random", "spike", "doubled", "partition"), (3, 2, 2, 3, 1, 1, 2))
    region = None
    if kind == "star":
        n, k = _STARS[int(rng.integers(len(_STARS)))]
        paths = [[placed(star(n, k, centre(), float(rng.uniform(8, 14)), float(rng.uniform(0, 2 * np.pi))))]]
    elif kind == "ring":
        outer = placed(regular(int(rng.integers(3, 25)), centre(), float(rng.uniform(11, 15)), float(rng.uniform(0, 1))))
        hole = placed(regular(int(rng.integers(3, 18)), centre(), float(rng.uniform(3, 7)), float(rng.uniform(0, 1))))
        paths = [[outer, hole[:: _choice(rng, (1, -1))]]]
    elif kind == "overlap":
        paths = [[placed(regular(int(rng.integers(3, 8)), rng.uniform(8, 24, 2), float(rng.uniform(5, 11)),
                                 float(rng.uniform(0, 7))))[:: _choice(rng, (1, -1))] for _ in range(int(rng.integers(2, 4)))]]
    elif kind == "random":
        paths = [_random_contours(rng, int(rng.integers(1, 4)), size, scale) for _ in range(int(rng.integers(1, 4)))]
    elif kind == "spike":
        a, b = np.sort(rng.integers(3, 14, 2)) + np.array([0, 12])
        tip = placed(rng.uniform(0, size, 2))
        out = np.array([float(rng.integers(a, b)) + 0.5, float(a)])
        paths = [[np.array([[a, a], out, tip, out, [b, a], [b, b], [a, b]], dtype=np.float64)]]
    elif kind == "doubled":
        n, k = _STARS[int(rng.integers(len(_STARS)))]
        doubled = np.repeat(placed(star(n, k, centre(), float(rng.uniform(8, 14)))), 2, axis=0)
        paths = [[np.concatenate([doubled, doubled[:1]])]]
    else:
        jitter = _choice(rng, ("lattice", "half", "float"))
        lo = float(_choice(rng, (4.0, 3.5)))
        cells, square = quad_grid(int(rng.integers(2, 6)), lo, lo + 24.0, jitter, rng)
        flip = rng.random(len(cells)) < 0.5
        paths = [[c[::-1] if f else c] for c, f in zip(cells, flip)]
        region = square
    scene = PathScene.from_paths(size, size, paths, rule)
    return Case(case_id, scene, lattice=_on_lattice(scene.vertices), region=region)


# -- lines -----------------------------------------------------------------------------------

LINE_SIZE = 32
# Two ordinary strips that the bad-segment scenes carry first (segments 0, 1 and 2).
_LINE_ANCHORS = [np.array([[1.5, 1.5], [9.5, 4.5], [12.0, 9.25]]), np.array([[30.5, 24.0], [22.25, 30.5]])]


def _bad_segment(rng: np.random.Generator) -> Positions:
    """One bad segment (2, 2): zero length, 1e-9 px, huge or non-finite."""
    kind = _choice(rng, ("zero-length", "epsilon", "huge", "non-finite"))
    p = np.floor(rng.uniform(2, LINE_SIZE - 2, 2)) + _choice(rng, (0.0, 0.5, 0.25, float(rng.uniform(0, 1))))
    if kind == "zero-length":
        return np.array([p, p])
    if kind == "epsilon":
        return np.array([p, p + rng.integers(-2, 3, 2) * 1e-9])
    if kind == "huge":
        big = float(_choice(rng, (10.0 ** int(rng.integers(4, 30)), 2.0 ** int(rng.integers(12, 700)))))
        far = np.array([big * _choice(rng, (1.0, -1.0)), big * rng.uniform(-1, 1)])
        return np.array([p, far]) if rng.random() < 0.5 else np.array([-far, far + p])
    q = p + rng.uniform(-8, 8, 2)
    q[int(rng.integers(2))] = _choice(rng, (np.nan, np.inf, -np.inf))
    return np.array([p, q])


def _lines(case_id: str, rng: np.random.Generator) -> Case:
    size = LINE_SIZE
    width = 1.0 if rng.random() < 0.9 else float(_choice(rng, (2.5, 0.25, 1.5)))
    kind = _choice(rng, ("fan", "lattice", "float", "near-ties", "sub-pixel", "strips", "bad"), (2, 3, 2, 2, 1, 3, 1))
    refusable: tuple[int, ...] = ()
    if kind == "fan":
        origin = np.floor(rng.uniform(10, 22, 2)) + _choice(rng, ((0.5, 0.5), (0.0, 0.0), (0.5, 0.0), (0.25, 0.25)))
        reach = int(rng.integers(2, 10))
        steps = tuple(sorted({0, *(int(s) for s in rng.integers(1, reach, 2))}))
        a, b = line_shapes.fan(origin, reach, steps)
        scene = LineScene.from_segments(size, size, a, b, width)
    elif kind == "lattice":
        a, b = line_shapes._lattice_segments(rng, int(rng.integers(8, 49)), size, int(rng.integers(1, 17)),
                                              int(_choice(rng, (1, 2, 4, 8, 16))))
        scene = LineScene.from_segments(size, size, a, b, width)
    elif kind == "float":
        short = rng.random() < 0.5
        a, b = line_shapes._random_segments(rng, int(rng.integers(8, 49)), size, (0.5, 4.0) if short else (4.0, 40.0))
        scene = LineScene.from_segments(size, size, a, b, width)
    elif kind == "near-ties":
        segments = line_shapes._lattice_segments(rng, int(rng.integers(8, 49)), size, 8, int(_choice(rng, (2, 4))))
        a, b = line_shapes._nudged(segments, rng, float(_choice(rng, (1e-6, 1e-9))))
        scene = LineScene.from_segments(size, size, a, b, width)
    elif kind == "sub-pixel":
        a, b = line_shapes._around_centres(rng, int(rng.integers(8, 49)), size)
        scene = LineScene.from_segments(size, size, a, b, width)
    elif kind == "strips":
        shape = _choice(rng, ("walk", "diamond-walk", "spiral", "zigzag", "star"))
        if shape == "walk":
            strips = [line_shapes._walk(rng, int(rng.integers(4, 13)), size, int(rng.integers(2, 9)),
                                        int(_choice(rng, (1, 2, 8))),
                                        float(_choice(rng, (0.0, 0.5)))) for _ in range(int(rng.integers(1, 4)))]
        elif shape == "diamond-walk":
            strips = [line_shapes._diamond_walk(rng, int(rng.integers(4, 11)), size) for _ in range(int(rng.integers(1, 4)))]
        elif shape == "spiral":
            spiral = line_shapes.spiral(rng.uniform(14, 18, 2), float(rng.uniform(1, 4)), int(rng.integers(12, 48)),
                                        float(rng.uniform(6, 14)))
            strips = [_path_lattice(spiral, 4) if rng.random() < 0.5 else spiral]
        elif shape == "zigzag":
            start = np.floor(rng.uniform(1, 6, 2)) + _choice(rng, (0.0, 0.5))
            step = rng.integers(1, 5, 2).astype(np.float64) * _choice(rng, ((1.0, 1.0), (-1.0, 1.0)))
            strips = [line_shapes.zigzag(start, step, int(rng.integers(3, 8)))]
        else:
            n, k = _STARS[int(rng.integers(len(_STARS)))]
            closed = line_shapes._star(n, k, rng.uniform(14, 18, 2), float(rng.uniform(8, 13)), float(rng.uniform(0, 6)))
            strips = [_path_lattice(closed, 4) if rng.random() < 0.5 else closed]
        scene = LineScene.from_strips(size, size, strips, width)
    else:
        bad = [_bad_segment(rng) for _ in range(int(rng.integers(1, 6)))]
        scene = LineScene.from_strips(size, size, [*_LINE_ANCHORS, *bad], width)
        a, b = scene.segments()
        refusable = _refusable(np.stack([a, b], axis=1))
    return Case(case_id, scene, lattice=_on_lattice(scene.vertices, 4), refusable=refusable)


# -- tall triangles --------------------------------------------------------------------------

TALL_WIDTH = 1152


def _tall(case_id: str, rng: np.random.Generator) -> Case:
    height = int(_choice(rng, (2064, 2112, 2560)))
    tris = tall_triangles(int(rng.integers(1, 4)), TALL_WIDTH, height, rng)
    return Case(case_id, Scene(TALL_WIDTH, height, tris), lattice=_on_lattice(tris, 2))


# -- deep winding ----------------------------------------------------------------------------

# windings either side of where 8- and 16-bit counters wrap or saturate (weighted), or small
_DEEP = (127, 128, 129, 255, 256, 257, 32767, 32768, 65535, 65536, 65537)


def _winding(case_id: str, rng: np.random.Generator) -> Case:
    size = int(_choice(rng, (8, 16)))
    turns = int(_choice(rng, _DEEP, (2, 3, 2, 2, 3, 2, 1, 1, 1, 2, 1))) if rng.random() < 0.8 else int(rng.integers(2, 301))
    scale = _choice(rng, (4, 2, None))

    def shape() -> Positions:
        if rng.random() < 0.5:
            lo = rng.uniform(0.5, size / 2, 2)
            contour = rectangle(lo[0], lo[1], *rng.uniform(lo + 2, size - 0.5, 2))
        else:
            contour = regular(3, rng.uniform(size / 2 - 1, size / 2 + 1, 2), float(rng.uniform(size / 4, size / 2)),
                              float(rng.uniform(0, 2 * np.pi)))
        contour = _path_lattice(contour, scale) if scale else contour
        return contour[:: _choice(rng, (1, -1))]

    deep = wound(shape(), turns)
    # others overlapping it, once or a few times over, either way round: windings next to
    # the deep one's (even-odd fills some where it leaves the deep one's out)
    others = [wound(shape(), int(_choice(rng, (1, 1, 2, 3)))) for _ in range(int(rng.integers(1, 4)))]
    scene = PathScene.from_paths(size, size, [[deep, *others]], _choice(rng, ("nonzero", "evenodd")))
    return Case(case_id, scene, lattice=_on_lattice(scene.vertices))


_BUILDERS: dict[str, Callable[[str, np.random.Generator], Case | MotionCase]] = {
    "lattice": _lattice, "float": _float, "partitions": _partitions, "meshes": _meshes, "degenerate": _degenerate,
    "motion": _motion, "paths": _paths, "lines": _lines, "tall": _tall, "winding": _winding,
}
assert set(_BUILDERS) == set(FAMILIES) == set(FAMILY_CODE) == set(SUITE_FAMILY)
