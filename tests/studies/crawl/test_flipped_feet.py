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
