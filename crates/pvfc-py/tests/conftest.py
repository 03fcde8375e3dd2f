import os
import pathlib
import shutil
import subprocess

import pytest
from hypothesis import settings

# In CI the property tests are derandomized (the same cases every run, so a run's outcome
# depends on the code only); locally they explore new random cases each time.
settings.register_profile("ci", derandomize=True)
if os.environ.get("CI"):
    settings.load_profile("ci")

REPO = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def repo() -> pathlib.Path:
    return REPO


@pytest.fixture(scope="session")
def pvfc_cli() -> pathlib.Path:
    """The Rust `pvfc` command line, built in release mode (for parity tests)."""
    cargo = shutil.which("cargo")
    assert cargo is not None, "cargo is needed for the Rust/Python parity tests"
    subprocess.run([cargo, "build", "--release", "--locked", "--bin", "pvfc"], cwd=REPO, check=True)
    return REPO / "target" / "release" / "pvfc"
