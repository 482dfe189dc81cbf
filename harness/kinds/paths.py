"""Paths: filled outlines under a fill rule (:class:`harness.contract.scenes.PathScene`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.scenes import PathScene
from harness.kinds.base import JSON_POINT, PrimitiveKind

__all__ = ["PATHS"]


# its case-file fields: each path a list of closed contours, each a list of points; the rule
JSON_FIELDS = {
    "paths": {"type": "array", "items": {"type": "array", "minItems": 1,
                                         "items": {"type": "array", "items": JSON_POINT, "minItems": 1}}},
    "fill_rule": {"enum": ["nonzero", "evenodd"]},
}


def _coordinates_of(scene: PathScene, prims: NDArray[np.int64]) -> list[NDArray[np.float64]]:
    return [np.concatenate(scene.contours_of(int(k))) for k in prims]


def _degenerate(scene: PathScene, snapped: dict[int, NDArray[np.float64]]) -> set[int]:
    return set()  # a path's fill rule decides what it covers, whatever its area


def _keeps_shapes(scene: PathScene, moved: PathScene) -> bool:
    return True  # a path's fill rule decides what it covers, whatever its contours' shapes


def _work_size(scene: PathScene) -> int:
    # its vertices: a path needs at most one span per row for every two of its edges
    return int(scene.vertices.shape[0])


def _undefined(scene: PathScene, convention: Any) -> str:
    return ""


PATHS: PrimitiveKind[PathScene] = PrimitiveKind(
    name="paths", scene_class=PathScene, json_key="paths", convention_attribute="path_convention",
    own_fit=None, translate_shift=(3, 2), translate_needs_positive=False, near_ties_by_own_rule=False,
    coordinates_of=_coordinates_of, degenerate=_degenerate, work_size=_work_size, keeps_shapes=_keeps_shapes,
    undefined=_undefined, exact_tie_words=("samples", "an edge of their {noun}"),
    case_word="path", may_overlap=False, json_fields=JSON_FIELDS, json_required=("paths", "fill_rule"),
    size_limits={"paths": 1 << 16, "contours": 1 << 18, "path vertices": 1 << 20},
    caption_words=lambda scene: f" under the {scene.fill_rule} rule", invariance_families=("paths", "path-partitions"),
    to_json="harness.contract.case:paths_to_json", from_json="harness.contract.case:paths_from_json",
    json_sizes="harness.contract.case:path_sizes",
    oracle="harness.oracle.winding:path_coverage",
    near_ties="harness.checks.near_ties:path_near_ties",
    invariance_variants="harness.checks.invariance:path_variants",
    probes="harness.identify.path_probes:fit_path_convention",
    verdict_cases="harness.identify.fingerprint:path_verdict_cases",
    still_pictures="harness.report.pictures:fill_pictures",
    repro_picture="harness.report.picture_repro:fill_repro",
    conformance_class="harness.diagnose.signatures:fill_conformance",
    hypotheses="harness.diagnose.facts:path_hypotheses",
    tie_trial="harness.diagnose.trials:vertex_row_trial",
    dropped_trial="harness.diagnose.trials:path_orders_trial",
    vectors="harness.report.picture_svg:path_vectors",
)
