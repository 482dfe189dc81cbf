"""The coverage models: what one sample per pixel, a multisample pattern and anti-aliased
area coverage each mean to the engine, one object each.

A convention's declaration (its ``coverage`` and whether it has ``samples``) chooses its
model in one place, :func:`model_for`, behind :attr:`Convention.model
<harness.contract.conventions.Convention.model>`; the engine then asks the model, never compares
its name:

==============  ===========  ===========================================================
model           ``kind``     what a (triangle, pixel) gets
==============  ===========  ===========================================================
``single``      single       covered or not, at the convention's one sample point
``multisample`` multisample  each sample of the pattern covered or not (a sample id each)
``area``        area         an alpha, the exact area inside the pixel
``supersampled  area         an alpha, the share of the pattern's samples covered (a
area``                       box-filter resolve)
``area-         single       covered or not: iff the triangle covers at least
threshold``                  ``threshold`` of the pixel's area (aggdraw's aliased mode)
``conservative- single       covered or not: iff the pixel's closed square meets the
over``                       closed triangle (D3D12/Vulkan overestimate)
``conservative- single       covered or not: iff the pixel's closed square lies in the
under``                      closed triangle (D3D12/Vulkan underestimate)
``agg-cover``   single       covered or not: iff AGG's 8-bit cell cover of the pixel is at
                             least 256 ``threshold`` (aggdraw's and matplotlib's aliased fills)
``inclusive-    single       covered or not: every row between the integer vertices, from
scanline``                   the truncated left crossing to the right one, both included (pygame)
``closed``      single       covered or not: iff the sample point lies in the closed
                             triangle, on an edge included (FreeType's monochrome)
``row-sampled   area         an alpha, the mean of the triangle's cross-sections on n lines
area``                       per pixel row, exact along x (cairo; ``Convention.rows``)
``skia-super-   area         an alpha, skia's supersampler's 8-bit level: 2**shift sub-scanlines,
sampled area``               x rounded to 1/2**shift px (tiny-skia; ``Convention.supersample``)
``quantised     area         an alpha, the level a library's arithmetic makes of the exact
area``                       area (FreeType, Qt, AGG, Blend2D; ``Convention.quantisation``)
==============  ===========  ===========================================================

``closed`` is a coverage rule decided at the sample point (``sample_point`` True: its near
ties are measured there) whose edges belong to every triangle sharing them: a planar
partition's samples on shared edges are hit twice (``exactly_once`` False), and its
convention may declare dropout control (:class:`harness.contract.conventions.Dropout`).

The other five are *coverage rules* (``rule``): declared by their name as
``Convention.coverage``, answered as one sample per pixel is (a (triangle, pixel) covered or
not, so the single-sample checks judge them), but decided on the pixel's square, not at a
sample point: the tie rule and ``sample`` mean nothing to them (``sample_point`` False: no
near tie is measured at a sample), and a planar partition's pixels are not hit exactly once
under them (``exactly_once`` False: watertight, overdraw and closed excuse the holes and
double hits the rule's own exact answer has). Paths, lines and points are not defined under
them (triangles only; the oracles refuse in one line). The last two are procedures read from
libraries' sources (:mod:`harness.oracle.library_rules`), defined on the integer grid their
library receives (``input_bits``: a convention must declare an input precision that fine or
coarser).

``coverage_kind`` is the coverage kind of :attr:`Convention.coverage_kind
<harness.contract.conventions.Convention.coverage_kind>`, the word JSON, reports, the command line and
:attr:`harness.checks.Check.coverage_kinds` use: supersampled area coverage is area coverage to
them (its answers have the same form and the same checks judge it); it is a model of its
own only where it differs (its oracle, and that it is defined for paths).

Each model owns what differs per model: its triangle oracle (:meth:`CoverageModel.
exact_triangles`), the form of its answers (sample ids, alphas, attributes), whether a
check written for one sample judges it sample by sample (``layered``), whether paths and
lines have an oracle under it, the checks that judge it (:meth:`CoverageModel.applies`;
identify's verdict checks) and the words messages use. A new coverage model is one more
object in :data:`COVERAGE_MODELS` (and its oracle).

This module sits beside :mod:`harness.contract.conventions`, below everything that computes: it
imports no other module of the harness. The oracles sit above the conventions they
apply, so a model names its oracle (``"harness.oracle.coverage:exact_multisample"``) and resolves
the name when first asked, as :mod:`harness` resolves its lazily imported names.

>>> [m.name for m in COVERAGE_MODELS.values()]  # doctest: +NORMALIZE_WHITESPACE
['single', 'multisample', 'area', 'supersampled area', 'area-threshold', 'conservative-over', 'conservative-under',
 'agg-cover', 'inclusive-scanline', 'closed', 'row-sampled area', 'skia-supersampled area', 'quantised area']
>>> model_named("multisample").sample_ids, model_named("area").alphas
(True, True)
>>> model_named("conservative")  # doctest: +NORMALIZE_WHITESPACE
Traceback (most recent call last):
...
ValueError: no coverage model is named 'conservative': single, multisample, area, supersampled area, area-threshold,
conservative-over, conservative-under, agg-cover, inclusive-scanline, closed, row-sampled area, skia-supersampled area,
quantised area
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

__all__ = ["CoverageModel", "CoverageKind", "COVERAGE_KINDS", "COVERAGE_MODELS", "DECLARED_COVERAGES", "SINGLE",
           "MULTISAMPLE", "AREA", "SUPERSAMPLED_AREA", "ROW_SAMPLED_AREA", "SKIA_SUPERSAMPLED_AREA", "QUANTISED_AREA",
           "AREA_THRESHOLD", "CONSERVATIVE_OVER", "CONSERVATIVE_UNDER",
           "AGG_COVER", "INCLUSIVE_SCANLINE", "CLOSED", "COVERAGE_RULES", "MAX_SAMPLES", "MAX_AREA_SAMPLES", "model_named",
           "model_for"]

CoverageKind = Literal["single", "multisample", "area"]
# what Convention.coverage may say: point samples (one, or a pattern's), area, or a coverage
# rule by its model's name (COVERAGE_RULES)
DECLARED_COVERAGES: tuple[str, ...] = ("sample", "area", "area-threshold", "conservative-over", "conservative-under",
                                       "agg-cover", "inclusive-scanline", "closed")
# The most samples per pixel a pattern may have (GL/Vulkan implementations top out at 32 or
# 64 with no standard locations; 32 keeps a garbage answer's span budget bounded).
MAX_SAMPLES = 32
# ... and a supersampled area convention (alpha = share of its samples) up to 16 x 16:
# its answer is one alpha per pixel, however many samples stand behind it.
MAX_AREA_SAMPLES = 256


@dataclass(frozen=True, eq=False)
class CoverageModel:
    """One coverage model: a few facts the engine asks instead of comparing names.

    Compared by identity (one object per model, kept one across processes: a pickled
    model is unpickled as the same object).

    Parameters
    ----------
    name : str
        Its key in :data:`COVERAGE_MODELS`.
    coverage_kind : {"single", "multisample", "area"}
        The coverage kind it is (:attr:`Convention.coverage_kind
        <harness.contract.conventions.Convention.coverage_kind>`, :attr:`harness.checks.Check.coverage_kinds`).
    triangle_oracle : str
        ``"module:function"``, its exact oracle of a triangle scene under a convention
        of this model (:meth:`exact_triangles`).
    declared : str
        How a message says a convention declares it (``{n}``: the samples per pixel).
    seen : str
        How a message says what an answer of it carries.
    single_sample : bool
        One sample per pixel, at the convention's ``sample``: a fragment is a (triangle,
        pixel) covered or not.
    sample_ids : bool
        Its answers carry a sample id per span (and no alphas).
    alphas : bool
        Its answers carry an alpha per pixel (and no sample ids).
    layered : bool
        A check written for one sample judges its answers sample by sample, each
        sample's layer as a single-sample answer (:meth:`harness.checks.Subject.layer`).
    interpolates : bool
        Its oracle interpolates the scene's attributes at each covered sample (area
        coverage has no sample to interpolate at).
    paths : bool
        The exact coverage of path scenes is defined under it.
    lines : bool
        The exact coverage of line scenes is defined under it.
    max_samples : int
        The most samples per pixel its convention's pattern may hold (0: it has none).
    verdict_checks : tuple of str
        The checks that judge a declared convention of it before identify calls the
        declaration confirmed or consistent (:data:`harness.identify.fingerprint.VERDICT_CHECKS`).
    rule : bool
        A coverage rule: declared by its name as ``Convention.coverage`` (no sample pattern).
    sample_point : bool
        Its decisions are made at sample points (the near ties of the checks are measured
        there); False: on the pixel's square, and no deviation is a near tie.
    exactly_once : bool
        Its exact answer hits every pixel inside a planar partition exactly once (but where
        snapping folds the mesh); False: the rule's own holes and double hits are expected
        (watertight, overdraw and closed excuse those its exact answer has).
    thresholded : bool
        Its convention's ``threshold`` means something (``declared`` may name it: ``{t}``).
    uncertain : bool
        Its convention may declare an ``uncertainty`` region (the conservative rules).
    input_bits : int or None
        A rule defined on an integer grid of 2**-input_bits px (the one its library
        receives): its convention's ``input`` must be ``fixedN`` with N <= input_bits or
        ``integer``; None: any input.
    zero_area : bool
        Its zero-area triangles may draw (the closed rule: the samples on their segment);
        False: a zero-area triangle draws nothing (the degenerate check's expectation).
    path_oracle : str
        ``"module:function"``, its own exact oracle of path scenes (:meth:`exact_paths`),
        when it has one; "" (default): the winding oracle's sample-point paths.
    quantum : int
        Its oracle's alphas are exact multiples of 1/quantum (the library's own levels: the
        exact value of an oracle alpha a is round(a * quantum) / quantum, and the float
        oracle has no error beyond that rounding); 0 (default): no such promise.
    """

    name: str
    coverage_kind: CoverageKind
    triangle_oracle: str
    declared: str
    seen: str
    single_sample: bool = False
    sample_ids: bool = False
    alphas: bool = False
    layered: bool = False
    interpolates: bool = False
    paths: bool = True
    lines: bool = False
    max_samples: int = 0
    verdict_checks: tuple[str, ...] = ()
    rule: bool = False
    sample_point: bool = True
    exactly_once: bool = True
    thresholded: bool = False
    uncertain: bool = False
    input_bits: int | None = None
    zero_area: bool = False
    path_oracle: str = ""
    quantum: int = 0

    def __repr__(self) -> str:
        return f"CoverageModel({self.name!r})"

    def __reduce__(self) -> tuple[Callable[[str], CoverageModel], tuple[str]]:
        return model_named, (self.name,)

    def applies(self, check: Any) -> bool:
        """Whether ``check`` (a :class:`harness.checks.Check`) judges answers of this
        model: its ``coverage_kinds`` name this model's coverage kind."""
        return self.coverage_kind in check.coverage_kinds

    def declared_as(self, convention: Any) -> str:
        """How a message says ``convention`` (of this model) declares it: ``one sample per
        pixel``, ``a multisample pattern of 4 samples``, ``area coverage``."""
        dropout = getattr(convention, "dropout_control", None)
        sx, sy = getattr(convention, "sample", (0.5, 0.5))
        return self.declared.format(n=convention.n_samples, t=f"{getattr(convention, 'threshold', 0.5):g}",
                                    s=f"({sx:g}, {sy:g})",
                                    d="" if dropout is None or not dropout.active else f", {dropout.describe()}")

    def exact_triangles(self, scene: Any, convention: Any) -> Any:
        """The exact coverage (a :class:`harness.contract.coverage.Coverage`) of the triangle scene
        ``scene`` under ``convention``, a convention of this model: what
        :func:`harness.oracle.coverage.exact_coverage` gives for triangles (uncached)."""
        return _resolved(self.triangle_oracle)(scene, convention)

    def exact_paths(self, scene: Any, convention: Any) -> Any:
        """The exact coverage of the path scene ``scene`` under ``convention`` by its own
        :attr:`path_oracle` (what :func:`harness.oracle.winding.path_coverage` gives)."""
        return _resolved(self.path_oracle)(scene, convention)


