"""Each known-bad path filler fails conformance on a named path case where the reference
passes, and passes a control case its bug does not touch (so the failure is the bug's)."""

from __future__ import annotations

import numpy as np
import pytest

from cases.paths import DEEP_WINDINGS, deep_winding
from harness.checks import conformance
from harness.contract.case import Case
from harness.contract.coverage import Coverage
from harness.contract.scenes import PathScene
from harness.engine.runner import run_suite
from harness.oracle.coverage import exact_coverage
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


def _case(name: str, contours: list, fill_rule: str) -> Case:
    return Case(f"paths/{name}/{fill_rule}", PathScene.from_paths(SIZE, SIZE, [contours], fill_rule), lattice=True)


# the deep-winding cases (16 x 16 px): windings N, N - 1 and 1
DEEP = {f"deep-{turns}{'' if rule == 'nonzero' else '-evenodd'}": Case(f"paths/deep-winding/{turns}/{rule}",
                                                                       deep_winding(turns, rule), lattice=True)
        for turns in DEEP_WINDINGS for rule in ("nonzero", "evenodd")}

CASES = {
    **DEEP,
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
    # a wrap adds a multiple of 2**bits: only a nonzero winding that is such a multiple
    # reads as 0, and parity never changes
    "int8-winding": (["deep-256", "deep-65536"], ["deep-128", "deep-128-evenodd", "deep-256-evenodd", "deep-65536-evenodd",
                                                  "pentagram", "ring-same"]),
    "int16-winding": (["deep-65536"], ["deep-128", "deep-256", "deep-65536-evenodd", "pentagram"]),
    # a saturated counter is off by the crossings it dropped: wrong from 128 on, either rule
    "int8-saturating": (list(DEEP), ["pentagram", "pentagram-evenodd", "ring-same", "ring-opposite"]),
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


def test_the_deep_winding_cases_wind_that_deep_and_cannot_be_passed_by_drawing_nothing() -> None:
    """Each deep-winding case has samples of winding N, N - 1 and 1 (counted here edge by
    edge: no sample lies on an edge), and drawing nothing, only the square or only the
    deep triangle fails it: no deep-winding case passes vacuously."""
    for name, case in DEEP.items():
        assert isinstance(case.scene, PathScene)
        turns = int(name.split("-")[1])
        assert case.scene.vertices.shape[0] == 3 * turns + 1
        a, b, _ = case.scene.edges()
        for (px, py), winding in (((1.5, 1.5), turns - 1), ((3.5, 3.5), turns), ((5.5, 5.5), 1), ((0.5, 6.5), 0)):
            crosses = (a[:, 1] <= py) != (b[:, 1] <= py)
            at = a[crosses, 0] + (py - a[crosses, 1]) * (b[crosses, 0] - a[crosses, 0]) / (b[crosses, 1] - a[crosses, 1])
            down = np.sign(b[crosses, 1] - a[crosses, 1])
            assert abs(int(down[at < px].sum())) == winding, (name, px, py)
        oracle = exact_coverage(case.scene, TrapezoidFill.convention)
        assert oracle.n_pixels >= 16, name
        assert conformance(case, Coverage.empty(), oracle, TrapezoidFill.convention).status == "fail", name
        for contour in case.scene.contours():
            part = PathScene.from_paths(case.scene.width, case.scene.height, [[contour]], case.scene.fill_rule)
            alone = exact_coverage(part, TrapezoidFill.convention)
            assert conformance(case, alone, oracle, TrapezoidFill.convention).status == "fail", name
    # the rules part where the winding is even (N): nonzero fills it, even-odd leaves it
    nonzero, evenodd = (exact_coverage(DEEP[n].scene, TrapezoidFill.convention) for n in ("deep-256", "deep-256-evenodd"))
    assert 0 < evenodd.n_pixels < nonzero.n_pixels


def test_the_winding_fuzz_family_catches_wrapping_counters() -> None:
    """On the first winding fuzz scenes, fillers whose winding counter wraps in 8 or 16
    bits fail conformance where the reference passes (the family's campaigns find them)."""
    from cases.fuzz import generate

    winding = [generate("winding", 5, index) for index in range(12)]

    def failing(rasterizer: object) -> set[str]:
        results = run_suite([rasterizer], cases=winding, isolate=False, identify=False, repros=False,  # type: ignore[list-item]
                            only={"conformance"})
        assert len(results) == len(winding), [(r.case, r.check, r.status) for r in results]
        return {r.case for r in results if r.status != "pass"}

    assert not failing(TrapezoidFill())
    wrapped = {bits: failing(PathFillBug(f"int{bits}-winding")) for bits in (8, 16)}
    assert wrapped[16] and wrapped[16] < wrapped[8]  # what wraps in 16 bits wraps in 8, and more does
