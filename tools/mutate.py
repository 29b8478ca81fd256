#!/usr/bin/env python3
"""Mutation testing of src/: do the tests notice single-point faults?

Usage:
    python3 tools/mutate.py [--sample N] [--seed S] [--files GLOB ...] [--only NAME ...] [--list]
                            [--jobs J] [--json FILE] [--rebuild-coverage] [--equivalents] [--journal FILE]

Each mutant changes one place of one C file under src/ (operators, constants, a removed statement, a
negated or forced condition, a changed return status; code compiled for Windows only, under #ifdef
_WIN32, is left out: the host build does not compile it, tools/cross_test.sh runs it under wine). It
is built in a scratch copy of the repository (build/mutate/scratch; a build that fails is
"stillborn" and not scored) and run against the tests that execute the mutated line, and only those:
a mutant is "killed" when one of them fails, and again when rerun; it is a "timeout" when the run
exceeds its time limit (three times the tests' measured time plus 60 s) or the only failures are tests
stopped at their own limit (pytest.ini's timeout, ctest's TIMEOUT): a hang is no failure, so a timeout
is counted, listed (with --json: its own verdict and count) and left out of the score; it "survives" when all of them pass, and it is
"uncovered" (a survivor) when no test executes its line (a continuation line takes the tests of its
statement's first line, and a declaration or a static table's initializer, on which gcov counts no
code, those of its function). The tests run as tools/test.sh runs them: the FMU tests with the
default solver and, when the solver choice reaches the mutated line (the FMU tests that execute it
differ between solvers), also with each VI_SOLVER value of tools/test.sh's loop, each with the tests
that execute the line under that solver; a survivor in array or loop code (its function has '[',
'for (' or 'while (': a bound test may guard an index on another line) is built again with the
sanitizers (-DVI_SANITIZE=ON, as tools/test.sh's build-asan; build-san in the scratch copy) and its
C tests run there, where an access out of bounds fails them.
The score is
killed / (killed + survived + uncovered);
mutants listed in tools/mutants-equivalent.txt are left out (no test can tell them apart from the
original; each entry gives the reason), and so are those the compiler turns into the same object
code as the original ("identical", trivial compiler equivalence: every object file built from the
mutated source is byte for byte the original's, or the mutated source compiles to the original's
assembly under one of the compilers and optimization levels of TCE_COMPILERS; a correct compiler gives
two sources the same code only when they compute the same on every input without undefined
behaviour, so no test can tell them apart and none is run). --jobs J (default: the number of cores) runs J mutants at
once, each in its own scratch copy (build/mutate/scratch, scratch-1, ...).

Which test executes which line comes from a coverage map, built once per revision of the
repository (a hash of the files the tests depend on) and cached in build/mutate/: a build with gcov
(--coverage -O0, build/mutate/cov) runs each ctest test alone (except the fuzz test) and then the
FMU tests (pytest, fmu-test/) in one process per solver of tools/test.sh, writing the gcov counters
of every FMU binary loaded after each test (vi_coverage_flush, tests/coverage_flush.c) and reading
them with gcov. A test is given the lines of the work it shares: the setup of the module- and
session-scoped fixtures it uses (run once and cached) and its module's import. The map
also records each test's time and outcome; tests that fail on the unmutated code are never
selected (they are listed).

A mutant is named after its place in a way that survives edits elsewhere in the file:
    <file>:<function>:<kind>:<old>-><new>:<k> | <the code of its line>
(k counts the mutants of that kind and text on lines of that code in that function, in order). --list
prints the names with the line and column of today. The same names key tools/mutants-equivalent.txt: "<name>  # <reason>".

--equivalents replays the mutants listed in tools/mutants-equivalent.txt under every condition of the
test command (the FMU tests that execute the line with every solver, the C tests also in the
sanitized build) and lists those a test kills or that time out, and the stale entries (names no
mutant of today's src/ has); its exit status is 1 then, and --json holds both lists (a step of a
release: doc/testing.md, "Equivalent mutants", says when it last ran and what it found). A locale is a condition only through the tests that set it
themselves: the environment's does not reach the code (a test run with LC_ALL=de_DE.utf8 still has
LC_NUMERIC "C" in a Criterion test and in pytest, which set no numeric locale).

Sampling: --sample N draws N mutants, stratified by file (every file of src/ gets its share), with
--seed S; without --seed the seed is fresh and printed, so that a run can be repeated. Without
--sample every mutant is run.
"""
import argparse
import concurrent.futures
import ctypes
import dataclasses
import fnmatch
import functools
import hashlib
import itertools
import json
import os
import pathlib
import queue
import random
import re
import shlex
import shutil
import signal
import statistics
import subprocess
import sys
import threading
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
EQUIVALENT = ROOT / "tools" / "mutants-equivalent.txt"
CACHE = ROOT / "build" / "mutate"


@dataclasses.dataclass
class Mutant:
    file: str      # path relative to ROOT
    start: int     # character offset of the replaced text
    end: int
    new: str
    kind: str
    line: int      # first and last line of the replaced text
    last_line: int
    col: int
    old: str
    function: str  # the function the place is in
    site: str      # the code of its line, comments removed, whitespace collapsed
    k: int = 1     # among the mutants of this kind and text on the line
    stmt_line: int = 0  # the first line of the statement (or condition) the place is in
    body: tuple = (0, 0)  # the first and last line of the function's body

    @property
    def ident(self):
        return f"{self.file}:{self.function}:{self.kind}:{flat(self.old)}->{flat(self.new)}:{self.k} | {self.site}"

    @property
    def where(self):
        return f"{self.file}:{self.line}:{self.col}"


def flat(text):
    return " ".join(text.split())


# ---- finding mutation sites ------------------------------------------------------------------

def mask(text, strings=True):
    """The text with comments and preprocessor lines (and, with strings, string and character
    literals) blanked out, same length, so that the patterns below only see code."""
    out = list(text)
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":  # preprocessor line, with continuations
            j = i
            while j < n and not (text[j] == "\n" and text[j - 1] != "\\"):
                j += 1
            for k in range(i, j):
                out[k] = " "
            i = j
            continue
        if c == "\n":
            at_line_start = True
            i += 1
            continue
        if not c.isspace():
            at_line_start = False
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            for k in range(i, j):
                if text[k] != "\n":
                    out[k] = " "
            i = j
            continue
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            for k in range(i, j):
                out[k] = " "
            i = j
            continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            if strings:
                for k in range(i, min(j + 1, n)):
                    out[k] = " "
            i = j + 1
            continue
        i += 1
    return "".join(out)


RELATIONAL = {"<": "<=", "<=": "<", ">": ">=", ">=": ">", "==": "!=", "!=": "=="}
ARITH = {"+": "-", "-": "+", "*": "/", "/": "*"}
LOGICAL = {"&&": "||", "||": "&&"}
STATUS = {"fmi2OK": "fmi2Error", "fmi2Error": "fmi2OK", "fmi2Discard": "fmi2OK", "fmi2Warning": "fmi2OK"}
NUMBER = re.compile(r"(?<![\w.])(\d+\.\d*(?:[eE][-+]?\d+)?|\d*\.\d+(?:[eE][-+]?\d+)?|\d+[eE][-+]?\d+|\d+)(?![\w.])")


