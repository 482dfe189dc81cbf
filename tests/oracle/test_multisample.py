"""The fused multisample oracle (harness.oracle.multisample) against the former one, the
single-sample oracle once per offset (harness.oracle.coverage.*_layers): bit for bit, on
random scenes, lattice and tie scenes, huge, far and tiny coordinates, degenerate and
non-finite triangles, every standard and custom pattern, every tie rule, snapping, culling
and input precision, and hypothesis scenes."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from cases.strategies import conventions, float_scenes, grid_scenes, lattice_scenes, thin_scenes
from harness.contract.conventions import CULL_MODES, SNAP_ROUNDINGS, TIE_RULES, Convention
from harness.contract.coverage import Coverage
from harness.contract.samples import STANDARD_PATTERNS, pattern
from harness.contract.scenes import Scene
from harness.oracle import multisample
from harness.oracle.coverage import (
    RECENT_ANSWERS,
    exact_multisample,
    exact_multisample_layers,
    exact_samples,
    exact_samples_layers,
    prepare_triangles,
    sample_shares,
    sample_shares_layers,
)
from harness.oracle.multisample import fused_shares, multisample_spans

FIELDS = ("primitive", "y", "x0", "x1", "sample", "alpha", "attributes")


def identical(new: Coverage, old: Coverage) -> None:
    """Every array of the two coverages the same, bit for bit (NaN attributes too)."""
    for field in FIELDS:
        a, b = getattr(new, field), getattr(old, field)
        assert (a is None) == (b is None), field
        if a is not None:
            assert a.dtype == b.dtype and a.shape == b.shape, field
            assert np.ascontiguousarray(a).tobytes() == np.ascontiguousarray(b).tobytes(), field


def agree(scene: Scene, convention: Convention, samples: Any = 4) -> None:
    """exact_multisample, exact_samples and sample_shares equal to the former path."""
    offsets = pattern(samples)
    single = Convention(**{**_fields(convention), "samples": None, "coverage": "sample"})
    with RECENT_ANSWERS.off():  # each answer computed, none looked up
        if len(offsets) <= 32:
            multi = Convention(**{**_fields(convention), "samples": offsets, "coverage": "sample"})
            identical(exact_multisample(scene, multi), exact_multisample_layers(scene, multi))
        new_layers = exact_samples(scene, single, offsets)
        old_layers = exact_samples_layers(scene, single, offsets)
        assert len(new_layers) == len(old_layers) == len(offsets)
        for new, old in zip(new_layers, old_layers, strict=True):
            identical(new, old)
        area = Convention(**{**_fields(convention), "samples": offsets, "coverage": "area"})
        identical(sample_shares(scene, area), sample_shares_layers(scene, area))


def _fields(convention: Convention) -> dict[str, Any]:
    return {"tie": convention.tie, "subpixel_bits": convention.subpixel_bits, "snap_rounding": convention.snap_rounding,
            "cull": convention.cull, "input": convention.input, "sample": convention.sample}


def random_triangles(n: int, size: int, area: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    centre = rng.uniform(-4, size + 4, size=(n, 1, 2))
    return centre + rng.normal(0.0, np.sqrt(area), size=(n, 3, 2))


# -- random scenes ------------------------------------------------------------------------


@pytest.mark.parametrize("samples", sorted(STANDARD_PATTERNS))
@pytest.mark.parametrize("area", [2.0, 50.0, 5000.0])
def test_random_scenes_every_standard_pattern(samples, area):
    scene = Scene(96, 80, random_triangles(300, 90, area, int(area) + samples))
    agree(scene, Convention(), samples)


def test_random_scenes_with_attributes_and_w():
    rng = np.random.default_rng(7)
    positions = random_triangles(200, 64, 40.0, 7)
    attributes = rng.normal(size=(200, 3, 3))
    w = rng.uniform(0.1, 4.0, size=(200, 3))
    for scene in (Scene(64, 64, positions, attributes), Scene(64, 64, positions, attributes, w)):
        for samples in (2, 4, 8, 16):
            agree(scene, Convention(), samples)
        agree(scene, Convention(tie="bottom-right", cull="cw"), 8)


def test_the_fused_path_answers_safe_scenes():
    """Inside the expansions' safe range the fused kernel answers (no per-sample detour)."""
    scene = Scene(32, 32, random_triangles(50, 32, 30.0, 3))
    prepared = prepare_triangles(scene, Convention())
    assert multisample_spans(scene, prepared, pattern(8)) is not None
    assert fused_shares(scene, prepared, pattern(8), 8) is not None
    far = Scene(32, 32, np.concatenate([scene.positions, [[[0, 0], [2.0**460, 0], [0, 4]]]]))
    assert multisample_spans(far, prepare_triangles(far, Convention()), pattern(8)) is None


# -- ties: lattices, edges through samples, vertices on samples ------------------------------


