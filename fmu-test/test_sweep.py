"""`vibroimpact sweep`, the sweep command, on small grids and short runs: physics against closed forms
(rest, the linear response's Poincare samples, the resonance at f_contact), results independent of
the number of workers and of the scheduler (a Dask scheduler and worker started here on loopback),
failed points kept with the FMU's message, enumerations by item name, continuation sweeps."""
import csv
import math
import os
import pathlib
import signal
import socket
import subprocess
import sys
import time

import numpy as np
import pytest
from conftest import DEFAULT_SOLVER, DEFAULTS, FMU, effective

from vibroimpact.sweep import spec

SWEEP = [sys.executable, "-m", "vibroimpact", "sweep"]

W = DEFAULTS["P"] + DEFAULTS["m"] * DEFAULTS["g"]  # static load P + m g [N]
RUN_TIMEOUT_S = 100


def sweep(out, *args, workers=2, check=True):
    """Run the command; return (returncode, stderr, rows of sweep.csv, rows of poincare.csv)."""
    cmd = [*SWEEP, "--fmu", str(FMU), "--out", str(out), "--no-progress", "--no-plots", *args]
    if workers and "--scheduler" not in args:
        cmd += ["--workers", str(workers)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=RUN_TIMEOUT_S, cwd=out.parent)
    if check:
        assert p.returncode == 0, p.stderr
    rows = poincare = None
    if p.returncode == 0:
        with open(out / "sweep.csv", newline="") as fh:
            rows = list(csv.DictReader(fh))
        with open(out / "poincare.csv", newline="") as fh:
            poincare = list(csv.DictReader(fh))
    return p.returncode, p.stderr, rows, poincare


def linear_resonance_hz(p=None):
    """sqrt(k/m)/(2 pi) with k = 1.5 K sqrt(delta_static): Hertz linearised at the static load."""
    e = effective(p or {})
    delta_s = (e["W"] / e["K"]) ** (2 / 3)
    return math.sqrt(1.5 * e["K"] * math.sqrt(delta_s) / e["m"]) / (2 * math.pi), delta_s


def col(rows, name):
    return np.array([float(r[name]) if r[name] != "" else np.nan for r in rows])


# ---- physics ------------------------------------------------------------------------------------
def test_rest_gives_the_static_load(tmp_path):
    """a = 0: the mass rests on the Hertz curve, F = P + m g throughout, in contact, no impact. The sweep
    runs the FMU's default solver: CVODE keeps rest to rounding, the explicit method (dop853, and auto
    while it runs it) to its tolerance (rtol 1e-6; the force 1.5 times the indentation's error, with a
    factor 10 of global over local error, as in test_hertz and test_extremes)."""
    rel = 1.5e-5 if DEFAULT_SOLVER in (3, 4) else 1e-9
    _, _, rows, pc = sweep(tmp_path / "rest", "--set", "contact_model=hertz", "--set", "a=0",
                           "--grid", "f=100:300:2", "--stop-time", "0.02", "--transient", "0.01")
    _, delta_s = linear_resonance_hz()
    for r in rows:
        assert r["status"] == "ok", r["message"]
        for k in ("F_max", "F_min", "F_mean"):
            assert float(r[k]) == pytest.approx(W, rel=rel)
        assert float(r["delta_max"]) == pytest.approx(delta_s, rel=rel)
        assert float(r["contact_fraction"]) == 1.0
        assert int(r["n_impacts"]) == 0 and float(r["sep_max"]) == 0.0
    # once per period from the transient to the end: 0.01 s at 100 Hz -> 2 samples, at 300 Hz -> 4
    assert [sum(p["f"] == r["f"] for p in pc) for r in rows] == [2, 4]


