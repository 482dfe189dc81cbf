"""Static check that the built-ins satisfy the Rasterizer protocol (mypy), and that the
check can fail."""

import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parents[1] / "typing"
ROOT = Path(__file__).parents[2]
# run by `make types`, after mypy has filled its cache (cold, this module's mypy takes 17 s)
pytestmark = pytest.mark.types


@pytest.fixture(scope="module")
def mypy() -> subprocess.CompletedProcess:
    """One mypy run over both files: its lines name their file. With the project's options
    and its cache (``.mypy_cache``, which ``make types``' own mypy run has just filled), so
    that only these two files are checked afresh (under a second), not every module they
    import (several seconds); those modules' own errors, if any, are that run's to report."""
    pytest.importorskip("mypy", reason="mypy is in the test extras: pip install -e '.[test]'")
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--ignore-missing-imports", str(HERE / "builtins_are_rasterizers.py"),
         str(HERE / "not_a_rasterizer.py")],
        capture_output=True, text=True, cwd=ROOT,
    )


def errors_in(run: subprocess.CompletedProcess, name: str) -> list[str]:
    return [line for line in run.stdout.splitlines() if Path(line.split(":", 1)[0]).name == name and ": error:" in line]


def test_builtins_satisfy_the_protocol_statically(mypy):
    # mypy ran to the end (exit 1, not 2) over both files, and of the two only the broken one has errors
    assert mypy.returncode == 1 and "(checked 2 source files)" in mypy.stdout, mypy.stdout + mypy.stderr
    assert not errors_in(mypy, "builtins_are_rasterizers.py"), mypy.stdout


def test_the_static_check_can_fail(mypy):
    assert mypy.returncode == 1, mypy.stdout + mypy.stderr
    errors = errors_in(mypy, "not_a_rasterizer.py")
    assert errors and any("rasterize" in line for line in errors), mypy.stdout
