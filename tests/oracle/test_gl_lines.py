"""GL's aliased-line rule (issue 29, point 5): its own LineRule value beside D3D's, the
exact oracle against its rational reference and against the spec's definition with a
concrete tiny eps, the places it parts from D3D's, and an independent GL drawer
(tests/gl_lines.py) through the quick line suite and identify, with a known-bad one."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from cases.lines import line_cases
from harness.contract.case import Case
from harness.contract.conventions import DIAMOND_RULES, LINE_RULES, Convention, LineRule
from harness.contract.scenes import LineScene
from harness.engine.runner import run_suite
from harness.identify.fingerprint import identify
from harness.oracle.coverage import exact_coverage
from harness.oracle.diamond_lines import (
    diamond_exit_spans,
    diamond_exit_spans_rational,
    diamond_wide_spans,
    diamond_wide_spans_rational,
)
from rasterizers.lines import DiamondExitDDA
from tests.gl_lines import GLDiamondLines, PerturbedUpwards, WideNotMoved
from tests.oracle.test_lines import QUICK, SIZE, _pixels, _same, _sorted, segments

GL = "diamond-exit-gl"
HALF = Fraction(1, 2)


def test_gl_is_one_value_of_the_line_rule() -> None:
    assert GL in LINE_RULES and DIAMOND_RULES == ("diamond-exit", GL)
    rule = LineRule(GL)
    assert rule.last_pixel is False and "GL diamond-exit" in rule.describe()
    assert Convention(line=GL).line == rule
    with pytest.raises(ValueError, match="direction"):
        LineRule(GL, direction="smaller-x")
    with pytest.raises(ValueError, match="rule must be one of diamond-exit, diamond-exit-gl"):
        diamond_exit_spans([[0.0, 0.0]], [[1.0, 1.0]], 4, 4, rule="bresenham")


# -- the oracle against its references ---------------------------------------------------------


@QUICK
@given(segments, st.booleans())
@example((np.array([[0.5, 0.0]]), np.array([[3.5, 3.0]])), False)  # 45 degrees along upper-right edges
@example((np.array([[3.0, 3.0]]), np.array([[0.0, 0.0]])), False)  # 45 degrees through corners, backwards
@example((np.array([[0.5, 2.5]]), np.array([[3.0, 2.5]])), False)  # x-major, ending on a right corner
@example((np.array([[0.5, 1.0]]), np.array([[5.5, 1.0]])), False)  # along the bottom corners of row 0
@example((np.array([[2.0, 0.5]]), np.array([[2.0, 5.5]])), True)  # y-major through right corners
@example((np.array([[0.5, 0.0]]), np.array([[4.5, 2.0]])), False)  # slope 1/2 through corners (y(xc) integer)
@example((np.array([[4.5, 2.0]]), np.array([[0.5, 0.0]])), False)  # the same, drawn the other way
@example((np.array([[1.5, 2.0]]), np.array([[1.5, 2.0]])), True)  # zero length on a top corner
def test_gl_oracle_matches_its_rational_reference(segs, last_pixel) -> None:  # type: ignore[no-untyped-def]
    a, b = segs
    fast = diamond_exit_spans(a, b, SIZE, SIZE, last_pixel, rule=GL)
    _same(fast, diamond_exit_spans_rational(a, b, SIZE, SIZE, last_pixel, rule=GL))
    _sorted(fast)


_EPS = Fraction(1, 2**40)


def _spec_with_eps(a: tuple[float, float], b: tuple[float, float], size: int, last_pixel: bool) -> set[tuple[int, int]]:
    """GL 14.5.1 with a concrete eps = 2**-40 (far below any sign change of a 1/8-lattice
    segment's conditions): the moved closed segment meets the open diamond (the t in
    [0, 1] meeting its four strict half-planes, an interval), and the moved b is not in it.
    Written apart from the oracle's rational reference: numbers, not polynomials in eps."""
    pa = (Fraction(a[0]) - _EPS, Fraction(a[1]) - _EPS * _EPS)
    pb = (Fraction(b[0]) - _EPS, Fraction(b[1]) - _EPS * _EPS)
    fx, fy = pb[0] - pa[0], pb[1] - pa[1]
    out = set()
    for j in range(size):
        for i in range(size):
            xc, yc = i + HALF, j + HALF
            lo, hi, ok = Fraction(0), Fraction(1), True
            for sx, sy in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                g0 = HALF - sx * (pa[0] - xc) - sy * (pa[1] - yc)
                g1 = -sx * fx - sy * fy
                if g1 == 0:
                    ok &= g0 > 0
                elif g1 > 0:
                    lo = max(lo, -g0 / g1)  # t > -g0/g1
                else:
                    hi = min(hi, -g0 / g1)
            met = ok and lo < hi  # t > roots (strict), 0 <= t <= 1: never lo == hi with a point left
            inside = abs(pb[0] - xc) + abs(pb[1] - yc) < HALF
            if met and (last_pixel or not inside):
                out.add((i, j))
    return out


