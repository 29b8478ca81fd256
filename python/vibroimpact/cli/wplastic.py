"""Where Johnson's unloading curves return more energy than the loading took, from the closed forms
(doc/model.md, doc/numerics.md).

    vibroimpact wplastic [--Y Y]      (default Y = 6e8 Pa, the paper's Fig. 4b data)

Prints, for paper unloading and for the radius-continuous curve (force and eq. 3's contact radius
continuous at delta_c, which continuous unloading follows where it dissipates), the largest
delta_c/delta_Y with W_plastic < 0, the impact speed that reaches it (in units of the yield speed v_Y,
1/2 m v_Y^2 = 2/5 F_Y delta_Y), the most negative W_plastic (J and in units of F_Y delta_Y) and the
largest restitution; and for continuous unloading, which returns the loading work there instead, its
largest restitution and where its permanent set is negative. The closed forms
(vibroimpact.reference.closed_forms) are the ones fmu-test/test_laws.py and test_passive.py check the
FMU against.
"""
import argparse
import math

from ..reference.closed_forms import (effective, impact_speed, negative_permanent_set, negative_w_plastic,
                                      restitution_peak)


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact wplastic", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--Y", type=float, default=6e8, help="yield stress [Pa] (default 6e8)")
    Y = p.parse_args(argv).Y
    if not (math.isfinite(Y) and Y > 0):
        p.error(f"--Y is the yield stress in Pa, a finite number > 0 (got {Y:g})")
    e = effective(dict(Y=Y))
    unit = e["F_Y"] * e["delta_Y"]
    print(f"Y = {Y:g} Pa: F_Y = {e['F_Y']:.6g} N, delta_Y = {e['delta_Y']:.6g} m, F_Y delta_Y = {unit:.6g} J, "
          f"v_Y = {math.sqrt(0.8 * unit / e['m']):.6g} m/s (1/2 m v_Y^2 = 2/5 F_Y delta_Y)")
    for variant, name in ((1, "paper"), (3, "radius-continuous")):
        r_zero, r_min, w_min = negative_w_plastic(Y, variant)
        e_max, v_max = restitution_peak(Y, variant)
        print(f"{name}: W_plastic < 0 for delta_c < {r_zero:.4f} delta_Y (impacts below {impact_speed(Y, r_zero):.3f} "
              f"v_Y); most negative {w_min:.4g} J = {w_min / unit:.4f} F_Y delta_Y at delta_c = {r_min:.3f} delta_Y; "
              f"restitution up to {e_max:.4f} (at {v_max:.2f} v_Y)")
    e_max, _ = restitution_peak(Y, 2)
    below = negative_permanent_set(Y)
    where = (f"delta_f < 0 for {below[0]:.3f} < delta_c/delta_Y < {below[1]:.3f} (impacts {impact_speed(Y, below[0]):.2f} "
             f"to {impact_speed(Y, below[1]):.2f} v_Y)") if below else "delta_f >= 0 everywhere"
    print(f"continuous: the radius-continuous curve where it dissipates, else the loading work returned "
          f"(W_plastic = 0); restitution up to {e_max:.4f}; {where}")
