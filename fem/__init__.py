"""Large-strain finite elements on scikit-fem: Neo-Hookean solids, follower chamber pressure,
embedded fibers and path following. `fem` never imports pyvista, optuna or `studies`."""
