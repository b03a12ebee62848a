"""The foot's two meshers behind one call, for every command and study that meshes a foot.

- "revolved": `geometry.foot_revolved`, a structured mesh swept about the axis, every vertex
  and P2 midside node on the exact surfaces; refined by `sectors` around the axis and
  `thickness_layers` cells through the skirt; deterministic, no cache.
- "tetwild": `geometry.tetwild.mesh_foot` (pytetwild), refined by its `edge_length` (mm),
  cached in `cache_dir`.

A setting that belongs to the other mesher is a `DesignError` naming it, not silently ignored.

Quick revolved meshes (`quick_sectors`): the rule n = max(24, ceil(48 cos(angle / 2))) keeps 24
at 120 deg (every committed quick run) and gives 34 / 42 / 45 / 47 at 90 / 60 / 45 / 30 deg
(docs/decisions/066-body-geometry.md). It was set by scikit-fem's inversion of the curved P2 map,
which failed on the contact faces below those counts (the skirt's chordal bow, r_tip (1 - cos(pi /
n)), lies across its thin cells as it turns towards the axis). `fem.p2_mapping` now places the
facet points from 22-26 sectors where scikit-fem needed 32-40 (docs/decisions/086-curved-facet-points.md);
the rule stays because the committed feet and crawl results were computed on its meshes.
"""

from __future__ import annotations

import math
from pathlib import Path

from softcrawl.geometry import foot_revolved as fr
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.errors import DesignError
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tetwild import mesh_foot

FOOT_MESHERS = ("revolved", "tetwild")
#: Sectors of the quick revolved foot mesh at 120 deg and above (module docstring).
QUICK_SECTORS = 24


def quick_sectors(design: FootDesign) -> int:
    """Sectors of a quick revolved mesh of `design`: max(24, ceil(48 cos(angle / 2)))."""
    return max(QUICK_SECTORS, math.ceil(2 * QUICK_SECTORS * math.cos(math.radians(design.angle / 2)) - 1e-9))


def mesh_foot_with(
    design: FootDesign,
    mesher: str,
    *,
    sectors: int | None = None,
    thickness_layers: int | None = None,
    edge_length: float | None = None,
    cache_dir: str | Path | bool | None = None,
    copies: int = 1,
) -> TaggedMesh:
    """The foot `design` meshed by `mesher` (module docstring); None: the mesher's default.
    `copies` > 1: the revolved mesh's wedge of 2 pi / copies (`foot_revolved.mesh_foot_revolved`)."""
    if mesher == "revolved":
        if edge_length is not None:
            raise DesignError("edge_length", "refines the tetwild mesh; the revolved one takes sectors")
        return fr.mesh_foot_revolved(
            design,
            n_theta=fr.N_THETA if sectors is None else sectors,
            thickness_layers=fr.THICKNESS_LAYERS if thickness_layers is None else thickness_layers,
            copies=copies,
        )
    if mesher == "tetwild":
        if copies != 1:
            raise DesignError("copies", "a wedge of the feet needs the revolved mesh, not pytetwild's")
        for name, value in (("sectors", sectors), ("thickness_layers", thickness_layers)):
            if value is not None:
                raise DesignError(name, "refines the revolved mesh, not pytetwild's")
        return mesh_foot(design, edge_length=edge_length, cache_dir=cache_dir)
    raise DesignError("mesher", f"{mesher!r} is not a foot mesher: one of {', '.join(FOOT_MESHERS)}")
