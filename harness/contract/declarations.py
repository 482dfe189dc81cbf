"""Refusals that teach: what a rasterizer declares must agree with itself and with its answers.

A plugin whose declarations contradict each other (a line rule but no line scenes, fill
rules but no path scenes, a coverage kind its scene kinds cannot have) is refused when it is
loaded, in one line saying what to add (:func:`declaration_problem`). One whose answers
contradict its declared convention (no alphas under area coverage, sample ids under one
sample per pixel) or that asks a scene for what only another scene kind has (``segments``
of a triangle scene) is refused at its first such answer, in one line, and handed no more
scenes of that kind (:func:`answer_problem`, :func:`scene_kind_problem`; the runner keeps
the verdict per rasterizer and scene kind). Every message names what to add or change.
"""

from __future__ import annotations

import re

from harness.contract.conventions import FILL_RULES, Convention, LineRule
from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer, fingerprint_of, scene_kinds_of
from harness.contract.scenes import AnyScene
from harness.kinds import KINDS, SCENE_KINDS

__all__ = ["REFUSED", "declaration_problem", "answer_problem", "scene_kind_problem"]

# what every refusal's message starts with (the report's cause: the text before the colon)
REFUSED = "contradicts its declaration"

# the members only one scene kind has, by kind (a plugin asking another kind's scene for one
# draws that kind: its scene_kinds forgot it)
_MEMBERS = {name: {m for m in dir(kind.scene_class) if not m.startswith("_")} for name, kind in KINDS.items()}
_MISSING_MEMBER = re.compile(r"'(" + "|".join(k.scene_class.__name__ for k in KINDS.values())
                             + r")' object has no attribute '(\w+)'")


def _tuple(kinds: tuple[str, ...]) -> str:
    return "(" + ", ".join(f'"{k}"' for k in kinds) + ("," if len(kinds) == 1 else "") + ")"


def _adding(kinds: tuple[str, ...], kind: str) -> str:
    """How to add ``kind`` to ``kinds``, in words: a plugin on the default (triangles only)
    most likely draws that kind alone."""
    if kinds == ("triangles",):
        return f"scene_kinds = {_tuple((kind,))} (or {_tuple((*kinds, kind))} if it fills triangles too)"
    return f"\"{kind}\" (scene_kinds = {_tuple((*kinds, kind))})"


