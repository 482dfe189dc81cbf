"""Isolation: every call of a rasterizer in a forked worker process, with a time limit.

The one place where rastercheck calls a plugin. An exception (any ``BaseException``,
``KeyboardInterrupt`` and ``SystemExit`` raised by the plugin included) becomes an
:class:`Outcome` carrying its type, text and traceback; an exception that cannot cross
the process boundary, or whose ``__str__`` itself raises, is carried as text. A call
that outlives its time limit, or a worker that dies (a segfault, ``os._exit``), becomes
an outcome too; the worker is then replaced and the caller goes on.

The time limit adapts: after a few calls, a call that takes far longer than the
rasterizer's own typical call for a scene of its size (``patience`` times the median
rate, never below ``floor`` seconds, never above the absolute ``timeout``) counts as
hung, so that a rasterizer that hangs is known in seconds rather than minutes.
"""

from __future__ import annotations

import bisect
import multiprocessing
import os
import pickle
import time
import traceback
import weakref
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

from harness.api import AnyScene, Coverage, PathScene, Rasterizer, Scene

__all__ = ["Outcome", "layer_of", "Worker", "InProcess", "call_in_process", "each_until_error", "describe", "span_limit", "Call", "AnyCall", "PluginError",
           "kill_all"]


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
    return Outcome(usable, seconds=outcome.seconds, received=outcome.coverage, flaws=flaws)


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
    """An exception of the plugin's that could not be carried as itself (it cannot be
    pickled or unpickled, or its text cannot be shown): its type name and text."""


def _portable(outcome: Outcome) -> Outcome:
    """The outcome with its exception replaced by a PluginError carrying its text when it
    would not survive the trip to the parent process."""
    error = outcome.error
    if error is None:
        return outcome
    try:
        str(error)
        pickle.loads(pickle.dumps(error))
    except BaseException:  # noqa: B036
        error = PluginError(describe(error))
    return Outcome(None, error, outcome.traceback, outcome.seconds)


def _pieces(scene: AnyScene) -> int:
    """Triangles, or for paths their vertices: a path needs at most one span per row for
    every two of its edges."""
    return int(scene.vertices.shape[0]) if isinstance(scene, PathScene) else len(scene)


def span_limit(scene: AnyScene) -> int:
    """The most spans an answer may hold: a triangle is convex, so it needs at most one
    span per row, a path one per row for every two edges (16 allowed, for one per sample of
    a 16x multisample pattern)."""
    return 16 * (_pieces(scene) + 1) * scene.height + 1024


