"""Isolation: every call of a rasterizer in a forked worker process, with a time limit.

The one place where rastercheck calls a plugin. An exception (any ``BaseException``,
``KeyboardInterrupt`` and ``SystemExit`` raised by the plugin included) becomes an
:class:`~harness.engine.outcomes.Outcome` carrying its type, text and traceback (text even when its ``__str__``
raises). Nothing the plugin made crosses back by pickle: the worker sends each outcome as
plain data (:mod:`harness.engine.outcomes`). A call that outlives its time limit
(:class:`~harness.engine.time_limits.TimeLimit`), or a worker that dies (a segfault, ``os._exit``),
becomes an outcome too; the worker is then replaced and the caller goes on.

The outcome records and the time-limit policy live in :mod:`harness.engine.outcomes` and
:mod:`harness.engine.time_limits`; their names are re-exported here, where callers have
always found them.
"""

from __future__ import annotations

import multiprocessing
import os
import time
import traceback
import weakref
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

from harness.contract.coverage import Coverage
from harness.contract.protocol import Rasterizer
from harness.contract.scenes import AnyScene, Scene, scene_digest
from harness.engine.outcomes import (
    ERROR_BASES,
    AnyCall,
    Call,
    Outcome,
    PluginError,
    _plain_text,
    _tidied,
    decode_outcome,
    describe,
    encode_outcome,
    layer_of,
    span_limit,
)
from harness.engine.time_limits import TimeLimit, samples_of, samples_seen, scene_work
from harness.engine.wire import MAX_HEADER_BYTES, WireError

__all__ = ["Outcome", "layer_of", "Worker", "InProcess", "call_in_process", "each_until_error", "describe", "span_limit", "Call",
           "AnyCall", "PluginError", "kill_all", "TimeLimit", "answer_bytes_limit", "MAX_ANSWER_BYTES", "scene_work",
           "samples_of", "samples_seen", "CallTally", "encode_outcome", "decode_outcome", "ERROR_BASES"]


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
            error = describe(outcome.error, with_type=not outcome.timed_out)
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
        # it is ready, up to the first error; or scenes drawn ahead (("each", scenes):
        # Worker.prefetch), each answered whatever the others gave
        each = isinstance(request, tuple)
        for scene in request[1] if each else request if isinstance(request, list) else [request]:
            message, answered = _answer_message(call_in_process(rasterizer, scene))
            conn.send_bytes(message)
            if not answered and not each:
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
        # scenes sent ahead (:meth:`prefetch`) whose answers are not read yet, in the order
        # the worker answers them, and answers read but not yet asked for (by scene digest)
        self._pending: deque[tuple[bytes, AnyScene]] = deque()
        self._ready: dict[bytes, deque[tuple[Outcome, float]]] = {}
        self._context = multiprocessing.get_context("fork")
        self._start()
        _LIVE.add(self)

    @property
    def timeout(self) -> float:
        """The cap of one call, in seconds."""
        return self.limits.cap

    def _start(self) -> None:
        self._pending = deque()  # a new worker has nothing sent ahead
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

    def prefetch(self, scenes: Sequence[AnyScene]) -> int:
        """Send ``scenes`` to the worker at once, to be drawn while this process works:
        a later :meth:`rasterize` of one of them (a scene with the same digest,
        :func:`harness.contract.scenes.scene_digest`) takes the answer drawn ahead, once per
        time it was sent. Each answer is read within its own time limit, from when it is
        waited for; a call cut off is asked again alone (as any call), and the scenes sent
        ahead with it that were not answered yet are drawn again when asked for. Scenes of
        a kind the worker has not answered yet (whose first call may compile) are not sent
        ahead. Returns how many were sent.

        >>> from rasterizers.centre_scanline import CentreScanline
        >>> from harness.contract.scenes import Scene
        >>> scene = Scene(8, 8, [[[0, 0], [4, 0], [0, 4]]])
        >>> with Worker(CentreScanline()) as worker:
        ...     first = worker.rasterize(scene)  # the kind's first call goes alone
        ...     sent = worker.prefetch([scene, scene.with_viewport(9, 9)])
        ...     ahead = worker.rasterize(scene)
        >>> sent, ahead.coverage.n_pixels == first.coverage.n_pixels
        (2, True)
        """
        ahead = [(scene_digest(scene), scene) for scene in scenes if scene.kind in self._kinds]
        if not ahead:
            return 0
        # answers still on their way are read first: a worker blocked writing them to a full pipe
        # reads nothing, and a large request would wait on it for ever
        self._drain()
        try:
            self._conn.send(("each", [scene for _, scene in ahead]))
        except (EOFError, BrokenPipeError, ConnectionResetError, OSError):
            self._died(time.perf_counter())
            return 0
        self._pending.extend(ahead)
        return len(ahead)

    def forget_prefetched(self) -> None:
        """Read every answer still on its way (the pipe back in step) and drop those not
        asked for."""
        self._drain()
        self._ready.clear()

    def _drain(self) -> None:
        """Read every answer sent ahead, keeping it for when its scene is asked for."""
        while self._pending:
            self._read_ahead()

    def _read_ahead(self) -> None:
        """Read the next answer sent ahead and keep it (with its limit) for when its scene
        is asked for. An answer the worker was replaced on (cut off: asked again alone
        when asked for, as any call; died; refused) is kept too, and then nothing else
        sent ahead is on its way any more: those scenes are drawn anew when asked for."""
        key, scene = self._pending.popleft()
        # an answer already there needs no limit (the limit's policy costs more than the wait)
        limit, said = (self.limits.cap, "") if self._conn.poll(0) else self.limit(scene)
        self._ready.setdefault(key, deque()).append((self._answer(scene, limit, said), limit))

    def _taken(self, scene: AnyScene) -> Outcome | None:
        """The answer drawn ahead for ``scene``, read now if it is still on its way; None
        when none is (the answers ahead of it are kept, and the pipe is in step)."""
        key = scene_digest(scene)
        while key not in self._ready and self._pending:
            if all(k != key for k, _ in self._pending):
                self._drain()  # a call of its own: its answer comes after every one on its way
                return None
            self._read_ahead()
        kept = self._ready.get(key)
        if not kept:
            return None
        outcome, limit = kept.popleft()
        if not kept:
            del self._ready[key]
        return self._again(scene, limit, outcome)

    def rasterize(self, scene: AnyScene) -> Outcome:
        """One call in the worker; one cut off by its limit is asked again once, with a
        longer limit (:meth:`TimeLimit.retry_limit`), before it is a timeout. A scene
        drawn ahead (:meth:`prefetch`) takes that answer."""
        if self._pending or self._ready:
            ahead = self._taken(scene)
            if ahead is not None:
                return ahead
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
        while len(outcomes) < len(scenes) and (self._pending or self._ready):  # those drawn ahead (:meth:`prefetch`)
            ahead = self._taken(scenes[len(outcomes)])
            if ahead is None:
                break
            outcomes.append(ahead)
            if ahead.coverage is None:
                return outcomes
        self._drain()  # the pipe in step: the answers of those sent now come next
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

    def prefetch(self, scenes: Sequence[AnyScene]) -> int:
        """Nothing is drawn ahead in this process: each call draws its scene."""
        return 0

    def forget_prefetched(self) -> None:
        pass

    def __call__(self, scene: AnyScene) -> Outcome:
        return self.rasterize(scene)

    def close(self) -> None:
        pass

    def __enter__(self) -> InProcess:
        return self

    def __exit__(self, *exc: object) -> None:
        pass
