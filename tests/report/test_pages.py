"""The HTML report says what is wrong: failures grouped by cause and signature under a table
of contents with counts, filters by check and status without JavaScript, each failure's
minimal repro drawn, its evidence as tables, motion series plotted with axes and units,
replay commands quoting the spec the user gave, skipped rasterizers listed with why, and
links to the other pages of the folder."""

import base64
import io
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from cases.motion import motion_cases
from cases.suites import suite
from harness.checks import Result
from harness.cli.main import main
from harness.contract.case import Case, case_to_json
from harness.contract.scenes import Scene
from harness.diagnose.signatures import Signature
from harness.engine.registry import Unavailable
from harness.engine.runner import run_suite
from harness.report import pictures
from harness.report.pages import evidence_table, write_comparison, write_report
from harness.results.output import results_from_json, results_to_json
from tests.known_bad.misc import Raises, WrongTieClaim
from tests.known_bad.scanlines import ScanlineBug
from tests.report.pictured import repro_drawn, repro_picture

ROOT = Path(__file__).resolve().parents[2]
LATTICE = [c for c in suite("quick") if c.id == "lattice/bits-0"]
MOVING = [c for c in motion_cases(0) if c.id == "motion/triangle/translate-x-1/16"]
CONVENTIONS = {"bad_wrong_tie_claim": "claims bottom-right", "bad_no-prestep": "centre sampling", "bad_raises": "top-left"}
TIE_PAGE, MOTION_PAGE, RAISES_PAGE = ("rasterizer-bad_wrong_tie_claim.html", "rasterizer-bad_no-prestep.html",
                                      "rasterizer-bad_raises.html")


@pytest.fixture(scope="module")
def results():
    """A conformance failure with its minimal repro (saved as the command line saves it), a
    motion failure with a per-frame series, and two crashes."""
    tie = run_suite([WrongTieClaim()], cases=LATTICE, isolate=False, identify=False)
    motion = run_suite([ScanlineBug("no-prestep")], cases=MOVING, isolate=False, identify=False, repros=False,
                       only={"jaggy"})
    crashes = run_suite([Raises()], cases=LATTICE + [c for c in suite("quick") if c.id == "watertight/fan-8/centre"],
                        isolate=False, identify=False, repros=False)
    return tie + motion + crashes


@pytest.fixture(scope="module")
def report(results, tmp_path_factory):
    out = tmp_path_factory.mktemp("report")
    for r in results:
        if "repro" in r.evidence:
            path = out / "repros" / "bad_wrong_tie_claim" / "lattice-bits-0--conformance.json"
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps(r.evidence["repro"]))
            r.evidence["repro_path"] = str(path.relative_to(out))
    write_report(out, CONVENTIONS, results, seed=0, specs={"bad_wrong_tie_claim": "my_raster.py:MyRasterizer"},
                 skipped={"cairo": "pycairo is not installed: pip install '.[cairo]' (build error: cairo.h not found)"})
    return out


def _failure(html: str, anchor: str) -> str:
    """The part of a page that shows one failure."""
    start = html.index(f'<div class="failure" id="{anchor}">')
    return html[start:html.index('<div class="failure"', start + 1) if '<div class="failure"' in html[start + 1:] else None]


def _decoded(uri: str) -> bytes:
    return base64.b64decode(uri.split(",", 1)[1])


def test_the_contents_list_each_cause_and_signature_with_counts_and_link_to_them(report):
    """Grouped as the campaign page groups (harness.diagnose.causes.by_cause): a cause, then its
    signatures in their own words, whole."""
    html = (report / TIE_PAGE).read_text()
    assert '<h2 id="contents">Failures by cause</h2>' in html
    assert '<a href="#cause-0">tie-rule</a> <span class="count">1</span> — seen by conformance' in html
    words = Signature("conformance", "exact-tie-slanted-edge", "tie-rule").describe()
    group = re.search(r'<a href="#(group-\d+)">fail · ([^<]*)</a> <span class="count">1</span>', html)
    assert group and group.group(2) == words.replace("'", "&#39;"), html[:3000]
    assert f'<section id="{group.group(1)}" class="group c-conformance s-fail">' in html
    crashes = (report / RAISES_PAGE).read_text()
    assert '<a href="#cause-0">exception-RuntimeError</a> <span class="count">2</span> — seen by run' in crashes
    assert re.search(r'<a href="#group-\d+">error · run: raised RuntimeError</a> <span class="count">2</span>', crashes)
    motion = (report / MOTION_PAGE).read_text()  # a flicker read through the frame that fails conformance
    assert re.search(r'<a href="#cause-0">sample-point</a> <span class="count">1</span> — seen by jaggy', motion)