def call_in_process(rasterizer: Rasterizer, scene: AnyScene) -> Outcome:
    """One rasterize call, in this process, with any exception captured. An answer of
    more spans than :func:`span_limit` is refused at once, with its size."""
    start = time.perf_counter()
    try:
        coverage = rasterizer.rasterize(scene)  # type: ignore[arg-type]  # a path scene only to one that takes paths
        if not isinstance(coverage, Coverage):
            raise TypeError(f"rasterize returned {type(coverage).__name__}, not a harness.Coverage")
        if len(coverage) > span_limit(scene):
            raise PluginError(f"refused an answer of {len(coverage):,} spans: {len(scene):,} {scene.noun}s on {scene.height:,} "
                              f"rows need at most {16 * (_pieces(scene) + 1) * scene.height + 1024:,}")
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
            outcome = _portable(call_in_process(rasterizer, scene))
            try:
                conn.send(outcome)
            except Exception:  # a coverage that cannot be pickled
                outcome = Outcome(None, PluginError("the rasterizer's answer cannot be sent back (it cannot be pickled)"),
                                  "", outcome.seconds)
                conn.send(outcome)
            if outcome.coverage is None:
                break


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
    """A rasterizer in a forked process of its own, called with a time limit.

    Parameters
    ----------
    rasterizer : Rasterizer
    timeout : float
        The absolute limit of one call, in seconds.
    patience : float or None
        After ``warmup`` answered calls, a call may take at most ``patience`` times the
        median seconds per unit of work (triangles, plus screen pixels / 256) times its
        scene's work, but never less than ``floor`` seconds; None keeps the absolute
        limit only.
    """

    def __init__(self, rasterizer: Rasterizer, timeout: float = 60.0, *, patience: float | None = 20.0,
                 floor: float = 2.0, warmup: int = 5) -> None:
        self.rasterizer = rasterizer
        self.timeout, self.patience, self.floor, self.warmup = timeout, patience, floor, warmup
        self._rates: list[float] = []
        self._context = multiprocessing.get_context("fork")
        self._start()
        _LIVE.add(self)

    def _start(self) -> None:
        self._conn, child = self._context.Pipe()
        self._process = self._context.Process(target=_serve, args=(self.rasterizer, child), daemon=True)
        self._process.start()
        child.close()

    @staticmethod
    def _work(scene: AnyScene) -> float:
        return _pieces(scene) + scene.width * scene.height / 256 + 1

    def limit(self, scene: AnyScene) -> tuple[float, str]:
        """The time limit of a call on ``scene``, and how it was set."""
        if self.patience is None or len(self._rates) < self.warmup:
            return self.timeout, f"{self.timeout:g} s"
        rates, n = self._rates, len(self._rates)
        expected = (rates[(n - 1) // 2] + rates[n // 2]) / 2 * self._work(scene)  # the median
        adaptive = max(self.floor, self.patience * expected)
        if adaptive >= self.timeout:
            return self.timeout, f"{self.timeout:g} s"
        return adaptive, (f"{adaptive:.3g} s, {self.patience:g} times its typical call on a scene this size "
                          f"(the absolute limit is {self.timeout:g} s)")

    def rasterize(self, scene: AnyScene, timeout: float | None = None) -> Outcome:
        """One call in the worker; ``timeout`` overrides the limit (absolute, not adaptive)."""
        try:
            self._conn.send(scene)
        except (EOFError, BrokenPipeError, ConnectionResetError, OSError):
            return self._died(time.perf_counter())
        return self._answer(scene, timeout)

    def rasterize_all(self, scenes: list[Scene]) -> list[Outcome]:
        """One call per scene, in order, up to and including the first that gives no
        coverage. The scenes go to the worker at once and it answers each as soon as it
        is drawn, so the worker draws the next while this process reads the last; each
        call keeps its own time limit. Until the limit has adapted, calls go one by one."""
        outcomes: list[Outcome] = []
        while len(outcomes) < len(scenes) and len(self._rates) < self.warmup:
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
        for scene in rest:
            outcomes.append(self._answer(scene, None))
            if outcomes[-1].coverage is None:
                break
        return outcomes

    def _died(self, start: float) -> Outcome:
        self._process.join(1)
        code = self._process.exitcode
        self.close()
        self._start()
        return Outcome(None, RuntimeError(f"the rasterizer's worker process died (exit code {code})"), "",
                       time.perf_counter() - start)

    def _answer(self, scene: AnyScene, timeout: float | None) -> Outcome:
        """The worker's answer on ``scene`` (already sent), within its time limit."""
        limit, said = (timeout, f"{timeout:g} s") if timeout is not None else self.limit(scene)
        start = time.perf_counter()
        try:
            if self._conn.poll(limit):
                try:
                    outcome: Outcome = self._conn.recv()
                except (EOFError, OSError):
                    raise
                except Exception as exc:  # the answer arrived whole but cannot be unpickled
                    return Outcome(None, PluginError(f"the rasterizer's answer cannot be read back ({describe(exc)})"),
                                   "", time.perf_counter() - start)
                if outcome.coverage is not None:
                    bisect.insort(self._rates, outcome.seconds / self._work(scene))  # kept sorted
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

    def rasterize(self, scene: AnyScene, timeout: float | None = None) -> Outcome:
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
