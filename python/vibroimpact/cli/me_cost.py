"""vibroimpact me-cost: Model Exchange in fmpy (CVode) against the FMU's co-simulation on paper
scenarios, error against the reference and CPU time (doc/model-exchange.md). Prints a Markdown table."""
import argparse

from ..fmu import Relay, check_start
from ..me import COST_RTOLS, COST_SCENARIOS, call_cost, cost
from ..reference.scenarios import SCENARIOS


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact me-cost", description="Model Exchange in fmpy (CVode) against the "
                                "FMU's co-simulation on paper scenarios: error against the reference and CPU time "
                                "(doc/model-exchange.md)")
    p.add_argument("--scenarios", nargs="+", default=list(COST_SCENARIOS), choices=list(SCENARIOS), metavar="NAME",
                   help=f"default: {' '.join(COST_SCENARIOS)}; one of {', '.join(SCENARIOS)}")
    p.add_argument("--rtols", nargs="+", type=float, default=list(COST_RTOLS))
    p.add_argument("--repeat", type=int, default=3, help="runs per case; the fastest counts (default 3)")
    a = p.parse_args(argv)
    if a.repeat < 1:
        p.error("--repeat is at least 1")
    for rtol in a.rtols:
        check_start({"rtol": rtol}, f"the FMU refuses --rtols {rtol:g}")
    print("| scenario | rtol | ME: max abs(y - y_ref) [m] | ME: CPU [s] | ME mode changes | CS: max abs(y - y_ref) [m] "
          "| CS: CPU [s] | CPU ME / CS |")
    print("|---|---|---|---|---|---|---|---|")
    rows = cost(a.scenarios, a.rtols, repeat=a.repeat, warned=Relay("me-cost"))
    for i in range(0, len(rows), 2):
        (name, _, rtol, e_me, c_me, same), (_, _, _, e_cs, c_cs, _) = rows[i], rows[i + 1]
        print(f"| {name} | {rtol:g} | {e_me:.1e} | {c_me:.3f} | {same} | {e_cs:.1e} | {c_cs:.3f} | {c_me / c_cs:.1f} |")
    print(f"\none derivative evaluation through fmpy (fmi2SetTime, fmi2SetContinuousStates, fmi2GetDerivatives from "
          f"Python): {1e6 * call_cost():.1f} us")
    return 0
