"""The release wheel on a machine without a compiler (run by tools/cross_test.sh after tools/release.sh):

    python tools/wheel_test.py <wheel> <the FMI 2.0 FMU it must hold> <the FMI 3.0 FMU>

A fresh virtual environment, and a PATH holding only its bin/ (checked: no cc, gcc, clang, cmake,
make, zig or mingw on it); the wheel installed there by pip from wheels only (--only-binary :all:,
its dependencies from the package index or pip's cache: nothing may be built). Then, in that
environment:
  - `vibroimpact path` prints an FMU inside the environment, the same bytes as the release FMU
  - vibroimpact.fmu_path() and its FMI 3.0 sibling run through fmpy (simulate_fmu, the default
    experiment): the two give the same y at every output point, and no SUNDIALS library is loaded
    into the process (/proc/self/maps)
  - `vibroimpact compare` (every scenario of the paper against the independent reference in the
    package): every scenario agrees with the reference over its whole horizon, with the same mode changes
Prints one line per check; exits 1 at the first failure.
"""
import hashlib
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import venv

TIMEOUT = 900  # s, each command (the install may download the dependencies)
BUILD_TOOLS = ["cc", "gcc", "clang", "cmake", "make", "zig", "x86_64-w64-mingw32-gcc", "aarch64-linux-gnu-gcc"]

IN_ENV = r"""
import json, sys
import numpy as np
from fmpy import simulate_fmu
import vibroimpact
fmu2 = vibroimpact.fmu_path()
fmu3 = fmu2.parent / "fmi3" / fmu2.name
r2 = simulate_fmu(str(fmu2), output=["y"])
r3 = simulate_fmu(str(fmu3), output=["y"])
maps = open("/proc/self/maps").read()
print(json.dumps(dict(
    fmu2=str(fmu2), fmu3=str(fmu3), n2=len(r2), n3=len(r3),
    same_y=bool(len(r2) == len(r3) and np.array_equal(r2["y"], r3["y"]) and np.array_equal(r2["time"], r3["time"])),
    finite=bool(np.isfinite(r2["y"]).all()),
    sundials=sorted({line.split()[-1] for line in maps.splitlines() if "sundials" in line.lower()}))))
"""


def fail(message):
    print(f"wheel_test: FAILED: {message}")
    sys.exit(1)


def ok(message):
    print(f"wheel_test: {message}")


def sha256(path):
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def run(command, env, what):
    try:
        done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        fail(f"{what}: more than {TIMEOUT} s")
    if done.returncode != 0:
        fail(f"{what} failed:\n{done.stdout[-3000:]}{done.stderr[-3000:]}")
    return done.stdout


def main():
    if len(sys.argv) != 4:
        fail("usage: wheel_test.py <wheel> <FMI 2.0 FMU> <FMI 3.0 FMU>")
    wheel, fmu2, fmu3 = (pathlib.Path(a).resolve() for a in sys.argv[1:])
    with tempfile.TemporaryDirectory() as tmp:
        env_dir = pathlib.Path(tmp) / "venv"
        venv.EnvBuilder(with_pip=True).create(env_dir)
        bin_dir = env_dir / "bin"
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VI_FMU", "VIRTUAL_ENV")}
        env.update(PATH=str(bin_dir), HOME=os.environ.get("HOME", tmp), PIP_DISABLE_PIP_VERSION_CHECK="1")
        found = {t: shutil.which(t, path=env["PATH"]) for t in BUILD_TOOLS}
        if any(found.values()):
            fail(f"build tools on the test PATH: {[p for p in found.values() if p]}")
        ok(f"PATH={env['PATH']}: none of {' '.join(BUILD_TOOLS)}")
        python = str(bin_dir / "python")
        run([python, "-m", "pip", "install", "--quiet", "--only-binary", ":all:", str(wheel)], env,
            "pip install --only-binary :all: of the wheel")
        ok(f"pip install {wheel.name} (wheels only: nothing built)")
        check_path(bin_dir, env, env_dir, fmu2)
        check_fmpy(python, env, env_dir, fmu3)
        check_compare(bin_dir, env)


def check_path(bin_dir, env, env_dir, fmu2):
    path = pathlib.Path(run([str(bin_dir / "vibroimpact"), "path"], env, "vibroimpact path").strip().splitlines()[-1])
    if env_dir not in path.parents:
        fail(f"vibroimpact path: {path} is not inside the fresh environment {env_dir}")
    if sha256(path) != sha256(fmu2):
        fail(f"vibroimpact path: {path} is not the release FMU {fmu2}")
    ok(f"vibroimpact path: {path.relative_to(env_dir)} (the release FMI 2.0 FMU, byte for byte)")


def check_fmpy(python, env, env_dir, fmu3):
    out = json.loads(run([python, "-c", IN_ENV], env, "fmpy's simulate_fmu of vibroimpact.fmu_path()").splitlines()[-1])
    if sha256(out["fmu3"]) != sha256(fmu3):
        fail(f"{out['fmu3']} is not the release FMI 3.0 FMU {fmu3}")
    if not (out["same_y"] and out["finite"] and out["n2"] > 10):
        fail(f"fmpy: FMI 2.0 and 3.0 runs differ or are not finite: {out}")
    if out["sundials"]:
        fail(f"fmpy: a SUNDIALS library was loaded: {out['sundials']}")
    ok(f"fmpy simulate_fmu: the FMI 2.0 and 3.0 FMUs give the same y at {out['n2']} points; no SUNDIALS library loaded")


def check_compare(bin_dir, env):
    table = run([str(bin_dir / "vibroimpact"), "compare"], env, "vibroimpact compare")
    rows = [r for r in table.splitlines() if r.startswith("| ") and not r.startswith("| scenario")]
    if not rows:
        fail(f"vibroimpact compare printed no scenario:\n{table}")
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        horizon, until = float(cells[1]), float(cells[2])
        if until < horizon or "(same)" not in cells[5]:
            fail(f"vibroimpact compare: {cells[0]} leaves the reference before its horizon or changes modes "
                 f"otherwise: {row}")
    ok(f"vibroimpact compare: {len(rows)} scenarios agree with the reference over their horizons, same mode changes")


if __name__ == "__main__":
    main()
