r"""Stress, strain and deformation summaries of the contact studies (groove segment, foot).

Element values are quadrature averages (`fem.post.element_fields`): von Mises stress (MPa) and
the max principal strain, taken as the largest principal stretch minus one (nominal strain).
Re-entrant corners (the groove corners) are stress singularities: their raw maximum grows
without bound under mesh refinement, so every quantity is reported twice, as the raw maximum and
as the volume-weighted 99th percentile, which a few corner elements cannot move.

Deformation: the largest displacement of a node relative to the mean displacement of a
reference face (the backing of the groove strip, the hub of the foot): how far the soft part
bends and shears, without the rigid motion it is dragged by.
"""

from __future__ import annotations

import numpy as np

from softcrawl.fem.post import element_fields


def weighted_percentile(values: np.ndarray, weights: np.ndarray, q: float) -> float:
    """The q-th percentile (0-100) of `values` weighted by `weights` (the value below which a
    fraction q/100 of the total weight lies)."""
    order = np.argsort(values)
    v, w = values[order], weights[order]
    cum = np.cumsum(w) / w.sum()
    return float(v[min(np.searchsorted(cum, q / 100.0), v.size - 1)])


def _summary(prefix: str, values: np.ndarray, volume: np.ndarray) -> dict:
    return {
        f"{prefix}_max": float(values.max()),
        f"{prefix}_p99": weighted_percentile(values, volume, 99.0),
    }


def solid_metrics(model, x: np.ndarray, backing: str, elements: np.ndarray | None = None) -> dict:
    """von Mises (MPa), max principal strain, deformation (mm) over `elements` (default all)."""
    fields = element_fields(model, x)
    volume = model.dx.sum(axis=1)
    sel = np.arange(volume.size) if elements is None else elements
    u = model.displacement(x)
    ref = u[:, model.boundary_nodes(backing)].mean(axis=1)
    rel = np.linalg.norm(u - ref[:, None], axis=0)
    out = _summary("von_mises_mpa", fields.von_mises[sel], volume[sel])
    out |= _summary("max_principal_strain", fields.max_stretch[sel] - 1.0, volume[sel])
    out["deformation_max_mm"] = float(rel.max())
    return out


def face_elements(model, tag: str) -> np.ndarray:
    """The elements with a facet on boundary `tag`."""
    facets = model.mesh.boundaries[tag]
    return np.unique(model.mesh.f2t[0, facets])


def face_metrics(model, x: np.ndarray, tag: str, backing: str) -> dict:
    """`solid_metrics` over the elements next to boundary `tag`, keys prefixed with the tag."""
    m = solid_metrics(model, x, backing, face_elements(model, tag))
    return {f"{tag}_{k}": v for k, v in m.items() if k != "deformation_max_mm"}
