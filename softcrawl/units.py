"""Pressure units at the edges: kPa outside, MPa inside.

The rule: pressures enter in kPa at the CLI and in spec values, are converted once, here. Inside
the models the units are mm, N, MPa, s and tonne, so an FE pressure is in MPa (N/mm^2); what
people read (CLI options, spec and settings values, tables, messages, VTU fields named
``pressure_kPa``) is in kPa. The analytic models of the paper (`softcrawl.analytic`) keep kPa
throughout: the paper's fits (eqs. 19-24) are printed per kPa, so they need no conversion.

Both functions work on floats and on numpy arrays (element-wise). The arithmetic is fixed, so that
every committed result keeps its printed digits: kPa -> MPa is ``value / 1e3`` (exact round trip
``mpa_to_kpa(kpa_to_mpa(p)) == p`` for every whole kPa up to 1000, so a 36 kPa target is reported
as 36.0, not 36.00000000000001) and MPa -> kPa is ``value * 1e3``. A bare ``1e-3`` or ``1e3`` on a
pressure anywhere else fails tests/test_architecture.py.
"""

from __future__ import annotations

from typing import TypeVar

T = TypeVar("T")


def kpa_to_mpa(value: T) -> T:
    """A pressure in kPa (float or numpy array) in MPa, the unit of the FE models."""
    return value / 1e3


def mpa_to_kpa(value: T) -> T:
    """A pressure in MPa (float or numpy array) in kPa, the unit people read and type."""
    return value * 1e3
