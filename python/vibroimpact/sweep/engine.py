"""Dask runs the sweep: a LocalCluster by default, or a running scheduler by address.

The code the workers run goes to the scheduler and the workers with Client.upload_file (package_zip),
the FMU inside a worker plugin (worker.FMUPlugin), so a remote worker needs fmpy, numpy and
distributed but neither this repository nor the installed package. One task per chain (see spec.chains): an independent point is a chain of one.
Each chain's rows are appended to the files as it finishes (Output), so an interrupted sweep keeps
what it finished; when the sweep ends the files are rewritten in grid order, so they do not depend on
which worker ran what or when.
"""
import contextlib
import csv
import hashlib
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

from ..files import replacing
from . import spec as _spec
from .point import STATS
from .probe import output_vrs
from .worker import FMUPlugin, chain_task, leave_ctrl_c_to_the_client

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
    path: the vibroimpact package with its helpers (fmu.py, failure.py) and this subpackage, nothing else."""
    path = os.path.join(directory, "vibroimpact.zip")
    with zipfile.ZipFile(path, "w") as z:
        for f in (TOP / "__init__.py", TOP / "fmu.py", TOP / "failure.py", *sorted(SWEEP.glob("*.py"))):
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
        # silence_logs CRITICAL: a task's error comes back through its future, and a worker whose
        # heartbeat meets the scheduler closing (an interrupted sweep) would print a traceback of its own
        cluster = LocalCluster(n_workers=workers or os.cpu_count(), threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.CRITICAL)
        client = Client(cluster)
    try:
        with tempfile.TemporaryDirectory() as tmp:
            client.upload_file(package_zip(tmp), load=True)
        if cluster is not None:
            client.run(leave_ctrl_c_to_the_client)
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def run(sweep, interface, fmu_path, client=None, progress=True, done=(), on_chain=None, **connect_options):
    """Run the points on `client` (or on connect(**connect_options)); return [(values, result)] in
    grid order, result None for a point not run. done: indices of points finished before; a chain
    all of whose points are done is not run (a continuation chain with one point left runs whole).
    on_chain(indices, results) is called on this thread as each chain finishes."""
    if client is None:
        with connect(**connect_options) as c:
            return run(sweep, interface, fmu_path, client=c, progress=progress, done=done, on_chain=on_chain)
    _spec.check(sweep, interface)
    with open(fmu_path, "rb") as fh:
        fmu_bytes = fh.read()
    plugin = FMUPlugin(fmu_bytes, interface.guid, interface.model_identifier, output_vrs(interface))
    done = set(done)
    work = [c for c in _spec.chains(sweep, interface) if not set(c[0]) <= done]
    points = sweep.points()
    timing = dict(stop_time=sweep.stop_time, step=sweep.step, transient=sweep.transient)
    topic = f"vi-sweep-progress-{uuid.uuid4().hex}" if sweep.direction else None
    results = [None] * len(points)
    bar = _Bar(sum(len(c[0]) for c in work), progress)
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
            if on_chain is not None:
                on_chain(indices, out)
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


def run_here(sweep, interface, fmu_path):
    """The same points as run(), one chain after the other in this process (no Dask): [(values,
    result)] in grid order. For small sweeps and the benchmark's baseline."""
    from fmpy import extract

    from .point import OUTPUT_NAMES, FMUFiles, run_chain
    _spec.check(sweep, interface)
    timing = dict(stop_time=sweep.stop_time, step=sweep.step, transient=sweep.transient)
    points = sweep.points()
    results = [None] * len(points)
    with tempfile.TemporaryDirectory() as tmp:
        files = FMUFiles(extract(fmu_path, unzipdir=tmp), interface.guid, interface.model_identifier,
                         {n: interface.variables[n].vr for n in OUTPUT_NAMES})
        for indices, fixed, per_point in _spec.chains(sweep, interface):
            for i, r in zip(indices, run_chain(files, fixed, per_point, timing)):
                results[i] = r
    return [(values, results[i]) for i, values in points]


# ---- files ----------------------------------------------------------------------------------------
def _fmt(x):
    if isinstance(x, float):
        return "" if math.isnan(x) else repr(x)
    return str(x)


def write(out_dir, sweep, rows, argv=None):
    """DIR/sweep.csv (one row per point), DIR/poincare.csv (one row per sample), DIR/sweep.json of a
    finished sweep's [(values, result)] in grid order."""
    out = Output(out_dir, sweep, argv=argv)
    out.add(range(len(rows)), [r for _, r in rows])
    out.finish()


