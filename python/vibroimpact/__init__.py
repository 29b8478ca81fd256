"""VibroImpact: an FMU (FMI 2.0 and 3.0) of dynamic unilateral elasto-plastic contact (Kowalska 2002),
and the Python around it: the independent reference model, the sweeps on Dask, the figures and the
benchmark, behind one command, `vibroimpact` (vibroimpact.cli).

    import vibroimpact
    vibroimpact.fmu_path()     # the FMU: $VI_FMU, the one installed in this package, or build/ of a checkout

The library (no module here reads command-line options or writes where it is not told):
  fmu, fmi3        access to the FMU, FMI 2.0 and 3.0: paths, values, initialization, logs; FMI 3.0 steps
  reference        the independent reference model, closed forms, the scenarios
  paper, rolling, diagrams, early_return, compare, me
                   the runs behind the commands, and their tables
  sweep            parameter sweeps on Dask
  bench            the benchmark's measurements
  plotting         the figures (matplotlib, imported when a figure is made)
  failure          how a command says what went wrong
The commands are vibroimpact.cli, one module each.
"""
import importlib as _importlib
import sys as _sys

# The sweep ships this package's worker-side code to Dask workers with Client.upload_file, which reloads
# the package on a long-lived worker: reload the modules a worker runs with it, so that it never runs an
# older sweep's code.
for _name in ("fmu", "sweep.point", "sweep.worker"):
    if f"{__name__}.{_name}" in _sys.modules:
        _importlib.reload(_sys.modules[f"{__name__}.{_name}"])

from .fmu import ENV, Logged, MessageLog, build_dir, fmu_path, initialize, set_value  # noqa: E402

__all__ = ["ENV", "Logged", "MessageLog", "build_dir", "fmu_path", "initialize", "set_value"]
