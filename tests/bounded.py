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
import subprocess
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


def run_bounded(args: list[str], *, seconds: float = SECONDS, megabytes: float = MEGABYTES, **popen: Any) -> Finished:
    """Run ``args`` as a process (``popen``: cwd, env, ...), kill it past ``seconds``, and
    assert it finished within ``seconds`` with a peak resident memory (its own
    ``ru_maxrss``, and that of any child it waited for) under ``megabytes``."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.monotonic()
        proc = subprocess.Popen(args, stdout=out, stderr=err, **popen)
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - start > seconds:
                proc.kill()
                pid, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(0.02)
        took = time.monotonic() - start
        proc.returncode = os.waitstatus_to_exitcode(status)  # reaped here: Popen must not wait for it again
        out.seek(0)
        err.seek(0)
        done = Finished(proc.returncode, out.read().decode(errors="replace"), err.read().decode(errors="replace"), took,
                        usage.ru_maxrss / 1024)
    assert done.seconds < seconds, f"{args[:4]} took {done.seconds:.1f} s, more than {seconds:g} s (killed)"
    assert done.megabytes < megabytes, f"{args[:4]} reached {done.megabytes:,.0f} MB, more than {megabytes:g} MB"
    return done