def prev_code_char(masked, pos):
    j = pos - 1
    while j >= 0 and masked[j].isspace():
        j -= 1
    return masked[j] if j >= 0 else ""


def function_bodies(masked):
    """[(start, end, name)] of the function definitions: regions opened by a '{' at file scope that
    follows ')', named by the identifier before the matching '('."""
    bodies, d, start, name = [], 0, None, None
    for i, c in enumerate(masked):
        if c == "{":
            if d == 0 and prev_code_char(masked, i) == ")":
                j = masked.rfind(")", 0, i)
                depth, k = 0, j
                while k >= 0:
                    if masked[k] == ")":
                        depth += 1
                    elif masked[k] == "(":
                        depth -= 1
                        if depth == 0:
                            break
                    k -= 1
                m = re.search(r"(\w+)\s*$", masked[:k])
                start, name = i, m.group(1) if m else "?"
            d += 1
        elif c == "}":
            d -= 1
            if d == 0 and start is not None:
                bodies.append((start, i, name))
                start = None
    return bodies


FOREIGN = re.compile(r"#\s*(ifdef\s+_WIN32|if\s+defined\s*\(?\s*_WIN32\b)")


def foreign_regions(text):
    """[(start, end)] of the code compiled for Windows only (#ifdef _WIN32 up to its #else or #endif):
    the host build does not compile it, so a mutant there cannot change what the tests run."""
    regions, stack, pos = [], [], 0
    for line in text.splitlines(keepends=True):
        s = line.strip()
        if s.startswith("#"):
            word = re.match(r"#\s*(\w+)", s)
            word = word.group(1) if word else ""
            if word.startswith("if"):
                stack.append(pos + len(line) if FOREIGN.match(s) else None)
            elif word in ("else", "elif", "endif") and stack:
                if stack[-1] is not None:
                    regions.append((stack[-1], pos))
                if word == "endif":
                    stack.pop()
                else:
                    stack[-1] = None
        pos += len(line)
    return regions


# A declaration without an initializer (an array's size, say): gcov counts no line of it.
DECLARATION = re.compile(r"^(?:static |const )*[A-Za-z_]\w*(?: \*?[A-Za-z_]\w*(?:\[[^]=]*\])*,?)+;$")
# A variable of static storage in a function: its initializer is data, on which gcov counts no code.
STATIC_DATA = re.compile(r"^\s*static\b[^(]*=")


@functools.lru_cache(maxsize=None)
def source_lines(rel):
    return (ROOT / rel).read_text().splitlines()


def source_line(rel, line):
    """Line `line` (from 1) of the source file rel, as the repository holds it."""
    lines = source_lines(rel)
    return lines[line - 1] if 0 < line <= len(lines) else ""


def statement_start(masked, start):
    """Where the statement (or condition) holding masked[start] begins: after the last ';', '{' or '}'
    before it that is not a brace of an initializer ('= {', '{ {', ', {' and the '}' closing one)."""
    i = start
    while i > 0:  # bounded: i falls every pass
        i -= 1
        ch = masked[i]
        if ch == ";":
            break
        if ch == "{":
            j = i - 1
            while j >= 0 and masked[j].isspace():
                j -= 1
            if j >= 0 and masked[j] in "=,{(":
                continue  # an initializer's brace: the statement began before it
            break
        if ch == "}":
            j = i + 1
            while j < len(masked) and masked[j].isspace():
                j += 1
            if j < len(masked) and masked[j] in ",}":
                depth = 1  # a nested initializer closed before start: back to its opening brace
                while i > 0 and depth:
                    i -= 1
                    depth += (masked[i] == "}") - (masked[i] == "{")
                continue
            break
    else:
        i = -1
    b = i + 1
    while b < start and masked[b].isspace():
        b += 1
    return b


def operator_sites(masked, text):
    """(start, end, new, kind) of the operator, constant, condition and status mutants of a masked source."""
    for m in re.finditer(r"<=|>=|==|!=|(?<![<>-])[<>](?![<>=])", masked):
        yield m.start(), m.end(), RELATIONAL[m.group()], "relational"
    for m in re.finditer(r"&&|\|\|", masked):
        yield m.start(), m.end(), LOGICAL[m.group()], "logical"
    for m in re.finditer(r"(?<![+\-*/=<>!&|])([+\-*/])(?![+\-*/=>])", masked):
        pos = m.start()
        p = prev_code_char(masked, pos)
        if not (p.isalnum() or p in "_)]"):
            continue  # unary
        if m.group() in "+-" and re.search(r"\d[eE]$", masked[max(0, pos - 30):pos]):
            continue  # exponent of a number
        yield pos, pos + 1, ARITH[m.group()], "arithmetic"
    for m in NUMBER.finditer(masked):
        lit = m.group()
        if re.fullmatch(r"\d+", lit):
            new = str(int(lit) + 1) if lit != "1" else "0"
        else:
            new = repr(float(lit) * 1.01) if float(lit) != 0.0 else "1e-3"
        yield m.start(), m.end(), new, "constant"
    yield from condition_sites(masked, text)
    for m in re.finditer(r"\b(fmi2OK|fmi2Error|fmi2Discard|fmi2Warning)\b", masked):
        if re.search(r"return\s*$", masked[max(0, m.start() - 20):m.start()]):
            yield m.start(), m.end(), STATUS[m.group()], "status"
    for m in re.finditer(r"\breturn\s+(-1|0)\s*;", masked):
        yield m.start(1), m.end(1), "0" if m.group(1) == "-1" else "-1", "status"


def condition_sites(masked, text):
    """The condition of every if: negated, and forced false."""
    for m in re.finditer(r"\bif\s*\(", masked):
        open_ = m.end() - 1
        d, j = 0, open_
        while j < len(masked):
            if masked[j] == "(":
                d += 1
            elif masked[j] == ")":
                d -= 1
                if d == 0:
                    break
            j += 1
        cond = text[open_ + 1:j]
        yield open_ + 1, j, f"!({cond})", "negate-condition"
        yield open_ + 1, j, "0", "condition-false"


def removed_statement_sites(masked):
    """A whole line that is one expression statement (assignment or call), removed."""
    pos = 0
    for line in masked.splitlines(keepends=True):
        s = line.strip()
        if (s.endswith(";") and not s.startswith(("return", "break", "continue", "case", "default"))
                and re.match(r"^[\w\->.\[\]*()]+\s*(\(|[+\-*/]?=)", s)
                and not re.match(r"^(const\s+)?(unsigned\s+|signed\s+)?(int|long|double|float|char|size_t|"
                                 r"void|struct|vi_\w+|fmi2\w+|N_Vector|SUNContext|sunrealtype)\b", s)):
            start = pos + len(line) - len(line.lstrip())
            yield start, pos + len(line.rstrip("\n")), ";", "remove-statement"
        pos += len(line)


