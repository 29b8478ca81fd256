"""The FMU does the same in every locale of the importer's process.

An importer may run with LC_NUMERIC set (a German modelling tool: de_DE, decimal point ','). Each run
here is a subprocess (this file run as a program) that sets its locale with
locale.setlocale(locale.LC_ALL, ...) before it loads the FMU, then runs the profile tests' cases
(numbers of every form in profile files, refused files with what their lines hold, a byte-order mark,
a wall too steep for doubles, the ends of a table), values out of their
ranges, and two paper scenarios (Fig. 5a in contact, Fig. 5c with impacts, its events logged), printing every output value as a hexadecimal float and every message the FMU logged. The
run in de_DE.UTF-8 must print exactly what the run in the C locale prints: the same results to the
bit and the same messages, with '.' as the decimal point.
"""
import json
import locale
import pathlib
import subprocess
import sys

import pytest

GERMAN = "de_DE.UTF-8"
MISSING = (f"the locale {GERMAN} is missing: install Debian's package locales and generate it with "
           "localedef -i de_DE -f UTF-8 de_DE.UTF-8 (tools/setup.sh does both)")

# Profile files: numbers of every form the reader takes (more than 19 digits, exponents beyond +-27,
# 1.5e-30, hexadecimal, signs, "5." and ".5", separators) and what it refuses.
PROFILES = {
    "forms": "# x [m]  h [m]\n0 1.5e-30\n0.012345678901234567890123\t2.5e-5\n0x1.999999999999ap-4; -1.5E-6\n"
             "+.25 0.000000000000000000000000000000000000000000001e40\n0.5 3e-5\n1. 0\n",
    "decreasing": "0 0\n1 0\n0.5 0\n",
    "nan": "0 0\n1 nan\n",
    "one_row": "0 0\n",
    "letters": "0 0\n1 x\n",
    "step": "0 0\n0.1 0\n0.1000001 0.6\n0.2 0.6\n",
    "decimal_commas": "0,5\n1,5\n2,5\n",
    "header": "x h\n0 0\n1 0\n",
    "bom": "\ufeff# x h\n0 0\n0.5 1e-5\n1 0\n",
}
# the periodic wall too steep for doubles at R1 = 1.217226034797203e-06 m (its message prints numbers)
STEEP = "-0.46331928351137353 3.3603288399901734\n16.478735101136888 2.1854535280021321\n16.478783788505101 3.3603288399901734\n"


def run_profile(slave_of, tmp, name, params, steps, h):
    """Messages and yC at each step of a rolling run over profile `name` (refusals end it)."""
    path = tmp / f"{name}.txt"
    path.write_text(PROFILES[name] if name in PROFILES else STEEP, encoding="utf-8")
    inst, slave, vr = slave_of()
    values = []
    try:
        from vibroimpact.fmu import initialize
        initialize(slave, vr, {"profile_file": str(path), **params})
        for k in range(steps):
            slave.doStep(k * h, h)
            values.append(slave.getReal([vr["yC"]])[0].hex())
    except Exception as e:  # a refusal: its message is in the log
        values.append(type(e).__name__)
    return {"values": values, "messages": [m.replace(str(tmp), "<tmp>") for m in inst.texts()]}


def run_scenario(slave_of, name, steps, h):
    """Messages (events included) and the outputs at each step of a paper scenario."""
    from vibroimpact.fmu import initialize
    from vibroimpact.reference.scenarios import SCENARIOS
    inst, slave, vr = slave_of(["logEvents", "logStatusWarning", "logStatusDiscard", "logStatusError"])
    initialize(slave, vr, SCENARIOS[name].full, tolerance=1e-8, stop_time=steps * h)
    names = ["y", "v", "F", "delta", "W_plastic"]
    values = []
    for k in range(steps):
        slave.doStep(k * h, h)
        values.append([x.hex() for x in slave.getReal([vr[n] for n in names])])
    return {"values": values, "messages": inst.texts()}


