"""Static check that the built-ins satisfy the Rasterizer protocol (mypy), and that the
check can fail."""

import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent / "typing"
ROOT = Path(__file__).parent.parent


@pytest.fixture(scope="module")
def mypy() -> subprocess.CompletedProcess:
    """One mypy run over both files (a run costs seconds): its lines name their file."""
    pytest.importorskip("mypy", reason="mypy is in the test extras: pip install -e '.[test]'")
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--follow-imports=silent", "--ignore-missing-imports",
         "--no-incremental", "--cache-dir=/dev/null", str(HERE / "builtins_are_rasterizers.py"),
         str(HERE / "not_a_rasterizer.py")],
        capture_output=True, text=True, cwd=ROOT,
    )


def errors_in(run: subprocess.CompletedProcess, name: str) -> list[str]:
    return [line for line in run.stdout.splitlines() if Path(line.split(":", 1)[0]).name == name and ": error:" in line]


def test_builtins_satisfy_the_protocol_statically(mypy):
    # mypy ran to the end (exit 1, not 2), and only the broken file has errors
    assert mypy.returncode == 1 and "in 1 file (checked 2 source files)" in mypy.stdout, mypy.stdout + mypy.stderr
    assert not errors_in(mypy, "builtins_are_rasterizers.py"), mypy.stdout


def test_the_static_check_can_fail(mypy):
    assert mypy.returncode == 1, mypy.stdout + mypy.stderr
    errors = errors_in(mypy, "not_a_rasterizer.py")
    assert errors and any("rasterize" in line for line in errors), mypy.stdout
