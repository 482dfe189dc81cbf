"""The upstream bug scripts (rasterizers/real/upstream): each uses its library alone (no
rastercheck), runs on its own, and still reproduces its bug here (exit 1). A script whose
library is missing is skipped, naming the install."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

from tests.optional import need

UPSTREAM = Path(__file__).parents[3] / "rasterizers" / "real" / "upstream"
SCRIPTS = sorted(p for p in UPSTREAM.glob("*.py") if not p.name.startswith("_"))
STANDARD = set(sys.stdlib_module_names) | {"numpy"}


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text())
    names = {a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    names |= {n.module.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module and not n.level}
    return names


def test_there_are_scripts():
    assert len(SCRIPTS) >= 2


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_the_script_uses_its_library_alone_and_documents_the_bug(script):
    libraries = _imports(script) - STANDARD
    assert libraries and not libraries & {"harness", "rasterizers", "cases", "tests"}, libraries
    doc = ast.get_docstring(ast.parse(script.read_text())) or ""
    for part in ("Library:", "Input:", "Expected:", "What happens:", "Exit status:"):
        assert part in doc, f"{script.name}: its docstring lacks {part!r}"


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_the_script_reproduces_its_bug(script):
    for module in sorted(_imports(script) - STANDARD):
        need(module)
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300, cwd=script.parent)
    assert done.returncode == 1, f"{script.name} exited {done.returncode}: {done.stdout[-1000:]} {done.stderr[-2000:]}"
    assert done.stdout.strip(), "it prints its evidence"
