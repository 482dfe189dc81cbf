"""hygiene: the answer is well-formed, whatever the convention."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from harness.case import Case
from harness.api import Coverage
from harness.checks.records import EVIDENCE_LIMIT, Check, first, register, result, Result

__all__ = ["hygiene"]


def hygiene(case: Case, coverage: Coverage, interpolates: bool = True) -> Result:
    """Spans inside the viewport, valid triangle ids, ``x0 < x1``, no pixel emitted twice by
    one triangle, one attribute row per pixel (when the scene has attributes and the
    rasterizer interpolates; one that declares ``interpolates = False`` may return none)."""
    scene = case.scene
    t, y, x0, x1 = coverage.triangle, coverage.y, coverage.x0, coverage.x1
    problems: dict[str, NDArray] = {
        "outside_viewport": np.flatnonzero((y < 0) | (y >= scene.height) | (x0 < 0) | (x1 > scene.width)),
        "bad_triangle_id": np.flatnonzero((t < 0) | (t >= len(scene))),
        "empty_or_reversed": np.flatnonzero(x0 >= x1),
    }
    tri, x, yy = coverage.pixels()
    order = np.lexsort((x, yy, tri))
    same = (np.diff(tri[order]) == 0) & (np.diff(yy[order]) == 0) & (np.diff(x[order]) == 0)
    repeated = order[1:][same]
    metrics = {k: float(v.size) for k, v in problems.items()}
    metrics["repeated_pixels"] = float(repeated.size)
    evidence: dict[str, Any] = {k: first(v) for k, v in problems.items() if v.size}
    if repeated.size:
        evidence["repeated_pixels"] = np.stack([tri[repeated], x[repeated], yy[repeated]], axis=1)[:EVIDENCE_LIMIT].tolist()
    attribute_problem = ""
    if scene.attributes is not None and (interpolates or coverage.attributes is not None):
        rows = None if coverage.attributes is None else coverage.attributes.shape[0]
        if coverage.attributes is None or rows != coverage.n_pixels:
            attribute_problem = f"{rows} attribute rows for {coverage.n_pixels} pixels"
        elif coverage.attributes.shape[1] != scene.n_attributes:
            attribute_problem = f"{coverage.attributes.shape[1]} attributes per pixel, the scene has {scene.n_attributes}"
    parts = [f"{int(v)} {k.replace('_', ' ')}" for k, v in metrics.items() if v]
    if attribute_problem:
        parts.append(attribute_problem)
        evidence["attributes"] = attribute_problem
    quiet = "well-formed" if interpolates or scene.attributes is None else "well-formed (interpolates no attributes, as it declares)"
    return result(case.id, "hygiene", not parts, "; ".join(parts) or quiet, metrics, evidence)


def _is_static(case: Any) -> bool:
    return not hasattr(case, "frames")


register(Check(
    "hygiene", lambda s: hygiene(s.case, s.coverage, s.interpolates), _is_static, shrinks=True,
    caption="spans inside the viewport, valid triangle ids, x0 < x1, no pixel twice per triangle, one attribute row per pixel",
))
