"""Motion checks: jaggy monotonicity, texel swimming and perspective accuracy.

Pure functions over a sequence's coverages and the oracle's coverages of the same frames;
each returns a :class:`harness.checks.Result` whose metrics hold totals and whose evidence
holds per-frame series (ready to plot) and the offending frames, rows and columns.

Directions come from the oracle: under a monotone motion the exact boundary of each
triangle's span on each row moves one way (or stays); when the rasterizer's boundary
moves the other way, that is a backward jump. Where the oracle does not move at a step,
the direction of its most recent move (or of its next one) stands in.
"""

from __future__ import annotations

from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from harness.checks.records import EVIDENCE_LIMIT, Check, Result, Subject, Tolerance, register, result
from harness.contract.coverage import Coverage

__all__ = ["jaggy", "texel_swimming", "perspective", "boundary_series", "filled_direction", "TIE"]

# A texel coordinate u*T within this (relative) distance of an integer sits on a texel
# edge: which side it falls on is float rounding, not swimming.
TIE = 1e-9



def _spans(coverages: list[Coverage]) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray]:
    """Every frame's spans at once: (frame, primitive, y, x0, x1), frame by frame."""
    sizes = [c.y.size for c in coverages]
    frame = np.repeat(np.arange(len(coverages)), sizes)
    if not coverages:
        empty = np.zeros(0, dtype=np.int64)
        return frame, empty, empty, empty, empty
    t, y, x0, x1 = (np.concatenate([getattr(c, name) for c in coverages]) for name in ("triangle", "y", "x0", "x1"))
    return frame, t, y, x0, x1


def boundary_series(coverages: list[Coverage], n_triangles: int, height: int) -> tuple[NDArray, NDArray]:
    """Left and right span ends per frame, triangle and row: (F, N, H) float, NaN where the
    triangle covers nothing on that row (several runs on a row count from the outermost)."""
    f, t, y, x0, x1 = _spans(coverages)
    return _series_kernel(f, t, y, x0, x1, len(coverages), n_triangles, height)  # type: ignore[no-any-return]


@numba.njit(cache=True)
def _series_kernel(f, t, y, x0, x1, frames, n_triangles, height):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """:func:`boundary_series` of the spans (frame, primitive, y, x0, x1)."""
    lo = np.full((frames, n_triangles, height), np.nan)
    hi = np.full((frames, n_triangles, height), np.nan)
    for s in range(t.size):
        if t[s] < 0 or t[s] >= n_triangles or y[s] < 0 or y[s] >= height or x1[s] <= x0[s]:
            continue
        a, b = float(x0[s]), float(x1[s])
        if np.isnan(lo[f[s], t[s], y[s]]) or a < lo[f[s], t[s], y[s]]:
            lo[f[s], t[s], y[s]] = a
        if np.isnan(hi[f[s], t[s], y[s]]) or b > hi[f[s], t[s], y[s]]:
            hi[f[s], t[s], y[s]] = b
    return lo, hi


def filled_direction(steps: NDArray) -> NDArray:
    """Signs of ``steps`` along axis 0 with zeros (and NaN) replaced by the most recent
    nonzero sign, or the next one where there is none before.

    >>> filled_direction(np.array([0.0, 1.0, 0.0, np.nan, -2.0, 0.0]))
    array([ 1.,  1.,  1.,  1., -1., -1.])
    """
    sign = np.nan_to_num(np.sign(steps))
    n = sign.shape[0]
    index = np.arange(n).reshape((n,) + (1,) * (sign.ndim - 1))
    nonzero = sign != 0
    last = np.maximum.accumulate(np.where(nonzero, index, -1), axis=0)
    forward = np.where(last >= 0, np.take_along_axis(sign, np.maximum(last, 0), axis=0), 0.0)
    reverse = nonzero[::-1]
    nxt = np.maximum.accumulate(np.where(reverse, index, -1), axis=0)
    backward = np.where(nxt >= 0, np.take_along_axis(sign[::-1], np.maximum(nxt, 0), axis=0), 0.0)[::-1]
    return np.where(forward != 0, forward, backward)


def _backward_jumps(series: NDArray, oracle: NDArray) -> NDArray:
    """(F-1, ...) bool: steps where the rasterizer's series moves against the oracle's."""
    step = np.diff(series, axis=0)
    direction = filled_direction(np.diff(oracle, axis=0))
    backward: NDArray = np.isfinite(step) & (step != 0) & (np.sign(step) == -direction) & (direction != 0)
    return backward


