/*
 * vehicle_variables.h - the variables of the Vehicle FMU (vehicle-track example): one row per FMU
 * variable, value reference = row number (see src/fmi/vi_table.h). modelDescription.xml mirrors
 * it; fmu-test/test_vehicle_track.py fails when the two disagree. Parameter values and their
 * sources: examples/vehicle-track/parameters.py.
 */
#ifndef VEHICLE_VARIABLES_H
#define VEHICLE_VARIABLES_H

#include "vi_solver.h" /* VI_RTOL_MIN, VI_RTOL_MAX, VI_RTOL_DEFAULT, VI_MAX_STEP_MIN */
#include "vi_table.h"

#define VI_GUID "{b6ec21ce-4df2-4930-9fdf-88f4cb1b9483}"
#define VI_MODEL_IDENTIFIER "Vehicle"
#define VI_MODEL_DESCRIPTION "Sprung mass on the primary suspension above one wheel; takes the wheel's position and velocity, gives the suspension force on the wheel"
#define VI_DEFAULT_EXPERIMENT {.start_s = 0.0, .stop_s = 0.1, .tolerance = VI_RTOL_DEFAULT, .step_s = 1e-5}
#define VI_CAN_INTERPOLATE_INPUTS 0

#define VI_VARIABLES(X) \
  X(y_wheel, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "m", 0, "", "wheel position, up positive (connect the contact FMU's y)") \
  X(v_wheel, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "m/s", 0, "", "wheel velocity, up positive (connect the contact FMU's v); from the time it is set the wheel is taken to move at this velocity") \
  X(m_body, Real, none, parameter, fixed, exact, 5750.0, VI_ABOVE(0.0), VI_NONE, "kg", 0, "", "sprung mass above one wheel: a quarter of a 3 t bogie frame and an eighth of a 40 t car body") \
  X(k_susp, Real, none, parameter, fixed, exact, 800000.0, VI_ABOVE(0.0), VI_NONE, "N/m", 0, "", "primary suspension stiffness at one wheel") \
  X(c_susp, Real, none, parameter, fixed, exact, 20000.0, VI_AT(0.0), VI_NONE, "N.s/m", 0, "", "primary suspension damping at one wheel") \
  X(g, Real, none, parameter, fixed, exact, 9.81, VI_AT(0.0), VI_NONE, "m/s2", 0, "", "gravity") \
  X(rtol, Real, none, parameter, fixed, exact, 0.0, VI_AT(0.0), VI_AT(VI_RTOL_MAX), "", 0, "", "relative tolerance: 0 = the experiment's tolerance (fmi2SetupExperiment, fmi3EnterInitializationMode), " VI_STRING_OF(VI_RTOL_DEFAULT) " without one; else at least " VI_STRING_OF(VI_RTOL_MIN) ", used whatever the experiment's") \
  X(F_wheel, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "N", 0, "y_wheel v_wheel z_body v_body", "force of the primary suspension on the wheel, up positive, static load -m_body g included (connect to the contact FMU's F_ext)") \
  X(z_body, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "z_body", "sprung mass position, up positive, measured so that z_body = y_wheel when the spring carries the static load") \
  X(v_body, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", 0, "v_body", "sprung mass velocity, up positive") \
  X(E, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "y_wheel z_body v_body", "stored energy: kinetic energy of the sprung mass, elastic energy of the spring about its static load, and the potential m_body g y_wheel") \
  X(W_dissipated, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "W_dissipated", "work dissipated in the suspension damper so far") \
  X(W_in, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "", "work done on the vehicle by the wheel motion so far: integral of -F_wheel v_wheel dt") \
  X(f_body, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "Hz", 0, "", "undamped natural frequency of the sprung mass on the suspension, wheel held") \
  X(der_z_body, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", 0, "v_body", "Model Exchange: the time derivative of the state z_body") \
  X(der_v_body, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s2", 0, "y_wheel v_wheel z_body v_body", "Model Exchange: the time derivative of the state v_body") \
  X(der_W_dissipated, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "W", 0, "v_wheel v_body", "Model Exchange: the time derivative of the state W_dissipated")

#define VI_ENUMERATIONS(E)

VI_TABLE_DECLARE

#endif
