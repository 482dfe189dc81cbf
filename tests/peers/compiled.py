"""Build a peer's original C or C++ source into a shared library and load it with ctypes.

The tests that check a port against its original call :func:`load`; with no compiler on
the machine they skip, naming the install. Builds are cached by the hash of the sources
and flags (headers, ``*.h`` and ``*.hpp``, beside them included) in the temporary directory
and written atomically, so that pytest-xdist workers building the same library at once each
get a whole file.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import tempfile
from collections.abc import Sequence
from pathlib import Path

import pytest

__all__ = ["SOURCES", "NO_COMPILER", "compiler", "load"]

SOURCES = Path(__file__).parent / "src"
"""The peers' original sources, one folder per peer, each with its licence."""

NO_COMPILER = "no C/C++ compiler: install one (apt-get install gcc g++) to check the ports against their originals"


def compiler(language: str) -> str | None:
    """The compiler for ``language`` (``c`` or ``c++``) on the ``PATH``, or None."""
    names = ("cc", "gcc", "clang") if language == "c" else ("c++", "g++", "clang++")
    return next((found for name in names if (found := shutil.which(name))), None)


def load(name: str, sources: Sequence[Path], language: str = "c", flags: Sequence[str] = ()) -> ctypes.CDLL:
    """The shared library built from ``sources`` (compiled once per content), loaded.

    Parameters
    ----------
    name : str
        The peer's name, for the file and messages.
    sources : sequence of Path
        The source files to compile and link (headers they include live beside them).
    language : {"c", "c++"}
    flags : sequence of str
        Extra compiler flags (defines, ``-O2`` is always given).

    Skips the calling test when no compiler is found; raises RuntimeError with the
    compiler's output when the build fails.
    """
    cc = compiler(language)
    if cc is None:
        pytest.skip(NO_COMPILER)
    digest = hashlib.sha256()
    parts: list[str | bytes] = [language, *flags, *(Path(s).read_bytes() for s in sources)]
    for part in parts:
        digest.update(part if isinstance(part, bytes) else part.encode())
    for header in sorted({h for s in sources for pattern in ("*.h", "*.hpp") for h in Path(s).parent.glob(pattern)}):
        digest.update(header.read_bytes())
    folder = Path(tempfile.gettempdir()) / "rastercheck-peers"
    folder.mkdir(exist_ok=True)
    library = folder / f"{name}-{digest.hexdigest()[:16]}.so"
    if not library.exists():
        partial = folder / f".{library.name}.{os.getpid()}"
        command = [cc, "-O2", "-shared", "-fPIC", *flags, "-o", str(partial), *map(str, sources), "-lm"]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"building {name} failed ({' '.join(command)}):\n{done.stderr}")
        os.replace(partial, library)
    return ctypes.CDLL(str(library))
