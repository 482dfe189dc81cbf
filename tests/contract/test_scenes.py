import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from harness import Convention, Coverage, Rasterizer, Scene
from harness.contract.scenes import _pixel_bounds


def test_public_imports():
    from harness.oracle.coverage import exact_coverage  # noqa: F401

    assert Rasterizer is not None and Convention is not None


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(width=0, height=4, positions=np.zeros((1, 3, 2))), "width"),
        (dict(width=4, height=2.5, positions=np.zeros((1, 3, 2))), "height"),
        (dict(width=4, height=4, positions=np.zeros((1, 2, 2))), "positions"),
        (dict(width=4, height=4, positions=np.array([[["a", "b"]] * 3])), "positions"),
        (dict(width=4, height=4, positions=np.zeros((1, 3, 2)), attributes=np.zeros((2, 3, 1))), "attributes"),
        (dict(width=4, height=4, positions=np.zeros((1, 3, 2)), w=np.zeros((1, 2))), "w"),
        (dict(width=4, height=4, positions=np.zeros((1, 3, 2)), w=np.array([[1.0, -1.0, 1.0]])), "w"),
    ],
)
def test_scene_validation_names_the_field(kwargs, field):
    with pytest.raises(ValueError, match=f"Scene.{field}"):
        Scene(**kwargs)


def test_scene_allows_non_finite_and_is_read_only():
    scene = Scene(4, 4, [[[np.nan, 0.0], [np.inf, 1.0], [0.0, 2.0]]])
    assert not scene.positions.flags.writeable
    assert np.isnan(scene.positions[0, 0, 0])


def test_coverage_validation():
    with pytest.raises(ValueError, match="equal lengths"):
        Coverage([0], [0, 1], [0], [1])
    with pytest.raises(ValueError, match="Coverage.x0 must hold integers"):
        Coverage([0], [0], [0.5], [1])
    with pytest.raises(ValueError, match="Coverage.attributes"):
        Coverage([0], [0], [0], [1], np.zeros(3))


pixel_lists = st.lists(st.tuples(st.integers(0, 3), st.integers(0, 9), st.integers(0, 7)), max_size=60)


@given(pixel_lists)
def test_from_pixels_round_trip_and_counts(pixels):
    arr = np.array(pixels, dtype=np.int64).reshape(-1, 3)
    cov = Coverage.from_pixels(arr[:, 0], arr[:, 1], arr[:, 2], attributes=arr[:, :1].astype(float))
    tri, x, y = cov.pixels()
    assert sorted(zip(tri.tolist(), x.tolist(), y.tolist())) == sorted(map(tuple, arr.tolist()))
    # attributes follow their pixels
    assert cov.attributes is not None
    assert np.array_equal(cov.attributes[:, 0], tri)
    expected = np.zeros((8, 10), dtype=np.int32)
    np.add.at(expected, (arr[:, 2], arr[:, 1]), 1)
    assert np.array_equal(cov.counts(10, 8), expected)
    assert cov == Coverage.from_pixels(arr[::-1, 0], arr[::-1, 1], arr[::-1, 2], attributes=arr[::-1, :1].astype(float))


@given(pixel_lists)
def test_canonical_merges_and_keeps_duplicates(pixels):
    arr = np.array(pixels, dtype=np.int64).reshape(-1, 3)
    # one span per pixel, shuffled: canonical form merges touching spans only
    cov = Coverage(arr[:, 0], arr[:, 2], arr[:, 1], arr[:, 1] + 1)
    canon = cov.canonical()
    assert canon.n_pixels == len(pixels)
    assert cov == canon
    assert np.array_equal(canon.counts(10, 8), cov.counts(10, 8))
    # a canonical coverage is its own canonical form; no other is
    assert canon.canonical() is canon
    spans = np.stack([canon.primitive, canon.y, canon.x0, canon.x1])
    assert (cov.canonical() is cov) == (spans.shape == (4, len(cov)) and np.array_equal(
        spans, np.stack([cov.primitive, cov.y, cov.x0, cov.x1])))


def test_from_mask_and_counts_clip():
    mask = np.array([[0, 1, 1, 0], [1, 1, 1, 1]], dtype=bool)
    cov = Coverage.from_mask(5, mask)
    assert cov.triangle.tolist() == [5, 5] and cov.x0.tolist() == [1, 0] and cov.x1.tolist() == [3, 4]
    assert np.array_equal(cov.counts(4, 2), mask.astype(np.int32))
    outside = Coverage([0, 0], [-1, 0], [-5, 2], [2, 9])
    assert outside.counts(4, 2).tolist() == [[0, 0, 1, 1], [0, 0, 0, 0]]


