"""Input files are read bounded: what is not a regular file (a FIFO, a device) or is larger
than the limit is refused in one line before any of it is read (issue 30: `gate
--known-campaign /dev/zero` reached 3.4 GB, a FIFO hung). Each command line and file read
here is held to 60 s and 2 GB (tests/bounded.py)."""

from __future__ import annotations

import json
import os
import signal
import sys
from pathlib import Path

import numpy as np
import pytest

from harness.results.files import MAX_INPUT_MB, read_input
from tests.bounded import bounded, run_bounded

REPO = Path(__file__).resolve().parents[2]


def test_a_regular_file_is_read_whole(tmp_path: Path) -> None:
    path = tmp_path / "case.json"
    path.write_bytes(b"x" * 1000)
    assert read_input(path, "the case") == b"x" * 1000


def test_a_device_or_fifo_is_refused_before_reading(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"^/dev/zero: the baseline is a device, not a regular file: refused"):
        read_input("/dev/zero", "the baseline")
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)  # opening it to read would wait for a writer forever
    with pytest.raises(ValueError, match="the case is a FIFO, not a regular file"):
        read_input(fifo, "the case")
    with pytest.raises(IsADirectoryError):
        read_input(tmp_path, "the case")


def test_a_file_over_the_limit_is_refused_naming_the_limit_and_how_to_raise_it(tmp_path: Path,
                                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "huge.json"
    path.write_bytes(b" " * (2 * 2**20 + 1))
    monkeypatch.setenv("RASTERCHECK_MAX_INPUT_MB", "2")
    with pytest.raises(ValueError, match=r"the campaign state holds 2 MiB, more than the 2 MiB an input may hold "
                                         r"\(RASTERCHECK_MAX_INPUT_MB raises the limit\)"):
        read_input(path, "the campaign state")
    monkeypatch.setenv("RASTERCHECK_MAX_INPUT_MB", "3")
    assert len(read_input(path, "the campaign state")) == 2 * 2**20 + 1
    assert MAX_INPUT_MB >= 64  # the default takes any real case, baseline or state


@pytest.mark.parametrize("argv, culprit", [
    (["replay", "{fifo}", "--rasterizer", "centre_scanline"], "the case is a FIFO"),
    (["gate", "--baseline", "{fifo}", "--rasterizer", "centre_scanline", "--case", "lattice/bits-0", "--out", "{rep}"],
     "the baseline is a FIFO"),
    (["run", "--rasterizer", "centre_scanline", "--skip", "{fifo}", "--case", "lattice/bits-0", "--out", "{rep}"],
     "the skip list is a FIFO"),
    (["fuzz", "--merge", "{state}", "--state", "{out}", "--out", "{rep}"], "the campaign state is a FIFO"),
])
def test_commands_refuse_a_fifo_at_once_in_one_line(tmp_path: Path, argv: list[str], culprit: str,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    (tmp_path / "state").mkdir()
    os.mkfifo(tmp_path / "state" / "campaign.json")
    args = [a.format(fifo=fifo, state=tmp_path / "state", out=tmp_path / "merged", rep=tmp_path / "rep") for a in argv]
    if argv[0] == "replay":  # one in a process of its own, as a user runs it
        proc = run_bounded([sys.executable, "-m", "harness.cli.main", *args], cwd=REPO,
                           env={**os.environ, "PYTHONPATH": str(REPO)})
        code, err = proc.returncode, proc.stderr.strip()
    else:  # the rest here, an alarm standing in for the timeout (a FIFO opened would wait forever)
        from harness.cli.main import main

        def stuck(*_: object) -> None:
            raise TimeoutError(f"{argv[0]} opened the FIFO and waited on it")

        previous = signal.signal(signal.SIGALRM, stuck)
        signal.alarm(60)
        try:
            with bounded():
                code = main(args)
        finally:
            signal.alarm(0)
            signal.signal(signal.SIGALRM, previous)
        err = capsys.readouterr().err.strip()
    assert code == 2 and culprit in err and err.count("\n") == 0, (code, err)


def test_the_case_reader_refuses_a_huge_file_naming_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from harness.contract.case import read_case_file

    path = tmp_path / "big.json"
    path.write_text(json.dumps({"schema": 1, "id": "x", "width": 8, "height": 8, "positions": [[0, 0]] * 150000}))
    monkeypatch.setenv("RASTERCHECK_MAX_INPUT_MB", "1")
    with bounded(), pytest.raises(ValueError, match=rf"^{path}: the case holds \d+ MiB, more than the 1 MiB"):
        read_case_file(path)


TRIANGLE = '{"schema": 1, "id": "t", "width": 8, "height": 8, "positions": [[[%s, 0], [4, 0], [0, 4]]]%s}'


@pytest.mark.parametrize("text, said", [
    (TRIANGLE % ('"0x1p+2000"', ""), "at positions: 0x1p+2000 is beyond float64's range (its largest is "
                                     "0x1.fffffffffffffp+1023); write \"inf\" for an infinity"),
    (TRIANGLE % ("1e400", ""), "at positions: 1E+400 is beyond float64's range (it would be read as inf)"),
    (TRIANGLE % ("NaN", ""), "at positions: nan is not a JSON number: write \"nan\", \"inf\" or \"-inf\""),
    (TRIANGLE % ("0", ', "region": [[0, 0], ["nan", 0], [0, 4]]'), "at region: the region a partition covers has a "
                                                                   "non-finite corner"),
    ('{"schema": 1, "id": "t", "width": 8, "height": 8, "lines": [[[0, 0], [4, 4]]], "line_width": "abc"}',
     "at line_width: 'abc' is not a number"),
    ('{"schema": 1, "id": "t", "width": 8, "height": 8, "fill_rule": "nonzero", "paths": [[[[1e400, 0], [4, 0], [0, 4]]]]}',
     "at paths[0][0]: 1E+400 is beyond float64's range"),
    ('{"schema": 1, "id": "t", "width": 8, "height": 8, "fill_rule": "nonzero", "paths": [%s]}'
     % ", ".join(['[[[1, 1], [5, 1], [1, 5]]]'] * 65537), "the case holds 65,537 paths, more than the 65,536 a case may "
                                                         "hold (RASTERCHECK_MAX_CASE_SCALE=k allows k times more)"),
    ('{"schema": 1, "id": "t", "width": 8, "height": 8, "lines": [[[0, 0], [1, 1]]%s]}' % (", [[0, 0], [1, 1]]" * 262144),
     "the case holds 262,145 line strips, more than the 262,144"),
])
def test_a_malformed_case_file_is_one_line_naming_the_field(tmp_path: Path, text: str, said: str) -> None:
    from harness.contract.case import read_case_file

    path = tmp_path / "case.json"
    path.write_text(text)
    with bounded(), pytest.raises(ValueError) as refused:
        read_case_file(path)
    message = str(refused.value)
    assert message.startswith(f"{path}: ") and said in message and "\n" not in message, message


def test_words_and_hex_still_give_infinities_and_nans(tmp_path: Path) -> None:
    from harness.contract.case import Case, read_case_file
    from harness.contract.scenes import Scene

    path = tmp_path / "case.json"
    path.write_text((TRIANGLE % ('"inf"', "")).replace("[4, 0]", '["-inf", "nan"]'))
    case = read_case_file(path)[0]
    assert isinstance(case, Case) and isinstance(case.scene, Scene)
    positions = case.scene.positions
    assert positions[0, 0, 0] == float("inf") and positions[0, 1, 0] == -float("inf") and np.isnan(positions[0, 1, 1])


@pytest.mark.parametrize("argv", [
    ["run", "--rasterizer", "centre_scanline", "--json", ""],
    ["run", "--rasterizer", "centre_scanline", "--junit", " "],
    ["run", "--rasterizer", "centre_scanline", "--out", ""],
    ["gate", "--baseline", "", "--rasterizer", "centre_scanline"],
    ["identify", "--rasterizer", "centre_scanline", "--json", ""],
    ["compare", "centre_scanline", "pineda_topleft", "--json", ""],
    ["fuzz", "--rasterizer", "centre_scanline", "--budget", "4", "--state", ""],
    ["run", "--rasterizer", "centre_scanline", "--json", "a\0b"],
])
def test_an_empty_path_is_a_usage_error_before_any_work(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    """`--json ''` was accepted and wrote nothing, silently."""
    from harness.cli.main import main

    with bounded(), pytest.raises(SystemExit) as info:
        main(argv)
    err = capsys.readouterr().err
    assert info.value.code == 2 and ("an empty path" in err or "holds a NUL character" in err), err


@pytest.mark.parametrize("command", ["run", "compare"])
def test_a_plugin_that_hangs_at_import_is_given_the_calls_time_limit(tmp_path: Path, command: str,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    """A module that hangs when imported took 122 s before its error (a fixed 120 s probe):
    it is given --timeout, as a call is (compare had no --timeout at all)."""
    import time

    from harness.cli.main import main

    plugin = tmp_path / "hangs.py"
    plugin.write_text("import time\ntime.sleep(600)\nclass Never:\n    pass\n")
    start = time.monotonic()
    argv = (["run", "--rasterizer", f"{plugin}:Never"] if command == "run" else ["compare", f"{plugin}:Never", "centre_scanline"])
    with bounded(seconds=30):
        assert main([*argv, "--timeout", "2", "--out", str(tmp_path / "rep")]) == 2
    assert time.monotonic() - start < 30
    assert f"{plugin}:Never: loading the plugin did not finish within 2 s" in capsys.readouterr().err


@pytest.mark.parametrize("option, kind", [("--out", "a file"), ("--json", "a folder")])
def test_compare_checks_its_outputs_before_any_work(tmp_path: Path, option: str, kind: str,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    """`compare --out FILE` and `compare --json DIR` were tracebacks, after the work."""
    from harness.cli.main import main

    target = tmp_path / "taken"
    target.write_text("") if kind == "a file" else target.mkdir()
    with bounded():
        assert main(["compare", "centre_scanline", "pineda_topleft", option, str(target)]) == 2
    err = capsys.readouterr().err.strip()
    assert f"{option} {target} is {kind}" in err and err.count("\n") == 0, err
