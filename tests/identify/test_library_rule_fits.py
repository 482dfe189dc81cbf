"""identify's rule probes on the real libraries whose aliased fills are rules read from their
sources (issue 33): each fit exact, input rounding included, and the adapter's FOUND."""

from __future__ import annotations

import numpy as np
import pytest

from harness.contract.scenes import Scene
from harness.identify.rule_probes import fit_rule
from harness.oracle.coverage import exact_coverage
from tests.optional import need

LIBRARIES = [("aggdraw", "agg", "AggAliased"), ("matplotlib", "matplotlib_agg", "MatplotlibAgg"),
             ("pygame", "pygame_draw", "PygameDraw")]


@pytest.mark.parametrize("library, module, cls", LIBRARIES)
def test_the_probes_find_the_adapters_rule_exactly(library, module, cls):
    need(library)
    adapter = __import__(f"rasterizers.real.{module}", fromlist=[cls])
    rasterizer = getattr(adapter, cls)()
    fit = fit_rule(rasterizer.rasterize)
    assert fit.exact and fit.convention == adapter.FOUND, fit.describe()
    assert fit.runner_up is not None and fit.runner_up[1] > 0  # no plain area threshold does it


@pytest.mark.parametrize("library, module, cls", LIBRARIES)
def test_the_found_rule_draws_what_the_library_draws(library, module, cls):
    """Random triangles on screen, off the probes' lattice: float64, 1/256 px and 1/4 px vertices."""
    need(library)
    adapter = __import__(f"rasterizers.real.{module}", fromlist=[cls])
    rasterizer = getattr(adapter, cls)()
    rng = np.random.default_rng(7)
    for n in range(60):
        scale = (None, 256.0, 4.0)[n % 3]
        p = rng.uniform(1, 17, size=(3, 2)) if scale is None else rng.integers(0, int(16 * scale), size=(3, 2)) / scale + 1
        scene = Scene(20, 20, p[None])
        got = rasterizer.rasterize(scene).counts(20, 20) > 0
        want = exact_coverage(scene, adapter.FOUND).counts(20, 20) > 0
        assert np.array_equal(got, want), (p.tolist(), np.argwhere(got != want).tolist())
