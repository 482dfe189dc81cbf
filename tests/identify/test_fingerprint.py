"""identify recovers declared conventions from outside; the real adapters work where their
libraries are installed and are skipped with the install hint elsewhere."""

import functools
import re

import pytest

from harness.contract.conventions import Convention, TieRule
from harness.engine.registry import load
from harness.identify.fingerprint import identify
from harness.oracle.coverage import exact_coverage

BUILTINS = ["floor_scanline", "centre_scanline", "pineda_topleft", "fixed_point"]


class BlackBox:
    """A rasterizer that follows a convention it does not declare (the exact oracle's)."""

    convention = None

    def __init__(self, convention: Convention) -> None:
        self.hidden = convention
        self.name = f"blackbox-{convention.tie}-{convention.sample}-{convention.subpixel_bits}"

    def rasterize(self, scene):
        return exact_coverage(scene, self.hidden)


@functools.cache
def _identified(name):
    """identify of a built-in, once per module (several tests read the same fingerprint)."""
    return identify(load(name))


@functools.cache
def _identified_hidden(hidden):
    """identify of the exact oracle of ``hidden``, declaring none, once per module."""
    return identify(BlackBox(hidden))


@pytest.mark.parametrize("name", BUILTINS)
def test_identify_recovers_each_builtin(name):
    r = load(name)
    fingerprint = _identified(name)
    assert fingerprint.exact and fingerprint.convention == r.convention, fingerprint.card()
    assert fingerprint.facts["watertight"].startswith("yes")
    assert fingerprint.facts["viewport edge"].startswith("exact")
    assert fingerprint.facts["epsilon"].startswith("exact")
    assert ("agrees" in fingerprint.facts["vertex sweep"]), fingerprint.card()


@pytest.mark.parametrize("hidden", [
    Convention(tie="top-right"),
    Convention(tie="bottom-left", sample=(0.0, 0.0)),
    Convention(tie="bottom-right", sample=(1.0, 1.0), subpixel_bits=4),
    Convention(tie="top-left", subpixel_bits=6),
    Convention(tie="top-left", cull="cw"),
    Convention(tie="bottom-left", sample=(0.25, 0.75)),
    Convention(tie="top-right", sample=(0.375, 0.125), subpixel_bits=4),
    Convention(tie="bottom-right", sample=(0.0, 1.0), subpixel_bits=5, snap_rounding="floor"),
    # odd multiples of the snapping step: the sweep flips where the snapped edge crosses them,
    # half a step off (76.5/256), and the candidates hold the grid points either side (issue 29)
    Convention(sample=(77 / 256, 179 / 256), subpixel_bits=8, snap_rounding="half-away"),
], ids=str)
def test_identify_recovers_hidden_conventions(hidden):
    fingerprint = _identified_hidden(hidden)
    assert fingerprint.convention == hidden and fingerprint.exact, fingerprint.card()


def test_a_tie_with_the_runner_up_is_never_claimed():
    from harness.identify.fingerprint import Fingerprint

    tied = Fingerprint("r", Convention(), 0, 1000, ("sample (0.5, 0.5), bottom-left ties", 0))
    assert not tied.exact and "ambiguous" in tied.card()
    assert Fingerprint("r", Convention(), 0, 1000, ("other", 3)).exact


def test_the_sample_sweep_measures_an_unusual_sample_point():
    # one of the hidden conventions above (its fingerprint is shared, not drawn again)
    fingerprint = _identified_hidden(Convention(tie="bottom-left", sample=(0.25, 0.75)))
    assert "(0.25, 0.75)" in fingerprint.facts["sample sweep"], fingerprint.card()


def test_identify_never_claims_what_it_cannot_confirm():
    from tests.known_bad.edge_functions import EdgeFunctionBug

    fingerprint = identify(EdgeFunctionBug("inclusive"))
    assert not fingerprint.exact and "best guess only" in fingerprint.card()
    assert fingerprint.facts["watertight"].startswith("no")


