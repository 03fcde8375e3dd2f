"""Runs per second of a study: here on 1 and 2 threads, and on a Dask LocalCluster of 1 and 2
worker processes; the overhead per run of shipping the study and its rows, against the run's
own time. Usage: python scripts/study_speed.py [RUNS] [SECONDS]  (defaults: 48 runs of 10 s).
Prints a Markdown table; the CPU model heads it (figures differ between machines)."""

import platform
import sys
import time

import distributed

import pvfc


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 48
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
    base = pvfc.Scenario.preset("fig8_R100").to_dict()
    base["duration"] = seconds
    study = pvfc.Study.from_toml(
        f'name = "speed"\nmetrics = ["mean_u", "mean_tau_rate"]\n[[axis]]\n'
        f'key = "controller.self_pacing"\nrange = {{ from = 0, to = 400, steps = {runs} }}\n',
        pvfc.Scenario.from_dict(base),
    )
    rows = []

    def timed(label, f, workers):
        f()  # warm: the workers import pvfc, the caches fill
        best = min(_time(f) for _ in range(3))
        rows.append((label, workers, best))

    timed("this machine, 1 thread", lambda: pvfc.sweep(study, threads=1), 1)
    timed("this machine, 2 threads", lambda: pvfc.sweep(study, threads=2), 2)
    for n in (1, 2):
        with distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                      dashboard_address=None) as cluster:
            with distributed.Client(cluster) as client:
                timed(f"Dask, {n} worker process{'es' if n > 1 else ''}",
                      lambda: pvfc.sweep(study, client), n)
    one = rows[0][2] / runs
    print(f"{runs} runs of the Fig. 8 SCARA scenario, {seconds:g} s each, on {cpu_model()} "
          f"(best of 3)\n")
    print("| where | runs/s | s per run per worker | overhead per run vs 1 thread |")
    print("|---|---:|---:|---:|")
    for label, workers, t in rows:
        per = t * workers / runs
        print(f"| {label} | {runs / t:.1f} | {per * 1e3:.1f} ms | {100 * (per - one) / one:+.1f} % |")


def _time(f) -> float:
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


if __name__ == "__main__":
    main()
