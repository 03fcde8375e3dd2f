"""Studies as a user runs them: pvfc.sweep here, on a LocalCluster of worker processes, and on
a scheduler and two workers started as separate processes; the same numbers, bit for bit; a
worker killed mid-sweep loses no run; Scenario and Study pickle."""

import os
import pickle
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import pvfc

pd = pytest.importorskip("pandas")
distributed = pytest.importorskip("distributed")

GRID = """
name = "grid"
metrics = ["mean_u", "mean_tau_rate", "peak_force", "converge_time"]
[[axis]]
key = "controller.self_pacing"
values = [0, 200]
[[axis]]
key = "controller.energy"
values = [800, 2000, 3200]
"""


def short(seconds: float) -> pvfc.Scenario:
    d = pvfc.Scenario.preset("fig8_R100").to_dict()
    d["duration"] = seconds
    return pvfc.Scenario.from_dict(d)


@pytest.fixture(scope="module")
def study() -> pvfc.Study:
    return pvfc.Study.from_toml(GRID, short(13.0))


@pytest.fixture(scope="module")
def local(study) -> "pd.DataFrame":
    return pvfc.sweep(study, threads=2)


def same_bits(a: "pd.DataFrame", b: "pd.DataFrame") -> None:
    assert list(a.columns) == list(b.columns)
    assert list(a["error"]) == list(b["error"])
    numbers = [c for c in a.columns if c != "error"]
    x = a[numbers].to_numpy(dtype=np.float64)
    y = b[numbers].to_numpy(dtype=np.float64)
    assert x.shape == y.shape
    assert np.array_equal(x.view(np.uint64), y.view(np.uint64))


def test_a_local_sweep_is_a_table_of_its_runs(study, local):
    assert len(study) == 6
    assert list(local.columns) == study.columns == [
        "run", "controller.self_pacing", "controller.energy",
        "mean_u", "mean_tau_rate", "peak_force", "converge_time", "error",
    ]
    assert list(local["run"]) == list(range(6))
    assert list(local["controller.energy"]) == [800.0, 2000.0, 3200.0] * 2
    assert local["error"].isna().all()
    assert local["peak_force"].isna().all()  # no contact
    # More energy, less contour error (Fig. 9's ordering), at either gain.
    for g in (0.0, 200.0):
        u = local[local["controller.self_pacing"] == g]["mean_u"].to_numpy()
        assert u[0] > u[1] > u[2] > 0
    # One thread or two, or the runs one by one through simulate: the same numbers.
    same_bits(local, pvfc.sweep(study, threads=1))
    r = pvfc.simulate(study.scenario(4))
    assert study.parameters(4) == [200.0, 2000.0]
    assert r.name == "grid_0004"


def test_scenario_and_study_pickle(study, repo):
    # A URDF arm's scenario keeps the folder its relative paths are read from.
    for s in (short(3.0), pvfc.Scenario.from_file(str(repo / "scenarios" / "ur5_cartesian.toml"))):
        back = pickle.loads(pickle.dumps(s))
        assert back.to_toml() == s.to_toml()
    st = pickle.loads(pickle.dumps(study))
    assert (st.name, st.keys, st.metrics, len(st)) == (study.name, study.keys, study.metrics, len(study))
    assert st.scenario(5).to_toml() == study.scenario(5).to_toml()
    assert st.run([5]) == study.run([5])


def test_bad_studies_name_what_is_wrong():
    with pytest.raises(pvfc.PvfcError, match="contour_eror"):
        pvfc.Study.from_toml(GRID.replace('"mean_u"', '"contour_eror"'), short(3.0))
    with pytest.raises(pvfc.PvfcError, match="self_pacng"):
        pvfc.Study.from_toml(GRID.replace("self_pacing", "self_pacng"), short(3.0))
    with pytest.raises(IndexError):
        pvfc.Study.from_toml(GRID, short(3.0)).run([6])


