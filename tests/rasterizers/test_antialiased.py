"""Issue 14's reference rasterizers against the oracles of their declared conventions:
multisample Pineda (exact per sample), the signed-area scanline (within its declared
tolerance of the exact area) and the n x n supersampler (the exact share of samples)."""

import tomllib
from fractions import Fraction
from functools import cache
from importlib import import_module
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings

from cases.strategies import float_scenes, lattice_scenes
from cases.suites import suite
from harness.checks import pixel_classes
from harness.contract.case import Case
from harness.contract.conventions import TIE_RULES, Convention
from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer
from harness.contract.scenes import Scene
from harness.oracle.area import area_coverage, area_error_bound, exact_area
from harness.oracle.coverage import exact_coverage
from rasterizers.area_scanline import MAX_COORDINATE, TOLERANCE, AreaScanline
from rasterizers.multisample import MultisamplePineda, PinedaMSAA4, PinedaMSAA8
from rasterizers.supersample import Supersampler, Supersampler4, grid_pattern

REFERENCES: list[MultisamplePineda | AreaScanline | Supersampler] = [PinedaMSAA4(), PinedaMSAA8(), AreaScanline(),
                                                                     Supersampler4()]


@cache
def static_cases() -> list[Case]:
    return [c for c in suite("quick") if isinstance(c, Case) and c.scene.kind == "triangles"]  # the references take triangles


def answer(rasterizer: Rasterizer, case: Case) -> Coverage | None:
    """The rasterizer's coverage, or None when it refuses -- which it may only do for a
    triangle the case marks refusable, and must do naming it."""
    try:
        return rasterizer.rasterize(case.scene)
    except ValueError as exc:
        assert case.refusable, f"{rasterizer.name} refused {case.id}: {exc}"
        assert any(f"{rasterizer.name}: triangle {t} " in str(exc) for t in case.refusable), str(exc)
        return None


def alpha_image(coverage: Coverage, scene: Scene) -> np.ndarray:
    """(N, H, W) alphas, 0 where a triangle left a pixel out."""
    assert coverage.alpha is not None
    image = np.zeros((len(scene), scene.height, scene.width))
    t, x, y = coverage.pixels()
    np.add.at(image, (t, y, x), coverage.alpha)
    return image


def test_each_reference_satisfies_the_protocol_and_declares_its_kind():
    kinds = []
    for r in REFERENCES:
        typed: Rasterizer = r  # the static assignment a type checker verifies
        assert isinstance(typed, Rasterizer)
        kinds.append(r.convention.coverage_kind)
    assert kinds == ["multisample", "multisample", "area", "area"]
    assert REFERENCES[0].convention == Convention(samples=4) and REFERENCES[1].convention.n_samples == 8
    assert AreaScanline.convention.alpha_tolerance == TOLERANCE and 0.0 <= TOLERANCE <= 1.0
    assert Supersampler4().convention == Convention(coverage="area", samples=grid_pattern(4), levels=17)


def test_entry_points_name_no_argument_classes():
    table = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())
    points = table["project"]["entry-points"]["rastercheck.rasterizers"]
    for name in ("pineda_msaa4", "pineda_msaa8", "area_scanline", "supersample4"):
        module, attr = points[name].split(":")
        assert getattr(import_module(module), attr)().name == name


# -- multisample -------------------------------------------------------------------------


@pytest.mark.parametrize("rasterizer", REFERENCES[:2], ids=["4x", "8x"])
def test_multisample_equals_the_exact_oracle_on_the_quick_suite(rasterizer):
    for case in static_cases():
        cov = answer(rasterizer, case)
        if cov is None:
            continue
        ref = exact_coverage(case.scene, rasterizer.convention)
        if case.scene.attributes is None:
            assert cov == ref, case.id
            continue
        # the spans and sample indices exactly; the attributes interpolated at the same
        # samples from the same vertices (vertex order may differ: rounding only)
        spans = [Coverage(c.triangle, c.y, c.x0, c.x1, sample=c.sample) for c in (cov, ref)]
        assert spans[0] == spans[1], case.id
        a, b = cov.canonical().attributes, ref.canonical().attributes
        assert a is not None and b is not None
        assert a.shape == b.shape and np.max(np.abs(a - b), initial=0.0) <= 1e-9, case.id


