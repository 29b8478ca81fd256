"""The `vibroimpact` commands as a user meets them: an option that the command or the FMU refuses ends
the command before its long work, with a non-zero exit and one line that names what was wrong (in the
FMU's own words when the FMU refused it), never a traceback; `paper` run on some scenarios keeps the
other scenarios' figures; the README's command table names every command and its output folder.
(The sweep's own checks are in test_sweep.py.)"""
import csv
import os
import re
import subprocess
import sys

import pytest
from conftest import ROOT

from vibroimpact import cli
from vibroimpact.cli import diagrams
from vibroimpact.cli import sweep as sweep_command
from vibroimpact.fmi3 import fmu3_path
from vibroimpact.fmu import ENV
from vibroimpact.reference.scenarios import SCENARIOS

VI = [sys.executable, "-m", "vibroimpact"]
RUN_TIMEOUT_S = 100
README = ROOT / "README.md"


def vi(*args, cwd, env=None):
    return subprocess.run([*VI, *args], capture_output=True, text=True, timeout=RUN_TIMEOUT_S, cwd=cwd,
                          env=None if env is None else {**os.environ, **env})


def refused(p, code, *words):
    """Exit `code`, no traceback, and the last line of stderr holds every one of `words`."""
    assert p.returncode == code, (p.returncode, p.stderr)
    assert "Traceback" not in p.stderr, p.stderr
    last = p.stderr.strip().splitlines()[-1] if p.stderr.strip() else ""
    assert all(w in last for w in words), (words, p.stderr)
    return last


# ---- options the FMU refuses: its reason, before the long work ------------------------------------
def test_fmi3_says_why_the_fmu_refuses_the_tolerance(tmp_path):
    if not fmu3_path(required=False).is_file():
        pytest.fail(f"{fmu3_path(required=False)} is missing: build it with cmake --build build")
    p = vi("fmi3", "--rtol", "1", cwd=tmp_path)
    refused(p, 1, "vibroimpact fmi3:", "--rtol 1", "fmi3EnterInitializationMode", "tolerance")
    assert "| scenario" not in p.stdout   # stopped before the table


@pytest.mark.parametrize("args, words", [
    (["compare", "--rtol", "5"], ["--rtol 5", "fmi2SetupExperiment", "tolerance"]),
    (["compare", "--solver", "9"], ["--solver 9", "solver = 9", "bdf=1"]),
    (["me-cost", "--rtols", "7"], ["--rtols 7", "rtol = 7 is outside its range"]),
])
def test_table_commands_say_why_the_fmu_refuses_an_option(tmp_path, args, words):
    p = vi(*args, cwd=tmp_path)
    refused(p, 1, f"vibroimpact {args[0]}:", *words)
    assert "| scenario" not in p.stdout


def test_a_simulation_the_fmu_refuses_says_why(fmu_path):
    """paper and rolling run fmpy.simulate_fmu through vibroimpact.fmu.simulate, which keeps the log."""
    from vibroimpact.failure import CommandError
    from vibroimpact.fmu import simulate
    with pytest.raises(CommandError, match=r"^the run: fmi2SetReal: m = -1 is outside its range m > 0"):
        simulate("the run", fmu_path, start_values={"m": -1.0}, stop_time=0.01)


