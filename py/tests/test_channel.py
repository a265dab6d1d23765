"""Channel measures of arbitrary numpy channels: properties (hypothesis) and sparse input."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import sceneinfo


@st.composite
def channels(draw):
    """A distribution w (positive) and a row-stochastic P with some zero entries."""
    n = draw(st.integers(1, 12))
    w = draw(arrays(np.float64, n, elements=st.floats(0.01, 1.0)))
    raw = draw(arrays(np.float64, (n, n), elements=st.floats(0.0, 1.0)))
    raw[np.arange(n), np.arange(n)] += 0.01  # no empty row
    return w / w.sum(), raw / raw.sum(axis=1, keepdims=True)


# Tolerance: the core sums in a different order than H_P + H_S does (compensated sums of
# up to 144 terms of at most log2(144) bits): 1e-12 relative is far above that rounding and
# far below any real violation.
@given(channels())
@settings(max_examples=200, deadline=None)
def test_mutual_information_is_non_negative_and_joint_entropy_adds_up(wp):
    w, p = wp
    c = sceneinfo.channel(w, p)
    # I_S = I(X;Y) + D(wP || w) >= 0 for row-stochastic P and any w (3.8)
    assert c.i_s >= -1e-12
    # H_J = H_P + H_S (3.7)
    assert c.h_j == pytest.approx(c.h_p + c.h_s, rel=1e-12, abs=1e-12)
    # I_i sums to I_S (6.9); w_i H_i to H_S (3.1)
    assert c.patch_information.sum() == pytest.approx(c.i_s, rel=1e-9, abs=1e-12)
    assert (w * c.patch_entropies).sum() == pytest.approx(c.h_s, rel=1e-9, abs=1e-12)


def test_sparse_and_dense_channels_agree():
    sparse = pytest.importorskip("scipy.sparse")
    rng = np.random.default_rng(5)
    n = 30
    p = rng.random((n, n)) * (rng.random((n, n)) < 0.3)
    p[np.arange(n), (np.arange(n) + 1) % n] += 0.5
    p /= p.sum(axis=1, keepdims=True)
    w = rng.random(n)
    w /= w.sum()
    a = sceneinfo.channel(w, p)
    b = sceneinfo.channel(w, sparse.csr_matrix(p))
    assert a.measures() == b.measures()
    np.testing.assert_array_equal(a.patch_information, b.patch_information)


def test_a_scene_channel_equals_its_measurement():
    m = sceneinfo.measure(sceneinfo.Scene.preset("cube", grid=2))
    c = sceneinfo.channel(m.patch_sizes, m.form_factors(sparse=False))
    assert c.i_s == pytest.approx(m.i_s, rel=1e-14)
    assert c.h_s == pytest.approx(m.h_s, rel=1e-14)
