"""Workspace of the robot tip (paper Fig. 11(d)).

Pressure triples on a grid over 0-100 kPa -> ePSA lengths by the statics model (eq. 3, without
gravity, as the paper's kinematics) -> (kappa, theta, phi) and the tip position by eqs. (4)-(6),(9),
with the rear foot at the origin and the body along z.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcrawl.analytic import kinematics as kin
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.limits import MAX_PRESSURE_KPA, MAX_WORKSPACE_LEVELS, check
from softcrawl.analytic.prototype import actuator_set
from softcrawl.paper import D_MM, P_MAX_KPA


@dataclass(frozen=True)
class Workspace:
    pressures_kpa: np.ndarray  # (n, 3)
    lengths_mm: np.ndarray  # (n, 3)
    kappa: np.ndarray
    theta: np.ndarray
    phi: np.ndarray
    tip_mm: np.ndarray  # (n, 3)

    def rows(self) -> np.ndarray:
        """(n, 12) rows in the order of `HEADER`."""
        cols = np.column_stack(
            [self.pressures_kpa, self.lengths_mm, self.kappa, self.theta, self.phi, self.tip_mm]
        )
        return cols


HEADER = "P1_kpa,P2_kpa,P3_kpa,l1_mm,l2_mm,l3_mm,kappa_per_mm,theta_rad,phi_rad,x_mm,y_mm,z_mm"


def sample(
    n: int = 11, actuators: str = "prototype", d: float = D_MM, g: float = 0.0, p_max: float = P_MAX_KPA
) -> Workspace:
    """n^3 pressure triples on a regular grid over [0, p_max] kPa (2 <= n <= MAX_WORKSPACE_LEVELS)."""
    n = check(n, "n", minimum=2, maximum=MAX_WORKSPACE_LEVELS, integer=True)
    p_max = check(p_max, "p_max", minimum=0.0, min_open=True, maximum=MAX_PRESSURE_KPA, unit="kPa")
    if not isinstance(actuators, str):
        raise ModelInputError("actuators", f"must be 'nominal' or 'prototype', got {actuators!r}")
    acts = actuator_set(actuators)
    v = np.linspace(0.0, p_max, n)
    P = np.stack(np.meshgrid(v, v, v, indexing="ij"), -1).reshape(-1, 3)
    L = np.stack([acts[i].length(P[:, i], g) for i in range(3)], -1)
    k, t, p, lc = kin.forward(L, d)
    return Workspace(P, L, k, t, p, kin.arc_point(t, p, lc))


def save_csv(ws: Workspace, path: str | Path) -> None:
    np.savetxt(path, ws.rows(), delimiter=",", header=HEADER, comments="", fmt="%.8g")
