"""harness.geometry.keys gives numpy's own answers (np.unique, np.union1d, np.lexsort), by sorting."""

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from harness.geometry import keys

# small ranges (repeats, keys in order) and the whole int64 range (a composite key overflows)
ints = st.one_of(st.integers(-3, 3), st.integers(-(2**63), 2**63 - 1))
key_arrays = st.integers(0, 40).flatmap(lambda n: st.tuples(*[arrays(np.int64, n, elements=ints)] * 3))


@given(key_arrays)
def test_the_same_answers_as_numpy(three):
    a, b, c = three
    assert np.array_equal(keys.unique(a), np.unique(a))
    for mine, theirs in zip(keys.unique_counts(a), np.unique(a, return_counts=True), strict=True):
        assert np.array_equal(mine, theirs)
    distinct, inverse = keys.unique_inverse(a)
    assert np.array_equal(distinct, np.unique(a)) and np.array_equal(distinct[inverse], a)
    assert np.array_equal(keys.union(a, b), np.union1d(a, b))
    for chosen in ((a,), (a, b), (a, b, c), (np.sort(a), np.sort(b))):
        assert np.array_equal(keys.lexsort(chosen), np.lexsort(chosen))
