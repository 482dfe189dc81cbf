"""Pictures of multisample and anti-aliased failures show the samples: what the
rasterizer drew beside what the convention says, the pattern's samples in each pixel
(a dot where covered, a ring where not), the samples where the two differ ringed, and the
alphas of the offending pixels as shares of the samples."""

import base64
import xml.etree.ElementTree as ET

import pytest

from harness.checks import Result
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.scenes import Scene
from harness.engine.runner import run_suite
from harness.oracle.coverage import exact_coverage
from harness.report import pictures
from tests.known_bad.antialiasing import GRID_4X4, InclusiveSupersampledTies, SwappedSampleBits
from tests.report.pictured import attr, number, repro_picture, title_text, titled

SVG = "{http://www.w3.org/2000/svg}"
# a right edge at x = 3.125 through a column of the 4 x 4 grid's samples: top-left ties
# leave them out, an inclusive test counts them
ON_SAMPLES = Case("aa/right-edge-on-samples", Scene(8, 12, [[[1.0, 1.0], [3.125, 1.0], [3.125, 9.0]]]), lattice=True)
SMALL = Case("ms/one-triangle", Scene(10, 10, [[[1.0, 1.25], [8.5, 2.0], [3.25, 8.75]]]), lattice=True)


def _panels(uri: str) -> list[ET.Element]:
    """The pictures side by side of a data URI: the rasterizer's, then the convention's."""
    root = ET.fromstring(base64.b64decode(uri.split(",", 1)[1]))
    return root.findall(SVG + "svg")


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#{:02x}{:02x}{:02x}".format(*rgb)


def _dots(panel: ET.Element, **attributes: str) -> set[tuple[float, float]]:
    """The centres of the circles with these attributes."""
    return {(round(number(c, "cx"), 6), round(number(c, "cy"), 6)) for c in panel.iter(SVG + "circle")
            if all(c.get(k) == v for k, v in attributes.items())}


def _covered_samples(coverage_of_sample: list, window: tuple[int, int, int, int], offsets) -> set[tuple[float, float]]:
    """Each covered sample's position: coverage_of_sample[k] is sample k's (H, W) bool."""
    x0, y0, x1, y1 = window
    return {(round(x + offsets[k][0], 6), round(y + offsets[k][1], 6)) for k, hit in enumerate(coverage_of_sample)
            for y in range(y0, y1) for x in range(x0, x1) if hit[y, x]}


def _window(panel: ET.Element) -> tuple[int, int, int, int]:
    x0, y0, w, h = (int(float(v)) for v in attr(panel, "viewBox").split())
    return x0, y0, x0 + w, y0 + h


def _failure(rasterizer, case: Case, check: str, repros: bool = False) -> Result:
    results = run_suite([rasterizer], cases=[case], isolate=False, identify=False, repros=repros, only={check})
    return next(r for r in results if r.check == check and r.status == "fail")


@pytest.fixture(scope="module")
def aa_failure() -> Result:
    return _failure(InclusiveSupersampledTies(), ON_SAMPLES, "accuracy")


@pytest.fixture(scope="module")
def ms_failure() -> Result:
    return _failure(SwappedSampleBits(), SMALL, "conformance", repros=True)


def test_an_anti_aliased_crop_draws_the_conventions_samples_and_both_alphas(aa_failure: Result) -> None:
    images = pictures.draw(aa_failure)
    assert list(images) == ["alpha error", "samples"]
    left, right = _panels(images["samples"])
    window = _window(right)
    scene = ON_SAMPLES.scene
    assert isinstance(scene, Scene)
    want = [exact_coverage(scene, Convention(sample=o)).counts(scene.width, scene.height) > 0 for o in GRID_4X4]
    hit = _hex(pictures.SAMPLE_LEGEND["sample covered (dot)"])
    assert _dots(right, fill=hit) == _covered_samples(want, window, GRID_4X4)
    assert not _dots(left, fill=hit)  # an alpha says nothing of which samples the rasterizer counted
    # the offending pixels: outlined, and their alphas written as shares of the 16 samples, k/16
    offending = {(p["x"], p["y"]) for p in aa_failure.evidence["pixels"] if p["over"]}  # the rest: its worst, within tolerance
    got = InclusiveSupersampledTies().rasterize(scene)
    assert got.alpha is not None
    got_alpha = {(x, y): a for x, y, a in zip(got.pixels()[1].tolist(), got.pixels()[2].tolist(), got.alpha.tolist())}
    for panel, share in ((left, lambda x, y: round(16 * got_alpha.get((x, y), 0.0))),
                         (right, lambda x, y: sum(int(w[y, x]) for w in want))):
        labels = {title_text(t): titled(t).tail for t in panel.iter(SVG + "text")
                  if t.find(SVG + "title") is not None and title_text(t).startswith("alpha of pixel")}
        assert labels == {f"alpha of pixel ({x}, {y})": f"{share(x, y)}/16" for x, y in offending}
        red = _hex(pictures.CROP_LEGEND["offending pixel (outlined)"])
        outlined = {(int(number(r, "x")), int(number(r, "y"))) for r in panel.iter(SVG + "rect") if r.get("stroke") == red}
        assert outlined == offending
    assert "off_level" not in aa_failure.evidence  # off by the samples on the edge, not off a level
    assert all(round(16 * got_alpha[p]) == sum(int(w[p[1], p[0]]) for w in want) + 4 for p in offending)


def test_a_multisample_crop_rings_the_samples_where_the_rasterizer_and_the_convention_differ(ms_failure: Result) -> None:
    assert ms_failure.drawing is not None
    assert ms_failure.drawing.whole is not None and ms_failure.drawing.whole.convention == SwappedSampleBits.convention
    images = pictures.draw(ms_failure)
    assert list(images) == ["heatmap", "diff", "crop", "samples"]
    left, right = _panels(images["samples"])
    window = _window(right)
    scene, pattern = SMALL.scene, SwappedSampleBits.convention.samples
    assert isinstance(scene, Scene)
    answer, oracle = SwappedSampleBits().rasterize(scene), exact_coverage(scene, SwappedSampleBits.convention)
    got = [answer.layer(k).counts(scene.width, scene.height) > 0 for k in range(len(pattern))]
    want = [oracle.layer(k).counts(scene.width, scene.height) > 0 for k in range(len(pattern))]
    hit, red = _hex(pictures.SAMPLE_LEGEND["sample covered (dot)"]), _hex(pictures.SAMPLE_LEGEND[pictures._DIFFERS])
    assert _dots(left, fill=hit) == _covered_samples(got, window, pattern)
    assert _dots(right, fill=hit) == _covered_samples(want, window, pattern)
    differ = _covered_samples([g != w for g, w in zip(got, want)], window, pattern)
    assert differ and _dots(left, stroke=red) == _dots(right, stroke=red) == differ


def test_a_multisample_repro_is_drawn_with_its_samples(ms_failure: Result) -> None:
    uri, caption = repro_picture(ms_failure)
    assert "left: what the rasterizer drew, right: what the convention (D3D11 4x, top-left ties" in caption
    left, right = _panels(uri)
    red = _hex(pictures.SAMPLE_LEGEND[pictures._DIFFERS])
    assert _dots(left, stroke=red) and _dots(left, stroke=red) == _dots(right, stroke=red)
