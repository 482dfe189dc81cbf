"""Input precision as part of a convention (issue 33, point 1): ``Convention(input=...)``, applied
first and exactly by every oracle, said by describe() and the fingerprint's JSON, and recovered
by identify from outside."""

from __future__ import annotations

import math
from dataclasses import replace
from fractions import Fraction
from typing import Any

import numpy as np
import pytest

from harness.contract.conventions import INPUT_ROUNDINGS, Convention, InputPrecision, SnapRounding, input_precision
from harness.contract.scenes import Scene
from harness.oracle.coverage import exact_coverage
from harness.oracle.reference import brute_force_coverage

# --- the field -----------------------------------------------------------------------------


def test_default_input_changes_nothing():
    c = Convention(subpixel_bits=8)
    assert c.input == "float64" and c == Convention(subpixel_bits=8, input="float64")
    assert repr(c) == "Convention(sample=(0.5, 0.5), tie='top-left', subpixel_bits=8, cull='none')"
    assert c.describe() == "sample (0.5, 0.5), top-left ties, snapped to 1/256 px (8 bits), no culling"
    p = np.array([[0.1, 1e300], [-np.inf, np.nan]])
    assert Convention().snap(p) is not None and np.array_equal(Convention().receive(p), p, equal_nan=True)
    assert not Convention().quantizes and Convention(input="float32").quantizes


@pytest.mark.parametrize("spec, name", [
    ("float64", "float64"), ("float32", "float32"), ("fixed6", "fixed6"), ("fixed6-nearest-even", "fixed6"),
    ("fixed6-floor", "fixed6-floor"), ("fixed16-toward-zero", "fixed16-toward-zero"), ("integer", "integer"),
    ("integer-toward-zero", "integer-toward-zero"), ("integer-half-away", "integer-half-away")])
def test_the_grammar_is_canonical(spec, name):
    c = Convention(input=spec)
    assert c.input == name and input_precision(name).name == name
    assert eval(repr(c), {"Convention": Convention}) == c  # noqa: S307 -- our own repr


@pytest.mark.parametrize("spec", ["float16", "fixed0", "fixed17", "fixed", "integer-up", "float32-floor", "Float32", "", 32])
def test_bad_inputs_are_refused(spec):
    with pytest.raises(ValueError, match="input"):
        Convention(input=spec)


def test_describe_says_it():
    assert Convention(input="float32", subpixel_bits=8, snap_rounding="half-away").describe() == (
        "sample (0.5, 0.5), top-left ties, float32 input, snapped to 1/256 px (8 bits, half away from zero), no culling")
    assert "26.6 fixed-point input (1/64 px, nearest-even), no snapping" in Convention(input="fixed6").describe()
    assert "integer input (whole pixels, toward-zero)" in Convention(input="integer-toward-zero").describe_lines()


# --- exactness against rationals -------------------------------------------------------------------


def _float32_rational(v: float) -> float:
    """Round-to-nearest-even to float32, by brute force on rationals (normal, subnormal,
    overflow to infinity)."""
    if v == 0 or not math.isfinite(v):
        return v
    x = Fraction(v)
    sign = -1 if x < 0 else 1
    x = abs(x)
    e = math.floor(math.log2(x))  # may be off by one: fixed below
    while Fraction(2) ** e > x:
        e -= 1
    while Fraction(2) ** (e + 1) <= x:
        e += 1
    quantum = Fraction(2) ** (max(e, -126) - 23)
    q, r = divmod(x, quantum)
    if r * 2 > quantum or (r * 2 == quantum and q % 2 == 1):
        q += 1
    y = q * quantum
    largest = (2 - Fraction(2) ** -23) * Fraction(2) ** 127
    if y > largest:
        return sign * math.inf
    return sign * float(y)


def _grid_rational(v: float, bits: int, rounding: str) -> float:
    if not math.isfinite(v):
        return v
    x = Fraction(v) * 2**bits
    floor = math.floor(x)
    frac = x - floor
    if rounding == "floor":
        n = floor
    elif rounding == "toward-zero":
        n = math.trunc(x)
    elif frac != Fraction(1, 2):
        n = floor + (1 if frac > Fraction(1, 2) else 0)
    elif rounding == "half-away":
        n = floor + 1 if x > 0 else floor
    else:
        n = floor + (floor % 2)
    return float(Fraction(n, 2**bits))


