"""The ``closed`` rule with dropout control: TrueType's scan conversion as FreeType's
monochrome rasterizer (``src/raster/ftraster.c``, FreeType 2.13.2) runs it, one triangle
at a time (each triangle is one outline).

Without dropout control and with exact crossings this is the closed rule
(:mod:`harness.oracle.closed_rule`). :class:`~harness.contract.conventions.Dropout` adds:

Crossings (``step_bits``)
    None: each edge's crossing with a scanline through pixel centres is exact. 6:
    ftraster.c's ``Line_Up`` (``Line_Down`` calls it with y negated): in its frame (26.6
    shifted by half a pixel, ``SCALED``, so that pixel centres sit on multiples of 64), an
    edge from (x1, y1) to (x2, y2) crosses its first scanline e1 = CEILING(y1) at
    ``x1 + MulDiv(Dx, e1 - y1, Dy)`` (rounded to nearest, halves away from zero;
    ``FT_MulDiv``), and every further scanline k steps on at
    ``x_first + sign(Dx) * floor(64 k |Dx| / Dy)`` (``FT_MulDiv_No_Round`` plus the
    remainder ``Ax``): stepped from the edge's start, so the pixels depend on its
    direction. An edge clipped at the bitmap's bottom (or top, descending) starts there,
    rounded likewise. Where two edges of one monotone chain meet on a scanline, the later
    edge's crossing (its start, exact) replaces the earlier's (``ras.joint``).
Spans (both sweeps)
    Up and down profiles (the monotone chains of the contour) are sorted by their crossing
    on each scanline and paired; a pair draws CEILING(x1) .. FLOOR(x2) (the closed rule)
    in the vertical sweep (per pixel-centre row); the horizontal sweep (per column, x and
    y swapped) draws only span ends lying exactly on a pixel centre
    (``Horizontal_Sweep_Span``: horizontal edges through centres).
Dropouts (``mode``; ``Draw_Sweep``, ``Vertical_Sweep_Drop``, ``Horizontal_Sweep_Drop``)
    A pair whose ends lie strictly between the same two neighbouring pixel centres
    (``x2 - x1 <= 1 px``, no centre in [x1, x2]) is a dropout: after the scanline's spans,
    the left pixel (``simple``, SCANTYPE 0/1) or SMART(x1, x2) = FLOOR((x1 + x2 + 63/64 px) / 2)
    (``smart``, 4/5: the centre nearer the midpoint, ties and the 1/128 px above them to
    the left) is set, unless the other of the two pixels is already set; a pixel outside
    the bitmap is replaced by the one inside ("undocumented but confirmed"). With stubs
    excluded (1, 5), a dropout at the top scanline of an up profile whose contour
    successor is the paired down profile (an upper stub), or at the bottom scanline of an
    up profile that follows its paired down profile (a lower stub), is skipped unless
    that profile overshoots the scanline by at least half a pixel (``Overshoot_Top``,
    ``Overshoot_Bottom``, set from the turning vertex; the contour's first profile from
    its first vertex) and the pair is at least half a pixel wide. With dropout control
    on, a vertical span of at most 1 px + 2/64 whose ends both miss pixel centres draws
    its first pixel only (``Vertical_Sweep_Span``).
The render pool
    ftraster.c converts the outline into profiles in a fixed pool (16384 bytes: 2,040
    Longs for headers of 8 and crossings of 1, less one per distinct turning scanline);
    when they do not fit (a triangle over about 1,000 px tall), it bisects the bitmap into
    bands, upper half first, and converts each band on its own: an edge then starts again
    at the band's lower (upper) edge, its first crossing there rounded as at a clip. The
    oracle does the same accounting and bisection (``Render_Single_Pass``), so the
    pixels of tall triangles are FreeType's too.
The bitmap
    FreeType draws into the caller's bitmap and clips at its edges; the harness's adapter
    (:mod:`rasterizers.real.freetype_outline`, :func:`rasterizers.real._masks.draw_each`)
    gives each triangle its bounding box grown by 2 px, clipped to the viewport, so a
    triangle is clipped only at the viewport's edges, which is what this oracle does
    (the rule is translation invariant by whole pixels otherwise).

Zero-area triangles: their up and down profiles coincide (stepped from different starts,
they may differ by the rounding); without dropout control they draw the centres they pass
through (the closed rule's segment), with it also a dropout pixel per scanline and column
they cross. A triangle collapsed to a point has no profile and draws nothing.

The stepped arithmetic is integer and exact; the per-triangle work is compiled (numba,
cached) for 26.6 coordinates within +/-2**25 (products below 2**53), in Python integers
beyond. Exact crossings are rationals (:class:`fractions.Fraction`, Python).
:func:`scan_convert_reference` is the slow, line-by-line transcription of ftraster.c used
as the reference in tests (and checked against FreeType itself there).
"""

from __future__ import annotations

from dataclasses import replace  # noqa: F401  (doctests)
from fractions import Fraction
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene, Scene
from harness.geometry.exact import orientation
from harness.oracle.closed_rule import closed_coverage

