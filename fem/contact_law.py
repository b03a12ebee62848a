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
eps_N delta / 8 (docs/decisions/040-contact-fixes.md).

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
repair at any step size (seen in the crawl, docs/decisions/053-crawl-solver.md).

Rounded cone (optional, `ContactSpec.slip_band` = w, a share of the Coulomb radius; off by
default). With r = |t*| / (mu p_N), the traction is f_T = mu p_N phi(r) m, where phi(r) = min(r, 1)
is the exact law and its C1 rounding is

    phi(r) = r                               r <= 1 - w/2        (stick: f_T = t*)
    phi(r) = r - (r - 1 + w/2)^2 / (2 w)     |r - 1| < w/2       (the band)
    phi(r) = 1                               r >= 1 + w/2        (slip)

so |f_T| <= mu p_N always (the Coulomb limit is not moved; on the band the traction is below the
stick value by at most mu p_N w / 8) and the tangent is continuous across the cone. On the band

    d f_T / dx = mu (phi - r phi') m (d p_N/dx)^T + phi' m m^T d t*/dx + mu p_N phi / |t*| (I - m m) d t*/dx

(phi' = 1 - (r - 1 + w/2) / w), which is the stick tangent at r = 1 - w/2 and the slip tangent at
1 + w/2. Why: with the exact cone a point at the Coulomb limit switches between the stick tangent
eps_T P and the slip tangent (no stiffness along m) from one Newton iteration to the next, and in
the foot's backward drag two such points flip ten times in a solve without converging
(docs/decisions/037-coulomb-cone.md); with the rounded cone the residual is C1 and Newton's local
convergence holds.

Viscous slip (optional, `ContactSpec.slip_viscosity` = eta, MPa s/mm: traction per slip speed;
off by default). Coulomb's law is rate-independent: a point in full slip has no stiffness along
its slide, and a skirt that goes into gross slip leaves nothing but the body to hold it along the
wall (docs/decisions/088-viscous-slip.md). The viscous (Perzyna) regularisation lets the traction
exceed the cone by eta times the slip speed: over a sub-step of duration dt the slip increment
dgamma satisfies |t*| - eps_T dgamma = mu p_N + eta dgamma / dt (backward Euler), so

    f_T = (1 - kappa) f_T^C + kappa t*,     kappa = eta / (eta + eps_T dt)  in [0, 1]

a blend of the rate-independent traction f_T^C (the exact or rounded cone above) and the elastic
trial, and its tangent the same blend of theirs (kappa is fixed within the increment). kappa = 0
is Coulomb (eta = 0, or a stage without a duration: pseudo-time only); dt -> 0 gives kappa -> 1,
a point that cannot slip in no time, so that cutting a sub-step back makes every point stiffer
along its slide. Closed form: a point dragged at a steady speed v converges to
|f_T| = mu p_N + eta v (the fixed point of the update below; `steady_slip_traction`).

History update, after an increment has converged (never inside Newton): stick points keep x_s;
slipping points move it so that the elastic part of the tangential spring equals the traction,
x_s <- x + f_T / eps_T; points out of contact reset it, x_s <- x. With the rounded cone the
return goes to the cone, r <- min(r, 1): points with r > 1 get x_s <- x + mu p_N m / eps_T (the
same formula at w = 0), the others keep x_s. A point that slid is therefore stored at r = 1 on
the band, where phi' = 1/2 (a stiffness along the slip for the next increment; at 1 + w/2 it
would be 0, the free-slide failure SLIP_MARGIN prevents for w = 0), at the price of a one-off
drop of its traction by at most mu p_N w / 8 at that commit; a point held still is not moved by
further commits. With viscous slip the points with r > 1 keep their overstress instead,
r <- 1 + kappa (r - 1). The Uzawa update at a converged state sets lambda <- p_N (zero where
the point has separated).

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
    slip: np.ndarray  # (n,) bool: active and in full slip (r > 1 + w/2 with a rounded cone)
    force: np.ndarray  # (n, 3) f_N + f_T: the surface's force on the body per reference area
    stiffness: np.ndarray | None  # (n, 3, 3) -d force / dx
    trial: np.ndarray  # (n, 3) t*, the elastic trial traction (0 without friction)


def normal_pressure(trial: np.ndarray, width: float):
    """(p_N, dp_N/dq, active) of the trial pressure q = lambda - eps_N g (module docstring): the
    kink <q>_+ or, with width w > 0, its C1 rounding over |q| < w / 2."""
    if width <= 0.0:
        active = trial >= 0.0  # at g = 0 exactly: active with zero pressure (keeps the stiffness)
        return np.where(active, trial, 0.0), active.astype(float), active
    ramp = np.clip(trial + 0.5 * width, 0.0, width)
    p = np.where(trial >= 0.5 * width, trial, ramp * ramp / (2.0 * width))
    return p, ramp / width, trial > -0.5 * width


def cone(r: np.ndarray, band: float):
    """(phi, phi') of the rounded Coulomb cone at r = |t*| / (mu p_N) (module docstring); band 0:
    the exact min(r, 1)."""
    if band <= 0.0:
        return np.minimum(r, 1.0), (r <= 1.0).astype(float)
    a = np.clip(r - 1.0 + 0.5 * band, 0.0, band)
    return np.where(r >= 1.0 + 0.5 * band, 1.0, r - a * a / (2.0 * band)), 1.0 - a / band


def viscous_share(viscosity: float, eps_t: float, dt: float | None) -> float:
    """kappa = eta / (eta + eps_T dt) of viscous slip (module docstring): 0 without viscosity or
    without a time step (pseudo-time), 1 at dt = 0."""
    if viscosity <= 0.0 or dt is None:
        return 0.0
    return viscosity / (viscosity + eps_t * max(float(dt), 0.0))


def steady_slip_traction(mu_p: float, viscosity: float, speed: float) -> float:
    """The closed form a point dragged at a steady slip speed v reaches: mu p_N + eta v."""
    return mu_p + viscosity * speed


def evaluate(
    x, surface, multiplier, stick, eps_n, eps_t, mu, with_tangent, smoothing=0.0, slip_band=0.0, kappa=0.0
) -> PointState:
    """The contact law at points x (n, 3) against `surface` (module docstring); `smoothing` (mm)
    rounds the normal law's kink over a gap band of that width, `slip_band` (a share of the
    Coulomb radius) rounds the cone (0: the exact law), `kappa` is the viscous share of the slip
    (`viscous_share`; 0: Coulomb)."""
    g, n, C = surface.project(x)
    trial = multiplier - eps_n * g
    p, dp, active = normal_pressure(trial, eps_n * smoothing)
    f_n = p[:, None] * n
    f_t = np.zeros_like(x)
    t_trial = np.zeros_like(x)
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
        radius = mu * p
        if slip_band > 0.0:
            stuck = active & (norm <= radius * (1.0 - 0.5 * slip_band))
        else:
            stuck = active & (norm <= radius * (1.0 + SLIP_MARGIN))
        rounded = active & ~stuck  # on the band or beyond (w = 0: in slip)
        slip = active & (norm > radius * (1.0 + 0.5 * slip_band) * (1.0 + SLIP_MARGIN))
        safe = np.where(rounded, norm, 1.0)
        m = t_trial / safe[:, None]
        r = np.where(rounded & (radius > 0), norm / np.where(radius > 0, radius, 1.0), np.inf)
        phi, dphi = cone(r, slip_band)
        f_round = (1.0 - kappa) * (radius * phi)[:, None] * m + kappa * t_trial
        f_t = np.where(stuck[:, None], t_trial, 0.0) + np.where(rounded[:, None], f_round, 0.0)
        if with_tangent:
            dt = -eps_t * (np.eye(3)[None] - n[:, :, None] * n[:, None, :])
            if C is not None:
                Cv = np.einsum("nij,nj->ni", C, v)
                dt = dt - eps_t * (v_n[:, None, None] * C + n[:, :, None] * Cv[:, None, :])
            mm = m[:, :, None] * m[:, None, :]
            dp_dx = -(eps_n * dp)[:, None] * n
            coupling = phi - np.where(np.isfinite(r), r, 0.0) * dphi  # r = inf: phi = 1, phi' = 0
            d_round = (radius * phi / safe)[:, None, None] * np.matmul(np.eye(3)[None] - mm, dt)
            d_round += (mu * coupling)[:, None, None] * m[:, :, None] * dp_dx[:, None, :]
            d_round += dphi[:, None, None] * np.matmul(mm, dt)
            if kappa > 0.0:
                d_round = (1.0 - kappa) * d_round + kappa * dt
            K = K - np.where(stuck[:, None, None], dt, 0.0) - np.where(rounded[:, None, None], d_round, 0.0)
    return PointState(p, n, g, f_t, active, slip, f_n + f_t, K, t_trial)


def committed_stick(
    state: PointState, x: np.ndarray, stick: np.ndarray, eps_t: float, mu: float, kappa: float = 0.0
) -> np.ndarray:
    """The stick points after a converged increment (`state` evaluated at x with `stick`): the
    return to the cone r <- min(r, 1) (module docstring; at w = 0 the points in slip); with viscous
    slip (kappa > 0) to the overstress r <- 1 + kappa (r - 1) of the points past the cone."""
    norm = np.linalg.norm(state.trial, axis=1)
    radius = mu * state.pressure
    past = state.active & (norm > radius)
    m = state.trial / np.where(past & (norm > 0), norm, 1.0)[:, None]
    kept = (1.0 - kappa) * radius + kappa * norm
    out = np.where(past[:, None], x + (kept[:, None] * m) / eps_t, stick)
    return np.where(state.active[:, None], out, x)