def owners(text, masked):
    """The function each character of text belongs to (None outside functions and in code compiled for
    another platform only, which tools/cross_test.sh runs), and each function's first and last line."""
    owner = [None] * (len(text) + 1)
    span = {}
    for s, e, name in function_bodies(masked):
        span[name] = (text.count("\n", 0, s) + 1, text.count("\n", 0, e) + 1)
        for i in range(s + 1, e):
            owner[i] = name
    for s, e in foreign_regions(text):  # not compiled here: no mutants
        for i in range(s, e):
            owner[i] = None
    return owner, span


def mutants_of(path, text=None):
    rel = str(path.relative_to(ROOT))
    text = path.read_text() if text is None else text
    masked = mask(text)
    code = mask(text, strings=False)  # comments removed, strings kept: the site of a mutant
    line_starts = [0] + [i + 1 for i, c in enumerate(text) if c == "\n"]
    owner, span = owners(text, masked)
    found = []
    for start, end, new, kind in itertools.chain(operator_sites(masked, text), removed_statement_sites(masked)):
        if owner[start] is None:
            continue
        line = text.count("\n", 0, start) + 1
        last = text.count("\n", 0, end) + 1
        ls = line_starts[line - 1]
        le = text.find("\n", ls)
        site = flat(code[ls:le if le >= 0 else len(text)])
        b = statement_start(masked, start)
        found.append(Mutant(rel, start, end, new, kind, line, last, start - ls + 1, text[start:end], owner[start], site,
                            stmt_line=text.count("\n", 0, b) + 1, body=span[owner[start]]))
    found.sort(key=lambda m: (m.start, m.kind))
    seen = {}
    for m in found:  # k: the same change on the same code in the same function (on one line, or on lines alike)
        key = (m.function, m.site, m.kind, flat(m.old), flat(m.new))
        seen[key] = seen.get(key, 0) + 1
        m.k = seen[key]
    return found


def all_mutants(globs):
    files = sorted(p for p in (ROOT / "src").rglob("*.c")
                   if any(fnmatch.fnmatch(str(p.relative_to(ROOT)), g) for g in globs))
    out = []
    for f in files:
        out.extend(mutants_of(f))
    return out


def sample(mutants, n, seed):
    """n mutants, every file getting a share proportional to its mutants (at least one)."""
    if n is None or n >= len(mutants):
        return mutants
    rng = random.Random(seed)
    by_file = {}
    for m in mutants:
        by_file.setdefault(m.file, []).append(m)
    picked = []
    for f, ms in sorted(by_file.items()):
        k = max(1, round(n * len(ms) / len(mutants)))
        picked.extend(rng.sample(ms, min(k, len(ms))))
    rng.shuffle(picked)
    return sorted(picked[:n], key=lambda m: (m.file, m.start))


def read_equivalent():
    """Lines '<name>  # reason'. Returns {name: reason}."""
    eq = {}
    if EQUIVALENT.exists():
        for line in EQUIVALENT.read_text().splitlines():
            if line.strip() and not line.startswith("#"):
                ident, _, reason = line.partition("  # ")
                eq[ident.strip()] = reason.strip()
    return eq


# ---- running commands --------------------------------------------------------------------------

def descendants(pid):
    """pid and every process below it (from /proc), parents before children."""
    children = {}
    for stat in pathlib.Path("/proc").glob("[0-9]*/stat"):
        try:
            ppid = int(stat.read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue  # ended meanwhile
        children.setdefault(ppid, []).append(int(stat.parent.name))
    tree = [pid]
    for p in tree:  # bounded: each process is added once, as the child of its one parent
        tree.extend(children.get(p, []))
    return tree


def kill_tree(pid):
    """SIGKILL pid's process group and every process below pid, in whatever group or session: ctest
    starts each test in a process group of its own, which a kill of the command's group does not
    reach. The tree is stopped first, so that none of it forks or loses its parent while it is
    collected again."""
    for sig in (signal.SIGSTOP, signal.SIGKILL):
        for p in descendants(pid):
            try:
                os.kill(p, sig)
            except ProcessLookupError:
                pass
    try:
        os.killpg(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def run(cmd, cwd, timeout=None, env=None):
    """(exit status or "timeout", output). At the timeout the command and every process it started
    are killed: a test binary ctest or pytest started does not outlive a hung mutant."""
    with subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, text=True,
                          errors="replace", start_new_session=True) as p:
        try:
            out, _ = p.communicate(timeout=timeout)
            return p.returncode, out
        except subprocess.TimeoutExpired:
            kill_tree(p.pid)
            out, _ = p.communicate()
            return "timeout", out


def python_exe():
    return shutil.which(os.environ.get("PYTHON", "python3")) or sys.executable


def tracked_files():
    out = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, stdout=subprocess.PIPE,
                         check=True).stdout.decode()
    return sorted(f for f in out.split("\0") if f and (ROOT / f).is_file() and not f.startswith(".venv/"))


# Files that do not change what the tests execute or whether they pass, left out of the revision key.
NOT_IN_KEY = ("doc/", "tests/fuzz/", "tools/mutate.py", "tools/mutants-equivalent.txt", "tools/fuzz.sh")


def revision_key():
    """A hash of the tracked (and untracked, not ignored) files the tests depend on: the revision the
    map is for (documentation, the fuzz harness and this tool left out)."""
    h = hashlib.sha256()
    for f in tracked_files():
        if f.startswith(NOT_IN_KEY) or (f.endswith(".md") and f != "README.md"):
            continue
        h.update(f.encode() + b"\0" + (ROOT / f).read_bytes() + b"\0")
    return h.hexdigest()[:16]


def configure_and_build(source, build, extra, label):
    if not (build / "CMakeCache.txt").exists():
        rc, out = run(["cmake", "-S", str(source), "-B", str(build), "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
                       "-DVI_FUZZ=OFF", "-DVI_REQUIRE_TESTS=ON", f"-DPython3_EXECUTABLE={python_exe()}"] + extra,
                      ROOT, 900)
        if rc != 0:
            sys.exit(f"configuring the {label} build failed:\n{out}")
    rc, out = run(["cmake", "--build", str(build), "-j2"], ROOT, 1800)
    if rc != 0:
        sys.exit(f"the {label} build failed:\n{out}")


# ---- the coverage map --------------------------------------------------------------------------

MAP_FORMAT = "v3"  # the FMU tests per solver, with their shared fixtures', caches' and imports' lines
COVERAGE_FLAGS = ["-DVI_COVERAGE=ON", "-DCMAKE_BUILD_TYPE=Debug", "-DCMAKE_C_FLAGS=--coverage -O0",
                  "-DCMAKE_EXE_LINKER_FLAGS=--coverage", "-DCMAKE_SHARED_LINKER_FLAGS=--coverage"]


def clear_counters(build):
    for f in build.rglob("*.gcda"):
        f.unlink()


