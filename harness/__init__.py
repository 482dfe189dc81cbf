"""rastercheck: a rasterization conformance and artifact test harness.

>>> from harness import Scene, Coverage, Convention, Rasterizer
"""

from __future__ import annotations

from typing import Any

from harness.api import Convention, Coverage, Rasterizer, Scene

__all__ = ["Scene", "Coverage", "Convention", "Rasterizer", "run_suite"]
__version__ = "0.1.0"


def run_suite(*args: Any, **kwargs: Any) -> Any:
    """Run a suite of checks; see :func:`harness.runner.run_suite`."""
    from harness.runner import run_suite as run

    return run(*args, **kwargs)
