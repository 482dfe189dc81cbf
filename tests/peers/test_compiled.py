"""The peers' originals are built with the machine's compiler, or their checks skip naming it."""

import shutil

import pytest

from tests.peers import compiled


def test_without_a_compiler_the_check_skips_naming_the_install(monkeypatch):
    monkeypatch.setattr(shutil, "which", lambda name: None)  # a bare machine: no cc, gcc, clang, c++, g++
    assert compiled.compiler("c") is None and compiled.compiler("c++") is None
    with pytest.raises(pytest.skip.Exception, match=r"apt-get install gcc g\+\+"):
        compiled.load("stb", [compiled.SOURCES / "stb" / "shim.c"])


def test_a_build_that_fails_says_why(tmp_path):
    if compiled.compiler("c") is None:
        pytest.skip(compiled.NO_COMPILER)
    broken = tmp_path / "broken.c"
    broken.write_text("int f(void) { return }\n")
    with pytest.raises(RuntimeError, match=r"building broken failed .*broken\.c"):
        compiled.load("broken", [broken])
