"""Nothing a plugin made crosses into the harness's process by pickle (issue 30): a worker
sends each outcome as plain data (harness.engine.wire), the parent rebuilds coverages from checked
buffers and errors from their type name, nearest base and text. Hostile answers whose
unpickling would run code in the parent (tests/known_bad/hostile_pickles.py) leave a
marker file naming the process that ran it: the parent's pid must never be in it."""

from __future__ import annotations

import functools
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cases.suites import suite
from harness import run_suite
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene, Unsupported
from harness.engine.isolation import Worker
from harness.engine.outcomes import ERROR_BASES, Outcome, PluginError, decode_outcome, describe, encode_outcome, rebuilt_error
from harness.engine.wire import WireError, pack, unpack
from tests.known_bad.hostile_pickles import (
    HOSTILE_PICKLES,
    ArraysDetonate,
    ClaimsTimedOut,
    CoverageDetonates,
    RaisesDetonating,
    RaisesUnprintableDetonating,
    SendsJunk,
)

SCENE = Scene(16, 16, [[[0.25, 1.0], [6.75, 2.0], [1.0, 9.5]], [[8.0, 8.0], [15.0, 9.0], [9.0, 15.0]]],
              attributes=np.arange(18.0).reshape(2, 3, 3))


@functools.cache
def _cases():
    """Two single-scene cases and a motion case (its frames streamed: rasterize_all)."""
    quick = tuple(suite("quick"))
    wanted = ("lattice/bits-0", "watertight/fan-32/centre")
    return [c for c in quick if c.id in wanted] + [c for c in quick if c.family == "motion"][:1]


def _ran_here(marker: Path) -> bool:
    """Whether hostile code ran in this process: its pid in the marker file."""
    return marker.exists() and str(os.getpid()) in marker.read_text().split()


# -- hostile plugins end to end -----------------------------------------------------------------


@pytest.mark.parametrize("bad, words", [
    (ArraysDetonate, None),
    (CoverageDetonates, None),
    (RaisesDetonating, "DetonatingError: triangle 0 is not welcome here"),
    (RaisesUnprintableDetonating, "UnprintableError: <its text cannot be shown: __str__ raised DetonatingError>"),
])
def test_a_hostile_pickle_never_runs_in_the_parent_and_the_run_goes_on(tmp_path, bad, words):
    marker = tmp_path / "detonated"
    results = run_suite([bad(str(marker)), "centre_scanline"], cases=_cases(), repros=False)
    assert not _ran_here(marker), "the hostile object was unpickled in the harness's process"
    mine = [r for r in results if r.rasterizer == bad.__name__]
    assert mine
    if words is None:  # the right coverage, carried back as a plain one
        assert all(r.status in ("pass", "skip") for r in mine), [r.message for r in mine if r.status not in ("pass", "skip")]
        assert any(r.status == "pass" for r in mine)
    else:
        assert all(r.status == "error" and words in r.message for r in mine), [r.message for r in mine]
    others = [r for r in results if r.rasterizer == "centre_scanline"]
    assert others and all(r.status in ("pass", "skip") for r in others)
    assert {r.case for r in others} == {c.id for c in _cases()}


def test_the_hostile_catalogue_is_complete():
    assert len(HOSTILE_PICKLES) == 4


def test_a_worker_hands_back_plain_classes_not_the_plugins(tmp_path):
    marker = tmp_path / "detonated"
    with Worker(CoverageDetonates(str(marker)), timeout=60) as worker:
        coverage = worker.rasterize(SCENE).coverage
    assert type(coverage) is Coverage
    assert all(type(getattr(coverage, f)) is np.ndarray for f in ("primitive", "y", "x0", "x1", "attributes"))
    with Worker(RaisesDetonating(str(marker)), timeout=60) as worker:
        outcome = worker.rasterize(SCENE)
    error = outcome.error
    assert isinstance(error, ValueError) and type(error).__name__ == "DetonatingError"
    assert type(error).__module__ == "harness.engine.outcomes" and "DetonatingError" in outcome.traceback
    assert describe(error) == "DetonatingError: triangle 0 is not welcome here"
    assert not _ran_here(marker)


