"""The CI gate (``rastercheck gate``, harness.results.gate) and the JUnit it writes (harness.results.output).

Most tests feed small synthetic result lists to the functions; a few run the command on
one or two cases. The JUnit is validated against tests/data/JUnit.xsd: the Ant/Jenkins
schema as published at github.com/windyroad/JUnit-Schema (Apache License 2.0, its text in
tests/data/JUnit.xsd.LICENSE), copied unchanged.
"""

import json
import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from cases.suites import suite
from harness.checks import Result, timing_metrics
from harness.cli.main import main
from harness.engine.runner import run_suite
from harness.results.gate import compare_with_baseline, gated_metrics, key, load_baseline, save_baseline
from harness.results.output import write_junit

JUNIT_XSD = Path(__file__).parents[1] / "data" / "JUnit.xsd"

BROKEN = textwrap.dedent('''
    from harness import Convention
    from rasterizers.centre_scanline import CentreScanline

    class CentreScanline2(CentreScanline):
        """Registered under the built-in's name: a change that breaks its tie rule."""
        name = "centre_scanline"
        convention = Convention(tie="bottom-right")
''')


@pytest.fixture(scope="module")
def junit_schema():
    import xmlschema  # here, not at collection: every test worker collects every module

    return xmlschema.XMLSchema(JUNIT_XSD)


def R(case, check="conformance", status="pass", message="ok", rasterizer="r", **metrics):
    return Result(rasterizer, case, check, status, message, metrics)


def lines_of(verdict):
    return "\n".join(verdict.lines())


# -- completeness -------------------------------------------------------------------------


def test_a_baseline_entry_missing_from_the_run_is_a_regression_unless_allowed(tmp_path):
    save_baseline(tmp_path / "b.json", [R("a"), R("b"), R("b", "degenerate")])
    baseline = load_baseline(tmp_path / "b.json")
    verdict = compare_with_baseline([R("a")], baseline)
    assert not verdict.ok and len(verdict.regressions) == 2
    assert "MISSING r|b|conformance: in the baseline (pass), not in this run" in lines_of(verdict)
    allowed = compare_with_baseline([R("a")], baseline, allow_missing=True)
    assert allowed.ok and len(allowed.of("absent")) == 2 and "not run (missing allowed)" in allowed.counts()


def test_a_run_of_another_rasterizer_is_refused_in_one_line(tmp_path):
    save_baseline(tmp_path / "b.json", [R("a", rasterizer="theirs")])
    with pytest.raises(ValueError, match="no rasterizer in common") as info:
        compare_with_baseline([R("a", rasterizer="mine")], load_baseline(tmp_path / "b.json"))
    assert "\n" not in str(info.value) and "theirs" in str(info.value) and "mine" in str(info.value)
    # one rasterizer in common is enough: the other's entries are missing
    verdict = compare_with_baseline([R("a", rasterizer="theirs"), R("a", rasterizer="mine")],
                                    {**load_baseline(tmp_path / "b.json"), "gone|a|conformance": {"status": "pass"}})
    assert [f.key for f in verdict.of("missing")] == ["gone|a|conformance"] and len(verdict.of("new")) == 1


def test_one_line_per_regressed_result_grouped_by_check_with_counts():
    baseline = {key(R(c)): {"status": "pass", "metrics": {"wrong": 0}} for c in ("a", "b", "c")}
    baseline |= {key(R("a", "closed")): {"status": "pass", "metrics": {}},
                 key(R("k", "closed")): {"status": "fail", "metrics": {}, "reason": "winds the wrong way"}}
    run = [R("a", status="fail", message="3 pixels wrong", wrong=3),  # status and metric: one line
           R("b", wrong=2),  # a metric alone
           R("c"), R("a", "closed"), R("k", "closed", "fail")]
    verdict = compare_with_baseline(run, baseline)
    text = lines_of(verdict)
    assert verdict.lines()[0] == "conformance: 2 regressions"
    assert "  REGRESSION r|a|conformance: was pass, now fail: 3 pixels wrong; wrong worsened from 0 to 3" in text
    assert "  REGRESSION r|b|conformance: pass as before; wrong worsened from 0 to 2" in text
    assert text.count("r|a|conformance") == 1 and len(verdict.regressions) == 2
    assert "closed: 1 known failure" in text and "r|k|closed" not in text  # known failures are counted, not listed
    assert verdict.lines().index("closed: 1 known failure") > 0  # the registry's order: conformance first