@QUICK
@given(segments, st.booleans())
@example((np.array([[0.5, 0.0]]), np.array([[3.5, 3.0]])), False)
@example((np.array([[0.5, 2.5]]), np.array([[3.0, 2.5]])), False)
def test_the_rational_reference_is_the_spec_with_a_tiny_eps(segs, last_pixel) -> None:  # type: ignore[no-untyped-def]
    a, b = segs
    for k in range(a.shape[0]):
        if not np.isfinite([*a[k], *b[k]]).all() or (np.abs(a[k] * 8 - np.round(a[k] * 8)).max() > 0
                                                      or np.abs(b[k] * 8 - np.round(b[k] * 8)).max() > 0):
            continue  # the concrete eps is small enough on the 1/8 lattice only
        want = _spec_with_eps(tuple(a[k]), tuple(b[k]), SIZE, last_pixel)
        got = {(x, y) for _, x, y in _pixels(diamond_exit_spans_rational(a[k:k + 1], b[k:k + 1], SIZE, SIZE, last_pixel, rule=GL))}
        assert got == want, (a[k], b[k])


def test_far_gl_segments_match_the_kernel() -> None:
    # beyond the kernels' range the rational walk decides; the same segment scaled into range agrees
    a = np.array([[0.5, 0.0], [-1e300, 2.5], [1.5, -1e300]])
    b = np.array([[3.5, 3.0], [1e300, 2.5], [1.5, 1e300]])
    cov = exact_coverage(LineScene.from_segments(6, 6, a, b), Convention(line=GL))
    pixels = {(int(s), x, int(y)) for s, y, x0, x1 in zip(cov.primitive, cov.y, cov.x0, cov.x1) for x in range(x0, x1)}
    near = LineScene.from_segments(6, 6, np.array([[0.5, 0.0], [-8.0, 2.5], [1.5, -8.0]]), np.array([[3.5, 3.0], [8.0, 2.5], [1.5, 8.0]]))
    cov = exact_coverage(near, Convention(line=GL))
    assert pixels == {(int(s), x, int(y)) for s, y, x0, x1 in zip(cov.primitive, cov.y, cov.x0, cov.x1) for x in range(x0, x1)}
    # a horizontal line on a row boundary: the row above (its bottom corners); vertical on a column boundary: the left
    assert {(x, y) for s, x, y in pixels if s == 1} == {(x, 2) for x in range(6)}
    assert {(x, y) for s, x, y in pixels if s == 2} == {(1, y) for y in range(6)}


# -- where GL parts from D3D --------------------------------------------------------------------


def _drawn(a, b, rule, last_pixel=False, size=6):  # type: ignore[no-untyped-def]
    return {(x, y) for _, x, y in _pixels(diamond_exit_spans([a], [b], size, size, last_pixel, rule=rule))}


def test_gl_and_d3d_part_exactly_at_their_different_test_areas() -> None:
    # 45 degrees half a pixel off the centres: D3D owns the lower-left edges, GL the upper-right
    assert _drawn((0.5, 0.0), (3.5, 3.0), "diamond-exit") == {(1, 0), (2, 1)}
    assert _drawn((0.5, 0.0), (3.5, 3.0), GL) == {(0, 0), (1, 1), (2, 2)}
    # an x-major segment ending on a right corner: in GL's test area, not in D3D's
    assert _drawn((0.5, 2.5), (3.0, 2.5), "diamond-exit") == {(0, 2), (1, 2), (2, 2)}
    assert _drawn((0.5, 2.5), (3.0, 2.5), GL) == {(0, 2), (1, 2)}
    # ... and on a bottom corner: in D3D's test area, not in GL's
    assert _drawn((2.5, 0.25), (2.5, 1.0), "diamond-exit") == set()
    assert _drawn((2.5, 0.25), (2.5, 1.0), GL) == {(2, 0)}
    # slope 1/2 crossing a column centre on a row boundary: GL takes the lower row when y grows with x
    assert _drawn((0.5, 0.0), (4.5, 2.0), GL) & {(2, 1), (2, 0)} == {(2, 1)}
    assert _drawn((0.5, 0.0), (4.5, 2.0), "diamond-exit") & {(2, 1), (2, 0)} == {(2, 0)}
    assert _drawn((4.5, 0.0), (0.5, 2.0), GL) & {(2, 1), (2, 0)} == {(2, 0)}  # y falling with x: the upper
    # away from ties they agree
    rng = np.random.default_rng(5)
    a, b = rng.uniform(0, 12, (200, 2)), rng.uniform(0, 12, (200, 2))
    _same(diamond_exit_spans(a, b, 12, 12, rule=GL), diamond_exit_spans(a, b, 12, 12))


