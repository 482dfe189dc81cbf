"""Numba's on-disk kernel cache made safe for processes that compile side by side.

rastercheck's kernels are compiled with ``cache=True``; test workers, ``rastercheck run``
workers and Dask workers load them from that cache, and compile them into it on a fresh
machine -- several processes at once. See :func:`safe_numba_cache` for the race in numba's
cache this closes (it crashed CI's test workers inside the trapezoid fill).
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import AbstractContextManager
from typing import Any

__all__ = ["safe_numba_cache"]


def safe_numba_cache() -> None:
    """Make numba's on-disk cache safe for processes that compile at the same time.

    Numba (0.68) names a kernel's data files ``<kernel>.1.nbc``, ``.2.nbc``, ... after
    the first number its index does not list yet. Two processes that compile *different*
    specialisations of one kernel at once both read the index before either wrote it, both
    take ``.1.nbc``, and one's index entry ends up naming the other's machine code: the
    next process to load that specialisation runs code compiled for other argument types
    (garbage, or a segfault -- the crash the xdist workers met inside the trapezoid
    fill's ``_sweep``). Here each specialisation's data file is named after a hash of its
    index key, so a name never holds another key's code; the data is written before the
    index names it, and the index is read, updated and written under a file lock, so no
    process loses another's entry. Applied when :mod:`harness` is imported, so that every
    process rastercheck runs in (test workers, ``run -j`` workers, Dask workers) is safe.
    Numba internals are patched only when they are the ones described; otherwise (another
    numba version) nothing is changed."""
    import hashlib
    from contextlib import nullcontext

    from numba.core import caching

    cls = getattr(caching, "IndexDataCacheFile", None)
    if cls is None or getattr(cls, "_rastercheck_safe", False) or \
            not all(hasattr(cls, name) for name in ("save", "_save_data", "_load_index", "_save_index")):
        return  # not the numba this was written for: leave it alone
    original = cls.save

    def _lock(path: str) -> AbstractContextManager[None]:
        try:
            import fcntl

            handle = open(path, "a")
        except (ImportError, OSError):  # no locking here: names still never clash
            return nullcontext()

        class _Held:
            def __enter__(self) -> None:
                fcntl.flock(handle, fcntl.LOCK_EX)

            def __exit__(self, *exc: object) -> None:
                fcntl.flock(handle, fcntl.LOCK_UN)
                handle.close()

        return _Held()

    def save(self: Any, key: Any, data: bytes) -> None:
        pattern = getattr(self, "_data_name_pattern", None)
        if not isinstance(pattern, str) or "{number:d}" not in pattern or not hasattr(self, "_index_path"):
            original(self, key, data)
            return
        digest = hashlib.sha256(repr(key).encode()).hexdigest()[:20]
        name = pattern.replace("{number:d}", digest)
        self._save_data(name, data)  # (atomic: a temporary file, then os.replace)
        with _lock(self._index_path + ".lock"):
            overloads = self._load_index()
            if overloads.get(key) != name:
                overloads[key] = name
                self._save_index(overloads)

    cls.save = save
    cls._rastercheck_safe = True
    _compile_one_at_a_time(_lock)


def _compile_one_at_a_time(lock: Callable[[str], AbstractContextManager[None]]) -> None:
    """Let one process at a time compile (or load) each cached kernel.

    Two processes that miss the cache for one kernel at once both compile it and both save
    it; a third then loads one's build beside callers compiled against the other's (session
    12 saw the trapezoid fill crash so, in a caller cached beside ``harness.geometry.exact``'s
    kernels compiled twice). Here a process takes a lock file beside the kernel's index
    before it looks in the cache, so a second process waits and loads the first one's
    build instead of compiling its own. Locks are taken callee after caller along the call
    graph (a kernel's compile compiles its callees), which has no cycle: no deadlock. A
    kernel already being compiled in this process (recursion, or a second thread) is not
    locked again."""
    from numba.core import dispatcher

    cls = getattr(dispatcher, "Dispatcher", None)
    if cls is None or getattr(cls, "_rastercheck_one_at_a_time", False) or not hasattr(cls, "compile"):
        return
    original = cls.compile
    held: set[str] = set()  # the index files whose lock this process holds

    def compile(self: Any, sig: Any) -> Any:
        index = getattr(getattr(getattr(self, "_cache", None), "_cache_file", None), "_index_path", None)
        if not isinstance(index, str) or index in held:  # not cached on disk, or ours already
            return original(self, sig)
        with lock(index + ".compile.lock"):
            held.add(index)
            try:
                return original(self, sig)
            finally:
                held.discard(index)

    cls.compile = compile
    cls._rastercheck_one_at_a_time = True
