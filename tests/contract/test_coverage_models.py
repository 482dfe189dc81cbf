"""A coverage model is one object (issue 31, point 2): each convention chooses its model
once, the model's answers agree with what the oracle does under it, an unknown model is
refused, and the engine asks the model instead of comparing coverage-kind strings."""

from __future__ import annotations

import pickle
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from harness.checks import checks
from harness.contract.conventions import COVERAGE_KINDS, Convention
from harness.contract.coverage import Coverage
from harness.contract.coverage_models import (
    AREA,
    COVERAGE_MODELS,
    MULTISAMPLE,
    SINGLE,
    SUPERSAMPLED_AREA,
    CoverageModel,
    model_for,
    model_named,
)
from harness.contract.scenes import LineScene, PathScene, Scene
from harness.oracle.coverage import exact_coverage, exact_coverage_python, exact_multisample, exact_single, sample_shares

# a convention of each model
CONVENTIONS = {
    "single": Convention(tie="bottom-right", subpixel_bits=4),
    "multisample": Convention(samples=4, subpixel_bits=4),
    "area": Convention(coverage="area", subpixel_bits=4),
    "supersampled area": Convention(coverage="area", samples=16, levels=17),
    # the coverage rules (issue 33)
    "area-threshold": Convention(coverage="area-threshold", subpixel_bits=4),
    "conservative-over": Convention(coverage="conservative-over", subpixel_bits=4),
    "conservative-under": Convention(coverage="conservative-under", subpixel_bits=4),
    # the rules read from libraries' sources (issue 33)
    "agg-cover": Convention(coverage="agg-cover", input="fixed8-half-away"),
    "inclusive-scanline": Convention(coverage="inclusive-scanline", input="integer-toward-zero"),
    "closed": Convention(coverage="closed", subpixel_bits=4),
    # cairo's row-sampled hybrid (issue 34)
    "row-sampled area": Convention(coverage="area", rows=15, full_rows=True, input="fixed8"),
    # skia's supersampler as tiny-skia runs it (issue 34)
    "skia-supersampled area": Convention(coverage="area", supersample=2, input="float32"),
    "quantised area": Convention(coverage="area", quantisation="ftgrays", input="fixed6"),
}
# two overlapping triangles with an attribute each vertex, edges through pixel centres
SCENE = Scene(6, 5, np.array([[[0.0, 0.0], [6.0, 0.0], [0.0, 5.0]], [[5.5, 4.75], [1.25, 0.5], [6.0, 4.0]]]),
              attributes=np.arange(6, dtype=np.float64).reshape(2, 3, 1))


def test_a_convention_of_each_kind_gets_its_model():
    assert {name: c.model for name, c in CONVENTIONS.items()} == COVERAGE_MODELS
    models = COVERAGE_MODELS.values()
    assert [CONVENTIONS[m.name].coverage_kind for m in models] == [m.coverage_kind for m in models]
    # the kinds keep their strings (JSON, reports, the command line); supersampled area is area to them
    assert [c.coverage_kind for c in CONVENTIONS.values()] == ["single", "multisample", "area", "area", "single", "single",
                                                                "single", "single", "single", "single", "area", "area",
                                                                "area"]
    assert COVERAGE_KINDS == ("single", "multisample", "area")
    # chosen again when the declaration changes, kept across processes (one object per model)
    assert replace(CONVENTIONS["multisample"], samples=None).model is SINGLE
    assert replace(CONVENTIONS["area"], samples=4).model is SUPERSAMPLED_AREA
    assert replace(CONVENTIONS["supersampled area"], coverage="sample").model is MULTISAMPLE
    for convention in CONVENTIONS.values():
        again = pickle.loads(pickle.dumps(convention))
        assert again == convention and again.model is convention.model and hash(again) == hash(convention)
    # the model is no part of a convention's fields, equality or repr
    assert "model" not in repr(CONVENTIONS["area"]) and "model" not in Convention.__dataclass_fields__


def test_a_convention_of_each_model_reads_back_where_only_records_may():
    """The campaign's identified-convention file admits the harness's record classes only:
    a convention of each model still reads back (its model is derived, not pickled)."""
    import io

    from harness.campaign.state import _FingerprintUnpickler

    for convention in CONVENTIONS.values():
        again = _FingerprintUnpickler(io.BytesIO(pickle.dumps(convention))).load()
        assert again == convention and again.model is convention.model


