"""skia's supersampler as tiny-skia runs it (issue 34, harness.oracle.supersample_models): the
compiled oracle against the uncompiled reference and against exact sub-sample counts
(Fractions), the convention's declaration, tiny-skia itself, and the known-bad supersamplers
caught by accuracy."""

from __future__ import annotations

import functools
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from cases.suites import suite
from harness.contract.conventions import Convention
from harness.contract.coverage_models import SKIA_SUPERSAMPLED_AREA, model_for
from harness.contract.scenes import PathScene, Scene
from harness.oracle.coverage import exact_coverage
from harness.oracle.supersample_models import (
    path_levels,
    reference_levels,
    skia_supersampled_coverage,
    skia_supersampled_paths,
)
from tests.accuracy_runs import assert_judged_by_accuracy
from tests.known_bad.supersample_models import EightSubScanlines, FlooredSubPixels, SampleCountLevels
from tests.optional import need

W = H = 8


def _alpha(coverage: Any) -> Any:
    assert coverage.alpha is not None
    return coverage.alpha


TINY = Convention(coverage="area", supersample=2, input="float32")

# vertices on 1/4 px (sub-pixel boundaries: ties with the sub-sample spans on purpose), on
# 1/256 px (tiny-skia's input grid) and anywhere
_coordinate = st.one_of(st.integers(0, W * 4).map(lambda v: v / 4), st.integers(0, W * 256).map(lambda v: v / 256),
                        st.floats(0.0, float(W), allow_nan=False))
_contour = st.lists(st.tuples(_coordinate, _coordinate), min_size=2, max_size=7)
_path = st.lists(_contour, min_size=1, max_size=3)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_path, st.sampled_from(["nonzero", "evenodd"]), st.sampled_from([1, 2, 3]))
@example([[(0.0, 0.0), (2.0, 0.0), (0.0, 1.0)]], "nonzero", 2)
@example([[(1.0, 1.0), (5.0, 1.0), (5.0, 5.0)], [(1.0, 1.0), (5.0, 5.0), (1.0, 5.0)]], "nonzero", 2)  # a shared diagonal
@example([[(2.375, 1.0), (6.0, 2.375), (2.375, 6.0)], [(2.375, 1.0), (2.375, 6.0), (0.5, 3.0)]], "evenodd", 2)
def test_the_compiled_oracle_is_the_reference(contours, fill_rule, shift):
    path = [np.array(c, dtype=np.float64) for c in contours]
    compiled = path_levels(path, W, H, fill_rule, shift)
    assert np.array_equal(compiled, reference_levels(path, W, H, fill_rule, shift))


def _winding(contours: list[list[tuple[Fraction, Fraction]]], px: Fraction, py: Fraction) -> int:
    """The winding number of the point (crossings of the ray to the right), exactly."""
    w = 0
    for c in contours:
        for k in range(len(c)):
            (ax, ay), (bx, by) = c[k], c[(k + 1) % len(c)]
            if (ay <= py) != (by <= py):
                x = ax + (py - ay) * (bx - ax) / (by - ay)
                if x > px:
                    w += 1 if by > ay else -1
    return w


_rect = st.tuples(st.integers(0, 4 * W), st.integers(0, 4 * H), st.integers(1, 4 * W), st.integers(1, 4 * H))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_rect, min_size=1, max_size=4), st.sampled_from(["nonzero", "evenodd"]), st.booleans())
def test_rectilinear_paths_count_their_sub_samples(rects, fill_rule, reverse):
    """Axis-aligned contours on the 1/4 px lattice pass through no sub-sample centre and the DDA
    is exact: a pixel's level is within one level of 255 N / 16, N its sub-sample centres
    (i + (q + 1/2)/4, j + (k + 1/2)/4) where the fill rule holds (Fractions), as the
    supersampler's blit_h sums them (16 each, 63 for a full pixel's last sub-row)."""
    contours: list[list[tuple[Fraction, Fraction]]] = []
    for x, y, w, h in rects:
        x1, y1 = min(x + w, 4 * W), min(y + h, 4 * H)
        if x1 <= x or y1 <= y:
            continue
        c = [(Fraction(x, 4), Fraction(y, 4)), (Fraction(x1, 4), Fraction(y, 4)), (Fraction(x1, 4), Fraction(y1, 4)),
             (Fraction(x, 4), Fraction(y1, 4))]
        contours.append(c[::-1] if reverse and len(contours) % 2 else c)
    if not contours:
        return
    levels = path_levels([np.array([[float(a), float(b)] for a, b in c]) for c in contours], W, H, fill_rule)
    for j in range(H):
        for i in range(W):
            n = 0
            for k in range(4):
                for q in range(4):
                    w = _winding(contours, i + Fraction(2 * q + 1, 8), j + Fraction(2 * k + 1, 8))
                    n += (w % 2 == 1) if fill_rule == "evenodd" else (w != 0)
            assert abs(Fraction(int(levels[j, i])) - Fraction(255 * n, 16)) <= 1, (i, j, n, levels[j, i])


