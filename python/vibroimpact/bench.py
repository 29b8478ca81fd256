"""Speed against accuracy: the measurements of `vibroimpact bench` (the command: vibroimpact.cli.bench,
whose help says what each section runs). run_suite runs them and writes the report and the plots
into the folder it is given.

It needs a CMake build folder with the FMU and the programs vi_bench_driver, vi_bench_rk4 and
vi_bench_profile (tools/bench_*.c), which build on Linux with the GNU C library (dlopen, mallinfo2).
"""
import os
import pathlib
import subprocess
import tempfile
import time

import numpy as np

from . import bench_rolling, plotting
from .failure import out_dir
from .files import write_text
from .fmu import NAME
from .reference.closed_forms import effective
from .reference.scenarios import SCENARIOS

PROGRAMS = ("vi_bench_driver", "vi_bench_rk4", "vi_bench_profile")

SOLVERS = {"bdf": 1, "adams": 2, "dop853": 3, "auto": 4}
AUTO_TARGET = 1.3  # auto's CPU at matched accuracy against the fastest other solver's
FLOOR_TARGET_NS = {"dop853": 40.0, "bdf": 150.0, "adams": 150.0}  # a step inside the last internal step, y read
FLOOR_H = 1e-9  # communication step of the floor runs: a thousand and more per internal step
BUDGET_S = 2.0  # a work-precision run is not repeated once its runs took this much CPU
RTOLS = [10.0 ** (-e / 2) for e in range(6, 25)]  # 1e-3 ... 1e-12, half decades
H_COMM = 1e-5
BOUND = 1e-5
RK4_STEPS = [1e-5, 5e-6, 2e-6, 1e-6, 5e-7, 2e-7, 1e-7, 5e-8, 2e-8, 1e-8, 5e-9, 2e-9]  # divide H_COMM
RK4_CAP_S = 20.0  # skip RK4 steps whose run would take longer than this
STEPS_S = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3]  # communication steps of the cost per step (fig4b)
SPANS_S = [0.01, 0.03, 0.1, 0.3, 1.0]  # simulated times of the cost against simulated time (fig4b)
FREQS_HZ = [500.0, 1000.0, 2000.0, 4000.0, 8000.0]  # excitations of the cost against impacts
DPI = 90
PROFILE_ROWS = [10 ** 4, 10 ** 5, 10 ** 6]
PROFILE_TARGET_US = 0.3  # per row, and no slower than numpy.loadtxt reading the same file
CASES = {
    "fig4b": dict(params=SCENARIOS["fig4b"].full, t_stop=0.04, title="Fig. 4b (Johnson, bouncing, plastic), 40 ms"),
    "fig5a": dict(params=SCENARIOS["fig5a"].full, t_stop=0.1, title="Fig. 5a (Hertz, sustained contact), 0.1 s"),
    "drop": dict(params=dict(contact_model=1, init=2, P=0.0, g=0.0, v0=-0.1, a=0.0), t_stop=0.003,
                 title="Hertz drop, one impact, closed form, 3 ms"),
    "stiff": dict(params=dict(contact_model=1, m=1e-7, a=1e-4), t_stop=0.01,
                  title="A stiff contact: m = 1e-7 kg under the default load, a = 0.1 mm at 560 Hz, 10 ms"),
}


# ---- the FMU and the programs ---------------------------------------------------------------------

class Fmu:
    def __init__(self, workdir, build):
        from fmpy import extract, read_model_description
        self.build = build
        self.path = build / NAME
        self.md = read_model_description(str(self.path))
        self.unzip = extract(str(self.path), unzipdir=str(workdir / "fmu"))
        from fmpy import platform, sharedLibraryExtension
        self.so = str(pathlib.Path(self.unzip) / "binaries" / platform
                      / (self.md.coSimulation.modelIdentifier + sharedLibraryExtension))
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.vrs = ",".join(str(self.vars[n].valueReference) for n in ("y", "v", "F", "delta", "mode", "n_impacts"))
        self.work = workdir

    def arg(self, name, value):
        v = self.vars[name]
        if v.type == "String":
            return f"s{v.valueReference}={value}"
        kind = {"Real": "r", "Integer": "i", "Enumeration": "i", "Boolean": "b"}[v.type]
        return f"{kind}{v.valueReference}={float(value)!r}"

    def run(self, params, t_stop, rtol, repeat, h=H_COMM, extra=()):
        """-> (dict of the driver's figures, samples (t, y, v, F, delta, mode))."""
        out = self.work / "samples.bin"
        cmd = [str(self.build / "vi_bench_driver"), self.so, self.md.guid, repr(t_stop), repr(h), str(repeat),
               repr(rtol), "--vrs", self.vrs, "--out", str(out), "--budget", repr(BUDGET_S), *extra]
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