def test_poincare_samples_follow_the_linear_response(tmp_path):
    """Small amplitude: the samples at phase 0 (t = k/f) are those of the linearised base-excited
    oscillator started at rest: delta - delta_s = -a (r - 1)(1 - cos wn t), v = a (r - 1) wn sin wn t,
    r = wn^2/(wn^2 - w^2). This checks the sampling instants (the period) and the values."""
    a, f = 1e-8, 200.0
    _, _, rows, pc = sweep(tmp_path / "lin", "--set", "contact_model=hertz", "--set", f"a={a}", "--set", f"f={f}",
                           "--set", "rtol=1e-10", "--grid", "P=40000:40000:1", "--stop-time", "0.05",
                           "--step", "1e-4")
    assert rows[0]["status"] == "ok", rows[0]["message"]
    fn, delta_s = linear_resonance_hz()
    wn, w = 2 * math.pi * fn, 2 * math.pi * f
    r = wn ** 2 / (wn ** 2 - w ** 2)
    t = col(pc, "t")
    np.testing.assert_allclose(t, np.arange(len(t)) / f, rtol=0, atol=1e-12)
    assert len(t) == 11  # t = 0, 5 ms, ..., 50 ms
    amp = 2 * a * (r - 1)
    np.testing.assert_allclose(col(pc, "delta") - delta_s, -a * (r - 1) * (1 - np.cos(wn * t)), rtol=0,
                               atol=2e-3 * amp)
    np.testing.assert_allclose(col(pc, "v"), a * (r - 1) * wn * np.sin(wn * t), rtol=0, atol=2e-3 * amp * wn)


@pytest.mark.timeout(150)
def test_small_amplitude_hertz_peaks_at_f_contact(tmp_path):
    """a = 10 nm, undamped: from rest the response near resonance grows with the beat between
    forcing and free oscillation, so the largest force over a fixed time falls at the grid point
    nearest the contact resonance. The grid (2 Hz apart) does not contain f_contact."""
    fn, _ = linear_resonance_hz()
    assert fn == pytest.approx(271.5, abs=0.05)  # 271.5 Hz: the paper's data, Hertz linearised at P + m g
    # rtol 1e-9: at the default 1e-6 the integration error of the 10-nm response is 4 % of its swing
    _, _, rows, _ = sweep(tmp_path / "peak", "--set", "contact_model=hertz", "--set", "a=1e-8", "--set", "rtol=1e-9",
                          "--grid", "f=260.3:280.3:11", "--stop-time", "0.2", "--step", "1e-4")
    assert all(r["status"] == "ok" for r in rows)
    f, swing = col(rows, "f"), col(rows, "F_max") - col(rows, "F_min")
    assert abs(f[np.argmax(swing)] - fn) < 1.0, (f[np.argmax(swing)], fn)
    # and the response falls off on both sides (a peak, not an edge)
    assert swing[0] < 0.2 * swing.max() and swing[-1] < 0.2 * swing.max()


# ---- engine -------------------------------------------------------------------------------------
BOUNCING = ["--set", "contact_model=johnson", "--set", "a=1e-4", "--grid", "f=150:550:5", "--grid", "Y=6e8:1e9:2",
            "--stop-time", "0.03", "--transient", "0.01"]


@pytest.fixture(scope="module")
def two_workers(tmp_path_factory):
    out = tmp_path_factory.mktemp("w2") / "out"
    sweep(out, *BOUNCING, workers=2)
    return out


