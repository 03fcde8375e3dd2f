#!/usr/bin/env bash
# All the tests: the Rust workspace (cargo test), the C ABI from C and C++ (GoogleTest; under
# valgrind and the sanitizers), the CMake package, the Python wheel built into a fresh virtual
# environment, the C++ torque loop on MuJoCo and Pinocchio's C++ beside pvfc (from the wheels),
# the same examples in Rust, Python and C++ printing the same numbers, the pytest suite and
# the stub check (mypy.stubtest).
# Needs Rust (rustup), a C and a C++ compiler, CMake, and Python ≥ 3.9 with venv; installs the
# Python packages itself. Uses valgrind, GoogleTest, Eigen and urdfdom's headers when they are
# installed (required with PVFC_REQUIRE_VALGRIND=1, as in CI).
set -euo pipefail
cd "$(dirname "$0")/.."
stage() { echo "=== $* (${SECONDS} s so far)"; }

stage "cargo test"
# One build of the tests, whose artifacts the C stage links: cargo compiles pvfc-c's library
# once with all its crate types (rlib, staticlib, cdylib) and the features the tests resolve;
# a separate `cargo build -p pvfc-c` would resolve other features and compile it and its
# dependencies again (3 minutes on 2 cores).
mkdir -p target/c
cargo test --locked --no-run --message-format=json-render-diagnostics >target/c/test-build.json
cargo test --locked

stage "C and C++: the C ABI (crates/pvfc-c) from C and from C++ (GoogleTest), with sanitizers and under valgrind"
# The static library that `cargo test` built.
clib=$(python3 scripts/cargo_artifact.py pvfc_c .a < target/c/test-build.json)
test -s "$clib" || { echo "cargo test did not build pvfc-c's static library" >&2; exit 1; }
cc -std=c99 -Wall -Wextra -Werror -pedantic crates/pvfc-c/tests/c/test_pvfc.c \
  -Icrates/pvfc-c/include "$clib" -lm -lpthread -ldl -o target/c/test_pvfc
# The real-time calls make no system call (seccomp's strict mode kills the process if one
# does; natively, as valgrind makes system calls of its own).
cc -std=gnu99 -Wall -Wextra -Werror crates/pvfc-c/tests/c/test_no_syscall.c \
  -Icrates/pvfc-c/include "$clib" -lm -lpthread -ldl -o target/c/test_no_syscall
target/c/test_no_syscall models/ur5/ur5_robot.urdf
# The set-up (a robot, three controllers, a Cartesian contour) runs in a thread of 128 KiB of
# stack, musl's default (a release build needs 96 KiB), the real-time calls in one of 32 KiB
# (they need 24 KiB).
cc -std=c99 -Wall -Wextra -Werror -pedantic crates/pvfc-c/tests/c/test_stack.c \
  -Icrates/pvfc-c/include "$clib" -lm -lpthread -ldl -o target/c/test_stack
target/c/test_stack models/ur5/ur5_robot.urdf 128 32
# The header also compiles as C++ (cbindgen's cpp_compat).
c++ -std=c++17 -Wall -Wextra -Werror -fsyntax-only -x c++ crates/pvfc-c/include/pvfc.h
c_tests=(target/c/test_pvfc)
# The C++ header (pvfc.hpp) with GoogleTest (Debian's libgtest-dev), when it is installed,
# and with Eigen's vectors and maps when Debian's libeigen3-dev is.
eigen=()
[ -f /usr/include/eigen3/Eigen/Core ] && eigen=(-I/usr/include/eigen3)

if [ -f /usr/include/gtest/gtest.h ]; then
  c++ -std=c++17 -Wall -Wextra -Werror "${eigen[@]}" -Icrates/pvfc-c/include crates/pvfc-c/tests/cpp/test_pvfc.cpp \
    "$clib" -lgtest -lgtest_main -lpthread -ldl -lm -o target/c/test_pvfc_cpp
  c_tests+=(target/c/test_pvfc_cpp)
elif [ -n "${PVFC_REQUIRE_VALGRIND:-}" ]; then
  echo "GoogleTest (libgtest-dev) is needed in CI" >&2
  exit 1
else
  echo "GoogleTest not found: skipping the C++ tests"
fi
export PVFC_UR5_URDF=models/ur5/ur5_robot.urdf
# The same tests with AddressSanitizer and UndefinedBehaviorSanitizer (leaks included).
asan=(-g -fsanitize=address,undefined -fno-omit-frame-pointer)
cc -std=c99 "${asan[@]}" crates/pvfc-c/tests/c/test_pvfc.c -Icrates/pvfc-c/include \
  "$clib" -lm -lpthread -ldl -o target/c/test_pvfc_asan
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1 \
  target/c/test_pvfc_asan models/ur5/ur5_robot.urdf
