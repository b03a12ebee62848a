"""`TaggedMesh`: the hand-off from geometry to the solver, a plain frozen container of arrays.

Fields (units mm):

* ``points`` (n, 3) float64 node coordinates;
* ``tets`` (m, 4) int64 linear tetrahedra, all positively oriented
  (det[p1 - p0, p2 - p0, p3 - p0] > 0);
* ``region`` (m,) int region id per tet and ``region_names`` {id: name} (``{1: "epsa"}`` for a single
  ePSA; ``epsa1..3``, ``ring1..``, ``seal_head1..3``, ``foot_rear``, ``foot_front`` for the robot);
* ``facets`` {tag: (k, 3) int64}: boundary triangles, outward oriented (normal (p1-p0) x (p2-p0)
  points out of the solid). Tags of an ePSA: ``chamber_wall``, ``chamber_ends``, ``outer``,
  ``end_bottom`` (z = 0), ``end_top`` (z = L). Assemblies are meshed part by part (the paper ties the
  parts, Abaqus *Tie*); the meshes of two touching parts do not share nodes, and the facets of part a
  that touch part b carry the tag ``interface:a/b`` (and those of b touching a ``interface:b/a``).
  A facet carries exactly one tag;
* ``fibers``: tuple of (n_i, 3) float64 polylines (reference configuration), () for none;
* ``design_hash``, ``edge_length`` (target edge length given to the mesher, mm).

Quality measure: the mean ratio q = 12 (3 V)^(2/3) / sum_ij l_ij^2, 1 for the regular tetrahedron and
0 for a degenerate one; plus the minimum dihedral angle.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from softcrawl.geometry.errors import DesignError
from softcrawl.geometry.tagging import RevolvedSegment, embed_points, tet_volumes

if TYPE_CHECKING:
    import meshio
    import skfem

_EDGES = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])
_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


def facet_keys(tris: np.ndarray) -> np.ndarray:
    """One int64 per triangle: its sorted vertex numbers in 21 bits each (a mesh of at most 2^21
    vertices; more is refused, naming `mesh`, rather than keys that collide)."""
    s = np.sort(np.asarray(tris, dtype=np.int64), axis=1)
    if s.size and int(s.max()) >= 1 << 21:
        raise DesignError("mesh", f"at most {1 << 21} vertices for the facet keys, not {int(s.max()) + 1}")
    return (s[:, 0] << 42) | (s[:, 1] << 21) | s[:, 2]


@dataclass(frozen=True, eq=False)
class TaggedMesh:
    """Linear tetrahedral mesh with region ids, tagged boundary facets and fiber polylines."""

    points: np.ndarray
    tets: np.ndarray
    region: np.ndarray
    region_names: dict[int, str]
    facets: dict[str, np.ndarray]
    fibers: tuple[np.ndarray, ...] = ()
    design_hash: str = ""
    edge_length: float = 0.0
    meta: dict = field(default_factory=dict)

    # ----------------------------------------------------------------- measures
    @property
    def n_nodes(self) -> int:
        return len(self.points)

    @property
    def n_tets(self) -> int:
        return len(self.tets)

    def tet_volumes(self) -> np.ndarray:
        return tet_volumes(self.points, self.tets)

    def volume(self, region: str | None = None) -> float:
        """Total volume, or the volume of one named region."""
        v = self.tet_volumes()
        if region is not None:
            v = v[self.region == self.region_id(region)]
        return float(v.sum())

    def region_id(self, name: str) -> int:
        for k, v in self.region_names.items():
            if v == name:
                return k
        raise KeyError(name)

    def area(self, tag: str) -> float:
        tris = self.facets[tag]
        p = self.points
        n = np.cross(p[tris[:, 1]] - p[tris[:, 0]], p[tris[:, 2]] - p[tris[:, 0]])
        return float(0.5 * np.linalg.norm(n, axis=1).sum())

    def fiber_lengths(self) -> list[float]:
        return [float(np.linalg.norm(np.diff(f, axis=0), axis=1).sum()) for f in self.fibers]

    def embed_fibers(self, tag: str = "outer") -> list[dict]:
        """Fiber points located on the boundary facets of ``tag`` (for tying the fibers to the body).

        Per fiber: ``facet`` (n,) index into ``facets[tag]``, ``nodes`` (n, 3) its node ids,
        ``weights`` (n, 3) barycentric coordinates of the closest point, ``distance`` (n,) mm.
        The closest point sum_k weights_k * points[nodes_k] is the fiber point on the meshed surface.
        """
        out = []
        tris = self.facets[tag]
        for f in self.fibers:
            host, bary, dist = embed_points(f, self.points, tris)
            out.append({"facet": host, "nodes": tris[host], "weights": bary, "distance": dist})
        return out

    def quality(self) -> dict:
        """Mean ratio (min, mean, share below 0.1), min dihedral angle (deg), counts."""
        p, t = self.points, self.tets
        vol = self.tet_volumes()
        edges = p[t[:, _EDGES[:, 1]]] - p[t[:, _EDGES[:, 0]]]
        l2 = np.einsum("ijk,ijk->ij", edges, edges).sum(axis=1)
        q = 12.0 * np.cbrt(3.0 * np.abs(vol)) ** 2 / l2 * np.sign(vol)
        fa = p[t[:, _FACES]]  # (m, 4, 3, 3)
        n = np.cross(fa[:, :, 1] - fa[:, :, 0], fa[:, :, 2] - fa[:, :, 0])
        n /= np.linalg.norm(n, axis=2, keepdims=True)
        cosines = [np.einsum("ij,ij->i", n[:, i], n[:, j]) for i in range(4) for j in range(i + 1, 4)]
        dihedral = np.degrees(np.pi - np.arccos(np.clip(np.array(cosines), -1, 1)))
        return {
            "n_nodes": self.n_nodes,
            "n_tets": self.n_tets,
            "n_boundary_facets": int(sum(len(f) for f in self.facets.values())),
            "min_volume_mm3": float(vol.min()),
            "n_inverted": int(np.count_nonzero(vol <= 0)),
            "min_quality": float(q.min()),
            "mean_quality": float(q.mean()),
            "share_quality_below_0.1": float(np.mean(q < 0.1)),
            "min_dihedral_deg": float(dihedral.min()),
            "max_dihedral_deg": float(dihedral.max()),
            "quality_measure": "mean ratio 12 (3V)^(2/3) / sum l^2",
        }

    def summary(self) -> dict:
        """The figures of ``mesh.json``."""
        q = self.quality()
        return {
            "n_nodes": self.n_nodes,
            "n_tets": self.n_tets,
            "volume_mm3": self.volume(),
            "region_volume_mm3": {name: self.volume(name) for name in self.region_names.values()},
            "area_mm2": {tag: self.area(tag) for tag in sorted(self.facets)},
            "n_facets": {tag: int(len(f)) for tag, f in sorted(self.facets.items())},
            "fiber_length_mm": float(sum(self.fiber_lengths())),
            "fiber_lengths_mm": self.fiber_lengths(),
            "min_quality": q["min_quality"],
            "quality": q,
            "design_hash": self.design_hash,
            "edge_length_mm": self.edge_length,
            **{k: v for k, v in self.meta.items() if isinstance(v, (int, float, str))},
        }

    # ----------------------------------------------------------------- transforms
    def transformed(
        self, rotation_deg: float = 0.0, offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    ) -> TaggedMesh:
        """Rotated about z by ``rotation_deg``, then translated (orientation is preserved)."""
        c, s = np.cos(np.radians(rotation_deg)), np.sin(np.radians(rotation_deg))
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        off = np.asarray(offset, dtype=float)
        return TaggedMesh(
            self.points @ rot.T + off,
            self.tets,
            self.region,
            dict(self.region_names),
            dict(self.facets),
            tuple(f @ rot.T + off for f in self.fibers),
            self.design_hash,
            self.edge_length,
            dict(self.meta),
        )

    # ----------------------------------------------------------------- solver hand-off
    def facet_indices(self, mesh: skfem.Mesh, tag: str) -> np.ndarray:
        """Indices into ``mesh.facets`` (a skfem mesh built from these tets) of the facets of ``tag``."""
        keys = facet_keys(mesh.facets.T)
        order = np.argsort(keys)
        want = facet_keys(self.facets[tag])
        pos = np.searchsorted(keys, want, sorter=order)
        found = order[np.clip(pos, 0, len(order) - 1)]
        if not np.array_equal(keys[found], want):
            raise RuntimeError(f"facets of tag {tag!r} not found in the skfem mesh")
        return found

    def to_skfem(self, order: int = 1) -> skfem.MeshTet | skfem.MeshTet2:
        """skfem ``MeshTet`` (order 1) or ``MeshTet2`` (order 2), with named boundaries and subdomains.

        ``mesh.boundaries[tag]`` are indices into ``mesh.facets``; ``mesh.subdomains[name]`` element
        indices per region. For order 2 the midside nodes of edges on curved tagged surfaces (cylinders,
        cones: ``meta['curved_surfaces']``) are moved onto the exact surface; other midside nodes stay at
        the edge midpoints.
        """
        from skfem import MeshTet, MeshTet2

        if order not in (1, 2):
            raise ValueError("order must be 1 or 2")
        m1 = MeshTet(np.ascontiguousarray(self.points.T), np.ascontiguousarray(self.tets.T))
        boundaries = {tag: self.facet_indices(m1, tag) for tag in self.facets}
        subdomains = {name: np.nonzero(self.region == rid)[0] for rid, name in self.region_names.items()}
        if order == 1:
            return MeshTet(m1.doflocs, m1.t, _boundaries=boundaries, _subdomains=subdomains)
        m2 = MeshTet2.from_mesh(m1)
        doflocs = np.array(m2.doflocs)
        for tag, segs in self.meta.get("curved_surfaces", {}).items():
            if tag not in boundaries:
                continue
            segments = [RevolvedSegment(tag, tuple(s[0]), tuple(s[1]), tuple(s[2])) for s in segs]
            edges = np.unique(m2.f2e[:, boundaries[tag]])
            cols = m2.nvertices + edges
            x = doflocs[:, cols].T
            best, dist = x.copy(), np.full(len(x), np.inf)
            for seg in segments:
                q, d = seg.closest(x)
                take = d < dist
                best[take], dist[take] = q[take], d[take]
            doflocs[:, cols] = best.T
        return MeshTet2(doflocs, m2.t, _boundaries=boundaries, _subdomains=subdomains)

    # ----------------------------------------------------------------- files
    def physical_ids(self) -> dict[str, int]:
        """Ids of regions (their region id) and tags (1000 + rank of the sorted tag) for file export."""
        ids = {name: int(rid) for rid, name in self.region_names.items()}
        ids.update({tag: 1000 + i for i, tag in enumerate(sorted(self.facets))})
        return ids

    def to_meshio(self) -> meshio.Mesh:
        import meshio

        ids = self.physical_ids()
        tags = sorted(self.facets)
        tri = np.vstack([self.facets[t] for t in tags]) if tags else np.zeros((0, 3), dtype=np.int64)
        tri_ids = (
            np.concatenate([np.full(len(self.facets[t]), ids[t]) for t in tags]) if tags else np.zeros(0)
        )
        phys = [self.region.astype(np.int32), tri_ids.astype(np.int32)]
        field_data = {
            name: np.array([i, 3 if name in self.region_names.values() else 2]) for name, i in ids.items()
        }
        return meshio.Mesh(
            self.points,
            [("tetra", self.tets), ("triangle", tri)],
            cell_data={"gmsh:physical": phys, "gmsh:geometrical": phys},
            field_data=field_data,
        )

    def write(self, path: str | Path) -> Path:
        """Write with meshio: ``.vtu`` (cell data ``gmsh:physical``: region id for tets, tag id for
        triangles; ids in ``mesh.json``/``physical_ids()``), ``.msh`` (Gmsh 2.2, physical groups named)
        or any other meshio format (``.xdmf`` needs h5py, which is not a dependency)."""
        import meshio

        path = Path(path)
        m = self.to_meshio()
        if path.suffix == ".msh":
            meshio.write(path, m, file_format="gmsh22", binary=False)
        elif path.suffix == ".vtu":
            m.cell_data = {"region_or_tag": m.cell_data["gmsh:physical"]}
            meshio.write(path, m)
        else:
            meshio.write(path, m)
        return path

    def save_npz(self, path: str | Path) -> Path:
        """Lossless cache file (re-read with :meth:`load_npz`)."""
        path = Path(path)
        arrays = {"points": self.points, "tets": self.tets, "region": self.region}
        for tag, f in self.facets.items():
            arrays[f"facet:{tag}"] = f
        for i, f in enumerate(self.fibers):
            arrays[f"fiber:{i:04d}"] = f
        header = {
            "region_names": {str(k): v for k, v in self.region_names.items()},
            "design_hash": self.design_hash,
            "edge_length": self.edge_length,
            "meta": self.meta,
            "facet_order": list(self.facets),
        }
        arrays["header"] = np.array(json.dumps(header))
        import os

        tmp = path.with_name(f"{path.stem}.{os.getpid()}.tmp.npz")  # atomic for concurrent writers
        np.savez_compressed(tmp, **arrays)
        tmp.replace(path)
        return path

    @classmethod
    def load_npz(cls, path: str | Path) -> TaggedMesh:
        with np.load(path) as data:
            header = json.loads(str(data["header"]))
            facets = {tag: data[f"facet:{tag}"].astype(np.int64) for tag in header["facet_order"]}
            fibers = tuple(
                data[k].astype(float) for k in sorted(k for k in data.files if k.startswith("fiber:"))
            )
            return cls(
                data["points"].astype(float),
                data["tets"].astype(np.int64),
                data["region"].astype(int),
                {int(k): v for k, v in header["region_names"].items()},
                facets,
                fibers,
                header["design_hash"],
                float(header["edge_length"]),
                header["meta"],
            )
