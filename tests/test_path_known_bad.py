"""Each known-bad path filler fails conformance on a named path case where the reference
passes, and passes a control case its bug does not touch (so the failure is the bug's)."""

from __future__ import annotations

import pytest

from harness.api import PathScene
from harness.case import Case
from harness.runner import run_suite
from rasterizers.trapezoid import TrapezoidFill
from tests.known_bad.paths import BUGS, PathFillBug

SIZE = 8
# All on the 1/4 lattice: float arithmetic is exact, no deviation passes for rounding.
PENTAGRAM = [[4, 0.25], [6.25, 7.5], [0.25, 2.75], [7.75, 2.75], [1.75, 7.5]]
OUTER = [[0.25, 0.25], [7.75, 0.25], [7.75, 7.75], [0.25, 7.75]]
HOLE = [[2.25, 2.25], [5.75, 2.25], [5.75, 5.75], [2.25, 5.75]]
ROW_RECTANGLE = [[1, 0.5], [5, 0.5], [5, 4.5], [1, 4.5]]  # top and bottom edges on sample rows 0 and 4
ROW_DIAMOND = [[4, 0.25], [7.25, 3.5], [4, 6.75], [0.75, 3.5]]  # side vertices on sample row 3
TRIANGLE = [[0.5, 0.25], [7.25, 2.75], [2.25, 7.5]]
QUAD = [[1.25, 0.75], [6.75, 1.25], [7.25, 6.25], [0.75, 7.25]]  # no vertex or horizontal edge on a sample row


def _case(name: str, contours: list, fill_rule: str) -> Case:  # type: ignore[type-arg]
    return Case(f"paths/{name}/{fill_rule}", PathScene.from_paths(SIZE, SIZE, [contours], fill_rule), lattice=True)


CASES = {
    "pentagram": _case("pentagram", [PENTAGRAM], "nonzero"),
    "pentagram-evenodd": _case("pentagram", [PENTAGRAM], "evenodd"),
    "ring-same": _case("ring-same", [OUTER, HOLE], "nonzero"),
    "ring-opposite": _case("ring-opposite", [OUTER, HOLE[::-1]], "nonzero"),
    "ring-opposite-evenodd": _case("ring-opposite", [OUTER, HOLE[::-1]], "evenodd"),
    "row-rectangle": _case("row-rectangle", [ROW_RECTANGLE], "evenodd"),
    "row-diamond": _case("row-diamond", [ROW_DIAMOND], "evenodd"),
    "quad": _case("quad", [QUAD], "evenodd"),
    "triangle": _case("triangle", [TRIANGLE], "nonzero"),
}

# bug -> (cases where it must fail, control cases where it must pass)
SHOWS = {
    "evenodd-for-nonzero": (["pentagram", "ring-same"], ["pentagram-evenodd", "ring-opposite", "quad"]),
    "unsigned-crossings": (["pentagram", "ring-opposite"], ["ring-same", "pentagram-evenodd", "ring-opposite-evenodd"]),
    "horizontal-crossings": (["row-rectangle"], ["row-diamond", "pentagram", "ring-opposite"]),
    "inclusive-ends": (["row-diamond", "row-rectangle"], ["quad", "pentagram", "ring-opposite"]),
    "open-contours": (["triangle", "pentagram", "ring-opposite"], []),
    "first-contour-only": (["ring-opposite", "ring-opposite-evenodd"], ["triangle", "pentagram", "ring-same", "quad"]),
    "contours-apart": (["ring-opposite", "ring-opposite-evenodd"], ["triangle", "pentagram", "ring-same", "quad"]),
}


def _verdicts(rasterizer: object, names: list[str]) -> dict[str, str]:
    results = run_suite([rasterizer], cases=[CASES[n] for n in names], isolate=False, identify=False,  # type: ignore[list-item]
                        repros=False, only={"conformance"})
    by_id = {r.case: r for r in results if r.check == "conformance"}
    assert len(by_id) == len(names), [(r.case, r.check, r.status, r.message) for r in results]
    return {n: by_id[CASES[n].id].status for n in names}


def test_every_bug_is_covered() -> None:
    assert set(SHOWS) == set(BUGS)


def test_the_reference_passes_every_case() -> None:
    assert set(_verdicts(TrapezoidFill(), list(CASES)).values()) == {"pass"}


@pytest.mark.parametrize("bug", BUGS)
def test_known_bad_fails_conformance(bug: str) -> None:
    fails, passes = SHOWS[bug]
    verdicts = _verdicts(PathFillBug(bug), fails + passes)
    assert {n: verdicts[n] for n in fails} == dict.fromkeys(fails, "fail")
    assert {n: verdicts[n] for n in passes} == dict.fromkeys(passes, "pass")


def test_known_bads_declare_the_reference_convention() -> None:
    for bug in BUGS:
        bad = PathFillBug(bug)
        assert bad.convention == TrapezoidFill.convention and bad.scene_kinds == TrapezoidFill.scene_kinds
    with pytest.raises(ValueError, match="bug"):
        PathFillBug("none")
