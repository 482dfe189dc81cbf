"""identify's input-precision probe: which coordinates the rasterizer receives before its own
snapping -- float64, float32, a fixed-point grid (26.6) or whole pixels (:class:`InputPrecision`).

After the fit of sample point, tie rule and snapping (:mod:`harness.identify.triangle_probes`),
two scenes are drawn where the input candidates disagree: right triangles whose corner sits a
hair off the fitted sample point (and off a half step either side of it on the fitted snapping grid), moved by
amounts that float32 (2**-21 px), a 1/256 px grid, 26.6 (1/256 px kept by 8 bits, dropped by 6)
and whole pixels (1/4, 3/4) each keep or drop; and triangles with vertices on both sides of
zero, where flooring and truncating part. Each candidate -- an input precision with the
fitted snapping or none, and for inputs that move the lattice scenes' vertices (coarser than
1/16 px) every usual sample point and tie rule again -- is scored on the tie fit's scenes,
the float scenes and these; ties go to float64 with the fitted snapping, the answer before
this probe, then to the order of :data:`INPUTS`.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from harness.contract.conventions import TIE_RULES, Convention
from harness.contract.scenes import Scene
from harness.engine.isolation import Call
from harness.identify.triangle_probes import SAMPLES, Drawn, SnapFit, TieFit, draw

__all__ = ["INPUTS", "InputFit", "fit_input", "fit_input_beside", "input_scenes", "same_ties"]

# the candidates, in order of preference on a tie
INPUTS: tuple[str, ...] = (
    "float64", "float32", "fixed8", "fixed6", "fixed6-half-away", "fixed6-floor", "fixed6-toward-zero", "fixed4",
    "integer", "integer-half-away", "integer-floor", "integer-toward-zero")
# how far the probe's corners sit off a sample point (each sign): float32 drops 2**-21 at
# magnitudes below 64, 26.6 drops 1/256 where 8 bits keep it; whole pixels part at 1/4 and 3/4
_NUDGES = (2.0**-21, 2.0**-10, 1.0 / 256, 0.25, 0.75)


@dataclass(frozen=True)
class InputFit:
    """The input precision (and the snapping, sample point and tie rule beside it) that best
    explains the rasterizer; ``scores``: each input's best mismatches on all the fit scenes."""

    convention: Convention
    mismatches: int
    scores: tuple[tuple[str, int], ...]
    drawn: tuple[Drawn, ...] = field(repr=False)
    # inputs that explain it as well but see some fit scene's vertices elsewhere: not told apart
    ambiguous: tuple[str, ...] = ()
    # the fitted snapping was dropped: on the input grid it moves nothing
    moot_snapping: bool = False
    # when the sample point and tie rule were fitted again (an input that moves the lattice's
    # vertices): the best candidate with another sample point or tie rule, and its mismatches
    runner_up: tuple[Convention, int] | None = None

    @property
    def input(self) -> str:
        return self.convention.input

    @property
    def tied(self) -> tuple[str, ...]:
        """The inputs that explain it as well as the one chosen."""
        best = min(score for _, score in self.scores)
        return tuple(name for name, score in self.scores if score == best)

    @property
    def text(self) -> str:
        said = self.convention.input_precision.describe()
        others = "; ".join(f"{name} {score}" for name, score in self.scores[:6])
        same = [t for t in self.tied if t != self.input]
        return (f"{said} ({others} mismatches on the fit scenes"
                + (f"; not told apart from {', '.join(self.ambiguous)}" if self.ambiguous else "")
                + (f"; the same vertices as {', '.join(t for t in same if t not in self.ambiguous)}"
                   if set(same) - set(self.ambiguous) else "") + ")")


