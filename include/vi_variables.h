/*
 * vi_variables.h - the one table of VibroImpact's FMU variables.
 *
 * Every FMU variable is one row of VI_VARIABLES. Its value reference is its
 * position in the table (0, 1, 2, ...). From the rows the compiler generates
 *   - the structs vi_parameters, vi_inputs and vi_outputs, one field per
 *     variable, named as the variable (so the model reads p->m, p->Y, ...),
 *   - the defaults (start values) of parameters and inputs,
 *   - vi_variable_table, the descriptor array the FMI glue uses for get/set.
 * modelDescription.xml repeats the table by hand; fmu-test/test_interface.py
 * fails when the two disagree (it reads the table through vi_dump_variables).
 *
 * Columns: X(name, type, enum, causality, variability, initial, start, unit, description)
 *   type        Real | Integer | Boolean | Enumeration (read and written as Integer)
 *   enum        the enumeration type (VI_ENUMERATIONS) of an Enumeration, else none
 *   causality   parameter | input | output | calculatedParameter
 *   initial     exact | calculated  (outputs and calculated parameters: calculated)
 *   start       start value (ignored when initial is calculated)
 *   unit        SI unit symbol as declared in modelDescription.xml, "" for none
 */
#ifndef VI_VARIABLES_H
#define VI_VARIABLES_H

#include <stddef.h>

#define VI_GUID "{5b7e0c3a-2f1d-4e8b-9a61-7c4d2e9f1a03}"
#define VI_MODEL_IDENTIFIER "VibroImpact"

