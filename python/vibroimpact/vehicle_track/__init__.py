"""The vehicle-track example (examples/vehicle-track): a wheel on a rough rail, the contact FMU as the
wheel-rail contact between a vehicle FMU and a track FMU (build/Vehicle.fmu, build/Track.fmu, built
from the example's folder).

  parameters   the wheel, the roughness, the run's length; the companion FMUs' start values
  roughness    the rail roughness profile (ISO 3095:2013 limit, raised, seeded)
  master       the co-simulation master on fmpy's FMU2Slave (Gauss-Seidel or Jacobi)
  me_master    the three FMUs as Model Exchange, integrated together by one solver

The example's scripts (study.py, master.py, me_master.py, ...) run them against its monolithic
reference.
"""
