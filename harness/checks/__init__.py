"""Checks: pure functions from (case, coverage, oracle, tolerance) to result records.

No I/O, no plotting. One family per module, each registering its checks once
(:class:`harness.checks.records.Check`); every list of checks elsewhere -- the runner's
dispatch, the convention-bound ones, the shrinkable ones, the gate's metrics, the report's
columns, captions and figures, ``rastercheck list``, the signatures' classifiers, the
campaign's root and consequent checks, the motion checks read through their frames -- is
derived from that registry.

Tolerances are data (:class:`Tolerance`): ``strict`` allows no deviation at all,
``default`` excuses deviations at near ties (the sample within ``near_tie`` of an edge,
relative to the coordinates' magnitude, and within ``near_tie_pixels`` absolutely: float
rounding) on non-lattice cases only. Distances are rigorous upper bounds, and exactly 0
only where the exact predicate puts the sample on an edge line.

Registration order is the order results come in: hygiene, conformance, watertight,
overdraw (on request), closed, degenerate, invariance; jaggy, texel, perspective on motion
cases; then accuracy (still cases, and each frame of a motion case), seams (still
cases) and popping (motion cases), which judge area
(anti-aliased) coverage only; then triangulation (path cases: a path against its
triangles); then the line checks (line cases, :mod:`harness.checks.lines`): connectivity,
joints, reversal, length, line-motion. Checks that mean nothing for lines (watertight,
closed, degenerate, triangulation, the area ones) do not apply to line cases.

Each check says which coverage kinds it judges (:attr:`Check.coverage_kinds`): the sample-based
ones judge a multisample rasterizer sample by sample (each sample's layer against the
convention at that sample, results merged), hygiene, degenerate and invariance judge
every kind, and the area checks anti-aliased coverage.
"""

from __future__ import annotations

# isort: off
# in the order the checks run and are listed (each module registers its checks on import)
from harness.checks.records import (
    EVIDENCE_LIMIT, NEAR_TIE, NEAR_TIE_PIXELS, Check, Drawing, Figure, Result, Status, Subject, Tolerance, check_names, checks,
    every_check, metric_tolerance, register, registered, result, skip, timing_metrics,
)
from harness.checks.hygiene import hygiene
from harness.checks.conformance import FragmentCounter, conformance, deviations, edge_distance, near_ties
from harness.checks.watertight import blame, overdraw, pixel_classes, watertight
from harness.checks.closed import closed_balance
from harness.checks.degenerate import control_scene, degenerate, measure_work, refusal
from harness.checks.invariance import invariance, invariance_variants
from harness.checks.motion import jaggy, perspective, texel_swimming
from harness.checks.area import accuracy, motion_accuracy
from harness.checks.area_seams import seams
from harness.checks.area_popping import popping
from harness.checks.paths import triangulation
from harness.checks.lines import connectivity, joints, length, line_motion, reversal
# isort: on

__all__ = [
    "Result", "Drawing", "Status", "Tolerance", "NEAR_TIE", "NEAR_TIE_PIXELS", "EVIDENCE_LIMIT", "CHECKS",
    "Check", "Figure", "Subject", "register", "registered", "checks", "every_check", "check_names", "metric_tolerance",
    "timing_metrics", "result", "skip",
    "deviations", "FragmentCounter", "edge_distance", "near_ties", "hygiene", "conformance", "watertight",
    "pixel_classes", "blame", "overdraw", "closed_balance", "degenerate", "control_scene", "measure_work", "refusal",
    "invariance", "invariance_variants", "jaggy", "texel_swimming", "perspective", "accuracy", "motion_accuracy", "seams",
    "popping", "triangulation", "connectivity", "joints", "reversal", "length", "line_motion",
]

# The built-in checks, in order (a check registered later shows in check_names()).
CHECKS: tuple[str, ...] = check_names()
