"""The Dask cluster a campaign runs on: a quiet local cluster (:func:`local_cluster`), or a
scheduler's address checked (:func:`scheduler_address`) and connected to within a time limit
(:func:`connect`).
"""

from __future__ import annotations

import logging
import os
import re
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from distributed import Client


# The LocalCluster's background work, turned down: Dask's defaults sample every worker's
# stack every 10 ms (its profiler), check each event loop every 20 ms and memory every
# 100 ms -- measured idle, 0.17 of a core for two workers, 0.02 with these.
QUIET_DASK = {"distributed.worker.profile.enabled": False, "distributed.admin.tick.interval": "1s",
              "distributed.admin.system-monitor.interval": "2s", "distributed.worker.memory.monitor-interval": "500ms"}


@contextmanager
def _children_ignore_ctrl_c() -> Iterator[None]:
    """Start processes that ignore Ctrl-C: the terminal sends SIGINT to the whole process
    group, and each Dask worker and nanny printed a KeyboardInterrupt traceback of its own
    (four on two workers) while this process, which stops them, said what was kept. An
    ignored signal stays ignored in a child, across ``exec`` and Python's start-up, so
    SIGINT is ignored here only while the cluster's processes start (a Ctrl-C meanwhile is
    lost: the cluster is up in seconds, and the next one stops the campaign)."""
    import signal

    try:
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread: its children keep the default
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextmanager
def local_cluster(workers: int | None = None) -> Iterator[Client]:
    """A client of a fresh Dask ``LocalCluster`` of ``workers`` worker processes (default
    one per core) of one thread each, closed on leaving: what a campaign runs on unless it
    is given a scheduler.

    No dashboard, and the scheduler's small HTTP server (health, metrics) on a free port of
    this host: never the default 8787, which another cluster may hold. Dask's own background
    work is turned down (:data:`QUIET_DASK`).
    """
    import dask
    from distributed import Client, LocalCluster

    with dask.config.set(QUIET_DASK), _children_ignore_ctrl_c():
        cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                               dashboard_address="127.0.0.1:0", scheduler_kwargs={"dashboard": False},
                               silence_logs=logging.CRITICAL)  # (a worker outliving the scheduler at Ctrl-C logged a traceback)
    try:
        with Client(cluster) as client:
            yield client
    finally:
        cluster.close()


SCHEDULER_TIMEOUT = 10.0
"""Seconds a connection to a Dask scheduler may take, handshake included (``--scheduler-timeout``)."""


def scheduler_address(text: str) -> str:
    """A Dask scheduler's address as a campaign connects to it, ``tcp://HOST:PORT`` (a bare
    ``HOST:PORT`` is TCP); ValueError in one line for anything else.

    >>> scheduler_address("10.0.0.5:8786"), scheduler_address("tcp://[::1]:8786")
    ('tcp://10.0.0.5:8786', 'tcp://[::1]:8786')
    >>> scheduler_address("tls://sched:8786")
    Traceback (most recent call last):
    ...
    ValueError: --scheduler tls://sched:8786: tls:// is not a transport a campaign connects over: give tcp://HOST:PORT (tls:// needs certificates rastercheck does not configure, ucx:// a UCX install, inproc:// lives inside one process)
    """
    scheme, separator, rest = text.partition("://")
    if not separator:
        scheme, rest = "tcp", text
    if scheme != "tcp":
        raise ValueError(f"--scheduler {text}: {scheme}:// is not a transport a campaign connects over: give tcp://HOST:PORT "
                         "(tls:// needs certificates rastercheck does not configure, ucx:// a UCX install, inproc:// lives "
                         "inside one process)")
    match = re.fullmatch(r"(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):([0-9]{1,5})", rest)
    if match is None or not 1 <= int(match.group(2)) <= 65535:
        raise ValueError(f"--scheduler {text}: not HOST:PORT (a Dask scheduler's address, as tcp://10.0.0.5:8786)")
    return f"tcp://{rest}"


def connect(address: str, seconds: float = SCHEDULER_TIMEOUT) -> Client:
    """A client of the Dask scheduler at ``address`` (:func:`scheduler_address`), within
    ``seconds``; ValueError in one line naming the address when it cannot be reached, does
    not answer in time, or answers what no scheduler would (garbage, a frame of exabytes)."""
    from distributed import Client

    address = scheduler_address(address)
    outcome: dict[str, Any] = {}

    def attempt() -> None:
        try:
            outcome["client"] = Client(address, timeout=f"{seconds}s")
        except BaseException as exc:  # noqa: B036 - whatever the peer's bytes make of the client
            outcome["error"] = exc

    thread = threading.Thread(target=attempt, name="rastercheck-connect", daemon=True)
    thread.start()
    thread.join(seconds + 1.0)  # (Dask's own timeout first; this, when it does not hold: a peer that never answers)
    if thread.is_alive() or isinstance(outcome.get("error"), TimeoutError):
        raise ValueError(f"the Dask scheduler at {address} gave no answer within {seconds:g} s "
                         "(--scheduler-timeout S waits longer)")
    if "error" in outcome:
        error = outcome["error"]
        raise ValueError(f"cannot connect to the Dask scheduler at {address}: "
                         f"{type(error).__name__}: {str(error).splitlines()[0] if str(error) else 'no reason given'}"[:300])
    return outcome["client"]  # type: ignore[no-any-return]


@contextmanager
def _dask(scheduler: str | Client | None, workers: int | None,
          scheduler_timeout: float = SCHEDULER_TIMEOUT) -> Iterator[Client]:
    """A Dask client: to ``scheduler`` (an address, or a client already made), else to a
    :func:`local_cluster` of ``workers`` processes."""
    from distributed import Client

    if isinstance(scheduler, Client):
        yield scheduler
    elif scheduler is not None:
        with connect(scheduler, scheduler_timeout) as client:
            yield client
    else:
        with local_cluster(workers) as client:
            yield client
