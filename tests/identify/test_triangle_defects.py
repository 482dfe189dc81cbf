"""identify's robustness probes (:mod:`harness.identify.triangle_defects`): the viewport edge,
tiny triangles and non-finite input, each shown to fire on a known-bad rasterizer and to stay
quiet on correct ones."""

from harness.contract.conventions import Convention
from harness.engine.isolation import InProcess
from harness.engine.registry import load
from harness.identify.fingerprint import identify
from harness.identify.triangle_defects import epsilon, non_finite, viewport_edge
from tests.identify.test_triangle_probes import _inclusive
from tests.known_bad.edge_functions import EdgeFunctionBug
from tests.known_bad.misc import ClipsBeforeSnapping


def test_viewport_edge_fact_tells_a_clipper_from_an_exact_rasterizer():
    # the probe behind identify's fact (identify(...).facts["viewport edge"] is its text)
    assert viewport_edge(InProcess(load("centre_scanline")), 0).text.startswith("exact")
    fingerprint = identify(ClipsBeforeSnapping())
    assert "change when triangles cross it" in fingerprint.facts["viewport edge"], fingerprint.card()
    # each scene that changes is the suite's own lattice case, failing conformance there with a repro
    moved = fingerprint.defects["viewport edge"]
    assert moved and {d.case for d in moved} <= {"lattice/bits-0", "lattice/bits-2", "lattice/bits-4"}
    assert all(d.check == "conformance" and d.evidence["pixels"] for d in moved) and moved[0].repro is not None
    assert "lattice/bits-0' fails conformance" in fingerprint.card()
    # away from the edge it is exactly its convention
    assert fingerprint.convention == Convention(subpixel_bits=8) and fingerprint.exact, fingerprint.card()


def test_epsilon_fact_catches_single_precision():
    assert epsilon(InProcess(load("pineda_topleft")), Convention()).text.startswith("exact")
    assert "decided unlike the convention" in epsilon(InProcess(EdgeFunctionBug("float32")), Convention()).text


def test_non_finite_and_residual_facts_name_what_a_broken_rasterizer_does():
    # the non-finite fact is the text of its probe (identify's facts["non-finite"]); the
    # residual lies need the whole fit
    drawn = non_finite(InProcess(EdgeFunctionBug("nan-to-num"))).text
    assert "NaN: DRAWS" in drawn and "inf: DRAWS" in drawn
    assert "DRAWS" not in non_finite(InProcess(load("floor_scanline"))).text
    inclusive = _inclusive().facts["residual lies"]
    # inclusive edges, named the closed rule, disagree with it only exactly on edges: nothing off them
    on_edges = [int(part.split()[0]) for part in inclusive.split(", ")[:3]]
    assert inclusive.endswith("0 off every edge (lattice scenes)") and sum(on_edges) > 0, inclusive
