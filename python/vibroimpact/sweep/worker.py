"""What runs on a Dask worker: the plugin that brings the FMU there, and the task that runs one chain.

The client sends this code to the scheduler and the workers with Client.upload_file
(engine.package_zip), so a worker needs fmpy, numpy and distributed, not this repository. This module
and point.py import nothing from the package but vibroimpact.fmu, which imports fmpy only when used
(the scheduler imports them to read the task graph).
"""
import hashlib
import os
import shutil
import signal
import uuid
import zipfile

from distributed import get_worker
from distributed.diagnostics.plugin import WorkerPlugin

from . import point as _point


class FMUPlugin(WorkerPlugin):
    """Carries the FMU to each worker and extracts it there once, into the worker's local directory
    (removed with the plugin or the worker)."""

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


def leave_ctrl_c_to_the_client():
    """In a local cluster's worker process: ignore SIGINT. A terminal's Ctrl-C reaches every process of
    its group; the client then stops the workers itself, and they print no traceback of their own."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def chain_task(plugin_name, fixed, per_point, timing, topic, chain_id):
    """One chain (spec.chains) on this worker's copy of the FMU; reports each point on `topic`."""
    worker = get_worker()
    files = worker.plugins[plugin_name].files

    def progress(k):
        if topic:
            worker.log_event(topic, (chain_id, k))

    return _point.run_chain(files, fixed, per_point, timing, progress if len(per_point) > 1 else None)

