"""Exact 3D form factors with occlusion from Python: a tolerance, error estimates, sparse
access, rows split and merged, View3D's .vs3 input and output, and the CLI's bits."""

import subprocess

import numpy as np
import pytest

import sceneinfo
from conftest import ROOT

# View3D's .vs3 of a room with a two-sided plate and a hexagon (written by the View3D
# anchor's converter, not by sceneinfo)
ROOM_VS3 = ROOT / "tests" / "data" / "vs3" / "room_with_plate.vs3"
TOL = 1e-3


def entries(m):
    """(indptr, indices, data, errors) of a measurement's form factors."""
    data, indices, indptr = m.form_factors_csr()
    return indptr, indices, data, m.form_factor_errors()


def test_occluded_vs3_scene_has_estimates_within_the_tolerance():
    m = sceneinfo.measure(ROOM_VS3, tol=TOL, threads=2)
    e = m.exact_errors
    assert e is not None and e["pairs_integrated"] > 0 and e["pairs_over_tolerance"] == 0
    assert e["tolerance"] == TOL and 0 < e["max_error"] <= TOL
    indptr, indices, data, errors = entries(m)
    n = m.n_patches
    i_of = np.repeat(np.arange(len(indptr) - 1), np.diff(indptr))
    patch = (i_of < n) & (indices < n)
    # An estimate for every entry between patches, none for the background state's
    assert len(errors) == len(data) and np.array_equal(np.isnan(errors), ~patch)
    assert np.all(errors[patch] >= 0) and np.all(errors[patch] <= TOL)
    # Reciprocity a_i F_ij = a_j F_ji within the entries' estimates (2.8); rows within
    # their estimates of at most 1
    a = m.patch_sizes
    F = np.zeros((n, n))
    E = np.zeros((n, n))
    for i in range(n):
        for k in range(indptr[i], indptr[i + 1]):
            if indices[k] < n:
                F[i, indices[k]] = data[k]
                E[i, indices[k]] = errors[k]
    gap = np.abs(a[:, None] * F - (a[:, None] * F).T)
    assert np.all(gap <= a[:, None] * E + (a[:, None] * E).T + 1e-15)
    assert np.all(F.sum(1) <= 1 + 1e-12)
    # tol belongs to exact jobs
    with pytest.raises(sceneinfo.SceneinfoError):
        sceneinfo.measure(ROOM_VS3, lines=1000, tol=TOL)


def test_rows_in_ranges_merge_into_the_whole_job_bit_for_bit(tmp_path):
    whole = sceneinfo.exact_rows(ROOM_VS3, tol=TOL, threads=1)
    assert whole.is_complete and whole.rows == (0, whole.n_patches)
    n = whole.n_patches
    parts = [
        sceneinfo.exact_rows(ROOM_VS3, tol=TOL, rows=(4, n), threads=2),
        sceneinfo.exact_rows(ROOM_VS3, tol=TOL, rows=(0, 4), threads=3),
    ]
    parts[0].save(tmp_path / "b.sir")
    merged = sceneinfo.merge_rows([tmp_path / "b.sir", parts[1]])
    assert merged.to_bytes() == whole.to_bytes()
    a, b = merged.measurement(), sceneinfo.measure(ROOM_VS3, tol=TOL, threads=2)
    for x, y in zip(entries(a), entries(b)):
        assert np.array_equal(x, y, equal_nan=True)
    assert a.exact_errors == b.exact_errors
    with pytest.raises(sceneinfo.SceneinfoError) as e:
        sceneinfo.merge_rows([parts[1], sceneinfo.exact_rows(ROOM_VS3, tol=TOL, rows=(3, n))])
    assert e.value.kind == "RowRanges"
    with pytest.raises(sceneinfo.SceneinfoError) as e:
        parts[1].measurement()
    assert e.value.kind == "MissingRows"


def test_the_cli_writes_the_same_entries_and_view3d_file(cli, tmp_path):
    m = sceneinfo.measure(ROOM_VS3, tol=TOL)
    ijv, vf3 = tmp_path / "F.ijv", tmp_path / "F.vf3"
    for out in (ijv, vf3):
        subprocess.run(
            [cli, "formfactors", str(ROOM_VS3), "--tol", str(TOL), "--out", str(out)],
            check=True,
            capture_output=True,
        )
    rows = [line.split(",") for line in ijv.read_text().splitlines()[1:]]
    indptr, indices, data, errors = entries(m)
    i_of = np.repeat(np.arange(len(indptr) - 1), np.diff(indptr))
    assert [(int(r[0]), int(r[1])) for r in rows] == list(zip(i_of.tolist(), indices.tolist()))
    assert [float(r[2]) for r in rows] == data.tolist()
    assert [r[3] == "" for r in rows] == np.isnan(errors).tolist()
    assert [float(r[3]) for r in rows if r[3]] == errors[~np.isnan(errors)].tolist()
    v = sceneinfo.read_view3d(vf3)
    n = m.n_patches
    assert v["form_factors"].shape == (n, n) and not v["encl"] and not v["emit"]
    dense = m.form_factors(sparse=False)
    assert np.array_equal(v["form_factors"], dense[:n, :n])
    assert np.allclose(v["areas"] / v["areas"].sum(), m.patch_sizes, rtol=1e-12)


