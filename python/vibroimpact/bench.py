"""Speed against accuracy: the benchmark suite of the FMU's solvers (figures, not a test).

    vibroimpact bench [--repeat N] [--quick] [--out DIR] [--build DIR]

Prints Markdown tables and writes DIR/bench.md and the PNG plots (DIR: doc/bench by default). It
needs a CMake build folder (default: the folder of vibroimpact.fmu_path(), build/ in a checkout)
with the FMU and the programs vi_bench_driver and vi_bench_rk4 (tools/bench_driver.c, bench_rk4.c).

What it runs (the FMU binary through tools/bench_driver.c, dlopen'ed from C with no Python in the
loop, unless said otherwise; CPU times are the minimum of N runs, default 5, because other
processes disturb single runs; instruction counts would be steadier but do not compare with Python):

1. Work-precision, every solver (bdf, adams, dop853), rtol 1e-3 ... 1e-12 in half decades, on
     fig4b   Johnson, Y = 6e8 Pa, bouncing and plastic (paper Fig. 4b), 40 ms;
     fig5a   Hertz, 100 Hz, sustained contact (paper Fig. 5a), 0.1 s;
     drop    Hertz drop P = g = 0, v0 = -0.1 m/s, one impact, 3 ms: closed form (energy
             1/2 m v^2 + 2/5 K delta^2.5 conserved, so the peak indentation is
             (15 m v0^2 / (16 E* sqrt(R*)))^(2/5), and restitution 1),
   communication step 1e-5 s, y read after every step. The error of fig4b and fig5a is the largest
   |y - y_ref| over the communication points divided by the range of y_ref, y_ref from dop853 at
   rtol 1e-14 (checked against adams at 1e-13 and the Python reference at 1e-12: the table prints
   their distance). The error of the drop is the larger of the relative energy error over the run
   and |restitution - 1|.
   In the same run: the Python reference (vibroimpact.reference.model, SciPy DOP853 with
   event location) at its own tolerances, and a fixed-step RK4 without event location
   (tools/bench_rk4.c: guards looked at only at step ends) from the communication step down, until
   it reaches the accuracy or its run would take more than RK4_CAP_S.
2. Matched accuracy: per solver the loosest rtol from which on (for it and every tighter rtol) the
   error stays within 1e-5 (fig4b: of the motion range; the error is not monotone in rtol on a
   chaotic trace), its CPU time, the Python reference's at its own such rtol, and the ratio; the
   RK4 step that reaches the same accuracy (if any does below the cost cap); the limit: the rhs
   evaluations the run needed times the cost of one rhs evaluation alone, and the ratio to it.
3. The importer's share: the matched runs again through fmpy (FMU2Slave, doStep and getReal in
   Python), against the C driver.
4. Cost per fmi2DoStep at communication steps 1e-7 ... 1e-3 s (fig4b, 10 ms, matched rtol).
5. Cost against simulated time (fig4b at matched rtol, 10 ms ... 1 s) and against the number of
   impacts (Hertz, a = 0.1 mm, f = 500 ... 8000 Hz, one impact per period, 0.1 s).
6. Memory per instance (heap after initialization) and the cost of taking an FMU state before
   every step (a master ready to roll back), with the error that follows from it (CVODE restarts at
   every checkpoint; the one-step method carries its continuation).
7. A stiff configuration (a light mass on a stiff contact), where the explicit method pays.
8. The work bound: fig4b in one fmi2DoStep of 1e6 s, CPU until fmi2Discard and where it stopped.
"""
import argparse
import os
import pathlib
import subprocess
import tempfile
import time

import numpy as np

from .fmu import NAME, build_dir
from .reference.closed_forms import effective
from .reference.scenarios import SCENARIOS

PROGRAMS = ("vi_bench_driver", "vi_bench_rk4")

