"""The area checks on anti-aliased lines (issue 34): accuracy judges line scenes against the
exact stroke areas (harness.oracle.area_lines); the known-bad AA line drawers fail it."""

from typing import Any

import numpy as np
import pytest

from harness.checks.area import accuracy
from harness.checks.area_popping import popping
from harness.contract.case import Case, MotionCase
from harness.contract.scenes import LineScene
from harness.oracle.coverage import exact_coverage
from tests.known_bad.aa_lines import ExactAALines, ForgetsCaps, MajorAxisBoxLines, QuarterPixelLines


def _cases():
    rng = np.random.default_rng(34)
    a = rng.uniform(2, 30, (24, 2))
    b = rng.uniform(2, 30, (24, 2))
    t = np.linspace(0, 2 * np.pi, 13)[:-1]
    fan = np.stack([np.full((12, 2), 16.0), np.stack([16 + 12 * np.cos(t), 16 + 12 * np.sin(t)], axis=1)], axis=1)
    return [
        Case("aa-lines/random-w1", LineScene.from_segments(32, 32, a, b, 1.0)),
        Case("aa-lines/random-w2.5", LineScene.from_segments(32, 32, a, b, 2.5)),
        Case("aa-lines/fan-w1.5", LineScene.from_strips(32, 32, list(fan), 1.5)),
        Case("aa-lines/strip-w0.5", LineScene.from_strips(32, 32, [np.array([[2, 3], [29, 9.5], [4.25, 28], [30, 30]])], 0.5)),
    ]


def _judge(rasterizer, case):
    return accuracy(case, rasterizer.rasterize(case.scene), exact_coverage(case.scene, rasterizer.convention),
                    rasterizer.convention)


@pytest.mark.parametrize("cap", ["butt", "square", "round"])
def test_exact_strokes_pass(cap):
    good = ExactAALines(cap)
    for case in _cases()[: 4 if cap != "round" else 2]:
        result = _judge(good, case)
        assert result.status == "pass", result.message
        assert result.metrics["max_error"] <= 0.5 / 255 + 1e-9


def test_major_axis_box_fails():
    results = [_judge(MajorAxisBoxLines(), case) for case in _cases()]
    assert any(r.status == "fail" for r in results)
    assert max(r.metrics["max_error"] for r in results) > 0.1


def test_forgotten_caps_fail():
    results = [_judge(ForgetsCaps(), case) for case in _cases()]
    assert all(r.status == "fail" for r in results), [r.message for r in results]


def _motion(cap_width=1.5, steps=12):
    a = np.array([[3.0, 4.0], [4.0, 20.0], [2.0, 12.0]])
    b = np.array([[27.0, 9.0], [21.0, 29.0], [28.0, 12.5]])
    shift = np.array([1 / 16, 1 / 48])
    frames: tuple[Any, ...] = tuple(LineScene.from_segments(32, 32, a + k * shift, b + k * shift, cap_width)
                                    for k in range(steps))
    return MotionCase("aa-lines/motion", frames)


def _pops(rasterizer, case):
    conv = rasterizer.convention
    return popping(case.id, list(case.frames), [rasterizer.rasterize(f) for f in case.frames],
                   [exact_coverage(f, conv) for f in case.frames], conv)


def test_popping_exact_strokes_pass():
    result = _pops(ExactAALines(), _motion())
    assert result.status == "pass", result.message


def test_popping_quarter_pixel_lines_fail():
    result = _pops(QuarterPixelLines(), _motion())
    assert result.status == "fail", result.message
    assert result.metrics["alpha_jumps"] > 0