def collect(build):
    """{file under src/: [lines executed]} from the gcov counters in build, which are then removed."""
    files = [str(f) for f in build.rglob("*.gcda")]
    lines = {}
    if not files:
        return lines
    raw = subprocess.run(["gcov", "-j", "-t"] + files, cwd=build, stdout=subprocess.PIPE,
                         stderr=subprocess.DEVNULL).stdout.decode(errors="replace")
    dec, i = json.JSONDecoder(), 0
    src = str(ROOT / "src") + os.sep
    while True:
        while i < len(raw) and raw[i].isspace():
            i += 1
        if i >= len(raw):
            break
        doc, i = dec.raw_decode(raw, i)
        for f in doc["files"]:
            path = f["file"] if os.path.isabs(f["file"]) else os.path.join(doc["current_working_directory"], f["file"])
            path = os.path.normpath(path)
            if path.startswith(src):
                executed = {ln["line_number"] for ln in f["lines"] if ln["count"] > 0}
                lines.setdefault(os.path.relpath(path, ROOT), set()).update(executed)
    for f in files:
        os.unlink(f)
    return {k: sorted(v) for k, v in lines.items()}


def flush_loaded_binaries(known=set()):  # noqa: B006 (a cache of paths without the hook)
    """Write and reset the gcov counters of every FMU binary loaded in this process."""
    with open("/proc/self/maps") as f:
        paths = {line.split(None, 5)[5].strip() for line in f if len(line.split(None, 5)) == 6}
    for p in sorted(paths):
        if not p.endswith(".so") or p in known or p.startswith(("/usr/", "/lib")):
            continue
        try:
            ctypes.CDLL(p).vi_coverage_flush()
        except (OSError, AttributeError):
            known.add(p)


def merge_lines(into, lines):
    for f, ls in lines.items():
        into.setdefault(f, set()).update(ls)
    return into


def fingerprint(value):
    """What a test changes when it fills a cache a fixture handed out: the sizes of a container, of an
    object's attributes (functools.cached_property) and of its class's functools.lru_cache methods."""
    sizes = []
    if isinstance(value, (dict, list, set)):
        sizes.append(len(value))
    if hasattr(value, "__dict__") and not isinstance(value, type):
        sizes.append(len(vars(value)))
        for name in dir(type(value)):
            info = getattr(getattr(type(value), name, None), "cache_info", None)
            if callable(info):
                sizes.append(info().currsize)
    return tuple(sizes)


def pytest_worker(build, out, args):
    """The coverage run of the FMU tests, in this process (python tools/mutate.py _pytest ...)."""
    import pytest

    build = pathlib.Path(build)

    def flushed():
        flush_loaded_binaries()
        return collect(build)

    os.environ["VI_FMU"] = str(build / "VibroImpact.fmu")  # the FMU the tests use (and its build folder)
    return pytest.main(["-q", "-p", "no:cacheprovider"] + args,
                       plugins=[coverage_plugin(flushed, out, lambda: clear_counters(build))])


def coverage_plugin(flushed, out, clear=lambda: None):
    """The pytest plugin of the coverage run: after each test, the lines it executed (and its time and
    outcome) as one JSON line in `out`; flushed() gives the lines executed since it was last called. A
    test is also given the lines of the work it shares with others, so that a mutant there selects
    every test that reads the shared result, not only the one that happened to do the work: the setup
    of every fixture of a wider scope than the function it uses (run once, in the first test that asks
    for it, and cached), what its module executed when it was imported (collection), and the lines of
    every test that uses the same cache: a module- or class-scoped fixture (it may hand out a cache
    that the first test to ask fills: test_paper.py's `compared`), and a fixture of any scope (session,
    package) whose value a test changed (fingerprint(): test_docs.py's `sources`, whose facts the
    first test to ask computes through the FMU). Longer than a screen: the plugin's hooks share their
    state in one class, defined here where pytest is imported."""
    import pytest

    class CoveragePlugin:
        def __init__(self):
            self.failed, self.entries = False, []
            self.own, self.shared, self.module = {}, {}, {}  # this test's lines; by fixture; by module file
            self.caches, self.last = set(), {}  # the fixtures whose value a test changed; their last fingerprints

        def pytest_sessionstart(self, session):
            flushed()
            clear()

        @pytest.hookimpl(hookwrapper=True)
        def pytest_make_collect_report(self, collector):
            if not isinstance(collector, pytest.Module):
                yield
                return
            flushed()  # counters of work before the import belong to no module
            yield
            self.module[str(collector.path)] = merge_lines({}, flushed())

        @pytest.hookimpl(hookwrapper=True)
        def pytest_fixture_setup(self, fixturedef, request):
            if fixturedef.scope == "function":
                yield
                return
            merge_lines(self.own, flushed())
            yield
            merge_lines(self.shared.setdefault(id(fixturedef), {}), flushed())
            self.last.update(self.values([fixturedef]))

        def pytest_runtest_logreport(self, report):
            self.failed |= report.failed

        @staticmethod
        def values(defs):
            """{fixture: fingerprint of its value} of the fixtures set up."""
            return {id(fd): fingerprint(fd.cached_result[0]) for fd in defs if getattr(fd, "cached_result", None)}

        @pytest.hookimpl(hookwrapper=True)
        def pytest_runtest_protocol(self, item, nextitem):
            self.failed, self.own, t0 = False, {}, time.monotonic()
            info = getattr(item, "_fixtureinfo", None)
            defs = [fd for fds in (info.name2fixturedefs.values() if info else ()) for fd in fds if fd.scope != "function"]
            yield
            now = self.values(defs)  # a value this test changed since its setup or the last test: a cache
            self.caches |= {k for k, v in now.items() if self.last.get(k, v) != v}
            self.last.update(now)
            lines = merge_lines(self.own, flushed())
            for fd in defs:
                merge_lines(lines, self.shared.get(id(fd), {}))
            merge_lines(lines, self.module.get(str(getattr(item, "path", "")), {}))
            always = {id(fd) for fd in defs if fd.scope in ("module", "class")}
            self.entries.append((dict(test=item.nodeid, duration=time.monotonic() - t0, passed=not self.failed),
                                 lines, {id(fd) for fd in defs}, always))

        def pytest_sessionfinish(self, session):
            group_lines = {}
            grouped = [(entry, lines, {g for g in groups if g in always or g in self.caches})
                       for entry, lines, groups, always in self.entries]
            for _, lines, groups in grouped:
                for g in groups:
                    merge_lines(group_lines.setdefault(g, {}), lines)
            with open(out, "w") as f:
                for entry, lines, groups in grouped:
                    for g in groups:
                        merge_lines(lines, group_lines[g])
                    f.write(json.dumps(dict(entry, lines={k: sorted(v) for k, v in lines.items()})) + "\n")

    return CoveragePlugin()


def ctest_names(build):
    rc, out = run(["ctest", "--test-dir", str(build), "-N"], ROOT, 120)
    return [m.group(1) for m in re.finditer(r"Test\s+#\d+: (\S+)", out) if not m.group(1).startswith("fuzz")]


