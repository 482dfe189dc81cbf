"""The record of a primitive kind: :class:`PrimitiveKind`.

A kind bundles what the harness does differently for triangles, paths and lines: its
scene class, its case-JSON codec, its exact oracle, its near-tie distance, its invariance
variants, its degenerate test, its identify probes, its pictures and its signature hooks.
The hooks that live above the scene contract (the oracle, the checks, identify, diagnosis,
pictures) are named as ``"module:function"`` strings and imported on first use, so that
this package imports nothing but the scene classes and any layer may ask it (the engine
never reaches the presentation through it: a picture drawer is a string until a picture
is drawn). A resolved hook is kept on the kind: a second use costs one dict lookup.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields
from typing import Any, Generic, TypeGuard, TypeVar

import numpy as np
from numpy.typing import NDArray

__all__ = ["PrimitiveKind", "HOOKS", "resolve", "JSON_NUMBER", "JSON_POINT"]

# A coordinate in a case file: a decimal string that is exactly a float ("0.375"), a
# float.hex string ("0x1.8p+1"), "inf", "-inf", "nan", or a JSON number (read exactly: an
# inexact one is refused, never rounded). Each kind's JSON fields are built from these.
JSON_NUMBER: dict[str, Any] = {"anyOf": [
    {"type": "string", "pattern": r"^-?(0x[0-9a-f]+(\.[0-9a-f]*)?(p[+-]?[0-9]+)?|inf|nan)$"},
    {"type": "string", "pattern": r"^-?[0-9]+(\.[0-9]+)?$"},
    {"type": "number"},
]}
JSON_POINT: dict[str, Any] = {"type": "array", "items": JSON_NUMBER, "minItems": 2, "maxItems": 2}

S = TypeVar("S")

# The hooks every kind names, each a "module:function" string, imported on first use.
HOOKS = (
    "to_json",              # (scene) -> dict: the case-JSON fields of its scene
    "from_json",            # (data, width, height) -> scene: its scene from those fields
    "json_sizes",           # (data) -> {what: count}: what the fields hold, counted before any is read
    "oracle",               # (scene, convention) -> Coverage: the exact coverage
    "near_ties",            # (scene, convention or None, fragments, tolerance) -> (near, distance)
    "invariance_variants",  # (scene, seed) -> [(name, scene, index)]: the kind's own variants
    "probes",               # identify's fit of the kind's convention (what identify composes for a rasterizer taking it)
    "verdict_cases",        # (seed, coverage model) -> cases: the suite's cases a declared convention is judged on
    "still_pictures",       # (case, drawing, result) -> {name: uri}: the report's pictures of a failure
    "repro_picture",        # (result, case, payload, convention, said, seen) -> (uri, caption): the minimal repro's
    "conformance_class",    # (result, convention, scene, wrong, prims, snapped, judged, magnitude, complete) -> (class, part)
    "hypotheses",           # (answer, scene, prims, subset, convention, near, exact) -> (class, part) or None: beyond snapping
    "tie_trial",            # (result, case, judge, convention) -> evidence dict or None: wrong only on edges, shifted off
    "dropped_trial",        # (result, case, judge, convention, answer) -> evidence dict or None: missing whole, moved copies
    "vectors",              # (Vectors) -> [svg element]: a picture's vector layer of the kind's primitives
)


def resolve(dotted: str) -> Callable[..., Any]:
    """The function a ``"module:function"`` name names (imported now)."""
    module, _, attribute = dotted.partition(":")
    function: Callable[..., Any] = getattr(importlib.import_module(module), attribute)
    return function


@dataclass(frozen=True, eq=False)
class PrimitiveKind(Generic[S]):
    """One primitive kind: what the harness does differently for its scenes.

    Parameters
    ----------
    name : str
        The scene kind (``scene.kind``): the key of :data:`harness.kinds.KINDS`.
    scene_class : type
        Its scene class.
    json_key : str
        The case-JSON field that holds its primitives (how a case file says its kind).
    convention_attribute : str or None
        The rasterizer attribute naming a convention of its own for this kind (identify
        found one: ``path_convention``, ``line_convention``), None when the kind is judged
        by the rasterizer's ``convention`` alone.
    own_fit : (str, str) or None
        The fingerprint attribute holding identify's fit of this kind's own convention and
        what a message calls that convention (lines: ``("line_fit", "line convention")``),
        None when the kind is judged by the triangle (path) fit.
    translate_shift : (int, int)
        The whole-pixel translation of the invariance check's ``translate`` variant.
    translate_needs_positive : bool
        Whether that variant needs every coordinate positive to be exact (lines: a
        half-away-from-zero rounding of an end point at or left of 0 changes side).
    near_ties_by_own_rule : bool
        Whether invariance measures near ties under the rasterizer's own convention
        (lines: its line rule; without one, the least distance under any rule) rather than
        at a declared sample point alone.
    coordinates_of : callable
        ``(scene, prims) -> [(K, 2) float64]``: each primitive's coordinates (a path's
        every contour together).
    degenerate : callable
        ``(scene, snapped) -> set of int``: of the primitives ``snapped`` maps (primitive ->
        its snapped coordinates, as :attr:`coordinates_of` gives them), those that draw
        nothing: a triangle of zero orientation, a segment of zero length; never a path
        (its fill rule decides).
    work_size : callable
        ``scene -> int``: the size an isolated call's timeout grows with.
    keeps_shapes : callable
        ``(scene, moved) -> bool``: whether a rounded move of the scene (same kind, same
        primitives) kept every primitive's shape class, exactly: a triangle's orientation
        (a sliver within rounding of flat may collapse or flip), a segment's being a point
        or not; always for paths.
    undefined : callable
        ``(scene, convention) -> str``: why the convention defines no answer on the scene
        ("" when it does; lines: a line rule that draws width 1 only, on wider lines).
    exact_tie_words : (str, str)
        How conformance says that every wrong fragment is an exact tie: what they are and
        where they lie (``{noun}`` is the primitive's noun).
    case_word : str
        What a message calls one of its scenes or cases: "a {case_word} scene", "a
        {case_word} case" (``line`` for lines, whose primitive is the segment).
    may_overlap : bool
        Whether its primitives overlap by design (lines cross and share end pixels, points'
        squares overlap): a pixel hit twice is then no overdraw.
    json_fields : mapping of str to JSON Schema
        Its scene's fields in a case file and each one's schema (the case schema's
        properties and its one-kind-per-case rule are built from every kind's).
    json_required : tuple of str
        The fields a case of this kind must give (its ``json_key`` first).
    size_limits : mapping of str to int
        What its case fields may hold at most (``json_sizes`` counts them), per what.
    invariance_families : tuple of str or None
        The case families the invariance check judges (None: every family of the kind;
        triangles leave out the degenerate and mesh families, paths their degenerate one).
    caption_words : callable
        ``scene -> str``: what a repro's caption adds to "N {noun}s" (paths: their fill
        rule; lines: their strips; points: their size).
    to_json, from_json, json_sizes, oracle, near_ties, invariance_variants, probes, verdict_cases,
    still_pictures, repro_picture, conformance_class, hypotheses, tie_trial, dropped_trial, vectors : str
        The hooks of :data:`HOOKS`, each ``"module:function"``.
    """

    name: str
    scene_class: type[S]
    json_key: str
    convention_attribute: str | None
    own_fit: tuple[str, str] | None
    translate_shift: tuple[int, int]
    translate_needs_positive: bool
    near_ties_by_own_rule: bool
    coordinates_of: Callable[[S, NDArray[np.int64]], list[NDArray[np.float64]]]
    degenerate: Callable[[S, dict[int, NDArray[np.float64]]], set[int]]
    work_size: Callable[[S], int]
    keeps_shapes: Callable[[S, S], bool]
    undefined: Callable[[S, Any], str]
    exact_tie_words: tuple[str, str]
    case_word: str
    may_overlap: bool
    json_fields: Mapping[str, Any]
    json_required: tuple[str, ...]
    size_limits: Mapping[str, int]
    invariance_families: tuple[str, ...] | None
    caption_words: Callable[[S], str]
    to_json: str
    from_json: str
    json_sizes: str
    oracle: str
    near_ties: str
    invariance_variants: str
    probes: str
    verdict_cases: str
    still_pictures: str
    repro_picture: str
    conformance_class: str
    hypotheses: str
    tie_trial: str
    dropped_trial: str
    vectors: str
    _resolved: dict[str, Callable[..., Any]] = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in HOOKS:
            value = getattr(self, name)
            if not isinstance(value, str) or value.count(":") != 1:
                raise ValueError(f"kind {self.name!r}: hook {name} must be 'module:function', not {value!r}")

    def hook(self, name: str) -> Callable[..., Any]:
        """Hook ``name`` (one of :data:`HOOKS`) as a function, imported on first use."""
        function = self._resolved.get(name)
        if function is None:
            if name not in HOOKS:
                raise KeyError(f"no hook {name!r}: a kind's hooks are {', '.join(HOOKS)}")
            function = self._resolved[name] = resolve(getattr(self, name))
        return function

    def owns(self, scene: object) -> TypeGuard[S]:
        """Whether ``scene`` is one of this kind's scenes (narrowing it to its class)."""
        return isinstance(scene, self.scene_class)

    def narrow(self, scene: object) -> S:
        """``scene`` as this kind's scene class; ValueError for a scene of another kind
        (code that judges only this kind's scenes)."""
        if not isinstance(scene, self.scene_class):
            raise ValueError(f"{self.name} code handed a {getattr(scene, 'kind', type(scene).__name__)} scene")
        return scene

    def missing_hooks(self) -> list[str]:
        """The hooks (of :data:`HOOKS`) and callables that do not resolve: empty when the
        kind is whole."""
        missing = [f.name for f in fields(self)
                   if f.name in ("coordinates_of", "degenerate", "work_size", "keeps_shapes", "undefined", "caption_words")
                   and not callable(getattr(self, f.name))]
        for name in HOOKS:
            try:
                self.hook(name)
            except (ImportError, AttributeError, KeyError, ValueError):
                missing.append(name)
        return missing
