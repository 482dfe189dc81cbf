"""The catalogue of bad input (issue 13): every row a command line and the files it reads,
with the outcome it must end in -- one line and exit 2 for bad input, never a traceback --
within 60 s and 2 GB (tests/bounded.py).

Hostile plugins (that raise, hang, exit, lie or return garbage) have their own tests in
test_hostile.py, test_registry_and_cli.py and test_cli_run.py; baselines in test_gate.py.
"""

import json

import pytest

from cases.suites import suite
from harness.cli.main import main
from harness.contract.case import case_to_json
from tests.bounded import bounded, run_bounded


def _case(**changes):
    data = case_to_json(next(c for c in suite("quick") if c.id == "lattice/bits-0"))
    data.update(changes)
    return json.dumps(data)


def _nested(depth):
    return "[" * depth + "]" * depth


CATALOGUE = [
    # (what, files, argv, exit code, words on stderr)
    ("replay: not JSON", {"c.json": "{not json"}, ["replay", "c.json"], 2, "cannot read the case"),
    ("replay: nested too deep", {"c.json": _nested(100_000)}, ["replay", "c.json"], 2, "cannot read the case"),
    ("replay: not a case", {"c.json": "[1, 2]"}, ["replay", "c.json"], 2, "not a rastercheck case"),
    ("replay: missing file", {}, ["replay", "nothing.json"], 2, "cannot read the case"),
    ("replay: width 1e999", {"c.json": _case(width=1e999)}, ["replay", "c.json"], 2, "at width"),
    ("replay: width inf as text", {"c.json": _case(width="inf")}, ["replay", "c.json"], 2, "at width"),
    ("replay: width past the viewport limit", {"c.json": _case(width=2**20 + 3)}, ["replay", "c.json"], 2, "at width"),
    ("replay: a huge viewport", {"c.json": _case(width=2**20, height=2**20)}, ["replay", "c.json"], 2, "viewport is more than"),
    ("replay: width 64.9", {"c.json": _case(width=64.9)}, ["replay", "c.json"], 2, "at width"),
    ("replay: a decimal that no float64 is", {"c.json": _case(positions=[[["0.1", "0x0p+0"], [4, 0], [0, 4]]])},
     ["replay", "c.json"], 2, "0.1 is not exactly a float64"),
    ("replay: a JSON number that no float64 is", {"c.json": _case(positions=[[[0.1, 0], [4, 0], [0, 4]]]).replace(
        "0.1", "0.1000000000000000000001")}, ["replay", "c.json"], 2, "is not exactly a float64"),
    ("replay: text that is neither decimal nor hex", {"c.json": _case(positions=[[["1,5", "0"], [4, 0], [0, 4]]])},
     ["replay", "c.json"], 2, "at positions[0][0][0]"),
    ("replay: lattice 'no'", {"c.json": _case(lattice="no")}, ["replay", "c.json"], 2, "at lattice"),
    ("replay: region of the wrong shape", {"c.json": _case(region=[[0, 0, 0], [1, 1, 1], [2, 2, 2]])},
     ["replay", "c.json"], 2, "at region"),
    ("replay: a triangle of two vertices", {"c.json": _case(positions=[[[0, 0], [4, 0]]])}, ["replay", "c.json"], 2,
     "at positions[0]"),
    ("replay: ragged attributes", {"c.json": _case(attributes=[[[1.0], [1.0, 2.0], [3.0]]])}, ["replay", "c.json"], 2,
     "attributes"),
    ("replay: NUL in the id", {"c.json": _case(id="a\u0000b")}, ["replay", "c.json"], 0, ""),
    ("run: --jobs 0", {}, ["run", "--jobs", "0"], 2, "--jobs"),
    ("run: --jobs -1", {}, ["run", "--jobs", "-1"], 2, "--jobs"),
    ("run: --timeout 0", {}, ["run", "--timeout", "0"], 2, "--timeout"),
    ("run: --timeout nan", {}, ["run", "--timeout", "nan"], 2, "--timeout"),
    ("run: --timeout inf", {}, ["run", "--timeout", "inf"], 2, "--timeout"),
    ("run: --out is a file", {"out": ""}, ["run", "--out", "out"], 2, "--out out is a file"),
    ("run: --json is a folder", {"j/x": ""}, ["run", "--json", "j"], 2, "--json j is a folder"),
    ("run: --junit is a folder", {"j/x": ""}, ["run", "--junit", "j"], 2, "--junit j is a folder"),
    ("run: --out under /proc", {}, ["run", "--out", "/proc/rastercheck"], 2, "cannot be written"),
    ("run: unknown rasterizer", {}, ["run", "--rasterizer", "nope"], 2, "not a registered rasterizer"),
    ("run: a missing plugin file", {}, ["run", "--rasterizer", "missing.py:X"], 2, "no such file"),
    ("run: a plugin with a syntax error", {"p.py": "def ("}, ["run", "--rasterizer", "p.py:X"], 2, "importing it failed"),
    ("run: a plugin that is not a rasterizer", {"p.py": "X = 3"}, ["run", "--rasterizer", "p.py:X"], 2, "is not a rasterizer"),
    ("run: --shard 0/2", {}, ["run", "--shard", "0/2"], 2, "--shard"),
    ("run: --rerun -1", {}, ["run", "--rerun", "-1"], 2, "--rerun"),
    ("run: --skip a missing file", {}, ["run", "--skip", "none.txt", "--rasterizer", "centre_scanline"], 2, "--skip none.txt"),
    ("diff: not a results file", {"a.json": "{}", "b.json": "{}"}, ["diff", "a.json", "b.json"], 2, "a.json"),
]


@pytest.mark.parametrize("what, files, argv, code, words", CATALOGUE, ids=[row[0] for row in CATALOGUE])
def test_bad_input_ends_in_one_line_not_a_traceback(tmp_path, monkeypatch, capsys, what, files, argv, code, words):
    monkeypatch.chdir(tmp_path)
    for name, content in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(content)
    if argv[0] == "replay":
        argv = [*argv, "--rasterizer", "centre_scanline"]
    got: int | str | None
    with bounded():  # under 60 s and 2 GB allocated
        try:
            got = main(argv)
        except SystemExit as exc:  # argparse's own usage errors
            got = exc.code
    err = capsys.readouterr().err
    assert got == code, err
    assert words in err and "Traceback" not in err


def test_the_bounds_catch_a_row_that_takes_too_much():
    """The measure the rows are held to fails a block or a process that allocates or takes
    more than its bound."""
    import sys
    import time

    import numpy as np

    with pytest.raises(AssertionError, match=r"rose 1\d\d MB at its peak, more than 100 MB"), bounded(megabytes=100):
        big = np.ones(20 * 2**20)  # 160 MiB, every page written
        time.sleep(0.05)  # sampled, should this process have been larger before
        del big
    with pytest.raises(AssertionError, match="more than 0.5 s"), bounded(seconds=0.5):
        time.sleep(0.6)
    with bounded(megabytes=100):
        np.ones(2**20)  # 8 MiB
    script = "import numpy as np; a = np.ones(40 * 2**20); print(a.sum() > 0)"  # 320 MiB, every page written
    with pytest.raises(AssertionError, match=r"reached [\d,]+ MB, more than 200 MB"):
        run_bounded([sys.executable, "-c", script], megabytes=200)
    assert run_bounded([sys.executable, "-c", script], megabytes=2048).stdout.strip() == "True"
