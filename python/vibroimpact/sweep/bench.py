"""What `vibroimpact bench-sweep` times: a sweep in one process without Dask (the baseline), and the
same sweep on a Dask cluster.

The sweep: Hertz, a = 0.1 mm, f from 100 to 600 Hz (the paper's data; most points bounce), each
point 0.1 s with a 10 us communication step. Times are the best of --repeat runs; the cluster's
start-up is timed apart. "Cores kept busy" is the workers' CPU time (time.process_time on each
worker, through Client.run) over the wall time: on a machine shared with other jobs it shows how
much of the cluster the sweep actually got, and the wall times move by 10 % or more between runs.
"""
import time

from . import engine, spec


def make_sweep(interface, n, stop_time, step):
    fixed = dict(spec.parse_set(interface, s) for s in ("contact_model=hertz", "a=1e-4"))
    return spec.Sweep(fixed=fixed, grids=[spec.parse_grid(interface, f"f=100:600:{n}")], stop_time=stop_time,
                      step=step)


def baseline(fmu, sweep, interface):
    """The same chains, one after the other, in this process (no Dask): (wall time [s], results)."""
    t = time.perf_counter()
    rows = engine.run_here(sweep, interface, fmu)
    return time.perf_counter() - t, [r for _, r in rows]


def on_cluster(client, fmu, sweep, interface, repeat):
    """The sweep `repeat` times on a connected cluster: ([(wall [s], the workers' CPU [s])], the last results)."""
    times, res = [], None
    for _ in range(repeat):
        cpu0 = sum(client.run(time.process_time).values())
        t = time.perf_counter()
        res = engine.run(sweep, interface, fmu, client=client, progress=False)
        times.append((time.perf_counter() - t, sum(client.run(time.process_time).values()) - cpu0))
    return times, res