def test_the_filters_are_css_targets_and_the_page_reads_without_them(report):
    for page, check, status in ((TIE_PAGE, "conformance", "fail"), (RAISES_PAGE, "run", "error")):
        html = (report / page).read_text()
        assert "<script" not in html
        for target in (f"only-{check}", f"only-status-{status}"):
            assert f'<a href="#{target}">' in html and f'<span id="{target}" class="filter-target"></span>' in html
            assert f"#{target}:target ~ #failures" in html  # a CSS rule hides the rest
        assert f"#only-{check}:target ~ #failures .group:not(.c-{check})" in html
        assert f"#only-{check}:target ~ #failures .cause:not(.has-c-{check})" in html
        assert re.search(f'<section id="cause-0" class="cause has-c-{check} has-{status}">', html)
        # nothing is hidden until a filter is chosen: no rule applies without :target
        rules = re.findall(r"^[^{\n]*\{ display: none; \}", html.split("<style>")[2].split("</style>")[0], re.M)
        assert rules and all(":target" in rule for rule in rules)
    index = (report / "index.html").read_text()
    assert f'href="{TIE_PAGE}#only-conformance"' in index


def test_the_evidence_is_tables_never_json_cut_short(report):
    html = (report / TIE_PAGE).read_text()
    failure = _failure(html, "failure-0")
    assert "<table>" in failure and "<th>triangle</th><th>x</th><th>y</th><th>kind</th>" in failure
    assert '{"pixels"' not in html and '"kind": "missing"' not in html and "&#34;kind&#34;" not in html
    motion = _failure((report / MOTION_PAGE).read_text(), "failure-0")
    assert "<th>series</th>" in motion and "<th>changed_pixels</th>" in motion
    crash = _failure((report / RAISES_PAGE).read_text(), "failure-0")
    assert "<pre>Traceback" in crash and "RuntimeError: rasterizer exploded" in crash


def test_long_evidence_lists_show_their_first_rows_and_count_the_rest():
    rows = [{"x": k, "y": 2 * k, "blame": [k, k + 1]} for k in range(120)]
    node = evidence_table({"pixels": rows, "series": {"hits": list(range(64))}, "note": "text"})
    pixels, series, note = (value for _, value in node["rows"])
    assert pixels["kind"] == "table" and pixels["columns"] == ["x", "y", "blame"]
    assert len(pixels["rows"]) == 50 and pixels["more"] == 70 and pixels["rows"][3] == ["3", "6", "[3, 4]"]
    hits = series["rows"][0][1]
    assert hits["text"].startswith("[0, 1, 2") and hits["text"].endswith("49, … 14 more]")  # whole items only
    assert note == {"kind": "text", "text": "text", "capped": 0}
    capped = evidence_table({"strays": [[k, k] for k in range(50)]})["rows"][0][1]
    assert capped["capped"] == 50  # as many as a check keeps: the page says there may be more


def test_each_failure_draws_its_minimal_repro(report, results):
    failure = _failure((report / TIE_PAGE).read_text(), "failure-0")
    figure = re.search(r'<figure><img src="(data:image/svg\+xml;base64,[^"]+)" alt="minimal '
                       r'repro"><figcaption>([^<]+)</figcaption>', failure)
    assert figure, failure[:2000]
    repro = next(r for r in results if "repro" in r.evidence)
    n = len(repro.evidence["repro"]["positions"])
    assert figure.group(2).startswith(f"minimal repro: its {n} triangle")
    assert "left: what the rasterizer drew, right: what the convention" in figure.group(2)
    svg = _decoded(figure.group(1)).decode()
    assert svg.startswith("<svg") and svg.count("<polygon") == 2 * n  # the triangles in both pictures
    covered = "#{:02x}{:02x}{:02x}".format(*pictures.CROP_LEGEND[pictures._CONVENTION])
    assert f'fill="{covered}"' in svg


def test_a_repro_too_large_to_draw_says_so(results):
    rng = np.random.default_rng(0)
    big = Case("big", Scene(64, 64, rng.uniform(0, 64, size=(300, 3, 2))))
    failure = next(r for r in results if "repro" in r.evidence)
    result = Result("r", "big", "conformance", "fail", "m", {}, {"repro": case_to_json(big)})
    uri, caption = repro_drawn(result)
    assert uri is None and "300 triangles" in caption and "not drawn" in caption
    huge = Case("huge", Scene(2048, 16, [[[0, 0], [4, 0], [0, 4]]]))
    uri, caption = repro_drawn(Result("r", "huge", "conformance", "fail", "m", {}, {"repro": case_to_json(huge)}))
    assert uri is None and "2048 x 16" in caption
    assert pictures.draw_repro(Result("r", "c", "run", "error", "m")) is None
    back = results_from_json(json.loads(json.dumps(results_to_json([failure], "custom", 0, {}))))[0]
    uri, caption = repro_picture(back)  # read back: no convention known, the triangles alone
    assert "no convention known" in caption


