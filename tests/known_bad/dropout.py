"""Known-bad rasterizers of the closed rule and dropout control (issue 33): each claims
FreeType's scan conversion and breaks it where the rule is decided exactly."""

from __future__ import annotations

from dataclasses import replace

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.oracle.coverage import exact_coverage
from harness.oracle.dropout import dropout_coverage

__all__ = ["ClosedWithTies", "LeftDropout", "FREETYPE_MONO", "FREETYPE_MONO_DROPOUT"]

# FreeType's monochrome rasterizer, dropouts off and in its smart mode (rasterizers.real.freetype_outline)
FREETYPE_MONO = Convention(coverage="closed", input="fixed6", dropout="none-stepped6")
FREETYPE_MONO_DROPOUT = Convention(coverage="closed", input="fixed6", dropout="smart-no-stubs-stepped6")


class ClosedWithTies:
    """Declares the closed rule (a sample on an edge is inside for every triangle sharing
    it) but decides samples on edges by the top-left tie rule: a sample on a shared edge
    goes to one side only, and one on a bottom or right edge of the mesh to none."""

    name = "bad_closed_ties"
    convention = Convention(coverage="closed")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        return exact_coverage(scene, Convention())


class LeftDropout:
    """Declares FreeType's smart dropout control (SCANTYPE 5) but always draws the left
    (lower) pixel of a dropout: the simple mode's choice, wrong wherever the span's
    midpoint lies nearer the right pixel's centre."""

    name = "bad_left_dropout"
    convention = FREETYPE_MONO_DROPOUT
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        simple = replace(self.convention, dropout="simple-no-stubs-stepped6")
        return dropout_coverage(scene, simple)
