"""dEQP's reference rasterizer at 2, 4, 8 and 16 samples (:mod:`tests.peers.deqp`): the port
decides every sample as the original compiled from ``tests/peers/src/deqp`` does, identify
recovers each pattern exactly from outside (offsets, tie rule, half-away 8-bit snapping),
and the quick suite judges the port against what was identified without a false alarm.

The aliased lines (``SingleSampleLineRasterizer``) and multisample lines are ported and
checked alike; judged against GL's aliased-line rule, dEQP's lines show its corner bugs,
each found by conformance on one segment (:data:`DEQP_LINE_BUGS`), and nothing else.

``RASTERCHECK_PEER_SCENES=N`` sets the random scenes per pattern of the cross-checks (N
aliased-line scenes, N / 4 multisample-line scenes per pattern) and runs every check of
the quick suite on every pattern. Measured with N = 20,000: triangles 80,000 scenes,
83,930,017 covered samples, 0 differing; aliased lines 20,000 scenes, 935,023 pixels, 0
differing; multisample lines 20,000 scenes, 7,707,418 samples, 0 differing; the quick
suite clean at 2x, 4x, 8x and 16x.
"""

from __future__ import annotations

import ctypes
import functools
import os

import numpy as np
import pytest
from numpy.typing import NDArray

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene, Scene
from harness.oracle.lines import diamond_exit_spans
from tests.peers.compiled import SOURCES, load
from tests.peers.deqp import DeqpLines, DeqpMultisample, DeqpMultisampleLines, to_subpixel

PATTERNS = (2, 4, 8, 16)
LONG = int(os.environ.get("RASTERCHECK_PEER_SCENES", "0"))
SCENES = LONG or 150  # per pattern

# What rrRasterizer.cpp's sample tables become through its own toSubpixelCoord (float32:
# 0.3f * 256 = 76.8000031 -> 77, 0.7f * 256 = 179.199997 -> 179; the others are exact),
# in sample order; 8 subpixel bits, half away from zero, ties as initEdgeCCW's FILL_LEFT
# and FILL_BOTTOM give them in the harness's y-down screen: top-left.
DEQP_PATTERNS = {
    2: ((77 / 256, 77 / 256), (179 / 256, 179 / 256)),
    4: ((0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)),
    8: ((7 / 16, 9 / 16), (9 / 16, 13 / 16), (11 / 16, 3 / 16), (13 / 16, 11 / 16),
        (1 / 16, 7 / 16), (5 / 16, 1 / 16), (15 / 16, 5 / 16), (3 / 16, 15 / 16)),
    16: tuple(((2 * i + 1) / 8, (2 * j + 1) / 8) for j in range(4) for i in range(4)),
}


def expected_convention(samples: int) -> Convention:
    # vertices are tcu::Vec4 floats: the port receives float32, which identify recovers (issue 33)
    return Convention(samples=DEQP_PATTERNS[samples], tie="top-left", subpixel_bits=8, snap_rounding="half-away",
                      input="float32")


# -- the compiled original ---------------------------------------------------------------------


@functools.cache
def _original() -> ctypes.CDLL:
    folder = SOURCES / "deqp"
    library = load("deqp", [folder / "rrRasterizer.cpp", folder / "shim.cpp"], language="c++", flags=("-std=c++17",))
    pointer, size = ctypes.c_void_p, ctypes.c_int
    library.deqp_triangles.argtypes = [pointer, size, size, size, size, size, pointer, ctypes.c_int64]
    library.deqp_triangles.restype = ctypes.c_int64
    library.deqp_lines.argtypes = [pointer, size, size, size, size, ctypes.c_float, pointer, ctypes.c_int64]
    library.deqp_lines.restype = ctypes.c_int64
    library.deqp_lines_multisample.argtypes = [pointer, size, size, size, size, size, ctypes.c_float, pointer,
                                               ctypes.c_int64]
    library.deqp_lines_multisample.restype = ctypes.c_int64
    return library


