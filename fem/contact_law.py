r"""The pointwise contact law: penalty normal pressure and Coulomb friction by return mapping.

At a point of the body's surface at spatial position x, against a rigid surface with gap g(x),
normal n(x) (into the admissible side) and curvature dn/dx = -C (`fem.rigid_surfaces`):

Normal (penalty with an augmented-Lagrangian multiplier lambda >= 0, Uzawa):

    p_N = < lambda + eps_N (-g) >_+,        f_N = p_N n          (force per reference area)
    d f_N / dx = -eps_N n n - p_N C          (active points; zero elsewhere)

Smoothing (optional, `ContactSpec.smoothing` = delta, mm; off by default). With the width
w = eps_N delta in pressure, the kink of <q>_+ (q = lambda - eps_N g, the trial pressure) is
rounded to p_N = (q + w/2)^2 / (2 w) for |q| < w / 2; p_N = q above (no offset: the Uzawa loop
still drives the penetration of pressed points to zero) and 0 below. p_N and dp_N/dq are
continuous, so a point at the edge of the contact zone no longer switches the stiffness eps_N
n n (and the slip-normal coupling mu eps_N m n) on and off between Newton iterations: at g = 0
it has dp_N/dq = 1/2. The price: points within delta / 2 outside the surface carry at most
eps_N delta / 8 (docs/DESIGN.md section 11).

Friction (penalty regularised Coulomb law, elastic predictor and return mapping). The stick
point x_s is history, fixed during the Newton iterations of an increment. With v = x - x_s,
the projector P = I - n n and v_n = n . v, the trial traction is

    t* = -eps_T P v,      d t*/dx = -eps_T [ P + v_n C + n (C v)^T ]

(the last two terms vanish on a plane; they are the curvature part of the projector). Stick
where |t*| <= mu p_N (1 + SLIP_MARGIN): f_T = t*. Slip otherwise: with m = t* / |t*|

    f_T = mu p_N m,
    d f_T / dx = mu m (d p_N/dx)^T + mu p_N / |t*| (I - m m) d t*/dx,   d p_N/dx = -eps_N (dp_N/dq) n

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


def normal_pressure(trial: np.ndarray, width: float):
    """(p_N, dp_N/dq, active) of the trial pressure q = lambda - eps_N g (module docstring): the
    kink <q>_+ or, with width w > 0, its C1 rounding over |q| < w / 2."""
    if width <= 0.0:
        active = trial >= 0.0  # at g = 0 exactly: active with zero pressure (keeps the stiffness)
        return np.where(active, trial, 0.0), active.astype(float), active
    ramp = np.clip(trial + 0.5 * width, 0.0, width)
    p = np.where(trial >= 0.5 * width, trial, ramp * ramp / (2.0 * width))
    return p, ramp / width, trial > -0.5 * width


def evaluate(x, surface, multiplier, stick, eps_n, eps_t, mu, with_tangent, smoothing=0.0) -> PointState:
    """The contact law at points x (n, 3) against `surface` (module docstring); `smoothing` (mm)
    rounds the normal law's kink over a gap band of that width (0: the exact kink)."""
    g, n, C = surface.project(x)
    trial = multiplier - eps_n * g
    p, dp, active = normal_pressure(trial, eps_n * smoothing)
    f_n = p[:, None] * n
    f_t = np.zeros_like(x)
    slip = np.zeros(x.shape[0], dtype=bool)
    K = None
    if with_tangent:
        K = (eps_n * dp)[:, None, None] * n[:, :, None] * n[:, None, :]
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
            d_slip += mu * m[:, :, None] * (-(eps_n * dp)[:, None] * n)[:, None, :]
            K = K - np.where(stuck[:, None, None], dt, 0.0) - np.where(slip[:, None, None], d_slip, 0.0)
    return PointState(p, n, g, f_t, active, slip, f_n + f_t, K)


def committed_stick(state: PointState, x: np.ndarray, stick: np.ndarray, eps_t: float) -> np.ndarray:
    """The stick points after a converged increment (module docstring)."""
    out = np.where(state.slip[:, None], x + state.friction / eps_t, stick)
    return np.where(state.active[:, None], out, x)
