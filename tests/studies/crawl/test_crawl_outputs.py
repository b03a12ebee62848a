"""Identities of what the crawl records (`studies.crawl.outputs`), with stubbed foot positions and
contact reports, no solve (issue 32): stride = the centre's advance = the mean of the feet's
advances, speed = stride / cycle time, per foot and per cycle; each phase's movement per foot;
the state row's per-foot sums and the momentum balance."""

from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.studies.crawl.outputs import SLID_SHARE, CrawlResult, StateRecorder, steady_stride


class Spring:
    """A ground spring: its extension is the foot's axial position, read from the state x."""

    def __init__(self, key, force=0.0):
        self.key, self.force = key, force

    def extension(self, x):
        return x[self.key]

    def tension(self, x):
        return x.get(f"{self.key}_ground", self.force)


def report(normal, friction_z, area, slip):
    return SimpleNamespace(
        normal_force=normal,
        friction_force=np.array([0.0, 0.0, friction_z]),
        area_reference=area,
        slip_fraction=slip,
    )


def stub(contacts=None, copies=1):
    nodes = np.zeros((3, 6))
    nodes[2] = [0.0, 1.0, 10.0, 11.0, 7.0, 7.0]
    tags = {"rear:rim": [0], "rear:hub_top": [1], "front:rim": [3], "front:hub_top": [2]}
    if copies > 1:  # a wedge: one more rim node on each foot's cut at 2 pi / copies
        tags |= {"rear:rim": [0, 4], "front:rim": [3, 5], "rear:cut_end": [4], "front:cut_end": [5]}
    model = SimpleNamespace(
        boundary_nodes=lambda tag: np.array(tags[tag]),
        nodes=nodes,
        displacement=lambda x: np.zeros((3, 6)) + np.array([[0.0], [0.0], [x.get("dz", 0.0)]]),
        n_dofs=12,
    )
    act = SimpleNamespace(
        stiffness=2.0, preload=0.5, tension=lambda x: 3.0, extension=lambda x: x.get("delta", 0.0)
    )
    law = SimpleNamespace(l0=100.0, chamber_volume=lambda d: 7.0 * d)
    terms = {"actuator": act, "ground_rear": Spring("rear"), "ground_front": Spring("front")}
    contacts = contacts or {"rear": [], "front": []}
    return SimpleNamespace(
        model=model,
        setup=SimpleNamespace(mirrored=(False, True), copies=copies),
        terms=terms,
        law=law,
        contacts_of=lambda f: [SimpleNamespace(report=lambda x, r=r: r) for r in contacts[f]],
    )


def step(stage="crawl"):
    return SimpleNamespace(x=None, stage=stage, iterations=(4,), penetration=0.0)


def record(rec, x, cycle, phase, t=0.0, pressures=(0.0, 0.0, 0.0), stage="crawl"):
    s = step(stage)
    s.x = x
    rec.record(s, cycle, t, pressures, phase)


def test_stride_is_the_centres_advance_and_speed_is_stride_over_cycle_time():
    rec = StateRecorder(stub())
    rec.begin_cycle(0, {"rear": 1.0, "front": 2.0})
    rec.states.append(
        {
            "phase": "extend",
            "rear_u_mm": 1.0,
            "front_u_mm": 2.0,
            "rear_slip_share": 0.0,
            "front_slip_share": 0.0,
            "rear_tip_lead_mm": -1.0,
            "front_tip_lead_mm": -2.0,
        }
    )
    rec.end_cycle(0, {"rear": 4.0, "front": 3.0}, 2.5)
    c = rec.cycles[-1]
    assert c["cycle"] == 1
    assert c["rear_advance_mm"] == 3.0 and c["front_advance_mm"] == 1.0
    assert c["stride_mm"] == 2.0  # the centre: (1 + 2) / 2 -> (4 + 3) / 2
    assert c["cycle_s"] == 2.5 and c["speed_mm_s"] == pytest.approx(2.0 / 2.5, rel=1e-15)


