"""closed: on a closed mesh in front of the camera, front-facing minus back-facing hits
is zero at every pixel; convention-free."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from harness.checks.records import EVIDENCE_LIMIT, Check, Result, register, result, skip
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.geometry.exact import orientation
from harness.kinds import TRIANGLES

__all__ = ["closed_balance"]


def closed_balance(case: Case, coverage: Coverage, convention: Convention | None,
                   oracle: Callable[[], Coverage] | None = None) -> Result:
    """On a closed mesh in front of the camera, hits by clockwise triangles equal hits by
    counter-clockwise ones at every pixel. Orientation is taken after the declared
    snapping, if any (snapping can flip a tiny triangle). Under a coverage rule that does
    not hit a partition exactly once (``CoverageModel.exactly_once`` False), the balance
    its exact answer (``oracle()``) has is the rule's own: only a pixel whose balance
    differs from it counts."""
    if not case.closed:
        return skip(case, "closed", "not a closed mesh")
    scene = case.scene
    scene = TRIANGLES.narrow(scene)  # closed meshes are triangle scenes
    sign = orientation(convention.snap(scene.positions) if convention is not None else scene.positions).astype(np.int64)
    valid = (coverage.triangle >= 0) & (coverage.triangle < len(scene))
    signed = Coverage(coverage.triangle[valid], coverage.y[valid], coverage.x0[valid], coverage.x1[valid])
    balance = _balance(Coverage(signed.triangle, signed.y, signed.x0, signed.x1), sign, scene.width, scene.height)
    if convention is not None and convention.model.uncertain and convention.uncertainty:
        # between what the rule must and may draw, per facing: outside that interval only
        from harness.oracle.coverage_rules import uncertainty_bounds

        must, may = uncertainty_bounds(scene, convention)
        low = _facing(must, sign, 1, scene.width, scene.height) - _facing(may, sign, -1, scene.width, scene.height)
        high = _facing(may, sign, 1, scene.width, scene.height) - _facing(must, sign, -1, scene.width, scene.height)
        balance = np.where(balance < low, balance - low, np.where(balance > high, balance - high, 0))
    elif convention is not None and oracle is not None and not convention.model.exactly_once:
        balance = balance - _balance(oracle(), sign, scene.width, scene.height)
    bad = np.argwhere(balance != 0)
    metrics = {"unbalanced_pixels": float(len(bad))}
    evidence = {"pixels": [[int(x), int(y), int(balance[y, x])] for y, x in bad[:EVIDENCE_LIMIT]]} if len(bad) else {}
    message = "front minus back is zero everywhere" if not len(bad) else f"{len(bad)} pixels where front minus back is not zero"
    return result(case.id, "closed", not len(bad), message, metrics, evidence)


def _facing(coverage: Coverage, sign: np.ndarray, facing: int, width: int, height: int) -> np.ndarray:
    """(H, W): hits by the triangles of orientation ``facing``."""
    keep = sign[coverage.triangle] == facing
    counts: np.ndarray = Coverage(coverage.triangle[keep], coverage.y[keep], coverage.x0[keep],
                                  coverage.x1[keep]).counts(width, height)
    return counts


def _balance(coverage: Coverage, sign: np.ndarray, width: int, height: int) -> np.ndarray:
    """(H, W): hits by clockwise triangles minus hits by counter-clockwise ones."""
    facing = sign[coverage.triangle]
    front = Coverage(coverage.triangle[facing > 0], coverage.y[facing > 0], coverage.x0[facing > 0], coverage.x1[facing > 0])
    back = Coverage(coverage.triangle[facing < 0], coverage.y[facing < 0], coverage.x0[facing < 0], coverage.x1[facing < 0])
    balance: np.ndarray = front.counts(width, height) - back.counts(width, height)
    return balance


register(Check(
    "closed", lambda s: closed_balance(s.case, s.coverage, s.convention, lambda: s.oracle),
    lambda case: bool(getattr(case, "closed", False)),
    metrics={"unbalanced_pixels": (1.0, 0.0)}, caption="on a closed mesh: front-facing minus back-facing hits is zero everywhere",
    classifier="harness.diagnose.signatures:classify_closed", cause_role="consequent", motion_role="none", figures=(),
))
