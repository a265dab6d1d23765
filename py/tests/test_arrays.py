"""Scenes from numpy arrays and back: the arrays a scene gives are those it was built from."""

import numpy as np
import pytest

import sceneinfo


def square_segments(per_side=3):
    """The unit square as `per_side` segments a side, counter-clockwise, facing inwards."""
    corners = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], dtype=float)
    rows = []
    for a, b in zip(corners[:-1], corners[1:]):
        for k in range(per_side):
            p = a + (b - a) * k / per_side
            q = a + (b - a) * (k + 1) / per_side
            rows.append([p[0], p[1], q[0], q[1]])
    return np.array(rows)


def cube_mesh():
    """A unit cube as 12 triangles facing inwards (a closed room)."""
    v = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    # Vertex k is (x, y, z) = bits of k (x = 4s, y = 2s, z = 1s); counter-clockwise seen
    # from inside the cube, so by the right-hand rule every face's front looks inwards
    quads = [
        [4, 6, 2, 0],
        [3, 7, 5, 1],
        [1, 5, 4, 0],
        [6, 7, 3, 2],
        [2, 3, 1, 0],
        [5, 7, 6, 4],
    ]
    return v, quads


def test_segments_round_trip_sizes_and_materials(tmp_path):
    seg = square_segments(3)
    rho = np.linspace(0.1, 0.8, len(seg))
    emit = np.zeros((len(seg), 3))
    emit[0] = [1.0, 2.0, 3.0]
    s = sceneinfo.Scene.from_segments(seg, reflectance=rho, emittance=emit)
    assert s.is_flat and s.n_patches == 12
    np.testing.assert_array_equal(s.reflectance, np.repeat(rho[:, None], 3, axis=1))
    np.testing.assert_array_equal(s.emittance, emit)
    # Equal segments: a_i = 1/12 each (3.3)
    np.testing.assert_allclose(s.patch_sizes, np.full(12, 1 / 12), rtol=1e-15)
    # Written as .flat and read back: the same scene, the same measures bit for bit
    path = tmp_path / "square.flat"
    s.save(path)
    back = sceneinfo.Scene.load(path)
    assert back.n_patches == 12
    np.testing.assert_array_equal(back.patch_sizes, s.patch_sizes)
    np.testing.assert_array_equal(back.reflectance, s.reflectance)
    a, b = sceneinfo.measure(s), sceneinfo.measure(back)
    assert a.measures() == b.measures()


def test_triangles_and_polygons_give_the_same_scene(tmp_path):
    v, quads = cube_mesh()
    tris = np.array([[q[0], q[1], q[2]] for q in quads] + [[q[0], q[2], q[3]] for q in quads])
    offsets = np.arange(0, 4 * len(quads) + 1, 4)
    flat_idx = np.array(quads).ravel()
    by_tri = sceneinfo.Scene.from_triangles(v, tris)
    by_poly = sceneinfo.Scene.from_polygons(v, flat_idx, offsets)
    assert by_tri.n_patches == 12 and by_poly.n_patches == 6
    assert by_tri.patch_sizes.sum() == pytest.approx(1.0, abs=1e-15)
    # Each quad is two triangles of half its area
    np.testing.assert_allclose(
        np.sort(by_tri.patch_sizes), np.full(12, 1 / 12), rtol=1e-14
    )
    np.testing.assert_allclose(by_poly.patch_sizes, np.full(6, 1 / 6), rtol=1e-14)
    # Fronts inwards: a closed room (facing outwards every row of F would be lost)
    m_tri, m_poly = sceneinfo.measure(by_tri), sceneinfo.measure(by_poly)
    assert m_tri.background is False and m_poly.background is False
    # Splitting every face into two triangles cannot decrease I_S (refinement, Prop. 3)
    assert m_tri.i_s >= m_poly.i_s
    # OBJ round trip of the array scene
    path = tmp_path / "cube.obj"
    by_poly.save(path)
    back = sceneinfo.Scene.load(path)
    np.testing.assert_array_equal(back.patch_sizes, by_poly.patch_sizes)


def test_per_patch_arrays_have_the_scene_shape():
    s = sceneinfo.Scene.from_segments(square_segments(4))
    m = sceneinfo.measure(s)
    n = s.n_patches
    for name in ("patch_sizes", "patch_information", "patch_entropies"):
        a = getattr(m, name)
        assert isinstance(a, np.ndarray) and a.dtype == np.float64 and a.shape == (n,), name
    # Σ_i I_i = I_S (6.9) and Σ_i a_i H_i = H_S (3.1), to rounding of the summation order
    assert m.patch_information.sum() == pytest.approx(m.i_s, rel=1e-12)
    assert (m.patch_sizes * m.patch_entropies).sum() == pytest.approx(m.h_s, rel=1e-12)
    f = m.form_factors(sparse=False)
    assert f.shape == (n, n)
    # Rows of a closed scene sum to one (2.3)
    np.testing.assert_allclose(f.sum(axis=1), 1.0, atol=1e-12)
    lines = sceneinfo.measure(s, lines=100_000, seed=3, threads=1)
    assert lines.patch_continuous.shape == (n,)
    assert lines.pair_continuous.shape == (n, n)
    assert lines.patch_continuous.sum() == pytest.approx(lines.i_s_continuous, rel=1e-9)


def test_lists_are_accepted_as_arrays():
    s = sceneinfo.Scene.from_segments([[0, 0, 1, 0], [1, 0, 1, 1], [1, 1, 0, 1], [0, 1, 0, 0]])
    assert s.n_patches == 4


def test_obj_materials_and_emit_from_ka(tmp_path):
    (tmp_path / "m.mtl").write_text("newmtl lamp\nKd 0.25 0.5 0.75\nKa 2 3 4\n")
    (tmp_path / "t.obj").write_text(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n"
    )
    plain = sceneinfo.Scene.load(tmp_path / "t.obj")
    lit = sceneinfo.Scene.load(tmp_path / "t.obj", emit_from_ka=True)
    np.testing.assert_array_equal(plain.reflectance, [[0.25, 0.5, 0.75]])
    np.testing.assert_array_equal(plain.emittance, [[0.0, 0.0, 0.0]])
    np.testing.assert_array_equal(lit.emittance, [[2.0, 3.0, 4.0]])
