"""One wedge of 120 deg carries the FE body's symmetric states (`studies.crawl_fe.wedge`).

On a short body (30 mm actuators, one ring, the quick mesh) built whole and as a wedge, a
displacement and pressure field that is the same in every wedge,
u(R X) = R u(X) (radial, twisting and axial parts that vary with radius and height, and a part of
three lobes), gives:

- the wedge's residual, its cut rows folded onto their partners (`SolidModel.fold`), equal to the
  whole body's on the same nodes, with the chambers pressurised and the skirts pressed into the
  wall (1e-12 of the largest force; a wrong turn of the tie, a cut through a chamber or a missing
  fiber sheet leaves 1e-3 or more);
- the same for the tangent's product with a symmetric direction (Newton's steps agree);
- the whole body's wall forces, chamber volumes and foot positions from the wedge (`pipe.record`,
  `BodyModel.volumes`, `cycle.FootProbe`) and its mass (its drift, bend and heading are 0 by
  construction);
- its VTU file the whole body's; its two holds the axial translation and the twist, apart;
- unequal pressures and the asymmetric pipes refused before any work.
"""

import math

import meshio
import numpy as np
import pytest
from scipy.spatial import cKDTree

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.periodic_tie import rotation_z
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.fem.vtu import write_state
from softcrawl.geometry.body_mesh import mesh_body, settings_for
from softcrawl.geometry.design import EPSADesign, RobotDesign
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl_fe.cycle import FootProbe
from softcrawl.studies.crawl_fe.mass import part_masses
from softcrawl.studies.crawl_fe.model import build_body
from softcrawl.studies.crawl_fe.pipe import record
from softcrawl.studies.crawl_fe.wedge import CUTS, wedge_mesh, whole_force

DESIGN = RobotDesign(n_rings=1, epsa=EPSADesign(length=30.0)).replace(foot=CrawlSetup().foot)
QUICK = settings_for(DESIGN.foot, "quick")
TURN = rotation_z(2 * math.pi / 3)
P = 0.05  # MPa in every chamber


@pytest.fixture(scope="module")
def bodies():
    whole = build_body(CrawlSetup(), "quick", design=DESIGN)
    wedge = build_body(CrawlSetup(copies=3), "quick", design=DESIGN)
    for bm in (whole, wedge):
        bm.set_holds(0.0)  # the holds differ (six against two): both carry nothing here
        for c in bm.model.contacts:  # the wall 1 mm inside the skirt tips: every face pressed
            c.set_surface(CylinderWall(bm.design.foot.tip_radius - 1.0))
    return whole, wedge


def symmetric_state(model) -> np.ndarray:
    """u = a e_r + b e_theta + c e_z with a, b, c functions of (r, z) and of cos 3 theta; the
    mixed pressures as a field of the same kind; the same in every wedge."""
    X = np.asarray(model.nodes).T
    r, th, z = np.hypot(X[:, 0], X[:, 1]), np.arctan2(X[:, 1], X[:, 0]), X[:, 2]
    a, b = 0.01 * r * np.sin(z / 20.0), 0.005 * r * (1.0 + 0.3 * np.cos(3 * th))
    c = 0.02 * z + 0.01 * np.cos(3 * th) * r / 30.0
    u = np.column_stack([a * np.cos(th) - b * np.sin(th), a * np.sin(th) + b * np.cos(th), c])
    x = np.zeros(model.n_dofs)
    x[: model.space.n_u] = u.ravel()
    v = model.space.pressure_vertex
    x[model.space.n_u :] = 1e-3 * np.cos(3 * th[v]) + 1e-4 * z[v] / 50.0
    return x


def node_map(whole, wedge) -> np.ndarray:
    """The whole body's node at each of the wedge's nodes."""
    dist, idx = cKDTree(np.asarray(whole.model.nodes).T).query(np.asarray(wedge.model.nodes).T)
    assert dist.max() < 1e-9
    return idx


def test_the_wedge_is_one_tet_of_each_orbit_and_its_cuts_pair():
    whole = mesh_body(DESIGN, QUICK)
    w = wedge_mesh(whole)
    assert 3 * len(w.tets) == len(whole.tets)
    centroids = w.points[w.tets].mean(axis=1)
    turned = np.vstack([centroids @ np.linalg.matrix_power(TURN, k).T for k in range(3)])
    dist, idx = cKDTree(whole.points[whole.tets].mean(axis=1)).query(turned)
    assert dist.max() < 1e-9 and np.unique(idx).size == len(whole.tets)  # the three wedges are the body
    start, end = (np.unique(w.facets[c]) for c in CUTS)
    dist, idx = cKDTree(w.points[end]).query(w.points[start] @ TURN.T)
    assert dist.max() < 1e-9 and np.unique(idx).size == end.size == start.size > 0
    assert {n for n in w.region_names.values() if n.startswith("epsa")} == {"epsa1"}
    whole_epsa1 = np.sum(whole.region == next(k for k, n in whole.region_names.items() if n == "epsa1"))
    assert np.sum(w.region == next(k for k, n in w.region_names.items() if n == "epsa1")) == whole_epsa1


