#!/usr/bin/env bash
# The firmware of examples/firmware in QEMU (netduinoplus2, Cortex-M4F): build it, report its
# flash and RAM, run it (10,000 control steps at 1 kHz, its exit code says whether the
# controller faulted), compare its trace with the host twin (tests/firmware_twin.rs), and count
# the instructions of a control step from an execution trace.
# Then the same for the 6-joint step (--bin ur5) and the passive digital controller (--bin
# passive), and the RTIC firmware (examples/firmware/rtic): its run, its trace against its host
# twin (the operator's commands replayed at the periods it applied them), its control period
# counted; then its hardware-in-the-loop binary against a plant on the host.
# Needs: rustup target thumbv7em-none-eabihf, qemu-system-arm, binutils-arm-none-eabi.
set -euo pipefail
cd "$(dirname "$0")/.."
fw=examples/firmware
elf=$fw/target/thumbv7em-none-eabihf/release/pvfc-firmware
out=${PVFC_FIRMWARE_OUT:-target/firmware}
mkdir -p "$out"

echo "--- build"
(cd $fw && cargo build --locked --release --bins)
echo "--- size (text = flash code, data = flash + RAM, bss = RAM)"
arm-none-eabi-size "$elf" | tee "$out/size.txt"

echo "--- run in QEMU"
status=0
(cd $fw && timeout 300 cargo run --locked --release) > "$out/trace.txt" || status=$?
tail -n 3 "$out/trace.txt"
if [ "$status" -ne 0 ]; then
  echo "the firmware exited with $status (a controller fault, or QEMU failed)" >&2
  exit 1
fi
grep -q "pvfc: done, 10000 steps, no fault" "$out/trace.txt"

echo "--- the trace against the host twin"
# The twin as `cargo test` builds it (the README's test command): `cargo test --test
# firmware_twin` alone would resolve the dev-dependencies' features for one package only and
# compile the whole dependency tree a second time (three minutes on two cores).
cargo test --locked --no-run --message-format=json >"$out/test-build.json"
twin=$(python3 scripts/cargo_artifact.py firmware_twin exe <"$out/test-build.json")
test -x "$twin" || { echo "cargo test did not build tests/firmware_twin.rs" >&2; exit 1; }
# The `pvfc` command as `cargo test` builds it (for pvfc-cli's tests).
pvfc=$(python3 scripts/cargo_artifact.py pvfc bin <"$out/test-build.json")
test -x "$pvfc" || { echo "cargo test did not build the pvfc command" >&2; exit 1; }
PVFC_FIRMWARE_TRACE="$out/trace.txt" "$twin" --ignored --nocapture firmware_trace_matches_the_host_twin \
  2>&1 | grep -E "firmware vs|host f32 vs|test result|panicked|assert" | tee "$out/twin.txt"
grep -q "test result: ok. 1 passed" "$out/twin.txt"

echo "--- instructions per control step (QEMU execution trace)"
python3 scripts/firmware_instructions.py "$elf" --steps 1000 | tee "$out/instructions.txt"

# run_bin NAME: size one of the firmware's binaries and run it in QEMU; it must end without a
# fault (its log in $out/NAME.txt).
run_bin() {
  local bin=$fw/target/thumbv7em-none-eabihf/release/$1
  arm-none-eabi-size "$bin" | tee -a "$out/size.txt"
  timeout 120 qemu-system-arm -machine netduinoplus2 -nographic -semihosting-config enable=on,target=native \
    -kernel "$bin" | tee "$out/$1.txt"
  grep -q "no fault" "$out/$1.txt"
}

echo "--- the 6-joint f32 step (UR5, gravity compensation): run and count"
run_bin ur5
python3 scripts/firmware_instructions.py "$fw/target/thumbv7em-none-eabihf/release/ur5" --symbol pvfc_arm_step \
  --steps 200 | tee "$out/ur5_instructions.txt"

