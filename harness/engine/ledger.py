"""Where a worker's time goes: a :class:`Ledger` of exclusive seconds per section (scene
generation, the isolated rasterizer's calls, the oracle, each check, the signatures), kept
while a campaign's batch runs (:func:`harness.campaign.worker.run_batch`) and summed per
campaign (``rastercheck bench --campaign`` prints it per scene).

A section's time is exclusive: while the oracle runs inside a check, the seconds are the
oracle's, not the check's, so the sections add up to the time measured. Outside a ledger
(:func:`keeping`), :func:`section` costs one global read.

>>> import time
>>> with keeping() as ledger:
...     with section("check:watertight"):
...         with section("oracle"):
...             time.sleep(0.002)
>>> sorted(ledger.seconds), ledger.seconds["oracle"] >= 0.002 > ledger.seconds["check:watertight"]
(['check:watertight', 'oracle'], True)
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import AbstractContextManager, contextmanager, nullcontext

__all__ = ["Ledger", "section", "keeping", "active", "note"]


class Ledger:
    """Exclusive seconds per section name, and notes (seconds measured elsewhere, such as
    the rasterizer's own time in its process, which overlaps the sections)."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}
        self.notes: dict[str, float] = {}
        self._stack: list[tuple[str, list[float]]] = []  # (name, [start of its current stretch])

    @contextmanager
    def section(self, name: str) -> Iterator[None]:
        """Time spent inside, less the time of sections opened inside it, goes to ``name``."""
        now = _clock()
        stack = self._stack
        if stack:
            outer, since = stack[-1]
            self.seconds[outer] = self.seconds.get(outer, 0.0) + now - since[0]
        entry = (name, [now])
        stack.append(entry)
        try:
            yield
        finally:
            now = _clock()
            self.seconds[name] = self.seconds.get(name, 0.0) + now - entry[1][0]
            stack.pop()
            if stack:
                stack[-1][1][0] = now

    def note(self, name: str, seconds: float) -> None:
        """Add ``seconds`` measured elsewhere to the note ``name``."""
        self.notes[name] = self.notes.get(name, 0.0) + seconds

    def to_dict(self) -> dict[str, dict[str, float]]:
        """Plain data: ``{"seconds": {...}, "notes": {...}}``."""
        return {"seconds": dict(self.seconds), "notes": dict(self.notes)}


_ACTIVE: Ledger | None = None
_clock = time.perf_counter  # wall time: a campaign's worker waits on its rasterizer too
_NOTHING: AbstractContextManager[None] = nullcontext()


def active() -> Ledger | None:
    """The ledger being kept in this process, if any."""
    return _ACTIVE


def section(name: str) -> AbstractContextManager[None]:
    """A section of the ledger being kept (:func:`keeping`); nothing when none is."""
    ledger = _ACTIVE
    return _NOTHING if ledger is None else ledger.section(name)


def note(name: str, seconds: float) -> None:
    """A note in the ledger being kept, if any."""
    if _ACTIVE is not None:
        _ACTIVE.note(name, seconds)


@contextmanager
def keeping() -> Iterator[Ledger]:
    """Keep a fresh ledger in this process while inside (the one kept before, if any, is
    kept again after)."""
    global _ACTIVE
    before, _ACTIVE = _ACTIVE, Ledger()
    try:
        yield _ACTIVE
    finally:
        _ACTIVE = before
