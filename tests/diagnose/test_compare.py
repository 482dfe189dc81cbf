"""compare explains each rasterizer with identify's own fit (so the two never disagree on a
sample point or tie rule), and says what separates two explanations, even when they are
the same best guess."""

from harness.contract.conventions import Convention
from harness.diagnose.compare import Explanation, _separation, as_dict, compare
from harness.engine.registry import load
from harness.identify.fingerprint import identify
from tests.known_bad.edge_functions import EdgeFunctionBug


def test_compare_explains_each_rasterizer_as_identify_fits_it():
    # vertex-order ties: no candidate explains it exactly, and the fit compare used to make
    # on its own scenes (top-left) differed from identify's (bottom-left, y first)
    bad, good = EdgeFunctionBug("vertex-order-ties"), load("centre_scanline")
    explanations, comparisons = compare([bad, good])
    for explanation, rasterizer in zip(explanations, (bad, good)):
        fingerprint = identify(rasterizer)
        fitted = (fingerprint.convention.sample, fingerprint.convention.tie)
        assert (explanation.convention.sample, explanation.convention.tie) == fitted, fingerprint.card()
        assert explanation.runner_up is not None
        assert (explanation.runner_up[0].describe(), explanation.runner_up[1]) == fingerprint.runner_up
    assert not explanations[0].exact and explanations[0].mismatches > 0
    assert explanations[1].exact and explanations[1].convention == Convention()
    separation = comparisons[0].separation
    assert "explains bad_vertex-order-ties exactly" in separation, separation
    data = as_dict(explanations, comparisons)
    assert [e["exact"] for e in data["explanations"]] == [False, True]


def test_the_same_best_guess_is_never_said_to_differ():
    guess = Convention(tie="top-right")
    a, b = Explanation("a", guess, 749, 5000), Explanation("b", guess, 12, 5000)
    said = _separation(a, b)
    assert said == (f"no candidate convention explains either exactly; both are best explained by {guess.describe()}, "
                    "neither exactly")
    one = _separation(a, Explanation("b", guess, 0, 5000))
    assert "differ" not in one and f"both are best explained by {guess.describe()}, a with 749 mismatches" in one
    other = _separation(a, Explanation("b", Convention(), 3, 5000))
    assert f"best guesses differ: {guess.describe()} vs {Convention().describe()}" in other


def test_exact_explanations_that_differ_only_in_snapping_say_so():
    said = _separation(Explanation("a", Convention(), 0, 10), Explanation("b", Convention(subpixel_bits=4), 0, 10))
    assert said == "separated by snapping (none vs 4 bits nearest-even)"
