"""The documentation cannot go stale unnoticed: doc/testing.md names every test file and no other,
every relative link of README.md and doc/ resolves (file and heading), every number that the code
decides is what the code gives (doc_numbers.py lists them), every file and C name the pages give
exists, doc/using.md's statement of which outputs follow an input is measured, the README stays a front
door (at most 300 lines), the pages hold no pointers outside the repository and no lab notes, the
README's fmpy example runs and finds the impact count of the independent reference, and every
example of README.md and doc/ that runs the FMU runs: each ```python block, and each line of a ```sh
block that starts an importer (fmpy, fmi-sim), with the FMU located by vibroimpact.fmu_path() or
`vibroimpact path` (never build/, which a pip install has not). The other commands of the pages
are the repository's own tools (tools/*.sh, vibroimpact paper/sweep/bench, examples/vehicle-track/run.sh),
which take minutes to hours and are run by tools/test.sh and tools/main.sh themselves."""
import glob
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys

import pytest
import doc_numbers
from conftest import DEFAULT_SOLVER, RUN_SOLVER

ROOT = pathlib.Path(__file__).resolve().parent.parent
TESTING = ROOT / "doc" / "testing.md"
README = ROOT / "README.md"
README_MAX_LINES = 300

# What counts as a test file: every C, Python or shell file under the test folders, and every
# test_* or *_test file anywhere else.
TEST_DIRS = ("tests", "fmu-test")
TEST_SUFFIXES = {".c", ".py", ".sh"}
# Folders that hold generated or installed files, never the repository's own tests.
SKIP_DIRS = {"results", "__pycache__", "node_modules", "dist", "_skbuild"}


def skipped_dir(name):
    return name in SKIP_DIRS or name.startswith((".", "build")) or name.endswith(".egg-info")


def repo_test_files():
    found = set()
    stack = [ROOT]
    while stack:
        folder = stack.pop()
        for p in folder.iterdir():
            if p.is_dir():
                if not skipped_dir(p.name):
                    stack.append(p)
                continue
            rel = p.relative_to(ROOT)
            if p.suffix not in TEST_SUFFIXES:
                continue
            if rel.parts[0] in TEST_DIRS or p.stem.startswith("test_") or p.stem.endswith("_test"):
                found.add(rel.as_posix())
    return found


def section(text, heading):
    """The lines of a markdown section, from its heading to the next heading of the same level."""
    level = heading.split(" ", 1)[0]
    lines = text.splitlines()
    start = lines.index(heading)
    end = next((i for i in range(start + 1, len(lines))
                if lines[i].startswith(level + " ") and lines[i].count("#") == len(level)), len(lines))
    return lines[start + 1:end]


def listed_test_files():
    rows = [ln for ln in section(TESTING.read_text(), "## Every test file") if ln.startswith("| `")]
    return [re.match(r"\| `([^`]+)` \|", ln).group(1) for ln in rows]


def test_testing_md_names_every_test_file():
    listed = listed_test_files()
    assert len(listed) == len(set(listed)), f"named twice in doc/testing.md: {sorted(p for p in listed if listed.count(p) > 1)}"
    missing = sorted(repo_test_files() - set(listed))
    assert not missing, f"test files without a line in doc/testing.md, section 'Every test file': {missing}"


def test_testing_md_names_no_file_that_does_not_exist():
    gone = sorted(p for p in listed_test_files() if not (ROOT / p).is_file())
    assert not gone, f"doc/testing.md names files that do not exist: {gone}"


def test_the_test_file_rule_sees_the_known_kinds():
    """The rule above must see C tests, FMU tests and the reference's tests (else it checks nothing)."""
    found = repo_test_files()
    assert any(p.startswith("tests/test_") and p.endswith(".c") for p in found)
    assert any(p.startswith("fmu-test/test_") for p in found)
    assert any(p.endswith("test_reference.py") for p in found)
    assert "fmu-test/test_docs.py" in found


# ---- links ----------------------------------------------------------------------------------------

def pages():
    return [README] + sorted((ROOT / "doc").rglob("*.md"))


