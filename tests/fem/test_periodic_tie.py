"""Cyclic symmetry, exact (`fem.periodic_tie`, condensed by `fem.dirichlet`): the cuts follow each
other turned, and a wedge of the revolved foot against the whole foot under an axisymmetric load."""

import math

import numpy as np
import pytest

from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.newton import NewtonOptions, NewtonSolver
from softcrawl.fem.periodic_tie import CyclicTie, cut_pairs, rotation_z
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.foot_revolved import mesh_foot_revolved

RUBBER = NeoHookean(mu=1.8, bulk=1800.0)  # nearly incompressible, as the feet's rubber
SECTORS = 12


def _foot(copies):
    return mesh_foot_revolved(FootDesign(), n_theta=SECTORS, copies=copies).to_skfem(2)


def _ties(copies, pressure=True):
    return [CyclicTie("cut_start", "cut_end", 2 * math.pi / copies, pressure)]


def test_the_tied_dofs_follow_their_partners_turned():
    """Every state the solver makes keeps u_b = R u_a on the cuts (exactly, to round-off), for a
    quarter wedge (a signed map: one master per dof) and a third (two masters per dof)."""
    for copies in (4, 3):
        model = SolidModel(_foot(copies), RUBBER, ties=_ties(copies))
        a, b = cut_pairs(model.space, "cut_start", "cut_end", 2 * math.pi / copies)
        rng = np.random.default_rng(copies)
        x = model.step(model.initial_state(), rng.normal(size=model.free_dofs.size))
        u = model.displacement(x)
        assert np.abs(u[:, b] - rotation_z(2 * math.pi / copies) @ u[:, a]).max() < 1e-12
        p = model.reduce(np.zeros(model.n_dofs))
        assert p.size == model.free_dofs.size < model.n_dofs


def _pulled(mesh, ties, pull=-2.0):
    """The foot's hub top held, its rim pulled axially by `pull` mm (an axisymmetric load)."""
    bcs = [Dirichlet("hub_top", (0, 1, 2), (0.0, 0.0, 0.0)), Dirichlet("rim", (2,), (pull,))]
    model = SolidModel(mesh, RUBBER, dirichlet=bcs, ties=ties)
    res = run_stages(model, [Stage("pull", factor=1.0, steps=2)])
    assert res.converged, res.message
    x = res.x
    rim = model.boundary_nodes("rim")
    radius = np.hypot(*(model.nodes[:2, rim] + model.displacement(x)[:2, rim]))
    return model.reaction(x, "rim", factor=1.0)[2], float(radius.mean()), float(radius.min())


@pytest.fixture(scope="module")
def whole():
    return _pulled(_foot(1), [])


@pytest.mark.parametrize("copies", [4, 3])
def test_a_wedge_carries_its_share_of_the_whole_foot(whole, copies):
    """Exact to the Newton tolerance (the penalty tie of record 082 left 1e-6 of the force)."""
    force, mean_r, min_r = _pulled(_foot(copies), _ties(copies))
    assert force * copies == pytest.approx(whole[0], rel=1e-8)
    assert min_r == pytest.approx(whole[2], abs=1e-9)


def test_the_pressure_tie_is_needed(whole):
    """Without it the mixed pressure jumps across the cut: another discretisation, whose force
    differs by far more than the tied wedge's (the test above would fail on it)."""
    force, _, _ = _pulled(_foot(4), _ties(4, pressure=False))
    assert abs(force * 4 / whole[0] - 1) > 1e-4


def test_bad_ties_are_refused():
    with pytest.raises(SolverInputError, match="periodic_tie"):
        SolidModel(_foot(4), RUBBER, ties=[CyclicTie("cut_start", "cut_end", math.pi / 3)])
    with pytest.raises(SolverInputError, match="angle"):
        CyclicTie("cut_start", "cut_end", 0.0)
    with pytest.raises(SolverInputError, match="angle"):
        CyclicTie("cut_start", "cut_end", 7.0)
    # one cut held where the other is free: the tie cannot hold
    held = [Dirichlet("cut_start", (0, 1, 2), (0.0, 0.0, 0.0))]
    with pytest.raises(SolverInputError, match="tie"):
        SolidModel(_foot(4), RUBBER, dirichlet=held, ties=_ties(4))


def _merit_of_a_turned_state(copies):
    """Newton's merit (relative force residual) of the axisymmetric state u = 0.01 (x z, y z,
    0.1 r) with the hub top held: no equilibrium, so the held cut nodes carry reactions."""
    ties = _ties(copies) if copies > 1 else []
    model = SolidModel(_foot(copies), RUBBER, dirichlet=[Dirichlet.fixed("hub_top")], ties=ties)
    X, Y, Z = model.nodes
    u = 0.01 * np.stack([X * Z, Y * Z, 0.1 * np.hypot(X, Y)])
    x = model.initial_state()
    x[: model.n_u] = u.T.ravel()
    x = model.constraints.apply(x, 1.0)
    solver = NewtonSolver(model, NewtonOptions())
    merit, _, scale = solver._merit(model.residual(x), x, 0.0, 1.0)
    return merit


def test_a_wedge_with_held_cut_nodes_measures_its_residual_as_the_whole_foot():
    """The held cut nodes' reactions fold onto their partners (`Constraints.fold`), so Newton's
    force scale, and the merit it stops on, is the whole foot's. Left split between the two
    cuts, the quarter's merit was 0.9606 against the whole foot's 0.9587 (2e-3)."""
    whole = _merit_of_a_turned_state(1)
    for copies in (4, 3):
        assert _merit_of_a_turned_state(copies) == pytest.approx(whole, rel=1e-9)
