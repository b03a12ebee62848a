"""Designs: Table 1 defaults, validation with named errors, hashing, JSON/TOML round trips."""

import dataclasses
import json
import math
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from softcrawl.geometry.design import (
    DesignError,
    EPSADesign,
    FootDesign,
    RingDesign,
    RobotDesign,
    load_design,
)


def test_table1_defaults():
    r = RobotDesign()
    assert (r.epsa.length, r.epsa.outer_radius, r.epsa.chamber_radius, r.epsa.fiber_turns) == (100, 9, 3, 20)
    assert r.foot.groove_height == 1 and r.d == 14 and r.n_rings == 3
    assert r.epsa.fiber_diameter == 0.3
    assert r.foot.angle == 120
    assert r.max_diameter == 78 and r.bundle_diameter == 46  # prototype max/min diameters
    assert r.channel_radius == pytest.approx(5.0)


def test_analytic_helpers():
    e = EPSADesign()
    assert e.chamber_length == 90
    assert e.body_volume == pytest.approx(math.pi * (81 * 100 - 9 * 90))
    assert e.helix_length == pytest.approx(20 * math.sqrt((2 * math.pi * 9) ** 2 + (100 / 20) ** 2))
    assert EPSADesign(fiber_turns=0).helix_length == 100


BAD = [
    (EPSADesign, {"chamber_radius": 9.0}, "chamber_radius"),
    (EPSADesign, {"chamber_radius": 12.0}, "chamber_radius"),
    (EPSADesign, {"length": 0.0}, "length"),
    (EPSADesign, {"length": -5.0}, "length"),
    (EPSADesign, {"outer_radius": float("nan")}, "outer_radius"),
    (EPSADesign, {"fiber_turns": -1}, "fiber_turns"),
    (EPSADesign, {"fiber_turns": 2.5}, "fiber_turns"),
    (EPSADesign, {"fiber_diameter": 0.0}, "fiber_diameter"),
    (EPSADesign, {"end_cap_thickness": 50.0}, "end_cap_thickness"),
    (EPSADesign, {"seal_head_thickness": -1.0}, "seal_head_thickness"),
    (EPSADesign, {"length": "long"}, "length"),
    (EPSADesign, {"chamber_radius": True}, "chamber_radius"),
    (FootDesign, {"groove_height": 3.0}, "groove_height"),
    (FootDesign, {"angle": 200.0}, "angle"),
    (FootDesign, {"angle": 0.0}, "angle"),
    (FootDesign, {"n_grooves": 40}, "n_grooves"),
    (FootDesign, {"tip_radius": 20.0}, "tip_radius"),
    (FootDesign, {"hub_thickness": 2.0}, "hub_thickness"),
    (FootDesign, {"bore_radius": 30.0}, "bore_radius"),
    (RingDesign, {"outer_radius": 20.0}, "outer_radius"),
    (RingDesign, {"hole_radius": 13.0}, "hole_radius"),
    (RingDesign, {"bore_radius": 5.0}, "bore_radius"),
    (RobotDesign, {"d": 10.0}, "d"),  # actuators of radius 9 overlap at d = 10
    (RobotDesign, {"d": 0.0}, "d"),
    (RobotDesign, {"n_rings": 30}, "n_rings"),  # rings do not fit along the body
    (RobotDesign, {"n_rings": -1}, "n_rings"),
    (RobotDesign, {"foot": FootDesign(d=12.0)}, "foot.d"),
    (RobotDesign, {"ring": RingDesign(outer_radius=30.0)}, "ring.outer_radius"),  # 60 mm ring, 55 mm pipe
    (
        RobotDesign,
        {"foot": FootDesign(tip_radius=37.0)},
        "foot.tip_radius",
    ),  # 74 mm foot misses a 75 mm pipe wall
    (RobotDesign, {"foot": FootDesign(hub_radius=20.0, tip_radius=39.0)}, "foot.hub_radius"),
]


@pytest.mark.parametrize(
    "cls, kwargs, parameter", BAD, ids=[f"{c.__name__}-{p}-{i}" for i, (c, k, p) in enumerate(BAD)]
)
def test_invalid_designs_name_the_parameter(cls, kwargs, parameter):
    with pytest.raises(DesignError) as info:
        cls(**kwargs)
    assert info.value.parameter == parameter
    assert parameter in str(info.value)
    assert isinstance(info.value, ValueError)


def test_nested_errors_and_unknown_keys():
    with pytest.raises(DesignError) as info:
        RobotDesign.from_dict({"epsa": {"chamber_radius": 10}})
    assert info.value.parameter == "epsa.chamber_radius"
    with pytest.raises(DesignError) as info:
        EPSADesign.from_dict({"radius": 3})
    assert info.value.parameter == "radius"
    with pytest.raises(DesignError) as info:
        RobotDesign.from_dict({"foot": {"colour": 1}})
    assert info.value.parameter == "foot.colour"


def test_frozen_and_keyword_only():
    e = EPSADesign()
    with pytest.raises(dataclasses.FrozenInstanceError):
        e.length = 3  # type: ignore[misc]
    with pytest.raises(TypeError):
        EPSADesign(100.0)  # type: ignore[misc]


def test_hash_stable_across_processes():
    h = RobotDesign().short_hash()
    code = "from softcrawl.geometry.design import RobotDesign; print(RobotDesign().short_hash())"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == h and len(h) == 12
    assert EPSADesign(chamber_radius=4).short_hash() != EPSADesign().short_hash()
    assert EPSADesign(length=100).short_hash() == EPSADesign(length=100.0).short_hash()


@pytest.mark.parametrize("suffix", [".json", ".toml"])
@pytest.mark.parametrize(
    "design",
    [EPSADesign(chamber_radius=4), FootDesign(angle=100), RingDesign(), RobotDesign(d=15, n_rings=2)],
)
def test_save_load_round_trip(tmp_path, design, suffix):
    path = design.save(tmp_path / f"d{suffix}")
    assert type(design).load(path) == design
    assert load_design(path) == design
    assert load_design(path).short_hash() == design.short_hash()


def test_wrong_kind_in_file(tmp_path):
    path = EPSADesign().save(tmp_path / "e.json")
    with pytest.raises(DesignError) as info:
        FootDesign.load(path)
    assert info.value.parameter == "kind"
    assert json.loads(path.read_text())["kind"] == "epsa"


@settings(max_examples=40, deadline=None)
@given(L=st.floats(20, 300), R=st.floats(2, 20), frac=st.floats(0.1, 0.9), N=st.integers(0, 60))
def test_round_trip_property(L, R, frac, N):
    e = EPSADesign(
        length=L,
        outer_radius=R,
        chamber_radius=frac * R if R - frac * R >= 0.5 else R - 0.5,
        fiber_turns=N,
        end_cap_thickness=min(5.0, L / 4),
    )
    assert EPSADesign.from_dict(json.loads(json.dumps(e.to_dict()))) == e
    assert e.body_volume > 0 and e.helix_length >= L
