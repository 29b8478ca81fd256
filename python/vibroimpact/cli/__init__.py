"""The command `vibroimpact` (also `python -m vibroimpact`): one subcommand per job, each with --help.

The command layer: each command is a module of this package with main(argv) that reads its options
(argparse), calls the library modules of vibroimpact (which read no options and write only where they
are told) and prints. This module dispatches to them.
"""
import argparse
import importlib
import sys

from ..failure import describe

# name: (module of this package, what it does)
COMMANDS = {
    "paper": ("paper", "simulate the paper's scenarios: CSV files and figures (results/)"),
    "rolling": ("rolling", "the wheel rolling over a corrugated rail at three speeds (results/rolling/)"),
    "sweep": ("sweep", "parameter sweeps on Dask: statistics and Poincare samples per point (results/sweep/)"),
    "diagrams": ("diagrams", "frequency response and bifurcation diagrams, up and down sweeps (results/diagrams/)"),
    "bench": ("bench", "speed against accuracy of the FMU's solvers (results/bench/)"),
    "bench-sweep": ("bench_sweep", "wall time of a sweep with and without Dask"),
    "compare": ("compare", "the FMU against the committed reference on every scenario (a table)"),
    "me-cost": ("me_cost", "Model Exchange in fmpy against co-simulation: error and CPU time (doc/model-exchange.md)"),
    "reference": ("reference", "recompute the reference traces from the independent model (results/reference/)"),
    "laws": ("laws", "what each contact law and option changes and costs, scene by scene (results/laws/)"),
    "wplastic": ("wplastic", "where Johnson's unloading curves return more than the loading took (closed forms)"),
    "energy": ("energy", "the energy balance of every contact law in every interface (doc/model.md)"),
    "fmi3": ("fmi3", "the FMI 3.0 FMU's early returns on every scenario against the reference (a table)"),
    "path": ("path", "print the path of the FMU the commands use (vibroimpact.fmu_path())"),
}


def parser():
    width = max(map(len, COMMANDS))
    p = argparse.ArgumentParser(
        prog="vibroimpact", formatter_class=argparse.RawDescriptionHelpFormatter,
        description="VibroImpact: the FMU of dynamic unilateral elasto-plastic contact, its reference model, "
                    "sweeps, figures and benchmark.",
        epilog="commands:\n" + "\n".join(f"  {n:{width}}  {text}" for n, (_, text) in COMMANDS.items())
        + "\n\n`vibroimpact COMMAND --help` describes each. A command that cannot go on says why in one line "
          "and exits non-zero; --debug (anywhere on the line) shows the traceback instead.\n"
          "The FMU: $VI_FMU when set, else the one installed in the package (pip install .), "
          "else build/VibroImpact.fmu of the development checkout.")
    p.add_argument("command", choices=list(COMMANDS), metavar="COMMAND", help="one of the commands below")
    p.add_argument("args", nargs=argparse.REMAINDER, help="the command's own options")
    return p


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    debug = "--debug" in argv
    argv = [x for x in argv if x != "--debug"]   # no command has an option of that name
    if not argv:
        parser().print_help()
        return 2
    a = parser().parse_args(argv[:1])   # the command's own options may look like ours (--help)
    module, _ = COMMANDS[a.command]
    try:
        return importlib.import_module(f"{__name__}.{module}").main(argv[1:]) or 0
    except BrokenPipeError:          # the output's reader left (| head)
        sys.stderr.close()
        return 1
    except KeyboardInterrupt:
        if debug:
            raise
        print(f"vibroimpact {a.command}: interrupted", file=sys.stderr)
        return 130
    except Exception as e:
        if debug:
            raise
        print(f"vibroimpact {a.command}: {describe(e)}", file=sys.stderr)
        return 1
