"""A made-up library in two modes, as the atlas groups real ones: ``Fakelib`` draws top-left
at pixel centres (a black box: identify finds it) and, in its second mode, draws the same
but declares bottom-right ties (its conformance fails on ties: the atlas's causes)."""

from __future__ import annotations

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers.centre_scanline import CentreScanline

__all__ = ["FakelibAliased", "FakelibWrongTie", "FakelibNotInstalled"]

_NO_PATHS_OR_LINES = {"paths": "Fakelib fills no paths", "lines": "Fakelib draws no lines"}


class FakelibAliased:
    """Top-left ties at pixel centres, declaring nothing."""

    name = "fakelib_aliased"
    library = "Fakelib"
    library_version = "1.0"
    coverage_kind = "single"
    convention: Convention | None = None
    kinds_not_taken = _NO_PATHS_OR_LINES

    def rasterize(self, scene: Scene) -> Coverage:
        return CentreScanline().rasterize(scene)


class FakelibWrongTie(FakelibAliased):
    """The same pixels, declaring bottom-right ties: wrong on every tie."""

    name = "fakelib_wrong_tie"
    convention = Convention(tie="bottom-right")


class FakelibNotInstalled(FakelibAliased):
    """A mode whose library is not installed: the atlas lists it with the install."""

    name = "fakelib_missing"

    def __init__(self) -> None:
        from harness.engine.registry import Unavailable

        raise Unavailable("fakelib_missing: no module named 'fakelib' (pip install fakelib)")
