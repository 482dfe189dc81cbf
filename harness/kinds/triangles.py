"""Triangles: the first primitive kind (:class:`harness.contract.scenes.Scene`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.contract.scenes import Scene
from harness.geometry.exact import orientation
from harness.kinds.base import JSON_NUMBER, JSON_POINT, PrimitiveKind

__all__ = ["TRIANGLES"]


# its case-file fields: the (N, 3, 2) positions, and the per-vertex values and w
JSON_FIELDS = {
    "positions": {"type": "array", "items": {"type": "array", "items": JSON_POINT, "minItems": 3, "maxItems": 3}},
    "attributes": {"type": ["array", "null"], "items": {"type": "array", "minItems": 3, "maxItems": 3,
                                                        "items": {"type": "array", "items": JSON_NUMBER}}},
    "w": {"type": ["array", "null"], "items": {"type": "array", "items": JSON_NUMBER, "minItems": 3, "maxItems": 3}},
}


def _coordinates_of(scene: Scene, prims: NDArray[np.int64]) -> list[NDArray[np.float64]]:
    return [scene.positions[k] for k in prims]


def _degenerate(scene: Scene, snapped: dict[int, NDArray[np.float64]]) -> set[int]:
    if not snapped:
        return set()
    keys = list(snapped)
    return {k for k, sign in zip(keys, orientation(np.stack([snapped[k] for k in keys]))) if sign == 0}


def _keeps_shapes(scene: Scene, moved: Scene) -> bool:
    finite: NDArray[np.bool_] = np.asarray(np.isfinite(scene.positions).all(axis=(1, 2)))
    before = orientation(np.where(finite[:, None, None], scene.positions, 0.0))
    after = orientation(np.where(finite[:, None, None], moved.positions, 0.0))
    return bool(np.array_equal(before, after))


def _work_size(scene: Scene) -> int:
    return len(scene)


def _undefined(scene: Scene, convention: Any) -> str:
    return ""


TRIANGLES: PrimitiveKind[Scene] = PrimitiveKind(
    name="triangles", scene_class=Scene, json_key="positions", convention_attribute=None,
    own_fit=None, translate_shift=(3, 2), translate_needs_positive=False, near_ties_by_own_rule=False,
    coordinates_of=_coordinates_of, degenerate=_degenerate, work_size=_work_size, keeps_shapes=_keeps_shapes,
    undefined=_undefined, exact_tie_words=("samples", "an edge of their {noun}"),
    case_word="triangle", may_overlap=False, json_fields=JSON_FIELDS, json_required=("positions",),
    size_limits={"triangles": 1 << 20}, caption_words=lambda scene: "",
    invariance_families=("lattice", "float", "watertight"),
    to_json="harness.contract.case:triangles_to_json", from_json="harness.contract.case:triangles_from_json",
    json_sizes="harness.contract.case:triangle_sizes",
    # the convention's coverage model names the oracle (exact single, multisample, shares, area)
    oracle="harness.oracle.coverage:exact_triangles",
    near_ties="harness.checks.near_ties:triangle_near_ties",
    invariance_variants="harness.checks.invariance:triangle_variants",
    probes="harness.identify.triangle_probes:fit_ties",
    verdict_cases="harness.identify.fingerprint:triangle_verdict_cases",
    still_pictures="harness.report.pictures:fill_pictures",
    repro_picture="harness.report.picture_repro:fill_repro",
    conformance_class="harness.diagnose.signatures:fill_conformance",
    hypotheses="harness.diagnose.facts:no_hypothesis",
    tie_trial="harness.diagnose.trials:triangle_tie_trial",
    dropped_trial="harness.diagnose.trials:triangle_dropped_trial",
    vectors="harness.report.picture_svg:triangle_vectors",
)
