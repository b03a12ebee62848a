"""The FE body's gait cycles (`studies.crawl_fe.cycle`): where a foot is, and what a stride is.

The probe reads each foot's axial position as the mean u_z of the hub face the holds use, so a
rigid translation moves both feet by it and the actuators' extension (u_z = e (z + t_hub), the
rear hub's bottom face at rest) moves only the front foot. The cycle's bookkeeping is checked on
a scripted solver that translates the body by a known amount per schedule segment: each cycle's
stride is the sum of its segments' translations, and a schedule that does not start at zero
pressure gets a first segment to its first row, which is not part of any cycle's stride. The
physics of a cycle (the body crawling in its pipe) is the slow run of bench/body_bench.py
--cycles (docs/decisions/076-one-body.md).
"""

from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.fem.discretisation import Discretisation
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.pipe_surfaces import ElbowPipe
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.geometry.body_mesh import mesh_body
from softcrawl.geometry.design import RobotDesign
from softcrawl.studies.crawl.schedule import Schedule
from softcrawl.studies.crawl_fe import cycle
from softcrawl.studies.crawl_fe.model import with_hold_tags


@pytest.fixture(scope="module")
def space():
    return Discretisation(with_hold_tags(mesh_body(RobotDesign(), "quick")).to_skfem(order=2))


def _field(space, u):
    x = np.zeros(space.n_dofs)
    x[: space.n_u] = np.asarray(u).T.reshape(-1)
    return x


def test_a_rigid_translation_moves_both_feet_and_the_extension_only_the_front(space):
    probe = cycle.FootProbe(space)
    X = space.nodes
    x = _field(space, [0.3 + 0 * X[0], -0.2 + 0 * X[1], 1.5 + 0 * X[2]])
    assert probe.z(x) == pytest.approx({"rear": 1.5, "front": 1.5}, abs=1e-12)
    assert probe.drift(x) == pytest.approx((0.3, -0.2), abs=1e-12)
    hub = RobotDesign().foot.hub_thickness
    x = _field(space, [0 * X[0], 0 * X[1], 0.01 * (X[2] + hub)])
    z = probe.z(x)
    assert z["rear"] == pytest.approx(0.0, abs=1e-12)
    front_top = X[2, space.boundary_nodes("front_top")]
    assert z["front"] == pytest.approx(0.01 * (front_top.mean() + hub), rel=1e-12)
    assert z["front"] > 1.0  # the front hub's top is ~120 mm up the body


@pytest.mark.parametrize("angle", [0.0, 7.0, 30.0])
def test_a_rigid_rotation_turns_the_heading_and_does_not_bend_the_body(space, angle):
    """A rotation by `angle` about the x axis: the heading is the angle, the bend zero, and each
    foot's centreline position that of its face's centroid along the pipe's axis, the same on a
    straight pipe and on the entry leg of an elbow whose bend starts far ahead."""
    c, s = np.cos(np.radians(angle)), np.sin(np.radians(angle))
    X = space.nodes
    rotated = np.array([X[0], c * X[1] - s * X[2], s * X[1] + c * X[2]])
    x = _field(space, rotated - X)
    for wall in (None, CylinderWall(35.0), ElbowPipe(35.0, 60.0, entry=1000.0)):
        probe = cycle.FootProbe(space, wall)
        bend, heading = probe.angles(x)
        assert bend == pytest.approx(0.0, abs=1e-6) and heading == pytest.approx(angle, abs=1e-6)
        for foot, nodes in probe.nodes.items():
            assert probe.arc(x)[foot] == pytest.approx(rotated[2, nodes].mean(), rel=1e-12)


def test_opposite_tilts_of_the_two_faces_bend_the_body(space):
    """The front face rotated by 10 deg about x and the rear face by -10 deg: a bend of 20 deg."""
    probe = cycle.FootProbe(space)
    X = space.nodes
    u = np.zeros_like(X)
    for foot, sign in (("rear", -1.0), ("front", 1.0)):
        n = probe.nodes[foot]
        a = np.radians(10.0 * sign)
        zc = X[2, n].mean()
        u[1, n] = np.cos(a) * X[1, n] - np.sin(a) * (X[2, n] - zc) - X[1, n]
        u[2, n] = np.sin(a) * X[1, n] + np.cos(a) * (X[2, n] - zc) + zc - X[2, n]
    bend, heading = probe.angles(_field(space, u))
    assert bend == pytest.approx(20.0, abs=1e-6) and heading == pytest.approx(10.0, abs=1e-6)


