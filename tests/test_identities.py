"""Identities on the committed results/ tables (issue 32): the reported numbers agree with each
other the way their definitions say, so a unit factor dropped or a quantity taken from the wrong
foot in the code that wrote them shows up here as well as in the unit tests of that code.

- units: every ``*kpa`` column of a table is in kPa (a pressure 1000x too small, an MPa value
  written unconverted, is below 1 kPa where the study ramps to 100 kPa);
- crawl cycles: stride = mean of the two feet's advances (the centre's advance), speed = stride /
  cycle time; crawl states: centre = mean of the feet, ePSA length - Delta = l0 constant, momentum
  = the sum of both feet's friction and ground forces;
- foot summary: mean pressure * contact area = normal force; the face forces sum to it.
"""

import csv
import math
from pathlib import Path

import pytest

from softcrawl.units import kpa_to_mpa, mpa_to_kpa

RESULTS = Path(__file__).resolve().parents[1] / "results"


def rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def num(value):
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


CYCLES = sorted(RESULTS.glob("crawl/**/cycles.csv"))
STATES = sorted(RESULTS.glob("crawl/**/states.csv"))


def test_there_are_tables_to_check():
    assert len(CYCLES) >= 5 and len(STATES) >= 3
    assert (RESULTS / "foot/rubber-70a/summary.csv").exists()


@pytest.mark.parametrize("path", CYCLES, ids=lambda p: str(p.relative_to(RESULTS)))
def test_crawl_cycles_stride_is_the_centres_advance_and_speed_is_stride_over_time(path):
    for r in rows(path):
        stride = num(r["stride_mm"])
        assert stride == pytest.approx(
            0.5 * (num(r["rear_advance_mm"]) + num(r["front_advance_mm"])), abs=1e-12
        )
        assert num(r["speed_mm_s"]) == pytest.approx(stride / num(r["cycle_s"]), rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("path", STATES, ids=lambda p: str(p.relative_to(RESULTS)))
def test_crawl_states_centre_length_and_momentum(path):
    table = rows(path)
    l0 = {round(num(r["epsa_length_mm"]) - num(r["delta_mm"]), 9) for r in table}
    assert len(l0) == 1
    for r in table:
        assert num(r["centre_u_mm"]) == pytest.approx(
            0.5 * (num(r["rear_u_mm"]) + num(r["front_u_mm"])), abs=1e-12
        )
        balance = sum(num(r[f"{f}_{k}_n"]) for f in ("rear", "front") for k in ("friction", "ground"))
        balance += num(r.get("rim_springs_n") or 0.0)  # the flipped feet's fold springs (record 067)
        balance += num(r.get("stabilisation_n") or 0.0)  # their insertion's stabilisation (record 094)
        assert num(r["momentum_n"]) == pytest.approx(balance, abs=1e-9)
        assert all(0.0 <= num(r[f"{f}_slip_share"]) <= 1.0 + 1e-12 for f in ("rear", "front"))


def test_foot_summary_mean_pressure_times_area_is_the_normal_force():
    table = rows(RESULTS / "foot/rubber-70a/summary.csv")
    checked = 0
    for r in table:
        force, area, mean = num(r["normal_force_n"]), num(r["contact_area_mm2"]), num(r["mean_pressure_kpa"])
        if not all(map(math.isfinite, (force, area, mean))) or area <= 0:
            continue
        assert kpa_to_mpa(mean) * area == pytest.approx(force, rel=1e-9)
        faces = num(r["normal_smooth_n"]) + num(r["normal_grooved_n"])
        assert faces == pytest.approx(force, rel=1e-6)
        assert num(r["max_pressure_kpa"]) >= mean
        checked += 1
    assert checked >= 3


KPA_TABLES = sorted(p for p in RESULTS.glob("**/*.csv") if "points" not in p.parts)


def kpa_columns(path):
    with open(path, newline="") as handle:
        header = next(csv.reader(handle), [])
    return [c for c in header if c.lower().endswith("kpa") and not c.startswith("withstands")]


@pytest.mark.parametrize(
    "path", [p for p in KPA_TABLES if kpa_columns(p)], ids=lambda p: str(p.relative_to(RESULTS))
)
def test_reported_pressures_are_in_kpa(path):
    """Every study ramps to tens of kPa: a pressure column whose largest value is below 1 has lost
    the MPa -> kPa factor (mpa_to_kpa), one above 10 000 has gained it twice."""
    table = rows(path)
    for col in kpa_columns(path):
        values = [abs(num(r[col])) for r in table if math.isfinite(num(r[col]))]
        if not values or max(values) == 0.0:
            continue
        assert 1.0 <= max(values) <= 1e4, (col, max(values))


def test_unit_factor_both_ways():
    for p in (0.5, 1.0, 36.0, 100.0):
        assert kpa_to_mpa(p) * 1000.0 == pytest.approx(p, rel=1e-15)
        assert mpa_to_kpa(p) / 1000.0 == pytest.approx(p, rel=1e-15)
    assert kpa_to_mpa(100.0) < 100.0 < mpa_to_kpa(100.0)
