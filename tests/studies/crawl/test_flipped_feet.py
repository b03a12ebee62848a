"""The backward crawl's start state: each flipped foot folded with its actuators' hub face held.

The crawl's plates (`studies.crawl.model`) are the rear foot's hub top and the front foot's hub
bottom (`mesh.attach_tag`): equal axial and zero lateral displacements. A fold copied onto a foot
must leave that face undeformed, or the plate's penalty and lateral constraint put an imbalance of
the order of the force scale into the insertion's first sub-step, whatever its size
(docs/decisions/078-backward-stall.md: with the hub top held for both feet, the quick crawl's start
state had a relative residual of 1.0 at 55 mm, and its insertion stalled in cut-backs).
"""

from dataclasses import replace

import numpy as np
import pytest

from softcrawl.fem.model import SolidModel
from softcrawl.geometry.design import RobotDesign
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.crawl import flipped
from softcrawl.studies.crawl.mesh import crawl_mesh
from softcrawl.studies.crawl.model import CrawlSetup, build
from softcrawl.studies.foot.flip import Fold


def _setup(diameter: float) -> CrawlSetup:
    foot = RobotDesign().foot
    return CrawlSetup(pipe_diameter=diameter, feet="backward", foot=foot, insert_steps=4, sectors=24)


def _law():
    return solid_law(get_material("rubber-70a"), hyperelastic_only=True)


def test_each_foot_is_folded_with_the_face_its_actuators_act_on_held(monkeypatch):
    """A stand-in fold (no FE): a displacement that vanishes on the held hub face and grows with
    the axial distance from it, on a coarse mesh (12 sectors, two cells through the skirt; no
    contact terms). The copy onto the crawl's mesh must come from the rear foot's fold with its
    hub top held and the front foot's with its hub bottom held, so both plates start undeformed;
    with one fold (hub top held) for both, the front plate moved by 0.1 x the hub thickness."""
    calls, models = [], {}

    def fake_fold(mesh, material, design, phi, *, steps=12, options=None, hub="hub_top"):
        calls.append(hub)
        model = models.setdefault("single", SolidModel(mesh, material))
        z_hub = float(model.nodes[2, model.boundary_nodes(hub)].mean())
        u = 0.1 * (model.nodes[2] - z_hub) * np.array([[1.0], [0.5], [1.0]])
        x = np.zeros(model.n_dofs)
        x[: model.n_u] = u.T.ravel()
        return Fold(True, "folded", phi, x, None)

    monkeypatch.setattr(flipped, "fold", fake_fold)
    setup = replace(_setup(70.0), sectors=12, thickness_layers=2)
    design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
    springs = flipped.rim_springs()
    model = SolidModel(mesh, _law(), extra_terms=[springs])
    x0, message = flipped.folded_feet(model, _law(), design, setup, springs)
    assert x0 is not None, message
    assert sorted(calls) == ["hub_bottom", "hub_top"]
    u = model.displacement(x0)
    for tag in ("rear:hub_top", "front:hub_bottom"):
        assert np.abs(u[:, model.boundary_nodes(tag)]).max() < 1e-12, tag
    # the other faces carry their own fold's displacement (the copy is not zeroed)
    for tag in ("rear:hub_bottom", "front:hub_top"):
        assert np.abs(u[2, model.boundary_nodes(tag)]).min() > 0.05 * design.hub_thickness, tag
    assert np.array_equal(springs.target, x0[springs.rim_dofs])


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_the_folded_feet_start_in_equilibrium_in_the_55mm_pipe():
    """The FE folds of the quick feet (24 sectors) copied onto the crawl's model at 55 mm, where the
    fold is about 110 deg. Off the plates and the rims the start state is in equilibrium (the
    folds' tolerance); on them remain the folds' reactions (about 96 N in all, measured), which
    the stiff ground and rim springs take with displacements of about 0.1 mm. The insertion's
    first sub-step that does not yet reach the feet (the wall at s = 1/8) converges. With one fold
    (hub top held) for both feet the start state's residual was 6.9e4 N, nearly all on the front
    plate, and that sub-step stalled at a relative residual of 0.23 at every cut-back."""
    from softcrawl.fem.newton import NewtonSolver
    from softcrawl.studies.crawl.model import CRAWL_NEWTON, _clear_radius
    from softcrawl.studies.foot.model import insertion_wall

    setup = _setup(55.0)
    design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
    cm = build(mesh, _law(), design, setup)
    assert cm.folded is not None, cm.fold_message
    m, P = cm.model, np.zeros(1)
    solver = NewtonSolver(m, CRAWL_NEWTON)
    R = np.zeros(m.n_dofs)
    R[solver.free_u] = m.residual(cm.folded, P, 0.0)[solver.free_u]
    R = R[: m.n_u].reshape(-1, 3)
    tags = ("rear:hub_top", "front:hub_bottom", "rear:rim", "front:rim")
    held = np.concatenate([m.boundary_nodes(t) for t in tags])
    off = np.ones(len(R), bool)
    off[held] = False
    assert np.linalg.norm(R[off]) < 1e-3  # N
    assert np.linalg.norm(R) < 500.0  # N
    wall = insertion_wall(setup.pipe, _clear_radius(cm))(0.5 / setup.insert_steps)
    for term in m.contacts:
        term.set_surface(wall)
    _, record = solver.load_step(cm.folded, P, 0.0)  # raised Diverged (a stall at 0.23) before
    assert record.converged


