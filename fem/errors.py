"""Errors the solver raises for bad input.

`SolverInputError` (an `softcrawl.errors.InputError`) names the offending parameter. Divergence is
*not* an exception: path-following returns a result whose `converged` flag is False and whose
`message` names the last converged load.
"""

from __future__ import annotations

from softcrawl.errors import InputError


class SolverInputError(InputError):
    """Unphysical material, impossible boundary condition, unknown tag."""
