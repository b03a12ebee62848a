"""The six holds of `studies.crawl_fe.model` fix the six rigid-body modes and nothing else, and
hand their force to the wall's friction (`studies.crawl_fe.pipe.into_pipe`).

For each rigid mode (translations along x, y, z; small rotations about x, y, z through the body's
mid-point) the six holds' extensions form a 6 x 6 matrix: it must be regular (every rigid mode is
held, so the tangent is regular with the wall clear), while a deformation that leaves the rear
hub's bottom face in place, the front hub's top face without lateral motion and no twist (the
actuators' axial extension, u_z = e (z + t_hub)) must stretch none of them: the holds resist
the rigid modes, not the body's own deformation. Holds that carry a force at the insertion's end
keep it as their preload when friction comes on and release it in a stage of its own; holds that
carry none (straight pipes) take no such stage.
"""

import numpy as np
import pytest

from softcrawl.fem.axial_link import AxialLink
from softcrawl.fem.discretisation import Discretisation
from softcrawl.geometry.body_mesh import mesh_body
from softcrawl.geometry.design import RobotDesign
from softcrawl.studies.crawl_fe.model import HOLDS, with_hold_tags


def test_the_holds_fix_the_rigid_modes_and_nothing_else():
    design = RobotDesign()
    tagged = with_hold_tags(mesh_body(design, "quick"))
    space = Discretisation(tagged.to_skfem(order=2))
    terms = [AxialLink(b, a, c, 1.0, name=name).build(space) for name, b, a, c in HOLDS]
    X = space.nodes
    centre = 0.5 * (X.min(axis=1) + X.max(axis=1))[:, None]
    modes = []
    for axis in range(3):
        u = np.zeros_like(X)
        u[axis] = 1.0
        modes.append(u)
    for axis in range(3):
        w = np.zeros(3)
        w[axis] = 1e-3
        modes.append(np.cross(w, (X - centre).T).T)
    x = np.zeros(space.n_dofs)
    matrix = []
    for u in modes:
        x[: space.n_u] = u.T.reshape(-1)
        matrix.append([t.extension(x) for t in terms])
    s = np.linalg.svd(np.array(matrix), compute_uv=False)
    assert s.min() > 1e-6 * s.max()  # regular: observed 1.5e-2 (rotations of 1e-3 rad)
    x[: space.n_u] = np.stack([0 * X[0], 0 * X[1], 0.01 * (X[2] + design.foot.hub_thickness)]).T.reshape(-1)
    assert max(abs(t.extension(x)) for t in terms) < 1e-12


def _inserted(monkeypatch, carried_n):
    """`pipe.into_pipe` on a stand-in body with one stiff hold along z that carries `carried_n` at
    the insertion's end (its three nodes moved by -carried_n / HOLD_STIFF), the solver replaced by
    a recorder of the stages it is given (each converged where it starts)."""
    from types import SimpleNamespace

    from softcrawl.fem.rigid_surfaces import CylinderWall
    from softcrawl.studies.crawl.model import CrawlSetup
    from softcrawl.studies.crawl_fe import pipe
    from softcrawl.studies.crawl_fe.model import HOLD_STIFF, BodyModel

    space = SimpleNamespace(boundary_nodes=lambda tag: np.arange(3))
    hold = AxialLink("rear_bottom", None, 2, HOLD_STIFF, name="hold_z").build(space)
    stages = []
    inserted = np.zeros(9)
    inserted[2::3] = -carried_n / HOLD_STIFF

    def run_stages(model, staged, *, x0, **kwargs):
        stages.extend(staged)
        x = inserted if x0 is None else x0
        return SimpleNamespace(converged=True, x=x, newton_iterations=0, assembly_s=0.0, solve_s=0.0,
                               factorizations=0)  # fmt: skip

    monkeypatch.setattr(pipe, "run_stages", run_stages)
    monkeypatch.setattr(pipe, "record", lambda bm, name, x: name)
    contacts = [SimpleNamespace(spec=SimpleNamespace(name="rear_smooth"))]
    tip = SimpleNamespace(foot=SimpleNamespace(tip_radius=39.0))
    model = SimpleNamespace(contacts=contacts, n_dofs=9)
    bm = SimpleNamespace(setup=CrawlSetup(), model=model, design=tip, holds={"hold_z": hold})
    bm.hold_forces = lambda x: BodyModel.hold_forces(bm, x)
    bm.set_holds = lambda *a, **k: BodyModel.set_holds(bm, *a, **k)
    run = pipe.into_pipe(bm, wall=CylinderWall(35.0))
    return run, stages, hold, inserted


def test_holds_that_carry_the_walls_axial_push_keep_it_when_friction_comes_on_then_release_it(monkeypatch):
    """A bellows' slopes push the feet along the axis while the wall is frictionless, and the
    stiff holds carry it: softened with that force as their preload, the inserted state stays
    balanced; the release stage then ramps the preload to zero."""
    from softcrawl.studies.crawl_fe.model import HOLD_SOFT
    from softcrawl.studies.crawl_fe.pipe import RELEASE_STEPS

    run, stages, hold, x = _inserted(monkeypatch, 2.5)
    assert [s.name for s in stages] == ["insert", "friction", "release"] and run.states == (
        "insert",
        "friction",
        "release",
    )
    release = stages[-1]
    assert release.steps == RELEASE_STEPS and hold.stiffness == HOLD_SOFT
    release.drive(0.0)
    assert hold.tension(x) == pytest.approx(2.5, rel=1e-12)  # balanced as inserted
    release.drive(0.5)
    assert hold.tension(x) == pytest.approx(1.25, rel=1e-12)
    release.drive(1.0)
    assert hold.tension(x) == 0.0


def test_holds_that_carry_nothing_take_no_release_stage(monkeypatch):
    """A straight pipe's holds carry about 2e-9 N at the insertion's end: re-based with no
    preload, and no release stage, as every committed straight and elbow run was made."""
    run, stages, hold, x = _inserted(monkeypatch, 2e-9)
    assert [s.name for s in stages] == ["insert", "friction"] and run.states == ("insert", "friction")
    assert hold.preload == 0.0 and abs(hold.tension(x)) < 1e-12