def test_phase_movement_per_foot_and_slid_at_the_share():
    rec = StateRecorder(stub())
    base = {"rear_tip_lead_mm": 0.0, "front_tip_lead_mm": 0.0}
    rec.states.append(
        {
            **base,
            "phase": "hold",
            "rear_u_mm": 0.0,
            "front_u_mm": 0.0,
            "rear_slip_share": 1.0,
            "front_slip_share": 1.0,
        }
    )
    rec.begin_cycle(0, {"rear": 0.0, "front": 0.0})
    rows = [
        ("extend", 0.0, 2.0, 0.0, SLID_SHARE),
        ("extend", 0.0, 3.0, 0.1, 0.2),
        ("retract", 1.5, 3.0, SLID_SHARE - 1e-9, 0.0),
        ("retract", 2.0, 3.0, 0.0, 0.0),
    ]
    for phase, r, f, sr, sf in rows:
        rec.states.append(
            {
                **base,
                "phase": phase,
                "rear_u_mm": r,
                "front_u_mm": f,
                "rear_slip_share": sr,
                "front_slip_share": sf,
            }
        )
    rec.states[-1]["rear_tip_lead_mm"], rec.states[-2]["front_tip_lead_mm"] = 0.7, 0.4
    rec.end_cycle(0, {"rear": 2.0, "front": 3.0}, 4.0)
    c = rec.cycles[-1]
    assert c["extend_rear_moved_mm"] == 0.0 and c["extend_front_moved_mm"] == 3.0
    assert c["retract_rear_moved_mm"] == 2.0 and c["retract_front_moved_mm"] == 0.0
    assert (
        c["extend_front_slid"] is True and c["extend_rear_slid"] is False
    )  # the hold row's 1.0 is not counted
    assert c["retract_rear_slid"] is False and c["retract_front_slid"] is False
    assert c["max_tip_lead_rear_mm"] == 0.7 and c["max_tip_lead_front_mm"] == 0.4
    assert c["stride_mm"] == 2.5 and c["speed_mm_s"] == 2.5 / 4.0


def test_first_cycle_counts_movement_from_its_own_first_state():
    rec = StateRecorder(stub())
    rec.begin_cycle(0, {"rear": 0.0, "front": 0.0})
    for u in (1.0, 4.0):
        rec.states.append(
            {
                "phase": "extend",
                "rear_u_mm": u,
                "front_u_mm": 2 * u,
                "rear_slip_share": 0.0,
                "front_slip_share": 0.0,
                "rear_tip_lead_mm": 0.0,
                "front_tip_lead_mm": 0.0,
            }
        )
    rec.end_cycle(0, {"rear": 4.0, "front": 8.0}, 1.0)
    assert rec.cycles[0]["extend_rear_moved_mm"] == 3.0 and rec.cycles[0]["extend_front_moved_mm"] == 6.0


def test_state_row_sums_each_foot_its_own_contacts_and_balances_momentum():
    contacts = {
        "rear": [report(2.0, -1.0, 3.0, 1.0), report(4.0, -0.5, 1.0, 0.0)],
        "front": [report(10.0, 0.25, 2.0, 0.5)],
    }
    rec = StateRecorder(stub(contacts))
    x = {"rear": 1.0, "front": 5.0, "delta": 0.5, "dz": 0.2, "rear_ground": 1.25, "front_ground": -0.5}
    record(rec, x, 0, "extend", t=0.75, pressures=(10.0, 20.0, 30.0))
    row = rec.states[-1]
    assert (row["index"], row["cycle"], row["phase"], row["time_s"]) == (0, 1, "extend", 0.75)
    assert (row["p1_kpa"], row["p2_kpa"], row["p3_kpa"]) == (10.0, 20.0, 30.0)
    assert row["actuator_force_n"] == 3.0 and row["delta_mm"] == 0.5 and row["epsa_length_mm"] == 100.5
    assert row["chamber_volume_mm3"] == 3.5 and row["actuator_stiffness_n_mm"] == 2.0
    assert row["actuator_preload_n"] == 0.5 and row["newton"] == 4
    assert row["rear_u_mm"] == 1.0 and row["front_u_mm"] == 5.0 and row["centre_u_mm"] == 3.0
    assert row["rear_normal_n"] == 6.0 and row["front_normal_n"] == 10.0
    assert row["rear_friction_n"] == -1.5 and row["front_friction_n"] == 0.25
    assert row["rear_slip_share"] == pytest.approx(3.0 / 4.0) and row["front_slip_share"] == 0.5
    assert row["rear_ground_n"] == 1.25 and row["front_ground_n"] == -0.5
    assert row["momentum_n"] == pytest.approx(-1.5 + 1.25 + 0.25 - 0.5)
    # tip lead: rim - hub top along the opening (+z for the rear foot, -z for the mirrored front)
    assert row["rear_tip_lead_mm"] == pytest.approx(0.0 - 1.0) and row["front_tip_lead_mm"] == pytest.approx(
        -(11.0 - 10.0)
    )


