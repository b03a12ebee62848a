"""Input errors of the `robot` package.

Every bad user input (negative pressure, unknown actuator, a tip the arc cannot reach, a pipe the
body does not fit in) raises `ModelInputError`, an `softcrawl.errors.InputError` that names the
offending parameter. The CLI turns it into one line on stderr and exit code 2.
"""

from __future__ import annotations

from softcrawl.errors import InputError


class ModelInputError(InputError):
    """Bad input to an analytic model."""
