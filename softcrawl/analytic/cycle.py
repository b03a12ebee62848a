"""The crawling cycle's geometry and the pipe-fit check, shared by every gait planner.

Model of one crawling cycle (paper Section IV, eqs. 16-18; assumption (c) of Section III-C and
Fig. 4):

1. Inflation, rear foot fixed. The pressures go linearly from the deflated triple to the inflated
   triple P, whose ePSA lengths come from the statics model (eq. 3); each stage is a
   constant-curvature arc (eqs. 4-6) posed from the rear foot frame (eq. 9). During inflation the
   ePSA lengths go linearly from the deflated lengths to the statics lengths of the inflated
   triple (the shape path between two static states is not modelled by the paper); `stages`
   evenly spaced stages, the inflated state last, are checked.
2. Deflation, front foot fixed, curvature kept (eqs. 16, 18: kappa_2 = kappa_1, phi_2 = phi_1). The
   body shrinks along its own arc to the deflated centreline length l_def, so the rear foot slides
   along the inflated arc by (l_c - l_def), i.e. through the angle theta_2 = (l_c - l_def) kappa
   (eq. 17; the paper writes (l_1 - 100) kappa).

Deflated length, two modes (`deflation=`):

* "paper" (default): eq. (17) as printed, the deflated centreline has the rest length whatever the
  curvature. We use the model's P = 0 centreline length, mean_i l_i(0) (99.25 mm for the nominal
  actuator), instead of the printed 100 mm so that a straight robot deflates to exactly P = 0.
  The deflated ePSA lengths l_i = l_def (1 - kappa d cos(psi_i - phi)) then put the inner ePSA below
  its rest length: it is fully vented (0 kPa) and the kept curvature is the paper's assumption
  (the pipe and the anchored front foot hold it), while ePSAs above their rest length keep the
  pressure that the inverted statics model gives (the paper's gait 2, "deflated but not fully").
* "held": no ePSA may go below its rest length, so the curvature is held by pressure alone:
  l_def = max_i l_i(0) / (1 - kappa d cos(psi_i - phi)). Bent bodies then stay long after
  deflation and the stride in a bend is much shorter.

Deflated triples invert the statics model (`EPSAParams.pressure_for_length`: smallest pressure on
the monotone branch; a length inside an upward 60 kPa gap -> 60 kPa; lengths below rest -> 0 kPa).

Pipe-fit check (`PipeFit`). With `body="tube"` (default) the body is a tube of radius
`body_radius` (d + R0 = 23 mm, half the prototype's 46 mm minimum diameter; the feet, 78 mm, deform
and are not checked) around the arc, so every sampled arc point of every inflation stage must lie
within allow = D/2 - 23 = 12 mm of the pipe centreline (70 mm pipe). With `body="epsa"` only the
three ePSA tubes (R0 = 9 mm around their own centrelines at d = 14 mm) are checked; this ignores
the connecting rings. Deflated bodies are sub-arcs of the inflated one, hence inside as well.

Roll. In an elbow the robot is inserted with ePSA 1 (psi = 90 deg) facing the inside of the bend, so
bends in the bend plane are the family P2 = P3, P1 lower (the paper's gait 2: "ePSA2 and ePSA3 are
inflated for 1.5 s, ePSA1 for 0.3 s").

Bend-plane form (`analytic.planar`, `analytic.refine`). With that roll and P2 = P3 every cycle is a
planar arc of signed curvature k (> 0 towards ePSA 1, i.e. towards the bend):

    l1 = l_c (1 - k d),  l2 = l3 = l_c (1 + k d / 2),  l_c = (l1 + 2 l23)/3,  k = (1 - l1/l_c)/d,

the rear foot's pose is (x, z, heading) in the x-z plane, and the paper deflation gives the
deflated lengths l_def (1 - k d), l_def (1 + k d / 2).

Gravity: only the "vertical" pipe applies g along the body axis (climbing). Straight and elbow plans
are made without gravity, as the paper's kinematics are (assumption (d)).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.analytic import kinematics as kin
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.limits import MIN_PLAN_STEP_KPA, check
from softcrawl.analytic.pipe import Pipe
from softcrawl.analytic.prototype import BODY_RADIUS_MM
from softcrawl.analytic.statics import G_STANDARD, EPSAParams
from softcrawl.paper import EPSA_RADIUS_MM, P_MAX_KPA

#: Deflated-length modes (module docstring).
DEFLATIONS = ("paper", "held")
#: Bodies of the pipe-fit check: the 23 mm tube, or the three ePSA tubes.
BODIES = ("tube", "epsa")


def check_deflation(deflation: str) -> None:
    if deflation not in DEFLATIONS:
        raise ModelInputError("deflation", f"must be 'paper' or 'held', got {deflation!r}")


def gravity(pipe: Pipe) -> float:
    """Axial gravity of the statics, mm/s^2: g in a vertical pipe (the robot climbs), else 0."""
    return G_STANDARD if pipe.kind == "vertical" else 0.0


def elbow_roll(pipe: Pipe) -> np.ndarray:
    """Roll ePSA 1 (psi = 90 deg, local +y) to the inside of an elbow's bend (world +x)."""
    if pipe.kind == "elbow":
        return np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    return np.eye(3)


