"""identify's probes for path-taking rasterizers: which fill rule it applies, then its
convention for paths.

A rasterizer that lists ``"paths"`` in its ``scene_kinds`` (:func:`harness.contract.protocol.scene_kinds_of`)
fills each path of a :class:`~harness.contract.scenes.PathScene` in one go under the scene's fill rule.
Two questions, asked from outside in this order:

1. *The fill rule* (:func:`fill_rules`). For each rule it is asked (those it declares,
   :func:`harness.contract.protocol.fill_rules_of`), one scene of paths where nonzero and even-odd
   part -- a pentagram (centre wound twice), two overlapping squares wound the same way
   (one path), a ring whose hole is wound like its outside -- beside controls where they
   agree but careless fills do not -- a ring whose hole is wound the other way (filled by
   a fill that ignores holes) and the pentagram wound the other way (a fill of one
   orientation only). What it drew is compared with each model of a fill on the pixels
   whose answer no sample point, tie rule or snapping can change (every vertex is an
   integer, and a pixel counts only when its centre lies more than 1.5 px from every edge
   of its path and of its path's convex hull: its whole square is then on one side of
   each); the model with no mismatch names what it drew: ``nonzero``, ``evenodd``, or
   neither (``fills the outline's hull``, ``ignores holes``, ``drops the contours after each
   path's first`` -- the overlapping squares tell the last two apart --, ...), with the pixel counts
   as the evidence.
2. *The convention for paths* (:func:`fit_path_convention`). A triangle is a one-contour
   path, so the triangle probes -- :func:`harness.identify.triangle_probes.fit_ties` (sample point, tie
   rule) and :func:`~harness.identify.triangle_probes.fit_snapping` -- run unchanged through the path
   interface (:func:`as_paths` sends each triangle scene as a path scene of one-contour
   paths, whose coverage names the same primitives), and the result is compared with what
   the rasterizer does on triangles: a path convention that differs from the triangle one
   is a finding. The fitted convention is then tried on genuine paths with vertices on
   sample points (self-intersecting, several contours, horizontal edges: ties on purpose)
   under each honoured rule (:func:`lattice_paths`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from harness.checks import FragmentCounter
from harness.contract.conventions import FILL_RULES, Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, PathScene, Scene
from harness.engine.isolation import Call, Outcome, describe
from harness.oracle.coverage import exact_coverage

__all__ = ["FILL_MODELS", "RuleSeen", "FillRules", "PathFit", "LatticePaths", "triangle_paths", "as_paths", "send",
           "fill_rule_scene", "fill_rules", "fit_path_convention", "path_fit_of", "lattice_path_scene", "lattice_paths",
           "with_lattice"]


# --- calling a rasterizer with paths -------------------------------------------------------


def send(call: Call, scene: AnyScene) -> Outcome:
    """``call`` on a scene of any kind: a path-taking rasterizer's call takes path scenes
    (:class:`harness.engine.isolation.Call` names triangle scenes only; a worker and an in-process
    call send whatever they are given)."""
    return call(scene)  # type: ignore[arg-type]


def triangle_paths(scene: Scene, fill_rule: str = "nonzero") -> PathScene:
    """The triangles of ``scene`` as a path scene: path k is triangle k, one contour of
    three vertices, so its coverage names the same primitives. A triangle's winding
    number is 0 or +-1 everywhere, so both fill rules give it the same pixels.

    >>> tri = Scene(8, 8, [[[1, 1], [7, 1], [1, 7]], [[2, 2], [2, 6], [6, 6]]])
    >>> paths = triangle_paths(tri)
    >>> len(paths), paths.contour_sizes.tolist(), paths.vertices.shape
    (2, [3, 3], (6, 2))
    """
    from cases.paths import triangles_as_paths  # the suite's own: its path partitions are these scenes

    return triangles_as_paths(scene, fill_rule)


def as_paths(call: Call, fill_rule: str) -> Call:
    """``call`` seen as a triangle rasterizer: each triangle scene is sent as a path scene
    of one-contour paths (:func:`triangle_paths`) under ``fill_rule``; the answer names the
    same primitives, so every triangle probe reads it unchanged."""

    def through_paths(scene: Scene) -> Outcome:
        return send(call, triangle_paths(scene, fill_rule))

    return through_paths


# --- the fill rule ---------------------------------------------------------------------------


def _pentagram(cx: int, cy: int, radius: float, reverse: bool) -> list[list[int]]:
    """A {5/2} star with integer vertices: its centre pentagon is wound twice."""
    order = [0, 2, 4, 1, 3][::-1] if reverse else [0, 2, 4, 1, 3]
    angles = [2.0 * np.pi * k / 5.0 for k in order]
    return [[cx + round(radius * np.sin(a)), cy - round(radius * np.cos(a))] for a in angles]


def _square(x0: int, y0: int, x1: int, y1: int, reverse: bool = False) -> list[list[int]]:
    corners = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    return corners[::-1] if reverse else corners


# The probe paths, one region each in a 320 x 64 viewport; every vertex an integer (no
# snapping moves it), each path with what sets it apart.
PROBE_PATHS: tuple[tuple[str, tuple[list[list[int]], ...]], ...] = (
    ("pentagram", (_pentagram(32, 32, 28, False),)),
    ("overlapping squares", (_square(70, 6, 104, 40), _square(88, 24, 122, 58))),
    ("ring with a hole wound alike", (_square(132, 6, 182, 58), _square(146, 20, 168, 44))),
    ("ring with a hole wound opposite", (_square(196, 6, 246, 58), _square(210, 20, 232, 44, reverse=True))),
    ("pentagram wound opposite", (_pentagram(286, 32, 28, True),)),
)
PROBE_SIZE = (320, 64)


def fill_rule_scene(fill_rule: str) -> PathScene:
    """The probe paths (:data:`PROBE_PATHS`) as one scene under ``fill_rule``."""
    return PathScene.from_paths(*PROBE_SIZE, [[np.array(c, dtype=np.float64) for c in contours]
                                              for _, contours in PROBE_PATHS], fill_rule)


# What a fill may do, as a function of each contour's winding number at a pixel centre
# (w_c, (C, H, W)), its path's total (w) and its path's hull; the first two are the rules.
FILL_MODELS: dict[str, str] = {
    "nonzero": "nonzero",
    "evenodd": "even-odd",
    "contours": "ignores holes (fills each contour on its own, the union)",
    "first": "drops the contours after each path's first (fills the first alone, under the rule asked)",
    "hull": "fills the outline's hull (each path's convex hull)",
    "positive": "fills one orientation only (winding number > 0)",
    "negative": "fills one orientation only (winding number < 0)",
    "abs_geq_two": "fills only where the winding number is 2 or more in magnitude",
    "nothing": "draws nothing",
}


def _winding(contour: NDArray[np.float64], px: NDArray[np.float64], py: NDArray[np.float64]) -> NDArray[np.int64]:
    """The winding number of each point (px, py) around a closed contour: every edge
    crossing the point's row right of it adds +1 running down the screen, -1 up. Exact for
    integer vertices and half-integer points (every product is a small dyadic number), and
    no point lies on a vertex's row."""
    w = np.zeros(px.shape, dtype=np.int64)
    for k in range(contour.shape[0]):
        (ax, ay), (bx, by) = contour[k], contour[(k + 1) % contour.shape[0]]
        if ay == by:
            continue
        crosses = (ay < py) != (by < py)
        direction = 1 if by > ay else -1
        edge = (bx - ax) * (py - ay) - (by - ay) * (px - ax)  # E_ab: its sign times dir > 0 right of p
        w += np.where(crosses & (edge * direction > 0), direction, 0)
    return w


