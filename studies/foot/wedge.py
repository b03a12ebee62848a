r"""Feet as one wedge of `copies` (cyclic symmetry; docs/decisions/082-crawl-wedge.md): the one
foot of the foot study (`studies.foot.model`) and the crawl's two (`studies.crawl.model`).

In a straight pipe a foot, its hub's support (held, or a rigid plate under the actuators' axial
law) and the wall are the same in every sector of the revolved mesh, so the foot deforms the same
way in every wedge of 2 pi / copies (until a bifurcation breaks that, which the whole model on
this mesh does not follow either: its lateral drift stays at round-off). The wedge model keeps
the first n_theta / copies sectors of each foot (`geometry.foot_revolved`, node for node the
whole mesh's), ties each foot's cut at theta = 2 pi / copies to its cut at theta = 0 turned by
that angle (`fem.periodic_tie`, exact: the tied dofs are condensed out, and the mixed pressure's
too), and carries 1 / copies of every axial link (`fem.axial_link`, `share`). Forces it
reports are the whole foot's: the contact terms' times `copies`; the links already speak of the
whole link. Means over a tag's nodes skip the cut at 2 pi / copies (`off_cut`): those nodes are
the next wedge's cut at 0.

The plates' holds of the crawl's flipped feet count the whole plate's nodes (`whole_nodes`).
"""

from __future__ import annotations

import math

import numpy as np

from softcrawl.fem.periodic_tie import CyclicTie


def wedge_sectors(sectors: int, copies: int) -> int:
    """`sectors` rounded up to a multiple of `copies`: the least mesh a wedge of 2 pi / copies
    can cut, no coarser than asked (`studies.crawl.feet_study`, the optimiser's foot and crawls)."""
    return -(-int(sectors) // copies) * copies


def _tag(foot: str, tag: str) -> str:
    return f"{foot}:{tag}" if foot else tag


def ties(copies: int, feet=("",)) -> list:
    """Each foot's cyclic tie (`feet`: the tags' prefixes, "" for a lone foot's plain tags), of the
    displacements and the mixed pressure, for `SolidModel(ties=...)`; none for the whole feet,
    copies = 1."""
    if copies == 1:
        return []
    angle = 2 * math.pi / copies
    return [CyclicTie(_tag(f, "cut_start"), _tag(f, "cut_end"), angle) for f in feet]


def off_cut(model, tag: str, copies: int) -> np.ndarray:
    """The nodes of boundary `tag` ("foot:tag" or a lone foot's "tag") whose mean is the whole
    foot's: all of them for the whole foot, a wedge's off its cut at 2 pi / copies."""
    nodes = model.boundary_nodes(tag)
    if copies == 1:
        return nodes
    foot = tag.split(":", 1)[0] if ":" in tag else ""
    return nodes[~np.isin(nodes, model.boundary_nodes(_tag(foot, "cut_end")))]


def whole_nodes(model, tag: str, copies: int) -> int:
    """How many nodes the whole foot's boundary `tag` has (a wedge's: copies x `off_cut`)."""
    return int(copies * off_cut(model, tag, copies).size)
