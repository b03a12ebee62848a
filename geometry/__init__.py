"""Parametric designs, watertight surfaces, fibers and tagged tetrahedral meshes of the robot."""
