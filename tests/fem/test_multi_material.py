"""Two materials tied in one conforming mesh: exact uniform stress across the interface.

A bar [0, 1] x [0, 1] x [0, 2] mm of silicone (z < 1) and ABS (z > 1), held on rollers on its
four sides (u_x = 0 on x = 0, 1; u_y = 0 on y = 0, 1) and at its base (u_z = 0), pulled by a dead
traction t on its top. The exact solution is piecewise homogeneous: F = diag(1, 1, lam_m) in each
material, with the same nominal stress t in both (equilibrium across the interface),

    P_zz(lam) = mu lam^(-2/3) (lam - (2 + lam^2) / (3 lam)) + K (lam - 1) = t,

which the P2-P1 space represents exactly when each material has its own pressure field. One
pressure field continuous across the interface cannot represent the jump of p = K (J - 1) and
spreads it into the elements next to the interface.
"""

import numpy as np
import pytest
import skfem
from scipy.optimize import brentq

from softcrawl.fem.dead_load import body_force_vector
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.path import load_path
from softcrawl.fem.structured import tag_boundaries

SILICONE = NeoHookean.nearly_incompressible(0.03, 1000.0)
ABS = NeoHookean(mu=740.7, bulk=2222.2)
T = 0.02  # MPa


def _exact_stretch(law, t):
    def pzz(lam):
        return law.mu * lam ** (-2 / 3) * (lam - (2 + lam**2) / (3 * lam)) + law.bulk * (lam - 1.0) - t

    return brentq(pzz, 0.5, 2.0, xtol=1e-15)


def two_material_bar(pressure_fields="per-material"):
    n = 3
    mesh = skfem.MeshTet.init_tensor(np.linspace(0, 1, n), np.linspace(0, 1, n), np.linspace(0, 2, 2 * n - 1))
    zc = mesh.p[2, mesh.t].mean(axis=0)
    mesh = mesh.with_subdomains({"soft": np.nonzero(zc < 1)[0], "stiff": np.nonzero(zc > 1)[0]})
    mesh = tag_boundaries(
        mesh,
        {
            **{
                f"{c}{v}": (lambda x, i=i, v=v: np.abs(x[i] - v) < 1e-9)
                for i, c in enumerate("xy")
                for v in (0, 1)
            },
            "bottom": lambda x: np.abs(x[2]) < 1e-9,
            "top": lambda x: np.abs(x[2] - 2) < 1e-9,
        },
    )
    bcs = [Dirichlet.symmetry(f"{c}{v}", i) for i, c in enumerate("xy") for v in (0, 1)]
    bcs.append(Dirichlet.symmetry("bottom", 2))
    return SolidModel(
        mesh,
        {"soft": SILICONE, "stiff": ABS},
        dirichlet=bcs,
        dead_loads={"top": (0.0, 0.0, T)},
        pressure_fields=pressure_fields,
    )


def _solve(model):
    res = load_path(model, [(0.0, 1.0)])
    assert res.converged, res.message
    return res.steps[-1].x


def test_tied_materials_carry_the_exact_uniform_stress():
    model = two_material_bar()
    x = _solve(model)
    P = model.solid.stress(x).P  # (3, 3, E, Q)
    assert np.abs(P[2, 2] - T).max() <= 1e-10 * T  # observed 5.5e-12 (round-off)
    assert np.abs(P[0, 1]).max() <= 1e-9 * T
    lam_soft, lam_stiff = _exact_stretch(SILICONE, T), _exact_stretch(ABS, T)
    top = model.boundary_nodes("top")
    uz = model.displacement(x)[2, top]
    assert np.allclose(uz, (lam_soft - 1.0) + (lam_stiff - 1.0), rtol=1e-9, atol=0)
    # each material has its own pressure dofs at the interface vertices
    assert model.n_p > model.space.pbasis.N


def test_one_pressure_field_across_the_jump_is_wrong():
    """The control case: the continuous field misses the exact stress by far more than round-off."""
    model = two_material_bar("continuous")
    x = _solve(model)
    P = model.solid.stress(x).P
    assert np.abs(P[2, 2] - T).max() > 1e-2 * T  # observed 3.1e-2 T near the interface


def test_body_force_totals_the_weight():
    model = two_material_bar()
    b = body_force_vector(model.space, {"soft": (0.0, 0.0, -2.0), "stiff": (1.0, 0.0, 0.0)})
    f = b[: model.n_u].reshape(-1, 3).sum(axis=0)
    assert f == pytest.approx((1.0, 0.0, -2.0), abs=1e-12)  # unit volume each
