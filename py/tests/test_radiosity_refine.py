"""radiosity (the façade's solve_radiosity) and refine (flatland, §6.5.2) from Python."""

import json
import subprocess

import numpy as np
import pytest

import sceneinfo


def test_radiosity_equals_the_cli_bit_for_bit(cli, tmp_path):
    scene = tmp_path / "cornell.obj"
    subprocess.run([cli, "scene", "solid", "cornell", "--grid", "3", "-o", str(scene)], check=True)
    out = subprocess.run(
        [cli, "radiosity", str(scene), "--lines", "140000", "--seed", "3", "--threads", "2", "--json"],
        check=True, capture_output=True, text=True,
    ).stdout
    j = json.loads(out)
    lit = sceneinfo.radiosity(scene, lines=140_000, seed=3, threads=2)
    assert list(lit.i_s) == j["i_s_rgb"]
    assert list(lit.h_s) == j["h_s_rgb"]
    assert list(lit.h_p) == j["h_p_rgb"]
    assert list(lit.i_s_continuous) == j["i_s_continuous_rgb"]
    assert lit.visibility_i_s_continuous == j["i_s_continuous"]
    assert lit.iterations == [int(k) for k in j["iterations_rgb"]]
    b = lit.radiosity
    assert b.shape == (lit.visibility.n_states, 3)
    for c, name in enumerate(["red", "green", "blue"]):
        assert list(b[:, c]) == j["radiosity"][name]
    assert lit.visibility.i_s == j["i_s"]


def test_exact_radiosity_of_an_emitting_square():
    # A closed square of 4 grey walls (ρ = 0.5), one emitting E = 1: B solves B = E + ρFB (2.6)
    seg = [[0, 0, 1, 0], [1, 0, 1, 1], [1, 1, 0, 1], [0, 1, 0, 0]]
    s = sceneinfo.Scene.from_segments(seg, reflectance=[0.5] * 4, emittance=[1, 0, 0, 0])
    lit = sceneinfo.radiosity(s)
    f = lit.visibility.form_factors(sparse=False)
    b = lit.radiosity[:, 0]
    e = np.array([1.0, 0, 0, 0])
    # The residual of (2.6) at the solver's tolerance (1e-10 relative to max E)
    np.testing.assert_allclose(b, e + 0.5 * f @ b, atol=1e-9)
    assert lit.lines == 0 and lit.i_s_continuous is None


def test_radiosity_with_unsampled_patches_is_refused():
    s = sceneinfo.Scene.preset("cornell", grid=12)
    with pytest.raises(sceneinfo.SceneinfoError) as info:
        sceneinfo.radiosity(s, lines=200, threads=1)
    assert info.value.kind == "RowsUnknown"


def test_refine_grows_the_mesh_and_reports():
    s = sceneinfo.Scene.catalogue("l-room-1", 1)
    r = sceneinfo.refine(s, patches=s.n_patches + 5, lines=200_000, seed=2)
    rep = r.report()
    assert rep["n_patches"] == s.n_patches + 5 == r.scene.n_patches
    assert rep["step"] == 5
    n = rep["n_patches"]
    assert r.patch_information.shape == r.patch_continuous.shape == r.patch_errors.shape == (n,)
    np.testing.assert_allclose(r.patch_errors, r.patch_continuous - r.patch_information, atol=1e-15)
    one = r.step()
    assert one["n_patches"] == n + 1 and one["split"] is not None


def test_refine_refuses_3d():
    with pytest.raises(sceneinfo.SceneinfoError):
        sceneinfo.Refiner(sceneinfo.Scene.preset("cube", 2))


def test_refine_hierarchy_of_the_cornell_box():
    """3D refinement (§6.4): more leaves than patches, light conserved in the leaves'
    radiosity (positive, finite), the leaf areas summing to the scene's, and the same
    bits for the same seed."""
    box = sceneinfo.Scene.preset("cornell", 1)
    h = sceneinfo.refine_hierarchy(box, oracle="mi", leaves=200, seed=3)
    assert h.n_leaves > box.n_patches and h.rays > 0 and h.n_links > 0
    b = h.leaf_radiosity
    assert b.shape == (h.n_leaves, 3) and np.all(np.isfinite(b)) and np.all(b >= 0)
    assert b.max() > 0
    polygons = h.leaf_polygons()
    assert len(polygons) == h.n_leaves and all(p.shape[1] == 3 for p in polygons)
    assert len(h.leaf_patches) == h.n_leaves
    again = sceneinfo.refine_hierarchy(box, oracle="mi", epsilon=h.epsilon, seed=3)
    np.testing.assert_array_equal(again.leaf_radiosity, b)


def test_refine_hierarchy_refuses_flatland_and_bad_arguments():
    flat = sceneinfo.Scene.from_text("poly 4 0 0 1 0 1 1 0 1 per_side 2\n")
    with pytest.raises(sceneinfo.SceneinfoError):
        sceneinfo.refine_hierarchy(flat, epsilon=0.1)
    box = sceneinfo.Scene.preset("cornell", 1)
    with pytest.raises(sceneinfo.SceneinfoError):
        sceneinfo.refine_hierarchy(box)  # neither epsilon nor leaves
    with pytest.raises(sceneinfo.SceneinfoError):
        sceneinfo.refine_hierarchy(box, oracle="nope", epsilon=0.1)
