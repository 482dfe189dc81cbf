"""Scenes drawn ahead (harness.engine.isolation.Worker.prefetch): a campaign sends a batch's
scenes to the isolated rasterizer at once, and every answer must be the one a call of its
own gives -- whatever the rasterizer does on one of them (raises, crashes, hangs) -- and
every scene the checks hand the rasterizer must be among those planned
(harness.engine.session.planned_scenes), so that nothing is drawn twice."""

from __future__ import annotations

import os
import time
from typing import Any

import numpy as np
import pytest

from cases.fuzz import generate
from harness.campaign.state import Batch, CampaignTask
from harness.campaign.worker import run_batch
from harness.contract.case import Case, MotionCase
from harness.contract.coverage import Coverage
from harness.contract.scenes import AnyScene, Scene, scene_digest
from harness.engine import ledger
from harness.engine.isolation import Outcome, TimeLimit, Worker
from harness.engine.session import Session, check_case, check_motion, planned_scenes
from rasterizers.centre_scanline import CentreScanline
from rasterizers.pineda_topleft import PinedaTopLeft

SMALL = Scene(16, 16, [[[0.25, 1.0], [6.75, 2.0], [1.0, 9.5]]])


@pytest.fixture(scope="module", autouse=True)
def warm() -> None:
    """Compile the kernels here, so every forked worker inherits them."""
    CentreScanline().rasterize(SMALL)
    PinedaTopLeft().rasterize(SMALL)


def _scenes(n: int) -> list[Scene]:
    rng = np.random.default_rng(7)
    return [Scene(32, 32, rng.uniform(-2.0, 34.0, size=(3, 3, 2))) for _ in range(n)]


def _same(a: Outcome, b: Outcome) -> bool:
    if a.coverage is None or b.coverage is None:
        return a.coverage is None and b.coverage is None and type(a.error) is type(b.error)
    return all(np.array_equal(getattr(a.coverage, f), getattr(b.coverage, f)) for f in ("primitive", "y", "x0", "x1"))


def test_answers_drawn_ahead_are_the_answers_of_calls_of_their_own() -> None:
    scenes = _scenes(12)
    with Worker(CentreScanline()) as alone:
        direct = [alone.rasterize(s) for s in scenes]
    with Worker(CentreScanline()) as worker:
        worker.rasterize(SMALL)  # the kind's first call goes alone
        assert worker.prefetch(scenes) == len(scenes)
        # asked out of order, one twice (the second drawn anew), one scene never sent ahead in between
        order = [3, 0, 1, 11, 2, 3]
        got = [worker.rasterize(scenes[k]) for k in order[:3]]
        got.append(worker.rasterize(SMALL))
        got += [worker.rasterize(scenes[k]) for k in order[3:]]
        assert all(_same(g, direct[k]) for g, k in zip(got[:3] + got[4:], order, strict=True))
        assert got[3].coverage is not None
        worker.forget_prefetched()
        assert not worker._pending and not worker._ready
        # the pipe is in step afterwards
        assert _same(worker.rasterize(scenes[5]), direct[5])


def test_a_scene_of_a_kind_not_answered_yet_is_not_sent_ahead() -> None:
    with Worker(CentreScanline()) as worker:
        assert worker.prefetch(_scenes(3)) == 0  # the first call of a kind may compile: it goes alone, with its own limit
        assert worker.rasterize(_scenes(1)[0]).coverage is not None


class RaisesOnSecond(CentreScanline):
    """Raises on any scene whose first vertex has x == 99 (so that the scene can say)."""

    name = "raises_on_marked"

    def rasterize(self, scene: Scene) -> Coverage:
        if scene.positions[0, 0, 0] == 99.0:
            raise ValueError("marked scene")
        return super().rasterize(scene)


class CrashesOnMarked(CentreScanline):
    name = "crashes_on_marked"

    def rasterize(self, scene: Scene) -> Coverage:
        if scene.positions[0, 0, 0] == 99.0:
            os._exit(3)
        return super().rasterize(scene)


class HangsOnMarked(CentreScanline):
    name = "hangs_on_marked"

    def rasterize(self, scene: Scene) -> Coverage:
        if scene.positions[0, 0, 0] == 99.0:
            time.sleep(60)
        return super().rasterize(scene)


def _marked() -> Scene:
    return Scene(32, 32, [[[99.0, 1.0], [6.75, 2.0], [1.0, 9.5]]])


@pytest.mark.parametrize("rasterizer, error", [(RaisesOnSecond(), "marked scene"), (CrashesOnMarked(), "died"),
                                               (HangsOnMarked(), "no answer within")])
def test_a_failing_scene_among_those_drawn_ahead_fails_alone(rasterizer: Any, error: str) -> None:
    scenes = _scenes(4)
    batch = [scenes[0], _marked(), scenes[1], scenes[2]]
    with Worker(CentreScanline()) as alone:
        direct = [alone.rasterize(s) for s in scenes]
    limits = TimeLimit(cap=60.0, base=0.5, rate=0.0, retry=2.0)
    with Worker(rasterizer, limits) as worker:
        worker.rasterize(SMALL)
        worker.prefetch(batch)
        # asked for in order: the one before it answered, the marked one fails as a call of its own would,
        # and every one after it is answered all the same (drawn anew when the worker was replaced)
        first = worker.rasterize(scenes[0])
        marked = worker.rasterize(_marked())
        rest = [worker.rasterize(scenes[1]), worker.rasterize(scenes[2])]
    assert _same(first, direct[0])
    assert marked.coverage is None and error in str(marked.error)
    if error == "no answer within":
        assert marked.timed_out and marked.retried is not None  # cut off, asked again alone, cut off again
    assert _same(rest[0], direct[1]) and _same(rest[1], direct[2])


