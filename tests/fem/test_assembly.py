"""The vectorised assembly of `fem.model` against a plain einsum of the 81-component tangent
on a distorted mesh with a random state (several chunkings, so the threaded chunk loop is covered),
and its tangent against central differences of the residual (chamber pressure and "p2")."""

import numpy as np
import pytest
import scipy.sparse as sp
import skfem

import softcrawl.fem.solid as mech
from softcrawl.fem import reference_models as RM
from softcrawl.fem.discretisation import element_first
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.neohooke import det3, inv_transpose3, iso_stress, mixed_tangent


def distorted_box_model(formulation):
    rng = np.random.default_rng(1)
    m = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 4)] * 3)
    shift = 0.08 * rng.uniform(-1, 1, m.p.shape)
    shift[2, m.p[2] == 0.0] = 0.0  # the bottom stays plane
    m = skfem.MeshTet(m.p + shift, m.t).with_boundaries({"z0": lambda x: np.abs(x[2]) < 1e-12})
    m = m.with_subdomains({"soft": lambda x: x[0] < 0.5, "hard": lambda x: x[0] >= 0.5})
    mats = {"soft": NeoHookean.nearly_incompressible(0.03, 50.0), "hard": NeoHookean(mu=0.1, bulk=2.0)}
    model = SolidModel(m, mats, dirichlet=[Dirichlet.fixed("z0")], formulation=formulation)
    x = model.initial_state()
    X = model.nodes  # a smooth large deformation + noise
    u = 0.2 * rng.uniform(-1, 1, (3, 3)) @ X + 0.05 * np.sin(3 * X[[1, 2, 0]])
    x[: model.n_u] = (u + 0.003 * rng.standard_normal(u.shape)).T.ravel()
    if model.mixed:
        x[model.n_u :] = 0.01 * rng.standard_normal(model.n_p)
    return model, x


def reference(model, x):
    """Element residuals and matrices straight from `fem.neohooke`, assembled on all dofs."""
    dN, dx, mu, K = model.space.dN, model.dx, model.mu, model.bulk
    node_dofs = model.space.node_dofs
    ue = x[: model.n_u].reshape(-1, 3)[node_dofs]  # (10, E, 3)
    F = np.einsum("aei,aJeq->iJeq", ue, dN) + np.eye(3)[:, :, None, None]
    J, H = det3(F), inv_transpose3(F)
    p = np.einsum("ce,ceq->eq", x[model.p_dofs], model.space.Np) if model.mixed else K * (J - 1)
    A = mixed_tangent(F, mu, p, J, H)
    if not model.mixed:
        A = A + K * J * J * H[:, :, None, None] * H[None, None]
    P = iso_stress(F, mu, J, H) + p * J * H
    u_dofs = 3 * node_dofs[:, None, :] + np.arange(3)[None, :, None]  # (10, 3, E)
    rows, cols, vals = [], [], []

    def add(block, r, c):  # block (E, nr, nc); r (nr, E), c (nc, E)
        rows.append(np.broadcast_to(r.T[:, :, None], block.shape).ravel())
        cols.append(np.broadcast_to(c.T[:, None, :], block.shape).ravel())
        vals.append(block.ravel())

    u = u_dofs.reshape(30, -1)
    add(np.einsum("aJeq,iJkLeq,bLeq,eq->eaibk", dN, A, dN, dx).reshape(-1, 30, 30), u, u)
    R = np.zeros(model.n_dofs)
    np.add.at(R, u.ravel(), np.einsum("aJeq,iJeq,eq->aie", dN, P, dx).reshape(30, -1).ravel())
    if model.mixed:
        Np = model.space.Np
        Kup = np.einsum("aJeq,iJeq,ceq,eq->eaic", dN, J * H, Np, dx).reshape(-1, 30, 4)
        add(Kup, u, model.p_dofs)
        add(Kup.transpose(0, 2, 1), model.p_dofs, u)
        add(-np.einsum("ceq,deq,eq->ecd", Np, Np, dx / K), model.p_dofs, model.p_dofs)
        np.add.at(R, model.p_dofs.ravel(), np.einsum("ceq,eq->ce", Np, (J - 1 - p / K) * dx).ravel())
    Kfull = sp.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(model.n_dofs,) * 2
    ).tocsr()
    return R, Kfull[model.free_dofs][:, model.free_dofs]


