"""One version: the package's __version__ is the program's `--version` and the installed
distribution's (the wheel's metadata, which maturin reads from Cargo.toml); the MuJoCo
library of the `mujoco` extra's wheel is found on the path."""

import importlib.metadata
import subprocess

import proleg
from proleg._mujoco import library_from_wheel


def test_the_package_the_wheel_and_the_program_carry_one_version(proleg_bin):
    out = subprocess.run([proleg_bin, "--version"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == f"proleg {proleg.__version__}"
    assert importlib.metadata.version("proleg") == proleg.__version__


def test_the_mujoco_wheels_library_is_found_on_the_path(tmp_path):
    name = proleg._native.MUJOCO_LIBRARY
    assert name.startswith("libmujoco.so.")
    assert library_from_wheel(name, [str(tmp_path)]) is None
    (tmp_path / "mujoco").mkdir()
    (tmp_path / "mujoco" / name).write_bytes(b"")
    assert library_from_wheel(name, ["/no/such/dir", str(tmp_path)]) == str(tmp_path / "mujoco" / name)
