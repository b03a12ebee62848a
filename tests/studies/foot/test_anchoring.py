"""The objectives of optimise-feet (`studies.foot.anchoring`): the bundle's forces against record
062's closed forms, the margin at its flips (each inequality alone decides), the mass against a
closed-form volume, bad input."""

from __future__ import annotations

import math

import pytest

from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.foot_meshers import mesh_foot_with
from softcrawl.materials import get_material
from softcrawl.studies.foot.anchoring import (
    ActuatorForces,
    MarginError,
    anchoring_margin,
    foot_mass_g,
    pipe_margins,
    prototype_forces,
)

#: Round numbers, so that every margin below is exact by hand: F_ext = 20 N, K = K0 = 1 N/mm, so
#: F_slide = (20 / 1) / (1 + 1) = 10 N.
FORCES = ActuatorForces(extension_n=20.0, stiffness_inflated=1.0, stiffness_deflated=1.0)


def test_the_bundle_is_record_062s():
    f = prototype_forces()
    assert f.hold_n == pytest.approx(24.39, abs=0.005)  # 3 (f_p(100) - f_p(0))
    assert f.stiffness_inflated == pytest.approx(0.4479, abs=5e-5)
    assert f.stiffness_deflated == pytest.approx(0.7399, abs=5e-5)
    # F_slide is the zero of record 062's stride law S(F) = 54.46 - 3.584 F mm
    assert f.slide_n == pytest.approx(54.46 / 3.584, rel=2e-4)
    stride = f.hold_n / f.stiffness_inflated - f.slide_n * (
        1 / f.stiffness_inflated + 1 / f.stiffness_deflated
    )
    assert stride == pytest.approx(0.0, abs=1e-9)


def test_each_inequality_alone_decides_at_its_flip():
    assert FORCES.slide_n == 10.0
    # a foot that holds 30 N and slides at 5 N: hold (30 - 20) / 20 = 0.5, slide (10 - 5) / 10 = 0.5
    assert pipe_margins(5.0, 30.0, FORCES) == (0.5, 0.5)
    # the hold decides when the backward resistance falls below the flip, whatever F_fwd is
    m = anchoring_margin({70.0: (5.0, 26.0)}, FORCES)
    assert (m.value, m.inequality) == (pytest.approx(0.3), "hold")
    # the slide decides when the forward resistance rises past it
    m = anchoring_margin({70.0: (8.0, 30.0)}, FORCES)
    assert (m.value, m.inequality) == (pytest.approx(0.2), "slide")
    # a sign change of each alone: the foot that cannot hold the bundle, and the one it cannot drag
    assert anchoring_margin({70.0: (5.0, 19.0)}, FORCES).value == pytest.approx(-0.05)
    assert anchoring_margin({70.0: (11.0, 30.0)}, FORCES).value == pytest.approx(-0.1)
    # continuous across the flip (the two are equal at F_fwd = 5, F_bwd = 30)
    eps = 1e-6
    assert anchoring_margin({70.0: (5.0 + eps, 30.0)}, FORCES).value == pytest.approx(0.5, abs=1e-6)
    assert anchoring_margin({70.0: (5.0, 30.0 - eps)}, FORCES).value == pytest.approx(0.5, abs=1e-6)


def test_the_worst_pipe_decides():
    # the small pipe squeezes: it slides too hard; the wide pipe holds too little
    per_pipe = {55.0: (12.0, 60.0), 65.0: (6.0, 30.0), 75.0: (2.0, 21.0)}
    m = anchoring_margin(per_pipe, FORCES)
    assert (m.value, m.pipe_diameter, m.inequality) == (pytest.approx(-0.2), 55.0, "slide")
    per_pipe[55.0] = (9.0, 60.0)
    m = anchoring_margin(per_pipe, FORCES)
    assert (m.value, m.pipe_diameter, m.inequality) == (pytest.approx(0.05), 75.0, "hold")
    assert m.per_pipe[65.0] == (pytest.approx(0.5), pytest.approx(0.4))


@pytest.mark.parametrize("f_fwd, f_bwd, name", [(-1.0, 30.0, "f_fwd"), (5.0, math.nan, "f_bwd"),
                                                (5.0, math.inf, "f_bwd"), (True, 30.0, "f_fwd")])  # fmt: skip
def test_bad_forces_name_themselves(f_fwd, f_bwd, name):
    with pytest.raises(MarginError) as exc:
        pipe_margins(f_fwd, f_bwd, FORCES)
    assert exc.value.parameter == name


def test_no_pipe_is_an_error():
    with pytest.raises(MarginError) as exc:
        anchoring_margin({}, FORCES)
    assert exc.value.parameter == "pipes"


def _flat_disk():
    """A flat (180 deg) ungrooved foot: a hub annulus and a skirt annulus, a closed-form volume."""
    design = FootDesign(angle=180.0, n_grooves=0, skirt_thickness=2.0)
    hub = math.pi * (design.hub_radius**2 - design.bore_radius**2) * design.hub_thickness
    skirt = math.pi * (design.tip_radius**2 - design.hub_radius**2) * design.skirt_thickness
    return design, hub + skirt


def test_mass_is_the_closed_form_volume_times_the_density():
    design, volume = _flat_disk()
    rubber = get_material("rubber-50a")
    assert rubber.density == pytest.approx(1.15e-9)  # 1.15 g/cm^3 in t/mm^3
    assert foot_mass_g(design, rubber) == pytest.approx(volume * 1.15e-3, rel=1e-12)
    # the paper's foot: 18.08 g (its hub, skirt and five grooves)
    assert foot_mass_g(FootDesign(), get_material("rubber-70a")) == pytest.approx(18.077, abs=1e-3)


def test_the_mesh_volume_converges_to_the_mass_volume():
    """The study's revolved meshes are the chordal polygon of the revolved section: with n sectors
    their volume is V sin(2 pi / n) / (2 pi / n), a 1.1 % deficit at the quick mesh's 24."""
    design, volume = _flat_disk()
    for sectors in (24, 48):
        step = 2 * math.pi / sectors
        mesh = mesh_foot_with(design, "revolved", sectors=sectors)
        assert mesh.volume() == pytest.approx(volume * math.sin(step) / step, rel=1e-9)