echo "--- the passive digital controller (encoder positions only, 2^17 counts, |u| <= 3 N·m): run and count"
run_bin passive
# The same measured states through Controller::step and through the passive step (velocity
# measured, as the host bench), then the loop's encoder-only passive step.
for symbol in pvfc_control_step pvfc_passive_step pvfc_encoder_step; do
  echo "$symbol:"
  python3 scripts/firmware_instructions.py "$fw/target/thumbv7em-none-eabihf/release/passive" \
    --symbol "$symbol" --steps 1000
done | tee "$out/passive_instructions.txt"

echo "--- the RTIC firmware (SysTick at 1 kHz, the passive controller from encoder counts, an operator's script)"
(cd $fw && cargo build --locked --release -p pvfc-firmware-rtic)
rtic=$fw/target/thumbv7em-none-eabihf/release/pvfc-firmware-rtic
arm-none-eabi-size "$rtic" | tee -a "$out/size.txt"
status=0
# QEMU's clock counts instructions (-icount): the periods at which the operator's commands
# land do not depend on how busy the host is.
timeout 120 qemu-system-arm -machine netduinoplus2 -nographic -semihosting-config enable=on,target=native \
  -icount shift=0,sleep=off -kernel "$rtic" > "$out/rtic.txt" || status=$?
grep -E "^cmd|pvfc rtic" "$out/rtic.txt"
if [ "$status" -ne 0 ]; then
  echo "the RTIC firmware exited with $status (a controller fault, or QEMU failed)" >&2
  exit 1
fi
PVFC_RTIC_TRACE="$out/rtic.txt" "$twin" --ignored --nocapture rtic_trace_matches_the_host_twin \
  2>&1 | grep -E "vs host|test result|panicked|assert" | tee "$out/rtic_twin.txt"
grep -q "test result: ok. 1 passed" "$out/rtic_twin.txt"
python3 scripts/firmware_instructions.py "$rtic" --symbol pvfc_drive_period --steps 1000 \
  | tee "$out/rtic_instructions.txt"

echo "--- hardware in the loop: the RTIC drive (--bin hil) on QEMU's USART1, the plant on the host"
# Lockstep over a Unix socket, 10,000 periods, one frame corrupted on purpose and one period
# skipped (tests/firmware_twin.rs, hil_run_matches_the_host_twin).
PVFC_HIL_FIRMWARE="$fw/target/thumbv7em-none-eabihf/release/hil" timeout 300 "$twin" --ignored --nocapture \
  hil_run_matches_the_host_twin 2>&1 | grep -E "^hil|host twin|test result|panicked|assert" | tee "$out/hil.txt"
grep -q "test result: ok. 1 passed" "$out/hil.txt"
# The same drive against pvfc-sim's plant with `pvfc hil` (scenarios/hil_scara.toml describes
# the firmware's drive): the MCAP log, the line's figures, and the host twin (the scenario's
# own drive, in f64) beside it.
timeout 300 "$pvfc" hil scenarios/hil_scara.toml --qemu "$fw/target/thumbv7em-none-eabihf/release/hil" \
  --corrupt-at 5000 --twin --out "$out/hil" | tee "$out/pvfc_hil.txt"
grep -q "10001 periods" "$out/pvfc_hil.txt"
grep -q "corrupted on purpose 1, unread by the drive 1," "$out/pvfc_hil.txt"
test -s "$out/hil/logs/hil_scara-hil.mcap"
python3 - "$out/pvfc_hil.txt" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
dq = float(re.search(r"largest \|Δq\| ([0-9.e+-]+) rad", text).group(1))
# The firmware's f32 drive against the host's f64 one: within the f32 twin's own distance
# from the f64 one (tests/firmware_twin.rs measures 1.3e-3 rad on the firmware's plant).
assert dq < 2e-3, f"pvfc hil: the firmware is {dq} rad from the host twin"
print(f"pvfc hil: the firmware within {dq:.2e} rad of the host twin")
PY
