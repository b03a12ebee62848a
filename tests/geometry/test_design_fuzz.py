"""Fuzz of every design class: whatever the field values (huge integers, subnormals, NaN, inf,
strings, None), construction either succeeds with finite, in-range fields or raises `DesignError`
naming a field of the design; never another exception."""

import dataclasses
import math
import typing

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from softcrawl.geometry.design import (
    MAX_DIMENSION,
    DesignError,
    EPSADesign,
    FootDesign,
    RingDesign,
    RobotDesign,
)

CLASSES = (EPSADesign, FootDesign, RingDesign, RobotDesign)

#: Values that broke validation before: huge and negative integers (OverflowError), subnormal and
#: extreme floats (ZeroDivisionError, infinite helix lengths), NaN and inf, wrong types.
NASTY = st.one_of(
    st.integers(min_value=-(10**400), max_value=10**400),
    st.sampled_from(
        [
            0,
            1,
            -1,
            10**20,
            10**308,
            10**400,
            2**1023,
            5e-324,
            -5e-324,
            2.2e-308,
            1e-300,
            1e308,
            1.7976931348623157e308,
            -1e308,
            math.inf,
            -math.inf,
            math.nan,
            0.0,
            -0.0,
            True,
            None,
            "3",
            [],
            3 + 0j,
        ]
    ),
    st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True),
    st.floats(min_value=0.0, max_value=200.0),
)


def _scalar_fields(cls):
    hints = typing.get_type_hints(cls)
    return [f.name for f in dataclasses.fields(cls) if hints[f.name] in (int, float)]


def _field_names(cls) -> set[str]:
    names = set()
    for f in dataclasses.fields(cls):
        names.add(f.name)
    for part, sub in getattr(cls, "_nested", {}).items():
        names |= {f"{part}.{f.name}" for f in dataclasses.fields(sub)}
    return names


@st.composite
def design_kwargs(draw):
    cls = draw(st.sampled_from(CLASSES))
    names = _scalar_fields(cls)
    chosen = draw(st.lists(st.sampled_from(names), min_size=1, max_size=len(names), unique=True))
    kwargs = {name: draw(NASTY) for name in chosen}
    if cls is RobotDesign and draw(st.booleans()):
        part = draw(st.sampled_from(["epsa", "foot", "ring"]))
        sub = RobotDesign._nested[part]
        field = draw(st.sampled_from(_scalar_fields(sub)))
        kwargs[part] = {field: draw(NASTY)}
    return cls, kwargs


def _build(cls, kwargs):
    """Nested parts given as dicts go through `from_dict`, as a design file would."""
    if any(isinstance(v, dict) for v in kwargs.values()):
        return cls.from_dict(kwargs)
    return cls(**kwargs)


@settings(max_examples=600, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(design_kwargs())
def test_any_field_values_give_a_valid_design_or_a_named_design_error(case):
    cls, kwargs = case
    try:
        design = _build(cls, kwargs)
    except DesignError as exc:
        assert exc.parameter.split(".")[-1] in {n.split(".")[-1] for n in _field_names(cls)}, exc
        assert "\n" not in str(exc) and len(str(exc)) < 400
        return
    flat = design.to_dict()
    for value in _leaves(flat):
        if isinstance(value, (int, float)):
            assert math.isfinite(value) and abs(value) <= MAX_DIMENSION * 10, flat
    if isinstance(design, EPSADesign):
        assert math.isfinite(design.helix_length) and math.isfinite(design.body_volume)


def _leaves(d):
    for v in d.values():
        if isinstance(v, dict):
            yield from _leaves(v)
        else:
            yield v