def test_a_sequence_of_frames_drawn_ahead_is_read_from_them() -> None:
    frames = _scenes(5)
    with Worker(CentreScanline()) as worker:
        worker.rasterize(SMALL)
        worker.prefetch(frames)
        outcomes = worker.rasterize_all(frames)
        assert not worker._pending and not worker._ready  # every frame taken from those drawn ahead
        assert len(outcomes) == 5 and all(o.coverage is not None for o in outcomes)


def _recorded(session_call: Any, asked: list[bytes]) -> Any:
    def call(scene: AnyScene) -> Outcome:
        asked.append(scene_digest(scene))
        outcome: Outcome = session_call(scene)
        return outcome

    return call


@pytest.mark.parametrize("family", ["lattice", "float", "partitions", "meshes", "degenerate", "motion", "tall"])
def test_the_scenes_planned_are_those_the_checks_hand_the_rasterizer(family: str) -> None:
    """Every call the checks make on a passing rasterizer's case is planned (and nothing
    planned goes unasked): a campaign's scenes drawn ahead are exactly the ones needed."""
    rasterizer = PinedaTopLeft()
    with Session(rasterizer, isolate=False) as session:
        for index in range(6):
            case = generate(family, 0, index)
            asked: list[bytes] = []
            call = _recorded(session.call, asked)
            if isinstance(case, MotionCase):
                check_motion(case, rasterizer, call)
            else:
                assert isinstance(case, Case)
                check_case(case, rasterizer, call)
            planned = [scene_digest(s) for s in planned_scenes(case, rasterizer)]
            first = case.frames[0] if isinstance(case, MotionCase) else case.scene
            if session.call(first).coverage is None:  # refused (a non-finite triangle): no check asks for more
                assert asked == planned[:1], (family, index)
            else:
                assert sorted(asked) == sorted(planned), (family, index)


class DrawsOneSpanShort(PinedaTopLeft):
    """A known-bad: drops the last pixel of every span of a 2nd triangle onwards."""

    name = "one_span_short"

    def rasterize(self, scene: Scene) -> Coverage:
        cov = super().rasterize(scene)
        x1 = np.where(cov.primitive > 0, np.maximum(cov.x1 - 1, cov.x0), cov.x1)
        return Coverage(cov.primitive, cov.y, cov.x0, x1)


def test_a_batch_finds_the_same_with_and_without_scenes_drawn_ahead(monkeypatch: pytest.MonkeyPatch) -> None:
    spec = f"{__name__}:DrawsOneSpanShort"
    task = CampaignTask(spec, Batch("lattice", 0, 0, 8), timeout=60.0)
    ahead = run_batch(task)
    monkeypatch.setattr(Worker, "prefetch", lambda self, scenes: 0)
    alone = run_batch(task)
    assert ahead.findings and ahead.findings == alone.findings
    assert ahead.scenes == alone.scenes == 8 and ahead.primitives == alone.primitives
    # where the time went: exclusive sections that add up to no more than the batch
    sections = {k: v for k, v in ahead.sections.items() if not k.startswith("note:")}
    assert {"generation", "isolation", "check:conformance", "oracle"} <= set(sections)
    assert sum(sections.values()) <= ahead.sections["note:batch"] + 1e-6


def test_the_ledger_keeps_exclusive_time_and_costs_nothing_outside(monkeypatch: pytest.MonkeyPatch) -> None:
    ticks = iter(range(100))
    monkeypatch.setattr(ledger, "_clock", lambda: float(next(ticks)))  # each reading one second later: no timing
    assert ledger.active() is None
    with ledger.section("anything"):  # no ledger kept: nothing recorded, nothing raised
        pass
    with ledger.keeping() as kept:
        with ledger.section("outer"):  # t0
            with ledger.section("inner"):  # t1 .. t2
                pass
            with ledger.section("outer"):  # t3 .. t4: re-entered, still its own
                pass
        ledger.note("rasterizer", 1.5)  # the outer section ended at t5
    assert ledger.active() is None
    assert kept.seconds == {"outer": 4.0, "inner": 1.0}  # outer: (1 - 0) + (3 - 2) + (4 - 3) + (5 - 4)
    assert kept.notes == {"rasterizer": 1.5}


def test_answers_larger_than_the_pipe_and_a_second_prefetch_do_not_block() -> None:
    """Hundreds of answers of thousands of spans each (megabytes: far beyond a pipe's
    buffer), asked for last first, and more scenes sent ahead while answers are on their way."""
    big = [Scene(512, 512, [[[0.5 + k * 1e-3, 0.0], [512.0, 0.25], [0.0, 512.0]]]) for k in range(150)]
    with Worker(CentreScanline()) as worker:
        worker.rasterize(SMALL)
        worker.prefetch(big[:100])
        worker.prefetch(big[100:])  # while the first hundred are on their way
        last = worker.rasterize(big[-1])
        first = worker.rasterize(big[0])
        assert last.coverage is not None and first.coverage is not None and len(first.coverage) == 512
        worker.forget_prefetched()
        assert worker.rasterize(big[3]).coverage is not None
