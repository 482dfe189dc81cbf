"""What a call of a rasterizer gives back, and how it crosses from the worker process to the
parent without pickle: the :class:`Outcome` of one call, and its plain-data encoding
(:func:`encode_outcome`, :func:`decode_outcome`, over :mod:`harness.engine.wire`).

Nothing the plugin made crosses back by pickle: the worker sends each outcome as plain data,
and the parent rebuilds the coverage from checked int64 and float64 buffers and the error as
an exception of the plugin's type name deriving from its nearest builtin or harness base
(:func:`decode_outcome`), so no code of the plugin's runs in the parent.
"""

from __future__ import annotations

import builtins
import functools
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, Scene, Unsupported
from harness.engine.wire import WireError, pack, unpack
from harness.kinds import kind_of

__all__ = ["Outcome", "layer_of", "describe", "Call", "AnyCall", "PluginError", "span_limit", "encode_outcome", "decode_outcome",
           "rebuilt_error", "ERROR_BASES", "MAX_TEXT"]


@dataclass(frozen=True, slots=True)
class Outcome:
    """What one rasterize call gave: a coverage, or an error (with its traceback).

    ``coverage`` is always safe to expand into pixels (:meth:`Coverage.tidy`: spans
    clipped to the viewport and to their triangle's reach, no pixel twice); when the
    rasterizer's own answer was malformed, ``received`` holds it as it came and ``flaws``
    the offending spans by kind (the hygiene check reports them).
    """

    coverage: Coverage | None
    error: BaseException | None = None
    traceback: str = ""
    seconds: float = 0.0
    timed_out: bool = False
    received: Coverage | None = None
    flaws: dict[str, Any] | None = None
    retried: float | None = None  # the limit (s) of a first ask that was cut off, when it was asked again

    @property
    def retry_text(self) -> str:
        """How the call was asked again, in words ("" when it was asked once)."""
        if self.retried is None:
            return ""
        if self.coverage is None and self.timed_out:
            return f"cut off after {self.retried:.3g} s, asked again: {describe(self.error, with_type=False)}"
        return f"cut off after {self.retried:.3g} s, answered when asked again (in {self.seconds:.3g} s)"


def layer_of(outcome: Outcome, index: int) -> Outcome:
    """Sample ``index`` of a multisample outcome (:meth:`Coverage.layer`); errors as they are."""
    if outcome.coverage is None:
        return outcome
    received = None if outcome.received is None else outcome.received.layer(index)
    return replace(outcome, coverage=outcome.coverage.layer(index), received=received)


def _tidied(outcome: Outcome, scene: AnyScene) -> Outcome:
    if outcome.coverage is None:
        return outcome
    usable, flaws = outcome.coverage.tidy(scene)
    if usable is outcome.coverage:
        return outcome
    return Outcome(usable, seconds=outcome.seconds, received=outcome.coverage, flaws=flaws, retried=outcome.retried)


# What the checks and probes hold: the rasterizer again, as a function of a scene.
Call = Callable[[Scene], Outcome]
# A call that takes a scene of any kind (the runner's: it hands path scenes to path fillers).
AnyCall = Callable[[AnyScene], Outcome]


def describe(error: BaseException | None, with_type: bool = True) -> str:
    """``Type: text`` of an exception (only its text without ``with_type``), even when its
    ``__str__`` raises.

    >>> describe(ValueError("triangle 3 is huge"))
    'ValueError: triangle 3 is huge'
    """
    if error is None:
        return "no error"
    try:
        text = str(error)
    except BaseException as inner:  # noqa: B036 - a plugin's __str__ may raise anything
        text = f"<its text cannot be shown: __str__ raised {type(inner).__name__}>"
    if not with_type:
        return text
    return f"{type(error).__name__}: {text}" if text else type(error).__name__


class PluginError(RuntimeError):
    """The harness's error about a plugin's answer: refused (too many spans), or one that
    cannot be sent back or read back as plain data."""


