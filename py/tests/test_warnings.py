"""What the numbers cannot promise arrives as Python warnings."""

import warnings

import pytest

import sceneinfo


def test_a_line_job_warns_of_approximate_stationarity():
    with pytest.warns(sceneinfo.SceneinfoWarning, match="stationary only within"):
        m = sceneinfo.measure(sceneinfo.Scene.preset("cube", grid=2), lines=70_000)
    assert any("stationary" in w for w in m.warnings)


def test_unsampled_patches_warn_and_leave_the_measures_undefined():
    scene = sceneinfo.Scene.preset("cube", grid=20)  # 2,400 patches, 100 lines
    with pytest.warns(sceneinfo.SceneinfoWarning, match="received none of the 100 lines"):
        m = sceneinfo.measure(scene, lines=100, threads=1)
    assert m.i_s is None and m.form_factors() is None and m.unsampled_patches > 0
    assert m.i_s_continuous is not None


def test_exact_measures_of_a_closed_scene_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sceneinfo.measure(sceneinfo.Scene.preset("cube", grid=2))


def test_loader_warnings_are_issued(tmp_path):
    p = tmp_path / "t.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 3\n")
    with pytest.warns(sceneinfo.SceneinfoWarning, match="duplicate face"):
        s = sceneinfo.Scene.load(p)
    assert s.load_warnings == ["line 5: dropped a duplicate face (of line 4)"]
