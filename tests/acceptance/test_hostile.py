"""Hostile plugins (issue 13): garbage answers cost time and memory in proportion to their
spans, faults of every kind end in an error naming them, and the run goes on."""

import functools
import subprocess
import sys

import pytest

from cases.suites import suite
from harness import run_suite
from tests.known_bad.hostile import (
    HOSTILE,
    BeyondReach,
    Copies,
    ExitsWithSystemExit,
    FarAway,
    HugeSpan,
    MillionCopies,
    NaNEverywhere,
    RaisesKeyboardInterrupt,
    RaisesUnpicklable,
    RaisesUnprintable,
)


@functools.cache
def _quick():
    """The quick suite, built once for the module (each build takes a tenth of a second)."""
    return tuple(suite("quick"))


def _cases():
    wanted = ("lattice/bits-0", "watertight/fan-32/centre")
    return [c for c in _quick() if c.id in wanted] + [c for c in _quick() if c.family == "motion"][:1]


@pytest.mark.parametrize("bad", [HugeSpan, Copies, FarAway, BeyondReach])
def test_garbage_spans_fail_hygiene_naming_the_fault(bad):
    results = run_suite([bad()], cases=_cases()[:2], repros=False)
    hygiene = [r for r in results if r.check == "hygiene"]
    assert hygiene and all(r.status == "fail" for r in hygiene)
    said = " ".join(r.message for r in hygiene)
    assert {"HugeSpan": "outside viewport", "Copies": "repeated pixels", "FarAway": "outside viewport",
             "BeyondReach": "outside triangle"}[bad.__name__] in said
    assert all(r.status in ("pass", "fail", "skip") for r in results), [r.message for r in results if r.status == "error"]


@pytest.mark.parametrize("bad, words", [
    (MillionCopies, "spans: "),
    (RaisesUnpicklable, "_Unpicklable: 1, 2"),
    (RaisesUnprintable, "__str__ raised RuntimeError"),
    (RaisesKeyboardInterrupt, "KeyboardInterrupt"),
    (ExitsWithSystemExit, "SystemExit"),
])
def test_every_fault_is_an_error_naming_it_and_the_run_goes_on(bad, words):
    results = run_suite([bad(), "centre_scanline"], cases=_cases(), repros=False)
    mine = [r for r in results if r.rasterizer == bad.__name__]
    assert mine and all(r.status == "error" and words in r.message for r in mine), [r.message for r in mine]
    others = [r for r in results if r.rasterizer == "centre_scanline"]
    assert others and all(r.status in ("pass", "skip") for r in others)


def test_nan_attributes_fail_hygiene_and_the_motion_checks_without_crashing():
    results = run_suite([NaNEverywhere()], cases=[c for c in _quick() if c.family == "motion" and c.texels][:2]
                        + [c for c in _quick() if c.id == "mesh/box/near-clipped"], repros=False)
    assert not [r for r in results if r.status == "error"], [r.message for r in results if r.status == "error"]
    hygiene = [r for r in results if r.check == "hygiene"]
    assert hygiene and "NaN or infinite attributes" in hygiene[0].message
    assert any(r.check == "texel" and r.status == "fail" for r in results)


def test_garbage_costs_bounded_memory():
    """Measured in a fresh process: peak memory stays far below what expanding the spans
    into pixels would take, and the run ends (the reported fault: 16 GB past 300 s)."""
    code = (
        "import resource\n"
        "from cases.suites import suite\n"
        "from harness import run_suite\n"
        "from tests.known_bad.hostile import Copies, FarAway, HugeSpan, MillionCopies\n"
        "cases = [c for c in suite('quick') if c.id == 'watertight/fan-32/centre']\n"
        "before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
        "run_suite([MillionCopies(), Copies(), HugeSpan(), FarAway()], cases=cases, isolate=False, identify=False)\n"
        "print((resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) // 1024)\n"
    )
    grown = int(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                               timeout=600).stdout.split()[-1])
    assert grown < 1500, f"{grown} MiB"


def test_hostile_catalogue_is_complete():
    assert len(HOSTILE) == 10


def test_a_hang_is_known_in_the_scaled_limit_and_one_retry_not_after_the_cap():
    """Under a 60 s cap, a call on a small scene gets the policy's scaled limit and, cut off,
    one more ask with a longer one: a rasterizer that hangs is known in seconds."""
    from harness.engine.isolation import TimeLimit
    from tests.known_bad.misc import HangsOnEpsilon

    cases = [c for c in _quick() if c.family == "degenerate"][:12]
    policy = TimeLimit(cap=60.0, base=0.3, rate=0.0, retry=2.0, first=60.0)
    results = run_suite([HangsOnEpsilon()], cases=cases, timeout=policy, repros=False, identify=False)
    hung = [r for r in results if r.status == "error"]
    assert hung and all(r.message == "timeout: no answer within 0.3 s, nor within 0.6 s when asked again" for r in hung), \
        [r.message for r in hung]


