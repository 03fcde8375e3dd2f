#!/usr/bin/env bash
# The C library built for x86-64-v3 (-DPVFC_TARGET_CPU=x86-64-v3) computes the same bits as
# the portable build: the MuJoCo loop of examples/cpp/mujoco_ur5.cpp, linked against each,
# prints the same 30 s of text (its energy residuals, ~1e-12 J, are rounding noise that any
# changed bit would move). Run after `bash scripts/test.sh`, whose MuJoCo stage leaves the
# portable package (target/cmake-install), the Python environment with MuJoCo
# (target/py-venv) and the portable loop's output (target/mujoco-portable.txt). A second
# release build of the library and its dependencies (about three minutes on two cores).
set -euo pipefail
cd "$(dirname "$0")/.."

for f in avx avx2 bmi1 bmi2 f16c fma abm movbe xsave; do
  if [ "$(uname -m)" != x86_64 ] || ! grep -qw "$f" /proc/cpuinfo; then
    echo "this processor lacks x86-64-v3's instructions ($f): the build for it cannot run here" >&2
    exit 1
  fi
done
py="${PVFC_VENV:-target/py-venv}/bin/python"
for need in "$py" target/mujoco-portable.txt target/cmake-install; do
  [ -e "$need" ] || { echo "$need is missing: run bash scripts/test.sh first" >&2; exit 1; }
done
mujoco_dir=$("$py" -c "import mujoco, os; print(os.path.dirname(mujoco.__file__))")
prefix="$PWD/target/cmake-install-x86-64-v3"
rm -rf target/cmake-build-x86-64-v3 "$prefix" target/cmake-example-mujoco-v3
cmake -S crates/pvfc-c -B target/cmake-build-x86-64-v3 -DPVFC_TARGET_CPU=x86-64-v3 \
  -DCMAKE_INSTALL_PREFIX="$prefix" >/dev/null
cmake --build target/cmake-build-x86-64-v3 >/dev/null
cmake --install target/cmake-build-x86-64-v3 >/dev/null
cmake -S examples/cpp -B target/cmake-example-mujoco-v3 -DCMAKE_PREFIX_PATH="$prefix" \
  -DPVFC_STATIC=ON -DMUJOCO_DIR="$mujoco_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build target/cmake-example-mujoco-v3 >/dev/null
target/cmake-example-mujoco-v3/mujoco_ur5 models/ur5/ur5_robot.urdf 30 >target/mujoco-v3.txt
diff target/mujoco-portable.txt target/mujoco-v3.txt \
  || { echo "pvfc built for x86-64-v3 computes other numbers than the portable build" >&2; exit 1; }
echo "pvfc built for x86-64-v3: the same 30 s of the MuJoCo loop, to the printed digit"
