"""Isolation: every call of a rasterizer in a forked worker process, with a time limit.

The one place where rastercheck calls a plugin. An exception (any ``BaseException``,
``KeyboardInterrupt`` and ``SystemExit`` raised by the plugin included) becomes an
:class:`Outcome` carrying its type, text and traceback (text even when its ``__str__``
raises). Nothing the plugin made crosses back by pickle: the worker sends each outcome as
plain data (:func:`encode_outcome`, :mod:`harness.engine.wire`), and the parent rebuilds the
coverage from checked int64 and float64 buffers and the error as an exception of the
plugin's type name deriving from its nearest builtin or harness base (:func:`decode_outcome`),
so no code of the plugin's runs in the parent. A call
that outlives its time limit, or a worker that dies (a segfault, ``os._exit``), becomes
an outcome too; the worker is then replaced and the caller goes on.

Every call's time limit comes from one policy, :class:`TimeLimit`: a base plus a rate
times the work the scene implies (its primitives, the pixels of their bounding boxes
times the samples per pixel the rasterizer's convention, declared or seen in its
answers, implies, the edges' rows), never above the user's cap (``--timeout``). A call
cut off by its limit is asked again once, in a fresh process, with a longer limit before
it counts as a timeout: the machine's load never turns a slow answer into a verdict.
"""

from __future__ import annotations

import builtins
import functools
import math
import multiprocessing
import os
import re
import time
import traceback
import weakref
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer
from harness.contract.scenes import AnyScene, Scene, Unsupported
from harness.engine.wire import MAX_HEADER_BYTES, WireError, pack, unpack
from harness.kinds import kind_of

__all__ = ["Outcome", "layer_of", "Worker", "InProcess", "call_in_process", "each_until_error", "describe", "span_limit", "Call", "AnyCall", "PluginError",
           "kill_all", "TimeLimit", "answer_bytes_limit", "MAX_ANSWER_BYTES", "scene_work", "samples_of", "samples_seen", "CallTally", "encode_outcome", "decode_outcome",
           "ERROR_BASES"]


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
            return f"cut off after {self.retried:.3g} s, asked again: {describe(self.error, kind=False)}"
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