def original_fragments(scene: Scene, samples: int) -> NDArray[np.int64]:
    """The compiled original's covered samples, as sorted keys (see :func:`keys`); the
    scene's positions go to it as float32, as a dEQP caller passes ``tcu::Vec4``."""
    library = _original()
    xy = np.ascontiguousarray(scene.positions.reshape(-1, 6), dtype=np.float32)
    capacity = 4096
    while True:
        out = np.zeros((capacity, 4), dtype=np.int32)
        n = library.deqp_triangles(xy.ctypes.data, len(scene), scene.width, scene.height, samples, 8,
                                   out.ctypes.data, capacity)
        if n <= capacity:
            break
        capacity = int(n)
    out = out[:n].astype(np.int64)
    bit = (out[:, 3:4] >> np.arange(samples)) & 1
    rows, sample = np.nonzero(bit)
    t, x, y = out[rows, 0], out[rows, 1], out[rows, 2]
    return np.sort(((t * samples + sample) * scene.height + y) * scene.width + x)


def keys(coverage: Coverage, scene: Scene | LineScene, samples: int) -> NDArray[np.int64]:
    """Each covered (triangle, sample, y, x) as one sorted int64 key."""
    parts = []
    for s in range(samples):
        t, x, y = coverage.layer(s).pixels()
        parts.append(((t * samples + s) * scene.height + y) * scene.width + x)
    return np.sort(np.concatenate(parts)) if parts else np.zeros(0, dtype=np.int64)


# -- random scenes with ties, huge and tiny triangles ------------------------------------------


def random_scene(rng: np.random.Generator) -> Scene:
    """A few triangles of one kind on a small screen: float32-exact floats; vertices on
    the 1/256 grid or at its half steps (snapping ties) or on coarse grids (samples exactly
    on edges); huge triangles (to 2**20 px); tiny ones; degenerate ones; float64 input;
    triangles on a screen reaching past 32,768 or 49,152 px, where float32 rounding moves
    odd 1/256 steps."""
    width, height = int(rng.integers(1, 40)), int(rng.integers(1, 40))
    n = int(rng.integers(1, 7))
    kind = int(rng.integers(0, 8))
    lo, hi = -4.0, max(width, height) + 4.0
    p = rng.uniform(lo, hi, (n, 3, 2))
    if kind == 0:  # the 1/256 grid
        p = np.round(p * 256) / 256
    elif kind == 1:  # half steps of the snapping grid: round half away
        p = np.round(p * 256) / 256 + rng.choice([-1, 1], p.shape) / 512
    elif kind == 2:  # coarse grids: samples (at k/16 or 77/256) exactly on edges
        step = float(rng.choice([1, 2, 4, 8, 16, 256]))
        p = np.round(p * step) / step
    elif kind == 3:  # huge: one or two vertices far away
        far = rng.choice([2.0**10, 2.0**15, 2.0**16, 2.0**20], p.shape) * rng.choice([-1, 1], p.shape)
        mask = rng.random(p.shape[:2]) < 0.5
        p = np.where(mask[:, :, None], np.round((p + far) * 256) / 256, p)
        p = np.clip(p, 1 / 256 - 2**20, 2**20 - 1 / 256)
        odd = np.floor(p * 128) / 128 + 1 / 256  # odd multiples of 1/256 (float32-exact below 65536)
        p = np.where(rng.random(p.shape) < 0.5, odd, p)
    elif kind == 4:  # tiny: within a pixel or two
        base = rng.uniform(lo, hi, (n, 1, 2))
        p = base + rng.uniform(-1, 1, (n, 3, 2)) * float(rng.choice([1 / 256, 1 / 32, 0.5, 2]))
        p = np.round(p * 1024) / 1024
    elif kind == 5:  # degenerate: collinear or repeated vertices
        p[:, 2] = p[:, 0] + (p[:, 1] - p[:, 0]) * rng.choice([0.0, 0.5, 1.0, 2.0], (n, 1))
        p = np.round(p * 256) / 256
    elif kind == 6:  # float64 input: the caller's conversion to float32 rounds it
        pass
    elif kind == 7:  # far from the origin: from 32,768 px float32 moves odd 1/256 steps by one
        far = 32768.0 + float(rng.integers(0, 2)) * 16384
        p = np.round(p * 256) / 256
        axis = int(rng.integers(0, 2))
        p[:, :, axis] += far
        width, height = (width + int(far), height) if axis == 0 else (width, height + int(far))
    if kind != 6:
        p = p.astype(np.float32).astype(np.float64)
    return Scene(width, height, p)


