"""The closed rule and dropout control (issue 33): the oracles against the rational
reference and a line-by-line transcription of ftraster.c, that transcription against
FreeType itself, the declaration, the checks' expectations and the known-bad doubles."""

from __future__ import annotations

import dataclasses
import json
import pickle
from fractions import Fraction
from typing import Any

import numpy as np
import pytest

from harness.checks import conformance, overdraw, watertight
from harness.contract.case import Case
from harness.contract.conventions import Convention, Dropout, dropout_control
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.oracle.closed_rule import closed_coverage, closed_reference
from harness.oracle.coverage import exact_coverage
from harness.oracle.dropout import (
    _Builder,
    dropout_coverage,
    scan_convert,
    scan_convert_reference,
    stepped_crossing,
)
from tests.known_bad.dropout import FREETYPE_MONO, FREETYPE_MONO_DROPOUT, ClosedWithTies, LeftDropout

SCANTYPES = (0, 1, 2, 4, 5)


def _triangles(seed: int, n: int, w: int, h: int, lattice: int | None) -> np.ndarray:
    """Random triangles: a third on the 1/``lattice`` grid through the viewport and beyond
    its edges, a third thin slivers, a third zero-area (or float when lattice is None)."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        kind = k % 3
        if lattice is None and kind != 1:
            out.append(rng.uniform(-2, max(w, h) + 2, size=(3, 2)))
            continue
        q = lattice or 64
        if kind == 0:
            p = rng.integers(-3 * q, q * (w + 3), size=(3, 2)) / q
        elif kind == 1:
            a = rng.integers(0, q * w, size=2)
            d = rng.integers(-6 * q, 6 * q, size=2)
            e = rng.integers(-q // 2, q // 2 + 1, size=2)
            p = np.array([a, a + d, a + d // 2 + e]) / q
        else:
            a = rng.integers(0, q * w, size=2)
            d = rng.integers(-3 * q, 3 * q, size=2)
            p = np.array([a, a + d, a + 2 * d]) / q
        out.append(p)
    return np.array(out, dtype=np.float64)


# --- the closed rule -------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("convention", [
    Convention(coverage="closed"), Convention(coverage="closed", sample=(0.0, 0.0), subpixel_bits=2),
    Convention(coverage="closed", cull="cw"), Convention(coverage="closed", input="fixed6")])
def test_closed_agrees_with_the_rational_reference(seed, convention):
    for lattice in (2, 4, None):
        scene = Scene(10, 8, _triangles(seed, 24, 10, 8, lattice))
        assert closed_coverage(scene, convention) == closed_reference(scene, convention), lattice


def test_samples_on_a_shared_edge_are_drawn_by_both_triangles():
    scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]], [[4, 0], [4, 4], [0, 4]]])
    counts = exact_coverage(scene, Convention(coverage="closed")).counts(4, 4)
    assert counts.tolist() == [[1, 1, 1, 2], [1, 1, 2, 1], [1, 2, 1, 1], [2, 1, 1, 1]]
    # the tie rule draws each once
    assert exact_coverage(scene, Convention()).counts(4, 4).max() == 1


def test_zero_area_triangles_draw_the_centres_on_their_segment():
    segment = Scene(6, 6, [[[0.5, 0.5], [2.5, 2.5], [4.5, 4.5]]])  # through five centres
    assert closed_coverage(segment, Convention(coverage="closed")).counts(6, 6).trace() == 5
    assert closed_coverage(segment, Convention(coverage="closed")).counts(6, 6).sum() == 5
    point = Scene(3, 3, [[[1.5, 1.5], [1.5, 1.5], [1.5, 1.5]]])
    assert len(closed_coverage(point, Convention(coverage="closed"))) == 0  # no edge: nothing, as ftraster.c
    # and ftraster.c with dropouts off draws the same (the closed rule's, not dropouts)
    fixed = [[(int(x * 64), 64 * 6 - int(y * 64)) for x, y in segment.positions[0]]]
    assert scan_convert_reference(fixed, 6, 6, 2).sum() == 5


_PARTITION = Case("partitions/closed/fan", Scene(6, 6, [[[1, 1], [5, 1], [3, 3]], [[5, 1], [5, 5], [3, 3]],
                                                         [[5, 5], [1, 5], [3, 3]], [[1, 5], [1, 1], [3, 3]]]),
                  lattice=True, region=np.array([[1.0, 1.0], [5.0, 1.0], [5.0, 5.0], [1.0, 5.0]]))


@pytest.mark.parametrize("convention", [Convention(coverage="closed", sample=(0.0, 0.0)), FREETYPE_MONO])
def test_watertight_and_overdraw_expect_the_rules_double_hits(convention):
    own = exact_coverage(_PARTITION.scene, convention)
    assert own.counts(6, 6).max() >= 2  # the diagonals' samples, twice or four times
    result = watertight(_PARTITION, own, convention, lambda: own)
    assert result.status == "pass" and result.metrics.get("rule_own", 0) > 0, result.message
    assert overdraw(_PARTITION, own, convention, lambda: own).status == "pass"
    twice = Coverage.concat([own, own])
    assert watertight(_PARTITION, twice, convention, lambda: own).status == "fail"


# --- ftraster.c: the crossings, the kernel, the exact-crossing scan --------------------------------

def test_stepped_crossings_are_the_closed_form_of_line_up():
    rng = np.random.default_rng(1)
    for _ in range(400):
        x1, x2 = (int(v) for v in rng.integers(-2000, 2000, size=2))
        y1 = int(rng.integers(-500, 500))
        y2 = y1 + int(rng.integers(1, 3000))
        builder = _Builder(2, -10**6, 10**6, True)
        builder.new_profile(1, False)
        builder.line_up(x1, y1, x2, y2, -10**6, 10**6, 1)
        first = -((-y1) // 64) * 64
        scanlines = range(first, y2 + 1, 64)
        assert builder.cur.entries == [stepped_crossing(x1, y1, x2, y2, s) for s in scanlines]
        # within one 1/64 unit of the exact crossing (rounded first, then truncated steps)
        for s, x in zip(scanlines, builder.cur.entries):
            assert abs(x - (x1 + Fraction((s - y1) * (x2 - x1), y2 - y1))) < 1 + Fraction(1, 2)


@pytest.mark.parametrize("mode", SCANTYPES)
def test_the_kernel_is_the_transcription(mode):
    w, h = 12, 10
    for p in _triangles(mode, 90, w, h, 64):
        fixed = [(int(round(x * 64)), 64 * h - int(round(y * 64))) for x, y in p]
        want = scan_convert_reference([fixed], w, h, mode)
        got = np.zeros((h, w), dtype=np.bool_)
        scan_convert(np.array(fixed, dtype=np.int64), w, h, mode, got)
        assert (got == want).all(), (p.tolist(), mode)


@pytest.mark.parametrize("seed", range(2))
def test_with_exact_crossings_and_no_dropouts_the_scan_is_the_closed_rule(seed):
    w, h = 9, 7
    for p in _triangles(seed, 45, w, h, None):
        fixed = [(Fraction(float(x)) * 64, 64 * h - Fraction(float(y)) * 64) for x, y in p]
        scan = scan_convert_reference([fixed], w, h, 2, stepped=False)
        closed = closed_coverage(Scene(w, h, p[None]), Convention(coverage="closed")).counts(w, h) > 0
        assert (scan == closed).all(), p.tolist()


def test_simple_and_smart_pick_their_pixel():
    # a vertical sliver 0.2 px wide between the centres of columns 1 and 2, nearer column 2's
    scene = Scene(4, 6, [[[2.25, 1.0], [2.375, 1.0], [2.375, 5.0]]])
    picked = {}
    for mode in ("simple", "smart"):
        convention = Convention(coverage="closed", input="fixed6", dropout=f"{mode}-stepped6")
        picked[mode] = set(np.flatnonzero(dropout_coverage(scene, convention).counts(4, 6).sum(axis=0)).tolist())
    assert picked == {"simple": {1}, "smart": {2}}
    assert len(exact_coverage(scene, Convention(coverage="closed", input="fixed6"))) == 0  # no centre inside


def test_a_dropout_outside_the_bitmap_takes_the_pixel_inside():
    # a sliver between column 0's centre and the viewport's left edge: simple would take column -1
    scene = Scene(3, 4, [[[-0.375, 0.0], [0.25, 0.0], [0.25, 4.0]]])
    convention = Convention(coverage="closed", input="fixed6", dropout="simple-stepped6")
    assert set(exact_coverage(scene, convention).x0.tolist()) == {0}


# --- FreeType itself ----------------------------------------------------------------------------------

def _freetype(flags: int):
    pytest.importorskip("freetype")
    from rasterizers.real.freetype_outline import _PIXEL_MODE_MONO, _Outline

    return _Outline(_PIXEL_MODE_MONO, flags)


# FT_OUTLINE_IGNORE_DROPOUTS 0x8, SMART_DROPOUTS 0x10, INCLUDE_STUBS 0x20 -> SCANTYPE
_FLAGS = {0: 0x20, 1: 0x0, 2: 0x8, 4: 0x30, 5: 0x10}


@pytest.mark.parametrize("mode", SCANTYPES)
def test_the_transcription_is_freetypes_monochrome_rasterizer(mode):
    outline = _freetype(_FLAGS[mode])
    w, h = 14, 12
    for p in _triangles(10 + mode, 150, w, h, 64):
        fixed = [(int(round(x * 64)), 64 * h - int(round(y * 64))) for x, y in p]
        got = np.zeros((h, w), dtype=np.bool_)
        scan_convert(np.array(fixed, dtype=np.int64), w, h, mode, got)
        assert (got == (outline.render([p], w, h) > 0)).all(), (p.tolist(), mode)


@pytest.mark.parametrize("convention", [FREETYPE_MONO, FREETYPE_MONO_DROPOUT])
def test_the_adapters_are_their_declared_conventions(convention):
    pytest.importorskip("freetype")
    from rasterizers.real.freetype_outline import FreeTypeMono, FreeTypeMonoDropout

    rasterizer = FreeTypeMono() if convention is FREETYPE_MONO else FreeTypeMonoDropout()
    assert rasterizer.convention == convention
    scene = Scene(20, 16, np.concatenate([_triangles(3, 90, 20, 16, 64), _triangles(4, 30, 20, 16, None)]))
    assert rasterizer.rasterize(scene) == exact_coverage(scene, convention)
    outlines: list[Any] = [[[[1, 1], [15, 2.5], [8.25, 11.125]], [[3, 9], [13, 9], [8, 0.5]]],
                           [[[2.1, 2.2], [2.3, 10.4], [2.35, 10.41]]]]
    paths = PathScene.from_paths(16, 12, outlines)
    assert rasterizer.rasterize(paths) == exact_coverage(paths, convention)


# --- the declaration ----------------------------------------------------------------------------------

def test_dropout_is_declared_validated_described_and_round_tripped():
    assert Convention() == Convention(dropout=None) and Convention().dropout == "none"  # type: ignore[arg-type]
    assert repr(Convention(coverage="closed")) == \
        "Convention(sample=(0.5, 0.5), tie='top-left', subpixel_bits=None, cull='none', coverage='closed')"
    assert FREETYPE_MONO_DROPOUT.dropout == "smart-no-stubs-stepped6"
    assert FREETYPE_MONO_DROPOUT.dropout_control == Dropout("smart", stubs=False, step_bits=6)
    assert FREETYPE_MONO_DROPOUT.describe() == (
        "the closed rule (a sample on an edge is inside) at sample (0.5, 0.5), smart dropout control (SCANTYPE 5, "
        "stubs excluded), crossings stepped at 1/64 px from each edge's start, 26.6 fixed-point input (1/64 px, "
        "nearest-even), no snapping, no culling")
    for convention in (FREETYPE_MONO, FREETYPE_MONO_DROPOUT, Convention(coverage="closed", dropout="simple")):
        fields = {f.name: getattr(convention, f.name) for f in dataclasses.fields(convention) if f.name != "line"}
        assert Convention(**json.loads(json.dumps(fields))) == convention
        assert pickle.loads(pickle.dumps(convention)) == convention
        assert eval(repr(convention)) == convention  # noqa: S307 - the repr is the declaration
    assert [Dropout.from_scantype(m).scantype for m in SCANTYPES] == list(SCANTYPES)
    assert Dropout.from_scantype(6) == Dropout() and dropout_control({"mode": "smart"}) == Dropout("smart")
    with pytest.raises(ValueError, match=r"^Convention.dropout is the closed rule's"):
        Convention(dropout="smart")
    with pytest.raises(ValueError, match=r"input must lie on it"):
        Convention(coverage="closed", dropout="smart-stepped6")
    with pytest.raises(ValueError, match=r"^Convention.dropout must be 'none', 'simple' or 'smart'"):
        Convention(coverage="closed", dropout="smarter")
    with pytest.raises(ValueError, match=r"^Dropout.step_bits must be None"):
        Dropout("simple", step_bits=8)
    with pytest.raises(ValueError, match=r"^Dropout.mode must be one of none, simple, smart"):
        Dropout("always")  # type: ignore[arg-type]


def test_the_closed_rule_refuses_points_and_even_odd_paths_in_one_line():
    from harness.kinds.points import PointScene
    from harness.oracle.points import point_coverage

    with pytest.raises(ValueError, match="points are defined for single-sample and multisample conventions, not the closed"):
        point_coverage(PointScene(3, 3, [[1.0, 1.0]]), Convention(coverage="closed"))
    square = PathScene.from_paths(4, 4, [[[[0, 0], [4, 0], [4, 4], [0, 4]]]], fill_rule="evenodd")
    with pytest.raises(ValueError, match="fills paths by the nonzero rule only"):
        exact_coverage(square, Convention(coverage="closed"))


# --- known-bad doubles, and identify ------------------------------------------------------------------

@pytest.mark.parametrize("bad", [ClosedWithTies, LeftDropout])
def test_each_known_bad_rasterizer_is_caught_by_conformance(bad):
    rasterizer = bad()
    scene = Scene(12, 10, np.concatenate([[[[0, 0], [6, 0], [0, 6]], [[6, 0], [6, 6], [0, 6]]],
                                          _triangles(2, 30, 12, 10, 64)]))
    case = Case("rules/closed-known-bad", scene, lattice=True)
    oracle = exact_coverage(scene, rasterizer.convention)
    result = conformance(case, rasterizer.rasterize(scene), oracle, rasterizer.convention)
    assert result.status == "fail" and result.metrics["wrong"] > 0, result.message


class _Oracular:
    def __init__(self, convention: Convention) -> None:
        self.convention = convention

    def rasterize(self, scene: Scene) -> Coverage:
        return exact_coverage(scene, self.convention)


@pytest.mark.parametrize("convention", [FREETYPE_MONO, FREETYPE_MONO_DROPOUT,
                                        Convention(coverage="closed", input="fixed6", dropout="simple-stepped6")])
def test_identify_recovers_the_scan_conversion(convention):
    from harness.identify.rule_probes import fit_rule

    fit = fit_rule(_Oracular(convention).rasterize)
    assert fit.exact and fit.convention == convention, fit.describe()


def test_identify_does_not_call_the_known_bad_exact_under_their_claims():
    from harness.identify.rule_probes import fit_rule

    for bad in (ClosedWithTies(), LeftDropout()):
        fit = fit_rule(bad.rasterize)
        assert not (fit.exact and fit.convention == bad.convention), fit.describe()


@pytest.mark.parametrize("mode", [2, 5])
def test_tall_triangles_are_drawn_in_bands_as_the_render_pool_forces(mode):
    """Over about 1,000 px tall, ftraster.c's profiles overflow its render pool and it
    bisects the bitmap into bands: the kernel, the transcription and FreeType agree."""
    outline = _freetype(_FLAGS[mode])
    rng = np.random.default_rng(mode)
    w, h = 24, 1500
    for _ in range(3):
        p = np.stack([rng.uniform(0, w, size=3), [rng.uniform(0, 2), rng.uniform(h - 2, h), rng.uniform(0, h)]], 1)
        fixed = [(int(np.rint(64 * x)), 64 * h - int(np.rint(64 * y))) for x, y in p]
        got = np.zeros((h, w), dtype=np.bool_)
        scan_convert(np.array(fixed, dtype=np.int64), w, h, mode, got)
        assert (got == scan_convert_reference([fixed], w, h, mode)).all()
        assert (got == (outline.render([p], w, h) > 0)).all()


# --- the checks' expectations under the closed rule ---------------------------------------------------

def test_degenerate_expects_the_closed_rules_zero_area_pixels_but_not_non_finite_ones():
    from harness.checks import degenerate

    scene = Scene(6, 6, [[[0.5, 0.5], [2.5, 2.5], [4.5, 4.5]], [[np.nan, 1.0], [2.0, 2.0], [3.0, 1.0]]])
    case = Case("degenerate/closed/segment", scene, lattice=True)
    own = exact_coverage(scene, Convention(coverage="closed"))
    assert len(own) and degenerate(case, own, Convention(coverage="closed")).status == "pass"
    assert degenerate(case, own, Convention()).status == "fail"  # under a tie rule they draw nothing
    garbage = Coverage.concat([own, Coverage(np.array([1]), np.array([1]), np.array([1]), np.array([3]))])
    assert degenerate(case, garbage, Convention(coverage="closed")).status == "fail"  # a non-finite triangle drew


def test_invariance_excuses_the_stepped_crossings_own_changes_only():
    from harness.checks import invariance, invariance_variants

    scene = Scene(16, 12, _triangles(7, 30, 16, 12, 64))
    case = Case("float/closed/invariance", scene, lattice=False)
    convention = FREETYPE_MONO_DROPOUT
    own = exact_coverage(scene, convention)
    variants = [(label, index, exact_coverage(s, convention)) for label, s, index in invariance_variants(case)]
    plain = invariance(case, own, variants)
    assert plain.status == "fail"  # reversing the winding moves stepped crossings: the rule itself changes
    judged = invariance(case, own, variants, own=(own, variants))
    assert judged.status == "pass" and judged.metrics["rule_own"] > 0, judged.message
    # a rasterizer whose change the rule does not have still fails
    shifted = [(label, index, Coverage.concat([cov, Coverage(np.array([0]), np.array([0]), np.array([15]),
                                                             np.array([16]))])) for label, index, cov in variants]
    assert invariance(case, own, shifted, own=(own, variants)).status == "fail"
