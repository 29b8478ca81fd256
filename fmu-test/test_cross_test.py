"""tools/cross_test.sh fails when any of its parts fails: the script itself, copied into a tree of stand-ins
(a release command that does nothing, drivers that print records and compare them as equal, wine and qemu
that run the driver they are given, a Python that plays tools/fmu_source_build.py and tools/wheel_test.py).
A clean run of the stand-ins passes; each part told to fail (FAKE_FAIL) must give a non-zero exit, its
FAILED line and no "all passed", wherever the script runs the part (in a command substitution, a pipe, a
process substitution)."""
import os
import pathlib
import shutil
import subprocess
import zipfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent

# one stand-in for fmu_driver and fmu3_driver of every platform; FAKE_FAIL names the part that fails
DRIVER = r"""#!/bin/bash
fail() { [ "${FAKE_FAIL-}" = "$1" ]; }
case $1 in
  cases) echo case_a; echo case_b
         if [[ $0 == *fmu3_driver* ]] && fail fmi3-cases; then exit 1; fi ;;
  run) if [[ $0 == *aarch64* ]] && fail aarch64-run; then echo crashed >&2; exit 1; fi
       echo "record $3" ;;
  companion) echo "companion $2" ;;
  compare) if fail compare && [[ $3 == *aarch64* ]]; then echo "differs"; exit 1; fi
           echo "max difference 0 (bit for bit)" ;;
  layer) cat "$ROOT_VALUE"
         if fail resource-exit; then exit 1; fi ;;
  *) echo "fmu_driver: all checks passed" ;;
esac
"""
# tools/fmu_source_build.py and tools/wheel_test.py as "$PYTHON" runs them
PYTHON = r"""#!/bin/bash
fail() { [ "${FAKE_FAIL-}" = "$1" ]; }
case $1 in
  *fmu_source_build.py)
    if fail source-build; then echo "error: the compiler failed"; exit 1; fi
    if [[ $2 == cc ]]; then lib=$4/VibroImpact.dll; else lib=$4/VibroImpact.so; fi
    echo "$lib" ;;
  *wheel_test.py)
    echo "wheel_test: the FMUs ran"
    if fail wheel; then exit 1; fi ;;
  *) exit 2 ;;
esac
"""
WINE = '#!/bin/bash\n[ "$1" = wineboot ] && exit 0\nexec "$@"\n'
QEMU = '#!/bin/bash\nshift 2  # -L <sysroot>\nexec "$@"\n'


def _script(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    path.chmod(0o755)


@pytest.fixture(scope="module")
def tree(tmp_path_factory):
    """A copy of tools/cross_test.sh in a tree of stand-ins for what it runs and reads."""
    t = tmp_path_factory.mktemp("cross")
    (t / "tools").mkdir()
    shutil.copy(ROOT / "tools" / "cross_test.sh", t / "tools" / "cross_test.sh")
    _script(t / "tools" / "release.sh", "#!/bin/sh\nexit 0\n")
    for header in ("tests/layer_fmu/layer_variables.h", "examples/vehicle-track/track/track_variables.h",
                   "examples/vehicle-track/vehicle/vehicle_variables.h"):
        (t / header).parent.mkdir(parents=True, exist_ok=True)
        (t / header).write_text('#define GUID "{00000000-0000-0000-0000-000000000000}"\n')
    (t / "tests/layer_fmu/value.txt").write_text("42\n")
    for fmu in ("dist/fmi2/VibroImpact.fmu", "dist/fmi2/Track.fmu", "dist/fmi2/Vehicle.fmu", "dist/fmi3/VibroImpact.fmu"):
        (t / fmu).parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(t / fmu, "w") as z:
            z.writestr("modelDescription.xml", "<fmiModelDescription/>")
    (t / "dist/vibroimpact-0-py3-none-any.whl").write_bytes(b"")
    for target, ext in (("x86_64-linux", ""), ("x86_64-windows", ".exe"), ("aarch64-linux", "")):
        for driver in ("fmu_driver", "fmu3_driver"):
            _script(t / "build/release" / target / (driver + ext), DRIVER)
    _script(t / "fake/python", PYTHON)
    _script(t / "fake/wine64", WINE)
    _script(t / "fake/qemu-aarch64", QEMU)
    return t


def run(tree, fail=None):
    env = {**os.environ, "PYTHON": str(tree / "fake/python"), "VI_WINE": str(tree / "fake/wine64"),
           "VI_QEMU": str(tree / "fake/qemu-aarch64"), "ROOT_VALUE": str(tree / "tests/layer_fmu/value.txt")}
    env.pop("FAKE_FAIL", None)
    if fail:
        env["FAKE_FAIL"] = fail
    return subprocess.run(["bash", str(tree / "tools/cross_test.sh")], env=env, capture_output=True, text=True,
                          timeout=100)


def test_the_stand_ins_pass(tree):
    """The control: with nothing failing the script passes, so a failure below is the part's."""
    r = run(tree)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "cross_test: all passed" in r.stdout
    assert "FAILED" not in r.stderr
    # every part ran: the platforms, FMI 3.0, both source builds of fmpy and MinGW's, the wheel
    for part in ("aarch64-linux   case_a", "x86_64-windows  resources", "fmi3-case_b", "source-fmpy",
                 "source-mingw", "wheel"):
        assert part in r.stdout, (part, r.stdout)


@pytest.mark.parametrize("part, message", [
    ("source-build", "the fmpy-fmi2 build from sources"),  # run inside $(...): was lost, "all passed"
    ("fmi3-cases", "fmu3_driver cases fails"),  # a process substitution: its status was not read
    ("resource-exit", "LayerTest"),  # the right value printed by a driver that then fails: `| tr || true`
    ("aarch64-run", "aarch64-linux: case case_a fails"),
    ("compare", "differs"),
    ("wheel", "the wheel"),
])
def test_a_failing_part_fails_the_run(tree, part, message):
    r = run(tree, part)
    assert r.returncode != 0, r.stdout + r.stderr
    assert "all passed" not in r.stdout
    assert "cross_test: FAILED" in r.stderr and message in r.stderr, r.stderr
