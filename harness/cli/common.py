"""What every ``rastercheck`` command shares: the usage error (exit 2, one line, no traceback),
the rasterizers loaded from their specs (:func:`_load_all`, which remembers for the report what
it loaded and skipped) and whether the terminal is quiet.
"""

from __future__ import annotations

import os
import sys
from typing import Any


class UsageError(Exception):
    """A usage or configuration problem: exit 2 with one line, no traceback."""


# what the last _load_all loaded (the spec of each rasterizer, in load order) and skipped
# (spec -> why), for the report: its replay commands quote the spec, its index lists the skipped
_loaded_specs: list[str] = []
_skipped: dict[str, str] = {}


def _load_all(specs: list[str] | None, timeout: float = 120.0, tolerant: bool = False) -> tuple[list[Any], list[str]]:
    """The rasterizers of ``specs`` (default every registered one), each given ``timeout``
    seconds to import and build, and the problems of those that could not be loaded. A
    spec the user named that is broken is a usage error, unless ``tolerant`` (the atlas,
    which names every adapter itself)."""
    from harness.engine.registry import Unavailable, available, load

    names = specs or available()
    loaded, problems = [], []
    _loaded_specs.clear()
    _skipped.clear()
    for spec in names:
        try:
            loaded.append(load(spec, import_timeout=timeout))
            _loaded_specs.append(spec)
        except Unavailable as exc:  # a missing library: skipped with its install hint, never fatal
            print(f"skipped {spec}: {exc}", file=sys.stderr)
            _skipped[spec] = str(exc)
        except ValueError as exc:
            if specs and not tolerant:  # the user named it: a configuration error
                raise UsageError(str(exc)) from None
            problems.append(str(exc))  # a broken plugin is reported and skipped
            _skipped[spec] = f"broken plugin: {exc}"
    return loaded, problems


def _quiet() -> bool:
    return bool(os.environ.get("CI")) or not sys.stderr.isatty()
