"""Tests that need an optional library skip, naming it and its install.

``need("cairo")`` returns the module, or skips the test with
:func:`harness.engine.optional.missing`'s sentence (what is missing, the command that installs it,
and why ``make``'s install failed here if it did) — never a bare "could not import".
"""

from __future__ import annotations

from typing import Any

import pytest

from harness.engine.optional import missing


def need(module: str) -> Any:
    """The module, imported; otherwise the test is skipped, naming its install."""
    why = missing(module)
    if why is not None:
        pytest.skip(why)
    return __import__(module)


def chromium() -> str | None:
    """The headless browser the report tests drive: ``RASTERCHECK_CHROMIUM`` when it is set
    (empty: none, as on a bare machine; CI's bare-machine stage sets it so, since a
    machine CI already ran on may have the browser), else Chromium on the ``PATH``."""
    import os
    import shutil

    chosen = os.environ.get("RASTERCHECK_CHROMIUM")
    if chosen is not None:
        return chosen or None
    return shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


NO_CHROMIUM = "no Chromium: install Debian's chromium (apt-get install chromium) to run the browser tests"
