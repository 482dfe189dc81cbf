"""What a test knows of a case or a scene, asserted, so that the type checker knows it too:
a still case, a motion case, a scene of triangles, paths or lines."""

from __future__ import annotations

from harness.contract.case import Case, MotionCase
from harness.contract.scenes import AnyScene, LineScene, PathScene, Scene


def still(case: Case | MotionCase) -> Case:
    assert isinstance(case, Case), case.id
    return case


def moving(case: Case | MotionCase) -> MotionCase:
    assert isinstance(case, MotionCase), case.id
    return case


def triangles(scene: AnyScene) -> Scene:
    assert isinstance(scene, Scene), scene.kind
    return scene


def paths(scene: AnyScene) -> PathScene:
    assert isinstance(scene, PathScene), scene.kind
    return scene


def lines(scene: AnyScene) -> LineScene:
    assert isinstance(scene, LineScene), scene.kind
    return scene
