"""The contract every rasterizer implements: Scene in, Coverage out.

A rasterizer is any object with ``name``, ``convention`` and ``rasterize(scene)`` (see
:class:`Rasterizer`); there is no base class to inherit. The optional members are read
only through the ``*_of`` functions here.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol, runtime_checkable

from harness.contract.conventions import FILL_RULES, Convention, InputPrecision, input_precision
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, Scene
from harness.kinds import LINES, PATHS, kind_of


@runtime_checkable
class Rasterizer(Protocol):
    """Anything that turns a Scene into a Coverage.

    Attributes
    ----------
    name : str
        Short identifier, shown in reports.
    convention : Convention or None
        The fill convention it claims to follow; None when it declares none.

    Optional members, read only through :func:`interpolates_of`, :func:`received_of` and
    :func:`fingerprint_of` (a plugin that lacks them is still a Rasterizer):

    interpolates : bool
        False for a coverage-only rasterizer (True when absent): its hygiene check then
        accepts missing attribute rows, and the texel and perspective checks are skipped
        with that reason instead of failing.
    input : str or InputPrecision
        The coordinates the library receives (:class:`harness.contract.conventions.InputPrecision`:
        ``"float32"`` at the GL and Vulkan APIs, ``"fixed6"`` for FreeType's 26.6,
        ``"fixed8-toward-zero"`` for AGG 2.0's ``int(c * 256)``), for a rasterizer that declares
        no convention (one that does says it in ``Convention(input=...)``). Read by
        :func:`input_of` and :func:`received_of`.
    received : callable, ``received(scene) -> Scene``
        The scene as the library really receives it, for an input format ``input`` cannot
        say: a failure that passes on it is blamed on the input format. Read by
        :func:`received_of`, which otherwise derives it from the declared input.
    fingerprint : harness.identify.fingerprint.Fingerprint
        Set by rastercheck on a rasterizer that declares no convention: what identify
        found, so that verdicts against a best guess say so.
    scene_kinds : tuple of str
        The scene kinds it takes, of :data:`SCENE_KINDS` (``("triangles",)`` when absent):
        one listing ``"paths"`` is handed :class:`PathScene` too, and fills each path in
        one go under the scene's fill rule; one listing ``"lines"`` is handed
        :class:`LineScene` and draws each segment by its convention's ``line`` rule
        (:class:`harness.contract.conventions.LineRule`). Read by :func:`scene_kinds_of`.
    fill_rules : tuple of str
        The fill rules a path-taking rasterizer honours (both when absent): it is handed
        only path scenes of these rules. Read by :func:`fill_rules_of`.
    path_convention : Convention
        The convention its path fills follow when not ``convention`` (set by identify on a
        black box whose paths and triangles differ). Read by :func:`convention_for`.
    line_convention : Convention
        The convention its lines follow when not ``convention`` (set by identify on a
        black box whose lines are snapped otherwise than its triangles, or drawn as
        rectangles at another sample point or tie rule). Read by :func:`convention_for`.
    library, library_version : str
        The library it drives (the same for each of the library's modes) and its version:
        the atlas's rows. Read by :func:`library_of`.
    coverage_kind : str
        The coverage it returns, ``single``, ``multisample`` or ``area``, when it
        declares no convention that says so. Read by :func:`coverage_kind_of`.
    kinds_not_taken : dict of str to str
        For the atlas: why it takes no scene of a kind (``{"lines": "the library draws
        no lines"}``).
    """

    # Read-only members: a plain class attribute or instance attribute of a narrower
    # type (say ``convention = Convention()``) satisfies them.
    @property
    def name(self) -> str: ...

    @property
    def convention(self) -> Convention | None: ...

    # ``scene`` is an AnyScene of a kind the rasterizer takes (``scene_kinds``). Typed Any, not
    # AnyScene: a plugin annotates only the kinds it takes (``scene: Scene`` for triangles),
    # and a parameter is contravariant -- against ``AnyScene`` no triangle-only plugin would
    # satisfy the protocol statically (tests/typing/builtins_are_rasterizers.py).
    def rasterize(self, scene: Any) -> Coverage:
        """Cover the scene's primitives (a scene of a kind it takes, ``scene_kinds``:
        :class:`~harness.contract.scenes.AnyScene`); attributes interpolated when the
        scene has them."""
        ...


def scene_kinds_of(rasterizer: Rasterizer) -> tuple[str, ...]:
    """The scene kinds a rasterizer takes (``scene_kinds``; triangles only when absent)."""
    kinds = getattr(rasterizer, "scene_kinds", None)
    return ("triangles",) if kinds is None else tuple(str(k) for k in kinds)


def convention_for(rasterizer: Rasterizer, scene: AnyScene) -> Convention | None:
    """The convention a rasterizer's answer on ``scene`` is judged by: its
    ``path_convention`` for a path scene when it has one (a black box whose path fills
    identify found to follow another convention than its triangles), its
    ``line_convention`` for a line scene when it has one (likewise for lines), else its
    ``convention``; for a line scene, as line end points see it (its line rule's own snap
    rounding, :meth:`Convention.for_lines`)."""
    attribute = kind_of(scene).convention_attribute
    found = rasterizer.convention
    if attribute is not None:
        own = getattr(rasterizer, attribute, None)
        if isinstance(own, Convention):
            found = own
    return found.for_lines() if found is not None and LINES.owns(scene) else found


def fill_rules_of(rasterizer: Rasterizer) -> tuple[str, ...]:
    """The fill rules a path-taking rasterizer honours (``fill_rules``; both when absent)."""
    rules = getattr(rasterizer, "fill_rules", None)
    return tuple(FILL_RULES) if rules is None else tuple(str(r) for r in rules)


def takes(rasterizer: Rasterizer, scene: AnyScene) -> bool:
    """Whether the rasterizer is handed ``scene``: a kind it takes (and, for paths, a fill
    rule it honours). The runner gives each rasterizer only such scenes."""
    if scene.kind not in scene_kinds_of(rasterizer):
        return False
    # a fill rule is a path's: only path scenes carry one
    return not PATHS.owns(scene) or scene.fill_rule in fill_rules_of(rasterizer)


def library_of(rasterizer: Rasterizer) -> tuple[str, str]:
    """The library a rasterizer drives and its version (``library``, ``library_version``):
    its own name and ``""`` when it names none (a reference rasterizer, a plugin)."""
    inner = getattr(rasterizer, "inner", rasterizer)  # an identified black box: the adapter it wraps
    library = getattr(inner, "library", "") or rasterizer.name
    return str(library), str(getattr(inner, "library_version", "") or "")


def coverage_kind_of(rasterizer: Rasterizer) -> str:
    """The kind of coverage a rasterizer returns: its declared convention's, else its own
    ``coverage_kind``, else ``single``."""
    if rasterizer.convention is not None:
        return str(rasterizer.convention.coverage_kind)
    inner = getattr(rasterizer, "inner", rasterizer)
    return str(getattr(inner, "coverage_kind", "single") or "single")


def interpolates_of(rasterizer: Rasterizer) -> bool:
    """Whether the rasterizer interpolates attributes (``interpolates``, True when absent)."""
    return bool(getattr(rasterizer, "interpolates", True))


def input_of(rasterizer: Rasterizer) -> InputPrecision:
    """The input precision the rasterizer declares: its ``input`` member, else its
    convention's ``input``, else float64 (what the scene holds).

    >>> class Box:
    ...     name, convention, input = "box", None, "fixed6"
    >>> input_of(Box()).describe()
    '26.6 fixed-point input (1/64 px, nearest-even)'
    """
    declared = getattr(rasterizer, "input", None)
    if declared is not None:
        return input_precision(declared)
    convention = getattr(rasterizer, "convention", None)
    return convention.input_precision if isinstance(convention, Convention) else InputPrecision()


def received_of(rasterizer: Rasterizer) -> Callable[[Scene], Scene] | None:
    """The rasterizer's ``received(scene) -> Scene``: its own member when it has one, else
    the scene with every coordinate as its ``input`` member says the library receives it
    (:meth:`InputPrecision.apply`); None for neither, or float64 input. (A convention's
    ``input`` is no account of a failure: its oracle applies it already.)"""
    received: Callable[[Scene], Scene] | None = getattr(rasterizer, "received", None)
    if callable(received):
        return received
    declared = getattr(rasterizer, "input", None)
    precision = InputPrecision() if declared is None else input_precision(declared)
    if precision.kind == "float64":
        return None

    def as_received(scene: Any) -> Any:
        return scene.with_coordinates(precision.apply(scene.coordinates))

    return as_received


def receive(rasterizer: Rasterizer, scene: Any) -> Any:
    """``scene`` as the rasterizer's library receives it (:func:`received_of`; unchanged for
    float64 input)."""
    received = received_of(rasterizer)
    return scene if received is None else received(scene)


def fingerprint_of(rasterizer: Rasterizer) -> Any:
    """What identify found for a rasterizer that declared no convention, or None."""
    return getattr(rasterizer, "fingerprint", None)