def test_design_points_multiply_the_runs():
    st = pvfc.Study.from_toml(
        GRID.replace("values = [800, 2000, 3200]", "values = [800, 2000]")
        + '[[point]]\n"plant.friction.coulomb[1]" = 2.8\n[[point]]\n"plant.friction.coulomb[1]" = 4.2\n',
        short(3.0),
    )
    assert len(st) == 8
    assert st.keys == ["controller.self_pacing", "controller.energy", "plant.friction.coulomb[1]"]
    assert st.parameters(5) == [200.0, 800.0, 4.2]
    assert st.scenario(5).to_dict()["plant"]["friction"]["coulomb"][1] == 4.2
    with pytest.raises(pvfc.PvfcError, match="point 1"):
        pvfc.Study.from_toml(GRID + '[[point]]\n"duration" = 2.0\n[[point]]\n"plant.friction.coulomb[1]" = 4.2\n', short(3.0))


def test_a_failed_run_is_a_row():
    st = pvfc.Study.from_toml(
        'name = "g"\nmetrics = ["mean_u"]\n[[axis]]\nkey = "controller.gamma"\nvalues = [0.025, 1e8]\n',
        short(3.0),
    )
    df = pvfc.sweep(st)
    assert df["error"][0] is None and isinstance(df["error"][1], str)
    assert np.isnan(df["mean_u"][1])


def test_a_local_cluster_of_worker_processes_gives_the_same_numbers(study, local):
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            same_bits(local, pvfc.sweep(study, client, batch_size=2))


def _start(args, log):
    """`python -m ARGS`, its output into the file `log`."""
    with open(log, "wb") as out:
        return subprocess.Popen([sys.executable, "-m", *args], stdout=out, stderr=subprocess.STDOUT)


def test_a_scheduler_and_two_workers_as_processes_and_a_worker_killed(study, local, tmp_path):
    file = tmp_path / "scheduler.json"
    # Any free port (the workers find it in the scheduler file): the default, 8786, is taken
    # when another suite runs beside this one, and a scheduler that cannot bind exits.
    log = tmp_path / "scheduler.log"
    procs = [_start(["distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
                     "--scheduler-file", str(file), "--no-dashboard"], log)]
    try:
        for i in range(2):
            procs.append(_start(["distributed.cli.dask_worker", "--scheduler-file", str(file),
                                 "--nthreads", "1", "--nworkers", "1", "--no-dashboard",
                                 "--no-nanny"], tmp_path / f"worker{i}.log"))
        deadline = time.time() + 60
        while not file.exists() and time.time() < deadline and procs[0].poll() is None:
            time.sleep(0.2)
        if not file.exists():
            pytest.fail(f"the scheduler did not start (exit {procs[0].poll()}):\n"
                        + log.read_text(errors="replace")[-3000:])
        with distributed.Client(scheduler_file=str(file), timeout=60) as client:
            client.wait_for_workers(2, timeout=60)
            same_bits(local, pvfc.sweep(study, client, batch_size=1))
            # A longer study; one worker killed once the sweep is under way: no run lost.
            long = pvfc.Study.from_toml(GRID.replace("[0, 200]", "[0, 50, 100, 200, 400]"), short(40.0))
            expected = pvfc.sweep(long, threads=2)
            done, killed_mid_sweep = [], []

            def kill_one_when_started():
                while len(done) == 0 and time.time() < deadline + 60:
                    if sum(len(v) for v in client.processing().values()) > 0:
                        time.sleep(0.3)
                        killed_mid_sweep.append(len(done) == 0)
                        procs[1].send_signal(signal.SIGKILL)
                        return
                    time.sleep(0.05)

            import threading
            killer = threading.Thread(target=kill_one_when_started)
            killer.start()
            got = pvfc.sweep(long, client, batch_size=1)
            done.append(True)
            killer.join()
            assert killed_mid_sweep == [True] and procs[1].poll() is not None
            same_bits(expected, got)
    finally:
        for p in procs:
            if p.poll() is None:
                p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()


