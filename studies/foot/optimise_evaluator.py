r"""One trial of `softcrawl study optimise-feet`: a foot design -> (anchoring margin, mass).

    params (angle deg, skirt_thickness mm, hardness: a printed-rubber preset)
      -> FootDesign(angle, skirt_thickness) (tip 39 mm, hub derived: record 066)
      -> per pipe D of the study: the foot simulator (`studies.foot.simulate.simulate_foot`: one
         frictionless insertion, then a forward and a backward drag at the identified mu) -> F_fwd, F_bwd
      -> `studies.foot.anchoring.anchoring_margin` (maximised) and `foot_mass_g` (minimised)

A drag that stopped past a limit point (`studies.foot.model.limit_point`) counts with its largest
computed resistance, a lower bound flagged in the table (``lower_bounds``): for F_bwd the margin is
then conservative; for F_fwd the limit point is where the foot starts to snap forward. A failed
insertion, or a drag that stopped without passing a limit point, makes the trial FAIL with the pipe
and the solver's reason (the sweep machinery records it); the remaining pipes are not run.

``settings`` (`studies.foot.optimise.search_spec`): pipes (mm), quick, mu_smooth, mu_grooved (the
identified values, `studies.foot.identify`), max_wall_s (per pipe), and optionally simulator
(MODULE:FUNCTION with `simulate_foot`'s call; the tests' fakes).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from softcrawl.geometry.design import FootDesign
from softcrawl.materials import get_material
from softcrawl.studies.foot.anchoring import anchoring_margin, foot_mass_g, prototype_forces
from softcrawl.studies.sweeps.spec import Evaluation, load_callable

#: The foot simulator a trial calls unless the settings name another (`--simulator`).
SIMULATOR = "softcrawl.studies.foot.simulate:simulate_foot"


def pipe_key(diameter: float) -> str:
    """The column suffix of a pipe: D55, D62.5."""
    return f"D{float(diameter):g}"


def metric_columns(pipes) -> tuple[str, ...]:
    """The trial attributes the table shows, in order (`SearchSpec.metric_columns`)."""
    per_pipe = [f"{q}_{pipe_key(d)}" for d in pipes for q in ("f_fwd_n", "f_bwd_n", "normal_force_n")]
    return (
        "deciding_pipe_mm",
        "deciding_inequality",
        "hold_n",
        "slide_n",
        *per_pipe,
        "lower_bounds",
        "mu_smooth",
        "mu_grooved",
        "wall_s",
    )


def _drag_force(curve, direction: str, diameter: float) -> tuple[float | None, str, bool]:
    """(force or None, why not, lower bound?) of one drag."""
    if curve is None:
        return None, f"D = {diameter:g} mm: no {direction} drag", False
    if curve.converged:
        return curve.peak, "", False
    if curve.limit_point is not None:
        return curve.limit_point[1], "", True
    return None, f"D = {diameter:g} mm: the {direction} drag stopped: {curve.message}", False


def evaluate_feet_design(params: Mapping[str, Any], fixed: Mapping[str, Any], settings: Mapping[str, Any]):
    """The trial of the module docstring -> Evaluation(values=(margin, mass_g))."""
    design = FootDesign(angle=float(params["angle"]), skirt_thickness=float(params["skirt_thickness"]))
    material = get_material(str(params["hardness"]))
    simulate = load_callable(settings.get("simulator") or SIMULATOR, parameter="simulator")
    forces = prototype_forces()
    mu_s, mu_g = float(settings["mu_smooth"]), float(settings["mu_grooved"])
    attrs: dict[str, Any] = {
        "hold_n": forces.hold_n,
        "slide_n": forces.slide_n,
        "mu_smooth": mu_s,
        "mu_grooved": mu_g,
        "mass_g": foot_mass_g(design, material),
    }
    per_pipe, bounds, wall = {}, [], 0.0
    for diameter in map(float, settings["pipes"]):
        r = simulate(
            design,
            diameter,
            material=material,
            mu_smooth=mu_s,
            mu_grooved=mu_g,
            quick=bool(settings.get("quick", False)),
            max_wall_s=settings.get("max_wall_s"),
            **({"wedge": int(settings["copies"])} if int(settings.get("copies", 1)) > 1 else {}),
        )
        wall += float(r.wall_s)
        key = pipe_key(diameter)
        attrs[f"normal_force_n_{key}"] = r.normal_force
        forward = _drag_force(r.forward, "forward", diameter)
        backward = _drag_force(r.backward, "backward", diameter)
        attrs |= {f"f_fwd_n_{key}": forward[0], f"f_bwd_n_{key}": backward[0], "wall_s": wall}
        bounds += [f"{q} {key}" for q, f in (("f_fwd", forward), ("f_bwd", backward)) if f[2]]
        attrs["lower_bounds"] = ", ".join(bounds)
        why = r.message if r.forward is None and r.backward is None else forward[1] or backward[1]
        if forward[0] is None or backward[0] is None:
            reason = why if why.startswith("D = ") else f"D = {diameter:g} mm: {why}"
            return Evaluation(ok=False, attrs=attrs, message=reason)
        per_pipe[diameter] = (forward[0], backward[0])
    margin = anchoring_margin(per_pipe, forces)
    attrs |= {
        "deciding_pipe_mm": margin.pipe_diameter,
        "deciding_inequality": margin.inequality,
        "margins": {pipe_key(d): {"hold": h, "slide": s} for d, (h, s) in margin.per_pipe.items()},
    }
    return Evaluation(ok=True, values=(margin.value, attrs["mass_g"]), attrs=attrs)
