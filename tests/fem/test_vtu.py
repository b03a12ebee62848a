"""VTU files as ParaView users expect them, read back with meshio and pyvista (VTK's own reader).

A fibered ePSA on the quick mesh, 0 -> 10 kPa: curved quadratic tetrahedra (VTK type 24) with every
point used, the reference state first in the series, named vector and tensor components, region
names, pressure and load factor in every file, and the winding's fiber tension."""

import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from softcrawl.fem.vtu import (
    SKFEM_TET_EDGES,
    VTK_TET10_EDGES,
    path_times,
    turned_copies,
    write_path,
    write_state,
)
from softcrawl.geometry.design import EPSADesign
from softcrawl.studies.epsa.response import simulate_epsa

pv = pytest.importorskip("pyvista")


@pytest.fixture(scope="module")
def series(tmp_path_factory):
    design = EPSADesign(length=40.0, fiber_turns=8)
    solved = simulate_epsa(design, quick=True, pressures_kpa=(5.0, 10.0), keep_model=True)
    folder = tmp_path_factory.mktemp("vtu")
    files = write_path(folder, solved.model, solved.path)
    return solved, folder, files


def test_the_skfem_and_vtk_edge_orders_are_the_same_edges():
    assert [set(e) for e in SKFEM_TET_EDGES] == [set(e) for e in VTK_TET10_EDGES]


def test_solid_files_are_quadratic_tets_without_orphan_points(series):
    solved, folder, files = series
    assert len(files) == 3  # the reference state and the two pressures
    m = meshio.read(files[-1])
    assert [c.type for c in m.cells] == ["tetra10"]
    cells = m.cells[0].data
    assert cells.shape == (solved.model.mesh.t.shape[1], 10)
    assert np.array_equal(np.unique(cells), np.arange(len(m.points)))  # every point is used
    # every midside node lies on its VTK edge (the mesh is curved: near, not at, the midpoint),
    # and it is nearer to its own edge's midpoint than to any other edge's of the cell
    p = m.points[cells]  # (E, 10, 3)
    mids = np.stack([(p[:, a] + p[:, b]) / 2 for a, b in VTK_TET10_EDGES], axis=1)  # (E, 6, 3)
    dist = np.linalg.norm(p[:, 4:, None, :] - mids[:, None, :, :], axis=-1)  # (E, node, edge)
    assert np.array_equal(dist.argmin(axis=2), np.tile(np.arange(6), (len(cells), 1)))
    grid = pv.read(files[-1])
    assert set(np.unique(grid.celltypes)) == {24}  # VTK_QUADRATIC_TETRA
    # the curved geometry survives: VTK's volume of the quadratic cells (it subdivides them) is
    # far closer to the solver's exact P2 volume than that of the straight-sided tetrahedra
    exact = solved.model.space.volume
    straight = grid.linear_copy().volume
    assert abs(grid.volume - exact) < 0.5 * abs(straight - exact)


def test_every_file_names_its_pressure_load_factor_regions_and_components(series):
    solved, folder, files = series
    pressures = [0.0, 5.0, 10.0]
    for f, p in zip(files, pressures):
        grid = pv.read(f)
        assert grid.field_data["pressure_kPa"][0] == pytest.approx(p, rel=1e-6)
        assert grid.field_data["load_factor"][0] == 0.0
        regions = {
            k.split(":", 1)[1]: int(v[0]) for k, v in grid.field_data.items() if k.startswith("region:")
        }
        assert regions == {"epsa": 0, "seal_head": 1}
        assert set(np.unique(grid.cell_data["region"])) == {0, 1}
    tree = ET.parse(files[-1])
    names = {
        a.get("Name"): [a.get(f"ComponentName{i}") for i in range(int(a.get("NumberOfComponents", 1)))]
        for a in tree.iter("DataArray")
    }
    assert names["displacement_mm"] == ["X", "Y", "Z"]
    assert names["cauchy_stress_MPa"] == ["XX", "YY", "ZZ", "XY", "YZ", "XZ"]
    grid = pv.read(files[-1])
    array = grid.GetCellData().GetArray("cauchy_stress_MPa")
    assert array.GetComponentName(3) == "XY"  # VTK's reader sees the names
    m = meshio.read(files[-1])
    assert m.field_data["pressure_kPa"][0] == pytest.approx(10.0)
    # the nodal displacements are the solver's, in float32 by default (063), to the last digit
    # with precision=64
    u_model = solved.model.displacement(solved.path.steps[-1].x)
    u_file = m.point_data["displacement_mm"]
    assert u_file.dtype == np.float32 and m.points.dtype == np.float32
    assert np.abs(u_file).max(axis=0) == pytest.approx(np.abs(u_model).max(axis=1), rel=1e-6)
    assert u_file[:, 2].max() > 1.0  # and the state is not the reference one
    full = write_state(folder / "f64.vtu", solved.model, solved.path.steps[-1].x, precision=64)
    u64 = meshio.read(full).point_data["displacement_mm"]
    assert np.abs(u64).max(axis=0) == pytest.approx(np.abs(u_model).max(axis=1), rel=1e-12)
    assert full.stat().st_size > 1.5 * files[-1].stat().st_size