def same_files(a, b):
    for name in ("sweep.csv", "poincare.csv"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


@pytest.mark.timeout(150)
def test_results_do_not_depend_on_the_number_of_workers(two_workers, tmp_path):
    _, _, rows, pc = sweep(tmp_path / "w1", *BOUNCING, workers=1)
    assert len(rows) == 10 and all(r["status"] == "ok" for r in rows)
    assert sum(int(r["n_impacts"]) for r in rows) > 0 and len(pc) > 0  # bouncing: a meaningful comparison
    same_files(two_workers, tmp_path / "w1")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_port(port, proc, timeout=60):
    end = time.monotonic() + timeout
    while time.monotonic() < end:  # bounded by the timeout
        if proc.poll() is not None:
            raise RuntimeError(f"the process exited with {proc.returncode}")
        with socket.socket() as s:
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return
        time.sleep(0.2)
    raise TimeoutError(f"nothing listens on port {port} after {timeout} s")


@pytest.fixture
def dask_cluster(tmp_path):
    """`dask scheduler` and one `dask worker` on loopback, as separate processes started in a directory
    of their own (the sweep ships its code and the FMU to the worker)."""
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    work = tmp_path / "cluster"
    work.mkdir()
    procs = []
    try:
        procs.append(subprocess.Popen(
            [sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
            cwd=work, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True))
        wait_for_port(port, procs[0])
        procs.append(subprocess.Popen(
            [sys.executable, "-m", "dask", "worker", f"tcp://127.0.0.1:{port}", "--host", "127.0.0.1",
             "--nworkers", "1", "--nthreads", "1", "--no-dashboard", "--local-directory", str(work)],
            cwd=work, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True))
        yield f"tcp://127.0.0.1:{port}"
    finally:
        for p in reversed(procs):
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGTERM)
        for p in reversed(procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait(timeout=10)


@pytest.mark.timeout(200)
def test_same_sweep_on_a_separately_started_scheduler(two_workers, dask_cluster, tmp_path):
    _, _, rows, _ = sweep(tmp_path / "remote", *BOUNCING, "--scheduler", dask_cluster, workers=None)
    assert len(rows) == 10
    same_files(two_workers, tmp_path / "remote")


def test_no_scheduler_is_an_error_not_a_hang(tmp_path):
    code, err, _, _ = sweep(tmp_path / "none", "--grid", "f=100:200:2", "--scheduler",
                            f"tcp://127.0.0.1:{free_port()}", "--connect-timeout", "3", workers=None,
                            check=False)
    assert code == 1 and "sweep:" in err


def test_a_failed_point_stays_with_the_fmus_message(tmp_path):
    _, _, rows, _ = sweep(tmp_path / "bad", "--set", "a=1e-5", "--grid", "nu1=0.1:0.7:3", "--grid", "m=-100:400:2",
                          "--stop-time", "0.005")
    assert [(r["nu1"], r["m"]) for r in rows] == [(x, y) for x in ("0.1", "0.4", "0.7") for y in ("-100.0", "400.0")]
    status = {(float(r["nu1"]), float(r["m"])): r for r in rows}
    for (nu, m), r in status.items():
        bad = nu > 0.5 or m <= 0
        assert r["status"] == ("error" if bad else "ok"), r
        if bad:
            assert r["F_max"] == "" and r["n_impacts"] == ""
            wrong = {"nu1 = ": nu > 0.5, "m = -100": m <= 0}  # the message names a value that is wrong
            named = [w for w in wrong if w in r["message"]]
            assert named and all(wrong[w] for w in named), r["message"]
        else:
            assert float(r["F_max"]) > 0 and r["message"] == ""


@pytest.mark.parametrize("args, words", [
    (["--set", "m=-1", "--grid", "f=100:200:3"], ["every corner", "m = -1 is outside its range m > 0"]),
    (["--set", "nu1=0.7"], ["--set values", "nu1 = 0.7 is outside its range"]),
    (["--grid", "m=-200:-100:3"], ["every corner", "m = -200 is outside its range m > 0"]),
])
def test_values_the_fmu_refuses_everywhere_stop_the_sweep_before_it_starts(tmp_path, args, words):
    """The FMU's reason, at once: nothing is distributed and nothing is written."""
    code, err, _, _ = sweep(tmp_path / "refused", *args, check=False)
    assert code == 2 and "Traceback" not in err, err
    assert all(w in err for w in words), err
    assert not (tmp_path / "refused").exists()


def test_a_corner_the_fmu_refuses_is_named_and_the_sweep_runs(tmp_path):
    code, err, rows, _ = sweep(tmp_path / "corner", "--set", "a=1e-5", "--grid", "m=-100:400:2", "--stop-time", "0.005")
    assert code == 0 and "m=-100" in err and "m = -100 is outside its range" in err, err
    assert [r["status"] for r in rows] == ["error", "ok"]


def test_an_fmi3_fmu_is_refused(tmp_path):
    from vibroimpact.fmi3 import fmu3_path
    fmu3 = fmu3_path(required=False)
    if not fmu3.is_file():
        pytest.fail(f"{fmu3} is missing: build it with cmake --build build")
    p = subprocess.run([*SWEEP, "--fmu", str(fmu3), "--out", str(tmp_path / "x"), "--grid", "f=100:200:2"],
                       capture_output=True, text=True, timeout=RUN_TIMEOUT_S)
    assert p.returncode == 2 and "FMI 3.0" in p.stderr and "FMI 2.0" in p.stderr, p.stderr


def test_every_point_failing_exits_nonzero_with_the_first_reason(tmp_path):
    """The FMU accepts the start values but every run ends: a profile of 1 mm rolled over at 10 m/s
    runs off its end after 0.1 ms."""
    profile = tmp_path / "short.txt"
    profile.write_text("0 0\n0.001 0\n")
    out = tmp_path / "short"
    code, err, _, _ = sweep(out, "--set", f"profile_file={profile}", "--set", "V=10", "--grid", "f=100:200:2",
                            "--stop-time", "0.01", check=False)
    assert code == 1 and "Traceback" not in err, err
    last = err.strip().splitlines()[-1]
    assert "every point failed" in last and "f=100" in last and "end of the profile" in last, err
    with open(out / "sweep.csv", newline="") as fh:
        assert [r["status"] for r in csv.DictReader(fh)] == ["error", "error"]


INTERRUPTED = ["--set", "a=1e-4", "--grid", "f=100:600:24", "--stop-time", "0.3"]


def data_rows(path):
    return len(path.read_text().splitlines()) - 1 if path.is_file() else 0


@pytest.mark.timeout(250)
def test_ctrl_c_keeps_the_finished_points_and_resume_runs_the_rest(tmp_path):
    """SIGINT to the whole process group, as a terminal's Ctrl-C sends it, once some points are in
    sweep.csv: exit 130, one line saying what was kept, the finished points in grid order. --resume
    then runs the rest: the files are those of an uninterrupted run, byte for byte."""
    out = tmp_path / "cut"
    cmd = [*SWEEP, "--fmu", str(FMU), "--out", str(out), "--no-progress", "--no-plots", "--workers", "1", *INTERRUPTED]
    # a terminal's process has SIGINT's default action, whatever this one inherited (a test command
    # started in the background of a script runs with SIGINT ignored, and so would the sweep)
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        end = time.monotonic() + RUN_TIMEOUT_S
        while data_rows(out / "sweep.csv") < 3 and p.poll() is None and time.monotonic() < end:  # bounded
            time.sleep(0.05)
        os.killpg(p.pid, signal.SIGINT)
        _, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=10)
    assert p.returncode == 130 and "Traceback" not in err, err
    assert "interrupted" in err and "--resume" in err, err
    with open(out / "sweep.csv", newline="") as fh:
        kept = list(csv.DictReader(fh))
    grid = [repr(float(x)) for x in np.linspace(100, 600, 24)]
    assert 3 <= len(kept) < 24 and all(r["status"] == "ok" for r in kept)
    assert [r["f"] for r in kept] == [f for f in grid if f in {r["f"] for r in kept}]  # grid order
    assert f"{len(kept)} of 24 points" in err, err

    resumed = subprocess.run([*cmd, "--resume"], capture_output=True, text=True, timeout=RUN_TIMEOUT_S)
    assert resumed.returncode == 0, resumed.stderr
    assert f"sweep: {24 - len(kept)} point{'s' if len(kept) < 23 else ''} in" in resumed.stdout, resumed.stdout
    assert f"{len(kept)} kept from before" in resumed.stdout, resumed.stdout
    sweep(tmp_path / "whole", *INTERRUPTED, workers=1)
    same_files(tmp_path / "whole", out)


def test_resume_runs_a_continuation_chain_with_a_missing_point_whole(tmp_path):
    """A continuation point depends on the one before it on its chain: --resume with the last
    point of one chain missing reruns that chain from its start, and the files come out as those
    of the complete sweep."""
    args = ["--set", "contact_model=hertz", "--set", "f=200", "--grid", "F_ext=0:2000:3", "--grid", "a=1e-6:2e-6:2",
            "--stop-time", "0.01", "--sweep-direction", "up"]
    sweep(tmp_path / "whole", *args)
    cut = tmp_path / "cut"
    sweep(cut, *args)
    lines = (cut / "sweep.csv").read_text().splitlines(keepends=True)
    (cut / "sweep.csv").write_text("".join(lines[:-1]))   # F_ext = 2000, a = 2e-6: the end of a chain
    _, _, rows, _ = sweep(cut, *args, "--resume")
    assert len(rows) == 6
    same_files(tmp_path / "whole", cut)


def test_resume_refuses_a_folder_of_another_sweep(tmp_path):
    sweep(tmp_path / "one", "--set", "a=1e-5", "--grid", "f=100:200:2", "--stop-time", "0.005")
    code, err, _, _ = sweep(tmp_path / "one", "--set", "a=2e-5", "--grid", "f=100:200:2", "--stop-time", "0.005",
                            "--resume", check=False)
    assert code == 2 and "--resume" in err and "other settings (set)" in err, err


def test_options_that_cannot_run_are_refused_before_running(tmp_path):
    for args, words in ((["--grid", "nosuch=1:2:2"], "unknown variable 'nosuch'"),
                        (["--set", "contact_model=plastic"], "neither an integer nor an item name"),
                        (["--grid", "F=1:2:2"], "only parameters and inputs"),
                        (["--grid", "f=1:2:2", "--transient", "0.2"], "--transient"),
                        (["--grid", "m=300:400:2", "--sweep-direction", "up"], "must be tunable")):
        code, err, _, _ = sweep(tmp_path / "refused", *args, check=False)
        assert code == 2 and words in err, (args, err)


# ---- enumerations -------------------------------------------------------------------------------
def test_enumerations_by_item_name_or_value(tmp_path):
    common = ["--set", "a=1e-4", "--set", "Y=6e8", "--grid", "f=300:560:2", "--stop-time", "0.01"]
    _, _, by_name, _ = sweep(tmp_path / "name", "--set", "contact_model=lepp", "--set", "unloading=continuous", *common)
    _, _, by_value, _ = sweep(tmp_path / "value", "--set", "contact_model=3", "--set", "unloading=2", *common)
    _, _, hertz, _ = sweep(tmp_path / "hertz", "--set", "contact_model=hertz", *common)
    assert by_name == by_value
    assert [r["F_max"] for r in by_name] != [r["F_max"] for r in hertz]


def test_item_names_from_the_description_of_an_integer(tmp_path):
    """An enumeration declared as an Integer (as for libcosim) may keep 'name=value' pairs in its
    description; the sweep maps item names through them."""
    from fmpy import extract
    xml = pathlib.Path(extract(str(FMU), unzipdir=str(tmp_path / "x"))) / "modelDescription.xml"
    text = xml.read_text()
    old = '<Enumeration declaredType="ContactModel" start="2"/>'
    assert old in text or 'name="contact_model"' in text
    text = text.replace('description="contact law" causality="parameter"',
                        'description="contact law: hertz=1, johnson=2, lepp=3" causality="parameter"')
    text = text.replace(old, '<Integer start="2"/>')
    xml.write_text(text)
    interface = spec.Interface(str(xml))
    assert interface.variables["contact_model"].kind == spec.INTEGER
    assert interface.value("contact_model", "lepp") == 3
    assert interface.value("contact_model", "1") == 1
    with pytest.raises(spec.SpecError, match="hertz=1, johnson=2, lepp=3"):
        interface.value("contact_model", "plastic")


# ---- continuation -------------------------------------------------------------------------------

def test_continuation_continues_the_state(tmp_path):
    """A chain of two equal points is one run cut in two: the second point's statistics over its
    [0, T] are the uninterrupted run's over [T, 2T] (the value is set again at the cut; the solver
    may restart there, hence a tolerance). The continued parameter is the input F_ext."""
    base = ["--set", "contact_model=hertz", "--set", "a=5e-6", "--set", "f=200", "--set", "rtol=1e-10"]
    _, _, chain, pc_chain = sweep(tmp_path / "chain", *base, "--grid", "F_ext=1000:1000:2", "--stop-time", "0.02",
                                  "--sweep-direction", "up")
    _, _, whole, pc_whole = sweep(tmp_path / "whole", *base, "--grid", "F_ext=1000:1000:1", "--stop-time", "0.04",
                                  "--transient", "0.02")
    assert [r["status"] for r in chain] == ["ok", "ok"]
    for k in ("F_max", "F_min", "F_mean", "delta_max"):
        assert float(chain[1][k]) == pytest.approx(float(whole[0][k]), rel=1e-6), k
    second = pc_chain[-len(pc_whole):]  # the second point's samples: t = 0.02 (the cut, its start) to 0.04
    np.testing.assert_allclose(col(second, "t"), col(pc_whole, "t"), rtol=0, atol=1e-12)
    np.testing.assert_allclose(col(second, "delta"), col(pc_whole, "delta"), rtol=1e-7)
    # the first point of a chain is an ordinary independent point
    _, _, first, _ = sweep(tmp_path / "first", *base, "--grid", "F_ext=1000:1000:1", "--stop-time", "0.02")
    assert chain[0] == first[0]


def test_chains_run_along_the_first_grid_one_per_combination_of_the_others():
    """Grid order: first grid outermost. A continuation runs one chain per value of the other grids,
    along the first grid in the sweep's direction; independent points are chains of one."""
    interface = spec.Interface(str(FMU))
    grids = [spec.parse_grid(interface, "F_ext=0:2000:3"), spec.parse_grid(interface, "a=1e-6:1e-4:2", log=True)]
    assert grids[1][1] == [1e-6, 1e-4]
    sw = spec.Sweep(fixed={"contact_model": 1}, grids=grids, stop_time=0.01, step=1e-5, direction="down")
    points = sw.points()
    assert [(v["F_ext"], v["a"]) for _, v in points] == [(x, y) for x in (0.0, 1000.0, 2000.0) for y in (1e-6, 1e-4)]
    chains = spec.chains(sw, interface)
    assert [c[0] for c in chains] == [[4, 2, 0], [5, 3, 1]]
    for indices, fixed, per_point in chains:
        assert {n for n, *_ in fixed} == {"contact_model", "a"}
        assert [e[0][3] for e in per_point] == [points[i][1]["F_ext"] for i in indices]
    sw.direction = None
    assert [c[0] for c in spec.chains(sw, interface)] == [[i] for i in range(6)]


def test_continuation_direction_orders_the_chain(tmp_path):
    """Rows stay in grid order; up runs ascending, down descending: the Poincare times say which
    point ran first on the instance."""
    args = ["--set", "contact_model=hertz", "--set", "a=5e-6", "--set", "f=200", "--grid", "F_ext=0:2000:3",
            "--stop-time", "0.01"]
    for direction in ("up", "down"):
        _, _, rows, pc = sweep(tmp_path / direction, *args, "--sweep-direction", direction)
        assert [r["F_ext"] for r in rows] == ["0.0", "1000.0", "2000.0"]
        first_t = [min(float(p["t"]) for p in pc if p["F_ext"] == r["F_ext"]) for r in rows]
        assert first_t == sorted(first_t, reverse=(direction == "down"))
        assert min(first_t) == 0.0


@pytest.mark.timeout(150)
def test_up_and_down_sweeps_jump_on_either_side_of_the_resonance(tmp_path):
    """Hertz, a = 5 um, continuation in the tunable f. Sweeping up, the mass stays on the platform
    until the growing response lifts it off below the contact resonance; sweeping down it stays on
    until above it. Without damping the bouncing then persists, so between the two jumps each
    direction keeps a branch the other does not reach: hysteresis around f_contact."""
    assert spec.Interface(str(FMU)).variables["f"].tunable, "the continuation in f needs f tunable"
    fn, _ = linear_resonance_hz()
    args = ["--set", "contact_model=hertz", "--set", "a=5e-6", "--grid", "f=230:310:9", "--stop-time", "0.1",
            "--transient", "0.05"]
    _, _, up, _ = sweep(tmp_path / "up", *args, "--sweep-direction", "up")
    _, _, down, _ = sweep(tmp_path / "down", *args, "--sweep-direction", "down")
    f = col(up, "f")
    cu, cd = col(up, "contact_fraction"), col(down, "contact_fraction")
    assert cu[0] == 1.0 and cd[-1] == 1.0  # both start in permanent contact
    f_up = f[np.argmax(cu < 1)]            # first loss of contact going up
    f_down = f[::-1][np.argmax(cd[::-1] < 1)]  # first loss going down
    assert f_up < fn < f_down, (f_up, fn, f_down)
    # the bouncing, once reached, persists (no damping): each direction keeps a branch the other misses
    below, above = f < f_up, f > f_down
    assert below.any() and above.any()
    assert np.all(cu[below] == 1) and np.all(cd[below] < 1)
    assert np.all(cd[above] == 1) and np.all(cu[above] < 1)


class _InterruptAfterFlush:
    """A file whose flush() writes, then raises KeyboardInterrupt: Ctrl-C the instant a row is on disk."""

    def __init__(self, fh):
        self.fh = fh

    def __getattr__(self, name):
        return getattr(self.fh, name)

    def flush(self):
        self.fh.flush()
        raise KeyboardInterrupt


def test_a_row_on_disk_when_ctrl_c_comes_is_kept(tmp_path):
    """Ctrl-C may come the instant a point's row reached sweep.csv: the files the interrupted sweep
    leaves still hold that row (finish() rewrites them from what the sweep holds)."""
    from vibroimpact.sweep import engine
    sw = spec.Sweep(fixed={}, grids=[("f", [100.0, 200.0])], stop_time=0.01, step=1e-5)
    out = engine.Output(str(tmp_path), sw)
    result = dict(status="ok", message="", poincare=[], **{k: 1.0 for k in engine.STATS})
    out.add([0], [result])
    out._files[0] = _InterruptAfterFlush(out._files[0])
    with pytest.raises(KeyboardInterrupt):
        out.add([1], [result])
    out._files[0] = out._files[0].fh
    out.finish()
    with open(tmp_path / "sweep.csv", newline="") as fh:
        kept = [row["f"] for row in csv.DictReader(fh)]
    assert kept == ["100.0", "200.0"]