def test_multisample_refuses_only_beyond_the_exact_range():
    drawn = {c.id for c in static_cases() if answer(REFERENCES[0], c) is not None}
    # 1e9 and 1e30 are within exact expansions' reach; the largest float is not
    assert {"degenerate/huge/cover-1e30", "degenerate/huge/wedge-1e9"} <= drawn
    assert "degenerate/huge/cover-max-float" not in drawn
    tiny = np.array([[[1, 1], [9, 1], [1, 9]], [[1e-300, 1], [9, 1], [1, 9]]])
    for r in (REFERENCES[0], Supersampler4()):
        with pytest.raises(ValueError, match=f"{r.name}: triangle 1 .*2\\*\\*-450"):
            r.rasterize(Scene(12, 12, tiny))


@pytest.mark.parametrize("tie", TIE_RULES[::3])
@given(scene=lattice_scenes(max_bits=4, size=16, max_triangles=4))
@settings(max_examples=15)
def test_multisample_and_supersampler_take_any_tie_rule_and_pattern(tie, scene):
    for samples in (2, 16, [(0.0, 0.0), (0.5, 0.25), (0.9375, 0.75)]):
        r = MultisamplePineda(samples, tie=tie)
        assert r.rasterize(scene) == exact_coverage(scene, r.convention)
    grid = Supersampler(2, tie=tie)
    assert grid.rasterize(scene) == exact_coverage(scene, grid.convention)


def test_multisample_interpolates_at_each_sample():
    rng = np.random.default_rng(3)
    positions = rng.uniform(-4, 36, size=(12, 3, 2))
    values = rng.uniform(-5, 5, size=(12, 3, 2))
    for w in (None, rng.uniform(0.5, 4.0, size=(12, 3))):
        scene = Scene(32, 32, positions, attributes=values, w=w)
        cov = PinedaMSAA4().rasterize(scene)
        ref = exact_coverage(scene, PinedaMSAA4().convention)
        assert cov.attributes is not None and ref.attributes is not None
        assert cov.sample is not None and ref.sample is not None
        assert cov.attributes.shape == (cov.n_pixels, 2)
        assert np.array_equal(cov.sample, ref.sample) and cov.x0.tolist() == ref.x0.tolist()
        assert np.max(np.abs(cov.attributes - ref.attributes)) <= 1e-9


# -- area scanline ------------------------------------------------------------------------


def test_area_scanline_is_within_its_tolerance_on_the_quick_suite():
    r = AreaScanline()
    rng = np.random.default_rng(0)
    worst = 0.0
    for case in static_cases():
        cov = answer(r, case)
        if cov is None:
            continue
        scene = case.scene
        assert isinstance(scene, Scene)
        ref = area_coverage(scene, r.convention)
        mine, exact = alpha_image(cov, scene), alpha_image(ref, scene)
        # the oracle is within area_error_bound of the exact area
        slack = area_error_bound(scene.positions, scene.width, scene.height)[:, None, None]
        error = np.abs(mine - exact)
        assert np.all(error <= TOLERANCE + slack), (case.id, error.max())
        assert np.all(np.abs(mine * 255 - np.rint(mine * 255)) <= 1e-9)  # quantised to 256 levels
        worst = max(worst, float(error.max(initial=0.0)))
        # and against the rationals themselves on a few pixels
        t, y, x = np.nonzero(mine + exact)
        for k in rng.choice(t.size, size=min(4, t.size), replace=False):
            area = exact_area(scene.positions[t[k]], int(x[k]), int(y[k]))
            assert abs(Fraction(mine[t[k], y[k], x[k]]) - area) <= TOLERANCE, case.id
    assert worst <= TOLERANCE
    print(f"area_scanline: largest |alpha - area| on the quick suite {worst * 255:.4f} levels")


@given(scene=float_scenes(size=10, max_triangles=3))
@settings(max_examples=25)
def test_area_scanline_is_within_its_tolerance_of_the_rational_areas(scene):
    mine = alpha_image(AreaScanline().rasterize(scene), scene)
    for t in range(len(scene)):
        if not np.isfinite(scene.positions[t]).all():
            continue
        for y, x in [(1, 1), (4, 5), (9, 0), (5, 8)]:
            area = exact_area(scene.positions[t], x, y)
            assert abs(Fraction(mine[t, y, x]) - area) <= TOLERANCE, (t, x, y)