def describe(error: BaseException | None, kind: bool = True) -> str:
    """``Type: text`` of an exception (only its text without ``kind``), even when its
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
    if not kind:
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


# The most bytes one answer may take on the worker's pipe, whatever the scene (1 GiB: a
# coverage of 20 million spans), and the least any scene is allowed (the header's texts and
# a small scene's answer with room to spare): :func:`answer_bytes_limit`.
MAX_ANSWER_BYTES = 2**30
MIN_ANSWER_BYTES = 64 * 2**20
_SPAN_BYTES = 8 * 6  # primitive, y, x0, x1, sample, and a share of the header's entries


def answer_bytes_limit(scene: AnyScene) -> int:
    """The most bytes the worker's message answering ``scene`` may take on the pipe: a
    coverage of :func:`span_limit` spans (int64 fields and sample ids), one float64 alpha
    and the scene's attributes per pixel of spans as wide as the viewport, and the header
    (:data:`harness.engine.wire.MAX_HEADER_BYTES`: the texts of an error); at least
    :data:`MIN_ANSWER_BYTES`, at most :data:`MAX_ANSWER_BYTES`. The parent refuses a frame
    announcing more before reading it: a plugin writing a frame header of its own on the
    pipe cannot make the parent allocate gigabytes.

    >>> from harness.contract.scenes import Scene
    >>> answer_bytes_limit(Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]])) == MIN_ANSWER_BYTES
    True
    """
    spans = span_limit(scene)
    per_pixel = 8 * (1 + scene.n_attributes)
    derived = MAX_HEADER_BYTES + 64 + spans * (_SPAN_BYTES + per_pixel * max(1, int(scene.width)))
    return int(min(MAX_ANSWER_BYTES, max(MIN_ANSWER_BYTES, derived)))


def _listed(items: list[str], most: int = 4) -> str:
    """The first ``most`` of ``items``, comma-separated, and how many more."""
    shown = ", ".join(items[:most])
    return shown + (f" and {len(items) - most} more" if len(items) > most else "")


class CallTally:
    """A :data:`Call` that passes each call on and keeps count: how many calls were made,
    which gave no answer (timed out after the second ask, or failed: raised, crashed) and
    which were answered only when asked again. Each is named by its number (1 for the
    first call) and its scene's size.

    >>> from harness.contract.scenes import Scene
    >>> tally = CallTally(lambda scene: Outcome(None, TimeoutError("no answer within 2 s"), timed_out=True))
    >>> _ = tally(Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]]))
    >>> tally.text
    '1 of 1 probe calls timed out (each asked twice): #1 (1 triangle on 8 x 8 px: no answer within 2 s)'
    """

    def __init__(self, call: Callable[[Any], Outcome]) -> None:
        self.call = call
        self.calls = 0
        self.timed_out: list[tuple[int, str, str]] = []  # (number, scene, error)
        self.failed: list[tuple[int, str, str]] = []
        self.retried: list[tuple[int, str, str]] = []

    def __call__(self, scene: AnyScene) -> Outcome:
        self.calls += 1
        outcome = self.call(scene)
        n = len(scene)
        what = f"{n:,} {scene.noun}{'' if n == 1 else 's'} on {scene.width} x {scene.height} px"
        if outcome.coverage is None:
            error = describe(outcome.error, kind=not outcome.timed_out)
            (self.timed_out if outcome.timed_out else self.failed).append((self.calls, what, error))
        elif outcome.retried is not None:
            self.retried.append((self.calls, what, outcome.retry_text))
        return outcome

    def to_dict(self) -> dict[str, Any]:
        """Plain data: the count and each call that timed out, failed or was asked again."""
        def listed(found: list[tuple[int, str, str]]) -> list[dict[str, Any]]:
            return [{"call": k, "scene": what, "error": error} for k, what, error in found]

        return {"calls": self.calls, "timed_out": listed(self.timed_out), "failed": listed(self.failed),
                "retried": listed(self.retried)}

    @property
    def text(self) -> str:
        """The card's line: how many calls timed out or failed, and which."""
        parts = []
        for found, said in ((self.timed_out, "timed out (each asked twice)"), (self.failed, "failed")):
            if found:
                parts.append(f"{len(found)} of {self.calls:,} probe calls {said}: "
                             + _listed([f"#{k} ({what}: {error})"[:160] for k, what, error in found]))
        if self.retried:
            parts.append(f"{len(self.retried)} answered only when asked again: "
                         + _listed([f"#{k} ({what}: {said})" for k, what, said in self.retried]))
        return "; ".join(parts) if parts else f"{self.calls:,} probe calls, every one answered"


def _too_many_spans(spans: int, scene: AnyScene) -> PluginError:
    """The refusal of an answer of ``spans`` spans, more than :func:`span_limit`."""
    return PluginError(f"refused an answer of {spans:,} spans: {len(scene):,} {scene.noun}s on {scene.height:,} "
                       f"rows need at most {span_limit(scene):,}")


def call_in_process(rasterizer: Rasterizer, scene: AnyScene) -> Outcome:
    """One rasterize call, in this process, with any exception captured. An answer of
    more spans than :func:`span_limit` is refused at once, with its size."""
    start = time.perf_counter()
    try:
        coverage = rasterizer.rasterize(scene)  # a path (line) scene only to one that takes paths (lines)
        if not isinstance(coverage, Coverage):
            raise TypeError(f"rasterize returned {type(coverage).__name__}, not a harness.Coverage")
        if len(coverage) > span_limit(scene):
            raise _too_many_spans(len(coverage), scene)
    except BaseException as exc:  # noqa: B036 - a plugin's KeyboardInterrupt or SystemExit is its failure
        try:
            trace = traceback.format_exc()
        except BaseException:  # noqa: B036 - formatting calls the exception's __str__
            trace = ""
        return Outcome(None, exc, trace, time.perf_counter() - start)
    return Outcome(coverage, seconds=time.perf_counter() - start)


