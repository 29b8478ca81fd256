"""Rolling over a corrugated rail (paper Fig. 1b; Fig. 5-like): the wheel of the paper (R1 = 0.475 m,
Hertz, P = 40 kN = 10 m g) rolls over a sinusoidal corrugation at three speeds, so that the passing
frequency V/lambda lies below, near and above the contact resonance (as Fig. 5a/b/c do with the
harmonic platform). The FMU's platform motion is the rolling constraint yb(x0 + V t) of the profile
(profile_file), not the profile itself: the wheel cannot follow a trough sharper than its radius.

    vibroimpact rolling [--out DIR] [--gallery]
        ->  DIR/{corrugation.txt, rolling.png, rolling.csv, constraint_harmonics.csv}

The FMU is vibroimpact.fmu_path(); the constraint drawn beside it comes from the independent
reference (vibroimpact.reference.profile).
"""
import argparse
import csv
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from .failure import out_dir  # noqa: E402
from .fmu import fmu_path, simulate  # noqa: E402
from .reference import profile as profile_ref  # noqa: E402

OUT = pathlib.Path("results", "rolling")
GALLERY = pathlib.Path("doc", "gallery")

LAMBDA = 0.05      # m, corrugation wavelength (short-pitch rail corrugation: 30-80 mm)
AMPLITUDE = 1e-4   # m, as the paper's a = 0.1 mm
SAMPLES = 200      # per wavelength
R1 = 0.475         # m
STOP = 0.1         # s
INTERVAL = 1e-5    # s
PASSING = {"below": 100.0, "near": 267.0, "above": 560.0}  # Hz, the frequencies of Fig. 5a/b/c
OUTPUTS = ["yC", "y", "F", "delta", "contact", "n_impacts"]


def corrugation(path):
    """One wavelength of h = A cos(2 pi x / lambda), repeated (profile_periodic)."""
    x = np.linspace(0.0, LAMBDA, SAMPLES + 1)
    h = AMPLITUDE * np.cos(2 * np.pi * x / LAMBDA)
    h[-1] = h[0]
    with open(path, "w") as f:
        f.write(f"# corrugation: lambda = {LAMBDA} m, amplitude {AMPLITUDE} m; x [m]  h [m]\n")
        for a, b in zip(x, h):
            f.write(f"{float(a)!r} {float(b)!r}\n")
    return x, h


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact rolling", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR", help=f"output folder (default {OUT})")
    p.add_argument("--gallery", action="store_true",
                   help=f"also write a smaller copy of the figure to {GALLERY / 'rolling.png'}")
    args = p.parse_args(argv)
    fmu = str(fmu_path())
    out = out_dir(args.out)
    path = out / "corrugation.txt"
    x, h = corrugation(path)
    runs = {}
    for name, f_pass in PASSING.items():
        V = f_pass * LAMBDA
        start = dict(contact_model=1, profile_file=str(path.resolve()), V=V, profile_periodic=True)
        runs[name] = (V, simulate(f"the FMU refuses the rolling run {name} the resonance", fmu, start_values=start,
                                  stop_time=STOP, output_interval=INTERVAL, relative_tolerance=1e-10, output=OUTPUTS))
    fig, axes = plt.subplots(len(runs) + 1, 2, figsize=(12, 3 * (len(runs) + 1)))
    s = np.linspace(0.0, 2 * LAMBDA, 801)
    ax = axes[0, 0]
    ax.plot(1e3 * s, 1e6 * np.interp(np.mod(s, LAMBDA), x, h), lw=0.8, color="0.5", label="profile h(x)")
    ax.plot(1e3 * s, 1e6 * profile_ref.yb(x, h, R1, s, periodic=True), lw=1.2, color="k",
            label=f"constraint yb(x), R1 = {R1} m")
    ax.set_xlabel("x [mm]"), ax.set_ylabel("[um]"), ax.legend(fontsize=8)
    ax.set_title("corrugation h(x) and the constraint yb(x) the wheel's lowest point follows", fontsize=9)
    axes[0, 1].axis("off")
    rows = []
    for i, (name, (V, r)) in enumerate(runs.items(), start=1):
        ms = 1e3 * r["time"]
        a, b = axes[i]
        a.plot(ms, 1e3 * r["yC"], lw=0.5, color="k", label="1: rail under the wheel $y_C$")
        a.plot(ms, 1e3 * r["y"], lw=1.2, color="C0", label="2: wheel $y$")
        a.set_ylabel("[mm]"), a.legend(fontsize=7, loc="lower left")
        a.set_title(f"{name} the contact resonance: V = {V:.2f} m/s, passing {PASSING[name]:g} Hz", fontsize=9)
        b.plot(ms, 1e-3 * r["F"], lw=0.8, color="C3")
        b.set_ylabel("F [kN]")
        for ax in (a, b):
            ax.set_xlabel("t [ms]")
        rows.append(dict(case=name, V_m_s=V, passing_Hz=PASSING[name], n_impacts=int(r["n_impacts"][-1]),
                         contact_fraction=float(np.mean(r["contact"])), F_min_kN=float(r["F"].min()) / 1e3,
                         F_max_kN=float(r["F"].max()) / 1e3, y_p2p_mm=float(np.ptp(r["y"])) * 1e3))
    fig.tight_layout()
    fig.savefig(out / "rolling.png", dpi=110)
    if args.gallery:
        GALLERY.mkdir(parents=True, exist_ok=True)
        fig.savefig(GALLERY / "rolling.png", dpi=60)
    with open(out / "rolling.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    # the constraint's harmonics: one period of yb, sampled, Fourier amplitudes of orders 1-5
    s_per = np.linspace(0.0, LAMBDA, 512, endpoint=False)
    amp = 2 * np.abs(np.fft.rfft(profile_ref.yb(x, h, R1, s_per, periodic=True)))[1:6] / len(s_per)
    with open(out / "constraint_harmonics.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["order", "amplitude_um", "relative_to_first"])
        for k, a in enumerate(amp, start=1):
            w.writerow([k, a * 1e6, a / amp[0]])
    print("harmonics of yb [um]: " + ", ".join(f"{k}: {a * 1e6:.3g}" for k, a in enumerate(amp, start=1)))
    for row in rows:
        print(", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()))
