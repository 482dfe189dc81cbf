"""Lines: segments in strips under a line rule (:class:`harness.contract.scenes.LineScene`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.scenes import LineScene
from harness.kinds.base import JSON_POINT, PrimitiveKind

__all__ = ["LINES", "LINE_SHIFT"]

# Lines move by an even number of pixels: a half-to-even rounding of an end point (snapping
# to whole pixels, Bresenham's end point to its pixel) keeps its tie's side.
LINE_SHIFT = (4, 2)

# its case-file fields: each strip (polyline) of at least two points, and the width
JSON_FIELDS = {
    "lines": {"type": "array", "items": {"type": "array", "items": JSON_POINT, "minItems": 2}},
    "line_width": {"anyOf": [{"type": "number", "exclusiveMinimum": 0}, {"type": "string"}]},
}


def _strips_words(scene: LineScene) -> str:
    strips = scene.strip_sizes.size
    return f" in {strips} strip{'' if strips == 1 else 's'}" if strips != len(scene) else ""


def _coordinates_of(scene: LineScene, prims: NDArray[np.int64]) -> list[NDArray[np.float64]]:
    a, b = scene.segments()
    return [np.stack([a[k], b[k]]) for k in prims]


def _degenerate(scene: LineScene, snapped: dict[int, NDArray[np.float64]]) -> set[int]:
    return {k for k, c in snapped.items() if np.array_equal(c[0], c[1])}


def _keeps_shapes(scene: LineScene, moved: LineScene) -> bool:
    (a, b), (c, d) = scene.segments(), moved.segments()
    return bool(np.array_equal(np.all(a == b, axis=1), np.all(c == d, axis=1)))


def _work_size(scene: LineScene) -> int:
    return len(scene)


def _undefined(scene: LineScene, convention: Any) -> str:
    return str(convention.line.undefined_width(scene.line_width))


LINES: PrimitiveKind[LineScene] = PrimitiveKind(
    name="lines", scene_class=LineScene, json_key="lines", convention_attribute="line_convention",
    own_fit=("line_fit", "line convention"), translate_shift=LINE_SHIFT, translate_needs_positive=True,
    near_ties_by_own_rule=True,
    coordinates_of=_coordinates_of, degenerate=_degenerate, work_size=_work_size, keeps_shapes=_keeps_shapes,
    undefined=_undefined, exact_tie_words=("pixels", "the line rule's boundary"),
    case_word="line", may_overlap=True, json_fields=JSON_FIELDS, json_required=("lines",),
    size_limits={"line strips": 1 << 18, "line vertices": 1 << 20}, caption_words=_strips_words, invariance_families=None,
    to_json="harness.contract.case:lines_to_json", from_json="harness.contract.case:lines_from_json",
    json_sizes="harness.contract.case:line_sizes",
    oracle="harness.oracle.lines:line_coverage",
    near_ties="harness.checks.near_ties:line_near_ties",
    invariance_variants="harness.checks.invariance:line_variants",
    probes="harness.identify.line_probes:fit_lines",
    verdict_cases="harness.identify.fingerprint:line_verdict_cases",
    still_pictures="harness.report.pictures:line_pictures",
    repro_picture="harness.report.picture_repro:line_repro",
    conformance_class="harness.diagnose.signatures:line_conformance",
    hypotheses="harness.diagnose.facts:line_hypotheses",
    tie_trial="harness.diagnose.trials:no_trial",
    dropped_trial="harness.diagnose.trials:no_trial",
    vectors="harness.report.picture_svg:line_vectors",
)
