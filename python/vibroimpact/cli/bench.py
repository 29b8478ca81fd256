"""Speed against accuracy: the benchmark suite of the FMU's solvers (figures, not a test).

    vibroimpact bench [--repeat N] [--quick] [--out DIR] [--build DIR] [--only SECTION,...]
    vibroimpact bench --against OTHER_BUILD [--repeat N] [--build DIR]

Prints Markdown tables and writes DIR/bench.md and the PNG plots (DIR: results/bench by default; the
documentation's are made with --out doc/bench). It runs on Linux with the GNU C library, and needs a
CMake build folder (default: the folder of vibroimpact.fmu_path(), build/ in a checkout) with the FMU
and the programs vi_bench_driver, vi_bench_rk4 and vi_bench_profile (tools/bench_*.c, which use dlopen
and glibc's mallinfo2).
--against compares two builds (this one and, say, the previous commit's): every case below with every
solver at rtol 1e-6 and 1e-10, runs of the two FMUs alternated, the ratios of their CPU times and
their geometric mean printed; nothing is written.
--only runs just the named sections that stand alone (profile; floor, at rtol 1e-10; setup; rolling; fig4b: item 1
and 2 for fig4b alone, then where the time of dop853 at its matched rtol goes: the solver's counters
and, with valgrind, callgrind's instructions by part) and prints them, writing nothing.

What it runs (the FMU binary through tools/bench_driver.c, dlopen'ed from C with no Python in the
loop, unless said otherwise; CPU times are the minimum of N runs, default 5, because other
processes disturb single runs; instruction counts would be steadier but do not compare with Python):

1. Work-precision, every solver (bdf, adams, dop853, auto), rtol 1e-3 ... 1e-12 in half decades, on
     fig4b   Johnson, Y = 6e8 Pa, bouncing and plastic (paper Fig. 4b), 40 ms;
     fig5a   Hertz, 100 Hz, sustained contact (paper Fig. 5a), 0.1 s;
     drop    Hertz drop P = g = 0, v0 = -0.1 m/s, one impact, 3 ms: closed form (energy
             1/2 m v^2 + 2/5 K delta^2.5 conserved, so the peak indentation is
             (15 m v0^2 / (16 E* sqrt(R*)))^(2/5), and restitution 1);
     stiff   m = 1e-7 kg at rest under the default load, a = 0.1 mm at 560 Hz, 10 ms: the contact
             rings at about 10 MHz and the mass follows the platform, y = a (cos(2 pi f t) - 1) -
             delta_static (closed form, error / 2a), where the explicit method is held by stability,
   communication step 1e-5 s, y read after every step (a run taking more than BUDGET_S of CPU is
   not repeated). The error of fig4b and fig5a is the largest
   |y - y_ref| over the communication points divided by the range of y_ref, y_ref from dop853 at
   rtol 1e-14 (checked against adams at 1e-13 and the Python reference at 1e-12: the table prints
   their distance). The error of the drop is the larger of the relative energy error over the run
   and |restitution - 1|.
   In the same run (not on the stiff case): the Python reference (vibroimpact.reference.model,
   SciPy DOP853 with event location) at its own tolerances, and a fixed-step RK4 without event location
   (tools/bench_rk4.c: guards looked at only at step ends) from the communication step down, until
   it reaches the accuracy or its run would take more than RK4_CAP_S.
2. Matched accuracy: per solver the loosest rtol from which on (for it and every tighter rtol) the
   error stays within 1e-5 (fig4b: of the motion range; the error is not monotone in rtol on a
   chaotic trace), its CPU time, the Python reference's at its own such rtol, and the ratio; the
   RK4 step that reaches the same accuracy (if any does below the cost cap); the limit: the rhs
   evaluations the run needed times the cost of one rhs evaluation alone, and the ratio to it;
   then auto against the fastest other solver (target AUTO_TARGET).
3. The importer's share: the matched runs again through fmpy (FMU2Slave, doStep and getReal in
   Python), against the C driver.
4. The per-call floor: fig4b at matched rtol in communication steps of FLOOR_H (nearly every step
   inside the last internal step): fmi2DoStep alone, with y read, with every Real output read
   (targets FLOOR_TARGET_NS), and, when valgrind is installed, the instructions per call by part
   (callgrind). Then the cost per fmi2DoStep at communication steps 1e-7 ... 1e-3 s (fig4b, 10 ms).
5. Cost against simulated time (fig4b at matched rtol, 10 ms ... 1 s) and against the number of
   impacts (Hertz, a = 0.1 mm, f = 500 ... 8000 Hz, one impact per period, 0.1 s).
6. Memory per instance (heap after initialization) and the cost of taking an FMU state before
   every step (a master ready to roll back), with the error that follows from it (CVODE restarts at
   every checkpoint; the one-step method carries its continuation).
7. The work bound: fig4b in one fmi2DoStep of 1e6 s, CPU until fmi2Discard and where it stopped.
8. Loading a rolling profile of 1e4 ... 1e6 rows (vi_profile_load: reading and the envelope; the FMU's
   initialization with it) against numpy.loadtxt reading the same file, per row, with the memory;
   then the rail of 1e6 rows written in each number format (PROFILE_FORMATS: %.6e, %.17g, %.4f, %g,
   integers, %.19g, %.18e) against numpy.loadtxt, the two alternated, and their ratio.
9. A short run per law (setup): instantiate, initialize, one step of 1 ms and free, on the drop, for
   hertz and hertz_damped (exact at e = 0.8 and 0.05, hunt_crossley), the laws alternated, each
   against hertz (target: within SETUP_TARGET_MS).
   initialization with it) against numpy.loadtxt reading the same file, per row, with the memory.
10. Rolling over a sampled rail (vibroimpact.bench_rolling): the paper's wheel (Hertz) at 30 m/s for
   0.1 s over a periodic corrugation (50 mm, 20 um) given as 21, 201, 2001 and 20001 rows per
   wavelength, rtol 1e-8, 1 ms steps, with profile_interpolation linear and cubic, in Co-Simulation
   (the C driver, loading the table included) and Model Exchange (fmpy's CVode driver): CPU, the
   ratios to the 21-row table's, the peak force and its convergence with the rows, the cost per
   row passed and per kink of the polyline, and the spline against its targets (bench_rolling.TARGETS).
"""
import argparse
import pathlib
import platform

