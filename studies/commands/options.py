"""Options shared by several commands, parsed once: pressure lists in kPa."""

from __future__ import annotations

import numpy as np

from geometry.design import DesignError


def parse_pressures(spec: str) -> tuple[float, ...]:
    """'0:100:20' -> (20, 40, 60, 80, 100) (kPa; the 0 kPa reference row is always written);
    '10,30,50' -> (10, 30, 50)."""
    try:
        if ":" in spec:
            a, b, s = (float(v) for v in spec.split(":"))
            if s <= 0 or b <= a:
                raise ValueError
            values = np.arange(a, b + 1e-9 * s, s)
        else:
            values = np.array([float(v) for v in spec.split(",")])
    except ValueError:
        raise DesignError("pressures", f"{spec!r} is not START:STOP:STEP or a comma list (kPa)") from None
    values = values[values > 0]
    if values.size == 0 or np.any(np.diff(values) <= 0) or values.max() > 1000:
        raise DesignError("pressures", f"{spec!r}: give increasing pressures in (0, 1000] kPa")
    return tuple(float(v) for v in values)
