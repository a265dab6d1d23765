"""Bad input gives a SceneinfoError with the file, the line and the kind; never a crash."""

import numpy as np
import pytest

import sceneinfo


def test_bad_number_names_file_and_line(tmp_path):
    p = tmp_path / "bad.flat"
    p.write_text("# comment\nseg 0 0 1 0 1\nseg 1 0 1 x 1\n")
    with pytest.raises(sceneinfo.SceneinfoError) as info:
        sceneinfo.Scene.load(p)
    e = info.value
    assert e.file == str(p)
    assert e.line == 3
    assert e.kind == "BadNumber"
    assert str(e).startswith(f"{p}:3: ")
    assert isinstance(e, ValueError)


def test_measure_of_a_bad_path_reports_the_line(tmp_path):
    p = tmp_path / "bad.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(sceneinfo.SceneinfoError) as info:
        sceneinfo.measure(str(p))
    assert info.value.line == 4 and info.value.file == str(p)
    assert info.value.kind == "FaceIndex"


def test_array_errors_carry_the_row():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)
    with pytest.raises(sceneinfo.SceneinfoError) as info:
        sceneinfo.Scene.from_triangles(v, np.array([[0, 1, 2], [0, 1, 7]]))
    assert info.value.line == 2 and info.value.kind == "VertexIndex" and info.value.file is None
    # A degenerate segment in row 2
    with pytest.raises(sceneinfo.SceneinfoError) as info:
        sceneinfo.Scene.from_segments([[0, 0, 1, 0], [1, 1, 1, 1]])
    assert info.value.line == 2
    # A reflectance of 1.5 in row 1
    with pytest.raises(sceneinfo.SceneinfoError) as info:
        sceneinfo.Scene.from_segments([[0, 0, 1, 0]], reflectance=[1.5])
    assert info.value.line == 1


@pytest.mark.parametrize(
    "call",
    [
        lambda: sceneinfo.Scene.from_segments(np.zeros((3, 3))),
        lambda: sceneinfo.Scene.from_triangles(np.zeros((3, 2)), [[0, 1, 2]]),
        lambda: sceneinfo.Scene.from_triangles(np.eye(3), [[0, 1, -1]]),
        lambda: sceneinfo.Scene.from_segments([[0, 0, 1, 0]], reflectance=[0.1, 0.2]),
        lambda: sceneinfo.Scene.from_segments([[0, 0, np.nan, 0]]),
        lambda: sceneinfo.Scene.from_text("nonsense\n"),
        lambda: sceneinfo.Scene.from_text("", "ply"),
        lambda: sceneinfo.measure(sceneinfo.Scene.preset("cube", 2), lines=10, method="magic"),
        lambda: sceneinfo.measure(sceneinfo.Scene.preset("cube", 2), lines=-5),
        lambda: sceneinfo.measure(sceneinfo.Scene.preset("cube", 2), lines=0),
        lambda: sceneinfo.measure(sceneinfo.Scene.preset("cube", 2), lines=10, threads=0),
        lambda: sceneinfo.Scene.preset("no-such-scene"),
        lambda: sceneinfo.channel([0.5, 0.5], [[0.5, 0.6], [0.5, 0.5]]),
        lambda: sceneinfo.channel([0.5, 0.4], [[0.5, 0.5], [0.5, 0.5]]),
        lambda: sceneinfo.channel([0.5, 0.5], [[0.5, 0.5]]),
        lambda: sceneinfo.Partial.from_bytes(b"not a partial file"),
    ],
)
def test_bad_input_raises_a_sceneinfo_error(call):
    with pytest.raises(sceneinfo.SceneinfoError) as info:
        call()
    assert info.value.kind and info.value.message


def test_occluded_3d_exact_refuses_a_tolerance_out_of_range_with_its_kind():
    # Exact form factors of an occluded scene are computed with occlusion (the CLI's
    # measure --tol; test_exact_occluded.py), to a tolerance from 1e-10 to 1
    s = sceneinfo.Scene.preset("cornell", 2)
    for tol in (0.0, 1e-11, 2.0, float("nan")):
        with pytest.raises(sceneinfo.SceneinfoError) as info:
            sceneinfo.measure(s, tol=tol)
        assert info.value.kind == "BadParameter"


def test_missing_file_is_an_os_error(tmp_path):
    with pytest.raises(OSError):
        sceneinfo.Scene.load(tmp_path / "none.flat")
