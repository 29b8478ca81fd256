"""The FMU on every scenario against the committed reference traces (vibroimpact/reference/data/);
`vibroimpact compare` prints the figures as a table.

The FMU runs at RTOL_FMU = 1e-11, the tolerance of the reference trace, through FMU2Slave: one
doStep per reference sample, with logEvents on so that every mode change inside a step is recorded
with its exact time. The tests (fmu-test/test_paper.py) assert on the figures compare() returns.
"""
import csv
import gzip
import json

import numpy as np

from .fmu import Logged, fmu_path, initialize
from .reference.generate import DATA, horizon, transitions
from .reference.scenarios import SCENARIOS

SUMMARY = json.loads((DATA / "summary.json").read_text())
RTOL_FMU = 1e-11
EVENT_DT = 1e-6  # s: event times are compared up to the horizon minus this
REALS = ["y", "v", "F", "W_plastic"]
INTEGERS = ["mode", "n_impacts"]


def read_trace(name):
    with gzip.open(DATA / f"{name}.trace.csv.gz", "rt") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def read_events(name):
    """(t, mode before, mode after) of the reference's mode changes."""
    with open(DATA / f"{name}.events.csv") as f:
        return [(float(r["time"]), int(r["mode_before"]), int(r["mode_after"])) for r in csv.DictReader(f)]


def fmu_events(messages, contact="lower"):
    """(t, before, after) of every mode change of one contact at a state event the FMU logged, from the
    event log's lines "event t=<t> kind=guard guard=<g> mode=<a>-><b> ..." (doc/using.md, "The event
    log"); events that keep the mode are skipped. contact: "lower" (the platform's, the only one
    without the upper stop, whose lines name none) or "upper" (the lines ending in contact=upper)."""
    out = []
    for _, category, text in messages:
        if category != "logEvents" or not text.startswith("event "):
            continue
        fields = dict(word.split("=", 1) for word in text.split()[1:])
        if fields.get("contact", "lower") != contact:
            continue
        if fields["kind"] == "guard":
            before, after = (int(x) for x in fields["mode"].split("->"))
            if before != after:
                out.append((float(fields["t"]), before, after))
    return out


class Runner:
    """Simulates scenarios with the FMU on the reference's sample grid."""

    def __init__(self, fmu=None, unzipdir=None):
        from fmpy import extract, read_model_description
        fmu = str(fmu or fmu_path())
        self.md = read_model_description(fmu)
        self.unzipdir = unzipdir or extract(fmu)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}

    def run(self, name, t, rtol=RTOL_FMU, solver=None, warned=None):
        """-> ({output name: samples at t}, [(t, before, after) of each mode change]); solver: the
        `solver` enumeration value (None: the FMU's default); warned: called with (name, the FMU's
        warnings) when it logged any (a fmu.Relay)."""
        inst = Logged(self.md, self.unzipdir, name=name)
        s, vr = inst.instantiate(logging=True), self.vr
        s.setDebugLogging(True, ["logEvents"])
        params = {**SCENARIOS[name].full, **({} if solver is None else {"solver": solver})}
        initialize(s, vr, params, tolerance=rtol, start_time=float(t[0]), stop_time=float(t[-1]))
        reals, integers = [vr[n] for n in REALS], [vr[n] for n in INTEGERS]
        out = np.empty((len(t), len(REALS) + len(INTEGERS)))
        for k in range(len(t)):
            if k:
                s.doStep(t[k - 1], t[k] - t[k - 1])
            out[k] = s.getReal(reals) + s.getInteger(integers)
        s.terminate()
        s.freeInstance()
        if warned is not None and inst.warnings():
            warned(name, inst.warnings())
        return dict(zip(REALS + INTEGERS, out.T)), fmu_events(inst.messages)


def compare(name, runner, rtol=RTOL_FMU, solver=None, warned=None):
    """Figures of the FMU against the reference for one scenario (all over the horizon unless said);
    warned: as Runner.run's."""
    ref, info = read_trace(name), SUMMARY[name]
    fmu, events = runner.run(name, ref["time"], rtol, solver, **({} if warned is None else {"warned": warned}))
    t, h = ref["time"], info["horizon"]
    within = t <= h
    err_y = np.abs(fmu["y"] - ref["y"])
    ref_events = [e for e in read_events(name) if e[0] <= h - EVENT_DT]
    # the force jumps at some mode changes (paper unloading, stick): event times agree to EVENT_DT, so
    # samples that close to a reference event may lie on either side of it and are not compared for F
    near_event = np.zeros_like(within)
    for e in read_events(name):
        near_event |= np.abs(t - e[0]) <= EVENT_DT
    force_compared = within & ~near_event
    fmu_ev = [e for e in events if e[0] <= h - EVENT_DT]
    return dict(
        horizon=h,
        agrees_until=horizon(t, ref["y"], fmu["y"]),  # FMU within EPS_Y of the reference
        dy=float(err_y[within].max()),
        dF_rel=float(np.abs(fmu["F"] - ref["F"])[force_compared].max() / np.abs(ref["F"]).max()),
        dW_rel=float(np.abs(fmu["W_plastic"] - ref["W_plastic"])[within].max() / max(np.abs(ref["W_plastic"]).max(),
                                                                                   1e-300)),
        events_ref=[e[1:] for e in ref_events], events_fmu=[e[1:] for e in fmu_ev],
        event_dt=max((abs(a[0] - b[0]) for a, b in zip(fmu_ev, ref_events)), default=0.0),
        transitions=transitions(events), transitions_ref=info["transitions"],
        n_impacts=int(fmu["n_impacts"][-1]), n_impacts_ref=info["n_impacts"],
        fmu=fmu, ref=ref)
