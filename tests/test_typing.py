"""Static check that the built-ins satisfy the Rasterizer protocol (mypy), and that the
check can fail."""

import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent / "typing"
ROOT = Path(__file__).parent.parent


def mypy(path: Path) -> subprocess.CompletedProcess:
    pytest.importorskip("mypy", reason="mypy is in the test extras: pip install -e '.[test]'")
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--follow-imports=silent", "--ignore-missing-imports",
         "--no-incremental", "--cache-dir=/dev/null", str(path)],
        capture_output=True, text=True, cwd=ROOT,
    )


def test_builtins_satisfy_the_protocol_statically():
    result = mypy(HERE / "builtins_are_rasterizers.py")
    assert result.returncode == 0, result.stdout + result.stderr


def test_the_static_check_can_fail():
    result = mypy(HERE / "not_a_rasterizer.py")
    assert result.returncode == 1
    assert "rasterize" in result.stdout