def test_series_starts_at_the_reference_state_and_has_the_winding(series):
    solved, folder, files = series
    pvd = ET.parse(folder / "step.pvd").getroot()
    entries = [(float(d.get("timestep")), d.get("file")) for d in pvd.iter("DataSet")]
    # the time is the ramp's path parameter: here, below any limit point, the pressure in kPa
    assert entries == [(0.0, "step_000.vtu"), (5.0, "step_001.vtu"), (10.0, "step_002.vtu")]
    assert pv.read(files[-1]).field_data["path_parameter"][0] == pytest.approx(10.0)
    assert np.abs(meshio.read(files[0]).point_data["displacement_mm"]).max() == 0.0
    winding = sorted(folder.glob("winding_*.vtu"))
    assert len(winding) == 3 and (folder / "winding.pvd").exists()
    w = pv.read(winding[-1])
    assert set(np.unique(w.celltypes)) == {22}  # VTK_QUADRATIC_TRIANGLE: the wrapped outer surface
    assert w.GetCellData().GetArray("fiber_tension_N").GetComponentName(1) == "family 2"
    # and one array per family, for readers that drop VTK's component names
    assert np.array_equal(w.cell_data["fiber_tension_family2_N"], w.cell_data["fiber_tension_N"][:, 1])
    tension = w.cell_data["fiber_tension_N"]
    assert tension.shape[1] == 2 and tension.max() > 0
    # the same fibers, the same forces as the solver's (facet averages of its quadrature points)
    assert tension.max() <= solved.curve.rows[-1].max_fiber_tension_n * (1 + 1e-9)
    assert tension.max() > 0.5 * solved.curve.rows[-1].max_fiber_tension_n
    assert w.field_data["pressure_kPa"][0] == pytest.approx(10.0)
    assert np.abs(pv.read(winding[0]).cell_data["fiber_tension_N"]).max() < 1e-12
    used = meshio.read(winding[-1]).cells[0].data
    assert np.unique(used).size == w.n_points  # no orphan points in the winding file either


def test_line_fibers_are_written_with_their_segment_forces(tmp_path):
    from softcrawl.fem.vtu import write_winding

    design = EPSADesign(length=40.0, fiber_turns=8)
    solved = simulate_epsa(design, quick=True, pressures_kpa=(5.0,), keep_model=True, fibers="lines")
    step = solved.path.steps[-1]
    path = write_winding(tmp_path / "w.vtu", solved.model, step.x, pressure_mpa=step.pressure)
    w = pv.read(path)
    assert set(np.unique(w.celltypes)) == {3}  # VTK_LINE
    assert w.cell_data["fiber_tension_N"].max() == pytest.approx(solved.curve.rows[-1].max_fiber_tension_n)
    assert w.field_data["pressure_kPa"][0] == pytest.approx(5.0)


def test_path_times_increase_past_a_limit_point():
    """Under volume control past a limit point the pressure falls; the path parameter does not."""
    times = path_times([0.0, 40.0, 80.0, 92.0, 85.0, 70.0], [0.0] * 6)
    assert times == [0.0, 40.0, 80.0, 92.0, 99.0, 114.0]
    assert path_times([[0, 0, 0], [100, 40, 60], [100, 40, 60]], [0, 1, 1])[1:] == [200.0, 200.000001]


def test_a_wedge_is_written_as_the_whole_body_its_vectors_and_stresses_turned():
    """`turned_copies`: a quarter wedge's point at (1, 0, 0) with the vector e_x and the stress
    e_x (x) e_x lands at (0, 1, 0) with e_y and e_y (x) e_y in the next copy; cells are offset by
    the point count and scalars repeated."""
    points = np.array([[1.0, 0.0, 0.0], [2.0, 0.0, 0.5], [1.0, 1.0, 0.0], [1.0, 0.0, 1.0]])
    stress = np.zeros((1, 6))
    stress[0, 0] = 1.0  # XX
    mesh = meshio.Mesh(
        points,
        [("tetra", np.array([[0, 1, 2, 3]]))],
        point_data={"u": np.tile([1.0, 0.0, 0.0], (4, 1)), "p": np.arange(4.0)},
        cell_data={"s": [stress], "q": [np.array([7.0])]},
    )
    whole = turned_copies(mesh, 4, {"u"}, {"s"})
    # a shear turned by 120 deg: R s R^T, not R^T s R (they differ for XY)
    sheared = meshio.Mesh(points, [("tetra", np.array([[0, 1, 2, 3]]))], cell_data={"s": [np.eye(1, 6, 3)]})
    c, s = np.cos(2 * np.pi / 3), np.sin(2 * np.pi / 3)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    shear = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    t = R @ shear @ R.T
    expected = [t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[1, 2], t[0, 2]]
    assert np.allclose(turned_copies(sheared, 3, (), {"s"}).cell_data["s"][0][1], expected, atol=1e-15)
    assert not np.allclose(R.T @ shear @ R, t)  # the test tells the two apart
    assert whole.points.shape == (16, 3) and np.allclose(whole.points[4], [0.0, 1.0, 0.0], atol=1e-15)
    assert np.array_equal(whole.cells[0].data[1], [4, 5, 6, 7])
    assert np.allclose(whole.point_data["u"][4], [0.0, 1.0, 0.0], atol=1e-15)
    assert np.allclose(whole.point_data["u"][8], [-1.0, 0.0, 0.0], atol=1e-15)
    assert np.allclose(whole.cell_data["s"][0][1], [0.0, 1.0, 0.0, 0.0, 0.0, 0.0], atol=1e-15)  # YY
    assert np.array_equal(whole.point_data["p"], np.tile(np.arange(4.0), 4))
    assert np.array_equal(whole.cell_data["q"][0], [7.0] * 4)
    assert turned_copies(mesh, 1) is mesh