def declaration_problem(rasterizer: Rasterizer) -> str | None:
    """What a rasterizer declares that its other declarations contradict, in one line that
    says what to add; None when they agree. Read once, when it is loaded.

    The convention read is the plugin's own (one identify found for it is not checked):
    its ``line`` rule needs ``"lines"`` in ``scene_kinds``; ``fill_rules`` need
    ``"paths"``; lines are drawn with one sample per pixel (multisample: rectangles per sample), and the coverage rules
    are defined for triangles only, unless ``line_convention`` (``path_convention``) says how.

    Examples
    --------
    >>> from harness.contract.conventions import Convention, LineRule
    >>> class Drawer:
    ...     name = "mine"
    ...     convention = Convention(line=LineRule("bresenham"))
    ...     def rasterize(self, scene): ...
    >>> print(declaration_problem(Drawer()))  # doctest: +NORMALIZE_WHITESPACE
    contradicts its declaration: its convention declares Bresenham lines, end points to pixels by nearest-even, ties step, last
    pixel drawn, but its scene_kinds ("triangles",) lack "lines", so no line scene would reach it: add scene_kinds = ("lines",)
    (or ("triangles", "lines") if it fills triangles too)
    """
    if fingerprint_of(rasterizer) is not None:
        return None  # rastercheck's own wrapper of an identified black box, whose plugin was read when loaded
    raw_kinds = getattr(rasterizer, "scene_kinds", None)
    if isinstance(raw_kinds, str):
        return (f"{REFUSED}: scene_kinds = {raw_kinds!r} is one string, not a tuple of kinds: "
                f"write scene_kinds = {_tuple((raw_kinds,))}")
    try:
        kinds = scene_kinds_of(rasterizer)
    except TypeError:
        return f"{REFUSED}: scene_kinds = {raw_kinds!r} is not a tuple of kinds: list some of {_tuple(SCENE_KINDS)}"
    unknown = [k for k in kinds if k not in SCENE_KINDS]
    if unknown:
        return (f"{REFUSED}: scene_kinds names {', '.join(repr(k) for k in unknown)}, which is no scene kind: "
                f"list some of {_tuple(SCENE_KINDS)}")
    if not kinds:
        return f"{REFUSED}: scene_kinds is empty, so no scene would reach it: list the kinds it draws, of {_tuple(SCENE_KINDS)}"
    raw_rules = getattr(rasterizer, "fill_rules", None)
    if raw_rules is not None:
        if isinstance(raw_rules, str):
            return (f"{REFUSED}: fill_rules = {raw_rules!r} is one string, not a tuple of rules: "
                    f"write fill_rules = {_tuple((raw_rules,))}")
        try:
            rules = tuple(str(r) for r in raw_rules)
        except TypeError:
            return f"{REFUSED}: fill_rules = {raw_rules!r} is not a tuple of rules: list some of {_tuple(FILL_RULES)}"
        bad = [r for r in rules if r not in FILL_RULES]
        if bad:
            return (f"{REFUSED}: fill_rules names {', '.join(repr(r) for r in bad)}, which is no fill rule: "
                    f"list some of {_tuple(FILL_RULES)}")
        if "paths" not in kinds:
            return (f"{REFUSED}: it declares fill_rules {_tuple(rules)} but its scene_kinds {_tuple(kinds)} lack \"paths\", "
                    f"so no path scene would reach it: add \"paths\" (scene_kinds = {_tuple((*kinds, 'paths'))})")
        if not rules:
            return (f"{REFUSED}: fill_rules is empty, so no path scene would reach it: "
                    f"list the rules it honours, of {_tuple(FILL_RULES)}")
    convention = rasterizer.convention
    if convention is None:
        return None
    if convention.line != LineRule() and "lines" not in kinds:
        return (f"{REFUSED}: its convention declares {convention.line.describe()}, but its scene_kinds {_tuple(kinds)} lack "
                f"\"lines\", so no line scene would reach it: add {_adding(kinds, 'lines')}")
    line = getattr(rasterizer, "line_convention", None)
    model = convention.model
    # lines: one sample per pixel, or a pattern's samples in a rectangle
    if ("lines" in kinds and not isinstance(line, Convention) and not model.single_sample
            and not (model.lines and convention.line.rule == "rectangle")):
        return (f"{REFUSED}: it takes lines, which are drawn with one sample per pixel (or, multisample, as rectangles "
                f"per sample), but its convention declares "
                + (model.declared_as(convention) if model.rule else f"{convention.coverage_kind} coverage")
                + (" with " + convention.line.describe() if model.lines else "")
                + ": give it line_convention = Convention(line=...) for its lines"
                + (", or line=LineRule(\"rectangle\") for multisample lines" if model.lines else "")
                + ", or leave \"lines\" out of scene_kinds")
    path = getattr(rasterizer, "path_convention", None)
    if "paths" in kinds and not isinstance(path, Convention) and not model.paths and model.rule:
        return (f"{REFUSED}: it takes paths, but its convention declares {model.declared_as(convention)}, a coverage rule "
                f"defined for triangles only: give it path_convention = Convention(...) for its paths, or leave \"paths\" "
                f"out of scene_kinds")
    if "paths" in kinds and not isinstance(path, Convention) and not model.paths:
        return (f"{REFUSED}: it takes paths, but its convention declares analytic area coverage, which is not defined for "
                f"paths: give the area convention a sample pattern (Convention(coverage=\"area\", samples=...)), or "
                f"path_convention = Convention(...) for its paths, or leave \"paths\" out of scene_kinds")
    return None