@functools.cache
def _resolved(spec: str) -> Callable[[Any, Any], Any]:
    """The function ``"module:function"`` names (imported when first asked)."""
    module, _, function = spec.partition(":")
    found: Callable[[Any, Any], Any] = getattr(importlib.import_module(module), function)
    return found


SINGLE = CoverageModel(
    "single", "single", "harness.oracle.coverage:exact_single", declared="one sample per pixel", seen="one sample per pixel",
    single_sample=True, interpolates=True, lines=True, max_samples=1, verdict_checks=("conformance",))
MULTISAMPLE = CoverageModel(
    "multisample", "multisample", "harness.oracle.coverage:exact_multisample", declared="a multisample pattern of {n} samples",
    seen="samples per pixel", sample_ids=True, layered=True, interpolates=True, lines=True, max_samples=MAX_SAMPLES,
    verdict_checks=("conformance",))  # judged sample by sample
AREA = CoverageModel(
    "area", "area", "harness.oracle.area:area_coverage", declared="area coverage",
    seen="an alpha per pixel and triangle (anti-aliased)", alphas=True, lines=True,
    verdict_checks=("accuracy", "seams", "popping"))  # paths: harness.oracle.path_area; lines: harness.oracle.area_lines
# cairo's model (issue 34): each pixel row sampled on n lines, exact along x (harness.oracle.aa_models)
ROW_SAMPLED_AREA = CoverageModel(
    "row-sampled area", "area", "harness.oracle.aa_models:row_sampled_coverage", declared="row-sampled area coverage",
    seen="an alpha per pixel and triangle (anti-aliased)", alphas=True,
    path_oracle="harness.oracle.row_sampled_paths:row_sampled_path_coverage",  # paths: each sample line's cross-section
    verdict_checks=("accuracy", "seams", "popping"))
