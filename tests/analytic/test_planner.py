"""Gait planner (Section IV): straight and vertical pipes, elbows, containment."""

import numpy as np
import pytest

from softcrawl.analytic import kinematics as kin
from softcrawl.analytic.pipe import Pipe
from softcrawl.analytic.planner import plan, replay
from softcrawl.analytic.prototype import actuator_set
from softcrawl.analytic.refine import _perturbed, continuous_plan, simulate


def _check_inside(result, samples=41):
    """Re-pose every inflated body of the plan from its rear foot and check the wall clearance."""
    pipe = result.pipe
    allow = pipe.diameter / 2 - result.body_radius
    rot = np.asarray(result.start_rotation)
    f = np.linspace(0.0, 1.0, samples)
    for c in result.cycles:
        pts = np.asarray(c.rear_before) + kin.arc_point(c.theta * f, c.phi, c.length_inflated * f) @ rot.T
        dist, _ = pipe.locate(pts)
        assert dist.max() <= allow + 1e-6
        np.testing.assert_allclose(pts[-1], c.front, atol=1e-9)
        step = c.length_inflated - c.length_deflated
        rear = np.asarray(c.rear_before) + kin.arc_point(c.kappa * step, c.phi, step) @ rot.T
        np.testing.assert_allclose(rear, c.rear_after, atol=1e-9)
        rot = rot @ kin.arc_rotation(c.kappa * step, c.phi)


@pytest.mark.parametrize("kind", ["straight", "vertical"])
def test_straight_pipe_gives_equal_pressures(kind):
    result = plan(Pipe(kind, 70.0, entry=300.0), step_kpa=10.0)
    assert result.success
    for _phase, *P in result.gait():
        assert P[0] == P[1] == P[2]
    assert result.cycles[0].pressures_inflated == (100.0, 100.0, 100.0)
    assert all(c.theta == 0.0 for c in result.cycles)
    stride = result.cycles[0].progress
    assert stride == pytest.approx(53.97 if kind == "straight" else 53.37, abs=0.01)
    assert len(result.cycles) == int(np.ceil(300.0 / stride))
    _check_inside(result)


def test_prototype_actuators_straight_pipe_stays_inside():
    result = plan(Pipe("straight", 70.0, entry=300.0), actuators="prototype", step_kpa=10.0)
    assert result.success
    _check_inside(result)


def test_elbow_r80_passes_inside_the_pipe():
    result = plan(Pipe("elbow", 70.0, 80.0), step_kpa=10.0)
    assert result.success, result.message
    assert len(result.cycles) == 7
    _check_inside(result)
    # the bend is taken by the P2 = P3 family (ePSA 1 faces the inside of the bend), as gait 2
    assert all(c.pressures_inflated[1] == c.pressures_inflated[2] for c in result.cycles)
    assert any(c.pressures_inflated[0] < c.pressures_inflated[1] for c in result.cycles)


def test_elbow_r40_acceptance():
    """Issue #5: a 90 deg elbow of bend radius 40 mm in the 70 mm pipe, the 23 mm body inside.

    No grid search passes it (the gaits are thinner than a 5-10 kPa grid); the continuous
    refinement does, from a straight seed, in 25 cycles with a few hundredths of a mm to spare.
    """
    result = continuous_plan(Pipe("elbow", 70.0, 40.0), cycles=25)
    assert result.success, result.message
    assert len(result.cycles) <= 25
    _check_inside(result)
    triples = [c.pressures_inflated for c in result.cycles]
    assert all(P[1] == P[2] for P in triples)
    # an S: the first cycles bend away from the elbow (P1 > P23), the last ones into it
    assert triples[0][0] > triples[0][1] and triples[-2][0] < triples[-2][1]
    # the inflation path between the planner's 4 stages stays inside too
    fine = replay(result.pipe, triples, stages=16, samples=81)
    assert fine.success and min(c.clearance for c in fine.cycles) > 0.0


