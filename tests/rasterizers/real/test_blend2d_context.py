"""Blend2D (rasterizers.real.blend2d_context): ``blend2d``, area coverage, compared with
the exact area of each pixel; its path API's two fill rules."""

import sys
import time

import numpy as np
import pytest

from harness.contract.scenes import Scene
from harness.engine.registry import Unavailable
from rasterizers.real import blend2d_context
from tests.optional import need
from tests.rasterizers.real._agg_probe import PROBE, H, W, exact_areas, image


@pytest.fixture
def adapter():
    need("blend2d")
    return blend2d_context.Blend2DContext()


def test_a_missing_library_makes_the_adapter_unavailable(monkeypatch):
    monkeypatch.setitem(sys.modules, "blend2d", None)  # import raises ImportError
    with pytest.raises(Unavailable, match="blend2d is not installed"):
        blend2d_context.Blend2DContext()


def test_name_and_mode(adapter):
    assert adapter.name == "blend2d" and adapter.library == "Blend2D" and adapter.coverage_kind == "area"
    assert adapter.library_version.startswith("Blend2D ") and adapter.convention is None


def test_blend2d_alphas_of_a_quarter_offset_triangle(adapter):
    """The coordinate mapping: each alpha within 0.0095 of the exact area of the probe
    triangle (Blend2D's analytic coverage to 8 bits), nothing drawn elsewhere, so no
    half-pixel shift, flip or transposition."""
    alphas = image(adapter.rasterize(Scene(W, H, [PROBE])))
    areas = exact_areas([PROBE])
    assert np.abs(alphas - areas).max() <= 0.0095
    assert np.array_equal(alphas > 0, areas > 0)


def test_the_path_api_honours_both_fill_rules(adapter):
    """Two overlapping squares of one orientation on whole pixels: nonzero fills their
    union, even-odd leaves the overlap empty (the adapter's AA paths, issue 34)."""
    blend2d = need("blend2d")
    a = np.array([[2, 2], [8, 2], [8, 8], [2, 8]], dtype=float)
    b = a + 3
    union = np.zeros((H, W))
    union[2:8, 2:8] = union[5:11, 5:11] = 255
    assert np.array_equal(blend2d_context.fill(blend2d, [a, b], W, H, "nonzero"), union)
    union[5:8, 5:8] = 0
    assert np.array_equal(blend2d_context.fill(blend2d, [a, b], W, H, "evenodd"), union)


def test_a_nan_triangle_draws_nothing_and_an_infinite_one_its_limit(adapter):
    """A NaN vertex: nothing drawn. An infinite vertex: Blend2D draws the limit of the
    triangle as the vertex goes to infinity (the same alphas, within 0.01, as with the
    vertex at 2**20, the largest the harness hands over); no hang either way."""
    tail = [[6.25, 2.25], [2.25, 6.25]]
    start = time.perf_counter()
    cov = adapter.rasterize(Scene(W, H, np.array([[[np.nan, 1.25], *tail], PROBE])))
    assert time.perf_counter() - start < 5 and set(cov.triangle.tolist()) == {1}
    far = image(adapter.rasterize(Scene(W, H, [[[2.0**20, 1.25], *tail]])))
    got = adapter.rasterize(Scene(W, H, [[[np.inf, 1.25], *tail]]))
    assert far.sum() > 10 and np.abs(image(got) - far).max() <= 0.01