if [ -f target/c/test_pvfc_cpp ]; then
  c++ -std=c++17 "${asan[@]}" "${eigen[@]}" -Icrates/pvfc-c/include crates/pvfc-c/tests/cpp/test_pvfc.cpp \
    "$clib" -lgtest -lgtest_main -lpthread -ldl -lm -o target/c/test_pvfc_cpp_asan
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1 target/c/test_pvfc_cpp_asan >/dev/null
fi
# Runs a program under valgrind (no error, no leak) when it is installed.
run_checked() {
  if command -v valgrind >/dev/null; then
    valgrind --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite,indirect \
      --quiet ${VALGRIND_EXTRA:-} "$@"
  elif [ -n "${PVFC_REQUIRE_VALGRIND:-}" ]; then
    echo "valgrind is needed (PVFC_REQUIRE_VALGRIND is set)" >&2
    exit 1
  else
    echo "valgrind not found: running $1 without it"
    "$@"
  fi
}
for t in "${c_tests[@]}"; do
  run_checked "$t" models/ur5/ur5_robot.urdf
done

stage "CMake: install the pvfc package, then find_package(pvfc) from a project outside the tree"
prefix="$PWD/target/cmake-install"
rm -rf target/cmake-build "$prefix"
cmake -S crates/pvfc-c -B target/cmake-build -DCMAKE_INSTALL_PREFIX="$prefix" >/dev/null
cmake --build target/cmake-build
cmake --install target/cmake-build >/dev/null
# One version: the package's version file and the shared library's soname (crates/pvfc-c/build.rs).
version=$(sed -n '/^\[workspace.package\]/,/^\[/s/^version = "\(.*\)"/\1/p' Cargo.toml)
grep -q "set(PACKAGE_VERSION \"$version\")" "$(find "$prefix" -name pvfcConfigVersion.cmake)" \
  || { echo "the CMake package's version is not $version" >&2; exit 1; }
so=$(find "$prefix" -name "libpvfc_c.so.$version")
soname=$(objdump -p "$so" | awk '/SONAME/ {print $2}')
test "$soname" = "libpvfc_c.so.${version%.*}" || { echo "libpvfc_c's soname is '$soname'" >&2; exit 1; }
test "$(readlink "$(dirname "$so")/libpvfc_c.so")" = "$soname" || { echo "libpvfc_c.so is not a link to $soname" >&2; exit 1; }
# The versioned binary package (CPack): pvfc-VERSION-Linux-ARCH.tar.gz, unpacked elsewhere and
# used by the examples below through CMAKE_PREFIX_PATH, like the installed tree.
(cd target/cmake-build && cpack -G TGZ >/dev/null)
tarball=$(ls target/cmake-build/pvfc-"$version"-Linux-*.tar.gz)
unpacked=$(mktemp -d)
tar xzf "$tarball" -C "$unpacked"
tar_prefix=$(ls -d "$unpacked"/pvfc-"$version"-Linux-*)
rm -rf target/cmake-example-tarball
cmake -S examples/cpp -B target/cmake-example-tarball -DCMAKE_PREFIX_PATH="$tar_prefix" -DPVFC_STATIC=OFF >/dev/null
cmake --build target/cmake-example-tarball >/dev/null
target/cmake-example-tarball/ur5_contour models/ur5/ur5_robot.urdf >/dev/null
objdump -p target/cmake-example-tarball/ur5_contour | grep -q "NEEDED *$soname" \
  || { echo "the example does not load the library by its soname" >&2; exit 1; }
echo "CMake package $version: soname $soname, $(basename "$tarball")"
for static in OFF ON; do
  rm -rf "target/cmake-example-$static"
  cmake -S examples/cpp -B "target/cmake-example-$static" -DCMAKE_PREFIX_PATH="$prefix" \
    -DPVFC_STATIC="$static" >/dev/null
  cmake --build "target/cmake-example-$static" >/dev/null
  run_checked "target/cmake-example-$static/ur5_contour" models/ur5/ur5_robot.urdf
done

stage "Python: the manylinux wheel and the sdist (maturin, zig), the wheel into a fresh virtual environment"
# The wheel users install: manylinux2014 (glibc 2.17), linked by zig's toolchain (maturin
# --zig; the ziglang package from PyPI) so that it runs on older Linux than the building
# machine's (built natively here, it would need glibc 2.34). maturin checks the tag's symbols.
build_venv=target/py-build
[ -x "$build_venv/bin/maturin" ] || { rm -rf "$build_venv"; python3 -m venv "$build_venv"; }
"$build_venv/bin/python" -m pip install --quiet maturin==1.16.0 ziglang==0.17.1
rm -rf target/wheels
PATH="$PWD/$build_venv/bin:$PATH" maturin build --release --locked --zig --compatibility manylinux2014 \
  -m crates/pvfc-py/Cargo.toml -o target/wheels