def answer_problem(convention: Convention | None, coverage: Coverage) -> str | None:
    """What the form of an answer contradicts in the coverage kind its convention
    declares, in one line saying what to change; None when it agrees (or when nothing
    was declared: identify reads the kind of such a rasterizer from its answers).

    Single: spans without sample ids or alphas; multisample: spans with a sample id each,
    no alphas; area: an alpha per pixel, no sample ids. An answer without a span agrees
    with every kind.

    >>> from harness.contract.conventions import Convention
    >>> print(answer_problem(Convention(coverage="area"), Coverage([0], [0], [0], [2])))  # doctest: +NORMALIZE_WHITESPACE
    contradicts its declaration: its convention declares area coverage, but its answer carries no alphas: return Coverage(...,
    alpha=a) with one alpha per pixel in span order, or declare one sample per pixel (Convention(coverage="sample"))
    """
    if convention is None or not len(coverage):
        return None
    model = convention.model
    head = f"{REFUSED}: its convention declares {model.declared_as(convention)}, but its answer carries"
    if model.alphas:
        if coverage.sample is not None:
            return (f"{head} sample ids: return one alpha per pixel (Coverage(..., alpha=a)) without sample=, or declare the "
                    f"pattern without coverage=\"area\" (Convention(samples=...)) for multisample coverage")
        if coverage.alpha is None:
            return (f"{head} no alphas: return Coverage(..., alpha=a) with one alpha per pixel in span order, or declare one "
                    f"sample per pixel (Convention(coverage=\"sample\"))")
        return None
    if coverage.alpha is not None:
        return (f"{head} alphas: declare Convention(coverage=\"area\", ...) for anti-aliased coverage, or return the covered "
                f"spans without alpha=")
    if model.sample_ids and coverage.sample is None:
        return (f"{head} no sample ids: return Coverage(..., sample=s) with the sample of the pattern each span covers, or "
                f"declare one sample per pixel (Convention(sample=(x, y)) without samples=)")
    if not model.sample_ids and coverage.sample is not None:
        return (f"{head} sample ids: declare the pattern (Convention(samples=n or [(x, y), ...])) for multisample coverage, "
                f"or return the covered spans without sample=")
    return None


def scene_kind_problem(rasterizer: Rasterizer, scene: AnyScene, error: BaseException | None) -> str | None:
    """When a rasterizer's error says it asked ``scene`` for a member only another scene
    kind has (``'Scene' object has no attribute 'segments'``: a line drawer handed
    triangles), one line saying which kind it draws and what to add to its
    ``scene_kinds`` (or, when it lists that kind already, to leave this one out); None
    otherwise.

    >>> from harness.contract.scenes import Scene
    >>> class Drawer:
    ...     name, convention = "mine", None
    >>> print(scene_kind_problem(Drawer(), Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]]),  # doctest: +NORMALIZE_WHITESPACE
    ...                          AttributeError("'Scene' object has no attribute 'segments'")))
    contradicts its declaration: it asked a triangle scene for `segments`, which line scenes have, but its scene_kinds
    ("triangles",) lack "lines": add scene_kinds = ("lines",) (or ("triangles", "lines") if it fills triangles too)
    """
    if not isinstance(error, AttributeError):
        return None
    match = _MISSING_MEMBER.search(str(error))
    if match is None:
        return None
    member = match.group(2)
    kinds = scene_kinds_of(rasterizer)
    owners = [k for k in SCENE_KINDS if k != scene.kind and member in _MEMBERS[k] and member not in _MEMBERS[scene.kind]]
    if not owners:
        return None
    noun = {name: kind.case_word for name, kind in KINDS.items()}
    asked = (f"{REFUSED}: it asked a {noun[scene.kind]} scene for `{member}`, "
             f"which {' and '.join(noun[k] for k in owners)} scenes have")
    missing = [k for k in owners if k not in kinds]
    if not missing:  # it lists this kind but draws it as another: the kind is listed in error
        rest = tuple(k for k in kinds if k != scene.kind)
        return (f"{asked}: it lists \"{scene.kind}\" in scene_kinds but does not draw them: leave \"{scene.kind}\" out "
                f"(scene_kinds = {_tuple(rest)}), or read a {type(scene).__name__}'s own arrays")
    lacking = " and ".join(f'"{k}"' for k in missing)
    return f"{asked}, but its scene_kinds {_tuple(kinds)} lack {lacking}: add " + " or ".join(_adding(kinds, k) for k in missing)