def _window(coverages: list[Coverage], width: int, height: int) -> tuple[int, int, int, int]:
    """The smallest rectangle (x0, y0, x1, y1) of the viewport holding every span."""
    _, _, y, x0, x1 = _spans(coverages)
    ok = (x1 > x0) & (y >= 0) & (y < height)
    if not ok.any():
        return 0, 0, 1, 1
    left, right = max(int(x0[ok].min()), 0), min(int(x1[ok].max()), width)
    return left, int(y[ok].min()), max(right, left + 1), int(y[ok].max()) + 1


def _masks(coverages: list[Coverage], window: tuple[int, int, int, int]) -> NDArray:
    """(F, h, w) bool coverage masks of the frames, cropped to ``window``: per pixel
    whether some span covers it."""
    x0, y0, x1, y1 = window
    f, _, y, a, b = _spans(coverages)
    return _masks_kernel(f, y, a, b, len(coverages), x0, y0, x1, y1)  # type: ignore[no-any-return]


@numba.njit(cache=True)
def _masks_kernel(f, y, a, b, frames, x0, y0, x1, y1):  # type: ignore[no-untyped-def]  # pragma: no cover - compiled
    """:func:`_masks` of the spans (frame, y, x0, x1) in the window [x0, x1) x [y0, y1)."""
    out = np.zeros((frames, y1 - y0, x1 - x0), dtype=np.bool_)
    for s in range(y.size):
        row = y[s] - y0
        if row < 0 or row >= y1 - y0:
            continue
        left = min(max(a[s], x0), x1) - x0
        right = min(max(b[s], x0), x1) - x0
        for x in range(left, right):
            out[f[s], row, x] = True
    return out


def jaggy(case_id: str, coverages: list[Coverage], oracles: list[Coverage], n_triangles: int,
          width: int, height: int) -> Result:
    """Per pixel, coverage may change no more often over the sequence than the oracle's
    (the excess is flicker); per triangle and row, each span end moves only the way the
    exact one does (a backward jump is counted with its frame, row and column)."""
    window = _window([*coverages, *oracles], width, height)
    got, want = _masks(coverages, window), _masks(oracles, window)
    changes_got = (got[1:] != got[:-1]).sum(axis=0)
    changes_want = (want[1:] != want[:-1]).sum(axis=0)
    excess = np.clip(changes_got - changes_want, 0, None)
    left, right = boundary_series(coverages, n_triangles, height)
    left_o, right_o = boundary_series(oracles, n_triangles, height)
    back_left = _backward_jumps(left, left_o)
    back_right = _backward_jumps(right, right_o)
    # every backward jump, ordered by frame, then side, triangle and row; the first few as evidence
    where = [np.argwhere(back_left), np.argwhere(back_right)]
    n_jumps = len(where[0]) + len(where[1])
    found = np.concatenate(where)
    side = np.repeat([0, 1], [len(where[0]), len(where[1])])
    jumps = []
    for k in np.lexsort((side, found[:, 0]))[:EVIDENCE_LIMIT] if n_jumps else ():
        f, t, y = (int(v) for v in found[k])
        series = right if side[k] else left
        jumps.append({"frame": f + 1, "triangle": t, "row": y, "side": ("left", "right")[side[k]],
                      "column": int(series[f + 1, t, y]), "previous": int(series[f, t, y])})
    per_frame = {
        "changed_pixels": [0] + (got[1:] != got[:-1]).sum(axis=(1, 2)).tolist(),
        "oracle_changed_pixels": [0] + (want[1:] != want[:-1]).sum(axis=(1, 2)).tolist(),
        "backward_jumps": [0] + (back_left.sum(axis=(1, 2)) + back_right.sum(axis=(1, 2))).tolist(),
    }
    flicker = np.argwhere(excess > 0)
    metrics = {"flicker": float(excess.sum()), "flicker_pixels": float(len(flicker)), "backward_jumps": float(n_jumps),
               "frames": float(len(coverages))}
    evidence: dict[str, Any] = {"series": per_frame}
    # the frames (0-based) whose coverage differs from the oracle's, on the screen or in a
    # triangle's own spans (a double hit leaves the screen's union alike): where a cause is read
    with np.errstate(invalid="ignore"):
        ends_differ = ((left != left_o) & ~(np.isnan(left) & np.isnan(left_o))) \
            | ((right != right_o) & ~(np.isnan(right) & np.isnan(right_o)))
    mismatched = np.flatnonzero((got != want).any(axis=(1, 2)) | ends_differ.any(axis=(1, 2)))
    if mismatched.size:
        evidence["oracle_mismatch_frames"] = mismatched[:EVIDENCE_LIMIT].tolist()
    if len(flicker):
        evidence["flicker"] = [[int(x + window[0]), int(y + window[1]), int(changes_got[y, x]), int(changes_want[y, x])]
                               for y, x in flicker[:EVIDENCE_LIMIT]]
    if jumps:
        evidence["backward_jumps"] = jumps
    ok = not len(flicker) and not n_jumps
    message = ("monotone: no flicker, no backward jump" if ok
               else f"{int(excess.sum())} extra changes at {len(flicker)} pixels (flicker), {n_jumps} backward jumps")
    return result(case_id, "jaggy", ok, message, metrics, evidence)


