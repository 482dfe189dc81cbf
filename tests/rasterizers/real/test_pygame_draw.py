"""pygame.draw (rasterizers.real.pygame_draw): the coordinate mapping, the even-odd fill,
1-px lines, the refused stall on a non-finite y, and the upstream repro scripts."""

import sys
import time
from pathlib import Path

import numpy as np
import pytest

from harness.contract.scenes import LineScene, PathScene, Scene, Unsupported
from harness.engine.registry import Unavailable
from rasterizers.real import pygame_draw
from tests.optional import need

ROOT = Path(__file__).parents[3]


@pytest.fixture
def pygame_adapter():
    need("pygame")
    return pygame_draw.PygameDraw()


def pixel_set(cov, primitive=None):
    t, x, y = cov.pixels()
    keep = np.ones(t.size, dtype=bool) if primitive is None else t == primitive
    return set(zip(x[keep].tolist(), y[keep].tolist()))


def star(cx, cy, r):
    a = 4 * np.pi * np.arange(5) / 5
    return np.c_[cx + r * np.sin(a), cy - r * np.cos(a)]


def test_pygame_maps_coordinates_exactly(pygame_adapter):
    """A right triangle with vertices at integer-plus-0.25 is truncated to (2, 1), (9, 1),
    (2, 8), whose edges (axis-aligned and 45 degrees) cross every row at an integer: it
    draws exactly the pixels (i, j) of that closed integer triangle, 1 <= j <= 8,
    2 <= i <= 10 - j. A half-pixel shift (truncating x - 0.5), a flip or a transposition
    would move it. Its mirror image (right angle at the bottom right) checks the other
    edges."""
    scene = Scene(16, 16, [[[2.25, 1.25], [9.25, 1.25], [2.25, 8.25]], [[12.75, 14.75], [12.75, 7.75], [5.75, 14.75]]])
    cov = pygame_adapter.rasterize(scene)
    assert pixel_set(cov, 0) == {(i, j) for j in range(1, 9) for i in range(2, 11 - j)}
    assert pixel_set(cov, 1) == {(i, j) for j in range(7, 15) for i in range(19 - j, 13)}


def test_pygame_fills_even_odd_one_contour(pygame_adapter):
    """Sorted crossings taken in pairs: a pentagram's centre is empty; nonzero scenes and
    paths of several contours are refused."""
    assert pygame_adapter.fill_rules == ("evenodd",)
    cov = pygame_adapter.rasterize(PathScene.from_paths(32, 32, [[star(16, 16, 14)]], "evenodd"))
    got = pixel_set(cov)
    assert (16, 16) not in got and (16, 4) in got
    with pytest.raises(Unsupported, match="evenodd only"):
        pygame_adapter.rasterize(PathScene.from_paths(32, 32, [[star(16, 16, 14)]], "nonzero"))
    square = np.array([[2.0, 2.0], [9.0, 2.0], [9.0, 9.0], [2.0, 9.0]])
    with pytest.raises(Unsupported, match="one contour per call"):
        pygame_adapter.rasterize(PathScene.from_paths(32, 32, [[square, square + 12]], "evenodd"))
    # fewer than three vertices: pygame refuses them; the adapter draws nothing
    assert not pygame_adapter.rasterize(PathScene.from_paths(32, 32, [[square[:2]]], "evenodd")).n_pixels


def test_pygame_lines_are_one_pixel_wide_from_the_truncated_end_points(pygame_adapter):
    """A horizontal and a 45-degree segment: both end pixels (those holding the end
    points) and every pixel between them, one per column; wide lines are refused."""
    scene = LineScene.from_segments(16, 16, [[1.75, 2.25], [3.5, 5.5]], [[9.25, 2.75], [8.5, 10.5]])
    cov = pygame_adapter.rasterize(scene)
    assert pixel_set(cov, 0) == {(i, 2) for i in range(1, 10)}
    assert pixel_set(cov, 1) == {(3 + k, 5 + k) for k in range(6)}
    with pytest.raises(Unsupported, match="hairlines"):
        pygame_adapter.rasterize(LineScene.from_segments(16, 16, [[1.0, 1.0]], [[9.0, 9.0]], line_width=3.0))


def test_a_non_finite_y_is_refused_naming_the_bug_and_its_repro(pygame_adapter):
    """draw.polygon stalls on a NaN or infinite y: refused at once with a RuntimeError
    naming the repro. A NaN or infinite x is handed over: pygame returns at once (and
    draws pixels: a finding the checks record)."""
    for bad in (np.nan, np.inf, -np.inf):
        start = time.monotonic()
        with pytest.raises(RuntimeError, match="pygame_polygon_inf_stall.py"):
            pygame_adapter.rasterize(Scene(16, 16, [[[1.0, 1.0], [5.0, 5.0], [3.0, 9.0]], [[1.0, 1.0], [5.0, bad], [3.0, 10.0]]]))
        with pytest.raises(RuntimeError, match="path 0 has a NaN or infinite y"):
            pygame_adapter.rasterize(PathScene.from_paths(16, 16, [[[[1.0, 1.0], [5.0, bad], [3.0, 10.0]]]], "evenodd"))
        assert time.monotonic() - start < 1.0
    start = time.monotonic()
    cov = pygame_adapter.rasterize(Scene(16, 16, [[[1.0, 1.0], [np.nan, 3.0], [3.0, 10.0]]]))
    assert time.monotonic() - start < 1.0
    assert cov.n_pixels > 0  # the bug of pygame_polygon_nan_draws.py, seen through the adapter


def test_kinds_and_version(pygame_adapter):
    assert pygame_adapter.library == "pygame" and pygame_adapter.name == "pygame"
    assert pygame_adapter.library_version.startswith("2.") and "SDL" in pygame_adapter.library_version
    assert pygame_adapter.scene_kinds == ("triangles", "paths", "lines") and pygame_adapter.line_widths == (1.0,)
    assert pygame_adapter.convention is None and pygame_adapter.coverage_kind == "single"


def test_a_missing_library_makes_the_adapter_unavailable(monkeypatch):
    monkeypatch.setitem(sys.modules, "pygame", None)
    with pytest.raises(Unavailable, match="pygame"):
        pygame_draw.PygameDraw()