def _distance(a: NDArray[np.float64], b: NDArray[np.float64], px: NDArray[np.float64],
              py: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance from each point to the segment a-b (a margin only: never an inside test)."""
    d = b - a
    length = float(d @ d)
    t = np.zeros(px.shape) if length == 0 else np.clip(((px - a[0]) * d[0] + (py - a[1]) * d[1]) / length, 0.0, 1.0)
    distance: NDArray[np.float64] = np.hypot(px - a[0] - t * d[0], py - a[1] - t * d[1])
    return distance


def _hull(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Convex hull (monotone chain), counter-clockwise in y-up terms, without collinear points."""
    pts = sorted(set(map(tuple, points.tolist())))
    if len(pts) < 3:
        return np.array(pts, dtype=np.float64)

    def half(seq: list[tuple[float, float]]) -> list[tuple[float, float]]:
        out: list[tuple[float, float]] = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1], dtype=np.float64)


@dataclass(frozen=True)
class _Models:
    """Each model's answer (P, H, W) bool on the probe scene, and the sure pixels (P, H, W)."""

    answers: dict[str, NDArray[np.bool_]]
    sure: NDArray[np.bool_]


def _probe_models(scene: PathScene, margin: float = 1.5) -> _Models:
    """Every model of :data:`FILL_MODELS` at the pixel centres of ``scene`` (integer
    vertices), and which pixels are sure: centres farther than ``margin`` px from every
    edge of the path and of its hull, and within the path's bounding box grown by 3 px."""
    width, height = scene.width, scene.height
    py, px = np.mgrid[0:height, 0:width] + 0.5
    n = len(scene)
    answers = {name: np.zeros((n, height, width), dtype=bool) for name in FILL_MODELS}
    sure = np.zeros((n, height, width), dtype=bool)
    for p in range(n):
        contours = scene.contours_of(p)
        per_contour = np.stack([_winding(c, px, py) for c in contours])
        w = per_contour.sum(axis=0)
        vertices = np.concatenate(contours)
        hull = _hull(vertices)
        inside_hull = np.ones(px.shape, dtype=bool)
        near = np.full(px.shape, np.inf)
        for k in range(hull.shape[0]):
            a, b = hull[k], hull[(k + 1) % hull.shape[0]]
            # the chain turns so that the interior is where E_ab > 0 (left of a-b in y-up terms)
            inside_hull &= (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]) > 0
            near = np.minimum(near, _distance(a, b, px, py))
        for c in contours:
            for k in range(c.shape[0]):
                near = np.minimum(near, _distance(c[k], c[(k + 1) % c.shape[0]], px, py))
        lo, hi = vertices.min(axis=0) - 3.0, vertices.max(axis=0) + 3.0
        sure[p] = (near > margin) & (px >= lo[0]) & (px <= hi[0]) & (py >= lo[1]) & (py <= hi[1])
        answers["nonzero"][p] = w != 0
        answers["evenodd"][p] = (w & 1) == 1
        answers["contours"][p] = np.any(per_contour != 0, axis=0)
        answers["first"][p] = per_contour[0] != 0 if scene.fill_rule == "nonzero" else (per_contour[0] & 1) == 1
        answers["hull"][p] = inside_hull
        answers["positive"][p] = w > 0
        answers["negative"][p] = w < 0
        answers["abs_geq_two"][p] = np.abs(w) >= 2
    return _Models(answers, sure)


