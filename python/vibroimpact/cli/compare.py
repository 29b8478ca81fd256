"""The FMU on every scenario against the committed reference traces (vibroimpact/reference/data/).

    vibroimpact compare [--rtol R] [--solver S]      prints a Markdown table, one row per scenario

The FMU runs at the tolerance of the reference trace (1e-11) unless --rtol says otherwise, one
doStep per reference sample, with every mode change recorded with its exact time
(vibroimpact.compare).
"""
import argparse

from ..compare import RTOL_FMU, Runner, compare
from ..fmu import Relay, check_start
from ..reference.generate import RTOL_TRUE
from ..reference.scenarios import SCENARIOS


def parser():
    p = argparse.ArgumentParser(prog="vibroimpact compare", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--rtol", type=float, default=RTOL_FMU,
                   help=f"the FMU's relative tolerance (default {RTOL_FMU:g}; the FMU's own default is 1e-6)")
    p.add_argument("--solver", type=int, default=None, help="the FMU's `solver` value: 1 bdf, 2 adams, 3 dop853 "
                   "(default: the FMU's default)")
    return p


def main(argv=None):
    a = parser().parse_args(argv)
    rtol, solver = a.rtol, a.solver
    first = next(iter(SCENARIOS))
    check_start({**SCENARIOS[first].full, **({} if solver is None else {"solver": solver})},
                f"the FMU refuses {first} at --rtol {rtol:g}" + ("" if solver is None else f", --solver {solver}"),
                tolerance=rtol)
    runner = Runner()
    relay = Relay("compare")   # each scenario's warnings once, on stderr
    print(f"FMU at rtol {rtol:g} (solver {solver or 'default'}), reference at rtol {RTOL_TRUE:g}\n")
    print("| scenario | horizon [ms] | FMU within 0.1 um until [ms] | max abs(y - y_ref) [m] | max abs(F - F_ref)/max F "
          "| mode changes compared | max event time diff [s] | impacts FMU / ref (0.1 s) |")
    print("|---|---|---|---|---|---|---|---|")
    for name in SCENARIOS:
        c = compare(name, runner, rtol, solver, relay)
        same = "same" if c["events_fmu"] == c["events_ref"] else "DIFFERENT"
        print(f"| {name} | {1e3 * c['horizon']:.1f} | {1e3 * c['agrees_until']:.1f} | {c['dy']:.1e} | {c['dF_rel']:.1e} "
              f"| {len(c['events_ref'])} ({same}) | {c['event_dt']:.1e} | {c['n_impacts']} / {c['n_impacts_ref']} |")
