r"""The inside of a corrugated (bellows-like) pipe as a rigid contact surface.

`CorrugatedPipe(radius, amplitude, pitch, centre, axis)`: a surface of revolution about the line
through `centre` along the unit `axis` a, whose wall radius varies along the axis as

    f(z) = r0 + h cos(k z),     k = 2 pi / pitch,    z = (x - centre) . a,

(r0 = `radius`, the mean inner radius; h = `amplitude` >= 0; h = 0 is `CylinderWall`). It gives
what `fem.contact_law` asks of a surface, `project(x) -> (g, n, C)`: the signed gap (positive
inside), the unit normal into the pipe, and C = -dn/dx.

Closest point. In the meridian half-plane of x (coordinates z and rho = |(I - a a)(x - centre)|,
radial unit e_r) the wall is the profile curve P(zeta) = (zeta, f(zeta)). Its foot zeta* minimises
D^2 = (zeta - z)^2 + (f(zeta) - rho)^2; since the wall point at the same z is |f(z) - rho| away,
zeta* lies in [z - delta, z + delta], delta = |f(z) - rho|. That interval is sampled (at most
pitch / 32 apart) and the best sample polished by Newton on the stationarity condition
F = (zeta - z) + (f - rho) f' = 0, F' = 1 + f'^2 + (f - rho) f''. With L = sqrt(1 + f'^2), the
profile's tangent tau = (1, f') / L and its normal into the pipe nu = (f', -1) / L, in 3D
tau3 = (a + f' e_r) / L and n = (f' a - e_r) / L, and g = (x - P(zeta*)) . n: the signed
distance, negative for a point past the wall.

Curvature. n depends on x through the foot (along the meridian) and through e_r (around the
axis). With the profile's curvature kappa = -f'' / L^3 (dnu/ds = -kappa tau along the arc length;
positive in a crest of f, where the wall is concave seen from inside, like a cylinder), the
meridian part is the 2D signed-distance Hessian dnu/dp = -kappa / (1 - kappa g) tau tau, and
d e_r / dx = t t / rho with t = a x e_r, so

    C = -dn/dx = kappa / (1 - kappa g) tau3 tau3 + (1 / (L rho)) t t,

the two principal curvatures at the wall (g = 0): kappa along the axis, and 1 / (L f) around it
(the normal's radial share over the radius). h = 0 gives C = t t / rho, the cylinder's.
The foot is unique, and C finite, for points closer to the wall than the profile's smallest
radius of curvature on the concave side, 1 / (h k^2) at the crests: `max_gap` states it. The
smallest radius r0 - h must be positive (`contact.surface.amplitude`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.rigid_surfaces import point3, positive, unit3

#: Samples per pitch of the foot search (the basin of the nearest foot is about half a pitch wide).
SAMPLES_PER_PITCH = 32
#: Newton polish of the sampled foot: iterations (each at most one sample spacing).
POLISH_ITERATIONS = 30


@dataclass(frozen=True)
class CorrugatedPipe:
    """The inside of a bellows-like pipe of mean radius `radius` (module docstring)."""

    radius: float
    amplitude: float
    pitch: float
    centre: tuple[float, float, float] = (0.0, 0.0, 0.0)
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    _a: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        r0 = positive(self.radius, "contact.surface.radius")
        pitch = positive(self.pitch, "contact.surface.pitch")
        try:
            h = float(self.amplitude)
        except (TypeError, ValueError):
            h = float("nan")
        if not (np.isfinite(h) and 0.0 <= h < r0):
            raise SolverInputError(
                "contact.surface.amplitude",
                f"must be in [0, radius {r0:g} mm) so that the narrowest radius stays positive, "
                f"got {self.amplitude!r}",
            )
        object.__setattr__(self, "radius", r0)
        object.__setattr__(self, "amplitude", h)
        object.__setattr__(self, "pitch", pitch)
        object.__setattr__(self, "centre", tuple(point3(self.centre, "contact.surface.centre")))
        a = unit3(self.axis, "contact.surface.axis")
        object.__setattr__(self, "axis", tuple(a))
        object.__setattr__(self, "_a", a)

    @property
    def wavenumber(self) -> float:
        return 2.0 * np.pi / self.pitch

    @property
    def max_gap(self) -> float:
        """The profile's smallest radius of curvature on the pipe's side, 1 / (h k^2) (inf at h = 0):
        closer to the wall than this, every point has one foot."""
        return np.inf if self.amplitude == 0 else 1.0 / (self.amplitude * self.wavenumber**2)

    def with_radius(self, radius: float) -> CorrugatedPipe:
        return replace(self, radius=radius)

    def arc_length(self, x: np.ndarray) -> np.ndarray:
        """Position (n,) of points x (n, 3) along the straight centreline: (x - centre) . axis."""
        return (np.asarray(x, dtype=float).reshape(-1, 3) - np.asarray(self.centre)) @ self._a

    def profile(self, z):
        """(f, f', f'') of the wall radius at axial coordinates z."""
        k, h = self.wavenumber, self.amplitude
        z = np.asarray(z, dtype=float)
        return self.radius + h * np.cos(k * z), -h * k * np.sin(k * z), -h * k * k * np.cos(k * z)

    def foot(self, z: np.ndarray, rho: np.ndarray) -> np.ndarray:
        """The axial coordinate zeta* of the nearest wall point in the meridian half-plane of each
        point (z, rho) (module docstring: sampled, then polished by Newton)."""
        delta = np.abs(self.profile(z)[0] - rho) + 1e-12 * self.radius
        m = int(max(8, np.ceil(2.0 * delta.max() / self.pitch * SAMPLES_PER_PITCH)))
        grid = z[:, None] + delta[:, None] * np.linspace(-1.0, 1.0, 2 * m + 1)[None, :]
        f = self.profile(grid)[0]
        best = np.argmin((grid - z[:, None]) ** 2 + (f - rho[:, None]) ** 2, axis=1)
        zeta = grid[np.arange(z.size), best]
        spacing = delta / m
        for _ in range(POLISH_ITERATIONS):
            f, df, ddf = self.profile(zeta)
            F = (zeta - z) + (f - rho) * df
            dF = 1.0 + df * df + (f - rho) * ddf
            step = np.where(dF > 0, -F / np.where(dF > 0, dF, 1.0), 0.0)
            zeta = zeta + np.clip(step, -spacing, spacing)
            if np.all(np.abs(step) <= 1e-13 * self.pitch):
                break
        return zeta

    def project(self, x: np.ndarray):
        """(gap (n,), normal (n, 3), curvature C (n, 3, 3) with dn/dx = -C) at points x (n, 3)."""
        a = self._a
        x = np.asarray(x, dtype=float).reshape(-1, 3)
        d = x - np.asarray(self.centre)
        z = d @ a
        r_vec = d - np.outer(z, a)
        rho = np.linalg.norm(r_vec, axis=1)
        safe = np.maximum(rho, 1e-12 * self.radius)
        e_r = r_vec / safe[:, None]
        t = np.cross(a, e_r)
        zeta = self.foot(z, rho)
        f, df, ddf = self.profile(zeta)
        L = np.sqrt(1.0 + df * df)
        n = (df[:, None] * a - e_r) / L[:, None]
        g = (zeta - z) * (-df / L) + (rho - f) * (-1.0 / L)  # (x - P) . n in the meridian plane
        tau = (a + df[:, None] * e_r) / L[:, None]
        kappa = -ddf / L**3
        meridian = kappa / (1.0 - kappa * g)
        C = meridian[:, None, None] * tau[:, :, None] * tau[:, None, :]
        C += (1.0 / (L * safe))[:, None, None] * t[:, :, None] * t[:, None, :]
        return g, n, C