def prose(text):
    """The text without fenced code blocks and inline code (links there are not links)."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(page):
    seen, result = {}, set()
    for line in re.sub(r"^```.*?^```", "", page.read_text(), flags=re.S | re.M).splitlines():
        m = re.match(r"#{1,6} (.*)", line)
        if m:
            s = slug(m.group(1))
            n = seen.get(s, 0)
            seen[s] = n + 1
            result.add(s if n == 0 else f"{s}-{n}")
    return result


def test_slug_follows_github():
    assert slug("Energy and negative plastic work") == "energy-and-negative-plastic-work"
    assert slug("7.1 A step that cannot finish ends early, in a consistent state") == \
        "71-a-step-that-cannot-finish-ends-early-in-a-consistent-state"
    assert slug("What `W_plastic` means") == "what-w_plastic-means"


def test_every_relative_link_resolves():
    bad = []
    for page in pages():
        for target in LINK.findall(prose(page.read_text())):
            if re.match(r"[a-z][a-z0-9+.-]*:", target):  # https:, mailto:
                continue
            path, _, anchor = target.partition("#")
            dest = (page.parent / path).resolve() if path else page
            where = f"{page.relative_to(ROOT)}: {target}"
            if ROOT not in dest.parents and dest != ROOT:
                bad.append(f"{where} (outside the repository)")
            elif not dest.exists():
                bad.append(f"{where} (no such file)")
            elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                bad.append(f"{where} (no such heading)")
    assert not bad, "broken links:\n" + "\n".join(bad)


def test_readme_is_a_front_door():
    n = len(README.read_text().splitlines())
    assert n <= README_MAX_LINES, f"README.md has {n} lines; move detail to a page under doc/"


LAB_NOTES = [r"\.\./shared", r"\b[Ii]ssues? #?[0-9]+", r"\bcontract C[0-9]+", r"\bmissed by\b",
             r"\btarget (was|of)\b", r"\bagainst a target\b", r"\bbefore this change\b",
             r"\bload average\b", r"\bagent\b"]


def test_pages_hold_no_lab_notes():
    hits = []
    for page in pages():
        for i, line in enumerate(page.read_text().splitlines(), 1):
            for pattern in LAB_NOTES:
                if re.search(pattern, line):
                    hits.append(f"{page.relative_to(ROOT)}:{i}: {line.strip()}")
    assert not hits, "history, targets and pointers outside the repository belong in commit messages:\n" + \
        "\n".join(hits)


# ---- the README's example -------------------------------------------------------------------------

def readme_example():
    m = re.search(r"^```python\n(.*?)^```", README.read_text(), flags=re.S | re.M)
    assert m, "README.md has no ```python example"
    return m.group(1)


@pytest.mark.timeout(60)
def test_readme_example_runs_and_finds_the_references_impacts(fmu_path, tmp_path):
    """The README's example is the paper's Fig. 4b at rtol 1e-11; the independent reference
    (its reference/data/summary.json) counts the impacts of that run. It finds the FMU as an installed
    package would (vibroimpact.fmu_path(): here $VI_FMU, which conftest sets to the FMU under test)."""
    code = readme_example()
    assert "vibroimpact.fmu_path()" in code and "build/" not in code
    run = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=50)
    assert run.returncode == 0, run.stderr
    m = re.search(r"(\d+) impacts", run.stdout)
    assert m, run.stdout
    found = [p for top in ("python", "fmu-test") for p in (ROOT / top).glob("**/reference/data/summary.json")]
    assert len(found) == 1, found
    reference = json.loads(found[0].read_text())
    assert int(m.group(1)) == reference["fig4b"]["n_impacts"], run.stdout
    if RUN_SOLVER == DEFAULT_SOLVER:  # the chaotic run's numbers are those of the default solver
        said = re.search(r"It prints `([^`]*)`", (ROOT / "README.md").read_text())
        assert said and run.stdout.strip() == said.group(1), (run.stdout, said)


# ---- every example that runs the FMU -------------------------------------------------------------------

IMPORTERS = ("fmpy ", "fmi-sim ")
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", flags=re.S | re.M)


def code_blocks(language):
    """(page, block) of every fenced block of the language in README.md and doc/."""
    return [(page.relative_to(ROOT).as_posix(), m.group(2)) for page in pages()
            for m in FENCE.finditer(page.read_text()) if m.group(1) == language]


def importer_commands():
    """(page, command) of every line of a sh block that starts an importer (continuation lines joined)."""
    found = []
    for page, block in code_blocks("sh"):
        for command in re.sub(r"\\\n\s*", " ", block).splitlines():
            if command.startswith(IMPORTERS):
                found.append((page, command.split(" #")[0].strip()))
    return found


def example_env():
    """The environment of the examples: this interpreter's commands (fmpy, vibroimpact) and cargo's
    (fmi-sim) first on the PATH; VI_FMU (conftest) names the FMU under test."""
    bins = [pathlib.Path(sys.executable).parent, pathlib.Path.home() / ".cargo" / "bin"]
    return {**os.environ, "PATH": os.pathsep.join([*map(str, bins), os.environ.get("PATH", "")])}


def test_the_examples_are_found():
    """The collection must see the kinds of examples the pages have (else the tests below check nothing)."""
    assert len(code_blocks("python")) >= 4
    commands = [c for _, c in importer_commands()]
    assert any(c.startswith("fmpy simulate") for c in commands) and any(c.startswith("fmi-sim") for c in commands)


def test_no_example_takes_the_fmu_from_build():
    """build/VibroImpact.fmu exists in a built clone only: examples locate the FMU with fmu_path()."""
    bad = [(page, line) for language in ("python", "sh") for page, block in code_blocks(language)
           for line in block.splitlines() if re.search(r"build/(fmi3/)?VibroImpact\.fmu", line)]
    assert not bad, bad


@pytest.mark.timeout(300)
@pytest.mark.parametrize("index", range(len(code_blocks("python"))))
def test_python_example_runs(fmu_path, tmp_path, index):
    page, code = code_blocks("python")[index]
    run = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=example_env(), capture_output=True,
                         text=True, timeout=280)
    assert run.returncode == 0, f"{page}: the example\n{code}\nfailed:\n{run.stderr}"


@pytest.mark.timeout(120)
@pytest.mark.parametrize("index", range(len(importer_commands())))
def test_importer_command_runs(fmu_path, tmp_path, index):
    page, command = importer_commands()[index]
    program = command.split()[0]
    env = example_env()
    assert shutil.which(program, path=env["PATH"]), \
        f"{page}: {program} not found: install it with ./tools/setup.sh (fmpy with pip, fmi-sim with cargo)"
    assert "--show-plot" not in command, f"{page}: --show-plot opens a window and needs plotly: {command}"
    run = subprocess.run(["bash", "-c", "set -eo pipefail; " + command], cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=110)
    assert run.returncode == 0, f"{page}: {command}\n{run.stdout[-2000:]}\n{run.stderr[-2000:]}"
    for out in re.findall(r"(?:--output-file|-o) (\S+)", command):
        assert (tmp_path / out).stat().st_size > 0, f"{page}: {command} wrote no {out}"


# ---- the numbers the code decides ---------------------------------------------------------------------

@pytest.fixture(scope="session")
def sources(fmu_path):
    from conftest import BUILD
    return doc_numbers.Sources(fmu_path, BUILD)


def test_number_agreement_rule():
    """A number agrees when the value rounds to it at the digits shown (the rule every fact below uses)."""
    agrees = doc_numbers.agrees
    assert agrees("267.19", 267.1923) and not agrees("267.19", 267.1849)
    assert agrees("1,000,000", 1e6) and not agrees("1,000,000", 999999.0)
    assert agrees("5.6e-5", 5.5635e-5) and not agrees("5.6e-5", 5.54e-5)
    assert agrees("-1.37", -1.3655) and not agrees("-1.37", -1.3649)
    assert agrees("six", 6) and not agrees("Eight", 7.0)
    assert agrees("42", 41.74) and not agrees("41.7", 41.76)


@pytest.mark.timeout(120)
@pytest.mark.parametrize("fact", doc_numbers.FACTS, ids=lambda f: f"{f.page}:{f.phrase[:40]}")
def test_page_number_is_what_the_code_gives(sources, fact):
    found = doc_numbers.phrase_regex(fact.phrase).findall(doc_numbers.page_text(fact.page))
    assert found, f"{fact.page} no longer says \"{fact.phrase}\": update the page or fmu-test/doc_numbers.py"
    value = fact.source(sources)
    wrong = [n for n in found if not doc_numbers.agrees(n, value)]
    assert not wrong, f"{fact.page}: \"{fact.phrase}\" says {wrong[0]}, the code gives {value:.6g}"


@pytest.mark.timeout(60)
@pytest.mark.parametrize("fact", doc_numbers.TABLE_FACTS, ids=lambda f: f"{f.page}:{f.column}:{f.row}")
def test_table_number_is_what_the_data_give(sources, fact):
    cells = doc_numbers.table_cells(fact.page, fact.column, fact.row)
    assert cells, f"{fact.page}: no table row '{fact.row}' with a column '{fact.column}'"
    value = fact.source(sources)
    for cell in cells:
        m = re.fullmatch(doc_numbers.phrase_regex(fact.cell), cell)
        assert m, f"{fact.page}: the cell '{cell}' (row {fact.row}, column {fact.column}) is not '{fact.cell}'"
        assert doc_numbers.agrees(m.group("n"), value), \
            f"{fact.page}: row {fact.row}, column '{fact.column}' says {m.group('n')}, the data give {value:.6g}"


# ---- names the pages give ---------------------------------------------------------------------------------

REPO_FOLDERS = ("src/", "tools/", "tests/", "fmu-test/", "cmake/", "python/", "examples/", "doc/")


def named_paths():
    """(page, path) of every file or folder of the repository the pages name in inline code: a token
    starting with one of the repository's folders (patterns such as <scenario> or * are globbed)."""
    found = set()
    for page in pages():
        text = re.sub(r"^```.*?^```", "", page.read_text(), flags=re.S | re.M)
        for code in re.findall(r"`([^`\n]+)`", text):
            for token in re.findall(r"(?<![\w/.$-])(?:" + "|".join(map(re.escape, REPO_FOLDERS)) + r")[\w./<>*{},-]*", code):
                found.add((page.relative_to(ROOT).as_posix(), token.rstrip(".,")))
    return sorted(found)