SOLVERS = {"bdf": 1, "adams": 2, "dop853": 3}
RTOLS = [10.0 ** (-e / 2) for e in range(6, 25)]  # 1e-3 ... 1e-12, half decades
H_COMM = 1e-5
BOUND = 1e-5
RK4_STEPS = [1e-5, 5e-6, 2e-6, 1e-6, 5e-7, 2e-7, 1e-7, 5e-8, 2e-8, 1e-8, 5e-9, 2e-9]  # divide H_COMM
RK4_CAP_S = 20.0  # skip RK4 steps whose run would take longer than this
CASES = {
    "fig4b": dict(params=SCENARIOS["fig4b"].full, t_stop=0.04, title="Fig. 4b (Johnson, bouncing, plastic), 40 ms"),
    "fig5a": dict(params=SCENARIOS["fig5a"].full, t_stop=0.1, title="Fig. 5a (Hertz, sustained contact), 0.1 s"),
    "drop": dict(params=dict(contact_model=1, init=2, P=0.0, g=0.0, v0=-0.1, a=0.0), t_stop=0.003,
                 title="Hertz drop, one impact, closed form, 3 ms"),
}


# ---- the FMU and the programs ---------------------------------------------------------------------

class Fmu:
    def __init__(self, workdir, build):
        from fmpy import extract, read_model_description
        self.build = build
        self.path = build / NAME
        self.md = read_model_description(str(self.path))
        self.unzip = extract(str(self.path), unzipdir=str(workdir / "fmu"))
        self.so = str(pathlib.Path(self.unzip) / "binaries" / "linux64" / "VibroImpact.so")
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.vrs = ",".join(str(self.vars[n].valueReference) for n in ("y", "v", "F", "delta", "mode", "n_impacts"))
        self.work = workdir

    def arg(self, name, value):
        v = self.vars[name]
        kind = {"Real": "r", "Integer": "i", "Enumeration": "i", "Boolean": "b"}[v.type]
        return f"{kind}{v.valueReference}={float(value)!r}"

    def run(self, params, t_stop, rtol, repeat, h=H_COMM, extra=()):
        """-> (dict of the driver's figures, samples (t, y, v, F, delta, mode))."""
        out = self.work / "samples.bin"
        cmd = [str(self.build / "vi_bench_driver"), self.so, self.md.guid, repr(t_stop), repr(h), str(repeat),
               repr(rtol), "--vrs", self.vrs, "--out", str(out), *extra]
        cmd += [self.arg(k, v) for k, v in params.items()]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode:
            return None, None
        words = r.stdout.split()
        return {k: float(v) for k, v in zip(words[::2], words[1::2])}, np.fromfile(out).reshape(-1, 6)


def rk4(build, params, t_stop, h, repeat, work):
    out = work / "rk4.bin"
    cmd = [str(build / "vi_bench_rk4"), repr(t_stop), repr(H_COMM), repr(h), str(repeat), str(out)]
    cmd += [f"{k}={float(v)!r}" for k, v in params.items()]
    r = subprocess.run(cmd, capture_output=True, text=True, check=True)
    words = r.stdout.split()
    return {k: float(v) for k, v in zip(words[::2], words[1::2])}, np.fromfile(out).reshape(-1, 6)


def rhs_ns(build, params):
    cmd = [str(build / "vi_bench_rk4"), "--rhs-cost", "2000000"] + [f"{k}={float(v)!r}" for k, v in params.items()]
    return float(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout.split()[1])


def python_reference(params, t_stop, rtol, repeat):
    from .reference.model import simulate
    t = H_COMM * np.arange(1, round(t_stop / H_COMM) + 1)
    best, r = np.inf, None
    for _ in range(repeat):
        c = time.process_time()
        r = simulate(params, t_stop, rtol=rtol, t_eval=t)
        best = min(best, time.process_time() - c)
    return best, np.column_stack([r.t, r.y, r.v, r.F, r.delta, r.mode])


def through_fmpy(fmu, params, t_stop, rtol, repeat):
    """CPU time of the same run driven from Python by fmpy (FMU2Slave: doStep and getReal per step)."""
    from fmpy.fmi2 import FMU2Slave
    vr_y = fmu.vars["y"].valueReference
    n = round(t_stop / H_COMM)
    best = np.inf
    for _ in range(repeat):
        c = time.process_time()
        s = FMU2Slave(guid=fmu.md.guid, unzipDirectory=fmu.unzip, modelIdentifier="VibroImpact", instanceName="b")
        s.instantiate()
        s.setupExperiment(tolerance=rtol, startTime=0.0)
        s.enterInitializationMode()
        for k, v in params.items():
            var = fmu.vars[k]
            if var.type == "Real":
                s.setReal([var.valueReference], [float(v)])
            elif var.type == "Boolean":
                s.setBoolean([var.valueReference], [bool(v)])
            else:
                s.setInteger([var.valueReference], [int(v)])
        s.exitInitializationMode()
        for k in range(n):
            s.doStep(k * H_COMM, H_COMM)
            s.getReal([vr_y])
        s.terminate()
        s.freeInstance()
        best = min(best, time.process_time() - c)
    return best


