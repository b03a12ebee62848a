"""A custom optuna study over the actuator's design, each trial one quick-mesh simulation.

Shows how to script your own design search with the public API instead of `softcrawl study`:
optuna's TPE sampler proposes a chamber radius r0 and a number of fibre turns N, `sc.simulate_epsa`
evaluates that `sc.EPSADesign` on the quick mesh, and the objective is how far its extension at
30 kPa is from a target (25 mm). An impossible design is an `sc.InputError` naming the field, which
optuna records as a failed trial. Six trials take about 10 s; the trials go to OUT/trials.csv.

    python examples/custom_sweep.py [OUT]        (OUT defaults to ./custom-sweep-out)
"""

import sys
from pathlib import Path

import optuna

import softcrawl as sc

TARGET_MM = 25.0
PRESSURE_KPA = 30.0
TRIALS = 6


def extension_at(design: sc.EPSADesign, pressure_kpa: float) -> float:
    """Extension (mm) of the design at `pressure_kpa` on the quick mesh (NaN if not reached)."""
    curve = sc.simulate_epsa(design, pressures_kpa=(pressure_kpa,), quick=True)
    return curve.rows[-1].length_mm - curve.rows[0].length_mm if curve.converged else float("nan")


def objective(trial: optuna.Trial) -> float:
    design = sc.EPSADesign(
        chamber_radius=trial.suggest_float("chamber_radius", 2.0, 4.0),
        fiber_turns=trial.suggest_int("fiber_turns", 10, 30),
    )
    extension = extension_at(design, PRESSURE_KPA)
    trial.set_user_attr("extension_mm", extension)
    print(
        f"trial {trial.number}: r0 = {design.chamber_radius:.3f} mm, N = {design.fiber_turns}: "
        f"extension {extension:.2f} mm at {PRESSURE_KPA:g} kPa",
        flush=True,
    )
    return abs(extension - TARGET_MM)  # NaN (not reached) makes the trial a failed one


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    sampler = optuna.samplers.TPESampler(seed=1, n_startup_trials=3)
    study = optuna.create_study(direction="minimize", sampler=sampler)
    study.optimize(objective, n_trials=TRIALS, catch=(sc.InputError,))
    lines = ["number,state,chamber_radius_mm,fiber_turns,extension_mm,error_mm"]
    for t in study.trials:
        p = t.params
        lines.append(
            f"{t.number},{t.state.name},{p.get('chamber_radius', '')},{p.get('fiber_turns', '')},"
            f"{t.user_attrs.get('extension_mm', '')},{'' if t.value is None else t.value}"
        )
    (out / "trials.csv").write_text("\n".join(lines) + "\n")
    best = study.best_trial
    print(
        f"best: r0 = {best.params['chamber_radius']:.3f} mm, N = {best.params['fiber_turns']}: "
        f"extension {best.user_attrs['extension_mm']:.2f} mm (target {TARGET_MM:g} mm); "
        f"trials in {out / 'trials.csv'}"
    )


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("custom-sweep-out"))
