"""Known-bad declarations (issue 28, point 6): plugins whose convention, ``scene_kinds`` or
``fill_rules`` contradict each other or their answers. Each draws what the exact oracle
says; only its declaration is wrong, and rastercheck must say so in one line
(:mod:`harness.contract.declarations`), not with an error on every case.

Refused when loaded (their declarations contradict each other):

- :class:`LineRuleNoLines`: a Bresenham drawer that forgot ``scene_kinds = ("lines",)``.
- :class:`FillRulesNoPaths`: fill rules declared, ``"paths"`` not in its scene kinds.
- :class:`KindsAsString`: ``scene_kinds = "lines"`` (a string, not a tuple).

Refused at their first contradicting answer (then handed no more scenes of that kind):

- :class:`DiamondDrawerNoLines`: a line drawer on the default line rule that forgot its
  scene kinds: it asks each triangle scene for ``segments()``.
- :class:`AreaWithoutAlphas`: declares area coverage, answers bare spans.
- :class:`SingleWithSampleIds`: declares one sample per pixel, answers sample ids.
- :class:`MultisampleWithoutIds`: declares 4 samples, answers spans without sample ids.
- :class:`SingleWithAlphas`: declares one sample per pixel, answers alphas.
"""

from __future__ import annotations

import numpy as np

from harness.contract.conventions import Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, LineScene
from harness.oracle.coverage import exact_coverage

__all__ = ["LineRuleNoLines", "FillRulesNoPaths", "KindsAsString", "DiamondDrawerNoLines", "AreaWithoutAlphas",
           "SingleWithSampleIds", "MultisampleWithoutIds", "SingleWithAlphas", "LOAD_BADS", "ANSWER_BADS"]


class _Oracle:
    """Draws what its convention's exact oracle says (a test double)."""

    name = "oracle"
    convention = Convention()
    interpolates = False

    def rasterize(self, scene: AnyScene) -> Coverage:
        return exact_coverage(scene, self.convention)


class LineRuleNoLines(_Oracle):
    name = "line_rule_no_lines"
    convention = Convention(line=LineRule("bresenham"))

    def rasterize(self, scene: AnyScene) -> Coverage:
        assert isinstance(scene, LineScene)
        scene.segments()
        return exact_coverage(scene, self.convention)


class FillRulesNoPaths(_Oracle):
    name = "fill_rules_no_paths"
    fill_rules = ("evenodd",)


class KindsAsString(_Oracle):
    name = "kinds_as_string"
    convention = Convention(line="bresenham")
    scene_kinds = "lines"


class DiamondDrawerNoLines(_Oracle):
    name = "diamond_drawer_no_lines"

    def rasterize(self, scene: AnyScene) -> Coverage:
        scene.segments()  # type: ignore[attr-defined]  # the bug: it is handed triangles
        return exact_coverage(scene, self.convention)


class AreaWithoutAlphas(_Oracle):
    name = "area_without_alphas"
    convention = Convention(coverage="area")

    def rasterize(self, scene: AnyScene) -> Coverage:
        exact = exact_coverage(scene, self.convention)
        return Coverage(exact.primitive, exact.y, exact.x0, exact.x1)


class SingleWithSampleIds(_Oracle):
    name = "single_with_sample_ids"

    def rasterize(self, scene: AnyScene) -> Coverage:
        exact = exact_coverage(scene, self.convention)
        return Coverage(exact.primitive, exact.y, exact.x0, exact.x1, sample=np.zeros(len(exact), dtype=np.int64))


class MultisampleWithoutIds(_Oracle):
    name = "multisample_without_ids"
    convention = Convention(samples=4)

    def rasterize(self, scene: AnyScene) -> Coverage:
        exact = exact_coverage(scene, self.convention)
        return Coverage(exact.primitive, exact.y, exact.x0, exact.x1)


class SingleWithAlphas(_Oracle):
    name = "single_with_alphas"

    def rasterize(self, scene: AnyScene) -> Coverage:
        exact = exact_coverage(scene, self.convention)
        return Coverage(exact.primitive, exact.y, exact.x0, exact.x1, alpha=np.ones(exact.n_pixels))


# known-bad -> what its one line must say
LOAD_BADS: dict[type, str] = {
    LineRuleNoLines: 'lack "lines", so no line scene would reach it: add scene_kinds = ("lines",)',
    FillRulesNoPaths: 'lack "paths", so no path scene would reach it: add "paths"',
    KindsAsString: "is one string, not a tuple of kinds: write scene_kinds = (\"lines\",)",
}
ANSWER_BADS: dict[type, str] = {
    DiamondDrawerNoLines: 'asked a triangle scene for `segments`, which line scenes have, but its scene_kinds ("triangles",) '
                          'lack "lines"',
    AreaWithoutAlphas: "declares area coverage, but its answer carries no alphas: return Coverage(..., alpha=a)",
    SingleWithSampleIds: "declares one sample per pixel, but its answer carries sample ids: declare the pattern",
    MultisampleWithoutIds: "declares a multisample pattern of 4 samples, but its answer carries no sample ids",
    SingleWithAlphas: "declares one sample per pixel, but its answer carries alphas",
}
