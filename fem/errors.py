"""Errors the solver raises for bad input, and the record of a failed solve.

`SolverInputError` is a `ValueError` that names the offending parameter (the CLI turns it into a
one-line message with exit code 2). Divergence is *not* an exception: path-following returns a
result whose `converged` flag is False and whose `message` names the last converged load.
"""
from __future__ import annotations


class SolverInputError(ValueError):
    """Unphysical material, impossible boundary condition, unknown tag: names `parameter`."""

    def __init__(self, parameter: str, message: str):
        super().__init__(f"{parameter}: {message}")
        self.parameter = parameter
