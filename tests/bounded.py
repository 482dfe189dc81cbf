"""Time and memory bounds of the catalogue's rows (issue 30: each input "asserting time under
60 s and memory under 2 GB").

:func:`bounded` measures a row run in this process: its wall time and how far its resident
memory rose above where it began, at its peak -- sampled every few milliseconds by a thread,
and exactly when the row set a new peak for the process (``ru_maxrss``), which an
allocation of gigabytes does. It costs next to nothing (``tracemalloc`` made the rows three
times slower). :func:`run_bounded` measures a row run as a process of its own: its wall time
and its peak resident memory (``ru_maxrss`` of that child alone, read by ``os.wait4``).
"""

from __future__ import annotations

import os
import resource
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

SECONDS = 60.0
MEGABYTES = 2048
_PAGE = os.sysconf("SC_PAGE_SIZE")


def _resident() -> int:
    """This process's resident memory now, in bytes."""
    with open("/proc/self/statm", "rb") as statm:
        return int(statm.read().split()[1]) * _PAGE


def _peak() -> int:
    """This process's peak resident memory so far, in bytes."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


@dataclass
class Measured:
    """What a bounded row took: seconds, and megabytes its resident memory rose at its peak
    (filled in at its end)."""

    seconds: float = 0.0
    megabytes: float = 0.0


@contextmanager
def bounded(seconds: float = SECONDS, megabytes: float = MEGABYTES, every: float = 0.005) -> Iterator[Measured]:
    """Assert that the block finishes within ``seconds`` and that this process's resident
    memory rises by less than ``megabytes`` above where it began (sampled ``every`` seconds,
    and read exactly from ``ru_maxrss`` when the block raised the process's peak). A block
    that raises is not judged: its exception goes on."""
    measured = Measured()
    began, peak_before = _resident(), _peak()
    highest = [began]
    done = threading.Event()

    def sample() -> None:
        while not done.wait(every):
            highest[0] = max(highest[0], _resident())

    sampler = threading.Thread(target=sample, name="bounded-rss", daemon=True)
    sampler.start()
    start = time.monotonic()
    try:
        yield measured
        measured.seconds = time.monotonic() - start
    finally:
        done.set()
        sampler.join()
    peak_after = _peak()
    top = max(highest[0], _resident(), peak_after if peak_after > peak_before else 0)
    measured.megabytes = (top - began) / 2**20
    assert measured.seconds < seconds, f"took {measured.seconds:.1f} s, more than {seconds:g} s"
    assert measured.megabytes < megabytes, f"rose {measured.megabytes:,.0f} MB at its peak, more than {megabytes:g} MB"


@dataclass
class Finished:
    """A process run by :func:`run_bounded`: its exit code, output, seconds and peak RSS."""

    returncode: int
    stdout: str
    stderr: str
    seconds: float
    megabytes: float


# A process forked from this one starts as large as this one (a test worker: a gigabyte),
# and Linux keeps that high-water mark in the ``ru_maxrss`` of whatever it then executes. So
# the command runs under a small Python that reports its child's peak on a pipe: forked from
# that, the command starts small and its peak is its own.
_LAUNCHER = """import os, resource, signal, subprocess, sys
code = subprocess.call(sys.argv[2:])
os.write(int(sys.argv[1]), str(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss).encode())
if code < 0:
    signal.signal(-code, signal.SIG_DFL)
    os.kill(os.getpid(), -code)
sys.exit(code)
"""


def run_bounded(args: list[str], *, seconds: float = SECONDS, megabytes: float = MEGABYTES, **popen: Any) -> Finished:
    """Run ``args`` as a process (``popen``: cwd, env, ...), kill it past ``seconds``, and
    assert it finished within ``seconds`` with a peak resident memory (its own
    ``ru_maxrss``, and that of any child it waited for) under ``megabytes``."""
    read_end, write_end = os.pipe()
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.monotonic()
        try:
            proc = subprocess.Popen([sys.executable, "-c", _LAUNCHER, str(write_end), *args], stdout=out, stderr=err,
                                    pass_fds=(write_end,), start_new_session=True, **popen)
        finally:
            os.close(write_end)
        try:
            proc.wait(seconds)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)  # the command with its launcher
            proc.wait()
        took = time.monotonic() - start
        with os.fdopen(read_end, "rb") as said:
            kilobytes = int(said.read() or 0)
        out.seek(0)
        err.seek(0)
        done = Finished(proc.returncode, out.read().decode(errors="replace"), err.read().decode(errors="replace"), took,
                        kilobytes / 1024)
    assert done.seconds < seconds, f"{args[:4]} took {done.seconds:.1f} s, more than {seconds:g} s (killed)"
    assert done.megabytes < megabytes, f"{args[:4]} reached {done.megabytes:,.0f} MB, more than {megabytes:g} MB"
    return done