PATH="$PWD/$build_venv/bin:$PATH" maturin sdist -m crates/pvfc-py/Cargo.toml -o target/wheels
wheel=$(ls target/wheels/pvfc-*-cp39-abi3-manylinux*.whl)
case "$wheel" in
  *manylinux_2_17_x86_64.whl | *manylinux_2_17_aarch64.whl) echo "wheel: $wheel" ;;
  *) echo "the wheel's tag is not manylinux_2_17: $wheel" >&2; exit 1 ;;
esac
sdist=$(ls target/wheels/pvfc-*.tar.gz)
venv="${PVFC_VENV:-target/py-venv}"
rm -rf "$venv"
python3 -m venv "$venv"
py="$(cd "$venv" && pwd)/bin/python"   # absolute: the pytest stage runs from another directory
"$py" -m pip install --quiet --upgrade pip
"$py" -m pip install --quiet "$wheel[test,reference]"
"$py" -c "import pvfc, numpy; print('pvfc', pvfc.__version__, 'numpy', numpy.__version__)"

stage "The release builds of the stages below: the pvfc command and the side-by-side examples"
# Built here, before the suites below start, so that the command they run is ready.
cargo build --locked --release --bin pvfc --example scara_contour --example ur5_tool_path \
  --example part_program

stage "The wheel on the oldest and the newest CPython it claims (3.9, 3.13), with no Rust on the path: started"
# pyenv's interpreters; the reference packages as binary wheels only (on 3.9 the newest
# Pinocchio and MuJoCo with a wheel for it). The parity tests use the pvfc command built above
# (PVFC_CLI). Both suites run in the background, each into its own log, beside the stages
# below (whose programs leave a core idle most of the time), and their results are shown at the
# end; each is a process group of its own, stopped if this script stops first. The hour-long
# MuJoCo energy loop runs in the pytest stage below only (it checks the controller, not the
# interpreter).
export wheel
wheel_on() {
  local version=$1 base=$2
  local v_env="$PWD/target/py-venv-$version"
  rm -rf "$v_env"
  "$base/bin/python3" -m venv "$v_env"
  "$v_env/bin/python" -m pip install --quiet --upgrade pip
  "$v_env/bin/python" -m pip install --quiet --only-binary=:all: "$wheel[test,reference]"
  (cd crates/pvfc-py && env PATH="$v_env/bin:/usr/bin:/bin" PVFC_CLI="$PWD/../../target/release/pvfc" \
    timeout --kill-after=30 900 "$v_env/bin/python" -m pytest -q -p no:cacheprovider --benchmark-disable \
      -k "not for_an_hour")
}
pids=()
versions=()
trap 'for p in "${pids[@]}"; do kill -- "-$p" 2>/dev/null || true; done' EXIT
for version in 3.9 3.13; do
  base=""
  if command -v pyenv >/dev/null; then
    base=$(ls -d "$(pyenv root)/versions/$version".* 2>/dev/null | sort -V | tail -n 1 || true)
  fi
  if [ -z "$base" ] || [ ! -x "$base/bin/python3" ]; then
    if [ -n "${PVFC_REQUIRE_VALGRIND:-}" ]; then
      echo "CPython $version (pyenv) is needed in CI" >&2
      exit 1
    fi
    echo "CPython $version not found (pyenv): skipping the wheel's tests on it"
    continue
  fi
  setsid bash -c "$(declare -f wheel_on); wheel_on $(printf %q "$version") $(printf %q "$base")" >"target/py-$version.log" 2>&1 &
  pids+=("$!")
  versions+=("$version")
done

stage "MuJoCo: the C++ torque loop (examples/cpp/mujoco_ur5.cpp) on the mujoco wheel's library"
mujoco_dir=$("$py" -c "import mujoco, os; print(os.path.dirname(mujoco.__file__))")
# Builds the MuJoCo example into $1 against the pvfc package installed in $2.
build_mujoco_example() {
  rm -rf "$1"
  cmake -S examples/cpp -B "$1" -DCMAKE_PREFIX_PATH="$2" \
    -DPVFC_STATIC=ON -DMUJOCO_DIR="$mujoco_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$1" >/dev/null
}
build_mujoco_example target/cmake-example-mujoco "$prefix"
# 30 s of the loop: convergence onto the path, the energy balance, no allocation in update().
target/cmake-example-mujoco/mujoco_ur5 models/ur5/ur5_robot.urdf 30 | tee target/mujoco-portable.txt
# The package built for x86-64-v3 (-DPVFC_TARGET_CPU) computes the same bits: checked by
# scripts/same_bits_x86_64_v3.sh after this script (a second release build of the library and
# its dependencies, three minutes that CI does not spend); CI checks that pvfc's sources choose
# no code by the processor's features (.ci/run).
# Under valgrind, 1 s of it. The example counts allocations by replacing the global operator
# new with malloc; valgrind's own operator new in libstdc++ then looks mismatched with our
# free, which is not an error of the program.
VALGRIND_EXTRA=--show-mismatched-frees=no run_checked \
  target/cmake-example-mujoco/mujoco_ur5 models/ur5/ur5_robot.urdf 1

