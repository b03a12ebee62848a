"""Input limits of the analytic models, each with its reason (docs/decisions/024-input-limits.md).

The models are closed forms and small searches, so the limits are of two kinds: physical ranges
(a length, a force, a gravity) wide enough for any robot of this kind and narrow enough that a
unit mistake (m for mm, Pa for kPa) or a typo (1e12) is caught before it turns into overflow or a
silent wrong number; and caps on the sizes of the searches, whose cost grows as a power of them.
`check` applies one of them and raises `ModelInputError` naming the parameter.
"""

from __future__ import annotations

from softcrawl.analytic.errors import ModelInputError
from softcrawl.checks import number

#: Lengths, radii, diameters and positions (mm): 10 m. The robot is 100-300 mm long and crawls in
#: 55-75 mm pipes; a pipe or an arc a hundred times larger is still accepted.
MAX_LENGTH_MM = 1.0e4
#: Pressures of the identified laws (kPa): 1 MPa, ten times the identified 0-100 kPa range. A
#: silicone ePSA bursts far below it; the laws are only extrapolated above 100 kPa (with a warning).
MAX_PRESSURE_KPA = 1000.0
#: Forces (N): 10 kN, a thousand times the ePSA's ~8 N output force.
MAX_FORCE_N = 1.0e4
#: Masses (g): one tonne; the robot weighs 70 g and one ePSA 23 g.
MAX_MASS_G = 1.0e6
#: Gravity along the axis (m/s^2): ten times Earth's. The models are static or slow; g only sets
#: the weight term.
MAX_G = 100.0
#: Times (s): cycle times of the gait; 1e4 s is almost three hours per cycle.
MAX_TIME_S = 1.0e4
#: Speeds (mm/s): 10 m/s, 500 times the prototype's 18.3 mm/s.
MAX_SPEED_MM_S = 1.0e4
#: Pressure levels per actuator of the workspace cloud: n^3 tips. 51 levels (2 kPa steps) give
#: 132,651 tips, far denser than a plot resolves; the CSV grows as n^3 (n = 101: ~120 MB).
MAX_WORKSPACE_LEVELS = 51
#: Finest pressure grid of the gait searches (kPa). The grid has (100 / step + 1)^3 triples (the
#: planar elbow search: squared), each expanded from every beam state: at 1 kPa and beam 1 a
#: straight pipe took 132 s for 3 cycles (loaded 2-core machine); finer grids grow as step^-3.
MIN_PLAN_STEP_KPA = 1.0
#: Widest beam of the gait search: the cost of a cycle grows with the beam (64 x the 5 kPa grid is
#: ~6 s per elbow cycle); wider beams did not pass more elbows in the paper's range.
MAX_BEAM = 64
#: Largest number of candidate pressure triples examined per cycle, beam x grid size: 1.1e6 is
#: the 1 kPa full grid at beam 1, ~45 s per cycle; beyond it a plan takes hours.
MAX_CANDIDATES_PER_CYCLE = 1_100_000
#: Most cycles of the continuous (SLSQP) elbow search: its unknowns are 2 per cycle and SLSQP's
#: cost grows with their cube; the paper's elbows need 10-25 cycles.
MAX_CONTINUOUS_CYCLES = 100
#: Most bend radii of one elbow scan (each is a full plan).
MAX_SCAN_RADII = 50


def check(value: object, parameter: str, **bounds: float | bool | str | None) -> float | int:
    """`softcrawl.checks.number` raising `ModelInputError`."""
    return number(value, parameter, error=ModelInputError, **bounds)


def length_mm(value: object, parameter: str, *, positive: bool = True) -> float:
    """A finite length in (0, MAX_LENGTH_MM] mm ([-MAX, MAX] for a coordinate)."""
    if positive:
        return check(value, parameter, minimum=0.0, min_open=True, maximum=MAX_LENGTH_MM, unit="mm")
    return check(value, parameter, minimum=-MAX_LENGTH_MM, maximum=MAX_LENGTH_MM, unit="mm")