def _matched(cov: Coverage, oracle: Coverage) -> tuple[NDArray, NDArray, NDArray]:
    """Attribute rows of the fragments both have, as (keys (t, x, y), got rows, oracle rows)."""
    if cov.attributes is None or oracle.attributes is None or cov.attributes.shape[0] != cov.n_pixels:
        return np.zeros((0, 3), dtype=np.int64), np.zeros((0, 2)), np.zeros((0, 2))
    t, x, y = cov.pixels()
    ot, ox, oy = oracle.pixels()
    big = np.int64(1) << 20
    keys = (t * big + y) * big + x
    okeys = (ot * big + oy) * big + ox
    common, i, j = np.intersect1d(keys, okeys, return_indices=True)
    return np.stack([t[i], x[i], y[i]], axis=1), cov.attributes[i], oracle.attributes[j]


def _frames_without_attributes(coverages: list[Coverage]) -> list[int]:
    """Frames that cover pixels but return no attribute row for each of them: nothing to
    compare there, which must never read as a pass."""
    return [f for f, cov in enumerate(coverages)
            if cov.n_pixels and (cov.attributes is None or cov.attributes.shape[0] != cov.n_pixels)]


def _lacking_attributes(case_id: str, check: str, coverages: list[Coverage]) -> Result | None:
    """A failed result when some frame lacks attribute rows, else None."""
    missing = _frames_without_attributes(coverages)
    if not missing:
        return None
    message = (f"{len(missing)} of {len(coverages)} frames came back without one attribute row per covered pixel "
               f"(first: frame {missing[0]}); a rasterizer that interpolates nothing should say so with interpolates = False")
    return result(case_id, check, False, message, {"frames_without_attributes": float(len(missing))},
                   {"frames_without_attributes": missing[:EVIDENCE_LIMIT]})


def _without_uv(case_id: str, check: str, coverages: list[Coverage]) -> Result | None:
    """A failed result when some frame's attribute rows hold fewer than the two columns
    (u, v) the check compares, else None."""
    narrow = [f for f, c in enumerate(coverages) if c.attributes is not None and c.n_pixels and c.attributes.shape[1] < 2]
    if not narrow:
        return None
    return result(case_id, check, False,
                  f"{len(narrow)} of {len(coverages)} frames came back with fewer than the two attribute columns (u, v) "
                  f"interpolated (first: frame {narrow[0]}, {coverages[narrow[0]].attributes.shape[1]} columns)",  # type: ignore[union-attr]
                  {"frames_without_attributes": float(len(narrow))}, {"frames_without_attributes": narrow[:EVIDENCE_LIMIT]})


