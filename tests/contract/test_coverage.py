"""The contract beyond one sample per pixel: multisample spans (a sample index per span)
and area coverage (an alpha per pixel) flow through Coverage, the oracle and the checks,
and the single-sample checks judge a multisample answer sample by sample."""

from __future__ import annotations

import numpy as np
import pytest

from cases.suites import suite
from harness import run_suite
from harness.checks import checks, hygiene
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.samples import pattern
from harness.contract.scenes import Scene
from harness.oracle.coverage import exact_coverage, exact_samples
from tests.narrow import triangles

QUICK = suite("quick")
STATIC = [c for c in QUICK if isinstance(c, Case)]


class OracleMSAA:
    """The exact multisample oracle as a rasterizer: the reference answer."""

    name = "oracle_msaa4"
    convention = Convention(samples=4)

    def rasterize(self, scene: Scene) -> Coverage:
        return exact_coverage(scene, self.convention)


class DropsOneSample(OracleMSAA):
    """Forgets sample 2 of every pixel: per-sample conformance must name sample 2."""

    name = "drops_sample_2"

    def rasterize(self, scene: Scene) -> Coverage:
        full = exact_coverage(scene, self.convention)
        return full.take(np.flatnonzero(full.sample != 2))


class OracleArea:
    """The exact area, quantised to 8 bits."""

    name = "oracle_area"
    convention = Convention(coverage="area", tolerance=0.5 / 255 + 2.0**-24)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = exact_coverage(scene, self.convention)
        assert exact.alpha is not None
        return Coverage(exact.triangle, exact.y, exact.x0, exact.x1, alpha=np.round(exact.alpha * 255) / 255)


def test_multisample_coverage_round_trips_through_pixels_layers_and_canonical_form():
    scene = Scene(6, 5, [[[0.3, 0.2], [5.7, 1.1], [1.2, 4.9]], [[5.5, 0.5], [6.0, 5.0], [2.0, 5.0]]])
    convention = Convention(samples=8)
    cov = exact_coverage(scene, convention)
    assert cov.sample is not None and set(cov.sample.tolist()) <= set(range(8))
    layers = exact_samples(scene, Convention(), 8)
    for s in range(8):
        assert cov.layer(s) == layers[s]  # the layer is the single-sample oracle at that offset
    t, x, y = cov.pixels()
    again = Coverage.from_pixels(t[::-1], x[::-1], y[::-1], sample=cov.fragment_samples()[::-1])
    assert again == cov and again.canonical() == cov
    assert again != Coverage(cov.triangle, cov.y, cov.x0, cov.x1)  # sample indices are part of the answer
    assert cov.counts(6, 5).sum() == cov.n_pixels


def test_tidy_keys_multisample_spans_on_triangle_and_sample():
    scene = Scene(8, 4, [[[0, 0], [8, 0], [0, 4]]])
    # sample 1 emits pixel (2, 1) twice, sample 3 once; a span names sample 99 (none of 32)
    cov = Coverage([0, 0, 0, 0], [1, 1, 1, 1], [0, 2, 2, 0], [3, 3, 3, 1], sample=[1, 1, 3, 99])
    usable, flaws = cov.tidy(scene)
    assert flaws["repeated"].tolist() == [1] and flaws["bad_sample"].tolist() == [3]
    assert flaws["repeated_pixels"].tolist() == [1] and not flaws["bad_primitive_id"].size
    assert usable.sample is not None and usable.sample.tolist() == [1, 3] and usable.n_pixels == 4
    clean = Coverage([0, 0], [1, 1], [0, 0], [3, 3], sample=[0, 1])
    assert clean.tidy(scene)[0] is clean  # the same pixel in two samples is no repeat


def test_alpha_rows_follow_their_pixels_through_tidy_and_canonical_form():
    scene = Scene(4, 2, [[[0, 0], [4, 0], [0, 2]]])
    cov = Coverage([0, 0], [1, 0], [0, 1], [2, 3], alpha=[0.5, 0.25, 1.0, 0.75])
    canonical = cov.canonical()
    assert canonical.alpha is not None
    assert canonical.y.tolist() == [0, 1] and canonical.alpha.tolist() == [1.0, 0.75, 0.5, 0.25]
    clipped, flaws = Coverage([0], [0], [-2], [2], alpha=[0.1, 0.2, 0.3, 0.4]).tidy(scene)
    assert clipped.alpha is not None
    assert flaws["outside_viewport"].tolist() == [0] and clipped.alpha.tolist() == [0.3, 0.4]
    assert cov == canonical and cov != Coverage([0, 0], [1, 0], [0, 1], [2, 3], alpha=[0.5, 0.25, 1.0, 0.5])


