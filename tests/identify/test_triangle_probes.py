"""identify's direct probes (vertex sweep; the viewport edge, epsilon and non-finite probes are
tests/identify/test_triangle_defects.py), the repro probes that say why a
failure happens (viewport edge, input precision), coverage-only rasterizers, and the
side-by-side fingerprint page: each shown to fire on a known-bad rasterizer and to stay
quiet on correct ones."""

import functools
import json

import numpy as np
import pytest

from cases.meshes import mesh_cases
from cases.motion import motion_cases
from cases.partitions import partition_cases
from cases.suites import conformance_cases
from harness.checks import watertight
from harness.contract.conventions import Convention, snap
from harness.engine.isolation import InProcess
from harness.engine.registry import load
from harness.engine.runner import run_suite
from harness.identify.fingerprint import identify
from harness.identify.triangle_probes import vertex_sweep
from tests.identify.test_fingerprint import BlackBox
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.known_bad.misc import ClipsBeforeSnapping, DropsAttributes, Float32Input, NaNAttributes
from tests.narrow import still, triangles


def test_snap_can_round_down():
    values = np.array([0.125, 0.375, -0.125, 1.0 / 3.0])
    assert snap(values, 2, "floor").tolist() == [0.0, 0.25, -0.25, 0.25]
    assert repr(Convention(subpixel_bits=6, snap_rounding="floor")).endswith("snap_rounding='floor')")
    assert "rounding down" in Convention(subpixel_bits=6, snap_rounding="floor").describe()
    with pytest.raises(ValueError, match="snap_rounding"):
        Convention(snap_rounding="up")  # type: ignore[arg-type]  # no such rounding: refused


@pytest.mark.parametrize("hidden, grid", [
    (Convention(subpixel_bits=8), 9),
    (Convention(tie="bottom-right", subpixel_bits=6, snap_rounding="floor"), 6),
    (Convention(sample=(1.0, 1.0), subpixel_bits=2), 3),
    (Convention(), None),
], ids=str)
def test_vertex_sweep_finds_the_snapping_grid(hidden, grid):
    sweep = vertex_sweep(InProcess(BlackBox(hidden)))
    assert sweep.located >= 12 and sweep.grid == grid


def test_identify_recovers_snapping_that_rounds_down():
    hidden = Convention(tie="bottom-right", subpixel_bits=6, snap_rounding="floor")
    fingerprint = identify(BlackBox(hidden))
    assert fingerprint.convention == hidden and fingerprint.exact, fingerprint.card()
    assert "agrees with the fit" in fingerprint.facts["vertex sweep"]


def test_repros_say_when_a_failure_lives_at_the_viewport_edge():
    cases = [c for c in conformance_cases(0) if c.id.startswith("lattice/bits-")]
    # conformance alone: its failures are the ones judged here (shrinking the invariance
    # failures too would cost six times as much and prove nothing more)
    results = run_suite([ClipsBeforeSnapping()], cases=cases, isolate=False, repro_seconds=60, only={"conformance"})
    failed = [r for r in results if r.status == "fail" and r.check == "conformance"]
    assert failed
    assert all("viewport_edge" in r.evidence and "cross the viewport edge" in r.message for r in failed)
    # an exact rasterizer fails nowhere, so the probe has nothing to say
    assert all(r.status in ("pass", "skip") for r in run_suite([load("fixed_point")], cases=cases, isolate=False))


def test_repros_say_when_a_failure_comes_from_the_input_format():
    cases = [c for c in conformance_cases(0) if c.id == "float/near-ties-1e-6"]
    told = [r for r in run_suite([Float32Input(tell=True)], cases=cases, isolate=False) if r.check == "conformance"]
    silent = [r for r in run_suite([Float32Input(tell=False)], cases=cases, isolate=False) if r.check == "conformance"]
    assert told[0].status == "fail" and "input_precision" in told[0].evidence and "input format" in told[0].message
    assert silent[0].status == "fail" and "input_precision" not in silent[0].evidence


def test_a_coverage_only_rasterizer_says_so_or_fails():
    mesh = [c for c in mesh_cases(0) if c.scene.attributes is not None][:1]
    textured = [c for c in motion_cases(0) if c.texels][:1]
    assert mesh and textured
    declared = run_suite([DropsAttributes(declares=True)], cases=[*mesh, *textured], isolate=False)
    silent = run_suite([DropsAttributes(declares=False)], cases=[*mesh, *textured], isolate=False)
    by = lambda results, check: [r for r in results if r.check == check]  # noqa: E731
    assert all(r.status == "pass" and "as it declares" in r.message for r in by(declared, "hygiene"))
    assert all(r.status == "skip" and "interpolates = False" in r.message for r in by(declared, "texel"))
    assert all(r.status == "fail" for r in by(silent, "hygiene"))
    assert all(r.status == "fail" and "without one attribute row" in r.message for r in by(silent, "texel"))


