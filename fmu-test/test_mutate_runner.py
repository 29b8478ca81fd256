"""tools/mutate.py: its way of running a command (a command past its time limit is killed with every
process it started, also those in a session of their own, as ctest starts each test); its coverage map
(a test that reads work a fixture of any scope cached gets that work's lines); its verdicts (a timeout
is its own verdict, outside the score)."""
import importlib.util
import json
import pathlib
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent


def load_mutate():
    spec = importlib.util.spec_from_file_location("mutate_tool", ROOT / "tools" / "mutate.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def running(pid):
    """Is pid a process that has not ended (a zombie has)?"""
    try:
        state = pathlib.Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return False
    return state != "Z"


def test_a_command_past_its_limit_leaves_no_process_behind(tmp_path):
    mutate = load_mutate()
    pids = tmp_path / "pids"
    # a child in a session of its own (setsid) and a grandchild of it, both sleeping past the limit
    script = f"setsid bash -c 'sleep 300 & echo $! >> {pids}; wait' & echo $! >> {pids}; wait"
    t0 = time.monotonic()
    status, _ = mutate.run(["bash", "-c", script], tmp_path, timeout=2)
    assert status == "timeout"
    assert time.monotonic() - t0 < 60
    started = [int(p) for p in pids.read_text().split()]
    assert len(started) == 2
    for _ in range(100):  # SIGKILL is delivered at once; the wait is for the kernel to tear them down
        if not any(running(p) for p in started):
            break
        time.sleep(0.05)
    assert not [p for p in started if running(p)], "still running after the timeout"


def test_a_command_within_its_limit_gives_its_status_and_output(tmp_path):
    status, out = load_mutate().run(["bash", "-c", "echo done; exit 3"], tmp_path, timeout=60)
    assert (status, out) == (3, "done\n")


# ---- the coverage map: tests that share cached work ------------------------------------------------

# A stand-in for the FMU's lines: work() "executes" a line of src/fake.c that the plugin's flushed() reads.
SHARED_TESTS = '''
import functools
import pytest

EXECUTED = []


def work(line):
    EXECUTED.append(line)
    return line


class Facts:
    """Facts computed on first use and cached, as fmu-test/doc_numbers.py's Sources."""
    @functools.cached_property
    def first(self):
        return work(1)

    @functools.lru_cache(maxsize=None)
    def fact(self, n):
        return work(n)


@pytest.fixture(scope="session")
def facts():
    return Facts()


@pytest.fixture(scope="session")
def path():
    work(50)  # the fixture's own setup: shared with every test that uses it
    return "/a/path"


@pytest.fixture(scope="module")
def table():
    return {}


def test_a(facts):
    assert facts.first == 1 and facts.fact(10) == 10


def test_b(facts):
    assert facts.first == 1 and facts.fact(10) == 10  # both cached: test_a did the work


def test_c(path):
    work(60)


def test_d(path):
    pass


def test_e(table):
    table.setdefault("x", work(70))


def test_f(table):
    assert table["x"] == 70
'''

RUN_PLUGIN = '''
import json, sys
import importlib.util
spec = importlib.util.spec_from_file_location("mutate_tool", sys.argv[2])
mutate = importlib.util.module_from_spec(spec)
spec.loader.exec_module(mutate)
import pytest


def flushed():
    test_shared = sys.modules.get("test_shared")  # as pytest imports it from its rootdir, once collected
    if test_shared is None or not test_shared.EXECUTED:
        return {}
    lines = {"src/fake.c": sorted(set(test_shared.EXECUTED))}
    test_shared.EXECUTED.clear()
    return lines


sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", "-p", "no:randomly", "--rootdir", sys.argv[1], sys.argv[1]],
                     plugins=[mutate.coverage_plugin(flushed, sys.argv[3])]))
'''


def test_tests_that_read_a_cache_of_any_fixture_scope_get_its_lines(tmp_path):
    """A test that reads a fact a session-scoped fixture cached (computed in the test that asked first)
    is selected by the fact's lines, as one that reads a module-scoped fixture's cache is; a session
    fixture whose value no test changes (a path) shares its setup only, not its users' lines."""
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "test_shared.py").write_text(SHARED_TESTS)
    (tmp_path / "tests" / "pytest.ini").write_text("[pytest]\n")
    out = tmp_path / "map.jsonl"
    r = subprocess.run([sys.executable, "-c", RUN_PLUGIN, str(tmp_path / "tests"), str(ROOT / "tools" / "mutate.py"),
                        str(out)], capture_output=True, text=True, timeout=100, cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    lines = {}
    for row in out.read_text().splitlines():
        e = json.loads(row)
        lines[e["test"].split("::")[1]] = set(e["lines"].get("src/fake.c", []))
    assert lines["test_a"] == {1, 10}
    assert lines["test_b"] == {1, 10}  # before: set(), never selected by a mutant of the fact's lines
    assert lines["test_e"] == lines["test_f"] == {70}
    assert lines["test_c"] == {50, 60} and lines["test_d"] == {50}


# ---- verdicts: a timeout is no kill ------------------------------------------------------------------

def test_a_timeout_is_its_own_verdict_counted_and_listed_apart(tmp_path, monkeypatch, capsys):
    mutate = load_mutate()
    mutant = type("M", (), dict(file="src/x.c", ident="src/x.c:f:op:+->-:1 | a + b", where="src/x.c:3:5",
                                body=(1, 2)))()
    runner = object.__new__(mutate.Runner)
    runner.original_code = {tmp_path: {"src/x.c": {}}}
    runner.durations, runner.equivalent, runner.replay, runner.make_jobs = {"pytest:t": 1.0}, {}, False, "-j1"
    monkeypatch.setattr(mutate, "run", lambda *a, **k: (0, ""))  # the build of the mutant
    monkeypatch.setattr(mutate, "run_selected", lambda *a, **k: ("timeout", "pytest: past the limit of 63 s"))
    runner.compilers = []
    verdict, _, why = runner.verdict(mutant, tmp_path, tmp_path / "src/x.c", ["pytest:t"], "")
    assert verdict == "timeout" and "past the limit" in why  # before: "killed"

    base = dict(where="src/x.c:3:5", tests=1, seconds=1.0, sanitized=False, killed_by="", timed_out="")
    results = [dict(base, name="k", verdict="killed", killed_by="t"), dict(base, name="s", verdict="survived"),
               dict(base, name="slow", verdict="timeout", timed_out="pytest: past the limit of 63 s"),
               dict(base, name="listed", verdict="timeout", timed_out="pytest: t - past its time limit")]
    listed = mutate.report(results, 1, 4, {"listed": "a reason"}, "")
    text = capsys.readouterr().out
    assert "killed 1, survived 1, uncovered 0, timeout 2" in text
    assert "1 of 2 non-equivalent mutants killed, 50.0 %" in text  # the timeouts are outside the score
    assert "timeout (a test ran past its time limit" in text and "slow" in text.split("timeout (")[1]
    assert [r["name"] for r in listed] == ["listed"]  # a listed equivalent that timed out is not shown equivalent


# A source compiled by two targets (the second defines TWICE); the mutants change the store to unused.
TCE_SOURCE = """int f(int x) {
    int unused = x + 1;
#ifdef TWICE
    return 2 * unused;
#endif
    return x;
}
int g(int x) { return x + 3; }
"""


def test_a_mutant_compiled_to_the_original_assembly_in_every_target_is_identical(tmp_path):
    """Trivial compiler equivalence beyond the build's objects: a mutant whose source a compiler of
    TCE_COMPILERS turns into the original's assembly in every way the build compiles it is "identical" and
    runs no test; one that differs in one target (a store dead only without TWICE) or anywhere (g's
    constant) is not."""
    import shutil
    if not shutil.which("gcc"):
        raise AssertionError("gcc is not installed (Debian: apt-get install gcc)")
    mutate = load_mutate()
    src = tmp_path / "src" / "fake.c"
    src.parent.mkdir()
    src.write_text(TCE_SOURCE)
    (tmp_path / "build").mkdir()

    def commands(defines):
        entries = [dict(directory=str(tmp_path / "build"), file=str(src),
                        command=f"/usr/bin/cc {d} -O3 -flto=auto -Wall -o CMakeFiles/t{k}.dir/fake.c.o -c {src}")
                   for k, d in enumerate(defines)]
        (tmp_path / "build" / "compile_commands.json").write_text(json.dumps(entries))

    runner = object.__new__(mutate.Runner)
    runner.compilers, runner.original_asm = [("gcc", "-O2")], {}
    store = TCE_SOURCE.index("x + 1") + 2

    def mutant(at, new):
        m = type("M", (), dict(file="src/fake.c", start=at, end=at + 1, new=new))()
        src.write_text(TCE_SOURCE[:at] + new + TCE_SOURCE[at + 1:])  # in place, as run_mutant writes it
        return runner.same_assembly(m, tmp_path, src, TCE_SOURCE)

    commands(["-DONE"])
    assert mutate.compile_flags(tmp_path / "build", "src/fake.c") == [
        (str(tmp_path / "build"), ["-DONE", "-Wall", str(src)])]  # no output, level or link-time flags
    assert mutant(store, "-") == "gcc -O2"  # the store is dead: the same code
    assert src.read_text() == TCE_SOURCE[:store] + "-" + TCE_SOURCE[store + 1:]  # the mutant left in place
    assert mutant(TCE_SOURCE.index("x + 3") + 2, "-") == ""  # g returns another value
    runner.original_asm = {}
    commands(["-DONE", "-DTWICE"])
    assert mutant(store, "-") == ""  # the store is read where TWICE is defined


def test_a_test_stopped_at_its_own_time_limit_is_a_timeout(tmp_path):
    """pytest.ini's timeout stops a hung test as a failure: mutate.py reads it as a timeout."""
    mutate = load_mutate()
    (tmp_path / "test_hang.py").write_text("import time\n\ndef test_hangs():\n    time.sleep(30)\n\n"
                                           "def test_fails():\n    assert False\n")
    base = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--timeout", "1", "--rootdir", str(tmp_path)]
    limit = 60
    outcome, why = mutate.run_confirmed(base + [str(tmp_path / "test_hang.py") + "::test_hangs"], None, tmp_path,
                                        time.monotonic() + limit, limit)
    assert outcome == "timeout", why
    outcome, why = mutate.run_confirmed(base + [str(tmp_path / "test_hang.py") + "::test_fails"], None, tmp_path,
                                        time.monotonic() + limit, limit)
    assert outcome == "failed", why


# ---- the tests VI_SOLVER reaches (fmu-test/conftest.py), as tools/test.sh's loop and mutate.py select them ----

def test_the_solver_loop_runs_the_tests_the_solver_choice_reaches(tmp_path):
    """--solver-tests-out lists the tests that start a run without a solver of their own (test_me_call_order's
    instances take VI_SOLVER's) and not those whose runs take the FMU's default whatever VI_SOLVER says
    (test_read_all's); --solver-tests-from runs only the listed ones; mutate.py's coverage passes read the
    same selection from tools/test.sh's loop."""
    files = ["fmu-test/test_read_all.py", "fmu-test/test_me_call_order.py"]
    listed = tmp_path / "solver-tests.json"
    r = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *files, "--solver-tests-out",
                        str(listed)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout[-2000:]
    ids = json.loads(listed.read_text())
    assert len(ids) == 66 and all(i.startswith("fmu-test/test_me_call_order.py::") for i in ids), ids
    r = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider", *files,
                        "--solver-tests-from", str(listed)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert "66/71 tests collected (5 deselected)" in r.stdout, r.stdout[-2000:]
    solvers, select = load_mutate().test_solvers()
    assert solvers == ["1", "2", "3"] and select[:3] == ["-m", "not libcosim", "--solver-tests-from"]


# ---- a journal: a long run over several sittings ------------------------------------------------------

def test_a_journal_keeps_each_result_and_gives_back_only_todays_revision(tmp_path, monkeypatch):
    """--journal: each mutant's result is appended as it ends; a later run takes the results held for
    today's revision (and only those: another revision's code or tests may give another verdict)."""
    mutate = load_mutate()
    (tmp_path / "src").mkdir()
    (tmp_path / "src/x.c").write_text("int f(int a, int b) { return a + b; }\n")
    source = (tmp_path / "src/x.c").read_text()
    start = source.index("+")
    mutant = type("M", (), dict(file="src/x.c", ident="src/x.c:f:op:+->-:1 | return a + b;", where="src/x.c:1:33",
                                start=start, end=start + 1, new="-"))()
    journal = tmp_path / "journal.jsonl"
    journal.write_text(json.dumps(dict(revision="old", result=dict(name="other", verdict="killed"))) + "\n")
    runner = object.__new__(mutate.Runner)
    runner.journal, runner.revision, runner.n_mutants, runner.done, runner.t0 = journal, "today", 1, 0, time.monotonic()
    runner.free = mutate.queue.Queue()
    runner.free.put(tmp_path)
    runner.printing = mutate.threading.Lock()
    runner.tests_of = lambda m: ["pytest:t"]
    seen = []
    runner.verdict = lambda m, scratch, target, tests, original: (seen.append(target.read_text()), ("survived", "", ""))[1]
    result = runner.run_mutant(mutant)
    assert seen == ["int f(int a, int b) { return a - b; }\n"]  # the mutant was in place while it ran
    assert (tmp_path / "src/x.c").read_text() == source  # and is gone after
    held = mutate.read_journal(journal, "today")
    assert held == {mutant.ident: result} and result["verdict"] == "survived"
    assert set(mutate.read_journal(journal, "old")) == {"other"}
    assert mutate.read_journal(tmp_path / "none.jsonl", "today") == {}
