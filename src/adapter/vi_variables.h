/*
 * vi_variables.h - the one table of VibroImpact's FMU variables (the contact model).
 *
 * Every FMU variable is one row of VI_VARIABLES; the columns and what the compiler generates from
 * the rows (structs vi_parameters, vi_inputs, vi_outputs named field by field as the variables,
 * value references VI_VR_<name>, enumeration constants VI_<Type>_<item>, start values, and the
 * descriptor array vi_variable_table the FMI layer uses for get/set) are explained in vi_table.h.
 * The value reference of a variable is its row number: append new rows at the end, so that the
 * value references users already rely on stay valid.
 * Both model descriptions are generated from this table at build time (cmake/vi_model_description.py);
 * the top-level modelDescription.xml is the FMI 2.0 one as generated (fmu-test/test_interface.py).
 *
 * Enumerated options are Integer variables whose enum column names their items (VI_ITEMS_*):
 * libcosim ignores FMI 2.0 Enumeration variables, every importer sets Integers. The XML gives
 * them min/max of the item values and lists the items in the description as "name=value" pairs,
 * e.g. "contact law: hertz=1, johnson=2, lepp=3", so that tools can map names to values.
 */
#ifndef VI_VARIABLES_H
#define VI_VARIABLES_H

#include "vi_solver.h" /* VI_RTOL_MIN, VI_RTOL_MAX, VI_MAX_STEP_MIN */
#include "vi_table.h"

#define VI_GUID "{5b7e0c3a-2f1d-4e8b-9a61-7c4d2e9f1a03}"
#define VI_MODEL_IDENTIFIER "VibroImpact"
#define VI_MODEL_DESCRIPTION "Mass pressed onto a vibrating platform through a Hertz, Johnson elastic-plastic, linear elastic-perfectly plastic, Thornton elastic-perfectly plastic, damped Hertz or linear spring-dashpot contact; Co-Simulation (its own solvers with event location inside the step) and Model Exchange (states y, v; the guards of the mode as event indicators); optionally a second surface above the mass (upper_stop)"
#define VI_DEFAULT_EXPERIMENT {.start_s = 0.0, .stop_s = 0.1, .tolerance = 1e-6, .step_s = 1e-4}
#define VI_CAN_INTERPOLATE_INPUTS 1