@pytest.mark.parametrize("tie", TIE_RULES)
@pytest.mark.parametrize("samples", [1, 2, 4, 8, 16])
def test_lattice_of_sixteenths_every_tie_rule(tie, samples):
    """Vertices on the 1/16 lattice of the standard patterns: edges run through sample
    points and vertices sit on them, in every pattern, under every tie rule."""
    rng = np.random.default_rng(samples)
    positions = rng.integers(-16, 16 * 18, size=(150, 3, 2)) / 16.0
    agree(Scene(16, 16, positions), Convention(tie=tie), samples)


@pytest.mark.parametrize("tie", TIE_RULES)
@pytest.mark.parametrize("samples", [4, 8, 16])
def test_ties_between_vertex_rows_are_settled_after_the_rows_loop(tie, samples):
    """Vertices off the sample lattice (y on odd 1/32nds: no sample row meets one) whose
    edges run through the pattern's first sample point in rows between them (slopes 2 and
    -2): those rows take the rows' loop, which leaves them unsure, and are settled
    exactly after it (multisample._settle_spans), ties and all, as the former path."""
    sx, sy = pattern(samples)[0]
    x, y = 10 + sx, 5 + sy  # a sample point both long edges run through
    tris = [[[x - 8 - 1 / 16, y - 4 - 1 / 32], [x + 24 + 1 / 16, y + 12 + 1 / 32], [-6.0, 9 + 3 / 32]],
            [[x + 8 + 1 / 16, y - 4 - 1 / 32], [x - 24 - 1 / 16, y + 12 + 1 / 32], [30.0, 11 + 5 / 32]]]
    scene = Scene(48, 32, tris)
    prepared = prepare_triangles(scene, Convention(tie=tie))
    offsets = multisample._offsets(pattern(samples))
    capacity = int(multisample._sample_rows(prepared.snapped, prepared.active, offsets, scene.height))
    block = np.empty((5, capacity), dtype=np.int64)
    _, unsure = multisample._multisample_kernel(prepared.snapped, prepared.sign, prepared.owned, prepared.active,
                                                offsets, scene.width, scene.height, *block)
    assert unsure > 0  # the settling is exercised
    agree(scene, Convention(tie=tie), samples)


@pytest.mark.parametrize("tie", TIE_RULES)
def test_vertices_on_samples_and_shared_edges(tie):
    # a mesh of squares split both ways whose vertices are the samples of the 4x pattern
    offsets = pattern(4)
    tris = []
    for i in range(6):
        for j in range(6):
            sx, sy = offsets[(i + j) % 4]
            a, b, c, d = (i + sx, j + sy), (i + 1 + sx, j + sy), (i + 1 + sx, j + 1 + sy), (i + sx, j + 1 + sy)
            tris += [[a, b, c], [a, c, d]] if (i + j) % 2 else [[a, b, d], [b, c, d]]
    scene = Scene(8, 8, tris)
    for samples in (4, 8, offsets):
        agree(scene, Convention(tie=tie), samples)


def test_horizontal_and_vertical_edges_on_sample_rows():
    s = pattern(8)
    tris: list[list[list[float]]] = [[[0, s[k][1] + 1], [6, s[k][1] + 1], [3, 5]] for k in range(8)]
    tris += [[[s[k][0] + 1, 0], [s[k][0] + 1, 6], [5, 3]] for k in range(8)]
    tris += [[[5, 3], [s[k][0] + 1, 6], [s[k][0] + 1, 0]] for k in range(8)]  # the other winding
    for tie in TIE_RULES:
        agree(Scene(8, 8, tris), Convention(tie=tie), 8)


# -- custom patterns -------------------------------------------------------------------------