def test_the_motion_series_is_a_png_plot_with_axes_and_units(report):
    failure = _failure((report / MOTION_PAGE).read_text(), "failure-0")
    plot = re.search(r'<img src="(data:image/png;base64,[^"]+)" alt="per-frame metrics">', failure)
    assert plot
    image = Image.open(io.BytesIO(_decoded(plot.group(1))))
    assert image.format == "PNG" and image.width >= 400 and image.height >= 200
    assert pictures.series_label("changed_pixels") == ("pixels that changed", "pixels")
    assert pictures.series_label("max_uv_error_texels") == ("largest u, v error", "texels")


def test_the_plot_labels_its_axes_and_names_its_series(monkeypatch):
    from matplotlib.figure import Figure

    drawn = []
    monkeypatch.setattr(Figure, "savefig", lambda self, *args, **kwargs: drawn.append(self))
    pictures.series_plot({"mismatches": [0, 2, 1], "max_uv_error_texels": [0.1, float("inf"), 0.2]})
    axes = drawn[0].axes
    assert [ax.get_ylabel().replace("\n", " ") for ax in axes] == ["texel mismatches (pixels)", "largest u, v error (texels)"]
    assert axes[-1].get_xlabel() == "frame"
    legends = [[t.get_text() for t in ax.get_legend().get_texts()] for ax in axes]
    assert legends == [["texel mismatches"], ["largest u, v error (1 non-finite frames not drawn)"]]


def test_the_replay_command_quotes_the_spec_given(report, results, tmp_path):
    failure = _failure((report / TIE_PAGE).read_text(), "failure-0")
    assert "<code>rastercheck replay repros/bad_wrong_tie_claim/lattice-bits-0--conformance.json " \
           "--rasterizer my_raster.py:MyRasterizer</code>" in failure
    write_report(tmp_path, CONVENTIONS, results, seed=0)  # no specs: the name
    assert "--rasterizer bad_wrong_tie_claim</code>" in (tmp_path / TIE_PAGE).read_text()


def test_skipped_rasterizers_are_listed_with_why(report):
    html = (report / "index.html").read_text()
    assert '<h2 id="skipped">Skipped</h2>' in html
    assert "<code>cairo</code>" in html and "pycairo is not installed: pip install &#39;.[cairo]&#39;" in html


def test_the_heat_map_and_the_diff_share_no_colour(report):
    heat, diff = set(pictures.HEAT_LEGEND.values()), set(pictures.DIFF_LEGEND.values())
    assert not heat & diff
    # the animations say missing and extra as the diff does, and use no heat-map colour
    assert pictures.LEGEND["oracle only (missing)"] == pictures.DIFF_LEGEND["missing (oracle only)"]
    assert pictures.LEGEND["extra"] == pictures.DIFF_LEGEND["extra (rasterizer only)"]
    assert not set(pictures.LEGEND.values()) & heat
    html = (report / TIE_PAGE).read_text()
    for legend in (pictures.HEAT_LEGEND, pictures.DIFF_LEGEND, pictures.LEGEND, pictures.CROP_LEGEND):
        for name, rgb in legend.items():
            assert f'<span class="swatch" style="background: rgb({rgb[0]}, {rgb[1]}, {rgb[2]})"></span>{name}' in html


def test_the_pictures_use_the_legend_colours(results):
    failure = next(r for r in results if r.check == "conformance" and r.status == "fail")
    drawn = pictures.draw(failure)
    for key, legend in (("heatmap", pictures.HEAT_LEGEND), ("diff", pictures.DIFF_LEGEND)):
        image = np.asarray(Image.open(io.BytesIO(_decoded(drawn[key]))).convert("RGB")).reshape(-1, 3)
        used = {tuple(int(c) for c in rgb) for rgb in np.unique(image, axis=0)}
        assert used <= set(legend.values()) | {(255, 255, 255)}, used - set(legend.values())


def test_index_links_the_comparison_and_diff_pages_whenever_they_exist(results, tmp_path):
    write_report(tmp_path, CONVENTIONS, results, seed=0)
    html = (tmp_path / "index.html").read_text()
    assert 'href="compare.html"' not in html and 'href="diff.html"' not in html
    data: dict[str, list] = {"explanations": [], "comparisons": []}
    write_comparison(tmp_path, data, candidates=3, seed=0)  # written after the report: the index learns of it
    assert 'href="compare.html"' in (tmp_path / "index.html").read_text()
    (tmp_path / "diff.html").write_text("<!doctype html>")
    write_report(tmp_path, CONVENTIONS, results, seed=0)
    html = (tmp_path / "index.html").read_text()
    assert 'href="compare.html"' in html and 'href="diff.html"' in html