def test_the_convention_and_its_model():
    assert TINY.model is SKIA_SUPERSAMPLED_AREA and model_for("area", False, 0, 2) is SKIA_SUPERSAMPLED_AREA
    assert TINY.coverage_kind == "area" and SKIA_SUPERSAMPLED_AREA.quantum == 255 and SKIA_SUPERSAMPLED_AREA.paths
    assert "supersample=2" in repr(TINY) and "skia's supersampler (4 sub-scanlines" in TINY.describe()
    assert Convention(coverage="area").model is not SKIA_SUPERSAMPLED_AREA  # the default changes nothing
    bads: list[dict[str, Any]] = [dict(supersample=5), dict(supersample=-1), dict(supersample=True),
                                  dict(supersample=2, rows=15), dict(supersample=2, samples=4),
                                  dict(supersample=2, coverage="sample")]
    for bad in bads:
        with pytest.raises(ValueError):
            Convention(**{"coverage": "area", **bad})


def test_a_triangle_is_its_one_contour_path_and_the_oracle_is_exact_coverage():
    tri = np.array([[0.3, 0.7], [7.6, 2.2], [2.9, 7.4]])
    triangles = exact_coverage(Scene(W, H, tri[None]), TINY)
    paths = exact_coverage(PathScene.from_paths(W, H, [[tri]]), TINY)
    for a, b in ((triangles, skia_supersampled_coverage(Scene(W, H, tri[None]), TINY)),
                 (paths, skia_supersampled_paths(PathScene.from_paths(W, H, [[tri]]), TINY)), (triangles, paths)):
        assert np.array_equal(a.y, b.y) and np.array_equal(a.x0, b.x0) and np.array_equal(_alpha(a), _alpha(b))


def test_culling_non_finite_and_nearly_flat_paths():
    tri = np.array([[[0.5, 0.5], [6.5, 1.5], [2.5, 6.5]]])
    assert _alpha(exact_coverage(Scene(W, H, tri), TINY)).size
    assert not _alpha(exact_coverage(Scene(W, H, tri), Convention(coverage="area", supersample=2, cull="cw"))).size
    assert not _alpha(exact_coverage(Scene(W, H, tri[:, ::-1]), Convention(coverage="area", supersample=2, cull="ccw"))).size
    nan = tri.copy()
    nan[0, 0, 0] = np.nan
    assert not _alpha(exact_coverage(Scene(W, H, nan), TINY)).size
    flat = np.array([[[0.5, 2.0], [6.5, 2.0 + 2**-13], [2.5, 2.0]]])  # 2**-13 tall: is_nearly_zero
    assert not _alpha(exact_coverage(Scene(W, H, flat), TINY)).size


def test_paths_leaving_the_screen_keep_only_its_pixels():
    path = [np.array([[-5.3, 1.2], [6.1, 2.7], [2.2, 7.6]])]
    inside = path_levels(path, W, H)
    assert inside[:, 0].any() and np.array_equal(inside, reference_levels(path, W, H))
    thin = [np.array([[20.7, 75.9], [59.6, 115.1], [-15.1, 32.2]])]  # inside the screen only where x < 0
    assert not path_levels(thin, 4, 96)[33:45, 0].any()


# -- tiny-skia itself (resvg) ------------------------------------------------------------------


@pytest.fixture(scope="module")
def smooth() -> Any:
    need("resvg_py")
    need("PIL")
    from rasterizers.real import tiny_skia

    return tiny_skia.TinySkiaAntialiased()


def _image(coverage, width, height):
    out = np.zeros((height, width), dtype=np.int64)
    _, x, y = coverage.pixels()
    np.add.at(out, (y, x), np.rint(np.asarray(coverage.alpha) * 255).astype(np.int64))
    return out


def test_tiny_skia_is_its_model_exactly(smooth):
    """Random float and lattice triangles inside the screen: every level the model's."""
    rng = np.random.default_rng(34)
    tris = np.concatenate([rng.uniform(2.0, 30.0, (40, 3, 2)), rng.integers(8, 120, (40, 3, 2)) / 4.0])
    scene = Scene(32, 32, tris)
    got, want = smooth.rasterize(scene), exact_coverage(scene, smooth.convention)
    for t in range(len(scene)):
        g = got.take(np.flatnonzero(got.primitive == t))
        w = want.take(np.flatnonzero(want.primitive == t))
        assert np.array_equal(_image(g, 32, 32), _image(w, 32, 32)), t