def stiff_error(samples, params):
    """The light mass follows the platform quasi-statically: y = a (cos(2 pi f t) - 1) - delta_static
    (its inertia moves delta by m a (2 pi f)^2 / k, about 1e-13 m); the largest deviation over the
    run divided by the motion's range 2 a."""
    e = effective(params)
    a, f = params["a"], 560.0
    t, y = samples[:, 0], samples[:, 1]
    y_ref = a * (np.cos(2 * np.pi * f * t) - 1.0) - (e["W"] / e["K"]) ** (2.0 / 3.0)
    return float(np.abs(y - y_ref).max() / (2.0 * a))


def matched(rtols, errors):
    """The loosest rtol from which on every tighter rtol has error <= BOUND (None if none)."""
    ok = None
    for r, e in sorted(zip(rtols, errors)):  # tightest first
        if e is None or not e <= BOUND:
            break
        ok = r
    return ok


# ---- the suite ------------------------------------------------------------------------------------

# The sections that need no work-precision results, for --only.
ALONE = {"profile": lambda out, fmu, work, repeat: (profile_loading(out, fmu, work, repeat),
                                                   profile_formats(out, fmu, work, repeat)),
         "setup": lambda out, fmu, work, repeat: setup_cost(out, fmu, work, repeat),
         "rolling": lambda out, fmu, work, repeat: bench_rolling.rolling(out, fmu, work, repeat),
         # the floor at rtol 1e-10 for every solver (the full suite uses the matched rtols)
         "floor": lambda out, fmu, work, repeat: per_call_floor(out, fmu, {"fig4b": {"matched": {}}}, repeat),
         # Fig. 4b alone: its work-precision table, matched accuracy, and where the time goes
         "fig4b": lambda out, fmu, work, repeat: fig4b_alone(out, fmu, work, repeat)}


AGAINST_RTOLS = (1e-6, 1e-10)  # the tolerances of the comparison of two builds


def against(out, fmu, other, repeat, rtols=AGAINST_RTOLS):
    """CPU of this build's FMU against another build's (other: an Fmu), every case and solver at the
    given rtols, the two runs alternated so that both see the same machine; prints the ratios
    this/other and their geometric mean. -> {(case, solver, rtol): ratio}."""
    ratios = {}
    out("## This build against another\n")
    out(f"`{fmu.path}` against `{other.path}`: CPU per run, minimum of {repeat} alternated runs of each.\n")
    out("| case | solver | rtol | this [ms] | other [ms] | this / other |")
    out("|---|---|---|---|---|---|")
    for case, spec in CASES.items():
        for name, solver in SOLVERS.items():
            for rtol in rtols:
                best = [float("inf"), float("inf")]
                for _ in range(repeat):
                    for k, f in enumerate((fmu, other)):
                        fig, _ = f.run({**spec["params"], "solver": solver}, spec["t_stop"], rtol, 1)
                        best[k] = min(best[k], fig["cpu_s"] if fig else float("nan"))
                ratios[case, name, rtol] = best[0] / best[1]
                out(f"| {case} | {name} | {rtol:.0e} | {1e3 * best[0]:.3f} | {1e3 * best[1]:.3f} | "
                    f"{ratios[case, name, rtol]:.3f} |")
    finite = [r for r in ratios.values() if np.isfinite(r) and r > 0]
    mean = float(np.exp(np.mean(np.log(finite)))) if finite else float("nan")
    out(f"\nGeometric mean of this / other over {len(finite)} runs: {mean:.3f}\n")
    return ratios