REAL = ["pillow", "skimage", "skia", "cairo", "mesa_llvmpipe", "mesa_softpipe"]


# The checks of the real adapters, as source: run here for the libraries that keep no
# process-wide state, and in a fresh Python for Mesa (it picks its driver once per
# process). Each part returns "OK", or "UNAVAILABLE <install hint>"; a failure raises.
SQUARE_CHECK = """
import sys
import numpy as np
from harness.contract.scenes import Scene
from harness.engine.registry import Unavailable, load


def square(name):
    try:
        r = load(name)
    except Unavailable as exc:
        return f"UNAVAILABLE {exc}"
    assert r.convention is None
    scene = Scene(16, 16, [[[2, 2], [12, 2], [12, 12]], [[2, 2], [12, 12], [2, 12]]])
    counts = r.rasterize(scene).counts(16, 16)
    assert (counts[3:11, 3:11] >= 1).all(), counts
    assert counts[:1].sum() == 0 and counts[:, 14:].sum() == 0, counts
    try:
        r.rasterize(Scene(16, 16, [[[2, 2], [12, 2], [12, 12]], [[0, 0], [1e30, 0], [0, 5]]]))
    except ValueError as exc:
        assert f"{name}: triangle 1 " in str(exc), exc
    else:
        raise AssertionError("no error for a huge triangle")
    return "OK"
"""

# the parts run in a fresh Python, each ending in a line "=== <part>: <what it returned or
# FAILED and the traceback>"
RUN_PARTS = """
import traceback
if __name__ == "__main__":
    for part in sys.argv[1:]:
        try:
            said = PARTS[part]()
        except BaseException:
            said = "FAILED\\n" + traceback.format_exc()
        print(f"=== {part}: {said}", flush=True)
"""


def _in_fresh_process(script: str, *parts: str, timeout: float = 300) -> dict[str, str]:
    """Run the parts of a check script in one fresh Python: part -> what it said."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", script + RUN_PARTS, *parts], capture_output=True, text=True, timeout=timeout)
    said = {}
    for block in ("\n" + done.stdout).split("\n=== ")[1:]:
        part, _, text = block.partition(": ")
        said[part] = text.strip()
    assert done.returncode == 0 and set(said) == set(parts), done.stdout + done.stderr
    return said


def _verdict(text: str) -> None:
    """Skip with the install hint when a part says UNAVAILABLE; else it must say OK."""
    if text.startswith("UNAVAILABLE"):
        pytest.skip(text)
    assert text.partition("\n")[0] == "OK", text


def _in_this_process(script: str, part: str, *args: str) -> str:
    space: dict = {"__name__": "check"}
    exec(script, space)
    said: str = space[part](*args)
    return said


@pytest.fixture(scope="module")
def llvmpipe():
    """The llvmpipe checks, in one fresh Python: what each part said."""
    return _in_fresh_process(LLVMPIPE, "square", "identify", "batch")


@pytest.fixture(scope="module")
def softpipe():
    return _in_fresh_process(SQUARE_CHECK + "\nPARTS = {'square': lambda: square('mesa_softpipe')}\n", "square",
                             timeout=120)


@pytest.mark.parametrize("name", REAL)
def test_real_adapter_draws_a_square_without_gaps(name, request):
    if name.startswith("mesa_"):  # in a fresh Python of its own (softpipe) or shared with the llvmpipe checks
        _verdict(request.getfixturevalue(name.removeprefix("mesa_"))["square"])
    else:
        _verdict(_in_this_process(SQUARE_CHECK, "square", name))


def _undeclared_box(folder, convention_args):
    """A plugin file whose class ``Box`` follows Convention(convention_args) and declares none."""
    path = folder / "box.py"
    path.write_text(
        "from harness.contract.conventions import Convention\n"
        "from harness.oracle.coverage import exact_coverage\n"
        "class Box:\n"
        "    name = 'box'\n"
        "    convention = None\n"
        "    def rasterize(self, scene):\n"
        f"        return exact_coverage(scene, Convention({convention_args}))\n"
    )
    return path


def test_run_identifies_an_undeclared_convention(tmp_path):
    from harness.cli.main import main

    path = _undeclared_box(tmp_path, "tie='bottom-left'")
    assert main(["run", "--rasterizer", f"{path}:Box", "--case", "lattice/*", "--out", str(tmp_path / "rep")]) == 0
    page = (tmp_path / "rep" / "index.html").read_text()
    assert "none declared; identified as sample (0.5, 0.5), bottom-left ties" in page


def test_the_card_lists_every_fact():
    card = _identified("centre_scanline").card()
    for fact in ("sample sweep", "culling", "zero area", "epsilon", "non-finite", "viewport edge", "watertight", "snapping",
                 "vertex sweep"):
        assert f"\n{fact}" in card, card


LLVMPIPE = SQUARE_CHECK + """