stage "Pinocchio's C++ beside pvfc's C ABI (benches/cpp): the same M, C, g and RNEA, and the timing table"
if [ -f /usr/include/eigen3/Eigen/Core ] && [ -f /usr/include/urdf_model/model.h ]; then
  cmeel_prefix=$("$py" -c "import cmeel, os; print(os.path.join(os.path.dirname(os.path.dirname(cmeel.__file__)), 'cmeel.prefix'))")
  rm -rf target/cmake-bench
  # (Quiet: CMake 3.25 warns about every component of the wheel's newer Boost.)
  cmake -S benches/cpp -B target/cmake-bench -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix;$cmeel_prefix" -Wno-dev >target/cmake-bench.log 2>&1 \
    || { cat target/cmake-bench.log; exit 1; }
  cmake --build target/cmake-bench >/dev/null
  # A short run: it fails if the two libraries' M, C, g or RNEA differ (the timing is a
  # benchmark's: run it alone, with the default 1,000 states and 31 rounds, to quote it).
  target/cmake-bench/dynamics_vs_pinocchio models 200 5
elif [ -n "${PVFC_REQUIRE_VALGRIND:-}" ]; then
  echo "Eigen and urdfdom's headers (libeigen3-dev, liburdfdom-headers-dev) are needed in CI" >&2
  exit 1
else
  echo "Eigen or urdfdom's headers not found: skipping the Pinocchio benchmark"
fi

stage "The same examples in Rust, Python and C++ (examples/side_by_side): the same numbers"
rm -rf target/cmake-side
cmake -S examples/side_by_side -B target/cmake-side -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build target/cmake-side >/dev/null
# Each entry: the program, the URDF, the tip (the part program on the UR5 and on the Panda).
for example in scara_contour:models/scara.urdf: ur5_tool_path:models/ur5/ur5_robot.urdf: \
  part_program:models/ur5/ur5_robot.urdf:tool0 \
  part_program:models/panda/panda.urdf:panda_hand_tcp; do
  IFS=: read -r name urdf tip <<<"$example"
  args=("$urdf")
  if [ -n "$tip" ]; then args+=("$tip"); fi
  out=target/side-by-side-$name-$(basename "$urdf" .urdf)
  "target/release/examples/$name" "${args[@]}" >"$out-rust.txt"
  "$py" "examples/side_by_side/$name.py" "${args[@]}" >"$out-python.txt"
  "target/cmake-side/$name" "${args[@]}" >"$out-cpp.txt"
  python3 scripts/same_output.py "$out-rust.txt" "$out-python.txt" "$out-cpp.txt"
  run_checked "target/cmake-side/$name" "${args[@]}" >/dev/null
done

stage "pytest"
# Bounded: a hung test fails the stage (after pytest's faulthandler has printed where it hangs).
(cd crates/pvfc-py && timeout --kill-after=30 1200 "$py" -m pytest -q -p no:cacheprovider --durations=10)

stage "stubtest"
"$py" -m mypy.stubtest pvfc

stage "The sdist builds from source (into a wheel, installed and imported)"
# The Rust dependencies of the release build above are reused (CARGO_TARGET_DIR).
rm -rf target/sdist-wheel target/py-venv-sdist
CARGO_TARGET_DIR="$PWD/target" "$py" -m pip wheel --quiet --no-deps "$sdist" -w target/sdist-wheel
python3 -m venv target/py-venv-sdist
target/py-venv-sdist/bin/python -m pip install --quiet target/sdist-wheel/pvfc-*.whl
repo=$PWD
(cd "$(mktemp -d)" && "$repo/target/py-venv-sdist/bin/python" -c "
import pvfc
r = pvfc.Robot.from_urdf('$repo/models/ur5/ur5_robot.urdf', tip='tool0')
print('pvfc', pvfc.__version__, 'from the sdist:', r.dof, 'joints')")

stage "The wheel on CPython 3.9 and 3.13: the results"
failed=0
for i in "${!pids[@]}"; do
  if wait "${pids[$i]}"; then
    echo "CPython ${versions[$i]}: $(tail -n 1 "target/py-${versions[$i]}.log")"
  else
    echo "CPython ${versions[$i]}: the wheel's tests failed:" >&2
    cat "target/py-${versions[$i]}.log" >&2
    failed=1
  fi
done
pids=()
[ "$failed" = 0 ] || exit 1

stage "done"
