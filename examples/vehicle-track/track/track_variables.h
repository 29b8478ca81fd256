/*
 * track_variables.h - the variables of the Track FMU (vehicle-track example): one row per FMU
 * variable, value reference = row number (see include/vi_table.h). modelDescription.xml mirrors
 * it; fmu-test/test_vehicle_track.py fails when the two disagree. Parameter values and their
 * sources: examples/vehicle-track/parameters.py.
 */
#ifndef TRACK_VARIABLES_H
#define TRACK_VARIABLES_H

#include "vi_solver.h" /* VI_RTOL_MIN, VI_RTOL_MAX, VI_MAX_STEP_MIN */
#include "vi_table.h"

#define VI_GUID "{bd12441e-8795-46b4-b963-d52197ebec94}"
#define VI_MODEL_IDENTIFIER "Track"

#define VI_VARIABLES(X) \
  X(F_contact, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "N", "wheel-rail contact force on the wheel, up positive (connect the contact FMU's F_mean); the rail receives -F_contact, held over each step") \
  X(m_rail, Real, none, parameter, fixed, exact, 33.0, VI_ABOVE(0.0), VI_NONE, "kg", "rail mass of one support: UIC60 rail, 60.0 kg/m over a 0.55 m sleeper spacing") \
  X(k_pad, Real, none, parameter, fixed, exact, 225000000.0, VI_ABOVE(0.0), VI_NONE, "N/m", "rail pad stiffness") \
  X(c_pad, Real, none, parameter, fixed, exact, 21542.0, VI_AT(0.0), VI_NONE, "N.s/m", "rail pad damping (loss factor 0.25 at the rail-on-pad frequency)") \
  X(m_sleeper, Real, none, parameter, fixed, exact, 170.0, VI_ABOVE(0.0), VI_NONE, "kg", "mass of half a sleeper") \
  X(k_ballast, Real, none, parameter, fixed, exact, 20000000.0, VI_ABOVE(0.0), VI_NONE, "N/m", "ballast stiffness under half a sleeper") \
  X(c_ballast, Real, none, parameter, fixed, exact, 58310.0, VI_AT(0.0), VI_NONE, "N.s/m", "ballast damping (loss factor 1 at the sleeper-on-ballast frequency)") \
  X(rtol, Real, none, parameter, fixed, exact, 1e-8, VI_AT(VI_RTOL_MIN), VI_AT(VI_RTOL_MAX), "", "relative tolerance of the integrator (a tolerance from fmi2SetupExperiment wins)") \
  X(z_rail, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", "rail displacement, up positive (connect to the contact FMU's yC_in)") \
  X(v_rail, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", "rail velocity, up positive") \
  X(z_sleeper, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", "sleeper displacement, up positive") \
  X(v_sleeper, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", "sleeper velocity, up positive") \
  X(E, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", "stored energy: kinetic energy of rail and sleeper and elastic energy of pad and ballast") \
  X(W_dissipated, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", "work dissipated in the pad and ballast dampers so far") \
  X(W_in, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", "work done on the rail by the input force so far: integral of -F_contact v_rail dt") \
  X(k_static, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "N/m", "static stiffness at the rail, 1/(1/k_pad + 1/k_ballast)") \
  X(f1, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "Hz", "lower undamped natural frequency of the track (rail and sleeper in phase)") \
  X(f2, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "Hz", "upper undamped natural frequency of the track (rail against sleeper)") \
  X(der_z_rail, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", "Model Exchange: the time derivative of the state z_rail") \
  X(der_v_rail, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s2", "Model Exchange: the time derivative of the state v_rail") \
  X(der_z_sleeper, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", "Model Exchange: the time derivative of the state z_sleeper") \
  X(der_v_sleeper, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s2", "Model Exchange: the time derivative of the state v_sleeper")

#define VI_ENUMERATIONS(E)

VI_TABLE_DECLARE

#endif
