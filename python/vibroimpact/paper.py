"""The paper's scenarios through fmpy: one run per scenario of vibroimpact/reference/scenarios.py, its
summary figures, and the files `vibroimpact paper` keeps (a run's CSV file, summary.csv).

Runs use rtol 1e-11 (not the FMU's default 1e-6): the bouncing scenarios are chaotic, and the tighter
tolerance keeps the drawn trajectory on the reference's for longer (vibroimpact/reference/data/summary.json
has each scenario's predictable horizon).
"""
import csv

import numpy as np

from .files import replacing
from .fmu import fmu_path, simulate as simulate_logged
from .reference.scenarios import SCENARIOS, STOP_TIME

INTERVAL = 1e-5  # s, output grid
RTOL = 1e-11
OUTPUTS = ["yC", "y", "delta", "F", "v", "contact", "mode", "n_impacts", "delta_c", "delta_f", "delta_p",
           "Rbar", "W_plastic"]
SUMMARY = ["scenario", "n_impacts", "F_min_kN", "F_max_kN", "F_mean_kN", "contact_fraction", "stick_fraction",
           "delta_max_um", "delta_p_um", "delta_f_um", "W_plastic_J", "y_p2p_mm", "warnings"]
WARNINGS_SEP = " | "   # between the FMU's warnings in summary.csv's column warnings


def simulate(scenario, fmu=None, stop_time=STOP_TIME, warned=None):
    """The FMU (default fmu_path()) on one scenario from 0 to stop_time [s]: fmpy's result (OUTPUTS).
    warned: called with the FMU's warnings when it logged any (vibroimpact.fmu.simulate)."""
    return simulate_logged(f"the FMU refuses the scenario '{scenario.title}'", fmu or fmu_path(), warned=warned,
                           start_values=scenario.full, stop_time=stop_time, output_interval=INTERVAL,
                           relative_tolerance=RTOL, output=OUTPUTS)


def summarize(name, r, warnings=()):
    """The figures of one run (Python numbers: fmpy's result keeps its own type through max() and the like)
    and the warnings the FMU logged in it (one text, WARNINGS_SEP between them)."""
    return dict(scenario=name, warnings=WARNINGS_SEP.join(warnings), n_impacts=int(r["n_impacts"][-1]),
                F_min_kN=float(r["F"].min()) / 1e3,
                F_max_kN=float(r["F"].max()) / 1e3,
                F_mean_kN=float(np.trapezoid(r["F"], r["time"])) / (r["time"][-1] - r["time"][0]) / 1e3,
                contact_fraction=float(np.mean(r["contact"])), stick_fraction=float(np.mean(r["mode"] == 4)),
                delta_max_um=float(r["delta"].max()) * 1e6,
                delta_p_um=float(r["delta_p"][-1]) * 1e6, delta_f_um=float(r["delta_f"][-1]) * 1e6,
                W_plastic_J=float(r["W_plastic"][-1]), y_p2p_mm=float(np.ptp(r["y"])) * 1e3)


def summary_row(s):
    """A summary (summarize) as summary.csv's text."""
    return {k: f"{s[k]:.6g}" if isinstance(s[k], float) else str(s[k]) for k in SUMMARY}


def write_run(path, r):
    """A run's outputs as a CSV file, one column per output (read_run reads it back)."""
    with replacing(path) as fh:
        np.savetxt(fh, np.column_stack([r[c] for c in r.dtype.names]), delimiter=",", header=",".join(r.dtype.names),
                   comments="", fmt="%.10g")


def read_run(path):
    """A scenario's CSV file back as {output name: column}, the columns simulate() returned."""
    with open(path) as fh:
        names = fh.readline().strip().split(",")
    return dict(zip(names, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2).T))


def read_summary(out):
    """The rows of <out>/summary.csv by scenario (text as written), those of known scenarios only (a row
    written before summary.csv had its column warnings: none recorded)."""
    path = out / "summary.csv"
    if not path.is_file():
        return {}
    with open(path, newline="") as fh:
        found = [{"warnings": "", **r} for r in csv.DictReader(fh)]
    return {r["scenario"]: r for r in found if r.get("scenario") in SCENARIOS and set(SUMMARY) <= set(r)}


def write_summary(out, rows):
    """<out>/summary.csv: one row per scenario in `rows`, in the scenario table's order."""
    with replacing(out / "summary.csv", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(SUMMARY)
        for name in (n for n in SCENARIOS if n in rows):
            w.writerow([rows[name][k] for k in SUMMARY])
