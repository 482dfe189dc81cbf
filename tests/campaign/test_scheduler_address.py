"""``fuzz --scheduler``: the address is validated before any work, and the connection is
bounded in time and survives whatever the peer sends (issue 30: a server that accepts and
never answers hung past 120 s; one announcing a huge frame made the client allocate 4 EiB;
ucx://, tls:// without certificates and inproc:// were tracebacks)."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from harness.campaign.cluster import connect, scheduler_address
from harness.cli.main import main

pytest.importorskip("distributed")


@pytest.mark.parametrize("address, said", [
    ("ucx://10.0.0.5:8786", "ucx:// is not a transport a campaign connects over"),
    ("tls://10.0.0.5:8786", "tls:// needs certificates rastercheck does not configure"),
    ("inproc://10.0.0.5/1/2", "inproc:// lives inside one process"),
    ("tcp://10.0.0.5", "not HOST:PORT"),
    ("tcp://10.0.0.5:99999", "not HOST:PORT"),
    ("tcp://a b:8786", "not HOST:PORT"),
])
def test_an_address_that_is_no_tcp_host_and_port_is_a_usage_error(address: str, said: str, tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(ValueError, match=said.replace("(", r"\(")):
        scheduler_address(address)
    with pytest.raises(SystemExit) as info:
        main(["fuzz", "--rasterizer", "pineda_topleft", "--budget", "4", "--scheduler", address, "--state", str(tmp_path / "s")])
    assert info.value.code == 2 and said in capsys.readouterr().err
    assert not (tmp_path / "s").exists()  # refused before any work


@contextmanager
def _server(answer: bytes | None) -> Iterator[str]:
    """A TCP server on this host that accepts and sends ``answer`` (or nothing), never more."""
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen(8)
    held: list[socket.socket] = []
    stop = threading.Event()

    def serve() -> None:
        listener.settimeout(0.2)
        while not stop.is_set():
            try:
                peer, _ = listener.accept()
            except OSError:
                continue
            if answer:
                peer.sendall(answer)
            held.append(peer)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{listener.getsockname()[1]}"
    finally:
        stop.set()
        thread.join(5)
        for peer in held:
            peer.close()
        listener.close()


@pytest.mark.parametrize("answer, said", [
    (None, "gave no answer within 2 s (--scheduler-timeout S waits longer)"),
    (b"\xff" * 64, "cannot connect to the Dask scheduler at"),  # a frame of exabytes announced
    (b"HTTP/1.1 200 OK\r\n\r\nhello" * 10, "the Dask scheduler at"),  # garbage: an error, or no answer in time
])
def test_a_peer_that_is_no_scheduler_is_refused_in_time_naming_it(answer: bytes | None, said: str) -> None:
    with _server(answer) as address:
        start = time.monotonic()
        with pytest.raises(ValueError) as refused:
            connect(address, 2.0)
        assert time.monotonic() - start < 30
    message = str(refused.value)
    assert said in message and address in message and "\n" not in message, message
