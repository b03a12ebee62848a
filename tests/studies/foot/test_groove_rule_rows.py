"""The groove rule at the flip and its Table 1 row read from a results folder, no solve (issue 32).

Each clause of `decide` alone decides: the strain limit (at and just above it), the minimum
height, a candidate missing at one mu, a non-finite strain, the friction spread at its bound, a
non-rising stress or deformation. The row (`table1_rows`) is read from RESULTS/groove/<material>/
summary.csv, the full run before the -quick one, and a missing study is a pending row that names
the command.
"""

import csv
import math

import pytest

from softcrawl.studies.foot.groove_rule import (
    GROOVE_RULE,
    GrooveRuleInputs,
    decide,
    decide_from_results,
    groove_summary,
    markdown,
    table1_rows,
)

COLUMNS = (
    "groove_height",
    "mu",
    "trial_status",
    "plateau_over_mu_n",
    "von_mises_mpa_p99",
    "max_principal_strain_p99",
    "deformation_max_mm",
)


def row(h, mu=0.3, ratio=1.0, vm=None, strain=None, deform=None, status="completed"):
    vm = 0.2 * h if vm is None else vm
    strain = 0.04 * h if strain is None else strain
    deform = 0.1 * h if deform is None else deform
    return dict(zip(COLUMNS, (str(h), str(mu), status, str(ratio), str(vm), str(strain), str(deform))))


INPUTS = GrooveRuleInputs(candidates=(0.5, 1.0, 1.5), friction_spread=0.1, strain_limit=0.04, min_height=0.5)


def test_the_strain_limit_is_inclusive_and_decides_the_largest_height():
    rows = [row(h) for h in (0.5, 1.0, 1.5)]  # strain 0.02, 0.04, 0.06
    d = decide(rows, INPUTS)
    assert (d.value, d.status) == (1.0, "decided")  # 0.04 <= 0.04
    d = decide(rows, GrooveRuleInputs(candidates=INPUTS.candidates, strain_limit=0.0399999))
    assert (d.value, d.status) == (0.5, "decided")
    d = decide(rows, GrooveRuleInputs(candidates=INPUTS.candidates, strain_limit=0.01))
    assert (d.value, d.status) == (0.5, "fallback")
    assert d.reason.startswith("no candidate keeps p99 strain <= 0.01: smallest allowed h; friction ")


def test_min_height_missing_mu_and_non_finite_strain_each_exclude_a_candidate():
    rows = [row(h) for h in (0.5, 1.0, 1.5)]
    d = decide(rows, GrooveRuleInputs(candidates=(0.5, 1.0, 1.5), strain_limit=1.0, min_height=1.0))
    assert d.value == 1.5
    # min_height above every allowed candidate but one: the fallback is the smallest >= min_height
    d = decide(rows, GrooveRuleInputs(candidates=(0.5, 1.0, 1.5), strain_limit=0.0, min_height=1.0))
    assert (d.value, d.status) == (1.0, "fallback")
    # h = 1.5 computed at mu = 0.3 only, the others at 0.3 and 0.5: 1.5 is not allowed
    two_mu = rows + [row(h, mu=0.5) for h in (0.5, 1.0)]
    assert decide(two_mu, GrooveRuleInputs(candidates=(0.5, 1.0, 1.5), strain_limit=1.0)).value == 1.0
    nan = [row(0.5), row(1.0, strain=math.nan)]
    assert decide(nan, GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=1.0)).value == 0.5
    # a height off the candidates and an unfinished point are not read
    off = [row(0.5), row(0.75, strain=0.0), row(1.0, status="failed", strain=0.0)]
    d = decide(off, GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=1.0))
    assert d.value == 0.5 and [e["h_mm"] for e in d.evidence] == [0.5]


def test_each_check_is_reported_at_its_flip():
    base = [row(0.5, ratio=1.0), row(1.0, ratio=1.1)]  # spread 0.1 / 1.05 = 0.0952
    d = decide(base, GrooveRuleInputs(candidates=(0.5, 1.0), friction_spread=0.0953, strain_limit=1.0))
    assert (
        d.friction_independent is True and "friction almost independent of h (spread <= 0.0953)" in d.reason
    )
    d = decide(base, GrooveRuleInputs(candidates=(0.5, 1.0), friction_spread=0.0952, strain_limit=1.0))
    assert d.friction_independent is False and "friction NOT independent of h" in d.reason
    flat = [row(0.5, vm=1.0, deform=1.0), row(1.0, vm=1.0, deform=2.0)]
    d = decide(flat, GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=1.0))
    assert (d.stress_rises, d.deformation_rises) == (False, True)
    assert "stress does NOT rise and deformation rises with h" in d.reason
    d = decide(
        [row(0.5, vm=1.0, deform=1.0), row(1.0, vm=2.0, deform=1.0)], GrooveRuleInputs(candidates=(0.5, 1.0))
    )
    assert (d.stress_rises, d.deformation_rises) == (True, False)
    assert "stress rises and deformation does NOT rise with h" in d.reason
    # rising in every mu group, not only in one
    two = [row(0.5), row(1.0), row(0.5, mu=0.5, vm=2.0), row(1.0, mu=0.5, vm=1.0)]
    assert decide(two, GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=1.0)).stress_rises is False


