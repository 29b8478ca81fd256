/*
 * vehicle_variables.h - the variables of the Vehicle FMU (vehicle-track example): one row per FMU
 * variable, value reference = row number (see include/vi_table.h). modelDescription.xml mirrors
 * it; fmu-test/test_vehicle_track.py fails when the two disagree. Parameter values and their
 * sources: examples/vehicle-track/parameters.py.
 */
#ifndef VEHICLE_VARIABLES_H
#define VEHICLE_VARIABLES_H

#include "vi_solver.h" /* VI_RTOL_MIN, VI_RTOL_MAX, VI_MAX_STEP_MIN */
#include "vi_table.h"

#define VI_GUID "{b6ec21ce-4df2-4930-9fdf-88f4cb1b9483}"
#define VI_MODEL_IDENTIFIER "Vehicle"

#define VI_VARIABLES(X) \
  X(y_wheel, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "m", "wheel position, up positive (connect the contact FMU's y)") \
  X(v_wheel, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "m/s", "wheel velocity, up positive (connect the contact FMU's v); from the time it is set the wheel is taken to move at this velocity") \
  X(m_body, Real, none, parameter, fixed, exact, 5750.0, VI_ABOVE(0.0), VI_NONE, "kg", "sprung mass above one wheel: a quarter of a 3 t bogie frame and an eighth of a 40 t car body") \
  X(k_susp, Real, none, parameter, fixed, exact, 800000.0, VI_ABOVE(0.0), VI_NONE, "N/m", "primary suspension stiffness at one wheel") \
  X(c_susp, Real, none, parameter, fixed, exact, 20000.0, VI_AT(0.0), VI_NONE, "N.s/m", "primary suspension damping at one wheel") \
  X(g, Real, none, parameter, fixed, exact, 9.81, VI_AT(0.0), VI_NONE, "m/s2", "gravity") \
  X(rtol, Real, none, parameter, fixed, exact, 1e-8, VI_AT(VI_RTOL_MIN), VI_AT(VI_RTOL_MAX), "", "relative tolerance of the integrator (a tolerance from fmi2SetupExperiment wins)") \
  X(F_wheel, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "N", "force of the primary suspension on the wheel, up positive, static load -m_body g included (connect to the contact FMU's F_ext)") \
  X(z_body, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", "sprung mass position, up positive, measured so that z_body = y_wheel when the spring carries the static load") \
  X(v_body, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", "sprung mass velocity, up positive") \
  X(E, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", "stored energy: kinetic energy of the sprung mass, elastic energy of the spring about its static load, and the potential m_body g y_wheel") \
  X(W_dissipated, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", "work dissipated in the suspension damper so far") \
  X(W_in, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", "work done on the vehicle by the wheel motion so far: integral of -F_wheel v_wheel dt") \
  X(f_body, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "Hz", "undamped natural frequency of the sprung mass on the suspension, wheel held") \
  X(der_z_body, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", "Model Exchange: the time derivative of the state z_body") \
  X(der_v_body, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s2", "Model Exchange: the time derivative of the state v_body") \
  X(der_W_dissipated, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "W", "Model Exchange: the time derivative of the state W_dissipated")

#define VI_ENUMERATIONS(E)

VI_TABLE_DECLARE

#endif
