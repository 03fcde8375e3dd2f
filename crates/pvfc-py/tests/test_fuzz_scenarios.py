"""Fuzzing scenario dicts under a memory limit: every mutation either runs or raises a
documented exception; none may kill the process (the issue's `controller.rate = 1e308`
aborted it with "memory allocation of 1073741824 bytes failed" before the sizes were checked).

The mutations run in a child process whose address space is capped (`ulimit -v`, here
RLIMIT_AS = 3 GiB): an allocation that the checks let through would abort the child, and the
test sees its exit status."""

import os
import subprocess
import sys
import textwrap

import pytest

CHILD = textwrap.dedent(
    r"""
    import copy, math, random, sys
    import pvfc

    rng = random.Random(int(sys.argv[1]))
    base = pvfc.Scenario.preset("fig8_R100").to_dict()
    base["duration"] = 0.05
    extremes = [0, -1, 1e-300, 1e308, 2.0**70, 2**70, float("nan"), float("inf"), -float("inf"),
                1e6, 1e7, 3, "x", None, [1.0], [1e308, 1e308], True]
    numeric = []
    def walk(d, path):
        for k, v in d.items():
            if isinstance(v, dict):
                walk(v, path + [k])
            elif isinstance(v, (int, float, list)) and not isinstance(v, bool):
                numeric.append(path + [k])
    walk(base, [])
    counts = {"ran": 0, "rejected": 0}
    for i in range(int(sys.argv[2])):
        d = copy.deepcopy(base)
        for _ in range(rng.randint(1, 3)):
            path = rng.choice(numeric)
            node = d
            for k in path[:-1]:
                node = node[k]
            node[path[-1]] = rng.choice(extremes)
        try:
            s = pvfc.Scenario.from_dict(d)
            if d["duration"] * d["controller"]["rate"] * d["simulation"]["plant_substeps"] > 2e5:
                continue  # valid but long: its sizes were checked; running it proves nothing more
            pvfc.simulate(s)
            counts["ran"] += 1
        except (pvfc.PvfcError, TypeError, ValueError, OverflowError, KeyError):
            counts["rejected"] += 1
    print(counts)
    """
)


def _limit_memory() -> None:  # pragma: no cover - runs in the child
    import resource

    cap = 3 * 1024**3
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS is Linux's")
def test_fuzzed_scenarios_never_kill_the_process() -> None:
    seed = "0" if os.environ.get("CI") else str(os.getpid())
    r = subprocess.run(
        [sys.executable, "-c", CHILD, seed, "600"],
        capture_output=True,
        text=True,
        preexec_fn=_limit_memory,
        timeout=600,
    )
    assert r.returncode == 0, f"child died ({r.returncode}): {r.stderr[-2000:]}"
    assert "rejected" in r.stdout


def test_the_reported_sizes_are_typed_errors() -> None:
    import pvfc

    for field, value in [("rate", 1e308), ("rate", 2.0**70)]:
        d = pvfc.Scenario.preset("fig8_R100").to_dict()
        d["duration"] = 0.05
        d["controller"][field] = value
        with pytest.raises(pvfc.PvfcError, match="controller.rate"):
            pvfc.Scenario.from_dict(d)
    d = pvfc.Scenario.preset("fig8_R100").to_dict()
    d["duration"] = 1e9
    with pytest.raises(pvfc.PvfcError, match="samples"):
        pvfc.Scenario.from_dict(d)
    d = pvfc.Scenario.preset("fig8_R100").to_dict()
    d["simulation"]["plant_substeps"] = 10**9
    with pytest.raises(pvfc.PvfcError, match="plant_substeps"):
        pvfc.Scenario.from_dict(d)
