"""Dask runs the sweep: a LocalCluster by default, or a running scheduler by address.

The FMU goes to the workers inside a worker plugin (its bytes; each worker extracts it once into
its own local directory, which Dask removes when the plugin or the worker goes). The worker-side
code of this package is shipped by value (cloudpickle), so a remote worker needs fmpy and numpy but
not this repository. One task per chain (see spec.chains): an independent point is a chain of one.
Results come back as plain data and are put in grid order, so the files do not depend on which
worker ran what or when.
"""
import csv
import hashlib
import json
import logging
import math
import os
import shutil
import sys
import uuid
import zipfile

import cloudpickle
from distributed import Client, LocalCluster, as_completed, get_worker
from distributed.diagnostics.plugin import WorkerPlugin

from . import point as _point
from . import spec as _spec
from .point import OUTPUT_NAMES, STATS

# ship this package's code with the tasks: remote workers need fmpy and numpy, not the repository
cloudpickle.register_pickle_by_value(sys.modules[__package__])

CONNECT_TIMEOUT_S = 60   # to reach a given scheduler, and for its first worker to be there
STATUS_COLUMNS = ["status", "message"]
POINCARE_COLUMNS = ["period", "t", "delta", "v"]


class FMUPlugin(WorkerPlugin):
    """Carries the FMU to each worker and extracts it there once."""

    def __init__(self, fmu_bytes, guid, model_identifier, vrs):
        self.fmu_bytes, self.guid, self.model_identifier, self.vrs = fmu_bytes, guid, model_identifier, vrs
        # one name per sweep: two sweeps on one cluster never share (or remove) each other's copy
        self.name = f"vi-sweep-fmu-{hashlib.sha256(fmu_bytes).hexdigest()[:12]}-{uuid.uuid4().hex[:8]}"
        self.dir = self.files = None

    def setup(self, worker):
        self.dir = os.path.join(worker.local_directory, self.name)
        os.makedirs(self.dir, exist_ok=True)
        fmu = os.path.join(self.dir, "model.fmu")
        with open(fmu, "wb") as fh:
            fh.write(self.fmu_bytes)
        unzipdir = os.path.join(self.dir, "unzipped")
        with zipfile.ZipFile(fmu) as z:
            z.extractall(unzipdir)
        self.files = _point.FMUFiles(unzipdir, self.guid, self.model_identifier, self.vrs)

    def teardown(self, worker):
        if self.dir:
            shutil.rmtree(self.dir, ignore_errors=True)


def _chain_task(plugin_name, fixed, per_point, timing, topic, chain_id):
    worker = get_worker()
    files = worker.plugins[plugin_name].files

    def progress(k):
        if topic:
            worker.log_event(topic, (chain_id, k))

    return _point.run_chain(files, fixed, per_point, timing, progress if len(per_point) > 1 else None)


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


def run(sweep, interface, fmu_path, workers=None, scheduler=None, progress=True):
    """Run every point; return [(values, result)] in grid order."""
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

    cluster = None
    if scheduler:
        client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S}s")
        try:
            client.wait_for_workers(1, timeout=CONNECT_TIMEOUT_S)
        except Exception:
            client.close()
            raise RuntimeError(f"no worker joined the scheduler {scheduler} within {CONNECT_TIMEOUT_S} s") from None
    else:
        cluster = LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        client = Client(cluster)
    bar = _Bar(len(points), progress)
    done_in_chain = [0] * len(work)
    try:
        if topic:
            def on_event(event):
                chain_id, _ = event[1]
                done_in_chain[chain_id] += 1
                bar.update(1)
            client.subscribe_topic(topic, on_event)
        client.register_plugin(plugin)
        futures = {}
        for c, (indices, fixed, per_point) in enumerate(work):
            fut = client.submit(_chain_task, plugin.name, fixed, per_point, timing, topic, c,
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
            bar.update(len(indices) - done_in_chain[c])
            done_in_chain[c] = len(indices)
    finally:
        bar.close()
        try:
            if topic:
                client.unsubscribe_topic(topic)
            client.unregister_worker_plugin(plugin.name)
        except Exception:
            pass
        client.close()
        if cluster is not None:
            cluster.close()
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
