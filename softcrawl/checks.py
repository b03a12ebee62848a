"""The number check every package runs on its inputs: a real number, finite, within stated bounds.

`number` accepts Python and numpy integers and floats (never bools or strings), and compares
arbitrarily large integers exactly before converting them, so a 400-digit integer is an input
error naming its parameter, not an `OverflowError`. The bounds are closed unless marked open;
`integer=True` asks for a whole number (a float such as 3.0 is accepted and returned as 3).
Each package passes its own `InputError` subclass as `error`, so the error names the domain.

Bounds are the caller's named constants (docs/decisions/024-input-limits.md): a physical range, or a
cap where a larger value would exhaust memory or time.
"""

from __future__ import annotations

import math
import numbers

from softcrawl.errors import InputError


def _fmt(value) -> str:
    """An int in full (2**32 - 1 = 4294967295), a float in %g."""
    return str(value) if isinstance(value, int) else format(value, "g")


def _describe(minimum, maximum, min_open: bool, max_open: bool, unit: str) -> str:
    unit = f" {unit}" if unit else ""
    if minimum is not None and maximum is not None:
        lo, hi = "(" if min_open else "[", ")" if max_open else "]"
        return f"in {lo}{_fmt(minimum)}, {_fmt(maximum)}{hi}{unit}"
    if minimum is not None:
        return f"{'>' if min_open else '>='} {_fmt(minimum)}{unit}"
    if maximum is not None:
        return f"{'<' if max_open else '<='} {_fmt(maximum)}{unit}"
    return ""


def _outside(value, minimum, maximum, min_open: bool, max_open: bool) -> bool:
    """True if `value` (an exact int or a finite float) lies outside the bounds."""
    if minimum is not None and (value < minimum or (min_open and value == minimum)):
        return True
    return maximum is not None and (value > maximum or (max_open and value == maximum))


def number(
    value,
    parameter: str,
    *,
    minimum: float | None = None,
    maximum: float | None = None,
    min_open: bool = False,
    max_open: bool = False,
    integer: bool = False,
    unit: str = "",
    error: type[InputError] = InputError,
) -> float | int:
    """`value` as a float (an int with `integer=True`) if it is a finite number within the bounds;
    otherwise raise `error(parameter, ...)` that says what was expected and what was given."""
    bounds = _describe(minimum, maximum, min_open, max_open, unit)
    expected = ("an integer" if integer else "a finite number") + (f" {bounds}" if bounds else "")
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise error(parameter, f"must be {expected}, got {brief(value)}")
    if not isinstance(value, numbers.Integral):
        try:
            value = float(value)
        except (OverflowError, ValueError):  # e.g. a Fraction beyond the float range
            raise error(parameter, f"must be {expected}, got {brief(value)}") from None
        if not math.isfinite(value) or (integer and not value.is_integer()):
            raise error(parameter, f"must be {expected}, got {value!r}")
        if integer:
            value = int(value)
    else:
        value = int(value)  # exact comparisons, whatever its size
    if _outside(value, minimum, maximum, min_open, max_open):
        raise error(parameter, f"must be {expected}, got {brief(value)}")
    if integer:
        return value
    try:
        return float(value)
    except OverflowError:  # an integer beyond the float range, with no upper bound given
        raise error(
            parameter, f"must be {expected} within the float range (|x| < 1.8e308), got {brief(value)}"
        ) from None


def brief(value, width: int = 40) -> str:
    """repr of a value cut to `width` characters (a 401-digit integer stays one readable line)."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 100:
        return f"an integer of {len(str(abs(value))) if value.bit_length() < 10_000 else 'over 3000'} digits"
    text = repr(value)
    return text if len(text) <= width else f"{text[: width - 12]}... ({len(text)} characters)"
