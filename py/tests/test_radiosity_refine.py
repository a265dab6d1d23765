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