def coverage_map(rebuild=False):
    key = revision_key()
    path = CACHE / f"coverage-{MAP_FORMAT}-{key}.json"
    if path.exists() and not rebuild:
        print(f"coverage map: {path.relative_to(ROOT)} (cached for this revision)", flush=True)
        return dict(json.loads(path.read_text()), cached=True)
    build = CACHE / "cov"
    t0 = time.monotonic()
    print(f"coverage map for revision {key}: building {build.relative_to(ROOT)} ...", flush=True)
    configure_and_build(ROOT, build, COVERAGE_FLAGS, "coverage")
    tests = {}
    for name in ctest_names(build):
        clear_counters(build)
        t = time.monotonic()
        rc, _ = run(["ctest", "--test-dir", str(build), "-R", f"^{re.escape(name)}$", "--timeout", "900"], ROOT, 1000)
        tests[f"ctest:{name}"] = dict(duration=time.monotonic() - t, passed=rc == 0, lines=collect(build))
        print(f"  ctest {name}: {tests[f'ctest:{name}']['duration']:.1f} s", flush=True)
    default = ["--solver-tests-out", str(CACHE / "solver-tests.json")]  # read by the passes of the other solvers
    for solver, select in [("", default)] + [(s, test_solvers()[1]) for s in test_solvers()[0]]:
        clear_counters(build)
        out = CACHE / f"pytest-coverage{solver}.jsonl"
        out.unlink(missing_ok=True)  # a run that writes nothing must not leave an older run's tests behind
        t = time.monotonic()
        rc, text = run([python_exe(), str(pathlib.Path(__file__).resolve()), "_pytest", str(build), str(out), "fmu-test"]
                       + select, ROOT, 7200, dict(os.environ, VI_SOLVER=solver))
        if rc not in (0, 1) or not out.exists():  # pytest: 0 all passed, 1 some failed, others: no test run
            sys.exit(f"the FMU tests did not run in the coverage build (exit status {rc}): {text[-2000:]}")
        prefix = f"pytest@{solver}:" if solver else "pytest:"
        for line in out.read_text().splitlines():
            e = json.loads(line)
            tests[prefix + e["test"]] = dict(duration=e["duration"], passed=e["passed"], lines=e["lines"])
        py = [v for k, v in tests.items() if k.startswith(prefix)]
        print(f"  pytest{' with VI_SOLVER=' + solver if solver else ''}: {len(py)} tests, {time.monotonic() - t:.0f} s",
              flush=True)
        if not py or sum(1 for v in py if v["lines"]) < len(py) / 2:
            sys.exit(f"the FMU tests executed no line of src/ in the coverage build (did they load another FMU?): "
                     f"{text[-2000:]}")
    cmap = dict(revision=key, seconds=time.monotonic() - t0, tests=tests)
    path.write_text(json.dumps(cmap))
    print(f"coverage map: {len(tests)} tests in {cmap['seconds']:.0f} s -> {path.relative_to(ROOT)}", flush=True)
    return cmap


def test_solvers():
    """([VI_SOLVER values], [pytest's selecting options]): the solvers tools/test.sh runs the FMU tests with
    besides the default, and the tests it selects for them (-m or -k and its expression), read from its loop."""
    text = (ROOT / "tools" / "test.sh").read_text()
    m = re.search(r'for solver in ([\d ]+); do\s+VI_SOLVER=\$solver [^\n]*pytest[^\n]*(-[mk]) "([^"]*)"([^\n]*)', text)
    if not m:
        sys.exit("tools/test.sh: no loop 'for solver in ...; do VI_SOLVER=$solver ... pytest ... -m \"...\"' found: "
                 "mutate.py runs the FMU tests with the solvers of that loop (update test_solvers())")
    select = [m.group(2), m.group(3)]
    if "--solver-tests-from" in m.group(4):  # only the tests VI_SOLVER reaches, as the default pass wrote them
        select += ["--solver-tests-from", str(CACHE / "solver-tests.json")]
    return m.group(1).split(), select


def by_solver(tests):
    """{solver ('' for the default): {nodeid: test name}} of the FMU tests among the names."""
    out = {}
    for name in tests:
        m = re.match(r"pytest(?:@(\w+))?:(.*)", name)
        if m:
            out.setdefault(m.group(1) or "", {})[m.group(2)] = name
    return out


def prune_solvers(tests, ran):
    """The selected tests without the runs with another solver when the solver choice does not reach
    the mutated line: the same FMU tests execute it with every solver (ran: {solver: the nodeids run
    with it}). Otherwise every solver's selection is kept: a line that some solver reaches in other
    tests (or only some solver reaches) is tested as tools/test.sh tests it."""
    groups = by_solver(tests)
    default = set(groups.get("", {}))
    if all(set(groups.get(s, {})) == default & ran[s] for s in ran if s):
        return [t for t in tests if not t.startswith("pytest@")]
    return tests


def line_index(cmap):
    """{(file, line): [test names]} over the tests that pass on the unmutated code."""
    index = {}
    for name, t in cmap["tests"].items():
        if not t["passed"]:
            continue
        for f, lines in t["lines"].items():
            for ln in lines:
                index.setdefault((f, ln), []).append(name)
    return index


# ---- mutant runs -------------------------------------------------------------------------------

def objects_of(build, rel):
    """The object files compiled from the source rel in a build tree (one per target compiling it)."""
    name = pathlib.PurePath(rel).name + ".o"
    return sorted(p for p in build.glob("**/" + name) if "CMakeFiles" in p.parts and p.as_posix().endswith("/" + rel + ".o"))


# Trivial compiler equivalence beyond the build's own objects: the source compiled to assembly by each of
# these (those installed), with the build's other flags.
TCE_COMPILERS = (("gcc", "-O1"), ("gcc", "-O2"), ("gcc", "-O3"), ("gcc", "-Os"), ("clang", "-O2"), ("clang", "-O3"))


def compile_flags(build, rel):
    """[(directory, flags)]: each distinct way the build compiles the source rel (compile_commands.json: one
    per target, their definitions and include folders differ), the flags without the compiler, output,
    optimization level and link-time optimization."""
    commands = build / "compile_commands.json"
    if not commands.exists():
        run(["cmake", "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON", str(build)], ROOT, 900)
    ways = []
    for e in json.loads(commands.read_text()) if commands.exists() else []:
        if pathlib.Path(e["file"]).as_posix().endswith("/" + rel):
            words, flags, skip = shlex.split(e["command"])[1:], [], False
            for w in words:
                if skip or w in ("-o", "-c"):
                    skip = not skip
                    continue
                if not (w.startswith(("-O", "-flto")) or w == "-fno-fat-lto-objects" or w == e["file"]):
                    flags.append(w)
            if (e["directory"], flags + [e["file"]]) not in ways:
                ways.append((e["directory"], flags + [e["file"]]))
    return ways


def assembly(compiler, opt, where):
    """The assembly compiler gives the source at opt (where: compile_flags' answer), without the lines that
    name the file or the compiler; None if it does not compile."""
    directory, flags = where
    try:  # the assembly alone: a warning (on stderr) quotes the code
        r = subprocess.run([compiler, opt, "-S", "-o", "-", *flags], cwd=directory, capture_output=True, text=True,
                           errors="replace", timeout=300)
    except subprocess.TimeoutExpired:
        return None
    if r.returncode != 0:
        return None
    return "\n".join(ln for ln in r.stdout.splitlines() if not ln.lstrip().startswith((".file", ".ident")))


def sync_scratch(scratch):
    """Make scratch a copy of the tracked files (copying only what differs)."""
    for f in tracked_files():
        src, dst = ROOT / f, scratch / f
        if not dst.exists() or dst.read_bytes() != src.read_bytes():
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(src, dst)  # a new modification time: the copy's build must see the change (copy2 kept
            # the original's, older than the objects a mutant run had just rebuilt, and make skipped it)