def _pieces(scene: AnyScene) -> int:
    """Triangles, or for paths their vertices: a path needs at most one span per row for
    every two of its edges."""
    return kind_of(scene).work_size(scene)


def span_limit(scene: AnyScene) -> int:
    """The most spans an answer may hold: a triangle is convex, so it needs at most one
    span per row, a path one per row for every two edges (16 allowed, for one per sample of
    a 16x multisample pattern)."""
    return 16 * (_pieces(scene) + 1) * scene.height + 1024


# -- the wire: an outcome as plain data, worker to parent without pickle ------------------

# Texts an outcome carries (an error's message, a traceback) are cut to this many characters.
MAX_TEXT = 200_000
_SPAN_FIELDS = ("primitive", "y", "x0", "x1")
_OPTIONAL_FIELDS = {"attributes": (np.float64, 2), "sample": (np.int64, 1), "alpha": (np.float64, 1)}
_COVERAGES = ("coverage", "received")
_OUTCOME_FIELDS = {"seconds", "timed_out", "traceback", "retried", "error", "coverage", "received", "flaws"}
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,99}")


def _error_bases() -> dict[str, type[BaseException]]:
    """Python's builtin exceptions a carried error may derive from, by name: those a
    subclass of can be built from one message (``cls("text")``); exception groups and the Unicode errors' five
    arguments leave theirs to a base above them."""
    found: dict[str, type[BaseException]] = {}
    for name, value in vars(builtins).items():
        if not (isinstance(value, type) and issubclass(value, BaseException)) or value.__name__ != name \
                or issubclass(value, BaseExceptionGroup):
            continue
        try:
            type("Probe", (value,), {})("text")
        except Exception:  # noqa: S112 - not buildable from one message (or not a base): one above it serves
            continue
        found[name] = value
    return found


# What an error rebuilt in the parent derives from: the nearest of these in the plugin's
# exception's MRO (Python's builtin exceptions and the harness's own).
ERROR_BASES: dict[str, type[BaseException]] = {**_error_bases(), "Unsupported": Unsupported, "PluginError": PluginError}
_BASE_NAMES: dict[type[BaseException], str] = {cls: name for name, cls in ERROR_BASES.items()}


def _plain_text(text: str, most: int = MAX_TEXT) -> str:
    """``text`` as a plain ``str`` (not a subclass of the plugin's), cut to ``most`` characters."""
    plain = str.__str__(text) if isinstance(text, str) else "<not text>"
    if len(plain) > most:
        plain = f"{plain[:most]}... ({len(plain) - most:,} more characters)"
    return plain


