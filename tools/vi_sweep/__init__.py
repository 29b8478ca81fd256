"""Parameter sweeps of the VibroImpact FMU on Dask (tools/sweep.py is the command).

spec    the FMU's interface, the --set/--grid options, the grid product and the chains (client side)
point   one chain of points on one FMU instance, statistics on the fly, Poincare samples (worker side)
engine  Dask: local cluster or scheduler, the FMU shipped to the workers, progress, CSV files
plots   the PNGs of one sweep, and the response / bifurcation drawings the diagrams reuse
"""
import importlib as _importlib
import sys as _sys

# Client.upload_file reloads this package on a long-lived cluster; reload the worker-side modules
# with it, so that a worker never runs an older sweep's code.
for _name in ("point", "worker"):
    if f"{__name__}.{_name}" in _sys.modules:
        _importlib.reload(_sys.modules[f"{__name__}.{_name}"])
