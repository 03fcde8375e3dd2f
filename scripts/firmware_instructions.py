#!/usr/bin/env python3
"""Counts the instructions of the firmware's control step on the target, from QEMU's
execution trace (QEMU models no cycle counter): QEMU runs the firmware one instruction per
translation block (`-singlestep -d exec,nochain`), its log goes through a FIFO, and every
instruction from the entry of `pvfc_control_step` to its return address (callees included:
libm, soft-float routines) is counted, for the first N control steps. QEMU's clock counts
instructions (`-icount`), so the firmware runs as on a 1 GHz core whatever the trace costs.

Cycles are estimated from the executed mnemonics with the Cortex-M4 technical reference
manual's timings (ARM DDI 0439B, table 3-1, and the FPU's table 7-1): 1 cycle by default;
loads and stores 2 (LDM/STM/PUSH/POP 1 + registers); taken branches and calls 1 + 2 (pipeline
refill; conditional branches counted as taken); VDIV.F32 and VSQRT.F32 14; VLDR/VSTR 2;
VFMA/VFMS/VMLA/VMLS 3; SDIV/UDIV 7 (2-12); the rest 1. No wait states (flash at the core
clock, as QEMU models it). An estimate, not a measurement.

Usage: firmware_instructions.py ELF [--steps N] [--symbol NAME] [--machine MACHINE]

(The cycle estimate is the Cortex-M4's table whatever the machine: for another core, read the
instruction count.)
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

CYCLES = {
    "vdiv.f32": 14, "vsqrt.f32": 14, "vldr": 2, "vstr": 2, "vfma.f32": 3, "vfms.f32": 3,
    "vmla.f32": 3, "vmls.f32": 3, "sdiv": 7, "udiv": 7, "b": 3, "bl": 3, "blx": 3, "bx": 3,
    "ldr": 2, "ldrb": 2, "ldrh": 2, "ldrd": 3, "str": 2, "strb": 2, "strh": 2, "strd": 3,
    "ldrsb": 2, "ldrsh": 2, "tbb": 3, "tbh": 3, "cbz": 2, "cbnz": 2,
}


def cycles_of(mnemonic: str, operands: str) -> int:
    m = mnemonic.split(".")[0] if not mnemonic.startswith("v") else mnemonic
    base = re.sub(r"(eq|ne|cs|cc|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)$", "", m.split(".")[0])
    if base in ("push", "pop", "ldmia", "stmia", "ldm", "stm", "stmdb", "ldmdb", "vpush", "vpop", "vldmia", "vstmia", "vstmdb"):
        return 1 + max(1, operands.count(",") + 1)
    if base.startswith("b") and base not in ("bic", "bics", "bfi", "bfc"):
        return 3
    return CYCLES.get(mnemonic, CYCLES.get(base, 1))


def disassembly(elf: str) -> dict:
    out = subprocess.run(["arm-none-eabi-objdump", "-d", elf], capture_output=True, text=True, check=True).stdout
    table = {}
    for line in out.splitlines():
        m = re.match(r"^\s*([0-9a-f]+):\s+(?:[0-9a-f]{4}\s?){1,2}\s+(\S+)\s*(.*)$", line)
        if m:
            table[int(m.group(1), 16)] = (m.group(2), m.group(3))
    return table


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("elf")
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--machine", default="netduinoplus2", help="QEMU's machine (-machine)")
    ap.add_argument("--symbol", default="pvfc_control_step", help="the function whose calls are counted")
    ap.add_argument("--by-function", action="store_true", help="also tally the instructions per function")
    ap.add_argument("--by-source", action="store_true",
                    help="also tally them per source function, inlined ones included (addr2line -i), and per line")
    args = ap.parse_args()
    nm = subprocess.run(["arm-none-eabi-nm", args.elf], capture_output=True, text=True, check=True).stdout
    entry = next(int(l.split()[0], 16) for l in nm.splitlines() if l.endswith(" " + args.symbol))
    code = disassembly(args.elf)
    calls = [a for a, (mn, ops) in code.items() if mn.startswith("bl") and f"{entry:x} <{args.symbol}>" in ops]
    if len(calls) != 1:
        print(f"expected one call of {args.symbol}, found {len(calls)}", file=sys.stderr)
        return 1
    ret = calls[0] + 4
    fifo = os.path.join(tempfile.mkdtemp(), "trace")
    os.mkfifo(fifo)
    qemu = subprocess.Popen(
        ["qemu-system-arm", "-machine", args.machine, "-nographic", "-semihosting-config",
         "enable=on,target=native", "-singlestep", "-d", "exec,nochain", "-D", fifo,
         # Time in instructions (1 ns each), not the host's clock: traced one at a time, the
         # target would otherwise see its timer fire again before a period's work is done, and
         # its lower priorities (the RTIC firmware's operator) would never run.
         "-icount", "shift=0,sleep=off", "-kernel", args.elf],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    counts, cycles = [], []
    inside, n, c = False, 0, 0
    per_function: dict = {}
    per_pc: dict = {}
    pc_re = re.compile(rb"\[[0-9a-f]+/([0-9a-f]+)/")
    with open(fifo, "rb") as log:
        for line in log:
            m = pc_re.search(line)
            if not m:
                continue
            pc = int(m.group(1), 16)
            if not inside:
                if pc == entry:
                    inside, n, c = True, 0, 0
                else:
                    continue
            if pc == ret:
                inside = False
                counts.append(n)
                cycles.append(c)
                if len(counts) >= args.steps:
                    break
                continue
            n += 1
            if args.by_source:
                per_pc[pc] = per_pc.get(pc, 0) + 1
            if args.by_function:
                name = line.rsplit(b"]", 1)[-1].strip().decode(errors="replace") or "?"
                per_function[name] = per_function.get(name, 0) + 1
            mn, ops = code.get(pc, ("?", ""))
            c += cycles_of(mn, ops)
    qemu.kill()
    qemu.wait()
    if not counts:
        print("no control step seen in the trace", file=sys.stderr)
        return 1
    worst = max(range(len(counts)), key=lambda i: counts[i])
    print(f"control steps traced: {len(counts)}")
    print(f"instructions per step: median {statistics.median(counts):.0f}, min {min(counts)}, max {counts[worst]} (step {worst})")
    print(f"estimated cycles per step (Cortex-M4 timings, no wait states): median {statistics.median(cycles):.0f}, max {max(cycles)}")
    if args.by_function:
        for name, k in sorted(per_function.items(), key=lambda kv: -kv[1])[:15]:
            print(f"  {k / len(counts):8.1f} per step in {name}")
    if args.by_source:
        by_source(args.elf, per_pc, len(counts))
    print(f"at 168 MHz: median {statistics.median(cycles) / 168:.1f} µs, worst {max(cycles) / 168:.1f} µs per step")
    return 0


def by_source(elf: str, per_pc: dict, steps: int) -> None:
    """Prints where a step's instructions come from: the innermost source function of each
    address (inlined ones included) and its line, from the ELF's debug information."""
    pcs = sorted(per_pc)
    out = subprocess.run(["arm-none-eabi-addr2line", "-e", elf, "-f", "-i", "-C", "-a"] + [f"{p:x}" for p in pcs],
                         capture_output=True, text=True, check=True).stdout.splitlines()
    place: dict = {}
    at = None
    for line in out:
        if line.startswith("0x"):
            at = int(line, 16)
            place[at] = None
        elif at is not None and place[at] is None:
            place[at] = [line, None]
        elif at is not None and place[at][1] is None:
            place[at][1] = line
    functions: dict = {}
    lines: dict = {}
    for p, k in per_pc.items():
        f, loc = place.get(p) or ["?", "?"]
        f = re.sub(r"<.*>", "<…>", f or "?")
        loc = re.sub(r".*/(crates|src)/", r"\1/", loc or "?").split(" ")[0]
        functions[f] = functions.get(f, 0) + k
        lines[loc] = lines.get(loc, 0) + k
    print("per source function (innermost inlined):")
    for f, k in sorted(functions.items(), key=lambda kv: -kv[1])[:25]:
        print(f"  {k / steps:8.1f} {f}")
    print("per source line:")
    for l, k in sorted(lines.items(), key=lambda kv: -kv[1])[:30]:
        print(f"  {k / steps:8.1f} {l}")


if __name__ == "__main__":
    sys.exit(main())