SUPERSAMPLED_AREA = CoverageModel(
    "supersampled area", "area", "harness.oracle.coverage:sample_shares", declared="area coverage",
    seen="an alpha per pixel and triangle (anti-aliased)", alphas=True, max_samples=MAX_AREA_SAMPLES,
    verdict_checks=("accuracy", "seams", "popping"))
# the coverage rules (issue 33): one (triangle, pixel) covered or not, decided on the pixel's square
AREA_THRESHOLD = CoverageModel(
    "area-threshold", "single", "harness.oracle.coverage_rules:threshold_coverage",
    declared="an area threshold (a pixel iff at least {t} of it is covered)", seen="one sample per pixel",
    paths=False, verdict_checks=("conformance",), rule=True, sample_point=False, exactly_once=False, thresholded=True)
CONSERVATIVE_OVER = CoverageModel(
    "conservative-over", "single", "harness.oracle.coverage_rules:conservative_over",
    declared="conservative overestimate (a pixel iff its square meets the triangle)", seen="one sample per pixel",
    paths=False, verdict_checks=("conformance",), rule=True, sample_point=False, exactly_once=False, uncertain=True)
CONSERVATIVE_UNDER = CoverageModel(
    "conservative-under", "single", "harness.oracle.coverage_rules:conservative_under",
    declared="conservative underestimate (a pixel iff its square lies in the triangle)", seen="one sample per pixel",
    paths=False, verdict_checks=("conformance",), rule=True, sample_point=False, exactly_once=False, uncertain=True)

