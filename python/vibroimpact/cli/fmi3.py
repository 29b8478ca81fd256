"""The FMI 3.0 FMU's early return on every scenario, against the committed reference (doc/fmi3.md).

    vibroimpact fmi3 [--step H] [--rtol R]       prints a Markdown table, one row per scenario

Each scenario runs through the FMI 3.0 Co-Simulation interface (fmpy's FMU3Slave) at the
reference's tolerance, on communication points every H seconds, three ways: plain steps; with
earlyReturnAllowed (vibroimpact.fmi3.run_to_events: a step ends at the first change of mode, the
next goes on from there); and with Event Mode too. The table gives the reference's mode changes
within the scenario's predictable horizon, the early returns there, whether their sequence of
(mode before, mode after) is the reference's, the largest |t_stop - t_ref|, whether Event Mode
gave the same stops bit for bit, and the wall time of the whole run each way.
"""
import argparse
import math

from fmpy import extract, read_model_description

from ..compare import EVENT_DT, SUMMARY, read_events
from ..early_return import run
from ..failure import CommandError
from ..fmu import Relay, fmu3_path
from ..reference.scenarios import SCENARIOS, STOP_TIME


def main(argv=None):
    ap = argparse.ArgumentParser(prog="vibroimpact fmi3", description=__doc__.splitlines()[0])
    ap.add_argument("--step", type=float, default=1e-3, help="communication step [s] (default 1e-3)")
    ap.add_argument("--rtol", type=float, default=1e-11, help="the tolerance given to fmi3EnterInitializationMode")
    a = ap.parse_args(argv)
    if not (math.isfinite(a.step) and 0 < a.step <= STOP_TIME):
        ap.error(f"--step is the communication step in s, in (0, {STOP_TIME:g}] (got {a.step:g})")
    path = fmu3_path()
    md = read_model_description(str(path))
    if md.fmiVersion != "3.0":
        raise CommandError(f"{path} is an FMI {md.fmiVersion} FMU; this command runs the FMI 3.0 build "
                           "(vibroimpact path --fmi3)")
    unzipdir = extract(str(path))
    run(md, unzipdir, next(iter(SCENARIOS)), None, a.rtol, True, True)   # the FMU accepts --rtol
    relay = Relay("fmi3")   # each scenario's warnings once, on stderr
    print(f"FMI 3.0 FMU {path}, rtol {a.rtol:g}, communication step {a.step:g} s\n")
    print("| scenario | reference changes within the horizon | early returns there | same sequence | "
          "max abs(t - t_ref) [s] | Event Mode: same stops | wall plain / early return / + Event Mode [s] |")
    print("|---|---|---|---|---|---|---|")
    for name in SCENARIOS:
        h = SUMMARY[name]["horizon"]
        ref = [e for e in read_events(name) if e[0] <= h - EVENT_DT]
        _, wall_plain = run(md, unzipdir, name, a.step, a.rtol, False, False, relay)
        stops, wall_er = run(md, unzipdir, name, a.step, a.rtol, True, False, relay)
        stops_ev, wall_ev = run(md, unzipdir, name, a.step, a.rtol, True, True, relay)
        got = [e for e in stops if e[0] <= h - EVENT_DT]
        same = [e[1:] for e in got] == [e[1:] for e in ref]
        dt = max((abs(x[0] - y[0]) for x, y in zip(got, ref)), default=0.0)
        print(f"| {name} | {len(ref)} | {len(got)} | {'yes' if same else 'NO'} | {dt:.1e} | "
              f"{'yes' if stops_ev == stops else 'NO'} | {wall_plain:.2f} / {wall_er:.2f} / {wall_ev:.2f} |")
    return 0
