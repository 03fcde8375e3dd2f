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
    """The Rust `pvfc` command line (for parity tests): `PVFC_CLI` when it is set (a `pvfc`
    built beforehand: the wheel's tests on a machine without Rust), otherwise built here in
    release mode with cargo. Without either the parity tests are skipped, unless `CI` is set."""
    given = os.environ.get("PVFC_CLI")
    if given:
        path = pathlib.Path(given).resolve()
        assert path.is_file(), f"PVFC_CLI={given} is not a file"
        return path
    cargo = shutil.which("cargo")
    if cargo is None:
        if os.environ.get("CI"):
            pytest.fail("cargo (or PVFC_CLI) is needed for the Rust/Python parity tests in CI")
        pytest.skip("neither cargo nor PVFC_CLI: the Rust/Python parity tests need the pvfc command")
    subprocess.run([cargo, "build", "--release", "--locked", "--bin", "pvfc"], cwd=REPO, check=True)
    return REPO / "target" / "release" / "pvfc"