def pressure_grid(step_kpa: float, planar: bool = False) -> np.ndarray:
    """All triples on a `step_kpa` grid, or only P2 = P3 (bending in the plane of ePSA 1); the step
    is at least `analytic.limits.MIN_PLAN_STEP_KPA` and divides 100 kPa."""
    step_kpa = check(step_kpa, "step", minimum=MIN_PLAN_STEP_KPA, maximum=P_MAX_KPA, unit="kPa")
    n = int(round(P_MAX_KPA / step_kpa))
    if n < 1 or abs(n * step_kpa - P_MAX_KPA) > 1e-9:
        raise ModelInputError("step", f"must divide {P_MAX_KPA:g} kPa, got {step_kpa:g}")
    v = np.linspace(0.0, P_MAX_KPA, n + 1)
    if planar:
        a, b = np.meshgrid(v, v, indexing="ij")
        return np.stack([a.ravel(), b.ravel(), b.ravel()], -1)
    return np.stack(np.meshgrid(v, v, v, indexing="ij"), -1).reshape(-1, 3)


def epsa_lengths(acts: Sequence[EPSAParams], pressures: ArrayLike, g: float) -> np.ndarray:
    """Statics lengths (..., 3) in mm of the triples `pressures` (..., 3) in kPa (eq. 3)."""
    P = np.asarray(pressures)
    return np.stack([acts[i].length(P[..., i], g) for i in range(3)], -1)


def stage_fractions(stages: int) -> np.ndarray:
    """Fractions of the inflation path at the checked stages: 1/stages, 2/stages, ..., 1."""
    return np.linspace(0.0, 1.0, stages + 1)[1:]


def inflation_lengths(l_from: ArrayLike, l_to: ArrayLike, fraction: ArrayLike) -> np.ndarray:
    """ePSA lengths a `fraction` of the way from the deflated `l_from` to the inflated `l_to`."""
    l_from = np.asarray(l_from)
    return l_from + fraction * (np.asarray(l_to) - l_from)


def body_points(
    pos: np.ndarray, rot: np.ndarray, lengths: np.ndarray, d: float, n_s: int, epsa: bool = False
) -> np.ndarray:
    """World points of the body arcs with the given ePSA lengths, posed from the rear foot.

    (..., n_s, 3) on the body centreline, or with `epsa` (..., 3 * n_s, 3) on the three ePSA
    centrelines (offset d at psi_i in the cross-section frame, which follows the arc by eq. 9).
    """
    k, t, p, lc = kin.forward(lengths, d)
    f = np.linspace(0.0, 1.0, n_s)
    local = kin.arc_point(t[..., None] * f, p[..., None], lc[..., None] * f)
    if epsa:
        frames = kin.arc_rotation(t[..., None] * f, p[..., None])  # (..., n_s, 3, 3)
        offs = d * np.stack([np.cos(kin.PSI), np.sin(kin.PSI), np.zeros(3)], -1)  # (3, 3)
        local = local[..., None, :] + np.einsum("...ij,aj->...ai", frames, offs)
        local = local.reshape(local.shape[:-3] + (-1, 3))
    return pos + local @ rot.T