def test_equality_distinguishes():
    a = Coverage([0], [1], [2], [5])
    assert a == Coverage([0, 0], [1, 1], [3, 2], [5, 3])
    assert a != Coverage([0], [1], [2], [6])
    assert a != Coverage([1], [1], [2], [5])
    assert Coverage([0], [0], [0], [1], np.zeros((1, 1))) != Coverage([0], [0], [0], [1], np.ones((1, 1)))


def test_integers_past_2_53_are_refused_not_rounded():
    with pytest.raises(ValueError, match="beyond 2\\*\\*53"):
        Scene(8, 8, np.array([[[2**53 + 1, 0], [4, 0], [0, 4]]], dtype=np.int64))
    assert Scene(8, 8, np.array([[[2**53, 0], [4, 0], [0, 4]]], dtype=np.int64)).positions[0, 0, 0] == 2.0**53


span_lists = st.lists(st.tuples(st.integers(-2, 3), st.integers(-3, 12), st.integers(-5, 14), st.integers(-5, 14)), max_size=40)


@given(span_lists, st.lists(st.floats(-3, 13, allow_nan=False), min_size=6, max_size=6))
@example([(0, 0, 1, 2), (0, 0, 0, 2)], [0.0] * 6)  # a later span starting further left: pixel 1 is the first span's
@example([(0, 4, 0, 9), (0, 4, 3, 5), (0, 4, 4, 12), (0, 4, 2, 3)], [0.0, 0.0, 9.0, 0.0, 0.0, 9.0])
def test_tidy_keeps_exactly_the_first_emission_of_each_pixel_within_reach(spans, corners):
    """Against a pixel-by-pixel reference: a pixel is kept once per triangle when its
    triangle id is valid and it lies in the viewport and in the triangle's grown box."""
    scene = Scene(10, 9, [np.array(corners).reshape(3, 2), np.array([[1, 1], [2, 1], [1, 2]])])
    arr = np.array(spans, dtype=np.int64).reshape(-1, 4)
    cov = Coverage(arr[:, 0], arr[:, 1], arr[:, 2], arr[:, 3],
                   np.arange(max(int(np.maximum(arr[:, 3] - arr[:, 2], 0).sum()), 0))[:, None].astype(float))
    usable, flaws = cov.tidy(scene)
    box = [(np.floor(scene.positions[t].min(axis=0)) - 2, np.ceil(scene.positions[t].max(axis=0)) + 2) for t in range(2)]
    want: dict = {}
    row = 0
    for t, y, x0, x1 in arr.tolist():
        for x in range(x0, x1):
            reach = 0 <= t < 2 and box[t][0][0] <= x <= box[t][1][0] and box[t][0][1] <= y <= box[t][1][1]
            if reach and 0 <= x < 10 and 0 <= y < 9:
                want.setdefault((t, x, y), float(row))
            row += 1
    kept, columns, rows = usable.pixels()
    assert usable.attributes is not None
    got = dict(zip(zip(kept.tolist(), columns.tolist(), rows.tolist()), usable.attributes[:, 0].tolist()))
    assert got == want and len(kept) == len(want)  # each pixel once, with its first attribute row
    clean = not any(v.size for k, v in flaws.items() if k != "repeated_pixels")
    assert (usable is cov) == clean


@given(st.lists(st.tuples(st.integers(-1, 2), st.integers(-3, 12), st.integers(-5, 14), st.integers(1, 6)), max_size=12),
       st.lists(st.floats(-3, 13, allow_nan=False), min_size=6, max_size=6), st.booleans())
@example([(0, 2, 1, 3), (0, 3, 0, 2), (1, 1, 1, 2)], [0.0, 0.0, 9.0, 0.0, 0.0, 9.0], True)
def test_the_quick_tidiness_test_never_passes_what_tidying_would_change(spans, corners, ordered):
    """Coverage.tidy returns a clean answer as it is after one pass (spans.already_tidy);
    whenever that pass says clean, the full tidying keeps every span whole, flags nothing."""
    from harness.geometry.spans import already_tidy, tidy

    scene = Scene(10, 9, [np.array(corners).reshape(3, 2), np.array([[1, 1], [2, 1], [np.inf, 2]])])
    rows = sorted(spans) if ordered else spans
    t, y, x0, length = (np.array(column, dtype=np.int64) for column in zip(*rows)) if rows else [np.zeros(0, np.int64)] * 4
    x1 = x0 + length
    if already_tidy(_pixel_bounds(scene), t, y, x0, x1):
        keep, start, end, flaws, again = tidy(t, y, x0, x1, 2, _pixel_bounds(scene))
        assert keep.tolist() == list(range(t.size)) and start.tolist() == x0.tolist() and end.tolist() == x1.tolist()
        assert again == 0 and not any(v.size for v in flaws.values())
        assert Coverage(t, y, x0, x1).tidy(scene)[1]["outside_viewport"].size == 0
        assert ((x0 >= 0) & (x1 <= 10) & (y >= 0) & (y < 9)).all()