def test_a_refused_simulation_leaves_fmpy_able_to_run_the_next(fmu_path):
    """After vibroimpact.fmu.simulate failed (its log kept), an fmpy run with fmpy's default logger whose
    FMU logs a warning (rtol against the importer's 1e-4) runs and prints it. fmpy's `logger=` option
    installs a logger in a native proxy its later default instances share: used here, this run called
    freed memory once the failed call's logger was gone (a segmentation fault). In a subprocess, so that
    such a crash fails this test only."""
    code = f"""
from vibroimpact.fmu import simulate
from fmpy import simulate_fmu
try:
    simulate("the run", {fmu_path!r}, start_values={{"m": -1.0}}, stop_time=0.01)
except Exception as e:
    print("refused:", e)
import gc
gc.collect()
simulate_fmu({fmu_path!r}, start_values=dict(contact_model=1, a=1e-4, rtol=1e-10), relative_tolerance=1e-4,
             stop_time=1e-3)
print("done")
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=RUN_TIMEOUT_S)
    assert p.returncode == 0, (p.returncode, p.stderr[-2000:])
    assert "refused: the run: fmi2SetReal: m = -1" in p.stdout and p.stdout.rstrip().endswith("done"), p.stdout
    assert "rtol = 1e-10 is used, not the experiment's tolerance 0.0001" in p.stdout, p.stdout


# ---- options the command refuses ------------------------------------------------------------------
def test_wplastic_refuses_a_yield_stress_that_is_not_positive(tmp_path):
    for y in ("-5", "0", "nan"):
        refused(vi("wplastic", "--Y", y, cwd=tmp_path), 2, "--Y", "> 0")


@pytest.mark.parametrize("args, option", [(["me-cost", "--repeat", "0"], "--repeat"),
                                          (["bench", "--repeat", "0"], "--repeat"),
                                          (["bench-sweep", "--points", "0"], "--points"),
                                          (["diagrams", "--workers", "0"], "--workers")])
def test_counts_below_one_are_refused(tmp_path, args, option):
    p = vi(*args, cwd=tmp_path)
    refused(p, 2, option, "at least 1")
    assert "| scenario" not in p.stdout


@pytest.mark.parametrize("command", ["paper", "rolling", "diagrams", "sweep"])
def test_out_naming_a_file_is_refused(tmp_path, command):
    (tmp_path / "taken").write_text("a file the user keeps\n")
    p = vi(command, "--out", "taken", *(["--grid", "f=100:200:2"] if command == "sweep" else []), cwd=tmp_path)
    refused(p, 2 if command == "sweep" else 1, "--out taken is a file")
    assert (tmp_path / "taken").read_text() == "a file the user keeps\n"


def test_a_missing_fmu_named_by_the_environment_is_said_so(tmp_path):
    last = refused(vi("paper", "fig4a", cwd=tmp_path, env={ENV: "missing.fmu"}), 1, f"{ENV} names",
                   str(tmp_path / "missing.fmu"))
    assert f"set {ENV}" not in last   # it is set: the line says what to do instead


def test_an_unknown_scenario_lists_the_scenarios(tmp_path):
    refused(vi("paper", "fig4", cwd=tmp_path), 2, "unknown scenario fig4", *SCENARIOS)


def test_debug_shows_the_traceback(tmp_path):
    (tmp_path / "taken").write_text("")
    p = vi("--debug", "paper", "--out", "taken", cwd=tmp_path)
    assert p.returncode != 0 and "Traceback" in p.stderr and "CommandError" in p.stderr, p.stderr


# ---- paper keeps the other scenarios' figures -----------------------------------------------------
def read_summary(path):
    with open(path, newline="") as fh:
        return {r["scenario"]: r for r in csv.DictReader(fh)}


@pytest.mark.timeout(200)
def test_paper_on_a_subset_updates_the_summary(tmp_path):
    """A run of one scenario, then of another: summary.csv has both rows, the first one as its own
    run wrote it, in the scenario table's order; the overview is redrawn; the figures are written
    to six significant digits."""
    first, second = "stick", "fig4a"   # fig4a comes first in the table
    assert list(SCENARIOS).index(second) < list(SCENARIOS).index(first)
    assert vi("paper", "--out", "out", first, cwd=tmp_path).returncode == 0
    alone = read_summary(tmp_path / "out" / "summary.csv")
    assert list(alone) == [first]
    p = vi("paper", "--out", "out", second, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    both = read_summary(tmp_path / "out" / "summary.csv")
    assert list(both) == [second, first]
    assert both[first] == alone[first]
    for row in both.values():
        for key, text in row.items():
            if key not in ("scenario", "warnings"):
                digits = re.sub(r"e.*$", "", text.lstrip("-")).replace(".", "").lstrip("0")
                assert len(digits) <= 6, (key, text)
    assert (tmp_path / "out" / "overview.png").stat().st_size > 0


@pytest.mark.timeout(200)
def test_paper_relays_the_fmus_warnings_once_per_scenario_and_records_them(tmp_path):
    """Fig. 6a's indentation (about 10 mm) takes the contact radius beyond 0.1 R*: the FMU logs a
    warning that the results leave the model's range of validity. paper prints it on stderr once, after
    the scenario's name, and keeps it in the scenario's row of summary.csv; fig5a (2 um of indentation
    at most) has none."""
    p = vi("paper", "--out", "out", "fig5a", "fig6a", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    lines = [line for line in p.stderr.splitlines() if "warning" in line]
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("vibroimpact paper: fig6a: warning: ") and "range of validity" in lines[0], lines
    rows = read_summary(tmp_path / "out" / "summary.csv")
    assert 9000 < float(rows["fig6a"]["delta_max_um"]) < 11000   # the indentation the warning is about
    assert lines[0].endswith(rows["fig6a"]["warnings"]) and "exceeds 0.01 R*" in rows["fig6a"]["warnings"]
    assert rows["fig5a"]["warnings"] == ""
    assert "fig6a: " in p.stdout and "1 FMU warning" in p.stdout, p.stdout


@pytest.mark.timeout(200)
@pytest.mark.parametrize("args, runs", [(["compare"], ["fig6a"]),
                                        (["me-cost", "--scenarios", "fig6a", "--rtols", "1e-6", "--repeat", "2"],
                                         ["fig6a ME", "fig6a CS"]),
                                        (["energy", "--variants", "lepp"],
                                         [f"lepp drop {i} FMI {v}.0" for i in ("CS", "ME") for v in (2, 3)])])
def test_other_commands_relay_the_fmus_warnings_as_paper_does(tmp_path, args, runs):
    """The commands that run the FMU pass its warnings on through vibroimpact.fmu.Relay: fig6a's
    indentation (energy: the drop's under LEPP) named once per run (me-cost: its Model Exchange and its
    Co-Simulation run, however often it repeats them; energy: each interface), as paper does."""
    p = vi(*args, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    for run in runs:
        lines = [line for line in p.stderr.splitlines() if line.startswith(f"vibroimpact {args[0]}: {run}: warning: ")]
        assert len(lines) == 1 and "range of validity" in lines[0], p.stderr


def test_a_relay_prints_each_warning_once_per_run():
    import io

    from vibroimpact.fmu import Relay
    out = io.StringIO()
    relay = Relay("cmd", out)
    relay("a", ["w1", "w2"])
    relay("a", ["w1"])
    relay("b", ["w1"])
    assert out.getvalue() == "vibroimpact cmd: a: warning: w1\nvibroimpact cmd: a: warning: w2\n" \
                             "vibroimpact cmd: b: warning: w1\n"
    assert relay.of("a") == ["w1", "w2"] and relay.of("c") == []


@pytest.mark.timeout(200)
def test_rolling_prints_its_figures_to_four_digits(tmp_path):
    p = vi("rolling", "--out", "roll", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    cases = [line for line in p.stdout.splitlines() if line.startswith("case ")]
    assert len(cases) == 3, p.stdout
    for line in cases:
        for number in re.findall(r"-?\d+\.\d+(?:e[-+]?\d+)?", line):
            assert len(number.lstrip("-").split("e")[0].replace(".", "").lstrip("0")) <= 4, (number, line)


# ---- names a user can find ------------------------------------------------------------------------
def readme_commands():
    """{command: the row's text} of the README's command table (rows naming `vibroimpact ...`)."""
    rows = [line for line in README.read_text().splitlines() if line.startswith("| `vibroimpact")]
    named = {}
    for row in rows:
        first = row.split("|")[1]
        words = re.findall(r"`(?:vibroimpact )?([a-z0-9-]+)`", first)
        for w in words:
            named[w] = row
    return named


def test_the_readme_lists_every_command():
    named = readme_commands()
    missing = [c for c in cli.COMMANDS if c not in named]
    assert not missing, f"README's command table lacks {missing}"


def test_sweep_and_diagrams_write_to_folders_named_after_them():
    sweep_out = sweep_command.parse_args([]).out
    named = readme_commands()
    assert sweep_out.rstrip("/").endswith("sweep") and str(diagrams.OUT).endswith("diagrams")
    assert f"`{sweep_out}/`" in named["sweep"] and f"`{diagrams.OUT}/`" in named["diagrams"]


# ---- a command that fails leaves the results it would replace -------------------------------------
LAWS_FILES = ("laws.csv", "laws.md", "laws.png")


def test_an_unknown_laws_scene_is_refused_before_anything_is_written(tmp_path):
    """A finished laws.csv, laws.md and laws.png stay as they were: exit 2, the unknown name and the
    known ones on the last line."""
    from vibroimpact.laws_guide import SCENES
    out = tmp_path / "laws"
    out.mkdir()
    for name in LAWS_FILES:
        (out / name).write_text(f"finished {name}\n")
    refused(vi("laws", "--out", "laws", "--scenes", "fig4b", "nosuch", cwd=tmp_path), 2, "unknown scene nosuch",
            *SCENES)
    assert sorted(p.name for p in out.iterdir()) == sorted(LAWS_FILES)
    for name in LAWS_FILES:
        assert (out / name).read_text() == f"finished {name}\n"


def test_the_laws_scene_names_are_the_scenes_it_runs(tmp_path):
    from vibroimpact import laws_guide
    assert list(laws_guide.scenes(tmp_path / "c.txt", tmp_path / "r.txt")) == list(laws_guide.SCENES)
    with pytest.raises(ValueError, match="unknown scene or variant nosuch: the scenes are drop_0.1"):
        laws_guide.run(tmp_path, only_scenes=["nosuch"])
    assert not list(tmp_path.iterdir())


def test_a_file_whose_writing_fails_keeps_what_it_held(tmp_path):
    """files.replacing: an exception (Ctrl-C included) while writing leaves the old file and no
    temporary one; a complete write replaces it."""
    from vibroimpact import files
    path = tmp_path / "table.csv"
    path.write_text("finished\n")
    for failure in (RuntimeError("the run failed"), KeyboardInterrupt()):
        with pytest.raises(type(failure)):
            with files.replacing(path) as fh:
                fh.write("half a ro")
                raise failure
        assert path.read_text() == "finished\n" and sorted(tmp_path.iterdir()) == [path]
    files.write_text(path, "new\n")
    assert path.read_text() == "new\n" and sorted(tmp_path.iterdir()) == [path]


def test_a_table_whose_writing_fails_keeps_what_it_held(tmp_path):
    """laws.csv written with a row that cannot be written (a column missing) after good ones: the
    finished file stays; matplotlib's figures draw before they open their file, the tables did not."""
    from vibroimpact import laws_guide
    path = tmp_path / "laws.csv"
    path.write_text("finished\n")
    good = dict.fromkeys(laws_guide.COLUMNS, 1.0)
    with pytest.raises(KeyError):
        laws_guide.write_csv(path, [good, {"scene": "drop_1"}])
    assert path.read_text() == "finished\n" and sorted(tmp_path.iterdir()) == [path]


def test_laws_interrupted_while_it_measures_keeps_the_old_results(tmp_path, monkeypatch):
    """Ctrl-C during the runs: exit 130, the finished files as they were."""
    from vibroimpact import laws_guide

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt
    monkeypatch.setattr(laws_guide, "measure", interrupted)
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "laws"
    out.mkdir()
    for name in LAWS_FILES:
        (out / name).write_text(f"finished {name}\n")
    assert cli.main(["laws", "--out", "laws", "--scenes", "drop_1"]) == 130
    for name in LAWS_FILES:
        assert (out / name).read_text() == f"finished {name}\n"


def test_a_sweep_interrupted_before_its_first_point_keeps_the_finished_sweep(tmp_path, monkeypatch):
    """sweep writes each point as it finishes (for --resume); a new sweep in the folder of a finished
    one that is interrupted, or fails, before its first point leaves that sweep's files as they were."""
    from vibroimpact.sweep import engine
    out = tmp_path / "sw"
    out.mkdir()
    finished = {name: f"finished {name}\n" for name in ("sweep.csv", "poincare.csv", "sweep.json")}
    for name, text in finished.items():
        (out / name).write_text(text)
    monkeypatch.chdir(tmp_path)
    for failure, code in ((KeyboardInterrupt(), 130), (OSError("no scheduler there"), 1)):
        def run(*args, **kwargs):
            raise failure
        monkeypatch.setattr(engine, "run", run)
        assert cli.main(["sweep", "--out", "sw", "--grid", "f=100:200:2", "--no-plots"]) == code
        assert {p.name: p.read_text() for p in out.iterdir()} == finished