def test_pvfc_sweep_on_the_command_line_writes_the_same_numbers(study, local, pvfc_cli, tmp_path):
    import csv

    (tmp_path / "base.toml").write_text(study.base.to_toml())
    (tmp_path / "grid.toml").write_text('base = "base.toml"\n' + GRID)
    out = tmp_path / "out"
    subprocess.run([str(pvfc_cli), "sweep", str(tmp_path / "grid.toml"), "--out", str(out),
                    "--threads", "2"], check=True, stdout=subprocess.DEVNULL)
    with open(out / "grid.csv", newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == study.columns
    for cells, (_, expected) in zip(rows[1:], local.iterrows()):
        assert int(cells[0]) == expected["run"]
        for name, cell in zip(study.columns[1:-1], cells[1:-1]):
            want = expected[name]
            if cell == "":
                assert np.isnan(want), name
            else:
                assert float(cell).hex() == float(want).hex(), name
    assert (out / "grid_mean_u.png").stat().st_size > 5000


def test_the_arrow_table_reads_in_pandas_and_polars_as_the_sweep(pvfc_cli, tmp_path):
    """`pvfc sweep`'s NAME.arrow, read by pyarrow (pandas.read_feather) and by Polars' own
    reader, holds pvfc.sweep's numbers bit for bit, its nulls (a metric that does not apply,
    a failed run) and its errors."""
    pl = pytest.importorskip("polars")
    pytest.importorskip("pyarrow")
    text = (
        'name = "mixed"\nmetrics = ["mean_u", "peak_force", "converge_time"]\n'
        '[[axis]]\nkey = "controller.gamma"\nvalues = [0.025, 1e8]\n'
        '[[axis]]\nkey = "controller.energy"\nvalues = [800, 2000]\n'
    )
    st = pvfc.Study.from_toml(text, short(3.0))
    want = pvfc.sweep(st, threads=2)
    (tmp_path / "base.toml").write_text(st.base.to_toml())
    (tmp_path / "mixed.toml").write_text('base = "base.toml"\n' + text)
    out = tmp_path / "out"
    subprocess.run([str(pvfc_cli), "sweep", str(tmp_path / "mixed.toml"), "--out", str(out),
                    "--no-figures"], check=True, stdout=subprocess.DEVNULL)
    got = pd.read_feather(out / "mixed.arrow")
    assert str(got["run"].dtype) == "int64"
    assert list(got["run"]) == list(range(4))
    assert want["peak_force"].isna().all() and got["peak_force"].isna().all()
    assert want["error"].notna().sum() == 2
    assert [e if isinstance(e, str) else None for e in got["error"]] == list(want["error"])
    same_bits(want.assign(error=""), got.assign(error=""))
    polars = pl.read_ipc(out / "mixed.arrow")
    assert polars.columns == st.columns
    assert polars["error"].to_list() == list(want["error"])
    for name in st.columns[1:-1]:
        x = polars[name].to_numpy().astype(np.float64)  # nulls become NaN
        y = want[name].to_numpy(dtype=np.float64)
        assert np.array_equal(x.view(np.uint64), y.view(np.uint64)), name


def _columns(r: "pvfc.SimulationResult") -> dict:
    names = ["t", "q", "qdot", "energy", "tau", "tau_dot", "flywheel_speed", "beta", "w_beta",
             "potential", "lambda1", "lambda2", "torque", "friction_power"]
    out = {n: np.asarray(getattr(r, n)) for n in names}
    for k, v in (r.contact or {}).items():
        out["contact." + k] = np.asarray(v)
    return out


def test_results_pickle_bit_for_bit_and_cross_processes():
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    scenarios = [short(2.0), pvfc.Scenario.preset("contact_wall")]
    local = [pvfc.simulate(s) for s in scenarios]
    assert local[1].contact is not None
    # Fresh interpreters ("spawn"), never fork: this process has threads by now (Dask's, the
    # library's), and a forked child can deadlock on a lock one of them held (CPython 3.12+
    # warns of it; the default becomes "forkserver" in 3.14).
    spawn = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=2, mp_context=spawn) as pool:
        remote = list(pool.map(pvfc.simulate, scenarios))
    for a in local:
        back = pickle.loads(pickle.dumps(a))
        assert (back.name, back.period, len(back)) == (a.name, a.period, len(a))
        for got, want in ((back, a), (remote[local.index(a)], a)):
            x, y = _columns(got), _columns(want)
            assert x.keys() == y.keys()
            for k in x:
                assert x[k].shape == y[k].shape and np.array_equal(
                    x[k].view(np.uint64), y[k].view(np.uint64)
                ), k
    with pytest.raises(pvfc.PvfcError, match="no column"):
        pvfc.SimulationResult._from_state("x", 1.0, [], None)