#define VI_VARIABLES(X) \
  X(yC_in, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "m", 0, "", "platform displacement input (interpolated with its derivative when given)") \
  X(F_ext, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "N", 0, "", "external force on the mass, up positive") \
  X(m, Real, none, parameter, fixed, exact, 407.747, VI_ABOVE(0.0), VI_NONE, "kg", 0, "", "mass") \
  X(P, Real, none, parameter, fixed, exact, 40000.0, VI_NONE, VI_NONE, "N", 0, "", "constant pressing load") \
  X(g, Real, none, parameter, fixed, exact, 9.81, VI_NONE, VI_NONE, "m/s2", 0, "", "gravity (0 makes P the whole load)") \
  X(R1, Real, none, parameter, fixed, exact, 0.475, VI_AT(0.0), VI_NONE, "m", 0, "", "radius of body 1 (0 = plane)") \
  X(R2, Real, none, parameter, fixed, exact, 0.0, VI_AT(0.0), VI_NONE, "m", 0, "", "radius of body 2 (0 = plane)") \
  X(E1, Real, none, parameter, fixed, exact, 2.1e11, VI_ABOVE(0.0), VI_NONE, "Pa", 0, "", "Young's modulus of body 1") \
  X(E2, Real, none, parameter, fixed, exact, 2.1e11, VI_ABOVE(0.0), VI_NONE, "Pa", 0, "", "Young's modulus of body 2") \
  X(nu1, Real, none, parameter, fixed, exact, 0.3, VI_ABOVE(-1.0), VI_AT(0.5), "", 0, "", "Poisson's ratio of body 1") \
  X(nu2, Real, none, parameter, fixed, exact, 0.3, VI_ABOVE(-1.0), VI_AT(0.5), "", 0, "", "Poisson's ratio of body 2") \
  X(Y, Real, none, parameter, fixed, exact, 6e8, VI_ABOVE(0.0), VI_NONE, "Pa", 0, "", "uniaxial yield stress") \
  X(theta_Y, Real, none, parameter, fixed, exact, 1.1, VI_ABOVE(0.0), VI_NONE, "", 0, "", "limiting mean pressure p_Y = theta_Y Y") \
  X(contact_model, Integer, ContactModel, parameter, fixed, exact, 2, VI_NONE, VI_NONE, "", 0, "", "contact law (lepp: linear elastic-perfectly plastic; hertz_damped, linear: with damping; thornton: elastic-perfectly plastic sphere)") \
  X(moving_contact, Boolean, none, parameter, fixed, exact, 0, VI_NONE, VI_NONE, "", 0, "", "Johnson with a moving contact point: virgin curve both ways") \
  X(unloading, Integer, Unloading, parameter, fixed, exact, 1, VI_NONE, VI_NONE, "", 0, "", "Johnson unloading curve") \
  X(yield_formula, Integer, YieldFormula, parameter, fixed, exact, 1, VI_NONE, VI_NONE, "", 0, "", "formula for the yield force F_Y") \
  X(init, Integer, Init, parameter, fixed, exact, 1, VI_NONE, VI_NONE, "", 0, "", "initial state") \
  X(v0, Real, none, parameter, fixed, exact, 0.0, VI_NONE, VI_NONE, "m/s", 0, "", "initial velocity of the mass when touching") \
  X(a, Real, none, parameter, tunable, exact, 0.0, VI_NONE, VI_NONE, "m", 0, "", "amplitude of the internal harmonic platform excitation (tunable: a change moves the platform)") \
  X(f, Real, none, parameter, tunable, exact, 560.0, VI_AT(0.0), VI_NONE, "Hz", 0, "", "frequency of the internal harmonic platform excitation (tunable: the phase stays continuous)") \
  X(rtol, Real, none, parameter, fixed, exact, 0.0, VI_AT(0.0), VI_AT(VI_RTOL_MAX), "", 0, "", "relative tolerance: 0 = the experiment's tolerance (fmi2SetupExperiment, fmi3EnterInitializationMode), " VI_STRING_OF(VI_RTOL_DEFAULT) " without one; else at least " VI_STRING_OF(VI_RTOL_MIN) ", used whatever the experiment's") \
  X(solver, Integer, Solver, parameter, fixed, exact, 4, VI_NONE, VI_NONE, "", 0, "", "integration method (auto: Dormand-Prince 8(5,3), CVODE BDF while stiff; doc/model.md section 5)") \
  X(max_step, Real, none, parameter, fixed, exact, 0.0, VI_AT(0.0), VI_NONE, "s", 0, "", "maximum internal step of the solver: 0 = none, else at least " VI_STRING_OF(VI_MAX_STEP_MIN) " s") \
  X(F, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "N", 0, "yC_in F_ext y v vC_in", "contact force") \
  X(delta, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "yC_in y", "indentation yC - y") \
  X(y, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 1e-5, "y", "mass position") \
  X(v, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", 0.1, "v", "mass velocity") \
  X(yC, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "yC_in", "platform position actually applied") \
  X(contact, Boolean, none, output, discrete, calculated, 0, VI_NONE, VI_NONE, "", 0, "", "bodies touch") \
  X(mode, Integer, Mode, output, discrete, calculated, 0, VI_NONE, VI_NONE, "", 0, "", "mode of the hybrid automaton") \
  X(delta_c, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "yC_in y", "maximum indentation reached (Johnson)") \
  X(delta_f, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "yC_in y", "final indentation of the unloading curve (Johnson)") \
  X(delta_p, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "yC_in y", "permanent set (linear elastic-perfectly plastic)") \
  X(Rbar, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "yC_in y", "effective radius after plastic deformation (Johnson)") \
  X(W_plastic, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "yC_in y", "plastic work dissipated so far") \
  X(n_impacts, Integer, none, output, discrete, calculated, 0, VI_NONE, VI_NONE, "", 0, "", "contact onsets so far (a contact present at the start is not counted)") \
  X(E_star, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "Pa", 0, "", "effective Young's modulus (paper eq. 1)") \
  X(R_star, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "", "effective radius (paper eq. 1)") \
  X(F_Y, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "N", 0, "", "yield force") \
  X(delta_Y, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "", "yield indentation") \
  X(k_lin, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "N/m", 0, "", "stiffness of the linear elastic-perfectly plastic model, F_Y/delta_Y") \
  X(f_contact, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "Hz", 0, "", "linearised contact resonance at the static load") \
  X(F_mean, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "N", 0, "yC_in F_ext y v vC_in", "contact force averaged over the last communication step: its impulse divided by the step") \
  X(k_contact, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "N/m", 0, "yC_in y v vC_in", "tangent contact stiffness dF/ddelta at the current state, 0 out of contact") \
  X(profile_file, String, none, parameter, fixed, exact, "", VI_NONE, VI_NONE, "", 0, "", "profile rolled over (Fig. 1b): two-column text table x [m], h [m]; relative paths: FMU resources, then working directory; empty = none") \
  X(V, Real, none, parameter, fixed, exact, 0.0, VI_NONE, VI_NONE, "m/s", 0, "", "rolling speed over the profile: yC = yC_in + a (cos(2 pi f t) - 1) + yb(x0 + V t)") \
  X(x0, Real, none, parameter, fixed, exact, 0.0, VI_NONE, VI_NONE, "m", 0, "", "position on the profile at the start time") \
  X(profile_periodic, Boolean, none, parameter, fixed, exact, 0, VI_NONE, VI_NONE, "", 0, "", "repeat the profile beyond its ends (its last height must equal the first); false: the run stops at its end") \
  X(der_y, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s", 0, "v", "time derivative of y (Model Exchange: the derivative of the state y)") \
  X(der_v, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m/s2", 0, "yC_in F_ext y v vC_in", "time derivative of v, the acceleration of the mass (Model Exchange: the derivative of the state v)") \
  X(e_restitution, Real, none, parameter, fixed, exact, 0.8, VI_ABOVE(0.0), VI_AT(1.0), "", 0, "", "coefficient of restitution of an isolated impact (hertz_damped, linear)") \
  X(damping_formula, Integer, DampingFormula, parameter, fixed, exact, 1, VI_NONE, VI_NONE, "", 0, "", "damping of hertz_damped (exact: the restitution is e_restitution at every impact speed)") \
  X(k_spring, Real, none, parameter, fixed, exact, 1.2e9, VI_ABOVE(0.0), VI_NONE, "N/m", 0, "", "spring stiffness of the linear spring-dashpot (contact_model = linear)") \
  X(vC_in, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "m/s", 0, "", "platform velocity input, the rate of yC_in: used wherever the FMU needs the platform's rate when velocity_input is true") \
  X(velocity_input, Boolean, none, parameter, fixed, exact, 0, VI_NONE, VI_NONE, "", 0, "", "take the rate of yC_in from vC_in (coupled masters hold the rail's velocity); false: from yC_in's derivative in Co-Simulation, none in Model Exchange") \
  X(W_dissipated, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "yC_in y W_damping", "everything the contact has dissipated so far: W_plastic plus W_damping (kinetic energy + E_contact + W_dissipated = work of the platform, F_ext, P and gravity)") \
  X(E_contact, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "J", 0, "yC_in y", "elastic energy stored in the contact now: the work of the current branch's force from its contact surface to delta") \
  X(F_peak, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "N", 0, "yC_in F_ext y v vC_in", "largest contact force since the last communication point (Co-Simulation: over the whole step, events and the inside of the solver's steps included; Model Exchange: F)") \
  X(W_damping, Real, none, local, continuous, exact, 0.0, VI_NONE, VI_NONE, "J", 1.0, "", "work of the damping of hertz_damped and linear: the power of the force beyond its spring part, (F - F_spring(delta)) delta' (Model Exchange: a continuous state)") \
  X(der_W_damping, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "W", 0, "yC_in y v vC_in", "time derivative of W_damping, the damping's power (Model Exchange: the derivative of the state W_damping)") \
  X(profile_interpolation, Integer, ProfileInterpolation, parameter, fixed, exact, 1, VI_NONE, VI_NONE, "", 0, "", "how the rows of profile_file are joined: linear (the exact polyline, its corners kept) or cubic (the C2 spline through them: a sampled smooth rail without a kink at every row)") \
  X(upper_stop, Boolean, none, parameter, fixed, exact, 0, VI_NONE, VI_NONE, "", 0, "", "a second surface at yC + gap above the mass, moving with the platform, with the same law and material (the upper contact: a cavity's lid, the other flank of a clearance)") \
  X(gap, Real, none, parameter, fixed, exact, 0.0, VI_AT(0.0), VI_NONE, "m", 0, "", "clearance between the two surfaces' contact points, > 0 with upper_stop (the upper surface at yC + gap)") \
  X(F_upper, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "N", 0, "yC_in F_ext y v vC_in", "the upper contact's force on the mass, down positive (0 without upper_stop)") \
  X(delta_upper, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "m", 0, "yC_in y", "the upper contact's indentation y - (yC + gap) (0 without upper_stop)") \
  X(mode_upper, Integer, Mode, output, discrete, calculated, 0, VI_NONE, VI_NONE, "", 0, "", "mode of the upper contact") \
  X(n_impacts_upper, Integer, none, output, discrete, calculated, 0, VI_NONE, VI_NONE, "", 0, "", "contact onsets on the upper surface so far")

/* Enumeration types: E(type, description); items in VI_ITEMS_<type>(I) as I(type, name, value).
 * Items are matched by name in the model through the constants VI_<type>_<name>. */
#define VI_ENUMERATIONS(E) \
  E(ContactModel, "contact law") \
  E(DampingFormula, "damping of the damped Hertz law") \
  E(Unloading, "Johnson unloading curve") \
  E(YieldFormula, "yield force formula") \
  E(Init, "initial state") \
  E(Solver, "integration method") \
  E(ProfileInterpolation, "joining of the profile rows") \
  E(Mode, "mode of the hybrid automaton")
#define VI_ITEMS_ContactModel(I) I(ContactModel, hertz, 1) I(ContactModel, johnson, 2) I(ContactModel, lepp, 3) \
  I(ContactModel, hertz_damped, 4) I(ContactModel, linear, 5) I(ContactModel, thornton, 6)
#define VI_ITEMS_DampingFormula(I) I(DampingFormula, exact, 1) I(DampingFormula, hunt_crossley, 2) \
  I(DampingFormula, lankarani_nikravesh, 3) I(DampingFormula, flores, 4)
#define VI_ITEMS_Unloading(I) I(Unloading, paper, 1) I(Unloading, continuous, 2)
#define VI_ITEMS_YieldFormula(I) I(YieldFormula, textbook, 1) I(YieldFormula, printed, 2)
#define VI_ITEMS_Init(I) I(Init, static, 1) I(Init, touching, 2)
#define VI_ITEMS_Solver(I) I(Solver, bdf, 1) I(Solver, adams, 2) I(Solver, dop853, 3) I(Solver, auto, 4)
#define VI_ITEMS_ProfileInterpolation(I) I(ProfileInterpolation, linear, 1) I(ProfileInterpolation, cubic, 2)
#define VI_ITEMS_Mode(I) I(Mode, free, 0) I(Mode, elastic, 1) I(Mode, plastic, 2) I(Mode, unload, 3) I(Mode, stick, 4)

VI_TABLE_DECLARE

#endif
