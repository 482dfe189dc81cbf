"""Planar partitions: triangles that tile a convex region exactly, sharing their edges.

Whatever the convention, every pixel whose square lies inside the union must be hit once,
no pixel outside it ever, and no pixel twice. Vertices sit on pixel centres, on corners,
on other sample points, on a 1/16 lattice or on unconstrained floats; windings are mixed.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, Delaunay

from harness.contract.case import Case
from harness.contract.scenes import Scene

__all__ = ["grid", "fan", "strip", "delaunay", "sliver_fan", "partition_cases"]

SIZE = 64


def _mix_windings(triangles: NDArray[np.float64], rng: np.random.Generator) -> NDArray[np.float64]:
    """Reverse the vertex order of a random half of the triangles."""
    flip = rng.random(triangles.shape[0]) < 0.5
    out = triangles.copy()
    out[flip] = out[flip][:, ::-1]
    return out


def grid(cells: int, lo: float, hi: float, jitter: str, diagonal: str, rng: np.random.Generator) -> NDArray[np.float64]:
    """A cells x cells grid over [lo, hi]^2 split on the main or anti diagonal (or each
    cell at random with "mixed"); interior vertices moved by ``jitter``: "none", "lattice"
    (multiples of 1/16, up to 3/8 px) or "float" (uniform up to 0.37 px)."""
    lines = np.linspace(lo, hi, cells + 1)
    gx, gy = np.meshgrid(lines, lines, indexing="xy")
    v = np.stack([gx, gy], axis=-1)
    inner = v[1:-1, 1:-1]
    if jitter == "lattice":
        inner += rng.integers(-6, 7, size=inner.shape) / 16
    elif jitter == "float":
        inner += rng.uniform(-0.37, 0.37, size=inner.shape)
    tris = []
    for j in range(cells):
        for i in range(cells):
            a, b, c, d = v[j, i], v[j, i + 1], v[j + 1, i], v[j + 1, i + 1]
            main = diagonal == "main" or (diagonal == "mixed" and rng.random() < 0.5)
            tris += [(a, b, d), (a, d, c)] if main else [(a, b, c), (b, d, c)]
    return np.array(tris)


def fan(count: int, centre: NDArray[np.float64], radius: float, rng: np.random.Generator) -> tuple[NDArray, NDArray]:
    """``count`` triangles around ``centre``; the rim points lie on a circle at sorted
    angles no more than a half-turn apart, so the union is the convex rim polygon."""
    gaps = rng.uniform(0.8, 1.2, size=count)  # each gap under 0.43 of a turn for count >= 3
    angles = np.cumsum(gaps) / gaps.sum() * 2 * np.pi + rng.uniform(0, 2 * np.pi)
    rim = centre + radius * np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    tris = np.array([(centre, rim[k], rim[(k + 1) % count]) for k in range(count)])
    return tris, rim


def sliver_fan(count: int, centre: NDArray[np.float64], radius: float, rng: np.random.Generator) -> tuple[NDArray, NDArray]:
    """A fan whose rim points crowd into a few clusters: long slivers meeting at the
    centre, a few wide triangles closing the gaps."""
    clusters = np.array([0.3, 2.2, 4.1])
    spread = rng.uniform(0, 0.02, size=count)
    angles = np.sort(clusters[np.arange(count) % 3] + spread) + rng.uniform(0, 0.1)
    rim = centre + radius * np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    tris = np.array([(centre, rim[k], rim[(k + 1) % count]) for k in range(count)])
    return tris, rim


def strip(count: int, top: float, bottom: float, rng: np.random.Generator) -> tuple[NDArray, NDArray]:
    """A triangle strip between two horizontal lines, vertices at random x on each."""
    xt = np.sort(rng.uniform(2, SIZE - 2, size=count // 2 + 1))
    xb = np.sort(rng.uniform(2, SIZE - 2, size=count // 2 + 1))
    xt[0], xb[0], xt[-1], xb[-1] = 2.0, 2.0, SIZE - 2.0, SIZE - 2.0
    top_v = np.stack([xt, np.full_like(xt, top)], axis=-1)
    bot_v = np.stack([xb, np.full_like(xb, bottom)], axis=-1)
    tris = []
    for k in range(len(xt) - 1):
        tris.append((top_v[k], top_v[k + 1], bot_v[k]))
        tris.append((top_v[k + 1], bot_v[k + 1], bot_v[k]))
    outline = np.array([top_v[0], top_v[-1], bot_v[-1], bot_v[0]])
    return np.array(tris), outline


def delaunay(count: int, rng: np.random.Generator, lattice: bool) -> tuple[NDArray, NDArray]:
    """A Delaunay triangulation of random points (optionally on the 1/16 lattice)."""
    points = rng.uniform(3, SIZE - 3, size=(count, 2))
    if lattice:
        points = np.round(points * 16) / 16
        points = np.unique(points, axis=0)
    tri = Delaunay(points)
    hull = points[ConvexHull(points).vertices]
    return points[tri.simplices], hull


def partition_cases(seed: int, full: bool = False) -> list[Case]:
    """The partition family: ``watertight/<shape>/<detail>``."""
    rng = np.random.default_rng(seed)
    cases = []

    def add(name: str, tris: NDArray, region: NDArray, lattice: bool) -> None:
        tris = _mix_windings(tris, rng)
        cases.append(Case(f"watertight/{name}", Scene(SIZE, SIZE, tris), lattice=lattice, region=np.asarray(region, float)))

    cells = (6, 10) if full else (6,)

    def square(lo: float, hi: float) -> NDArray:
        return np.array([[lo, lo], [hi, lo], [hi, hi], [lo, hi]])

    for n in cells:
        for diagonal in ("main", "anti", "mixed"):
            for jitter in ("none", "lattice", "float"):
                # 60 = 6 * 10 and a multiple of 4: lines at exact multiples of 1, 1/2 ...
                add(f"grid-{n}x{n}-{diagonal}/{jitter}", grid(n, 2.0, 62.0, jitter, diagonal, rng), square(2.0, 62.0),
                    jitter != "float" and 60 % n == 0)
        for where, offset in (("centres", 0.5), ("corners", 0.0), ("samples-0.25", 0.25)):
            # every vertex on a sample point of the named kind
            add(f"grid-{n}x{n}-on-{where}/lattice", grid(n, 2.0 + offset, 62.0 + offset, "none", "mixed", rng),
                square(2.0 + offset, 62.0 + offset), 60 % n == 0)
    for diagonal in ("main", "anti"):
        # lines at non-dyadic spacing: many samples within rounding of an edge
        add(f"grid-12x12-{diagonal}/non-dyadic", grid(12, 1.0, 63.0, "none", diagonal, rng), square(1.0, 63.0), False)
    for count in (8, 32, 64) if full else (8, 32):
        for where, centre in (("centre", np.array([31.5, 31.5])), ("corner", np.array([32.0, 32.0])),
                              ("random", rng.uniform(28, 36, 2))):
            tris, rim = fan(count, centre, 26.0, rng)
            add(f"fan-{count}/{where}", tris, rim, False)
    tris, rim = sliver_fan(24, np.array([31.5, 32.0]), 28.0, rng)
    add("sliver-fan-24/centre", tris, rim, False)
    tris, outline = strip(24, 20.25, 43.75, rng)
    add("strip-24/float", tris, outline, False)
    for lattice in (False, True):
        tris, hull = delaunay(80 if full else 40, rng, lattice)
        add(f"delaunay-{'lattice' if lattice else 'float'}", tris, hull, lattice)
    return cases
