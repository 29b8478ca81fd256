"""The independent reference: a second implementation of the model in Python (SciPy), written from
doc/model.md and the paper, not from the C code, and what the FMU is compared with.

model          the hybrid model with event location (simulate)
two_sided      a mass between the platform and a second surface at yC + gap (simulate)
profile        the rolling constraint yb of a profile table, from its definition
closed_forms   effective properties, yield limit, Johnson's curves, plastic work
laws           damped Hertz, linear spring-dashpot, Thornton: forces, restitutions, closed forms
scenarios      the paper's scenarios: the one table every run and figure uses
generate       the committed reference traces (data/) and each scenario's predictable horizon
"""