def test_named_files_exist():
    missing = []
    for page, path in named_paths():
        pattern = re.sub(r"<[^>]*>|\{[^}]*\}", "*", path)
        if "results/" in path:  # what a command writes: not in the repository
            continue
        if not glob.glob(str(ROOT / pattern)):
            missing.append(f"{page}: {path}")
    assert len(named_paths()) > 50, "the rule sees too few paths: it checks nothing"
    assert not missing, "the pages name files that do not exist:\n" + "\n".join(missing)


def code_identifiers():
    """Every identifier of the C and CMake code (also the tests, tools and package, for options and variables)."""
    words = set()
    for top in ("src", "tests", "tools", "cmake", "python", "fmu-test", "examples"):
        for p in (ROOT / top).rglob("*"):
            if p.suffix in {".c", ".h", ".cmake", ".py", ".sh", ".txt"} and p.is_file():
                words.update(re.findall(r"\w+", p.read_text(errors="replace")))
    words.update(re.findall(r"\w+", (ROOT / "CMakeLists.txt").read_text()))
    return words


def test_named_c_names_exist():
    """A function, constant or CMake option the pages name in inline code (vi_*, VI_*) exists in the code."""
    known = code_identifiers()
    named = {(page.relative_to(ROOT).as_posix(), m) for page in pages()
             for code in re.findall(r"`([^`\n]+)`", page.read_text())
             for m in re.findall(r"^(?:-D)?((?:vi|VI)_\w*[A-Za-z0-9](?:_\*)?)", code)}
    assert len(named) > 20, "the rule sees too few names: it checks nothing"
    exists = lambda n: any(k.startswith(n[:-1]) for k in known) if n.endswith("*") else n in known  # noqa: E731
    gone = sorted(f"{page}: {name}" for page, name in named if not exists(name))
    assert not gone, "the pages name functions or constants the code no longer has:\n" + "\n".join(gone)


