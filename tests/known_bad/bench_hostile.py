"""Hostile rasterizers for ``rastercheck bench`` (tests/acceptance/test_bench_hostile.py): each fails
its calls in one way -- a raise, a ``None`` answer, a segfault, ``os._exit(0)``, a hang,
or a segfault only once it has answered -- and the bench must report it as that
contender's row and go on with the others."""

from __future__ import annotations

import ctypes
import faulthandler
import os
import time

from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers.pineda_topleft import PinedaTopLeft
from tests.known_bad.hostile import _Base  # a correct declaration, named after the class

__all__ = ["BenchRaises", "BenchAnswersNone", "BenchSegfaults", "BenchExits", "BenchHangs", "BenchCrashesWhenWarm",
           "BenchExitsOnPaths"]


class BenchRaises(_Base):
    """Raises on every call."""

    def rasterize(self, scene: Scene) -> Coverage:
        raise ValueError(f"refuses {len(scene)} triangles")


class BenchAnswersNone(_Base):
    """Answers ``None`` instead of a coverage."""

    def rasterize(self, scene: Scene) -> Coverage:
        return None  # type: ignore[return-value]


class BenchSegfaults(_Base):
    """Reads address 0: its process dies of SIGSEGV."""

    def rasterize(self, scene: Scene) -> Coverage:
        faulthandler.disable()  # the crash alone, without pytest's dump of every thread
        ctypes.string_at(0)
        raise AssertionError("unreachable")


class BenchExits(_Base):
    """Ends its process with exit code 0, as if all were well."""

    def rasterize(self, scene: Scene) -> Coverage:
        os._exit(0)


class BenchHangs(_Base):
    """Never answers."""

    def rasterize(self, scene: Scene) -> Coverage:
        time.sleep(3600)
        raise AssertionError("unreachable")


class BenchCrashesWhenWarm(_Base):
    """Answers its first call correctly, then segfaults on the next (a warm run)."""

    def __init__(self) -> None:
        super().__init__()
        self.calls = 0

    def rasterize(self, scene: Scene) -> Coverage:
        self.calls += 1
        if self.calls > 1:
            faulthandler.disable()  # (as BenchSegfaults)
            ctypes.string_at(0)
        return PinedaTopLeft().rasterize(scene)


class BenchExitsOnPaths(BenchExits):
    """Fills paths (and only paths) by ending its process with exit code 0."""

    scene_kinds = ("paths",)
