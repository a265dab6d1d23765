"""Form factors dense and sparse: the same matrix."""

import numpy as np
import pytest

import sceneinfo

scipy_sparse = pytest.importorskip("scipy.sparse")


def test_sparse_and_dense_form_factors_are_equal():
    s = sceneinfo.Scene.preset("cube", grid=3)
    m = sceneinfo.measure(s, lines=150_000, seed=7, threads=2)
    dense = m.form_factors(sparse=False)
    sparse = m.form_factors(sparse=True)
    assert isinstance(dense, np.ndarray)
    assert scipy_sparse.issparse(sparse) and sparse.format == "csr"
    assert sparse.shape == dense.shape == (m.n_states, m.n_states)
    np.testing.assert_array_equal(sparse.toarray(), dense)
    data, indices, indptr = m.form_factors_csr()
    np.testing.assert_array_equal(data, sparse.data)
    np.testing.assert_array_equal(indptr, sparse.indptr)


def test_exact_form_factors_dense_and_sparse_are_equal():
    s = sceneinfo.Scene.preset("cube", grid=2)
    m = sceneinfo.measure(s)
    np.testing.assert_array_equal(m.form_factors(sparse=True).toarray(), m.form_factors(sparse=False))


def test_default_is_sparse_above_the_size_only():
    small = sceneinfo.measure(sceneinfo.Scene.preset("cube", grid=2))
    assert isinstance(small.form_factors(), np.ndarray)
    big = sceneinfo.measure(sceneinfo.Scene.preset("cube", grid=13), lines=70_000, threads=2)
    # 6 · 13² = 1,014 patches > SPARSE_ABOVE, unless some patch got no line (None)
    f = big.form_factors()
    assert big.n_patches > sceneinfo.SPARSE_ABOVE
    assert f is None or scipy_sparse.issparse(f)
