"""Wire: plain data across a process boundary, without pickle.

A message is a small JSON header and the raw bytes of numbered arrays: what a worker
process sends back to the parent (:mod:`harness.engine.isolation`) when the data was made, or
could have been tampered with, by a plugin. The parent never unpickles anything: the
header is JSON (strings, numbers, lists, dicts), every array is rebuilt with
``np.frombuffer`` after its dtype (int64 or float64 only), shape and byte count were
checked against the message's length.

Layout: 8 bytes, the header's length (little-endian unsigned); the header, UTF-8 JSON
``{"fields": ..., "arrays": [{"name", "dtype", "shape"}, ...]}``; then each array's bytes in
that order, C-contiguous, native byte order, nothing after the last.

>>> import numpy as np
>>> message = pack({"seconds": 0.5}, {"y": np.arange(3), "alpha": np.zeros((0,))})
>>> fields, arrays = unpack(message)
>>> fields, arrays["y"], arrays["alpha"].shape
({'seconds': 0.5}, array([0, 1, 2]), (0,))
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["WireError", "pack", "unpack", "DTYPES", "MAX_HEADER_BYTES", "MAX_DIMENSIONS"]

# The only array types a message may hold, by the name its header gives them.
DTYPES: dict[str, np.dtype[Any]] = {"int64": np.dtype(np.int64), "float64": np.dtype(np.float64)}
MAX_HEADER_BYTES = 16 * 2**20  # texts (a traceback, an error's message) are cut well below this
MAX_DIMENSIONS = 2
_LENGTH_BYTES = 8


class WireError(ValueError):
    """A message that is not what :func:`pack` makes: what is wrong with it, in one line."""


def pack(fields: Mapping[str, Any], arrays: Mapping[str, NDArray[Any] | None]) -> bytes:
    """One message: ``fields`` (JSON-serialisable plain data) and named arrays (None ones
    are left out), each int64 or float64 in native byte order; the message holds a copy of
    their bytes (a value that is not a plain ndarray is first copied into one).

    Raises
    ------
    WireError
        An array of another dtype or of more than :data:`MAX_DIMENSIONS` dimensions, or a
        header that is too large.
    """
    described: list[dict[str, Any]] = []
    buffers: list[Any] = []  # bytes-like: each array's memory, copied once into the message
    for name, value in arrays.items():
        if value is None:
            continue
        array = value if type(value) is np.ndarray else np.array(value, copy=True, subok=False)
        array = np.ascontiguousarray(array)
        dtype = next((key for key, known in DTYPES.items() if array.dtype == known), None)
        if dtype is None or array.ndim > MAX_DIMENSIONS:
            raise WireError(f"array {name!r}: {array.dtype} of {array.ndim} dimensions cannot be sent "
                            f"(int64 or float64, at most {MAX_DIMENSIONS} dimensions)")
        described.append({"name": str(name), "dtype": dtype, "shape": [int(n) for n in array.shape]})
        buffers.append(array.data.cast("B") if array.size else b"")
    header = json.dumps({"fields": fields, "arrays": described}, allow_nan=False, separators=(",", ":")).encode("utf-8")
    if len(header) > MAX_HEADER_BYTES:
        raise WireError(f"the header is {len(header):,} bytes, more than {MAX_HEADER_BYTES:,}")
    return b"".join([len(header).to_bytes(_LENGTH_BYTES, "little"), header, *buffers])


def unpack(message: bytes) -> tuple[dict[str, Any], dict[str, NDArray[Any]]]:
    """The fields and the arrays (read-only, over ``message``'s buffer) of a message.

    Raises
    ------
    WireError
        Anything not as :func:`pack` writes it: a short or long message, a header that is
        not JSON of the expected form, an unknown dtype, a bad shape, a repeated name.
    """
    view = memoryview(message).cast("B")
    if len(view) < _LENGTH_BYTES:
        raise WireError(f"a message of {len(view)} bytes, shorter than its length prefix")
    length = int.from_bytes(view[:_LENGTH_BYTES], "little")
    if length > MAX_HEADER_BYTES or _LENGTH_BYTES + length > len(view):
        raise WireError(f"a header of {length:,} bytes in a message of {len(view):,}")
    try:
        header = json.loads(bytes(view[_LENGTH_BYTES:_LENGTH_BYTES + length]).decode("utf-8"),
                            parse_constant=_no_constant)
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise WireError(f"the header is not JSON ({type(exc).__name__})") from None
    if not isinstance(header, dict) or set(header) != {"fields", "arrays"} or not isinstance(header["fields"], dict) \
            or not isinstance(header["arrays"], list):
        raise WireError("the header is not {fields: {...}, arrays: [...]}")
    offset = _LENGTH_BYTES + length
    arrays: dict[str, NDArray[Any]] = {}
    for entry in header["arrays"]:
        name, dtype, shape = _entry(entry)
        if name in arrays:
            raise WireError(f"array {name!r} twice")
        size = math.prod(shape) * dtype.itemsize
        if size > len(view) - offset:
            raise WireError(f"array {name!r} of shape {tuple(shape)} needs {size:,} bytes, {len(view) - offset:,} are left")
        array = np.frombuffer(message, dtype=dtype, count=math.prod(shape), offset=offset).reshape(shape)
        array.setflags(write=False)
        arrays[name] = array
        offset += size
    if offset != len(view):
        raise WireError(f"{len(view) - offset:,} bytes after the last array")
    return header["fields"], arrays


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not JSON")


def _entry(entry: Any) -> tuple[str, np.dtype[Any], list[int]]:
    """An array's (name, dtype, shape) from its header entry, checked."""
    if not isinstance(entry, dict) or set(entry) != {"name", "dtype", "shape"}:
        raise WireError("an array entry is not {name, dtype, shape}")
    name, dtype, shape = entry["name"], entry["dtype"], entry["shape"]
    if not isinstance(name, str):
        raise WireError("an array's name is not a string")
    if not isinstance(dtype, str) or dtype not in DTYPES:
        raise WireError(f"array {name!r}: dtype {str(dtype)[:40]!r} (only {', '.join(DTYPES)})")
    if not isinstance(shape, list) or len(shape) > MAX_DIMENSIONS \
            or not all(type(n) is int and 0 <= n < 2**62 for n in shape):
        raise WireError(f"array {name!r}: shape {str(shape)[:60]} (at most {MAX_DIMENSIONS} sizes, each an int >= 0)")
    return name, DTYPES[dtype], shape
