"""The terminal names failures (issue 28, point 4): ``rastercheck run`` ends with the
failing results grouped by cause -- the grouping of the run report and of the campaign
page (harness.diagnose.causes.by_cause) -- the largest first, each with its count, checks, reasons
and a minimal repro that exists, the rest counted; one line bug is one cause; the report's
headings are the signatures' words, whole; a passing rasterizer prints no failure block."""

import contextlib
import fnmatch
import io
import json
import re
from pathlib import Path
from typing import Any

import pytest

from cases.suites import suite
from harness import run_suite
from harness.cli.main import main
from harness.diagnose.causes import by_cause
from harness.diagnose.signatures import Signature
from harness.results.output import results_from_json
from tests.known_bad.antialiasing import BiasedArea
from tests.known_bad.lines import OffByOneLast
from tests.known_bad.misc import WrongTieClaim

BAD = ["tests.known_bad.lines:OffByOneLast", "tests.known_bad.misc:WrongTieClaim", "tests.known_bad.antialiasing:BiasedArea"]
CASES = ["lines/octants/*", "lattice/bits-0", "motion/triangle/translate-x-1/16"]
CAUSE = re.compile(r"^  (\S+): (\S+) -- (\d+) failing, seen by (.+)$")
SIGNATURE = re.compile(r"^ +(\d+) (fail|error) (\S+?): (.+)$")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The command line on a line drawer off by one at the last pixel, a wrong tie claim
    and a biased anti-aliaser, two causes named in the terminal: (exit code, printed lines,
    report folder, results read back from its JSON)."""
    out = tmp_path_factory.mktemp("causes")
    argv = ["run", "--no-fingerprints", "--out", str(out / "report"), "--json", str(out / "r.json"), "--causes", "2"]
    for spec in BAD:
        argv += ["--rasterizer", spec]
    for glob in CASES:
        argv += ["--case", glob]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(argv)
    results = results_from_json(json.loads((out / "r.json").read_text()))
    return code, printed.getvalue().splitlines(), out / "report", results


def _causes(lines):
    """The causes printed: (rasterizer, cause, count, checks, [(count, status, check, words)], repro)."""
    found: list[list[Any]] = []
    for line in lines:
        if (m := CAUSE.match(line)) is not None:
            found.append([m.group(1), m.group(2), int(m.group(3)), m.group(4).split(", "), [], None])
        elif found and (m := SIGNATURE.match(line)) is not None:
            found[-1][4].append((int(m.group(1)), m.group(2), m.group(3), m.group(4)))
        elif found and line.startswith("    repro: "):
            found[-1][5] = line.removeprefix("    repro: ")
    return found


def test_the_terminal_ends_with_the_failures_by_cause_the_largest_first(run):
    code, lines, report, results = run
    failing = [r for r in results if r.status in ("fail", "error")]
    groups = by_cause(results)  # as the JSON keeps each result's signature
    assert code == 1 and len(groups) == 3
    start = next(k for k, line in enumerate(lines) if line.endswith("most first:"))
    assert lines[start] == f"{len(failing)} failing results in 3 causes, most first:"
    assert lines[start - 1].startswith("report: ")  # the block ends the output
    printed = _causes(lines[start:])
    assert [(p[0], p[1], p[2]) for p in printed] == [(g.rasterizer, g.cause, g.count) for g in groups[:2]]
    assert printed[0][2] >= printed[1][2] >= groups[2].count
    for (rasterizer, _, _, checks, signatures, repro), group in zip(printed, groups):
        assert checks == group.checks and set(checks) <= {r.check for r in failing if r.rasterizer == rasterizer}
        assert signatures and signatures[0][:2] == (group.signatures[0].count, group.signatures[0].status)
        for (_, _, check, words), shown in zip(signatures, group.signatures):  # each reason in the signature's words
            assert f"{check}: {words}" == shown.describe() and check in checks
        saved = json.loads(Path(repro).read_text())  # a repro run wrote, of this cause
        assert Path(repro).is_relative_to(report / "repros" / rasterizer) and saved["check"] in checks
    rest = groups[2]
    assert lines[-1] == f"  ... 1 more cause ({rest.count} failing) in {report / 'index.html'}"


def test_a_line_bug_is_one_cause_whichever_checks_see_it(run):
    """A drawer one pixel short at each end fails conformance, reversal and length on each
    case: one cause (the line rule), its signatures under it -- not a heading per message."""
    _, lines, report, results = run
    mine = [g for g in by_cause(results) if g.rasterizer == OffByOneLast.name]
    assert len(mine) == 1 and mine[0].cause == "line-rule"
    assert len(mine[0].checks) >= 3 and len(mine[0].signatures) >= 3
    assert mine[0].count == sum(r.status == "fail" for r in results if r.rasterizer == OffByOneLast.name)
    page = (report / f"rasterizer-{OffByOneLast.name}.html").read_text()
    assert page.count('class="cause ') == 1 and f"{mine[0].count} failing results of" in page
    printed = [p for p in _causes(lines) if p[0] == OffByOneLast.name]
    assert len(printed) == 1 and len(printed[0][4]) == min(3, len(mine[0].signatures))
    hidden = len(mine[0].signatures) - 3
    assert hidden <= 0 or any(line.strip().startswith(f"... {hidden} more signature") for line in lines)


def test_the_report_headings_are_the_signatures_words_whole(run):
    """Each signature's heading is its description as the campaign page words it, never
    cut (the anti-aliased ones included)."""
    _, _, report, results = run
    for name in (OffByOneLast.name, WrongTieClaim.name, BiasedArea.name):
        page = (report / f"rasterizer-{name}.html").read_text()
        headings = re.findall(r'<h3 class="(?:fail|error)">(fail|error) · (.*?) <span class="count">(\d+) · ([^<]+)</span></h3>',
                              page)
        groups = [s for g in by_cause(results) if g.rasterizer == name for s in g.signatures]
        assert len(headings) == len(groups) > 0
        for (status, words, count, key), group in zip(headings, groups):
            assert words.replace("&#39;", "'") == Signature(*key.split("|")).describe() == group.describe()
            assert (status, int(count), key) == (group.status, group.count, group.signature.key)
            assert "…" not in words and not words.endswith("(")


def test_the_library_groups_as_the_command_does(run):
    """run_suite's results carry the same signatures: by_cause over them is the grouping
    the command printed and wrote (read back from JSON)."""
    _, _, _, results = run
    cases = [c for c in suite("quick") if any(fnmatch.fnmatchcase(c.id, glob) for glob in CASES)]
    library = run_suite([OffByOneLast(), WrongTieClaim(), BiasedArea()], cases=cases, isolate=False, identify=False)

    def shape(groups):
        return [(g.rasterizer, g.cause, [(s.signature.key, s.status, s.count) for s in g.signatures]) for g in groups]

    assert shape(by_cause(library)) == shape(by_cause(results))


def test_a_passing_rasterizer_prints_no_failure_block(tmp_path, capsys):
    code = main(["run", "--rasterizer", "centre_scanline", "--no-fingerprints", "--case", "lattice/bits-0",
                 "--out", str(tmp_path)])
    printed = capsys.readouterr().out
    assert code == 0 and "failing" not in printed and "cause" not in printed and "report: " in printed


def test_an_error_without_a_repro_names_its_case(tmp_path, capsys):
    code = main(["run", "--rasterizer", "tests.known_bad.misc:Raises", "--no-fingerprints", "--case", "lattice/bits-0",
                 "--out", str(tmp_path)])
    lines = capsys.readouterr().out.splitlines()
    assert code == 1 and lines[-4:] == [
        "1 failing result in 1 cause, most first:",
        "  bad_raises: exception-RuntimeError -- 1 failing, seen by run",
        "       1 error run: raised RuntimeError",
        "    case: lattice/bits-0 (no minimal repro)"]


def test_samples_on_edges_by_chance_are_not_a_tie_rule_cause():
    """A scanline filler without its prestep whose wrong samples on a mesh all happen to lie
    exactly on edges: the run draws the wrong triangles again shifted off them (the tie
    trial, as a campaign does), they are still wrong, and the failure goes under the
    sample point with the filler's others -- one cause, not a tie rule besides."""
    from tests.known_bad.scanlines import ScanlineBug

    cases = [c for c in suite("quick") if c.id in ("watertight/grid-6x6-anti/none", "lattice/bits-0")]
    results = run_suite([ScanlineBug("no-prestep")], cases=cases, isolate=False, identify=False, repros=False)
    on_edges = next(r for r in results if r.case == "watertight/grid-6x6-anti/none" and r.check == "conformance")
    assert on_edges.evidence["tie_trial"]["passes"] is False
    assert [g.cause for g in by_cause(results)] == ["sample-point"]
