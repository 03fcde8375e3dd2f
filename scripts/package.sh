#!/usr/bin/env bash
# The crates as crates.io would receive them: `cargo publish --dry-run` packages every crate
# from its own files (in dependency order, each against the others' packages); then every
# packaged crate is built from its package alone, each once (cargo's own verification builds
# every crate again as a dependency of the next: pvfc-sim's and pvfc-control's twice): the
# `pvfc` command is installed from its packaged crate (its dependencies the packaged pvfc
# crates, not the workspace) and run from a folder outside the repository (`--version`,
# `presets`, and a UR5 scenario whose URDF comes from the packaged pvfc-sim), and the C
# library is built from its packaged crate.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_INCREMENTAL=0
# The builds below run the packaged command once and check that the C library links: no debug
# information (this script in a fresh clone on 2 AMD EPYC cores: 185 → 170 s).
export CARGO_PROFILE_DEV_DEBUG=0

crates=(pvfc-core pvfc-workspace-hack pvfc-link pvfc-control pvfc-sim pvfc-c pvfc-cli)
packages=()
for c in "${crates[@]}"; do packages+=(-p "$c"); done
version=$(cargo metadata --format-version 1 --no-deps \
  | python3 -c "import json,sys; print(next(p['version'] for p in json.load(sys.stdin)['packages'] if p['name']=='pvfc-cli'))")
# A packaged crate is unpacked only where no folder of its name is (an earlier run's would
# stay): they are removed first.
for c in "${crates[@]}"; do
  rm -rf "target/package/$c-$version" "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/"$c-$version"
done
cargo publish --locked --dry-run --allow-dirty --no-verify "${packages[@]}"
# The same packages as files (target/package/NAME-VERSION.crate), unpacked to be built.
cargo package --locked --allow-dirty --no-verify "${packages[@]}"
for c in "${crates[@]}"; do
  # Touched: cargo judges a path dependency fresh by its files' times, and a packaged file
  # keeps its time in the archive, older than an earlier build of the same version.
  tar -xzf "target/package/$c-$version.crate" -C target/package --touch
done

# The core's docs as docs.rs builds them ([package.metadata.docs.rs]: every feature).
RUSTDOCFLAGS="-D warnings" cargo doc --locked --no-deps -p pvfc-core --all-features

pkg="$PWD/target/package"
patches=()
for c in pvfc-core pvfc-workspace-hack pvfc-link pvfc-control pvfc-sim; do
  patches+=(--config "patch.crates-io.$c.path=\"$pkg/$c-$version\"")
done
root=$(mktemp -d)
outside=$(mktemp -d)
# The debug profile: the dependencies are those of the builds above.
CARGO_TARGET_DIR="$PWD/target" cargo install --locked --debug --path "$pkg/pvfc-cli-$version" \
  --root "$root" "${patches[@]}"
# A library's package has no Cargo.lock: the workspace's pins its dependencies' versions (cargo
# only drops the entries it does not need).
cp Cargo.lock "$pkg/pvfc-c-$version/Cargo.lock"
CARGO_TARGET_DIR="$PWD/target" cargo build --manifest-path "$pkg/pvfc-c-$version/Cargo.toml" \
  "${patches[@]}"
(
  cd "$outside"
  test "$("$root/bin/pvfc" --version)" = "pvfc $version" || { echo "pvfc --version is not $version" >&2; exit 1; }
  "$root/bin/pvfc" presets --out scenarios >/dev/null
  test -s scenarios/fig9_R100.toml || { echo "pvfc presets wrote no fig9_R100.toml" >&2; exit 1; }
  # The packaged pvfc-sim carries the scenarios and the URDFs they name.
  "$root/bin/pvfc" run "$pkg/pvfc-sim-$version/scenarios/example_urdf_arm.toml" --out run
  test -s run/logs/example_urdf_arm.mcap || { echo "the installed pvfc wrote no log" >&2; exit 1; }
)
rm -rf "$root" "$outside"
echo "every crate packages and builds from its package; pvfc $version installs from its packaged crate and runs outside the repository"
