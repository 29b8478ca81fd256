"""Before a sweep hands anything to Dask: one FMU instance in this process, initialized with the fixed
start values and each corner of the grid (every combination of each grid's first and last value), so
that options the FMU refuses are said at once and in the FMU's words, not once per point in sweep.csv.
"""
import tempfile

from . import spec as _spec
from .point import OUTPUT_NAMES, FMUFiles, Instance


def output_vrs(interface):
    """Value reference by name of the variables a point reads; a SpecError naming any the FMU lacks."""
    missing = [n for n in OUTPUT_NAMES if n not in interface.variables]
    if missing:
        raise _spec.SpecError(f"the FMU lacks the variables the sweep reads: {', '.join(missing)}")
    return {n: interface.variables[n].vr for n in OUTPUT_NAMES}


def label(values):
    return ", ".join(f"{n}={x:g}" if isinstance(x, float) else f"{n}={x}" for n, x in values.items())


class NotHere(Exception):
    """The FMU's binary does not load in this process (an FMU for the workers' platform only)."""


def probe(sweep, interface, fmu_path):
    """[(corner, the FMU's reason)] of the corners whose initialization fails. A SpecError with the
    first reason when every corner fails: then every point would. NotHere when the FMU cannot be
    loaded here."""
    from fmpy import extract
    vrs = output_vrs(interface)
    fixed = _spec.value_entries(interface, sweep.fixed)
    corners = _spec.corners(sweep)
    failed = []
    with tempfile.TemporaryDirectory() as tmp:
        files = FMUFiles(extract(fmu_path, unzipdir=tmp), interface.guid, interface.model_identifier, vrs)
        try:
            slave = files.slave()
        except Exception as e:   # no binary for this platform, a library that does not load
            raise NotHere(str(e)) from None
        try:
            for corner in corners:
                inst = None
                try:
                    inst = Instance(slave, vrs)
                    inst.start(fixed + _spec.value_entries(interface, corner))
                except Exception as e:   # the FMU's own words when it gave any
                    failed.append((corner, inst.error(str(e)) if inst is not None else str(e)))
                finally:
                    if inst is not None:
                        inst.free()
        finally:
            slave.freeLibrary()
    if failed and len(failed) == len(corners):
        corner, reason = failed[0]
        where = f"at every corner of the grid, so every point would fail; at {label(corner)}" if corner \
            else "with the --set values, so every point would fail"
        raise _spec.SpecError(f"the FMU refuses to initialize {where}: {reason}")
    return failed
