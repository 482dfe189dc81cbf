"""Every deliberately broken rasterizer by name, as a plugin spec can name it: a campaign
on one of them is ``rastercheck fuzz --rasterizer tests/known_bad/catalogue.py:<name>``
(``bad_inclusive``, ``bad_rare_slope_tie``, ...; :data:`NAMES` lists them).

tests/acceptance/test_known_bad.py keeps its table's rasterizers in here (a test says so), so the
campaigns of the README's table and the known-bad tests are of the same rasterizers.
"""

from __future__ import annotations

from typing import Any

from tests.known_bad.aa_lines import DirectionalAALines, ForgetsCaps, MajorAxisBoxLines, QuarterPixelLines
from tests.known_bad.aa_models import HybridSamplesEveryRow, RowsAtTopEdges, RowsTruncatedLevels
from tests.known_bad.aa_paths import (
    BiasedPartialFiller,
    EvenOddForNonzeroArea,
    OrientationRoundedFiller,
    QuarterPixelPathFiller,
    SignedAreaPathFiller,
)
from tests.known_bad.analytic_models import ComplementsWhereQtNegates, FloorsWhereBlend2DScales, RoundsWhereFreeTypeFloors
from tests.known_bad.antialiasing import (
    BiasedArea,
    CentreSamples,
    CoarseSupersampleClaimsAnalytic,
    DriftingStepArea,
    Float32EdgeStepping,
    FourBitArea,
    GammaEncodedArea,
    HalfPixelShiftedArea,
    InclusiveSampleTies,
    MirroredPattern,
    PerEdgeMethodSwitch,
    RejectsNearEdges,
    SwappedSampleBits,
    TruncatedArea,
)
from tests.known_bad.conventions import DropsHuge, HalfAwayClaimsNearestEven, YFirstClaimsXFirst
from tests.known_bad.coverage_rules import BoxOverestimate, OpenUnderestimate, StrictThreshold
from tests.known_bad.dropout import ClosedWithTies, LeftDropout
from tests.known_bad.edge_functions import BUGS as EDGE_BUGS
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.known_bad.hairlines import LlvmpipeUnshiftedSnap, QtFlatCaps, SkiaCentredStart
from tests.known_bad.inputs import Float32ClaimsFloat64, TruncatesClaimsFloat64, UnshiftedClaimsPiglit
from tests.known_bad.library_rules import ExclusiveRightScanline, Float32AggCover
from tests.known_bad.lines import (
    BackwardPrestep,
    BothEndPixels,
    Float32DDA,
    FullWidthOffset,
    LeftmostFirst,
    OffByOneLast,
    RoundingDDA,
    YMajorAlongX,
)
from tests.known_bad.misc import (
    ClipsBeforeSnapping,
    Float32Input,
    HangsOnEpsilon,
    Int32FixedPoint,
    NaNAttributes,
    Raises,
    ReturnsGarbage,
    SlowOnEpsilon,
    WrongTieClaim,
)
from tests.known_bad.paths import BUGS as PATH_BUGS
from tests.known_bad.paths import PathFillBug, TwoFillers
from tests.known_bad.rare import RareSlopeTie
from tests.known_bad.scanlines import BUGS as SCANLINE_BUGS
from tests.known_bad.scanlines import ScanlineBug
from tests.known_bad.supersample_models import EightSubScanlines, FlooredSubPixels, SampleCountLevels

__all__ = ["KNOWN_BAD", "NAMES"]


def _all() -> list[Any]:
    return [
        *(EdgeFunctionBug(bug) for bug in EDGE_BUGS),
        *(ScanlineBug(bug) for bug in SCANLINE_BUGS if bug != "none"),
        *(PathFillBug(bug) for bug in PATH_BUGS), TwoFillers(),
        SignedAreaPathFiller(), EvenOddForNonzeroArea(),
        # issue 34, AA paths and lines beyond accuracy (tests/checks/test_aa_path_checks.py: AA_TABLE):
        # popping, invariance (reversal, exactly), seams, invariance (segments reversed)
        QuarterPixelPathFiller(), OrientationRoundedFiller(), BiasedPartialFiller(), DirectionalAALines(),
        WrongTieClaim(), YFirstClaimsXFirst(), HalfAwayClaimsNearestEven(), DropsHuge(), Int32FixedPoint(), NaNAttributes(),
        SlowOnEpsilon(), Raises(), ReturnsGarbage(), HangsOnEpsilon(), ClipsBeforeSnapping(), Float32Input(tell=True),
        MirroredPattern(), SwappedSampleBits(), InclusiveSampleTies(), BiasedArea(), PerEdgeMethodSwitch(),
        CoarseSupersampleClaimsAnalytic(), Float32EdgeStepping(), GammaEncodedArea(), HalfPixelShiftedArea(), TruncatedArea(),
        FourBitArea(), DriftingStepArea(), RejectsNearEdges(), CentreSamples(),
        RoundingDDA(), BothEndPixels(), YMajorAlongX(), OffByOneLast(), Float32DDA(), LeftmostFirst(), BackwardPrestep(),
        RareSlopeTie(),
        TruncatesClaimsFloat64(), Float32ClaimsFloat64(), StrictThreshold(), BoxOverestimate(), OpenUnderestimate(),
        FullWidthOffset(), Float32AggCover(), ExclusiveRightScanline(), ClosedWithTies(), LeftDropout(),
        SkiaCentredStart(), QtFlatCaps(), LlvmpipeUnshiftedSnap(),
        MajorAxisBoxLines(), ForgetsCaps(), QuarterPixelLines(),
        UnshiftedClaimsPiglit(),
        RowsAtTopEdges(), RowsTruncatedLevels(), HybridSamplesEveryRow(),
        EightSubScanlines(), FlooredSubPixels(), SampleCountLevels(),
        RoundsWhereFreeTypeFloors(), ComplementsWhereQtNegates(), FloorsWhereBlend2DScales(),
    ]


# name -> rasterizer
KNOWN_BAD: dict[str, Any] = {bad.name: bad for bad in _all()}
NAMES = tuple(KNOWN_BAD)


def __getattr__(name: str) -> Any:
    """``catalogue.py:<name>``: the known-bad rasterizer of that name."""
    try:
        return KNOWN_BAD[name]
    except KeyError:
        raise AttributeError(f"no known-bad rasterizer named {name!r} (known: {', '.join(NAMES)})") from None