def test_tiny_skia_paths_are_their_model_exactly():
    """Paths drawn by resvg directly (both fill rules, overlapping contours, shared edges)."""
    resvg = need("resvg_py")
    need("PIL")
    import io

    from PIL import Image

    rng = np.random.default_rng(7)
    for k in range(60):
        rule = ("nonzero", "evenodd")[k % 2]
        if k >= 30:  # past the screen's sides (the edge clipper), huge, slivers and sub-pixel paths
            sliver = rng.uniform(0.0, 16.0, (3, 2))
            sliver[2] = (sliver[0] + sliver[1]) / 2 + rng.normal(0.0, 1e-3, 2)
            contours = [(rng.uniform(-4.0, 20.0, (7, 2)), rng.uniform(-3000.0, 3000.0, (3, 2)), sliver,
                         5.0 + rng.uniform(0.0, 0.8, (3, 2)))[k % 4]]
        else:
            contours = [rng.integers(4, 60, (int(rng.integers(3, 8)), 2)) / 4.0 if k % 3 else rng.uniform(1.0, 15.0, (6, 2))
                        for _ in range(int(rng.integers(1, 4)))]
        d = " ".join("M " + " L ".join(f"{float(x)!r} {float(y)!r}" for x, y in c) + " Z" for c in contours)
        svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="16" height="16" viewBox="0 0 16 16">'
               f'<path d="{d}" fill="#000" fill-rule="{rule}"/></svg>')
        png = resvg.svg_to_bytes(svg_string=svg, skip_system_fonts=True)
        alpha = np.asarray(Image.open(io.BytesIO(png)).convert("RGBA"))[:, :, 3].astype(np.int64)
        assert np.array_equal(alpha, path_levels(contours, 16, 16, rule)), k


# -- accuracy against the declared model, and its known-bads -----------------------------------


@functools.cache
def _cases() -> list[Any]:
    return [c for c in suite("quick") if c.id.startswith(("float/random", "lattice/bits-2"))][:3]


class _Exact:
    name = "exact_skia_supersampler"
    convention = TINY
    interpolates = False

    def rasterize(self, scene: Scene) -> Any:
        return skia_supersampled_coverage(scene, self.convention)


@pytest.mark.parametrize("rasterizer, passes", [(_Exact(), True), (EightSubScanlines(), False), (FlooredSubPixels(), False),
                                                (SampleCountLevels(), False)],
                         ids=["exact", "eight-sub-scanlines", "floored-sub-pixels", "sample-count-levels"])
def test_accuracy_judges_the_supersampler_and_catches_its_known_bads(rasterizer, passes):
    assert_judged_by_accuracy(rasterizer, _cases(), passes)


def test_accuracy_on_paths_judges_the_model():
    from harness.checks.area_paths import path_accuracy
    from harness.contract.case import Case

    scene = PathScene.from_paths(W, H, [[[[0.3, 0.2], [7.7, 1.1], [4.2, 7.9]], [[2.0, 2.0], [5.0, 2.5], [3.0, 5.5]]]],
                                 "evenodd")
    case = Case("paths/test", scene)
    oracle = exact_coverage(scene, TINY)
    assert path_accuracy(case, oracle, oracle, TINY).status == "pass"
    moved = exact_coverage(PathScene(W, H, scene.vertices + 0.25, scene.contour_sizes, scene.contour_path, "evenodd"), TINY)
    assert path_accuracy(case, moved, oracle, TINY).status == "fail"


# -- skia-python: analytic AA, no supersampler model (SKIA_AAA_NOTE) ----------------------------


def test_skia_python_is_not_the_supersampler_nor_within_a_level_of_an_area():
    """The closing note's numbers, on one triangle: skia's alphas are not the supersampler's,
    not sample counts (levels off multiples of 16), and stray from the exact area of the
    triangle with y snapped to 1/4 px by far more than a level."""
    skia = need("skia")
    from harness.oracle.area import exact_area
    from rasterizers.real.adapters import _skia_fill

    tri = np.array([[2.3, 1.7], [13.6, 4.2], [5.1, 12.9]])
    alpha = _skia_fill(skia, [tri], 16, 16, True).astype(np.int64)
    model = path_levels([tri], 16, 16)
    assert (alpha != model).sum() >= 28  # of the triangle's 36 edge pixels
    assert (alpha[12, 5], model[12, 5]) == (155, 96) and abs(float(exact_area(tri, 5, 12)) * 255 - 118.75) < 0.01
    assert any(v % 16 and v != 255 for v in alpha.ravel().tolist())
    snapped = tri.copy()
    snapped[:, 1] = np.round(snapped[:, 1] * 4) / 4
    assert abs(alpha[12, 5] - float(exact_area(snapped, 5, 12)) * 255) > 8