def test_the_command_line_passes_specs_and_skipped_rasterizers_to_the_report(tmp_path, monkeypatch, capsys):
    import harness.engine.registry

    real = harness.engine.registry.load

    def load(spec, **options):
        if spec == "cairo_like":
            raise Unavailable("libcairo_like is not installed: pip install cairo_like")
        return real(spec, **options)

    monkeypatch.setattr(harness.engine.registry, "load", load)
    out = tmp_path / "rep"
    spec = "tests.known_bad.misc:WrongTieClaim"
    code = main(["run", "--rasterizer", spec, "--rasterizer", "cairo_like", "--case", "lattice/bits-0",
                 "--check", "conformance", "--no-fingerprints", "--out", str(out)])
    assert code == 1
    assert "skipped cairo_like: libcairo_like is not installed" in capsys.readouterr().err
    index = (out / "index.html").read_text()
    assert "<code>cairo_like</code>" in index and "libcairo_like is not installed: pip install cairo_like" in index
    page = (out / TIE_PAGE).read_text()
    assert f"--rasterizer {spec}</code>" in page and "rastercheck replay repros/bad_wrong_tie_claim/" in page


def test_the_presentation_imports_matplotlib_only_to_plot():
    code = "import sys, harness.report.pages, harness.report.pictures; assert 'matplotlib' not in sys.modules; print('ok')"
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr[-2000:]


def test_the_conventions_table_shows_each_rule_input_and_line_rule_in_its_columns(results, tmp_path):
    """The new rules (issue 33): a coverage rule, an input precision and a line rule each
    land in their own column, beside what identify found; a rasterizer with no convention
    says so."""
    from harness.contract.conventions import Convention, LineRule

    facets = {"bad_wrong_tie_claim": Convention(coverage="area-threshold", input="fixed6").facets(),
              "bad_no-prestep": Convention(input="float32", subpixel_bits=8, line=LineRule("parallelogram")).facets()}
    write_report(tmp_path, CONVENTIONS, results, seed=0, facets=facets,
                 scene_kinds={"bad_wrong_tie_claim": ("triangles",), "bad_no-prestep": ("triangles", "lines"),
                              "bad_raises": ("triangles",)})
    index = (tmp_path / "index.html").read_text()
    table = index[index.index('<table class="conventions">'):]
    table = table[:table.index("</table>")]
    rows = {}
    for row in table.split("<tr>")[2:]:
        named = re.search(r'<a href="[^"]+">([^<]+)</a>', row)
        assert named is not None, row
        rows[named.group(1)] = re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)
    assert rows["bad_wrong_tie_claim"][1:5] == ["an area threshold (a pixel iff at least 0.5 of it is covered)",
                                                "(none: the rule decides)",
                                                "26.6 fixed-point input (1/64 px, nearest-even)", "none"]
    assert "takes no lines" in rows["bad_wrong_tie_claim"][6]
    assert rows["bad_no-prestep"][3:5] == ["float32 input", "1/256 px"]
    assert rows["bad_no-prestep"][6] == "parallelogram lines (Vulkan non-strict)"
    assert "no convention declared or identified" in rows["bad_raises"][1]
    assert all("not identified" in cells[-1] for cells in rows.values())


def test_a_picture_that_cannot_be_drawn_costs_only_itself(monkeypatch):
    """The atlas once lost a 30-minute run: drawing a path failure of cairo's row-sampled
    model raised in the report (a convention the picture could not derive). A drawing bug
    now leaves that picture out and says why in the failure's evidence; the page is written."""
    from harness.checks.records import Result
    from harness.report import pages

    def broken(result):
        raise ValueError("no picture for this convention")

    monkeypatch.setattr(pages, "draw", broken)
    monkeypatch.setattr(pages, "draw_repro", broken)
    failure = Result("somebody", "paths/star/nonzero", "accuracy", "fail", "alphas off", {}, {"pixels": []})
    problem = pages._problem(failure, 0, "somebody")
    assert problem["images"] == []
    shown = str(problem)
    assert "picture not drawn" in shown and "no picture for this convention" in shown


def test_the_winding_picture_of_an_area_model_is_taken_at_its_point_sampled_twin():
    """Each area model (rows, a supersampler, a library's levels) has a single-sample twin
    for its windings and sample shares."""
    from harness.contract.conventions import Convention

    for convention in (Convention(coverage="area", rows=15, full_rows=True, input="fixed8"),
                       Convention(coverage="area", supersample=2, input="float32"),
                       Convention(coverage="area", quantisation="ftgrays", input="fixed6"),
                       Convention(coverage="area", samples=4)):
        twin = convention.point_sampled((0.5, 0.5))
        assert twin.model.single_sample and twin.input == convention.input
