import json
import subprocess
import sys
import textwrap

import pytest

from harness.cli.main import main
from harness.contract.protocol import Rasterizer
from harness.engine.optional import missing
from harness.engine.registry import available, load

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
    families = [a for g in ("lattice/*", "watertight/fan-*", "mesh/box/*", "degenerate/zero-area/*") for a in ("--case", g)]
    code = main(["run", "--rasterizer", "centre_scanline", "--rasterizer", "fixed_point", *families, "--no-fingerprints",
                 "--out", str(out), "--json", str(tmp_path / "r.json")])
    assert code == 0
    html = (out / "index.html").read_text()
    assert "centre_scanline" in html and "fixed_point" in html and "<script" not in html
    assert (out / "rasterizer-centre_scanline.html").exists()
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
    code = main(["run", "--rasterizer", f"{path}:Liar", "--case", "lattice/*", "--no-fingerprints", "--out",
                 str(tmp_path / "rep")])
    assert code == 1
    assert "fail" in (tmp_path / "rep" / "index.html").read_text()
    assert "against the oracle" in (tmp_path / "rep" / "rasterizer-liar.html").read_text()


def test_cli_usage_errors_exit_2(capsys):
    assert main(["run", "--rasterizer", "nope", "--out", "/tmp/unused-rc"]) == 2
    assert "nope" in capsys.readouterr().err


def test_cli_list_and_bench(tmp_path, capsys):
    assert main(["list"]) == 0
    assert "floor_scanline" in capsys.readouterr().out
    two = ["--rasterizer", "centre_scanline", "--rasterizer", "area_scanline"]  # (all of them: `make bench`)
    assert main(["bench", "--scale", "0.01", "--budget", "0", *two, "--json", str(tmp_path / "b.json")]) == 0
    out = capsys.readouterr().out
    assert "pillow" in out and "oracle" in out
    data = json.loads((tmp_path / "b.json").read_text())
    oracles = {"oracle", "oracle_area", "oracle_msaa4", "oracle_msaa8"}
    measured = {r["contender"] for r in data["results"]}
    assert measured >= {"pillow", *oracles, "centre_scanline", "area_scanline"}
    # a library peer is measured where its library is installed, and otherwise named with
    # its install, in the table and the JSON: never silently left out
    for peer, module in (("cairo_aa_fill", "cairo"), ("skia_aa_fill", "skia")):
        why = missing(module)
        if why is None:
            assert peer in measured and peer not in data.get("not_measured", {})
        else:
            assert peer not in measured and data["not_measured"][peer] == why
            assert f"not measured: {peer}: {module} is not installed" in out and "pip install" in why


