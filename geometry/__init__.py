"""Geometry of the pipe-crawling robot: validated designs, watertight surfaces, tagged tet meshes.

Modules (one job each):
    design    frozen, validated design dataclasses (Table 1 defaults), hashing, JSON/TOML files
    surfaces  watertight triangle surfaces from primitives (revolved profiles, flips, merges)
    epsa      ePSA body (closed air chamber), seal head, double-helix fibers
    foot      grooved flexible foot (conical skirt), with the reading of the paper's Fig. 3
    ring      connecting ring (plate with three actuator holes and a bore)
    robot     assembly of the parts into the robot (regions, interface tags), robot surfaces
    tagging   boundary facets, tagging by geometric predicates, snapping onto exact surfaces
    mesh      TaggedMesh, the hand-off to the solver (quality, skfem conversion, meshio export)
    meshing   pytetwild meshing + disk cache: mesh_epsa, mesh_foot, mesh_ring, mesh_robot
    render    off-screen PNG of a tagged mesh

Only ``geometry.design`` is imported eagerly (numpy/pyvista/pytetwild load on first use).
"""
from geometry.design import (ACTUATOR_ANGLES_DEG, DesignError, EPSADesign, FootDesign, RingDesign,
                             RobotDesign, load_design)

__all__ = ["ACTUATOR_ANGLES_DEG", "DesignError", "EPSADesign", "FootDesign", "RingDesign", "RobotDesign",
           "load_design", "TaggedMesh", "mesh_epsa", "mesh_foot", "mesh_ring", "mesh_robot"]


def __getattr__(name):
    if name == "TaggedMesh":
        from geometry.mesh import TaggedMesh

        return TaggedMesh
    if name in ("mesh_epsa", "mesh_foot", "mesh_ring", "mesh_robot"):
        from geometry import meshing

        return getattr(meshing, name)
    raise AttributeError(name)