__all__ = ["closed_triangles", "closed_paths", "dropout_coverage", "scan_convert_reference", "scan_convert",
           "stepped_crossing"]

P = 64  # ftraster.c's precision in its default (low) precision: 1/64 px, the 26.6 grid
HALF = 32
JITTER = 2  # precision_jitter at 1/64 px (ftraster.c Set_High_Precision)
FLOW_UP, OVERSHOOT_TOP, OVERSHOOT_BOTTOM = 8, 16, 32  # the profile flags above the 3 dropout-mode bits
MARGIN = 2  # the adapter's box margin (rasterizers.real._masks.draw_each)
# ftraster.c's render pool: FT_RENDER_POOL_SIZE (16384 bytes, ftoption.h) of 8-byte Longs, a profile's header
# taking AlignProfileSize = sizeof(TProfile) / sizeof(Long) = 64 / 8 of them (64-bit builds)
POOL = 16384 // 8
PROFILE_LONGS = 8


class _Overflow(Exception):
    """Raster_Overflow: the band's profiles do not fit the render pool (ftraster.c then
    bisects the band: Render_Single_Pass)."""
# 26.6 coordinates up to this magnitude take the compiled kernel: every product below 2**53
KERNEL_LIMIT = 2**25


def stepped_crossing(x1: int, y1: int, x2: int, y2: int, scanline: int) -> int:
    """ftraster.c's crossing of the edge (x1, y1) -> (x2, y2) (its SCALED 1/64 px frame, y1 < y2,
    no clipping) with ``scanline`` (a multiple of 64 in [y1, y2]), stepped from the start.

    The exact crossings are 18.6, 40.7, 62.8 and 84.8: the first rounds up, the steps
    then truncate.

    >>> [stepped_crossing(0, 10, 100, 300, s) for s in (64, 128, 192, 256)]
    [19, 41, 63, 85]
    """
    dx, dy = x2 - x1, y2 - y1
    e1 = -((-y1) // P) * P
    first = x1 + _mul_div(dx, e1 - y1, dy, True)
    k = (scanline - e1) // P
    step = (k * P * abs(dx)) // dy
    return int(first + (step if dx >= 0 else -step))


def _mul_div(a: Any, b: Any, c: Any, rounded: bool) -> Any:
    """FT_MulDiv (rounded: halves away from zero) and FT_MulDiv_No_Round (truncated)."""
    negative = (a < 0) ^ (b < 0) ^ (c < 0)
    a, b, c = abs(a), abs(b), abs(c)
    d = (a * b + (c // 2 if rounded else 0)) // c
    return -d if negative else d


def _floor(x: Any) -> Any:
    return (x // P) * P


def _ceiling(x: Any) -> Any:
    return -((-x) // P) * P


def _trunc(x: Any) -> int:
    return int(x // P)


class _Profile:
    """One profile record (ftraster.c's TProfile)."""

    __slots__ = ("start", "height", "entries", "flags", "next", "bottom", "top")

    def __init__(self) -> None:
        self.start: int = 0
        self.height = 0
        self.entries: list[Any] = []
        self.flags = 0
        self.next: _Profile | None = None
        self.bottom = 0
        self.top = 0


class _Builder:
    """Convert_Glyph for straight contours: the profiles of one sweep."""

    def __init__(self, mode: int, miny: int, maxy: int, stepped: bool) -> None:
        self.mode, self.miny, self.maxy, self.stepped = mode, miny, maxy, stepped
        self.profiles: list[_Profile] = []
        self.cur = _Profile()
        self.first: _Profile | None = None
        self.state = 0
        self.fresh = self.joint = False
        self.last_x: Any = 0
        self.last_y: Any = 0
        self.top = 0  # the render pool's use, in Longs (headers and crossings)
        self.max_buff = POOL - PROFILE_LONGS
        self.allocated = False

    def new_profile(self, state: int, overshoot: bool) -> None:
        if not self.allocated:  # the first profile's header
            self.top += PROFILE_LONGS
            self.allocated = True
        if self.top >= self.max_buff:
            raise _Overflow
        c = self.cur
        c.start, c.height, c.entries, c.next, c.flags = 0, 0, [], None, self.mode
        if state > 0:
            c.flags |= FLOW_UP | (OVERSHOOT_BOTTOM if overshoot else 0)
        elif overshoot:
            c.flags |= OVERSHOOT_TOP
        if self.first is None:
            self.first = c
        self.state, self.fresh, self.joint = state, True, False

    def end_profile(self, overshoot: bool) -> None:
        c = self.cur
        if c.entries:
            c.height = len(c.entries)
            if overshoot:
                c.flags |= OVERSHOOT_TOP if c.flags & FLOW_UP else OVERSHOOT_BOTTOM
            self.profiles.append(c)
            c.next = self.cur = _Profile()
            self.top += PROFILE_LONGS
        if self.top >= self.max_buff:
            raise _Overflow
        self.joint = False

    def line_up(self, x1: Any, y1: Any, x2: Any, y2: Any, miny: int, maxy: int, sign: int) -> None:
        c = self.cur
        dx, dy = x2 - x1, y2 - y1
        if dy <= 0 or y2 < miny or y1 > maxy:
            return
        if y1 < miny:
            x1 = x1 + (_mul_div(dx, miny - y1, dy, True) if self.stepped else Fraction(dx * (miny - y1)) / dy)
            e1, f1 = _trunc(miny), 0
        else:
            e1, f1 = _trunc(y1), y1 - _floor(y1)
        e2, f2 = (_trunc(maxy), 0) if y2 > maxy else (_trunc(y2), y2 - _floor(y2))
        if f1 > 0:
            if e1 == e2:
                return
            x1 = x1 + (_mul_div(dx, P - f1, dy, True) if self.stepped else Fraction(dx * (P - f1)) / dy)
            e1 += 1
        elif self.joint:
            c.entries.pop()  # ras.top--: this edge's exact start replaces the last crossing
            self.top -= 1
            self.joint = False
        self.joint = f2 == 0
        if self.fresh:
            c.start, self.fresh = e1 * sign, False
        size = e2 - e1 + 1
        if self.top + size >= self.max_buff:
            raise _Overflow
        self.top += size
        if self.stepped:
            ix = _mul_div(P, abs(dx), dy, False)
            rx, step = (P * abs(dx)) % dy, (1 if dx > 0 else -1)
            ix = ix if dx > 0 else -ix
            ax = -dy
            for _ in range(size):
                c.entries.append(x1)
                x1 += ix
                ax += rx
                if ax >= 0:
                    ax -= dy
                    x1 += step
        else:
            c.entries += [x1 + Fraction(dx * P * k) / dy for k in range(size)]

    def line_to(self, x: Any, y: Any) -> None:
        ly = self.last_y
        top_overshoot, bottom_overshoot = ly - _floor(ly) >= HALF, _ceiling(ly) - ly >= HALF
        if self.state == 0:
            if y > ly:
                self.new_profile(1, bottom_overshoot)
            elif y < ly:
                self.new_profile(-1, top_overshoot)
        elif self.state > 0 and y < ly:
            self.end_profile(top_overshoot)
            self.new_profile(-1, top_overshoot)
        elif self.state < 0 and y > ly:
            self.end_profile(bottom_overshoot)
            self.new_profile(1, bottom_overshoot)
        if self.state > 0:
            self.line_up(self.last_x, ly, x, y, self.miny, self.maxy, 1)
        elif self.state < 0:
            self.line_up(self.last_x, -ly, x, -y, -self.maxy, -self.miny, -1)
        self.last_x, self.last_y = x, y

    def contour(self, points: list[tuple[Any, Any]]) -> None:
        self.state, self.first = 0, None
        self.last_x, self.last_y = points[0]
        for x, y in points[1:] + points[:1]:
            self.line_to(x, y)
        ly = self.last_y
        if ly - _floor(ly) == 0 and self.miny <= ly <= self.maxy and self.first is not None \
                and (self.first.flags & FLOW_UP) == (self.cur.flags & FLOW_UP):
            self.cur.entries.pop()  # the first and last profiles meet on a scanline: once
            self.top -= 1
        last = self.cur
        up_with_entries = bool(self.cur.entries) and bool(self.cur.flags & FLOW_UP)
        self.end_profile(ly - _floor(ly) >= HALF if up_with_entries else _ceiling(ly) - ly >= HALF)
        if self.first is not None:
            last.next = self.first

    def finalize(self) -> list[_Profile]:
        if len(self.profiles) <= 1:
            return []
        turns: set[int] = set()
        for p in self.profiles:
            if p.flags & FLOW_UP:
                p.bottom, p.top = p.start, p.start + p.height - 1
            else:
                p.bottom, p.top = p.start - p.height + 1, p.start
                p.start = p.bottom
            for turn in (p.bottom, p.top + 1):  # Insert_Y_Turn: each new one takes a Long off the pool's end
                if turn not in turns:
                    turns.add(turn)
                    self.max_buff -= 1
                    if self.max_buff <= self.top:
                        raise _Overflow
        return self.profiles


def _x_at(p: _Profile, y: int) -> Any:
    return p.entries[y - p.bottom] if p.flags & FLOW_UP else p.entries[p.top - y]


def _smart(x1: Any, x2: Any) -> Any:
    """SMART(p, q) = FLOOR((p + q + 63) >> 1) (63 = 64 * 63 / 64), for integers or rationals."""
    s = x1 + x2 + P * 63 // 64
    return _floor(s // 2 if isinstance(s, int) else s / 2)


def _sweep(profiles: list[_Profile], n_span: int, bitmap: NDArray[np.bool_], vertical: bool, mode: int) -> None:
    """Draw_Sweep with the vertical or horizontal span and drop functions."""
    h = bitmap.shape[0]

    def at(scan: int, e: int) -> tuple[int, int]:
        return (h - 1 - scan, e) if vertical else (h - 1 - e, scan)

    if not profiles:
        return
    for y in range(min(p.bottom for p in profiles), max(p.top for p in profiles) + 1):
        active = [p for p in profiles if p.bottom <= y <= p.top]
        lefts = sorted((p for p in active if p.flags & FLOW_UP), key=lambda p: _x_at(p, y))
        rights = sorted((p for p in active if not p.flags & FLOW_UP), key=lambda p: _x_at(p, y))
        drops = []
        for left, right in zip(lefts, rights):
            x1, x2 = sorted((_x_at(left, y), _x_at(right, y)))
            if x2 - x1 <= P and _floor(x1) != x1 and _ceiling(x2) != x2 and _ceiling(x2) == _floor(x1) + P:
                if mode != 2:
                    drops.append((left, right, x1, x2))
                continue
            e1, e2 = _ceiling(x1), _floor(x2)
            if vertical:
                if mode != 2 and x2 - x1 - P <= JITTER and e1 != x1 and e2 != x2:
                    e2 = e1
                for e in range(max(_trunc(e1), 0), min(_trunc(e2), n_span - 1) + 1):
                    bitmap[at(y, e)] = True
            else:  # the horizontal sweep: span ends exactly on a pixel centre only
                for end, exact in ((e1, x1 == e1), (e2, x2 == e2)):
                    if exact and 0 <= _trunc(end) < n_span:
                        bitmap[at(y, _trunc(end))] = True
        for left, right, x1, x2 in drops:
            e1, e2 = _ceiling(x1), _floor(x2)
            if mode in (1, 5):
                if left.next is right and y == left.top and not (left.flags & OVERSHOOT_TOP and x2 - x1 >= HALF):
                    continue  # an upper stub
                if right.next is left and left.start == y and not (left.flags & OVERSHOOT_BOTTOM and x2 - x1 >= HALF):
                    continue  # a lower stub
            pixel = e2 if mode in (0, 1) else _smart(x1, x2)
            if pixel < 0:
                pixel = e1  # outside the bitmap: the pixel inside instead
            elif _trunc(pixel) >= n_span:
                pixel = e2
            other = _trunc(e2 if pixel == e1 else e1)
            if 0 <= other < n_span and bitmap[at(y, other)]:
                continue
            if 0 <= _trunc(pixel) < n_span:
                bitmap[at(y, _trunc(pixel))] = True


def scan_convert_reference(contours: list[list[tuple[Any, Any]]], width: int, height: int, mode: int,
                           stepped: bool = True) -> NDArray[np.bool_]:
    """ftraster.c's bitmap, (height, width) bool, row 0 the top row, for straight contours
    of 26.6 points (x, y up; ints, or rationals when not ``stepped``) under dropout mode
    ``mode`` (SCANTYPE: 0, 1, 2, 4, 5): both sweeps, line by line as the C does. Slow."""
    bitmap = np.zeros((height, width), dtype=np.bool_)
    for vertical in (True, False):
        n_scan, n_span = (height, width) if vertical else (width, height)
        scaled = [[(x - HALF, y - HALF) for x, y in points] for points in contours]  # SCALED: pixel centres on the grid
        if not vertical:
            scaled = [[(y, x) for x, y in points] for points in scaled]
        # Render_Single_Pass: the whole bitmap, or (the pool overflowing) its upper half first, bisected again
        stack: list[int] = []
        y_min, y_max = 0, n_scan - 1
        while True:
            builder = _Builder(mode, y_min * P, y_max * P, stepped)
            try:
                for points in scaled:
                    builder.contour(points)
                profiles = builder.finalize()
            except _Overflow:
                if y_min == y_max:  # FreeType fails with Raster_Overflow: this band draws nothing
                    profiles = []
                else:
                    stack.append(y_min)
                    y_min = (y_min + y_max) // 2 + 1
                    continue
            _sweep(profiles, n_span, bitmap, vertical, mode)
            if not stack:
                break
            y_max, y_min = y_min - 1, stack.pop()
    return bitmap


# -- the compiled kernel: the same steps on arrays (one triangle, one sweep at a time) --------------
# state st: 0 top (entries used), 1 cur (record), 2 n_records, 3 state, 4 fresh, 5 joint, 6 first record (-1),
# 7 last_x, 8 last_y, 9 mode, 10 the pool's use in Longs, 11 maxBuff, 12 a header allocated, 13 overflowed (sticky:
# the band is bisected whatever else happens after it)
_MAX_RECORDS = 8  # a triangle's contour has at most 4 monotone chains, plus the empty record after the last


@numba.njit(cache=True)
def _k_floor(x):  # type: ignore[no-untyped-def]
    return (x // P) * P


@numba.njit(cache=True)
def _k_ceiling(x):  # type: ignore[no-untyped-def]
    return -((-x) // P) * P


@numba.njit(cache=True)
def _k_mul_div(a, b, c, rounded):  # type: ignore[no-untyped-def]
    negative = (a < 0) ^ (b < 0) ^ (c < 0)
    a, b, c = abs(a), abs(b), abs(c)
    d = (a * b + (c // 2 if rounded else 0)) // c
    return -d if negative else d


@numba.njit(cache=True)
def _k_new_profile(st, rec, state, overshoot):  # type: ignore[no-untyped-def]
    if st[12] == 0:
        st[10] += PROFILE_LONGS
        st[12] = 1
    if st[10] >= st[11]:
        st[13] = 1
    c = st[1]
    rec[c, 0] = 0  # start
    rec[c, 1] = 0  # height
    rec[c, 2] = st[0]  # offset
    rec[c, 3] = -1  # next
    rec[c, 4] = st[9]  # flags
    if state > 0:
        rec[c, 4] |= FLOW_UP
        if overshoot:
            rec[c, 4] |= OVERSHOOT_BOTTOM
    elif overshoot:
        rec[c, 4] |= OVERSHOOT_TOP
    if st[6] < 0:
        st[6] = c
    st[3] = state
    st[4] = 1
    st[5] = 0


@numba.njit(cache=True)
def _k_end_profile(st, rec, overshoot):  # type: ignore[no-untyped-def]
    c = st[1]
    h = st[0] - rec[c, 2]
    if h > 0:
        rec[c, 1] = h
        if overshoot:
            rec[c, 4] |= OVERSHOOT_TOP if rec[c, 4] & FLOW_UP else OVERSHOOT_BOTTOM
        new = c + 1
        rec[new, 0] = 0
        rec[new, 1] = 0
        rec[new, 2] = st[0]
        rec[new, 3] = -1
        rec[new, 4] = st[9]
        rec[c, 3] = new
        st[1] = new
        st[2] = new
        st[10] += PROFILE_LONGS
    if st[10] >= st[11]:
        st[13] = 1
    st[5] = 0


@numba.njit(cache=True)
def _k_line_up(st, rec, ent, x1, y1, x2, y2, miny, maxy, sign):  # type: ignore[no-untyped-def]
    dx = x2 - x1
    dy = y2 - y1
    if dy <= 0 or y2 < miny or y1 > maxy:
        return
    if y1 < miny:
        x1 += _k_mul_div(dx, miny - y1, dy, True)
        e1 = miny // P
        f1 = 0
    else:
        e1 = y1 // P
        f1 = y1 - _k_floor(y1)
    if y2 > maxy:
        e2 = maxy // P
        f2 = 0
    else:
        e2 = y2 // P
        f2 = y2 - _k_floor(y2)
    if f1 > 0:
        if e1 == e2:
            return
        x1 += _k_mul_div(dx, P - f1, dy, True)
        e1 += 1
    elif st[5]:
        st[0] -= 1
        st[10] -= 1
        st[5] = 0
    st[5] = 1 if f2 == 0 else 0
    if st[4]:
        rec[st[1], 0] = e1 * sign
        st[4] = 0
    size = e2 - e1 + 1
    if st[10] + size >= st[11]:
        st[13] = 1
        return
    st[10] += size
    ix = _k_mul_div(P, abs(dx), dy, False)
    rx = (P * abs(dx)) % dy
    step = 1
    if dx <= 0:
        ix = -ix
        step = -1
    ax = -dy
    top = st[0]
    for _ in range(size):
        ent[top] = x1
        top += 1
        x1 += ix
        ax += rx
        if ax >= 0:
            ax -= dy
            x1 += step
    st[0] = top


@numba.njit(cache=True)
def _k_line_to(st, rec, ent, x, y, miny, maxy):  # type: ignore[no-untyped-def]
    ly = st[8]
    top_overshoot = ly - _k_floor(ly) >= HALF
    bottom_overshoot = _k_ceiling(ly) - ly >= HALF
    if st[3] == 0:
        if y > ly:
            _k_new_profile(st, rec, 1, bottom_overshoot)
        elif y < ly:
            _k_new_profile(st, rec, -1, top_overshoot)
    elif st[3] > 0 and y < ly:
        _k_end_profile(st, rec, top_overshoot)
        _k_new_profile(st, rec, -1, top_overshoot)
    elif st[3] < 0 and y > ly:
        _k_end_profile(st, rec, bottom_overshoot)
        _k_new_profile(st, rec, 1, bottom_overshoot)
    if st[3] > 0:
        _k_line_up(st, rec, ent, st[7], ly, x, y, miny, maxy, 1)
    elif st[3] < 0:
        _k_line_up(st, rec, ent, st[7], -ly, x, -y, -maxy, -miny, -1)
    st[7] = x
    st[8] = y


@numba.njit(cache=True)
def _k_profiles(xs, ys, band_min, band_max, mode, rec, ent):  # type: ignore[no-untyped-def]
    """Convert_Glyph for one triangle (scaled, maybe flipped, points xs, ys) in the band of
    scanlines band_min .. band_max: the records (start = bottom, height, offset, next,
    flags, top) and how many hold entries (0: none drawn, Finalize_Profile_Table's
    single-profile case; -1: the render pool overflowed)."""
    st = np.zeros(14, dtype=np.int64)
    st[6] = -1
    st[9] = mode
    st[11] = POOL - PROFILE_LONGS
    rec[0, 2] = 0
    miny = band_min * P
    maxy = band_max * P
    st[7] = xs[0]
    st[8] = ys[0]
    for k in (1, 2, 0):
        _k_line_to(st, rec, ent, xs[k], ys[k], miny, maxy)
    ly = st[8]
    c = st[1]
    if ly - _k_floor(ly) == 0 and miny <= ly <= maxy and st[6] >= 0 and (rec[st[6], 4] & FLOW_UP) == (rec[c, 4] & FLOW_UP):
        st[0] -= 1
        st[10] -= 1
    if st[0] != rec[c, 2] and rec[c, 4] & FLOW_UP:
        overshoot = ly - _k_floor(ly) >= HALF
    else:
        overshoot = _k_ceiling(ly) - ly >= HALF
    _k_end_profile(st, rec, overshoot)
    if st[6] >= 0:
        rec[c, 3] = st[6]
    n = st[1]  # records 0 .. n - 1 hold entries (the current one is empty)
    if st[13]:
        return -1
    if n <= 1:
        return 0
    turns = np.empty(2 * n, dtype=np.int64)
    n_turns = 0
    for p in range(n):
        if rec[p, 4] & FLOW_UP:
            rec[p, 5] = rec[p, 0] + rec[p, 1] - 1
        else:
            rec[p, 5] = rec[p, 0]
            rec[p, 0] = rec[p, 0] - rec[p, 1] + 1
        for turn in (rec[p, 0], rec[p, 5] + 1):  # Insert_Y_Turn: each new one takes a Long off the pool's end
            seen = False
            for k in range(n_turns):
                if turns[k] == turn:
                    seen = True
            if not seen:
                turns[n_turns] = turn
                n_turns += 1
                st[11] -= 1
                if st[11] <= st[10]:
                    return -1
    return n


@numba.njit(cache=True)
def _k_x_at(rec, ent, p, y):  # type: ignore[no-untyped-def]
    if rec[p, 4] & FLOW_UP:
        return ent[rec[p, 2] + y - rec[p, 0]]
    return ent[rec[p, 2] + rec[p, 5] - y]


@numba.njit(cache=True)
def _k_get(bitmap, vertical, scan, e):  # type: ignore[no-untyped-def]
    h = bitmap.shape[0]
    if vertical:
        return bitmap[h - 1 - scan, e]
    return bitmap[h - 1 - e, scan]


@numba.njit(cache=True)
def _k_set(bitmap, vertical, scan, e):  # type: ignore[no-untyped-def]
    h = bitmap.shape[0]
    if vertical:
        bitmap[h - 1 - scan, e] = True
    else:
        bitmap[h - 1 - e, scan] = True


@numba.njit(cache=True)
def _k_sweep(rec, ent, n, n_span, bitmap, vertical, mode):  # type: ignore[no-untyped-def]
    lo = rec[0, 0]
    hi = rec[0, 5]
    for p in range(n):
        lo = min(lo, rec[p, 0])
        hi = max(hi, rec[p, 5])
    lefts = np.empty(n, dtype=np.int64)
    rights = np.empty(n, dtype=np.int64)
    lx = np.empty(n, dtype=np.int64)
    rx = np.empty(n, dtype=np.int64)
    drops = np.empty((n, 4), dtype=np.int64)
    for y in range(lo, hi + 1):
        nl = 0
        nr = 0
        for p in range(n):
            if rec[p, 0] <= y <= rec[p, 5]:
                x = _k_x_at(rec, ent, p, y)
                if rec[p, 4] & FLOW_UP:  # insertion sort by x, stable
                    k = nl
                    while k > 0 and lx[k - 1] > x:
                        lx[k] = lx[k - 1]
                        lefts[k] = lefts[k - 1]
                        k -= 1
                    lx[k] = x
                    lefts[k] = p
                    nl += 1
                else:
                    k = nr
                    while k > 0 and rx[k - 1] > x:
                        rx[k] = rx[k - 1]
                        rights[k] = rights[k - 1]
                        k -= 1
                    rx[k] = x
                    rights[k] = p
                    nr += 1
        nd = 0
        for k in range(min(nl, nr)):
            x1 = min(lx[k], rx[k])
            x2 = max(lx[k], rx[k])
            if x2 - x1 <= P and _k_floor(x1) != x1 and _k_ceiling(x2) != x2 and _k_ceiling(x2) == _k_floor(x1) + P:
                if mode != 2:  # a dropout: drawn after the scanline's spans
                    drops[nd, 0] = lefts[k]
                    drops[nd, 1] = rights[k]
                    drops[nd, 2] = x1
                    drops[nd, 3] = x2
                    nd += 1
                continue
            _k_span(bitmap, vertical, mode, y, x1, x2, n_span)
        for d in range(nd):
            _k_drop(rec, bitmap, vertical, mode, y, drops[d, 0], drops[d, 1], drops[d, 2], drops[d, 3], n_span)


@numba.njit(cache=True)
def _k_span(bitmap, vertical, mode, y, x1, x2, n_span):  # type: ignore[no-untyped-def]
    """Vertical_Sweep_Span (CEILING(x1) .. FLOOR(x2)) or Horizontal_Sweep_Span (the ends on centres)."""
    e1 = _k_ceiling(x1)
    e2 = _k_floor(x2)
    if vertical:
        if mode != 2 and x2 - x1 - P <= JITTER and e1 != x1 and e2 != x2:
            e2 = e1
        for e in range(max(e1 // P, 0), min(e2 // P, n_span - 1) + 1):
            _k_set(bitmap, vertical, y, e)
    else:
        if x1 == e1 and 0 <= e1 // P < n_span:
            _k_set(bitmap, vertical, y, e1 // P)
        if x2 == e2 and 0 <= e2 // P < n_span:
            _k_set(bitmap, vertical, y, e2 // P)


@numba.njit(cache=True)
def _k_drop(rec, bitmap, vertical, mode, y, left, right, x1, x2, n_span):  # type: ignore[no-untyped-def]
    """Vertical_Sweep_Drop / Horizontal_Sweep_Drop for one dropout pair."""
    e1 = _k_ceiling(x1)
    e2 = _k_floor(x2)
    if mode == 1 or mode == 5:
        if rec[left, 3] == right and y == rec[left, 5] and not (rec[left, 4] & OVERSHOOT_TOP and x2 - x1 >= HALF):
            return  # an upper stub
        if rec[right, 3] == left and rec[left, 0] == y and not (rec[left, 4] & OVERSHOOT_BOTTOM and x2 - x1 >= HALF):
            return  # a lower stub
    if mode == 0 or mode == 1:
        pixel = e2
    else:
        pixel = _k_floor((x1 + x2 + P * 63 // 64) // 2)  # SMART
    if pixel < 0:
        pixel = e1
    elif pixel // P >= n_span:
        pixel = e2
    other = (e2 if pixel == e1 else e1) // P
    if 0 <= other < n_span and _k_get(bitmap, vertical, y, other):
        return
    if 0 <= pixel // P < n_span:
        _k_set(bitmap, vertical, y, pixel // P)


@numba.njit(cache=True)
def scan_convert(points, width, height, mode, bitmap):  # type: ignore[no-untyped-def]
    """The compiled :func:`scan_convert_reference` for one triangle: ``points`` (3, 2) int64
    in 26.6 (y up), ``bitmap`` (height, width) bool, drawn into."""
    rec = np.zeros((_MAX_RECORDS, 6), dtype=np.int64)
    for vertical in (True, False):
        n_scan = height if vertical else width
        n_span = width if vertical else height
        xs = np.empty(3, dtype=np.int64)
        ys = np.empty(3, dtype=np.int64)
        for k in range(3):
            if vertical:
                xs[k] = points[k, 0] - HALF
                ys[k] = points[k, 1] - HALF
            else:
                xs[k] = points[k, 1] - HALF
                ys[k] = points[k, 0] - HALF
        ent = np.empty(3 * (n_scan + 2) + 8, dtype=np.int64)
        # Render_Single_Pass: the whole bitmap, or (the pool overflowing) its upper half first, bisected again
        stack = np.empty(64, dtype=np.int64)
        depth = 0
        y_min = 0
        y_max = n_scan - 1
        while True:
            rec[:, :] = 0
            n = _k_profiles(xs, ys, y_min, y_max, mode, rec, ent)
            if n < 0 and y_min != y_max:
                stack[depth] = y_min
                depth += 1
                y_min = (y_min + y_max) // 2 + 1
                continue
            if n > 0:
                _k_sweep(rec, ent, n, n_span, bitmap, vertical, mode)
            if depth == 0:
                break
            y_max = y_min - 1
            depth -= 1
            y_min = stack[depth]


def _mask_runs(t: int, mask: NDArray[np.bool_], x0: int, y0: int) -> list[tuple[int, int, int, int]]:
    """(triangle, row, x0, x1) runs of a box's mask, in screen coordinates."""
    out = []
    for r in np.flatnonzero(mask.any(axis=1)):
        row = mask[r]
        edges = np.flatnonzero(np.diff(np.concatenate([[False], row, [False]]).astype(np.int8)))
        out += [(t, int(r) + y0, int(a) + x0, int(b) + x0) for a, b in zip(edges[::2], edges[1::2])]
    return out


def dropout_coverage(scene: Scene, convention: Convention) -> Coverage:
    """The exact coverage of a triangle scene under ``coverage="closed"`` with
    ``convention.dropout`` (module docstring): each finite, unculled triangle scan-converted
    on its own, in its bounding box grown by 2 px and clipped to the viewport.

    A sliver thinner than a pixel between two centres draws nothing under the closed rule
    and one pixel per row and column under dropout control:

    >>> from harness.contract.conventions import Dropout
    >>> scene = Scene(4, 3, [[[0.25, 1.25], [3.75, 1.375], [0.25, 1.375]]])
    >>> closed = Convention(coverage="closed", input="fixed6")
    >>> int(dropout_coverage(scene, closed).counts(4, 3).sum())
    0
    >>> dropout_coverage(scene, replace(closed, dropout=Dropout("smart", step_bits=6))).counts(4, 3).tolist()
    [[0, 0, 0, 0], [1, 1, 1, 1], [0, 0, 0, 0]]
    """
    dropout = convention.dropout_control
    mode = dropout.scantype
    stepped = dropout.step_bits is not None
    positions = convention.receive(scene.positions)
    sign = orientation(np.where(np.isfinite(positions), positions, np.nan))
    runs: list[tuple[int, int, int, int]] = []
    w, h = scene.width, scene.height
    for t, p in enumerate(positions):
        if not np.isfinite(p).all() or (convention.cull == "cw" and sign[t] > 0) or (convention.cull == "ccw" and sign[t] < 0):
            continue
        x0, y0, x1, y1 = _box(p, w, h)
        if x0 >= x1 or y0 >= y1:
            continue
        bw, bh = x1 - x0, y1 - y0
        fixed = [_fixed(x, y, x0, y0, bh, stepped) for x, y in p]
        if stepped and max(abs(v) for pt in fixed for v in pt) <= KERNEL_LIMIT:
            mask = np.zeros((bh, bw), dtype=np.bool_)
            scan_convert(np.array(fixed, dtype=np.int64), bw, bh, mode, mask)
        else:
            mask = scan_convert_reference([fixed], bw, bh, mode, stepped)
        runs += _mask_runs(t, mask, x0, y0)
    if not runs:
        return Coverage.empty()
    t_, y_, a_, b_ = (np.array(v, dtype=np.int64) for v in zip(*runs))
    return Coverage(t_, y_, a_, b_)


def closed_triangles(scene: Scene, convention: Convention) -> Coverage:
    """The ``closed`` model's triangle oracle: the closed rule
    (:func:`harness.oracle.closed_rule.closed_coverage`), or with an active
    :class:`~harness.contract.conventions.Dropout`, :func:`dropout_coverage`."""
    if convention.dropout_control.active:
        return dropout_coverage(scene, convention)
    return closed_coverage(scene, convention)


def _box(points: NDArray[np.float64], width: int, height: int) -> tuple[int, int, int, int]:
    """The adapter's box: the points' bounding box grown by 2 px, clipped to the viewport."""
    x0 = int(np.clip(np.floor(points[:, 0].min()) - MARGIN, 0, width))
    y0 = int(np.clip(np.floor(points[:, 1].min()) - MARGIN, 0, height))
    x1 = int(np.clip(np.ceil(points[:, 0].max()) + MARGIN, 0, width))
    y1 = int(np.clip(np.ceil(points[:, 1].max()) + MARGIN, 0, height))
    return x0, y0, x1, y1


def closed_paths(scene: PathScene, convention: Convention) -> Coverage:
    """The exact coverage of a path scene under ``coverage="closed"`` (with or without
    dropout control): each path's contours scan-converted together as one outline
    (:func:`scan_convert_reference`), in its bounding box grown by 2 px and clipped to the
    viewport. ftraster.c pairs the k-th up crossing with the k-th down crossing of a
    scanline, which fills the nonzero rule; it has no even-odd fill (ValueError).

    >>> square = PathScene.from_paths(4, 4, [[[[0.5, 0.5], [3.5, 0.5], [3.5, 3.5], [0.5, 3.5]]]])
    >>> closed_paths(square, Convention(coverage="closed")).counts(4, 4).tolist()  # edges through centres: inside
    [[1, 1, 1, 1], [1, 1, 1, 1], [1, 1, 1, 1], [1, 1, 1, 1]]
    """
    if scene.fill_rule != "nonzero":
        raise ValueError(f"{convention.model.declared_as(convention)} fills paths by the nonzero rule only "
                         f"(ftraster.c pairs up and down crossings), not {scene.fill_rule!r}")
    dropout = convention.dropout_control
    stepped = dropout.step_bits is not None
    runs: list[tuple[int, int, int, int]] = []
    for k in range(len(scene)):
        contours = [convention.snap(np.asarray(c, dtype=np.float64)) for c in scene.contours_of(k)]
        contours = [c for c in contours if c.shape[0] > 0]
        if not contours:
            continue
        points = np.concatenate(contours)
        if not np.isfinite(points).all():
            continue
        x0, y0, x1, y1 = _box(points, scene.width, scene.height)
        if x0 >= x1 or y0 >= y1:
            continue
        bw, bh = x1 - x0, y1 - y0
        outline = [[_fixed(x, y, x0, y0, bh, stepped) for x, y in c] for c in contours]
        runs += _mask_runs(k, scan_convert_reference(outline, bw, bh, dropout.scantype, stepped), x0, y0)
    if not runs:
        return Coverage.empty()
    t_, y_, a_, b_ = (np.array(v, dtype=np.int64) for v in zip(*runs))
    return Coverage(t_, y_, a_, b_)


def _fixed(x: float, y: float, x0: int, y0: int, bh: int, stepped: bool) -> tuple[Any, Any]:
    """A point in the box's 26.6 frame (y up about its top edge): integers when stepped
    (the input is on the grid), rationals otherwise."""
    fx, fy = Fraction(float(x)) * P - P * x0, P * (bh + y0) - Fraction(float(y)) * P
    return (int(fx), int(fy)) if stepped else (fx, fy)
