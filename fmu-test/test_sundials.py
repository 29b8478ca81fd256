"""The FMU on SUNDIALS 7.9 against the FMU on SUNDIALS 6.4: the build takes either (cmake/vi_sundials.cmake).

build/sundials7/ is the FMU built against SUNDIALS 7.9.0 from the sundials4py wheel (CVODES; built by
tools/sundials7.sh, which tools/test.sh runs); the FMU under test (build/) is built against Debian's
6.4.1 (CVODE). The paper's Fig. 4b, the chaotic bouncing Johnson run, with CVODE BDF and Adams at rtol
1e-11 over the whole 0.1 s: the same motion (y within 1e-6 of its range, F within 1e-6 of its largest
value), the same mode changes at the same times (within 1 us) and the same impacts. The 7.9 binaries
need only libc and libm and export only the fmi* functions (SUNDIALS linked statically, hidden), and
each build's model description says which SUNDIALS its binaries carry, as the SUNDIALS it was built
against names itself (its sundials_config.h); its licence is the one in the FMU."""
import pathlib
import re
import subprocess
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description

from conftest import BUILD, FMU, ROOT
from vibroimpact.compare import EVENT_DT, Runner, read_trace

SUNDIALS7 = ROOT / "build" / "sundials7"
REL = 1e-6  # of the range of y, of the largest |F|
BDF, ADAMS = 1, 2


def sundials7_fmu(version=2):
    path = SUNDIALS7 / ("VibroImpact.fmu" if version == 2 else "fmi3/VibroImpact.fmu")
    if not path.is_file():
        pytest.fail(f"{path} is missing: build it with tools/sundials7.sh (tools/test.sh runs it)")
    return path


def cache_value(build, name):
    """A variable of a build's CMakeCache.txt."""
    m = re.search(rf"^{name}:[A-Z]+=(.*)$", (build / "CMakeCache.txt").read_text(), re.M)
    assert m, f"{build}/CMakeCache.txt has no {name}"
    return m.group(1)


def sundials_of(build):
    """(version, its include folder) of the SUNDIALS a build took: the sundials_config.h above the
    CMake package it found (<prefix>/lib*/cmake/sundials, Debian's /usr/lib/<triplet>/cmake/sundials)."""
    package = pathlib.Path(cache_value(build, "SUNDIALS_DIR"))
    for prefix in package.parents[2], package.parents[3]:
        config = prefix / "include" / "sundials" / "sundials_config.h"
        if config.is_file():
            version = re.search(r'#define SUNDIALS_VERSION "([^"]+)"', config.read_text()).group(1)
            return version, prefix / "include"
    pytest.fail(f"no include/sundials/sundials_config.h above {package}")


@pytest.fixture(scope="module")
def runs():
    """(solver, build) -> Fig. 4b on the reference's grid: ({output: samples}, [mode changes])."""
    if sundials_of(BUILD)[0].split(".")[:2] != ["6", "4"]:
        pytest.fail(f"{FMU} is not built against SUNDIALS 6.4: this test compares build/sundials7 with it")
    t, runners = read_trace("fig4b")["time"], {6: Runner(FMU), 7: Runner(sundials7_fmu())}
    return {(solver, v): runners[v].run("fig4b", t, solver=solver) for solver in (BDF, ADAMS) for v in (6, 7)}


@pytest.mark.parametrize("solver", [BDF, ADAMS], ids=["bdf", "adams"])
def test_fig4b_on_sundials_7_9_is_the_run_on_6_4(runs, solver):
    (old, old_events), (new, new_events) = runs[solver, 6], runs[solver, 7]
    span = old["y"].max() - old["y"].min()
    dy = np.abs(new["y"] - old["y"]).max() / span
    dF = np.abs(new["F"] - old["F"]).max() / np.abs(old["F"]).max()
    print(f"fig4b, solver {solver}: max |y7.9 - y6.4| = {dy:.3g} of the range of y, max |F7.9 - F6.4| = {dF:.3g} "
          f"of max |F|, bit for bit: {np.array_equal(new['y'], old['y']) and np.array_equal(new['F'], old['F'])}")
    assert dy <= REL and dF <= REL
    assert len(old_events) > 20 and [e[1:] for e in new_events] == [e[1:] for e in old_events]
    assert max(abs(a[0] - b[0]) for a, b in zip(new_events, old_events)) <= EVENT_DT
    assert new["n_impacts"][-1] == old["n_impacts"][-1] > 10


@pytest.mark.parametrize("version", [2, 3])
def test_the_7_9_binaries_need_only_libc_and_libm_and_export_only_fmi(version):
    sundials7_fmu(version)
    library = SUNDIALS7 / ("VibroImpact.so" if version == 2 else "fmi3/VibroImpact.so")
    dynamic = subprocess.run(["readelf", "-d", str(library)], check=True, capture_output=True, text=True).stdout
    assert sorted(re.findall(r"\(NEEDED\).*\[(.*)\]", dynamic)) == ["libc.so.6", "libm.so.6"]
    symbols = subprocess.run(["nm", "-D", "--defined-only", str(library)], check=True, capture_output=True,
                             text=True).stdout.split()[2::3]
    assert symbols and all(s.startswith(f"fmi{version}") for s in symbols), symbols


@pytest.mark.parametrize("version", [2, 3])
def test_each_build_says_which_sundials_its_binaries_carry(version):
    builds = {BUILD: (FMU if version == 2 else BUILD / "fmi3" / FMU.name, "CVODE"),
              SUNDIALS7: (sundials7_fmu(version), "CVODES")}
    for build, (fmu, integrator) in builds.items():
        sundials, include = sundials_of(build)
        tool = read_model_description(str(fmu)).generationTool
        assert f"with SUNDIALS {sundials} {integrator} linked statically" in tool, (fmu, tool)
    # the licence of 7.9 in the FMU: its LICENSE and NOTICE (Debian's copyright file: fmu-test/test_release.py)
    include = sundials_of(SUNDIALS7)[1] / "sundials"
    with zipfile.ZipFile(sundials7_fmu(version)) as z:
        carried = z.read("documentation/licenses/SUNDIALS.txt").decode("utf-8")
    assert carried == (include / "LICENSE").read_text() + "\n" + (include / "NOTICE").read_text()
    assert "Redistributions in binary form must reproduce" in carried and "DE-AC52-07NA27344" in carried