def _values(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    mags = 2.0 ** rng.integers(-150, 130, 400)
    base = rng.uniform(-1, 1, 400) * mags
    # halfway cases of float32 and of the grids: k/2 steps, plus and minus one float64 ulp
    halves = np.array([k / 2**p for k in range(-9, 10, 2) for p in (1, 7, 17, 25)])
    f32_mid = np.array([1.0 + 2.0**-24, 1.0 + 3 * 2.0**-24, 2.0**-149 / 2, 3 * 2.0**-150, 3.4028235677973366e38,
                        -(1.0 + 2.0**-24), 2.0**-126 - 2.0**-150, 16777217.0, 16777219.0])
    near = np.concatenate([halves, f32_mid])
    return np.concatenate([base, near, np.nextafter(near, np.inf), np.nextafter(near, -np.inf), [0.0, -0.0]])


def test_float32_input_is_round_to_nearest_even_of_the_float64_value():
    v = _values(1)
    got = input_precision("float32").apply(v)
    want = np.array([_float32_rational(float(x)) for x in v])
    assert np.array_equal(got, want)


@pytest.mark.parametrize("rounding", INPUT_ROUNDINGS)
@pytest.mark.parametrize("bits", [0, 6, 16])
def test_grids_round_exactly(bits, rounding):
    v = _values(2)
    v = v[np.abs(v) < 2.0**40]
    spec = InputPrecision("integer" if bits == 0 else "fixed", bits, rounding)
    got = spec.apply(v)
    want = np.array([_grid_rational(float(x), bits, rounding) for x in v])
    assert np.array_equal(got, want), v[got != want][:5]


def test_non_finite_and_huge_values_pass_through():
    v = np.array([np.nan, np.inf, -np.inf, 2.0**60, -(2.0**60)])
    for spec in ("fixed6-floor", "integer-toward-zero", "integer"):
        assert np.array_equal(input_precision(spec).apply(v), v, equal_nan=True)
    assert np.array_equal(input_precision("float32").apply(np.array([1e300, -1e300])), [np.inf, -np.inf])


# --- the oracle applies it first ---------------------------------------------------------------


def _scene(seed: int, n: int = 30, size: int = 12) -> Scene:
    rng = np.random.default_rng(seed)
    centre = rng.uniform(1, size - 1, (n, 1, 2))
    # vertices a hair off pixel centres and half steps, where every input part
    nudge = rng.choice([2.0**-21, -(2.0**-21), 1 / 256, -1 / 256, 0.25, -0.75], (n, 3, 2))
    p = np.floor(centre + rng.uniform(-3, 3, (n, 3, 2))) + 0.5 + nudge
    return Scene(size, size, p)


@pytest.mark.parametrize("spec, bits", [("float32", 4), ("float32", None), ("fixed6", 8), ("fixed6-toward-zero", None),
                                         ("integer-floor", None), ("integer-toward-zero", 2), ("fixed8-half-away", 4)])
def test_the_oracle_applies_the_input_first_and_agrees_with_the_rational_reference(spec, bits):
    for seed in range(3):
        scene = _scene(seed)
        c = Convention(input=spec, subpixel_bits=bits, snap_rounding="half-away", tie="bottom-right")
        got = exact_coverage(scene, c)
        # the input applied by rationals (brute force), then the float64 oracle and the rational one
        grid = input_precision(spec)
        by_hand = [_float32_rational(float(v)) if grid.kind == "float32" else _grid_rational(float(v), grid.bits, grid.rounding)
                   for v in scene.positions.ravel()]
        received = Scene(scene.width, scene.height, np.array(by_hand).reshape(scene.positions.shape))
        assert got.counts(12, 12).tolist() == exact_coverage(received, replace(c, input="float64")).counts(12, 12).tolist()
        assert got.counts(12, 12).tolist() == brute_force_coverage(received, replace(c, input="float64")).counts(12, 12).tolist()
        assert got.counts(12, 12).tolist() == brute_force_coverage(scene, c).counts(12, 12).tolist()


def test_inputs_part_on_the_probe_scenes():
    from harness.identify.input_probes import INPUTS, input_scenes

    scene = input_scenes(Convention(subpixel_bits=8), 0)[0]
    answers = {name: exact_coverage(scene, Convention(subpixel_bits=8, input=name)).counts(scene.width, scene.height).tobytes()
               for name in INPUTS}
    # every candidate draws these scenes differently from float64, but the grids at or
    # finer than the snapping's with its own rounding (fixed8 under 8-bit nearest-even snapping)
    assert {n for n, a in answers.items() if a == answers["float64"]} == {"float64", "fixed8"}


# --- identify recovers it ----------------------------------------------------------------------


def _identified(rasterizer):
    from harness.identify.fingerprint import identify

    return identify(rasterizer)


@pytest.mark.parametrize("port", ["deqp-4", "deqp-8", "piglit-top_left-8", "piglit-left_top-4"])
def test_identify_recovers_float32_input_on_the_ported_references(port):
    """dEQP's and piglit's reference rasterizers compute in float32: fed float32-rounded input,
    identify names it, rounding included, with residual 0."""
    from tests.identify.test_fingerprint import PIGLIT_PORT_DRAWS
    from tests.known_bad.inputs import Float32Fed
    from tests.ports import DeqpReference, PiglitReference

    kind, *rest = port.split("-")
    inner = DeqpReference(int(rest[0])) if kind == "deqp" else PiglitReference(rest[0], int(rest[1]))
    fingerprint = _identified(Float32Fed(inner))
    bits = int(rest[-1])
    tie = "top-left" if kind == "deqp" else (PIGLIT_PORT_DRAWS[rest[0]] if bits == 8 else fingerprint.convention.tie)
    rounding: SnapRounding = "half-away" if kind == "deqp" else "half-away-shifted"  # piglit: in its shifted frame
    want = Convention(tie=tie, subpixel_bits=bits, snap_rounding=rounding, input="float32")
    assert fingerprint.exact and fingerprint.residual == 0 and fingerprint.convention == want, fingerprint.card()
    assert fingerprint.to_dict()["input"] == "float32" and "float32 input" in fingerprint.facts["input"]


def test_identify_keeps_float64_for_the_float64_ports():
    from tests.ports import DeqpReference

    fingerprint = _identified(DeqpReference(8))
    assert fingerprint.exact and fingerprint.convention.input == "float64" and fingerprint.to_dict()["input"] == "float64"


def test_identify_recovers_integer_truncation():
    from tests.known_bad.inputs import TruncatingInput

    fingerprint = _identified(TruncatingInput())
    want = Convention(input="integer-toward-zero")
    assert fingerprint.exact and fingerprint.convention == want, fingerprint.card()
    assert Convention(input=fingerprint.to_dict()["input"]) == want  # the JSON round-trips it


# --- known bad: a rasterizer that rounds its input and says it does not --------------------------


def test_conformance_catches_an_undeclared_input_precision():
    from harness import run_suite
    from tests.known_bad.inputs import TruncatesClaimsFloat64

    results = run_suite([TruncatesClaimsFloat64()], suite="quick", repros=False, only={"conformance"}, isolate=False)
    assert any(r.check == "conformance" and r.status == "fail" for r in results)
    # declared, the same rasterizer passes
    declared = TruncatesClaimsFloat64()
    declared.convention = Convention(input="integer-toward-zero")
    results = run_suite([declared], suite="quick", repros=False, only={"conformance"}, isolate=False)
    bad = [f"{r.case}: {r.message}" for r in results if r.status in ("fail", "error")]
    assert not bad, bad[:3]


def test_identify_recovers_float32_input_of_a_multisample_rasterizer():
    from harness.identify.fingerprint import identify
    from tests.identify.test_coverage_probes import Hidden

    hidden = Convention(samples=4, subpixel_bits=8, input="float32")
    fingerprint = identify(Hidden(hidden))
    assert fingerprint.exact and fingerprint.residual == 0 and fingerprint.convention == hidden, fingerprint.card()
    plain = identify(Hidden(replace(hidden, input="float64")))
    assert plain.exact and plain.convention.input == "float64", plain.card()


def test_conformance_catches_undeclared_float32_input_and_passes_it_declared():
    """Float32 input declared as float64 parts from the truth where float32 overflows (the
    max-float cases); declared, the same rasterizer passes every conformance case."""
    from harness import run_suite
    from tests.known_bad.inputs import Float32ClaimsFloat64

    bad = Float32ClaimsFloat64()
    failed = {r.case for r in run_suite([bad], suite="quick", repros=False, only={"conformance"}, isolate=False)
              if r.status == "fail"}
    assert "degenerate/huge/cover-max-float" in failed
    bad.convention = Convention(subpixel_bits=8, input="float32")
    results = run_suite([bad], suite="quick", repros=False, only={"conformance"}, isolate=False)
    assert not [r.case for r in results if r.status in ("fail", "error")]


# --- piglit's rounding: half away from zero in the frame shifted by half a pixel ---------------


def _shifted_rational(v: float, bits: int) -> float:
    """piglit's ``(iround(2**n * (v - 1/2)) + 2**(n-1)) / 2**n``, ``iround`` half away from zero,
    by rationals."""
    if not math.isfinite(v):
        return v
    half = Fraction(2**bits, 2)
    x = Fraction(v) * 2**bits - half
    whole = math.trunc(x)
    n = whole + (int(math.copysign(1, x)) if abs(x - whole) >= Fraction(1, 2) else 0)
    return float((n + half) / 2**bits)


@pytest.mark.parametrize("bits", [0, 1, 4, 8, 16])
def test_half_away_shifted_snaps_exactly(bits):
    from harness.contract.conventions import snap

    v = _values(3)
    v = v[np.abs(v) < 2.0**40]
    got = snap(v, bits, "half-away-shifted")
    want = np.array([_shifted_rational(float(x), bits) for x in v])
    assert np.array_equal(got, want), v[got != want][:5]


def test_half_away_shifted_parts_from_half_away_only_in_the_first_half_pixel():
    from harness.contract.conventions import snap

    ties = (np.arange(-64, 64) + 0.5) / 16  # every half step of 1/16 px in [-4, 4)
    shifted, away = snap(ties, 4, "half-away-shifted"), snap(ties, 4, "half-away")
    assert sorted(ties[shifted != away].tolist()) == [(k + 0.5) / 16 for k in range(8)]  # (0, 1/2) only
    assert (shifted[(ties > 0) & (ties < 0.5)] < ties[(ties > 0) & (ties < 0.5)]).all()  # rounded down there


def test_piglit_rounding_is_named_described_and_round_tripped():
    c = Convention(tie="bottom-left", subpixel_bits=8, snap_rounding="half-away-shifted", input="float32")
    assert c.describe() == ("sample (0.5, 0.5), bottom-left ties, float32 input, snapped to 1/256 px "
                            "(8 bits, half away in the frame shifted by half a pixel), no culling")
    assert eval(repr(c), {"Convention": Convention}) == c  # noqa: S307 -- our own repr
    from harness.contract.conventions import LineRule

    assert "shifted frame" in LineRule("parallelogram", snap_rounding="half-away-shifted").describe()
    with pytest.raises(ValueError, match="snap_rounding"):
        Convention(subpixel_bits=8, snap_rounding="half-away-centre")  # type: ignore[arg-type]


@pytest.mark.parametrize("spec, bits", [("float32", 4), ("float32", 8), ("fixed6", 4), ("float64", 0)])
def test_the_oracle_snaps_piglits_way_and_agrees_with_the_rational_reference(spec, bits):
    from cases.conformance import first_half_pixel

    c = Convention(input=spec, subpixel_bits=bits, snap_rounding="half-away-shifted", tie="bottom-left")
    for seed in range(2):
        scene = Scene(12, 12, np.concatenate([_scene(seed).positions, first_half_pixel(30, 12, seed)]))
        grid = input_precision(spec)
        received = [_float32_rational(float(v)) if grid.kind == "float32" else
                    float(v) if grid.kind == "float64" else _grid_rational(float(v), grid.bits, grid.rounding)
                    for v in scene.positions.ravel()]
        by_hand = np.array([_shifted_rational(v, bits) for v in received]).reshape(scene.positions.shape)
        snapped = Scene(scene.width, scene.height, by_hand)
        plain = Convention(tie="bottom-left")  # the rational reference on the vertices snapped by hand
        got = exact_coverage(scene, c).counts(12, 12).tolist()
        assert got == brute_force_coverage(snapped, plain).counts(12, 12).tolist()
        assert got == brute_force_coverage(scene, c).counts(12, 12).tolist()


def test_identify_tells_piglits_rounding_from_half_away():
    from tests.identify.test_coverage_probes import Hidden

    for rounding in ("half-away-shifted", "half-away"):
        hidden = Convention(subpixel_bits=4, snap_rounding=rounding)
        fingerprint = _identified(Hidden(hidden))
        assert fingerprint.exact and fingerprint.convention == hidden, fingerprint.card()
        assert fingerprint.to_dict()["snap_rounding"] == rounding


def test_conformance_catches_unshifted_rounding_claimed_as_piglits():
    """Rounding half away from zero while declaring piglit's shifted frame fails the quick
    suite's lattice/first-half-pixel case, and only it; declared as it is, it passes."""
    from harness import run_suite
    from tests.known_bad.inputs import UnshiftedClaimsPiglit

    bad = UnshiftedClaimsPiglit()
    failed = {(r.case, r.check) for r in run_suite([bad], suite="quick", repros=False, isolate=False) if r.status == "fail"}
    assert failed == {("lattice/first-half-pixel", "conformance")}, failed
    bad.convention = replace(bad.convention, snap_rounding="half-away")
    results = run_suite([bad], suite="quick", repros=False, only={"conformance", "invariance"}, isolate=False)
    assert not [r.case for r in results if r.status in ("fail", "error")]


# --- the adapters' received() is their declared input ---------------------------------------------


def test_the_adapters_declare_their_input_and_received_follows_it():
    """What each adapter's hand-written received() did is its declared ``input`` (read by
    received_of, without loading the library): float32 at the GL and Vulkan APIs and in
    tiny-skia, 26.6 for FreeType, 24.8 by truncation for AGG 2.0 and half away for AGG 2.4."""
    from harness.contract.protocol import input_of, received_of
    from rasterizers.real import agg, freetype_outline, matplotlib_agg, tiny_skia, vulkan
    from rasterizers.real.adapters import MesaLlvmpipe

    rng = np.random.default_rng(5)
    v = np.concatenate([rng.uniform(-40, 40, 300), (np.arange(-40, 40) + 0.5) / 256, (np.arange(-40, 40) + 0.5) / 64,
                        [0.1, -0.1, 1e9, -1e9]])
    scene = Scene(8, 8, v[: len(v) // 6 * 6].reshape(-1, 3, 2))
    expected = {
        freetype_outline.FreeTypeMono: ("fixed6", freetype_outline.received_26_6),
        freetype_outline.FreeTypeSmooth: ("fixed6", freetype_outline.received_26_6),
        agg.AggAliased: ("fixed8-toward-zero", agg._received), agg.AggAntialiased: ("fixed8-toward-zero", agg._received),
        matplotlib_agg.MatplotlibAgg: ("fixed8-half-away", matplotlib_agg._received),
        matplotlib_agg.MatplotlibAggAntialiased: ("fixed8-half-away", matplotlib_agg._received),
        tiny_skia.TinySkia: ("float32", tiny_skia._float32), tiny_skia.TinySkiaAntialiased: ("float32", tiny_skia._float32),
        vulkan.VulkanLavapipe: ("float32", tiny_skia._float32), MesaLlvmpipe: ("float32", tiny_skia._float32),
    }
    adapter: Any
    for adapter, (name, by_hand) in expected.items():
        assert input_of(adapter).name == name and not hasattr(adapter, "received"), adapter
        received = received_of(adapter)
        assert received is not None and np.array_equal(received(scene).coordinates, by_hand(scene).coordinates), adapter
    from rasterizers.fixed_point import FixedPoint

    assert received_of(FixedPoint(8)) is None  # float64 input: nothing to say
    assert received_of(FixedPoint(8, snap_rounding="half-away")) is None  # a convention's input is its oracle's, no account
    from harness.engine.registry import Renamed

    class Box:  # a plugin declaring its input only
        name, convention, input = "box", None, "fixed6"

        def rasterize(self, scene: Scene) -> Any:
            return exact_coverage(scene, Convention())

    renamed, own = received_of(Renamed(Box(), "box#2")), received_of(Box())  # the wrappers keep the declaration
    assert renamed is not None and own is not None
    assert np.array_equal(renamed(scene).coordinates, own(scene).coordinates)


def test_invariance_takes_a_declared_roundings_own_changes_under_translation_as_its_rule():
    """piglit's rounding is not translation invariant in the first half pixel (its ties go down
    there, up beyond 1/2; half away from zero is not either, left of 0): the invariance check
    excuses what the declared convention's own exact coverage changes under the shift, and
    nothing else."""
    from cases.suites import suite
    from harness import run_suite
    from rasterizers.fixed_point import FixedPoint

    case = [c for c in suite("quick") if getattr(c, "id", "") == "lattice/first-half-pixel"]
    right = FixedPoint(4, snap_rounding="half-away-shifted")
    results = run_suite([right], cases=case, repros=False, only={"invariance", "conformance"}, isolate=False)
    assert [r.status for r in results] == ["pass", "pass"], [r.message for r in results]
    class Wrong:  # piglit's rounding declared as half away from zero, translation invariant there
        name, interpolates = "shifted_claims_half_away", False
        convention = replace(right.convention, snap_rounding="half-away")

        def rasterize(self, scene: Scene) -> Any:
            return right.rasterize(scene)

    wrong = Wrong()
    results = run_suite([wrong], cases=case, repros=False, only={"invariance"}, isolate=False)
    assert [r.status for r in results] == ["fail"] and "translate" in results[0].message