def differing(samples: int, scenes: int, seed: int, port: DeqpMultisample | None = None) -> tuple[int, int]:
    """(differing samples, samples compared) over ``scenes`` random scenes."""
    rng = np.random.default_rng(seed)
    port = port or DeqpMultisample(samples)
    diff = total = 0
    for _ in range(scenes):
        scene = random_scene(rng)
        want, got = original_fragments(scene, samples), keys(port.rasterize(scene), scene, samples)
        diff += int(np.setxor1d(want, got).size) + (want.size - np.unique(want).size) + (got.size - np.unique(got).size)
        total += int(want.size)
    return diff, total


@pytest.mark.parametrize("samples", PATTERNS)
def test_the_port_decides_every_sample_as_the_original(samples):
    diff, total = differing(samples, SCENES, seed=samples)
    assert total > 1000 and diff == 0, f"{diff} of {total} samples differ"


def test_the_single_sample_port_of_tests_ports_is_the_original_below_32768_px():
    """:class:`tests.ports.DeqpReference` (``rasterizeSingleSample``, exact half-away
    snapping of float64 input) equals the original wherever float32 arithmetic is exact:
    on float32 input below 32,768 px (beyond, the original's float32 ``v * 256 + 0.5``
    moves odd 1/256 steps, which that port does not do)."""
    from tests.ports import DeqpReference

    rng = np.random.default_rng(1)
    port = DeqpReference()
    diff = total = scenes = 0
    while scenes < SCENES // 4:
        scene = random_scene(rng)
        p = scene.positions
        if np.any(np.abs(p) >= 32768) or np.any(p != p.astype(np.float32)):
            continue
        scenes += 1
        t, x, y = port.rasterize(scene).pixels()
        got, want = np.sort((t * scene.height + y) * scene.width + x), original_fragments(scene, 1)
        diff += int(np.setxor1d(want, got).size)
        total += int(want.size)
    assert total > 1000 and diff == 0, f"{diff} of {total} pixels differ"


class ExactSnapping(DeqpMultisample):
    """Broken on purpose: snaps the float64 input half away from zero exactly, without
    dEQP's float32 conversion and float32 ``v * 256 + 0.5``."""

    def snap(self, positions: NDArray[np.float64]) -> NDArray[np.int64]:
        scaled = positions * 2.0**self.bits
        return np.trunc(scaled + np.where(scaled < 0, -0.5, 0.5)).astype(np.int64)


class MisreadTwoX(DeqpMultisample):
    """Broken on purpose: dEQP's 2x samples at 78/256 and 180/256 (0.3 and 0.7 rounded
    from float64, not float32), as identify once misread them."""

    def __init__(self) -> None:
        super().__init__(2)
        self.offsets = np.array([[78, 78], [180, 180]], dtype=np.int64)


@pytest.mark.parametrize("broken", [ExactSnapping(2), ExactSnapping(8), MisreadTwoX()],
                         ids=["exact-snapping-2x", "exact-snapping-8x", "2x-at-78-180"])
def test_the_cross_check_tells_a_port_that_is_off_by_one_step(broken):
    """The random scenes reach the places where the original's float32 arithmetic and
    sample tables matter: a port that gets either slightly wrong differs."""
    diff, _ = differing(broken.samples, 40, seed=7, port=broken)
    assert diff > 0


def test_to_subpixel_is_the_originals_float32_rounding():
    # half away from zero; float32's own rounding at 2**23 and just below 1/512
    values = np.array([1.5 / 256, -1.5 / 256, 2.5 / 256, (32768 * 256 + 1) / 256, np.float32(0.5 - 2**-25) / 256])
    assert to_subpixel(values, 8).tolist() == [2, -2, 3, 32768 * 256 + 2, 1]


# -- identify and the quick suite ---------------------------------------------------------------


@functools.cache
def _identified(samples: int):
    from harness.identify.fingerprint import identify

    port = DeqpMultisample(samples)
    return port, identify(port)


@pytest.mark.parametrize("samples", PATTERNS)
def test_identify_recovers_deqps_pattern_exactly(samples):
    _, fingerprint = _identified(samples)
    assert fingerprint.coverage_kind == "multisample"
    assert fingerprint.exact and fingerprint.convention == expected_convention(samples), fingerprint.card()
    assert DeqpMultisample(samples).offsets.tolist() == [[round(x * 256), round(y * 256)] for x, y in DEQP_PATTERNS[samples]]


