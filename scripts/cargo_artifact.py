"""Prints the path of one artifact from cargo's `--message-format=json` output on stdin.

    cargo test --no-run --message-format=json | python3 scripts/cargo_artifact.py NAME KIND

NAME is the target's name (`pvfc_c`, `firmware_twin`, `pvfc`); KIND is `exe` (its executable,
a test's harness included), `bin` (a binary target's own executable, not its unit tests') or
a file suffix such as `.a` (its static library). Prints nothing when cargo did not build it.
"""
import json
import sys


def main() -> None:
    name, kind = sys.argv[1], sys.argv[2]
    found: list = []
    # Reads to the end even after a match: closing the pipe early would fail cargo's writes.
    for line in sys.stdin:
        m = json.loads(line)
        if found or m.get("reason") != "compiler-artifact" or m["target"]["name"] != name:
            continue
        if kind == "bin":
            own = "bin" in m["target"]["kind"] and not m["profile"]["test"]
            found = [m["executable"]] if own and m.get("executable") else []
        elif kind == "exe":
            found = [m["executable"]] if m.get("executable") else []
        else:
            found = [f for f in m.get("filenames") or [] if f.endswith(kind)]
    if found:
        print(found[0])


if __name__ == "__main__":
    main()
