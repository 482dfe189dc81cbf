"""Plugins that leave nothing to check (issue 30, point 3): each must make ``run``,
``identify``, ``compare`` or ``replay`` exit non-zero with one line naming it and why,
never 0 with nothing checked (tests/acceptance/test_exit_codes.py).

Refused when loaded (exit 2: their declarations leave no scene to hand them):

- :class:`EmptyKinds`, :class:`BogusKinds`, :class:`KindsAsString`, :class:`KindsAsNumber`:
  ``scene_kinds`` empty, ``("hexagons",)``, ``"triangles"``, ``3``.
- :class:`BogusFillRules`, :class:`EmptyFillRules`: ``fill_rules`` ``("zigzag",)`` or empty.
- :class:`Impostor`: named ``centre_scanline``, beside the built-in of that name.

A verdict (exit 1: nothing was judged):

- :class:`UnsupportedEverything`: raises ``Unsupported`` for every scene.
- :class:`LinesOnly`: takes lines only (handed only triangle cases: none reaches it).
- :class:`CrashesAlways`, :class:`SegfaultsAlways`, :class:`ExitsAlways`: every call raises,
  kills its process with SIGSEGV, or calls ``sys.exit(0)`` (each declaring no convention,
  so that identify has only their answers to go by).
- :class:`AreaDrawsSamples`: declares area coverage, answers bare spans (one sample per pixel).
"""

from __future__ import annotations

import faulthandler
import os
import signal
import sys

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, Unsupported
from harness.oracle.coverage import exact_coverage

__all__ = ["EmptyKinds", "BogusKinds", "KindsAsString", "KindsAsNumber", "BogusFillRules", "EmptyFillRules", "Impostor",
           "UnsupportedEverything", "LinesOnly", "CrashesAlways", "SegfaultsAlways", "ExitsAlways", "AreaDrawsSamples",
           "REFUSED_AT_LOAD"]


class _Oracle:
    """Draws what its convention's exact oracle says (a test double)."""

    name = "oracle"
    convention: Convention | None = Convention()
    interpolates = False

    def rasterize(self, scene: AnyScene) -> Coverage:
        return exact_coverage(scene, self.convention or Convention())


class EmptyKinds(_Oracle):
    name = "empty_kinds"
    scene_kinds: tuple[str, ...] = ()


class BogusKinds(_Oracle):
    name = "bogus_kinds"
    scene_kinds = ("hexagons",)


class KindsAsString(_Oracle):
    name = "kinds_as_string"
    scene_kinds = "triangles"


class KindsAsNumber(_Oracle):
    name = "kinds_as_number"
    scene_kinds = 3


class BogusFillRules(_Oracle):
    name = "bogus_fill_rules"
    scene_kinds = ("paths",)
    fill_rules = ("zigzag",)


class EmptyFillRules(_Oracle):
    name = "empty_fill_rules"
    scene_kinds = ("paths",)
    fill_rules: tuple[str, ...] = ()


class Impostor(_Oracle):
    """A copy of the built-in under its name, with another tie rule."""

    name = "centre_scanline"
    convention = Convention(tie="bottom-right")


# the class name and what its one-line refusal says
REFUSED_AT_LOAD = {
    "EmptyKinds": "scene_kinds is empty",
    "BogusKinds": "scene_kinds names 'hexagons', which is no scene kind",
    "KindsAsString": "scene_kinds = 'triangles' is one string",
    "KindsAsNumber": "scene_kinds = 3 is not a tuple of kinds",
    "BogusFillRules": "fill_rules names 'zigzag', which is no fill rule",
    "EmptyFillRules": "fill_rules is empty",
}


class UnsupportedEverything(_Oracle):
    name = "unsupported_everything"

    def rasterize(self, scene: AnyScene) -> Coverage:
        raise Unsupported("it draws nothing as given")


class LinesOnly(_Oracle):
    name = "lines_only"
    scene_kinds = ("lines",)


class CrashesAlways(_Oracle):
    name = "crashes_always"
    convention = None

    def rasterize(self, scene: AnyScene) -> Coverage:
        raise RuntimeError("the engine is not initialised")


class SegfaultsAlways(_Oracle):
    name = "segfaults_always"
    convention = None

    def rasterize(self, scene: AnyScene) -> Coverage:
        faulthandler.disable()  # the crash alone, without pytest's dump of every thread
        os.kill(os.getpid(), signal.SIGSEGV)
        raise AssertionError("unreachable")


class ExitsAlways(_Oracle):
    name = "exits_always"
    convention = None

    def rasterize(self, scene: AnyScene) -> Coverage:
        sys.exit(0)


class AreaDrawsSamples(_Oracle):
    name = "area_draws_samples"
    convention = Convention(coverage="area")

    def rasterize(self, scene: AnyScene) -> Coverage:
        single = exact_coverage(scene, Convention())
        return Coverage(single.primitive, single.y, single.x0, single.x1)


if __name__ == "__main__":  # a plugin that ends the process when run as a script, never when loaded
    sys.exit(0)