@pytest.mark.parametrize("samples", PATTERNS if LONG else (2, 8))
def test_the_port_passes_the_quick_suite_as_identified(samples):
    """Conformance, where an identified convention could fail falsely at ties and half
    steps, on the two irregular patterns (2x at odd 1/256 steps, 8x); every check of the
    quick suite on every pattern in a long run (``RASTERCHECK_PEER_SCENES``; all pass)."""
    from harness import run_suite
    from harness.identify.fingerprint import Identified

    port, fingerprint = _identified(samples)
    only = None if LONG else {"conformance"}
    results = run_suite([Identified(port, fingerprint)], suite="quick", repros=False, only=only, isolate=False)
    bad = [f"{r.case} {r.check}: {r.message}" for r in results if r.status in ("fail", "error")]
    assert not bad, bad[:5]
    assert sum(r.check == "conformance" and r.status == "pass" for r in results) > 50


def test_dEQPs_float32_snapping_beyond_32768_px_is_found():
    """dEQP's one triangle bug: ``v * 256.0f + 0.5f`` in float32 rounds an odd multiple of
    1/256 at 32,768 px or more up by one step (the sum's half is not representable: ties
    to even). A left edge at 32768 + 77/256 px is snapped to 78/256, leaving out the 2x
    samples that lie on it (at 77/256), which its own convention (half away from zero)
    gives the triangle. Judged against its identified convention, conformance fails on
    exactly those samples; the same triangle one step to the left (an even step) passes."""
    from harness import run_suite
    from harness.contract.case import Case
    from harness.identify.fingerprint import Identified

    port, fingerprint = _identified(2)
    cases = [Case(f"far/{name}", Scene(32772, 4, [[[x, 0.0], [x, 4.0], [32771.0, 0.0]]]), lattice=True)
             for name, x in (("odd-step", 32768 + 77 / 256), ("even-step", 32768 + 76 / 256))]
    odd, even = run_suite([Identified(port, fingerprint)], cases=cases, only={"conformance"}, isolate=False,
                          repros=False)
    assert odd.status == "fail" and "sample 0 (0.300781, 0.300781): 4 missing, 0 extra" in odd.message, odd.message
    assert even.status == "pass", even.message


# -- aliased lines: SingleSampleLineRasterizer ------------------------------------------------------

GL_LINES = Convention(subpixel_bits=8, snap_rounding="half-away", line=LineRule("diamond-exit-gl", wide="replicate"))
"""What dEQP's line rasterizer means to draw: GL's aliased lines (OpenGL ES 3.2 13.7.2.1,
OpenGL 4.6 14.5.1), on its 8-bit subpixel grid, wide lines by replication."""


def original_line_pixels(scene: LineScene) -> NDArray[np.int64]:
    """The compiled original's fragments of a line scene as sorted keys (segment, y, x)."""
    library = _original()
    a, b = scene.segments()
    xy = np.ascontiguousarray(np.concatenate([a, b], axis=1), dtype=np.float32)
    capacity = 4096
    while True:
        out = np.zeros((capacity, 4), dtype=np.int32)
        n = library.deqp_lines(xy.ctypes.data, len(a), scene.width, scene.height, 8, scene.line_width,
                               out.ctypes.data, capacity)
        if n <= capacity:
            break
        capacity = int(n)
    t, x, y = (out[:n, k].astype(np.int64) for k in range(3))
    return np.sort((t * scene.height + y) * scene.width + x)


def line_keys(coverage: Coverage, scene: LineScene) -> NDArray[np.int64]:
    t, x, y = coverage.pixels()
    return np.sort((t * scene.height + y) * scene.width + x)


def random_line_scene(rng: np.random.Generator) -> LineScene:
    """Strips of a few segments: end points on the half-pixel lattice (centres, corners,
    diamond corners: every tie of the diamond test), on the 1/256 grid and its half steps,
    float32 floats, float64 floats, far out (to 2**14 px); widths 1, and 0.5 to 4 (dEQP
    replicates floor(w + 0.5) copies); zero-length segments."""
    width, height = int(rng.integers(1, 33)), int(rng.integers(1, 33))
    strips = []
    for _ in range(int(rng.integers(1, 5))):
        v = rng.uniform(-3, max(width, height) + 3, (int(rng.integers(2, 5)), 2))
        kind = int(rng.integers(0, 6))
        if kind == 0:
            v = np.round(v * 2) / 2
        elif kind == 1:
            v = np.round(v * 256) / 256
        elif kind == 2:
            v = np.round(v * 256) / 256 + rng.choice([-1, 1], v.shape) / 512
        elif kind == 3:
            v[int(rng.integers(0, len(v)))] = np.round(rng.uniform(-2.0**14, 2.0**14, 2) * 2) / 2
        elif kind == 4:
            v[1] = v[0]
        if kind != 5:
            v = v.astype(np.float32).astype(np.float64)
        strips.append(v)
    line_width = float(rng.choice([1.0, 1.0, 1.0, 0.5, 1.4, 2.0, 2.6, 3.0, 4.0]))
    return LineScene.from_strips(width, height, strips, line_width=line_width)


