r"""Post-processing of solved states: actuator metrics, stretches and stresses.

- Actuator length: mean z of the deformed `top` face nodes minus that of the `bottom` face.
- Outer radius at a reference height Z0: the `outer` surface nodes of the node layer nearest to
  Z0 (in the reference configuration); radius = mean distance from the centre of the circle
  fitted to their deformed positions (so a shifted axis or a symmetry sector is handled).
- Principal stretches: square roots of the eigenvalues of C = F^T F at the quadrature points.
- Volumetric constraint error |J - 1 - p/K| (`volumetric_error`): max and volume average.
- Cauchy stress sigma = J^{-1} P F^T, with the mixed pressure p in P for the p2p1 formulation;
  von Mises sigma_vm = sqrt(3/2 s:s), s = dev sigma. Element values are quadrature averages.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.fem.model import SolidModel
from softcrawl.fem.neohooke import cauchy_stress, principal_stretches, von_mises


def deformed_nodes(model: SolidModel, x: np.ndarray) -> np.ndarray:
    return model.nodes + model.displacement(x)


def actuator_length(model: SolidModel, x, bottom="end_bottom", top="end_top") -> float:
    pos = deformed_nodes(model, x)
    return float(pos[2, model.boundary_nodes(top)].mean() - pos[2, model.boundary_nodes(bottom)].mean())


def outer_radius_at(model: SolidModel, x, z_ref: float, tag="outer") -> float:
    nodes = model.boundary_nodes(tag)
    Z = model.nodes[2, nodes]
    dz = np.abs(Z - z_ref)
    layer = nodes[dz <= dz.min() + 1e-9 * max(1.0, abs(z_ref))]
    pos = deformed_nodes(model, x)[:2, layer]
    centre = circle_centre(pos) if layer.size >= 3 else np.zeros(2)
    return float(np.hypot(*(pos - centre[:, None])).mean())


def circle_centre(xy: np.ndarray) -> np.ndarray:
    """Least-squares (Kasa) circle centre of points xy (2, n): 2 x.c + k = |x|^2. Works for a
    full ring and for an arc (symmetry sectors)."""
    M = np.column_stack([2 * xy[0], 2 * xy[1], np.ones(xy.shape[1])])
    sol, *_ = np.linalg.lstsq(M, (xy**2).sum(axis=0), rcond=None)
    return sol[:2]


@dataclass(frozen=True)
class ElementFields:
    """Per-element values (quadrature averages; maximum for the stretch)."""

    max_stretch: np.ndarray  # (E,)
    cauchy: np.ndarray  # (3, 3, E) MPa
    von_mises: np.ndarray  # (E,) MPa
    pressure: np.ndarray  # (E,) MPa, hydrostatic -tr(sigma)/3
    jacobian: np.ndarray  # (E,) det F


def element_fields(model: SolidModel, x: np.ndarray) -> ElementFields:
    state = model.solid.stress(x)  # the body's own law (Neo-Hookean, Yeoh, Gent)
    F, J = state.F, state.J
    sigma = cauchy_stress(state.P, F)
    w = model.dx / model.dx.sum(axis=1, keepdims=True)
    avg = lambda a: (a * w).sum(axis=-1)  # noqa: E731
    stretch = principal_stretches(F)[..., -1].max(axis=1)
    sig_e = avg(sigma)
    return ElementFields(stretch, sig_e, avg(von_mises(sigma)), -np.einsum("kke->e", sig_e) / 3, avg(J))


def max_principal_stretch(model: SolidModel, x) -> float:
    return float(element_fields(model, x).max_stretch.max())


def volumetric_error(model: SolidModel, x) -> tuple[float, float]:
    """(max, volume average) of |J - 1 - p/K| over the quadrature points: how far the mixed
    pressure p misses K (J - 1) pointwise (the P1 pressure enforces it only weakly, in L2).
    Zero by construction for the displacement-only "p2" formulation. The hydrostatic stress comes
    from the mixed p itself; a spurious volume change e enters the Cauchy stress through its
    J^-1 (the isochoric Neo-Hookean stress depends on J^-1/3 F only), so a point with error e has
    its deviatoric stress off by about a fraction e."""
    state = model.solid.stress(x)
    err = np.abs(state.J - 1.0 - state.p / model.bulk)
    return float(err.max()), float((err * model.dx).sum() / model.dx.sum())