# ---- errors -----------------------------------------------------------------------------------------

def trace_error(samples, ref):
    return float(np.abs(samples[:, 1] - ref[:, 1]).max() / np.ptp(ref[:, 1]))


def drop_error(samples, params):
    """Larger of the relative energy error over the run and |restitution - 1| (closed forms)."""
    e = effective(params)
    m, K, v0 = e["m"], e["K"], params["v0"]
    v, d = samples[:, 2], samples[:, 4]
    energy = 0.5 * m * v ** 2 + 0.4 * K * np.maximum(d, 0.0) ** 2.5
    e0 = 0.5 * m * v0 ** 2
    return float(max(np.abs(energy / e0 - 1).max(), abs(v[-1] / -v0 - 1)))


def matched(rtols, errors):
    """The loosest rtol from which on every tighter rtol has error <= BOUND (None if none)."""
    ok = None
    for r, e in sorted(zip(rtols, errors)):  # tightest first
        if e is None or not e <= BOUND:
            break
        ok = r
    return ok


# ---- the suite ------------------------------------------------------------------------------------

def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact bench", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeat", type=int, default=5, metavar="N", help="runs per figure; the fastest counts (default 5)")
    p.add_argument("--quick", action="store_true", help="every other tolerance only")
    p.add_argument("--out", type=pathlib.Path, default=pathlib.Path("doc", "bench"), metavar="DIR",
                   help="output folder (default doc/bench)")
    p.add_argument("--build", type=pathlib.Path, default=None, metavar="DIR",
                   help="the CMake build folder (default: the folder of vibroimpact.fmu_path())")
    a = p.parse_args(argv)
    build = a.build or build_dir()
    missing = [str(build / f) for f in (NAME,) + PROGRAMS if not (build / f).is_file()]
    if missing:
        p.error(f"missing {', '.join(missing)}: build them with cmake -S . -B build && cmake --build build "
                "in a checkout, or name the build folder with --build")
    run_suite(a.repeat, a.quick, a.out, build)


