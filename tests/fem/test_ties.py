"""Ties condensed exactly (`fem.dirichlet.Constraints`, `fem.pattern` links): the tangent a model
assembles with ties is T^T K T and its reduced residual T^T R, against the explicit product with
the untied model's K and R on a distorted box (prescribed dofs, a pressure tie, a fiber-free
body, dofs with two masters and a signed one)."""

import numpy as np
import pytest
import scipy.sparse as sp
import skfem

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel


class _Links:
    """A tie spec: top-face nodes' x follows (0.6 x + 0.8 y) of bottom-face partners, their y
    follows -x, and (mixed) a vertex pressure follows another's."""

    def __init__(self, a, b, pressure=None):
        self.a, self.b, self.pressure = a, b, pressure

    def links(self, space):
        s = np.concatenate([3 * self.b, 3 * self.b + 1])
        m = np.vstack([np.column_stack([3 * self.a, 3 * self.a + 1]), np.column_stack([3 * self.a] * 2)])
        c = np.vstack([np.tile([0.6, 0.8], (self.b.size, 1)), np.tile([-1.0, 0.0], (self.b.size, 1))])
        if self.pressure is not None:
            pa, pb = self.pressure
            s, m, c = np.append(s, pb), np.vstack([m, [pa, pa]]), np.vstack([c, [1.0, 0.0]])
        return s, m, c


def _box():
    m = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 4)] * 3)
    rng = np.random.default_rng(3)
    shift = np.zeros_like(m.p)
    shift[2] = 0.05 * rng.uniform(-1, 1, m.p.shape[1]) * (m.p[2] > 0) * (m.p[2] < 1)  # z only: rows stay
    m = skfem.MeshTet(m.p + shift, m.t)
    return m.with_boundaries({"z0": lambda x: np.abs(x[2]) < 1e-12})


def _pairs(mesh):
    """Bottom-row nodes at y = 1 (free) and their partners on the top face (x, y alike)."""
    p = mesh.p
    a = np.flatnonzero((np.abs(p[2] - 1 / 3) < 0.1) & (np.abs(p[1] - 1) < 1e-12))
    b = np.array(
        [
            np.flatnonzero((np.abs(p[2] - 1) < 1e-12) & np.all(np.abs(p[:2] - p[:2, [i]]) < 1e-9, 0))[0]
            for i in a
        ]
    )
    return a, b


def _T(model):
    """The explicit T (all dofs x free dofs) of the model's constraints."""
    c = model.constraints
    n, f = model.n_dofs, c.free_dofs.size
    rows = [c.free_dofs]
    cols = [np.arange(f)]
    vals = [np.ones(f)]
    for j in range(c.slave_free.shape[1]):
        keep = c.slave_free[:, j] >= 0
        rows.append(c.slave_dofs[keep])
        cols.append(c.slave_free[keep, j])
        vals.append(c.slave_coefs[keep, j])
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, f))


@pytest.mark.parametrize("formulation", ["p2", "p2p1"])
def test_tied_tangent_and_residual_are_the_condensed_ones(formulation):
    mesh = _box()
    law = NeoHookean.nearly_incompressible(0.05, 20.0)
    a, b = _pairs(mesh)
    free = SolidModel(mesh, law, formulation=formulation)  # the untied body, all dofs free
    pressure = None
    if free.mixed:
        pressure = (free.n_u, free.n_u + 5)
    bcs = [Dirichlet.fixed("z0")]
    tied = SolidModel(mesh, law, formulation=formulation, dirichlet=bcs, ties=[_Links(a, b, pressure)])
    assert tied.constraints.slave_dofs.size == 2 * a.size + (pressure is not None)
    rng = np.random.default_rng(0)
    x = tied.apply_dirichlet(
        tied.step(tied.initial_state(), 0.01 * rng.standard_normal(tied.free_dofs.size)), 1.0
    )
    R_all, K_all = free.residual_and_tangent(x)
    assert K_all.shape == (free.n_dofs, free.n_dofs)
    T = _T(tied)
    R, K = tied.residual_and_tangent(x)
    expected = (T.T @ K_all @ T).toarray()
    assert np.abs(K.toarray() - expected).max() < 1e-12 * np.abs(expected).max()
    assert np.abs(tied.reduce(R) - T.T @ R_all).max() < 1e-12 * np.abs(R_all).max()
    # the state the model made holds the ties
    assert np.allclose(x[3 * b], 0.6 * x[3 * a] + 0.8 * x[3 * a + 1], atol=1e-15)
    assert np.allclose(x[3 * b + 1], -x[3 * a], atol=1e-15)


def test_a_dof_tied_twice_is_refused():
    mesh = _box()
    a, b = _pairs(mesh)
    law = NeoHookean(mu=0.05, bulk=1.0)
    with pytest.raises(SolverInputError, match="tie"):
        SolidModel(mesh, law, formulation="p2", ties=[_Links(a, b), _Links(a, b)])
    with pytest.raises(SolverInputError, match="tie"):  # a master that is itself tied
        SolidModel(mesh, law, formulation="p2", ties=[_Links(a, b), _Links(b, a)])
