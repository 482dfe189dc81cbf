"""The sorts written out for kernels (harness.geometry.kernel_sorts) sort as numpy does."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from harness.geometry.kernel_sorts import heapsort, heapsort_pairs, stable_argsort

values = st.lists(st.integers(-5, 5) | st.integers(-(2**62), 2**62), max_size=80)


@settings(max_examples=150, deadline=None)
@given(values, st.data())
def test_heapsort_sorts_the_range_and_leaves_the_rest(keys, data):
    keys = np.array(keys, dtype=np.int64)
    lo = data.draw(st.integers(0, keys.size))
    hi = data.draw(st.integers(lo, keys.size))
    want = keys.copy()
    want[lo:hi] = np.sort(want[lo:hi])
    heapsort(keys, lo, hi)
    assert keys.tolist() == want.tolist()


@settings(max_examples=150, deadline=None)
@given(values)
def test_heapsort_pairs_moves_each_payload_with_its_key(keys):
    keys = np.array(keys, dtype=np.int64)
    payload = np.arange(keys.size, dtype=np.int64)
    original = keys.copy()
    heapsort_pairs(keys, payload, 0, keys.size)
    assert keys.tolist() == sorted(original.tolist())
    assert original[payload].tolist() == keys.tolist()
    assert sorted(payload.tolist()) == list(range(keys.size))


@settings(max_examples=150, deadline=None)
@given(values)
def test_stable_argsort_is_numpys_stable_argsort(keys):
    keys = np.array(keys, dtype=np.int64)
    order = np.full(keys.size, -1, dtype=np.int64)
    spare = np.empty(keys.size, dtype=np.int64)
    stable_argsort(keys, keys.size, order, spare)
    assert order.tolist() == np.argsort(keys, kind="stable").tolist()