def test_new_results_and_unexpected_passes():
    baseline = {key(R("k")): {"status": "fail", "metrics": {}, "reason": "claims top-left"}}
    verdict = compare_with_baseline([R("k"), R("n"), R("m", status="error", message="timeout: 60 s")], baseline)
    assert [str(f) for f in verdict.of("fixed")] == ["r|k|conformance: was fail (claims top-left), now passes"]
    assert verdict.of("new")[0].key == "r|n|conformance"
    assert verdict.regressions == ["r|m|conformance: new, error: timeout: 60 s"]
    assert "UNEXPECTEDLY PASSING r|k|conformance" in lines_of(verdict)


# -- timings never enter a baseline ---------------------------------------------------------


def test_timings_are_not_gated():
    assert {"seconds", "work_ratio"} <= timing_metrics()
    assert not timing_metrics() & set(gated_metrics()) and "wrong" in gated_metrics()


def test_an_unchanged_run_rewrites_the_baseline_byte_for_byte(tmp_path):
    cases = [c for c in suite("quick") if c.id in ("lattice/bits-0", "degenerate/epsilon/width-1e-8-above")]
    first, second = (run_suite(["centre_scanline"], cases=cases, repros=False) for _ in range(2))
    timed = [r for r in first if "work_ratio" in r.metrics]
    assert timed and all("seconds" in r.metrics for r in first)  # the runs do carry timings
    save_baseline(tmp_path / "one.json", first)
    save_baseline(tmp_path / "two.json", second, load_baseline(tmp_path / "one.json"))
    one = (tmp_path / "one.json").read_bytes()
    assert one == (tmp_path / "two.json").read_bytes()
    assert b"work_ratio" not in one and b"seconds" not in one
    data = json.loads(one)
    assert one.decode() == json.dumps(data, indent=1, sort_keys=True) + "\n"  # sorted keys, one stable layout


def test_reasons_survive_an_update_and_two_different_runs_differ(tmp_path):
    save_baseline(tmp_path / "b.json", [R("a", status="fail", message="3 pixels wrong", wrong=3, seconds=0.1)])
    entries = json.loads((tmp_path / "b.json").read_text())["entries"]
    entries["r|a|conformance"]["reason"] = "draws bottom-right ties; see issue 7"
    (tmp_path / "b.json").write_text(json.dumps({"schema": 1, "entries": entries}))
    save_baseline(tmp_path / "b.json", [R("a", status="fail", message="4 pixels wrong", wrong=4, seconds=0.2)],
                  load_baseline(tmp_path / "b.json"))
    entry = load_baseline(tmp_path / "b.json")["r|a|conformance"]
    assert entry == {"status": "fail", "metrics": {"wrong": 4}, "reason": "draws bottom-right ties; see issue 7"}


def test_an_update_of_a_partial_run_keeps_the_rest_only_when_asked(tmp_path):
    save_baseline(tmp_path / "b.json", [R("a"), R("b")])
    save_baseline(tmp_path / "b.json", [R("a")], load_baseline(tmp_path / "b.json"), keep_missing=True)
    assert set(load_baseline(tmp_path / "b.json")) == {"r|a|conformance", "r|b|conformance"}
    save_baseline(tmp_path / "b.json", [R("a")], load_baseline(tmp_path / "b.json"))
    assert set(load_baseline(tmp_path / "b.json")) == {"r|a|conformance"}


# -- the baseline file is validated ---------------------------------------------------------


@pytest.mark.parametrize("entries, where", [
    ({"r|a|conformance": "pass"}, 'entries["r|a|conformance"]'),
    ({"r|a|conformance": {"status": "pass", "metrics": {"wrong": "3"}}}, 'entries["r|a|conformance"].metrics.wrong'),
    ({"r|a|conformance": {"status": "pass", "metrics": [3]}}, 'entries["r|a|conformance"].metrics'),
    ({"r|a|conformance": {"status": "passed"}}, 'entries["r|a|conformance"].status'),
    ({"r|a|conformance": {"metrics": {}}}, 'entries["r|a|conformance"]: lacks \'status\''),
    ({"r|a|conformance": {"status": "fail", "reason": 7}}, 'entries["r|a|conformance"].reason'),
    ({"no-bars": {"status": "pass"}}, "rasterizer|case|check"),
    ([], "at entries"),
])
def test_a_malformed_baseline_is_named_in_one_line(tmp_path, entries, where):
    path = tmp_path / "b.json"
    path.write_text(json.dumps({"schema": 1, "entries": entries}))
    with pytest.raises(ValueError) as info:
        load_baseline(path)
    text = str(info.value)
    assert text.startswith(f"{path}: malformed baseline at ") and where in text and "\n" not in text