def test_gl_strips_draw_each_shared_vertex_once() -> None:
    # a closed loop through centres, corners and diamond edges: every vertex pixel once,
    # no pixel of the loop twice (GL's half-open lines)
    loop = [[1.0, 1.0], [4.5, 1.0], [4.5, 4.25], [1.25, 4.5], [1.0, 1.0]]
    scene = LineScene.from_strips(6, 6, [loop])
    counts = exact_coverage(scene, Convention(line=GL)).counts(6, 6)
    assert counts.max() == 1 and counts.sum() > 8


# -- an independent GL drawer through the suite and identify -------------------------------------


@QUICK
@given(segments)
def test_the_gl_drawer_draws_what_the_oracle_says(segs) -> None:  # type: ignore[no-untyped-def]
    a, b = segs
    scene = LineScene.from_segments(SIZE, SIZE, a, b)
    for drawer in (GLDiamondLines(), GLDiamondLines(last_pixel=True)):
        assert (drawer.rasterize(scene).counts(SIZE, SIZE) == exact_coverage(scene, drawer.convention).counts(SIZE, SIZE)).all()


@pytest.fixture(scope="module")
def quick_lines() -> list:
    return line_cases(0)


def _failing(rasterizer, cases):  # type: ignore[no-untyped-def]
    results = run_suite([rasterizer], cases=cases, isolate=False, identify=False, repros=False)
    return results, [r for r in results if r.status not in ("pass", "skip")]


def test_a_gl_drawer_passes_the_quick_line_suite(quick_lines) -> None:  # type: ignore[no-untyped-def]
    results, failing = _failing(GLDiamondLines(), quick_lines)
    assert not failing, [(r.case, r.check, r.message) for r in failing]
    assert {"conformance", "reversal", "joints", "length", "connectivity", "line-motion"} <= {r.check for r in results}


def test_a_gl_drawer_declared_as_d3d_fails(quick_lines) -> None:  # type: ignore[no-untyped-def]
    class DeclaredD3D(GLDiamondLines):
        name = "gl_declared_d3d"

    drawer = DeclaredD3D()
    drawer.convention = Convention(subpixel_bits=8, line=LineRule("diamond-exit"))
    _, failing = _failing(drawer, quick_lines)
    assert "conformance" in {r.check for r in failing}


def test_the_known_bad_gl_drawer_fails(quick_lines) -> None:  # type: ignore[no-untyped-def]
    _, failing = _failing(PerturbedUpwards(), quick_lines)
    assert {"conformance", "length"} <= {r.check for r in failing}, [(r.case, r.check) for r in failing]


def test_identify_tells_gl_from_d3d() -> None:
    for drawer, rule in ((GLDiamondLines(), LineRule(GL)), (GLDiamondLines(last_pixel=True), LineRule(GL, last_pixel=True)),
                         (DiamondExitDDA(), LineRule("diamond-exit"))):
        fp = identify(drawer)
        fit = fp.line_fit
        assert fit.exact and fit.residual == 0 and fit.runner_up[1] > 0, fp.card()
        assert fp.line_rule == rule and fp.line_convention.subpixel_bits == 8, fp.card()
        assert fp.to_dict()["line_convention"]["rule"] == rule.rule
    fp = identify(PerturbedUpwards())
    assert not fp.line_fit.exact and fp.line_fit.residual > 0, fp.card()


# -- wide lines: GL's replication along the minor axis ------------------------------------------


def test_replication_is_one_option_of_the_diamond_rules() -> None:
    rule = LineRule(GL, wide="replicate")
    assert "replication" in rule.describe() and rule.undefined_width(3.0) == "" and rule.undefined_width(1.0) == ""
    assert "integer widths, not 2.5" in rule.undefined_width(2.5)
    assert "width 1, not 3" in LineRule(GL).undefined_width(3.0) and LineRule("rectangle").undefined_width(2.5) == ""
    for other in ("bresenham", "rectangle"):
        with pytest.raises(ValueError, match="diamond-exit option"):
            LineRule(other, wide="replicate")
    with pytest.raises(ValueError, match="wide must be one of none, replicate"):
        LineRule(GL, wide="smooth")
    scene = LineScene.from_segments(6, 6, [[0.5, 2.5]], [[4.5, 2.5]], 3.0)
    with pytest.raises(ValueError, match="wide='replicate'"):
        exact_coverage(scene, Convention(line=LineRule(GL)))
    assert exact_coverage(scene, Convention(line=rule)).counts(6, 6).sum() == 12  # 4 columns x 3 rows