def each_until_error(call: Call, scenes: list[Scene]) -> list[Outcome]:
    """``call`` on each scene in turn, up to and including the first that gives no coverage."""
    outcomes: list[Outcome] = []
    for scene in scenes:
        outcomes.append(call(scene))
        if outcomes[-1].coverage is None:
            break
    return outcomes


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
    return {"type": name, "base": base, "text": _plain_text(describe(error, kind=False))}


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
    if not isinstance(present, dict) or set(present) != set(_OPTIONAL_FIELDS) or not all(isinstance(v, bool) for v in present.values()):
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
    if not isinstance(fields, dict) or set(fields) != {"type", "base", "text"} or not all(isinstance(v, str) for v in fields.values()):
        raise WireError("the error is not {type, base, text} of text")
    return rebuilt_error(fields["type"], fields["base"], fields["text"])


def _answer_message(outcome: Outcome) -> tuple[bytes, bool]:  # pragma: no cover - runs in the child
    """The message of ``outcome`` and whether it holds a coverage; an answer that cannot be
    made plain data (a bypassed Coverage's fields, ...) is sent as an error saying why."""
    try:
        return encode_outcome(outcome), outcome.coverage is not None
    except BaseException as exc:  # noqa: B036 - whatever the plugin's objects raise
        error = PluginError(f"the rasterizer's answer cannot be sent back ({_plain_text(describe(exc), 500)})")
        return encode_outcome(Outcome(None, error, "", outcome.seconds)), False


def _exit_with_parent(period: float = 1.0) -> None:  # pragma: no cover - runs in the child
    """Exit this (forked) process once its parent is gone, even in the middle of a call that
    never returns: a killed harness leaves no rasterizer process behind. A daemon thread
    polls the parent's pid (it becomes another's when the parent dies)."""
    import threading

    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(period)
        os._exit(0)

    threading.Thread(target=watch, name="rastercheck-parent-watch", daemon=True).start()


def _serve(rasterizer: Rasterizer, conn: Any) -> None:  # pragma: no cover - runs in the child
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    _exit_with_parent()
    while True:
        try:
            request = conn.recv()
        except (EOFError, OSError):
            return
        # one scene, or a sequence (a motion case's frames): each answer is sent as soon as
        # it is ready, up to the first error
        for scene in request if isinstance(request, list) else [request]:
            message, answered = _answer_message(call_in_process(rasterizer, scene))
            conn.send_bytes(message)
            if not answered:
                break


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
    width, height = float(scene.width), float(scene.height)
    lo, hi, finite = scene.primitive_boxes()
    size = np.array([width, height])
    with np.errstate(invalid="ignore"):
        lo = np.clip(np.floor(np.nan_to_num(lo, nan=0.0)), 0.0, size)
        hi = np.clip(np.ceil(np.nan_to_num(hi, nan=size.max())), 0.0, size)
    box = np.where(finite, np.maximum(hi - lo, 0.0).prod(axis=1), width * height)
    a, b, _ = scene.edges()
    with np.errstate(invalid="ignore"):
        rows = np.abs(np.clip(np.nan_to_num(a[:, 1], nan=0.0), 0.0, height) - np.clip(np.nan_to_num(b[:, 1], nan=height), 0.0, height))
    return float(width * height + 16 * len(box) + samples * box.sum() + np.ceil(rows).sum())


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


_LIVE: weakref.WeakSet[Worker] = weakref.WeakSet()


def kill_all() -> int:
    """Kill every worker process of this process at once (Ctrl-C: nothing is left behind,
    and a call in progress returns at once as an error); how many were alive."""
    killed = 0
    for worker in list(_LIVE):
        if worker._process.is_alive():
            worker._process.kill()
            killed += 1
    return killed


