"""Which rasterizers draw alike (harness.diagnose.alike): pixel-identical ones are grouped,
one that differs by a tie rule is not, and coverage kinds are never mixed."""

import numpy as np
import pytest

from cases.suites import suite
from harness.contract.case import Case
from harness.contract.conventions import Convention
from harness.contract.scenes import Scene
from harness.diagnose.alike import FEWEST_SHARED, Pair, draw_all, groups, pairs, picture
from harness.oracle.area import area_coverage
from rasterizers.area_scanline import AreaScanline
from rasterizers.centre_scanline import CentreScanline
from rasterizers.floor_scanline import FloorScanline
from rasterizers.pineda_topleft import PinedaTopLeft
from rasterizers.supersample import Supersampler4
from tests.known_bad.library_modes import FakelibAliased, FakelibWrongTie


@pytest.fixture(scope="module")
def lattice_cases():
    return [c for c in suite("quick") if isinstance(c, Case) and c.id.startswith("lattice/")][:8]


@pytest.fixture(scope="module")
def drawn(lattice_cases):
    return {r.name: draw_all(r, lattice_cases, isolate=False)
            for r in (CentreScanline(), PinedaTopLeft(), FakelibAliased(), FloorScanline(), AreaScanline(), Supersampler4())}


def test_rasterizers_drawing_the_same_pixels_are_one_group(drawn, lattice_cases):
    assert len(lattice_cases) >= FEWEST_SHARED
    found = pairs(drawn.values())
    same = {frozenset((p.a, p.b)) for p in found if p.alike}
    assert frozenset(("centre_scanline", "fakelib_aliased")) in same
    assert frozenset(("centre_scanline", "pineda_topleft")) in same
    grouped = groups(found)["triangles"]
    assert ["centre_scanline", "fakelib_aliased", "pineda_topleft"] in grouped


def test_a_rasterizer_with_other_ties_is_in_no_group_of_theirs(drawn):
    found = pairs(drawn.values())
    floor = [p for p in found if "floor_scanline" in (p.a, p.b) and p.kind == "triangles"]
    assert floor and all(not p.alike and p.differing > 0 for p in floor)
    assert all("floor_scanline" not in g for g in groups(found).get("triangles", []))


def test_area_rasterizers_are_compared_with_area_ones_only(drawn):
    found = pairs(drawn.values())
    area = {frozenset((p.a, p.b)) for p in found if "area_scanline" in (p.a, p.b)}
    assert area == {frozenset(("area_scanline", "supersample4"))}
    pair = next(p for p in found if {p.a, p.b} == {"area_scanline", "supersample4"})
    assert pair.differing > 0  # a 4-sample supersampler's alphas are quarters, not areas


def test_a_wrong_tie_claim_draws_alike_all_the_same(drawn, lattice_cases):
    # what it claims does not matter: the pixels do
    other = draw_all(FakelibWrongTie(), lattice_cases, isolate=False)
    found = pairs([drawn["fakelib_aliased"], other])
    assert [p.alike for p in found] == [True]


def test_too_few_shared_scenes_are_never_called_alike():
    assert not Pair("paths", "a", "b", FEWEST_SHARED - 1, 0, 10).alike
    assert Pair("paths", "a", "b", FEWEST_SHARED, 0, 10).alike


def test_an_area_picture_is_the_alphas_in_8_bit_steps():
    scene = Scene(8, 8, [[[1.0, 1.0], [6.5, 1.0], [1.0, 6.5]]])
    exact = area_coverage(scene, Convention(coverage="area"))
    _, x, y = exact.pixels()
    expected = np.zeros((8, 8), dtype=np.int64)
    assert exact.alpha is not None
    expected[y, x] = np.rint(255 * exact.alpha)
    image = picture(AreaScanline().rasterize(scene), scene, "area")
    assert image.dtype == np.int64 and np.array_equal(image, expected)
    assert 0 < image.max() <= 255 and len(np.unique(image)) > 2  # steps between 0 and 255, not a mask