@pytest.mark.parametrize("content, words", [
    ("{", "unreadable baseline"), ('{"schema": 2, "entries": {}}', "not a rastercheck baseline of schema 1"),
    ('["schema", 1]', "not a rastercheck baseline"), (None, "no such baseline"),
])
def test_an_unreadable_baseline_is_named_in_one_line(tmp_path, content, words):
    path = tmp_path / "b.json"
    if content is not None:
        path.write_text(content)
    with pytest.raises(ValueError, match=words):
        load_baseline(path)


def test_a_baseline_of_the_first_format_still_loads_and_gates(tmp_path):
    """As the gate wrote it before timings were left out and reasons lost their prefix."""
    path = tmp_path / "old.json"
    path.write_text(json.dumps({"schema": 1, "entries": {
        "r|a|conformance": {"metrics": {"wrong": 0.0}, "status": "pass"},
        "r|d|degenerate": {"metrics": {"work_ratio": 1.0107749851884105}, "status": "pass"},
        "r|k|conformance": {"metrics": {"wrong": 5.0}, "reason": "known failure: 5 pixels wrong", "status": "fail"},
    }}, indent=1, sort_keys=True))
    baseline = load_baseline(path)
    run = [R("a", wrong=0), R("d", "degenerate", work_ratio=40.0), R("k", status="fail", wrong=5)]
    verdict = compare_with_baseline(run, baseline)
    assert verdict.ok and len(verdict.of("known")) == 1  # a slower work_ratio is no regression: a timing
    write_junit(tmp_path / "j.xml", run, verdict)
    skipped = ET.parse(tmp_path / "j.xml").getroot().find(".//skipped")
    assert skipped is not None and skipped.get("message") == "known failure: 5 pixels wrong"


# -- JUnit ------------------------------------------------------------------------------------


def suites_of(path):
    return ET.parse(path).getroot().findall("testsuite")


def outcome(path, rasterizer, case, check="conformance"):
    for suite_ in suites_of(path):
        for tc in suite_.findall("testcase"):
            if tc.get("classname") == f"{rasterizer}.{check}" and tc.get("name") == case:
                return [child.tag for child in tc], tc
    raise AssertionError(f"no testcase {rasterizer}.{check} {case}")


def assert_counts_match(path):
    for suite_ in suites_of(path):
        cases = suite_.findall("testcase")
        assert int(suite_.get("tests")) == len(cases)
        for attribute, tag in (("failures", "failure"), ("errors", "error"), ("skipped", "skipped")):
            assert int(suite_.get(attribute)) == sum(tc.find(tag) is not None for tc in cases), attribute