def _drawn_mask(coverage: Coverage, n: int, width: int, height: int) -> NDArray[np.bool_]:
    """(n, height, width) bool: the pixels each path covers (any of its samples for
    multisample coverage, alpha at least 1/2 for area coverage)."""
    prim, x, y = coverage.pixels()
    keep = (prim >= 0) & (prim < n) & (x >= 0) & (x < width) & (y >= 0) & (y < height)
    if coverage.alpha is not None and coverage.alpha.shape[0] == prim.shape[0]:
        keep &= coverage.alpha >= 0.5
    mask = np.zeros((n, height, width), dtype=bool)
    mask[prim[keep], y[keep], x[keep]] = True
    return mask


@dataclass(frozen=True, slots=True)
class RuleSeen:
    """What the rasterizer drew when asked for one fill rule: the model that explains it
    (``drawn``: a rule, another model of :data:`FILL_MODELS`, or None when none does or
    nothing answered tells the rules apart), the mismatching sure pixels of every model,
    the sure pixels compared (``sure``) and the pixels drawn; ``error`` when no probe path
    was answered. When the whole probe scene was refused, each probe path was asked on its
    own: ``unanswered`` names those still refused (probe path label, error), and the rest
    decide."""

    requested: str
    drawn: str | None
    mismatches: tuple[tuple[str, int], ...] = ()
    sure: int = 0
    pixels: int = 0
    per_path: tuple[tuple[str, int, int], ...] = ()
    error: str = ""
    unanswered: tuple[tuple[str, str], ...] = ()

    @property
    def honoured(self) -> bool:
        return self.drawn == self.requested

    @property
    def label(self) -> str:
        """``nonzero``/``evenodd`` for a rule, ``neither: ...`` otherwise (the record's
        value in :attr:`harness.identify.fingerprint.Fingerprint.fill_rules`)."""
        if self.error:
            return f"unanswered: {self.error}"[:160]
        if self.drawn in FILL_RULES:
            return str(self.drawn)
        if self.drawn is not None:
            return f"neither: {FILL_MODELS[self.drawn]}"
        scores = dict(self.mismatches)
        if scores["nonzero"] == scores["evenodd"] == 0:
            return "unanswered: the paths it answered cannot tell the rules apart"
        name, off = min(self.mismatches, key=lambda m: m[1])
        return f"neither: closest is {FILL_MODELS[name]} ({off:,} of {self.sure:,} sure pixels off)"

    @property
    def text(self) -> str:
        if self.error:
            return f"asked {self.requested}: {self.label}"
        scores = dict(self.mismatches)
        rules = ", ".join(f"{r}: {scores[r]:,} off" for r in FILL_RULES)
        drawn = (self.label if self.honoured else f"{self.label.upper()}, not the rule asked" if self.drawn in FILL_RULES
                 else "NEITHER" + self.label.removeprefix("neither") if self.label.startswith("neither") else self.label)
        said = f"asked {self.requested}: draws {drawn} ({rules} of {self.sure:,} sure pixels)"
        if self.unanswered:
            said += (f" on the probe paths it answers; refused the {', '.join(label for label, _ in self.unanswered)}: "
                     f"{self.unanswered[0][1]}")
        return said


