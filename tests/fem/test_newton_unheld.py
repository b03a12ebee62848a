"""A body with no prescribed displacement, held only by terms (springs, contact): its Newton
scale (fem.newton, "Convergence"). Reference: the same cube with the springs' targets prescribed
as Dirichlet conditions, which the springs approach as their stiffness k grows (error ~ 1/k)."""

import numpy as np
import pytest

from softcrawl.fem.contact_verification import MATERIAL
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.newton import NewtonOptions, NewtonSolver
from softcrawl.fem.structured import box

STRETCH = 0.05  # mm, the top face's axial displacement


class _FaceSprings:
    """r = k (u - target) on the chosen components of the nodes of `tag` (a test's own term)."""

    def __init__(self, tag, components, target, k):
        self.tag, self.components, self.target, self.k = tag, components, target, k

    def build(self, space):
        nodes = space.boundary_nodes(self.tag)
        self.dofs = (3 * nodes[:, None] + np.asarray(self.components)).reshape(1, -1)
        return self

    def arrays(self, x, pressures=None, with_tangent=True):
        r = self.k * (x[self.dofs] - self.target)
        return r, (np.full((self.dofs.shape[1], 1, 1), self.k) if with_tangent else None)

    def force(self, x):
        return float(np.sum(self.k * (x[self.dofs] - self.target)))


def _spring_held(k):
    """The cube held by springs only: all components on its bottom, the axial one on its top."""
    bottom, top = _FaceSprings("z0", (0, 1, 2), 0.0, k), _FaceSprings("z1", (2,), STRETCH, k)
    model = SolidModel(box(cells=(2, 2, 2)), MATERIAL, extra_terms=[bottom, top])
    x, record = NewtonSolver(model, NewtonOptions(tol=1e-10)).load_step(model.initial_state(), 0.0, 0.0)
    return model, top, x, record


def _dirichlet_held():
    held = SolidModel(
        box(cells=(2, 2, 2)), MATERIAL, dirichlet=[Dirichlet.fixed("z0"), Dirichlet("z1", (2,), (STRETCH,))]
    )
    ref, _ = NewtonSolver(held, NewtonOptions(tol=1e-10)).load_step(held.initial_state(), 0.0, 1.0)
    return held, ref


def test_a_spring_held_body_converges_to_the_dirichlet_state_as_k_grows():
    """Before the fix Newton could not converge at all (the merit was 1.000 at every state). Now
    the spring-held state approaches the Dirichlet one at first order in 1/k, and the top springs
    carry the Dirichlet reaction."""
    held, ref = _dirichlet_held()
    u = slice(0, held.n_u)
    reaction = held.internal_force(ref)[held.space.boundary_nodes("z1") * 3 + 2].sum()
    assert reaction > 0.01  # a real load, far above the force floor
    errors = []
    for k in (1e3, 1e4):
        model, top, x, record = _spring_held(k)
        assert len(model.free_dofs) == model.n_dofs  # nothing prescribed
        assert record.converged and record.residuals[-1] <= 1e-10
        errors.append(np.linalg.norm(x[u] - ref[u]) / np.linalg.norm(ref[u]))
        assert -top.force(x) == pytest.approx(reaction, rel=10 / k)
    assert errors[1] < 2e-3 and 8 < errors[0] / errors[1] < 12  # first order in 1/k


def test_the_body_force_joins_the_scale_only_for_an_unheld_body():
    """At the spring-held equilibrium the scale is the solid's own force (the residual is ~0); a
    model with prescribed dofs keeps the reaction-carrying internal force as its scale."""
    model, _, x, _ = _spring_held(1e3)
    merit, _, scale = NewtonSolver(model, NewtonOptions())._merit(model.residual(x), x, np.zeros(1), 0.0)
    assert merit <= 1e-10 and scale == pytest.approx(np.linalg.norm(model.body_force(x)[: model.n_u]))
    held, ref = _dirichlet_held()
    scale = NewtonSolver(held, NewtonOptions())._merit(held.residual(ref, 0.0, 1.0), ref, np.zeros(1), 1.0)[2]
    assert scale == pytest.approx(np.linalg.norm(held.internal_force(ref)[: held.n_u]))
