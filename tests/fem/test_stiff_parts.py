"""The rigid-motion projection of a prediction on the stiff parts (fem.stiff_parts).

* Kabsch recovers a rotation exactly;
* a linearised rotation (the Euler predictor's chord) of a stiff part becomes a rigid motion of
  its last state: every distance between its nodes is that of the last state (round-off), its
  centroid is the prediction's, the soft nodes and the mixed pressures keep their prediction;
* a prediction that is already rigid is left unchanged;
* the stiff parts of a model are the connected stiff elements, and a part with a prescribed
  displacement is left out;
* on a path, the projection changes only Newton's starting point: the same converged state, in
  fewer Newton iterations (the block swings ~1.1 mm sideways on a 1.2 mm soft column).
"""

import numpy as np
import pytest
import skfem
from scipy.spatial.distance import pdist

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.newton import NewtonOptions
from softcrawl.fem.path import load_path
from softcrawl.fem.stiff_parts import StiffParts, kabsch
from softcrawl.fem.structured import tag_boundaries

SOFT = NeoHookean.nearly_incompressible(0.03, 1000.0)
STIFF = NeoHookean(mu=740.7, bulk=2222.2)


def _rotation(axis, angle):
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def test_kabsch_recovers_a_rotation():
    a = np.random.default_rng(0).standard_normal((20, 3))
    R = _rotation((1, 2, -0.5), 0.7)
    assert np.allclose(kabsch(a, a @ R.T + (3.0, -1.0, 2.0)), R, atol=1e-13)


def test_a_linearised_rotation_becomes_rigid():
    rng = np.random.default_rng(1)
    X = rng.uniform(0, 5, (3, 12))  # 12 nodes; nodes 0-7 stiff, 8-11 soft
    n_u = 36
    parts = StiffParts(X, [np.arange(8)], n_u)
    x_last = np.r_[0.01 * rng.standard_normal(n_u), rng.standard_normal(5)]  # 5 pressure dofs
    a = X.T + x_last[:n_u].reshape(-1, 3)
    w = np.array([0.0, 0.2, 0.1])  # a 13 deg turn, linearised: b = a + w x (a - c)
    pred = x_last.copy()
    pred[:n_u] += (np.cross(w, a - a[:8].mean(axis=0)) + (0.5, 0.0, 0.0)).ravel()
    out = parts.project(x_last, pred)
    b_out = X.T + out[:n_u].reshape(-1, 3)
    b_pred = X.T + pred[:n_u].reshape(-1, 3)
    assert np.max(np.abs(pdist(b_pred[:8]) - pdist(a[:8]))) > 1e-2  # the chord stretched the part
    assert np.allclose(pdist(b_out[:8]), pdist(a[:8]), rtol=0, atol=1e-12)
    assert np.allclose(b_out[:8].mean(axis=0), b_pred[:8].mean(axis=0), atol=1e-12)
    assert np.array_equal(out[24:], pred[24:])  # soft nodes and pressures untouched
    again = parts.project(x_last, out)  # already rigid: unchanged
    assert np.allclose(again, out, rtol=0, atol=1e-12)


def _bar(dirichlet_top: bool):
    """A soft column [0, 1]^2 x [0, 2] clamped at its base with a stiff block on top (z > 1)."""
    mesh = skfem.MeshTet.init_tensor(np.linspace(0, 1, 3), np.linspace(0, 1, 3), np.linspace(0, 2, 6))
    zc = mesh.p[2, mesh.t].mean(axis=0)
    mesh = mesh.with_subdomains({"soft": np.nonzero(zc < 1.2)[0], "stiff": np.nonzero(zc > 1.2)[0]})
    mesh = tag_boundaries(
        mesh, {"bottom": lambda x: np.abs(x[2]) < 1e-9, "top": lambda x: np.abs(x[2] - 2) < 1e-9}
    )
    bcs = [Dirichlet.fixed("bottom")] + ([Dirichlet.symmetry("top", 2)] if dirichlet_top else [])
    return SolidModel(
        mesh, {"soft": SOFT, "stiff": STIFF}, dirichlet=bcs, dead_loads={"top": (0.004, 0.0, 0.0)}
    )


def test_the_stiff_parts_of_a_model():
    model = _bar(dirichlet_top=False)
    parts = StiffParts.of(model, 100.0)
    assert len(parts.parts) == 1
    stiff = model.space.elem_nodes[model.mesh.subdomains["stiff"]]
    assert np.array_equal(parts.parts[0], np.unique(stiff))
    assert StiffParts.of(model, 1e6).parts == []  # nothing that much stiffer
    assert StiffParts.of(_bar(dirichlet_top=True), 100.0).parts == []  # held: left out


def test_a_ratio_of_one_or_less_is_refused():
    with pytest.raises(SolverInputError, match="rigid_ratio"):
        load_path(_bar(dirichlet_top=False), [(0.0, 1.0)], options=NewtonOptions(rigid_ratio=0.5))


def test_the_projection_changes_only_the_start_of_newton():
    model = _bar(dirichlet_top=False)
    targets = [(0.0, f) for f in (0.25, 0.5, 0.75, 1.0)]
    runs = [load_path(model, targets, options=NewtonOptions(rigid_ratio=r)) for r in (None, 100.0)]
    assert all(r.converged for r in runs), [r.message for r in runs]
    tip = [model.displacement(r.steps[-1].x)[:, model.boundary_nodes("top")].mean(axis=1) for r in runs]
    assert tip[0][0] > 0.1  # the block turns and moves sideways
    assert tip[1] == pytest.approx(tip[0], rel=1e-7, abs=1e-9)
    assert runs[1].stats.iterations < runs[0].stats.iterations  # observed 21 against 28
