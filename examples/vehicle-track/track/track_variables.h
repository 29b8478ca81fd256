/*
 * track_variables.h - the variables of the Track FMU (vehicle-track example): one row per FMU
 * variable, value reference = row number (see src/fmi/vi_table.h). modelDescription.xml mirrors
 * it; fmu-test/test_vehicle_track.py fails when the two disagree. Parameter values and their
 * sources: examples/vehicle-track/parameters.py.
 */
#ifndef TRACK_VARIABLES_H
#define TRACK_VARIABLES_H

#include "vi_solver.h" /* VI_RTOL_MIN, VI_RTOL_MAX, VI_RTOL_DEFAULT, VI_MAX_STEP_MIN */
#include "vi_table.h"

#define VI_GUID "{bd12441e-8795-46b4-b963-d52197ebec94}"
#define VI_MODEL_IDENTIFIER "Track"
#define VI_MODEL_DESCRIPTION "Discretely supported rail, lumped at one support: rail mass on pad stiffness and damping, sleeper mass on ballast stiffness and damping; loaded by the wheel-rail contact force"
#define VI_DEFAULT_EXPERIMENT {.start_s = 0.0, .stop_s = 0.1, .tolerance = VI_RTOL_DEFAULT, .step_s = 1e-5}
#define VI_CAN_INTERPOLATE_INPUTS 0

#define VI_VARIABLES(X) \
  X(F_contact, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "N", 0, "", "wheel-rail contact force on the wheel, up positive (connect the contact FMU's F_mean); the rail receives -F_contact, held over each step") \
  X(m_rail, Real, none, parameter, fixed, exact, 33.0, VI_ABOVE(0.0), VI_NONE, "kg", 0, "", "rail mass of one support: UIC60 rail, 60.0 kg/m over a 0.55 m sleeper spacing") \
  X(k_pad, Real, none, parameter, fixed, exact, 225000000.0, VI_ABOVE(0.0), VI_NONE, "N/m", 0, "", "rail pad stiffness") \
  X(c_pad, Real, none, parameter, fixed, exact, 21542.0, VI_AT(0.0), VI_NONE, "N.s/m", 0, "", "rail pad damping (loss factor 0.25 at the rail-on-pad frequency)") \
  X(m_sleeper, Real, none, parameter, fixed, exact, 170.0, VI_ABOVE(0.0), VI_NONE, "kg", 0, "", "mass of half a sleeper") \
  X(k_ballast, Real, none, parameter, fixed, exact, 20000000.0, VI_ABOVE(0.0), VI_NONE, "N/m", 0, "", "ballast stiffness under half a sleeper") \
  X(c_ballast, Real, none, parameter, fixed, exact, 58310.0, VI_AT(0.0), VI_NONE, "N.s/m", 0, "", "ballast damping (loss factor 1 at the sleeper-on-ballast frequency)") \
  X(rtol, Real, none, parameter, fixed, exact, 0.0, VI_AT(0.0), VI_AT(VI_RTOL_MAX), "", 0, "", "relative tolerance: 0 = the experiment's tolerance (fmi2SetupExperiment, fmi3EnterInitializationMode), " VI_STRING_OF(VI_RTOL_DEFAULT) " without one; else at least " VI_STRING_OF(VI_RTOL_MIN) ", used whatever the experiment's") \
  X(z_rail, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "z_rail", "rail displacement, up positive (connect to the contact FMU's yC_in)") \
  X(v_rail, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", 0, "v_rail", "rail velocity, up positive") \
  X(z_sleeper, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "z_sleeper", "sleeper displacement, up positive") \
  X(v_sleeper, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", 0, "v_sleeper", "sleeper velocity, up positive") \
  X(E, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "z_rail v_rail z_sleeper v_sleeper", "stored energy: kinetic energy of rail and sleeper and elastic energy of pad and ballast") \
  X(W_dissipated, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "z_rail v_rail z_sleeper v_sleeper", "work dissipated in the pad and ballast dampers so far") \
  X(W_in, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "", "work done on the rail by the input force so far: integral of -F_contact v_rail dt") \
  X(k_static, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "N/m", 0, "", "static stiffness at the rail, 1/(1/k_pad + 1/k_ballast)") \
  X(f1, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "Hz", 0, "", "lower undamped natural frequency of the track (rail and sleeper in phase)") \
  X(f2, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "Hz", 0, "", "upper undamped natural frequency of the track (rail against sleeper)") \
  X(der_z_rail, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", 0, "v_rail", "Model Exchange: the time derivative of the state z_rail") \
  X(der_v_rail, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s2", 0, "F_contact z_rail v_rail z_sleeper v_sleeper", "Model Exchange: the time derivative of the state v_rail") \
  X(der_z_sleeper, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", 0, "v_sleeper", "Model Exchange: the time derivative of the state z_sleeper") \
  X(der_v_sleeper, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s2", 0, "z_rail v_rail z_sleeper v_sleeper", "Model Exchange: the time derivative of the state v_sleeper")

#define VI_ENUMERATIONS(E)

VI_TABLE_DECLARE

#endif