def test_a_multisample_reference_passes_every_check_sample_by_sample():
    # (pineda_msaa4 equals this oracle on every still case: tests/rasterizers/test_antialiased.py)
    lattice = [c for c in STATIC if c.family in ("lattice", "watertight", "degenerate")][::4]
    motion = next(c for c in QUICK if not isinstance(c, Case))
    results = run_suite([OracleMSAA()], cases=lattice + [motion], isolate=False, repros=False, identify=False)
    failed = [r for r in results if r.status not in ("pass", "skip")]
    assert results and not failed, failed[:3]
    judged = {r.check for r in results if r.status == "pass"}
    assert {"hygiene", "conformance", "watertight", "invariance", "degenerate", "jaggy"} <= judged
    conformance = next(r for r in results if r.check == "conformance" and r.status == "pass")
    assert conformance.message.startswith("each of 4 samples")


def test_a_missing_sample_fails_conformance_on_that_sample_with_its_picture():
    case = next(c for c in STATIC if c.family == "lattice")
    results = run_suite([DropsOneSample()], cases=[case], isolate=False, repros=False, identify=False, only={"conformance"})
    (failed,) = results
    assert failed.status == "fail" and failed.metrics["failing_samples"] == 1
    assert failed.evidence["sample"] == 2 and failed.evidence["offset"] == list(pattern(4)[2])
    assert failed.message.startswith("sample 2 (0.125, 0.625):") and failed.metrics["missing"] > 0
    assert failed.drawing is not None and failed.drawing.convention == Convention(samples=4).at_sample(2)


def test_hygiene_names_sample_indices_outside_the_pattern_and_missing_alphas():
    case = STATIC[0]

    class NoSampleIds(OracleMSAA):
        name = "no_sample_ids"

        def rasterize(self, scene: Scene) -> Coverage:
            c = exact_coverage(scene, self.convention)
            assert c.sample is not None
            return Coverage(c.triangle, c.y, c.x0, c.x1, sample=np.where(c.sample == 3, 5, c.sample))

    class NoAlpha(OracleArea):
        name = "no_alpha"

        def rasterize(self, scene: Scene) -> Coverage:
            c = exact_coverage(scene, self.convention)
            return Coverage(c.triangle, c.y, c.x0, c.x1)

    (beyond,) = run_suite([NoSampleIds()], cases=[case], isolate=False, repros=False, identify=False, only={"hygiene"})
    assert beyond.status == "fail" and beyond.metrics["bad_sample"] > 0
    assert "no alphas" in hygiene(case, NoAlpha().rasterize(triangles(case.scene)), convention=NoAlpha.convention).message
    # run, the declaration it contradicts is refused once (harness.contract.declarations), not judged per case
    (alphaless,) = run_suite([NoAlpha()], cases=[case], isolate=False, repros=False, identify=False, only={"hygiene"})
    assert alphaless.status == "error" and "carries no alphas" in alphaless.message
    assert alphaless.evidence["refused"] == "triangles"


def test_area_rasterizers_get_only_the_checks_that_judge_area_coverage():
    for case in STATIC[:5]:
        names = {c.name for c in checks(case, coverage_kind="area")}
        assert not names & {"conformance", "watertight", "closed"}
        assert {"hygiene"} <= names
    results = run_suite([OracleArea()], cases=STATIC, isolate=False, repros=False, identify=False,
                        only={"hygiene", "degenerate", "invariance"})
    failed = [r for r in results if r.status not in ("pass", "skip")]
    assert results and not failed, failed[:3]


def test_area_invariance_fails_when_alphas_depend_on_the_vertex_order():
    case = next(c for c in STATIC if c.family == "float")

    class OrderDependent(OracleArea):
        name = "order_dependent"

        def rasterize(self, scene: Scene) -> Coverage:
            c = exact_coverage(scene, self.convention)
            first_x = scene.positions[c.pixels()[0], 0, 0]
            bias = np.where(first_x == scene.positions[c.pixels()[0]].min(axis=1)[:, 0], 0.0, 3 / 255)
            return Coverage(c.triangle, c.y, c.x0, c.x1, alpha=np.clip(c.alpha + bias, 0, 1))

    (changed,) = run_suite([OrderDependent()], cases=[case], isolate=False, repros=False, identify=False, only={"invariance"})
    assert changed.status == "fail" and changed.metrics["rotate-vertices_differences"] > 0


@pytest.mark.parametrize("bad", [dict(samples=[(k / 64, 0.0) for k in range(33)]), dict(coverage="areal"), dict(levels=1),
                                 dict(tolerance=2.0)])
def test_conventions_refuse_what_they_cannot_mean(bad):
    with pytest.raises(ValueError):
        Convention(**bad)
