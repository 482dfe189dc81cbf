"""Which rasterizers draw alike: the same pixels (samples, alphas) on the same scenes.

The atlas groups libraries that draw the same as each other (skia and tiny-skia aliased,
say): each rasterizer draws the quick suite's still scenes of every kind it takes, in a
worker process of its own, and two rasterizers of one coverage kind are compared on the
scenes both drew (a scene one of them failed on, or was not handed -- a fill rule it does
not honour -- is left out of that pair). Two draw alike on a kind when not one pixel differs
on any of at least :data:`FEWEST_SHARED` shared scenes; the groups are the connected sets of
such pairs, and every pair's differing pixels are kept, so that "nearest" is measured too.

What is compared, per pixel of a scene (the primitive that drew it is not: a library that
draws primitive 2's pixel for primitive 1 differs elsewhere):

* single-sample: how many primitives cover the pixel (:meth:`Coverage.counts`);
* multisample: that count for each sample (its layers);
* area: the sum of the primitives' alphas, in 8-bit steps (``round(255 alpha)``): the
  libraries return 8-bit alphas.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from itertools import combinations

import numpy as np
from numpy.typing import NDArray

from harness.contract.case import Case
from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer, coverage_kind_of, takes
from harness.contract.scenes import AnyScene
from harness.engine.isolation import InProcess, TimeLimit, Worker

__all__ = ["FEWEST_SHARED", "Pair", "Drawings", "draw_all", "pairs", "groups"]

FEWEST_SHARED = 5  # scenes two rasterizers must both have drawn to be called alike on a kind


@dataclass
class Drawings:
    """What one rasterizer drew: per case id its picture (:func:`picture`), the scene kind
    of each case, and the cases it gave no answer for (an error, a crash, a time-out)."""

    rasterizer: str
    coverage_kind: str
    pictures: dict[str, NDArray] = field(default_factory=dict)
    kinds: dict[str, str] = field(default_factory=dict)
    unanswered: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class Pair:
    """Two rasterizers of one coverage kind on one scene kind: the scenes both drew, the
    pixels (samples, 8-bit alphas) that differ there, and the pixels the first drew."""

    kind: str
    a: str
    b: str
    scenes: int
    differing: int
    pixels: int

    @property
    def alike(self) -> bool:
        return self.scenes >= FEWEST_SHARED and self.differing == 0


def picture(coverage: Coverage, scene: AnyScene, coverage_kind: str) -> NDArray:
    """The comparable picture of an answer: (H, W) counts, (S, H, W) per-sample counts or
    (H, W) 8-bit summed alphas (see the module docstring)."""
    w, h = scene.width, scene.height
    if coverage.alpha is not None:
        _, x, y = coverage.pixels()
        inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
        total = np.zeros((h, w))
        np.add.at(total, (y[inside], x[inside]), coverage.alpha[inside])
        return np.rint(255.0 * total).astype(np.int64)
    if coverage_kind == "multisample" and coverage.sample is not None:
        n = int(coverage.sample.max(initial=-1)) + 1
        return np.stack([coverage.layer(s).counts(w, h) for s in range(n)]) if n else np.zeros((0, h, w), np.int32)
    return coverage.counts(w, h)


def draw_all(rasterizer: Rasterizer, cases: Sequence[Case], timeout: float | TimeLimit = 60.0,
             isolate: bool = True) -> Drawings:
    """Every case ``rasterizer`` takes (:func:`harness.contract.protocol.takes`), drawn in a
    worker of its own (``isolate``)."""
    coverage_kind = coverage_kind_of(rasterizer)
    out = Drawings(rasterizer.name, coverage_kind)
    with Worker(rasterizer, timeout) if isolate else InProcess(rasterizer) as call:
        for case in cases:
            if not takes(rasterizer, case.scene):
                continue
            outcome = call(case.scene)
            if outcome.coverage is None:
                out.unanswered.append(case.id)
                continue
            out.pictures[case.id] = picture(outcome.coverage, case.scene, coverage_kind)
            out.kinds[case.id] = case.scene.kind
    return out


def pairs(drawings: Iterable[Drawings]) -> list[Pair]:
    """Every pair of rasterizers of one coverage kind, on each scene kind both drew."""
    out = []
    for a, b in combinations(list(drawings), 2):
        if a.coverage_kind != b.coverage_kind:
            continue
        shared = sorted(set(a.pictures) & set(b.pictures))
        for kind in sorted({a.kinds[c] for c in shared}):
            mine = [c for c in shared if a.kinds[c] == kind]
            differing = sum(int(np.count_nonzero(a.pictures[c] != b.pictures[c])) if a.pictures[c].shape == b.pictures[c].shape
                            else int(a.pictures[c].size) for c in mine)
            pixels = sum(int(np.count_nonzero(a.pictures[c])) for c in mine)
            out.append(Pair(kind, a.rasterizer, b.rasterizer, len(mine), differing, pixels))
    return out


def _root(parent: dict[str, str], x: str) -> str:
    """The representative of ``x``'s set (a set of its own when new)."""
    while parent.setdefault(x, x) != x:
        x = parent[x]
    return x


def groups(found: Iterable[Pair]) -> dict[str, list[list[str]]]:
    """Per scene kind, the sets of two or more rasterizers joined by pairs that draw alike
    (connected components), each sorted, the largest first.

    >>> groups([Pair("paths", "a", "b", 9, 0, 50), Pair("paths", "b", "c", 9, 0, 50), Pair("paths", "a", "d", 9, 3, 50)])
    {'paths': [['a', 'b', 'c']]}
    """
    out: dict[str, list[list[str]]] = {}
    by_kind: dict[str, list[Pair]] = {}
    for p in found:
        by_kind.setdefault(p.kind, []).append(p)
    for kind, kind_pairs in sorted(by_kind.items()):
        parent: dict[str, str] = {}
        for p in kind_pairs:
            if p.alike:
                parent[_root(parent, p.a)] = _root(parent, p.b)
        members: dict[str, list[str]] = {}
        for x in list(parent):
            members.setdefault(_root(parent, x), []).append(x)
        found_groups = sorted((sorted(m) for m in members.values() if len(m) > 1), key=lambda g: (-len(g), g))
        if found_groups:
            out[kind] = found_groups
    return out