# ---- what doc/using.md says about inputs, measured --------------------------------------------------------

# Model Exchange states in which an input may move outputs: (parameters, inputs, time, states y, v, W_damping or
# None for the static start); the states are set and an event iteration chooses the mode, then time moves on 10 us.
ME_STATES = {
    "static start, Hertz": ({"contact_model": 1}, {}, 0.0, None),
    "free flight": ({"contact_model": 1}, {}, 1e-3, (1e-4, 0.5, 0.0)),
    "Johnson, plastic loading": ({"contact_model": 2}, {}, 1e-6, (-1.2e-4, -1.0, 0.0)),
    "LEPP, plastic flow": ({"contact_model": 3}, {}, 1e-6, (-3e-4, -1.0, 0.0)),
    "Johnson, stick": ({"contact_model": 2}, {"F_ext": -1.3e5}, 1e-6, (-1.2e-4, 0.0, 0.0)),
    "damped Hertz, contact": ({"contact_model": 4}, {}, 1e-6, (-1e-4, -0.1, 0.0)),
}
INPUT_STEPS = {"yC_in": 1e-9, "F_ext": 10.0}


def read(instance, v):
    get = {"Real": instance.getReal, "Integer": instance.getInteger, "Boolean": instance.getBoolean}[v.type]
    return get([v.valueReference])[0]