def test_an_exit_at_unpickling_would_end_the_run_0_and_now_ends_nothing(tmp_path):
    """The issue's case: ``os._exit(0)`` run by unpickling in the parent ended the run with
    exit 0 and every other rasterizer's results lost. Run as its own process."""
    marker = tmp_path / "detonated"
    script = (
        "import sys\n"
        "from harness import run_suite\n"
        "from tests.known_bad.hostile_pickles import ArraysDetonate, RaisesDetonating\n"
        "from tests.engine.test_wire import _cases\n"
        f"bad = [ArraysDetonate({str(marker)!r}, exit_home=True), RaisesDetonating({str(marker)!r}, exit_home=True)]\n"
        "results = run_suite([*bad, 'centre_scanline'], cases=_cases()[:1], repros=False)\n"
        "print(sorted({(r.rasterizer, r.status) for r in results}))\n"
        "sys.exit(3)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=600,
                          cwd=Path(__file__).resolve().parents[2])
    assert done.returncode == 3, done.stdout + done.stderr[-2000:]
    said = done.stdout
    assert "('ArraysDetonate', 'pass')" in said and "('RaisesDetonating', 'error')" in said
    assert "('centre_scanline', 'pass')" in said
    home = [line for line in (marker.read_text().split() if marker.exists() else [])]
    assert not home, f"hostile code ran in processes {home}"


def test_a_tampered_message_is_an_error_and_what_only_the_parent_says_is_not_taken_from_the_worker():
    with Worker(SendsJunk("unused"), timeout=60) as worker:
        junk = worker.rasterize(SCENE)
        assert junk.coverage is None and isinstance(junk.error, PluginError)
        assert describe(junk.error).startswith("PluginError: the rasterizer's answer cannot be read back (WireError: ")
        assert worker.rasterize(SCENE).coverage is None  # the worker goes on, in step, still patched
    with Worker(ClaimsTimedOut("unused"), timeout=60) as worker:
        claimed = worker.rasterize(SCENE)
        assert claimed.coverage is not None and not claimed.timed_out and claimed.retried is None and claimed.flaws is None


def test_a_frame_header_announcing_gigabytes_is_refused_unread_and_the_worker_replaced():
    """A plugin writing its own frame header on the worker's pipe (tests/known_bad/hostile_frames.py):
    one announcing 2**40 bytes (the parent used to try to allocate it: MemoryError, the run
    lost), one announcing 512 MiB and writing them (the parent used to read them all into its
    own memory). Each is that call's one-line error, the parent's peak memory stays within
    64 MB of what it was, and the next call is answered. Run as its own process, whose peak
    memory (ru_maxrss) is this test's alone."""
    script = (
        "import json, resource\n"
        "from harness.contract.scenes import Scene\n"
        "from harness.engine.isolation import Worker, answer_bytes_limit, describe\n"
        "from tests.known_bad.hostile_frames import AnnouncesHugeFrame\n"
        "two = Scene(16, 16, [[[0, 0], [9, 0], [0, 9]], [[9, 9], [15, 9], [9, 15]]])\n"
        "one = Scene(16, 16, [[[0, 0], [9, 0], [0, 9]]])\n"
        "said = []\n"
        "for announced, written in ((2**40, 0), (512 * 2**20, 512 * 2**20)):\n"
        "    with Worker(AnnouncesHugeFrame(announced, written), timeout=60) as worker:\n"
        "        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
        "        refused = worker.rasterize(two)\n"
        "        grown = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before\n"
        "        after = worker.rasterize(one)\n"
        "        said.append({'error': describe(refused.error), 'grown_kb': grown, 'then': after.coverage is not None,\n"
        "                     'limit': answer_bytes_limit(two)})\n"
        "print(json.dumps(said))\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300,
                          cwd=Path(__file__).resolve().parents[2])
    assert done.returncode == 0, done.stderr[-2000:]
    for said in json.loads(done.stdout):
        assert said["error"] == (f"PluginError: refused an answer of more than {said['limit']:,} bytes on the worker's pipe, "
                                 "the most one on 2 triangles on 16 x 16 px may take")
        assert said["grown_kb"] < 64 * 1024, f"the parent's peak memory grew by {said['grown_kb']:,} KB"
        assert said["then"], "the worker was not replaced: the next call was not answered"