def _scripted(space, advance_per_segment):
    """run_stages for the stages given: two sub-steps each, the body translated along z by half
    of `advance_per_segment` in each, three Newton iterations per sub-step."""
    calls = []

    def run_stages(model, stages, *, x0, on_step, **kwargs):
        # one call for every segment: a new call would start its pressures from zero
        assert not calls, "the segments must be the stages of one run_stages call"
        calls.extend(stages)
        x = x0.copy()
        for stage in stages:
            for s in (0.5, 1.0):
                x = x.copy()
                x[2 : space.n_u : 3] += 0.5 * advance_per_segment
                on_step(SimpleNamespace(stage=stage.name, s=s, x=x, iterations=(3,)))
        n = 6 * len(stages)
        return SimpleNamespace(
            converged=True,
            message="",
            newton_iterations=n,
            assembly_s=0.0,
            solve_s=0.0,
            wall_s=0.0,
            factorizations=0,
        )

    return run_stages, calls


def _scripted_body(space, monkeypatch):
    """A body whose crawl is `_scripted` (0.25 mm per segment), with no wall forces or holds."""
    run_stages, calls = _scripted(space, 0.25)
    monkeypatch.setattr(cycle, "run_stages", run_stages)
    monkeypatch.setattr(
        cycle,
        "record",
        lambda bm, name, x: SimpleNamespace(
            normal={}, friction={f: np.zeros(3) for f in cycle.FEET}, holds={"h": 0.0}
        ),
    )
    body = SimpleNamespace(
        model=SimpleNamespace(space=space),
        copies=1,  # the whole body (a wedge: tests/studies/crawl_fe/test_body_wedge.py)
        pressures=list,
        volumes=lambda x: (0.0, 0.0, 0.0),
    )
    return body, calls


def test_each_cycle_strides_the_sum_of_its_segments(space, monkeypatch):
    bm, calls = _scripted_body(space, monkeypatch)
    gait = Schedule("test", np.array([0.0, 1.0, 2.0]), np.array([[0.0] * 3, [100.0] * 3, [0.0] * 3]), "test")
    out = cycle.crawl_cycles(bm, np.zeros(space.n_dofs), gait, cycles=2, steps=3)
    assert out.converged and out.strides == pytest.approx((0.5, 0.5))
    assert [s.pressure for s in calls] == [[0.1] * 3, [0.0] * 3] * 2  # kPa -> MPa once
    assert all(s.steps == 3 for s in calls) and out.newton_iterations == 24
    assert [s.duration for s in calls] == [1.0] * 4  # each segment's time (viscous slip reads it)
    assert [s.newton for s in out.states] == [6] * 4  # per segment
    assert [s.z["rear"] for s in out.states] == pytest.approx([0.25, 0.5, 0.75, 1.0])
    held = Schedule("held", np.array([0.0, 1.0]), np.array([[50.0] * 3, [100.0] * 3]), "test")
    calls.clear()
    out = cycle.crawl_cycles(bm, np.zeros(space.n_dofs), held, cycles=1)
    assert [s.pressure for s in calls] == [[0.05] * 3, [0.1] * 3]  # to the first row, then the cycle
    assert [s.duration for s in calls] == [None, 1.0]  # the ramp to the first row takes no time
    assert out.strides == pytest.approx((0.25,))  # the ramp to the first row is not the cycle's
    assert [s.cycle for s in out.states] == [0, 1]


def test_each_cycle_takes_the_wall_time_from_the_last_cycles_end_to_its_own(space, monkeypatch):
    """On a clock that moves 10 s between readings (read at the start and after each converged
    sub-step, two per segment): 40 s for each two-segment cycle; the ramp to a first row is in no
    cycle's time; a resumed log carries its cycle's time so far into the cycle it completes."""
    bm, calls = _scripted_body(space, monkeypatch)
    ticks = iter(range(0, 10_000, 10))
    monkeypatch.setattr(cycle, "time", SimpleNamespace(perf_counter=lambda: float(next(ticks))))
    gait = Schedule("test", np.array([0.0, 1.0, 2.0]), np.array([[0.0] * 3, [100.0] * 3, [0.0] * 3]), "test")
    out = cycle.crawl_cycles(bm, np.zeros(space.n_dofs), gait, cycles=2)
    assert out.cycle_s == (40.0, 40.0)
    calls.clear()
    held = Schedule("held", np.array([0.0, 1.0]), np.array([[50.0] * 3, [100.0] * 3]), "test")
    assert cycle.crawl_cycles(bm, np.zeros(space.n_dofs), held, cycles=1).cycle_s == (20.0,)
    calls.clear()
    log = cycle.CycleLog(start=({"rear": 0.0, "front": 0.0}, 0.0), strides=[0.5], turns=[0.0], seconds=[None],
                         clock=5.0)  # fmt: skip
    out = cycle.crawl_cycles(bm, np.zeros(space.n_dofs), gait, cycles=1, log=log)
    assert out.cycle_s == (None, 45.0)  # a cycle done before times were kept stays unknown


