"""identify's fits score a candidate only as far as the fit needs it (the input fit:
:class:`harness.identify.input_probes._Scorer`; the sample point and tie rule:
:class:`harness.identify.triangle_probes.LeastMismatches`): the fits are the same as scoring every
candidate on every scene, the references kept here."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import pytest

from harness.contract.conventions import Convention
from harness.identify import input_probes, triangle_probes
from harness.identify.fingerprint import identify
from harness.identify.triangle_probes import Drawn
from rasterizers.centre_scanline import CentreScanline
from rasterizers.fixed_point import FixedPoint
from rasterizers.floor_scanline import FloorScanline
from tests.known_bad.inputs import Float32Fed, TruncatingInput, UnshiftedClaimsPiglit


class EveryScore:
    """The reference: every candidate scored on every scene, sorted (the fit before)."""

    def __init__(self, answered: Sequence[Drawn], candidates: Sequence[Convention]) -> None:
        self.scored = sorted(((sum(d.mismatches(c) for d in answered), k, c) for k, c in enumerate(candidates)),
                             key=lambda s: (s[0], s[1]))

    def first(self, eligible: Callable[[Convention], bool]) -> tuple[Convention, int] | None:
        return next(((c, score) for score, _, c in self.scored if eligible(c)), None)


class EveryTotal:
    """The reference of :class:`~harness.identify.triangle_probes.LeastMismatches`: every candidate
    summed on every scene drawn so far, sorted by (total, index) (the tie fit before)."""

    def __init__(self, drawn: list[Drawn], candidates: Sequence[Convention]) -> None:
        self.drawn, self.candidates = drawn, list(candidates)

    def first(self, eligible: Callable[[Convention], bool] | None = None) -> tuple[Convention, int]:
        scores = sorted((sum(d.mismatches(c) for d in self.drawn if d.coverage is not None), i)
                        for i, c in enumerate(self.candidates))
        return next((self.candidates[i], total) for total, i in scores if eligible is None or eligible(self.candidates[i]))


RASTERIZERS: dict[str, Callable[[], Any]] = {
    "centre": CentreScanline, "fixed8": lambda: FixedPoint(8), "floor": FloorScanline, "truncating": TruncatingInput,
    "float32-fixed8": lambda: Float32Fed(FixedPoint(8)), "unshifted-piglit": UnshiftedClaimsPiglit,
}


@pytest.mark.parametrize("name", list(RASTERIZERS))
def test_the_input_fit_is_that_of_scoring_every_candidate(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    fast = identify(RASTERIZERS[name]())
    monkeypatch.setattr(input_probes, "_Scorer", EveryScore)
    reference = identify(RASTERIZERS[name]())
    got, want = fast.probes["input"], reference.probes["input"]
    assert isinstance(got, input_probes.InputFit) and isinstance(want, input_probes.InputFit)
    assert (got.convention, got.mismatches, got.scores, got.ambiguous, got.moot_snapping, got.runner_up) == \
        (want.convention, want.mismatches, want.scores, want.ambiguous, want.moot_snapping, want.runner_up)
    assert fast.to_dict() | {"calls": None} == reference.to_dict() | {"calls": None}
    assert fast.card() == reference.card()


@pytest.mark.parametrize("name", ["centre", "floor", "fixed8", "truncating"])
def test_the_tie_fit_is_that_of_scoring_every_candidate(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    fast = identify(RASTERIZERS[name]())
    monkeypatch.setattr(triangle_probes, "LeastMismatches", EveryTotal)
    reference = identify(RASTERIZERS[name]())
    assert fast.probes["sample sweep"] == reference.probes["sample sweep"]
    assert (fast.convention, fast.residual, fast.runner_up, fast.ambiguous) == \
        (reference.convention, reference.residual, reference.runner_up, reference.ambiguous)
    assert fast.to_dict() | {"calls": None} == reference.to_dict() | {"calls": None}
    assert fast.card() == reference.card()
