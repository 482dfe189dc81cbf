"""Shared probes of the AGG and Blend2D adapter tests: a triangle whose pixels' exact
areas lie far from 0, 1/2 and the library's quantisation (vertices at whole + 1/4 or
3/4 px, no edge axis-aligned or diagonal), and images of coverage."""

import numpy as np

from harness.contract.conventions import Convention
from harness.contract.scenes import Scene
from harness.oracle.area import area_coverage

W = H = 12
# every pixel it touches has an exact area in [0.058, 0.442] or [0.558, 1]: no pixel
# within 0.057 of being empty or half covered; asymmetric (a flip, a transposition or a
# half-pixel shift moves its pixels)
PROBE = np.array([[9.75, 1.25], [7.75, 7.75], [4.25, 7.25]])


def image(cov, width=W, height=H):
    """(H, W): each pixel's alpha (area coverage) or 1.0 (single coverage), summed over
    primitives."""
    t, x, y = cov.pixels()
    out = np.zeros((height, width))
    np.add.at(out, (y, x), np.ones(t.size) if cov.alpha is None else cov.alpha)
    return out


def exact_areas(positions, width=W, height=H):
    """(H, W): the exact area of each pixel covered by the triangles (summed)."""
    return image(area_coverage(Scene(width, height, positions), Convention(coverage="area")), width, height)


def margin_of_probe():
    """How far the probe's pixel areas lie from 0 (for touched pixels) and from 1/2."""
    areas = exact_areas([PROBE])
    touched = areas[areas > 0]
    return min(touched.min(), np.abs(touched - 0.5).min())
