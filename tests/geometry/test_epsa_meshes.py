"""Meshed Table 1 ePSA: acceptance figures, tags, orientation, skfem conversion, export, cache, CLI.

The mesh is built once per session (pytetwild takes seconds to a minute) into a temporary cache.
"""

import json
import math
import time

import numpy as np
import pytest

from softcrawl.geometry.design import EPSADesign
from softcrawl.geometry.epsa_shape import epsa_analytic_areas
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tagging import boundary_facets, distance_to_surface
from softcrawl.geometry.tetwild import mesh_epsa

EPSA_TAGS = {"chamber_wall", "chamber_ends", "outer", "end_bottom", "end_top"}
#: Fiber points must lie within this distance of the meshed outer surface (mm): one third of the
#: 0.3 mm fiber diameter. The facets are chords of the exact cylinder (their vertices are snapped onto
#: rho = R0), so the gap is the chord sagitta c^2 / (8 R0): 0.056 mm for the ~2 mm facets of the default mesh.
FIBER_SURFACE_TOL = 0.1


#: The session mesh fixture (pytetwild, ~25 s idle) is paid by the first test that uses it.
pytestmark = pytest.mark.timeout(600)


@pytest.fixture(scope="session")
def cache_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("mesh_cache")


@pytest.fixture(scope="session")
def design():
    return EPSADesign()


@pytest.fixture(scope="session")
def mesh(design, cache_dir) -> TaggedMesh:
    return mesh_epsa(design, cache_dir=cache_dir)


def test_volume_within_1_percent(mesh, design):
    assert abs(mesh.volume() / design.body_volume - 1) < 0.01


def test_chamber_wall_area_within_2_percent(mesh, design):
    exact = 2 * math.pi * design.chamber_radius * design.chamber_length
    assert abs(mesh.area("chamber_wall") / exact - 1) < 0.02


def test_every_tag_non_empty_with_its_area(mesh, design):
    assert set(mesh.facets) == EPSA_TAGS
    assert mesh.meta["n_untagged_facets"] == 0
    for tag, exact in epsa_analytic_areas(design).items():
        assert len(mesh.facets[tag]) > 0, tag
        assert abs(mesh.area(tag) / exact - 1) < 0.03, tag


def test_tets_positive_and_facets_outward(mesh):
    assert mesh.tets.dtype == np.int64 and mesh.points.dtype == np.float64
    assert (mesh.tet_volumes() > 0).all()
    # all boundary facets are tagged exactly once
    tris, _ = boundary_facets(mesh.tets)
    tagged = np.vstack(list(mesh.facets.values()))
    assert len(tagged) == len(tris)
    assert len(np.unique(np.sort(tagged, axis=1), axis=0)) == len(tagged)
    # outward orientation: the divergence theorem on the tagged facets gives the tet volume
    p = mesh.points
    vol = np.einsum("ij,ij->i", p[tagged[:, 0]], np.cross(p[tagged[:, 1]], p[tagged[:, 2]])).sum() / 6
    assert vol == pytest.approx(mesh.volume(), rel=1e-9)


def _on_surface(gap: np.ndarray, tol: float) -> None:
    """Every vertex of a tag is snapped onto its exact surface (gap < 1e-9 mm), except the few whose
    move `geometry.tagging.snap_to_surfaces` reverts because it would flatten a tetrahedron. pytetwild
    is not reproducible, so some meshes have such vertices (one CI mesh had one on the outer
    cylinder): at most 1 % of the tag's vertices, each still within the tagging tolerance."""
    gap = np.abs(gap)
    assert gap.max() <= tol
    assert np.count_nonzero(gap > 1e-9) <= 0.01 * gap.size