def test_an_unknown_model_is_refused_in_one_line():
    with pytest.raises(ValueError, match=r"^no coverage model is named 'conservative': single, multisample, area, "
                                         r"supersampled area, area-threshold, conservative-over, conservative-under, agg-cover, "
                                         r"inclusive-scanline, closed, row-sampled area, skia-supersampled area, "
                                         r"quantised area$"):
        model_named("conservative")
    with pytest.raises(ValueError, match=r"^Convention.coverage must be one of sample, area, area-threshold, "
                                         r"conservative-over, conservative-under, agg-cover, inclusive-scanline, closed, "
                                         r"not 'box'$"):
        Convention(coverage="box")  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        Convention(model=AREA)  # type: ignore[call-arg]  # chosen from the declaration, never given
    with pytest.raises((AttributeError, TypeError)):  # a frozen, slotted dataclass: never set either
        Convention().model = AREA  # type: ignore[misc]
    assert model_named("area") is AREA and model_for("area", True) is SUPERSAMPLED_AREA


def test_each_model_names_the_oracle_exact_coverage_used():
    """The oracle dispatch each model owns is what exact_coverage did per kind before."""
    wanted = {"single": exact_single, "multisample": exact_multisample, "supersampled area": sample_shares}
    from harness.oracle.area import area_coverage

    wanted["area"] = area_coverage
    from harness.oracle.coverage_rules import conservative_over, conservative_under, threshold_coverage

    wanted.update({"area-threshold": threshold_coverage, "conservative-over": conservative_over,
                   "conservative-under": conservative_under})
    from harness.oracle.library_rules import agg_cover_coverage, inclusive_scanline_coverage

    wanted.update({"agg-cover": agg_cover_coverage, "inclusive-scanline": inclusive_scanline_coverage})
    from harness.oracle.dropout import closed_triangles

    wanted["closed"] = closed_triangles
    from harness.oracle.aa_models import row_sampled_coverage

    wanted["row-sampled area"] = row_sampled_coverage
    from harness.oracle.supersample_models import skia_supersampled_coverage

    wanted["skia-supersampled area"] = skia_supersampled_coverage
    from harness.oracle.analytic_models import quantised_area_coverage

    wanted["quantised area"] = quantised_area_coverage
    for name, model in COVERAGE_MODELS.items():
        module, _, function = model.triangle_oracle.partition(":")
        assert getattr(__import__(module, fromlist=[function]), function) is wanted[name], name


def _spans(coverage: Coverage) -> Coverage:
    """The spans alone (no sample ids, attributes or alphas)."""
    return Coverage(coverage.triangle, coverage.y, coverage.x0, coverage.x1)


@pytest.mark.parametrize("name", list(CONVENTIONS))
def test_each_models_oracle_gives_what_exact_coverage_gives(name):
    convention = CONVENTIONS[name]
    mine = convention.model.exact_triangles(SCENE, convention)
    assert mine == exact_coverage(SCENE, convention)
    # and what each kind's oracle gave, computed independently of the dispatch
    if name == "single":
        assert _spans(mine) == exact_coverage_python(SCENE, convention)
    elif name == "multisample":
        for s in range(convention.n_samples):
            assert _spans(mine.layer(s)) == exact_coverage_python(SCENE, convention.at_sample(s)), s
    elif name == "closed":
        from harness.oracle.closed_rule import closed_reference

        assert mine == closed_reference(SCENE, convention)
    elif convention.model.rule:
        from harness.oracle.coverage_rules import rules_reference

        assert mine == rules_reference(SCENE, convention)
    else:
        assert mine.alpha is not None and np.all((mine.alpha > 0) & (mine.alpha <= 1))
        # every pixel a triangle covers whole has alpha 1 under both area models
        assert 1.0 in mine.alpha.tolist()


@pytest.mark.parametrize("name", list(CONVENTIONS))
def test_a_models_answers_have_the_form_it_says(name):
    """sample ids, alphas and attributes as the model says, in the oracle's own answers."""
    convention = CONVENTIONS[name]
    model = convention.model
    answer = exact_coverage(SCENE, convention)
    assert (answer.sample is not None) == model.sample_ids == model.layered
    assert (answer.alpha is not None) == model.alphas
    assert (answer.attributes is not None) == model.interpolates
    assert model.single_sample == (convention.n_samples == 1 and not model.alphas and model.sample_point)
    assert not (model.sample_ids and model.alphas)