def test_texel_and_perspective_alike_fail_an_answer_without_u_and_v():
    """One attribute column where the case interpolates u and v: both attribute checks fail
    it by the missing columns (perspective once compared a column it did not get by
    broadcasting, and called it a perspective error)."""
    sequence = next(c for c in motion_cases(0) if c.texels and c.perspective)
    results = run_suite([NaNAttributes()], cases=[sequence], isolate=False, only={"texel", "perspective"})
    assert sorted(r.check for r in results) == ["perspective", "texel"]
    for r in results:
        assert r.status == "fail" and "fewer than the two attribute columns" in r.message, r
        assert r.metrics["frames_without_attributes"] == len(sequence.frames)


def test_watertight_says_whether_failures_sit_at_vertices():
    fan = next(c for c in partition_cases(0) if c.id == "watertight/fan-8/centre")
    message = watertight(fan, EdgeFunctionBug("inclusive").rasterize(triangles(fan.scene))).message
    assert "mesh vertex" in message, message
    assert "every one at a pixel holding a mesh vertex" in message, message
    grid = next(c for c in partition_cases(0) if c.id == "watertight/grid-6x6-on-centres/lattice")
    message = watertight(grid, EdgeFunctionBug("inclusive").rasterize(triangles(grid.scene))).message
    assert "the rest along edges" in message, message


def test_a_double_hit_of_the_snapped_mesh_itself_is_the_conventions_own():
    """Snapped to 1/16 px, a sliver of a fuzz partition folds over its neighbour: the
    convention's exact answer hits one pixel twice, so a correct fixed-point rasterizer
    does too. Watertight (and overdraw) excuse it, counted apart; a scanline rounding its
    left edges up still fails, and unsnapped the excuse never applies."""
    from cases.fuzz import generate
    from harness.checks.watertight import overdraw
    from harness.oracle.coverage import exact_coverage
    from rasterizers.fixed_point import FixedPoint

    case = still(generate("partitions", 0, 7868))
    right = FixedPoint(4)
    coverage = right.rasterize(triangles(case.scene))
    oracle = exact_coverage(case.scene, right.convention)
    assert coverage == oracle and (oracle.counts(case.scene.width, case.scene.height) > 1).sum() == 1
    bare = watertight(case, coverage)  # convention-free: the fold reads as a double hit
    assert bare.status == "fail" and bare.metrics["double_hits"] == 1
    judged = watertight(case, coverage, right.convention, lambda: oracle)
    assert judged.status == "pass" and judged.metrics["snapped_own"] == 1 and "snapping folds" in judged.message
    assert overdraw(case, coverage, right.convention, lambda: oracle).status == "pass"
    assert overdraw(case, coverage).status == "fail"
    from tests.known_bad.catalogue import KNOWN_BAD

    wrong = KNOWN_BAD["bad_ceil-left"].rasterize(triangles(case.scene))  # left edges rounded up: holes all along
    assert watertight(case, wrong, right.convention, lambda: oracle).status == "fail"
    exact = watertight(case, coverage, Convention(), lambda: exact_coverage(case.scene, Convention()))
    assert "snapped_own" not in exact.metrics


def test_fingerprint_page_puts_everyone_side_by_side(tmp_path):
    from harness.cli.main import main

    path = tmp_path / "box.py"
    path.write_text(
        "from harness.contract.conventions import Convention\n"
        "from harness.oracle.coverage import exact_coverage\n"
        "class Box:\n"
        "    name = 'box<b>'\n"
        "    convention = None\n"
        "    def rasterize(self, scene):\n"
        "        return exact_coverage(scene, Convention(tie='bottom-left'))\n"
    )
    out = tmp_path / "rep"
    code = main(["run", "--rasterizer", "centre_scanline", "--rasterizer", f"{path}:Box", "--case", "lattice/*",
                 "--out", str(out), "--json", str(tmp_path / "r.json")])
    assert code == 0
    page = (out / "fingerprints.html").read_text()
    assert "box&lt;b&gt;" in page and "box<b>" not in page  # autoescaped
    assert "confirmed" in page and "nothing declared; checked against the identified one" in page
    assert "vertex sweep" in page and "viewport edge" in page and 'href="fingerprints.html"' in (out / "index.html").read_text()
    data = json.loads((tmp_path / "r.json").read_text())
    assert data["fingerprints"]["centre_scanline"]["exact"] is True
    assert data["fingerprints"]["box<b>"]["tie"] == "bottom-left"


