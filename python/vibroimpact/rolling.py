"""Rolling over a corrugated rail (paper Fig. 1b; Fig. 5-like): the wheel of the paper (R1 = 0.475 m,
Hertz, P = 40 kN = 10 m g) rolls over a sinusoidal corrugation at three speeds, so that the passing
frequency V/lambda lies below, near and above the contact resonance (as Fig. 5a/b/c do with the
harmonic platform). The FMU's platform motion is the rolling constraint yb(x0 + V t) of the profile
(profile_file), not the profile itself: the wheel cannot follow a trough sharper than its radius.
The constraint drawn beside it comes from the independent reference (vibroimpact.reference.profile).
"""
import csv

import numpy as np

from .files import replacing
from .fmu import fmu_path, simulate
from .reference import profile as profile_ref

LAMBDA = 0.05      # m, corrugation wavelength (short-pitch rail corrugation: 30-80 mm)
AMPLITUDE = 1e-4   # m, as the paper's a = 0.1 mm
SAMPLES = 200      # per wavelength
R1 = 0.475         # m
STOP = 0.1         # s
INTERVAL = 1e-5    # s
PASSING = {"below": 100.0, "near": 267.0, "above": 560.0}  # Hz, the frequencies of Fig. 5a/b/c
OUTPUTS = ["yC", "y", "F", "delta", "contact", "n_impacts"]
HARMONICS = 5      # orders of the constraint's Fourier series reported


def corrugation(path):
    """Write one wavelength of h = A cos(2 pi x / lambda), repeated (profile_periodic), to path: (x, h) [m]."""
    x = np.linspace(0.0, LAMBDA, SAMPLES + 1)
    h = AMPLITUDE * np.cos(2 * np.pi * x / LAMBDA)
    h[-1] = h[0]
    with replacing(path) as f:
        f.write(f"# corrugation: lambda = {LAMBDA} m, amplitude {AMPLITUDE} m; x [m]  h [m]\n")
        for a, b in zip(x, h):
            f.write(f"{float(a)!r} {float(b)!r}\n")
    return x, h


def run(profile_path, fmu=None, stop_time=STOP, warned=None):
    """The FMU over the profile at each passing frequency: case -> (V [m/s], fmpy's result). warned:
    called with (case, the FMU's warnings) for a run in which the FMU logged any (a fmu.Relay)."""
    fmu = str(fmu or fmu_path())
    runs = {}
    for name, f_pass in PASSING.items():
        V = f_pass * LAMBDA
        start = dict(contact_model=1, profile_file=str(profile_path.resolve()), V=V, profile_periodic=True)
        runs[name] = (V, simulate(f"the FMU refuses the rolling run {name} the resonance", fmu, start_values=start,
                                  stop_time=stop_time, output_interval=INTERVAL, relative_tolerance=1e-10,
                                  output=OUTPUTS, warned=warned and (lambda texts: warned(name, texts))))  # noqa: B023
    return runs


def constraint(x, h, periods=2, points=801):
    """(s, h(s), yb(s)) [m] over `periods` wavelengths, for the figure."""
    s = np.linspace(0.0, periods * LAMBDA, points)
    return s, np.interp(np.mod(s, LAMBDA), x, h), profile_ref.yb(x, h, R1, s, periodic=True)


def rows(runs, warnings=None):
    """One summary row per case; warnings: case -> the FMU's warnings in its run (a fmu.Relay's by_run),
    the column warnings (" | " between them)."""
    return [dict(case=name, V_m_s=V, passing_Hz=PASSING[name], n_impacts=int(r["n_impacts"][-1]),
                 contact_fraction=float(np.mean(r["contact"])), F_min_kN=float(r["F"].min()) / 1e3,
                 F_max_kN=float(r["F"].max()) / 1e3, y_p2p_mm=float(np.ptp(r["y"])) * 1e3,
                 warnings=" | ".join((warnings or {}).get(name, ())))
            for name, (V, r) in runs.items()]


def harmonics(x, h):
    """The constraint's Fourier amplitudes [m] of orders 1 ... HARMONICS (one period of yb, sampled)."""
    s = np.linspace(0.0, LAMBDA, 512, endpoint=False)
    return 2 * np.abs(np.fft.rfft(profile_ref.yb(x, h, R1, s, periodic=True)))[1:HARMONICS + 1] / len(s)


def write_rows(path, table):
    with replacing(path, newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0]))
        w.writeheader()
        w.writerows(table)


def write_harmonics(path, amp):
    with replacing(path, newline="") as f:
        w = csv.writer(f)
        w.writerow(["order", "amplitude_um", "relative_to_first"])
        for k, a in enumerate(amp, start=1):
            w.writerow([k, a * 1e6, a / amp[0]])
