"""The paper's scenarios (Kowalska 2002, Figs. 4-6; doc/model.md section 4): one table.

Every scenario starts in static equilibrium (init = static) at t = 0 and runs 0.1 s. Common to all:
R* = 0.475 m (R1 = 0.475, R2 = 0: sphere on a plane), steel E1 = E2 = 2.1e11 Pa, nu = 0.3,
P = 40 kN = 10 m g (m = P/(10 g) = 407.747 kg, g = 9.81), platform yC(t) = a (cos(2 pi f t) - 1)
with a = 0.1 mm and f = 560 Hz, textbook yield formula, theta_Y = 1.1.

What the paper leaves open, and what is chosen here:
- Fig. 5 (Hertz) names no frequencies, only "below", "close to" and "over" the contact resonance
  (267.19 Hz with g = 0; 271.5 Hz linearised at P + m g): 100 Hz, 267 Hz and 560 Hz.
- Fig. 6 (LEPP) names no yield stress: Y = 6e8 Pa as in Figs. 4b/c. P = 10, 12, 13 m g with m fixed.
- Fig. 6 at a = 0.1 mm cannot show the paper's description (the platform's acceleration, 1238 m/s^2,
  dwarfs what F_Y can give the mass, so every cycle flows plastically). The supplementary scenarios
  fig6a_30um ... run the same loads at a = 30 um, where the described behaviour appears.
"""
from dataclasses import dataclass, field

M = 407.747  # kg, P / (10 g)
G = 9.81     # m/s^2
STOP_TIME = 0.1  # s
COMMON = dict(m=M, P=40000.0, g=G, R1=0.475, R2=0.0, E1=2.1e11, E2=2.1e11, nu1=0.3, nu2=0.3,
              theta_Y=1.1, yield_formula=1, init=1, a=1e-4, f=560.0)
HERTZ, JOHNSON, LEPP = 1, 2, 3


@dataclass(frozen=True)
class Scenario:
    title: str            # what the figure shows
    paper: str            # the paper's caption / text for it
    params: dict          # start values beyond COMMON (FMU names, enumerations as integers)
    supplementary: bool = False
    full: dict = field(init=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "full", {**COMMON, **self.params})


SCENARIOS = {
    "fig4a": Scenario(
        "Fig. 4a: Johnson, fixed contact point, Y = 1e9 Pa",
        "yield stress Y = 1e9 N/m^2 is not exceeded; y(t) characteristic for frequencies much higher "
        "than the contact resonance",
        dict(contact_model=JOHNSON, Y=1e9)),
    "fig4b": Scenario(
        "Fig. 4b: Johnson, fixed contact point, Y = 6e8 Pa",
        "non-moving contact point, yield stress exceeded; the stiffer contact after the first plastic "
        "deformation starts high bouncing (typical at contact resonance)",
        dict(contact_model=JOHNSON, Y=6e8)),
    "fig4c": Scenario(
        "Fig. 4c: Johnson, moving contact point, Y = 6e8 Pa",
        "moving contact point, yield stress exceeded; only loading under the moving contact zone",
        dict(contact_model=JOHNSON, moving_contact=True, Y=6e8)),
    "fig5a": Scenario(
        "Fig. 5a: Hertz, f = 100 Hz (below the contact resonance)",
        "purely elastic; at low frequencies the bodies stay in contact",
        dict(contact_model=HERTZ, f=100.0)),
    "fig5b": Scenario(
        "Fig. 5b: Hertz, f = 267 Hz (close to the contact resonance)",
        "purely elastic; close to the contact resonance characteristic high bounces off the platform",
        dict(contact_model=HERTZ, f=267.0)),
    "fig5c": Scenario(
        "Fig. 5c: Hertz, f = 560 Hz (over the contact resonance)",
        "purely elastic; at high frequencies the mass moves less than the platform and the bodies lose "
        "and come into contact alternately",
        dict(contact_model=HERTZ, f=560.0)),
    "fig6a": Scenario(
        "Fig. 6a: LEPP, P = 10 m g",
        "F_Y exceeded only at the beginning of the oscillations, then the motion stabilises and the "
        "permanent deflection does not increase",
        dict(contact_model=LEPP, Y=6e8, P=10 * M * G)),
    "fig6b": Scenario(
        "Fig. 6b: LEPP, P = 12 m g",
        "with an increase in constant load the amplitude of oscillations decreases quickly with time, "
        "and the two bodies approach each other quickly",
        dict(contact_model=LEPP, Y=6e8, P=12 * M * G)),
    "fig6c": Scenario(
        "Fig. 6c: LEPP, P = 13 m g",
        "as 6b, faster",
        dict(contact_model=LEPP, Y=6e8, P=13 * M * G)),
}
for _k, _fig in ((10, "fig6a"), (12, "fig6b"), (13, "fig6c")):
    SCENARIOS[f"{_fig}_30um"] = Scenario(
        f"{SCENARIOS[_fig].title.split(':')[0]} at a = 30 um: LEPP, P = {_k} m g",
        SCENARIOS[_fig].paper,
        dict(SCENARIOS[_fig].params, a=3e-5), supplementary=True)

# Beyond the paper: the options its figures do not exercise, so that the FMU is checked against the
# reference on them too.
SCENARIOS["stick"] = Scenario(
    "Beyond the paper: stick (Johnson, paper unloading, Y = 2e8 Pa, f = 100 Hz)",
    "not in the paper: the Filippov sliding mode of doc/model.md section 3 (mass rides at delta = delta_c)",
    dict(contact_model=JOHNSON, Y=2e8, f=100.0), supplementary=True)
SCENARIOS["continuous"] = Scenario(
    "Beyond the paper: Johnson, continuous unloading, Y = 6e8 Pa",
    "not in the paper: unloading = continuous (force continuous at delta_c, passive)",
    dict(contact_model=JOHNSON, Y=6e8, unloading=2), supplementary=True)
SCENARIOS["printed"] = Scenario(
    "Beyond the paper: Johnson, printed yield formula (F_Y < P + m g: pre-loaded start)",
    "not in the paper's figures: eq. 5 as printed, without the factor pi; the static load already "
    "yields the material, so the mass starts on an unloading curve",
    dict(contact_model=JOHNSON, Y=6e8, yield_formula=2), supplementary=True)
