"""``rastercheck atlas`` end to end, on a made-up library in two modes beside reference
rasterizers (the real libraries' adapters have their own tests; the atlas is the same
machinery over them): the JSON twin against its schema and what it says, every cell of the
page linked to evidence that exists, and the page in a real browser."""

import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

from harness.cli.atlas import upstream_scripts
from harness.results.atlas import ATLAS_KINDS, atlas_fault, read_atlas_json
from tests.optional import NO_CHROMIUM, chromium

ROOT = Path(__file__).parents[2]
MODES = "tests.known_bad.library_modes"
SPECS = [f"{MODES}:FakelibAliased", f"{MODES}:FakelibWrongTie", f"{MODES}:FakelibNotInstalled", "trapezoid_fill",
         "diamond_exit_dda", "area_scanline", "tests.known_bad.misc:Raises"]
CASES = ["lattice/*", "path-partitions/triangles/strip-24/*", "line-strips/joints/*"]


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("atlas")
    command = [sys.executable, "-m", "harness.cli", "atlas", "--out", str(out), "--jobs", "2", "--timeout", "20"]
    command += [a for s in SPECS for a in ("--rasterizer", s)] + [a for c in CASES for a in ("--case", c)]
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=600)
    return out, done


def _adapters(document):
    return {a["adapter"]: (lib, a) for lib in document["libraries"] for a in lib["adapters"]}


def test_the_atlas_is_written_and_its_json_twin_keeps_its_schema(atlas):
    out, done = atlas
    assert done.returncode == 0, done.stderr[-3000:]
    assert (out / "atlas.html").exists() and (out / "index.html").exists()
    document = read_atlas_json(out / "atlas.json")
    assert document["schema"] == 1 and document["document"] == "rastercheck atlas"
    broken = dict(document, libraries="none")
    assert atlas_fault(broken) is not None  # the schema does refuse a malformed twin


def test_modes_of_one_library_are_grouped_and_identified(atlas):
    document = read_atlas_json(atlas[0] / "atlas.json")
    adapters = _adapters(document)
    lib, aliased = adapters["fakelib_aliased"]
    assert lib["library"] == "Fakelib" and lib["version"] == "1.0"
    assert [a["adapter"] for a in lib["adapters"]] == ["fakelib_aliased", "fakelib_wrong_tie"]
    cell = aliased["kinds"]["triangles"]
    assert cell["taken"] and cell["identified"]["exact"] and "top-left" in cell["identified"]["convention"]
    assert cell["results"]["pass"] > 0 and cell["results"]["fail"] == 0
    assert aliased["kinds"]["paths"] == dict(aliased["kinds"]["paths"], taken=False, why_not="Fakelib fills no paths")
    assert "fakelib_wrong_tie" in cell["alike"]  # the same pixels, whatever it claims


def test_a_mode_that_fails_has_its_causes_linked_to_the_run_report(atlas):
    out = atlas[0]
    document = read_atlas_json(out / "atlas.json")
    cell = _adapters(document)["fakelib_wrong_tie"][1]["kinds"]["triangles"]
    assert cell["results"]["fail"] > 0 and cell["causes"]
    for cause in cell["causes"]:
        page, anchor = cause["link"].split("#")
        assert f'id="{anchor}"' in (out / page).read_text()
        assert cause["repro"] is None or (out / cause["repro"]).exists()


def test_paths_lines_and_area_coverage_have_their_cells(atlas):
    adapters = _adapters(read_atlas_json(atlas[0] / "atlas.json"))
    paths = adapters["trapezoid_fill"][1]["kinds"]["paths"]
    assert paths["taken"] and paths["fill_rules"] == ["nonzero", "evenodd"] and paths["identified"] is not None
    lines = adapters["diamond_exit_dda"][1]["kinds"]["lines"]
    assert lines["taken"] and lines["identified"]["exact"] and lines["results"]["pass"] > 0
    assert adapters["area_scanline"][1]["coverage_kind"] == "area"


def test_a_library_that_raises_or_is_missing_is_reported_not_fatal(atlas):
    document = read_atlas_json(atlas[0] / "atlas.json")
    raises = _adapters(document)["bad_raises"][1]
    assert raises["kinds"]["triangles"]["results"]["error"] > 0 and raises["kinds"]["triangles"]["identified"] is None
    assert [m["adapter"] for m in document["missing"]] == [f"{MODES}:FakelibNotInstalled"]
    assert "pip install fakelib" in document["missing"][0]["why"]


class _Cells(HTMLParser):
    """The matrix cells' links and every id of a page."""

    def __init__(self):
        super().__init__()
        self.cells, self.ids = {}, set()

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.add(attrs["id"])
        if tag == "a" and "data-cell" in attrs:
            self.cells[attrs["data-cell"]] = attrs["href"]


def _resolves(out: Path, href: str) -> bool:
    page, _, anchor = href.partition("#")
    if not (out / page).exists():
        return False
    return not anchor or f'id="{anchor}"' in (out / page).read_text()


def test_every_cell_of_the_page_links_to_evidence_that_exists(atlas):
    out = atlas[0]
    document = read_atlas_json(out / "atlas.json")
    parsed = _Cells()
    parsed.feed((out / "atlas.html").read_text())
    expected = {f"{name}/{kind}" for name in _adapters(document) for kind in ATLAS_KINDS}
    assert set(parsed.cells) == expected
    assert all(_resolves(out, href) for href in parsed.cells.values()), parsed.cells


def test_the_page_in_a_browser_shows_every_cell_linked(atlas):
    browser = chromium()
    if browser is None:
        pytest.skip(NO_CHROMIUM)
    out = atlas[0]
    dom = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--dump-dom",
                          (out / "atlas.html").as_uri()], capture_output=True, text=True, timeout=120).stdout
    parsed = _Cells()
    parsed.feed(dom)
    document = read_atlas_json(out / "atlas.json")
    assert len(parsed.cells) == len(_adapters(document)) * len(ATLAS_KINDS)
    assert all(_resolves(out, href) for href in parsed.cells.values())
    assert re.search(r"Atlas: real rasterizers", dom)


def test_the_upstream_scripts_are_listed_with_their_titles():
    scripts = upstream_scripts()
    assert {"library": "cairo", "script": "upstream/cairo_aa_sliver_wraps.py",
            "title": "cairo: an anti-aliased sliver gets alpha 251/255 in a pixel it covers by 0.1% (8-bit coverage wraps)."
            } in scripts
