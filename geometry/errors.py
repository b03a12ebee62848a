"""Input errors of the `geometry` package.

`DesignError` is an `softcrawl.errors.InputError`: its ``parameter`` is the design field (dotted for
nested designs, e.g. ``foot.hub_radius``), and the CLI prints it as one line with exit code 2.
"""

from __future__ import annotations

from softcrawl.errors import InputError


class DesignError(InputError):
    """An invalid design parameter. ``parameter`` names the offending field."""