#define VI_VARIABLES(X) \
  X(yC_in, Real, none, input, continuous, exact, 0.0, "m", "platform displacement input (interpolated with its derivative when given)") \
  X(F_ext, Real, none, input, continuous, exact, 0.0, "N", "external force on the mass, up positive") \
  X(m, Real, none, parameter, fixed, exact, 407.747, "kg", "mass") \
  X(P, Real, none, parameter, fixed, exact, 40000.0, "N", "constant pressing load") \
  X(g, Real, none, parameter, fixed, exact, 9.81, "m/s2", "gravity (0 makes P the whole load)") \
  X(R1, Real, none, parameter, fixed, exact, 0.475, "m", "radius of body 1 (0 = plane)") \
  X(R2, Real, none, parameter, fixed, exact, 0.0, "m", "radius of body 2 (0 = plane)") \
  X(E1, Real, none, parameter, fixed, exact, 2.1e11, "Pa", "Young's modulus of body 1") \
  X(E2, Real, none, parameter, fixed, exact, 2.1e11, "Pa", "Young's modulus of body 2") \
  X(nu1, Real, none, parameter, fixed, exact, 0.3, "", "Poisson's ratio of body 1") \
  X(nu2, Real, none, parameter, fixed, exact, 0.3, "", "Poisson's ratio of body 2") \
  X(Y, Real, none, parameter, fixed, exact, 6e8, "Pa", "uniaxial yield stress") \
  X(theta_Y, Real, none, parameter, fixed, exact, 1.1, "", "limiting mean pressure p_Y = theta_Y Y") \
  X(contact_model, Enumeration, ContactModel, parameter, fixed, exact, 2, "", "contact law") \
  X(moving_contact, Boolean, none, parameter, fixed, exact, 0, "", "Johnson with a moving contact point: virgin curve both ways") \
  X(unloading, Enumeration, Unloading, parameter, fixed, exact, 1, "", "Johnson unloading curve") \
  X(yield_formula, Enumeration, YieldFormula, parameter, fixed, exact, 1, "", "formula for the yield force F_Y") \
  X(init, Enumeration, Init, parameter, fixed, exact, 1, "", "initial state") \
  X(v0, Real, none, parameter, fixed, exact, 0.0, "m/s", "initial velocity of the mass when touching") \
  X(a, Real, none, parameter, fixed, exact, 0.0, "m", "amplitude of the internal harmonic platform excitation") \
  X(f, Real, none, parameter, fixed, exact, 560.0, "Hz", "frequency of the internal harmonic platform excitation") \
  X(rtol, Real, none, parameter, fixed, exact, 1e-6, "", "relative tolerance (a tolerance from fmi2SetupExperiment wins)") \
  X(solver, Enumeration, Solver, parameter, fixed, exact, 1, "", "integration method: CVODE BDF or Adams (linear multistep), or Dormand-Prince 8(5,3) (explicit one-step, dense output)") \
  X(max_step, Real, none, parameter, fixed, exact, 0.0, "s", "CVODE maximum internal step, 0 = none") \
  X(F, Real, none, output, continuous, calculated, 0.0, "N", "contact force") \
  X(delta, Real, none, output, continuous, calculated, 0.0, "m", "indentation yC - y") \
  X(y, Real, none, output, continuous, calculated, 0.0, "m", "mass position") \
  X(v, Real, none, output, continuous, calculated, 0.0, "m/s", "mass velocity") \
  X(yC, Real, none, output, continuous, calculated, 0.0, "m", "platform position actually applied") \
  X(contact, Boolean, none, output, discrete, calculated, 0, "", "bodies touch") \
  X(mode, Enumeration, Mode, output, discrete, calculated, 0, "", "mode of the hybrid automaton") \
  X(delta_c, Real, none, output, continuous, calculated, 0.0, "m", "maximum indentation reached (Johnson)") \
  X(delta_f, Real, none, output, continuous, calculated, 0.0, "m", "final indentation of the unloading curve (Johnson)") \
  X(delta_p, Real, none, output, continuous, calculated, 0.0, "m", "permanent set (linear elastic-perfectly plastic)") \
  X(Rbar, Real, none, output, continuous, calculated, 0.0, "m", "effective radius after plastic deformation (Johnson)") \
  X(W_plastic, Real, none, output, continuous, calculated, 0.0, "J", "plastic work dissipated so far") \
  X(n_impacts, Integer, none, output, discrete, calculated, 0, "", "contact onsets so far (a contact present at the start is not counted)") \
  X(E_star, Real, none, calculatedParameter, fixed, calculated, 0.0, "Pa", "effective Young's modulus (paper eq. 1)") \
  X(R_star, Real, none, calculatedParameter, fixed, calculated, 0.0, "m", "effective radius (paper eq. 1)") \
  X(F_Y, Real, none, calculatedParameter, fixed, calculated, 0.0, "N", "yield force") \
  X(delta_Y, Real, none, calculatedParameter, fixed, calculated, 0.0, "m", "yield indentation") \
  X(k_lin, Real, none, calculatedParameter, fixed, calculated, 0.0, "N/m", "stiffness of the linear elastic-perfectly plastic model, F_Y/delta_Y") \
  X(f_contact, Real, none, calculatedParameter, fixed, calculated, 0.0, "Hz", "linearised contact resonance at the static load") \
  X(F_mean, Real, none, output, continuous, calculated, 0.0, "N", "contact force averaged over the last communication step: its impulse divided by the step") \
  X(k_contact, Real, none, output, continuous, calculated, 0.0, "N/m", "tangent contact stiffness dF/ddelta at the current state, 0 out of contact")

/* Enumeration types: E(type, description); items in VI_ITEMS_<type>(I) as I(type, name, value). */
#define VI_ENUMERATIONS(E) \
  E(ContactModel, "contact law") \
  E(Unloading, "Johnson unloading curve") \
  E(YieldFormula, "yield force formula") \
  E(Init, "initial state") \
  E(Solver, "integration method") \
  E(Mode, "mode of the hybrid automaton")