class Worker:
    """A rasterizer in a forked process of its own, each call within the time limit of
    :class:`TimeLimit`.

    Parameters
    ----------
    rasterizer : Rasterizer
    timeout : float or TimeLimit
        The time-limit policy; a number is the cap of the default one.
    deadline : float or None
        A ``time.monotonic()`` no call runs past (then the call is cut off there, and not
        asked again): a bound on a whole job (identify's).

    The samples per pixel that scale a call's limit are its convention's (declared), or
    the most its answers showed so far (an undeclared rasterizer being identified).
    """

    def __init__(self, rasterizer: Rasterizer, timeout: float | TimeLimit = 60.0, *, deadline: float | None = None) -> None:
        self.rasterizer = rasterizer
        self.limits = TimeLimit.of(timeout)
        self.deadline = deadline
        self._samples = samples_of(getattr(rasterizer, "convention", None))
        self._kinds: set[str] = set()  # scene kinds it has answered (their first call may compile)
        self._context = multiprocessing.get_context("fork")
        self._start()
        _LIVE.add(self)

    @property
    def timeout(self) -> float:
        """The cap of one call, in seconds."""
        return self.limits.cap

    def _start(self) -> None:
        self._conn, child = self._context.Pipe()
        self._process = self._context.Process(target=_serve, args=(self.rasterizer, child), daemon=True)
        self._process.start()
        child.close()

    def limit(self, scene: AnyScene) -> tuple[float, str]:
        """The time limit of a first ask on ``scene``, and how it was set."""
        if scene.kind not in self._kinds:
            limit = self.limits.first_limit()
            return limit, f"{limit:.3g} s (the first call on {scene.kind}, which may compile)"
        limit = self.limits.limit(scene, self._samples)
        if limit >= self.limits.cap:
            return limit, f"{limit:.3g} s"
        return limit, (f"{limit:.3g} s for {len(scene):,} {scene.noun}s on {scene.width} x {scene.height} px"
                       + (f" at {self._samples} samples per pixel" if self._samples > 1 else "")
                       + f", at most {self.limits.cap:g} s")

    def rasterize(self, scene: AnyScene) -> Outcome:
        """One call in the worker; one cut off by its limit is asked again once, with a
        longer limit (:meth:`TimeLimit.retry_limit`), before it is a timeout."""
        limit, said = self.limit(scene)
        outcome = self._ask(scene, limit, said)
        return self._again(scene, limit, outcome)

    def _ask(self, scene: AnyScene, limit: float, said: str) -> Outcome:
        try:
            self._conn.send(scene)
        except (EOFError, BrokenPipeError, ConnectionResetError, OSError):
            return self._died(time.perf_counter())
        return self._answer(scene, limit, said)

    def _again(self, scene: AnyScene, limit: float, outcome: Outcome) -> Outcome:
        """``outcome`` of a first ask of ``limit`` seconds, or, when the limit cut it off
        (and not the deadline), the second ask's."""
        if not outcome.timed_out or self._past_deadline():
            return outcome
        longer = self.limits.retry_limit(limit)
        again = self._ask(scene, longer, f"{limit:.3g} s, nor within {longer:.3g} s when asked again")
        return replace(again, retried=limit)

    def _past_deadline(self) -> bool:
        return self.deadline is not None and time.monotonic() >= self.deadline

    def rasterize_all(self, scenes: list[Scene]) -> list[Outcome]:
        """One call per scene, in order, up to and including the first that gives no
        coverage. The scenes go to the worker at once and it answers each as soon as it
        is drawn, so the worker draws the next while this process reads the last; each
        call keeps its own time limit (and is asked again alone when cut off, the rest then
        sent anew). The first call of a scene kind goes alone."""
        outcomes: list[Outcome] = []
        while len(outcomes) < len(scenes) and scenes[len(outcomes)].kind not in self._kinds:
            outcomes.append(self.rasterize(scenes[len(outcomes)]))
            if outcomes[-1].coverage is None:
                return outcomes
        rest = scenes[len(outcomes):]
        if not rest:
            return outcomes
        try:
            self._conn.send(list(rest))
        except (EOFError, BrokenPipeError, ConnectionResetError, OSError):
            return [*outcomes, self._died(time.perf_counter())]
        for k, scene in enumerate(rest):
            limit, said = self.limit(scene)
            outcome = self._answer(scene, limit, said)
            if outcome.timed_out:  # the worker was replaced: this one asked again, the rest sent anew
                outcome = self._again(scene, limit, outcome)
                outcomes.append(outcome)
                if outcome.coverage is None:
                    return outcomes
                return outcomes + self.rasterize_all(list(rest[k + 1:]))
            outcomes.append(outcome)
            if outcome.coverage is None:
                break
        return outcomes

    def _died(self, start: float) -> Outcome:
        self._process.join(1)
        code = self._process.exitcode
        self.close()
        self._start()
        return Outcome(None, RuntimeError(f"the rasterizer's worker process died (exit code {code})"), "",
                       time.perf_counter() - start)

    def _refused_frame(self, scene: AnyScene, most: int, start: float) -> Outcome:
        """The outcome of a frame announcing more than ``most`` bytes (refused unread): the
        worker, whose pipe is out of step, is replaced."""
        self.close()
        self._start()
        n = len(scene)
        return Outcome(None, PluginError(f"refused an answer of more than {most:,} bytes on the worker's pipe, the most "
                                         f"one on {n:,} {scene.noun}{'' if n == 1 else 's'} on {scene.width} x {scene.height} px "
                                         f"may take"), "", time.perf_counter() - start)

    def _answer(self, scene: AnyScene, limit: float, said: str) -> Outcome:
        """The worker's answer on ``scene`` (already sent), within ``limit`` seconds (and
        the deadline); ``said`` is how the limit reads in a timeout's message."""
        if self.deadline is not None and self.deadline - time.monotonic() < limit:
            limit = max(0.0, self.deadline - time.monotonic())
            said = f"{limit:.3g} s (the time left)"
        start = time.perf_counter()
        try:
            if self._conn.poll(limit):
                most = answer_bytes_limit(scene)
                try:
                    message = self._conn.recv_bytes(most)
                except OSError:
                    if not self._conn.closed and self._conn.readable:  # a reset pipe: the worker died
                        raise
                    # multiprocessing marks a connection unreadable (or closes it) on a frame over `most`
                    return self._refused_frame(scene, most, start)
                try:
                    sent = decode_outcome(message)
                    # a worker sends a call's answer alone: timeouts, retries and flaws are this process's to say
                    outcome = Outcome(sent.coverage, sent.error, sent.traceback, sent.seconds)
                    if outcome.coverage is not None and len(outcome.coverage) > span_limit(scene):
                        raise _too_many_spans(len(outcome.coverage), scene)  # (the worker refuses these: a tampered one)
                except (WireError, PluginError) as exc:  # the answer arrived whole but is not what a worker sends
                    return Outcome(None, PluginError(f"the rasterizer's answer cannot be read back ({describe(exc)})"),
                                   "", time.perf_counter() - start)
                if outcome.coverage is not None:
                    self._kinds.add(scene.kind)
                    self._samples = max(self._samples, samples_seen(outcome.coverage))
                return _tidied(outcome, scene)
        except (EOFError, BrokenPipeError, ConnectionResetError, OSError):
            return self._died(start)
        self.close()
        self._start()
        return Outcome(None, TimeoutError(f"no answer within {said}"), "", limit, timed_out=True)

    def __call__(self, scene: AnyScene) -> Outcome:
        return self.rasterize(scene)

    def close(self) -> None:
        if self._process.is_alive():
            self._process.kill()
        self._process.join(5)
        self._conn.close()

    def __enter__(self) -> Worker:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class InProcess:
    """The rasterizer called in this process (no isolation, no time limit), for debugging;
    the same interface as :class:`Worker`."""

    def __init__(self, rasterizer: Rasterizer) -> None:
        self.rasterizer = rasterizer

    def rasterize(self, scene: AnyScene) -> Outcome:
        return _tidied(call_in_process(self.rasterizer, scene), scene)

    def rasterize_all(self, scenes: list[Scene]) -> list[Outcome]:
        """One call per scene, in order, up to and including the first that gives no coverage."""
        return each_until_error(self.rasterize, scenes)

    def __call__(self, scene: AnyScene) -> Outcome:
        return self.rasterize(scene)

    def close(self) -> None:
        pass

    def __enter__(self) -> InProcess:
        return self

    def __exit__(self, *exc: object) -> None:
        pass
