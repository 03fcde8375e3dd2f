"""The robot's kind, said once in a scenario (`[plant] kind`), from Python dicts and TOML."""

import warnings

import pytest

import pvfc

INERTIA = [[1.2, 0.05, 0.0], [0.05, 1.0, 0.02], [0.0, 0.02, 0.8]]
BODY = {
    "name": "sat",
    "duration": 1.0,
    "contour": {"attitude": {"rate": [0.2, 0.1, 0.5]}},
    "initial": {"q": [0.5, 0.0, 0.0], "v": [0.0, 0.0, 0.0]},
    "controller": {"h": [1.0, 2.0, 3.0], "self_pacing": 20.0, "energy": 20.0, "gamma": 0.1},
}


def test_the_kind_reads_back_from_a_dict() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = pvfc.Scenario.from_dict({**BODY, "plant": {"kind": "rigid_body", "inertia": INERTIA}})
    d = s.to_dict()
    assert d["plant"]["kind"] == "rigid_body"
    assert pvfc.Controller(s).robot == "rigid_body"


def test_the_form_before_kind_warns_and_reads_the_same() -> None:
    with pytest.warns(DeprecationWarning, match='kind = "rigid_body"'):
        old = pvfc.Scenario.from_dict({**BODY, "plant": {"rigid_body": {"inertia": INERTIA}}})
    new = pvfc.Scenario.from_dict({**BODY, "plant": {"kind": "rigid_body", "inertia": INERTIA}})
    assert old.to_dict() == new.to_dict()


def test_a_key_of_another_kind_is_named() -> None:
    with pytest.raises(pvfc.ScenarioError, match="plant.arm"):
        pvfc.Scenario.from_dict(
            {**BODY, "plant": {"kind": "rigid_body", "inertia": INERTIA, "arm": "pelican"}}
        )