def run_suite(repeat, quick, outdir, build, only=None, other_build=None):
    if not only and not other_build:
        out_dir(outdir)
    lines = []

    def out(text=""):
        print(text, flush=True)
        lines.append(text)

    rtols = RTOLS[::2] if quick else RTOLS
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        fmu = Fmu(work, build)
        out(f"Machine: {os.cpu_count()} cores; CPU times are the minimum of {repeat} runs.\n")
        if other_build:
            (work / "other").mkdir()
            against(out, fmu, Fmu(work / "other", other_build), repeat)
            return
        if only:
            for name in only:
                ALONE[name](out, fmu, work, repeat)
            return
        results = {}
        for case, spec in CASES.items():
            results[case] = measure_case(fmu, work, case, spec, rtols, repeat)
            report_case(out, case, spec, res=results[case], rtols=rtols)
        report_matched(out, results, rtols)
        report_auto(out, results)
        importer_share(out, fmu, results, repeat)
        per_call_floor(out, fmu, results, repeat)
        per_step_cost(out, fmu, results, repeat)
        scaling(out, fmu, results, repeat)
        memory_and_checkpoints(out, fmu, results, repeat)
        work_bound(out, fmu)
        profile_loading(out, fmu, work, repeat)
        profile_formats(out, fmu, work, repeat)
        setup_cost(out, fmu, work, repeat)
        bench_rolling.rolling(out, fmu, work, repeat)
        plotting.save(plotting.work_precision_figure(results, rtols, CASES, SOLVERS, BOUND),
                      outdir / "work_precision.png", DPI)
        plotting.save(plotting.cost_figure(results, SOLVERS), outdir / "cost.png", DPI)
    write_text(outdir / "bench.md", "\n".join(lines) + "\n")
    print(f"\nwritten: {outdir / 'bench.md'} and the PNG plots in {outdir}")


def case_error(fmu, case, spec):
    """(error of a run's samples, what it is measured against) for one case of CASES."""
    p, T = spec["params"], spec["t_stop"]
    if case == "drop":
        return (lambda s: drop_error(s, p)), "closed form"
    if case == "stiff":
        return (lambda s: stiff_error(s, p)), ("the quasi-static closed form y = a (cos(2 pi f t) - 1) - delta_static "
                                               "(the Python reference and RK4, explicit methods held to 10 MHz steps, "
                                               "are left out)")
    _, ref = fmu.run({**p, "solver": 3}, T, 1e-14, 1)
    _, ref2 = fmu.run({**p, "solver": 2}, T, 1e-13, 1)
    _, ref3 = python_reference(p, T, 1e-12, 1)
    return (lambda s: trace_error(s, ref)), (f"dop853 at rtol 1e-14; adams at 1e-13 is {trace_error(ref2, ref):.1e} "
                                             f"from it, the Python reference at 1e-12 {trace_error(ref3, ref):.1e}")