def test_a_wedge_reports_the_whole_feet():
    """A 1/4 wedge's contact forces are a quarter of the feet's: the row reports 4x them (the
    links report the whole link themselves); node means skip the cut at 2 pi / copies, whose
    nodes are the next wedge's cut at 0."""
    contacts = {"rear": [report(2.0, -1.0, 3.0, 1.0)], "front": [report(10.0, 0.25, 2.0, 0.5)]}
    rec = StateRecorder(stub(contacts, copies=4))
    x = {"rear": 1.0, "front": 5.0, "rear_ground": 1.25, "front_ground": -0.5}
    record(rec, x, 0, "extend")
    row = rec.states[-1]
    assert row["rear_normal_n"] == 8.0 and row["front_normal_n"] == 40.0
    assert row["rear_friction_n"] == -4.0 and row["front_friction_n"] == 1.0
    assert row["rear_slip_share"] == 1.0 and row["rear_ground_n"] == 1.25
    assert row["momentum_n"] == pytest.approx(-4.0 + 1.25 + 1.0 - 0.5)
    assert row["rear_tip_lead_mm"] == pytest.approx(0.0 - 1.0)  # the cut's rim node (z = 7) skipped


def test_no_contact_area_is_no_slip():
    rec = StateRecorder(stub({"rear": [report(0.0, 0.0, 0.0, 1.0)], "front": []}))
    record(rec, {"rear": 0.0, "front": 0.0}, 0, "extend")
    assert rec.states[-1]["rear_slip_share"] == 0.0 and rec.states[-1]["front_slip_share"] == 0.0


def test_on_state_sees_each_row_and_the_result_collects_the_extremes():
    seen = []
    rec = StateRecorder(
        stub({"rear": [report(1.0, -2.0, 1.0, 0.0)], "front": [report(1.0, 0.5, 1.0, 0.0)]}),
        on_state=lambda row, model, x: seen.append(row["index"]),
    )
    record(
        rec,
        {"rear": 0.0, "front": 0.0, "rear_ground": 9.0, "front_ground": 0.0},
        -1,
        "insert",
        stage="insert",
    )
    record(rec, {"rear": 0.0, "front": 0.0, "rear_ground": 1.0, "front_ground": -3.0}, 0, "extend")
    record(rec, {"rear": 0.0, "front": 0.0, "rear_ground": 2.0, "front_ground": 0.5}, 1, "retract")
    assert seen == [0, 1, 2]
    stats = [SimpleNamespace(newton_iterations=3, assembly_s=0.5, solve_s=0.25)] * 2
    res = rec.result(True, "done", stats, 9.0)
    assert res.converged and res.message == "done" and res.increments == 3 and res.n_dofs == 12
    assert res.newton_iterations == 6 and res.assembly_s == 1.0 and res.solve_s == 0.5 and res.wall_s == 9.0
    assert res.ground_max_n == 3.0  # the insert state (cycle 0) is not counted
    assert res.friction_max_n == 2.0
    assert res.momentum_max_n == pytest.approx(abs(-2.0 + 1.0 + 0.5 - 3.0))  # insert (9 - 1.5) excluded