def run_out_of_range(slave_of):
    """The messages of values outside their ranges (the value and the range printed), each set in an
    instance of its own."""
    messages = []
    for name, value in (("nu1", 0.75), ("m", -0.5), ("f", -2.5e-7), ("rtol", 0.025)):
        inst, slave, vr = slave_of()
        try:
            slave.setReal([vr[name]], [value])
        except Exception:  # the refusal: its message is in the log
            pass
        messages += inst.texts()
    return {"values": [], "messages": messages}


def worker(locale_name, fmu, tmp):
    """Runs every case in locale_name (set before the FMU is loaded); prints the results as JSON."""
    try:
        locale.setlocale(locale.LC_ALL, locale_name)
    except locale.Error:
        sys.exit(MISSING)
    from fmpy import extract, read_model_description

    from vibroimpact.fmu import Logged
    md = read_model_description(fmu)
    unzipdir = extract(fmu, unzipdir=str(tmp / "fmu"))
    vr = {v.name: v.valueReference for v in md.modelVariables}

    def slave_of(categories=("logStatusWarning", "logStatusDiscard", "logStatusError")):
        inst = Logged(md, unzipdir)
        slave = inst.instantiate(logging=True)
        slave.setDebugLogging(True, list(categories))
        return inst, slave, vr

    rolling = dict(V=1.0, x0=0.0, contact_model=1)
    out = {name: run_profile(slave_of, tmp, name, rolling, 20, 0.045) for name in PROFILES}
    out["x0_outside"] = run_profile(slave_of, tmp, "forms", dict(rolling, x0=1.5), 1, 0.1)
    out["steep"] = run_profile(slave_of, tmp, "steep", dict(rolling, R1=1.217226034797203e-06, profile_periodic=True),
                               1, 0.1)
    out["fig5a"] = run_scenario(slave_of, "fig5a", 100, 1e-3)
    out["fig5c"] = run_scenario(slave_of, "fig5c", 100, 1e-3)
    out["out_of_range"] = run_out_of_range(slave_of)
    print(json.dumps(out))


def run_in(locale_name, fmu_path, tmp):
    r = subprocess.run([sys.executable, __file__, locale_name, fmu_path, str(tmp)], capture_output=True, text=True,
                       timeout=240)
    assert r.returncode == 0, f"the run in {locale_name} failed:\n{r.stderr[-3000:]}"
    return json.loads(r.stdout)


@pytest.mark.timeout(600)
def test_the_fmu_does_the_same_in_de_DE_as_in_the_c_locale(fmu_path, tmp_path):
    (tmp_path / "c").mkdir()
    (tmp_path / "de").mkdir()
    c = run_in("C", fmu_path, tmp_path / "c")
    de = run_in(GERMAN, fmu_path, tmp_path / "de")
    # the cases do what they are for: numbers with a decimal point in the messages, values read
    text = "\n".join(m for case in c.values() for m in case["messages"])
    for expect in ("line 3: x = 0.5 is not greater than x = 1 on line 2", "found 1 field '0,5' (separator: none)",
                   "'x' is not a number (a header? start it with #)", "make a slope of 24131, too steep for R1 = 1.21723e-06 m", "nu1 = 0.75 is outside its range",
                   "x0 = 1.5 m lies outside the profile", "m = -0.5 is outside its range", "f = -2.5e-07", "rtol = 0.025"):
        assert expect in text, text
    assert len(c["forms"]["values"]) == 20 and c["forms"]["values"][0] != "FMICallException", c["forms"]
    assert len(c["bom"]["values"]) == 20 and c["bom"]["values"][0] != "FMICallException", c["bom"]
    assert any("kind=start mode=1 delta=5.56347498e-05 " in m for m in c["fig5a"]["messages"]), c["fig5a"]["messages"]
    assert sum(m.startswith("event t=0.0") for m in c["fig5c"]["messages"]) > 10, c["fig5c"]["messages"]
    differ = {case: next(([a, b] for a, b in zip(de[case]["messages"], c[case]["messages"]) if a != b),
                         "the values or the count of messages")
              for case in c if de[case] != c[case]}
    assert not differ, differ


if __name__ == "__main__":
    worker(sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3]))
