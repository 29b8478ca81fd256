"""The reference traces and event tables from the independent reference model (model.py), and each
scenario's predictable horizon; `vibroimpact reference` writes them (the committed ones are in DATA).

For every scenario of scenarios.py the reference runs twice over [0, STOP_TIME]: at RTOL_TRUE (the
reference trace) and at RTOL_LOOSE. The predictable horizon is the first sample time at which the
two runs' mass positions differ by more than EPS_Y; it is how far a trajectory computed with a
relative error of about RTOL_LOOSE can be trusted to EPS_Y (the bouncing cases are chaotic: an error
grows by orders of magnitude over each long flight). Committed in DATA (vibroimpact/reference/data/):
  <name>.trace.csv.gz   time [s], y [m], v [m/s], F [N], mode, W_plastic [J] every SAMPLE s
                        (the whole run: the test uses it up to the horizon)
  <name>.events.csv     time [s], mode before, mode after, kind: every mode change of the RTOL_TRUE run
  summary.json          per scenario: tolerances, horizon, counts, the largest energy-balance
                        residual [J] of the RTOL_TRUE run, run times
"""
import gzip
import json
import pathlib
import time

import numpy as np

from ..files import replacing, write_text
from .model import simulate
from .scenarios import SCENARIOS, STOP_TIME

DATA = pathlib.Path(__file__).resolve().parent / "data"
SAMPLE = 2e-5      # s, trace grid (90 samples per period at 560 Hz)
RTOL_TRUE = 1e-11  # the reference
RTOL_LOOSE = 1e-8  # the perturbed run that defines the horizon
EPS_Y = 1e-7       # m: 0.1 % of the excitation amplitude a = 0.1 mm, about 0.1 % of the indentations


def grid():
    return np.linspace(0.0, STOP_TIME, int(round(STOP_TIME / SAMPLE)) + 1)


def horizon(t, y_true, y_loose, eps=EPS_Y):
    """First sample time at which |y_true - y_loose| > eps (the whole run if never). Also how long
    the FMU stays on the reference (vibroimpact compare, vibroimpact bench)."""
    bad = np.nonzero(np.abs(y_true - y_loose) > eps)[0]
    return float(t[bad[0]]) if len(bad) else float(t[-1])


def transitions(events):
    """Counts of each mode change 'before->after' in events (t, before, after, ...)."""
    counts = {}
    for e in events:
        counts[f"{e[1]}->{e[2]}"] = counts.get(f"{e[1]}->{e[2]}", 0) + 1
    return dict(sorted(counts.items()))


def write_trace(path, t, r):
    cols = np.column_stack([t, r.y, r.v, r.F, r.mode, r.W_plastic])
    with replacing(path, "wt", opener=gzip.open) as out:
        out.write("time,y,v,F,mode,W_plastic\n")
        for row in cols:
            out.write(f"{row[0]:.6g},{row[1]:.12e},{row[2]:.12e},{row[3]:.12e},{int(row[4])},{row[5]:.9e}\n")


def write_events(path, events):
    with replacing(path) as out:
        out.write("time,mode_before,mode_after,kind\n")
        for t, a, b, kind in events:
            out.write(f"{t:.15e},{a},{b},{kind}\n")


def generate(name, out=DATA):
    scenario = SCENARIOS[name]
    t = grid()
    t0 = time.perf_counter()
    true = simulate(scenario.full, STOP_TIME, rtol=RTOL_TRUE, t_eval=t)
    t1 = time.perf_counter()
    loose = simulate(scenario.full, STOP_TIME, rtol=RTOL_LOOSE, t_eval=t)
    t2 = time.perf_counter()
    write_trace(out / f"{name}.trace.csv.gz", t, true)
    write_events(out / f"{name}.events.csv", true.events)
    h = horizon(t, true.y, loose.y)
    info = dict(rtol_true=RTOL_TRUE, rtol_loose=RTOL_LOOSE, eps_y=EPS_Y, sample=SAMPLE, horizon=h,
                n_impacts=int(true.n_impacts[-1]), n_impacts_loose=int(loose.n_impacts[-1]),
                n_events=len(true.events), n_events_loose=len(loose.events),
                transitions=transitions(true.events), transitions_loose=transitions(loose.events),
                F_max=float(true.F.max()), W_plastic_end=float(true.W_plastic[-1]),
                energy_residual_max=float(np.abs(true.energy_residual()).max()),
                seconds_true=round(t1 - t0, 2), seconds_loose=round(t2 - t1, 2))
    print(f"{name}: horizon {1e3 * h:.1f} ms, {info['n_impacts']} impacts ({info['n_impacts_loose']} at rtol "
          f"{RTOL_LOOSE:g}), {info['n_events']} mode changes, {info['seconds_true']} s + {info['seconds_loose']} s")
    return info


def update(names, out):
    """generate() each of names into the folder out, and its entries of out/summary.json (the others kept)."""
    path = out / "summary.json"
    summary = json.loads(path.read_text()) if path.exists() else {}
    for name in names:
        summary[name] = generate(name, out)
    write_text(path, json.dumps({k: summary[k] for k in SCENARIOS if k in summary}, indent=1) + "\n")