def make_result(strides):
    cycles = tuple({"stride_mm": s} for s in strides)
    return CrawlResult(True, "", (), cycles, 0, 0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def test_steady_stride_skips_the_first_cycle():
    assert make_result([1.0, 2.0, 4.0]).strides == [1.0, 2.0, 4.0]
    assert steady_stride(make_result([1.0, 2.0, 4.0])) == 3.0
    assert steady_stride(make_result([1.5])) == 1.5
    assert np.isnan(steady_stride(make_result([])))


def test_steady_stride_of_two_cycles_is_the_second():
    assert steady_stride(make_result([1.0, 3.0])) == 3.0


def test_a_result_without_crawl_states_reports_zero_extremes_and_keeps_its_rows():
    rec = StateRecorder(stub({"rear": [report(1.0, -2.0, 1.0, 0.0)], "front": []}))
    assert rec.start is None and rec.states == [] and rec.cycles == []
    record(rec, {"rear": 0.0, "front": 0.0, "rear_ground": 9.0}, -1, "insert", stage="insert")
    rec.cycles.append({"stride_mm": 1.0})
    res = rec.result(False, "stopped", [], 1.0)
    assert (res.ground_max_n, res.friction_max_n, res.momentum_max_n) == (0.0, 0.0, 0.0)
    assert res.states == tuple(rec.states) and res.cycles == ({"stride_mm": 1.0},)
    assert res.newton_iterations == 0 and res.assembly_s == 0.0


def test_mark_start_records_each_foots_position():
    rec = StateRecorder(stub())
    rec.mark_start({"rear": -1.0, "front": 2.5})
    assert rec.start == {"rear": -1.0, "front": 2.5}


def test_state_row_reads_every_quantity_at_the_recorded_state():
    """Each quantity from the state x itself (stubs that read x), the skirt's lead from the
    deformed positions (nodes + displacement, not uniform), a small contact area still divides."""
    contacts = {"rear": [report(2.0, -1.0, 0.5, 1.0)], "front": [report(1.0, 0.5, 0.25, 0.5)]}
    cm = stub(contacts)
    # node z: rear rim 0, rear hub top 1, front hub top 10, front rim 11; displaced by x["uz"]
    cm.model.displacement = lambda x: np.vstack([np.zeros((2, 6)), x["uz"]])
    cm.terms["actuator"] = SimpleNamespace(
        stiffness=2.0, preload=0.5, tension=lambda x: x["T"], extension=lambda x: x["delta"]
    )
    reports = {"rear": contacts["rear"], "front": contacts["front"]}
    cm.contacts_of = lambda f: [
        SimpleNamespace(report=lambda x, r=r: r if x["live"] else None) for r in reports[f]
    ]
    seen = []
    rec = StateRecorder(cm, on_state=lambda row, model, x: seen.append((model, x)))
    x = {
        "rear": 0.0,
        "front": 1.0,
        "delta": 0.5,
        "T": 4.0,
        "live": True,
        "uz": np.array([3.0, 0.0, 0.0, -4.0, 0.0, 0.0]),
    }
    s = step()
    s.x, s.penetration = x, 0.125
    rec.record(s, 0, 1.0, (0.0, 0.0, 0.0), "extend")
    row = rec.states[-1]
    assert row["actuator_force_n"] == 4.0 and row["penetration_mm"] == 0.125
    assert row["rear_normal_n"] == 2.0 and row["rear_slip_share"] == 1.0 and row["front_slip_share"] == 0.5
    # rear: rim 0 + 3 over hub top 1 along +z = 2; front (mirrored): -(11 - 4 - 10) = 3
    assert row["rear_tip_lead_mm"] == pytest.approx(2.0) and row["front_tip_lead_mm"] == pytest.approx(3.0)
    assert seen == [(cm.model, x)]
