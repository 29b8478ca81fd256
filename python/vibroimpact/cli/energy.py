"""The energy balance of every contact law, from the FMU's outputs (doc/model.md, section 3, "Energy").

    vibroimpact energy [--rtol R] [--variants NAME ...] [--vehicle-track]

Prints a Markdown table: for each variant of vibroimpact.energy.VARIANTS and each scene (drop, fig4b),
the largest error of kinetic energy + E_contact + W_dissipated against the work of the platform and of
the load, relative to the energy exchanged, in Co-Simulation and Model Exchange (fmpy's CVode), FMI 2.0
and 3.0; samples every 1 us over 10 ms. --vehicle-track adds the contact FMU's balance inside the
vehicle-track example's co-simulation (needs Track.fmu and Vehicle.fmu beside the FMU, as a checkout's
build/ has them). A warning the FMU logs in a run is printed to stderr once, after the run's name.
"""
import argparse

from .. import energy
from ..fmu import Relay


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact energy", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--rtol", type=float, default=1e-9, help="the FMU's rtol and the importer's (default 1e-9)")
    p.add_argument("--variants", nargs="+", choices=list(energy.VARIANTS), metavar="NAME",
                   help="only these variants (default: all)")
    p.add_argument("--vehicle-track", action="store_true", help="also the vehicle-track example's co-simulation")
    a = p.parse_args(argv)
    if not 1e-14 <= a.rtol <= 1e-2:
        p.error(f"--rtol must lie in [1e-14, 1e-2] (got {a.rtol:g})")
    heads = [f"{'CS' if i == 'CoSimulation' else 'ME'} FMI {v}.0" for i, v in energy.INTERFACES]
    print(f"Balance error / energy exchanged (rtol {a.rtol:g}):\n")
    print("| variant | scene | " + " | ".join(heads) + " |")
    print("|---|---|" + "---|" * len(heads))
    relay = Relay("energy")   # the FMU's warnings, once per run, on stderr
    for variant, scene, errors in energy.table(a.variants, rtol=a.rtol, warned=relay):
        print(f"| {variant} | {scene} | " + " | ".join(f"{e:.1e}" for e in errors) + " |")
    if a.vehicle_track:
        print("\n| variant | vehicle-track, CS FMI 2.0 |\n|---|---|")
        for variant in a.variants or energy.VARIANTS:
            error = energy.vehicle_track_balance(
                variant, warned=lambda texts: relay(f"{variant} vehicle-track", texts))[0]   # noqa: B023
            print(f"| {variant} | {error:.1e} |")