def run_suite(repeat, quick, outdir, build):
    outdir.mkdir(parents=True, exist_ok=True)
    lines = []

    def out(text=""):
        print(text, flush=True)
        lines.append(text)

    rtols = RTOLS[::2] if quick else RTOLS
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        fmu = Fmu(work, build)
        out(f"Machine: {os.cpu_count()} cores; CPU times are the minimum of {repeat} runs.\n")
        results = {}
        for case, spec in CASES.items():
            p, T = spec["params"], spec["t_stop"]
            if case == "drop":
                err = lambda s: drop_error(s, p)  # noqa: E731
                ref_note = "closed form"
            else:
                _, ref = fmu.run({**p, "solver": 3}, T, 1e-14, 1)
                _, ref2 = fmu.run({**p, "solver": 2}, T, 1e-13, 1)
                _, ref3 = python_reference(p, T, 1e-12, 1)
                err = lambda s, ref=ref: trace_error(s, ref)  # noqa: E731
                ref_note = (f"dop853 at rtol 1e-14; adams at 1e-13 is {trace_error(ref2, ref):.1e} from it, the "
                            f"Python reference at 1e-12 {trace_error(ref3, ref):.1e}")
            res = dict(fmu={}, py={}, rk4={}, ref_note=ref_note)
            for name, solver in SOLVERS.items():
                for rtol in rtols:
                    fig, s = fmu.run({**p, "solver": solver}, T, rtol, repeat)
                    res["fmu"][name, rtol] = (fig["cpu_s"], err(s), fig["rhs"]) if fig else (None, None, None)
            for rtol in rtols:
                cpu, s = python_reference(p, T, rtol, max(1, repeat // 2))
                res["py"][rtol] = (cpu, err(s))
            for h in RK4_STEPS:
                if T / h * 60e-9 > RK4_CAP_S:  # about 60 ns per RK4 step
                    break
                fig, s = rk4(build, p, T, h, 1, work)
                res["rk4"][h] = (fig["cpu_s"], err(s))
                if err(s) <= BOUND:
                    break
            res["rhs_ns"] = rhs_ns(build, p)
            results[case] = res
            report_case(out, case, spec, res, rtols)
        report_matched(out, results, rtols)
        importer_share(out, fmu, results, repeat)
        per_step_cost(out, fmu, results, repeat)
        scaling(out, fmu, results, repeat)
        memory_and_checkpoints(out, fmu, results, repeat)
        stiff(out, fmu, repeat)
        work_bound(out, fmu)
        plots(results, rtols, outdir)
    (outdir / "bench.md").write_text("\n".join(lines) + "\n")
    print(f"\nwritten: {outdir / 'bench.md'} and the PNG plots in {outdir}")


def fmt(x, spec=".2f"):
    return "-" if x is None else format(x, spec)


def report_case(out, case, spec, res, rtols):
    out(f"### {spec['title']}\n")
    out(f"Error against: {res['ref_note']}. Communication step {H_COMM:g} s. CPU [ms] / error:\n")
    out("| rtol | " + " | ".join(SOLVERS) + " | Python reference |")
    out("|---|" + "---|" * (len(SOLVERS) + 1))
    for rtol in rtols:
        cells = []
        for name in SOLVERS:
            cpu, e, _ = res["fmu"][name, rtol]
            cells.append("failed" if cpu is None else f"{1e3 * cpu:.2f} / {e:.1e}")
        cpu, e = res["py"][rtol]
        cells.append(f"{1e3 * cpu:.0f} / {e:.1e}")
        out(f"| {rtol:.0e} | " + " | ".join(cells) + " |")
    out("")
    rk = ", ".join(f"h = {h:g} s: {1e3 * c:.1f} ms / {e:.1e}" for h, (c, e) in res["rk4"].items())
    out(f"Fixed-step RK4 without event location (CPU / error): {rk}.\n")


def matched_row(res, name, rtols):
    errors = [res["fmu"][name, r][1] for r in rtols]
    r = matched(rtols, errors)
    if r is None:
        return None
    cpu, e, rhs = res["fmu"][name, r]
    return r, cpu, e, rhs


def report_matched(out, results, rtols):
    out(f"### At matched accuracy (error within {BOUND:g} from that rtol on)\n")
    out("| case | solver | rtol | CPU [ms] | error | Python reference: rtol, CPU [ms] | speed-up | "
        "rhs evaluations x cost alone [ms] | CPU / that limit | RK4 without events |")
    out("|---|---|---|---|---|---|---|---|---|---|")
    for case, res in results.items():
        pr = matched(rtols, [res["py"][r][1] for r in rtols])
        py_cpu = res["py"][pr][0] if pr else None
        hits = sorted(((h, c) for h, (c, e) in res["rk4"].items() if e <= BOUND), reverse=True)
        last_h = min(res["rk4"]) if res["rk4"] else None
        rk = (f"h = {hits[0][0]:g} s, {1e3 * hits[0][1]:.0f} ms" if hits else
              f"not within {BOUND:g} at h = {last_h:g} s (error {res['rk4'][last_h][1]:.1e})" if last_h else "-")
        res["matched"] = {}
        for name in SOLVERS:
            m = matched_row(res, name, rtols)
            if m is None:
                out(f"| {case} | {name} | none | | | | | | | {rk} |")
                continue
            r, cpu, e, rhs = m
            res["matched"][name] = r
            limit = rhs * res["rhs_ns"] * 1e-9
            speed = f"{py_cpu / cpu:.0f}x" if py_cpu else "-"
            out(f"| {case} | {name} | {r:.0e} | {1e3 * cpu:.2f} | {e:.1e} | "
                f"{fmt(pr, '.0e')}, {fmt(py_cpu and 1e3 * py_cpu, '.0f')} | {speed} | "
                f"{1e3 * limit:.3f} | {cpu / limit:.1f} | {rk} |")
    out("\nOne rhs evaluation alone: " + ", ".join(f"{c} {r['rhs_ns']:.1f} ns" for c, r in results.items()) + ".\n")


def best_rtol(results, name, case="fig4b"):
    return results[case]["matched"].get(name, 1e-10)


def importer_share(out, fmu, results, repeat):
    out("### The importer's share (fig4b, 40 ms, 4000 steps, y read after each)\n")
    out("| solver | rtol | C driver [ms] | fmpy FMU2Slave [ms] | importer's share |")
    out("|---|---|---|---|---|")
    p = CASES["fig4b"]["params"]
    for name, solver in SOLVERS.items():
        r = best_rtol(results, name)
        fig, _ = fmu.run({**p, "solver": solver}, 0.04, r, repeat)
        py = through_fmpy(fmu, {**p, "solver": solver}, 0.04, r, max(1, repeat // 2))
        out(f"| {name} | {r:.0e} | {1e3 * fig['cpu_s']:.2f} | {1e3 * py:.1f} | {100 * (1 - fig['cpu_s'] / py):.0f} % |")
    out("")


def per_step_cost(out, fmu, results, repeat):
    out("### Cost per fmi2DoStep against the communication step (fig4b, 10 ms, y read after each step)\n")
    steps = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3]
    out("| solver | rtol | " + " | ".join(f"h = {h:g} s [us]" for h in steps) + " |")
    out("|---|---|" + "---|" * len(steps))
    p = CASES["fig4b"]["params"]
    results["per_step"] = {}
    for name, solver in SOLVERS.items():
        r = best_rtol(results, name)
        cells = []
        for h in steps:
            fig, _ = fmu.run({**p, "solver": solver}, 0.01, r, repeat, h=h)
            results["per_step"][name, h] = fig["step_us"]
            cells.append(f"{fig['step_us']:.3g}")
        out(f"| {name} | {r:.0e} | " + " | ".join(cells) + " |")
    out("\nAt 1e-7 s nearly every step lies inside the solver's last internal step: its cost is the "
        "interpolation, the step's bookkeeping and reading y.\n")


def scaling(out, fmu, results, repeat):
    p = CASES["fig4b"]["params"]
    spans = [0.01, 0.03, 0.1, 0.3, 1.0]
    out("### Cost against simulated time (fig4b, matched rtol) [ms]\n")
    out("| solver | " + " | ".join(f"{T:g} s" for T in spans) + " | per simulated second |")
    out("|---|" + "---|" * (len(spans) + 1))
    results["time"] = {}
    for name, solver in SOLVERS.items():
        r = best_rtol(results, name)
        cpus = []
        for T in spans:
            fig, _ = fmu.run({**p, "solver": solver}, T, r, max(1, repeat // 2))
            cpus.append(fig["cpu_s"])
        results["time"][name] = cpus
        slope = np.polyfit(spans, cpus, 1)[0]
        out(f"| {name} | " + " | ".join(f"{1e3 * c:.1f}" for c in cpus) + f" | {1e3 * slope:.1f} |")
    out("")
    freqs = [500.0, 1000.0, 2000.0, 4000.0, 8000.0]
    out("### Cost against the number of impacts (Hertz, a = 0.1 mm, 0.1 s, rtol 1e-8)\n")
    out("| solver | " + " | ".join(f"f = {f:g} Hz" for f in freqs) + " | per impact [us] |")
    out("|---|" + "---|" * (len(freqs) + 1))
    results["impacts"] = {}
    for name, solver in SOLVERS.items():
        cells, pts = [], []
        for f in freqs:
            fig, _ = fmu.run(dict(contact_model=1, a=1e-4, f=f, solver=solver), 0.1, 1e-8, max(1, repeat // 2))
            pts.append((fig["impacts"], fig["cpu_s"]))
            cells.append(f"{int(fig['impacts'])} impacts, {1e3 * fig['cpu_s']:.1f} ms")
        results["impacts"][name] = pts
        slope = np.polyfit([a for a, _ in pts], [c for _, c in pts], 1)[0]
        out(f"| {name} | " + " | ".join(cells) + f" | {1e6 * slope:.1f} |")
    out("")


def memory_and_checkpoints(out, fmu, results, repeat):
    p = CASES["fig4b"]["params"]
    _, ref = fmu.run({**p, "solver": 3}, 0.04, 1e-14, 1)
    out("### Memory per instance and the cost of an FMU state before every step (fig4b, 40 ms)\n")
    out("| solver | rtol | heap per instance [bytes] | CPU [ms] | with fmi2GetFMUstate before every step [ms] | "
        "error without / with |")
    out("|---|---|---|---|---|---|")
    for name, solver in SOLVERS.items():
        r = best_rtol(results, name)
        a, sa = fmu.run({**p, "solver": solver}, 0.04, r, repeat)
        b, sb = fmu.run({**p, "solver": solver}, 0.04, r, repeat, extra=["--checkpoint"])
        out(f"| {name} | {r:.0e} | {int(a['heap_bytes'])} | {1e3 * a['cpu_s']:.2f} | {1e3 * b['cpu_s']:.2f} | "
            f"{trace_error(sa, ref):.1e} / {trace_error(sb, ref):.1e} |")
    out("\nCVODE restarts at every state taken (its history cannot be copied out), so a state before every "
        "step costs a restart per step; dop853's state carries its continuation and costs a copy.\n")


def stiff(out, fmu, repeat):
    p = dict(contact_model=1, m=1e-7, a=1e-4)
    out("### A stiff configuration: m = 1e-7 kg under the default load, a = 0.1 mm at 560 Hz (the contact "
        "rings at about 10 MHz, the motion follows the platform), 10 ms, rtol 1e-6, step 1e-4 s\n")
    out("| solver | CPU [ms] | rhs evaluations |")
    out("|---|---|---|")
    for name, solver in SOLVERS.items():
        fig, _ = fmu.run({**p, "solver": solver}, 0.01, 1e-6, max(1, repeat // 2), h=1e-4)
        out(f"| {name} | {1e3 * fig['cpu_s']:.2f} | {int(fig['rhs'])} |")
    out("\nThe explicit method is held to steps its stability allows (about 1/(2 pi 10 MHz)); the implicit "
        "CVODE methods are not.\n")


def work_bound(out, fmu):
    p = CASES["fig4b"]["params"]
    out("### The work bound: fig4b in one fmi2DoStep of 1e6 s\n")
    out("| solver | CPU until fmi2Discard [s] | fmi2LastSuccessfulTime [s] |")
    out("|---|---|---|")
    for name, solver in SOLVERS.items():
        fig, _ = fmu.run({**p, "solver": solver}, 1e6, 1e-6, 1, h=1e6)
        out(f"| {name} | {fig['cpu_s']:.2f} | {fig['discard_at']:.6g} |")
    out("")


def plots(results, rtols, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    colors = dict(bdf="tab:blue", adams="tab:orange", dop853="tab:green")
    fig, axes = plt.subplots(1, 3, figsize=(16, 5))
    for ax, (case, res) in zip(axes, (c for c in results.items() if c[0] in CASES)):
        for name in SOLVERS:
            pts = [(res["fmu"][name, r][0], res["fmu"][name, r][1]) for r in rtols if res["fmu"][name, r][0]]
            ax.loglog([1e3 * c for c, _ in pts], [max(e, 1e-16) for _, e in pts], "o-", color=colors[name],
                      label=f"FMU {name}")
        pts = [res["py"][r] for r in rtols]
        ax.loglog([1e3 * c for c, _ in pts], [max(e, 1e-16) for _, e in pts], "s--", color="k",
                  label="Python reference (SciPy DOP853)")
        if res["rk4"]:
            pts = list(res["rk4"].values())
            ax.loglog([1e3 * c for c, _ in pts], [max(e, 1e-16) for _, e in pts], "x:", color="tab:red",
                      label="RK4, no event location")
        ax.axhline(BOUND, color="gray", lw=0.8)
        ax.set_title(CASES[case]["title"], fontsize=10)
        ax.set_xlabel("CPU [ms]")
        ax.set_ylabel("error" + (" / range of y" if case != "drop" else " (energy, restitution)"))
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(outdir / "work_precision.png", dpi=90)
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.5))
    steps = sorted({h for (_, h) in results["per_step"]})
    for name in SOLVERS:
        axes[0].loglog(steps, [results["per_step"][name, h] for h in steps], "o-", color=colors[name], label=name)
        axes[1].plot([0.01, 0.03, 0.1, 0.3, 1.0], [1e3 * c for c in results["time"][name]], "o-", color=colors[name],
                     label=name)
        pts = results["impacts"][name]
        axes[2].plot([a for a, _ in pts], [1e3 * c for _, c in pts], "o-", color=colors[name], label=name)
    axes[0].set(xlabel="communication step [s]", ylabel="CPU per fmi2DoStep [us]", title="fig4b, 10 ms")
    axes[1].set(xlabel="simulated time [s]", ylabel="CPU [ms]", title="fig4b, matched rtol")
    axes[2].set(xlabel="impacts", ylabel="CPU [ms]", title="Hertz, 0.1 s, rtol 1e-8")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(outdir / "cost.png", dpi=90)
    plt.close(fig)