@dataclass(frozen=True, slots=True)
class FillRules:
    """The fill rule drawn for each rule asked (:class:`RuleSeen`, in the order asked)."""

    seen: tuple[RuleSeen, ...]

    @property
    def drawn(self) -> dict[str, str]:
        """Requested rule -> what it drew (:attr:`RuleSeen.label`)."""
        return {s.requested: s.label for s in self.seen}

    @property
    def honoured(self) -> tuple[str, ...]:
        """The rules asked that it draws as asked."""
        return tuple(s.requested for s in self.seen if s.honoured)

    @property
    def fit_rule(self) -> str:
        """The rule the path convention is fitted under: the first honoured one, else the
        first asked (a triangle has the same pixels under both rules)."""
        honoured = self.honoured
        return honoured[0] if honoured else self.seen[0].requested if self.seen else FILL_RULES[0]

    @property
    def text(self) -> str:
        if not self.seen:
            return "not measured: it declares no fill rule"
        return "; ".join(s.text for s in self.seen)


def fill_rules(call: Call, requested: Sequence[str] = FILL_RULES) -> FillRules:
    """Which fill rule the rasterizer draws for each rule in ``requested``: one probe
    scene each (:func:`fill_rule_scene`), compared with every model of
    :data:`FILL_MODELS` on the sure pixels; the first model (in that order) without a
    mismatch names it."""
    seen = []
    for rule in requested:
        scene = fill_rule_scene(rule)
        n = len(scene)
        models = _probe_models(scene)
        outcome = send(call, scene)
        answered = np.ones(n, dtype=bool)
        refused: list[tuple[str, str]] = []
        if outcome.coverage is not None:
            got = _drawn_mask(outcome.coverage, n, scene.width, scene.height)
            pixels = outcome.coverage.n_pixels
        else:
            # refused whole (say, a library that fills one contour per path): each path on
            # its own, so that the ones it takes still say which rule it draws
            got = np.zeros((n, scene.height, scene.width), dtype=bool)
            pixels = 0
            for p in range(n):
                alone = send(call, scene.subset([p]))
                if alone.coverage is None:
                    answered[p] = False
                    refused.append((PROBE_PATHS[p][0], describe(alone.error)))
                    continue
                got[p] = _drawn_mask(alone.coverage, 1, scene.width, scene.height)[0]
                pixels += alone.coverage.n_pixels
            if not answered.any():
                seen.append(RuleSeen(rule, None, error=describe(outcome.error)))
                continue
        sure = models.sure & answered[:, None, None]
        off = {name: int(np.count_nonzero((got != answer) & sure)) for name, answer in models.answers.items()}
        exact = [name for name, count in off.items() if count == 0]
        if off["nonzero"] == off["evenodd"] == 0:
            exact = []  # the paths answered cannot tell the rules apart: nothing is claimed
        per_path = tuple((label, int(np.count_nonzero(got[p] & sure[p])), int(np.count_nonzero(sure[p])))
                         for p, (label, _) in enumerate(PROBE_PATHS))
        seen.append(RuleSeen(rule, exact[0] if exact else None, tuple(off.items()), int(np.count_nonzero(sure)),
                             pixels, per_path, unanswered=tuple(refused)))
    return FillRules(tuple(seen))


# --- genuine paths with ties --------------------------------------------------------------------


