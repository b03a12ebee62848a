"""3D renders of an actuator's run (`softcrawl epsa --render`): the reference state and every
computed state as a cut-away coloured by von Mises stress, one colour scale for the whole series
(so that the renders compare), the deformed Kevlar helices drawn on the body."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from softcrawl.fem.post import element_fields
from softcrawl.geometry.epsa_shape import fiber_helices
from softcrawl.studies.plots.labels import material_label
from softcrawl.studies.plots.render3d import render_state
from softcrawl.units import mpa_to_kpa


def render_path(out, design, solved, material: str) -> list[Path]:
    """render-PkPa.png for the reference state and each computed state of `solved`
    (`studies.epsa.response.Solved`); returns the files written."""
    model, steps = solved.model, solved.path.steps
    states = [(0.0, 0.0, model.initial_state())] + [(s.pressure, s.factor, s.x) for s in steps]
    top = max(float(element_fields(model, x).von_mises.max()) for _, _, x in states)
    helices = _helices(design) if design.fiber_turns > 0 else ()
    written = []
    for pressure, factor, x in states:
        kpa = mpa_to_kpa(pressure)
        top_nodes = model.boundary_nodes("end_top")
        length = solved.curve.rows[0].length_mm + float(np.mean(model.displacement(x)[2, top_nodes]))
        title = (
            f"ePSA r0 = {design.chamber_radius:g} mm, N = {design.fiber_turns} at P = {kpa:.3g} kPa "
            f"(length {length:.1f} mm); {material_label(material)}"
        )
        written.append(
            render_state(
                model,
                x,
                Path(out) / (f"render-{kpa:.0f}kPa" + ("-side-load" if factor and not kpa else "") + ".png"),
                pressure_mpa=pressure,
                factor=factor,
                title=title,
                clim=(0.0, top),
                helices=helices,
            )
        )
    return written


def _helices(design):
    """The reference helix polylines of the design's winding (for drawing)."""
    return fiber_helices(design)
