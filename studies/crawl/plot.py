"""Figure of one crawl: the feet's axial positions, the actuator force and the pressures against time."""

from __future__ import annotations

from softcrawl.paper import FRICTION_N
from softcrawl.studies.plots.style import pyplot, save


def plot_crawl(states, path, title: str = ""):
    """Top: rear, front and centre displacement (mm); middle: actuator force and the wall's axial
    friction on each foot (N); bottom: the three pressures (kPa). Setup states (insertion,
    friction on) are drawn at t = 0 before the schedule starts."""
    plt = pyplot()
    setup = [s for s in states if s["cycle"] == 0]
    rows = setup[-1:] + [s for s in states if s["cycle"] > 0]
    t = [s["time_s"] for s in rows]
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for key, label in (("rear_u_mm", "rear foot"), ("front_u_mm", "front foot"), ("centre_u_mm", "centre")):
        axes[0].plot(t, [s[key] for s in rows], "o-" if key != "centre_u_mm" else "k--", ms=3, label=label)
    axes[0].set(ylabel="axial displacement (mm)")
    fig.suptitle(title, fontsize=8)
    axes[1].plot(t, [s["actuator_force_n"] for s in rows], "k--", lw=2.5, label="actuators (push > 0)")
    for f in ("rear", "front"):
        axes[1].plot(t, [s[f"{f}_friction_n"] for s in rows], "o-", ms=3, label=f"wall friction on {f}")
    axes[1].set(ylabel="axial force (N)")
    for i in (1, 2, 3):
        axes[2].plot(t, [s[f"p{i}_kpa"] for s in rows], label=f"P{i}")
    axes[2].set(xlabel="time (s)", ylabel="pressure (kPa)")
    for ax in axes:
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    return save(fig, path)


def plot_crawl_study(rows, path):
    """Left: speed = stride / cycle time against pipe diameter, one line per mu through the points
    where a foot slid (hollow markers, not joined: no foot slid in the extension), beside Table 2's
    forward speeds and the analytic crawl_speed
    with the paper's friction; right: the anchoring slip ratio. Failed and missing points are not
    drawn (summary.csv and summary.md have their reasons)."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for mu in sorted({r["mu"] for r in rows}):
        ok = sorted(
            (r for r in rows if r["mu"] == mu and r["status"] == "completed"),
            key=lambda r: r["pipe_diameter"],
        )
        if not ok:
            continue
        # lines join only the points where a foot slid (the robot moved): a "no foot slid" point
        # is a hollow marker on its own, not a stretch of a curve through the moving ones
        moving = [r for r in ok if r.get("extend_slid") != "none"]
        d = [r["pipe_diameter"] for r in moving]
        speed = [r.get("speed_mm_s", float("nan")) for r in moving]
        ratio = [r.get("anchoring_slip_ratio", float("nan")) for r in moving]
        line = axes[0].plot(d, speed, "-", label=f"FE, mu = {mu:g}")[0]
        axes[1].plot(d, ratio, "-", color=line.get_color())
        for r in ok:
            face = "none" if r.get("extend_slid") == "none" else line.get_color()
            for ax, key in ((axes[0], "speed_mm_s"), (axes[1], "anchoring_slip_ratio")):
                ax.plot(r["pipe_diameter"], r.get(key, float("nan")), "o", color=line.get_color(), mfc=face)
    paper = sorted({(r["pipe_diameter"], r.get("table2_mm_s")) for r in rows if r.get("table2_mm_s")})
    if paper:
        axes[0].plot(*zip(*paper), "ks--", ms=4, label="paper, Table 2 (forward)")
    analytic = sorted(
        {
            (r["pipe_diameter"], r["analytic_paper_friction_mm_s"])
            for r in rows
            if "analytic_paper_friction_mm_s" in r
        }
    )
    if analytic:
        label = f"analytic crawl_speed, paper's {FRICTION_N['forward']:g} N"
        axes[0].plot(*zip(*analytic), "k:", label=label)
    axes[0].set(xlabel="pipe diameter (mm)", ylabel="speed (mm/s)", title="FE crawl, inflate 100 kPa, 2 s")
    axes[1].set(
        xlabel="pipe diameter (mm)",
        ylabel="|rear| / (|rear| + |front|) in extension",
        title="anchoring (hollow: no foot slid)",
    )
    axes[0].legend(fontsize=7, loc="center left")
    for ax in axes:
        ax.grid(alpha=0.3)
    return save(fig, path)
