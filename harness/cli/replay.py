"""``rastercheck replay``: the checks of a saved case (a minimal repro) on a rasterizer.
"""

from __future__ import annotations

import argparse
import sys

from harness.cli.common import UsageError, _load_all


def _replay(args: argparse.Namespace) -> int:
    from harness.contract.case import MotionCase, read_case_file
    from harness.contract.protocol import fill_rules_of, scene_kinds_of, takes
    from harness.engine.runner import nothing_checked, replay
    from harness.kinds import PATHS

    try:
        read_case_file(args.case)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    rasterizers, _ = _load_all([args.rasterizer], args.timeout)
    if not rasterizers:
        return 2  # unavailable: reported as skipped with its install hint; nothing was replayed
    case, _ = read_case_file(args.case)
    scene = case.frames[0] if isinstance(case, MotionCase) else case.scene
    if not takes(rasterizers[0], scene):
        kinds = scene_kinds_of(rasterizers[0])
        rule = f" under the {scene.fill_rule} fill rule" if PATHS.owns(scene) and scene.kind in kinds else ""
        raise UsageError(f"replay {args.case}: a case of {scene.kind}{rule}, which {rasterizers[0].name} does not take "
                         f"(scene_kinds={kinds!r}" + (f", fill_rules={fill_rules_of(rasterizers[0])!r}" if rule else "")
                         + "): nothing to replay")
    results = replay(args.case, rasterizers[0], isolate=True, timeout=args.timeout)
    for r in results:
        print(f"{r.status:<6} {r.check:<12} {r.message}")
    why = nothing_checked(rasterizers[0], results, [case])
    if why is not None:
        print(f"rastercheck: replay {args.case}: {why}", file=sys.stderr)
        return 1
    return 1 if any(r.status in ("fail", "error") for r in results) else 0
