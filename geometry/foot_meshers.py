"""The foot's two meshers behind one call, for every command and study that meshes a foot.

- "revolved": `geometry.foot_revolved`, a structured mesh swept about the axis, every vertex
  and P2 midside node on the exact surfaces; refined by `sectors` around the axis and
  `thickness_layers` cells through the skirt; deterministic, no cache.
- "tetwild": `geometry.tetwild.mesh_foot` (pytetwild), refined by its `edge_length` (mm),
  cached in `cache_dir`.

A setting that belongs to the other mesher is a `DesignError` naming it, not silently ignored.
"""

from __future__ import annotations

from pathlib import Path

from softcrawl.geometry import foot_revolved as fr
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.errors import DesignError
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tetwild import mesh_foot

FOOT_MESHERS = ("revolved", "tetwild")


def mesh_foot_with(
    design: FootDesign,
    mesher: str,
    *,
    sectors: int | None = None,
    thickness_layers: int | None = None,
    edge_length: float | None = None,
    cache_dir: str | Path | bool | None = None,
) -> TaggedMesh:
    """The foot `design` meshed by `mesher` (module docstring); None: the mesher's default."""
    if mesher == "revolved":
        if edge_length is not None:
            raise DesignError("edge_length", "refines the tetwild mesh; the revolved one takes sectors")
        return fr.mesh_foot_revolved(
            design,
            n_theta=fr.N_THETA if sectors is None else sectors,
            thickness_layers=fr.THICKNESS_LAYERS if thickness_layers is None else thickness_layers,
        )
    if mesher == "tetwild":
        for name, value in (("sectors", sectors), ("thickness_layers", thickness_layers)):
            if value is not None:
                raise DesignError(name, "refines the revolved mesh, not pytetwild's")
        return mesh_foot(design, edge_length=edge_length, cache_dir=cache_dir)
    raise DesignError("mesher", f"{mesher!r} is not a foot mesher: one of {', '.join(FOOT_MESHERS)}")
