#!/usr/bin/env python3
"""Compares `pvfc reproduce`'s summary with its reference by tolerance, not by bytes.

    python3 scripts/compare_summary.py REFERENCE NEW [--subset]

REFERENCE and NEW are a summary's CSV (`summary.csv`: id, statement, measure, measured, holds)
or its Markdown table (`summary.md`, the manual's `docs/src/reference/results.md`: claim,
holds, statement, measure, measured). Every claim of REFERENCE must be in NEW with the same
verdict, statement and measure, and the numbers of its measured text must agree one by one
(the same count), each within the tolerance of its kind:

- an integration residual or an audit (a number whose reference is below 1e-6 in magnitude,
  or printed with an exponent of -6 or less): within a decade of the reference (a factor of
  ten either way), or both at most 1e-12 (rounding noise); its verdict, above, says it stays
  below its limit;
- any other number (a state, a force, an error, a speed, a count): within 1e-6 relative of
  the reference or one unit of its last printed digit, whichever is larger.

Without --subset, NEW must not have claims REFERENCE lacks either (regenerate the reference:
`pvfc reproduce --out results` and copy `results/summary.md` to the manual). Prints a line
per row and number that moved, naming them, and exits 1 if any did; 0 otherwise.
"""

import csv
import math
import re
import sys
from pathlib import Path
from typing import Dict, List, NamedTuple, Tuple

NUMBER = re.compile(r"[+-]?\d+(?:\.\d+)?(?:e[+-]?\d+)?")
RESIDUAL = 1e-6
NOISE = 1e-12


class Claim(NamedTuple):
    statement: str
    measure: str
    measured: str
    holds: bool


def read(path: Path) -> Dict[str, Claim]:
    """The claims of a summary, by id, from its CSV or its Markdown table."""
    text = path.read_text(encoding="utf-8")
    claims: Dict[str, Claim] = {}
    if path.suffix == ".csv":
        for row in csv.DictReader(text.splitlines()):
            claims[row["id"]] = Claim(
                row["statement"], row["measure"], row["measured"], row["holds"] == "true"
            )
        return claims
    for line in text.splitlines():
        if not line.startswith("| ") or line.startswith("| claim |"):
            continue
        cells = [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", line)[1:-1]]
        if len(cells) != 5:
            raise ValueError(f"{path}: a row of {len(cells)} cells: {line[:60]}")
        claim, holds, statement, measure, measured = cells
        claims[claim] = Claim(statement, measure, measured, holds == "yes")
    return claims


def numbers(text: str) -> List[str]:
    """The numbers of a measured text, as printed."""
    return NUMBER.findall(text)


def unit(token: str) -> float:
    """One unit of the last printed digit of `token`."""
    mantissa, _, exponent = token.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 10.0 ** (int(exponent or 0) - decimals)


def is_residual(token: str) -> bool:
    value = abs(float(token))
    exponent = token.lower().partition("e")[2]
    return (0.0 < value < RESIDUAL) or (exponent != "" and int(exponent) <= -6)


def agree(ref: str, new: str) -> Tuple[bool, str]:
    """Whether `new` is within the tolerance of `ref`'s kind, and that tolerance in words."""
    a, b = float(ref), float(new)
    if is_residual(ref):
        if abs(a) <= NOISE and abs(b) <= NOISE:
            return True, "rounding noise"
        ok = a != 0.0 and b != 0.0 and (a > 0) == (b > 0) and 0.1 <= b / a <= 10.0
        return ok, "within a decade (a residual)"
    allowed = max(RESIDUAL * abs(a), unit(ref))
    return abs(a - b) <= allowed * (1 + 1e-9), f"±{allowed:.3g} (the printed precision)"


def compare(reference: Dict[str, Claim], new: Dict[str, Claim], subset: bool) -> List[str]:
    """The differences that break the tolerance, one message each."""
    out: List[str] = []
    for cid, ref in reference.items():
        got = new.get(cid)
        if got is None:
            out.append(f"{cid}: the claim is missing")
            continue
        if got.holds != ref.holds:
            verdict = "holds" if got.holds else "does not hold"
            out.append(f"{cid}: the verdict changed: it now {verdict}")
        for what, r, g in [("statement", ref.statement, got.statement), ("measure", ref.measure, got.measure)]:
            if r != g:
                out.append(f"{cid}: the {what} changed")
        rn, gn = numbers(ref.measured), numbers(got.measured)
        if len(rn) != len(gn):
            out.append(f"{cid}: {len(gn)} numbers in the measured text, the reference has {len(rn)}")
            continue
        for i, (r, g) in enumerate(zip(rn, gn), start=1):
            ok, tolerance = agree(r, g)
            if not ok:
                out.append(f"{cid}: number {i} moved from {r} to {g}, beyond {tolerance}")
    if not subset:
        for cid in new.keys() - reference.keys():
            out.append(f"{cid}: a claim the reference does not have (regenerate it)")
    return out


def main(argv: List[str]) -> int:
    args = [a for a in argv if not a.startswith("--")]
    if len(args) != 2 or any(a not in ("--subset",) for a in argv if a.startswith("--")):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    reference, new = read(Path(args[0])), read(Path(args[1]))
    problems = compare(reference, new, "--subset" in argv)
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print(
            f"{len(problems)} difference(s) between {args[1]} and its reference {args[0]} "
            "beyond the tolerances (a deliberate change regenerates the reference)",
            file=sys.stderr,
        )
        return 1
    print(f"{args[1]}: every claim of {args[0]} within its tolerances ({len(reference)} claims)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
