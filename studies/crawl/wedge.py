r"""The crawl's feet as one wedge of `copies` (cyclic symmetry; docs/decisions/082-crawl-wedge.md).

In a straight pipe the two feet, their plates, the actuators' axial law and the wall are the same
in every sector of the revolved mesh, so the feet deform the same way in every wedge of
2 pi / copies (until a bifurcation breaks that, which the whole model on this mesh does not
follow either: its lateral drift stays at round-off). The wedge model keeps the first
n_theta / copies sectors of each foot (`geometry.foot_revolved`, node for node the whole mesh's),
ties each foot's cut at theta = 2 pi / copies to its cut at theta = 0 turned by that angle
(`fem.periodic_tie`, a penalty of `TIE_PENALTY` E h per node pair), and carries 1 / copies of
every axial link (`fem.axial_link`, `share`). Forces it reports are the whole feet's: the
contact terms' times `copies`; the links already speak of the whole link.

The plates' holds of the flipped feet (`plate_hold`) count the whole plate's nodes: copies times
the wedge's plate nodes off the cut at 2 pi / copies (those are the next wedge's cut at 0).
"""

from __future__ import annotations

import math

import numpy as np

from softcrawl.fem.periodic_tie import PeriodicPressureTie, PeriodicTie
from softcrawl.studies.crawl.mesh import FEET

#: The tie's penalty per node pair in units of E h (E the rubber's small-strain modulus, h the
#: feet's median edge): the gap it leaves is the force across the cut at a node over k
#: (measured in record 082).
TIE_PENALTY = 1.0e4


def ties(copies: int, youngs: float, size: float, mixed: bool = True) -> list:
    """Each foot's periodic ties, of the displacements (k = TIE_PENALTY E h per node pair) and of
    the mixed pressure (k_p = TIE_PENALTY h^3 / E per vertex pair: the pressure equations' scale
    is a cell's volume over the modulus); none for the whole feet, copies = 1."""
    if copies == 1:
        return []
    angle = 2 * math.pi / copies
    k, k_p = TIE_PENALTY * youngs * size, TIE_PENALTY * size**3 / youngs
    out = []
    for f in FEET:
        cuts = (f"{f}:cut_start", f"{f}:cut_end", angle)
        out.append(PeriodicTie(*cuts, k, name=f"{f}:tie"))
        if mixed:
            out.append(PeriodicPressureTie(*cuts, k_p, name=f"{f}:pressure_tie"))
    return out


def whole_plate_nodes(model, tag: str, copies: int) -> int:
    """The nodes of the whole feet's plate `tag` (a wedge's: module docstring)."""
    nodes = model.boundary_nodes(tag)
    if copies == 1:
        return int(nodes.size)
    foot = tag.split(":", 1)[0]
    off_cut = nodes[~np.isin(nodes, model.boundary_nodes(f"{foot}:cut_end"))]
    return int(copies * off_cut.size)