from ..bench import ALONE, PROGRAMS, run_suite
from ..failure import CommandError
from ..fmu import NAME, build_dir

OUT = pathlib.Path("results", "bench")


def main(argv=None):
    p = argparse.ArgumentParser(prog="vibroimpact bench", description=__doc__.split("\n\n")[0],
                                epilog=__doc__.split("\n\n", 1)[1], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeat", type=int, default=5, metavar="N", help="runs per figure; the fastest counts (default 5)")
    p.add_argument("--quick", action="store_true", help="every other tolerance only")
    p.add_argument("--out", type=pathlib.Path, default=OUT, metavar="DIR",
                   help=f"output folder (default {OUT}; the documentation's: doc/bench)")
    p.add_argument("--build", type=pathlib.Path, default=None, metavar="DIR",
                   help="the CMake build folder (default: the folder of vibroimpact.fmu_path())")
    p.add_argument("--only", type=lambda text: text.split(","), default=None, metavar="SECTION,...",
                   help="only these sections, printed, nothing written: " + ", ".join(ALONE))
    p.add_argument("--against", type=pathlib.Path, default=None, metavar="DIR",
                   help="only compare: CPU of every case and solver at rtol 1e-6 and 1e-10 against the FMU of "
                        "another build folder (for example the previous commit's), alternated runs, ratios printed, "
                        "nothing written")
    a = p.parse_args(argv)
    if a.repeat < 1:
        p.error("--repeat is at least 1")
    if platform.system() != "Linux" or platform.libc_ver()[0] != "glibc":
        raise CommandError(f"the benchmark runs on Linux with the GNU C library (its programs use dlopen and "
                           f"mallinfo2), not on {platform.system()} {' '.join(platform.libc_ver()).strip()}")
    build = a.build or build_dir()
    missing = [str(build / f) for f in (NAME,) + PROGRAMS if not (build / f).is_file()]
    if missing:
        p.error(f"missing {', '.join(missing)}: build them with cmake -S . -B build && cmake --build build "
                "in a checkout, or name the build folder with --build")
    if a.against:
        missing = [str(a.against / f) for f in (NAME, "vi_bench_driver") if not (a.against / f).is_file()]
        if missing:
            p.error(f"--against: missing {', '.join(missing)}")
    if a.only and set(a.only) - set(ALONE):
        p.error(f"--only: unknown section {sorted(set(a.only) - set(ALONE))}; known: {', '.join(ALONE)}")
    run_suite(a.repeat, a.quick, a.out, build, a.only, a.against)
