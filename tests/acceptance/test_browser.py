"""The report in a real browser: every page loads, every image decodes, a screenshot is kept;
the repro pictures show the failure where it is (read back from the pixels Chromium draws).

Needs Debian's chromium (``.ci/run`` installs it); without it the test is skipped with a
reason saying how to install it.
"""

import base64
import json
import re
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from cases.fuzz import generate
from cases.lines import line_cases
from cases.motion import motion_cases
from cases.suites import suite
from harness.checks import deviations
from harness.contract.case import Case, case_from_json
from harness.contract.scenes import Scene
from harness.engine.registry import load
from harness.engine.runner import run_suite
from harness.identify.fingerprint import identify
from harness.oracle.coverage import exact_coverage
from harness.report import pictures
from harness.report.pages import write_report
from harness.report.pictures import draw, draw_repro
from tests.known_bad.antialiasing import SwappedSampleBits
from tests.known_bad.interpolation import InterpolationBug
from tests.known_bad.lines import LeftmostFirst
from tests.known_bad.misc import WrongTieClaim
from tests.known_bad.paths import PathFillBug
from tests.optional import NO_CHROMIUM, chromium

CHROMIUM = chromium()
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--hide-scrollbars"]
KEEP = Path(__file__).parents[2] / "reports" / "browser"

CHECKER = """<!doctype html><html><body><pre id="result">pending</pre>
<iframe id="frame" width="1280" height="900"></iframe>
<script>
const pages = PAGES;
const report = {};
const frame = document.getElementById("frame");
function next(i) {
  if (i >= pages.length) { document.getElementById("result").textContent = JSON.stringify(report); return; }
  frame.onload = () => {
    const doc = frame.contentDocument;
    const images = Array.from(doc.images);
    Promise.all(images.map(img => img.decode().then(() => img.naturalWidth > 0, () => false))).then(ok => {
      report[pages[i]] = {title: doc.title, images: images.length, broken: ok.filter(x => !x).length,
                          scripts: doc.scripts.length};
      next(i + 1);
    });
  };
  frame.src = pages[i];
}
next(0);
</script></body></html>"""


@pytest.mark.skipif(CHROMIUM is None, reason=NO_CHROMIUM)
def test_report_renders_in_a_real_browser(tmp_path):
    static = [c for c in suite("quick") if c.id in ("lattice/bits-0", "watertight/fan-8/centre")]
    moving = [c for c in motion_cases(0) if c.id == "motion/textured-64/quad/translate-x-1/64"]
    # in this process: the pages are what is checked here, and the results are the same either way
    results = run_suite([WrongTieClaim(), InterpolationBug("no-subtexel"), "centre_scanline"], cases=static + moving,
                        isolate=False)
    conventions = {"bad_wrong_tie_claim": "claims bottom-right", "bad_no-subtexel": "top-left", "centre_scanline": "top-left"}
    out = tmp_path / "report"
    fingerprints = {"bad_wrong_tie_claim": identify(WrongTieClaim()).to_dict(), "centre_scanline": identify(load("centre_scanline")).to_dict()}
    declared = {"bad_wrong_tie_claim": "sample (0.5, 0.5), bottom-right ties, no snapping, no culling"}
    write_report(out, conventions, results, seed=0, fingerprints=fingerprints, declared=declared,
                 kinds={"centre_scanline": "built-in", "bad_wrong_tie_claim": "plugin", "bad_no-subtexel": "plugin"})
    pages = sorted(p.name for p in out.glob("*.html"))
    assert len(pages) == 5 and "fingerprints.html" in pages
    assert "not confirmed" in (out / "fingerprints.html").read_text()
    checker = out / "check.html"
    checker.write_text(CHECKER.replace("PAGES", json.dumps(pages)))
    text = "pending"
    # a cold browser profile, or a machine busy with the other test workers, can run out of
    # virtual time before the frames load (a fresh clone's CI once did, three times over)
    for attempt in range(6):
        dom = subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={tmp_path / f'profile-{attempt % 2}'}",
                              "--allow-file-access-from-files", f"--virtual-time-budget={60000 * (1 + attempt)}",
                              "--dump-dom", checker.as_uri()],
                             capture_output=True, text=True, timeout=120).stdout
        text = dom.split('<pre id="result">', 1)[-1].split("</pre>", 1)[0]
        if text.startswith("{"):
            break
    assert text.startswith("{"), f"the checker page did not finish: {text[:200]!r}"
    report = json.loads(text.replace("&quot;", '"'))
    assert set(report) == set(pages)
    assert all(page["broken"] == 0 and page["scripts"] == 0 for page in report.values()), report
    assert sum(page["images"] for page in report.values()) >= 5  # heat map, diff, crop, animation, plot
    KEEP.mkdir(parents=True, exist_ok=True)
    for page in ("index.html", "rasterizer-bad_wrong_tie_claim.html", "fingerprints.html"):
        shot = KEEP / page.replace(".html", ".png")
        subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1280,1600",
                        f"--screenshot={shot}", (out / page).as_uri()], capture_output=True, timeout=120)
        assert shot.exists() and shot.stat().st_size > 10_000