@pytest.mark.parametrize("cycles", [0, -1, 1.5])
def test_a_count_of_cycles_below_one_names_the_parameter(space, cycles):
    gait = Schedule("test", np.array([0.0, 1.0]), np.array([[0.0] * 3, [100.0] * 3]), "test")
    bm = SimpleNamespace(model=SimpleNamespace(space=space, chamber_volume=lambda x, i: 0.0))
    with pytest.raises(SolverInputError) as err:
        cycle.crawl_cycles(bm, np.zeros(space.n_dofs), gait, cycles=cycles)
    assert err.value.parameter == "cycles"


def test_a_gait_plan_is_one_schedule_per_cycle_joined_where_the_last_deflated(space, monkeypatch, tmp_path):
    """`softcrawl model plan`'s gait.csv replayed: each planned cycle starts at the pressures the
    last one deflated to, inflates at half the cycle time and deflates at its end; the FE cycles
    follow the plan's pressures in order, one stride per planned cycle."""
    from softcrawl.studies.crawl_fe.gait_plan import read_gait_plan

    plan = tmp_path / "gait.csv"
    plan.write_text(
        "cycle,phase,P1_kpa,P2_kpa,P3_kpa,rear_x,rear_y,rear_z,front_x,front_y,front_z\n"
        "1,inflate,100,40,60,0,0,0,0,0,50\n"
        "1,deflate,0,20,0,0,0,0,0,0,50\n"
        "2,inflate,80,100,0,0,0,0,0,0,60\n"
        "2,deflate,0,0,0,0,0,0,0,0,60\n"
    )
    schedules = read_gait_plan(plan, 2.0)
    assert len(schedules) == 2
    assert schedules[0].times.tolist() == [0.0, 1.0, 2.0]
    assert schedules[0].pressures_kpa.tolist() == [[0, 0, 0], [100, 40, 60], [0, 20, 0]]
    assert schedules[1].pressures_kpa.tolist() == [[0, 20, 0], [80, 100, 0], [0, 0, 0]]
    bm, calls = _scripted_body(space, monkeypatch)
    out = cycle.crawl_cycles(bm, np.zeros(space.n_dofs), schedules, cycles=7)  # the plan's count wins
    expected = [[0.1, 0.04, 0.06], [0, 0.02, 0], [0.08, 0.1, 0], [0] * 3]
    assert np.allclose([s.pressure for s in calls], expected, rtol=1e-12, atol=0)
    assert out.strides == pytest.approx((0.5, 0.5))
    assert [(s.cycle, s.t, s.pressures_kpa) for s in out.states][1:3] == [
        (1, 2.0, (0, 20, 0)),
        (2, 1.0, (80, 100, 0)),
    ]


@pytest.mark.parametrize(
    "text",
    [
        "cycle,phase,P1_kpa,P2_kpa\n1,inflate,1,2\n1,deflate,0,0\n",  # a column missing
        "cycle,phase,P1_kpa,P2_kpa,P3_kpa\n1,inflate,1,2,3\n",  # no deflate row
        "cycle,phase,P1_kpa,P2_kpa,P3_kpa\n1,deflate,1,2,3\n1,inflate,0,0,0\n",  # out of order
        "cycle,phase,P1_kpa,P2_kpa,P3_kpa\n1,inflate,1,2,300\n1,deflate,0,0,0\n",  # above 100 kPa
        "cycle,phase,P1_kpa,P2_kpa,P3_kpa\n1,inflate,1,2,x\n1,deflate,0,0,0\n",  # not a number
    ],
)
def test_a_gait_plan_that_is_not_one_names_the_option(tmp_path, text):
    from softcrawl.studies.crawl.schedule import ScheduleError
    from softcrawl.studies.crawl_fe.gait_plan import read_gait_plan

    plan = tmp_path / "gait.csv"
    plan.write_text(text)
    with pytest.raises(ScheduleError) as err:
        read_gait_plan(plan, 2.0)
    assert err.value.parameter == "gait-plan"