class _FrameFaults:
    """centre_scanline, except on a scene whose first vertex x is 7 (it raises), 8 (it
    hangs) or 9 (its process dies)."""

    name = "frame_faults"

    def __init__(self):
        from rasterizers.centre_scanline import CentreScanline

        self.inner = CentreScanline()
        self.convention = self.inner.convention

    def rasterize(self, scene):
        import os
        import time

        fault = scene.positions[0, 0, 0]
        if fault == 7:
            raise ValueError("frame seven")
        if fault == 8:
            time.sleep(3600)
        if fault == 9:
            os._exit(3)
        return self.inner.rasterize(scene)


def test_frames_in_one_go_keep_each_call_limit_and_the_worker_in_step():
    """Worker.rasterize_all (a motion case's frames sent at once, answered one by one): the
    answers equal one call each, stop at the first error, a hang is a timeout within that
    frame's limit, a death is an error; after each the worker answers the next call right."""
    import time

    from harness.contract.scenes import Scene
    from harness.engine.isolation import InProcess, TimeLimit, Worker

    def frame(x):
        return Scene(16, 16, [[[x, 1.0], [x + 6.5, 2.0], [x + 1.0, 9.5]]])

    plain = [frame(x) for x in (0.25, 1.5, 2.75, 3.0, 4.5, 5.0, 6.25)]
    with Worker(_FrameFaults(), TimeLimit(cap=30.0, base=0.5, rate=0.0)) as worker:
        inline = InProcess(_FrameFaults())
        assert [o.coverage for o in worker.rasterize_all(plain)] == [o.coverage for o in inline.rasterize_all(plain)]
        for fault, words in ((7, "ValueError"), (8, "TimeoutError"), (9, "died")):
            start = time.monotonic()
            outcomes = worker.rasterize_all([plain[0], frame(fault), plain[1]])
            assert len(outcomes) == 2 and outcomes[0].coverage is not None and outcomes[1].coverage is None
            assert words in f"{type(outcomes[1].error).__name__}: {outcomes[1].error}", outcomes[1].error
            assert time.monotonic() - start < 10  # the frame's limit and one retry (0.5 + 2 s), not the 30 s cap
            assert worker.rasterize(plain[2]).coverage == inline.rasterize(plain[2]).coverage  # in step


HARNESS_KILLED_MID_CALL = """
import sys, time
from harness.contract.scenes import Scene
from harness.engine.isolation import Worker

class Stuck:
    name = "stuck"
    convention = None

    def rasterize(self, scene):
        time.sleep(600)

worker = Worker(Stuck(), timeout=600.0)
worker.rasterize(Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]]))  # never returns
"""


def test_a_killed_harness_leaves_no_rasterizer_process_behind(tmp_path):
    """The harness killed (SIGKILL: no cleanup runs) while its isolated rasterizer is in a
    call that never returns: the rasterizer's process sees its parent gone and exits."""
    import os
    import signal
    import time

    script = tmp_path / "stuck.py"
    script.write_text(HARNESS_KILLED_MID_CALL)
    harness = subprocess.Popen([sys.executable, str(script)], cwd=os.getcwd(), env={**os.environ, "PYTHONPATH": os.getcwd()})
    try:
        children: list[int] = []
        deadline = time.monotonic() + 60
        while not children and time.monotonic() < deadline:  # the isolated process, once forked
            time.sleep(0.2)
            found = subprocess.run(["pgrep", "-P", str(harness.pid)], capture_output=True, text=True).stdout.split()
            children = [int(pid) for pid in found]
        assert children, "the harness forked no rasterizer process"
        time.sleep(1.0)  # the call is under way
        os.kill(harness.pid, signal.SIGKILL)
        harness.wait()
        deadline = time.monotonic() + 10
        alive = children
        while alive and time.monotonic() < deadline:
            time.sleep(0.2)
            alive = [pid for pid in children if os.path.exists(f"/proc/{pid}") and "zombie" not in _state(pid)]
        assert not alive, f"rasterizer processes {alive} outlived their killed harness"
    finally:
        if harness.poll() is None:
            harness.kill()


def _state(pid: int) -> str:
    try:
        with open(f"/proc/{pid}/status") as status:
            return next((line for line in status if line.startswith("State:")), "").lower()
    except OSError:
        return "zombie"
