"""Friction, theoretical load and crawling speed (paper Section VII-A/D, eqs. 25-27).

Friction from extensions (eq. 26). Inside a pipe, eq. (3) gains the friction f_mu (eq. 25, printed
"k_p y + m y + f_mu = f_p"; the second term is m g as in eq. 3):

    k_p y + m g + f_mu = f_p,

so at one pressure the extension outside (y1) and inside (y2) a pipe differ by f_mu / k_p:

    f_mu = k_p (y1 - y2).                                            (26)

Theoretical load (eq. 27): M_load = (3 F_ePSA - M_r g) / g. The paper's 2.456 kg uses
F = 8.42 N, M_r = 70.2 g and g = 10 m/s^2; with 9.81 m/s^2 it is 2.505 kg. g is an explicit
argument here (mm/s^2, masses in tonne).

Crawling stride and speed (item 6 of issue 5). One cycle inflates then deflates. The rear foot
anchors while inflating, so the front foot advances by the extension against the friction the
front foot and body meet; the front anchors while deflating and the rear foot is pulled up by the
same amount. With the friction shared equally by the three ePSAs, the stride is the mean over the
actuators of

    y_i = (f_p,i(P) - m g_axial - f_mu / 3) / k_p,i(P)               (eq. 25 solved for y)

(clamped at 0: no motion when friction exceeds thrust), and the speed is stride / cycle time. This
ignores foot slip on the anchoring foot and the pressure not reaching its set point within the
inflation time, so it is an estimate to compare with Table 2, not a prediction.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.analytic.limits import (
    MAX_FORCE_N,
    MAX_G,
    MAX_MASS_G,
    MAX_PRESSURE_KPA,
    MAX_SPEED_MM_S,
    MAX_TIME_S,
    check,
)
from softcrawl.analytic.statics import EPSAParams


def friction_from_extensions(
    k_p_n_per_mm: ArrayLike, y_outside_mm: ArrayLike, y_inside_mm: ArrayLike
) -> np.ndarray:
    """Eq. (26): f_mu = k_p (y1 - y2), N."""
    return np.asarray(k_p_n_per_mm) * (np.asarray(y_outside_mm) - np.asarray(y_inside_mm))


def extension_with_friction(
    actuator: EPSAParams, pressure_kpa: ArrayLike, friction_n: ArrayLike, g: float = 0.0
) -> np.ndarray:
    """Eq. (25) solved for y: (f_p - m g - f_mu) / k_p, mm (friction per actuator)."""
    p = np.asarray(pressure_kpa, dtype=float)
    return (actuator.f_p(p) - actuator.mass * g - np.asarray(friction_n)) / actuator.k_p(p)


def theoretical_load(force_n: float, robot_mass_t: float, g: float) -> float:
    """Eq. (27): (3 F - M_r g) / g, tonne (force in N, mass in tonne, g in mm/s^2)."""
    g = check(g, "g", minimum=0.0, min_open=True, maximum=MAX_G * 1e3, unit="mm/s^2")
    force_n = check(force_n, "force", minimum=0.0, maximum=MAX_FORCE_N, unit="N")
    robot_mass_t = check(robot_mass_t, "robot_mass", minimum=0.0, maximum=MAX_MASS_G * 1e-6, unit="t")
    return (3.0 * force_n - robot_mass_t * g) / g


@dataclass(frozen=True)
class SpeedEstimate:
    pressure_kpa: float
    friction_n: float
    g_axial: float
    extensions_mm: tuple[float, float, float]
    stride_mm: float
    cycle_s: float
    speed_mm_s: float


def crawl_speed(
    actuators: Sequence[EPSAParams],
    pressure_kpa: float,
    friction_n: float,
    cycle_s: float = 2.0,
    g_axial: float = 0.0,
) -> SpeedEstimate:
    """Stride per cycle and speed (see module docstring); friction_n is the total for the robot."""
    cycle_s = check(cycle_s, "cycle", minimum=0.0, min_open=True, maximum=MAX_TIME_S, unit="s")
    friction_n = check(friction_n, "friction", minimum=0.0, maximum=MAX_FORCE_N, unit="N")
    pressure_kpa = check(pressure_kpa, "pressure", minimum=0.0, maximum=MAX_PRESSURE_KPA, unit="kPa")
    g_axial = check(g_axial, "g", minimum=0.0, maximum=MAX_G * 1e3, unit="mm/s^2")
    ys = tuple(
        max(0.0, float(extension_with_friction(a, pressure_kpa, friction_n / 3.0, g_axial)))
        for a in actuators
    )
    stride = float(np.mean(ys))
    return SpeedEstimate(
        float(pressure_kpa), float(friction_n), float(g_axial), ys, stride, float(cycle_s), stride / cycle_s
    )


def friction_for_speed(
    actuators: Sequence[EPSAParams],
    pressure_kpa: float,
    speed_mm_s: float,
    cycle_s: float = 2.0,
    g_axial: float = 0.0,
) -> float:
    """Total friction (N) at which `crawl_speed` would give `speed_mm_s` (all actuators moving)."""
    speed_mm_s = check(speed_mm_s, "speed", minimum=0.0, maximum=MAX_SPEED_MM_S, unit="mm/s")
    cycle_s = check(cycle_s, "cycle", minimum=0.0, min_open=True, maximum=MAX_TIME_S, unit="s")
    y = speed_mm_s * cycle_s
    per = [float(a.f_p(pressure_kpa) - a.mass * g_axial - a.k_p(pressure_kpa) * y) for a in actuators]
    return float(sum(per))