def test_refine_simulator_matches_the_planner_model():
    """The batched planar simulator of analytic.refine and its perturbed runs against replay."""
    pipe = Pipe("elbow", 600.0, 40.0)  # wide: every cycle is run
    rng = np.random.default_rng(5)
    P = rng.uniform(0.0, 100.0, (6, 2))
    triples = [(p1, p23, p23) for p1, p23 in P]
    a = actuator_set("nominal")[0]
    lengths = np.stack([a.length(P[:, 0], 0.0), a.length(P[:, 1], 0.0)], -1)
    rest = float(a.length(0.0, 0.0))
    dist, rear = simulate(pipe, lengths[None], rest, stages=4, samples=21)
    ref = replay(pipe, triples)
    assert len(ref.cycles) == 6
    for i, c in enumerate(ref.cycles):
        assert pipe.diameter / 2 - 23.0 - dist[0, i].max() == pytest.approx(c.clearance, abs=1e-9)
        np.testing.assert_allclose(
            [rear[0, i + 1, 0], rear[0, i + 1, 1]], [c.rear_after[0], c.rear_after[2]], atol=1e-9
        )
    h = 1e-3
    dp, rp = _perturbed(pipe, lengths, h, rest, 14.0, 4, 21)
    bumped = np.vstack([lengths.ravel(), lengths.ravel() + h * np.eye(12)]).reshape(13, 6, 2)
    db, rb = simulate(pipe, bumped, rest, stages=4, samples=21)
    np.testing.assert_allclose(dp, db, atol=1e-12)
    np.testing.assert_allclose(rp, rb[:, -1], atol=1e-12)


def test_replay_reproduces_the_planned_cycles():
    pipe = Pipe("elbow", 70.0, 80.0)
    planned = plan(pipe, step_kpa=10.0)
    again = replay(pipe, [c.pressures_inflated for c in planned.cycles])
    assert again.success and len(again.cycles) == len(planned.cycles)
    for a, b in zip(planned.cycles, again.cycles):
        np.testing.assert_allclose(b.rear_after, a.rear_after, atol=1e-9)
        np.testing.assert_allclose(b.pressures_deflated, a.pressures_deflated, atol=1e-9)
        assert b.clearance == pytest.approx(a.clearance, abs=1e-9)
    # a gait that hits the wall stops there, reported
    bent = replay(pipe, [(0.0, 100.0, 100.0)] * 3)
    assert not bent.success and "leaves the pipe" in bent.message and not bent.cycles


def test_failed_plan_is_reported_not_raised():
    result = plan(Pipe("elbow", 70.0, 40.0), step_kpa=20.0)
    assert not result.success and result.message
    _check_inside(result)  # what it did plan is still inside the pipe


def test_body_too_wide_raises():
    from softcrawl.analytic.errors import ModelInputError

    with pytest.raises(ModelInputError) as e:
        plan(Pipe("straight", 40.0))
    assert e.value.parameter == "diameter"


def test_planar_bfs_agrees_and_is_inside():
    from softcrawl.analytic.planar import bfs_plan

    through = bfs_plan(Pipe("elbow", 70.0, 80.0), step_kpa=20.0)
    assert through.success and len(through.cycles) == 11
    _check_inside(through)
    assert not bfs_plan(Pipe("elbow", 70.0, 40.0), step_kpa=20.0).success


@pytest.mark.slow
def test_planar_bfs_10kpa_r40_none_r60_through():
    from softcrawl.analytic.planar import bfs_plan

    assert not bfs_plan(Pipe("elbow", 70.0, 40.0), step_kpa=10.0).success
    r60 = bfs_plan(Pipe("elbow", 70.0, 60.0), step_kpa=10.0)
    assert r60.success and len(r60.cycles) == 10
    _check_inside(r60)


@pytest.mark.slow
def test_continuous_elbows_clearance_grows_with_the_radius():
    """Maximised clearance to spare: R = 40 mm by a hair (~0.05 mm), R = 45, 50 mm comfortably."""
    spare = {}
    for radius in (40.0, 45.0, 50.0):
        result = continuous_plan(Pipe("elbow", 70.0, radius), cycles=25, margin=None, attempts=1)
        assert result.success, result.message
        _check_inside(result)
        fine = replay(result.pipe, [c.pressures_inflated for c in result.cycles], stages=64, samples=161)
        assert fine.success
        spare[radius] = min(c.clearance for c in fine.cycles)
    assert 0.03 < spare[40.0] < 0.2 < spare[45.0] < spare[50.0]
