"""rastercheck: a rasterization conformance and artifact test harness.

>>> from harness import Scene, PathScene, Coverage, Convention, Rasterizer
"""

from __future__ import annotations

from typing import Any

from harness.api import Convention, Coverage, PathScene, Rasterizer, Scene
from harness.numba_cache import safe_numba_cache

# every process that imports rastercheck loads (and may compile) its kernels side by side
# with others: make numba's on-disk cache safe for that first
safe_numba_cache()

__all__ = ["Scene", "PathScene", "Coverage", "Convention", "Rasterizer", "run_suite", "replay"]
__version__ = "0.1.0"


def run_suite(*args: Any, **kwargs: Any) -> Any:
    """Run a suite of checks; see :func:`harness.runner.run_suite`."""
    from harness.runner import run_suite as run

    return run(*args, **kwargs)


def replay(path: Any, rasterizer: Any, isolate: bool = False) -> Any:
    """Run the checks of a saved case on a rasterizer; see :func:`harness.runner.replay`."""
    from harness.runner import replay as run

    return run(path, rasterizer, isolate=isolate)