@pytest.mark.parametrize("offsets", [
    [(0.5, 0.5)],
    [(0.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.5, 0.5)],
    [(0.75, 0.75), (0.25, 0.25)],  # out of order
    [(k / 8, k / 8) for k in range(8)],  # one sample row per offset
    [(k / 8, 0.5) for k in range(8)],  # eight samples on one sample row
    [((k % 4) / 4 + 1 / 8, (k // 4) / 4 + 1 / 8) for k in range(16)],
    [(0.0, 0.999755859375), (2.0**-32, 0.5)],
])
def test_custom_patterns(offsets):
    rng = np.random.default_rng(len(offsets))
    lattice = rng.integers(-8, 8 * 14, size=(120, 3, 2)) / 8.0
    floats = random_triangles(120, 12, 6.0, len(offsets))
    for positions in (lattice, floats):
        for tie in ("top-left", "bottom-right", "top-right"):
            agree(Scene(12, 12, positions), Convention(tie=tie), offsets)


@pytest.mark.parametrize("room", [1, 7, 1000])
def test_supersampled_shares_grow_their_buffers(monkeypatch, room):
    """Room for few pixels at first: the kernel stops before a triangle that does not fit
    and goes on in larger buffers, with the same answer."""
    monkeypatch.setattr(multisample, "FIRST_ROOM", room)
    rng = np.random.default_rng(room)
    start = rng.uniform(0, 20, size=(30, 2))
    slivers = np.stack([start, start + 200, start + [200.0, 202.5]], axis=1)  # long diagonal slivers
    scene = Scene(256, 256, np.concatenate([slivers, random_triangles(100, 256, 300.0, room)]))
    for samples in (4, 16):
        agree(scene, Convention(), samples)


def test_supersampled_shares_of_a_large_grid_pattern():
    grid = [((i + 0.5) / 16, (j + 0.5) / 16) for j in range(16) for i in range(16)]
    scene = Scene(24, 24, random_triangles(60, 24, 20.0, 11))
    agree(scene, Convention(), grid)


# -- snapping, culling, input precision ------------------------------------------------------


@pytest.mark.parametrize("rounding", SNAP_ROUNDINGS)
@pytest.mark.parametrize("bits", [0, 1, 4, 8])
def test_snapping(bits, rounding):
    scene = Scene(40, 40, random_triangles(200, 40, 12.0, bits))
    agree(scene, Convention(subpixel_bits=bits, snap_rounding=rounding), 8)


@pytest.mark.parametrize("cull", CULL_MODES)
def test_culling(cull):
    scene = Scene(40, 40, random_triangles(200, 40, 12.0, 5))
    agree(scene, Convention(cull=cull), 4)


@pytest.mark.parametrize("received", ["float32", "fixed6", "fixed4-floor", "integer", "integer-toward-zero"])
def test_input_precision(received):
    scene = Scene(40, 40, random_triangles(200, 40, 12.0, 9))
    agree(scene, Convention(input=received, subpixel_bits=4), 8)


# -- magnitudes, degenerate and non-finite triangles -----------------------------------------


@pytest.mark.parametrize("scale", [1e3, 1e6, 1e12, 1e15, 2.0**400, 2.0**460, 1e300])
def test_huge_and_far_coordinates(scale):
    """Triangles reaching far beyond the viewport (clipped), and triangles wholly far
    away; beyond the safe range (2**450) the per-sample rational path decides."""
    rng = np.random.default_rng(int(np.log2(scale)))
    near = rng.uniform(0, 16, size=(20, 3, 2))
    near[:, 0] = rng.choice([-1.0, 1.0], size=(20, 2)) * scale * rng.uniform(0.5, 1, size=(20, 2))
    far = rng.uniform(-1, 1, size=(10, 3, 2)) * scale
    sliver = np.array([[[-scale, 8.0 + 2.0**-10], [scale, 8.0], [scale, 8.0 + 1.0]]])
    for positions in (near, far, sliver, np.concatenate([near, far, sliver])):
        for tie in ("top-left", "bottom-left"):
            agree(Scene(16, 16, positions), Convention(tie=tie), 8)


@pytest.mark.parametrize("tiny", [1e-300, 2.0**-460, 5e-324, 1e-12])
def test_tiny_coordinates(tiny):
    positions = np.array([[[0.0, 0.0], [tiny, 0.0], [0.0, tiny]],
                          [[0.5 - tiny, 0.5], [3.5, 0.5 + tiny], [0.5, 3.5]],
                          [[0.0, 0.0], [4.0, tiny], [0.0, 4.0]]])
    agree(Scene(6, 6, positions), Convention(), 8)


def test_degenerate_and_non_finite_triangles():
    nan, inf = np.nan, np.inf
    positions = np.array([
        [[0, 0], [4, 4], [8, 8]],  # collinear
        [[2, 2], [2, 2], [2, 2]],  # a point
        [[1, 1], [5, 1], [1, 1]],  # a repeated vertex
        [[0, 0], [nan, 3], [3, 0]],
        [[0, 0], [inf, 3], [3, 0]],
        [[-inf, 0], [inf, 3], [3, 0]],
        [[0.5, 0.5], [6.5, 0.5], [0.5, 6.5]],  # a good one among them
    ], dtype=np.float64)
    for tie in TIE_RULES:
        agree(Scene(8, 8, positions), Convention(tie=tie), 8)
    agree(Scene(8, 8, positions[:6]), Convention(), 4)  # nothing covered at all


def test_empty_scene():
    agree(Scene(8, 8, np.zeros((0, 3, 2))), Convention(), 4)


# -- hypothesis ------------------------------------------------------------------------------

patterns = st.one_of(
    st.sampled_from(sorted(STANDARD_PATTERNS)),
    st.lists(st.tuples(*[st.integers(0, 15).map(lambda k: k / 16)] * 2), min_size=1, max_size=12, unique=True),
)


@given(lattice_scenes(max_bits=4), conventions(), patterns)
@example(Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]]), Convention(), 4)
@example(Scene(2, 2, [[[0, 0], [2, 0], [0, 2]]]), Convention(tie="bottom-right"), 8)
def test_hypothesis_lattice_scenes(scene, convention, samples):
    agree(scene, convention, samples)


@given(float_scenes(), conventions(), patterns)
def test_hypothesis_float_scenes(scene, convention, samples):
    agree(scene, convention, samples)


@given(thin_scenes(), st.sampled_from(TIE_RULES), patterns)
def test_hypothesis_thin_scenes(scene, tie, samples):
    agree(scene, Convention(tie=tie), samples)


@given(grid_scenes(), st.sampled_from(TIE_RULES), st.sampled_from(sorted(STANDARD_PATTERNS)))
@settings(max_examples=30)
def test_hypothesis_shared_edges(case, tie, samples):
    agree(case.scene, Convention(tie=tie), samples)
