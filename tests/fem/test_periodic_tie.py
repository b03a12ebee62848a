"""Cyclic symmetry by penalty (`fem.periodic_tie`): tangents against finite differences, and a
wedge of the revolved foot against the whole foot under an axisymmetric load."""

import math

import numpy as np
import pytest

from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.periodic_tie import PeriodicPressureTie, PeriodicTie
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.foot_revolved import mesh_foot_revolved

RUBBER = NeoHookean(mu=1.8, bulk=1800.0)  # nearly incompressible, as the feet's rubber
SECTORS = 12


def _foot(copies):
    return mesh_foot_revolved(FootDesign(), n_theta=SECTORS, copies=copies).to_skfem(2)


def _ties(copies, k=1.0e4 * 5.4 * 2.0, k_p=1.0e4 * 8.0 / 5.4, pressure=True):
    angle = 2 * math.pi / copies
    ties = [PeriodicTie("cut_start", "cut_end", angle, k)]
    return ties + ([PeriodicPressureTie("cut_start", "cut_end", angle, k_p)] if pressure else [])


def test_tie_tangents_match_finite_differences():
    model = SolidModel(_foot(4), RUBBER, extra_terms=_ties(4, k=3.0, k_p=2.0))
    rng = np.random.default_rng(5)
    x = rng.normal(size=model.n_dofs) * 1e-2
    dx = rng.normal(size=model.n_dofs) * 1e-6
    for term in model.terms[-2:]:
        r, K = term.arrays(x)
        r2, _ = term.arrays(x + dx)
        lin = np.einsum("kij,jk->ik", K, dx[term.dofs])
        assert np.allclose(r2 - r, lin, atol=1e-12 * max(1.0, np.abs(r).max()))
    # a rigid turn of the whole wedge about z opens no gap
    tie = model.terms[-2]
    R = tie.R
    u = ((R - np.eye(3)) @ model.nodes).T.ravel()
    assert tie.max_gap(np.concatenate([u, np.zeros(model.n_dofs - u.size)])) < 1e-12


def _pulled(mesh, ties, pull=-2.0):
    """The foot's hub top held, its rim pulled axially by `pull` mm (an axisymmetric load)."""
    bcs = [Dirichlet("hub_top", (0, 1, 2), (0.0, 0.0, 0.0)), Dirichlet("rim", (2,), (pull,))]
    model = SolidModel(mesh, RUBBER, dirichlet=bcs, extra_terms=ties)
    res = run_stages(model, [Stage("pull", factor=1.0, steps=2)])
    assert res.converged, res.message
    x = res.x
    rim = model.boundary_nodes("rim")
    radius = np.hypot(*(model.nodes[:2, rim] + model.displacement(x)[:2, rim]))
    return model.reaction(x, "rim", factor=1.0)[2], float(radius.mean()), float(radius.min())


@pytest.fixture(scope="module")
def whole():
    return _pulled(_foot(1), [])


def test_a_wedge_carries_its_share_of_the_whole_foot(whole):
    force, mean_r, min_r = _pulled(_foot(4), _ties(4))
    assert force * 4 == pytest.approx(whole[0], rel=1e-5)
    assert min_r == pytest.approx(whole[2], abs=1e-5)


def test_the_pressure_tie_is_needed(whole):
    """Without it the mixed pressure jumps across the cut: another discretisation, whose force
    differs by far more than the tied wedge's (the test above would fail on it)."""
    force, _, _ = _pulled(_foot(4), _ties(4, pressure=False))
    assert abs(force * 4 / whole[0] - 1) > 1e-4


def test_cuts_that_do_not_pair_up_are_refused():
    with pytest.raises(SolverInputError, match="periodic_tie"):
        SolidModel(_foot(4), RUBBER, extra_terms=[PeriodicTie("cut_start", "cut_end", math.pi / 3, 1.0)])
    with pytest.raises(SolverInputError, match="angle"):
        PeriodicTie("cut_start", "cut_end", 0.0, 1.0)


def test_a_pressure_tie_checks_its_spec():
    with pytest.raises(SolverInputError, match="stiffness"):
        PeriodicPressureTie("cut_start", "cut_end", math.pi / 2, -1.0)
    with pytest.raises(SolverInputError, match="angle"):
        PeriodicPressureTie("cut_start", "cut_end", 7.0, 1.0)