def measure_case(fmu, work, case, spec, rtols, repeat, rk4_steps=RK4_STEPS):
    """Work-precision of one case: every solver and the Python reference at each rtol, RK4 from the
    communication step down (rk4_steps) until it reaches BOUND; the cost of one rhs evaluation alone.
    -> dict(fmu={(solver, rtol): (CPU [s], error, rhs evaluations)}, py={rtol: (CPU, error)},
    rk4={h: (CPU, error)}, ref_note, rhs_ns)."""
    p, T = spec["params"], spec["t_stop"]
    err, ref_note = case_error(fmu, case, spec)
    res = dict(fmu={}, py={}, rk4={}, ref_note=ref_note)
    for name, solver in SOLVERS.items():
        for rtol in rtols:
            fig, s = fmu.run({**p, "solver": solver}, T, rtol, repeat)
            res["fmu"][name, rtol] = (fig["cpu_s"], err(s), fig["rhs"]) if fig else (None, None, None)
    for rtol in rtols:
        if case == "stiff":
            res["py"][rtol] = (None, None)
            continue
        cpu, s = python_reference(p, T, rtol, max(1, repeat // 2))
        res["py"][rtol] = (cpu, err(s))
    for h in rk4_steps if case != "stiff" else []:
        if T / h * 60e-9 > RK4_CAP_S:  # about 60 ns per RK4 step
            break
        fig, s = rk4(fmu.build, p, T, h, 1, work)
        res["rk4"][h] = (fig["cpu_s"], err(s))
        if err(s) <= BOUND:
            break
    res["rhs_ns"] = rhs_ns(fmu.build, p)
    return res


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
        cells.append("-" if cpu is None else f"{1e3 * cpu:.0f} / {e:.1e}")
        out(f"| {rtol:.0e} | " + " | ".join(cells) + " |")
    out("")
    rk = ", ".join(f"h = {h:g} s: {1e3 * c:.1f} ms / {e:.1e}" for h, (c, e) in res["rk4"].items())
    if rk:
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
        pr = matched(rtols, [res["py"][r][1] for r in rtols]) if res["py"][rtols[0]][0] is not None else None
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


def report_auto(out, results):
    out(f"### auto against the fastest other solver at matched accuracy (target: at most {AUTO_TARGET:g} times)\n")
    out("| case | fastest other: solver, rtol, CPU [ms] | auto: rtol, CPU [ms] | auto / fastest |")
    out("|---|---|---|---|")
    worst = 0.0
    for case, res in results.items():
        cpu = {n: res["fmu"][n, r][0] for n, r in res["matched"].items()}
        others = {n: c for n, c in cpu.items() if n != "auto"}
        if "auto" not in cpu or not others:
            out(f"| {case} | - | not within {BOUND:g} | - |")
            worst = np.inf
            continue
        best = min(others, key=others.get)
        ratio = cpu["auto"] / others[best]
        worst = max(worst, ratio)
        out(f"| {case} | {best}, {res['matched'][best]:.0e}, {1e3 * others[best]:.2f} | {res['matched']['auto']:.0e}, "
            f"{1e3 * cpu['auto']:.2f} | {ratio:.2f} |")
    out(f"\nTarget: auto within {AUTO_TARGET:g} times the fastest on every case: "
        f"{'met' if worst <= AUTO_TARGET else 'missed'} (worst {worst:.2f}).\n")


# The parts of the floor, by function (callgrind's self cost): a function belongs to the first part
# one of whose name fragments it contains.
FLOOR_PARTS = [
    ("the importer's loop (the C driver)", ["main"]),
    ("the FMI layer: state machine, argument and time checks, value access", ["fmi2", "vi_fmi_"]),
    ("the solver: the interpolant of its last internal step", [
        "vi_solver", "ode_advance", "cvode_advance", "vi_ode", "dense_", "CVode", "N_V", "Vaxpy", "Vscale", "cv"]),
    ("the simulation loop: inputs, restarts, kinks, events, range of validity", [
        "vi_sim_advance", "vi_model_indentation", "vi_model_rolling", "vi_model_next_breakpoint", "advance", "time_of"]),
    ("the outputs read: their groups, the platform position", ["outputs", "vi_model_platform"]),
    ("cos (libm), for the platform position", ["cos", "sin", "fenv"]),
]


def callgrind_per_call(fmu, params, rtol, calls):
    """Instructions per call by part: callgrind's self cost of every function, the difference of two runs
    (calls and 2 calls steps of FLOOR_H) divided by calls, so that the set-up cancels. None without
    valgrind."""
    import re
    import shutil
    if not (shutil.which("valgrind") and shutil.which("callgrind_annotate")):
        return None
    costs = []
    for n in (calls, 2 * calls):
        out = fmu.work / f"callgrind.{n}.out"
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", str(fmu.build / "vi_bench_driver"),
               fmu.so, fmu.md.guid, repr(n * FLOOR_H), repr(FLOOR_H), "1", repr(rtol), "--vrs", fmu.vrs]
        subprocess.run(cmd + [fmu.arg(k, v) for k, v in params.items()], capture_output=True, check=True)
        text = subprocess.run(["callgrind_annotate", "--inclusive=no", "--threshold=100", str(out)],
                              capture_output=True, text=True, check=True).stdout
        cost = {}
        for line in text.splitlines():
            hit = re.match(r"\s*([\d,]+) \([\s\d.]+%\)\s+(\S+)", line)
            if hit and "PROGRAM" not in hit.group(2):
                name = hit.group(2).rsplit(":", 1)[-1]
                cost[name] = cost.get(name, 0) + int(hit.group(1).replace(",", ""))
        costs.append(cost)
    parts = {label: 0.0 for label, _ in FLOOR_PARTS}
    parts["other"] = 0.0
    for name in set(costs[0]) | set(costs[1]):
        per_call = (costs[1].get(name, 0) - costs[0].get(name, 0)) / calls
        label = next((lab for lab, frags in FLOOR_PARTS if any(f in name for f in frags)), "other")
        parts[label] += per_call
    return parts


def per_call_floor(out, fmu, results, repeat):
    p = CASES["fig4b"]["params"]
    T = 5e5 * FLOOR_H
    reals = ",".join(str(v.valueReference) for v in fmu.md.modelVariables
                     if v.type == "Real" and v.causality == "output")
    out(f"### The per-call floor (fig4b at matched rtol, {T * 1e3:g} ms in steps of {FLOOR_H:g} s: nearly every "
        "fmi2DoStep lies inside the solver's last internal step)\n")
    out("| solver | rtol | fmi2DoStep alone [ns] | with y read [ns] | with every Real output read [ns] | "
        "target, y read [ns] |")
    out("|---|---|---|---|---|---|")
    verdicts = []
    for name, solver in SOLVERS.items():
        r = best_rtol(results, name)
        ns = []
        for extra in (["--reads", ""], [], ["--reads", reals]):
            fig, _ = fmu.run({**p, "solver": solver}, T, r, repeat, h=FLOOR_H, extra=extra)
            ns.append(1e3 * fig["step_us"])
        target = FLOOR_TARGET_NS.get(name)
        if target:
            verdicts.append(f"{name} {ns[1]:.0f} ns ({'met' if ns[1] <= target else 'missed'})")
        out(f"| {name} | {r:.0e} | {ns[0]:.0f} | {ns[1]:.0f} | {ns[2]:.0f} | {fmt(target, '.0f')} |")
    out("\nTarget: a step that needs no new internal step, with y read, at most "
        + ", ".join(f"{t:g} ns ({n})" for n, t in FLOOR_TARGET_NS.items()) + ": " + "; ".join(verdicts) + ".\n")
    parts = {name: callgrind_per_call(fmu, {**p, "solver": SOLVERS[name]}, best_rtol(results, name), 100000)
             for name in ("dop853", "bdf")}
    if parts["dop853"] is None:
        out("(valgrind not installed: the instructions per call by part are left out.)\n")
        return
    out("Where the floor goes, instructions per call with y read (valgrind --tool=callgrind, self cost of every "
        "function, the difference of runs of 1e5 and 2e5 calls divided by 1e5; deterministic):\n")
    out("| part | dop853 | bdf |")
    out("|---|---|---|")
    for label in list(parts["dop853"]):
        out(f"| {label} | {round(parts['dop853'][label])} | {round(parts['bdf'][label])} |")
    out(f"| total | {round(sum(parts['dop853'].values()))} | {round(sum(parts['bdf'].values()))} |\n")


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


def per_step_cost(out, fmu, results, repeat, steps=STEPS_S, t_stop=0.01):
    out(f"### Cost per fmi2DoStep against the communication step (fig4b, {1e3 * t_stop:g} ms, y read after each "
        "step)\n")
    out("| solver | rtol | " + " | ".join(f"h = {h:g} s [us]" for h in steps) + " |")
    out("|---|---|" + "---|" * len(steps))
    p = CASES["fig4b"]["params"]
    results["per_step"] = {}
    for name, solver in SOLVERS.items():
        r = best_rtol(results, name)
        cells = []
        for h in steps:
            fig, _ = fmu.run({**p, "solver": solver}, t_stop, r, repeat, h=h)
            results["per_step"][name, h] = fig["step_us"]
            cells.append(f"{fig['step_us']:.3g}")
        out(f"| {name} | {r:.0e} | " + " | ".join(cells) + " |")
    out("\nAt 1e-7 s nearly every step lies inside the solver's last internal step: its cost is the "
        "interpolation, the step's bookkeeping and reading y.\n")


def scaling(out, fmu, results, repeat, spans=SPANS_S, freqs=FREQS_HZ):
    p = CASES["fig4b"]["params"]
    out("### Cost against simulated time (fig4b, matched rtol) [ms]\n")
    out("| solver | " + " | ".join(f"{T:g} s" for T in spans) + " | per simulated second |")
    out("|---|" + "---|" * (len(spans) + 1))
    results["time"], results["time_spans"] = {}, spans
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


def profile_loading(out, fmu, work, repeat):
    """Loading a rolling profile against its number of rows, against numpy.loadtxt on the same file."""
    out("### Loading a rolling profile against the number of rows\n")
    out("A rail sampled every 0.1 mm (a random walk of 0.1 um steps and a 50 mm corrugation of 20 um), written by "
        "numpy.savetxt (19 significant digits), R1 = 0.475 m. vi_profile_load: reading the file and building the "
        "rigid-constraint envelope (tools/bench_profile.c); FMU: from fmi2Instantiate to the end of "
        "fmi2ExitInitializationMode with profile_file set (the C driver); numpy.loadtxt: reading the same file. "
        f"CPU times, the minimum of {repeat} runs; memory: the peak resident memory of the loading process above "
        "that of a two-row file.\n")
    out("| rows | file [MB] | vi_profile_load [ms] | [us/row] | numpy.loadtxt [us/row] | numpy.loadtxt / vi_profile_load "
        "| FMU initialization [ms] | memory [bytes/row] | kinks |")
    out("|---|---|---|---|---|---|---|---|---|")

    def load(path):
        r = subprocess.run([str(fmu.build / "vi_bench_profile"), str(path), "0.475", "0", str(repeat)], capture_output=True,
                           text=True, check=True)
        words = r.stdout.split()
        return {k: float(v) for k, v in zip(words[::2], words[1::2])}

    small = work / "profile_2.txt"
    np.savetxt(small, [[0.0, 0.0], [1.0, 0.0]])
    base_kb = load(small)["maxrss_kb"]
    rng = np.random.default_rng(19)
    worst, slower = 0.0, []
    for n in PROFILE_ROWS:
        x = 1e-4 * np.arange(n)
        h = np.cumsum(rng.normal(0.0, 1e-7, n)) + 2e-5 * np.sin(2 * np.pi * x / 0.05)
        path = work / f"profile_{n}.txt"
        np.savetxt(path, np.column_stack([x, h]))
        c = load(path)
        best = np.inf
        for _ in range(repeat):
            t0 = time.process_time()
            np.loadtxt(path)
            best = min(best, time.process_time() - t0)
        fig, _ = fmu.run(dict(contact_model=1, profile_file=str(path), V=1.0), 1e-4, 1e-6, repeat, h=1e-4)
        us, np_us = 1e6 * c["cpu_s"] / n, 1e6 * best / n
        worst = max(worst, us)
        if us > np_us:
            slower.append(n)
        out(f"| {n} | {path.stat().st_size / 1e6:.1f} | {1e3 * c['cpu_s']:.1f} | {us:.3f} | {np_us:.3f} | "
            f"{np_us / us:.1f} | {1e3 * fig['init_s']:.1f} | {1024 * (c['maxrss_kb'] - base_kb) / n:.0f} | "
            f"{int(c['kinks'])} |")
    verdict = "met" if worst <= PROFILE_TARGET_US and not slower else "missed"
    out(f"\nTarget: at most {PROFILE_TARGET_US} us per row and no slower than numpy.loadtxt: {verdict} (worst "
        f"{worst:.3f} us per row" + (f"; slower than numpy.loadtxt at {slower} rows" if slower else "") + ").\n")


SETUP_LAWS = {"hertz": dict(contact_model=1),
              "hertz_damped exact, e = 0.8": dict(contact_model=4, damping_formula=1, e_restitution=0.8),
              "hertz_damped exact, e = 0.05": dict(contact_model=4, damping_formula=1, e_restitution=0.05),
              "hertz_damped hunt_crossley, e = 0.8": dict(contact_model=4, damping_formula=2, e_restitution=0.8)}
SETUP_TARGET_MS = 0.2  # hertz_damped's set-up beyond hertz's


def setup_cost(out, fmu, work, repeat, h=1e-3):
    """A short run per law: instantiate, initialize and one fmi2DoStep, the laws alternated."""
    drop = CASES["drop"]["params"]
    out(f"### A short run: instantiate, initialize, one step of {1e3 * h:g} ms, free (the drop, rtol 1e-6)\n")
    out(f"CPU per run from fmi2Instantiate to the end of fmi2FreeInstance (tools/bench_driver.c), the laws "
        f"alternated, the minimum of {repeat} x 20 runs of each.\n")
    out("| law | CPU [ms] | beyond hertz [ms] |")
    out("|---|---|---|")
    best = {name: np.inf for name in SETUP_LAWS}
    for _ in range(repeat):
        for name, law in SETUP_LAWS.items():
            fig, _ = fmu.run({**drop, **law}, h, 1e-6, 20, h=h)
            best[name] = min(best[name], fig["cpu_s"])
    worst = 0.0
    for name, cpu in best.items():
        extra = 1e3 * (cpu - best["hertz"])
        worst = max(worst, extra)
        out(f"| {name} | {1e3 * cpu:.3f} | {extra:+.3f} |")
    out(f"\nTarget: every damped law within {SETUP_TARGET_MS:g} ms of hertz: "
        f"{'met' if worst <= SETUP_TARGET_MS else 'missed'} (worst {worst:+.3f} ms).\n")


# The number formats of profile_formats: a rail sampled every 0.1 mm as written by numpy.savetxt with fmt, and
# integers (x = 0, 1, 2 ... m, h from -3 to 3 m).
PROFILE_FORMATS = ("%.6e", "%.17g", "%.4f", "%g", "%d", "%.19g", "%.18e")


def profile_formats(out, fmu, work, repeat, n=PROFILE_ROWS[-1]):
    """vi_profile_load (reading and the envelope) against numpy.loadtxt on the same file, per number format,
    the two alternated. -> {format: numpy.loadtxt / vi_profile_load}."""
    out(f"### Loading a rolling profile of {n} rows against numpy.loadtxt, per number format\n")
    out(f"The two alternated, CPU times the minimum of {repeat} runs each; R1 = 0.475 m. The rail of the table "
        "above written with each format, and integers.\n")
    out("| format | file [MB] | vi_profile_load [ms] | numpy.loadtxt [ms] | numpy.loadtxt / vi_profile_load |")
    out("|---|---|---|---|---|")
    rng = np.random.default_rng(19)
    x = 1e-4 * np.arange(n)
    rail = np.column_stack([x, np.cumsum(rng.normal(0.0, 1e-7, n)) + 2e-5 * np.sin(2 * np.pi * x / 0.05)])
    ratios = {}
    for fmt in PROFILE_FORMATS:
        path = work / "profile_format.txt"
        data = np.column_stack([np.arange(n), rng.integers(-3, 4, n)]) if fmt == "%d" else rail
        np.savetxt(path, data, fmt=fmt)
        ours = theirs = np.inf
        for _ in range(repeat):
            r = subprocess.run([str(fmu.build / "vi_bench_profile"), str(path), "0.475", "0", "1"], capture_output=True,
                               text=True, check=True)
            ours = min(ours, float(r.stdout.split()[1]))
            t0 = time.process_time()
            np.loadtxt(path)
            theirs = min(theirs, time.process_time() - t0)
        ratios[fmt] = theirs / ours
        out(f"| `{fmt}` | {path.stat().st_size / 1e6:.1f} | {1e3 * ours:.0f} | {1e3 * theirs:.0f} | {ratios[fmt]:.2f} |")
    slower = [f for f, r in ratios.items() if r < 1.0]
    out(f"\nTarget: no slower than numpy.loadtxt on every format: {'missed on ' + ', '.join(slower) if slower else 'met'} "
        f"(least ratio {min(ratios.values()):.2f}).\n")
    return ratios


def work_bound(out, fmu):
    p = CASES["fig4b"]["params"]
    out("### The work bound: fig4b in one fmi2DoStep of 1e6 s\n")
    out("| solver | CPU until fmi2Discard [s] | fmi2LastSuccessfulTime [s] |")
    out("|---|---|---|")
    for name, solver in SOLVERS.items():
        fig, _ = fmu.run({**p, "solver": solver}, 1e6, 1e-6, 1, h=1e6)
        out(f"| {name} | {fig['cpu_s']:.2f} | {fig['discard_at']:.6g} |")
    out("")


# ---- Fig. 4b alone: where the time goes -------------------------------------------------------------

def callgrind_tree(fmu, params, t_stop, rtol):
    """One run of the C driver under valgrind's callgrind: ({function: inclusive instructions},
    {(caller, function): instructions of function's calls from caller}), function names without the
    compiler's suffixes (.lto_priv.0). None without valgrind."""
    import re
    import shutil
    if not (shutil.which("valgrind") and shutil.which("callgrind_annotate")):
        return None
    out = fmu.work / "callgrind.fig4b.out"
    cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", str(fmu.build / "vi_bench_driver"),
           fmu.so, fmu.md.guid, repr(t_stop), repr(H_COMM), "1", repr(rtol), "--vrs", fmu.vrs]
    subprocess.run(cmd + [fmu.arg(k, v) for k, v in params.items()], capture_output=True, check=True)
    text = subprocess.run(["callgrind_annotate", "--tree=caller", "--inclusive=yes", "--threshold=100", str(out)],
                          capture_output=True, text=True, check=True).stdout
    inclusive, calls, callers = {}, {}, []
    for line in text.splitlines():
        hit = re.match(r"\s*([\d,]+) \([\s\d.]+%\)\s+([<*])\s+(\S+)", line)
        if not hit:
            callers = []
            continue
        cost, name = int(hit.group(1).replace(",", "")), hit.group(3).rsplit(":", 1)[-1].split(".")[0]
        if hit.group(2) == "<":
            callers.append((name, cost))
            continue
        inclusive[name] = inclusive.get(name, 0) + cost
        for caller, c in callers:
            calls[caller, name] = calls.get((caller, name), 0) + c
        callers = []
    return inclusive, calls


