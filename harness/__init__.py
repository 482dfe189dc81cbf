"""rastercheck: a rasterization conformance and artifact test harness.

Everything a plugin uses is here (README, "What `rasterize` receives and returns"): the
scenes it receives, the coverage it returns, the convention it declares, the refusal it
may raise, and the runner.

>>> from harness import Convention, Coverage, LineRule, LineScene, PathScene, Rasterizer, Scene, Unsupported
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from harness.contract.conventions import COVERAGE_KINDS, FILL_RULES, LINE_RULES, TIE_RULES, Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer
from harness.contract.samples import STANDARD_PATTERNS, pattern
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene, Unsupported
from harness.geometry.numba_cache import safe_numba_cache
from harness.geometry.spans import span_buffers
from harness.kinds import SCENE_KINDS
from harness.kinds.points import PointScene

if TYPE_CHECKING:  # imported when first used (the runner and the checks take a second to import)
    from harness.checks.records import Result, Tolerance
    from harness.contract.case import Case, MotionCase
    from harness.diagnose.causes import by_cause
    from harness.engine.isolation import TimeLimit

# every process that imports rastercheck loads (and may compile) its kernels side by side
# with others: make numba's on-disk cache safe for that first
safe_numba_cache()

__all__ = [
    # what rasterize receives
    "Scene", "PathScene", "LineScene", "PointScene", "AnyScene", "SCENE_KINDS",
    # what it returns (span_buffers: four int64 arrays for a compiled kernel to fill), and may raise instead
    "Coverage", "span_buffers", "Unsupported",
    # what it declares
    "Rasterizer", "Convention", "LineRule", "TIE_RULES", "FILL_RULES", "LINE_RULES", "COVERAGE_KINDS",
    "STANDARD_PATTERNS", "pattern",
    # running it
    "run_suite", "replay", "Result", "Tolerance", "assert_conforms",
    # reading the results: the failures grouped by cause, as the terminal and the report show them
    "by_cause",
]
__version__ = "0.1.0"

# names imported on first use (module __getattr__): they pull in the checks
_LAZY = {"Result": "harness.checks.records", "Tolerance": "harness.checks.records",
         "assert_conforms": "harness.integrations.testing", "by_cause": "harness.diagnose.causes"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'harness' has no attribute {name!r}")


def run_suite(
    rasterizers: Iterable[Rasterizer | str],
    suite: str = "quick",
    seed: int = 0,
    *,
    cases: Sequence[Case | MotionCase] | None = None,
    tolerance: Tolerance | None = None,
    timeout: float | TimeLimit = 60.0,
    isolate: bool = True,
    repros: bool = True,
    repro_seconds: float = 120.0,
    on_result: Callable[[Result], None] | None = None,
    identify: bool = True,
    only: set[str] | None = None,
    rerun: int = 0,
    stop: threading.Event | None = None,
    deadline: float | None = None,
    on_case: Callable[[str, str], None] | None = None,
) -> list[Result]:
    """Run a suite's checks on each rasterizer; see :func:`harness.engine.runner.run_suite` for
    the parameters (``tolerance`` None: the default :class:`Tolerance`)."""
    from harness.checks.records import Tolerance
    from harness.engine.runner import run_suite as run

    return run(rasterizers, suite, seed, cases=cases, tolerance=Tolerance() if tolerance is None else tolerance,
               timeout=timeout, isolate=isolate, repros=repros, repro_seconds=repro_seconds, on_result=on_result,
               identify=identify, only=only, rerun=rerun, stop=stop, deadline=deadline, on_case=on_case)


def replay(path: Path | str, rasterizer: Rasterizer | str, isolate: bool = False, identify: bool = True,
           timeout: float | TimeLimit = 60.0) -> list[Result]:
    """Run the checks of a saved case or minimal repro on a rasterizer; see
    :func:`harness.engine.runner.replay`."""
    from harness.engine.runner import replay as run

    return run(path, rasterizer, isolate=isolate, identify=identify, timeout=timeout)