def test_a_mesh_without_the_symmetry_is_refused():
    whole = mesh_body(DESIGN, QUICK)
    points = whole.points.copy()
    points[np.argmax(points[:, 0])] += [0.3, 0.0, 0.0]
    with pytest.raises(SolverInputError, match="wedge"):
        wedge_mesh(type(whole)(points, whole.tets, whole.region, whole.region_names, whole.facets))
    with pytest.raises(SolverInputError, match="wedge"):
        wedge_mesh(whole, copies=4)
    # the mesher's own: without rings, the hubs' tets near the channel are not split the same way
    # in every wedge (docs/decisions/096-body-wedge.md)
    bare = RobotDesign(n_rings=0, epsa=EPSADesign(length=30.0)).replace(foot=DESIGN.foot)
    with pytest.raises(SolverInputError, match="not 3-fold symmetric"):
        wedge_mesh(mesh_body(bare, QUICK))


def test_a_symmetric_state_gives_the_whole_bodys_residual_and_tangent_on_the_wedge(bodies):
    whole, wedge = bodies
    xw, xm = symmetric_state(whole.model), symmetric_state(wedge.model)
    Rw, Kw = whole.model.residual_and_tangent(xw, pressure=[P, P, P])
    Rm, Km = wedge.model.residual_and_tangent(xm, pressure=[P])
    idx = node_map(whole, wedge)
    off = ~np.isin(np.arange(idx.size), wedge.model.boundary_nodes(CUTS[1]))  # the next wedge's nodes
    nu_w, nu_m = whole.model.space.n_u, wedge.model.space.n_u
    scale = np.abs(Rw[:nu_w]).max()
    assert scale > 1.0  # pressure, stretch and the wall: real forces

    def compare(vw, vm):
        folded = wedge.model.fold(vm)
        u_w, u_m = vw[:nu_w].reshape(-1, 3)[idx[off]], folded[:nu_m].reshape(-1, 3)[off]
        assert np.abs(u_w - u_m).max() < 1e-12 * np.abs(vw[:nu_w]).max()
        group_w = {(int(v), int(g)): k for k, (v, g) in enumerate(
            zip(whole.model.space.pressure_vertex, whole.model.space.pressure_group))}  # fmt: skip
        vm_, gm = wedge.model.space.pressure_vertex, wedge.model.space.pressure_group
        keep = off[vm_]
        p_w = np.array([vw[nu_w + group_w[(int(idx[v]), int(g))]] for v, g in zip(vm_[keep], gm[keep])])
        assert np.abs(p_w - folded[nu_m:][keep]).max() < 1e-12 * np.abs(vw[nu_w:]).max()

    compare(Rw, Rm)
    # the tangent (on the free dofs, T^T K T for the wedge) along a symmetric direction
    products = []
    for model, K, x in ((whole.model, Kw, xw), (wedge.model, Km, xm)):
        free = model.constraints.free_dofs
        v = np.zeros(model.n_dofs)
        v[free] = K @ (0.1 * x[free])
        products.append(v)
    compare(*products)
    assert len(set(wedge.model.pressures([P]))) == 1


def test_the_wedge_reports_the_whole_bodys_forces_volumes_feet_and_mass(bodies):
    whole, wedge = bodies
    xw, xm = symmetric_state(whole.model), symmetric_state(wedge.model)
    sw, sm = record(whole, "insert", xw), record(wedge, "insert", xm)
    for foot in ("rear", "front"):
        assert sw.normal[foot] > 1.0
        assert sm.normal[foot] == pytest.approx(sw.normal[foot], rel=1e-10)
        assert np.allclose(sm.friction[foot], sw.friction[foot], rtol=0, atol=1e-10 * sw.normal[foot])
    assert wedge.volumes(xm) == pytest.approx(whole.volumes(xw), rel=1e-12)
    # the axial hold's mean over one node per orbit is the whole face's (`wedge.face_nodes`)
    hold = wedge.holds["hold_z"].extension(xm)
    assert hold == pytest.approx(whole.holds["hold_z"].extension(xw), rel=1e-12) and abs(hold) > 1e-3
    pw, pm = FootProbe(whole.model.space), FootProbe(wedge.model.space, copies=3)
    for read in ("z", "arc"):
        a, b = getattr(pw, read)(xw), getattr(pm, read)(xm)
        assert b == pytest.approx(a, rel=1e-12, abs=1e-12)
    # (a wedge's drift, bend and heading are 0 by construction: its faces are turned copies)
    mass = lambda bm, n: sum(p.mass_g for p in part_masses(bm.model.mesh, bm.materials, n))  # noqa: E731
    assert mass(wedge, 3) == pytest.approx(mass(whole, 1), rel=1e-12)


