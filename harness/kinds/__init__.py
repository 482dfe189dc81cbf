"""Primitive kinds as objects: what the harness does differently for triangles, paths and
lines lives with the kind, and the rest of the harness asks the kind.

:data:`KINDS` maps ``scene.kind`` to a :class:`~harness.kinds.base.PrimitiveKind`, one
module per kind (:mod:`~harness.kinds.triangles`, :mod:`~harness.kinds.paths`,
:mod:`~harness.kinds.lines`); :func:`kind_of` is a scene's. A kind holds its scene class,
its case-JSON codec, oracle, near-tie distance, invariance variants, degenerate test,
identify probes, pictures and signature hooks.

Layering: this package imports only the scene contract (and the exact orientation of
:mod:`harness.geometry.exact`), so every layer may import it. Each hook that lives higher
(the codec in :mod:`harness.contract.case`, the oracles, the checks, identify, diagnosis and
the report's pictures) is named by a ``"module:function"`` string and imported the first
time it is asked for (:meth:`~harness.kinds.base.PrimitiveKind.hook`), then kept: the
engine never imports the presentation through a kind, and a hook costs one dict lookup
after its first use.

Adding a primitive kind: a module here with its scene class and record, its entry in
:data:`KINDS` (which makes :data:`SCENE_KINDS`), and the functions its hooks name; ``tests/kinds/test_kinds.py`` fails
while any hook does not resolve.
"""

from __future__ import annotations

from typing import Any

from harness.contract.scenes import AnyScene
from harness.kinds.base import HOOKS, PrimitiveKind
from harness.kinds.lines import LINES
from harness.kinds.paths import PATHS
from harness.kinds.points import POINTS
from harness.kinds.triangles import TRIANGLES

__all__ = ["PrimitiveKind", "HOOKS", "KINDS", "SCENE_KINDS", "POINTS", "TRIANGLES", "PATHS", "LINES", "kind_of", "kind_named",
           "kind_of_json"]

KINDS: dict[str, PrimitiveKind[Any]] = {k.name: k for k in (TRIANGLES, PATHS, LINES, POINTS)}
# the scene kinds a rasterizer may list in its scene_kinds, in this order everywhere
SCENE_KINDS: tuple[str, ...] = tuple(KINDS)


def kind_of(scene: AnyScene) -> PrimitiveKind[Any]:
    """The kind of ``scene`` (its ``kind``'s entry of :data:`KINDS`)."""
    return KINDS[scene.kind]


def kind_named(name: str) -> PrimitiveKind[Any]:
    """The kind called ``name``; ValueError naming the kinds for another name."""
    try:
        return KINDS[name]
    except KeyError:
        raise ValueError(f"no scene kind {name!r}: the kinds are {', '.join(KINDS)}") from None


def kind_of_json(data: dict[str, Any]) -> PrimitiveKind[Any]:
    """The kind whose primitives a case's JSON fields hold (its ``json_key``; triangles
    when none is there, for the schema to name the missing ``positions``)."""
    for kind in KINDS.values():
        if kind is not TRIANGLES and kind.json_key in data:
            return kind
    return TRIANGLES