def _backward_texel_steps(tracked: list[tuple[NDArray, NDArray, NDArray, NDArray]]) -> list[dict[str, Any]]:
    """At each pixel (triangle, x, y), followed over the frames that cover it, the steps
    from one frame to the next where the texel index moves against the oracle's (whose
    direction is filled over its still steps as by :func:`filled_direction`; steps over
    a gap of frames are not compared), along u and v: ordered by frame, then pixel (in
    the order of their first frame, then (triangle, y, x)), then axis."""
    if not tracked:
        return []
    frame = np.concatenate([t[0] for t in tracked]).astype(float)
    keys = np.concatenate([t[1] for t in tracked])
    got = np.concatenate([t[2] for t in tracked])
    want = np.concatenate([t[3] for t in tracked])
    big = np.int64(1) << 20
    pixel = (keys[:, 0] * big + keys[:, 2]) * big + keys[:, 1]
    order = np.argsort(pixel, kind="stable")  # each pixel's frames stay in order
    frame, keys, got, want, pixel = frame[order], keys[order], got[order], want[order], pixel[order]
    n = pixel.size
    if n < 2:
        return []
    same = pixel[1:] == pixel[:-1]  # step k (row k to k + 1) within one pixel's track
    start = np.flatnonzero(np.r_[True, ~same])  # each track's first row
    track = np.cumsum(np.r_[True, ~same]) - 1
    first_step = start[track[:-1]]  # the track's first step (= first row)
    last_step = np.r_[start[1:], n][track[:-1]] - 2  # and its last
    first_frame = frame[start][track]
    contiguous = same & (np.diff(frame) == 1)
    index = np.arange(n - 1)
    found = []
    for axis in (0, 1):
        got_steps = np.where(contiguous, np.diff(got[:, axis]), np.nan)
        sign = np.where(same, np.nan_to_num(np.sign(np.where(contiguous, np.diff(want[:, axis]), np.nan))), 0.0)
        nonzero = sign != 0
        last = np.maximum.accumulate(np.where(nonzero, index, -1))  # the most recent move, if in this track
        forward = np.where(last >= first_step, sign[np.maximum(last, 0)], 0.0)
        following = np.minimum.accumulate(np.where(nonzero, index, n)[::-1])[::-1]  # else the next one
        backward = np.where(following <= last_step, sign[np.minimum(following, n - 2)], 0.0)
        direction = np.where(forward != 0, forward, backward)
        back = same & np.isfinite(got_steps) & (got_steps != 0) & (np.sign(got_steps) == -direction) & (direction != 0)
        found.append(np.flatnonzero(back))
    steps = np.concatenate(found)
    axes = np.repeat([0, 1], [len(found[0]), len(found[1])])
    rows = steps + 1
    ranked = np.lexsort((axes, pixel[rows], first_frame[rows], frame[rows]))
    return [{"frame": int(frame[rows[k]]), "triangle": int(keys[rows[k], 0]), "x": int(keys[rows[k], 1]),
             "y": int(keys[rows[k], 2]), "axis": "uv"[axes[k]]} for k in ranked]


def texel_swimming(case_id: str, coverages: list[Coverage], oracles: list[Coverage], texels: int) -> Result:
    """The nearest texel (floor(u*T), floor(v*T)) at each covered pixel against the
    oracle's, mismatches at exact texel edges excused; at a fixed pixel, the texel index
    moves only the way the oracle's does (backward steps counted); the largest u, v error
    in texels."""
    lacking = _lacking_attributes(case_id, "texel", coverages)
    if lacking is not None:
        return lacking
    narrow = _without_uv(case_id, "texel", coverages)
    if narrow is not None:  # no u, v to take a texel from
        return narrow
    mismatches = 0
    worst = 0.0
    per_frame_mismatch = []
    per_frame_error = []
    examples: list[dict[str, Any]] = []
    tracked = []  # per frame: (frame, keys, texel got, texel exact) of the pixels with a finite u, v
    for f, (cov, oracle) in enumerate(zip(coverages, oracles)):
        keys, got, want = _matched(cov, oracle)
        if not len(keys):
            per_frame_mismatch.append(0)
            per_frame_error.append(0.0)
            continue
        scaled_got, scaled_want = got[:, :2] * texels, want[:, :2] * texels
        error = np.abs(scaled_got - scaled_want)
        finite = np.isfinite(error).all(axis=1)
        frame_error = float(error[finite].max()) if finite.any() else float("inf")
        texel_got, texel_want = np.floor(scaled_got), np.floor(scaled_want)
        tie = np.abs(scaled_want - np.round(scaled_want)) <= TIE * np.maximum(1.0, np.abs(scaled_want))
        bad = ((texel_got != texel_want) & ~tie).any(axis=1) | ~finite
        mismatches += int(bad.sum())
        worst = max(worst, frame_error if finite.all() else float("inf"))
        per_frame_mismatch.append(int(bad.sum()))
        per_frame_error.append(frame_error)
        for k in np.flatnonzero(bad)[: max(0, EVIDENCE_LIMIT - len(examples))]:
            examples.append({"frame": f, "triangle": int(keys[k, 0]), "x": int(keys[k, 1]), "y": int(keys[k, 2]),
                             "texel": texel_got[k].tolist(), "exact": texel_want[k].tolist()})
        # a NaN or infinite u, v has no texel to track (counted above)
        tracked.append((np.full(int(finite.sum()), f), keys[finite], texel_got[finite], texel_want[finite]))
    backward = _backward_texel_steps(tracked)
    metrics = {"texel_mismatches": float(mismatches), "max_uv_error_texels": worst, "swim_backward_steps": float(len(backward))}
    evidence: dict[str, Any] = {"series": {"mismatches": per_frame_mismatch, "max_uv_error_texels": per_frame_error}}
    if examples:
        evidence["mismatches"] = examples
    if backward:
        evidence["backward_steps"] = backward[:EVIDENCE_LIMIT]
    ok = mismatches == 0 and not backward
    message = (f"texels match the exact ones (largest u, v error {worst:.2g} texels)" if ok
               else f"{mismatches} texel mismatches outside exact ties, {len(backward)} backward texel steps, largest u, v error "
                    f"{worst:.3g} texels")
    return result(case_id, "texel", ok, message, metrics, evidence)


