"""The same numbers as the CLI, bit for bit: measure --json, threads, partial files, merge."""

import json
import subprocess

import numpy as np

import sceneinfo

LINES = 3 * 65_536 + 1_000  # four chunks, the last one short
SEED = 11
KEYS = [
    "h_p", "h_s", "h_j", "i_s", "h_s_norm", "i_s_norm", "e_mse", "fano",
    "h_s_joint_norm", "i_s_joint_norm", "n_states",
]


def cli_json(cli, *args):
    out = subprocess.run([cli, "measure", *map(str, args), "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def assert_same_as_cli(m, j):
    # json.loads reads the CLI's shortest round-trip digits back to the very same doubles
    for k in KEYS:
        assert getattr(m, k) == j[k], k
    assert m.n_patches == j["n_patches"]
    assert m.max_row_deficit == j["max_row_deficit"]


def test_lines_measure_equals_the_cli_bit_for_bit(cli, cube_file):
    j = cli_json(cli, cube_file, "--lines", LINES, "--seed", SEED, "--threads", 2)
    m = sceneinfo.measure(cube_file, lines=LINES, seed=SEED, threads=2)
    assert_same_as_cli(m, j)
    assert m.i_s_continuous == j["i_s_continuous"]
    assert m.i_s_continuous_stderr == j["i_s_continuous_stderr"]
    assert m.lines == j["lines"]


def test_exact_measure_equals_the_cli_bit_for_bit(cli, square_file):
    assert_same_as_cli(sceneinfo.measure(square_file), cli_json(cli, square_file))


def test_any_thread_count_gives_the_same_bits(cube_file):
    one = sceneinfo.measure(cube_file, lines=LINES, seed=SEED, threads=1)
    three = sceneinfo.measure(cube_file, lines=LINES, seed=SEED, threads=3)
    assert one.measures() == three.measures()
    assert one.i_s_continuous == three.i_s_continuous
    np.testing.assert_array_equal(one.patch_continuous, three.patch_continuous)


def test_python_and_cli_partials_merge_into_one_run(cli, cube_file, tmp_path):
    # Chunks 0..2 from Python, 2..4 from the CLI, merged in Python
    first = sceneinfo.measure_partial(cube_file, LINES, chunks=(0, 2), seed=SEED, threads=2)
    first.save(tmp_path / "a.sip")
    subprocess.run([cli, "measure", str(cube_file), "--lines", str(LINES), "--seed", str(SEED),
                    "--chunks", "2..4", "--partial", str(tmp_path / "b.sip")],
                   check=True, capture_output=True)
    merged = sceneinfo.merge([tmp_path / "a.sip", tmp_path / "b.sip"])
    assert merged.is_complete and merged.chunks == (0, 4)
    whole = sceneinfo.measure(cube_file, lines=LINES, seed=SEED, threads=2)
    m = merged.measurement()
    assert m.measures() == whole.measures()
    assert m.i_s_continuous == whole.i_s_continuous
    # Bytes round trip
    again = sceneinfo.Partial.from_bytes(merged.to_bytes())
    assert again.measurement().measures() == whole.measures()