def failed_tests(cmd, out):
    """The tests a failed ctest or pytest command names as failed (pytest's node ids, ctest's names)."""
    if cmd[0] == "ctest":
        return re.findall(r"^\s*\d+ - (\S+) \(", out, re.M)
    return [m.group(1) for m in re.finditer(r"^FAILED (.+?)(?: - .*)?$", out, re.M)]


def timed_out_tests(cmd, out):
    """The tests a failed command names as stopped at their own time limit (ctest's TIMEOUT, pytest.ini's
    timeout): a test that hangs has not failed."""
    if cmd[0] == "ctest":
        return re.findall(r"^\s*\d+ - (\S+) \(Timeout\)", out, re.M)
    return [m.group(1) for m in re.finditer(r"^FAILED (.+?) - Failed: Timeout\b", out, re.M)]


def rerun_of(cmd, names):
    """cmd narrowed to the tests `names`."""
    if cmd[0] == "ctest":
        i = cmd.index("-R")
        return cmd[:i + 1] + ["^(" + "|".join(re.escape(n) for n in names) + ")$"] + cmd[i + 2:]
    first_id = next(i for i, a in enumerate(cmd) if "::" in a or a.startswith("fmu-test/"))
    return cmd[:first_id] + names


def run_selected(scratch, tests, durations, limit, build="build"):
    """('passed', ''), ('failed', what failed) or ('timeout', where: the command's limit or a test's own) for
    the selected tests (fastest
    first, stopping at the first failure) within `limit` seconds: the ctest tests in the scratch copy's
    build folder `build`, the FMU tests with the solver they were selected for (VI_SOLVER, as
    tools/test.sh runs them). A failure counts when it repeats: the failed tests are run again alone,
    and if they pass, the whole command once more (a test that fails only now and then, or only under
    the load of the other scratch copies, kills no mutant)."""
    deadline = time.monotonic() + limit
    ctests = [t[len("ctest:"):] for t in tests if t.startswith("ctest:")]
    env = dict(os.environ)
    env.pop("VI_FMU", None)  # the tests take the scratch copy's build/VibroImpact.fmu
    env.pop("VI_SOLVER", None)
    cmds = []
    if ctests:
        cmds.append((["ctest", "--test-dir", build, "--stop-on-failure", "-R",
                      "^(" + "|".join(re.escape(t) for t in ctests) + ")$", "--timeout", str(int(limit) + 1)], env))
    for solver, names in sorted(by_solver(tests).items()):
        ids = sorted(names, key=lambda i: durations[names[i]])
        cmds.append(([python_exe(), "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider"] + ids,
                     dict(env, VI_SOLVER=solver) if solver else env))
    for cmd, cmd_env in cmds:
        where = "ctest" if cmd[0] == "ctest" else f"pytest (VI_SOLVER={cmd_env.get('VI_SOLVER', 'default')})"
        outcome, why = run_confirmed(cmd, cmd_env, scratch, deadline, limit)
        if outcome != "passed":
            return outcome, f"{where}: {why}"
    return "passed", ""


def run_confirmed(cmd, env, scratch, deadline, limit):
    """One command of run_selected, a failure confirmed as it says: (outcome, what failed). The tests
    that failed run again alone; when they pass alone, one more whole run decides."""
    def within(c):
        left = deadline - time.monotonic()
        if left <= 0:
            return "timeout", f"the limit of {limit:.0f} s was over before it ran"
        rc, out = run(c, scratch, left, env)
        return ("timeout", f"past the limit of {limit:.0f} s") if rc == "timeout" else (rc, out)

    def outcome(rc, out):
        if rc in ("timeout", 0):
            return ("passed", "", []) if rc == 0 else ("timeout", out, [])
        names = failed_tests(cmd, out)
        why = "; ".join(names[:3]) or (out.strip().splitlines() or ["(no output)"])[-1][:300]
        if names and set(names) <= set(timed_out_tests(cmd, out)):  # every failure a test's own time limit
            return "timeout", f"{why}: past its time limit", []
        return "failed", why, names

    result, why, names = outcome(*within(cmd))
    if result != "failed" or not names:
        return result, why
    alone, _ = within(rerun_of(cmd, names))
    if alone != 0:
        return ("timeout" if alone == "timeout" else "failed"), why
    return outcome(*within(cmd))[:2]


# The test command's sanitized build (tools/test.sh: build-asan, its ctest tests): an out-of-bounds
# access or undefined behaviour that the tests' own checks do not see fails a test there.
SANITIZE_FLAGS = ["-DVI_SANITIZE=ON"]
ARRAY_OR_LOOP = re.compile(r"\[|\b(for|while)\s*\(")


def in_array_or_loop_code(m):
    """Does the mutant's function index an array or loop? (A bound test may guard an index on
    another line of it.)"""
    lines = source_lines(m.file)[m.body[0] - 1:m.body[1]]
    return bool(ARRAY_OR_LOOP.search(mask("\n".join(lines), strings=False)))


