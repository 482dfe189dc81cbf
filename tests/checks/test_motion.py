"""Motion checks: each fails on its known-bad rasterizers and passes on the built-ins."""

import base64
import fnmatch
import io
from typing import Any

import numpy as np
import pytest
from PIL import Image

from cases.motion import motion_cases, rotate, translate, zoom
from harness import run_suite
from harness.checks.motion import filled_direction, jaggy
from harness.contract.case import MotionCase
from harness.contract.coverage import Coverage
from harness.report import pictures
from tests.known_bad.antialiasing import CoarseSupersampleClaimsAnalytic
from tests.known_bad.interpolation import Float32DDA, InterpolationBug
from tests.known_bad.scanlines import ScanlineBug

MOTION = motion_cases(0)

MOTION_TABLE: dict[Any, set[str]] = {  # (keys: known-bad rasterizers of many classes)
    ScanlineBug("no-prestep"): {"jaggy"},              # seed 000's first bug: no subpixel correction
    InterpolationBug("no-subtexel"): {"texel"},        # seed 000's second bug
    InterpolationBug("subtexel-wrong-sign"): {"texel"},
    InterpolationBug("pixel-corner"): {"texel"},
    InterpolationBug("affine"): {"perspective", "texel"},
    Float32DDA(): {"jaggy"},
    CoarseSupersampleClaimsAnalytic(): {"popping"},  # a 4x4 supersampler declared analytic: pops by 1/16
}


# the motion cases where a bug shows (the whole suite flags them too, slower): the coarse
# supersampler pops on every moving case (28 of the 29); three short translations of three
# meshes show it at a tenth of the cost
WHERE_IT_SHOWS = {"bad_no-prestep": "motion/triangle/*", "bad_float32_dda": "motion/tall-triangle/*",
                  "bad_coarse_supersample": "motion/*/translate-x-1/16"}


@pytest.fixture(scope="module")
def motion_flags():
    from harness.checks import Result, checks

    out: dict[str, dict[str, list[Result]]] = {}

    for bad, wanted in MOTION_TABLE.items():
        # only the cases and checks the table names: what must flag it, and nothing else
        mine = [c for c in MOTION if any(check.name in wanted for check in checks(c))
                and fnmatch.fnmatchcase(c.id, WHERE_IT_SHOWS.get(bad.name, "*"))]
        # in-process: none of them hangs or crashes, and a verdict depends only on the
        # coverages drawn (a worker process each would only add its start-up)
        results = run_suite([bad], cases=mine, timeout=30.0, repros=False, only=set(wanted), isolate=False)
        out[bad.name] = {}
        for r in results:
            if r.status in ("fail", "error"):
                out[bad.name].setdefault(r.check, []).append(r)
    return out


@pytest.mark.parametrize("bad", list(MOTION_TABLE), ids=lambda b: b.name)
def test_motion_known_bad_is_flagged(bad, motion_flags):
    missing = MOTION_TABLE[bad] - set(motion_flags[bad.name])
    assert not missing, f"{bad.name} not flagged by {sorted(missing)}"


# the built-ins pass every motion check: tests/engine/test_runner.py (the quick suite holds the
# motion cases; running them again here would prove nothing more)


def test_failures_carry_series_evidence_and_draw_an_animation(motion_flags):
    jump = next(r for r in motion_flags["bad_no-prestep"]["jaggy"] if r.metrics["backward_jumps"])
    assert jump.evidence["backward_jumps"][0].keys() >= {"frame", "row", "column"}
    series = jump.evidence["series"]
    assert len(series["backward_jumps"]) == int(jump.metrics["frames"])
    assert not {"animation", "plot", "images"} & set(jump.evidence)  # the engine draws nothing
    drawn = pictures.draw(jump)
    assert list(drawn) == ["animation", "plot"] and drawn["plot"].startswith("data:image/png;base64,")
    uri = drawn["animation"]
    image = Image.open(io.BytesIO(base64.b64decode(uri.split(",", 1)[1])))
    assert image.format == "GIF" and getattr(image, "n_frames", 1) > 1  # (n_frames: a multi-frame format's)
    texel = motion_flags["bad_no-subtexel"]["texel"][0]
    assert texel.metrics["max_uv_error_texels"] > 0.01 and texel.evidence["mismatches"]


def test_sequences_are_what_they_say():
    tri = np.array([[[1.0, 1.0], [5.0, 1.0], [1.0, 5.0]]])
    frames = translate(tri, (1 / 16, 0.0), 33)
    assert len(frames) == 33 and frames[-1][0, 0, 0] - frames[0][0, 0, 0] == 2.0  # exact, two pixels
    turned = rotate(tri, np.array([3.0, 3.0]), 0.05, 3)
    assert np.allclose(np.linalg.norm(turned[2][0] - 3, axis=1), np.linalg.norm(tri[0] - 3, axis=1))
    grown = zoom(tri, np.array([0.0, 0.0]), 0.01, 3)
    assert np.allclose(grown[2], tri * 1.0201)
    ids = [c.id for c in MOTION]
    assert len(ids) == len(set(ids)) and all(isinstance(c, MotionCase) for c in MOTION)
    assert any(c.perspective for c in MOTION) and {c.texels for c in MOTION} >= {8, 64, 256}