def test_junit_under_the_gate(tmp_path, junit_schema):
    baseline = {key(R(c)): {"status": "pass", "metrics": {"wrong": 0}} for c in ("same", "regressed", "crashed", "worse", "gone")}
    baseline |= {key(R("known")): {"status": "fail", "metrics": {}, "reason": "claims top-left, draws bottom-right"},
                 key(R("crashes")): {"status": "error", "metrics": {}, "reason": "segfaults on NaN"},
                 key(R("fixed")): {"status": "fail", "metrics": {}, "reason": "was off by one"}}
    run = [R("same"), R("regressed", status="fail", message="3 pixels wrong"),
           R("crashed", status="error", message="timeout: took longer than 60 s"), R("worse", wrong=2),
           R("known", status="fail", message="9 pixels wrong"), R("crashes", status="error", message="SIGSEGV: killed"),
           R("fixed"), R("skipped", status="skip", message="no convention"), R("other", rasterizer="s")]
    verdict = compare_with_baseline(run, baseline)
    path = write_junit(tmp_path / "j.xml", run, verdict)
    junit_schema.validate(path)
    assert_counts_match(path)
    assert outcome(path, "r", "same")[0] == []
    tags, tc = outcome(path, "r", "known")
    assert tags == ["skipped"] and tc.find("skipped").get("message") == "known failure: claims top-left, draws bottom-right"
    assert outcome(path, "r", "crashes")[0] == ["skipped"]  # a known crash is known too: the gate is green on it
    tags, tc = outcome(path, "r", "regressed")
    assert tags == ["failure"] and tc.find("failure").get("message") == "was pass, now fail: 3 pixels wrong"
    tags, crashed = outcome(path, "r", "crashed")
    assert tags == ["error"] and crashed.find("error").get("type") == "timeout"
    assert outcome(path, "r", "worse")[0] == ["failure"]
    assert outcome(path, "r", "fixed")[0] == []  # passes, with a note on its suite
    assert outcome(path, "r", "skipped")[0] == ["skipped"]
    assert outcome(path, "r", "gone")[1].find("failure").get("type") == "missing"
    r_suite = next(s for s in suites_of(path) if s.get("name") == "r")
    note = "UNEXPECTEDLY PASSING r|fixed|conformance: was fail (was off by one), now passes"
    assert [p.get("value") for p in r_suite.find("properties")] == [note] and note in r_suite.find("system-out").text
    assert (r_suite.get("tests"), r_suite.get("failures"), r_suite.get("errors"), r_suite.get("skipped")) == ("9", "3", "1", "3")
    # allowed to be missing: no testcase at all
    path = write_junit(tmp_path / "k.xml", run, compare_with_baseline(run, baseline, allow_missing=True))
    assert "gone" not in path.read_text()


def test_junit_of_a_plain_run(tmp_path, junit_schema):
    run = [R("a"), R("b", status="fail", message="3 pixels wrong"), R("c", status="error", message="ValueError: no"),
           R("d", status="skip", message="no convention"),
           R("e", status="fail", message="bad \x00 byte \x1b[31m", rasterizer="s")]
    run[1].evidence["repro_path"] = "repros/r/b--conformance.json"
    path = write_junit(tmp_path / "j.xml", run)
    junit_schema.validate(path)
    assert_counts_match(path)
    assert [outcome(path, "r", c)[0] for c in "abcd"] == [[], ["failure"], ["error"], ["skipped"]]
    assert "minimal repro: repros/r/b--conformance.json" in outcome(path, "r", "b")[1].find("failure").text
    assert outcome(path, "r", "c")[1].find("error").get("type") == "ValueError"
    assert "\ufffd" in outcome(path, "s", "e")[1].find("failure").get("message")  # control characters cannot go into XML


# -- the command ------------------------------------------------------------------------------


def gate(tmp_path, *args, rasterizer="centre_scanline"):
    return main(["gate", "--rasterizer", rasterizer, "--case", "lattice/bits-0", "--no-fingerprints",
                 "--out", str(tmp_path / "rep"), *args])


def test_gate_flags_a_regression_and_reports_a_fix(tmp_path, capsys):
    baseline = tmp_path / "baseline.json"
    assert gate(tmp_path, "--baseline", str(baseline), "--update-baseline") == 0
    assert "baseline updated" in capsys.readouterr().out
    bad = tmp_path / "bad.py"
    bad.write_text(BROKEN)
    assert gate(tmp_path, "--baseline", str(baseline), rasterizer=f"{bad}:CentreScanline2") == 1
    out = capsys.readouterr().out
    assert "conformance: 1 regression\n  REGRESSION centre_scanline|lattice/bits-0|conformance: was pass, now fail" in out
    # the broken one becomes the baseline, with reasons; the fix then shows up, with the command that accepts it
    assert gate(tmp_path, "--baseline", str(baseline), "--update-baseline", rasterizer=f"{bad}:CentreScanline2") == 0
    entries = json.loads(baseline.read_text())["entries"]
    assert entries["centre_scanline|lattice/bits-0|conformance"]["reason"]
    capsys.readouterr()
    assert gate(tmp_path, "--baseline", str(baseline)) == 0
    out = capsys.readouterr().out
    assert "UNEXPECTEDLY PASSING centre_scanline|lattice/bits-0|conformance" in out
    assert (f"to accept the 1 unexpected passes as the new baseline: rastercheck gate --rasterizer centre_scanline --suite quick "
            f"--seed 0 --case lattice/bits-0 --baseline {baseline} --update-baseline") in out