def perspective(case_id: str, coverages: list[Coverage], oracles: list[Coverage], texels: int,
                tolerance: Tolerance = Tolerance()) -> Result:
    """u, v against the exact perspective-correct values, in texels: the largest error may
    not exceed ``tolerance.uv_error`` texels."""
    lacking = _lacking_attributes(case_id, "perspective", coverages) or _without_uv(case_id, "perspective", coverages)
    if lacking is not None:
        return lacking
    worst = 0.0
    where: dict[str, Any] = {}
    for f, (cov, oracle) in enumerate(zip(coverages, oracles)):
        keys, got, want = _matched(cov, oracle)
        if not len(keys):
            continue
        error = np.abs(got[:, :2] - want[:, :2]).max(axis=1) * texels
        error = np.where(np.isfinite(error), error, np.inf)
        k = int(np.argmax(error))
        if error[k] > worst:
            worst = float(error[k])
            where = {"frame": f, "triangle": int(keys[k, 0]), "x": int(keys[k, 1]), "y": int(keys[k, 2]),
                     "uv": got[k, :2].tolist(), "exact_uv": want[k, :2].tolist()}
    ok = worst <= tolerance.uv_error
    message = (f"perspective-correct: largest u, v error {worst:.2g} texels" if ok
               else f"u, v off by up to {worst:.3g} texels from the perspective-correct values (limit {tolerance.uv_error:g})")
    return result(case_id, "perspective", ok, message, {"max_uv_error_texels": worst}, {"worst": where} if where else {})


def _is_motion(case: Any) -> bool:
    return hasattr(case, "frames")


def _jaggy(s: Subject) -> Result:
    first_frame = s.case.frames[0]
    return jaggy(s.case.id, s.coverages, s.oracles, len(first_frame), first_frame.width, first_frame.height)


register(Check(
    "jaggy", _jaggy, _is_motion, needs_convention=True, metrics={"flicker": (1.0, 0.0), "backward_jumps": (1.0, 0.0)},
    caption="under sub-pixel motion no pixel flickers more than the exact answer and no span end jumps backwards",
    classifier="harness.diagnose.signatures:classify_jaggy", cause_role="own", motion_role="through-frames", figures=(),
))
register(Check(
    "texel", lambda s: texel_swimming(s.case.id, s.coverages, s.oracles, s.case.texels),
    lambda case: _is_motion(case) and bool(case.texels), needs_convention=True, needs_attributes=True,
    metrics={"texel_mismatches": (1.0, 0.0), "swim_backward_steps": (1.0, 0.0)},
    caption="the nearest texel is the exact one and never steps backwards under translation",
    classifier="harness.diagnose.signatures:classify_texel", cause_role="own", motion_role="through-frames", figures=(),
))
register(Check(
    "perspective", lambda s: perspective(s.case.id, s.coverages, s.oracles, s.case.texels or 1, s.tolerance),
    lambda case: _is_motion(case) and bool(case.perspective), needs_convention=True, needs_attributes=True,
    metrics={"max_uv_error_texels": (2.0, 1e-9)},
    caption="u, v against the exact perspective-correct values",
    classifier="harness.diagnose.signatures:classify_perspective", cause_role="own", motion_role="through-frames", figures=(),
))