def test_the_registry_probe_sends_back_plain_text_only(tmp_path, monkeypatch):
    from harness.engine.registry import Unavailable, load

    marker = tmp_path / "detonated"
    monkeypatch.setenv("HOSTILE_PICKLES_MARKER", str(marker))
    monkeypatch.setenv("HOSTILE_PICKLES_HOME", str(os.getpid()))
    with pytest.raises(Unavailable) as refused:
        load("tests.known_bad.hostile_pickles:refuses_to_load")
    assert not _ran_here(marker), "the probe's answer was unpickled in the harness's process"
    assert str(refused.value) == "the plugin will not load" and type(str(refused.value)) is str


# -- errors rebuilt from plain data ------------------------------------------------------------


class _LibraryRefusal(Unsupported):
    pass


class _Odd(KeyError):
    pass


@pytest.mark.parametrize("error, name, base", [
    (ValueError("triangle 3 is huge"), "ValueError", ValueError),
    (_LibraryRefusal("one contour per call"), "_LibraryRefusal", Unsupported),
    (_Odd("key"), "_Odd", KeyError),
    (KeyError("key"), "KeyError", KeyError),
    (UnicodeDecodeError("utf-8", b"\xff", 0, 1, "invalid start byte"), "UnicodeDecodeError", UnicodeError),
    (KeyboardInterrupt(), "KeyboardInterrupt", KeyboardInterrupt),
    (SystemExit(0), "SystemExit", SystemExit),
    (PluginError("refused"), "PluginError", PluginError),
    (ExceptionGroup("two", [ValueError("a"), TypeError("b")]), "ExceptionGroup", Exception),
    (type("bad name!", (ZeroDivisionError,), {})("x"), "bad_name_", ZeroDivisionError),
])
def test_an_error_comes_back_with_its_type_name_base_and_text(error, name, base):
    back = decode_outcome(encode_outcome(Outcome(None, error, "Traceback ...", 0.5))).error
    assert type(back).__name__ == name and isinstance(back, base)
    assert describe(back, with_type=False) == describe(error, with_type=False)
    assert str(back) == str(error)


def test_a_rebuilt_error_pickles_as_itself_for_the_parent():
    import pickle

    error = rebuilt_error("TriangleTooLarge", "ValueError", "triangle 3 is huge")
    again = pickle.loads(pickle.dumps(error))
    assert type(again).__name__ == "TriangleTooLarge" and isinstance(again, ValueError) and str(again) == str(error)
    assert type(rebuilt_error("Whatever", "NotABase", "x")).__bases__ == (PluginError,)
    assert set(ERROR_BASES) >= {"ValueError", "Exception", "BaseException", "Unsupported", "PluginError", "KeyboardInterrupt"}


def test_a_str_subclass_text_crosses_as_plain_text():
    class Sly(str):
        def __reduce__(self):
            raise AssertionError("pickled")

    class Named(ValueError):
        def __str__(self):
            return Sly("sly text")

    back = decode_outcome(encode_outcome(Outcome(None, Named(), Sly("trace"), 0.0))).error
    assert type(str(back)) is str and str(back) == "sly text"


# -- the framing -----------------------------------------------------------------------------


_DTYPES = st.sampled_from([np.int64, np.float64])
_SHAPES = st.one_of(st.tuples(st.integers(0, 40)), st.tuples(st.integers(0, 12), st.integers(0, 6)))


@st.composite
def _arrays(draw):
    names = draw(st.lists(st.text(min_size=1, max_size=8), unique=True, max_size=6))
    found: dict[str, np.ndarray | None] = {}
    for name in names:
        if draw(st.booleans()) and draw(st.booleans()):
            found[name] = None
            continue
        dtype, shape = draw(_DTYPES), draw(_SHAPES)
        rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
        values = rng.integers(-(2**62), 2**62, size=shape) if dtype is np.int64 else rng.standard_normal(shape) * 1e300
        found[name] = np.asarray(values, dtype=dtype)
    return found


