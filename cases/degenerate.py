"""The degenerate and epsilon catalogue: zero areas, near-zero heights and widths, slivers,
vertices on samples, huge and negative coordinates, off-screen and non-finite triangles.

Each scene also holds ordinary triangles, so a rasterizer that mishandles one bad
triangle cannot hide it by drawing nothing at all.
"""

from __future__ import annotations

import numpy as np

from harness.contract.case import Case
from harness.contract.scenes import Scene

__all__ = ["degenerate_cases", "probe_scenes", "epsilon_scene"]

SIZE = 32
ULP = np.spacing(10.5)
BIG = np.finfo(np.float64).max

# Two ordinary triangles that every degenerate scene carries (indices 0 and 1).
_ANCHORS = np.array([[[1.25, 1.25], [9.75, 2.5], [3.5, 9.0]], [[22.0, 22.0], [30.0, 23.5], [24.5, 30.5]]])


def _scene(*triangles) -> Scene:  # type: ignore[no-untyped-def]
    return Scene(SIZE, SIZE, np.concatenate([_ANCHORS, np.array(triangles, dtype=float).reshape(-1, 3, 2)]))


def epsilon_scene(sample: tuple[float, float] = (0.5, 0.5)) -> Scene:
    """identify's epsilon probe (:func:`harness.identify.triangle_defects.epsilon`): 56 tiny triangles (1e-3
    down to 1e-9 px across, eight of each size) around the sample points at ``sample`` of
    a row of pixels, the even ones holding their sample strictly inside, the odd ones
    just to the right of it."""
    sx, sy = sample
    triangles = []
    for k, size in enumerate(np.repeat(10.0 ** -np.arange(3, 10), 8)):
        x, y = 4.0 + (k % 12) * 4.0 + sx, 4.0 + (k // 12) * 4.0 + sy
        shift = 0.0 if k % 2 == 0 else 2.0 * size  # odd ones sit just to the right of the sample
        triangles.append([[x - size + shift, y - size], [x + size + shift, y - size], [x + shift, y + size]])
    return Scene(56, 32, np.array(triangles))


def probe_scenes() -> dict[str, tuple[Scene, bool]]:
    """The scenes of identify's degenerate probes (:func:`harness.identify.triangle_defects.zero_area`,
    :func:`harness.identify.triangle_defects.non_finite`), as the suite holds them: ``degenerate/<name>`` ->
    (scene, lattice). A collinear triangle and one with two equal vertices; a triangle with
    a NaN (an infinite) coordinate beside a finite one; the epsilon probe's tiny triangles
    around pixel centres (:func:`epsilon_scene`)."""
    nan, inf = np.nan, np.inf
    finite = [[4.5, 4.5], [20.5, 4.5], [4.5, 20.5]]
    return {"zero-area/probe": (Scene(SIZE, SIZE, np.array([[[4.5, 4.5], [12.5, 12.5], [20.5, 20.5]], [[8, 8], [8, 8], [20, 14]]],
                                                          dtype=np.float64)), True),
            "non-finite/probe-nan": (Scene(SIZE, SIZE, np.array([[[nan, 4], [10, 10], [4, 20]], finite])), False),
            "non-finite/probe-inf": (Scene(SIZE, SIZE, np.array([[[inf, 4], [10, 10], [4, 20]], finite])), False),
            "epsilon/probe": (epsilon_scene(), False)}


def degenerate_cases(seed: int, full: bool = False) -> list[Case]:
    """``degenerate/<kind>/<detail>``."""
    rng = np.random.default_rng(seed)
    cases: list[Case] = []

    def add(name: str, scene: Scene, lattice: bool = False, refusable: tuple[int, ...] = (), region: np.ndarray | None = None) -> None:
        cases.append(Case(f"degenerate/{name}", scene, lattice=lattice, refusable=refusable, region=region))

    # zero area: nothing, always
    add("zero-area/collinear", _scene([[4.5, 4.5], [12.5, 12.5], [20.5, 20.5]], [[3, 20], [20, 3], [11.5, 11.5]]), lattice=True)
    add("zero-area/repeated-vertex", _scene([[4.5, 4.5], [4.5, 4.5], [20.5, 14.5]], [[10, 10], [20, 10], [20, 10]]), lattice=True)
    add("zero-area/single-point", _scene([[15.5, 15.5]] * 3, [[16, 16]] * 3), lattice=True)
    add("zero-area/horizontal-line", _scene([[2.5, 15.5], [12.5, 15.5], [28.5, 15.5]], [[2, 16], [30, 16], [9, 16]]), lattice=True)
    add("zero-area/vertical-line", _scene([[15.5, 2.5], [15.5, 12.5], [15.5, 28.5]], [[16, 2], [16, 30], [16, 9]]), lattice=True)
    # epsilon heights and widths: a long edge through sample points, the third vertex a
    # tiny step off it, on either side
    for label, eps in (("1e-8", 1e-8), ("1e-12", 1e-12), ("1ulp", ULP)):
        for side in (1, -1):
            tag = "below" if side > 0 else "above"
            add(f"epsilon/height-{label}-{tag}", _scene([[2.5, 10.5], [29.5, 10.5], [16.0, 10.5 + side * eps]]))
            add(f"epsilon/width-{label}-{tag}", _scene([[10.5, 2.5], [10.5, 29.5], [10.5 + side * eps, 16.0]]))
    add("epsilon/diagonal-1e-12", _scene([[2.5, 2.5], [29.5, 29.5], [16.0 + 1e-12, 16.0 - 1e-12]]))
    # slivers and samples on vertices
    slivers = [[[rng.uniform(1, 31), rng.uniform(1, 31)]] * 3 for _ in range(12)]
    for s in slivers:
        s[1] = [s[0][0] + rng.uniform(-20, 20), s[0][1] + rng.uniform(-20, 20)]
        s[2] = [s[0][0] + (s[1][0] - s[0][0]) * 0.5 + 1e-3, s[0][1] + (s[1][1] - s[0][1]) * 0.5]
    add("sliver/random-12", _scene(*slivers))
    on_samples = np.floor(rng.uniform(1, 31, size=(12, 3, 2))) + 0.5
    add("on-samples/centres-12", _scene(*on_samples), lattice=True)
    add("on-samples/corners-12", _scene(*np.floor(rng.uniform(1, 31, size=(12, 3, 2)))), lattice=True)
    # huge coordinates: screen-covering pairs, and a sliver from far away
    for label, big in (("1e6", 1e6), ("1e9", 1e9), ("1e30", 1e30), ("max-float", BIG)):
        pair = [[[-big, -big], [big, -big], [-big, big]], [[big, -big], [big, big], [-big, big]]]
        scene = Scene(SIZE, SIZE, np.array(pair, dtype=float))
        # the pair tiles the square of side 2*big: a partition, so watertight checks it too
        square = np.array([[-big, -big], [big, -big], [big, big], [-big, big]])
        add(f"huge/cover-{label}", scene, refusable=(0, 1), region=square)
        add(f"huge/sliver-{label}", _scene([[-big, 14.25], [big, 17.75], [16.5, 16.0]]), refusable=(2,))
        # a wedge from two far vertices to one on screen: a whole band of pixels to draw
        add(f"huge/wedge-{label}", _scene([[-big, 6.25], [big, 9.75], [16.5, 27.0]]), refusable=(2,))
    # off-screen and negative coordinates
    add("offscreen/partly", _scene([[-10.5, -4.25], [20.0, 5.5], [6.5, 40.75]], [[25.0, 10.0], [50.0, 14.0], [28.0, 60.0]]))
    add("offscreen/fully", _scene([[-40, -40], [-10, -35], [-30, -5]], [[40, 40], [60, 45], [50, 70]], [[5, -20], [25, -20], [15, -1]]))
    add("offscreen/negative", _scene([[-3.5, -3.5], [12.5, -1.5], [-2.5, 14.5]]), lattice=True)
    # non-finite triangles among finite ones: nothing from them, the rest still right
    nan, inf = np.nan, np.inf
    add("non-finite/mixed", _scene([[nan, 4], [10, 10], [4, 20]], [[4, 4], [inf, 10], [4, 20]], [[4, 4], [10, 10], [4, -inf]],
                                    [[nan, nan], [nan, nan], [nan, nan]], [[12.5, 12.5], [20.5, 12.5], [12.5, 20.5]]))
    # identify's own probe scenes: run fails where its card says they are drawn wrongly
    for name, (scene, lattice) in probe_scenes().items():
        add(name, scene, lattice=lattice)
    return cases