# -- the pictures of a failure, read back from what the browser draws ----------------------

HOLES = PathFillBug("horizontal-crossings")  # a campaign's rasterizer: tests.acceptance.test_browser:HOLES
HOLE_SCENE = ("paths", 0, 77)  # a 4 x 4 quad grid of paths on which it leaves a row out
LINE_CASE = "lines/octants/short-centres"
MULTISAMPLE = Case("ms/one-triangle", Scene(10, 10, [[[1.0, 1.25], [8.5, 2.0], [3.25, 8.75]]]), lattice=True)

PROBE = """<!doctype html><html><body><pre id="result">pending</pre>
<iframe id="frame" width="1280" height="900"></iframe>
<script>
const probes = PROBES;  // page -> [[image index, [[x, y], ...]], ...]
const pages = Object.keys(probes);
const out = {};
const frame = document.getElementById("frame");
function next(i) {
  if (i >= pages.length) { document.getElementById("result").textContent = JSON.stringify(out); return; }
  frame.onload = () => {
    const images = Array.from(frame.contentDocument.images);
    Promise.all(probes[pages[i]].map(([index, points]) => images[index].decode().then(() => {
      const img = images[index];
      const canvas = document.createElement("canvas");
      canvas.width = img.naturalWidth; canvas.height = img.naturalHeight;
      const context = canvas.getContext("2d");
      context.drawImage(img, 0, 0);
      // the 5 x 5 screen pixels around each point
      return points.map(([x, y]) => Array.from(context.getImageData(Math.round(x) - 2, Math.round(y) - 2, 5, 5).data));
    }, () => null))).then(found => { out[pages[i]] = found; next(i + 1); });
  };
  frame.src = pages[i];
}
next(0);
</script></body></html>"""


def _images(html: str) -> list[str]:
    """The data URIs of a page's images, in document order."""
    return re.findall(r'<img src="([^"]+)"', html)


def _panels(uri: str) -> list[tuple[float, float, float, tuple[float, float]]]:
    """Each picture side by side in an SVG data URI: (left, top, screen px per pixel, its
    window's top-left corner (x0, y0)), to place a point of the scene on the image."""
    root = ET.fromstring(base64.b64decode(uri.split(",", 1)[1]))
    out = []
    for panel in root.findall("{http://www.w3.org/2000/svg}svg"):
        x0, y0, w, _ = (float(v) for v in panel.get("viewBox").split())
        out.append((float(panel.get("x")), float(panel.get("y")), float(panel.get("width")) / w, (x0, y0)))
    return out


def _on_image(panel: tuple[float, float, float, tuple[float, float]], x: float, y: float) -> list[float]:
    left, top, scale, (x0, y0) = panel
    return [left + (x - x0) * scale, top + (y - y0) * scale]


def _outline_points(panel: tuple[float, float, float, tuple[float, float]], x: int, y: int) -> list[list[float]]:
    """Eight points on the border of pixel (x, y), one screen pixel in: where its outline is."""
    left, top, scale, (x0, y0) = panel
    sx, sy = left + (x - x0) * scale, top + (y - y0) * scale
    one = 1.0
    return [[sx + scale * f, sy + one] for f in (0.25, 0.75)] + [[sx + scale * f, sy + scale - one] for f in (0.25, 0.75)] + \
        [[sx + one, sy + scale * f] for f in (0.25, 0.75)] + [[sx + scale - one, sy + scale * f] for f in (0.25, 0.75)]


def _near(block: list[int], rgb: Any, within: float = 80.0) -> bool:
    """Whether a screen pixel of a 5 x 5 block (RGBA) is within ``within`` of the colour (of
    one of the colours, given several)."""
    pixels = np.asarray(block, dtype=float).reshape(-1, 4)[:, :3]
    colours = np.asarray(rgb, dtype=float).reshape(-1, 3)
    return bool((np.linalg.norm(pixels[:, None, :] - colours[None], axis=2) <= within).any())


def _clear(px: float, py: float, outlined: set[tuple[int, int]], scale: float) -> bool:
    """Whether no red outline (of the pixels ``outlined``) lies within the 5 x 5 screen
    pixels probed around scene point (px, py)."""
    i, j = int(np.floor(px)), int(np.floor(py))
    return (i, j) not in outlined or min(px - i, i + 1 - px, py - j, j + 1 - py) * scale > 4.5


