"""The vehicle-track example on libcosim (libcosimpy), from OspSystemStructure.xml.

libcosim's fixed-step algorithm steps every FMU with the outputs of the last communication point
(a Jacobi scheme); master.py with scheme="jacobi" does the same and gives the same numbers (the
test compares them). The file connects the rail velocity to the contact FMU's vC_in with
velocity_input = true (master.py's rail_motion "ramp": libcosim sets no input derivatives);
rail_motion="hold" renders it without (the rail held over each step). run() renders a copy of
OspSystemStructure.xml for one run (the step, the FMUs of a build folder, the profile as an
absolute path, F or F_mean to the track, the rail motion), loads it with
CosimExecution.from_osp_config_file, steps it and records the same signals as master.run.
"""
import pathlib
import tempfile
import xml.etree.ElementTree as ET

import numpy as np

import master
import parameters

HERE = pathlib.Path(__file__).resolve().parent
OSP = HERE / "OspSystemStructure.xml"
NS = "http://opensimulationplatform.com/MSMI/OSPSystemStructure"
RECORD = {"contact": master.CONTACT_OUT, "track": master.TRACK_OUT, "vehicle": master.VEHICLE_OUT}


def _q(tag):
    return f"{{{NS}}}{tag}"


def render(path, step, build, profile=None, excitation=None, force="F_mean", rail_motion="ramp"):
    """Write the system structure of one run to `path`. rail_motion: "ramp" (the file's: vC_in
    connected, velocity_input = true) or "hold" (neither)."""
    if rail_motion not in ("ramp", "hold"):
        raise ValueError(f"rail_motion = {rail_motion!r}: libcosim runs 'ramp' or 'hold'")
    ET.register_namespace("", NS)
    tree = ET.parse(OSP)
    root = tree.getroot()
    root.find(_q("BaseStepSize")).text = repr(float(step))
    names = {"contact": "VibroImpact.fmu", "track": "Track.fmu", "vehicle": "Vehicle.fmu"}
    for sim in root.iter(_q("Simulator")):
        sim.set("source", str(pathlib.Path(build).resolve() / names[sim.get("name")]))
        if sim.get("name") != "contact":
            continue
        iv = sim.find(_q("InitialValues"))
        for v in list(iv):
            name = v.get("variable")
            if name == "profile_file" and profile:
                v.find(_q("String")).set("value", str(pathlib.Path(profile).resolve()))
            elif name in ("profile_file", "V", "x0") and not profile:
                iv.remove(v)
            elif name == "velocity_input" and rail_motion == "hold":
                v.find(_q("Boolean")).set("value", "false")
        if excitation:
            for name, value in zip(("a", "f"), excitation):
                e = ET.SubElement(iv, _q("InitialValue"), variable=name)
                ET.SubElement(e, _q("Real"), value=repr(float(value)))
    connections = root.find(_q("Connections"))
    for con in list(connections):
        src, dst = con.findall(_q("Variable"))
        if src.get("simulator") == "contact" and src.get("name") == "F_mean":
            src.set("name", force)
        if dst.get("name") == "vC_in" and rail_motion == "hold":
            connections.remove(con)
    tree.write(path, xml_declaration=True, encoding="UTF-8")


def quiet():
    """libcosim logs every warning to the console; keep errors only."""
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    log_output_level(CosimLogLevel.ERROR)


def run(step, stop_time=parameters.STOP_TIME, force="F_mean", profile=None, excitation=None, build=None,
        rail_motion="ramp"):
    """Co-simulate on libcosim; the same record as master.run (without the energy bookkeeping)."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    quiet()
    build = pathlib.Path(build or master.build_dir())
    n_steps = int(round(stop_time / step))
    with tempfile.TemporaryDirectory(prefix="vt_osp_") as d:
        path = pathlib.Path(d) / "OspSystemStructure.xml"
        render(path, step, build, profile, excitation, force, rail_motion)
        ex = CosimExecution.from_osp_config_file(str(path))
        obs = CosimObserver.create_last_value()
        ex.add_observer(obs)
        idx, refs = {}, {}
        for name, signals in RECORD.items():
            i = ex.slave_index_from_instance_name(name)
            by_name = {v.name.decode(): v.reference for v in ex.slave_variables(i)}
            idx[name] = i
            refs[name] = [(s, by_name[s]) for s in signals if s in by_name]
        rec = {f"{n}.{s}": np.empty(n_steps + 1) for n in RECORD for s, _ in refs[n]}

        def record(k):
            for name in RECORD:
                values = obs.last_real_values(idx[name], [r for _, r in refs[name]])
                for (s, _), val in zip(refs[name], values):
                    rec[f"{name}.{s}"][k] = val

        # libcosim initializes (initial values, then outputs passed along the connections in
        # initialization mode) on the first step; the record starts after it
        ex.step(1)
        record(1)
        for k in range(2, n_steps + 1):  # bounded
            ex.step(1)
            record(k)
        rec["t"] = np.arange(n_steps + 1) * step
        for key in rec:
            if key != "t":
                rec[key][0] = np.nan  # the initial values are not observed
    return rec
