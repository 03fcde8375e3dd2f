#!/usr/bin/env bash
# The SCARA firmware of examples/firmware (its SysTick loop, src/main.rs) on the other Cortex-M
# cores QEMU has a machine for: a Cortex-M0 without an FPU (microbit, nRF51822: thumbv6m, f32
# in software), a Cortex-M7 (mps2-an500: thumbv7em-none-eabihf) and a Cortex-M33 (mps2-an505,
# secure state: thumbv8m.main-none-eabihf). For each: build it with the machine's memory
# layout (examples/firmware/memory/), report flash and RAM, run its 10,000 steps in QEMU (a
# clock counting instructions, so a slow core's steps still fit their periods), compare its
# trace with the host twin (tests/firmware_twin.rs) and count the instructions of a step.
# Then the same loop on RISC-V (examples/firmware/riscv, RV32IMAC without an FPU, QEMU's
# `virt`), which counts its steps itself from the core's minstret.
# Needs what scripts/firmware.sh needs, qemu-system-riscv32 (Debian: qemu-system-misc), and the
# rustup targets thumbv6m-none-eabi, thumbv8m.main-none-eabihf, riscv32imac-unknown-none-elf.
set -euo pipefail
cd "$(dirname "$0")/.."
fw=examples/firmware
out=${PVFC_FIRMWARE_OUT:-target/firmware}
mkdir -p "$out"
twin=$(cargo test --locked --no-run --message-format=json | python3 scripts/cargo_artifact.py firmware_twin exe)
test -x "$twin" || { echo "cargo test did not build tests/firmware_twin.rs" >&2; exit 1; }

# run_and_compare NAME QEMU ARGS...: runs a firmware in QEMU (a clock counting instructions:
# a slow core's steps still fit their periods) into $out/trace-NAME.txt; it must end its 10,000
# steps without a fault, and its trace must match the host twin's.
run_and_compare() {
  local name=$1
  shift
  local trace="$out/trace-$name.txt" status=0
  timeout 300 "$@" -nographic -semihosting-config enable=on,target=native > "$trace" || status=$?
  tail -n 2 "$trace"
  if [ "$status" -ne 0 ] || ! grep -q "pvfc: done, 10000 steps, no fault" "$trace"; then
    echo "the firmware on $name exited with $status (a controller fault, or QEMU failed)" >&2
    exit 1
  fi
  PVFC_FIRMWARE_TRACE="$trace" "$twin" --ignored --nocapture firmware_trace_matches_the_host_twin \
    2>&1 | grep -E "vs host|test result|panicked|assert" | tee "$out/twin-$name.txt"
  grep -q "test result: ok. 1 passed" "$out/twin-$name.txt"
}

: > "$out/cores.txt"
for spec in microbit:thumbv6m-none-eabi:200 mps2-an500:thumbv7em-none-eabihf:1000 \
            mps2-an505:thumbv8m.main-none-eabihf:1000; do
  IFS=: read -r machine target steps <<< "$spec"
  echo "--- $machine ($target)"
  (cd $fw && PVFC_MACHINE=$machine CARGO_TARGET_DIR=target/cores/$machine \
    cargo build --locked --release -p pvfc-firmware --bin pvfc-firmware --target "$target")
  elf=$fw/target/cores/$machine/$target/release/pvfc-firmware
  size=$(arm-none-eabi-size "$elf" | tail -n 1)
  echo "$size"
  run_and_compare "$machine" qemu-system-arm -machine "$machine" -icount shift=0,sleep=off -kernel "$elf"
  count=$(python3 scripts/firmware_instructions.py "$elf" --machine "$machine" --steps "$steps" \
    | grep "instructions per step")
  echo "$count"
  read -r text data bss _ <<< "$size"
  echo "$machine $target: flash $((text + data)) B, RAM $((data + bss)) B; $count" >> "$out/cores.txt"
done
echo "--- RISC-V (riscv32imac-unknown-none-elf, QEMU's virt)"
(cd $fw && cargo build --locked --release -p pvfc-firmware-riscv --target riscv32imac-unknown-none-elf)
elf=$fw/target/riscv32imac-unknown-none-elf/release/pvfc-firmware-riscv
text=$(size -A "$elf" | awk '$1 == ".text" || $1 == ".rodata" || $1 == ".init.rust" { n += $2 } END { print n }')
run_and_compare riscv qemu-system-riscv32 -machine virt -bios none -icount shift=0 -kernel "$elf"
grep "^stack:" "$out/trace-riscv.txt"
echo "virt riscv32imac-unknown-none-elf: code and read-only data $text B; $(grep "^stack:" "$out/trace-riscv.txt"); $(grep "instructions per step" "$out/trace-riscv.txt")" >> "$out/cores.txt"
cat "$out/cores.txt"
