#!/usr/bin/env bash
# All the tests: the Rust workspace (cargo test), then the Python wheel built into a fresh
# virtual environment with its pytest suite and the stub check (mypy.stubtest).
# Needs Rust (rustup) and Python ≥ 3.9 with venv; installs the rest itself.
set -euo pipefail
cd "$(dirname "$0")/.."
stage() { echo "=== $* (${SECONDS} s so far)"; }

stage "cargo test"
cargo test --locked

stage "Python: build the wheel into a fresh virtual environment"
venv="${PVFC_VENV:-target/py-venv}"
rm -rf "$venv"
python3 -m venv "$venv"
py="$venv/bin/python"
"$py" -m pip install --quiet --upgrade pip
"$py" -m pip install --quiet "./crates/pvfc-py[test,reference]"
"$py" -c "import pvfc, numpy; print('pvfc', pvfc.__version__, 'numpy', numpy.__version__)"

stage "pytest"
(cd crates/pvfc-py && "../../$py" -m pytest -q -p no:cacheprovider --durations=10)

stage "stubtest"
"$py" -m mypy.stubtest pvfc
stage "done"