def test_the_decided_reason_and_the_evidence_rows():
    d = decide([row(0.5), row(1.0, mu=0.3)], GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=1.0))
    assert d.reason == (
        "largest h >= 0.5 mm (lightest foot) with p99 strain <= 1 at mu = 0.3; friction almost "
        "independent of h (spread <= 0.05); stress rises and deformation rises with h"
    )
    assert d.evidence[1] == {
        "h_mm": 1.0,
        "mu": 0.3,
        "plateau_over_mu_n": 1.0,
        "von_mises_p99_mpa": 0.2,
        "strain_p99": 0.04,
        "deformation_mm": 0.1,
    }
    assert d.agrees_with_paper is True
    assert decide([], INPUTS).agrees_with_paper is None


def write_summary(folder, rows):
    folder.mkdir(parents=True)
    path = folder / "summary.csv"
    with open(path, "w", newline="") as handle:
        w = csv.DictWriter(handle, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    return path


def test_a_missing_study_is_a_pending_row_naming_the_command(tmp_path):
    decision, source = decide_from_results(tmp_path)
    assert (decision.value, decision.status, source) == (None, "pending", None)
    assert decision.reason == "no groove study under the results folder"
    ((name, r),) = table1_rows(tmp_path).items()
    assert name == "groove_height" and r.source is None and (r.material, r.quick) == ("-", False)
    assert (r.selection.parameter, r.selection.value, r.selection.status) == (
        "groove_height",
        None,
        "pending",
    )
    assert (
        r.selection.reason
        == "no groove study under the results folder (run `softcrawl study groove --out DIR`)"
    )
    assert r.evidence_lines[:2] == (
        "Groove height h: pending mm (pending; paper 1 mm). no groove study under the results folder.",
        "Source: none",
    )


@pytest.mark.parametrize("quick", [False, True])
def test_the_table1_row_of_a_decided_study(tmp_path, quick):
    folder = tmp_path / "groove" / ("rubber-70a-quick" if quick else "rubber-70a")
    source = write_summary(folder, [row(h) for h in (0.5, 1.0, 1.5, 2.0)])  # strain 0.02 ... 0.08
    r = table1_rows(tmp_path)["groove_height"]
    assert (r.material, r.quick, r.source) == ("rubber-70a", quick, source)
    s = r.selection
    assert (s.parameter, s.value, s.rule, s.status) == ("groove_height", 2.0, GROOVE_RULE, "selected")
    assert s.reason.startswith("largest h >= 0.5 mm")
    assert s.evidence[0] == "h = 0.5: mu = 0.3, plateau / mu N 1, strain p99 0.02, von Mises p99 0.1 MPa"
    assert len(s.evidence) == 4
    decision, _ = decide_from_results(tmp_path)
    assert r.evidence_lines == tuple(markdown(decision, source))


def test_the_table1_row_of_a_fallback_says_so(tmp_path):
    write_summary(tmp_path / "groove" / "rubber-70a", [row(h, strain=0.5) for h in (0.5, 1.0, 1.5, 2.0)])
    s = table1_rows(tmp_path)["groove_height"].selection
    assert (s.value, s.status) == (0.5, "selected")
    assert s.reason.startswith("fallback: no candidate keeps p99 strain <= 0.1: smallest allowed h; ")


def test_markdown_lines():
    d = decide([row(0.5), row(1.0)], GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=1.0))
    lines = markdown(d, None)
    assert lines[0] == f"Groove height h: 1.0 mm (decided; paper 1 mm). {d.reason}."
    assert lines[1:5] == [
        "Source: none",
        "",
        "| h (mm) | mu | plateau / mu N | von Mises p99 (MPa) | strain p99 | deformation (mm) |",
        "|---|---|---|---|---|---|",
    ]
    assert lines[5:] == [
        "| 0.5 | 0.3 | 1.0000 | 0.100 | 0.020 | 0.050 |",
        "| 1 | 0.3 | 1.0000 | 0.200 | 0.040 | 0.100 |",
    ]
    assert markdown(d, "results/groove/x/summary.csv")[1] == "Source: results/groove/x/summary.csv"


