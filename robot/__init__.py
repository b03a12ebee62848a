"""The paper's analytic models: ePSA statics/dynamics, constant-curvature kinematics, planning.
Stands alone: imports neither `fem`, `geometry` nor `studies`."""
