"""Multisample lines (issue 29, point 5): rectangles sampled at every sample of the
convention's pattern (GL 14.5.4, dEQP), each sample decided exactly as the rectangle rule
decides a pixel centre; the oracle against the rational reference per sample, an
independent drawer (tests/msaa_lines.py) through the quick line suite (its smaller cases), and a
known-bad one."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from cases.lines import line_cases
from harness.contract.conventions import TIE_RULES, Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from harness.engine.runner import run_suite
from harness.oracle.coverage import exact_coverage
from harness.oracle.rectangle_lines import rectangle_spans_rational
from tests.msaa_lines import ClosedRectangles, MultisampleRectangleLines
from tests.oracle.test_lines import QUICK, SIZE, segments


def test_multisample_lines_are_rectangles() -> None:
    scene = LineScene.from_segments(6, 4, [[0.5, 1.0]], [[4.5, 1.0]])
    with pytest.raises(ValueError, match="rectangles sampled per sample"):
        exact_coverage(scene, Convention(samples=4))
    cov = exact_coverage(scene, Convention(samples=4, line=LineRule("rectangle")))
    # standard 4x samples 0..3 at y offsets 1/8, 3/8, 5/8, 7/8: the band 1/2 < y < 3/2 holds
    # row 1's samples 0 and 1 and row 0's samples 2 and 3
    assert cov.sample is not None
    assert sorted({(int(s), int(y)) for s, y in zip(cov.sample, cov.y)}) == [(0, 1), (1, 1), (2, 0), (3, 0)]
    # under area coverage a rectangle's alpha is the exact area of the stroke (issue 34: harness.oracle.area_lines):
    # the 1-wide band over x in [0.5, 4.5] covers half of each of rows 0 and 1 there
    area = exact_coverage(scene, Convention(coverage="area", line=LineRule("rectangle")))
    assert area.alpha is not None and area.n_pixels and float(area.alpha.max()) == 0.5


@QUICK
@given(segments, st.sampled_from([0.25, 1.0, 2.5]), st.sampled_from(TIE_RULES), st.sampled_from([2, 4, 8]))
@example((np.array([[0.5, 1.0]]), np.array([[4.5, 1.0]])), 0.25, "top-left", 4)  # samples on the sides (y = 7/8)
@example((np.array([[0.375, 0.5]]), np.array([[0.375, 6.5]])), 1.0, "bottom-right", 4)  # a vertical through samples
def test_each_sample_is_the_rectangle_rule_at_its_offset(segs, w, tie, n) -> None:
    a, b = segs
    convention = Convention(samples=n, tie=tie, line=LineRule("rectangle"))
    cov = exact_coverage(LineScene.from_segments(SIZE, SIZE, a, b, w), convention)
    assert (np.diff(cov.primitive) >= 0).all()
    for k, offset in enumerate(convention.samples):
        want = Coverage(*rectangle_spans_rational(a, b, w, offset, tie, width=SIZE, height=SIZE))
        assert (cov.layer(k).counts(SIZE, SIZE) == want.counts(SIZE, SIZE)).all(), (k, offset)


@QUICK
@given(segments, st.sampled_from([0.25, 1.0, 2.5]), st.sampled_from(["top-left", "bottom-right-y-first"]))
def test_the_multisample_drawer_draws_what_the_oracle_says(segs, w, tie) -> None:
    a, b = segs
    scene = LineScene.from_segments(SIZE, SIZE, a, b, w)
    drawer = MultisampleRectangleLines(4, tie)
    got, want = drawer.rasterize(scene), exact_coverage(scene, drawer.convention)
    for k in range(4):
        assert (got.layer(k).counts(SIZE, SIZE) == want.layer(k).counts(SIZE, SIZE)).all()


@pytest.fixture(scope="module")
def quick_lines() -> list:
    return line_cases(0)


def _failing(rasterizer, cases):
    results = run_suite([rasterizer], cases=cases, isolate=False, identify=False, repros=False)
    return results, [r for r in results if r.status not in ("pass", "skip")]


def test_a_multisample_line_drawer_passes_the_quick_line_suite_and_a_closed_one_fails(quick_lines) -> None:
    # the quick suite's cases of at most 48 segments: every family (octants, ties, wide
    # lines, strips, degenerate ones), at a quarter of the whole suite's time
    small = [c for c in quick_lines if len(c.scene) <= 48]
    assert {c.family for c in small} == {"lines", "line-strips", "line-degenerate"} and len(small) >= 25
    assert any(c.scene.line_width != 1.0 for c in small)
    results, failing = _failing(MultisampleRectangleLines(), small)
    assert not failing, [(r.case, r.check, r.message) for r in failing]
    assert {"conformance", "joints", "reversal", "length", "line-motion"} <= {r.check for r in results if r.status == "pass"}
    _, failing = _failing(ClosedRectangles(), [c for c in small if c.lattice][:8])
    assert "conformance" in {r.check for r in failing}, [(r.case, r.check) for r in failing]