def test_backward_jump_and_flicker_detection():
    def frame(x0):
        return Coverage([0], [0], [x0], [x0 + 3])

    oracle = [frame(x) for x in (0, 0, 1, 1, 2)]
    smooth = [frame(x) for x in (0, 1, 1, 1, 2)]
    backward = [frame(x) for x in (0, 1, 0, 1, 2)]
    assert jaggy("t", smooth, oracle, 1, 8, 1).status == "pass"
    result = jaggy("t", backward, oracle, 1, 8, 1)
    assert result.status == "fail" and result.metrics["backward_jumps"] == 2 and result.metrics["flicker"] > 0


def test_filled_direction_uses_the_nearest_move():
    steps = np.array([[0.0, 0.0], [0.0, -1.0], [1.0, 0.0], [0.0, 0.0]])
    assert filled_direction(steps).tolist() == [[1.0, -1.0], [1.0, -1.0], [1.0, -1.0], [1.0, -1.0]]


OUTSIDE_TEXTURER = """
import numpy as np
from harness import Convention, Coverage
from rasterizers.pineda_topleft import PinedaTopLeft


class CornerTexturer:
    '''Written outside rastercheck: right coverage, but u, v from barycentrics taken at
    the pixel's integer corner.'''
    name = "corner_texturer"
    convention = Convention()

    def rasterize(self, scene):
        cov = PinedaTopLeft().rasterize(Scene_without_attributes(scene))
        if scene.attributes is None:
            return cov
        t, x, y = cov.pixels()
        p = scene.positions[t]
        def area(a, b, c):
            return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        q = np.stack([x, y], axis=1).astype(float)
        l0, l1, l2 = area(p[:, 1], p[:, 2], q), area(p[:, 2], p[:, 0], q), area(p[:, 0], p[:, 1], q)
        total = l0 + l1 + l2
        a = scene.attributes[t]
        values = (l0[:, None] * a[:, 0] + l1[:, None] * a[:, 1] + l2[:, None] * a[:, 2]) / total[:, None]
        return Coverage(cov.triangle, cov.y, cov.x0, cov.x1, values)


def Scene_without_attributes(scene):
    from harness import Scene
    return Scene(scene.width, scene.height, scene.positions)
"""


def test_an_outside_rasterizer_with_a_motion_bug_is_flagged(tmp_path):
    from harness.engine.registry import load

    path = tmp_path / "corner.py"
    path.write_text(OUTSIDE_TEXTURER)
    textured = [c for c in MOTION if c.texels and not c.perspective]
    results = run_suite([load(f"{path}:CornerTexturer")], cases=textured, repros=False, isolate=False)
    assert {r.check for r in results if r.status == "fail"} == {"texel"}
    assert all(r.status == "pass" for r in results if r.check == "jaggy")


def test_motion_checks_on_odd_answers_fail_or_pass_without_crashing():
    """A sequence that covers nothing (a zero-area triangle) is judged, not crashed on, by
    popping; an answer with one attribute column where u, v are due fails texel saying so."""
    from harness.contract.scenes import Scene
    from tests.known_bad.misc import NaNAttributes

    flat = np.array([[[13.5, 8.75], [18.0, 11.0], [14.5, 9.25]]])  # collinear: zero area
    frames = tuple(Scene(32, 32, flat + [k / 16, 0]) for k in range(4))
    popping = run_suite(["supersample4"], cases=[MotionCase("motion/flat", frames)], isolate=False, identify=False, repros=False)
    assert [r.status for r in popping if r.check == "popping"] == ["pass"]
    quad = np.array([[[2.0, 2.0], [20.0, 3.0], [4.0, 22.0]]])
    uv = np.array([[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]])
    textured = MotionCase("motion/uv", tuple(Scene(32, 32, quad + [k / 16, 0], uv) for k in range(3)), texels=8)
    texel = [r for r in run_suite([NaNAttributes()], cases=[textured], isolate=False, identify=False, repros=False)
             if r.check == "texel"]
    assert texel and texel[0].status in ("fail",) and "attribute" in texel[0].message


def test_the_plain_motion_cases_are_the_same_without_the_meshes() -> None:
    every, plain = motion_cases(0), motion_cases(0, meshes=False)
    assert plain and [m.id for m in plain] == [m.id for m in every][:len(plain)]
    assert not any(m.id.startswith(("motion/icosphere", "motion/textured", "motion/tall")) for m in plain)
    for a, b in zip(plain, every):
        assert all(np.array_equal(x.positions, y.positions) for x, y in zip(a.frames, b.frames))
