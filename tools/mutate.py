#!/usr/bin/env python3
"""Mutation testing of src/: do the tests notice single-point faults?

Usage:
    python3 tools/mutate.py [--sample N] [--seed S] [--files GLOB ...] [--timeout SEC] [--list]
                            [--only ID ...]

Each mutant changes one place of one C file under src/ (operators, constants, a removed statement,
a negated or forced condition, a changed return status). For each mutant the script copies the
tracked files of the repository into a scratch checkout, applies the change, rebuilds (a build
that fails counts as "stillborn" and is not scored), and runs the C tests (ctest) and the FMU
tests (pytest -x, stopping at the first failure) with a time limit per mutant; a mutant whose run
fails or times out is "killed", one whose run passes "survives". The score is
killed / (killed + survived), with the mutants listed in tools/mutants-equivalent.txt left out
(equivalent mutants: no test can tell them apart from the original; each entry gives the reason).
A mutant is named `file:line:column:kind:old->new` (the names --only and the equivalents file use).

The mutants are enumerated deterministically; --sample N draws N of them with --seed (default 1),
stratified by file, so a rerun with the same arguments tests the same mutants. --list prints the
mutants without running them. The scratch checkout lives in a temporary directory and is removed.
"""
import argparse
import dataclasses
import fnmatch
import os
import pathlib
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
EQUIVALENT = ROOT / "tools" / "mutants-equivalent.txt"


@dataclasses.dataclass
class Mutant:
    file: str      # path relative to ROOT
    start: int     # character offset of the replaced text
    end: int
    new: str
    kind: str
    line: int
    old: str
    col: int       # column of the replaced text (1-based): several mutants of one kind may share a line

    @property
    def ident(self):
        flat = lambda t: " ".join(t.split())  # noqa: E731
        return f"{self.file}:{self.line}:{self.col}:{self.kind}:{flat(self.old)}->{flat(self.new)}"


# ---- finding mutation sites ------------------------------------------------------------------

def mask(text):
    """The text with comments, string and character literals and preprocessor lines blanked out
    (same length), so that the patterns below only see code."""
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


def mutants_of(path):
    rel = str(path.relative_to(ROOT))
    text = path.read_text()
    masked = mask(text)
    found = []

    def add(start, end, new, kind):
        line, col = text.count("\n", 0, start) + 1, start - text.rfind("\n", 0, start)
        found.append(Mutant(rel, start, end, new, kind, line, text[start:end], col))

    # function bodies only: regions opened by a '{' at file scope that follows ')' (a definition)
    inside = bytearray(len(masked) + 1)
    d, in_fn = 0, False
    for i, c in enumerate(masked):
        if c == "{":
            if d == 0:
                in_fn = prev_code_char(masked, i) == ")"
            d += 1
        elif c == "}":
            d -= 1
            if d == 0:
                in_fn = False
        inside[i] = in_fn and d > 0
    body = lambda pos: bool(inside[pos])  # noqa: E731

    for m in re.finditer(r"<=|>=|==|!=|(?<![<>-])[<>](?![<>=])", masked):
        if body(m.start()):
            add(m.start(), m.end(), RELATIONAL[m.group()], "relational")
    for m in re.finditer(r"&&|\|\|", masked):
        if body(m.start()):
            add(m.start(), m.end(), LOGICAL[m.group()], "logical")
    for m in re.finditer(r"(?<![+\-*/=<>!&|])([+\-*/])(?![+\-*/=>])", masked):
        pos = m.start()
        if not body(pos):
            continue
        p = prev_code_char(masked, pos)
        if not (p.isalnum() or p in "_)]"):
            continue  # unary
        if m.group() in "+-" and re.search(r"\d[eE]$", masked[max(0, pos - 30):pos]):
            continue  # exponent of a number
        add(pos, pos + 1, ARITH[m.group()], "arithmetic")
    for m in NUMBER.finditer(masked):
        if not body(m.start()):
            continue
        lit = m.group()
        if re.fullmatch(r"\d+", lit):
            new = str(int(lit) + 1) if lit != "1" else "0"
        else:
            new = repr(float(lit) * 1.01) if float(lit) != 0.0 else "1e-3"
        add(m.start(), m.end(), new, "constant")
    for m in re.finditer(r"\bif\s*\(", masked):
        if not body(m.start()):
            continue
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
        add(open_ + 1, j, f"!({cond})", "negate-condition")
        add(open_ + 1, j, "0", "condition-false")
    for m in re.finditer(r"\b(fmi2OK|fmi2Error|fmi2Discard|fmi2Warning)\b", masked):
        if body(m.start()) and re.search(r"return\s*$", masked[max(0, m.start() - 20):m.start()]):
            add(m.start(), m.end(), STATUS[m.group()], "status")
    for m in re.finditer(r"\breturn\s+(-1|0)\s*;", masked):
        if body(m.start()):
            add(m.start(1), m.end(1), "0" if m.group(1) == "-1" else "-1", "status")
    # removed statements: a whole line that is one expression statement (assignment or call)
    pos = 0
    for line in masked.splitlines(keepends=True):
        s = line.strip()
        if (body(pos) and s.endswith(";") and not s.startswith(("return", "break", "continue", "case", "default"))
                and re.match(r"^[\w\->.\[\]*()]+\s*(\(|[+\-*/]?=)", s)
                and not re.match(r"^(const\s+)?(unsigned\s+|signed\s+)?(int|long|double|float|char|size_t|"
                                 r"void|struct|vi_\w+|fmi2\w+|N_Vector|SUNContext|sunrealtype)\b", s)):
            start = pos + len(line) - len(line.lstrip())
            end = pos + len(line.rstrip("\n"))
            add(start, end, ";", "remove-statement")
        pos += len(line)
    return found


