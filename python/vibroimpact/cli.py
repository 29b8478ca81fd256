"""The command `vibroimpact` (also `python -m vibroimpact`): one subcommand per job, each with --help."""
import argparse
import importlib
import sys

# name: (module, function, what it does)
COMMANDS = {
    "paper": ("paper", "main", "simulate the paper's scenarios: CSV files and figures (results/)"),
    "rolling": ("rolling", "main", "the wheel rolling over a corrugated rail at three speeds (results/rolling/)"),
    "sweep": ("sweep.command", "main", "parameter sweeps on Dask: statistics and Poincare samples per point"),
    "diagrams": ("diagrams", "main", "frequency response and bifurcation diagrams, up and down sweeps (results/sweeps/)"),
    "bench": ("bench", "main", "speed against accuracy of the FMU's solvers (doc/bench/)"),
    "bench-sweep": ("sweep.bench", "main", "wall time of a sweep with and without Dask"),
    "compare": ("compare", "main", "the FMU against the committed reference on every scenario (a table)"),
    "me-cost": ("me", "main", "Model Exchange in fmpy against co-simulation: error and CPU time (doc/model-exchange.md)"),
    "reference": ("reference.generate", "main", "regenerate the reference traces from the independent model"),
    "wplastic": ("wplastic", "main", "where the plastic work is negative after a Johnson yield (closed forms)"),
    "fmi3": ("fmi3_report", "main", "the FMI 3.0 FMU's early returns on every scenario against the reference (a table)"),
    "path": (None, None, "print the path of the FMU the commands use (vibroimpact.fmu_path())"),
}


def parser():
    width = max(map(len, COMMANDS))
    p = argparse.ArgumentParser(
        prog="vibroimpact", formatter_class=argparse.RawDescriptionHelpFormatter,
        description="VibroImpact: the FMU of dynamic unilateral elasto-plastic contact, its reference model, "
                    "sweeps, figures and benchmark.",
        epilog="commands:\n" + "\n".join(f"  {n:{width}}  {text}" for n, (_, _, text) in COMMANDS.items())
        + "\n\n`vibroimpact COMMAND --help` describes each. The FMU: $VI_FMU when set, else the one installed in the "
          "package (pip install .), else build/VibroImpact.fmu of the development checkout.")
    p.add_argument("command", choices=list(COMMANDS), metavar="COMMAND", help="one of the commands below")
    p.add_argument("args", nargs=argparse.REMAINDER, help="the command's own options")
    return p


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv:
        parser().print_help()
        return 2
    a = parser().parse_args(argv[:1])   # the command's own options may look like ours (--help)
    module, function, _ = COMMANDS[a.command]
    if module is None:
        from .fmi3 import fmu3_path
        from .fmu import fmu_path
        ap = argparse.ArgumentParser(prog="vibroimpact path", description=COMMANDS["path"][2])
        ap.add_argument("--fmi3", action="store_true", help="the FMI 3.0 FMU beside it (vibroimpact.fmi3.fmu3_path())")
        try:
            print(fmu3_path() if ap.parse_args(argv[1:]).fmi3 else fmu_path())
        except FileNotFoundError as e:
            print(f"vibroimpact: {e}", file=sys.stderr)
            return 1
        return 0
    run = getattr(importlib.import_module(f"{__package__}.{module}"), function)
    try:
        return run(argv[1:]) or 0
    except FileNotFoundError as e:   # no FMU: say how to get one, without a traceback
        print(f"vibroimpact {a.command}: {e}", file=sys.stderr)
        return 1
    except BrokenPipeError:          # the output's reader left (| head)
        sys.stderr.close()
        return 1
