"""llvmpipe's rectangular lines (harness.oracle.llvmpipe_lines): the oracle (the quad's two
triangles under the triangle oracle) against its reference (each sample against the quad's
four edges, in fractions), llvmpipe's snapping (util_iround in float32, in the frame shifted
by half a pixel), and the rule's place in the convention."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from harness.contract.conventions import TIE_RULES, Convention, LineRule, TieRule
from harness.contract.scenes import LineScene
from harness.oracle.lines import line_coverage
from harness.oracle.llvmpipe_lines import _iround, llvmpipe_rectangle_corners, llvmpipe_rectangle_rational
from tests.oracle.test_lines import QUICK, SIZE, segments


def _pixels(coverage) -> set[tuple[int, int, int]]:
    return set(zip(*(v.tolist() for v in coverage.pixels())))


@QUICK
@given(segments, st.sampled_from(TIE_RULES), st.sampled_from([1.0, 2.0, 0.5]))
@example((np.array([[1 + 2**-9, 2 + 2**-9]]), np.array([[6 - 2**-9, 2 - 2**-9]])), "top-left", 1.0)  # grid ties
@example((np.array([[0.5, 0.5]]), np.array([[0.5, 0.5]])), "top-left", 1.0)  # zero length: no normal
@example((np.array([[0.5, 0.5]]), np.array([[5.5, 3.5]])), "bottom-right", 1.0)
def test_llvmpipe_rectangle_matches_rational(segs, tie: TieRule, width: float) -> None:
    a, b = segs
    scene = LineScene.from_segments(SIZE, SIZE, a, b, line_width=width)
    convention = Convention(tie=tie, line="llvmpipe-rectangle")
    assert _pixels(line_coverage(scene, convention)) == llvmpipe_rectangle_rational(scene, convention)


def test_util_iround_is_half_away_with_float32_sums() -> None:
    f = np.float32
    values = np.array([0.5, -0.5, 1.5, -1.5, 2.4999998, 0.49999997], dtype=f)
    # 0.49999997 + 0.5f rounds to 1.0f in float32: 1, where exact rounding gives 0
    assert _iround(values).tolist() == [1.0, -1.0, 2.0, -2.0, 2.0, 1.0]


def test_ends_snap_half_away_in_the_shifted_frame() -> None:
    """An end on a tie of the 1/256 grid: v - 1/2 rounded half away from zero, so up for
    v >= 1/2 and down below it -- plain half-away but for 0 < v < 1/2, and never the
    triangles' nearest-even."""
    for y, want in ((3 + 2**-9, 3 + 2**-8), (3 - 2**-9, 3.0), (3 + 3 * 2**-9, 3 + 2 * 2**-8), (0.5 + 2**-9, 0.5 + 2**-8),
                    (0.5 - 2**-9, 0.5 - 2**-8), (2**-9, 0.0), (-(2**-9), -(2**-8))):
        corners = llvmpipe_rectangle_corners(np.array([[1.0, y]]), np.array([[6.0, y]]), 1.0, Convention())
        assert corners[0, :, 1].tolist() == [want + 0.5, want + 0.5, want - 0.5, want - 0.5], y


def test_the_normal_is_snapped_on_its_own() -> None:
    """The half-width normal of a (3, 1) segment, (0.158.., -0.474..), snaps to (40, -121)/256:
    the corners are off the exact rectangle's, which the rectangle rule cannot say."""
    corners = llvmpipe_rectangle_corners(np.array([[1.0, 1.0]]), np.array([[4.0, 2.0]]), 1.0, Convention())
    normal = corners[0, 3] - (corners[0, 0] + corners[0, 3]) / 2
    assert (normal * 256).tolist() == [40.0, -121.0]


def test_the_rule_in_the_convention() -> None:
    rule = LineRule("llvmpipe-rectangle")
    assert rule.own_snapping and not LineRule("rectangle").own_snapping
    assert "llvmpipe rectangular lines" in rule.describe()
    scene = LineScene.from_strips(12, 10, [[[0.5, 0.5], [9.25, 4.75], [2.0, 8.5]]], line_width=2.0)
    # its own snapping: the convention's plays no part
    one = _pixels(line_coverage(scene, Convention(line=rule)))
    assert one == _pixels(line_coverage(scene, Convention(line=rule, subpixel_bits=4, snap_rounding="floor")))
    assert one == _pixels(line_coverage(scene, Convention(line=rule, input="float32")))  # it takes float32 itself


@pytest.mark.parametrize("tie", ["top-left", "bottom-right"])
def test_the_two_triangles_share_the_diagonal(tie: TieRule) -> None:
    """No pixel twice: the quad's diagonal is given to one triangle by the tie rule."""
    a = np.array([[0.5, 0.5], [1.0, 7.0], [2.25, 2.75]])
    b = np.array([[7.5, 7.5], [7.0, 1.0], [6.75, 5.25]])
    coverage = line_coverage(LineScene.from_segments(SIZE, SIZE, a, b), Convention(tie=tie, line="llvmpipe-rectangle"))
    assert coverage.counts(SIZE, SIZE).max() <= 3 and len(_pixels(coverage)) == coverage.n_pixels
