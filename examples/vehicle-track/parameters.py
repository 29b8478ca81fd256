"""The vehicle-track example's parameters, in one place.

The track's and the vehicle's values are the start values of their FMUs (track/ and vehicle/
modelDescription.xml, generated from their C variable tables); they are read from there, so the
reference, the masters and the FMUs cannot disagree. Sources:

- Track, one support of a ballasted track (Math. Probl. Eng. 2017, article 5872419, "Study on
  transmission characteristics of vertical rail vibrations in ballast track", Table 1): UIC60 rail
  (7.745e-3 m^2, 7750 kg/m^3: 60.0 kg/m) on supports 0.55 m apart, rail pad 225 kN/mm with loss
  factor 0.25, half sleeper 170 kg, ballast 20 kN/mm per half sleeper with loss factor 1. The
  rail mass of one support is 60.0 kg/m * 0.55 m = 33 kg. The loss factors become viscous dampers
  at each layer's own frequency, c = eta * sqrt(k m): pad 21.5 kN s/m, ballast 58.3 kN s/m.
  One support carries the whole wheel load here: the rail beam, which spreads the load over a few
  sleepers, is not modelled, so the track is softer than a real one at low frequencies.
- Vehicle (Shock Vib. 2019, article 1212069, "A two-step composite time integration scheme for
  vehicle-track interaction analysis considering contact separation", Table 2): car body 40 t,
  bogie frame 3 t, wheelset 2 t, primary suspension 800 kN/m and 20 kN s/m per side. Per wheel:
  unsprung mass 1000 kg (half a wheelset), sprung mass 40000/8 + 3000/4 = 5750 kg on the primary
  suspension (the secondary suspension is not modelled).
- Wheel-rail contact: Hertz, steel on steel, a 920 mm wheel (R1 = 0.46 m) on a rail head flat
  along the track (R2 = 0): K = 4/3 E* sqrt(R1) = 1.04e11 N/m^1.5, within 10 % of the elliptic
  wheel-rail contact constants of 0.87e11 to 0.96e11 N/m^1.5 quoted for a 0.46 m wheel on a
  0.3 m rail crown.
"""
import pathlib
import xml.etree.ElementTree as ET

from vibroimpact.vehicle_track import parameters as P

HERE = pathlib.Path(__file__).resolve().parent


def fmu_defaults(folder):
    """Start values of the parameters in <folder>/modelDescription.xml, by name."""
    root = ET.parse(HERE / folder / "modelDescription.xml").getroot()
    out = {}
    for sv in root.iter("ScalarVariable"):
        if sv.get("causality") == "parameter":
            out[sv.get("name")] = float(sv.find("Real").get("start"))
    return out


TRACK = fmu_defaults("track")
VEHICLE = fmu_defaults("vehicle")

# The wheel (the contact FMU's mass), the roughness and the run's length: the vibroimpact package's, which
# runs the example's masters (vibroimpact.vehicle_track).
WHEEL, ROUGHNESS, STOP_TIME = P.WHEEL, P.ROUGHNESS, P.STOP_TIME
