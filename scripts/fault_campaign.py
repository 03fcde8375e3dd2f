#!/usr/bin/env python3
"""The fault campaign's verdict from a `pvfc sweep` table of examples/studies/faults_*.toml.

  usage: fault_campaign.py TABLE.csv --bound JOULES [--allow-error TEXT] [--require-recovery]
                           [--require-no-creation]

Prints, as a Markdown table: the runs, the runs that failed (and why), the most energy the
controller created over any stretch of a run (and in how many runs it passed `--bound`, the
encoders' rounding bound), the most it still owed at the end of a run, the recovery times
(median, 95th percentile, max), after each kind of fault where the table keeps it
(`recovery_KIND`), and the events never recovered from. Fails (exit 1) if a run
owes more than the bound at its end, if a run failed with an error that does not contain
`--allow-error` (none allowed without it), with `--require-recovery` if an event was never
recovered from, and with `--require-no-creation` if a run created more than the bound over
some stretch."""

import argparse
import csv
import statistics
import sys


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("table")
    p.add_argument("--bound", type=float, required=True)
    p.add_argument("--allow-error", default=None)
    p.add_argument("--require-recovery", action="store_true")
    p.add_argument("--require-no-creation", action="store_true")
    a = p.parse_args()
    rows = list(csv.DictReader(open(a.table, newline="")))
    done = [r for r in rows if not r.get("error")]
    failed = [r for r in rows if r.get("error")]

    def column(name: str) -> list[float]:
        return [float(r[name]) for r in done if r.get(name) not in (None, "")]

    created, owed = column("energy_created"), column("energy_owed_at_end")
    recovery, never = column("recovery_time"), column("unrecovered")
    if not done:
        print(f"{a.table}: no run finished", file=sys.stderr)
        return 1
    q95 = sorted(recovery)[int(0.95 * (len(recovery) - 1))] if recovery else float("nan")
    print(f"| {a.table} | |")
    print("|---|---|")
    print(f"| runs | {len(rows)} ({len(failed)} failed) |")
    print(f"| energy created over any stretch, max | {max(created):.3g} J (above {a.bound:.2g} J in {sum(c > a.bound for c in created)} runs) |")
    print(f"| energy owed at the end, max | {max(owed):.3g} J |")
    print(f"| recovery time, median / 95 % / max | {statistics.median(recovery):.3g} / {q95:.3g} / {max(recovery):.3g} s |")
    print(f"| events never recovered from | {int(sum(never))} |")
    # After each kind of fault (the `recovery_KIND` columns, where the study keeps them).
    for kind in [c[len("recovery_"):] for c in (rows[0].keys() if rows else []) if c.startswith("recovery_") and c != "recovery_time"]:
        after = sorted(column(f"recovery_{kind}"))
        if after:
            p95 = after[int(0.95 * (len(after) - 1))]
            print(f"| recovery after `{kind}`, median / 95 % / max ({len(after)} runs) | {statistics.median(after):.3g} / {p95:.3g} / {max(after):.3g} s |")
    reasons: dict[str, int] = {}
    for r in failed:
        reason = r["error"].split(":")[1].strip() if ":" in r["error"] else r["error"]
        reasons[reason] = reasons.get(reason, 0) + 1
    for reason, n in sorted(reasons.items()):
        print(f"| failed: {reason} | {n} |")
    bad = []
    if max(owed) > a.bound:
        bad.append(f"a run owes {max(owed):.3g} J at its end (bound {a.bound:.3g} J)")
    if a.require_no_creation and max(created) > a.bound:
        bad.append(f"a run created {max(created):.3g} J over a stretch (bound {a.bound:.3g} J)")
    if a.require_recovery and sum(never) > 0:
        bad.append(f"{int(sum(never))} events never recovered from")
    unexpected = [r["error"] for r in failed if not (a.allow_error and a.allow_error in r["error"])]
    if unexpected:
        bad.append(f"{len(unexpected)} runs failed: {unexpected[0]}")
    for b in bad:
        print(f"{a.table}: {b}", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
