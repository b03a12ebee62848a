"""`studies.foot.outputs` at prescribed states, no solve (issue 32: the reported stress, strain and
deformation of the contact studies guarded line by line).

* weighted percentile: the value below which q % of the weight lies, on hand-made data;
* max principal strain = largest principal stretch - 1: 0.2 under F = diag(1.2, 1, 0.9);
* deformation = largest displacement relative to the mean displacement of the backing face: 0
  under a rigid shift, max |(F - I)(X - mean_backing X)| under a homogeneous F;
* the summaries over a subset of elements (a face's) are the max and percentile of that subset;
  the face's elements are the elements with a facet on it.
"""

import numpy as np
import pytest

from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import SolidModel
from softcrawl.fem.post import element_fields
from softcrawl.fem.structured import box
from softcrawl.studies.foot.outputs import face_elements, face_metrics, solid_metrics, weighted_percentile


def test_weighted_percentile_by_hand():
    v = np.array([5.0, 1.0, 4.0, 2.0, 3.0])
    w = np.ones(5)
    assert weighted_percentile(v, w, 50.0) == 3.0  # 3 of 5 equal weights lie at or below 3
    assert weighted_percentile(v, w, 40.0) == 2.0
    assert weighted_percentile(v, w, 100.0) == 5.0
    assert weighted_percentile(v, w, 0.0) == 1.0
    # a heavy small value: 99 % of the weight is at 1, so the 99th percentile is 1, the 99.5th is 5
    w2 = np.array([1.0, 99.0 * 4, 1.0, 1.0, 1.0]) / 4
    assert weighted_percentile(v, w2, 99.0) == 1.0
    assert weighted_percentile(v, w2, 99.9) == 5.0
    # beyond the last weight (round-off in the cumulative sum): the largest value
    assert weighted_percentile(v, w, 100.0 + 1e-9) == 5.0


@pytest.fixture(scope="module")
def model():
    return SolidModel(box((2.0, 3.0, 4.0), (3, 3, 4)), NeoHookean.nearly_incompressible(0.03, 30.0))


def state(model, u_of_X):
    x = model.initial_state()
    x[: model.n_u] = u_of_X(model.nodes).T.ravel()
    return x


def test_strain_and_deformation_of_a_homogeneous_state(model):
    F = np.diag([1.2, 1.0, 0.9])
    x = state(model, lambda X: (F - np.eye(3)) @ X)
    m = solid_metrics(model, x, backing="z0")
    assert m["max_principal_strain_max"] == pytest.approx(0.2, rel=1e-12)
    assert m["max_principal_strain_p99"] == pytest.approx(0.2, rel=1e-12)
    X = model.nodes
    ref = X[:, model.boundary_nodes("z0")].mean(axis=1)
    expected = np.linalg.norm((F - np.eye(3)) @ (X - ref[:, None]), axis=0).max()
    assert m["deformation_max_mm"] == pytest.approx(expected, rel=1e-12)
    vm = element_fields(model, x).von_mises
    assert m["von_mises_mpa_max"] == pytest.approx(vm.max(), rel=1e-12)
    assert m["von_mises_mpa_max"] > 0
    rigid = solid_metrics(
        model, state(model, lambda X: 0 * X + np.array([[1.0], [-2.0], [3.0]])), backing="z0"
    )
    assert rigid["deformation_max_mm"] == pytest.approx(0.0, abs=1e-12)
    assert rigid["von_mises_mpa_max"] == pytest.approx(0.0, abs=1e-12)


def wavy(model):
    return state(model, lambda X: 0.05 * np.vstack([X[2] ** 2, np.sin(X[0]) * X[2], X[0] * X[1]]))


def test_summaries_over_a_subset_are_the_subsets(model):
    x = wavy(model)
    fields = element_fields(model, x)
    volume = model.dx.sum(axis=1)
    sel = np.sort(np.argsort(fields.von_mises)[: volume.size // 2])  # the lower half: not the maximum
    m = solid_metrics(model, x, backing="z0", elements=sel)
    assert m["von_mises_mpa_max"] == pytest.approx(fields.von_mises[sel].max(), rel=1e-12)
    assert m["von_mises_mpa_p99"] == pytest.approx(
        weighted_percentile(fields.von_mises[sel], volume[sel], 99.0), rel=1e-12
    )
    assert m["max_principal_strain_max"] == pytest.approx(fields.max_stretch[sel].max() - 1.0, rel=1e-12)
    assert m["max_principal_strain_p99"] == pytest.approx(
        weighted_percentile(fields.max_stretch[sel] - 1.0, volume[sel], 99.0), rel=1e-12
    )
    everything = solid_metrics(model, x, backing="z0")
    assert everything["von_mises_mpa_max"] == pytest.approx(fields.von_mises.max(), rel=1e-12)
    assert everything["von_mises_mpa_max"] > m["von_mises_mpa_max"]
    assert m["von_mises_mpa_p99"] < m["von_mises_mpa_max"]  # enough elements for 1 % above it
    assert everything["von_mises_mpa_p99"] > m["von_mises_mpa_p99"]
    # the deformation is over all nodes, whatever the elements
    assert m["deformation_max_mm"] == everything["deformation_max_mm"]
    assert set(m) == {
        "von_mises_mpa_max",
        "von_mises_mpa_p99",
        "max_principal_strain_max",
        "max_principal_strain_p99",
        "deformation_max_mm",
    }


def test_face_elements_and_face_metrics(model):
    mesh = model.mesh
    facets = mesh.boundaries["x1"]
    verts = {frozenset(mesh.facets[:, f]) for f in facets}
    expected = [e for e in range(mesh.t.shape[1]) if any(v <= set(mesh.t[:, e]) for v in verts)]
    assert face_elements(model, "x1").tolist() == expected
    x = wavy(model)
    fm = face_metrics(model, x, "x1", "z0")
    sm = solid_metrics(model, x, "z0", np.array(expected))
    assert fm == {f"x1_{k}": v for k, v in sm.items() if k != "deformation_max_mm"}
    assert len(fm) == 4
