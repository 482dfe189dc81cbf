"""Hypothesis strategies for scenes, public for users' own property tests.

Vertices are drawn as integers on a sub-pixel lattice and mapped to floats: exact, they
shrink well, and they hit ties on purpose (vertices on sample points, edges through them).
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from harness.contract.conventions import SNAP_ROUNDINGS, TIE_RULES, Convention, SnapRounding
from harness.contract.scenes import Scene

__all__ = ["conventions", "lattice_scenes", "float_scenes", "thin_scenes", "grid_scenes", "fan_scenes"]


@st.composite
def conventions(draw, snapping: bool = True):  # type: ignore[no-untyped-def]
    """Any convention: dyadic sample offsets, the eight tie rules, snapping 0..16 with the
    three roundings, culling."""
    sample = tuple(draw(st.integers(0, 8)) / 8 for _ in range(2))
    bits = draw(st.one_of(st.none(), st.integers(0, 16))) if snapping else None
    rounding: SnapRounding = draw(st.sampled_from(SNAP_ROUNDINGS)) if bits is not None else "nearest-even"
    return Convention(sample=sample, tie=draw(st.sampled_from(TIE_RULES)), subpixel_bits=bits,
                      cull=draw(st.sampled_from(["none", "cw", "ccw"])), snap_rounding=rounding)


@st.composite
def lattice_scenes(draw, max_bits: int = 4, size: int = 12, max_triangles: int = 4):  # type: ignore[no-untyped-def]
    """Triangles on the 2**-bits lattice (bits 0..max_bits), slightly beyond the viewport."""
    bits = draw(st.integers(0, max_bits))
    scale = 2**bits
    n = draw(st.integers(1, max_triangles))
    coord = st.integers(-2 * scale, (size + 2) * scale)
    ints = draw(st.lists(st.tuples(*[coord] * 6), min_size=n, max_size=n))
    positions = np.array(ints, dtype=np.float64).reshape(n, 3, 2) / scale
    return Scene(size, size, positions)


@st.composite
def float_scenes(draw, size: int = 12, max_triangles: int = 4):  # type: ignore[no-untyped-def]
    """Unconstrained float coordinates around the viewport."""
    n = draw(st.integers(1, max_triangles))
    coord = st.floats(-4.0, size + 4.0, allow_nan=False, allow_infinity=False)
    values = draw(st.lists(coord, min_size=6 * n, max_size=6 * n))
    return Scene(size, size, np.array(values).reshape(n, 3, 2))


@st.composite
def thin_scenes(draw, size: int = 12):  # type: ignore[no-untyped-def]
    """Near-zero heights or widths: a lattice edge plus a third vertex a tiny step off it."""
    scale = 4
    a = np.array([draw(st.integers(0, size * scale)) for _ in range(4)], dtype=np.float64).reshape(2, 2) / scale
    t = draw(st.sampled_from([0.0, 0.25, 0.5, 1.0]))
    off = draw(st.sampled_from([1e-8, 1e-12, 2.0**-52, 5e-324, -1e-12]))
    mid = a[0] + t * (a[1] - a[0])
    axis = draw(st.integers(0, 1))
    c = mid.copy()
    c[axis] += off
    return Scene(size, size, np.array([[a[0], a[1], c]]))


@st.composite
def grid_scenes(draw, size: int = 24):  # type: ignore[no-untyped-def]
    """Planar partitions: a grid on a sub-pixel lattice, split on random diagonals, with
    lattice jitter and mixed windings (cases with their exact region)."""
    from cases.partitions import grid
    from harness.contract.case import Case

    bits = draw(st.integers(0, 4))
    scale = 2**bits
    cells = draw(st.integers(1, 4))
    lo = draw(st.integers(0, 4 * scale)) / scale
    step = draw(st.integers(scale, 5 * scale)) / scale
    seed = draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    hi = lo + cells * step
    tris = grid(cells, lo, hi, draw(st.sampled_from(["none", "lattice"])), draw(st.sampled_from(["main", "anti", "mixed"])), rng)
    flip = rng.random(len(tris)) < 0.5
    tris[flip] = tris[flip][:, ::-1]
    region = np.array([[lo, lo], [hi, lo], [hi, hi], [lo, hi]])
    return Case("watertight/strategy-grid", Scene(size, size, tris), lattice=bits <= 4, region=region)


@st.composite
def fan_scenes(draw, size: int = 24):  # type: ignore[no-untyped-def]
    """Fans of 3..16 triangles around a pixel centre, a corner or a lattice point."""
    from cases.partitions import fan
    from harness.contract.case import Case

    count = draw(st.integers(3, 16))
    centre = np.array([draw(st.integers(16, 32 * 4 - 16)), draw(st.integers(16, 32 * 4 - 16))]) / 8 * size / 32
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    tris, rim = fan(count, centre, size / 3, rng)
    return Case("watertight/strategy-fan", Scene(size, size, tris), region=rim)


# -- paths ---------------------------------------------------------------------------------

__all__ += ["path_scenes"]


@st.composite
def path_scenes(draw, size: int = 12, bits: int = 2, max_vertices: int = 8, max_contours: int = 3, max_paths: int = 3,  # type: ignore[no-untyped-def]
                fill_rules: tuple[str, ...] = ("nonzero", "evenodd")):
    """Path scenes on the 2**-bits lattice (1/4 px by default), vertices up to 2 px beyond a
    size x size viewport: 1..max_paths paths of 1..max_contours contours of
    1..max_vertices vertices each (one- and two-vertex contours, repeated and collinear
    vertices and self-intersections all come up), under a fill rule of ``fill_rules``."""
    from harness.contract.scenes import PathScene

    scale = 2**bits
    coord = st.integers(-2 * scale, (size + 2) * scale)
    contour = st.lists(st.tuples(coord, coord), min_size=1, max_size=max_vertices)
    paths = draw(st.lists(st.lists(contour, min_size=1, max_size=max_contours), min_size=1, max_size=max_paths))
    rule = draw(st.sampled_from(fill_rules))
    return PathScene.from_paths(size, size, [[np.array(c, dtype=np.float64) / scale for c in path] for path in paths], rule)
