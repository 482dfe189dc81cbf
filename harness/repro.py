"""Minimal repros: shrink a failing case, save it as replayable JSON, replay it.

Shrinking is delta debugging over the triangles (Zeller's ddmin), then coarsening every
coordinate to the simplest dyadic lattice on which the check still fails. Coordinates are
stored with ``float.hex`` so that a replay sees exactly the same floats.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from cases.records import Case
from harness.api import Rasterizer, Scene
from harness.checks import Result
from harness.files import atomic_write_text

__all__ = ["ddmin", "shrink", "case_to_json", "case_from_json", "save_case", "load_case", "replay", "SCHEMA"]

SCHEMA = 1


def ddmin(items: list[int], fails: Callable[[list[int]], bool], budget: int) -> list[int]:
    """Zeller's ddmin: a 1-minimal sublist of ``items`` on which ``fails`` still holds,
    within ``budget`` calls of ``fails`` (the best found so far when it runs out).

    >>> ddmin(list(range(10)), lambda s: 3 in s and 7 in s, 100)
    [3, 7]
    """
    n = 2
    calls = 0
    while len(items) >= 2 and calls < budget:
        size = -(-len(items) // n)
        chunks = [items[i : i + size] for i in range(0, len(items), size)]
        reduced = False
        for chunk in chunks:
            calls += 1
            if calls > budget:
                break
            if fails(chunk):
                items, n, reduced = chunk, 2, True
                break
        if not reduced and n > 2 and calls < budget:
            for chunk in chunks:
                rest = [i for i in items if i not in set(chunk)]
                calls += 1
                if calls > budget:
                    break
                if fails(rest):
                    items, n, reduced = rest, max(n - 1, 2), True
                    break
        if not reduced:
            if n >= len(items):
                break
            n = min(2 * n, len(items))
    return items


def _subcase(case: Case, keep: list[int], positions: NDArray | None = None, lattice: bool | None = None) -> Case:
    scene = case.scene
    index = np.array(keep, dtype=np.int64)
    pos = (scene.positions if positions is None else positions)[index]
    attributes = None if scene.attributes is None else scene.attributes[index]
    w = None if scene.w is None else scene.w[index]
    remap = {int(t): k for k, t in enumerate(index)}
    return Case(
        f"{case.id}/repro",
        Scene(scene.width, scene.height, pos, attributes, w),
        lattice=case.lattice if lattice is None else lattice,
        refusable=tuple(remap[t] for t in case.refusable if t in remap),
    )


def shrink(case: Case, fails: Callable[[Case], bool], budget: int = 200, seconds: float = 20.0) -> Case:
    """The smallest and simplest case on which ``fails`` still holds.

    First ddmin over triangles, then coarsening all coordinates to multiples of 2**-b for
    the smallest b (0..24) that still fails. ``budget`` bounds the calls of ``fails`` and
    ``seconds`` the time; the best case found so far is returned when either runs out.
    """
    deadline = time.monotonic() + seconds
    calls = 0

    def guarded(candidate: Case) -> bool:
        nonlocal calls
        if calls >= budget or time.monotonic() > deadline:
            return False
        calls += 1
        return fails(candidate)

    keep = ddmin(list(range(len(case.scene))), lambda sub: guarded(_subcase(case, sub)), budget)
    best = _subcase(case, keep)
    with np.errstate(all="ignore"):
        for bits in range(0, 25):
            p = best.scene.positions
            coarse = np.where(np.isfinite(p) & (np.abs(p) < 2.0**40), np.round(p * 2.0**bits) / 2.0**bits, p)
            if np.array_equal(coarse, p, equal_nan=True):
                break
            candidate = _subcase(best, list(range(len(best.scene))), coarse, lattice=best.lattice or bits <= 8)
            if guarded(candidate):
                best = Case(best.id, candidate.scene, lattice=candidate.lattice, refusable=best.refusable)
                break
    return best


def _hex(array: NDArray | None) -> Any:
    return None if array is None else np.vectorize(float.hex, otypes=[object])(array).tolist()


def _unhex(data: Any) -> NDArray | None:
    return None if data is None else np.vectorize(float.fromhex, otypes=[float])(np.array(data, dtype=object))


def case_to_json(case: Case, **extra: Any) -> dict[str, Any]:
    """A JSON-ready dict with every float as ``float.hex``."""
    scene = case.scene
    return {
        "schema": SCHEMA,
        "id": case.id,
        "width": scene.width,
        "height": scene.height,
        "positions": _hex(scene.positions),
        "attributes": _hex(scene.attributes),
        "w": _hex(scene.w),
        "lattice": case.lattice,
        "region": _hex(case.region),
        "closed": case.closed,
        "refusable": list(case.refusable),
        **extra,
    }


def case_from_json(data: dict[str, Any]) -> Case:
    """The exact case back from :func:`case_to_json`; ValueError naming what is wrong."""
    if not isinstance(data, dict) or data.get("schema") != SCHEMA:
        raise ValueError(f"not a rastercheck case (schema {SCHEMA} expected)")
    try:
        positions = _unhex(data["positions"])
        if positions is None:
            raise ValueError("no positions")
        positions = positions.reshape(-1, 3, 2)
        scene = Scene(int(data["width"]), int(data["height"]), positions, _unhex(data.get("attributes")), _unhex(data.get("w")))
        return Case(
            str(data["id"]), scene, lattice=bool(data.get("lattice", False)), region=_unhex(data.get("region")),
            closed=bool(data.get("closed", False)), refusable=tuple(int(t) for t in data.get("refusable", ())),
        )
    except KeyError as exc:
        raise ValueError(f"case JSON lacks the field {exc.args[0]!r}") from None
    except (TypeError, AttributeError) as exc:
        raise ValueError(f"case JSON is malformed: {exc}") from None


def save_case(path: Path | str, case: Case, **extra: Any) -> Path:
    path = Path(path)
    atomic_write_text(path, json.dumps(case_to_json(case, **extra), indent=1))
    return path


def load_case(path: Path | str) -> Case:
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the case ({exc})") from None
    try:
        return case_from_json(data)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def replay(path: Path | str, rasterizer: Rasterizer | str, isolate: bool = False) -> list[Result]:
    """Run every applicable check of a saved case on a rasterizer."""
    from harness.runner import run_suite

    return run_suite([rasterizer], cases=[load_case(path)], isolate=isolate)