# the rules read from libraries' sources (issue 33): procedures on the integer grid the library receives
AGG_COVER = CoverageModel(
    "agg-cover", "single", "harness.oracle.library_rules:agg_cover_coverage",
    declared="AGG's cell cover (a pixel iff its 8-bit cover is at least 256 x {t})", seen="one sample per pixel",
    paths=False, verdict_checks=("conformance",), rule=True, sample_point=False, exactly_once=False, thresholded=True,
    input_bits=8)
INCLUSIVE_SCANLINE = CoverageModel(
    "inclusive-scanline", "single", "harness.oracle.library_rules:inclusive_scanline_coverage",
    declared="an inclusive scanline fill (each row from the truncated left crossing to the right one, both drawn)",
    seen="one sample per pixel", paths=False, verdict_checks=("conformance",), rule=True, sample_point=False,
    exactly_once=False, input_bits=0, zero_area=True)

# decided at the sample point, an edge's samples inside for every triangle sharing it (FreeType's monochrome)
CLOSED = CoverageModel(
    "closed", "single", "harness.oracle.dropout:closed_triangles",
    declared="the closed rule (a sample on an edge is inside) at sample {s}{d}", seen="one sample per pixel",
    single_sample=True, verdict_checks=("conformance",), rule=True, sample_point=True, exactly_once=False,
    zero_area=True, path_oracle="harness.oracle.dropout:closed_paths")

