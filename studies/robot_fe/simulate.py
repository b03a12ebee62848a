"""The robot from its design to its response, in one call: `simulate_robot` (the public API's).

    RobotDesign + material + chamber pressures in kPa -> `model.build_robot_model` ->
    `response.simulate_robot` (the path, pressures in MPa) -> `RobotRun`

What `softcrawl robot` does from its options, without the printing and the files: the pressure
path goes from zero to `pressures_kpa` in `steps` proportional steps, or first to `first_kpa` and
then to `pressures_kpa` (a sequential path; first 0,40,60 then 100,40,60 kPa is the paper's Fig. 11
load case). `quick=True` takes the quick mesh preset (`geometry.robot_mesh.MESH_PRESETS`).
"""

from __future__ import annotations

import math

from softcrawl.geometry.design import DesignError, RobotDesign
from softcrawl.studies.robot_fe.model import DEFAULT_MATERIAL, build_robot_model
from softcrawl.studies.robot_fe.response import RobotRun
from softcrawl.studies.robot_fe.response import simulate_robot as follow_path
from softcrawl.units import kpa_to_mpa

#: Highest chamber pressure accepted (kPa), as on the command line.
MAX_PRESSURE_KPA = 1000.0
MAX_STEPS = 1000


def _triple(values, parameter: str) -> tuple[float, float, float]:
    try:
        out = tuple(float(v) for v in values)
    except (TypeError, ValueError):
        raise DesignError(parameter, f"{values!r} is not three pressures in kPa") from None
    if len(out) != 3 or not all(math.isfinite(v) and 0.0 <= v <= MAX_PRESSURE_KPA for v in out):
        raise DesignError(parameter, f"{values!r}: give three pressures in [0, {MAX_PRESSURE_KPA:g}] kPa")
    return out


def pressure_targets(pressures_kpa, first_kpa=None, steps: int = 5) -> list[tuple[float, float, float]]:
    """The proportional sub-targets (kPa) of the path 0 -> [first_kpa ->] pressures_kpa."""
    if isinstance(steps, bool) or not isinstance(steps, int) or not 1 <= steps <= MAX_STEPS:
        raise DesignError("steps", f"must be an integer in [1, {MAX_STEPS}], got {steps!r}")
    ends = ([_triple(first_kpa, "first_kpa")] if first_kpa is not None else []) + [
        _triple(pressures_kpa, "pressures_kpa")
    ]
    out, start = [], (0.0, 0.0, 0.0)
    for end in ends:
        out += [tuple(a + (b - a) * k / steps for a, b in zip(start, end)) for k in range(1, steps + 1)]
        start = end
    return out


def simulate_robot(
    design: RobotDesign | None = None,
    pressures_kpa=(40.0, 0.0, 0.0),
    *,
    first_kpa=None,
    steps: int = 5,
    material=DEFAULT_MATERIAL,
    mesh: str = "default",
    quick: bool = False,
    gravity: bool = False,
) -> RobotRun:
    """The robot (Table 1 by default) under chamber pressures P1, P2, P3 in kPa -> `RobotRun`
    (one `RobotState` per converged step; a path that stops early is a result, not an error).
    `material`: the ePSA silicone, a preset name (`material_names()`) or a `Material`."""
    targets = pressure_targets(pressures_kpa, first_kpa, steps)
    robot = build_robot_model(
        design or RobotDesign(),
        material,
        "quick" if quick else mesh,
        gravity=(0.0, -1.0, 0.0) if gravity else None,
    )
    return follow_path(robot, [tuple(kpa_to_mpa(p) for p in P) for P in targets], gravity=gravity)
