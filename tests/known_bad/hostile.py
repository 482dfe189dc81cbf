"""Hostile plugins: answers and failures meant to exhaust or crash the harness.

Each must end in a clear verdict or error naming it, within bounded time and memory,
and the run must go on (tests/acceptance/test_hostile.py).
"""

from __future__ import annotations

import numpy as np

from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers.pineda_topleft import PinedaTopLeft


class _Base:
    convention = PinedaTopLeft().convention

    def __init__(self) -> None:
        self.name = type(self).__name__


class HugeSpan(_Base):
    """One span of 10**8 pixels per triangle (the row it starts on is right)."""

    def rasterize(self, scene: Scene) -> Coverage:
        n = len(scene)
        return Coverage(np.arange(n), np.full(n, scene.height // 2), np.zeros(n, np.int64), np.full(n, 10**8))


class Copies(_Base):
    """The correct answer, plus ``copies`` copies of its first span."""

    copies = 1000

    def rasterize(self, scene: Scene) -> Coverage:
        right = PinedaTopLeft().rasterize(scene)
        if len(right) == 0:
            return right
        k = self.copies
        return Coverage(np.concatenate([right.triangle, np.repeat(right.triangle[:1], k)]),
                        np.concatenate([right.y, np.repeat(right.y[:1], k)]),
                        np.concatenate([right.x0, np.repeat(right.x0[:1], k)]),
                        np.concatenate([right.x1, np.repeat(right.x1[:1], k)]))


class MillionCopies(Copies):
    """A million copies: more spans than any answer could need."""

    copies = 10**6


class FarAway(_Base):
    """Spans far outside the viewport, 1000 per triangle."""

    def rasterize(self, scene: Scene) -> Coverage:
        n = 1000 * len(scene)
        t = np.repeat(np.arange(len(scene)), 1000)
        y = np.tile(np.arange(1000) * 10**6, len(scene))
        return Coverage(t, y, np.full(n, -(10**12)), np.full(n, 10**12))


class BeyondReach(_Base):
    """The correct answer, plus for each triangle a span on screen but far from it."""

    def rasterize(self, scene: Scene) -> Coverage:
        right = PinedaTopLeft().rasterize(scene)
        n = len(scene)
        far_x = np.where(scene.positions[:, :, 0].max(axis=1) < scene.width / 2, scene.width - 2, 0).astype(np.int64)
        far_y = np.where(scene.positions[:, :, 1].max(axis=1) < scene.height / 2, scene.height - 1, 0).astype(np.int64)
        return Coverage(np.concatenate([right.triangle, np.arange(n)]), np.concatenate([right.y, far_y]),
                        np.concatenate([right.x0, far_x]), np.concatenate([right.x1, far_x + 1]))


class _Unpicklable(Exception):
    def __init__(self, a: int, b: int) -> None:  # pickling calls __init__ with one argument
        super().__init__(f"{a}, {b}")


class RaisesUnpicklable(_Base):
    def rasterize(self, scene: Scene) -> Coverage:
        raise _Unpicklable(1, 2)


class _Unprintable(Exception):
    def __str__(self) -> str:
        raise RuntimeError("no text for you")


class RaisesUnprintable(_Base):
    def rasterize(self, scene: Scene) -> Coverage:
        raise _Unprintable()


class RaisesKeyboardInterrupt(_Base):
    def rasterize(self, scene: Scene) -> Coverage:
        raise KeyboardInterrupt


class ExitsWithSystemExit(_Base):
    def rasterize(self, scene: Scene) -> Coverage:
        raise SystemExit(0)


class NaNEverywhere(_Base):
    """Correct coverage, every attribute NaN."""

    def rasterize(self, scene: Scene) -> Coverage:
        right = PinedaTopLeft().rasterize(scene)
        if right.attributes is None:
            return right
        return Coverage(right.triangle, right.y, right.x0, right.x1, np.full(right.attributes.shape, np.nan))


HOSTILE = (HugeSpan, Copies, MillionCopies, BeyondReach, FarAway, RaisesUnpicklable, RaisesUnprintable, RaisesKeyboardInterrupt,
           ExitsWithSystemExit, NaNEverywhere)
