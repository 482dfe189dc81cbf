"""harness.engine.session.Session: one loaded rasterizer with its worker, its calls and its checks."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from cases.motion import motion_cases
from harness.contract.case import Case
from harness.contract.scenes import Scene
from harness.engine.isolation import InProcess, TimeLimit, Worker
from harness.engine.session import Session
from rasterizers.centre_scanline import CentreScanline
from tests.known_bad.declarations import SingleWithSampleIds
from tests.known_bad.misc import HangsOnEpsilon, WrongTieClaim

TRIANGLE = Scene(8, 8, [[[0, 0], [8, 0], [0, 8]]])
# vertices on pixel centres, a lattice case (float arithmetic exact): which side owns a tie decides what is drawn
TIES = Case("session/ties", Scene(8, 8, [[[0.5, 0.5], [6.5, 0.5], [0.5, 6.5]], [[6.5, 0.5], [6.5, 6.5], [0.5, 6.5]]]),
            lattice=True)
THIN = Scene(8, 8, [[[0.0, 1.0], [8.0, 1 + 1e-8], [0.0, 1 + 2e-8]]])  # thinner than a micro-pixel: HangsOnEpsilon loops


def test_a_call_answers_in_the_worker_and_the_checks_judge_it() -> None:
    with Session(CentreScanline()) as session:
        assert isinstance(session.worker, Worker) and session.name == "centre_scanline"
        outcome = session.call(TRIANGLE)
        assert outcome.error is None and outcome.coverage is not None and len(outcome.coverage) > 0
        results = session.check(TIES)
        assert results and all(r.status == "pass" for r in results), [(r.check, r.message) for r in results]
        assert "conformance" in {r.check for r in results}
        judged = session.judge(TIES, "conformance")
        assert [(r.check, r.status) for r in judged] == [("conformance", "pass")]
        assert session.convention(TIES) == CentreScanline.convention


def test_judge_gives_the_one_check_a_wrong_declaration_fails() -> None:
    """The shrinker's question: the one check on a case, failing where the rasterizer breaks
    the rule it declares (a top-left drawer declaring bottom-right)."""
    with Session(WrongTieClaim(), isolate=False) as session:
        assert isinstance(session.worker, InProcess)
        judged = session.judge(TIES, "conformance")
        assert [(r.check, r.status) for r in judged] == [("conformance", "fail")], judged
        drawn = session.call(TIES.scene).coverage
        assert drawn is not None
        # the same verdict on an answer in hand, without a call
        assert [(r.check, r.status) for r in session.answered(TIES, drawn, "conformance")] == [("conformance", "fail")]


def test_a_motion_case_is_checked_on_all_its_frames() -> None:
    case = next(c for c in motion_cases(0) if len(c.frames) > 1)
    with Session(CentreScanline()) as session:
        results = session.check(case)
    assert results and all(r.status == "pass" for r in results), [(r.check, r.message) for r in results]


def test_a_refused_scene_kind_is_said_once_and_handed_no_more() -> None:
    """An answer contradicting the declaration (sample ids from a one-sample rasterizer) is
    one error naming the kind; the session hands it no more scenes of that kind. Without
    remembering refusals (a campaign), each scene is handed over and refused again."""
    other = Case("session/other", TRIANGLE)
    with Session(SingleWithSampleIds(), isolate=False) as session:
        first = session.check(TIES)
        assert [(r.check, r.status, r.evidence.get("refused")) for r in first] == [("run", "error", "triangles")]
        assert "no more triangles were handed to it" in first[0].message and "\n" not in first[0].message
        assert session.refused is not None and set(session.refused) == {"triangles"}
        assert session.check(other) == []
    with Session(SingleWithSampleIds(), isolate=False, remembers_refusals=False) as session:
        assert [r.evidence.get("refused") for r in session.check(TIES)] == ["triangles"]
        assert [r.evidence.get("refused") for r in session.check(other)] == ["triangles"]
        assert session.refused is None


def test_close_kills_the_worker_process() -> None:
    session = Session(CentreScanline())
    assert isinstance(session.worker, Worker)
    process = session.worker._process
    assert process.is_alive()
    session.close()
    assert not process.is_alive() and process.exitcode is not None
    with Session(CentreScanline()) as again:
        assert isinstance(again.worker, Worker)
        process = again.worker._process
        assert again.call(TRIANGLE).coverage is not None
    assert not process.is_alive()


def test_a_call_cut_off_by_its_limit_is_a_timeout_and_the_next_call_has_a_fresh_worker() -> None:
    """A hang is cut off (asked once more, then a timeout): its process is killed and the
    session's next call is answered by a fresh worker."""
    limits = TimeLimit(cap=5.0, base=0.5, retry=1.0, first=0.5)
    with Session(HangsOnEpsilon(), limits) as session:
        assert isinstance(session.worker, Worker)
        hung = session.worker._process
        outcome = session.call(THIN)
        assert outcome.timed_out and outcome.coverage is None and "no answer within" in str(outcome.error)
        assert not hung.is_alive()
        fresh = session.worker._process
        assert fresh.is_alive() and fresh.pid != hung.pid
        answered = session.call(TRIANGLE)
        assert answered.error is None and answered.coverage is not None
        assert np.array_equal(answered.coverage.y, CentreScanline().rasterize(TRIANGLE).y)
        # a check of a case that hangs is a timeout error, and the session goes on
        results = session.check(Case("session/thin", THIN), {"hygiene"})
        assert [(r.check, r.status) for r in results] == [("run", "error")] and results[0].message.startswith("timeout:")
        assert session.call(TRIANGLE).coverage is not None