def sanitized_names(ctests, build):
    """The selected ctest tests as the sanitized build names them (its memory check of the FMU driver
    is *_sanitized where the plain build's is *_valgrind), among the tests it has."""
    have = set(ctest_names(build))
    names = {re.sub(r"_valgrind$", "_sanitized", t) for t in ctests}
    return sorted(n for n in names if n in have)


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sample", type=int, default=None, help="number of mutants to draw (default: all)")
    ap.add_argument("--seed", type=int, default=None, help="seed of the sample (default: a fresh one, printed)")
    ap.add_argument("--files", nargs="+", default=["src/*"], help="globs of files under src/ to mutate")
    ap.add_argument("--list", action="store_true", help="list the mutants (name, line and column) and exit")
    ap.add_argument("--only", nargs="+", help="run only the mutants with these names (or file:line:col places)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="mutants run at once, each in its own scratch copy (default: the number of cores)")
    ap.add_argument("--json", help="write the results to this file")
    ap.add_argument("--rebuild-coverage", action="store_true", help="build the coverage map even if one is cached")
    ap.add_argument("--journal", help="append each mutant's result to this file as it ends, and take the results it "
                                      "holds for today's revision instead of running those mutants again (a long run "
                                      "over several sittings)")
    ap.add_argument("--equivalents", action="store_true",
                    help="replay the mutants listed as equivalent (with --files, --only, --sample: some of them) "
                         "under every condition of the test command: the FMU tests with every solver, the C tests "
                         "also in the sanitized build; exit status 1 when a test kills one")
    return ap.parse_args()


def select(args, equivalent, seed):
    """The mutants the arguments ask for."""
    mutants = all_mutants(args.files)
    if args.equivalents:
        mutants = [m for m in mutants if m.ident in equivalent]
    if args.only:
        wanted = set(args.only)
        mutants = [m for m in mutants if m.ident in wanted or m.where in wanted]
    return sample(mutants, args.sample, seed)


def stale_entries(equivalent):
    """Entries of the equivalents list that name no mutant of today's src/ (printed)."""
    names = {m.ident for m in all_mutants(["src/*"])}
    stale = [e for e in equivalent if e not in names]
    if stale:
        print(f"note: {len(stale)} entries of {EQUIVALENT.relative_to(ROOT)} name no mutant of today's src/:")
        for e in stale:
            print("  " + e)
    return stale


# A test that fails kills the mutant; one that runs past its time limit (the command's or its own) has
# neither failed nor passed: "timeout", counted and listed apart, outside the score.
VERDICT = {"passed": "survived", "failed": "killed", "timeout": "timeout"}
VERDICTS = ("killed", "survived", "uncovered", "timeout", "equivalent", "identical", "stillborn")


def read_journal(path, key):
    """The results a journal holds for the revision key, by mutant name (results of other revisions are
    left out: the code or the tests they ran on have changed)."""
    held = {}
    if path and path.exists():
        for line in path.read_text().splitlines():
            if line.strip():
                e = json.loads(line)
                if e.get("revision") == key:
                    held[e["result"]["name"]] = e["result"]
    return held


class Selection:
    """The tests the coverage map selects for a mutant, and their time in the map."""

    def __init__(self, cmap, replay):
        self.index = line_index(cmap)
        self.durations = {n: t["duration"] for n, t in cmap["tests"].items()}
        self.ran = {s: set(ids) for s, ids in by_solver(cmap["tests"]).items()}  # the FMU tests run with each solver
        self.replay = replay

    def tests_of(self, m):
        """The tests that execute the mutant's line (or its statement's, or its function's)."""
        index = self.index
        tests = sorted({t for ln in range(m.line, m.last_line + 1) for t in index.get((m.file, ln), [])})
        if not tests:  # gcov counts a statement that spans lines on one of them: those before it too
            tests = sorted({t for ln in range(m.stmt_line, m.line) for t in index.get((m.file, ln), [])})
        if not tests and (DECLARATION.match(m.site) or STATIC_DATA.match(source_line(m.file, m.stmt_line))):
            # no code of its own (a declaration, or a static table's initializer): the tests of its function
            tests = sorted({t for ln in range(m.body[0], m.body[1] + 1) for t in index.get((m.file, ln), [])})
        return tests if self.replay else prune_solvers(tests, self.ran)

    def seconds(self, mutants):
        """The time the selected tests of these mutants took in the coverage map, summed (one core)."""
        return sum(self.durations[t] for m in mutants for t in self.tests_of(m))


class Runner(Selection):
    """Runs mutants, each in a free scratch copy of the repository (one per job), against the tests the
    coverage map selects for its line; prints a line per mutant as it ends."""

    def __init__(self, cmap, jobs, sources, n_mutants, equivalent, replay, journal=None):
        super().__init__(cmap, replay)
        self.journal, self.revision = journal, cmap["revision"]
        self.equivalent, self.n_mutants = equivalent, n_mutants
        self.scratches = [CACHE / ("scratch" if j == 0 else f"scratch-{j}") for j in range(jobs)]
        for scratch in self.scratches:
            print(f"scratch copy {scratch.relative_to(ROOT)}: building the original ...", flush=True)
            sync_scratch(scratch)
            configure_and_build(scratch, scratch / "build", [], "scratch")
        self.make_jobs = f"-j{max(1, (os.cpu_count() or 1) // jobs)}"
        # the object code of the original, per scratch copy and source (a mutant compiled to the same code
        # is equivalent: "identical")
        self.original_code = {scratch: {f: {p: p.read_bytes() for p in objects_of(scratch / "build", f)}
                                        for f in sources} for scratch in self.scratches}
        self.compilers = [(c, o) for c, o in TCE_COMPILERS if shutil.which(c)]
        self.original_asm = {}  # (scratch, source, compiler, level, way): the original's assembly
        self.t0 = time.monotonic()
        self.free = queue.Queue()
        for scratch in self.scratches:
            self.free.put(scratch)
        self.printing = threading.Lock()
        self.done = 0

    def same_assembly(self, m, scratch, target, original):
        """The first compiler and level of TCE_COMPILERS under which the mutant (in place in scratch) compiles to
        the original's assembly in every way the build compiles its source, as "gcc -O2"; "" if none does."""
        ways = compile_flags(scratch / "build", m.file)
        for compiler, opt in self.compilers if ways else []:
            for k, where in enumerate(ways):
                key = (scratch, m.file, compiler, opt, k)
                if key not in self.original_asm:
                    target.write_text(original)
                    self.original_asm[key] = assembly(compiler, opt, where)
                    target.write_text(original[:m.start] + m.new + original[m.end:])
                mutated = assembly(compiler, opt, where)
                if mutated is None or mutated != self.original_asm[key]:
                    break
            else:
                return f"{compiler} {opt}"
        return ""

    def verdict(self, m, scratch, target, tests, original):
        """The mutant, in place in scratch, built and run: its verdict and how it was reached."""
        same = self.same_assembly(m, scratch, target, original)
        if same:
            return "identical", f" (the same assembly with {same})", ""
        rc, _ = run(["cmake", "--build", "build", self.make_jobs], scratch, 900)
        before = self.original_code[scratch][m.file]
        how = why = ""
        if rc != 0:
            verdict = "stillborn"
        elif before and all(before.get(p) == p.read_bytes() and p.stat().st_mtime_ns >= target.stat().st_mtime_ns
                            for p in objects_of(scratch / "build", m.file)):
            verdict = "identical"  # every object of the source rebuilt from the mutant, byte for byte the original
        elif not tests:
            verdict = "uncovered"
        else:
            limit = 3 * sum(self.durations[t] for t in tests) + 60
            outcome, why = run_selected(scratch, tests, self.durations, limit)
            verdict = VERDICT[outcome]
        ctests = [t[len("ctest:"):] for t in tests if t.startswith("ctest:")]
        if verdict == "survived" and ctests and (self.replay or in_array_or_loop_code(m)):
            (verdict, why), how = self.sanitized_run(scratch, ctests), " (sanitized build)"
        if verdict in ("survived", "uncovered") and m.ident in self.equivalent:
            verdict = "equivalent"
        return verdict, how, why

    def run_mutant(self, m):
        scratch = self.free.get()
        try:
            t0 = time.monotonic()
            target = scratch / m.file
            original = target.read_text()
            target.write_text(original[:m.start] + m.new + original[m.end:])
            tests = self.tests_of(m)
            try:
                verdict, how, why = self.verdict(m, scratch, target, tests, original)
            finally:
                target.write_text(original)
                os.utime(target, None)
            dt = time.monotonic() - t0
            result = dict(name=m.ident, where=m.where, verdict=verdict, tests=len(tests), seconds=dt,
                          sanitized=bool(how) and verdict in ("killed", "timeout"),
                          identical_under=how.strip(" ()") if verdict == "identical" else "",
                          killed_by=why if verdict == "killed" else "", timed_out=why if verdict == "timeout" else "")
            with self.printing:
                self.done += 1
                print(f"[{self.done}/{self.n_mutants} {time.monotonic() - self.t0:6.0f} s] {verdict:10s} {len(tests):3d} "
                      f"tests {dt:5.1f} s  {m.where}  {m.ident}{how if verdict in ('killed', 'timeout', 'identical') else ''}",
                      flush=True)
                if self.journal:
                    with self.journal.open("a") as f:
                        f.write(json.dumps(dict(revision=self.revision, result=result)) + "\n")
            return result
        finally:
            self.free.put(scratch)

    def sanitized_run(self, scratch, ctests):
        """('killed' or 'survived', what failed): the mutant (in place in scratch) built with the
        sanitizers, as the test command's build-asan, and its selected C tests run there (the build is
        made once per scratch copy and then rebuilt for each mutant that needs it)."""
        configure_and_build(scratch, scratch / "build-san", SANITIZE_FLAGS, "sanitized")
        names = sanitized_names(ctests, scratch / "build-san")
        limit = 10 * sum(self.durations[f"ctest:{t}"] for t in ctests) + 120
        outcome, why = run_selected(scratch, [f"ctest:{n}" for n in names], self.durations, limit, build="build-san")
        return VERDICT[outcome], why

    def run_all(self, mutants, jobs):
        with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
            results = list(pool.map(self.run_mutant, mutants))
        for scratch in self.scratches:  # the scratch copies back at the original
            run(["cmake", "--build", "build", self.make_jobs], scratch, 900)
        return results


def print_names(title, rows, fmt):
    if rows:
        print(title)
        for r in rows:
            print(fmt(r))


def report(results, seed, n_mutants, equivalent, timing):
    """The score and the mutants by verdict. Returns the listed equivalents a test killed or that timed out
    (neither is shown equivalent by the run)."""
    count = {v: [r for r in results if r["verdict"] == v] for v in VERDICTS}
    k, s, u, t = (len(count[v]) for v in ("killed", "survived", "uncovered", "timeout"))
    times = [r["seconds"] for r in results if r["verdict"] not in ("stillborn", "identical")]
    print()
    print(f"seed {seed}: {n_mutants} mutants; killed {k}, survived {s}, uncovered {u}, timeout {t}, "
          f"equivalent {len(count['equivalent'])}, identical object code {len(count['identical'])}, "
          f"stillborn (do not compile) {len(count['stillborn'])}")
    if k + s + u:
        print(f"mutation score: {k} of {k + s + u} non-equivalent mutants killed, {100.0 * k / (k + s + u):.1f} %"
              + (f" ({t} timed out, not scored: listed below)" if t else ""))
    if times:
        print(f"time per mutant: mean {statistics.mean(times):.1f} s, median {statistics.median(times):.1f} s; {timing}")

    def where(r):
        return f"  {r['where']}  {r['name']}"
    for v in ("survived", "uncovered"):
        print_names(f"\n{v}:", count[v], where)
    print_names("\ntimeout (a test ran past its time limit: neither killed nor survived; read why):", count["timeout"],
                lambda r: where(r) + ("  [sanitized build]" if r["sanitized"] else "") + f"\n      {r['timed_out']}")
    print_names("\nidentical object code (equivalent: the compiler made the same code of it):", count["identical"],
                lambda r: where(r) + (f"  [{r['identical_under']}]" if r.get("identical_under") else ""))
    print_names(f"\nequivalent ({EQUIVALENT.relative_to(ROOT)}):", count["equivalent"],
                lambda r: f"  {r['name']}  # {equivalent[r['name']]}")
    print_names("\nkilled in the sanitized build only:", [r for r in count["killed"] if r["sanitized"]], where)
    listed_killed = [r for r in count["killed"] + count["timeout"] if r["name"] in equivalent]
    print_names(f"\nlisted in {EQUIVALENT.relative_to(ROOT)}, but killed by a test or timed out (not shown equivalent: "
                "write down why, then take the entry out):", listed_killed,
                lambda r: where(r) + ("  [sanitized build]" if r["sanitized"] else "")
                + f"\n      {'by ' + r['killed_by'] if r['verdict'] == 'killed' else 'timeout: ' + r['timed_out']}")
    return listed_killed


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "_pytest":
        return pytest_worker(sys.argv[2], sys.argv[3], sys.argv[4:])
    args = parse_args()
    seed = args.seed if args.seed is not None else int.from_bytes(os.urandom(4), "little")
    equivalent = read_equivalent()
    mutants = select(args, equivalent, seed)
    if args.list:
        for m in mutants:
            print(f"{m.where}  {m.ident}" + ("   [equivalent]" if m.ident in equivalent else ""))
        print(f"{len(mutants)} mutants")
        return 0
    stale = stale_entries(equivalent)
    command = f"python3 tools/mutate.py --seed {seed}" + (" --equivalents" if args.equivalents else "") + \
        (f" --sample {args.sample}" if args.sample else "") + \
        ("" if args.files == ["src/*"] else " --files " + " ".join(args.files))
    print(f"seed {seed}: {len(mutants)} mutants (repeat with: {command})", flush=True)

    t_start = time.monotonic()
    CACHE.mkdir(parents=True, exist_ok=True)
    cmap = coverage_map(args.rebuild_coverage)
    failing = sorted(n for n, t in cmap["tests"].items() if not t["passed"])
    if failing:
        print(f"{len(failing)} tests fail on the unmutated code and are never selected: " + ", ".join(failing))
    jobs = max(1, args.jobs)
    journal = pathlib.Path(args.journal) if args.journal else None
    held = read_journal(journal, cmap["revision"])
    todo = [m for m in mutants if m.ident not in held]
    if journal:
        print(f"journal {journal}: {len(mutants) - len(todo)} of the {len(mutants)} mutants done for this revision, "
              f"{len(todo)} to run", flush=True)
    print(f"the tests selected for the {len(todo)} mutants to run took {Selection(cmap, args.equivalents).seconds(todo) / 3600:.1f} "
          f"hours in the coverage map (one core; a run takes less where a mutant is killed early)", flush=True)
    t_mutants = time.monotonic()
    results = [held[m.ident] for m in mutants if m.ident in held]
    if todo:
        runner = Runner(cmap, jobs, sorted({m.file for m in todo}), len(todo), equivalent, args.equivalents, journal)
        t_mutants = runner.t0
        results += runner.run_all(todo, jobs)
    timing = (f"mutants {time.monotonic() - t_mutants:.0f} s ({jobs} at once), whole run {time.monotonic() - t_start:.0f} s "
              f"(coverage map {'cached' if cmap.get('cached') else 'built in %.0f s' % cmap['seconds']})")
    listed_killed = report(results, seed, len(mutants), equivalent, timing)
    if stale:  # again at the end of a long run, with the killed entries
        print(f"\n{len(stale)} stale entries of {EQUIVALENT.relative_to(ROOT)} (they name no mutant of today's src/):")
        for e in stale:
            print("  " + e)
    if args.json:
        counts = {v: sum(r["verdict"] == v for r in results) for v in VERDICTS}
        pathlib.Path(args.json).write_text(json.dumps(dict(
            seed=seed, command=command, counts=counts, stale=stale, listed_killed=[r["name"] for r in listed_killed],
            results=results), indent=1))
    return 1 if args.equivalents and (listed_killed or stale) else 0


if __name__ == "__main__":
    sys.exit(main())