def differing_lines(scenes: int, seed: int, port) -> tuple[int, int]:
    rng = np.random.default_rng(seed)
    diff = total = 0
    for _ in range(scenes):
        scene = random_line_scene(rng)
        want, got = original_line_pixels(scene), line_keys(port.rasterize(scene), scene)
        diff += int(np.setxor1d(want, got).size) + (want.size - np.unique(want).size) + (got.size - np.unique(got).size)
        total += int(want.size)
    return diff, total


def test_the_line_port_draws_every_pixel_as_the_original():
    diff, total = differing_lines(SCENES, seed=29, port=DeqpLines())
    assert total > 1000 and diff == 0, f"{diff} of {total} pixels differ"


class GLRule:
    """Not dEQP: GL's own rule, exactly (:func:`harness.oracle.lines.diamond_exit_spans`), width 1."""

    def rasterize(self, scene: LineScene) -> Coverage:
        a, b = scene.segments()
        s, y, x0, x1 = diamond_exit_spans(GL_LINES.snap(a), GL_LINES.snap(b), scene.width, scene.height,
                                          rule="diamond-exit-gl")
        return Coverage(s, y, x0, x1)


def test_the_line_cross_check_tells_dEQP_from_GLs_rule():
    """The random scenes reach the ties where dEQP's corner rules part from GL's."""
    rng = np.random.default_rng(3)
    diff = 0
    for _ in range(40):
        scene = random_line_scene(rng)
        scene = LineScene(scene.width, scene.height, scene.vertices, scene.strip_sizes, 1.0)
        diff += int(np.setxor1d(original_line_pixels(scene), line_keys(GLRule().rasterize(scene), scene)).size)
    assert diff > 0


# dEQP's bugs against GL's rule, each a segment whose pixels follow from the source
# (LineRasterUtil::doesLineSegmentExitDiamond, window y taken as rows, the end points moved
# by -(eps, eps**2) as GL says):
DEQP_LINE_BUGS = {
    # the segment enters the diamond of (5, 4) through its right corner (6, 4.5) and ends at
    # its centre: GL omits the pixel (the end point lies in it); dEQP's corner rule
    # CORNER_EDGE_CASE_HIT counts any segment through the right corner as exiting
    "end pixel drawn right to left through a diamond corner": ([(8.5, 4.5), (5.5, 4.5)], {(5, 4)}, set()),
    # the same through the bottom corner (CORNER_EDGE_CASE_HIT_FIRST_QUARTER, dx * dy <= 0)
    "end pixel drawn upwards through a diamond corner": ([(9.5, 7.5), (9.5, 4.5)], {(9, 4)}, set()),
    # a segment running along a diamond's upper-right edge into its right corner: moved by
    # -(eps, eps**2) it runs inside and ends inside, so GL omits the pixel; dEQP draws it
    # (through the top corner, CORNER_EDGE_CASE_HIT_SECOND_QUARTER)
    "end pixel drawn along a diamond edge": ([(5.5, 6.0), (8.0, 8.5)], {(7, 8)}, set()),
    # ending on a top corner (5.5, 5.0) coming from below right: moved, the segment crosses
    # the diamond of (5, 5) and its end lies outside, so GL draws it; dEQP's end rule for
    # that corner (CORNER_END_CASE_DIRECTION_AND_SECOND_QUARTER) takes dx > 0, dy > 0, the
    # opposite quarter: it omits this one ...
    "top-corner end rule mirrored (pixel omitted)": ([(9.5, 7.5), (5.5, 5.0)], set(), {(5, 5)}),
    # ... and draws (7, 6) for a segment from above left ending on its top corner (7.5, 6),
    # which moved stays above the diamond
    "top-corner end rule mirrored (pixel drawn)": ([(5.5, 4.5), (7.5, 6.0)], {(7, 6)}, set()),
    # ending on a bottom corner, right to left and horizontal: moved, the segment runs just
    # inside the diamond of (4, 6) and ends outside it, so GL draws it; dEQP's end rule
    # (CORNER_END_CASE_DIRECTION_AND_FIRST_QUARTER) wants dy > 0, not dy >= 0
    "bottom-corner end rule misses horizontal lines": ([(6.5, 7.0), (4.5, 7.0)], set(), {(4, 6)}),
}