def identified():
    from dataclasses import replace

    from harness.contract.conventions import Convention
    from harness.identify.fingerprint import identify

    try:
        r = load("mesa_llvmpipe")
    except Unavailable as exc:
        return f"UNAVAILABLE {exc}"
    f = identify(r)
    # the triangles exactly; its lines are GL's diamond rule (a best guess, README "Lines")
    # it receives float32 (GL), which identify tells apart from float64 (issue 33)
    assert f.exact and replace(f.convention, line=Convention().line) == Convention(subpixel_bits=8, input="float32"), f.card()
    assert f.convention.line.rule == "diamond-exit-gl", f.card()
    assert f.facts["watertight"].startswith("yes") and "agrees" in f.facts["vertex sweep"], f.card()
    return "OK"


def batch_agrees():
    from cases.suites import suite
    from harness.cli.bench import workloads

    try:
        r = load("mesa_llvmpipe")
        r._context()
    except Unavailable as exc:
        return f"UNAVAILABLE {exc}"
    listed = r._list_program
    assert listed is not None, "llvmpipe offers GL 4.5: the fragment-list path should be on"
    small_and_large = [w.scene for w in workloads(scale=0.05)]  # many small triangles; a few of 100,000 px
    scenes = [*small_and_large, Scene(1024, 1024, np.concatenate([s.positions for s in small_and_large]))]
    for case in suite("quick")[:40]:
        scenes += case.frames[:2] if hasattr(case, "frames") else [case.scene]
    compared = 0
    for scene in scenes:
        try:
            r._list_program = listed
            one_draw = r.rasterize(scene)
            r._list_program = None
            each = r.rasterize(scene)
        except ValueError:
            continue
        assert one_draw == each, scene
        compared += 1
    assert compared >= 30, compared
    return "OK"


