"""Dask runs the sweep: a LocalCluster by default, or a running scheduler by address.

The code the workers run goes to the scheduler and the workers with Client.upload_file (package_zip),
the FMU inside a worker plugin (worker.FMUPlugin), so a remote worker needs fmpy, numpy and
distributed but neither this repository nor the installed package. One task per chain (see spec.chains): an independent point is a chain of one.
Results come back as plain data and are put in grid order, so the files do not depend on which
worker ran what or when.
"""
import contextlib
import csv
import json
import logging
import math
import os
import pathlib
import sys
import tempfile
import threading
import uuid
import zipfile

from distributed import Client, LocalCluster, as_completed

from . import spec as _spec
from .point import OUTPUT_NAMES, STATS
from .worker import FMUPlugin, chain_task

SWEEP = pathlib.Path(__file__).resolve().parent
TOP = SWEEP.parent   # the vibroimpact package

STATUS_COLUMNS = ["status", "message"]
POINCARE_COLUMNS = ["period", "t", "delta", "v"]


class _Bar:
    """tqdm when it is there and wanted, else nothing."""

    def __init__(self, total, enabled):
        self.bar = None
        if enabled:
            try:
                from tqdm import tqdm
                self.bar = tqdm(total=total, unit="pt", file=sys.stderr, smoothing=0.1, dynamic_ncols=True)
            except ImportError:
                print(f"sweep: {total} points (install tqdm for a progress bar)", file=sys.stderr)

    def update(self, n):
        if self.bar is not None and n > 0:
            self.bar.update(n)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _error_results(n, message):
    return [dict({k: math.nan for k in STATS}, status="error", message=message, poincare=[]) for _ in range(n)]


def package_zip(directory):
    """What the workers run as a zip that Client.upload_file puts on the scheduler's and workers'
    path: the vibroimpact package with its helpers (fmu.py) and this subpackage, nothing else."""
    path = os.path.join(directory, "vibroimpact.zip")
    with zipfile.ZipFile(path, "w") as z:
        for f in (TOP / "__init__.py", TOP / "fmu.py", *sorted(SWEEP.glob("*.py"))):
            z.write(f, f.relative_to(TOP.parent).as_posix())
    return path


@contextlib.contextmanager
def connect(workers=None, scheduler=None, connect_timeout=60.0):
    """A Dask client: to a running scheduler (waiting at most connect_timeout seconds for it and its
    first worker) or to a new LocalCluster of `workers` single-threaded processes (default: all
    cores). This package's code is uploaded once per client."""
    cluster = None
    if scheduler:
        client = Client(scheduler, timeout=f"{connect_timeout}s")
        try:
            client.wait_for_workers(1, timeout=connect_timeout)
        except Exception:
            client.close()
            raise RuntimeError(f"no worker joined the scheduler {scheduler} within {connect_timeout} s") from None
    else:
        cluster = LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        client = Client(cluster)
    try:
        with tempfile.TemporaryDirectory() as tmp:
            client.upload_file(package_zip(tmp), load=True)
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def run(sweep, interface, fmu_path, client=None, progress=True, **connect_options):
    """Run every point on `client` (or on connect(**connect_options)); return [(values, result)] in
    grid order."""
    if client is None:
        with connect(**connect_options) as c:
            return run(sweep, interface, fmu_path, client=c, progress=progress)
    _spec.check(sweep, interface)
    with open(fmu_path, "rb") as fh:
        fmu_bytes = fh.read()
    missing = [n for n in OUTPUT_NAMES if n not in interface.variables]
    if missing:
        raise _spec.SpecError(f"the FMU lacks the variables the sweep reads: {', '.join(missing)}")
    vrs = {n: interface.variables[n].vr for n in OUTPUT_NAMES}
    plugin = FMUPlugin(fmu_bytes, interface.guid, interface.model_identifier, vrs)
    work = _spec.chains(sweep, interface)
    points = sweep.points()
    timing = dict(stop_time=sweep.stop_time, step=sweep.step, transient=sweep.transient)
    topic = f"vi-sweep-progress-{uuid.uuid4().hex}" if sweep.direction else None
    results = [None] * len(points)
    bar = _Bar(len(points), progress)
    counted = [0] * len(work)   # points of each chain the bar has shown
    lock = threading.Lock()     # the progress events arrive on the client's event loop thread

    def count(c, n):
        with lock:
            n = min(n, len(work[c][0]) - counted[c])
            counted[c] += n
            bar.update(n)

    try:
        if topic:
            client.subscribe_topic(topic, lambda event: count(event[1][0], 1))
        client.register_plugin(plugin)
        futures = {}
        for c, (indices, fixed, per_point) in enumerate(work):
            fut = client.submit(chain_task, plugin.name, fixed, per_point, timing, topic, c,
                                key=f"vi-sweep-chain-{c}-{uuid.uuid4().hex[:8]}", pure=False)
            futures[fut] = c
        for fut in as_completed(futures):
            c = futures[fut]
            indices = work[c][0]
            try:
                out = fut.result()
            except Exception as e:  # the task itself broke (not the FMU): every point says so
                out = _error_results(len(indices), f"worker task failed: {e!r}")
            for i, r in zip(indices, out):
                results[i] = r
            count(c, len(indices))
    finally:
        bar.close()
        try:
            if topic:
                client.unsubscribe_topic(topic)
            client.unregister_worker_plugin(plugin.name)
        except Exception:
            pass
    return [(values, results[i]) for i, values in points]


# ---- files ----------------------------------------------------------------------------------------
def _fmt(x):
    if isinstance(x, float):
        return "" if math.isnan(x) else repr(x)
    return str(x)


def write(out_dir, sweep, rows, argv=None):
    """DIR/sweep.csv (one row per point), DIR/poincare.csv (one row per sample), DIR/sweep.json."""
    os.makedirs(out_dir, exist_ok=True)
    names = sweep.names
    with open(os.path.join(out_dir, "sweep.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(names + STATS + STATUS_COLUMNS)
        for values, r in rows:
            stats = [r[k] if not (k == "n_impacts" and r["status"] == "ok") else int(r[k]) for k in STATS]
            w.writerow([_fmt(values[n]) for n in names] + [_fmt(x) for x in stats] + [r["status"], r["message"]])
    with open(os.path.join(out_dir, "poincare.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(names + POINCARE_COLUMNS)
        for values, r in rows:
            for k, (t, d, v) in enumerate(r["poincare"]):
                w.writerow([_fmt(values[n]) for n in names] + [k, _fmt(t), _fmt(d), _fmt(v)])
    meta = dict(command=argv, set=sweep.fixed, grids=dict(sweep.grids), log_axes=list(sweep.log_axes),
                stop_time=sweep.stop_time, step=sweep.step, transient=sweep.transient, direction=sweep.direction,
                points=len(rows), failed=sum(r["status"] != "ok" for _, r in rows))
    with open(os.path.join(out_dir, "sweep.json"), "w") as fh:
        json.dump(meta, fh, indent=1)


def read(out_dir):
    """sweep.csv and poincare.csv back as dicts of numpy arrays (numbers) / lists (text)."""
    import numpy as np

    def load(name):
        with open(os.path.join(out_dir, name), newline="") as fh:
            rows = list(csv.DictReader(fh))
        cols = {}
        for key in (rows[0].keys() if rows else []):
            vals = [r[key] for r in rows]
            try:
                cols[key] = np.array([float(v) if v != "" else np.nan for v in vals])
            except ValueError:
                cols[key] = vals
        return cols

    return load("sweep.csv"), load("poincare.csv")