def test_area_scanline_error_bound_far_out():
    """Triangles reaching almost to the refusal limit: the float part of the error stays
    far under the declared 2**-23 (measured with the same kernel quantised to 2**-45)."""
    from harness.geometry.exact import frozen, orientation
    from rasterizers.area_scanline import _kernel

    rng = np.random.default_rng(1)
    positions = rng.uniform(-MAX_COORDINATE, MAX_COORDINATE, size=(20, 3, 2)) * 0.999
    positions[:, 0] = rng.uniform(0, 32, size=(20, 2))  # one vertex on screen
    block, alpha, n, m = _kernel(frozen(positions), orientation(positions), 32, 32, 2.0**45,
                                 np.empty((4, 8), dtype=np.int64), np.empty(8))
    cov = Coverage(block[0, :n], block[1, :n], block[2, :n], block[3, :n], alpha=alpha[:m])
    t, x, y = cov.pixels()
    assert cov.alpha is not None
    worst = max(abs(Fraction(cov.alpha[k]) - exact_area(positions[t[k]], int(x[k]), int(y[k])))
                for k in rng.choice(t.size, size=40, replace=False))
    assert worst <= 2.0**-26, float(worst)


def test_area_scanline_refuses_huge_and_draws_nothing_for_non_finite():
    r = AreaScanline()
    tris = np.array([[[1, 1], [9, 1], [1, 9]], [[np.nan, 1], [9, 1], [1, 9]], [[2, 2], [np.inf, 3], [2, 9]],
                     [[3, 3], [5, 5], [7, 7]]], dtype=float)
    cov = r.rasterize(Scene(12, 12, tris))
    assert set(cov.triangle.tolist()) == {0}
    assert cov == r.rasterize(Scene(12, 12, tris[:1]))
    with pytest.raises(ValueError, match="area_scanline: triangle 1 "):
        r.rasterize(Scene(12, 12, np.array([[[1, 1], [9, 1], [1, 9]], [[1, 1], [2**25, 1], [1, 9]]], dtype=float)))


# -- supersampler -------------------------------------------------------------------------


def test_supersampler_equals_the_share_of_samples_on_the_quick_suite():
    for r in (Supersampler4(), Supersampler(2, tie="bottom-right")):
        for case in static_cases():
            cov = answer(r, case)
            if cov is not None:
                assert cov == exact_coverage(case.scene, r.convention), (r.name, case.id)


def test_supersampler_rejects_other_grids_and_takes_up_to_16_x_16():
    for n in (3, 32, 0, True):
        with pytest.raises(ValueError, match="power of two"):
            Supersampler(n)
    scene = Scene(6, 5, [[[0.3, 0.2], [5.7, 1.1], [1.2, 4.9]], [[5.5, 0.5], [6.0, 5.0], [2.0, 5.0]]])
    fine = Supersampler(8)
    assert fine.rasterize(scene) == exact_coverage(scene, fine.convention)  # 64 samples: more than multisample holds


# -- seams on planar partitions -----------------------------------------------------------


@pytest.mark.parametrize("rasterizer", [AreaScanline(), Supersampler4()], ids=["area_scanline", "supersample4"])
def test_partitions_have_no_seams(rasterizer):
    """At a pixel wholly inside a partition, the pieces' alphas sum to 1 within half a
    level per piece touching it (each alpha is its area rounded); the supersampler's
    exactly, since every sample is covered exactly once."""
    half = 0.5 * rasterizer.convention.level_step
    partitions = [c for c in static_cases() if c.region is not None]
    assert len(partitions) > 10
    for case in partitions:
        cov = answer(rasterizer, case)
        if cov is None:
            continue
        scene = case.scene
        assert isinstance(scene, Scene) and case.region is not None
        inside, _ = pixel_classes(case.region, scene.width, scene.height)
        total = alpha_image(cov, scene).sum(axis=0)[inside]
        if isinstance(rasterizer, Supersampler):
            assert np.array_equal(total, np.ones_like(total)), case.id
            continue
        pieces = (alpha_image(area_coverage(scene, rasterizer.convention), scene) > 0).sum(axis=0)[inside]
        assert np.all(np.abs(total - 1.0) <= pieces * half + 1e-12), case.id