PARTS = {"square": lambda: square("mesa_llvmpipe"), "identify": identified, "batch": batch_agrees}
"""


def test_llvmpipe_is_identified_exactly(llvmpipe):
    """A production GL driver: centre samples, top-left ties (image row y = memory row y),
    vertices snapped to 1/256 px, watertight; the vertex sweep agrees."""
    _verdict(llvmpipe["identify"])


def test_llvmpipe_one_draw_with_a_fragment_list_equals_one_draw_per_triangle(llvmpipe):
    _verdict(llvmpipe["batch"])


@pytest.mark.parametrize("hidden", [
    Convention(tie="top-left-y-first"),
    Convention(tie="bottom-right-y-first", subpixel_bits=4),
    Convention(tie="top-right-y-first", sample=(0.0, 0.0)),
    Convention(tie="bottom-left-y-first", subpixel_bits=8, snap_rounding="half-away"),
    Convention(subpixel_bits=4, snap_rounding="half-away"),
    Convention(tie="bottom-right", subpixel_bits=6, snap_rounding="half-away"),
], ids=str)
def test_identify_recovers_y_first_rules_and_half_away_snapping(hidden):
    fingerprint = _identified_hidden(hidden)
    assert fingerprint.convention == hidden and fingerprint.exact, fingerprint.card()


def test_identify_separates_the_roundings_on_half_steps():
    fingerprint = identify(BlackBox(Convention(subpixel_bits=8)))
    assert fingerprint.exact and "nearest-even: 0 mismatches" in fingerprint.facts["rounding"], fingerprint.card()
    assert "half-away: 0 " not in fingerprint.facts["rounding"]


def test_a_rounding_that_was_not_separated_is_never_claimed():
    from harness.identify.fingerprint import Fingerprint

    unsure = Fingerprint("r", Convention(subpixel_bits=8), 0, 1000, ("other", 3), {}, ("8 bits nearest-even", "8 bits half-away"))
    assert not unsure.exact and "ambiguous between 8 bits nearest-even and 8 bits half-away" in unsure.card()


# piglit's rast_triangle biases its y-first conventions the other way round from the
# names its probe gives them (see harness.contract.conventions): what each port really draws.
PIGLIT_PORT_DRAWS: dict[str, TieRule] = {
    "top_left": "bottom-left", "top_right": "bottom-right", "bottom_left": "top-left", "bottom_right": "top-right",
    "left_top": "top-right-y-first", "right_top": "top-left-y-first",
    "left_bottom": "bottom-right-y-first", "right_bottom": "bottom-left-y-first",
}


@functools.cache
def _port(kind, *args):
    """A ported reference rasterizer and its fingerprint, once per module."""
    from tests.ports import DeqpReference, PiglitReference

    rasterizer = DeqpReference(*args) if kind == "deqp" else PiglitReference(*args)
    return rasterizer, identify(rasterizer)


@pytest.mark.parametrize("filling", sorted(PIGLIT_PORT_DRAWS))
def test_piglit_reference_is_identified_exactly(filling):
    _, fingerprint = _port("piglit", filling, 8)
    want = Convention(tie=PIGLIT_PORT_DRAWS[filling], subpixel_bits=8, snap_rounding="half-away-shifted")
    assert fingerprint.exact and fingerprint.residual == 0 and fingerprint.convention == want, fingerprint.card()


@pytest.mark.parametrize("port", ["deqp-8", "deqp-4", "piglit-left_top-4", "piglit-top_left-8"])
def test_ported_references_pass_the_quick_suite_as_identified(port):
    """dEQP's and piglit's reference rasterizers, identified from outside, then checked
    against what was identified: no false failure at half steps or ties."""
    from harness import run_suite
    from harness.identify.fingerprint import Identified

    kind, *rest = port.split("-")
    rasterizer, fingerprint = _port(kind, int(rest[0])) if kind == "deqp" else _port(kind, rest[0], int(rest[1]))
    # dEQP rounds half away from zero, piglit half away from the pixel centre (its shifted frame)
    rounding = "half-away" if kind == "deqp" else "half-away-shifted"
    assert fingerprint.exact and fingerprint.convention.snap_rounding == rounding, fingerprint.card()
    # conformance is where an identified convention could fail falsely (at half steps, at
    # ties); in this process (the verdicts are the same in a worker, which would only add
    # its start-up and the pickling of every answer)
    results = run_suite([Identified(rasterizer, fingerprint)], suite="quick", repros=False, only={"conformance"}, isolate=False)
    bad = [f"{r.case} {r.check}: {r.message}" for r in results if r.status in ("fail", "error")]
    assert not bad and any(r.check == "conformance" and r.status == "pass" for r in results), bad[:5]


def test_identify_tells_the_known_bad_claims_apart():
    from tests.known_bad.conventions import HalfAwayClaimsNearestEven, YFirstClaimsXFirst

    y_first = identify(YFirstClaimsXFirst())
    assert y_first.exact and y_first.convention == Convention(tie="top-left-y-first", subpixel_bits=8), y_first.card()
    half_away = identify(HalfAwayClaimsNearestEven())
    assert half_away.exact and half_away.convention == Convention(subpixel_bits=4, snap_rounding="half-away"), half_away.card()


def test_the_library_identifies_undeclared_rasterizers_as_the_command_does(tmp_path):
    """harness.run_suite and ``rastercheck run`` give the same verdicts on a rasterizer
    that declares no convention: both identify it and check it against what was found."""
    import json

    from harness import run_suite
    from harness.cli.main import main

    box = _undeclared_box(tmp_path, "tie='bottom-left-y-first', subpixel_bits=4, snap_rounding='half-away'")
    spec = f"{box}:Box"
    # every static family and some motion: all the checks, not the whole suite
    chosen = ["lattice/*", "float/*", "watertight/fan-*", "degenerate/zero-area/*", "mesh/box/*", "motion/triangle/*"]
    main(["run", "--rasterizer", spec, *(a for g in chosen for a in ("--case", g)), "--out", str(tmp_path / "rep"),
          "--json", str(tmp_path / "r.json")])
    command = {(r["case"], r["check"]): (r["status"], r["message"])
               for r in json.loads((tmp_path / "r.json").read_text())["results"]}
    import fnmatch

    from cases.suites import suite

    cases = [c for c in suite("quick") if any(fnmatch.fnmatchcase(c.id, g) for g in chosen)]
    library = {(r.case, r.check): (r.status, r.message) for r in run_suite([spec], cases=cases)}
    assert library.keys() == command.keys()
    differ = [k for k in library if library[k] != command[k] and k[1] != "degenerate"]  # degenerate quotes timings
    assert not differ, [(k, library[k], command[k]) for k in differ[:3]]
    assert all(library[k][0] == command[k][0] for k in library)
    assert any(k[1] == "conformance" and v[0] == "pass" for k, v in library.items())  # checked, not skipped


class ReversedAndMinInt:
    """Spans with x0 > x1, and spans at the most negative int64 rows and columns."""

    name = "reversed_and_min_int"
    convention = None

    def rasterize(self, scene):
        import numpy as np

        from harness.contract.coverage import Coverage

        n = len(scene)
        lo, hi = np.iinfo(np.int64).min, np.iinfo(np.int64).max
        t = np.concatenate([np.arange(n), np.arange(n)])
        return Coverage(t, np.concatenate([np.full(n, 3), np.full(n, lo)]),
                        np.concatenate([np.full(n, 9), np.full(n, lo)]), np.concatenate([np.full(n, 2), np.full(n, hi)]))


class RaisesOnBigScenes:
    """Correct, but raises on a scene of more than 100 triangles (every fit scene)."""

    name = "raises_on_big_scenes"
    convention = None

    def __init__(self):
        self.inner = load("centre_scanline")  # once: loading reads the entry points (ms a call)

    def rasterize(self, scene):
        if len(scene) > 100:
            raise MemoryError("too many triangles")
        return self.inner.rasterize(scene)


def _lying():
    from tests.known_bad.hostile import FarAway, HugeSpan
    from tests.known_bad.misc import Raises, ReturnsGarbage

    return [ReversedAndMinInt(), FarAway(), HugeSpan(), Raises(), ReturnsGarbage()]


@pytest.mark.parametrize("index", range(5), ids=["reversed-min-int", "far-away", "huge-span", "raises", "not-a-coverage"])
def test_identify_gives_a_lying_rasterizer_a_residual_not_an_exception(index):
    import json

    from harness.identify.fingerprint import Fingerprint

    rasterizer = _lying()[index]
    fingerprint = identify(rasterizer)
    # a residual over what it answered; fit scenes it did not answer are left out and named
    assert isinstance(fingerprint, Fingerprint) and not fingerprint.exact and (fingerprint.residual > 0
                                                                               or fingerprint.unanswered > 0)
    if fingerprint.no_answers is not None:  # no fit scene answered: no convention claimed, not even as a guess
        assert "convention   none identified: no answers" in fingerprint.card() and "mismatching pixels" not in fingerprint.card()
    else:
        assert "best guess only" in fingerprint.card()
    if fingerprint.unanswered:
        assert " probe calls failed: #" in fingerprint.facts["calls"]
        assert fingerprint.no_answers is not None or "best guess only because calls failed" in fingerprint.card()
    assert all(isinstance(text, str) for text in fingerprint.facts.values())
    json.dumps(fingerprint.to_dict())


def test_identify_reports_fit_scenes_the_rasterizer_did_not_answer():
    fingerprint = identify(RaisesOnBigScenes())
    # no answer is not an answer of nothing: no residual from the scenes it did not answer,
    # and no claim either
    assert not fingerprint.exact and fingerprint.residual == 0 and fingerprint.unanswered == 8, fingerprint.card()
    # none of them answered: the card claims no convention, not even as a best guess (issue 30)
    assert fingerprint.no_answers == "none of its 8 fit scenes was answered, first: MemoryError: too many triangles"
    assert "convention   none identified: no answers (none of its 8 fit scenes was answered" in fingerprint.card()
    assert "best guess" not in fingerprint.card() and "mismatching pixels" not in fingerprint.card()
    # 4 lattice scenes, tie triangles, pinwheels and 2 float scenes (no snapping seen: no half steps)
    assert fingerprint.facts["unanswered"].startswith("8 of 8 fit scenes unanswered, left out of the fit"), fingerprint.card()
    assert "probe calls failed: #" in fingerprint.facts["calls"] and "the fit is on the rest" not in fingerprint.facts["calls"]
    assert "MemoryError: too many triangles" in fingerprint.facts["unanswered"]
    # nothing it did not answer steers the guess, and what it did answer is still measured
    assert fingerprint.convention == Convention()
    assert "(0.5, 0.5)" in fingerprint.facts["sample sweep"] and fingerprint.facts["epsilon"].startswith("exact")
    assert type(fingerprint.probes["unanswered"]).__name__ == "Unanswered"


class DiesOnNaN:
    """Correct, but its process dies on a NaN coordinate (a segfault, as far as anyone can tell)."""

    name = "dies_on_nan"
    convention = None

    def __init__(self):
        self.inner = load("centre_scanline")

    def rasterize(self, scene):
        import os

        import numpy as np

        if np.isnan(scene.positions).any():
            os._exit(3)
        return self.inner.rasterize(scene)


def test_identify_isolated_goes_on_past_a_dying_call_and_agrees_with_identify():
    from harness.identify.fingerprint import identify_isolated

    isolated = identify_isolated(DiesOnNaN(), call_timeout=60)
    assert isolated.exact and isolated.convention == Convention(), isolated.card()
    assert "NaN: raises RuntimeError: the rasterizer's worker process died (exit code 3)" in isolated.facts["non-finite"]
    plain = _identified("centre_scanline").to_dict()
    # the dying call is named on the card, and is the one difference
    assert [f["error"] for f in isolated.to_dict()["calls"]["failed"]] == ["RuntimeError: the rasterizer's worker process died "
                                                                           "(exit code 3)"]
    assert re.search(r"^1 of [0-9,]+ probe calls failed: #[0-9]+ \(2 triangles on 32 x 32 px: RuntimeError",
                     isolated.facts["calls"]) and plain["calls"]["failed"] == []
    assert {**isolated.to_dict(), "rasterizer": None, "facts": None, "calls": None} == {**plain, "rasterizer": None,
                                                                                        "facts": None, "calls": None}


class Sluggish:
    name = "sluggish"
    convention = None

    def __init__(self):
        self.inner = load("centre_scanline")

    def rasterize(self, scene):
        import time

        time.sleep(0.02)
        return self.inner.rasterize(scene)


def test_identify_isolated_bounds_the_whole_identification():
    import time

    from harness.identify.fingerprint import identify_isolated

    start = time.monotonic()
    with pytest.raises(TimeoutError, match=r"identify sluggish: no answer within 1 s"):
        identify_isolated(Sluggish(), timeout=1.0, call_timeout=30)
    assert time.monotonic() - start < 10