def all_mutants(globs):
    files = sorted(p for p in (ROOT / "src").rglob("*.c")
                   if any(fnmatch.fnmatch(str(p.relative_to(ROOT)), g) for g in globs))
    out = []
    for f in files:
        out.extend(mutants_of(f))
    return out


def sample(mutants, n, seed):
    if n is None or n >= len(mutants):
        return mutants
    rng = random.Random(seed)
    by_file = {}
    for m in mutants:
        by_file.setdefault(m.file, []).append(m)
    total = len(mutants)
    picked = []
    for f, ms in sorted(by_file.items()):
        k = max(1, round(n * len(ms) / total))
        picked.extend(rng.sample(ms, min(k, len(ms))))
    rng.shuffle(picked)
    return sorted(picked[:n], key=lambda m: (m.file, m.start))


def read_equivalent():
    """Lines 'ident  # reason'. Returns {ident: reason}."""
    eq = {}
    if EQUIVALENT.exists():
        for line in EQUIVALENT.read_text().splitlines():
            if line.strip() and not line.startswith("#"):
                ident, _, reason = line.partition("  # ")
                eq[ident.strip()] = reason.strip()
    return eq


# ---- running ---------------------------------------------------------------------------------

def run(cmd, cwd, timeout, env=None):
    try:
        r = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout,
                           env=env, text=True)
        return r.returncode, r.stdout
    except subprocess.TimeoutExpired as e:
        return "timeout", (e.stdout or "") if isinstance(e.stdout, str) else ""


def prepare_scratch(scratch):
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, stdout=subprocess.PIPE, text=True, check=True).stdout.split()
    for f in files:
        src, dst = ROOT / f, scratch / f
        if src.is_file():
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)
    python = shutil.which(os.environ.get("PYTHON", "python3"))
    rc, out = run(["cmake", "-S", ".", "-B", "build", "-DVI_REQUIRE_TESTS=ON", f"-DPython3_EXECUTABLE={python}"],
                  scratch, 600)
    if rc != 0:
        sys.exit("configure failed:\n" + out)
    rc, out = run(["cmake", "--build", "build", "-j2"], scratch, 600)
    if rc != 0:
        sys.exit("the unmutated build failed:\n" + out)


def test_commands(timeout):
    python = os.environ.get("PYTHON", "python3")
    return [["ctest", "--test-dir", "build", "--stop-on-failure", "--timeout", str(timeout)],
            [python, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "fmu-test"]]


def run_tests(scratch, timeout):
    """'passed', 'failed' or 'timeout' for the whole test run within `timeout` seconds."""
    deadline = time.monotonic() + timeout
    for cmd in test_commands(timeout):
        left = deadline - time.monotonic()
        if left <= 0:
            return "timeout"
        rc, _ = run(cmd, scratch, left)
        if rc == "timeout":
            return "timeout"
        if rc != 0:
            return "failed"
    return "passed"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sample", type=int, default=None, help="number of mutants to draw (default: all)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--files", nargs="+", default=["src/*"], help="globs of files under src/ to mutate")
    ap.add_argument("--timeout", type=float, default=900, help="seconds per mutant for the whole test run")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--only", nargs="+", help="run only the mutants with these identifiers")
    args = ap.parse_args()

    mutants = all_mutants(args.files)
    if args.only:
        mutants = [m for m in mutants if m.ident in set(args.only)]
    mutants = sample(mutants, args.sample, args.seed)
    equivalent = read_equivalent()
    if args.list:
        for m in mutants:
            print(m.ident + ("   [equivalent]" if m.ident in equivalent else ""))
        print(f"{len(mutants)} mutants")
        return 0

    with tempfile.TemporaryDirectory(prefix="vi-mutate-") as tmp:
        scratch = pathlib.Path(tmp)
        print(f"scratch checkout {scratch}; building the original ...", flush=True)
        prepare_scratch(scratch)
        if run_tests(scratch, args.timeout) != "passed":
            sys.exit("the tests fail on the unmutated code: fix that first")
        results = {"killed": [], "survived": [], "stillborn": [], "equivalent": []}
        t0 = time.monotonic()
        for i, m in enumerate(mutants, 1):
            target = scratch / m.file
            original = target.read_text()
            target.write_text(original[:m.start] + m.new + original[m.end:])
            try:
                rc, _ = run(["cmake", "--build", "build", "-j2"], scratch, 600)
                if rc != 0:
                    verdict = "stillborn"
                else:
                    verdict = {"passed": "survived", "failed": "killed", "timeout": "killed"}[
                        run_tests(scratch, args.timeout)]
                    if verdict == "survived" and m.ident in equivalent:
                        verdict = "equivalent"
            finally:
                target.write_text(original)
                os.utime(target, None)
            results[verdict].append(m)
            print(f"[{i}/{len(mutants)} {time.monotonic() - t0:6.0f} s] {verdict:10s} {m.ident}", flush=True)
        run(["cmake", "--build", "build", "-j2"], scratch, 600)

    k, s = len(results["killed"]), len(results["survived"])
    print()
    print(f"mutants: {len(mutants)}; killed {k}, survived {s}, equivalent {len(results['equivalent'])}, "
          f"stillborn (do not compile) {len(results['stillborn'])}")
    if k + s:
        print(f"mutation score: {100.0 * k / (k + s):.1f} % of non-equivalent mutants killed")
    if results["survived"]:
        print("\nsurvivors:")
        for m in results["survived"]:
            print("  " + m.ident)
    if results["equivalent"]:
        print("\nequivalent (tools/mutants-equivalent.txt):")
        for m in results["equivalent"]:
            print(f"  {m.ident}  # {equivalent[m.ident]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
