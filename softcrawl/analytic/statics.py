"""Phenomenological ePSA model, statics part (paper Section III-B, eqs. 1-3).

An ePSA is a thrust element f_p, a spring k_p and a damper b_p in parallel (eq. 1):

    m y'' + b_p y' + k_p y + m g = f_p,      f_p, k_p, b_p linear in P (eq. 2),

and at rest (eq. 3) the extension is

    y(P) = (f_p(P) - m g) / k_p(P),          length l(P) = l0 + y(P).

Units inside: mm, N, s, tonne, so k_p is in N/mm, b_p in N s/mm, m in tonne and g in mm/s^2.
Pressures are in kPa here (the paper identifies the coefficients per kPa); this is the one
place in `robot` where a pressure is not in MPa, and every function says so in its argument
name (`pressure_kpa`).

`g` is the component of gravity along the actuator axis that opposes extension (the paper's
identification rig stands the actuator vertically). Pass `g=0` for a horizontal actuator and for
the kinematic analyses, which the paper does "without gravity and load" (Section III-C, (d)).

Piecewise parameters. The identified coefficients (eqs. 19-24) are two straight lines in P with a
breakpoint at 60 kPa, lower line for P <= breakpoint (as printed). The printed lines do not meet at
the breakpoint, so l(P) jumps there (see `PiecewiseLinear.jump` and `EPSAParams.length_jump`). This
model keeps the printed, discontinuous law as is: it evaluates exactly the printed branch for each P
and does not blend. The inverse (length -> pressure, `pressure_for_length`) treats the jump as
follows:

* on each branch y(P) = (f1 P + f0 - m g) / (k1 P + k0) is a Moebius map, monotone in P, and is
  inverted in closed form, P = (f0 - m g - y k0) / (y k1 - f1);
* the branches are searched in increasing pressure, and the smallest pressure reaching the length is
  returned (where the jump is downward, as for the printed actuator 2, a length is reached twice and
  the lower branch wins);
* a length inside an upward gap (reached by no pressure, as for actuators 1 and 3) returns the
  breakpoint pressure, whose length is the nearest reachable one below; `strict=True` raises instead.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from softcrawl.analytic.errors import ModelInputError
from softcrawl.paper import P_MAX_KPA

#: Standard gravity in mm/s^2 (the paper's eq. 27 example uses 10 m/s^2 = 10000 mm/s^2).
G_STANDARD = 9810.0


@dataclass(frozen=True)
class Line:
    """a P + b, P in kPa."""

    slope: float
    intercept: float

    def __call__(self, pressure_kpa: ArrayLike) -> np.ndarray:
        return self.slope * np.asarray(pressure_kpa, dtype=float) + self.intercept


@dataclass(frozen=True)
class PiecewiseLinear:
    """`low` for P <= breakpoint (kPa), `high` above; a single line if `high` is None."""

    low: Line
    high: Line | None = None
    breakpoint_kpa: float = 60.0

    def __call__(self, pressure_kpa: ArrayLike) -> np.ndarray:
        p = np.asarray(pressure_kpa, dtype=float)
        if self.high is None:
            return self.low(p)
        return np.where(p <= self.breakpoint_kpa, self.low(p), self.high(p))

    def branches(self) -> list[tuple[float, float, Line]]:
        """[(p_from, p_to, line)] in increasing pressure, over [0, inf)."""
        if self.high is None:
            return [(0.0, np.inf, self.low)]
        return [(0.0, self.breakpoint_kpa, self.low), (self.breakpoint_kpa, np.inf, self.high)]

    def jump(self) -> float:
        """high(bp) - low(bp): the discontinuity at the breakpoint (0 for a single line)."""
        if self.high is None:
            return 0.0
        return float(self.high(self.breakpoint_kpa) - self.low(self.breakpoint_kpa))

    def scaled(self, factor: float) -> PiecewiseLinear:
        def s(line: Line) -> Line:
            return None if line is None else Line(line.slope * factor, line.intercept * factor)

        return PiecewiseLinear(s(self.low), s(self.high), self.breakpoint_kpa)


@dataclass(frozen=True)
class EPSAParams:
    """One ePSA in internal units: k_p in N/mm, f_p in N, b_p in N s/mm, mass in tonne, l0 in mm."""

    k_p: PiecewiseLinear
    f_p: PiecewiseLinear
    b_p: PiecewiseLinear
    mass: float
    l0: float = 100.0
    name: str = "ePSA"

    # -- statics (eq. 3) ------------------------------------------------------------------------
    def extension(self, pressure_kpa: ArrayLike, g: float = G_STANDARD) -> np.ndarray:
        """y(P) = (f_p - m g)/k_p in mm, printed branch per pressure (no blending)."""
        p = _check_pressure(pressure_kpa)
        return (self.f_p(p) - self.mass * g) / self.k_p(p)

    def length(self, pressure_kpa: ArrayLike, g: float = G_STANDARD) -> np.ndarray:
        return self.l0 + self.extension(pressure_kpa, g)

    def blocked_force(self, pressure_kpa: ArrayLike, g: float = G_STANDARD) -> np.ndarray:
        """Output force held at the initial length (y = 0, the paper's Fig. 19): f_p - m g, N."""
        p = _check_pressure(pressure_kpa)
        return self.f_p(p) - self.mass * g

    def length_jump(self, g: float = 0.0) -> tuple[float, float, float]:
        """(length of the lower branch, of the upper branch, upper - lower) at the breakpoint, mm."""
        bp = self.k_p.breakpoint_kpa
        if self.f_p.breakpoint_kpa != bp:
            raise ModelInputError("breakpoint", "k_p and f_p breakpoints differ; no single jump")
        lo = self.l0 + (self.f_p.low(bp) - self.mass * g) / self.k_p.low(bp)
        hi_k = self.k_p.high or self.k_p.low
        hi_f = self.f_p.high or self.f_p.low
        hi = self.l0 + (hi_f(bp) - self.mass * g) / hi_k(bp)
        return float(lo), float(hi), float(hi - lo)

    def _segments(self) -> list[tuple[float, float, Line, Line]]:
        """Pressure intervals on which both k_p and f_p are single lines."""
        cuts = sorted(
            {0.0, np.inf}
            | {bp for bp in (self.k_p.breakpoint_kpa, self.f_p.breakpoint_kpa) if np.isfinite(bp)}
        )
        segs = []
        for a, b in zip(cuts[:-1], cuts[1:]):
            mid = a + 1.0 if not np.isfinite(b) else 0.5 * (a + b)
            kl = _line_at(self.k_p, mid)
            fl = _line_at(self.f_p, mid)
            segs.append((a, b, kl, fl))
        return segs

    def pressure_for_length(
        self, length_mm: float, g: float = 0.0, p_max: float = P_MAX_KPA, strict: bool = False
    ) -> float:
        """Inverse statics: the smallest pressure in [0, p_max] kPa whose length is `length_mm`.

        See the module docstring for the treatment of the 60 kPa jump. Lengths below l(0) or above
        the largest reachable length raise `ModelInputError('length')`.
        """
        y = float(length_mm) - self.l0
        mg = self.mass * g
        tol = 1e-9 * max(1.0, abs(y))
        best_gap = None
        reached_max = -np.inf  # largest extension reached by the branches below
        for a, b, kl, fl in self._segments():
            b = min(b, p_max)
            if a > p_max:
                break
            # Closed-form inverse on this branch.
            den = y * kl.slope - fl.slope
            ya = (fl(a) - mg) / kl(a)
            yb = (fl(b) - mg) / kl(b)
            lo_y, hi_y = min(ya, yb), max(ya, yb)
            if lo_y - tol <= y <= hi_y + tol:
                if abs(den) < 1e-300:
                    return float(a)
                p = (fl.intercept - mg - y * kl.intercept) / den
                return float(np.clip(p, a, b))
            if reached_max < y < lo_y:
                best_gap = a  # y lies in an upward jump just below this branch
                break
            reached_max = max(reached_max, hi_y)
        if best_gap is not None and not strict:
            return float(best_gap)
        lmin = float(self.length(0.0, g))
        lmax = float(np.max(self.length(np.linspace(0.0, p_max, 2001), g)))
        if best_gap is not None:
            raise ModelInputError("length", f"{length_mm:.4g} mm lies in the jump at {best_gap:g} kPa")
        raise ModelInputError(
            "length", f"{length_mm:.4g} mm is outside the reachable [{lmin:.4g}, {lmax:.4g}] mm"
        )

    def length_range(self, g: float = 0.0, p_max: float = P_MAX_KPA) -> tuple[float, float]:
        ps = np.linspace(0.0, p_max, 1001)
        ls = self.length(ps, g)
        return float(ls.min()), float(ls.max())


def _line_at(pw: PiecewiseLinear, p: float) -> Line:
    if pw.high is None or p <= pw.breakpoint_kpa:
        return pw.low
    return pw.high


def _check_pressure(pressure_kpa: ArrayLike) -> np.ndarray:
    p = np.asarray(pressure_kpa, dtype=float)
    if not np.all(np.isfinite(p)) or np.any(p < 0.0):
        raise ModelInputError("pressure", "pressures must be finite and >= 0 kPa")
    return p
