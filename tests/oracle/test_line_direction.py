"""The direction of travel of Bresenham lines (issue 28, point 7): ``LineRule(direction=...)``
for drawers that normalise it as textbooks' plotLine does (from the end point with smaller
x, or with smaller major coordinate), validated, described and serialised with the rule;
the exact oracle against a brute-force reference written from the definition, on lattice
and tie-hitting segments; two textbook drawers kept in tests/textbook_lines.py pass the
quick line suite declared with it and are identified exactly, fail it declared without it
(the reversal check and identify name the direction); a drawer that normalises
inconsistently fails; a direction-preserving Bresenham is still identified as such."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from cases.lines import line_cases
from harness.contract.conventions import BRESENHAM_ROUNDINGS, BRESENHAM_TIES, LINE_DIRECTIONS, Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from harness.engine.runner import run_suite
from harness.identify.fingerprint import identify
from harness.oracle.bresenham_lines import _round_pixel_rational, bresenham_spans, bresenham_spans_rational, walks_backwards
from harness.oracle.coverage import exact_coverage
from rasterizers.lines import BresenhamLines
from tests.known_bad.lines import SwapsShallowOnly
from tests.textbook_lines import TextbookPlotLine, WikipediaPlotLine

SIZE = 10
QUICK = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ROOT = Path(__file__).resolve().parents[2]


def _pixels(coverage: Coverage) -> set[tuple[int, int, int]]:
    return set(zip(*(v.tolist() for v in coverage.pixels())))


def _spans_pixels(spans) -> set[tuple[int, int, int]]:  # type: ignore[no-untyped-def]
    return {(int(s), x, int(y)) for s, y, x0, x1 in zip(*spans) for x in range(int(x0), int(x1))}


# -- the rule: validated, described, serialised ---------------------------------------------------


def test_direction_is_one_value_of_the_line_rule_validated_and_described() -> None:
    rule = LineRule("bresenham", rounding="floor", direction="smaller-x")
    assert rule.direction == "smaller-x" and LineRule("bresenham").direction == "as-given"
    assert rule == eval(repr(rule), {"LineRule": LineRule})  # repr round-trips, direction included
    assert "direction='smaller-major'" in repr(Convention(line=LineRule("bresenham", direction="smaller-major")))
    assert rule.describe() == ("Bresenham lines walked from the end point with smaller x, end points to pixels by floor, "
                               "ties step, last pixel drawn")
    assert LineRule("bresenham", last_pixel=False, direction="smaller-major").describe().endswith(
        "walked from the end point with smaller major coordinate, end points to pixels by nearest-even, ties step, "
        "last pixel omitted (the end walked to)")
    assert "walked" not in LineRule("bresenham").describe()  # as given: the words of before
    with pytest.raises(ValueError, match=r"LineRule.direction must be one of as-given, smaller-x, smaller-major, not 'left'"):
        LineRule("bresenham", direction="left")  # type: ignore[arg-type]
    for rule_name in ("diamond-exit", "rectangle"):
        with pytest.raises(ValueError, match=f"direction 'smaller-x' is a Bresenham option; {rule_name} lines"):
            LineRule(rule_name, direction="smaller-x")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="direction must be one of"):
        bresenham_spans([[0, 0]], [[3, 1]], 4, 4, direction="backwards")  # type: ignore[arg-type]


def test_walks_backwards_decides_on_the_end_pixels() -> None:
    p0 = np.array([[5, 0], [0, 5], [3, 9], [3, 1], [4, 4]])
    p1 = np.array([[0, 2], [2, 0], [3, 1], [3, 9], [0, 0]])
    assert walks_backwards(p0, p1, "as-given").tolist() == [False] * 5
    assert walks_backwards(p0, p1, "smaller-x").tolist() == [True, False, False, False, True]  # equal x: as given
    assert walks_backwards(p0, p1, "smaller-major").tolist() == [True, True, True, False, True]  # a diagonal is x-major
    huge = np.array([[10**40, 0]], dtype=object), np.array([[0, 10**40 + 1]], dtype=object)  # y-major, exactly
    assert walks_backwards(*huge, "smaller-major").tolist() == [False] and walks_backwards(*huge, "smaller-x").tolist() == [True]


# -- the oracle against a brute-force reference ---------------------------------------------------


def _brute_force(a: tuple[float, float], b: tuple[float, float], rounding: str, ties: str, last_pixel: bool,
                 direction: str) -> set[tuple[int, int, int]]:
    """The definition, pixel by pixel in rationals: the end points' pixels, the walk's start
    chosen by ``direction`` on them, then at step k (0..K, the last only with
    ``last_pixel``) the minor offset k*M/K rounded to nearest, halves away from the start
    (``step``) or towards it (``stay``)."""
    p = [tuple(_round_pixel_rational(Fraction(v), rounding) for v in q) for q in (a, b)]
    x_major = abs(p[1][0] - p[0][0]) >= abs(p[1][1] - p[0][1])
    major = 0 if x_major else 1
    if (direction == "smaller-x" and p[0][0] > p[1][0]) or (direction == "smaller-major" and p[0][major] > p[1][major]):
        p.reverse()
    (u0, v0), (u1, v1) = ((q[major], q[1 - major]) for q in p)
    big_k, big_m = abs(u1 - u0), abs(v1 - v0)
    su, sv = (1 if u1 >= u0 else -1), (1 if v1 >= v0 else -1)
    out = set()
    for k in range(big_k + 1 if last_pixel else big_k):
        exact = Fraction(k * big_m, big_k) if big_k else Fraction(0)
        offset = math.floor(exact + Fraction(1, 2)) if ties == "step" else math.ceil(exact - Fraction(1, 2))  # halves up / down
        u, v = u0 + su * k, v0 + sv * offset
        x, y = (u, v) if x_major else (v, u)
        if 0 <= x < SIZE and 0 <= y < SIZE:
            out.add((0, x, y))
    return out


quarter = st.integers(-8, 4 * SIZE + 8).map(lambda k: k / 4)


@st.composite
def tie_segment(draw):  # type: ignore[no-untyped-def]
    """A segment on the 1/4 px lattice, half of them an integer vector of slope +-1/2 or
    +-2 (a Bresenham tie every other step) or +-1, or axis-aligned, from anywhere."""
    a = (draw(quarter), draw(quarter))
    if draw(st.booleans()):
        return a, (draw(quarter), draw(quarter))
    k = draw(st.integers(1, 4)) * draw(st.sampled_from([-1, 1]))
    m = draw(st.sampled_from([-1, 1]))
    dx, dy = draw(st.sampled_from([(2 * k, k * m), (k, 2 * k * m), (k, k * m), (2 * k, 0), (0, 2 * k)]))
    return a, (a[0] + dx, a[1] + dy)


@QUICK
@given(tie_segment(), st.sampled_from(BRESENHAM_ROUNDINGS), st.sampled_from(BRESENHAM_TIES), st.booleans(),
       st.sampled_from(LINE_DIRECTIONS))
@example(((9.5, 5.5), (1.5, 1.5)), "nearest-even", "step", True, "smaller-x")  # right to left through ties
@example(((9.5, 0.5), (5.5, 8.5)), "floor", "stay", False, "smaller-major")  # y-major from the smaller x, larger y
@example(((6.0, 8.5), (6.0, 1.5)), "floor", "step", False, "smaller-x")  # vertical: the given order kept
def test_the_oracle_walks_as_the_definition_says(seg, rounding, ties, last_pixel, direction) -> None:  # type: ignore[no-untyped-def]
    a, b = seg
    want = _brute_force(a, b, rounding, ties, last_pixel, direction)
    assert _spans_pixels(bresenham_spans([a], [b], SIZE, SIZE, rounding, ties, last_pixel, direction)) == want
    assert _spans_pixels(bresenham_spans_rational([a], [b], SIZE, SIZE, rounding, ties, last_pixel, direction)) == want
    rule = LineRule("bresenham", last_pixel=last_pixel, rounding=rounding, ties=ties, direction=direction)
    scene = LineScene.from_segments(SIZE, SIZE, [a], [b])
    assert _pixels(exact_coverage(scene, Convention(line=rule))) == want
    backwards = _spans_pixels(bresenham_spans([b], [a], SIZE, SIZE, rounding, ties, last_pixel, direction))
    assert backwards == _brute_force(b, a, rounding, ties, last_pixel, direction)
    same_x = _round_pixel_rational(Fraction(a[0]), rounding) == _round_pixel_rational(Fraction(b[0]), rounding)
    if direction == "smaller-major" or (direction == "smaller-x" and (last_pixel or not same_x)):
        # a normalising drawer draws a segment and its reverse alike (walking from the smaller x, one whose end
        # pixels share their x keeps its given order: the end pixel it omits is its own)
        assert backwards == want


@QUICK
@given(st.lists(tie_segment(), min_size=1, max_size=6))
def test_the_textbook_drawers_draw_what_they_declare(segs) -> None:  # type: ignore[no-untyped-def]
    """Two implementations apart: the textbook kernels and the oracle."""
    scene = LineScene.from_segments(SIZE, SIZE, [s[0] for s in segs], [s[1] for s in segs])
    for drawer in (TextbookPlotLine(), WikipediaPlotLine()):
        assert _pixels(drawer.rasterize(scene)) == _pixels(exact_coverage(scene, drawer.convention)), drawer.name


def test_far_segments_are_walked_in_the_declared_direction() -> None:
    """End pixels beyond the compiled kernels' 2**30 (Python integers in closed form):
    walking from the smaller x (major coordinate) equals drawing the segment given from
    that end, and differs from walking as given (ties every other step on screen)."""
    a = np.array([[2.0**40 + 0.5, 2.0**39 + 3.5], [9.5, 0.5], [-2.0**31 + 0.5, 4.5 - 2.0**30]])
    b = np.array([[0.5, 3.5], [9.5 - 2.0**43, 0.5 + 2.0**44], [9.5, 4.5]])
    scene = LineScene.from_segments(SIZE, SIZE, a, b)
    for direction, backwards in (("smaller-x", [True, True, False]), ("smaller-major", [True, False, False])):
        rule = LineRule("bresenham", rounding="floor", ties="stay", last_pixel=False, direction=direction)
        as_given = Convention(line=replace(rule, direction="as-given"))
        back = walks_backwards(np.floor(a).astype(np.int64).astype(object), np.floor(b).astype(np.int64).astype(object),
                               direction)
        assert back.tolist() == backwards
        start, end = np.where(back[:, None], b, a), np.where(back[:, None], a, b)
        got = _pixels(exact_coverage(scene, Convention(line=rule)))
        assert got == _pixels(exact_coverage(LineScene.from_segments(SIZE, SIZE, start, end), as_given)), direction
        assert got != _pixels(exact_coverage(scene, as_given)) and {s for s, _, _ in got} == {0, 1, 2}, direction


# -- the textbook drawers through run and identify ------------------------------------------------


@pytest.fixture(scope="module")
def quick_lines() -> list:
    return line_cases(0)


class AsGiven(TextbookPlotLine):
    """The textbook plotLine declared as walking as given (the issue's user)."""

    name = "textbook_declared_as_given"
    convention = Convention(line=LineRule("bresenham", rounding="floor", ties="step"))


def _failing(rasterizer, cases):  # type: ignore[no-untyped-def]
    results = run_suite([rasterizer], cases=cases, isolate=False, identify=False, repros=False)
    return results, [r for r in results if r.status not in ("pass", "skip")]


@pytest.mark.parametrize("drawer", [TextbookPlotLine(), WikipediaPlotLine()], ids=lambda d: d.name)
def test_a_textbook_plotline_declared_with_its_direction_passes_the_quick_line_suite(drawer, quick_lines) -> None:  # type: ignore[no-untyped-def]
    results, failing = _failing(drawer, quick_lines)
    assert not failing, [(r.case, r.check, r.message) for r in failing]
    assert {"conformance", "reversal", "joints", "length", "connectivity"} <= {r.check for r in results}
    same = [r for r in results if r.check == "reversal" and r.status == "pass"]
    assert same and all(r.metrics["reversal_pixels"] == 0 for r in same)  # the same pixels both ways, as predicted


def test_the_same_drawer_declared_as_walking_as_given_fails_and_is_told_the_direction(quick_lines) -> None:  # type: ignore[no-untyped-def]
    _, failing = _failing(AsGiven(), quick_lines)
    checks = {r.check for r in failing}
    assert {"conformance", "reversal"} <= checks, checks
    named = [r for r in failing if r.check == "reversal" and r.evidence.get("direction") == "smaller-x"]
    assert named and "walked from the end point with smaller x: declare LineRule(..., direction='smaller-x')" in named[0].message


def test_a_drawer_that_normalises_inconsistently_fails(quick_lines) -> None:  # type: ignore[no-untyped-def]
    _, failing = _failing(SwapsShallowOnly(), quick_lines)
    assert {"conformance", "reversal"} <= {r.check for r in failing}
    # its steep segments given from the larger x break ties the other way: no direction explains it
    assert all("direction" not in r.evidence for r in failing if r.check == "reversal")
    fp = identify(SwapsShallowOnly())
    assert not fp.line_fit.exact and fp.line_fit.residual > 0, fp.card()


def test_identify_tells_a_textbook_plotline_from_a_direction_preserving_bresenham() -> None:
    for drawer in (TextbookPlotLine(), WikipediaPlotLine(), AsGiven()):
        fp = identify(drawer)
        fit = fp.line_fit
        walked = TextbookPlotLine.convention if isinstance(drawer, TextbookPlotLine) else drawer.convention
        assert fit.exact and fit.residual == 0 and fit.runner_up[1] > 0, fp.card()
        assert fp.line_convention == walked, fp.card()  # AsGiven's declaration is not what it does
        said = fp.to_dict()["line_convention"]
        json.dumps(said)
        assert said["direction"] == walked.line.direction and said["exact"]
        assert walked.line.walk in fp.facts["lines"] and walked.line.walk in fp.card()
        # the same rule walked as given explains it worse
        as_given = replace(walked, line=replace(walked.line, direction="as-given"))
        assert sum(d.mismatches(as_given) for d in fit.drawn if d.coverage is not None) > 0
    fp = identify(BresenhamLines(rounding="floor"))  # walks as given: not misread as normalising
    assert fp.line_fit.exact and fp.line_rule == LineRule("bresenham", rounding="floor"), fp.card()
    assert fp.to_dict()["line_convention"]["direction"] == "as-given" and "walked" not in fp.facts["lines"]


# -- the README's picture -------------------------------------------------------------------------


def test_the_direction_picture_script_runs(tmp_path: Path) -> None:
    out = tmp_path / "line-direction.png"
    done = subprocess.run([sys.executable, str(ROOT / "docs" / "line_direction.py"), str(out)], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 1000
    assert "differ" in done.stdout  # it says how many pixels the two directions part on
