"""Geometry of the pipe-crawling robot: validated designs, watertight surfaces, tagged tet meshes.

Modules (one job each):
    design        frozen, validated design dataclasses (Table 1 defaults), hashing
    design_files  a design's dict read from / written to .json or .toml
    errors        DesignError, the input error of this package
    surfaces      watertight triangle surfaces from primitives (revolved profiles, flips, merges)
    epsa_shape    ePSA body (closed air chamber), seal head, double-helix fibers and fiber families
    foot          grooved flexible foot (conical skirt), with the reading of the paper's Fig. 3
    ring          connecting ring (plate with three actuator holes and a bore)
    tagging       boundary facets, tagging by geometric predicates, snapping onto exact surfaces
    tagged_mesh   TaggedMesh, the hand-off to the solver (quality, skfem conversion, meshio export)
    tetwild       pytetwild meshing of one part + disk cache: mesh_epsa, mesh_seal_head, mesh_foot,
                  mesh_ring
    swept         structured (swept) tetrahedral mesh of the ePSA, lean for P2 elements
    foot_revolved structured (revolved) tetrahedral mesh of the foot, cells through the skirt
    assembly      the robot assembled from part meshes (regions, interface tags), robot surfaces

Only ``geometry.design`` is imported eagerly (numpy/pyvista/pytetwild load on first use).
"""

from softcrawl.geometry.design import (
    ACTUATOR_ANGLES_DEG,
    DesignError,
    EPSADesign,
    FootDesign,
    RingDesign,
    RobotDesign,
    load_design,
)

__all__ = [
    "ACTUATOR_ANGLES_DEG",
    "DesignError",
    "EPSADesign",
    "FootDesign",
    "RingDesign",
    "RobotDesign",
    "load_design",
    "TaggedMesh",
    "mesh_epsa",
    "mesh_foot",
    "mesh_ring",
    "mesh_robot",
]


def __getattr__(name: str) -> object:
    if name == "TaggedMesh":
        from softcrawl.geometry.tagged_mesh import TaggedMesh  # lazy: the package import stays numpy-free

        return TaggedMesh
    if name in ("mesh_epsa", "mesh_foot", "mesh_ring"):
        from softcrawl.geometry import tetwild  # lazy: the package import stays numpy-free

        return getattr(tetwild, name)
    if name == "mesh_robot":
        from softcrawl.geometry.assembly import mesh_robot  # lazy: the package import stays numpy-free

        return mesh_robot
    raise AttributeError(name)
