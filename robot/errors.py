"""Input errors of the `robot` package.

Every bad user input (negative pressure, unknown actuator, a tip the arc cannot reach, a pipe the
body does not fit in) raises `ModelInputError`, a `ValueError` that names the offending parameter in
its `parameter` attribute. The CLI turns it into one line on stderr and exit code 2.
"""
from __future__ import annotations


class ModelInputError(ValueError):
    """A `ValueError` that names the user parameter at fault."""

    def __init__(self, parameter: str, message: str) -> None:
        super().__init__(f"{parameter}: {message}")
        self.parameter = parameter
