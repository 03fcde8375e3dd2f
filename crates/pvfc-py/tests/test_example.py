"""The example script runs and writes its figures."""

import subprocess
import sys


def test_reproduce_paper_example(repo, tmp_path):
    script = repo / "examples" / "python" / "reproduce_paper.py"
    subprocess.run([sys.executable, script, "--out", tmp_path, "--quick"], check=True)
    for name in ["fig6_unforced.png", "fig7_self_pacing.png", "fig8_pacing_compensated.png",
                 "fig9_pacing_uncompensated.png", "fig10_nominal_speed.png"]:
        assert (tmp_path / name).stat().st_size > 10_000, name