def test_tags_lie_on_their_surfaces(mesh, design):
    p = mesh.points
    R, r, L, c = design.outer_radius, design.chamber_radius, design.length, design.end_cap_thickness
    tol = mesh.meta["tag_tolerance_mm"]
    rho = lambda tag: np.hypot(p[np.unique(mesh.facets[tag]), 0], p[np.unique(mesh.facets[tag]), 1])  # noqa: E731
    z = lambda tag: p[np.unique(mesh.facets[tag]), 2]  # noqa: E731
    _on_surface(rho("outer") - R, tol)  # snapped onto the exact cylinder
    _on_surface(rho("chamber_wall") - r, tol)
    _on_surface(z("end_bottom"), tol)
    _on_surface(z("end_top") - L, tol)
    zc = z("chamber_ends")
    _on_surface(np.minimum(np.abs(zc - c), np.abs(zc - (L - c))), tol)


def test_fiber_length_and_on_outer_surface(mesh, design):
    assert len(mesh.fibers) == 2
    for f in mesh.fibers:
        length = np.linalg.norm(np.diff(f, axis=0), axis=1).sum()
        assert abs(length / design.helix_length - 1) < 0.005
        dist = distance_to_surface(f, mesh.points, mesh.facets["outer"])
        assert dist.max() < FIBER_SURFACE_TOL


def test_quality_measures_of_known_tetrahedra():
    """The mean ratio 12 (3V)^(2/3) / sum l^2 and the dihedral angles on tets with known values:
    the regular tet (ratio 1, all dihedrals arccos(1/3) = 70.53 deg); the corner tet of the unit
    cube (V = 1/6, sum l^2 = 9: ratio 12 (1/2)^(2/3) / 9 = 0.8399; dihedrals 90 deg at the three
    edges through the corner, arccos(1/sqrt 3) = 54.74 deg at the others); a flattened one
    (ratio 0.0); an inverted copy (negative ratio, counted)."""
    s = np.sqrt
    regular = [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]
    corner = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    flat = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    points = np.array(regular + corner + flat, dtype=float)
    tets = np.array([[0, 1, 2, 3], [4, 5, 6, 7], [8, 9, 10, 11], [4, 6, 5, 7]])
    if np.linalg.det(points[[1, 2, 3]] - points[0]) < 0:
        tets[0] = tets[0][[0, 2, 1, 3]]
    single = {"x": np.zeros((0, 3), dtype=int)}
    one = lambda k: TaggedMesh(points, tets[k : k + 1], np.ones(1, int), {1: "t"}, single)  # noqa: E731
    q_regular, q_corner = one(0).quality(), one(1).quality()
    assert q_regular["min_quality"] == pytest.approx(1.0, abs=1e-12)
    assert q_regular["min_dihedral_deg"] == pytest.approx(np.degrees(np.arccos(1 / 3)), abs=1e-9)
    assert q_regular["max_dihedral_deg"] == pytest.approx(np.degrees(np.arccos(1 / 3)), abs=1e-9)
    assert q_corner["min_quality"] == pytest.approx(12 * 0.5 ** (2 / 3) / 9, rel=1e-12)
    assert q_corner["min_dihedral_deg"] == pytest.approx(np.degrees(np.arccos(1 / s(3))), abs=1e-9)
    assert q_corner["max_dihedral_deg"] == pytest.approx(90.0, abs=1e-9)
    assert one(2).quality()["min_quality"] == pytest.approx(0.0, abs=1e-12)
    both = TaggedMesh(points, tets[[1, 3]], np.ones(2, int), {1: "t"}, single).quality()
    assert both["n_inverted"] == 1 and both["min_quality"] == pytest.approx(-12 * 0.5 ** (2 / 3) / 9)


def test_quality_report(mesh):
    """The pytetwild ePSA mesh: no inverted tet, and no sliver (fTetWild optimises the tets; the
    Table 1 mesh's smallest dihedral angle is several degrees)."""
    q = mesh.quality()
    assert q["n_inverted"] == 0 and q["n_tets"] == mesh.n_tets
    assert q["min_dihedral_deg"] > 1.0 and q["min_quality"] > 0.01


