"""The layer check of `scripts/module_cycles.py` (run by `.ci/run` over pvfc-control and
pvfc-sim): it passes the shipped crates in their declared order, and fails, naming the
modules, on an import of a higher layer by a lower one, on a cycle, and on a top-level module
the order leaves out."""

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