def test_a_peer_whose_library_is_missing_is_named_with_its_install(monkeypatch):
    """Whatever this machine has installed: a library that does not import costs only its
    own peers, each named with the sentence that says how to install it."""
    import harness.cli.bench as bench
    import harness.cli.bench_peers as bench_peers
    import harness.engine.optional as optional

    real_import = __import__

    def no_cairo(name, *args, **kwargs):
        if name == "cairo":
            raise ModuleNotFoundError("No module named 'cairo'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr("builtins.__import__", no_cairo)
    absent = bench.missing_peers()
    assert set(absent) >= {"cairo_aa_fill", "cairo_fill", "cairo_line"}
    assert all("apt-get install libcairo2-dev" in absent[p] for p in ("cairo_aa_fill", "cairo_fill", "cairo_line"))
    assert "cairo_aa_fill" not in dict(bench_peers._library_peers())
    said = optional.missing("cairo")
    assert said is not None and said.startswith("cairo is not installed (ModuleNotFoundError): apt-get install")


def test_console_script_entry_point():
    result = subprocess.run([sys.executable, "-m", "harness.cli.main", "list"], capture_output=True, text=True)
    assert result.returncode == 0 and "pineda_topleft" in result.stdout


OUTSIDE_RASTERIZER = '''
"""Written outside rastercheck: a bounding-box rasterizer whose author thought "<= 0"
was the top-left rule and forgot that culling is not part of his convention."""
import numpy as np
from harness import Convention, Coverage


class Hobby:
    name = "hobby"
    convention = Convention()

    def rasterize(self, scene):
        parts = []
        for t, p in enumerate(scene.positions):
            if not np.isfinite(p).all() or np.abs(p).max() > 1e7:
                continue
            x0, y0 = np.clip(np.floor(p.min(axis=0)).astype(int), 0, [scene.width, scene.height])
            x1, y1 = np.clip(np.ceil(p.max(axis=0)).astype(int) + 1, 0, [scene.width, scene.height])
            ys, xs = np.mgrid[y0:y1, x0:x1] + 0.5
            w = [(p[(k + 1) % 3, 0] - p[k, 0]) * (ys - p[k, 1]) - (p[(k + 1) % 3, 1] - p[k, 1]) * (xs - p[k, 0])
                 for k in range(3)]
            mask = (w[0] >= 0) & (w[1] >= 0) & (w[2] >= 0)   # one winding, every edge inclusive
            y, x = np.nonzero(mask)
            parts.append(Coverage.from_pixels(np.full(x.size, t), x + x0, y + y0))
        if not parts:
            return Coverage.empty()
        return Coverage(*(np.concatenate([getattr(c, f) for c in parts]) for f in ("triangle", "y", "x0", "x1")))
'''


def test_an_outside_rasterizer_is_flagged_with_repros(tmp_path, capsys):
    path = tmp_path / "hobby.py"
    path.write_text(OUTSIDE_RASTERIZER)
    out = tmp_path / "rep"
    # the families that show each of its faults, not the whole suite: it is slow (numpy per triangle)
    families = ["--case", "lattice/bits-0", "--case", "watertight/fan-*", "--case", "mesh/box/*", "--no-fingerprints"]
    code = main(["run", "--rasterizer", f"{path}:Hobby", *families, "--out", str(out), "--json", str(tmp_path / "r.json")])
    assert code == 1
    data = json.loads((tmp_path / "r.json").read_text())
    failed = {r["check"] for r in data["results"] if r["status"] == "fail"}
    assert {"conformance", "watertight", "closed", "invariance"} <= failed
    repros = list((out / "repros" / "hobby").glob("*.json"))
    assert repros
    html = (out / "rasterizer-hobby.html").read_text()
    assert "minimal repro" in html and "data:image/png;base64," in html and "data:image/svg+xml;base64," in html
    assert 'href="rasterizer-hobby.html"' in (out / "index.html").read_text()
    assert main(["replay", str(repros[0]), "--rasterizer", f"{path}:Hobby"]) == 1
    assert all(main(["replay", str(r), "--rasterizer", "centre_scanline"]) == 0 for r in repros)
    assert main(["replay", str(tmp_path / "missing.json"), "--rasterizer", "centre_scanline"]) == 2


@pytest.mark.parametrize("argv", [
    ["run", "--jobs", "0"], ["run", "--jobs", "-1"], ["run", "--jobs", "two"],
    ["run", "--timeout", "0"], ["run", "--timeout", "-1"], ["run", "--timeout", "nan"], ["run", "--timeout", "inf"],
    ["gate", "--baseline", "b.json", "--timeout", "0"], ["identify", "centre_scanline", "--timeout", "-5"],
    ["bench", "--budget", "-1"], ["bench", "--budget", "nan"], ["bench", "--scale", "inf"],
])
def test_numbers_out_of_range_are_usage_errors(argv, capsys):
    """Before any work: one line naming the option and the value, exit 2."""
    from harness.cli.main import main

    with pytest.raises(SystemExit) as stopped:
        main(argv)
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert argv[-2] in err and repr(argv[-1]) in err and "Traceback" not in err


def test_a_hostile_name_never_becomes_a_path_outside_out(tmp_path):
    from harness.cli.main import main

    plugin = tmp_path / "hostile.py"
    plugin.write_text(
        "from harness.contract.conventions import Convention\n"
        "from harness.oracle.coverage import exact_coverage\n"
        "class Hostile:\n"
        "    name = '../../../escaped_repros'\n"
        "    convention = Convention()\n"
        "    def rasterize(self, scene):\n"
        "        return exact_coverage(scene, Convention(tie='bottom-right'))\n"
    )
    out = tmp_path / "deep" / "rep"
    assert main(["run", "--rasterizer", f"{plugin}:Hostile", "--case", "lattice/*", "--case", "watertight/fan-*", "--out",
                 str(out), "--no-fingerprints"]) == 1
    written = [p for p in tmp_path.rglob("*.json")]
    assert written and all(out in p.parents for p in written), [str(p) for p in written if out not in p.parents][:3]
    assert not (tmp_path / "escaped_repros").exists() and not (tmp_path / "deep" / "escaped_repros").exists()


def test_names_that_sanitise_alike_keep_their_own_pages_and_repros(tmp_path):
    """'my rast' and 'my/rast' are both my_rast as a path: each keeps its own page and
    repro folder (a hash of the name tells them apart), neither overwrites the other's."""
    from harness.cli.main import main

    plugin = tmp_path / "twins.py"
    plugin.write_text(
        "from harness.contract.conventions import Convention\n"
        "from harness.oracle.coverage import exact_coverage\n"
        "class Space:\n"
        "    name = 'my rast'\n"
        "    convention = Convention()\n"
        "    def rasterize(self, scene):\n"
        "        return exact_coverage(scene, Convention(tie='bottom-right'))\n"
        "class Slash(Space):\n"
        "    name = 'my/rast'\n"
    )
    out = tmp_path / "rep"
    assert main(["run", "--rasterizer", f"{plugin}:Space", "--rasterizer", f"{plugin}:Slash", "--case", "lattice/bits-0",
                 "--out", str(out), "--no-fingerprints"]) == 1
    pages = sorted(p.name for p in out.glob("rasterizer-*.html"))
    assert len(pages) == 2 and all(p.startswith("rasterizer-my_rast-") for p in pages), pages
    assert "my rast" in (out / pages[0]).read_text() or "my rast" in (out / pages[1]).read_text()
    folders = sorted(p.name for p in (out / "repros").iterdir())
    assert len(folders) == 2 and all(list((out / "repros" / f).glob("*.json")) for f in folders), folders


def test_two_rasterizers_of_one_name_are_told_apart():
    from harness import run_suite
    from harness.engine.registry import distinct_names, load
    from tests.known_bad.misc import WrongTieClaim

    impostor = WrongTieClaim()
    impostor.name = "centre_scanline"
    named = distinct_names([load("centre_scanline"), impostor])
    assert [r.name for r in named] == ["centre_scanline", "centre_scanline#2"]
    case = [c for c in __import__("cases.suites", fromlist=["x"]).conformance_cases(0) if c.id == "lattice/bits-0"]
    results = run_suite(["centre_scanline", impostor], cases=case, repros=False)
    verdicts = {(r.rasterizer, r.check): r.status for r in results}
    assert verdicts[("centre_scanline", "conformance")] == "pass" and verdicts[("centre_scanline#2", "conformance")] == "fail"


@pytest.mark.parametrize("where", ["import", "factory"])
def test_a_plugin_that_exits_cannot_make_run_pass(tmp_path, capsys, where):
    """sys.exit(0) in a plugin, at import or when built, is that plugin's failure to load:
    a usage error (exit 2) naming it, never exit 0 with nothing checked."""
    from harness.cli.main import main

    plugin = tmp_path / "quits.py"
    body = "import sys\n" + ("sys.exit(0)\n" if where == "import" else "") + (
        "def Quits():\n    sys.exit(0)\n" if where == "factory" else "class Quits:\n    pass\n")
    plugin.write_text(body)
    assert main(["run", "--rasterizer", f"{plugin}:Quits", "--out", str(tmp_path / "rep")]) == 2
    assert "sys.exit(0)" in capsys.readouterr().err


@pytest.mark.parametrize("ending", ["os._exit(0)", "os.kill(os.getpid(), signal.SIGKILL)",
                                    "os.kill(os.getpid(), signal.SIGTERM)"])
@pytest.mark.parametrize("where", ["import", "factory"])
def test_a_plugin_that_ends_the_process_while_loading_cannot_end_rastercheck(tmp_path, capsys, ending, where):
    """os._exit or a signal at import or construction ends a probe child, not the run:
    exit 2 naming the plugin and how it ended, never the plugin's own exit code."""
    from harness.cli.main import main

    plugin = tmp_path / "ends.py"
    body = "import os, signal\n" + (f"{ending}\n" if where == "import" else "") + (
        f"def Ends():\n    {ending}\n" if where == "factory" else "class Ends:\n    pass\n")
    plugin.write_text(body)
    assert main(["run", "--rasterizer", f"{plugin}:Ends", "--out", str(tmp_path / "rep")]) == 2
    err = capsys.readouterr().err
    assert "ended the process while being loaded" in err and "ends.py" in err


@pytest.mark.parametrize("ending", ["os._exit(0)", "sys.exit(0)", "os.kill(os.getpid(), signal.SIGKILL)",
                                    "raise KeyboardInterrupt"])
def test_a_plugin_that_ends_the_process_in_rasterize_is_an_error_result(tmp_path, ending):
    from harness.cli.main import main

    plugin = tmp_path / "ends_later.py"
    plugin.write_text("import os, signal, sys\nfrom rasterizers.centre_scanline import CentreScanline\n"
                      "class EndsLater(CentreScanline):\n    name = 'ends_later'\n    def rasterize(self, scene):\n        "
                      f"{ending}\n")
    out = tmp_path / "r.json"
    code = main(["run", "--rasterizer", f"{plugin}:EndsLater", "--rasterizer", "centre_scanline", "--case", "lattice/bits-0",
                 "--no-fingerprints", "--out", str(tmp_path / "rep"), "--json", str(out)])
    results = __import__("json").loads(out.read_text())["results"]
    assert code == 1
    assert all(r["status"] == "error" for r in results if r["rasterizer"] == "ends_later")
    assert all(r["status"] == "pass" for r in results if r["rasterizer"] == "centre_scanline")


NUMBA_PLUGIN = '''
import numba
from harness import Convention, Coverage


@numba.njit(cache=True)
def double(x):
    return 2.0 * x


class Doubler:
    name = "doubler"
    convention = Convention()

    def rasterize(self, scene):
        double(1.0)
        return Coverage.empty()
'''


def test_a_plugin_file_with_cached_kernels_loads_again_in_a_new_process(tmp_path):
    """numba's cache names each cached kernel's module: a plugin file loaded by path gets
    the same module name in every process, so its second run finds it (it failed with
    ModuleNotFoundError: rastercheck_user_...)."""
    (tmp_path / "numba_plugin.py").write_text(NUMBA_PLUGIN)
    code = ("import numpy as np; from harness import Scene; from harness.engine.registry import load; "
            f"r = load({str(tmp_path / 'numba_plugin.py:Doubler')!r}); r.rasterize(Scene(4, 4, np.zeros((1, 3, 2)))); "
            "print(type(r).__module__)")
    for run in range(2):
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, (run, done.stderr[-2000:])
        assert done.stdout.strip() == "numba_plugin"


def test_a_plugin_file_is_imported_by_a_stable_name(tmp_path, monkeypatch):
    from harness.engine.registry import _module_name

    package = tmp_path / "mine" / "sub"
    package.mkdir(parents=True)
    for folder in (tmp_path / "mine", package):
        (folder / "__init__.py").write_text("")
    (package / "raster.py").write_text("")
    (tmp_path / "json.py").write_text("")  # a stem another module answers to
    monkeypatch.syspath_prepend(str(tmp_path))
    assert _module_name(package / "raster.py") == "mine.sub.raster"  # as the code beside it imports it
    clash = _module_name(tmp_path / "json.py")
    assert clash.startswith("rastercheck_user_") and clash == _module_name(tmp_path / "json.py")
    lone = tmp_path / "elsewhere"
    lone.mkdir()
    (lone / "lone_raster.py").write_text("")
    assert _module_name(lone / "lone_raster.py") == "lone_raster"