@pytest.mark.parametrize("isolate", [True, False])
def test_a_session_closed_twice_is_closed_once(isolate: bool) -> None:
    session = Session(CentreScanline(), isolate=isolate)
    session.close()
    session.close()


PID_LOGGING = '''
import os
import time

from rasterizers.centre_scanline import CentreScanline

LOG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "pids.log")


class PidLogging(CentreScanline):
    """centre_scanline, logging the process of every call; it hangs on a 32 x 32 px scene
    (lattice/sub-pixel-triangles)."""

    name = "pid_logging"

    def rasterize(self, scene):
        with open(LOG, "a") as log:
            log.write(f"{os.getpid()}\\n")
        if scene.width == 32:
            time.sleep(600)
        return super().rasterize(scene)
'''


def test_the_pytest_plugin_keeps_one_worker_per_rasterizer_and_replaces_a_hung_one(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    """Every case of a rasterizer is drawn by one worker process (it started one per case);
    a case that hangs is cut off (asked again once, in a fresh process) and the next case
    is drawn by a fresh worker; the last worker is ended with the pytest session."""
    from tests.integrations.test_pytest_plugin import plugin_run_here

    plugin = tmp_path / "pid_logging.py"
    plugin.write_text(PID_LOGGING)
    proc = plugin_run_here(tmp_path, capsys, monkeypatch, "-q", "--rasterizer", f"{plugin}:PidLogging",
                           "--rastercheck-timeout", "1", "-k", "(lattice/ or float/random-50px) and conformance")
    assert proc.returncode == 1, proc.stdout[-3000:]
    assert "1 failed, 6 passed" in proc.stdout and "no answer within 1 s" in proc.stdout, proc.stdout[-3000:]
    pids = [int(line) for line in (tmp_path / "pids.log").read_text().split()]
    # bits-0, -2, -4, -8 and the hang's first ask in one worker; the ask again in a fresh one; the next
    # cases (lattice/first-half-pixel, float/random-50px) in another
    assert len(pids) == 8 and len(set(pids[:5])) == 1 and len(set(pids)) == 3 and pids[5] != pids[6] == pids[7], pids
    with pytest.raises(ProcessLookupError):
        os.kill(pids[-1], 0)  # closed (and reaped) when the pytest session ended


def test_a_check_that_cannot_judge_a_case_is_an_error_and_the_run_goes_on():
    """The harness's own failure (a check or its oracle raising: a convention it cannot judge
    the scene under) is an error result naming the check and the exception, not a crash of
    the run (the atlas once stopped on one)."""
    from types import SimpleNamespace

    from harness.engine.session import _judged

    class Raising:
        name = "accuracy"

        def verdict(self, subject):
            raise ValueError("anti-aliased lines are rectangles")

    case = Case("one/triangle", Scene(8, 8, [[[1.0, 1.0], [6.0, 1.0], [1.0, 6.0]]]))
    judged = _judged(Raising(), SimpleNamespace(case=case))  # type: ignore[arg-type]
    assert (judged.check, judged.status, judged.case) == ("accuracy", "error", "one/triangle")
    assert "ValueError: anti-aliased lines are rectangles" in judged.message
