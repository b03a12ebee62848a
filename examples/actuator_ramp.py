"""The Table 1 actuator (ePSA) under a pressure ramp from 0 to 40 kPa, on the quick mesh.

Shows the one-call actuator simulation of the public API: a design (`sc.EPSADesign()`, the paper's
Table 1 values), a silicone preset and pressures in kPa go in, a frozen `sc.ActuatorCurve` comes
out, one row per computed state. Prints the length and extension at each pressure (a few seconds).

    python examples/actuator_ramp.py
"""

import softcrawl as sc


def main() -> None:
    design = sc.EPSADesign()  # r0 = 3 mm, R0 = 9 mm, L0 = 100 mm, 20 fibre turns
    curve = sc.simulate_epsa(design, material="ecoflex-00-50", pressures_kpa=(10, 20, 30, 40), quick=True)
    print(f"ePSA {design.short_hash()}, {curve.material_law}, {curve.n_dofs} DOFs, {curve.wall_s:.1f} s")
    length0 = curve.rows[0].length_mm
    print("pressure_kPa  length_mm  extension_mm  status")
    for row in curve.rows:
        print(f"{row.pressure_kpa:12.1f} {row.length_mm:10.2f} {row.length_mm - length0:13.2f}  {row.status}")
    print(curve.message)
    raise SystemExit(0 if curve.converged else 1)


if __name__ == "__main__":
    main()
