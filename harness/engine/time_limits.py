"""The one policy of every call's time limit (:class:`TimeLimit`): a base plus a rate times the
work the scene implies (:func:`scene_work`: its primitives, the pixels of their bounding
boxes times the samples per pixel the rasterizer's convention, declared or seen in its
answers, implies, the edges' rows), never above the user's cap (``--timeout``). A call cut
off by its limit is asked again once, in a fresh process, with a longer limit before it
counts as a timeout: the machine's load never turns a slow answer into a verdict.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np

from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene

__all__ = ["AREA_SAMPLES", "scene_work", "samples_of", "samples_seen", "TimeLimit"]

# Samples per pixel an answer of alphas stands for in the work of a call: an exact area
# costs a pixel about what a few sample tests do, a supersampler as many as its samples.
AREA_SAMPLES = 16


def scene_work(scene: AnyScene, samples: int = 1) -> float:
    """The work a call on ``scene`` implies, in sample tests: the viewport's pixels, 16 per
    primitive, the pixels of each primitive's bounding box (clipped to the viewport; the
    whole viewport for a non-finite one) times ``samples`` per pixel, and the rows each edge
    spans (a path filler's scanlines meet every edge on every row it crosses).

    >>> from harness.contract.scenes import Scene
    >>> scene = Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]])
    >>> scene_work(scene), scene_work(scene, 16)
    (104.0, 344.0)
    """
    lo, hi, finite = scene.primitive_boxes()
    a, b, _ = scene.edges()
    return float(_work_kernel(np.ascontiguousarray(lo, dtype=np.float64), np.ascontiguousarray(hi, dtype=np.float64),
                              np.ascontiguousarray(finite, dtype=np.bool_), np.ascontiguousarray(a[:, 1], dtype=np.float64),
                              np.ascontiguousarray(b[:, 1], dtype=np.float64), float(scene.width), float(scene.height),
                              float(samples)))


@numba.njit(cache=True)
def _work_kernel(lo, hi, finite, ay, by, width, height, samples):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """:func:`scene_work` of the boxes ``lo``, ``hi`` ((N, 2)), ``finite`` ((N,)) and the
    edges' end rows ``ay``, ``by`` ((E,)): a NaN box side is the viewport's (low: 0, high:
    its size), a NaN end row 0 (start) or the height (end)."""
    size = (width, height)
    boxes = 0.0
    for t in range(lo.shape[0]):
        if not finite[t]:
            boxes += width * height
            continue
        area = 1.0
        for axis in range(2):
            low = lo[t, axis]
            high = hi[t, axis]
            low = 0.0 if math.isnan(low) else min(max(math.floor(low), 0.0), size[axis])
            high = size[axis] if math.isnan(high) else min(max(math.ceil(high), 0.0), size[axis])
            area *= max(high - low, 0.0)
        boxes += area
    rows = 0.0
    for e in range(ay.size):
        start = 0.0 if math.isnan(ay[e]) else min(max(ay[e], 0.0), height)
        end = height if math.isnan(by[e]) else min(max(by[e], 0.0), height)
        rows += math.ceil(abs(start - end))
    return width * height + 16.0 * lo.shape[0] + samples * boxes + rows


def samples_of(convention: Any) -> int:
    """The samples per pixel a convention implies for :func:`scene_work` (1 without one)."""
    if convention is None:
        return 1
    if getattr(getattr(convention, "model", None), "alphas", False):  # area coverage (its model: a Convention's)
        pattern = getattr(convention, "samples", None)
        return max(AREA_SAMPLES, len(pattern)) if pattern is not None else AREA_SAMPLES
    pattern = getattr(convention, "samples", None)
    return 1 if pattern is None else len(pattern)


def samples_seen(coverage: Coverage) -> int:
    """The samples per pixel an answer shows: its highest sample index + 1, or
    :data:`AREA_SAMPLES` for alphas (1 for a single-sample answer)."""
    if coverage.alpha is not None:
        return AREA_SAMPLES
    if coverage.sample is not None and len(coverage.sample):
        return int(np.max(coverage.sample)) + 1
    return 1


@dataclass(frozen=True, slots=True)
class TimeLimit:
    """How long one rasterize call may take: the one time-limit policy, shared by every
    worker (run, identify, compare, campaigns).

    A call on a scene gets ``base + rate * work`` seconds (:func:`scene_work`, with the
    samples per pixel the convention implies), at most ``cap``; the first call of each
    scene kind a worker makes (imports, a JIT compiling its kernels) gets ``first`` (the
    cap when None). A call cut off by its limit is asked again once, in a fresh process,
    with ``retry`` times that limit (at most the cap): only a call cut off twice is a
    timeout. Nothing depends on how fast earlier calls were, so a busy machine can only
    make a slow call slower, never a verdict out of it.

    Parameters
    ----------
    cap : float
        The most any call may take, in seconds (``--timeout``).
    base : float
        Seconds every call gets (the process round trip, setup).
    rate : float
        Seconds per unit of work (a sample test): 2 us, a pure-Python loop's pace with
        room to spare on a loaded machine.
    retry : float
        The second ask's limit, as a multiple of the first's.
    first : float or None
        The limit of the first call of each scene kind; None: ``cap``.

    Examples
    --------
    >>> from harness.contract.scenes import Scene
    >>> limits = TimeLimit(cap=60.0)
    >>> scene = Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]])
    >>> limits.limit(scene) < limits.limit(scene, samples=16) < limits.retry_limit(limits.limit(scene, samples=16))
    True
    """

    cap: float = 60.0
    base: float = 2.0
    rate: float = 2e-6
    retry: float = 4.0
    first: float | None = None

    def __post_init__(self) -> None:
        for name in ("cap", "base", "retry"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"TimeLimit.{name} must be a finite number > 0, not {value!r}")
        if not (math.isfinite(self.rate) and self.rate >= 0):
            raise ValueError(f"TimeLimit.rate must be a finite number >= 0, not {self.rate!r}")

    @classmethod
    def of(cls, timeout: float | TimeLimit) -> TimeLimit:
        """The policy of a ``timeout`` argument: a number is the cap of the default policy."""
        return timeout if isinstance(timeout, TimeLimit) else cls(cap=float(timeout))

    def limit(self, scene: AnyScene, samples: int = 1) -> float:
        """The first ask's limit on ``scene`` (seconds), ``samples`` per pixel."""
        return min(self.cap, self.base + self.rate * scene_work(scene, samples))

    def first_limit(self) -> float:
        """The limit of the first call of a scene kind."""
        return self.cap if self.first is None else self.first

    def retry_limit(self, limit: float) -> float:
        """The second ask's limit, after a first one of ``limit`` seconds was cut off."""
        return max(limit, min(self.cap, self.retry * limit))
