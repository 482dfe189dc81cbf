"""``rastercheck bench --kinds identify``: identify's seconds per built-in mode, grouped by
kind, in the bench's JSON. Smoke tests at the smallest scale: that it runs and reports, never
its timing."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from harness.cli.bench_identify import IDENTIFY_GOAL, format_identify_table, identify_summary, kind_of, run_identify_bench
from harness.cli.main import main


def test_each_mode_is_counted_under_its_kind() -> None:
    assert kind_of("single", ["triangles"]) == "triangles"
    assert kind_of("single", ["triangles", "paths"]) == "paths"
    assert kind_of("single", ["lines"]) == "lines"
    assert kind_of("single", ["points"]) == "points"
    assert kind_of("multisample", ["triangles"]) == "multisample"
    assert kind_of("area", ["triangles", "lines"]) == "area"


def test_a_mode_is_identified_in_a_fresh_process_and_reported() -> None:
    results = run_identify_bench(["point_sprites"], repeats=1, cold=False)
    assert len(results) == 1
    m = results[0]
    assert (m.workload, m.contender, m.kind, m.fault) == ("identify", "point_sprites", "points", "")
    assert m.seconds > 0 and 0 < m.identify_seconds <= m.seconds and m.calls > 0 and m.exact
    assert math.isnan(m.cold_seconds) and m.within_goal == (m.seconds < IDENTIFY_GOAL) and len(m.runs) == 1
    summary = identify_summary(results)
    assert summary["points"]["modes"] == ["point_sprites"] and summary["all"]["max_seconds"] == round(m.seconds, 3)
    table = format_identify_table(results)
    assert "point_sprites" in table and "slowest of points" in table


def test_an_unknown_mode_is_a_fault_of_its_own_row() -> None:
    m = run_identify_bench(["no_such_rasterizer_anywhere"], repeats=1, cold=False)[0]
    assert m.fault and math.isnan(m.seconds) and not m.within_goal


@pytest.mark.parametrize("kinds", ["identify"])
def test_the_command_writes_identify_rows_and_summary_in_the_json(tmp_path: Path, kinds: str,
                                                                  capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "bench.json"
    code = main(["bench", "--kinds", kinds, "--rasterizer", "point_sprites", "--budget", "0", "--json", str(out)])
    assert code == 0
    payload = json.loads(out.read_text())
    rows = payload["results"]
    assert [(r["workload"], r["contender"], r["kind"]) for r in rows] == [("identify", "point_sprites", "points")]
    assert payload["summary"]["identify"]["goal_seconds"] == IDENTIFY_GOAL
    assert "identify: rastercheck identify <spec>" in capsys.readouterr().out