@pytest.mark.parametrize("bug", sorted(DEQP_LINE_BUGS))
def test_dEQPs_line_bugs_are_found_by_conformance(bug):
    """Each bug: the compiled original draws (omits) the pixel, the port too, GL's rule
    does not (does), and the harness's conformance check, judging the port against GL's
    aliased-line convention, fails on that pixel -- while GL's own drawer
    (:class:`tests.gl_lines.GLDiamondLines`) passes the same case."""
    from harness import run_suite
    from harness.contract.case import Case
    from tests.gl_lines import GLDiamondLines

    segment, extra, missing = DEQP_LINE_BUGS[bug]
    scene = LineScene.from_strips(16, 12, [segment])
    original = {(int(k % 16), int(k // 16)) for k in original_line_pixels(scene)}
    gl = {(int(x), int(y)) for _, x, y in zip(*GLRule().rasterize(scene).pixels())}
    assert original - gl == extra and gl - original == missing, (sorted(original), sorted(gl))
    assert set(zip(*(a.tolist() for a in DeqpLines().rasterize(scene).pixels()[1:]))) == original

    case = Case(f"deqp/{bug}", scene, lattice=True)
    judged = DeclaredGL()
    results = run_suite([judged, GLDiamondLines()], cases=[case], only={"conformance"}, isolate=False, repros=False)
    verdict = {r.rasterizer: r for r in results}
    said = verdict[judged.name].message
    assert verdict[judged.name].status == "fail" and f"{len(missing)} missing, {len(extra)} extra" in said, said
    assert verdict["gl_diamond_lines"].status == "pass"


class DeclaredGL(DeqpLines):
    """dEQP's line rasterizer declaring the convention it means to follow: GL's."""

    name = "deqp_lines_as_gl"
    convention = GL_LINES


def test_identify_makes_no_exact_claim_for_dEQPs_lines():
    """No line rule explains dEQP's corner bugs: identify's nearest is GL's rule, as a best
    guess with its residual, never an exact convention."""
    from harness.identify.fingerprint import identify

    fingerprint = identify(DeqpLines())
    line = fingerprint.facts["lines"]
    assert not fingerprint.exact and "GL diamond-exit" in line and "best guess" in line, fingerprint.card()


# -- multisample lines: MultiSampleLineRasterizer -----------------------------------------------------


def original_multisample_line_fragments(scene: LineScene, samples: int) -> NDArray[np.int64]:
    """The compiled original's covered samples of a line scene, as sorted keys (:func:`keys`)."""
    library = _original()
    a, b = scene.segments()
    xy = np.ascontiguousarray(np.concatenate([a, b], axis=1), dtype=np.float32)
    capacity = 4096
    while True:
        out = np.zeros((capacity, 4), dtype=np.int32)
        n = library.deqp_lines_multisample(xy.ctypes.data, len(a), scene.width, scene.height, samples, 8,
                                           scene.line_width, out.ctypes.data, capacity)
        if n <= capacity:
            break
        capacity = int(n)
    out = out[:n].astype(np.int64)
    rows, sample = np.nonzero((out[:, 3:4] >> np.arange(samples)) & 1)
    t, x, y = out[rows, 0], out[rows, 1], out[rows, 2]
    return np.sort(((t * samples + sample) * scene.height + y) * scene.width + x)


@pytest.mark.parametrize("samples", PATTERNS)
def test_the_multisample_line_port_decides_every_sample_as_the_original(samples):
    """Zero-length segments left out: the original divides by their zero length (NaN corners)."""
    rng = np.random.default_rng(100 + samples)
    port = DeqpMultisampleLines(samples)
    diff = total = scenes = 0
    while scenes < SCENES // 4:
        scene = random_line_scene(rng)
        a, b = scene.segments()
        if np.any(np.all(a.astype(np.float32) == b.astype(np.float32), axis=1)):
            continue
        scenes += 1
        want, got = original_multisample_line_fragments(scene, samples), keys(port.rasterize(scene), scene, samples)
        diff += int(np.setxor1d(want, got).size) + (want.size - np.unique(want).size) + (got.size - np.unique(got).size)
        total += int(want.size)
    assert total > 1000 and diff == 0, f"{diff} of {total} samples differ"


def multisample_lines_as_gl(samples: int) -> DeqpMultisampleLines:
    """dEQP's multisample lines declaring what they mean to draw: GL's multisample lines
    (OpenGL ES 3.2 13.7.4, OpenGL 4.6 14.5.4), the samples inside the rectangle, under
    dEQP's pattern and tie rule, end points on its 8-bit grid."""
    port = DeqpMultisampleLines(samples)
    port.convention = Convention(samples=DEQP_PATTERNS[samples], subpixel_bits=8, snap_rounding="half-away",
                                 line=LineRule("rectangle"))
    port.name += "_as_gl"
    return port


def test_dEQPs_multisample_lines_are_gls_rectangles_where_float32_is_exact():
    """Axis-aligned lines on a lattice (the float32 normal exactly (0, +-1) or (+-1, 0), the
    corners exact) pass conformance against GL's rectangles at every pattern; a slanted
    one fails at a few samples next to its long sides: dEQP computes the corners in
    float32 and snaps each to 1/256 px, moving the sides by up to ~1/362 px (not a rule
    any convention expresses)."""
    from harness import run_suite
    from harness.contract.case import Case

    rng = np.random.default_rng(0)
    cases = []
    for line_width in (1.0, 2.0, 2.5, 0.5):
        starts = np.round(rng.uniform(-2, 26, (24, 2)) * 4) / 4
        lengths = np.round(rng.uniform(-20, 20, 24) * 4) / 4
        moves = np.where(np.arange(24)[:, None] % 2 == 0, [[1.0, 0.0]], [[0.0, 1.0]]) * lengths[:, None]
        strips = [[a, a + d] for a, d in zip(starts, moves) if np.any(d != 0)]
        cases.append(Case(f"axis-aligned/{line_width}", LineScene.from_strips(24, 24, strips, line_width=line_width),
                          lattice=True))
    for samples in PATTERNS:
        results = run_suite([multisample_lines_as_gl(samples)], cases=cases, only={"conformance"}, isolate=False,
                            repros=False)
        assert len(results) == len(cases) and all(r.status == "pass" for r in results), [r.message for r in results]
    slanted = Case("slanted", LineScene.from_strips(24, 24, [[(1.5, 1.5), (20.0, 9.0)]]), lattice=True)
    result, = run_suite([multisample_lines_as_gl(4)], cases=[slanted], only={"conformance"}, isolate=False, repros=False)
    assert result.status == "fail" and "sample 2 (0.25, 0.75): 0 missing, 2 extra" in result.message, result.message


def test_dEQPs_lines_part_from_GLs_rule_only_at_diamond_corners_on_the_segment():
    """On every 1-px line case of the quick suite, each pixel drawn by one of dEQP and GL's
    rule alone has a corner of its diamond lying on the (snapped) segment: the corner
    rules above are the whole difference -- no other tie, no rounding."""
    from cases.suites import suite

    corners = np.array([[0, -1], [-1, 0], [0, 1], [1, 0]]) * 128
    differing = 0
    for case in suite("quick"):
        scene = getattr(case, "scene", None)
        if not isinstance(scene, LineScene) or scene.line_width != 1.0:
            continue
        try:
            ours = DeqpLines().rasterize(scene)
        except ValueError:  # beyond 2**14 px: refused
            continue
        mine, gl = (set(zip(*(v.tolist() for v in c.pixels()))) for c in (ours, GLRule().rasterize(scene)))
        a, b = scene.segments()
        for t, x, y in mine ^ gl:
            start, end = to_subpixel(a[t], 8), to_subpixel(b[t], 8)
            d = end - start
            p = np.array([x * 256 + 128, y * 256 + 128]) + corners
            on_line = d[0] * (p[:, 1] - start[1]) - d[1] * (p[:, 0] - start[0]) == 0
            within = ((p - start) @ d >= 0) & ((p - end) @ d <= 0)
            assert np.any(on_line & within), (case.id, t, x, y, a[t].tolist(), b[t].tolist())
            differing += 1
    assert differing > 20
