r"""The pointwise contact law: penalty normal pressure and Coulomb friction by return mapping.

At a point of the body's surface at spatial position x, against a rigid surface with gap g(x),
normal n(x) (into the admissible side) and curvature dn/dx = -C (`fem.rigid_surfaces`):

Normal (penalty with an augmented-Lagrangian multiplier lambda >= 0, Uzawa):

    p_N = < lambda + eps_N (-g) >_+,        f_N = p_N n          (force per reference area)
    d f_N / dx = -eps_N n n - p_N C          (active points; zero elsewhere)

Friction (penalty regularised Coulomb law, elastic predictor and return mapping). The stick
point x_s is history, fixed during the Newton iterations of an increment. With v = x - x_s,
the projector P = I - n n and v_n = n . v, the trial traction is

    t* = -eps_T P v,      d t*/dx = -eps_T [ P + v_n C + n (C v)^T ]

(the last two terms vanish on a plane; they are the curvature part of the projector). Stick
where |t*| <= mu p_N (1 + SLIP_MARGIN): f_T = t*. Slip otherwise: with m = t* / |t*|

    f_T = mu p_N m,
    d f_T / dx = mu m (d p_N/dx)^T + mu p_N / |t*| (I - m m) d t*/dx,   d p_N/dx = -eps_N n

The first term is the slip-normal coupling, which is not symmetric; with it Newton converges
quadratically in slip (dropping it leaves a linearly converging iteration).

SLIP_MARGIN (1e-9, far above round-off, far below any physical change) makes the points that a
commit has put exactly on the Coulomb limit stick at the start of the next increment (the elastic
predictor of return mapping): without it their status at the start is decided by round-off, and a
foot in full slip whose load then decreases gets the slip tangent, which has no stiffness along
the slip: the first Newton step of the unloading is a free rigid slide that no line search can
repair at any step size (seen in the crawl, docs/DESIGN.md section 13).

History update, after an increment has converged (never inside Newton): stick points keep x_s;
slipping points move it so that the elastic part of the tangential spring equals the traction,
x_s <- x + f_T / eps_T; points out of contact reset it, x_s <- x. The Uzawa update at a
converged state sets lambda <- p_N (zero where the point has separated).

Everything is per point and vectorised over points (n, ...).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SLIP_MARGIN = 1e-9


@dataclass(frozen=True)
class PointState:
    """The law evaluated at n points."""

    pressure: np.ndarray  # (n,) p_N, MPa (force per reference area)
    normal: np.ndarray  # (n, 3)
    gap: np.ndarray  # (n,)
    friction: np.ndarray  # (n, 3) f_T, MPa
    active: np.ndarray  # (n,) bool
    slip: np.ndarray  # (n,) bool (active and slipping)
    force: np.ndarray  # (n, 3) f_N + f_T: the surface's force on the body per reference area
    stiffness: np.ndarray | None  # (n, 3, 3) -d force / dx


def evaluate(x, surface, multiplier, stick, eps_n, eps_t, mu, with_tangent) -> PointState:
    """The contact law at points x (n, 3) against `surface` (module docstring)."""
    g, n, C = surface.project(x)
    trial = multiplier - eps_n * g
    active = trial >= 0.0  # at g = 0 exactly: active with zero pressure (keeps the stiffness)
    p = np.where(active, trial, 0.0)
    f_n = p[:, None] * n
    f_t = np.zeros_like(x)
    slip = np.zeros(x.shape[0], dtype=bool)
    K = None
    if with_tangent:
        K = eps_n * n[:, :, None] * n[:, None, :]
        if C is not None:
            K = K + p[:, None, None] * C
        K[~active] = 0.0
    if mu > 0.0:
        v = x - stick
        v_n = np.einsum("ni,ni->n", n, v)
        t_trial = -eps_t * (v - v_n[:, None] * n)
        norm = np.linalg.norm(t_trial, axis=1)
        slip = active & (norm > mu * p * (1.0 + SLIP_MARGIN))
        stuck = active & ~slip
        safe = np.where(slip, norm, 1.0)
        m = t_trial / safe[:, None]
        f_t = np.where(stuck[:, None], t_trial, 0.0) + np.where(slip[:, None], (mu * p)[:, None] * m, 0.0)
        if with_tangent:
            dt = -eps_t * (np.eye(3)[None] - n[:, :, None] * n[:, None, :])
            if C is not None:
                Cv = np.einsum("nij,nj->ni", C, v)
                dt = dt - eps_t * (v_n[:, None, None] * C + n[:, :, None] * Cv[:, None, :])
            proj = np.eye(3)[None] - m[:, :, None] * m[:, None, :]
            d_slip = (mu * p / safe)[:, None, None] * np.matmul(proj, dt)
            d_slip += mu * m[:, :, None] * (-eps_n * n)[:, None, :]
            K = K - np.where(stuck[:, None, None], dt, 0.0) - np.where(slip[:, None, None], d_slip, 0.0)
    return PointState(p, n, g, f_t, active, slip, f_n + f_t, K)


def committed_stick(state: PointState, x: np.ndarray, stick: np.ndarray, eps_t: float) -> np.ndarray:
    """The stick points after a converged increment (module docstring)."""
    out = np.where(state.slip[:, None], x + state.friction / eps_t, stick)
    return np.where(state.active[:, None], out, x)
