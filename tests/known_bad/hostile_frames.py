"""A hostile plugin that writes on its worker's pipe itself: a frame header announcing a
huge answer, then as many bytes as it is told to, then ends its process.

Unchecked, the parent would read the announced length and allocate (and fill) that much:
a plugin could make the harness's own process take gigabytes, or fail with MemoryError
and lose the run. The parent refuses a frame longer than the scene's answer could need
(harness.engine.isolation.answer_bytes_limit) before reading it (tests/engine/test_wire.py).
"""

from __future__ import annotations

import os
import struct
import sys
from types import FrameType
from typing import Any

from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from rasterizers.pineda_topleft import PinedaTopLeft


def _worker_pipe() -> Any:
    """The connection the worker serves (``conn`` in :func:`harness.engine.isolation._serve`, up
    the call stack): the one whose other end the parent reads."""
    frame: FrameType | None = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_name == "_serve" and "conn" in frame.f_locals:
            return frame.f_locals["conn"]
        frame = frame.f_back
    raise RuntimeError("not called in a rastercheck worker")


class AnnouncesHugeFrame:
    """Answers scenes of one triangle right; on any other, writes straight to the worker's
    pipe a frame header announcing ``announced`` bytes, then ``written`` bytes of zeros (1 MiB
    at a time, stopping when the parent hangs up), then ends its process (``os._exit``)."""

    convention = PinedaTopLeft().convention

    def __init__(self, announced: int, written: int = 0) -> None:
        self.name = "announces_huge_frame"
        self.announced, self.written = announced, written

    def rasterize(self, scene: Scene) -> Coverage:
        if len(scene) == 1:
            return PinedaTopLeft().rasterize(scene)
        fd = _worker_pipe().fileno()
        # multiprocessing's framing: a 4-byte big-endian length, -1 then 8 bytes for a long one
        header = struct.pack("!i", -1) + struct.pack("!Q", self.announced) if self.announced > 0x7FFFFFFF \
            else struct.pack("!i", self.announced)
        chunk = bytes(2**20)
        try:
            os.write(fd, header)
            left = self.written
            while left > 0:
                left -= os.write(fd, chunk[:min(left, len(chunk))])
        except OSError:
            pass
        os._exit(0)
