"""Hostile plugins whose answers would run code in whatever process unpickles them.

Each hands back an object whose ``__reduce__`` names :func:`detonate`: unpickled in the
harness's process it writes that process's pid to a marker file and, when told to,
ends the process with ``os._exit(0)`` -- a run that ends 0 and loses every other
rasterizer's results. The worker sends answers as plain data (harness.engine.wire), so none of
this may ever run in the parent (tests/engine/test_wire.py).
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.engine.registry import Unavailable
from rasterizers.pineda_topleft import PinedaTopLeft


def detonate(marker: str, home: int, exit_home: bool) -> Any:
    """What unpickling a hostile object calls: appends this process's pid to ``marker``;
    in the process ``home`` (the harness's), with ``exit_home``, ends it at once (exit 0)."""
    with open(marker, "a", encoding="utf-8") as out:
        out.write(f"{os.getpid()}\n")
    if exit_home and os.getpid() == home:
        os._exit(0)
    return ValueError("detonated")


class _Base:
    convention = PinedaTopLeft().convention

    def __init__(self, marker: str, exit_home: bool = False) -> None:
        self.name = type(self).__name__
        self.trap = (marker, os.getpid(), exit_home)  # the pid of the process that built it: the harness's


class _DetonatingArray(np.ndarray):
    """An ndarray whose pickle calls :func:`detonate`."""

    trap: tuple[str, int, bool] = ("", 0, False)

    def __reduce__(self) -> Any:
        return detonate, self.trap


def _detonating(array: np.ndarray, trap: tuple[str, int, bool]) -> _DetonatingArray:
    hostile = np.asarray(array).view(_DetonatingArray)
    hostile.trap = trap
    return hostile


class ArraysDetonate(_Base):
    """The right coverage, its span and attribute arrays swapped (past the constructor,
    which would make them plain) for ndarrays whose pickle detonates."""

    def rasterize(self, scene: Scene) -> Coverage:
        right = PinedaTopLeft().rasterize(scene)
        for field in ("primitive", "y", "x0", "x1", "attributes"):
            value = getattr(right, field)
            if value is not None:
                object.__setattr__(right, field, _detonating(value, self.trap))
        return right


class _DetonatingCoverage(Coverage):
    """A Coverage whose pickle detonates."""

    __slots__ = ("trap",)
    trap: tuple[str, int, bool]

    def __reduce__(self) -> Any:
        return detonate, self.trap


class CoverageDetonates(_Base):
    """The right coverage, as a Coverage subclass whose pickle detonates."""

    def rasterize(self, scene: Scene) -> Coverage:
        right = PinedaTopLeft().rasterize(scene)
        hostile = _DetonatingCoverage(right.primitive, right.y, right.x0, right.x1, right.attributes)
        object.__setattr__(hostile, "trap", self.trap)
        return hostile


class DetonatingError(ValueError):
    """A ValueError whose pickle detonates."""

    def __init__(self, text: str, trap: tuple[str, int, bool]) -> None:
        super().__init__(text)
        self.trap = trap

    def __reduce__(self) -> Any:
        return detonate, self.trap


class RaisesDetonating(_Base):
    """Raises a :class:`DetonatingError` naming triangle 0."""

    def rasterize(self, scene: Scene) -> Coverage:
        raise DetonatingError("triangle 0 is not welcome here", self.trap)


class UnprintableError(Exception):
    """An exception whose ``__str__`` raises a :class:`DetonatingError`, and whose pickle
    detonates too."""

    def __init__(self, trap: tuple[str, int, bool]) -> None:
        super().__init__()
        self.trap = trap

    def __str__(self) -> str:
        raise DetonatingError("no text for you", self.trap)

    def __reduce__(self) -> Any:
        return detonate, self.trap


class RaisesUnprintableDetonating(_Base):
    """Raises an :class:`UnprintableError`."""

    def rasterize(self, scene: Scene) -> Coverage:
        raise UnprintableError(self.trap)


class SendsJunk(_Base):
    """Answers right, having first replaced, in its worker, the harness's encoder with
    one that sends bytes that are no message."""

    def rasterize(self, scene: Scene) -> Coverage:
        import harness.engine.isolation

        harness.engine.isolation.encode_outcome = lambda outcome: b"\x10\0\0\0\0\0\0\0not a header at all"
        return PinedaTopLeft().rasterize(scene)


class ClaimsTimedOut(_Base):
    """Answers right, its worker's encoder patched to say every answer timed out and was
    retried, with flaws: what only the parent may say."""

    def rasterize(self, scene: Scene) -> Coverage:
        import dataclasses

        import harness.engine.isolation

        encode = harness.engine.isolation.__dict__.get("_true_encode", harness.engine.isolation.encode_outcome)
        harness.engine.isolation._true_encode = encode  # type: ignore[attr-defined]
        flaws = {"repeated": np.arange(3)}
        harness.engine.isolation.encode_outcome = lambda outcome: encode(dataclasses.replace(outcome, timed_out=True, retried=1.0,
                                                                                             flaws=flaws))
        return PinedaTopLeft().rasterize(scene)


class _DetonatingText(str):
    """Text whose pickle detonates."""

    trap: tuple[str, int, bool] = ("", 0, False)

    def __reduce__(self) -> Any:
        return detonate, self.trap


class _RefusalWithTrappedText(Unavailable):
    def __str__(self) -> str:
        text = _DetonatingText("the plugin will not load")
        text.trap = (os.environ["HOSTILE_PICKLES_MARKER"], int(os.environ["HOSTILE_PICKLES_HOME"]), False)
        return text


class NamedDetonating(_Base):
    """Raises a ValueError on every scene (a finding a campaign shrinks) and is named by
    text whose pickle detonates: the name rides in what a campaign's worker sends back (the
    shrunk repro's ``rasterizer``)."""

    def __init__(self, marker: str, exit_home: bool = False) -> None:
        super().__init__(marker, exit_home)
        name = _DetonatingText("named_detonating")
        name.trap = self.trap
        self.name = name

    def rasterize(self, scene: Scene) -> Coverage:
        raise ValueError("triangle 0 is not welcome here")


def refuses_to_load() -> Any:
    """A factory (``tests.known_bad.hostile_pickles:refuses_to_load``) that raises an
    Unavailable (passed on as it is, not wrapped) whose text is a str subclass whose pickle
    detonates: what the registry's import probe sends back must be plain text. The marker and the harness's pid come from
    the environment (HOSTILE_PICKLES_MARKER, HOSTILE_PICKLES_HOME)."""
    raise _RefusalWithTrappedText()


HOSTILE_PICKLES = (ArraysDetonate, CoverageDetonates, RaisesDetonating, RaisesUnprintableDetonating)
