import json
import subprocess
import sys
import textwrap

import pytest

from harness.api import Rasterizer
from harness.cli import main
from harness.registry import available, load

BUILTIN_NAMES = ["centre_scanline", "fixed_point", "floor_scanline", "pineda_topleft"]


def test_available_lists_builtins_through_entry_points(monkeypatch):
    assert set(BUILTIN_NAMES) <= set(available())
    monkeypatch.setenv("RASTERCHECK_NO_PLUGINS", "1")
    assert set(BUILTIN_NAMES) <= set(available())


@pytest.mark.parametrize("spec", BUILTIN_NAMES + ["rasterizers.fixed_point:FixedPoint"])
def test_load_builtin_and_module_specs(spec):
    assert isinstance(load(spec), Rasterizer)


def test_load_file_specs(tmp_path):
    path = tmp_path / "mine.py"
    path.write_text(textwrap.dedent('''
        from rasterizers.centre_scanline import CentreScanline
        instance = CentreScanline()
        Klass = CentreScanline
        def factory():
            return CentreScanline()
        not_a_rasterizer = 42
        def needs_args(x):
            return x
    '''))
    for attr in ("instance", "Klass", "factory"):
        assert load(f"{path}:{attr}").name == "centre_scanline"
    with pytest.raises(ValueError, match="not_a_rasterizer.*is not a rasterizer"):
        load(f"{path}:not_a_rasterizer")
    with pytest.raises(ValueError, match="needs_args"):
        load(f"{path}:needs_args")
    with pytest.raises(ValueError, match="no attribute 'missing'"):
        load(f"{path}:missing")
    with pytest.raises(ValueError, match="no such file"):
        load(f"{tmp_path}/nope.py:x")
    broken = tmp_path / "broken.py"
    broken.write_text("raise RuntimeError('boom')\n")
    with pytest.raises(ValueError, match="broken.py: importing it failed: RuntimeError: boom"):
        load(f"{broken}:x")
    with pytest.raises(ValueError, match="not a registered rasterizer"):
        load("no_such_rasterizer")


def test_cli_run_writes_report_and_json(tmp_path, capsys):
    out = tmp_path / "rep"
    code = main(["run", "--rasterizer", "centre_scanline", "--rasterizer", "fixed_point", "--out", str(out), "--json", str(tmp_path / "r.json")])
    assert code == 0
    html = (out / "index.html").read_text()
    assert "centre_scanline" in html and "fixed_point" in html and "<script" not in html
    data = json.loads((tmp_path / "r.json").read_text())
    assert data["schema"] == 1 and {r["status"] for r in data["results"]} <= {"pass", "skip"}
    assert {r["check"] for r in data["results"]} >= {"hygiene", "conformance", "watertight", "closed", "degenerate", "invariance"}


def test_cli_run_fails_on_a_wrong_rasterizer(tmp_path):
    path = tmp_path / "wrong.py"
    path.write_text(textwrap.dedent('''
        from harness import Convention
        from rasterizers.centre_scanline import CentreScanline
        class Liar(CentreScanline):
            name = "liar"
            convention = Convention(tie="bottom-right")  # claims what it does not do
    '''))
    code = main(["run", "--rasterizer", f"{path}:Liar", "--out", str(tmp_path / "rep")])
    assert code == 1
    assert "fail" in (tmp_path / "rep" / "index.html").read_text()


def test_cli_usage_errors_exit_2(capsys):
    assert main(["run", "--rasterizer", "nope", "--out", "/tmp/unused-rc"]) == 2
    assert "nope" in capsys.readouterr().err


def test_cli_list_and_bench(tmp_path, capsys):
    assert main(["list"]) == 0
    assert "floor_scanline" in capsys.readouterr().out
    assert main(["bench", "--scale", "0.01", "--budget", "0", "--json", str(tmp_path / "b.json")]) == 0
    out = capsys.readouterr().out
    assert "pillow" in out and "oracle" in out
    data = json.loads((tmp_path / "b.json").read_text())
    assert {r["contender"] for r in data["results"]} >= {"pillow", "oracle", *BUILTIN_NAMES}


def test_console_script_entry_point():
    result = subprocess.run([sys.executable, "-m", "harness.cli", "list"], capture_output=True, text=True)
    assert result.returncode == 0 and "pineda_topleft" in result.stdout
