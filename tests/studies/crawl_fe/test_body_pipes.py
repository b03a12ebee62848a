"""The FE-body crawl's pipes (`studies.crawl_fe.pipe`) and the paper's speed each is compared with.

The command line's --pipe choices are the pipes the runner knows; a vertical pipe is the straight
one under the body's weight, pointing against the heading (up: -z, the body heading +z) or with
it (down); the elbow's bend starts ELBOW_AHEAD past the front skirt's tip, so that the inserted
body sits on its entry leg; the bellows is the corrugated pipe of the depth and pitch asked for,
widest at z = 0, and its insertion starts with its ridges clear of the skirt tips; the runner
refuses an unknown pipe naming the parameter.
"""

import numpy as np
import pytest

from softcrawl.analytic.cycle import elbow_roll
from softcrawl.analytic.pipe import Pipe
from softcrawl.fem.corrugated_pipe import CorrugatedPipe
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.pipe_surfaces import ElbowPipe
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.geometry.design import RobotDesign
from softcrawl.paper import VERTICAL_MM_S, table2
from softcrawl.studies.commands.crawl import PIPE_KINDS
from softcrawl.studies.crawl_fe import pipe as pipe_module
from softcrawl.studies.crawl_fe.pipe import BELLOWS_CORRUGATION, ELBOW_AHEAD, PIPES, PLAN_TURN_DEG, pipe_wall
from softcrawl.studies.crawl_fe.summary import paper_speed


def test_the_command_lines_pipes_are_the_runners():
    assert PIPE_KINDS == tuple(PIPES)


def test_vertical_pipes_are_the_straight_one_under_the_weight():
    assert PIPES["straight"] is None and PIPES["elbow"] is None
    assert PIPES["vertical-up"] == (0.0, 0.0, -1.0) and PIPES["vertical-down"] == (0.0, 0.0, 1.0)
    for kind in ("straight", "vertical-up", "vertical-down"):
        assert pipe_wall(kind, 35.0) == CylinderWall(35.0)


def test_the_elbows_bend_starts_ahead_of_the_front_skirt():
    wall = pipe_wall("elbow", 35.0, front_tip=150.0, bend_radius=60.0)
    assert isinstance(wall, ElbowPipe)
    assert (wall.radius, wall.bend_radius, wall.entry) == (35.0, 60.0, 150.0 + ELBOW_AHEAD)
    piece, arc, _, _ = wall.locate([[0.0, 0.0, 150.0], [0.0, 0.0, 156.0]])
    assert list(piece) == [0, 1] and arc[0] == pytest.approx(150.0)  # the tip on the entry leg


def test_a_replayed_plans_elbow_turns_towards_epsa_1_as_the_planner_rolls_the_robot():
    """The planner turns its elbow towards world +x with ePSA 1 (local +y) rolled to face it; the
    FE body is not rolled, so a plan's FE elbow turns towards the FE body's ePSA 1."""
    pipe = Pipe(kind="elbow", diameter=70.0, bend_radius=80.0)
    epsa1 = np.array([0.0, 1.0, 0.0])  # psi_1 = 90 deg in the planner's robot frame
    assert elbow_roll(pipe) @ epsa1 == pytest.approx([1.0, 0.0, 0.0])
    assert pipe.tangent([pipe.bend_end])[0] == pytest.approx(
        [1.0, 0.0, 0.0], abs=1e-12
    )  # +x: its bend's inside
    cx, cy = RobotDesign().actuator_centres[0]
    wall = pipe_wall("elbow", 35.0, front_tip=150.0, bend_radius=80.0, turn_deg=PLAN_TURN_DEG)
    end, _ = wall.centreline([np.pi / 2])  # the exit leg starts on the side the bend turns to
    assert end[0, :2] / np.hypot(*end[0, :2]) == pytest.approx(
        np.array([cx, cy]) / np.hypot(cx, cy), abs=1e-12
    )
    assert pipe_wall("elbow", 35.0, bend_radius=80.0).centreline([np.pi / 2])[0][0, :2] == pytest.approx(
        [80.0, 0]
    )


@pytest.mark.parametrize(
    "kind, kwargs, parameter",
    [("spiral", {}, "pipe"), ("elbow", {}, "bend_radius"), ("elbow", {"bend_radius": 30.0}, "bend_radius")],
)
def test_a_pipe_the_runner_cannot_build_names_the_parameter(kind, kwargs, parameter):
    with pytest.raises(SolverInputError) as err:
        pipe_wall(kind, 35.0, **kwargs)
    assert parameter in err.value.parameter


def test_each_pipe_is_compared_with_the_papers_own_speed():
    assert paper_speed("straight", 70.0)[0] == table2(70.0, "forward") == 18.3
    assert paper_speed("vertical-up", 70.0)[0] == VERTICAL_MM_S["up"] == 12.9
    assert paper_speed("vertical-down", 70.0)[0] == VERTICAL_MM_S["down"] == 19.1
    speed, source = paper_speed("elbow", 70.0)
    assert speed is None and "no bend radius" in source
    speed, source = paper_speed("bellows", 75.0)
    assert speed is None and "bellows" in source