# skia's supersampler as tiny-skia runs it (issue 34): its integer procedure, 8-bit levels (harness.oracle.supersample_models).
# Judged by accuracy alone: its own exact answer leaves seams (a vertex on a sub-row's centre line counts
# sub-samples twice: 288 levels summed on watertight/grid-6x6-main/lattice) and pops, which the seams and
# popping checks report as the library's artifacts, not as a departure from the declaration.
SKIA_SUPERSAMPLED_AREA = CoverageModel(
    "skia-supersampled area", "area", "harness.oracle.supersample_models:skia_supersampled_coverage",
    declared="skia's supersampled area coverage", seen="an alpha per pixel and triangle (anti-aliased)", alphas=True,
    verdict_checks=("accuracy",), path_oracle="harness.oracle.supersample_models:skia_supersampled_paths",
    quantum=255)
# an analytic library's model (issue 34): the exact area of the polygon as received, then
# the library's own levels (Convention.quantisation: harness.contract.quantisations)
QUANTISED_AREA = CoverageModel(
    "quantised area", "area", "harness.oracle.analytic_models:quantised_area_coverage",
    declared="area coverage at a library's levels", seen="an alpha per pixel and triangle (anti-aliased)", alphas=True,
    paths=False, verdict_checks=("accuracy", "seams", "popping"))

COVERAGE_MODELS: dict[str, CoverageModel] = {m.name: m for m in (SINGLE, MULTISAMPLE, AREA, SUPERSAMPLED_AREA, AREA_THRESHOLD,
                                                                  CONSERVATIVE_OVER, CONSERVATIVE_UNDER, AGG_COVER,
                                                                  INCLUSIVE_SCANLINE, CLOSED, ROW_SAMPLED_AREA,
                                                                  SKIA_SUPERSAMPLED_AREA, QUANTISED_AREA)}
# the coverage rules, by the Convention.coverage that declares each (its name)
COVERAGE_RULES: dict[str, CoverageModel] = {m.name: m for m in COVERAGE_MODELS.values() if m.rule}
# the coverage kinds, in the models' order
COVERAGE_KINDS: tuple[CoverageKind, ...] = tuple(dict.fromkeys(m.coverage_kind for m in COVERAGE_MODELS.values()))


def model_named(name: str) -> CoverageModel:
    """The model called ``name`` (a coverage kind names the model of that kind without a
    pattern: ``area`` is analytic area); a ValueError naming the models otherwise."""
    model = COVERAGE_MODELS.get(name)
    if model is None:
        raise ValueError(f"no coverage model is named {name!r}: {', '.join(COVERAGE_MODELS)}")
    return model


def model_for(coverage: str, pattern: bool, rows: int = 0, supersample: int = 0,
              quantisation: str = "nearest") -> CoverageModel:
    """The model a convention declaring ``coverage`` (``sample`` or ``area``:
    :data:`DECLARED_COVERAGES`) chooses, with a sample pattern or without: the one place
    a declaration becomes a model (any coverage but ``area`` is taken as ``sample``;
    :class:`~harness.contract.conventions.Convention` refuses the others).

    >>> model_for("sample", False), model_for("sample", True), model_for("area", False), model_for("area", True)
    (CoverageModel('single'), CoverageModel('multisample'), CoverageModel('area'), CoverageModel('supersampled area'))
    >>> model_for("area", False, rows=15)
    CoverageModel('row-sampled area')
    >>> model_for("area", False, supersample=2)
    CoverageModel('skia-supersampled area')
    >>> model_for("area", False, quantisation="ftgrays")
    CoverageModel('quantised area')
    >>> model_for("conservative-over", False)
    CoverageModel('conservative-over')
    """
    rule = COVERAGE_RULES.get(coverage)
    if rule is not None:
        return rule  # no pattern: Convention refuses samples with a coverage rule
    if coverage == "area":
        if rows and not pattern:
            return ROW_SAMPLED_AREA  # Convention(coverage="area", rows=n): n sample lines per pixel row
        if supersample and not pattern:
            return SKIA_SUPERSAMPLED_AREA  # Convention(coverage="area", supersample=shift): skia's supersampler
        if quantisation != "nearest" and not pattern:
            return QUANTISED_AREA  # Convention(coverage="area", quantisation=q): a library's levels of the exact area
        return SUPERSAMPLED_AREA if pattern else AREA
    return MULTISAMPLE if pattern else SINGLE