def lattice_path_scene(sample: tuple[float, float], fill_rule: str, seed: int, count: int = 60) -> PathScene:
    """``count`` paths of one or two contours of 3 to 9 vertices on sample points (i + sx,
    j + sy) of a 48 px square moved 4 px in, self-intersecting at will, a third of the
    edges horizontal: vertices, edges and crossings on samples, so that every tie rule
    shows on real paths."""
    rng = np.random.default_rng(seed + 23)
    paths = []
    for _ in range(count):
        contours = []
        for _ in range(int(rng.integers(1, 3))):
            m = int(rng.integers(3, 10))
            centre = rng.integers(8, 40, size=2)
            v = centre + rng.integers(-7, 8, size=(m, 2))
            flat = rng.random(m) < 0.33
            flat[0] = False
            for k in np.flatnonzero(flat):
                v[k, 1] = v[k - 1, 1]  # a horizontal edge into vertex k
            contours.append(v.astype(np.float64) + np.array(sample) + 4.0)
        paths.append(contours)
    return PathScene.from_paths(56, 56, paths, fill_rule)


@dataclass(frozen=True, slots=True)
class LatticePaths:
    """Mismatching pixels of the path convention on genuine paths with ties, per rule
    (``rule, mismatches, pixels``) over ``paths`` paths; ``error`` when a call gave one
    even on one-contour paths alone, ``refused`` when it took only those."""

    scores: tuple[tuple[str, int, int], ...]
    paths: int
    error: str = ""
    refused: str = ""

    @property
    def mismatches(self) -> int:
        return sum(m for _, m, _ in self.scores)

    @property
    def text(self) -> str:
        if self.error:
            return f"not measured: {self.error}"[:160]
        if not self.scores:
            return "not measured: no fill rule is honoured"
        said = "; ".join(f"{rule}: {m:,} mismatches of {px:,} pixels" for rule, m, px in self.scores)
        if self.refused:
            return (f"{said} ({self.paths} one-contour paths per rule, vertices on samples; "
                    f"it refused several contours: {self.refused})")[:300]
        return f"{said} ({self.paths} paths per rule, vertices on samples)"