def test_the_bellows_is_the_corrugated_pipe_asked_for_widest_at_z_0():
    assert PIPES["bellows"] is None and BELLOWS_CORRUGATION == (2.0, 10.0)
    assert pipe_wall("bellows", 37.5) == CorrugatedPipe(37.5, 1.0, 10.0)
    wall = pipe_wall("bellows", 37.5, corrugation=(3.0, 12.0))
    assert (wall.radius, wall.amplitude, wall.pitch) == (37.5, 1.5, 12.0)
    assert wall.profile([0.0, 6.0])[0] == pytest.approx([39.0, 36.0], abs=1e-12)  # depth 3 mm, peak to trough


def test_the_bellows_insertion_starts_with_its_ridges_clear_of_the_skirt_tips(monkeypatch):
    """The insertion's first wall: its narrowest radius (the ridges) 0.5 mm outside the 39 mm tips,
    its mean radius shrinking to the pipe's; read from the stage handed to the solver."""
    from types import SimpleNamespace

    from softcrawl.studies.crawl.model import CrawlSetup

    stages = []

    def run_stages(model, staged, **kwargs):
        stages.extend(staged)
        return SimpleNamespace(converged=False, message="recorded", newton_iterations=0, assembly_s=0.0,
                               solve_s=0.0, factorizations=0)  # fmt: skip

    monkeypatch.setattr(pipe_module, "run_stages", run_stages)
    contacts = [SimpleNamespace(spec=SimpleNamespace(name=n)) for n in ("rear_smooth", "rear_grooved")]
    model = SimpleNamespace(contacts=contacts, n_dofs=6)
    tip = SimpleNamespace(foot=SimpleNamespace(tip_radius=39.0))
    bm = SimpleNamespace(setup=CrawlSetup(pipe_diameter=75.0), model=model, design=tip)
    run = pipe_module.into_pipe(bm, wall=pipe_wall("bellows", 37.5, corrugation=(4.0, 10.0)))
    assert not run.converged and run.message == "insert: recorded"
    first, last = (stages[0].surfaces[0](s) for s in (0.0, 1.0))
    assert first.radius - first.amplitude == pytest.approx(39.5) and last == CorrugatedPipe(37.5, 2.0, 10.0)


def test_an_elbow_the_insertion_cannot_start_in_is_refused_before_any_work():
    """The insertion starts with the wall 0.5 mm clear of the skirt tips (39.5 mm): a bend radius
    at or below it is refused naming the parameter, before a solve (the model is never touched)."""
    from types import SimpleNamespace

    from softcrawl.studies.crawl.model import CrawlSetup
    from softcrawl.studies.crawl_fe.pipe import into_pipe

    bm = SimpleNamespace(
        setup=CrawlSetup(), model=None, design=SimpleNamespace(foot=SimpleNamespace(tip_radius=39.0))
    )
    with pytest.raises(SolverInputError) as err:
        into_pipe(bm, wall=pipe_wall("elbow", 35.0, bend_radius=39.5))
    assert err.value.parameter == "bend_radius" and "39.5" in str(err.value)


@pytest.mark.parametrize(
    "wall", [CylinderWall(35.0), ElbowPipe(35.0, 60.0, entry=150.0), CorrugatedPipe(37.5, 1.0, 10.0)]
)
def test_the_written_wall_lies_on_the_contact_surface(tmp_path, wall):
    """vtu/pipe.vtu's vertices are on the surface the contact uses (gap 0) and span the arc
    lengths asked for: what ParaView shows is the wall the feet pressed."""
    import meshio
    import numpy as np

    from softcrawl.studies.crawl_fe.files import write_wall

    mesh = meshio.read(write_wall(tmp_path / "pipe.vtu", wall, -20.0, 400.0))
    gap = wall.project(mesh.points)[0]
    assert np.abs(gap).max() < 1e-9
    if isinstance(wall, ElbowPipe):
        arc = wall.locate(mesh.points)[1]
        assert arc.min() == pytest.approx(-20.0, abs=1e-9) and arc.max() == pytest.approx(400.0, abs=1e-9)


def test_a_stop_at_the_time_limit_is_reported_with_the_users_limit():
    from softcrawl.studies.crawl_fe.files import ended

    solver = "stage 'cycle1-row2' stopped at the wall-time budget max_wall_s = 2525.97 s; last converged: x"
    assert ended(solver, 2700.0).startswith("time limit of 2700 s reached") and solver in ended(
        solver, 2700.0
    )
    assert ended("1 cycle(s) reached", 2700.0) == "1 cycle(s) reached"
    assert ended(solver, None) == solver
