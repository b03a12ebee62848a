"""The one error type for bad input, shared by every package.

`InputError` is a `ValueError` that names the offending parameter (`parameter`, dotted for nested
designs such as ``foot.hub_radius``) and keeps the bare explanation (`detail`). The command line
turns it into one line on stderr and exit code 2 (`studies.cli`). Each package derives a subclass
with no behaviour of its own (`DesignError`, `SolverInputError`, `MaterialError`,
`ModelInputError`, `StudyError`), so that callers may catch one domain; the mechanism is defined
once, here.

A failed computation is not an input error: a diverged solve is a result that records the last
converged load (`fem.path`), and a failed sweep point is a trial that records its reason.
"""

from __future__ import annotations


class InputError(ValueError):
    """Bad input: `parameter` names it, `detail` says what is wrong with it."""

    def __init__(self, parameter: str, message: str) -> None:
        super().__init__(f"{parameter}: {message}")
        self.parameter = parameter
        self.detail = message

    def renamed(self, parameter: str) -> InputError:
        """The same error (same class and detail) under another parameter name, e.g. with the
        prefix of the part it belongs to."""
        return type(self)(parameter, self.detail)
