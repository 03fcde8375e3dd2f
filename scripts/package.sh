#!/usr/bin/env bash
# The crates as crates.io would receive them: `cargo publish --dry-run` packages every crate
# from its own files (in dependency order, each verified by a build against the others'
# packages), then the `pvfc` command is installed from its packaged crate (its dependencies
# the packaged pvfc crates, not the workspace) and run from a folder outside the repository:
# `--version`, `presets`, and a UR5 scenario whose URDF comes from the packaged pvfc-sim.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_INCREMENTAL=0

crates=(pvfc-core pvfc-workspace-hack pvfc-control pvfc-sim pvfc-c pvfc-cli)
packages=()
for c in "${crates[@]}"; do packages+=(-p "$c"); done
version=$(cargo metadata --format-version 1 --no-deps \
  | python3 -c "import json,sys; print(next(p['version'] for p in json.load(sys.stdin)['packages'] if p['name']=='pvfc-cli'))")
# The verification extracts each packaged crate into cargo's registry folder and does not
# extract again a name and version it finds there: a second run on one machine would verify
# against the first run's sources. They are removed first.
for c in "${crates[@]}"; do
  rm -rf "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/"$c-$version"
done
cargo publish --locked --dry-run --allow-dirty "${packages[@]}"

# The core's docs as docs.rs builds them ([package.metadata.docs.rs]: every feature).
RUSTDOCFLAGS="-D warnings" cargo doc --locked --no-deps -p pvfc-core --all-features

pkg="$PWD/target/package"
patches=()
for c in pvfc-core pvfc-workspace-hack pvfc-control pvfc-sim; do
  patches+=(--config "patch.crates-io.$c.path=\"$pkg/$c-$version\"")
done
root=$(mktemp -d)
outside=$(mktemp -d)
# The debug profile: the dry run's verification already compiled every dependency in it.
CARGO_TARGET_DIR="$PWD/target" cargo install --locked --debug --path "$pkg/pvfc-cli-$version" \
  --root "$root" "${patches[@]}"
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
echo "every crate packages and verifies; pvfc $version installs from its packaged crate and runs outside the repository"