#define VI_ITEMS_ContactModel(I) I(ContactModel, hertz, 1) I(ContactModel, johnson, 2) I(ContactModel, lepp, 3)
#define VI_ITEMS_Unloading(I) I(Unloading, paper, 1) I(Unloading, continuous, 2)
#define VI_ITEMS_YieldFormula(I) I(YieldFormula, textbook, 1) I(YieldFormula, printed, 2)
#define VI_ITEMS_Init(I) I(Init, static, 1) I(Init, touching, 2)
#define VI_ITEMS_Solver(I) I(Solver, bdf, 1) I(Solver, adams, 2) I(Solver, dop853, 3)
#define VI_ITEMS_Mode(I) I(Mode, free, 0) I(Mode, elastic, 1) I(Mode, plastic, 2) I(Mode, unload, 3) I(Mode, stick, 4)

/* ---- generated from the tables above; nothing below names a variable ---- */

/* Enumeration constants: VI_ContactModel_hertz, ..., VI_Mode_stick. */
#define VI_ENUM_CONST_(T, n, v) VI_##T##_##n = v,
#define VI_ENUM_ITEMS_(T, d) VI_ITEMS_##T(VI_ENUM_CONST_)
enum { VI_ENUMERATIONS(VI_ENUM_ITEMS_) };

/* Value references: VI_VR_yC_in = 0, ...; VI_NVARS variables in all. */
#define VI_VR_(name, ...) VI_VR_##name,
enum { VI_VARIABLES(VI_VR_) VI_NVARS };

#define VI_CTYPE_Real double
#define VI_CTYPE_Integer int
#define VI_CTYPE_Boolean int /* fmi2Boolean */
#define VI_CTYPE_Enumeration int

/* Which struct holds a variable: parameters, inputs, or outputs (with calculated parameters). */
#define VI_IF_PAR_parameter(x) x
#define VI_IF_PAR_input(x)
#define VI_IF_PAR_output(x)
#define VI_IF_PAR_calculatedParameter(x)
#define VI_IF_IN_parameter(x)
#define VI_IF_IN_input(x) x
#define VI_IF_IN_output(x)
#define VI_IF_IN_calculatedParameter(x)
#define VI_IF_OUT_parameter(x)
#define VI_IF_OUT_input(x)
#define VI_IF_OUT_output(x) x
#define VI_IF_OUT_calculatedParameter(x) x

#define VI_FIELD_PAR_(name, type, en, caus, ...) VI_IF_PAR_##caus(VI_CTYPE_##type name;)
#define VI_FIELD_IN_(name, type, en, caus, ...) VI_IF_IN_##caus(VI_CTYPE_##type name;)
#define VI_FIELD_OUT_(name, type, en, caus, ...) VI_IF_OUT_##caus(VI_CTYPE_##type name;)
typedef struct { VI_VARIABLES(VI_FIELD_PAR_) } vi_parameters;
typedef struct { VI_VARIABLES(VI_FIELD_IN_) } vi_inputs;
typedef struct { VI_VARIABLES(VI_FIELD_OUT_) } vi_outputs;

typedef enum { VI_Real, VI_Integer, VI_Boolean, VI_Enumeration } vi_type;
typedef enum { VI_GROUP_PARAMETERS, VI_GROUP_INPUTS, VI_GROUP_OUTPUTS } vi_group;

typedef struct {
    const char *name;
    vi_type type;
    const char *enumeration;   /* declared type of an Enumeration, else "none" */
    const char *causality, *variability, *initial;
    double start;              /* meaningful when initial is exact */
    const char *unit, *description;
    vi_group group;            /* the struct that holds the value ... */
    size_t offset;             /* ... and where in it */
} vi_variable;

typedef struct { const char *type, *name; int value; } vi_enum_item;

/* vi_variable_table[vr] describes the variable with value reference vr (vr < VI_NVARS). */
extern const vi_variable vi_variable_table[VI_NVARS];
/* All enumeration items, grouped by type; vi_enum_item_count entries. */
extern const vi_enum_item vi_enum_items[];
extern const int vi_enum_item_count;

/* Fill the structs with the start values of the table. */
void vi_parameters_default(vi_parameters *p);
void vi_inputs_default(vi_inputs *in);

#endif