HANGS_ON_NAN = """
import time
import numpy as np
from rasterizers.centre_scanline import CentreScanline

class HangsOnNaN:
    name = "hangs_on_nan"
    convention = None

    def rasterize(self, scene):
        if np.isnan(scene.positions).any():
            while True:
                time.sleep(0.05)
        return CentreScanline().rasterize(scene)
"""


def test_identify_and_run_go_on_past_a_call_that_hangs(tmp_path, capsys):
    from harness.cli.main import main

    path = tmp_path / "hang.py"
    path.write_text(HANGS_ON_NAN)
    # a plain scene answers in milliseconds: 1 s, and a second ask in a fresh process for a
    # call cut off (harness.engine.isolation.TimeLimit), leave room for a loaded machine (at 0.5 s
    # and no second ask, one of identify's fit scenes once went unanswered beside two campaigns)
    assert main(["identify", f"{path}:HangsOnNaN", "--timeout", "1"]) == 0
    card = capsys.readouterr().out
    assert "NaN: raises TimeoutError" in card and "identified exactly" in card, card
    out = tmp_path / "rep"
    code = main(["run", "--rasterizer", f"{path}:HangsOnNaN", "--timeout", "1", "--out", str(out), "--case", "degenerate/[nz]*",
                 "--json", str(tmp_path / "r.json")])
    assert code == 1
    data = json.loads((tmp_path / "r.json").read_text())
    assert "raises TimeoutError" in data["fingerprints"]["hangs_on_nan"]["facts"]["non-finite"]
    assert any(r["status"] == "error" and "timeout" in r["message"] for r in data["results"])
    # the terminal and the JSON count the calls that timed out (asked twice) and name their cases
    hung = data["call_failures"]["hangs_on_nan"]["timed_out"]
    assert hung and all(case.startswith("degenerate/") for case in hung)
    calls = f"{len(hung)} call{'' if len(hung) == 1 else 's'}"
    assert f"calls: {calls} timed out (each asked twice): {hung[0]}" in capsys.readouterr().out


class Undeclared:
    """Ties owned by the edges leaving vertex 0 (a known-bad), declaring no convention.
    (Inclusive edges once stood here: identify now names them, nearly exactly, as the
    closed rule, against which the lattice passes.)"""

    name = "undeclared_vertex_order_ties"
    convention = None

    def rasterize(self, scene):
        return EdgeFunctionBug("vertex-order-ties").rasterize(scene)


def _guessed():
    """identify of the undeclared known-bad."""
    return identify(Undeclared())


class UndeclaredInclusive:
    """Inclusive edges (a known-bad), declaring no convention: identify names it the closed
    rule, nearly exactly (its float edge functions miss a few samples on edges)."""

    name = "undeclared_inclusive"
    convention = None

    def rasterize(self, scene):
        return EdgeFunctionBug("inclusive").rasterize(scene)


@functools.cache
def _inclusive():
    """identify of inclusive edges, once per process (tests in two modules read it)."""
    return identify(UndeclaredInclusive())


def test_failures_against_a_guessed_convention_say_so():
    from harness.identify.fingerprint import Identified

    fingerprint = _guessed()
    assert not fingerprint.exact
    case = [c for c in conformance_cases(0) if c.id == "lattice/bits-0"]
    results = run_suite([Identified(Undeclared(), fingerprint)], cases=case, isolate=False, repros=False)
    failed = [r for r in results if r.check == "conformance"]
    assert failed[0].status == "fail" and failed[0].message.startswith("against the best-guess convention")
    # a declared convention is never qualified
    declared = run_suite([EdgeFunctionBug("inclusive")], cases=case, isolate=False, repros=False)
    assert not any(r.message.startswith("against the best-guess") for r in declared)


def test_a_library_that_fails_on_a_triangle_is_named_with_it():
    from harness.contract.scenes import Scene
    from rasterizers.real._masks import draw_each

    def draw(p, w, h, origin):
        if not np.isfinite(p).all():
            raise OverflowError("cannot convert float NaN to integer")
        return np.ones((h, w), dtype=bool)

    scene = Scene(16, 16, [[[1.0, 1.0], [5.0, 1.0], [1.0, 5.0]], [[np.nan, 2.0], [8.0, 8.0], [2.0, 9.0]]])
    with pytest.raises(RuntimeError, match=r"lib: the library failed on triangle 1 .*OverflowError"):
        draw_each(scene, "lib", draw)
