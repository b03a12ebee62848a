"""The two unstable-mode counters of `studies.skirt` on one state: the whole tangent
(`fem.stability`) and one harmonic at a time (`fem.cyclic`), which must agree pivot for pivot.

`check_counters(out, sectors, cells)` takes the carried, settled state of that mesh (the
study's path, `runs.carried_state`, kept in DIR/skirt/MATERIAL/states/) and writes both
descriptions (`runs.describe_state`) to DIR/skirt/MATERIAL/checks/S<sectors>-C<cells>-counters.json:
  python -c "from softcrawl.studies.skirt.counter_check import check_counters; check_counters('results/')"
"""

from __future__ import annotations

from pathlib import Path

from softcrawl import jsonio
from softcrawl.analytic.pipe import Pipe
from softcrawl.geometry.design import FootDesign
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.skirt import model as sm
from softcrawl.studies.skirt import runs

COMPARED = (
    "n_unstable",
    "neg_tangent",
    "neg_pressure_block",
    "lowest_eigenvalues",
    "lobes_unstable",
    "stability_s",
)


def check_counters(out, sectors: int = 48, cells: int = 3, material: str = runs.DEFAULT_MATERIAL) -> dict:
    folder = Path(out) / "skirt" / material
    design, pipe = FootDesign(), Pipe(diameter=runs.PIPE_MM)
    law = solid_law(get_material(material), hyperelastic_only=True)
    model = sm.build_model(sm.foot_mesh(design, sectors, cells), law, design)
    res = runs.carried_state(sectors, cells, model, law, design, pipe, {}, folder / "states")
    row = {"sectors": sectors, "cells": cells, "n_dofs": int(model.n_dofs), "converged": res.converged}
    row |= {"message": res.message, "newton_iterations": res.newton_iterations, "settle_wall_s": res.wall_s}
    if not res.converged:
        return row
    whole = runs.describe_state(model, res.x, design)
    by_harmonic = runs.describe_state(model, res.x, design, cyclic_sectors=sectors)
    row["insertion_force_n"] = whole["insertion_force_n"]
    row |= {f"whole_{k}": whole[k] for k in COMPARED}
    row |= {f"harmonic_{k}": by_harmonic[k] for k in COMPARED}
    row |= {k: by_harmonic[k] for k in ("circulant_error", "unstable_by_harmonic", "lowest_by_harmonic")}
    row["agree"] = all(
        whole[k] == by_harmonic[k] for k in ("n_unstable", "neg_tangent", "neg_pressure_block")
    )
    (folder / "checks").mkdir(parents=True, exist_ok=True)
    jsonio.write(folder / "checks" / f"{runs.point_name(sectors, cells)}-counters.json", row)
    return row