def input_scenes(convention: Convention, seed: int = 0) -> list[Scene]:
    """The two scenes where input candidates disagree, for the fitted ``convention``.

    >>> [s.positions.shape for s in input_scenes(Convention(subpixel_bits=8))]
    [(120, 3, 2), (80, 3, 2)]
    """
    sx, sy = convention.sample
    # a half step of the snapping grid either side: nearest-even sends the two to different
    # neighbours, so float32's dropped nudge shows whichever the grid point's parity
    half = None if convention.subpixel_bits is None else 2.0 ** -(convention.subpixel_bits + 1)
    steps = [0.0] if half is None else [0.0, half, -half]
    corners = []
    for half in steps:
        for nudge in _NUDGES:
            for sign in (1.0, -1.0):
                for lx, ly in ((1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)):
                    corners.append((half + sign * nudge, lx, ly))
    tris = np.empty((len(corners), 3, 2), dtype=np.float64)
    for k, (off, lx, ly) in enumerate(corners):
        # 4 px cells from (4, 4); the legs reach 2.5 px towards (lx, ly)
        i, j = 4 + 4 * (k % 12), 4 + 4 * (k // 12)
        cx, cy = i + sx + off, j + sy + off
        tris[k] = ((cx, cy), (cx + 2.5 * lx, cy), (cx, cy + 2.5 * ly))
    height = 8 + 4 * ((len(corners) + 11) // 12)
    rng = np.random.default_rng(seed + 7919)
    # vertices on both sides of zero, where floor and truncation part: a sliver of screen in
    # the top-left corner reached from far-off vertices
    far = rng.uniform(-3.0, 12.0, size=(80, 3, 2))
    scenes = [Scene(56, max(56, height), tris), Scene(16, 16, far)]
    if convention.snap_rounding == "half-away-shifted" and convention.subpixel_bits is not None:
        scenes.append(first_half_pixel_scene(convention))
    return scenes


def first_half_pixel_scene(convention: Convention) -> Scene:
    """For piglit's rounding (half away from the pixel centre, which rounds the half steps in
    (0, 1/2) down): triangles whose first vertex sits a hair above or below such a half step t
    in x, where a coarser input grid's rounding toward zero parts from float64 (it lands on t,
    which rounds down, where the exact value rounds up) and nowhere else. Each triangle's
    edge from that vertex passes exactly through a sample point when the vertex snaps up (or,
    the twin, down), with the third vertex on either side: the tie rule owns the sample on the
    edge, the other snap puts it strictly on one side, and for one of the twins the two differ.

    >>> first_half_pixel_scene(Convention(subpixel_bits=4, snap_rounding="half-away-shifted")).positions.shape
    (128, 3, 2)
    """
    bits = convention.subpixel_bits
    assert bits is not None
    step = 2.0**-bits
    sx, sy = convention.sample
    sample = np.array([1.0 + sx, 5.0 + sy])
    halves = [(k + 0.5) * step for k in range(2 ** max(bits - 1, 0))]
    halves = halves[:: max(1, len(halves) // 8)][:8]  # up to 8 of them, spread over (0, 1/2)
    tris = []
    for t in halves:
        for nudge in (2.0**-21, 2.0**-10):
            for sign in (1.0, -1.0):
                for on in (t + step / 2, t - step / 2):  # the snapped x the edge is laid through the sample for
                    c = np.array([t + sign * nudge, 3.0])
                    far = 2.0 * sample - np.array([on, 3.0])  # the sample is the midpoint of (on, 3) -> far
                    for side in (3.0, -3.0):
                        tris.append((c, far, sample + np.array([side, 0.0])))
    return Scene(16, 16, np.array(tris, dtype=np.float64))


def _candidates(best: Convention, lattice: list[NDArray[np.float64]]) -> list[Convention]:
    snaps = [(best.subpixel_bits, best.snap_rounding)] + ([(None, "nearest-even")] if best.subpixel_bits is not None else [])
    out = []
    for name in INPUTS:
        for bits, rounding in snaps:
            base = replace(best, input=name, subpixel_bits=bits, snap_rounding=rounding)
            out.append(base)
            moved = any(not np.array_equal(base.receive(p), p) for p in lattice)
            if moved:
                # the lattice's vertices move: the sample point and tie rule fitted on them may too
                out += [replace(base, sample=s, tie=t) for s in SAMPLES for t in TIE_RULES
                        if (s, t) != (best.sample, best.tie)]
    return out


def _grid_bits(c: Convention) -> int | None:
    """The binary digits of the coordinates ``c`` decides on (an input grid's or the
    snapping's, the coarser), or None (floats: any)."""
    grid = c.input_precision
    bits = [b for b in (grid.bits if grid.kind in ("fixed", "integer") else None, c.subpixel_bits) if b is not None]
    return min(bits) if bits else None


def same_ties(a: Convention, b: Convention) -> bool:
    """Whether ``a`` and ``b`` (the same sample point and grid) decide every scene alike: their
    tie rules differ only in a part no sample can reach. On a grid of 2**-g px a horizontal
    edge holds a sample only if the sample's y is a multiple of 2**-g (a vertical one: its
    x); an x-first rule asks its y part only of horizontal edges, a y-first rule its x part
    only of vertical ones.

    >>> c = Convention(input="integer")
    >>> same_ties(c, replace(c, tie="bottom-left")), same_ties(c, replace(c, tie="top-right"))
    (True, False)
    >>> same_ties(Convention(), Convention(tie="bottom-left"))
    False
    """
    if a.sample != b.sample or _grid_bits(a) != _grid_bits(b):
        return False
    if a.tie == b.tie:
        return True
    (ax, ay, af), (bx, by, bf) = a.tie_perturbation, b.tie_perturbation
    bits = _grid_bits(a)
    if af != bf or bits is None:
        return False
    sx, sy = a.sample
    on_grid = [(v * 2.0**bits) % 1.0 == 0.0 for v in (sx, sy)]
    if not af:  # x-first: x part always asked (slanted edges), y part only of horizontal edges
        return ax == bx and not on_grid[1]
    return ay == by and not on_grid[0]


class _Scorer:
    """Each candidate's mismatches summed over the ``answered`` scenes, as far as the fit
    needs them. The fit reads the best candidate (least mismatches, then first listed),
    each input's least mismatches, every candidate as good as the best, and perhaps the
    best of some other candidates (:meth:`first`): a candidate is scored scene by scene and
    left off, with its partial sum, once that sum exceeds the least mismatches already
    found for its input -- it can then be none of those, as a sum only grows -- and
    finished only if :meth:`first` needs it. ``scored``: (mismatches, index, candidate) of
    the finished candidates, sorted; every candidate it leaves out has more mismatches
    than the best of its input (the answers are the same as scoring them all).

    >>> from harness.contract.coverage import Coverage
    >>> from harness.engine.isolation import Outcome
    >>> scene = Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])
    >>> drawn = Drawn(scene, Outcome(Coverage([0, 0, 0], [0, 1, 2], [0, 0, 0], [3, 2, 1])))  # the top-left rule's pixels
    >>> scorer = _Scorer([drawn, drawn], [Convention(tie=t) for t in ("bottom-right", "top-left", "top-right")])
    >>> [(score, k) for score, k, _ in scorer.scored], scorer.partial[2]  # top-right left off after one scene
    ([(0, 1), (8, 0)], (4, 1))
    >>> best = scorer.first(lambda c: c.tie != "top-left")  # finished as needed; ties to the first listed
    >>> best is not None and (best[0].tie, best[1])
    ('bottom-right', 8)
    """

    def __init__(self, answered: Sequence[Drawn], candidates: Sequence[Convention]) -> None:
        self.answered = list(answered)
        self.candidates = list(candidates)
        # index -> (partial sum, scenes summed)
        self.partial: dict[int, tuple[int, int]] = {}
        least: dict[str, int] = {}
        # the candidates as the fit first found them (each input's own snapping, sample point
        # and tie rule lead; they bound the rest): in their order
        for k, c in enumerate(self.candidates):
            bound = least.get(c.input)
            score = self._advance(k, bound)
            if score is not None and (bound is None or score < bound):
                least[c.input] = score
        self.scored = sorted(((self.partial[k][0], k, c) for k, c in enumerate(self.candidates)
                              if self.partial[k][1] == len(self.answered)), key=lambda s: (s[0], s[1]))

    def _advance(self, k: int, bound: int | None) -> int | None:
        """Sum candidate ``k``'s mismatches on, scene by scene, until done (its total) or the
        sum exceeds ``bound`` (None: left off there)."""
        total, done = self.partial.get(k, (0, 0))
        c = self.candidates[k]
        while done < len(self.answered):
            total += self.answered[done].mismatches(c)
            done += 1
            if bound is not None and total > bound and done < len(self.answered):
                self.partial[k] = (total, done)
                return None
        self.partial[k] = (total, done)
        return total

    def first(self, eligible: Callable[[Convention], bool]) -> tuple[Convention, int] | None:
        """The eligible candidate with least mismatches (first listed among equals) and its
        mismatches, or None: the unfinished ones finished only while their partial sum could
        still make them the one (least partial sum first)."""
        heap = [(self.partial[k][0], k) for k, c in enumerate(self.candidates) if eligible(c)]
        heapq.heapify(heap)
        while heap:
            total, k = heapq.heappop(heap)
            if self.partial[k][1] == len(self.answered):
                return self.candidates[k], total  # a lower bound of every other one's sum, ties to the first listed
            heapq.heappush(heap, (self._advance(k, None) or 0, k))
        return None


def fit_input(call: Call, seed: int, ties: TieFit, snapping: SnapFit) -> InputFit:
    """The input precision that best explains the rasterizer, with the fitted convention
    (``snapping.convention``) around it; the scenes drawn are in ``drawn``."""
    return fit_input_beside(call, seed, snapping.convention, [*ties.drawn, *snapping.drawn],
                            [d.scene.positions for d in ties.drawn])


def fit_input_beside(call: Call, seed: int, best: Convention, before: list[Drawn],
                     lattice: list[NDArray[np.float64]]) -> InputFit:
    """:func:`fit_input` beside the single-sample convention ``best`` fitted on the scenes
    ``before`` (``lattice``: the positions the sample point and tie rule were fitted on,
    refitted for an input that moves them; none: never refitted). A multisample
    rasterizer's sample 0 is fitted so (``call`` answering for it alone)."""
    if before and all(d.coverage is None for d in before):  # no answer at all: nothing to tell inputs apart by
        return InputFit(best, 0, ((best.input, 0),), tuple(before))
    drawn = [*before, *(draw(call, s) for s in input_scenes(best, seed))]
    answered = [d for d in drawn if d.coverage is not None]
    scorer = _Scorer(answered, _candidates(best, lattice))
    scored = scorer.scored
    per_input: dict[str, int] = {}
    for score, _, c in scored:
        per_input.setdefault(c.input, score)
    chosen = scored[0][2]
    ranked = tuple(sorted(per_input.items(), key=lambda kv: (kv[1], INPUTS.index(kv[0]))))
    seen = [chosen.snap(d.scene.positions) for d in answered]

    def same(c: Convention) -> bool:
        return (c.sample, c.tie) == (chosen.sample, chosen.tie) and all(
            np.array_equal(c.snap(d.scene.positions), p, equal_nan=True) for d, p in zip(answered, seen))

    ambiguous = tuple(sorted({c.input for score, _, c in scored
                              if score == scored[0][0] and c.input != chosen.input and not same(c)}))
    runner = None
    if any(not np.array_equal(chosen.receive(p), p) for p in lattice):
        runner = scorer.first(lambda c: (c.sample, c.tie) != (chosen.sample, chosen.tie) and not same_ties(c, chosen))
    grid = chosen.input_precision
    moot = (grid.kind in ("fixed", "integer") and chosen.subpixel_bits is not None and grid.bits <= chosen.subpixel_bits)
    if moot:  # a grid inside the snapping grid: snapping the received coordinates moves nothing
        chosen = replace(chosen, subpixel_bits=None, snap_rounding="nearest-even")
    return InputFit(chosen, scored[0][0], ranked, tuple(drawn), ambiguous, moot, runner)
