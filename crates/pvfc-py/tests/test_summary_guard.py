"""The guard of `pvfc reproduce`'s summary by tolerance (`scripts/compare_summary.py`, run by
`.ci/run`): it passes the reference itself and changes within each kind's tolerance, and it
fails, naming the row and the number, on a verdict that flips, a number beyond its printed
precision, a residual that moves more than a decade, a lost or a new claim."""

import importlib.util
import pathlib

REPO = pathlib.Path(__file__).resolve().parents[3]
spec = importlib.util.spec_from_file_location("compare_summary", REPO / "scripts" / "compare_summary.py")
assert spec is not None and spec.loader is not None
guard = importlib.util.module_from_spec(spec)
spec.loader.exec_module(guard)

Claim = guard.Claim


def ref() -> dict:
    return {
        "fig6": Claim("s", "m", "κ_a 50.0 → 14.9 J; U 1.93e-2 → 3.48e-2", True),
        "contact.audit": Claim("s", "m", "wall: 4.8e-9, push: 6.3e-11 (largest 4.6e-4)", True),
        "fig1": Claim("s", "m", "PVFC: mean 1.48e-2 rad, max 3.19e-2", False),
    }


def with_measured(cid: str, text: str) -> dict:
    new = ref()
    new[cid] = new[cid]._replace(measured=text)
    return new


def problems(new: dict, subset: bool = False) -> list:
    return guard.compare(ref(), new, subset)


def test_the_reference_and_changes_within_tolerance_pass() -> None:
    assert problems(ref()) == []
    # The last printed digit moves by one; a residual moves by less than a decade.
    assert problems(with_measured("fig6", "κ_a 50.0 → 15.0 J; U 1.94e-2 → 3.47e-2")) == []
    assert problems(with_measured("contact.audit", "wall: 2.1e-8, push: 9.9e-12 (largest 4.6e-4)")) == []


def test_a_number_beyond_its_printed_precision_is_named() -> None:
    out = problems(with_measured("fig6", "κ_a 50.0 → 15.1 J; U 1.93e-2 → 3.48e-2"))
    assert out == ["fig6: number 2 moved from 14.9 to 15.1, beyond ±0.1 (the printed precision)"]


def test_a_residual_beyond_a_decade_or_of_the_other_sign_is_named() -> None:
    out = problems(with_measured("contact.audit", "wall: 5.0e-8, push: 6.3e-11 (largest 4.6e-4)"))
    assert len(out) == 1 and out[0].startswith("contact.audit: number 1 moved from 4.8e-9 to 5.0e-8")
    out = problems(with_measured("contact.audit", "wall: -4.8e-9, push: 6.3e-11 (largest 4.6e-4)"))
    assert len(out) == 1 and "a residual" in out[0]
    # Below 1e-12 both ways: rounding noise.
    assert guard.agree("1.5e-14", "-8.0e-13")[0]


def test_a_verdict_a_text_a_lost_or_a_new_claim_is_named() -> None:
    new = ref()
    new["fig1"] = new["fig1"]._replace(holds=True)
    assert problems(new) == ["fig1: the verdict changed: it now holds"]
    new = ref()
    new["fig1"] = new["fig1"]._replace(statement="other")
    assert problems(new) == ["fig1: the statement changed"]
    new = ref()
    del new["fig6"]
    assert problems(new) == ["fig6: the claim is missing"]
    new = ref()
    new["extra"] = Claim("s", "m", "1", True)
    assert problems(new) == ["extra: a claim the reference does not have (regenerate it)"]
    assert problems(new, subset=True) == []
    assert problems(with_measured("fig6", "κ_a 50.0 → 14.9 J")) == [
        "fig6: 2 numbers in the measured text, the reference has 4"
    ]


def test_the_manuals_results_page_reads_as_its_csv() -> None:
    """The Markdown table and the CSV of a summary read the same (the page is the reference)."""
    page = guard.read(REPO / "docs" / "src" / "reference" / "results.md")
    round1 = guard.read(REPO / "docs" / "reproduce_summary_round1.csv")
    assert len(page) > len(round1) >= 18
    assert guard.compare(round1, page, subset=True) == []