def time_parts(fig, tree):
    """[(part, instructions)] of the loop (fmi2DoStep and fmi2GetReal), by what the instructions do:
    callgrind's inclusive costs of the functions that do each part, the rhs evaluations split by purpose
    with the solver's counters (an accepted step 12, its dense output 3, a rejected attempt 11, a restart
    2: f at the new start and the first step size)."""
    inc, calls = tree
    steps, rej, restarts = fig["solver_steps"], fig["rejected"], fig["restarts"]
    unit = inc.get("sim_rhs", 0) / fig["rhs"]  # instructions per rhs evaluation
    ode = inc.get("ode_advance", 0)
    inside = ["attempt_2", "dense_build", "root_search", "vi_ode_dense", "sim_piece", "sim_guards",
              "ode_spectral_radius", "sim_rhs"]
    parts = [
        ("rhs: accepted steps (12 each)", 12 * steps * unit),
        ("rhs: the dense output of each step (3 each)", 3 * steps * unit),
        ("rhs: rejected attempts (11 each)", 11 * rej * unit),
        ("rhs: restarts after events (2 each)", 2 * restarts * unit),
        ("stage sums and error estimates", inc.get("attempt_2", 0) - 11 * (steps + rej) * unit),
        ("dense-output coefficients", inc.get("dense_build", 0) - 3 * steps * unit),
        ("guards at step ends and interior samples", calls.get(("ode_advance", "sim_guards"), 0)),
        ("event location (root search on the interpolant)", inc.get("root_search", 0)),
        ("stability bound (spectral radius per step)", calls.get(("ode_advance", "ode_spectral_radius"), 0)),
        ("restarts besides their rhs", inc.get("ode_restart", 0) - 2 * restarts * unit),
        ("the integrator's bookkeeping", ode - sum(calls.get(("ode_advance", f), 0) for f in inside)),
        ("interpolation at the communication points", calls.get(("ode_advance", "vi_ode_dense"), 0)),
        ("the force's peak at each communication point (pieces)", inc.get("sim_piece", 0)),
        ("FMI layer and simulation loop of fmi2DoStep", inc["fmi2DoStep"] - ode - inc.get("ode_restart", 0)),
        ("reading y (fmi2GetReal: FMI layer, outputs, cos)", inc["fmi2GetReal"]),
    ]
    return parts, inc["fmi2DoStep"] + inc["fmi2GetReal"]