def test_a_wedges_force_turned_into_the_whole_bodys():
    assert np.allclose(whole_force([1.0, 2.0, 3.0], 3), [0.0, 0.0, 9.0], atol=1e-14)
    assert np.array_equal(whole_force([1.0, 2.0, 3.0], 1), [1.0, 2.0, 3.0])


def test_the_wedges_vtu_is_the_whole_bodys(bodies, tmp_path):
    """Written with `copies`, the wedge's VTU holds the whole body's points, displacements and
    stresses (at the cuts twice): each of its points carries the whole body's values there."""
    whole, wedge = bodies
    xw, xm = symmetric_state(whole.model), symmetric_state(wedge.model)
    a = meshio.read(write_state(tmp_path / "whole.vtu", whole.model, xw, precision=64))
    b = meshio.read(write_state(tmp_path / "wedge.vtu", wedge.model, xm, precision=64, copies=3))
    dist, idx = cKDTree(a.points).query(b.points)
    assert dist.max() < 1e-9 and np.unique(idx).size == len(a.points)  # every point of the body
    u = a.point_data["displacement_mm"]
    assert np.abs(b.point_data["displacement_mm"] - u[idx]).max() < 1e-12 * np.abs(u).max()
    centres = lambda m: m.points[m.cells[0].data].mean(axis=1)  # noqa: E731
    dist, cell = cKDTree(centres(a)).query(centres(b))
    assert dist.max() < 1e-9 and len(b.cells[0].data) == len(a.cells[0].data)
    s = a.cell_data["cauchy_stress_MPa"][0]
    assert np.abs(b.cell_data["cauchy_stress_MPa"][0] - s[cell]).max() < 1e-9 * np.abs(s).max()


def test_the_wedges_two_holds_see_the_axial_translation_and_the_twist_apart(bodies):
    """The tie leaves the axial translation and the twist about the axis; `hold_z` reads the
    first (its mean u_z over one node per orbit), `twist` the second (mean u_x: -theta ybar on the
    wedge about +y), each blind to the other, and both load the wedge through `AxialLink.nodes`."""
    _, wedge = bodies
    X = np.asarray(wedge.model.nodes).T
    shift, turn = np.zeros(wedge.model.n_dofs), np.zeros(wedge.model.n_dofs)
    shift[2 : wedge.model.space.n_u : 3] = 0.7
    theta = 1e-3
    turn[: wedge.model.space.n_u] = (theta * np.column_stack([-X[:, 1], X[:, 0], 0 * X[:, 2]])).ravel()
    hz, tw = wedge.holds["hold_z"], wedge.holds["twist"]
    assert hz.extension(shift) == pytest.approx(0.7, rel=1e-12) and abs(tw.extension(shift)) < 1e-15
    ybar = X[tw.dofs[:, 0] // 3, 1].mean()
    assert ybar > 10.0  # the rear hub face's third about +y
    assert tw.extension(turn) == pytest.approx(-theta * ybar, rel=1e-12) and abs(hz.extension(turn)) < 1e-15
    tw.set_load(5.0, 0.0, 0.0)  # the twist hold pulls the turned wedge back (share 1/3)
    r, _ = tw.arrays(turn)
    assert r.sum() == pytest.approx(-(-5.0 * tw.extension(turn)) * tw.spec.share, rel=1e-12)
    tw.set_load(0.0, 0.0, 0.0)


def test_a_wedge_refuses_unequal_pressures_and_asymmetric_pipes(bodies, tmp_path):
    from softcrawl.studies.crawl.schedule import preset
    from softcrawl.studies.crawl_fe.files import run_and_write

    _, wedge = bodies
    assert wedge.pressures([0.1, 0.1, 0.1]) == [0.1]
    with pytest.raises(SolverInputError, match="wedge"):
        wedge.pressures([0.1, 0.0, 0.1])
    for pipe in ("elbow", "bellows"):  # refused before any work: no folder written
        with pytest.raises(SolverInputError, match="wedge"):
            run_and_write(
                CrawlSetup(copies=3), preset("inflate"), tmp_path / pipe, pipe=pipe, bend_radius=80.0
            )
        assert not (tmp_path / pipe).exists()