def front_foot(pos: np.ndarray, rot: np.ndarray, theta: float, phi: float, lc: float) -> np.ndarray:
    """The front foot of the inflated arc posed from the rear foot (`pos`, `rot`)."""
    return pos + rot @ kin.arc_point(theta, phi, lc)


def deflated_length(
    acts: Sequence[EPSAParams], kappa: ArrayLike, phi: ArrayLike, d: float, g: float, mode: str
) -> np.ndarray:
    """Deflated centreline length l_def of bodies that keep (kappa, phi), mode "paper" or "held"."""
    rest = np.array([float(a.length(0.0, g)) for a in acts])
    if mode == "paper":
        return np.full(np.shape(kappa), rest.mean())
    c = 1.0 - np.asarray(kappa)[..., None] * d * np.cos(kin.PSI - np.asarray(phi)[..., None])
    return np.max(rest / c, axis=-1)


def deflated_lengths(l_def: float, kappa: float, phi: float, d: float) -> np.ndarray:
    """ePSA lengths l_def (1 - kappa d cos(psi_i - phi)) of the deflated body, (3,)."""
    return l_def * (1.0 - kappa * d * np.cos(kin.PSI - phi))


def deflated_pressures(acts: Sequence[EPSAParams], lengths: np.ndarray, g: float) -> np.ndarray:
    """Pressures (3,) in kPa that hold the deflated ePSA `lengths`; 0 below the rest length."""
    out = []
    for a, length in zip(acts, lengths):
        vented = length <= float(a.length(0.0, g)) + 1e-12
        out.append(0.0 if vented else a.pressure_for_length(length, g))
    return np.array(out)


def rear_slide(
    pos: np.ndarray, rot: np.ndarray, kappa: ArrayLike, phi: ArrayLike, step: ArrayLike
) -> np.ndarray:
    """Rear foot(s) after deflation: slid by `step` along the inflated arc (eq. 17)."""
    return pos + kin.arc_point(kappa * step, phi, step) @ rot.T


def frame_slide(rot: np.ndarray, kappa: ArrayLike, phi: ArrayLike, step: ArrayLike) -> np.ndarray:
    """Rear-foot frame(s) after deflation, rot Rz(phi) Ry(kappa step) Rz(-phi) (eq. 9)."""
    return rot @ kin.arc_rotation(kappa * step, phi)


def planar_configuration(l1: ArrayLike, l23: ArrayLike, d: float) -> tuple[np.ndarray, np.ndarray]:
    """Signed curvature k and centreline length l_c of the bend-plane arc of (l1, l23, l23)."""
    lc = (l1 + 2.0 * np.asarray(l23)) / 3.0
    return (1.0 - l1 / lc) / d, lc


def planar_deflated_lengths(l_def: float, k: ArrayLike, d: float) -> tuple[np.ndarray, np.ndarray]:
    """Deflated (l1, l23) of a bend-plane body of signed curvature k (paper deflation)."""
    return l_def * (1.0 - k * d), l_def * (1.0 + k * d / 2.0)