@pytest.mark.parametrize("formulation", ["p2p1", "p2"])
@pytest.mark.parametrize("chunk", [7, 128])
def test_assembly_matches_the_plain_tangent_on_a_distorted_mesh(formulation, chunk, monkeypatch):
    monkeypatch.setattr(mech, "_CHUNK", chunk)
    model, x = distorted_box_model(formulation)
    R_ref, K_ref = reference(model, x)
    R, K = model.residual_and_tangent(x, 0.0)
    scale = abs(K_ref).max()
    assert abs(K - K_ref).max() <= 1e-12 * scale
    assert np.abs(R - R_ref).max() <= 1e-12 * np.abs(R_ref).max()
    assert np.abs(model.internal_force(x) - R_ref).max() <= 1e-12 * np.abs(R_ref).max()


@pytest.mark.parametrize("formulation", ["p2p1", "p2"])
def test_tangent_is_the_derivative_of_the_residual_under_follower_pressure(formulation):
    model = RM.tube_model(3.0, 9.0, n_radial=2, n_angle=3, k_over_mu=50.0, formulation=formulation)
    rng = np.random.default_rng(2)
    x = model.initial_state()
    x[: model.n_u] = 2e-2 * rng.standard_normal(model.n_u)
    x = model.apply_dirichlet(x, 0.0)
    P = 0.01
    _, K = model.residual_and_tangent(x, P)
    free = model.free_dofs
    for _ in range(3):
        v = np.zeros(model.n_dofs)
        v[free] = rng.standard_normal(free.size)
        eps = 1e-6
        dR = (model.residual(x + eps * v, P) - model.residual(x - eps * v, P))[free] / (2 * eps)
        Kv = K @ v[free]
        assert np.linalg.norm(Kv - dR) <= 1e-6 * np.linalg.norm(Kv)


def test_mirrored_groups_assemble_like_full_blocks():
    """Upper triangles (Mirrored.upper) and mirrored off-diagonal blocks (Mirrored.block) give the
    matrix of the full symmetric element blocks, with Dirichlet rows/columns dropped."""
    from softcrawl.fem.pattern import Mirrored, Pattern

    rng = np.random.default_rng(3)
    n_dofs, n_items = 40, 25
    free_index = np.arange(n_dofs)
    free_index[[3, 17]] = -1
    free_index[free_index >= 0] = np.arange(n_dofs - 2)
    a = np.array([rng.choice(30, 6, replace=False) for _ in range(n_items)]).T  # (6, n_items)
    b = np.array([rng.choice(np.arange(30, 40), 2, replace=False) for _ in range(n_items)]).T
    both = np.vstack([a, b])
    Ke = rng.standard_normal((n_items, 8, 8))
    Ke = Ke + Ke.transpose(0, 2, 1)
    facets = a[:3, :7]  # a non-symmetric group on a few dofs
    Kf = rng.standard_normal((7, 3, 3))
    full = Pattern(free_index, [both, facets]).assemble([Ke, Kf])
    r, c = np.triu_indices(6)
    rp, cp = np.triu_indices(2)
    mirrored = Pattern(free_index, [Mirrored.upper(a), facets, Mirrored.block(a, b), Mirrored.upper(b)])
    K = mirrored.assemble([Ke[:, r, c], Kf, Ke[:, :6, 6:].reshape(n_items, -1), Ke[:, 6 + rp, 6 + cp]])
    assert mirrored.views(mirrored.new_values())[1].shape == (7, 3, 3)
    assert (K.indptr == full.indptr).all() and (K.indices == full.indices).all()
    assert np.abs(K.data - full.data).max() <= 1e-14 * np.abs(full.data).max()


def test_chamber_tangent_matches_the_plain_einsum():
    """dq/du of the follower pressure load against its einsum over (i, k, L) on every facet."""
    from softcrawl.fem.neohooke import cofactor3

    model = RM.tube_model(3.0, 9.0, n_radial=2, n_angle=3, k_over_mu=50.0)
    rng = np.random.default_rng(4)
    x = model.initial_state()
    x[: model.n_u] = 2e-2 * rng.standard_normal(model.n_u)
    chamber = model.chambers[0]
    _, dq = chamber.load(x, True)
    F = model.space.deformation_gradient(x, element_first(chamber.dN), chamber.node_dofs.T)
    J = det3(F)
    H = cofactor3(F) / J
    Nn = chamber.normal
    HN = np.einsum("iJfq,Jfq->ifq", H, Nn)
    D = -J * (np.einsum("ifq,klfq->iklfq", HN, H) - np.einsum("iLfq,kJfq,Jfq->ikLfq", H, H, Nn))
    ref = np.einsum("afq,ikLfq,bLfq,fq->faibk", chamber.N, D, chamber.dN, chamber.dx).reshape(-1, 30, 30)
    assert np.abs(dq - ref).max() <= 1e-12 * np.abs(ref).max()
