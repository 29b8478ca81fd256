"""The vehicle-track example's wheel, roughness and run length (examples/vehicle-track/parameters.py
gives the sources, and the track's and vehicle's values, which are their FMUs' start values).

Wheel-rail contact: Hertz, steel on steel, a 920 mm wheel (R1 = 0.46 m) on a rail head flat along the
track (R2 = 0): K = 4/3 E* sqrt(R1) = 1.04e11 N/m^1.5.
"""
GRAVITY = 9.81  # m/s^2, the vehicle FMU's g

# The contact FMU (build/VibroImpact.fmu) as the wheel-rail contact: its mass is the wheel.
WHEEL = {
    "m": 1000.0,          # kg, half a 2 t wheelset
    "P": 0.0,             # N: the load comes from the vehicle FMU through F_ext, and gravity
    "g": GRAVITY,
    "R1": 0.46, "R2": 0.0,
    "E1": 2.1e11, "E2": 2.1e11, "nu1": 0.3, "nu2": 0.3,
    "contact_model": 1,   # hertz
    "init": 1,            # static
    "V": 30.0,            # m/s rolling speed (108 km/h)
    "x0": 0.6,            # m: start on the flat first metre of the profile
}

# The roughness profile (roughness.py): ISO 3095 limit + 15 dB, seeded.
ROUGHNESS = {"level_db": 15.0, "seed": 1, "length": 6.0, "dx": 1e-3}

STOP_TIME = 0.15  # s: 4.5 m of rail at 30 m/s

COMPANIONS = ("Track.fmu", "Vehicle.fmu")  # built beside VibroImpact.fmu from examples/vehicle-track


def companion_fmus(build):
    """The companion FMUs in the folder `build`; FileNotFoundError naming how to build them when one is
    missing (an installed package has none: they come from a development checkout's build)."""
    import pathlib
    paths = [pathlib.Path(build) / name for name in COMPANIONS]
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        raise FileNotFoundError(f"{', '.join(missing)} missing: the vehicle-track example's FMUs are built from a "
                                "checkout (cmake -S . -B build && cmake --build build), beside build/VibroImpact.fmu")
    return paths


def start_values(md):
    """The Real parameters' start values of a model description read by fmpy, by name."""
    return {v.name: float(v.start) for v in md.modelVariables
            if v.causality == "parameter" and v.type == "Real" and v.start is not None}