def outputs_moved(sources, state, name, step):
    """The outputs and state derivatives of a Model Exchange instance that change when the input `name`
    changes by `step` at fixed time and states (plain fmpy calls)."""
    from fmpy.fmi2 import FMU2Model, fmi2Real
    params, inputs, t, x = state
    m, vr = sources.instance(FMU2Model, params)
    try:
        m.newDiscreteStates()
        m.enterContinuousTimeMode()
        if x is not None:
            for k, v in inputs.items():
                m.setReal([vr[k]], [v])
            m.setTime(t)
            m.setContinuousStates((fmi2Real * len(x))(*x), len(x))
            m.enterEventMode()
            m.newDiscreteStates()
            m.enterContinuousTimeMode()
            m.setTime(t + 1e-5)
        unknowns = [u.variable for u in sources.md.outputs + sources.md.derivatives]
        before = [read(m, v) for v in unknowns]
        m.setReal([vr[name]], [inputs.get(name, 0.0) + step])
        return {v.name for v, b in zip(unknowns, before) if read(m, v) != b}
    finally:
        m.freeInstance()


def using_md_inputs_table():
    rows = [line for line in section(ROOT.joinpath("doc", "using.md").read_text(), "## Inputs") if line.startswith("| `")]
    return {re.match(r"\| `(\w+)`", r).group(1): set(re.findall(r"`(\w+)`", r.split("|")[2])) for r in rows}


@pytest.mark.timeout(60)
def test_using_md_says_which_outputs_follow_an_input_in_model_exchange(sources):
    said = using_md_inputs_table()
    assert set(said) == set(INPUT_STEPS), said
    measured = {name: set() for name in INPUT_STEPS}
    for state in ME_STATES.values():
        for name, step in INPUT_STEPS.items():
            measured[name] |= outputs_moved(sources, state, name, step)
    assert measured == said, f"doc/using.md, section Inputs, lists {said}; measured in Model Exchange: {measured}"


@pytest.mark.timeout(60)
def test_using_md_co_simulation_outputs_wait_for_the_step(model_description, logged, vr):
    """No output changes when an input is set at a communication point; the next step feels it."""
    from conftest import start
    outputs = [u.variable for u in model_description.outputs]
    get = read
    for name, step in {"yC_in": 1e-6, "F_ext": 1e3}.items():
        s = logged().instantiate()
        start(s, vr, {"contact_model": 1, "a": 1e-4})
        for k in range(20):
            s.doStep(k * 1e-4, 1e-4)
        before = [get(s, v) for v in outputs]
        s.setReal([vr[name]], [step])
        assert [get(s, v) for v in outputs] == before, name
        s.doStep(20e-4, 1e-4)
        after = [get(s, v) for v in outputs]
        s.freeInstance()
        s = logged().instantiate()
        start(s, vr, {"contact_model": 1, "a": 1e-4})
        for k in range(21):
            s.doStep(k * 1e-4, 1e-4)
        assert [get(s, v) for v in outputs] != after, f"setting {name} changed nothing in the next step"
        s.freeInstance()


def test_using_md_names_every_log_category(model_description):
    logging = "\n".join(section(ROOT.joinpath("doc", "using.md").read_text(), "## Logging"))
    categories = [c.name for c in model_description.logCategories]
    assert len(categories) >= 5, categories
    missing = [c for c in categories if f"`{c}`" not in logging]
    assert not missing, f"doc/using.md, section Logging, does not name the categories {missing}"


# ---- commands and options the pages give ------------------------------------------------------------------

COMMAND_USE = re.compile(r"(?<![\w/.])(vibroimpact|tools/mutate\.py)((?: +[a-z][a-z0-9-]*(?=[\s`)]|$))?)"
                         r"((?: +[^\s`|#)\"']+)*)")


