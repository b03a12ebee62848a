"""Yeoh and Gent laws: stress and tangent against finite differences, the exact incompressible
uniaxial response, the assembled tangent of a mixed body against central differences of its
residual, and the Neo-Hookean limits (Yeoh with C20 = C30 = 0, Gent with Jm -> infinity)."""

import numpy as np
import pytest
import skfem

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import Gent, NeoHookean, Yeoh
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.neohooke import cauchy_stress

LAWS = {
    "yeoh": Yeoh(c10=0.0126, c20=9.1e-4, c30=2.0e-5, bulk=5.0),
    "yeoh-negative-c20": Yeoh(c10=0.015, c20=-2.0e-3, c30=4.0e-4, bulk=5.0),
    "gent": Gent(mu=0.03, jm=10.0, bulk=5.0),
}


@pytest.mark.parametrize("name", sorted(LAWS))
def test_stress_and_tangent_match_finite_differences(name):
    law = LAWS[name]
    rng = np.random.default_rng(4)
    F = np.eye(3)[:, :, None] + 0.3 * rng.standard_normal((3, 3, 9))
    F[:, :, 0] = np.diag([2.0, 0.8, 0.7])  # a stretched state where Psi'' matters
    P, A = law.stress(F), law.tangent(F)
    h = 1e-6
    for k in range(3):
        for m in range(3):
            dF = np.zeros_like(F)
            dF[k, m] = h
            dW = (law.energy(F + dF) - law.energy(F - dF)) / (2 * h)
            dP = (law.stress(F + dF) - law.stress(F - dF)) / (2 * h)
            assert np.allclose(dW, P[k, m], rtol=1e-6, atol=1e-8)
            assert np.allclose(dP, A[:, :, k, m], rtol=1e-6, atol=1e-7)


@pytest.mark.parametrize("name", sorted(LAWS))
def test_exact_incompressible_uniaxial_response(name):
    """sigma_zz - sigma_xx of the isochoric uniaxial state equals lam * nominal stress, with
    nominal P = 2 Psi'(x)(lam - lam^-2) (the law's own closed form, written out here again)."""
    law = LAWS[name]
    for lam in (1.2, 1.8, 2.4):
        F = np.diag([lam**-0.5, lam**-0.5, lam])[:, :, None]
        sigma = cauchy_stress(law.stress(F), F)[:, :, 0]
        x = lam**2 + 2 / lam - 3
        if isinstance(law, Yeoh):
            psi1 = law.c10 + 2 * law.c20 * x + 3 * law.c30 * x**2
        else:
            psi1 = law.mu / 2 / (1 - x / law.jm)
        nominal = 2 * psi1 * (lam - lam**-2)
        assert sigma[2, 2] - sigma[0, 0] == pytest.approx(lam * nominal, rel=1e-12)
        assert float(law.uniaxial_nominal_stress(lam)) == pytest.approx(nominal, rel=1e-12)


def test_neo_hookean_limits():
    F = np.eye(3)[:, :, None] + 0.2 * np.random.default_rng(7).standard_normal((3, 3, 5))
    nh = NeoHookean(mu=0.03, bulk=3.0)
    yeoh = Yeoh(c10=0.015, c20=0.0, c30=0.0, bulk=3.0)
    assert np.allclose(yeoh.stress(F), nh.stress(F), rtol=1e-13, atol=1e-16)
    assert np.allclose(yeoh.tangent(F), nh.tangent(F), rtol=1e-13, atol=1e-15)
    gent = Gent(mu=0.03, jm=1e9, bulk=3.0)
    assert np.allclose(gent.stress(F), nh.stress(F), rtol=1e-7, atol=1e-12)


@pytest.mark.parametrize(
    "make, parameter",
    [
        (lambda: Yeoh(c10=0.0, c20=0.0, c30=0.0, bulk=1.0), "c10"),
        (lambda: Yeoh(c10=0.01, c20=-0.01, c30=0.0, bulk=1.0), "c10"),
        (lambda: Yeoh(c10=0.01, c20=0.0, c30=-1e-6, bulk=1.0), "c10"),
        (lambda: Yeoh(c10=0.01, c20=np.nan, c30=0.0, bulk=1.0), "c20"),
        (lambda: Gent(mu=0.03, jm=0.0, bulk=1.0), "jm"),
        (lambda: Gent(mu=0.03, jm=5.0, bulk=0.001), "bulk"),
    ],
)
def test_unphysical_laws_name_the_parameter(make, parameter):
    with pytest.raises(SolverInputError) as err:
        make()
    assert err.value.parameter == parameter


def _box(materials, formulation):
    rng = np.random.default_rng(1)
    m = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 3)] * 3)
    m = skfem.MeshTet(m.p + 0.04 * rng.uniform(-1, 1, m.p.shape) * (m.p[2] > 0), m.t)
    m = m.with_boundaries({"z0": lambda x: np.abs(x[2]) < 1e-12})
    m = m.with_subdomains({"a": lambda x: x[0] < 0.5, "b": lambda x: x[0] >= 0.5})
    model = SolidModel(m, materials, dirichlet=[Dirichlet.fixed("z0")], formulation=formulation)
    x = model.initial_state()
    X = model.nodes
    u = 0.2 * rng.uniform(-1, 1, (3, 3)) @ X + 0.05 * np.sin(3 * X[[1, 2, 0]])
    x[: model.n_u] = u.T.ravel()
    if model.mixed:
        x[model.n_u :] = 0.002 * rng.standard_normal(model.n_p)
    return model, model.apply_dirichlet(x, 0.0), rng


@pytest.mark.parametrize("formulation", ["p2p1", "p2"])
def test_assembled_tangent_is_the_derivative_of_the_residual(formulation):
    """A body of Yeoh and Gent (and one of Yeoh and Neo-Hookean): K v = dR/dv by central
    differences, so the kernel's d D (x) D term and its grouping by subdomain are right."""
    for mats in (
        {"a": LAWS["yeoh-negative-c20"], "b": LAWS["gent"]},
        {"a": LAWS["yeoh"], "b": NeoHookean(mu=0.05, bulk=5.0)},
    ):
        model, x, rng = _box(mats, formulation)
        _, K = model.residual_and_tangent(x, 0.0)
        free = model.free_dofs
        for _ in range(3):
            v = np.zeros(model.n_dofs)
            v[free] = rng.standard_normal(free.size)
            eps = 1e-6
            dR = (model.residual(x + eps * v) - model.residual(x - eps * v))[free] / (2 * eps)
            Kv = K @ v[free]
            assert np.linalg.norm(Kv - dR) <= 1e-6 * np.linalg.norm(Kv)


def test_gent_locking_stretch_is_an_inverted_state_the_path_cuts_back():
    from softcrawl.fem.model import InvertedElement

    model, x, _ = _box({"a": Gent(mu=0.03, jm=0.05, bulk=3.0), "b": NeoHookean(mu=0.03, bulk=3.0)}, "p2p1")
    with pytest.raises(InvertedElement, match="Jm"):
        model.residual(x)