def test_paths_and_lines_are_defined_where_the_model_says():
    from harness.oracle.lines import line_coverage
    from harness.oracle.winding import path_coverage

    square = PathScene.from_paths(4, 4, [[[[0, 0], [4, 0], [4, 4], [0, 4]]]])
    line = LineScene.from_strips(6, 4, [[[0.5, 0.5], [4.5, 2.5]]])
    for name, model in COVERAGE_MODELS.items():
        # multisample and (analytic) area lines are rectangles
        convention = replace(CONVENTIONS[name], line="rectangle") if model.sample_ids or model.alphas else CONVENTIONS[name]
        if model.paths:
            assert len(path_coverage(square, convention)), name
        else:
            with pytest.raises(ValueError, match="coverage of paths is not defined"):
                path_coverage(square, convention)
        if model.lines:
            assert len(line_coverage(line, convention)), name
        else:
            with pytest.raises(ValueError, match="lines are defined for single-sample and multisample conventions"):
                line_coverage(line, convention)


def test_the_checks_that_apply_are_those_of_the_models_kind():
    registered = checks()
    for model in COVERAGE_MODELS.values():
        assert [c.name for c in registered if model.applies(c)] == [c.name for c in checks(coverage_kind=model.coverage_kind)]
    names = {m.name: {c.name for c in registered if m.applies(c)} for m in COVERAGE_MODELS.values()}
    assert "conformance" in names["single"] & names["multisample"] and "conformance" not in names["area"]
    assert "accuracy" in names["area"] and names["area"] == names["supersampled area"]
    assert "hygiene" in set.intersection(*names.values())


def test_the_words_a_model_gives_messages():
    assert [m.declared_as(CONVENTIONS[m.name]) for m in COVERAGE_MODELS.values()] == [
        "one sample per pixel", "a multisample pattern of 4 samples", "area coverage", "area coverage",
        "an area threshold (a pixel iff at least 0.5 of it is covered)",
        "conservative overestimate (a pixel iff its square meets the triangle)",
        "conservative underestimate (a pixel iff its square lies in the triangle)",
        "AGG's cell cover (a pixel iff its 8-bit cover is at least 256 x 0.5)",
        "an inclusive scanline fill (each row from the truncated left crossing to the right one, both drawn)",
        "the closed rule (a sample on an edge is inside) at sample (0.5, 0.5)", "row-sampled area coverage",
        "skia's supersampled area coverage", "area coverage at a library's levels"]
    from harness.identify.fingerprint import VERDICT_CHECKS

    assert VERDICT_CHECKS == {"single": ("conformance",), "multisample": ("conformance",),
                              "area": ("accuracy", "seams", "popping")}
    assert all(isinstance(m, CoverageModel) and repr(m) == f"CoverageModel({m.name!r})" for m in COVERAGE_MODELS.values())


# --- no coverage-kind string compares outside the models ------------------------------------

_KIND = r"""["'](?:single|multisample|area)["']"""
# x == "area", "area" != x, x in ("area", ...), x not in {"single", ...}
COMPARE = re.compile(rf"(?:==|!=)\s*{_KIND}|{_KIND}\s*(?:==|!=)|\bin\s*[(\[{{][^)\]}}]*{_KIND}")
# the module that owns the models
EXEMPT = {"coverage_models.py"}
MOST = 3


def _compares() -> list[str]:
    root = Path(__file__).resolve().parents[2] / "harness"
    found = []
    for path in sorted(root.rglob("*.py")):
        name = path.relative_to(root).as_posix()
        if name in EXEMPT:
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if COMPARE.search(line):
                found.append(f"harness/{name}:{number}: {line.strip()}")
    return found


def test_the_pattern_finds_the_compares_it_counts():
    for line in ('if convention.kind == "area":', "if kind != 'single':", 'if kind.kind in ("area", "multisample"):',
                 'ok = "multisample" == kind', "if coverage not in ('sample', 'area'):",
                 "getattr(convention, 'coverage', 'sample') == \"area\""):
        assert COMPARE.search(line), line
    for line in ('Convention(coverage="area")', 'kind=SINGLE.kind', 'if model.alphas:', 'series = {"area": []}',
                 'if c.kind in KINDS:', 'if kind == "regression":'):
        assert not COMPARE.search(line), line


def test_the_harness_asks_the_model_not_the_kinds_name():
    found = _compares()
    assert len(found) <= MOST, "coverage-kind string compares (ask convention.model):\n" + "\n".join(found)
