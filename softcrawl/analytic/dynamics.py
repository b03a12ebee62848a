"""ePSA dynamics (paper eq. 1): m y'' + b_p(P) y' + k_p(P) y + m g = f_p(P).

The pressure input is piecewise constant in time (a step, or a gait: a list of (duration, P)
phases). Within a phase the coefficients are constant and the ODE is linear; we still integrate it
with scipy's `solve_ivp` (Radau: the system is stiff, the mass is 23 g and b_p/m ~ 2000 1/s against
k_p/b_p ~ 2.5 1/s), restarting at every pressure switch so that no step straddles a discontinuity.
Units: mm, s, N, tonne; P in kPa. The damping b_p is an assumption (see `analytic.prototype`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.statics import G_STANDARD, EPSAParams


@dataclass(frozen=True)
class Response:
    t: np.ndarray  # s
    y: np.ndarray  # extension, mm
    v: np.ndarray  # velocity, mm/s
    pressure_kpa: np.ndarray


def simulate(
    actuator: EPSAParams,
    phases: Sequence[tuple[float, float]],
    y0: float = 0.0,
    v0: float = 0.0,
    g: float = G_STANDARD,
    samples_per_phase: int = 200,
) -> Response:
    """Integrate eq. (1) over `phases` = [(duration_s, pressure_kpa), ...]."""
    if not phases:
        raise ModelInputError("phases", "need at least one (duration, pressure) phase")
    m = actuator.mass
    if m <= 0:
        raise ModelInputError("mass", "must be > 0 for the dynamic model")
    ts, ys, vs, ps = [], [], [], []
    t0, state = 0.0, np.array([y0, v0], dtype=float)
    for duration, p in phases:
        if duration <= 0:
            raise ModelInputError("duration", "phase durations must be > 0 s")
        if p < 0:
            raise ModelInputError("pressure", "must be >= 0 kPa")
        k = float(actuator.k_p(p))
        b = float(actuator.b_p(p))
        f = float(actuator.f_p(p))

        def rhs(_t: float, s: np.ndarray, k: float = k, b: float = b, f: float = f) -> list[float]:
            return [s[1], (f - m * g - b * s[1] - k * s[0]) / m]

        def jac(_t: float, _s: np.ndarray, k: float = k, b: float = b) -> list[list[float]]:
            return [[0.0, 1.0], [-k / m, -b / m]]

        t_eval = np.linspace(t0, t0 + duration, samples_per_phase)
        sol = solve_ivp(
            rhs, (t0, t0 + duration), state, method="Radau", t_eval=t_eval, jac=jac, rtol=1e-7, atol=1e-9
        )
        if not sol.success:  # pragma: no cover - scipy failure is a bug, not user input
            raise RuntimeError(sol.message)
        ts.append(sol.t)
        ys.append(sol.y[0])
        vs.append(sol.y[1])
        ps.append(np.full(sol.t.shape, float(p)))
        t0 += duration
        state = sol.y[:, -1]
    return Response(np.concatenate(ts), np.concatenate(ys), np.concatenate(vs), np.concatenate(ps))


def step_response(
    actuator: EPSAParams, pressure_kpa: float, duration_s: float = 2.0, g: float = G_STANDARD
) -> Response:
    """Start at the P = 0 equilibrium and step to `pressure_kpa`."""
    y0 = float(actuator.extension(0.0, g))
    return simulate(actuator, [(duration_s, pressure_kpa)], y0=y0, g=g)


def gait_response(
    actuator: EPSAParams,
    pressure_kpa: float,
    inflate_s: float = 1.5,
    deflate_s: float = 0.5,
    cycles: int = 3,
    g: float = G_STANDARD,
) -> Response:
    """Paper's gait 1 style cycles: inflate to P for inflate_s, deflate to 0 for deflate_s."""
    y0 = float(actuator.extension(0.0, g))
    phases = [(inflate_s, pressure_kpa), (deflate_s, 0.0)] * int(cycles)
    return simulate(actuator, phases, y0=y0, g=g)


def gait_stride(
    actuator: EPSAParams,
    pressure_kpa: float,
    inflate_s: float = 1.5,
    deflate_s: float = 0.5,
    cycles: int = 4,
    g: float = 0.0,
) -> float:
    """Friction-free stride (mm) of a periodic inflate/deflate gait with eq. (1)'s dynamics.

    The extension at the end of the last inflation minus that at the end of the last deflation:
    with the 1.5 s + 0.5 s cycle of the paper's gait 1 the actuator neither fully extends nor fully
    retracts, so this is below the static stride y(P) - y(0).
    """
    r = gait_response(actuator, pressure_kpa, inflate_s, deflate_s, cycles, g)
    n = r.t.size // (2 * cycles)
    return float(r.y[-n - 1] - r.y[-1])