def test_to_skfem_linear_and_quadratic(mesh, design):
    from skfem import MeshTet1, MeshTet2

    m1 = mesh.to_skfem(1)
    assert isinstance(m1, MeshTet1)
    assert set(m1.boundaries) == EPSA_TAGS
    for tag in EPSA_TAGS:
        assert len(m1.boundaries[tag]) == len(mesh.facets[tag])
    assert set(m1.subdomains) == {"epsa"}
    assert np.allclose(m1.p.T, mesh.points)
    # the boundary facet indices really are boundary facets
    assert np.isin(np.concatenate(list(m1.boundaries.values())), m1.boundary_facets()).all()
    m2 = mesh.to_skfem(2)
    assert isinstance(m2, MeshTet2)
    assert {t: len(v) for t, v in m2.boundaries.items()} == {t: len(v) for t, v in m1.boundaries.items()}
    # midside nodes of chamber-wall edges on the exact cylinder rho = r0
    edges = np.unique(m2.f2e[:, m2.boundaries["chamber_wall"]])
    mid = m2.doflocs[:, m2.nvertices + edges]
    assert np.allclose(np.hypot(mid[0], mid[1]), design.chamber_radius, atol=1e-9)


def test_write_vtu_and_msh(mesh, tmp_path):
    import meshio

    for name in ("m.vtu", "m.msh"):
        mesh.write(tmp_path / name)
        back = meshio.read(tmp_path / name)
        assert len(back.points) == mesh.n_nodes
        assert len(back.cells_dict["tetra"]) == mesh.n_tets
        assert len(back.cells_dict["triangle"]) == sum(len(f) for f in mesh.facets.values())
    assert "chamber_wall" in meshio.read(tmp_path / "m.msh").field_data


def test_cache_returns_the_same_mesh(mesh, design, cache_dir):
    t0 = time.perf_counter()
    again = mesh_epsa(design, cache_dir=cache_dir)
    assert time.perf_counter() - t0 < 5
    assert np.array_equal(again.points, mesh.points) and np.array_equal(again.tets, mesh.tets)
    assert all(np.array_equal(again.facets[t], mesh.facets[t]) for t in mesh.facets)
    assert again.design_hash == design.short_hash() and again.edge_length == mesh.edge_length
    assert len(list(cache_dir.glob(f"epsa-{design.short_hash()}-*.npz"))) == 1


def test_transformed_keeps_orientation(mesh):
    moved = mesh.transformed(30.0, (1.0, 2.0, 3.0))
    assert (moved.tet_volumes() > 0).all()
    assert moved.volume() == pytest.approx(mesh.volume())
    assert moved.fibers[0][0] == pytest.approx(
        mesh.fibers[0][0]
        @ np.array(
            [
                [math.cos(math.radians(30)), math.sin(math.radians(30)), 0],
                [-math.sin(math.radians(30)), math.cos(math.radians(30)), 0],
                [0, 0, 1],
            ]
        )
        + [1, 2, 3]
    )


def test_cli_mesh_epsa_writes_outputs(mesh, cache_dir, tmp_path):
    from softcrawl.studies.cli import main

    out = tmp_path / "out"
    assert main(["mesh", "epsa", "--out", str(out), "--cache-dir", str(cache_dir)]) == 0
    data = json.loads((out / "mesh.json").read_text())
    for key in ("n_nodes", "n_tets", "volume_mm3", "area_mm2", "fiber_length_mm", "min_quality"):
        assert key in data
    assert set(data["area_mm2"]) == EPSA_TAGS
    assert data["n_tets"] == mesh.n_tets
    assert (
        (out / "mesh.vtu").exists()
        and (out / "mesh.msh").exists()
        and (out / "mesh.png").stat().st_size > 1000
    )


def test_embed_fibers_on_outer_facets(mesh):
    for fiber, emb in zip(mesh.fibers, mesh.embed_fibers("outer")):
        assert emb["distance"].max() < FIBER_SURFACE_TOL
        assert (emb["weights"] >= -1e-12).all() and np.allclose(emb["weights"].sum(axis=1), 1)
        on_surface = np.einsum("nk,nkj->nj", emb["weights"], mesh.points[emb["nodes"]])
        assert np.allclose(np.linalg.norm(on_surface - fiber, axis=1), emb["distance"])