def _identifier(name: str) -> str:
    """``name`` made a Python identifier of at most 100 characters (other characters become _)."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", _plain_text(name, 100)) or "PluginError"
    return name if _NAME.fullmatch(name) else f"_{name}"[:100]


def _error_fields(error: BaseException) -> dict[str, str]:
    """An exception as plain data: its type's name, its nearest base in :data:`ERROR_BASES`
    and its text (:func:`describe`)."""
    try:
        kind = type(error)
        name = _identifier(kind.__name__)
        base = next((_BASE_NAMES[cls] for cls in type.__dict__["__mro__"].__get__(kind) if cls in _BASE_NAMES), "BaseException")
    except BaseException:  # noqa: B036 - a type built to refuse being looked at
        name, base = "PluginError", "PluginError"
    return {"type": name, "base": base, "text": _plain_text(describe(error, with_type=False))}


def _keeps_text(cls: type[BaseException]) -> bool:
    """Whether ``str(cls(text))`` is ``text`` (not so for KeyError, which quotes it)."""
    try:
        return str(cls("text")) == "text"
    except Exception:
        return False


def _carried_text(error: BaseException) -> str:
    return str(error.args[0]) if error.args else ""


def _carried_reduce(error: BaseException) -> tuple[Any, ...]:
    return rebuilt_error, (type(error).__name__, getattr(type(error), "carried_base", "PluginError"), _carried_text(error))


@functools.lru_cache(maxsize=1024)
def _error_class(name: str, base: str) -> type[BaseException]:
    """The class of a rebuilt error: ``base`` itself when the plugin raised exactly it, else
    a class named ``name`` deriving from it, whose text is the carried one."""
    known = ERROR_BASES[base]
    if name == base and _keeps_text(known):
        return known
    return type(name, (known,), {"__str__": _carried_text, "__reduce__": _carried_reduce, "__module__": __name__,
                                 "__qualname__": name, "carried_base": base,
                                 "__doc__": f"A plugin's {name} ({base}), rebuilt from its name and text."})


def rebuilt_error(name: str, base: str, text: str) -> BaseException:
    """The parent's copy of a plugin's exception: an instance of a class named ``name``
    (made an identifier) that derives from ``ERROR_BASES[base]`` (PluginError for an
    unknown base), whose ``str`` is ``text``.

    >>> error = rebuilt_error("TriangleTooLarge", "ValueError", "triangle 3 is huge")
    >>> isinstance(error, ValueError), describe(error)
    (True, 'TriangleTooLarge: triangle 3 is huge')
    >>> type(rebuilt_error("ValueError", "ValueError", "bad")) is ValueError
    True
    """
    return _error_class(_identifier(name), base if base in ERROR_BASES else "PluginError")(_plain_text(text))


def _plain_coverage(coverage: Coverage) -> Coverage:  # runs in the child
    """``coverage`` rebuilt as a plain :class:`Coverage` of plain ndarrays: its fields read
    through Coverage's own slots (a subclass's overrides are not asked), each copied (the
    float ones by Coverage itself)."""
    def field(name: str) -> Any:
        value = Coverage.__dict__[name].__get__(coverage, Coverage)
        if value is None:
            return None
        return np.asarray(value) if name in ("attributes", "alpha") else np.array(value, copy=True, subok=False)

    return Coverage(*(field(f) for f in _SPAN_FIELDS), **{f: field(f) for f in _OPTIONAL_FIELDS})


def encode_outcome(outcome: Outcome) -> bytes:
    """``outcome`` as one :mod:`harness.engine.wire` message of plain data: its coverages' arrays
    (int64 spans, float64 attributes and alphas), the flaws' int64 arrays, its seconds,
    traceback text and error (:func:`decode_outcome` rebuilds it).

    >>> cov = Coverage.from_pixels([0, 0], [1, 2], [3, 3])
    >>> back = decode_outcome(encode_outcome(Outcome(cov, seconds=0.25)))
    >>> back.coverage.x0, back.coverage.x1, back.seconds, back.error
    (array([1]), array([3]), 0.25, None)
    """
    arrays: dict[str, Any] = {}
    fields: dict[str, Any] = {"seconds": float(outcome.seconds), "timed_out": bool(outcome.timed_out),
                              "traceback": _plain_text(outcome.traceback),
                              "retried": None if outcome.retried is None else float(outcome.retried),
                              "error": None if outcome.error is None else _error_fields(outcome.error), "flaws": None}
    for which in _COVERAGES:
        coverage = getattr(outcome, which)
        fields[which] = None
        if coverage is not None:
            plain = _plain_coverage(coverage)
            fields[which] = {f: getattr(plain, f) is not None for f in _OPTIONAL_FIELDS}
            arrays.update({f"{which}.{f}": getattr(plain, f) for f in (*_SPAN_FIELDS, *_OPTIONAL_FIELDS)})
    if outcome.flaws is not None:
        fields["flaws"] = [_plain_text(str(kind), 100) for kind in outcome.flaws]
        for kind, value in zip(fields["flaws"], outcome.flaws.values(), strict=True):
            arrays[f"flaws.{kind}"] = np.array(value, dtype=np.int64, copy=True).reshape(-1)
    return pack(fields, arrays)


def decode_outcome(message: bytes) -> Outcome:
    """The :class:`Outcome` an :func:`encode_outcome` message holds, every part checked:
    no pickle, only :mod:`harness.engine.wire`'s int64 and float64 buffers and JSON.

    Raises
    ------
    WireError
        Saying what in the message is not as :func:`encode_outcome` writes it.
    """
    fields, arrays = unpack(message)
    if set(fields) != _OUTCOME_FIELDS:
        raise WireError(f"the outcome's fields are {sorted(fields)[:10]}, not {sorted(_OUTCOME_FIELDS)}")
    seconds, retried = fields["seconds"], fields["retried"]
    if not _is_number(seconds) or not (retried is None or _is_number(retried)):
        raise WireError("seconds or retried is not a number")
    if not isinstance(fields["timed_out"], bool) or not isinstance(fields["traceback"], str):
        raise WireError("timed_out is not true or false, or the traceback is not text")
    used: set[str] = set()
    coverages = {which: _decoded_coverage(which, fields[which], arrays, used) for which in _COVERAGES}
    flaws = None
    if fields["flaws"] is not None:
        if not isinstance(fields["flaws"], list) or not all(isinstance(k, str) for k in fields["flaws"]):
            raise WireError("flaws is not a list of names")
        flaws = {kind: _array(arrays, f"flaws.{kind}", np.int64, 1, used) for kind in fields["flaws"]}
    if set(arrays) != used:
        raise WireError(f"arrays not part of the outcome: {sorted(set(arrays) - used)[:5]}")
    error = _decoded_error(fields["error"])
    if (coverages["coverage"] is None) == (error is None):
        raise WireError("an outcome holds a coverage or an error, not both or neither")
    return Outcome(coverages["coverage"], error, _plain_text(fields["traceback"]), float(seconds), fields["timed_out"],
                   coverages["received"], flaws, None if retried is None else float(retried))


def _is_number(value: Any) -> bool:
    return type(value) in (int, float) and math.isfinite(value) and value >= 0


def _array(arrays: dict[str, Any], name: str, dtype: Any, ndim: int, used: set[str]) -> Any:
    array = arrays.get(name)
    if array is None or array.dtype != dtype or array.ndim != ndim:
        what = "missing" if array is None else f"{array.dtype} of {array.ndim} dimensions"
        raise WireError(f"array {name!r}: {what}, not {np.dtype(dtype)} of {ndim}")
    used.add(name)
    return array


def _decoded_coverage(which: str, present: Any, arrays: dict[str, Any], used: set[str]) -> Coverage | None:
    if present is None:
        return None
    if not isinstance(present, dict) or set(present) != set(_OPTIONAL_FIELDS) or not all(isinstance(v, bool)
                                                                                         for v in present.values()):
        raise WireError(f"{which} does not say which of {', '.join(_OPTIONAL_FIELDS)} it holds")
    primitive, y, x0, x1 = (_array(arrays, f"{which}.{f}", np.int64, 1, used) for f in _SPAN_FIELDS)
    extra = {f: _array(arrays, f"{which}.{f}", dtype, ndim, used) if present[f] else None
             for f, (dtype, ndim) in _OPTIONAL_FIELDS.items()}
    try:
        return Coverage(primitive, y, x0, x1, attributes=extra["attributes"], sample=extra["sample"], alpha=extra["alpha"])
    except ValueError as exc:
        raise WireError(f"{which}: {exc}") from None


def _decoded_error(fields: Any) -> BaseException | None:
    if fields is None:
        return None
    if not isinstance(fields, dict) or set(fields) != {"type", "base", "text"} \
            or not all(isinstance(v, str) for v in fields.values()):
        raise WireError("the error is not {type, base, text} of text")
    return rebuilt_error(fields["type"], fields["base"], fields["text"])
