"""The FE-body crawl's summary: the paper's speed for each pipe, and the summary's text.

`paper_speed(pipe, diameter)` names what the paper measured in that pipe: Table 2's forward speed
in a straight pipe, Section VII-D-2's vertical speeds (12.9 mm/s up, 19.1 down), and none for the
elbow (no bend radius given) or the bellows (no speed, no corrugations given). `summary_text`
prints a written summary.json (`studies.crawl_fe.files`) as the lines the command shows: the pipe,
each cycle's stride, speed, turn and wall time, the paper's speed, the mass, the solver's effort.
"""

from __future__ import annotations

from softcrawl.paper import VERTICAL_MM_S, table2


def paper_speed(pipe: str, diameter: float) -> tuple[float | None, str]:
    """The paper's speed for this pipe (mm/s; None: none measured) and where it is from."""
    if pipe == "straight":
        return table2(diameter, "forward"), f"Table 2, forward, {diameter:g} mm"
    if pipe.startswith("vertical"):
        way = pipe.split("-")[1]
        return VERTICAL_MM_S[way], f"Section VII-D-2, vertical {way} (pipe diameter not stated)"
    if pipe == "bellows":
        return None, "Section VII-E: the paper gives no speed and no corrugations for its 75 mm bellows"
    return None, "the paper gives no bend radius for its L-shaped pipe (Fig. 24)"


def summary_mesh(mesh) -> str:
    return mesh if isinstance(mesh, str) else "custom (BodyMeshSettings)"


def summary_text(s: dict) -> str:
    pipe = s["pipe"]
    where = f"{pipe['kind']} {pipe['diameter_mm']:g} mm pipe"
    if pipe["bend_radius_mm"]:
        where += f", bend radius {pipe['bend_radius_mm']:g} mm"
    if pipe.get("corrugation_mm"):
        where += ", corrugations {:g} mm deep, {:g} mm pitch".format(*pipe["corrugation_mm"])
    mesh = s["mesh"] + (f" mesh, one wedge of 360/{s['wedge']} deg" if s.get("wedge", 1) > 1 else " mesh")
    lines = [f"FE body in the {where} ({mesh}, silicone {s['materials']['epsa']}): {s['message']}"]
    times = s.get("cycle_wall_s") or [None] * len(s["strides_mm"])  # runs before times were kept
    for k, (v, a, t) in enumerate(zip(s["strides_mm"], s["turns_deg"], times), start=1):
        took = "wall time not recorded" if t is None else f"{t:.0f} s of wall time"
        lines.append(
            f"  cycle {k}: stride {v:.3f} mm, speed {v / s['schedule']['cycle_s']:.2f} mm/s, "
            f"turn {a:+.2f} deg, {took}"
        )
    if s["paper_speed_mm_s"] is not None:
        lines.append(f"  paper: {s['paper_speed_mm_s']:g} mm/s ({s['paper_source']})")
    m = s["mass"]
    lines.append(f"  mass {m['total_g']:.1f} g (prototype {m['prototype_g']:g} g)")
    if s.get("inertia"):
        lines.append(f"  inertia: {s['inertia']['scheme']}, {s['inertia']['mass_g']:.1f} g")
    v = s["solver"]
    solver = f" ({v['linear_solver']})" if "linear_solver" in v else ""  # runs before it was kept
    lines.append(f"  {v['dofs']} DOFs, {v['newton_iterations']} Newton iterations, {v['factorizations']} "
                 f"factorisations{solver}, {v['wall_s']:.0f} s, peak {v['peak_rss_gb']:.2f} GB")  # fmt: skip
    lines.append(f"  wall time: linear solves {v['linear_s'] / v['wall_s']:.0%}, the contact terms' assembly "
                 f"{v['contact_share']:.0%} (this process's)")  # fmt: skip
    return "\n".join(lines)