def _probe(out: Path, probes: dict[str, list[tuple[int, list[list[float]]]]], profile: Path) -> dict[str, Any]:
    checker = out / "probe.html"
    checker.write_text(PROBE.replace("PROBES", json.dumps(probes)))
    text = "pending"
    for attempt in range(4):  # a machine busy with the other test workers can run out of virtual time
        dom = subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={profile}", "--allow-file-access-from-files",
                              f"--virtual-time-budget={60000 * (1 + attempt)}", "--dump-dom", checker.as_uri()],
                             capture_output=True, text=True, timeout=120).stdout
        text = dom.split('<pre id="result">', 1)[-1].split("</pre>", 1)[0]
        if text.startswith("{"):
            break
    assert text.startswith("{"), f"the probe page did not finish: {text[:200]!r}"
    found: dict[str, Any] = json.loads(text.replace("&quot;", '"'))
    assert all(block is not None for blocks in found.values() for block in blocks), found  # every image decoded
    return found


@pytest.mark.skipif(CHROMIUM is None, reason=NO_CHROMIUM)
def test_repro_pictures_mark_the_offending_pixels_and_draw_the_primitives_where_they_are(tmp_path):
    """A line failure, a multisample failure (the run report) and a path hole found by a
    campaign (its page), drawn by Chromium: at every pixel the failure names on the repro
    (computed here from the rasterizer's answer and the oracle, not read from the picture)
    the outline is red on both sides; the segment and the paths are drawn where the repro
    says they are; the samples where the rasterizer and the convention differ are ringed,
    dark where each covers them."""
    from harness.campaign.state import Batch, BatchResult, CampaignState
    from harness.campaign.worker import _finding, _loaded, shrink_finding
    from harness.report.campaign_page import write_campaign_page
    from harness.report.pictures import CROP_LEGEND, LINE_LEGEND, PATH_LEGEND, SAMPLE_LEGEND

    red = CROP_LEGEND["offending pixel (outlined)"]
    line_case = next(c for c in line_cases(0) if c.id == LINE_CASE)
    results = run_suite([LeftmostFirst(), SwappedSampleBits()], cases=[line_case, MULTISAMPLE], isolate=False, identify=False,
                        only={"conformance"})
    out = tmp_path / "report"
    write_report(out, {"bad_leftmost_first": "diamond-exit", "bad_swapped_sample_bits": "4x"},
                 [r for r in results if r.status == "fail"], seed=0)
    # the campaign: the finding on its scene, shrunk as the campaign shrinks it, on the page
    spec = "tests.acceptance.test_browser:HOLES"
    scene_case = generate(*HOLE_SCENE)
    loaded = _loaded(spec, None, 60.0)
    hole = next(r for r in loaded.check(scene_case, {"watertight"}) if r.status == "fail")
    finding = _finding(hole, scene_case, loaded, *HOLE_SCENE)
    state = CampaignState(tmp_path / "state", spec, HOLES.name)
    state.record(BatchResult(Batch(HOLE_SCENE[0], HOLE_SCENE[1], HOLE_SCENE[2], HOLE_SCENE[2] + 1), 1, len(scene_case.scene), 1.0,
                             (finding,), "here"), 1.0)
    state.save_repro(finding.signature_key, shrink_finding(spec, None, finding))
    write_campaign_page(out, state, rasterizer=HOLES)

    probes: dict[str, list[tuple[int, list[list[float]]]]] = {}
    # per image probed, per group of points: its colour, how many points, how many must show it (-1: none may)
    expect: dict[str, list[list[tuple[tuple[int, int, int], int, int]]]] = {}

    def probe(page: str, index: int, groups: list[tuple[list[list[float]], tuple[int, int, int], int]]) -> None:
        probes.setdefault(page, []).append((index, [p for points, _, _ in groups for p in points]))
        expect.setdefault(page, []).append([(rgb, len(points), least) for points, rgb, least in groups])

    # the line repro: one segment; the pixels where the drawer and the rule differ, outlined on both sides
    page = "rasterizer-bad_leftmost_first.html"
    html = (out / page).read_text()
    images = _images(html)
    line = next(r for r in results if r.rasterizer == "bad_leftmost_first" and r.status == "fail")
    uri = images.index(draw_repro(line)[0])
    repro = case_from_json(line.evidence["repro"])
    missing, extra = deviations(LeftmostFirst().rasterize(repro.scene), exact_coverage(repro.scene, LeftmostFirst.convention),
                                repro.scene.width, repro.scene.height)
    offending = sorted({(x, y) for _, x, y in np.concatenate([missing, extra], axis=1).T.tolist()})
    assert offending and len(repro.scene) == 1
    a, b = (v[0] for v in repro.scene.segments())
    groups = []
    for panel in _panels(images[uri]):
        groups += [(_outline_points(panel, x, y), red, 6) for x, y in offending]
        groups.append(([_on_image(panel, *(a + t * (b - a))) for t in (0.2, 0.35, 0.65, 0.8)],
                       LINE_LEGEND[next(iter(LINE_LEGEND))], 3))
    probe(page, uri, groups)

    # the multisample failure: its samples crop, each differing sample ringed, dark where covered
    page = "rasterizer-bad_swapped_sample_bits.html"
    images = _images((out / page).read_text())
    ms = next(r for r in results if r.rasterizer == "bad_swapped_sample_bits" and r.status == "fail")
    uri = images.index(draw(ms)["samples"])
    scene, pattern = MULTISAMPLE.scene, SwappedSampleBits.convention.samples
    answer, oracle = SwappedSampleBits().rasterize(scene), exact_coverage(scene, SwappedSampleBits.convention)
    left_panel, right_panel = _panels(images[uri])
    x0, y0 = left_panel[3]
    outlined = {(p["x"], p["y"]) for p in ms.evidence["pixels"]}
    groups = []
    for k, (sx, sy) in enumerate(pattern):
        got = answer.layer(k).counts(scene.width, scene.height) > 0
        want = oracle.layer(k).counts(scene.width, scene.height) > 0
        for y, x in np.argwhere(got != want).tolist():
            if x < x0 or y < y0 or x >= x0 + 12 or y >= y0 + 12:
                continue
            for panel, covered in ((left_panel, got[y, x]), (right_panel, want[y, x])):
                scale = panel[2]
                ring = 0.0875 * 1.9  # the ring's radius in pixels (harness.report.pictures._svg_samples)
                around = [(x + sx + dx, y + sy + dy) for dx, dy in ((ring, 0), (-ring, 0), (0, ring), (0, -ring))]

                kept = [_on_image(panel, px, py) for px, py in around if _clear(px, py, outlined, scale)]
                if len(kept) >= 2:
                    groups.append((kept, SAMPLE_LEGEND[pictures._DIFFERS], len(kept)))
                groups.append(([_on_image(panel, x + sx, y + sy)], SAMPLE_LEGEND["sample covered (dot)"],
                               1 if covered else -1))  # -1: no screen pixel there dark
    assert sum(rgb == SAMPLE_LEGEND[pictures._DIFFERS] for _, rgb, _ in groups) >= 4
    probe(page, uri, groups)

    # the campaign's hole: a few paths of the sixteen, the hole outlined, every path's outline where it is
    page = "campaign.html"
    images = _images((out / page).read_text())
    payload = json.loads((state.directory / state.signatures[finding.signature_key]["repro"]).read_text())
    cut = case_from_json(payload)
    assert payload["check"] == "holes" and len(cut.scene) < len(scene_case.scene) == 16
    hole_pixels = [tuple(p) for p in payload["evidence"]["pixels"]]
    drawn = [u for u in images if u.startswith("data:image/svg+xml") and len(_panels(u)) == 2]
    assert len(drawn) == 1
    uri = images.index(drawn[0])
    groups = []
    start, end, _ = cut.scene.edges()
    for panel in _panels(drawn[0]):
        groups += [(_outline_points(panel, x, y), red, 6) for x, y in hole_pixels]
        edge_points = [_on_image(panel, *(p + 0.3 * (q - p))) for p, q in zip(start, end)]
        numbered, other = PATH_LEGEND[next(iter(PATH_LEGEND))], tuple(PATH_LEGEND.values())[2]
        groups.append((edge_points, (numbered, other), len(edge_points)))  # each edge drawn, solid or dashed
    probe(page, uri, groups)

    found = _probe(out, probes, tmp_path / "profile")
    for page, images_expected in expect.items():
        for blocks, groups in zip(found[page], images_expected):
            at = 0
            for rgb, count, least in groups:
                shown = sum(_near(block, rgb) for block in blocks[at : at + count])
                assert shown >= least if least >= 0 else shown == 0, (page, rgb, shown, count, least)
                at += count
    KEEP.mkdir(parents=True, exist_ok=True)
    for page in ("rasterizer-bad_leftmost_first.html", "rasterizer-bad_swapped_sample_bits.html", "campaign.html"):
        shot = KEEP / ("repro-" + page.replace(".html", ".png"))
        subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1280,2400",
                        f"--screenshot={shot}", (out / page).as_uri()], capture_output=True, timeout=120)
        assert shot.exists() and shot.stat().st_size > 10_000
