"""Where W_plastic < 0 after a Johnson yield, from the closed forms (doc/model.md).

    vibroimpact wplastic [--Y Y]      (default Y = 6e8 Pa, the paper's Fig. 4b data)

Prints, for paper and continuous unloading, the largest delta_c/delta_Y with W_plastic < 0 and the
most negative W_plastic (J and in units of F_Y delta_Y). The closed form
(vibroimpact.reference.closed_forms) is the one fmu-test/test_laws.py checks the FMU against.
"""
import argparse
import math

from ..reference.closed_forms import effective, negative_w_plastic


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact wplastic", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--Y", type=float, default=6e8, help="yield stress [Pa] (default 6e8)")
    Y = p.parse_args(argv).Y
    if not (math.isfinite(Y) and Y > 0):
        p.error(f"--Y is the yield stress in Pa, a finite number > 0 (got {Y:g})")
    e = effective(dict(Y=Y))
    unit = e["F_Y"] * e["delta_Y"]
    print(f"Y = {Y:g} Pa: F_Y = {e['F_Y']:.6g} N, delta_Y = {e['delta_Y']:.6g} m, F_Y delta_Y = {unit:.6g} J")
    for variant, name in ((1, "paper"), (2, "continuous")):
        r_zero, r_min, w_min = negative_w_plastic(Y, variant)
        print(f"{name:10s}: W_plastic < 0 for delta_c < {r_zero:.4f} delta_Y; most negative {w_min:.4g} J "
              f"= {w_min / unit:.4f} F_Y delta_Y at delta_c = {r_min:.3f} delta_Y")
