"""Pictures are the report's: the engine attaches what a failure is drawn from (a
Drawing of references), and harness.report.pictures.draw makes the heat map, diff and crop, or
the animation and plot, when the report shows the failure."""

import base64
import io
import json
import pickle
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

from cases.motion import motion_cases
from cases.suites import suite
from harness.engine.runner import run_suite
from harness.report import picture_kit, pictures
from harness.report.pages import write_report
from harness.results.output import results_from_json, results_to_json
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.known_bad.interpolation import InterpolationBug
from tests.known_bad.misc import WrongTieClaim

ROOT = Path(__file__).resolve().parents[2]
STILL = [c for c in suite("quick") if c.id in ("lattice/bits-0", "watertight/fan-8/centre")]
PICTURE_KEYS = {"images", "animation", "plot"}


def _decoded(uri: str) -> bytes:
    return base64.b64decode(uri.split(",", 1)[1])


def _image(uri: str) -> Image.Image:
    return Image.open(io.BytesIO(_decoded(uri)))


@pytest.fixture(scope="module")
def tie_results():
    """A correct top-left rasterizer claiming bottom-right: conformance fails."""
    return run_suite([WrongTieClaim()], cases=STILL, isolate=False, identify=False, repros=False)


@pytest.fixture(scope="module")
def tie_failure(tie_results):
    return next(r for r in tie_results if r.status == "fail" and r.check == "conformance")


def test_the_engine_attaches_a_drawing_to_failures_only_and_draws_nothing(tie_results, tie_failure):
    assert all((r.drawing is not None) == (r.status == "fail") for r in tie_results)
    assert not any(PICTURE_KEYS & set(r.evidence) for r in tie_results)
    drawing = tie_failure.drawing
    assert drawing.case.id == tie_failure.case and len(drawing.coverages) == 1
    assert drawing.convention == WrongTieClaim.convention
    assert drawing.oracles is not None  # conformance computed the oracle: the drawing keeps it


def test_a_still_failure_draws_a_heat_map_a_diff_and_a_crop(tie_failure, monkeypatch):
    def no_second_oracle(*args, **kwargs):
        raise AssertionError("the oracle the check computed is computed again")

    monkeypatch.setattr(picture_kit, "exact_coverage", no_second_oracle)
    drawn = pictures.draw(tie_failure)
    assert list(drawn) == ["heatmap", "diff", "crop"]  # the order the report shows them
    for key in ("heatmap", "diff"):
        assert drawn[key].startswith("data:image/png;base64,")
        assert _image(drawn[key]).format == "PNG"
    assert drawn["crop"].startswith("data:image/svg+xml;base64,")
    svg = _decoded(drawn["crop"]).decode()
    red = "#{:02x}{:02x}{:02x}".format(*pictures.CROP_LEGEND["offending pixel (outlined)"])
    assert svg.startswith("<svg") and "<polygon" in svg and f'stroke="{red}"' in svg  # triangles, offending pixels


def test_a_failure_whose_check_needed_no_oracle_draws_the_diff_from_the_convention():
    fan = [c for c in STILL if c.id.startswith("watertight/")]
    results = run_suite([EdgeFunctionBug("exclusive")], cases=fan, isolate=False, identify=False, repros=False,
                        only={"watertight"})
    failure = next(r for r in results if r.status == "fail")
    assert failure.drawing.oracles is None  # watertight compares no oracle: none was computed
    drawn = pictures.draw(failure)
    assert list(drawn) == ["heatmap", "diff", "crop"]
    assert all(_image(drawn[k]).format == "PNG" for k in ("heatmap", "diff"))


def test_a_motion_failure_draws_an_animation():
    moving = [c for c in motion_cases(0) if c.id == "motion/textured-64/quad/translate-x-1/64"]
    results = run_suite([InterpolationBug("no-subtexel")], cases=moving, isolate=False, identify=False, repros=False,
                        only={"texel"})
    failure = next(r for r in results if r.status == "fail")
    assert not PICTURE_KEYS & set(failure.evidence)
    assert failure.drawing.oracles is not None and len(failure.drawing.coverages) == len(moving[0].frames)
    drawn = pictures.draw(failure)
    assert "animation" in drawn
    animation = _image(drawn["animation"])
    assert animation.format == "GIF" and animation.n_frames > 1


def test_results_without_a_drawing_draw_nothing(tie_results):
    assert all(pictures.draw(r) == {} for r in tie_results if r.status != "fail")
    back = results_from_json(json.loads(json.dumps(results_to_json(tie_results, "custom", 0, {}))))
    assert all(r.drawing is None and pictures.draw(r) == {} for r in back)


def test_results_pickle_with_their_drawing(tie_failure):
    """--jobs and worker processes send results across process boundaries."""
    back = pickle.loads(pickle.dumps(tie_failure))
    assert back == tie_failure and back.drawing is not None
    assert back.drawing.coverages[0].n_pixels == tie_failure.drawing.coverages[0].n_pixels
    assert list(pictures.draw(back)) == ["heatmap", "diff", "crop"]


def test_json_leaves_the_drawing_out(tie_results):
    rows = results_to_json(tie_results, "custom", 0, {})["results"]
    assert all(set(row) == {"rasterizer", "case", "check", "status", "message", "metrics", "evidence"} for row in rows)
    json.dumps(rows)


def test_the_report_draws_failures_and_shows_no_pictures_for_results_read_back(tie_results, tmp_path):
    conventions = {"bad_wrong_tie_claim": "claims bottom-right"}
    page = "rasterizer-bad_wrong_tie_claim.html"
    write_report(tmp_path / "live", conventions, tie_results, seed=0)
    html = (tmp_path / "live" / page).read_text()
    for caption in ("hit counts", "against the oracle", "crop: triangles over the pixel grid"):
        assert f"<figcaption>{caption}</figcaption>" in html
    assert html.count("<img ") == 3
    back = results_from_json(json.loads(json.dumps(results_to_json(tie_results, "custom", 0, {}))))
    write_report(tmp_path / "loaded", conventions, back, seed=0)
    html = (tmp_path / "loaded" / page).read_text()
    assert "<img " not in html and "conformance" in html  # the failure is listed, without pictures


def test_running_a_suite_imports_no_picture_code():
    """The engine never imports the presentation: a run with failures leaves
    harness.report.pictures and harness.report.pages unimported."""
    code = """
import sys
from cases.suites import suite
from harness.engine.runner import run_suite
from tests.known_bad.misc import WrongTieClaim

cases = [c for c in suite("quick") if c.id == "lattice/bits-0"]
results = run_suite([WrongTieClaim()], cases=cases, isolate=False, identify=False, repros=False)
assert any(r.status == "fail" and r.drawing is not None for r in results), results
loaded = sorted(m for m in ("harness.report.pictures", "harness.report.pages") if m in sys.modules)
assert not loaded, loaded
print("ok")
"""
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr[-2000:]