@given(_arrays(), st.dictionaries(st.text(max_size=5), st.one_of(st.none(), st.integers(-5, 5), st.text(max_size=5)), max_size=4))
def test_framing_round_trips_any_arrays_and_fields(arrays, fields):
    message = pack(fields, arrays)
    got_fields, got = unpack(message)
    assert got_fields == fields
    assert set(got) == {k for k, v in arrays.items() if v is not None}
    for name, array in got.items():
        assert array.dtype == arrays[name].dtype and array.shape == arrays[name].shape
        assert np.array_equal(array, arrays[name]) and not array.flags.writeable and type(array) is np.ndarray


@given(st.integers(0, 20), st.booleans(), st.sampled_from(["single", "sample", "alpha"]), st.integers(0, 3))
def test_an_outcome_round_trips_with_every_optional_part(spans, with_attributes, kind, k):
    rng = np.random.default_rng(spans * 7 + k)
    parts = [rng.integers(-5, 50, spans) for _ in range(4)]
    pixels = int(np.clip(parts[3] - parts[2], 0, None).sum())
    coverage = Coverage(parts[0], parts[1], parts[2], parts[3], rng.standard_normal((pixels, k)) if with_attributes else None,
                        sample=rng.integers(0, 4, spans) if kind == "sample" else None,
                        alpha=rng.random(pixels) if kind == "alpha" else None)
    flaws = {"repeated": np.arange(min(spans, 3)), "repeated_pixels": np.array([2])}
    outcome = Outcome(coverage, seconds=1.5, received=coverage, flaws=flaws, retried=2.0)
    back = decode_outcome(encode_outcome(outcome))
    for which in ("coverage", "received"):
        for field in ("primitive", "y", "x0", "x1", "attributes", "sample", "alpha"):
            ours, theirs = getattr(getattr(outcome, which), field), getattr(getattr(back, which), field)
            assert (ours is None) == (theirs is None) and (theirs is None or np.array_equal(ours, theirs))
    assert back.flaws is not None and {k: v.tolist() for k, v in back.flaws.items()} == {k: v.tolist() for k, v in flaws.items()}
    assert (back.seconds, back.retried, back.error, back.timed_out) == (1.5, 2.0, None, False)


def _message(fields=None, keep_arrays=True, **arrays):
    """A good outcome's message with some ``fields`` and ``arrays`` changed (or its arrays dropped)."""
    good_fields, good_arrays = unpack(encode_outcome(Outcome(Coverage.from_pixels([0, 0], [1, 2], [3, 3]), seconds=0.25)))
    return pack({**good_fields, **(fields or {})}, {**(good_arrays if keep_arrays else {}), **arrays})


@pytest.mark.parametrize("message, words", [
    (b"", "shorter than its length prefix"),
    ((10**9).to_bytes(8, "little") + b"{}", "a header of"),
    ((3).to_bytes(8, "little") + b"{x}", "not JSON"),
    ((2).to_bytes(8, "little") + b"[]", "not {fields"),
    (_message()[:-1], "are left"),
    (_message() + b"\0", "after the last array"),
    (_message(**{"coverage.y": np.zeros(1, np.float64)}), "coverage.y"),
    (_message(**{"coverage.y": np.zeros((1, 1), np.int64)}), "coverage.y"),
    (_message(**{"coverage.y": np.zeros(3, np.int64)}), "equal lengths"),
    (_message(**{"stray": np.zeros(3, np.int64)}), "not part of the outcome"),
    (_message(fields={"coverage": None}, keep_arrays=False), "not both or neither"),
    (_message(fields={"seconds": "1"}), "not a number"),
    (_message(fields={"error": {"type": "X", "base": "ValueError", "text": 3}}), "the error"),
])
def test_a_malformed_message_is_refused_in_one_line(message, words):
    with pytest.raises(WireError, match=None) as refused:
        decode_outcome(message)
    assert words in str(refused.value) and "\n" not in str(refused.value)


def test_pack_refuses_other_dtypes_and_shapes():
    with pytest.raises(WireError, match="object"):
        pack({}, {"a": np.array([object()])})
    with pytest.raises(WireError, match="dimensions"):
        pack({}, {"a": np.zeros((1, 1, 1))})
    header = b'{"fields":{},"arrays":[{"name":"a","dtype":"object","shape":[1]}]}'
    with pytest.raises(WireError, match="dtype"):
        unpack(len(header).to_bytes(8, "little") + header + b"\0" * 8)