@QUICK
@given(segments, st.integers(1, 4), st.booleans(), st.sampled_from(DIAMOND_RULES))
@example((np.array([[0.5, 2.5]]), np.array([[3.5, 2.5]])), 2, False, GL)  # moved onto a row boundary
@example((np.array([[2.5, 0.5]]), np.array([[2.5, 4.5]])), 2, False, GL)  # y-major: onto a column boundary
@example((np.array([[0.1, 2.5]]), np.array([[3.5, 2.7]])), 2, False, GL)  # the move rounds: the rational path
@example((np.array([[0.5, 1.0]]), np.array([[3.5, 4.0]])), 3, True, "diamond-exit")
def test_wide_oracle_matches_its_rational_reference(segs, w, last_pixel, rule) -> None:  # type: ignore[no-untyped-def]
    a, b = segs
    fast = diamond_wide_spans(a, b, w, SIZE, SIZE, last_pixel, rule)
    _same(fast, diamond_wide_spans_rational(a, b, w, SIZE, SIZE, last_pixel, rule))
    _sorted(fast)
    if w == 1:
        _same(fast, diamond_exit_spans(a, b, SIZE, SIZE, last_pixel, rule))


@QUICK
@given(segments, st.integers(2, 4))
def test_the_wide_gl_drawer_draws_what_the_oracle_says(segs, w) -> None:  # type: ignore[no-untyped-def]
    a, b = segs
    scene = LineScene.from_segments(SIZE, SIZE, a, b, float(w))
    drawer = GLDiamondLines(wide=True)
    assert (drawer.rasterize(scene).counts(SIZE, SIZE) == exact_coverage(scene, drawer.convention).counts(SIZE, SIZE)).all()


@pytest.fixture(scope="module")
def wide_lines(quick_lines) -> list:  # type: ignore[no-untyped-def]
    """The quick suite's lattice cases of width 1, at widths 2 and 3."""
    chosen = [c for c in quick_lines if c.lattice and c.scene.line_width == 1.0 and len(c.scene) <= 120][:12]
    return [Case(f"{c.id}@w{w}", c.scene.with_line_width(float(w)), lattice=True) for c in chosen for w in (2, 3)]


def test_a_wide_gl_drawer_passes_wide_cases_and_a_bad_one_fails(wide_lines) -> None:  # type: ignore[no-untyped-def]
    results, failing = _failing(GLDiamondLines(wide=True), wide_lines)
    assert not failing, [(r.case, r.check, r.message) for r in failing]
    assert {"conformance", "length", "reversal"} <= {r.check for r in results if r.status == "pass"}
    assert all(r.status == "skip" for r in results if r.check == "connectivity")
    _, failing = _failing(WideNotMoved(), wide_lines)
    assert {"conformance", "length"} & {r.check for r in failing} and all("@w3" in r.case for r in failing)
    # the width-1 drawer refuses them: skipped, not failed
    results, failing = _failing(GLDiamondLines(), wide_lines[:4])
    assert not failing and results and all(r.status == "skip" for r in results)


def test_identify_finds_gl_replication() -> None:
    fp = identify(GLDiamondLines(wide=True))
    fit = fp.line_fit
    assert fit.exact and fp.line_rule == LineRule(GL, wide="replicate"), fp.card()
    assert fit.wide.replicated == 0 and "GL's wide lines" in fp.facts["wide lines"]
    assert fp.to_dict()["line_convention"]["wide"] == "replicate"
    fp = identify(WideNotMoved())  # off centre at width 3: not replication
    assert fp.line_rule == LineRule(GL) and fp.line_fit.wide.replicated > 0, fp.card()


def test_a_gl_failure_picture_draws_gl_test_areas() -> None:
    import base64

    from harness.report import pictures

    case = Case("lines/gl-along-edges", LineScene.from_segments(8, 8, [[0.5, 0.0]], [[3.5, 3.0]]), lattice=True)
    results = run_suite([PerturbedUpwards()], cases=[case], isolate=False, identify=False, only={"conformance"})
    failure = next(r for r in results if r.check == "conformance")
    assert failure.status == "fail"
    svg = base64.b64decode(pictures.draw(failure)["crop"].split(",", 1)[1]).decode()
    assert "GL test area of pixel" in svg and "right edges and right corner in" in svg and "lower edges and bottom" not in svg