def test_the_flipped_feet_plates_are_held_until_friction(monkeypatch):
    """Record 079: while the wall closes on the flipped feet and their rims are released, each
    plate's ground spring is n k_p (n the plate's nodes, k_p = PLATE_PENALTY E h its penalty per
    node), not GROUND_HOLD, on which the 55 mm quick crawl's first contact sub-step wandered;
    the paper's feet keep GROUND_HOLD (their insertion, and its cache key, unchanged)."""
    from softcrawl.studies.crawl import model as crawl_model

    monkeypatch.setattr(flipped, "folded_feet", lambda model, *a: (np.zeros(model.n_dofs), "folded"))
    for feet in ("backward", "paper"):
        setup = replace(_setup(70.0), feet=feet, thickness_layers=2)
        design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
        cm = build(mesh, _law(), design, setup)
        m = cm.model
        grounds = [cm.terms[f"ground_{f}"] for f in ("rear", "front")]
        if feet == "backward":
            plates = [t for t in m.terms if type(t).__name__ == "_EqualTerm"]
            n = max(m.boundary_nodes(t).size for t in ("rear:hub_top", "front:hub_bottom"))
            k_p = plates[0].K[0, 0, 0] / (1.0 - 1.0 / plates[0].dofs.shape[0])  # the penalty per node
            assert cm.ground_hold == pytest.approx(n * k_p, rel=1e-12) and cm.ground_hold > 1e6
        else:
            assert cm.ground_hold == crawl_model.GROUND_HOLD
        assert all(g.stiffness == cm.ground_hold and g.preload == 0.0 for g in grounds)


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_the_first_contact_sub_step_converges_with_the_plates_held():
    """The 55 mm quick backward crawl (24 sectors, 4 insertion sub-steps) from its folded feet: the
    insertion's first sub-step (wall 30.46 -> 29.72 mm), the first to reach the feet's bow, is one
    Newton solve. With the plates held (ground springs of n k_p, record 079) it converges in 5
    iterations; on GROUND_HOLD (1000 N/mm, the code before) it stalled at a relative residual of
    6.6e-2 after 12 iterations (record 078's table, remeasured in record 079), and the insertion
    ground on in cut-backs."""
    from softcrawl.fem.newton import NewtonSolver
    from softcrawl.studies.crawl.model import CRAWL_NEWTON, _clear_radius
    from softcrawl.studies.foot.model import insertion_wall

    setup = _setup(55.0)
    design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
    cm = build(mesh, _law(), design, setup)
    assert cm.folded is not None, cm.fold_message
    wall = insertion_wall(setup.pipe, _clear_radius(cm))(1.0 / setup.insert_steps)
    assert wall.radius < 29.8  # inside the folded feet's bow (29.96 mm): the wall bites
    for term in cm.model.contacts:
        term.set_surface(wall)
    x, record = NewtonSolver(cm.model, CRAWL_NEWTON).load_step(cm.folded, np.zeros(1), 0.0)
    assert record.converged and record.iterations <= 8
    # the wall carries the rear foot's bow there (record 078: 72-192 active points of its grooved face)
    assert cm.model.contacts[1].report(x).normal_force > 1.0  # N


def test_the_flipped_feet_insertion_is_stabilised_where_the_fold_is_crushed(monkeypatch):
    """Record 094: where the folded feet reach outside the pipe (a stand-in fold: the moulded feet,
    tips at 39 mm, in a 70 mm pipe) the insertion is stabilised at c0 = STABILISE E / t^2, and the
    release ramps c linearly, with the rim springs, to exactly 0 (a static equilibrium); where they are
    inside (an 80 mm pipe) c0 = 0, and the paper's feet have no stabilisation."""
    from softcrawl.fem.stabilisation import Stabilisation
    from softcrawl.studies.foot.model import small_strain_youngs

    monkeypatch.setattr(flipped, "folded_feet", lambda model, *a: (np.zeros(model.n_dofs), "folded"))
    for feet, diameter in (("backward", 70.0), ("backward", 80.0), ("paper", 70.0)):
        setup = replace(_setup(diameter), feet=feet, thickness_layers=2)
        design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
        cm = build(mesh, _law(), design, setup)
        terms = [t for t in cm.model.terms if isinstance(t, Stabilisation)]
        if feet == "paper":
            assert terms == [] and cm.stabilisation is None and cm.stabilise == 0.0
            continue
        assert terms == [cm.stabilisation]
        if diameter == 80.0:
            assert cm.stabilise == 0.0
            continue
        c0 = flipped.STABILISE * small_strain_youngs(_law()) / design.skirt_thickness**2
        assert cm.stabilise == pytest.approx(c0, rel=1e-12) and c0 > 0
        flipped.insert_drive(cm.stabilisation, cm.stabilise)(0.5)
        assert cm.stabilisation.coefficient == cm.stabilise
        release = flipped.release_drive(cm.springs, cm.stabilisation, cm.stabilise)
        release(0.0)
        assert cm.stabilisation.coefficient == pytest.approx(c0, rel=1e-12)
        release(0.75)
        assert cm.stabilisation.coefficient == pytest.approx(0.25 * c0, rel=1e-12)
        release(1.0)
        assert cm.stabilisation.coefficient == 0.0 and cm.springs.stiffness == 0.0