class Output:
    """DIR/sweep.csv and DIR/poincare.csv as the points finish, and DIR/sweep.json.

    add() takes each point's rows, then appends and flushes them (its Poincare rows first, so a row in
    sweep.csv means its samples are there too); finish() rewrites both files in grid order from the
    rows taken, so that a row once on disk stays whenever an interruption comes. resume=True keeps the rows
    of an earlier run of the same sweep (same settings and FMU, else a SpecError) in DIR; `done` holds
    their point indices. Without resume the files of DIR are left as they are until the first point
    is added: a run that fails or is interrupted before it replaces no finished sweep with an empty one."""

    def __init__(self, out_dir, sweep, argv=None, fmu_sha256=None, resume=False):
        self.dir, self.names, self.points = out_dir, sweep.names, sweep.points()
        self.argv = argv
        self.settings = dict(set=sweep.fixed, grids=dict(sweep.grids), log_axes=list(sweep.log_axes),
                             stop_time=sweep.stop_time, step=sweep.step, transient=sweep.transient,
                             direction=sweep.direction, fmu_sha256=fmu_sha256)
        self.rows = {}   # point index -> (sweep.csv row, [poincare.csv rows]), as text
        os.makedirs(out_dir, exist_ok=True)
        self._files = self._writers = None   # opened by _start
        if resume:
            self._resume()
            self._start()

    def _start(self):
        """The files of this run: the rows taken so far (resume's), sweep.json, both CSV files open to append."""
        self._rewrite()
        self._write_meta(complete=False)
        self._files = [open(self._path(n), "a", newline="") for n in ("sweep.csv", "poincare.csv")]
        self._writers = [csv.writer(fh) for fh in self._files]

    @property
    def done(self):
        return set(self.rows)

    def _path(self, name):
        return os.path.join(self.dir, name)

    def _resume(self):
        if not os.path.isfile(self._path("sweep.json")):
            return   # nothing there yet: every point runs
        with open(self._path("sweep.json")) as fh:
            old = json.load(fh)
        mine = json.loads(json.dumps(self.settings))
        differ = [k for k in mine if old.get(k) != mine[k]]
        if differ:
            raise _spec.SpecError(f"--resume: {self.dir} holds a sweep with other settings ({', '.join(differ)}): "
                                  "give the options it was started with, or another --out")
        index = {tuple(v[n] for n in self.names): i for i, v in self.points}
        for name, header in (("sweep.csv", self.names + STATS + STATUS_COLUMNS),
                             ("poincare.csv", self.names + POINCARE_COLUMNS)):
            with open(self._path(name), newline="") as fh:
                reader = csv.reader(fh)
                if next(reader, None) != header:
                    raise _spec.SpecError(f"--resume: {self._path(name)} is not this sweep's file: use another --out")
                for row in reader:   # bounded by the file
                    i = index.get(tuple(float(x) for x in row[:len(self.names)]))
                    if name == "sweep.csv" and i is not None and len(row) == len(header):
                        self.rows[i] = (row, [])
                    elif name == "poincare.csv" and i in self.rows:
                        if row[len(self.names)] == "0":   # period 0: a point written again (a chain rerun)
                            self.rows[i][1].clear()
                        self.rows[i][1].append(row)

    def add(self, indices, results):
        if self._files is None:
            self._start()
        sw, pc = self._writers
        for i, r in zip(indices, results):
            values = self.points[i][1]
            keys = [_fmt(values[n]) for n in self.names]
            stats = [r[k] if not (k == "n_impacts" and r["status"] == "ok") else int(r[k]) for k in STATS]
            row = keys + [_fmt(x) for x in stats] + [r["status"], r["message"]]
            samples = [keys + [k, _fmt(t), _fmt(d), _fmt(v)] for k, (t, d, v) in enumerate(r["poincare"])]
            self.rows[i] = (row, samples)  # first: a row on disk is one finish() rewrites, whenever Ctrl-C comes
            pc.writerows(samples)
            self._files[1].flush()
            sw.writerow(row)
            self._files[0].flush()

    def failures(self):
        """[(values, message)] of the finished points that failed, in grid order."""
        return [(self.points[i][1], self.rows[i][0][-1]) for i in sorted(self.rows) if self.rows[i][0][-2] != "ok"]

    def finish(self):
        """Both files in grid order (each replaced at once) and sweep.json; True when every point is there.
        Nothing written when no point was added and none kept (DIR as it was; False)."""
        if self._files is None:
            if not self.points:
                self._start()
            else:
                return False
        for fh in self._files:
            fh.close()
        self._rewrite()
        complete = len(self.rows) == len(self.points)
        self._write_meta(complete)
        return complete

    def _rewrite(self):
        order = sorted(self.rows)
        for name, header, rows in (("sweep.csv", self.names + STATS + STATUS_COLUMNS,
                                    ([self.rows[i][0]] for i in order)),
                                   ("poincare.csv", self.names + POINCARE_COLUMNS, (self.rows[i][1] for i in order))):
            with open(self._path(name + ".tmp"), "w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(header)
                for block in rows:
                    w.writerows(block)
            os.replace(self._path(name + ".tmp"), self._path(name))

    def _write_meta(self, complete):
        meta = dict(command=self.argv, **self.settings, points=len(self.points), finished=len(self.rows),
                    failed=len(self.failures()), complete=complete)
        with replacing(self._path("sweep.json")) as fh:
            json.dump(meta, fh, indent=1)


def file_sha256(path):
    with open(path, "rb") as fh:
        return hashlib.sha256(fh.read()).hexdigest()


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