def command_uses():
    """{(program, command): {options}} of every use of `vibroimpact <command>` and tools/mutate.py in inline
    code and sh blocks of the pages (python blocks hold the package's API, not its commands)."""
    uses = {}
    for page in pages():
        text = page.read_text()
        spans = re.findall(r"`([^`\n]+)`", re.sub(r"^```.*?^```", "", text, flags=re.S | re.M))
        spans += [line for language, block in FENCE.findall(text) if language == "sh"
                  for line in re.sub(r"\\\n\s*", " ", block).splitlines()]
        for span in spans:
            for program, command, rest in COMMAND_USE.findall(span.split(" #")[0]):
                options = set(re.findall(r"(?<!\S)(--[A-Za-z][A-Za-z0-9-]*)", rest))
                uses.setdefault((program, command.strip()), set()).update(options)
    # doc/sweeps.md's table of the options of `vibroimpact sweep`
    rows = [line for line in ROOT.joinpath("doc", "sweeps.md").read_text().splitlines() if line.startswith("| `--")]
    uses.setdefault(("vibroimpact", "sweep"), set()).update(o for r in rows for o in re.findall(r"`(--[a-z-]+)", r))
    return uses


@pytest.mark.timeout(120)
def test_named_commands_and_options_exist():
    """Every `vibroimpact <command> --option` and `tools/mutate.py --option` the pages give exists: the
    command's --help succeeds and names the option."""
    uses = command_uses()
    assert len(uses) > 10 and ("vibroimpact", "sweep") in uses, "the rule sees too few commands: it checks nothing"
    bad = []
    for (program, command), options in sorted(uses.items()):
        argv = [sys.executable, "-m", "vibroimpact"] if program == "vibroimpact" else [sys.executable, str(ROOT / program)]
        run = subprocess.run(argv + command.split() + ["--help"], capture_output=True, text=True, timeout=60,
                             env=example_env())
        if run.returncode != 0:
            bad.append(f"{program} {command}: --help fails: {run.stderr.strip()[-300:]}")
            continue
        bad += [f"{program} {command} {o}: not in its --help" for o in sorted(options)
                if not re.search(rf"(?<![\w-]){re.escape(o)}(?![\w-])", run.stdout)]
    assert not bad, "the pages give commands or options that do not exist:\n" + "\n".join(bad)


def declared_range(v):
    """The range of a variable of the model description as doc/model.md's parameter table writes it."""
    if v.type == "Integer":
        return f"{v.min}-{v.max}" if v.min is not None else ""
    lo, hi = (None if b is None else float(b) for b in (v.min, v.max))
    known = {(None, None): "", (5e-324, None): "> 0", (0.0, None): ">= 0", (-0.9999999999999999, 0.5): "(-1, 0.5]",
             (5e-324, 1.0): "(0, 1]"}
    return known.get((lo, hi), f"[{v.min}, {v.max}]")


def range_agrees(cell, v):
    """The cell states the declared range; "0, or ..." is the declared >= 0 (or [0, max]) with a gap the
    FMU refuses when the value is set or at initialization, where max must be the declared one."""
    if cell.startswith("0, or "):
        hi = re.search(r"(\S+)\]$", cell)
        return float(v.min) == 0.0 and (v.max is None or bool(hi) and doc_numbers.agrees(hi.group(1), float(v.max)))
    return cell.startswith(declared_range(v)) if declared_range(v) else cell == ""


def test_model_md_ranges_are_the_declared_ones(model_description):
    text = ROOT.joinpath("doc", "model.md").read_text()
    rows = [line for line in section(text, "### Parameters") if line.startswith("| `")]
    variables = {v.name: v for v in model_description.modelVariables}
    checked, bad = 0, []
    for row in rows:
        cells = [c.strip() for c in row.strip().strip("|").split("|")]
        names, cell = re.findall(r"`(\w+)`", cells[0]), cells[3]
        named_in_cell = re.match(r"`(\w+)` (.*)", cell)
        for name in names:
            v = variables[name]
            own = (named_in_cell.group(2) if named_in_cell.group(1) == name else "") if named_in_cell else cell
            checked += 1
            if not range_agrees(own, v):
                bad.append(f"{name}: doc/model.md says '{own}', modelDescription.xml declares min={v.min} max={v.max}")
    assert checked >= 20, "the rule sees too few parameters: it checks nothing"
    assert not bad, "\n".join(bad)


def test_wheel_names_carry_the_version():
    """The release wheel the pages name is the one tools/release.sh makes: the CMake project's version."""
    version = re.search(r"project\(VibroImpact VERSION ([0-9.]+)", ROOT.joinpath("CMakeLists.txt").read_text()).group(1)
    named = {m for page in pages() for m in re.findall(r"vibroimpact-([0-9][0-9.]*[0-9])-py3", page.read_text())}
    assert named and named == {version}, f"the pages name wheels of versions {named}; the project's is {version}"
