"""One version: pvfc.__version__ is the installed distribution's and the workspace's."""

import pathlib
import re
from importlib import metadata

import pvfc


def test_version_is_the_distribution_version():
    assert pvfc.__version__ == metadata.version("pvfc")
    assert re.fullmatch(r"\d+\.\d+\.\d+", pvfc.__version__)


def test_version_is_the_workspace_version():
    # Where the tests run from the repository (not from an unpacked sdist elsewhere).
    cargo = pathlib.Path(__file__).resolve().parents[3] / "Cargo.toml"
    if not cargo.exists():
        import pytest

        pytest.skip("not run from the repository")
    table = cargo.read_text().split("[workspace.package]", 1)[1]
    declared = re.search(r'^version = "([^"]+)"', table, re.M).group(1)
    assert pvfc.__version__ == declared
