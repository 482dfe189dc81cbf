"""Atomic file writes: a reader sees the old file or the new one, never half of one."""

from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

__all__ = ["atomic_write_text", "safe_name"]


def safe_name(text: str) -> str:
    """A name (a rasterizer's, a case's) made safe to be one path component: letters,
    digits, ``_ . -`` kept, anything else (``/``, NUL, spaces) replaced by ``_``, and a
    leading dot escaped, so that no name can climb out of its folder or hide.

    >>> safe_name("../../../escaped"), safe_name("lattice/bits-0"), safe_name("")
    ('_.._.._.._escaped', 'lattice_bits-0', '_')
    """
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", text)
    return "_" + name if not name or name.startswith(".") else name


def atomic_write_text(path: Path | str, text: str) -> None:
    """Write ``text`` to a temporary file beside ``path``, then rename it into place."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        os.chmod(tmp, 0o644)  # mkstemp makes 0600; reports are meant to be read
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
