r"""The anchoring margin of a foot design (paper Fig. 4) and its mass: the objectives of
`softcrawl study optimise-feet` (`studies.foot.optimise`), pure functions, no FE.

The crawl cycle (Fig. 4, record 062). Inflated (100 kPa), the bundle pushes the feet apart: the
rear foot holds against being pushed back (its backward resistance F_bwd), the front foot slides
forward (its forward resistance F_fwd). Deflated (0 kPa), the stretched bundle pulls them
together: the front foot holds (F_bwd), the rear foot slides forward (F_fwd). Both feet are the
same design in the same pipe, so one foot's F_fwd and F_bwd (one insertion and two drags,
`studies.foot.model.run_foot`) decide both phases.

The actuators' forces, from the prototype's statics (eqs. 19-24, the nominal ePSA with f_p(0)
removed, record 062's table; three actuators in parallel):

    F_ext   = 3 (f_p(100) - f_p(0))                      = 24.39 N   the bundle's blocked force at 100 kPa
    K, K0   = 3 k_p(100), 3 k_p(0)                       = 0.4479, 0.7399 N/mm
    F_slide = (F_ext / K) / (1 / K + 1 / K0)             = 15.19 N

F_slide is the return force at 0 kPa over the stroke the extension leaves: a sliding foot of
resistance F lets the extension reach Delta = (F_ext - F) / K, and the deflated bundle then pulls
K0 Delta, which exceeds F only while F < F_slide; it is the zero of record 062's stride law
S(F) = 54.46 - 3.584 F mm. So F_slide is the largest resistance a sliding foot may have for the
cycle to advance (the extension alone would allow F_ext). The anchoring foot must hold the
largest force the bundle puts on it while the cycle works: the extension's blocked force F_ext
(reached whenever the sliding foot sticks); the retraction's pull is capped by the sliding foot's
F_fwd < F_slide < F_ext. Hence, per pipe D, the two inequalities of Fig. 4 as normalised
differences (> 0: satisfied):

    hold(D)  = (F_bwd(D) - F_ext) / F_ext
    slide(D) = (F_slide - F_fwd(D)) / F_slide
    margin   = min over D of min(hold(D), slide(D))

The margin is a continuous function of the forces, graded (a design that misses by 1 N scores
above one that misses by 10 N), Lipschitz with constant 1 / F_slide, and piecewise linear: its
gradient flips where the deciding pipe or inequality changes (`anchoring_margin` says which).

The mass: the exact volume of the revolved section (Pappus, `geometry.foot.foot_volume`; the
study's meshes are its chordal approximation, 1.1 % smaller at 24 sectors) times the material's
density (`softcrawl.materials`: 1.15 g/cm^3 for the printed rubbers, the same for every hardness).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from softcrawl.analytic.prototype import nominal_epsa
from softcrawl.errors import InputError
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.foot import foot_volume
from softcrawl.materials import Material

#: The crawl's pressures (kPa): inflated and deflated (paper Section VII-D: 0-100 kPa).
INFLATED_KPA, DEFLATED_KPA = 100.0, 0.0
#: The bundle: three actuators in parallel (Table 1).
N_ACTUATORS = 3
#: Grams per tonne (the mass is reported in g).
G_PER_TONNE = 1.0e6


class MarginError(InputError):
    """A force that cannot enter the margin (negative, not finite, no pipe); names the parameter."""


@dataclass(frozen=True)
class ActuatorForces:
    """The bundle's forces of the module docstring (N, N/mm)."""

    extension_n: float  # F_ext: blocked force at 100 kPa, f_p(0) removed
    stiffness_inflated: float  # K = 3 k_p(100), N/mm
    stiffness_deflated: float  # K0 = 3 k_p(0), N/mm (extrapolated: the paper identified 10-100 kPa)

    @property
    def hold_n(self) -> float:
        """What the anchoring foot must hold: F_ext."""
        return self.extension_n

    @property
    def slide_n(self) -> float:
        """F_slide: the largest sliding resistance the cycle overcomes (the stride law's zero)."""
        k, k0 = self.stiffness_inflated, self.stiffness_deflated
        return (self.extension_n / k) / (1.0 / k + 1.0 / k0)


def prototype_forces() -> ActuatorForces:
    """The paper's bundle (eqs. 19-24, the nominal ePSA, f_p(0) removed; record 062)."""
    a = nominal_epsa()
    f = N_ACTUATORS * float(a.f_p(INFLATED_KPA) - a.f_p(DEFLATED_KPA))
    return ActuatorForces(
        f, N_ACTUATORS * float(a.k_p(INFLATED_KPA)), N_ACTUATORS * float(a.k_p(DEFLATED_KPA))
    )


@dataclass(frozen=True)
class Margin:
    """The design's margin and what decides it: the pipe and the inequality ("hold" or "slide")."""

    value: float
    pipe_diameter: float
    inequality: str
    per_pipe: Mapping[float, tuple[float, float]]  # D -> (hold, slide)


def _force(value: float, name: str) -> float:
    if (
        isinstance(value, bool)
        or not isinstance(value, (int, float))
        or not math.isfinite(value)
        or value < 0
    ):
        raise MarginError(name, f"must be a finite force >= 0 N, got {value!r}")
    return float(value)


def pipe_margins(f_fwd: float, f_bwd: float, forces: ActuatorForces) -> tuple[float, float]:
    """(hold, slide) of one pipe: (F_bwd - F_ext) / F_ext and (F_slide - F_fwd) / F_slide."""
    f_fwd, f_bwd = _force(f_fwd, "f_fwd"), _force(f_bwd, "f_bwd")
    return (f_bwd - forces.hold_n) / forces.hold_n, (forces.slide_n - f_fwd) / forces.slide_n


def anchoring_margin(per_pipe: Mapping[float, tuple[float, float]], forces: ActuatorForces) -> Margin:
    """The worst-case margin over the pipes, `per_pipe`: D -> (F_fwd, F_bwd) in N."""
    if not per_pipe:
        raise MarginError("pipes", "the margin needs at least one pipe")
    margins = {float(d): pipe_margins(fwd, bwd, forces) for d, (fwd, bwd) in per_pipe.items()}
    value, d, which = min((m, d, name) for d, ms in margins.items() for name, m in zip(("hold", "slide"), ms))
    return Margin(value, d, which, margins)


def foot_mass_g(design: FootDesign, material: Material) -> float:
    """The foot's mass (g): its exact revolved volume (mm^3) x the material's density (t/mm^3)."""
    return foot_volume(design) * material.density * G_PER_TONNE