def fig4b_alone(out, fmu, work, repeat):
    """Fig. 4b's work-precision table and matched accuracy (as in the full suite), then where the time of
    the fastest solver at matched accuracy goes."""
    spec = CASES["fig4b"]
    res = measure_case(fmu, work, "fig4b", spec, RTOLS, repeat)
    report_case(out, "fig4b", spec, res, RTOLS)
    report_matched(out, {"fig4b": res}, RTOLS)
    name = "dop853"
    rtol = res["matched"].get(name)
    if rtol is None:
        return
    p = {**spec["params"], "solver": SOLVERS[name]}
    fig, _ = fmu.run(p, spec["t_stop"], rtol, repeat)
    floor, _ = fmu.run(p, 5e5 * FLOOR_H, rtol, repeat, h=FLOOR_H)
    calls = round(spec["t_stop"] / H_COMM)
    out(f"### Where the time goes (fig4b, {name} at rtol {rtol:.0e}, {calls} steps of {H_COMM:g} s, y read after each)\n")
    out(f"Solver counters: {int(fig['solver_steps'])} accepted steps, {int(fig['rejected'])} rejected attempts, "
        f"{int(fig['rhs'])} rhs evaluations, {int(fig['guard_evals'])} guard evaluations, {int(fig['restarts'])} "
        f"restarts. CPU of the loop {fig['step_us'] * calls / 1e3:.3f} ms (minimum of {repeat} runs); one rhs "
        f"evaluation alone {res['rhs_ns']:.1f} ns; the per-call floor (steps of {FLOOR_H:g} s, y read) "
        f"{1e3 * floor['step_us']:.0f} ns.\n")
    tree = callgrind_tree(fmu, p, spec["t_stop"], rtol)
    if tree is None:
        out("(valgrind not installed: the parts are left out.)\n")
        return
    parts, loop = time_parts(fig, tree)
    cpu_ms = 1e-3 * fig["step_us"] * calls
    out("Instructions by part (valgrind --tool=callgrind, inclusive cost of the functions that do it; "
        "deterministic), and the time that share of the loop's CPU makes:\n")
    out("| part | instructions | share | time [ms] |")
    out("|---|---|---|---|")
    for label, c in parts + [("other (what the split above counts twice: < 0)", loop - sum(c for _, c in parts))]:
        out(f"| {label} | {round(c)} | {100 * c / loop:.1f} % | {cpu_ms * c / loop:.3f} |")
    need = 15 * fig["solver_steps"] * res["rhs_ns"] * 1e-6
    floor_ms = 1e-3 * floor["step_us"] * calls
    py_rtol = matched(RTOLS, [res["py"][r][1] for r in RTOLS])
    py = 1e3 * res["py"][py_rtol][0] if py_rtol else None
    out(f"\nThe limit: the rhs evaluations of the accepted steps and their dense output at {res['rhs_ns']:.1f} ns "
        f"each ({need:.3f} ms) plus {calls} calls at the per-call floor ({floor_ms:.3f} ms): {need + floor_ms:.3f} ms"
        + (f", {py / (need + floor_ms):.0f} times faster than the Python reference ({py:.0f} ms); the loop takes "
           f"{cpu_ms:.3f} ms, {py / cpu_ms:.0f} times" if py else "") + ".\n")