def test_gate_with_known_failures_is_green_and_its_junit_has_no_failure(tmp_path, capsys, junit_schema):
    baseline, junit = tmp_path / "baseline.json", tmp_path / "junit.xml"
    bad = tmp_path / "bad.py"
    bad.write_text(BROKEN)
    spec = f"{bad}:CentreScanline2"
    assert gate(tmp_path, "--baseline", str(baseline), "--update-baseline", "--junit", str(junit), rasterizer=spec) == 0
    assert gate(tmp_path, "--baseline", str(baseline), "--update-baseline", rasterizer=spec) == 0
    assert "baseline unchanged" in capsys.readouterr().out
    assert gate(tmp_path, "--baseline", str(baseline), "--junit", str(junit), rasterizer=spec) == 0
    assert "conformance: 1 known failure" in capsys.readouterr().out
    junit_schema.validate(junit)
    assert_counts_match(junit)
    (suite_,) = suites_of(junit)
    assert suite_.get("failures") == "0" and suite_.get("errors") == "0" and int(suite_.get("skipped")) >= 1
    assert suite_.find("testcase/skipped").get("message").startswith("known failure: ")


def test_gate_of_another_rasterizer_is_a_usage_error(tmp_path, capsys, monkeypatch):
    save_baseline(tmp_path / "b.json", [R("lattice/bits-0", rasterizer="fixed_point")])

    def no_work(*args, **kwargs):
        raise AssertionError("the suite ran before the baseline's rasterizers were compared with the run's")

    monkeypatch.setattr("harness.identify.fingerprint.identify_all", no_work)  # refused as soon as the rasterizers are loaded
    assert gate(tmp_path, "--baseline", str(tmp_path / "b.json")) == 2
    err = capsys.readouterr().err
    assert "no rasterizer in common" in err and str(tmp_path / "b.json") in err and err.count("\n") == 1


def test_gate_with_an_entry_the_run_lacks_fails_on_it(tmp_path, capsys):
    baseline = tmp_path / "b.json"
    assert gate(tmp_path, "--baseline", str(baseline), "--update-baseline") == 0
    entries = load_baseline(baseline)
    entries["centre_scanline|lattice/bits-9|conformance"] = {"status": "pass", "metrics": {}}
    baseline.write_text(json.dumps({"schema": 1, "entries": entries}))
    capsys.readouterr()
    assert gate(tmp_path, "--baseline", str(baseline)) == 1
    out = capsys.readouterr().out
    assert "MISSING centre_scanline|lattice/bits-9|conformance" in out and "1 regressions (1 missing)" in out
    assert gate(tmp_path, "--baseline", str(baseline), "--allow-missing") == 0


@pytest.mark.parametrize("update", [False, True])
def test_a_baseline_that_is_a_folder_is_a_usage_error(tmp_path, capsys, update):
    folder = tmp_path / "folder"
    folder.mkdir()
    assert gate(tmp_path, "--baseline", str(folder), *(["--update-baseline"] if update else [])) == 2
    err = capsys.readouterr().err
    assert "folder" in err and err.count("\n") == 1


def test_gate_needs_a_baseline(tmp_path, capsys):
    assert gate(tmp_path, "--baseline", str(tmp_path / "none.json")) == 2
    assert "no such baseline" in capsys.readouterr().err


def test_a_malformed_baseline_is_a_usage_error_even_when_updating(tmp_path, capsys):
    (tmp_path / "b.json").write_text('{"schema": 1, "entries": {"r|a|c": "pass"}}')
    assert gate(tmp_path, "--baseline", str(tmp_path / "b.json"), "--update-baseline") == 2
    assert 'malformed baseline at entries["r|a|c"]' in capsys.readouterr().err


def test_a_flaky_result_is_shown_not_a_regression_and_a_dropped_pass_is_shown():
    from harness.checks import Result
    from harness.results.gate import compare_with_baseline

    baseline = {"r|a|conformance": {"status": "pass", "metrics": {}}, "r|b|conformance": {"status": "pass", "metrics": {}}}
    results = [Result("r", "a", "conformance", "fail", "1 pixel missing", {}, {"flaky": ["fail", "pass", "fail"]}),
               Result("r", "b", "conformance", "skip", "skipped: upstream bug")]
    verdict = compare_with_baseline(results, baseline)
    assert verdict.ok and not verdict.regressions
    text = "\n".join(verdict.lines())
    assert "FLAKY r|a|conformance" in text and "NOW SKIPPED r|b|conformance" in text
    assert "1 flaky" in text and "1 passing before, skipped now" in text
