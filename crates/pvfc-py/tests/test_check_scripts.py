"""The project's check scripts can fail. The layer check of `scripts/module_cycles.py` (run by
`.ci/run` over pvfc-control and pvfc-sim) passes the shipped crates in their declared order,
and fails, naming the modules, on an import of a higher layer by a lower one and on a
top-level module the order leaves out; `scripts/same_output.py` (the side-by-side examples'
check in `scripts/test.sh`) fails on another number, name or line count."""

import pathlib
import subprocess
import sys

REPO = pathlib.Path(__file__).resolve().parents[3]
SCRIPT = REPO / "scripts" / "module_cycles.py"


def check(src: pathlib.Path, layers: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(SCRIPT), str(src), "--layers", layers],
        capture_output=True,
        text=True,
        check=False,
    )


def crate(tmp: pathlib.Path, files: dict) -> pathlib.Path:
    src = tmp / "src"
    for name, text in files.items():
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        (src / name).write_text(text, encoding="utf-8")
    return src


def test_the_shipped_crates_keep_their_order() -> None:
    r = check(REPO / "crates/pvfc-sim/src", "plant,contact,scenario,trace,run,log,study")
    assert r.returncode == 0, r.stdout
    r = check(REPO / "crates/pvfc-control/src", "error,urdf,obstacles,model")
    assert r.returncode == 0, r.stdout


def test_an_upward_import_fails_and_is_named(tmp_path: pathlib.Path) -> None:
    src = crate(
        tmp_path,
        {
            "lib.rs": "pub mod low;\npub mod high;\n",
            "low.rs": "use crate::high::Thing;\n// crate::high in a comment does not count\n",
            "high.rs": "pub struct Thing;\n",
        },
    )
    r = check(src, "low,high")
    assert r.returncode == 1
    assert "upward import: low (layer low) imports high" in r.stdout
    # The other way round is the order.
    assert check(src, "high,low").returncode == 0


def test_a_module_out_of_the_order_fails(tmp_path: pathlib.Path) -> None:
    src = crate(tmp_path, {"lib.rs": "pub mod a;\npub mod b;\n", "a.rs": "", "b.rs": ""})
    r = check(src, "a")
    assert r.returncode == 1 and "top-level module b is in no layer" in r.stdout


SAME = REPO / "scripts" / "same_output.py"


def test_the_side_by_side_check_fails_on_another_number(tmp_path: pathlib.Path) -> None:
    """`scripts/same_output.py` (the side-by-side examples' check): Rust's exponents read as
    C's, and a number that differs in its 7th digit, a missing line or another name fail."""
    rust = tmp_path / "rust.txt"
    rust.write_text("x (Rust)\nt 0.5 tau 4.846213e-1 error 8.542154e-2\n", encoding="utf-8")
    cases = {
        "t 0.5 tau 4.846213e-01 error 8.542154e-02\n": 0,
        "t 0.5 tau 4.846214e-01 error 8.542154e-02\n": 1,
        "t 0.5 tau 4.846213e-01 err 8.542154e-02\n": 1,
        "": 1,
    }
    for body, code in cases.items():
        other = tmp_path / "other.txt"
        other.write_text("x (C++)\n" + body, encoding="utf-8")
        r = subprocess.run(
            [sys.executable, str(SAME), str(rust), str(other)], capture_output=True, text=True, check=False
        )
        assert r.returncode == code, (body, r.stdout, r.stderr)
