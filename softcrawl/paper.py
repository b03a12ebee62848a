"""The paper's measured and printed constants, in one place, each with its source.

"Design and Modeling of a Parallel-Pipe-Crawling Pneumatic Soft Robot": its Table 1 (the design
parameters), Table 2 (the crawl speeds), the prototype's mass, diameters, force and friction
(Sections VI-B and VII), and the identified ePSA laws (eqs. 19-24). The models that use them
stay where they are (`softcrawl.analytic` for the equations, `softcrawl.studies` for the FE);
only the numbers live here, so a value is read from the paper once.

Units are the paper's where it prints them and the project's otherwise (each name says its unit):
lengths mm, forces N, speeds mm/s, pressures kPa (the paper's fits are per kPa), masses in g as
printed and in tonne as the models use them. Core layer: imports nothing of the project.
"""

from __future__ import annotations

# -- Table 1: the design parameters of the prototype --------------------------------------------
#: ePSA length l0, mm (Table 1; Section V-A: l0 = 100 mm in the FE model).
L0_MM = 100.0
#: ePSA outer radius R0, mm (Table 1; Section V-A: R = 9 mm in the FE model).
EPSA_RADIUS_MM = 9.0
#: Air chamber radius r0, mm (Table 1).
CHAMBER_RADIUS_MM = 3.0
#: Fiber winding turns N (Table 1).
FIBER_TURNS = 20
#: Foot groove height h, mm (Table 1).
GROOVE_HEIGHT_MM = 1.0
#: Foot radius d, the radius of the circle the three actuators sit on, mm (Table 1).
D_MM = 14.0
#: Connecting rings (Table 1).
N_RINGS = 3
#: Table 1 as printed: parameter key -> (label, value, unit).
TABLE1 = {
    "length": ("ePSA length l0", L0_MM, "mm"),
    "outer_radius": ("ePSA radius R0", EPSA_RADIUS_MM, "mm"),
    "chamber_radius": ("air chamber radius r0", CHAMBER_RADIUS_MM, "mm"),
    "fiber_turns": ("fiber winding turns N", float(FIBER_TURNS), ""),
    "groove_height": ("foot groove height h", GROOVE_HEIGHT_MM, "mm"),
    "foot_radius": ("foot radius d", D_MM, "mm"),
    "rings": ("connecting rings", float(N_RINGS), ""),
}

# -- The prototype (Sections VI-B, VII-A) --------------------------------------------------------
#: Robot mass, g (Section VII-A and eq. 27's example).
ROBOT_MASS_G = 70.2
#: Robot mass, tonne (the same 70.2 g in the models' unit; written out, not computed, so that the
#: value the statics have always used stays bit for bit).
ROBOT_MASS_T = 70.2e-6
#: Maximum diameter (the feet's skirt tips) and minimum diameter (the actuator bundle), mm
#: (Section VI-B).
MAX_DIAMETER_MM = 78.0
MIN_DIAMETER_MM = 46.0
#: The pipes the prototype was built for and tested in (Section VI-B, Table 2), mm.
PIPE_DIAMETERS_MM = (55.0, 60.0, 65.0, 70.0, 75.0)
#: Highest pressure of the prototype's identification and gaits (Section VII-A), kPa.
P_MAX_KPA = 100.0
#: Measured maximum ePSA output force, blocked at the initial length (Fig. 19), N.
F_EPSA_MAX_N = 8.42
#: Gravity of eq. 27's worked example, m/s^2 (the paper uses 10, not 9.81).
G_EQ27_M_S2 = 10.0
#: Eq. 27's theoretical load for F_EPSA_MAX_N, ROBOT_MASS_G and G_EQ27_M_S2, kg.
THEORETICAL_LOAD_KG = 2.456

# -- The identified ePSA laws (eqs. 19-24, Section VII-A) -----------------------------------------
#: Breakpoint between the low- and high-pressure lines of eqs. 19-24, kPa.
BREAKPOINT_KPA = 60.0
#: Printed k_p(P) of ePSA 1-3: (low slope, low intercept, high slope, high intercept), N/m per kPa
#: and N/m (eqs. 19, 21, 23).
PRINTED_K_N_PER_M = {
    1: (-2.579, 266.8, 0.9125, 62.19),
    2: (-2.013, 243.2, 1.236, 34.99),
    3: (-1.784, 229.9, 0.167, 119.2),
}
#: Printed f_p(P) of ePSA 1-3: (low slope, low intercept, high slope, high intercept), N per kPa
#: and N (eqs. 20, 22, 24).
PRINTED_F_N = {
    1: (0.03575, -0.06627, 0.1463, -6.534),
    2: (0.0446, -0.239, 0.168, -8.235),
    3: (0.04175, -0.2493, 0.1118, -4.002),
}

# -- The crawl (Section VII-D) ---------------------------------------------------------------------
#: Table 2: pipe diameter (mm) -> (forward, backward) crawl speed, mm/s, 100 kPa, 2 s cycles. The
#: text of Section VII-D gives 17.7 mm/s backward at 70 mm where the table gives 16.7.
TABLE2_MM_S = {
    55.0: (17.4, 15.9),
    60.0: (20.1, 18.2),
    65.0: (19.5, 17.7),
    70.0: (18.3, 16.7),
    75.0: (17.6, 16.2),
}
#: Vertical crawl (Section VII-D-2, Fig. 23; pipe diameter and gait not stated, "a fixed gait"):
#: upward and downward speeds, mm/s.
VERTICAL_MM_S = {"up": 12.9, "down": 19.1}
#: Sliding friction in the 70 mm pipe, from the extensions outside and inside the pipe (eq. 26,
#: Section VII-D), N: the resistance of the one foot that slides (docs/decisions/062-crawl-reconciliation.md).
FRICTION_N = {"forward": 15.3, "backward": 16.9}


def table2(diameter: float, direction: str) -> float | None:
    """Table 2's speed (mm/s) in the pipe of `diameter` mm, "forward" or "backward"; None for a
    diameter the paper did not test."""
    row = TABLE2_MM_S.get(round(float(diameter), 6))
    return None if row is None else row[0 if direction == "forward" else 1]


# -- Foot selection (Section VII-C, Fig. 21) -------------------------------------------------------
#: Fig. 21's test: horizontal crawl in the 70 mm pipe, 2 s cycles, feet of several hardnesses and
#: angles. The figure's curves are not printed; its two statements are, and are checked as stated
#: (`studies.crawl.feet_statements`). Held out: no identification reads them.
FIG21_PIPE_MM = 70.0
FIG21_CYCLE_S = 2.0
#: "A desired crawling speed, that is, greater than 10 mm/s, can be obtained using material
#: hardness between 50A and 70A (shore) and foot angle between 30 and 120 deg."
FIG21_MIN_SPEED_MM_S = 10.0
FIG21_HARDNESS_SHORE_A = (50.0, 70.0)
FIG21_ANGLE_DEG = (30.0, 120.0)
#: "With 70A hardness, the crawling speed of the robot increases with the increase in the foot angle."
FIG21_RISING_SHORE_A = 70.0
