"""The paper's prototype: identified ePSA parameters (eqs. 19-24) and robot constants.

The printed numbers (eqs. 19-24, Table 1, the 70.2 g mass) live in `softcrawl.paper`; this module
turns them into the models' `EPSAParams` and adds what the paper does not give (mass split,
damping, the nominal actuator).

This module is the units boundary. The paper prints eqs. (19)-(24) with P in kPa, k_p in N/m,
f_p in N and the extension y in m (docs/decisions/007-analytic-models.md). Inside `robot` lengths are mm, so
every
k_p coefficient printed here in N/m is divided by 1000 (N/mm); f_p stays in N. Masses are in tonne
(1 g = 1e-6 t), g in mm/s^2.

Printed values (N/m and N, P in kPa, lower line for P <= 60 kPa):

    ePSA  k_p low            k_p high           f_p low              f_p high
    1     -2.579 P + 266.8   0.9125 P + 62.19   0.03575 P - 0.06627  0.1463 P - 6.534
    2     -2.013 P + 243.2   1.236 P + 34.99    0.0446 P - 0.239     0.168 P - 8.235
    3     -1.784 P + 229.9   0.167 P + 119.2    0.04175 P - 0.2493   0.1118 P - 4.002

Consequences worth knowing (g = 0): at P = 0 the fits give small negative extensions
(f_0/k_0 = -0.25, -0.98, -1.08 mm): the actuator "starts" only above about 2-6 kPa; we keep the
printed law and do not clamp. At 60 kPa the branches do not meet: the length jumps by
+0.64 mm (ePSA 1), -3.00 mm (ePSA 2) and +2.58 mm (ePSA 3); see `analytic.statics` for how the jump is
handled.

Decisions (not given in the paper):

* ePSA mass m = 70.2 g / 3 = 23.4 g. The paper gives only the robot mass (70.2 g). The Table 1
  geometry (annulus R = 9 mm, r = 3 mm, 100 mm long) at the Ecoflex 00-50 density 1.07 g/cm^3 gives
  24.2 g, which would make three ePSAs heavier than the whole robot; so we take the largest value
  consistent with 70.2 g. m g = 0.23 N shortens an actuator by about 2 mm at 60 kPa; the
  identification rig stands the actuator vertically, so eq. (3) keeps m g with g along the axis.
* Damping b_p = 0.05 N s/mm (50 N s/m), independent of P (b_1 = 0). The paper identifies no damping;
  with k_p ~ 0.12 N/mm the time constant b_p/k_p ~ 0.4 s lets an actuator settle within the 1.5 s
  inflation phase of the paper's gait 1. It only affects `analytic.dynamics`.
* The "nominal" actuator (used by the planner by default) averages the three prototypes'
  coefficients, so that equal lengths mean equal pressures.
"""

from __future__ import annotations

from collections.abc import Sequence

from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.statics import EPSAParams, Line, PiecewiseLinear
from softcrawl.body import BODY
from softcrawl.paper import (
    BREAKPOINT_KPA,
    L0_MM,
    PRINTED_F_N,
    PRINTED_K_N_PER_M,
    ROBOT_MASS_T,
)

#: ePSA mass, tonne (see module docstring).
EPSA_MASS_T = ROBOT_MASS_T / 3.0
#: Body radius for pipe clearance: the prototype's actuator envelope d + R0 = 23 mm, half its 46 mm
#: minimum diameter (`softcrawl.body`: the body geometry the FE foot and robot share).
BODY_RADIUS_MM = BODY.clearance_radius
#: Damping, N s/mm (assumed, see module docstring).
B_P_N_S_PER_MM = 0.05


def _pw(c: Sequence[float], factor: float = 1.0) -> PiecewiseLinear:
    return PiecewiseLinear(
        Line(c[0] * factor, c[1] * factor), Line(c[2] * factor, c[3] * factor), BREAKPOINT_KPA
    )


def prototype_epsa(index: int) -> EPSAParams:
    """ePSA 1, 2 or 3 of the paper (eqs. 19-24), in internal units."""
    if index not in PRINTED_K_N_PER_M:
        raise ModelInputError("actuator", f"must be 1, 2 or 3, got {index!r}")
    return EPSAParams(
        k_p=_pw(PRINTED_K_N_PER_M[index], 1e-3),  # N/m -> N/mm
        f_p=_pw(PRINTED_F_N[index]),
        b_p=PiecewiseLinear(Line(0.0, B_P_N_S_PER_MM)),
        mass=EPSA_MASS_T,
        l0=L0_MM,
        name=f"ePSA{index}",
    )


def nominal_epsa() -> EPSAParams:
    """The coefficient-wise mean of the three prototypes (a single, 'typical' actuator)."""
    k = [sum(PRINTED_K_N_PER_M[i][j] for i in (1, 2, 3)) / 3.0 for j in range(4)]
    f = [sum(PRINTED_F_N[i][j] for i in (1, 2, 3)) / 3.0 for j in range(4)]
    return EPSAParams(
        k_p=_pw(k, 1e-3),
        f_p=_pw(f),
        b_p=PiecewiseLinear(Line(0.0, B_P_N_S_PER_MM)),
        mass=EPSA_MASS_T,
        l0=L0_MM,
        name="nominal",
    )


def actuator_set(kind: str = "nominal") -> tuple[EPSAParams, EPSAParams, EPSAParams]:
    """'nominal': three identical mean actuators; 'prototype': ePSA 1, 2, 3 as identified."""
    if kind == "nominal":
        a = nominal_epsa()
        return (a, a, a)
    if kind == "prototype":
        return (prototype_epsa(1), prototype_epsa(2), prototype_epsa(3))
    raise ModelInputError("actuators", f"must be 'nominal' or 'prototype', got {kind!r}")