def test_the_full_run_is_read_before_the_quick_one(tmp_path):
    assert groove_summary(tmp_path) is None
    quick = write_summary(tmp_path / "groove" / "abs-quick", [row(0.5), row(1.0)])  # sorts first
    assert groove_summary(tmp_path) == quick
    full = write_summary(tmp_path / "groove" / "rubber-70a", [row(0.5), row(1.0, strain=1.0)])
    assert groove_summary(tmp_path) == full
    inputs = GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=2.0)
    decision, source = decide_from_results(tmp_path, inputs)
    assert source == full and decision.value == 1.0  # the inputs given, not the defaults (0.5 here)


def test_a_study_without_a_completed_point_is_pending_with_its_source(tmp_path):
    source = write_summary(tmp_path / "groove" / "rubber-70a", [row(0.5, status="failed")])
    r = table1_rows(tmp_path)["groove_height"]
    assert r.source == source and r.selection.status == "pending"
    assert r.selection.reason == "no completed groove-study point (run `softcrawl study groove --out DIR`)"
    d = decide([], INPUTS)
    assert (d.value, d.status, d.reason) == (None, "pending", "no completed groove-study point")
    assert (d.friction_independent, d.stress_rises, d.deformation_rises, d.evidence) == (None, None, None, [])


def test_every_mu_group_must_pass_each_check_and_unsorted_rows_are_sorted():
    ins = GrooveRuleInputs(candidates=(0.5, 1.0, 1.5), friction_spread=0.05, strain_limit=1.0)
    good = [row(h, mu=0.5) for h in (1.5, 0.5, 1.0)]  # unsorted, rising once sorted
    d = decide(good, ins)
    assert [e["h_mm"] for e in d.evidence] == [0.5, 1.0, 1.5] and d.stress_rises and d.deformation_rises
    assert d.reason.endswith(
        "at mu = 0.5; friction almost independent of h (spread <= 0.05); "
        "stress rises and deformation rises with h"
    )
    # the first mu group fails a check, the second passes: the check fails
    for bad in (
        [row(0.5, ratio=1.0), row(1.0, ratio=2.0)],
        [row(0.5, vm=2.0), row(1.0, vm=1.0)],
        [row(0.5, deform=2.0), row(1.0, deform=1.0)],
    ):
        d = decide(bad + [row(0.5, mu=0.5), row(1.0, mu=0.5)], ins)
        assert False in (d.friction_independent, d.stress_rises, d.deformation_rises)
        assert d.reason.startswith(
            "largest h >= 0.5 mm (lightest foot) with p99 strain <= 1 at mu = 0.3, 0.5; "
        )
    # rising means every step: the first step up, the second down
    d = decide([row(0.5, vm=1.0), row(1.0, vm=2.0), row(1.5, vm=1.5)], ins)
    assert d.stress_rises is False


def test_the_friction_spread_at_its_bound_and_below_a_mean_of_one():
    bound = (1.1 - 1.0) / ((1.0 + 1.1) / 2)
    ins = GrooveRuleInputs(candidates=(0.5, 1.0), friction_spread=bound, strain_limit=1.0)
    assert decide([row(0.5, ratio=1.0), row(1.0, ratio=1.1)], ins).friction_independent is True  # inclusive
    # ratios 0.5 and 0.52: the spread is relative to their mean 0.51, not to 1
    ins = GrooveRuleInputs(candidates=(0.5, 1.0), friction_spread=0.03, strain_limit=1.0)
    assert decide([row(0.5, ratio=0.5), row(1.0, ratio=0.52)], ins).friction_independent is False


def test_a_fallback_keeps_its_checks_and_evidence_and_unreadable_cells_are_nan():
    rows = [row(0.5, vm=2.0), row(1.0, vm=1.0)]
    d = decide(rows, GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=0.0))
    assert (d.status, d.friction_independent, d.stress_rises, d.deformation_rises) == (
        "fallback",
        True,
        False,
        True,
    )
    assert len(d.evidence) == 2
    rows[1]["von_mises_mpa_p99"] = "abc"
    d = decide(rows, GrooveRuleInputs(candidates=(0.5, 1.0), strain_limit=1.0))
    assert math.isnan(d.evidence[1]["von_mises_p99_mpa"]) and d.stress_rises is False
