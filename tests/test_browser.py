"""The report in a real browser: every page loads, every image decodes, a screenshot is kept.

Needs Debian's chromium (``.ci/run`` installs it); without it the test is skipped with a
reason saying how to install it.
"""

import json
import subprocess
from pathlib import Path

import pytest

from cases.motion import motion_cases
from cases.suites import suite
from harness.identify import identify
from harness.registry import load
from harness.report import write_report
from harness.runner import run_suite
from tests.known_bad.interpolation import InterpolationBug
from tests.known_bad.misc import WrongTieClaim
from tests.optional import NO_CHROMIUM, chromium

CHROMIUM = chromium()
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--hide-scrollbars"]
KEEP = Path(__file__).parent.parent / "reports" / "browser"

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
