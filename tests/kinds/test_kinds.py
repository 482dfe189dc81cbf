"""The primitive kinds (harness.kinds): one object per kind, every hook set, and the harness
asking the kind rather than switching on scene classes."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from harness.contract.case import Case, case_from_json, case_to_json
from harness.contract.conventions import Convention
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene
from harness.kinds import HOOKS, KINDS, LINES, PATHS, SCENE_KINDS, TRIANGLES, PrimitiveKind, kind_named, kind_of, kind_of_json
from harness.kinds.points import PointScene
from tests.narrow import still

TRIANGLE = Scene(8, 8, [[[1, 1], [7, 1], [1, 7]]])
PATH = PathScene.from_paths(8, 8, [[[[1, 1], [7, 1], [7, 7], [1, 7]]]])
LINE = LineScene.from_segments(8, 8, [[1, 1]], [[7, 3]])
SCENES: dict[str, AnyScene] = {"triangles": TRIANGLE, "paths": PATH, "lines": LINE,
                               "points": PointScene(8, 8, [[2.0, 3.5]], point_size=2.0)}


def test_every_scene_kind_has_a_kind_with_every_hook_set():
    assert tuple(KINDS) == SCENE_KINDS
    for name in SCENE_KINDS:
        kind = KINDS[name]
        assert kind.name == name and kind.scene_class.kind == name
        assert kind.missing_hooks() == [], (name, kind.missing_hooks())
        assert all(callable(kind.hook(h)) for h in HOOKS)


def test_a_kind_missing_a_hook_fails_the_check():
    # a hook naming nothing that exists: caught by missing_hooks (the test above fails for it)
    broken = replace(TRIANGLES, oracle="harness.oracle.coverage:no_such_oracle", _resolved={})
    assert broken.missing_hooks() == ["oracle"]
    gone = replace(TRIANGLES, still_pictures="harness.report.no_such_module:fill_pictures", _resolved={})
    assert gone.missing_hooks() == ["still_pictures"]
    # a hook left unnamed, or not "module:function", is refused when the kind is built
    with pytest.raises(ValueError, match="hook probes"):
        replace(TRIANGLES, probes="", _resolved={})
    with pytest.raises(ValueError, match="hook oracle"):
        replace(PATHS, oracle=None, _resolved={})  # type: ignore[arg-type]  # an unnamed hook: refused


def test_kind_of_each_scene_and_of_its_json():
    for name, scene in SCENES.items():
        kind = kind_of(scene)
        assert kind is KINDS[name] and kind_named(name) is kind and kind.owns(scene)
        assert [k.name for k in KINDS.values() if k.owns(scene)] == [name]
        assert kind.narrow(scene) is scene
        assert kind_of_json(case_to_json(Case("x/0", scene))) is kind
    with pytest.raises(ValueError, match="lines code handed a triangles scene"):
        LINES.narrow(TRIANGLE)
    with pytest.raises(ValueError, match="no scene kind 'curves'"):
        kind_named("curves")


def test_the_codec_round_trips_through_the_kind():
    for scene in SCENES.values():
        back = still(case_from_json(case_to_json(Case("x/0", scene)))).scene
        assert type(back) is type(scene) and np.array_equal(back.coordinates, scene.coordinates)


def test_the_hooks_answer_as_the_kind_says():
    from harness.oracle.coverage import exact_coverage

    convention = Convention()
    for scene in SCENES.values():
        kind = kind_of(scene)
        drawn = kind.hook("oracle")(scene, convention)
        assert drawn.n_pixels == exact_coverage(scene, convention).n_pixels > 0
        variants = kind.hook("invariance_variants")(scene, 0)
        assert variants and all(v.kind == scene.kind for _, v, _ in variants)
        assert [c.shape[-1] for c in kind.coordinates_of(scene, np.arange(len(scene)))] == [2] * len(scene)
    # the degenerate test: a flat triangle, a zero-length segment; never a path
    flat = {0: np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])}
    assert TRIANGLES.degenerate(TRIANGLE, flat) == {0}
    assert LINES.degenerate(LINE, {0: np.array([[3.0, 3.0], [3.0, 3.0]])}) == {0}
    assert PATHS.degenerate(PATH, flat) == set()
    assert LINES.translate_shift == (4, 2) and TRIANGLES.translate_shift == PATHS.translate_shift == (3, 2)


def test_a_hook_resolves_once():
    kind = replace(PATHS, _resolved={})
    first = kind.hook("near_ties")
    assert kind._resolved == {"near_ties": first} and kind.hook("near_ties") is first
    with pytest.raises(KeyError, match="no hook 'picture'"):
        kind.hook("picture")


def test_a_kind_is_a_frozen_record():
    assert isinstance(TRIANGLES, PrimitiveKind)
    with pytest.raises(AttributeError):
        TRIANGLES.name = "points"  # type: ignore[misc]


# --- no isinstance switches on scene classes outside the kinds ------------------------------

SWITCH = re.compile(r"isinstance\(.*\b(?:Scene|PathScene|LineScene)\b")
# the kinds own their classes; the adapters dispatch on what a library takes (rasterizers/, not harness/)
EXEMPT = ("kinds/",)
MOST = 5


def _switches() -> list[str]:
    root = Path(__file__).resolve().parents[2] / "harness"
    found = []
    for path in sorted(root.rglob("*.py")):
        name = path.relative_to(root).as_posix()
        if name.startswith(EXEMPT):
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if SWITCH.search(line):
                found.append(f"harness/{name}:{number}: {line.strip()}")
    return found


def test_the_pattern_finds_the_switches_it_counts():
    for line in ("if isinstance(scene, PathScene):", "assert isinstance(s.case.scene, LineScene)",
                 "ok = isinstance(getattr(case, 'scene', None), Scene)", "isinstance(scene, (Scene, PathScene))"):
        assert SWITCH.search(line), line
    for line in ("if PATHS.owns(scene):", "scene = LINES.narrow(scene)", "isinstance(coverage, Coverage)",
                 "isinstance(case, MotionCase)", "if kind_of(scene).own_fit:"):
        assert not SWITCH.search(line), line


def test_the_harness_asks_the_kind_not_the_scene_class():
    found = _switches()
    assert len(found) <= MOST, "isinstance switches on scene classes (ask harness.kinds):\n" + "\n".join(found)


def test_the_kinds_import_only_the_scene_contract():
    """Every layer may ask a kind: the package imports the scenes (and the exact orientation),
    and names every higher hook by a string."""
    root = Path(__file__).resolve().parents[2] / "harness" / "kinds"
    imported = set()
    for path in root.glob("*.py"):
        imported |= set(re.findall(r"^\s*(?:from|import) (harness[\w.]*)", path.read_text(), re.M))
    assert imported <= {"harness.contract.scenes", "harness.geometry.exact", "harness.kinds.base", "harness.kinds.lines",
                        "harness.kinds.paths", "harness.kinds.triangles", "harness.kinds.points"}, imported