def test_view3d_surfaces_of_a_vs3_file_are_view3d_s():
    """A .vs3 file with a subsurface, a mask or an obstruction-only plate: its View3D output
    surfaces from a measurement of it, as the CLI's --out F.vf3 writes them, and View3D
    4.0.0's own output for the file (tests/data/vs3/README.md) within its six printed
    decimals and the tolerance."""
    kinds = ROOT / "tests" / "data" / "vs3" / "surface-kinds"
    for name, numbers in [
        ("window", [1, 2, 3, 4, 5, 6, 7]),
        ("mask", [1, 2, 3, 4, 5, 6, 7]),
        ("null", [1, 2, 3, 4, 5, 6]),
    ]:
        path = kinds / f"{name}.vs3"
        m = sceneinfo.measure(path, tol=1e-6, threads=1)
        v = sceneinfo.view3d_surfaces(path, m)
        assert v["numbers"] == numbers
        ref = sceneinfo.read_view3d(kinds / f"{name}.view3d.txt")
        assert np.allclose(v["areas"], ref["areas"], rtol=1e-12, atol=0)
        assert np.max(np.abs(v["form_factors"] - ref["form_factors"])) <= 1.5e-6
    # The obstruction-only plate has no row: 6 surfaces from 7 patches
    m = sceneinfo.measure(kinds / "obstruction.vs3", tol=1e-3, threads=1)
    v = sceneinfo.view3d_surfaces(kinds / "obstruction.vs3", m)
    assert m.n_patches == 7 and v["form_factors"].shape == (6, 6)
    # A measurement of another scene is refused
    with pytest.raises(sceneinfo.SceneinfoError):
        sceneinfo.view3d_surfaces(kinds / "null.vs3", m)


# Squares of side 0.01 at z = 0 (facing up) and z = 1 (facing down), a plate of side 1 at
# z = 0.5 between them: the squares' pair is hidden, and its unoccluded flux (F about
# A / (pi d^2) = 3.2e-5) fits the tolerance 1e-3, so it is decided as 0 +- U by the bound
HIDDEN_PAIR_OBJ = """v 0 0 0
v 0.01 0 0
v 0.01 0.01 0
v 0 0.01 0
v 0 0 1
v 0.01 0 1
v 0.01 0.01 1
v 0 0.01 1
v -0.5 -0.5 0.5
v 0.5 -0.5 0.5
v 0.5 0.5 0.5
v -0.5 0.5 0.5
f 1 2 3 4
f 5 8 7 6
f 9 12 11 10
"""


def test_zero_entries_keep_their_estimates(cli, tmp_path):
    """An entry 0 +- U is not a stored entry of the CSR, so form_factor_errors() cannot
    give it: zero_form_factor_errors() does, as the CLI's .ijv writes it."""
    path = tmp_path / "hidden.obj"
    path.write_text(HIDDEN_PAIR_OBJ)
    m = sceneinfo.measure(path, tol=1e-3, threads=1)
    rows, cols, errors = m.zero_form_factor_errors()
    assert rows.dtype == np.int64 and cols.dtype == np.int64 and errors.dtype == np.float64
    assert list(zip(rows.tolist(), cols.tolist())) == [(0, 1), (1, 0)]
    assert np.all((errors > 1e-5) & (errors <= 1e-3))
    dense = m.form_factors(sparse=False)
    assert dense[0, 1] == 0.0 and dense[1, 0] == 0.0
    ijv = tmp_path / "F.ijv"
    subprocess.run(
        [cli, "formfactors", str(path), "--tol", "1e-3", "--threads", "1", "--out", str(ijv)],
        check=True,
        capture_output=True,
    )
    zeros = [
        (int(r[0]), int(r[1]), float(r[3]))
        for r in (line.split(",") for line in ijv.read_text().splitlines()[1:])
        if float(r[2]) == 0.0
    ]
    assert zeros == list(zip(rows.tolist(), cols.tolist(), errors.tolist()))
    # Nothing for form factors without estimates (unoccluded)
    cube = sceneinfo.measure(sceneinfo.Scene.preset("cube", grid=2), tol=1e-3)
    assert all(len(a) == 0 for a in cube.zero_form_factor_errors())


def test_view3d_surfaces_honour_the_file_s_controls():
    """encl=1 and emit=1 on View3D's surfaces, as the CLI's .vf3 and View3D 4.0.0's output
    (tests/data/vs3/controls/) give them: within its printed decimals plus the tolerance
    scaled by the adjustment (2.6)."""
    controls = ROOT / "tests" / "data" / "vs3" / "controls"
    for name in ["black", "encl", "emit", "encl_emit"]:
        path = controls / f"{name}.vs3"
        m = sceneinfo.measure(path, tol=1e-6, threads=1)
        v = sceneinfo.view3d_surfaces(path, m)
        ref = sceneinfo.read_view3d(controls / f"{name}.view3d.txt")
        assert (v["encl"], v["emit"]) == (ref["encl"], ref["emit"])
        assert v["emissivities"].tolist() == [0.9, 0.8, 0.5, 0.3, 0.7]
        assert np.max(np.abs(v["form_factors"] - ref["form_factors"])) <= 5e-7 + 2.6e-6
