"""Shared fixtures: small scene files, and the CLI binary the parity tests compare with."""

import os
import pathlib
import shutil

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# A closed square, 4 patches a side, written by hand in the .flat format
SQUARE = """# unit square, 4 patches a side
poly 4 0 0 1 0 1 1 0 1 per_side 4
"""


@pytest.fixture
def square_file(tmp_path):
    p = tmp_path / "square.flat"
    p.write_text(SQUARE)
    return p


@pytest.fixture(scope="session")
def cli():
    """The `sceneinfo` binary: $SCENEINFO_BIN, else target/debug/sceneinfo of this checkout.

    scripts/test.sh builds it and sets SCENEINFO_BIN, so there the parity tests always run.
    """
    env = os.environ.get("SCENEINFO_BIN")
    path = pathlib.Path(env) if env else ROOT / "target" / "debug" / "sceneinfo"
    if not path.exists():
        if env:
            pytest.fail(f"SCENEINFO_BIN={env} does not exist")
        pytest.skip("no CLI binary (build it with cargo build -p sceneinfo-cli)")
    return str(path)


@pytest.fixture(scope="session")
def cube_file(tmp_path_factory, cli):
    """The 600-patch cube as the CLI writes it (`sceneinfo scene cube --grid 10`)."""
    import subprocess

    d = tmp_path_factory.mktemp("cube")
    out = d / "cube.obj"
    subprocess.run([cli, "scene", "cube", "--grid", "10", "-o", str(out)], check=True)
    return out
