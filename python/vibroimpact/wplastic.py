"""Where W_plastic < 0 after a Johnson yield, from the closed forms (doc/model.md).

    vibroimpact wplastic [--Y Y]      (default Y = 6e8 Pa, the paper's Fig. 4b data)

Prints, for paper and continuous unloading, the largest delta_c/delta_Y with W_plastic < 0 and the
most negative W_plastic (J and in units of F_Y delta_Y). The closed form
(vibroimpact.reference.closed_forms) is the one fmu-test/test_laws.py checks the FMU against.
"""
import argparse
import math

import numpy as np
from scipy.optimize import brentq

from .reference.closed_forms import effective, w_plastic_closed_form


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
        wp = lambda r: w_plastic_closed_form(e, r * e["delta_Y"], variant)[1]  # noqa: E731
        r_zero = brentq(wp, 1.0 + 1e-9 if variant == 1 else 1.5, 50.0, xtol=1e-12)
        grid = np.linspace(1.0 + 1e-6, r_zero, 20001)
        w = np.array([wp(r) for r in grid])
        i = int(np.argmin(w))
        print(f"{name:10s}: W_plastic < 0 for delta_c < {r_zero:.4f} delta_Y; most negative {w[i]:.4g} J "
              f"= {w[i] / unit:.4f} F_Y delta_Y at delta_c = {grid[i]:.3f} delta_Y")