def planar_body_points(
    x: ArrayLike,
    z: ArrayLike,
    heading: ArrayLike,
    l1: ArrayLike,
    l23: ArrayLike,
    d: float,
    f: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Bend-plane points (x, z), shape (..., len(f)), at the fractions `f` of the body arcs (l1, l23).

    The rear foot (x, z, heading) broadcasts against l1 and l23 (the samples are the last axis).
    """
    k, lc = planar_configuration(l1, l23, d)
    lat, ax = kin.planar_arc(k[..., None], lc[..., None] * f)
    x, z, heading = (np.asarray(v)[..., None] for v in (x, z, heading))
    c, s = np.cos(heading), np.sin(heading)
    return x + c * lat + s * ax, z - s * lat + c * ax


def planar_slide(
    x: ArrayLike, z: ArrayLike, heading: ArrayLike, k: ArrayLike, step: ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rear foot (x, z, heading) after sliding by `step` along a bend-plane arc of curvature k."""
    lat, ax = kin.planar_arc(k, step)
    c, s = np.cos(heading), np.sin(heading)
    return x + c * lat + s * ax, z - s * lat + c * ax, heading + k * step


def planar_distances(
    pipe: Pipe,
    x: ArrayLike,
    z: ArrayLike,
    heading: ArrayLike,
    l1: ArrayLike,
    l23: ArrayLike,
    d: float,
    f: np.ndarray,
) -> np.ndarray:
    """Pipe-centreline distances (..., len(f)) of the bend-plane body arcs of `planar_body_points`."""
    return pipe.plane_distance(*planar_body_points(x, z, heading, l1, l23, d, f))


@dataclass(frozen=True)
class PipeFit:
    """The pipe-fit check: the body's sampled centreline points stay within `allow` of the pipe's.

    `epsa`: the points are on the three ePSA centrelines (`body_radius` is then R0). A body fits
    if its largest distance is at most allow + tol; its clearance is allow minus that distance.
    """

    pipe: Pipe
    body_radius: float = BODY_RADIUS_MM
    epsa: bool = False
    tol: float = 1e-9

    @classmethod
    def of(
        cls, pipe: Pipe, body_radius: float = BODY_RADIUS_MM, body: str = "tube", tol: float = 1e-9
    ) -> PipeFit:
        """The check of a `body` ("tube" or "epsa") after checking that it fits the pipe at all."""
        if body not in BODIES:
            raise ModelInputError("body", f"must be 'tube' or 'epsa', got {body!r}")
        epsa = body == "epsa"
        fit = cls(pipe, EPSA_RADIUS_MM if epsa else body_radius, epsa, tol)
        if fit.allow < 0:
            raise ModelInputError(
                "diameter", f"a {2 * fit.body_radius:g} mm body does not fit a {pipe.diameter:g} mm pipe"
            )
        return fit

    @property
    def allow(self) -> float:
        """Largest distance of a body centreline point from the pipe centreline, D/2 - r, mm."""
        return self.pipe.diameter / 2.0 - self.body_radius

    def fits(self, worst: ArrayLike) -> np.ndarray:
        """Whether bodies whose largest centreline distance is `worst` are inside the pipe."""
        return np.asarray(worst) <= self.allow + self.tol

    def clearance(self, worst: ArrayLike) -> np.ndarray:
        """Wall clearance to spare, mm, of bodies whose largest centreline distance is `worst`."""
        return self.allow - np.asarray(worst)

    def inflation_distances(
        self,
        pos: np.ndarray,
        rot: np.ndarray,
        l_from: np.ndarray,
        l_to: np.ndarray,
        fractions: np.ndarray,
        d: float,
        samples: int,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Inflation from `l_from` (3,) to `l_to` (..., 3), rear foot at (`pos`, `rot`).

        Returns the ePSA lengths (stages, ..., 3) at the stage `fractions` and the pipe-centreline
        distances (stages, ..., samples) of their body points.
        """
        lam = np.asarray(fractions).reshape((-1,) + (1,) * np.ndim(l_to))
        lengths = inflation_lengths(l_from, l_to, lam)
        return lengths, self.distances(pos, rot, lengths, d, samples)

    def distances(
        self, pos: np.ndarray, rot: np.ndarray, lengths: np.ndarray, d: float, samples: int
    ) -> np.ndarray:
        """Pipe-centreline distances (..., samples; 3 samples with `epsa`) of the bodies `lengths`."""
        dist, _ = self.pipe.locate(body_points(pos, rot, lengths, d, samples, self.epsa))
        return dist

    def planar_distances(
        self,
        x: ArrayLike,
        z: ArrayLike,
        heading: ArrayLike,
        l1: ArrayLike,
        l23: ArrayLike,
        d: float,
        f: np.ndarray,
    ) -> np.ndarray:
        """Pipe-centreline distances (..., len(f)) of the bend-plane body arcs of `planar_body_points`."""
        return planar_distances(self.pipe, x, z, heading, l1, l23, d, f)
