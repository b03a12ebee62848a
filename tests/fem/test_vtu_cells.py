"""The VTU connectivities other than the solid's quadratic tetrahedra (issue 32), at prescribed
states, no solve: the quadratic triangles (VTK type 22, meshio "triangle6") of the fiber sheets and
of the contact fields, and the line cells (VTK type 3) of the line fibers.

* triangle6: VTK wants the vertices, then the midpoints of the edges (0,1), (1,2), (2,0). On a mesh
  with straight edges each midside node is exactly its edge's midpoint; on the curved ePSA each is
  nearer its own edge's midpoint than the two others', and all six lie on the wrapped cylinder.
* line: the cells are the fiber segments, their points the fibers' points; under a homogeneous
  deformation x = F X the embedded fibers' points move by (F - I) X exactly (the P2 field
  interpolates a linear field exactly).
"""

import math

import meshio
import numpy as np
import pytest
import skfem

from softcrawl.fem.structured import box
from softcrawl.fem.vtu import _facet_triangle6, write_winding
from softcrawl.geometry.design import EPSADesign
from softcrawl.studies.epsa.model import build_model

F = np.diag([1.05, 1.05, 1.2])
DESIGN = EPSADesign(length=40.0, fiber_turns=8)


def homogeneous(model) -> np.ndarray:
    x = model.initial_state()
    x[: model.n_u] = ((F - np.eye(3)) @ model.nodes).T.ravel()
    return x


def test_triangle6_nodes_are_vertices_then_the_vtk_edge_midpoints():
    mesh = skfem.MeshTet2.from_mesh(box((1.0, 2.0, 3.0), (2, 2, 2)))
    facets = mesh.boundary_facets()
    nodes = _facet_triangle6(mesh, facets)
    p = mesh.doflocs[:, nodes]  # (3, F, 6)
    assert nodes.shape == (facets.size, 6)
    assert np.array_equal(np.sort(nodes[:, :3], axis=1), np.sort(mesh.facets[:, facets].T, axis=1))
    for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0))):
        assert np.allclose(p[:, :, 3 + k], (p[:, :, a] + p[:, :, b]) / 2, atol=1e-14)


@pytest.fixture(scope="module")
def sheet_model():
    return build_model(DESIGN, mesh="quick", fibers="sheet")[0]


def test_the_sheet_file_is_quadratic_triangles_on_the_wrapped_surface(sheet_model, tmp_path):
    x = homogeneous(sheet_model)
    m = meshio.read(write_winding(tmp_path / "w.vtu", sheet_model, x, precision=64))
    assert [c.type for c in m.cells] == ["triangle6"]
    cells = m.cells[0].data
    assert np.array_equal(np.unique(cells), np.arange(len(m.points)))
    p = m.points[cells]  # (E, 6, 3)
    mids = np.stack([(p[:, a] + p[:, b]) / 2 for a, b in ((0, 1), (1, 2), (2, 0))], axis=1)
    dist = np.linalg.norm(p[:, 3:, None, :] - mids[:, None, :, :], axis=-1)
    assert np.array_equal(dist.argmin(axis=2), np.tile(np.arange(3), (len(cells), 1)))
    assert np.hypot(p[..., 0], p[..., 1]) == pytest.approx(DESIGN.outer_radius, rel=1e-9)
    assert m.point_data["displacement_mm"] == pytest.approx(m.points @ (F - np.eye(3)).T, abs=1e-12)
    # a uniform stretch: every facet of a family carries the same tension, > 0 (fibers stretched)
    t = m.cell_data["fiber_tension_N"][0]
    assert t.shape == (len(cells), 2) and t.min() > 0
    assert t == pytest.approx(np.broadcast_to(t.mean(axis=0), t.shape), rel=1e-9)


def test_the_line_file_is_the_fiber_segments_with_their_points(tmp_path):
    model = build_model(DESIGN, mesh="quick", fibers="lines")[0]
    x = homogeneous(model)
    m = meshio.read(write_winding(tmp_path / "w.vtu", model, x, precision=64))
    assert [c.type for c in m.cells] == ["line"]
    fibers = model.fibers
    assert np.array_equal(m.cells[0].data, fibers.segments)
    assert np.allclose(m.points, fibers.points, atol=0)
    assert m.point_data["displacement_mm"] == pytest.approx(fibers.points @ (F - np.eye(3)).T, abs=1e-10)
    # every segment joins neighbouring points of one helix (no cell across fibers)
    seg = fibers.segments
    assert np.array_equal(fibers.fiber_of_segment, m.cell_data["fiber"][0])
    length = np.linalg.norm(fibers.points[seg[:, 1]] - fibers.points[seg[:, 0]], axis=1)
    assert length.max() < 2 * math.pi * DESIGN.outer_radius / 8
