#!/usr/bin/env python3
"""Simulate the paper's scenarios through fmpy and write results/<scenario>.csv and .png.

Usage: python3 tools/paper.py [scenario ...]   (default: all of SCENARIOS)
The FMU is build/VibroImpact.fmu (or $VI_FMU). Scenarios follow ../shared/design/model.md section 5.
"""
import os
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from fmpy import simulate_fmu  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
FMU = os.environ.get("VI_FMU", str(ROOT / "build" / "VibroImpact.fmu"))
OUT = ROOT / "results"
OUTPUTS = ["yC", "y", "delta", "F", "v", "mode", "n_impacts", "delta_c", "delta_f", "Rbar", "W_plastic"]

# name: (caption, start values); common: R* = 0.475 m, steel, P = 40 kN, m = P/(10 g), a = 0.1 mm, f = 560 Hz
SCENARIOS = {
    "fig4b": ("Fig. 4b: Johnson, fixed contact point, Y = 6e8 Pa (yields, then bounces)",
              dict(contact_model=2, Y=6e8, a=1e-4, f=560.0)),
}


def run(name, caption, params, stop=0.1, interval=1e-5):
    r = simulate_fmu(FMU, start_values=params, stop_time=stop, output_interval=interval, output=OUTPUTS)
    OUT.mkdir(exist_ok=True)
    np.savetxt(OUT / f"{name}.csv", np.column_stack([r[c] for c in r.dtype.names]), delimiter=",",
               header=",".join(r.dtype.names), comments="", fmt="%.10g")
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    ms = 1e3 * r["time"]
    ax1.plot(ms, 1e3 * r["yC"], lw=0.8, label="1: platform $y_C(t)$")
    ax1.plot(ms, 1e3 * r["y"], lw=1.2, label="2: mass $y(t)$")
    ax1.set_ylabel("position [mm]")
    ax1.legend(loc="lower right")
    ax1.set_title(caption, fontsize=10)
    ax2.plot(ms, 1e-3 * r["F"], lw=0.8, color="C3")
    ax2.set_ylabel("contact force [kN]")
    ax2.set_xlabel("time [ms]")
    fig.tight_layout()
    fig.savefig(OUT / f"{name}.png", dpi=110)
    plt.close(fig)
    print(f"{name}: {r['n_impacts'][-1]} impacts, max force {r['F'].max() / 1e3:.1f} kN, "
          f"W_plastic {r['W_plastic'][-1]:.4g} J -> results/{name}.csv, results/{name}.png")


if __name__ == "__main__":
    for name in sys.argv[1:] or SCENARIOS:
        run(name, *SCENARIOS[name])
