"""Atomic file writes: a reader sees the old file or the new one, never half of one."""

from __future__ import annotations

import hashlib
import os
import re
import stat
import tempfile
from pathlib import Path

__all__ = ["atomic_write_text", "atomic_write_bytes", "safe_name", "prepare_folder", "prepare_file", "sweep_partial",
           "read_input", "MAX_INPUT_MB"]


def safe_name(text: str) -> str:
    """A name (a rasterizer's, a case's) made safe to be one path component: letters,
    digits, ``_ . -`` kept, anything else (``/``, NUL, spaces) replaced by ``_``, a leading
    dot escaped, so that no name can climb out of its folder or hide; a name this changed
    (or cut to 100 characters) ends with a short hash of itself, so that two names never
    share a file (``a/b`` and ``a b`` would both be ``a_b``).

    >>> safe_name("../../../escaped"), safe_name("lattice/bits-0"), safe_name("centre_scanline")
    ('_.._.._.._escaped-e9d20ae4', 'lattice_bits-0-fa1f4ff3', 'centre_scanline')
    >>> safe_name("a/b") != safe_name("a b"), safe_name("")
    (True, '_-e3b0c442')
    """
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", text)
    if not name or name.startswith("."):
        name = "_" + name
    if name != text or len(name) > 100:
        digest = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()[:8]
        name = f"{name[:100]}-{digest}"
    return name


MAX_INPUT_MB = 256
"""The largest input file read (a case, repro, baseline, campaign state, skip list), in
MiB; ``RASTERCHECK_MAX_INPUT_MB`` raises it."""


def read_input(path: Path | str, what: str) -> bytes:
    """The bytes of the input file ``path`` (``what`` it is, for messages).

    ValueError in one line, before reading, for what is not a regular file (a FIFO would
    wait for a writer forever, ``/dev/zero`` never ends) or is larger than
    :data:`MAX_INPUT_MB` (or ``RASTERCHECK_MAX_INPUT_MB``); OSError as ``open`` raises it
    (no such file, a folder, no permission), for the caller to word.
    """
    path = Path(path)
    limit = _input_limit()
    info = os.stat(path)
    if stat.S_ISDIR(info.st_mode):
        raise IsADirectoryError(21, "a folder, not a file", str(path))
    if not stat.S_ISREG(info.st_mode):
        kind = "a FIFO" if stat.S_ISFIFO(info.st_mode) else "a device" if stat.S_ISCHR(info.st_mode) or \
            stat.S_ISBLK(info.st_mode) else "a socket" if stat.S_ISSOCK(info.st_mode) else "not a regular file"
        raise ValueError(f"{path}: {what} is {kind}, not a regular file: refused (it could block or never end)")
    if info.st_size > limit * 2**20:
        raise ValueError(f"{path}: {what} holds {info.st_size / 2**20:.0f} MiB, more than the {limit} MiB an input "
                         "may hold (RASTERCHECK_MAX_INPUT_MB raises the limit)")
    with open(path, "rb") as handle:
        data = handle.read(limit * 2**20 + 1)  # (a file that grew since: cut at the limit)
    if len(data) > limit * 2**20:
        raise ValueError(f"{path}: {what} grew past the {limit} MiB an input may hold while it was read")
    return data


def _input_limit() -> int:
    raw = os.environ.get("RASTERCHECK_MAX_INPUT_MB", "")
    try:
        return max(int(raw), 1) if raw else MAX_INPUT_MB
    except ValueError:
        raise ValueError(f"RASTERCHECK_MAX_INPUT_MB={raw!r} is not a whole number of MiB") from None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def sweep_partial(folder: Path | str) -> int:
    """Remove the temporary files that killed writes left in ``folder`` (those of
    :func:`atomic_write_text` whose writing process no longer exists); how many."""
    removed = 0
    for stale in Path(folder).glob(".*.partial"):
        parts = stale.name.rsplit(".", 3)  # .<name>.<pid>.<random>.partial
        if len(parts) == 4 and parts[1].isdigit() and not _alive(int(parts[1])):
            stale.unlink(missing_ok=True)
            removed += 1
    return removed


def prepare_folder(path: Path | str, what: str) -> Path:
    """The folder ``path``, created if need be and proven writable; ValueError in one line
    naming ``what`` it is for when it is a file, cannot be created or is not writable."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{what} {path} is a file, not a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = tempfile.NamedTemporaryFile(dir=path, prefix=".rastercheck-probe.", delete=True)
        probe.close()
    except OSError as exc:
        raise ValueError(f"{what} {path} cannot be written ({exc.strerror or exc})") from None
    sweep_partial(path)
    return path


def prepare_file(path: Path | str, what: str) -> Path:
    """A file path that can be written: not a folder, its folder created and writable;
    ValueError in one line naming ``what`` it is for otherwise."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{what} {path} is a folder, not a file")
    if path.exists() and not os.access(path, os.W_OK):
        raise ValueError(f"{what} {path} cannot be written (permission denied)")
    prepare_folder(path.parent if str(path.parent) else Path("."), f"the folder of {what}")
    return path


def atomic_write_text(path: Path | str, text: str, *, durable: bool = False) -> None:
    """Write ``text`` to a temporary file beside ``path``, then rename it into place (a
    write killed half-way leaves a ``.<name>.<pid>.*.partial`` file that the next
    :func:`sweep_partial` of the folder removes). ``durable``: the file and the rename are
    synced to the disk before returning (a state that a power cut must not empty)."""
    atomic_write_bytes(path, text.encode("utf-8"), durable=durable)


def atomic_write_bytes(path: Path | str, data: bytes, *, durable: bool = False) -> None:
    """:func:`atomic_write_text` for bytes."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=".partial", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            if durable:
                handle.flush()
                os.fsync(handle.fileno())
        os.chmod(tmp, 0o644)  # mkstemp makes 0600; reports are meant to be read
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    if durable:
        sync_folder(path.parent)


def sync_folder(folder: Path | str) -> None:
    """Make a rename or a new file in ``folder`` durable (where the platform allows)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
