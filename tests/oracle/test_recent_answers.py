"""The oracle's recent answers (harness.oracle.coverage.RECENT_ANSWERS): the same scene under the same
convention is answered once per process, anything that changes the answer is another key,
and the budget holds."""

from __future__ import annotations

import numpy as np
import pytest

from harness.contract.conventions import Convention
from harness.contract.scenes import LineScene, PathScene, Scene
from harness.oracle.coverage import RECENT_ANSWERS, _RecentAnswers, exact_coverage, scene_digest

TRIANGLE = [[[0.5, 0.5], [7.0, 1.0], [2.0, 6.5]]]


def test_the_same_scene_and_convention_is_answered_once() -> None:
    first = exact_coverage(Scene(8, 8, TRIANGLE), Convention())
    again = exact_coverage(Scene(8, 8, np.array(TRIANGLE)), Convention())  # another object, the same contents
    assert again is first
    assert not first.x0.flags.writeable  # shared, so read-only
    other = exact_coverage(Scene(8, 8, TRIANGLE), Convention(tie="bottom-right"))
    assert other is not first


@pytest.mark.parametrize("a, b", [
    (Scene(8, 8, TRIANGLE), Scene(9, 8, TRIANGLE)),
    (Scene(8, 8, TRIANGLE), Scene(8, 8, np.array(TRIANGLE) + 2.0**-40)),
    (Scene(8, 8, TRIANGLE), Scene(8, 8, TRIANGLE, attributes=np.ones((1, 3, 1)))),
    (Scene(8, 8, TRIANGLE, attributes=np.ones((1, 3, 1))), Scene(8, 8, TRIANGLE, attributes=np.ones((1, 3, 1)),
                                                                 w=np.array([[1.0, 2.0, 4.0]]))),
    (PathScene.from_paths(8, 8, [[TRIANGLE[0]]]), PathScene.from_paths(8, 8, [[TRIANGLE[0]]]).with_fill_rule("evenodd")),
    (LineScene.from_strips(8, 8, [TRIANGLE[0]]), LineScene.from_strips(8, 8, [TRIANGLE[0]], line_width=2.0)),
], ids=["width", "a last-bit move", "attributes", "w", "fill rule", "line width"])
def test_whatever_changes_the_answer_changes_the_key(a: object, b: object) -> None:
    assert scene_digest(a) != scene_digest(b)  # type: ignore[arg-type]


def test_the_kinds_never_share_a_key() -> None:
    path = PathScene.from_paths(8, 8, [[TRIANGLE[0]]])
    strip = LineScene.from_strips(8, 8, [TRIANGLE[0]])
    assert len({scene_digest(Scene(8, 8, TRIANGLE)), scene_digest(path), scene_digest(strip)}) == 3


def test_the_budget_holds_and_the_least_recent_goes_first() -> None:
    from harness.oracle.coverage import _footprint

    scenes = [Scene(64, 64, np.array(TRIANGLE) * 4 + [k, 0]) for k in range(12)]  # moved along x: the same size
    size = _footprint(exact_coverage(scenes[0], Convention()))
    answers = _RecentAnswers(budget=8 * size)  # 8 answers (an answer over an eighth of the budget is not kept)
    for k, scene in enumerate(scenes):
        answers.put((scene_digest(scene), Convention()), exact_coverage(scene, Convention()))
        if k == 7:
            assert answers.get((scene_digest(scenes[0]), Convention())) is not None  # now the most recent
    assert answers._bytes <= 8 * size
    assert answers.get((scene_digest(scenes[-1]), Convention())) is not None
    assert answers.get((scene_digest(scenes[0]), Convention())) is not None  # used at k == 7: kept
    assert answers.get((scene_digest(scenes[1]), Convention())) is None  # the least recently used went first
    nothing = _RecentAnswers(budget=0)  # RASTERCHECK_ORACLE_CACHE_MB=0
    nothing.put((scene_digest(scenes[0]), Convention()), exact_coverage(scenes[0], Convention()))
    assert nothing.get((scene_digest(scenes[0]), Convention())) is None
    assert RECENT_ANSWERS.budget > 0


def test_the_bench_times_the_oracle_computing_not_a_lookup(monkeypatch: pytest.MonkeyPatch) -> None:
    """Its repeats of one scene would otherwise time the cache (an oracle 260x "faster")."""
    from functools import partial

    import harness.oracle.coverage as oracle
    from harness.cli.bench import _measure_here

    computed = []
    real = oracle._exact_coverage

    def counting(scene: object, convention: Convention) -> object:
        computed.append(1)
        return real(scene, convention)  # type: ignore[arg-type]

    monkeypatch.setattr(oracle, "_exact_coverage", counting)
    scene = Scene(64, 64, np.array(TRIANGLE) * 8)
    exact_coverage(scene, Convention())  # kept before the bench starts: must not be reused either
    computed.clear()
    said = _measure_here(partial(exact_coverage, scene, Convention()), scene, 0.2, False, lambda message: None)
    assert said[0] == "done" and said[4] >= 2, said
    assert len(computed) == said[4] + 1  # every run computed its answer (and the cold call before them)
    assert RECENT_ANSWERS.budget > 0  # and the cache is back on after


def test_a_large_scene_is_not_kept_nor_hashed(monkeypatch: pytest.MonkeyPatch) -> None:
    """Hashing reads every byte: past KEPT_SCENE_BYTES the oracle computes at once (a
    10,000-triangle workload spent a third of its time in the digest)."""
    import harness.oracle.coverage as oracle

    rng = np.random.default_rng(0)
    big = Scene(256, 256, rng.uniform(0, 256, (2000, 3, 2)))
    assert big.positions.nbytes > oracle.KEPT_SCENE_BYTES
    hashed = []

    def digest(scene):
        hashed.append(scene)
        return b""

    monkeypatch.setattr(oracle, "scene_digest", digest)
    assert exact_coverage(big, Convention()) is not exact_coverage(big, Convention())
    assert not hashed
    small = Scene(8, 8, TRIANGLE)
    exact_coverage(small, Convention(tie="top-right"))
    assert hashed == [small]
