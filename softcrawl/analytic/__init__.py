"""The paper's analytic models: ePSA statics/dynamics, constant-curvature kinematics, planning.
Stands alone: imports neither `fem`, `geometry`, `materials` nor `studies` (its plots are drawn in
`studies.plots.analytic`).

Modules (one job each; units mm, N, s, tonne inside, pressures of the identified laws in kPa):

- `statics`         statics of one ePSA, eq. (3), piecewise-linear k_p, f_p, b_p (eq. 2), the 60 kPa
                    jump, inverse statics (length -> pressure)
- `prototype`       the identified parameters of the three prototype ePSAs (eqs. 19-24), units
                    boundary N/m -> N/mm, mass / damping decisions, robot constants
- `dynamics`        eq. (1) with scipy for a pressure step or gait
- `loads`           friction (eqs. 25-26), theoretical load (eq. 27), stride and crawling speed
- `identification`  Section VII-A: per-pressure least squares, then piecewise-linear fit in P
- `kinematics`      FK eqs. (4)-(6), (9); exact IK (the printed (11), (13)-(15) do not invert FK)
- `workspace`       tip cloud over 0-100 kPa (Fig. 11(d))
- `pipe`            straight / vertical / elbow centrelines, distance and arc length
- `cycle`           the crawling cycle's geometry (Section IV, eqs. 16-18) and the pipe-fit check,
                    shared by the three planners below
- `gait`            a planned gait (`Plan`, `Cycle`) and `replay`, which checks a given gait
- `planner`         beam search of a gait through a pipe on the pressure grid
- `planar`          exhaustive breadth-first elbow search on the pressure grid (bend plane)
- `refine`          elbow gaits with continuous pressures (SLSQP maximises the wall clearance)
- `errors`          `ModelInputError`, the input error of this package
"""
