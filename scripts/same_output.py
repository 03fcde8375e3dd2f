#!/usr/bin/env python3
"""Checks that the side-by-side examples print the same numbers in every language.

    python3 scripts/same_output.py rust.txt python.txt cpp.txt

Each file is one program's output: a first line naming the program and its language, then
lines of `name value` pairs. Every line after the first must have the same names and the same
numbers (to 1e-9 relative, or 1e-15 absolute near zero: the programs print 7 significant
digits, and Rust spells exponents differently). Exits 1, naming the line and the value, if
they differ, and if a file is empty or shorter than another.
"""

import sys


def rows(path: str) -> list:
    with open(path, encoding="utf-8") as f:
        lines = [line.split() for line in f.read().splitlines() if line.strip()]
    if len(lines) < 2:
        sys.exit(f"{path}: no output after its first line")
    return lines[1:]


def main() -> int:
    files = sys.argv[1:]
    first = rows(files[0])
    bad = 0
    for other in files[1:]:
        them = rows(other)
        if len(them) != len(first):
            print(f"{other}: {len(them)} lines, {files[0]}: {len(first)}")
            bad += 1
            continue
        for n, (a, b) in enumerate(zip(first, them), start=2):
            if a[0::2] != b[0::2]:
                print(f"{other}:{n}: names {b[0::2]}, {files[0]}: {a[0::2]}")
                bad += 1
                continue
            for name, x, y in zip(a[0::2], a[1::2], b[1::2]):
                x, y = float(x), float(y)
                if abs(x - y) > max(1e-9 * max(abs(x), abs(y)), 1e-15):
                    print(f"{other}:{n}: {name} = {y}, {files[0]}: {x}")
                    bad += 1
    print(f"{len(files)} outputs, {len(first)} lines each: {bad} differences")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