def lattice_paths(call: Call, convention: Convention, rules: Sequence[str], seed: int) -> LatticePaths:
    """The path convention against the rasterizer on :func:`lattice_path_scene` under each
    of ``rules`` (two scenes each); a scene refused whole is asked again with its
    one-contour paths alone (a library that fills one contour per call)."""
    scores: list[tuple[str, int, int]] = []
    count = 0
    refused = ""
    for rule in rules:
        off = pixels = 0
        for k in range(2):
            scene = lattice_path_scene(convention.sample, rule, seed + k)
            outcome = send(call, scene)
            if outcome.coverage is None:
                refused = describe(outcome.error)
                scene = scene.subset(np.flatnonzero(np.bincount(scene.contour_path, minlength=len(scene)) == 1))
                outcome = send(call, scene)
                if outcome.coverage is None:
                    return LatticePaths(tuple(scores), count, describe(outcome.error))
            counter = FragmentCounter(outcome.coverage, scene.width, scene.height)
            off += counter.mismatches(exact_coverage(scene, convention))
            pixels += outcome.coverage.n_pixels
            count += len(scene)
        scores.append((rule, off, pixels))
    return LatticePaths(tuple(scores), count // max(1, len(scores)), refused=refused)


# --- the convention for paths ---------------------------------------------------------------------


_PARTS = (("sample", "sample"), ("tie", "ties"), ("subpixel_bits", "snapping bits"), ("snap_rounding", "snap rounding"),
          ("input", "input"))


@dataclass(frozen=True)
class PathFit:
    """The convention that best explains the rasterizer on paths (the triangle probes
    through the path interface, under ``rule``), with its residual, runner-up and
    ambiguity as for triangles; ``triangles`` the convention found for triangles (None
    when it takes none); ``lattice`` the fit tried on genuine paths; ``skipped`` why no
    fit was made (a coverage kind the path fit does not cover).

    Culling takes no part in the comparison: a path has no culling (a fill rule decides
    what it covers), so a path fit that culls is reported on its own."""

    convention: Convention | None
    residual: int = 0
    pixels: int = 0
    runner_up: tuple[str, int] | None = None
    ambiguous: tuple[str, ...] = ()
    triangles: Convention | None = None
    rule: str = "nonzero"
    lattice: LatticePaths | None = None
    skipped: str = ""
    probes: dict[str, object] = field(default_factory=dict, repr=False, compare=False)
    unanswered: int = 0  # fit scenes it gave no answer for (left out of the fit and the residual)

    @property
    def exact(self) -> bool:
        """No mismatch, a runner-up with some, no ambiguity, none on genuine paths, and
        every fit scene answered."""
        return (self.convention is not None and self.residual == 0 and not (self.runner_up is not None and self.runner_up[1] == 0)
                and not self.ambiguous and (self.lattice is None or self.lattice.mismatches == 0) and not self.unanswered)

    @property
    def differences(self) -> tuple[str, ...]:
        """What differs from the triangle convention, culling aside, each as ``part value
        (triangles: value)`` (``ties top-right (triangles: top-left)``); empty when they
        agree or there is nothing to compare."""
        if self.convention is None or self.triangles is None:
            return ()
        return tuple(f"{label} {getattr(self.convention, part)} (triangles: {getattr(self.triangles, part)})"
                     for part, label in _PARTS if getattr(self.convention, part) != getattr(self.triangles, part))

    @property
    def same_as_triangles(self) -> bool | None:
        """Whether the path convention is the triangle one (culling aside); None when
        either is missing."""
        if self.convention is None or self.triangles is None:
            return None
        return not self.differences

    @property
    def text(self) -> str:
        if self.convention is None:
            return f"not fitted: {self.skipped}"
        fit = (f"{self.convention.describe()}, {self.residual:,} mismatches of {self.pixels:,} pixels"
               + ("" if self.exact else
                  f" (best guess only: {self.unanswered} fit scenes unanswered, left out of the fit)" if self.unanswered else
                  " (best guess only)" if self.residual else
                  f" (ambiguous between {' and '.join(self.ambiguous)})" if self.ambiguous else
                  " (ambiguous: the next best explains it as well)" if self.lattice is None or not self.lattice.mismatches
                  else " (genuine paths disagree)"))
        same = self.same_as_triangles
        said = (f"{fit}; the same as for triangles" if same else
                f"{fit}; DIFFERS from triangles: {', '.join(self.differences)}" if same is False else
                f"{fit} (it takes no triangles)")
        if self.convention.cull != "none":
            said += f"; CULLS {self.convention.cull} paths (a path's orientation must not matter)"
        return said + f"; under {self.rule}"


def path_fit_of(convention: Convention, residual: int, pixels: int, runner_up: tuple[str, int] | None,
                ambiguous: tuple[str, ...], triangles: Convention | None, rule: str, unanswered: int = 0) -> PathFit:
    """A :class:`PathFit` from a fit already made (a rasterizer that takes only paths is
    identified through :func:`as_paths` in the first place)."""
    return PathFit(convention, residual, pixels, runner_up, ambiguous, triangles, rule, unanswered=unanswered)


def fit_path_convention(call: Call, seed: int, rule: str, triangles: Convention | None) -> PathFit:
    """The convention for paths: :func:`harness.identify.triangle_probes.fit_ties` and
    :func:`~harness.identify.triangle_probes.fit_snapping` through :func:`as_paths` under ``rule``, compared
    with ``triangles`` (the convention found for triangles)."""
    from harness.identify.input_probes import fit_input
    from harness.identify.triangle_probes import fit_snapping, fit_ties

    paths = as_paths(call, rule)
    ties = fit_ties(paths, seed)
    snapping = fit_snapping(paths, seed, ties)
    inputs = fit_input(paths, seed, ties, snapping)  # the input precision, as for triangles
    convention = inputs.convention
    drawn = list(inputs.drawn)
    residual = sum(d.mismatches(convention) for d in drawn)
    runner_up = ((ties.runner_up.describe(), ties.runner_up_mismatches) if inputs.runner_up is None
                 else (inputs.runner_up[0].describe(), inputs.runner_up[1]))
    ambiguous = (() if inputs.moot_snapping else snapping.ambiguous) + tuple(f"{i} input" for i in inputs.ambiguous)
    return PathFit(convention, residual, sum(d.pixels for d in drawn), runner_up,
                   ambiguous, triangles, rule, probes={"ties": ties, "snapping": snapping, "input": inputs},
                   unanswered=len({id(d) for d in drawn if d.coverage is None}))


def with_lattice(fit: PathFit, call: Call, rules: Sequence[str], seed: int) -> PathFit:
    """The fit, tried on genuine paths under each of ``rules`` (:func:`lattice_paths`)."""
    if fit.convention is None:
        return fit
    return replace(fit, lattice=lattice_paths(call, fit.convention, rules, seed))
