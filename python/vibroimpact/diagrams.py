"""Amplitude-frequency response and bifurcation diagrams of the paper's system: the continuation
sweeps `vibroimpact diagrams` runs and the table it writes.

Hertz and Johnson (Y = 6e8 Pa) contact with the paper's data (R* = 0.475 m, steel, P = 40 kN =
10 m g), excitation frequency swept up and down as continuation sweeps (each point starts from the
previous point's final state, the frequency changed at phase 0), at the paper's amplitude
a = 0.1 mm and at a = 5 um, where the jump sits at the contact resonance.
"""
import csv

import numpy as np

from .files import replacing
from .sweep import spec

PAPER = ["R1=0.475", "R2=0", "E1=2.1e11", "E2=2.1e11", "nu1=0.3", "nu2=0.3", "P=40000", "m=407.747", "g=9.81",
         "init=static"]
LAWS = [("hertz", "Hertz", ["contact_model=hertz"]),
        ("johnson", "Johnson, Y = 6e8 Pa", ["contact_model=johnson", "Y=6e8"])]
# amplitude label, a [m], frequency grid START:STOP:N (full, quick)
AMPLITUDES = [("a100um", 1e-4, "f=100:600:51", "f=100:600:26"),
              ("a5um", 5e-6, "f=200:330:66", "f=200:330:27")]
STOP_TIME, TRANSIENT, STEP = 0.1, 0.05, 1e-5  # per point [s]
QUICK_STEP_FACTOR = 4                          # --quick: a coarser communication step
DIRECTIONS = ("up", "down")


def panels():
    """[(law, law title, amplitude label, a [m])] in the figures' order: by amplitude, then law."""
    return [(law, title, amp, a) for amp, a, _, _ in AMPLITUDES for law, title, _ in LAWS]


def f_contact(fmu, interface, sets):
    """The FMU's calculated linearised contact resonance [Hz] for these start values."""
    from fmpy import simulate_fmu
    values = {n: v for n, v in (spec.parse_set(interface, s) for s in sets)}
    r = simulate_fmu(fmu, start_values=values, stop_time=1e-4, output_interval=1e-4, output=["f_contact"])
    return float(r["f_contact"][0])


def sweep_of(interface, sets, grid, direction, quick, stop_time=STOP_TIME, transient=TRANSIENT):
    """The continuation sweep of one panel and direction."""
    fixed = dict(spec.parse_set(interface, s) for s in sets)
    return spec.Sweep(fixed=fixed, grids=[spec.parse_grid(interface, grid)], stop_time=stop_time,
                      step=STEP * (QUICK_STEP_FACTOR if quick else 1), transient=transient, direction=direction,
                      title=" ".join(s for s in sets if s not in PAPER))


def first_loss(cols, direction):
    """The first frequency, in the sweep's own order, at which the mass leaves the platform."""
    f = cols["f"][cols["contact_fraction"] < 1]
    return np.nan if not len(f) else (f.min() if direction == "up" else f.max())


def write_summary(runs, path):
    """Per sweep: where the mass first leaves the platform, the largest force and flight."""
    with replacing(path, newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["law", "amplitude", "direction", "points", "failed", "f_contact_lost_Hz",
                    "F_max_kN", "f_at_F_max_Hz", "sep_max_mm"])
        for (law, amp, direction), (cols, _) in runs.items():
            k = int(np.nanargmax(cols["F_max"]))
            w.writerow([law, amp, direction, len(cols["f"]), sum(s != "ok" for s in cols["status"]),
                        first_loss(cols, direction),
                        f"{cols['F_max'][k] / 1e3:.1f}", cols["f"][k], f"{np.nanmax(cols['sep_max']) * 1e3:.3f}"])
