/*
 * layer_variables.h - variables of LayerTest, the smallest model on the generic FMI layer
 * (src/fmi/vi_fmu.h). It exists to test the layer apart from any physics, and shows a model author
 * the whole of what a model writes: this table, layer_model.c, modelDescription.xml, and one
 * vi_add_fmu() call in CMakeLists.txt.
 *
 * The model: x' = -k x + u(t), x(t_start) = x0, with u a ramp u + du (t - t_set) over a step; in
 * Co-Simulation it is advanced by its closed-form solution. discard_at and fail_at make a step that
 * crosses them stop with fmi2Discard (at discard_at) or fail with fmi2Error. In Model Exchange the
 * importer integrates x (u as set, k as of the last event); x crossing x_event is a state event (x
 * jumps by `jump`), t_event a time event, and with `chatter` the event iteration never settles.
 */
#ifndef LAYER_VARIABLES_H
#define LAYER_VARIABLES_H

#include "vi_table.h"

#define VI_GUID "{0e9c4f5a-7d21-4b8e-a3c6-5f1d2b7e9a40}"
#define VI_MODEL_IDENTIFIER "LayerTest"
#define VI_MODEL_DESCRIPTION "x' = -k x + u, advanced by its closed form (Co-Simulation) or by the importer (Model Exchange, with a state event, a time event and a switch that keeps the event iteration from settling): a test model of the generic FMI layer"
#define VI_DEFAULT_EXPERIMENT {.start_s = 0.0, .stop_s = 1.0, .tolerance = 0.0, .step_s = 0.01}
#define VI_CAN_INTERPOLATE_INPUTS 1

#define VI_VARIABLES(X) \
  X(u, Real, none, input, continuous, exact, 0.0, VI_NONE, VI_NONE, "", 0, "", "input (interpolated with its derivative when given)") \
  X(k, Real, none, parameter, tunable, exact, 1.0, VI_ABOVE(0.0), VI_NONE, "1/s", 0, "", "decay rate (> 0), tunable") \
  X(x0, Real, none, parameter, fixed, exact, 1.0, VI_NONE, VI_NONE, "", 0, "", "initial value") \
  X(discard_at, Real, none, parameter, fixed, exact, 0.0, VI_NONE, VI_NONE, "s", 0, "", "a step across this time stops there with fmi2Discard (0 = never)") \
  X(fail_at, Real, none, parameter, fixed, exact, 0.0, VI_NONE, VI_NONE, "s", 0, "", "a step across this time fails with fmi2Error (0 = never)") \
  X(label, String, none, parameter, fixed, exact, "start", VI_NONE, VI_NONE, "", 0, "", "a String parameter") \
  X(method, Enumeration, Method, parameter, fixed, exact, 1, VI_NONE, VI_NONE, "", 0, "", "how to advance") \
  X(x, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "", 0, "x", "state") \
  X(steps, Integer, none, output, discrete, calculated, 0, VI_NONE, VI_NONE, "", 0, "", "steps done") \
  X(label_length, Integer, none, output, discrete, calculated, 0, VI_NONE, VI_NONE, "", 0, "", "length of label") \
  X(resource_value, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "", 0, "", "the number in resources/value.txt (-1 if unreadable)") \
  X(k_initial, Real, none, calculatedParameter, fixed, calculated, 0.0, VI_NONE, VI_NONE, "1/s", 0, "", "k at initialization") \
  X(checkpoint_time, Real, none, output, continuous, calculated, 0.0, VI_NONE, VI_NONE, "s", 0, "", "time of the last checkpoint (fmi2GetFMUstate when running)") \
  X(x_event, Real, none, parameter, fixed, exact, 0.0, VI_NONE, VI_NONE, "", 0, "", "Model Exchange: a state event where x crosses this value") \
  X(jump, Real, none, parameter, fixed, exact, 0.0, VI_NONE, VI_NONE, "", 0, "", "Model Exchange: x jumps by this at a state event") \
  X(t_event, Real, none, parameter, fixed, exact, 0.0, VI_AT(0.0), VI_NONE, "s", 0, "", "Model Exchange: a time event at this time (0 = none)") \
  X(chatter, Boolean, none, parameter, fixed, exact, 0, VI_NONE, VI_NONE, "", 0, "", "Model Exchange: the event iteration never settles (every pass asks for another)") \
  X(events, Integer, none, output, discrete, calculated, 0, VI_NONE, VI_NONE, "", 0, "", "Model Exchange: events so far (state and time events)") \
  X(der_x, Real, none, local, continuous, calculated, 0.0, VI_NONE, VI_NONE, "1/s", 0, "u x", "Model Exchange: the derivative of the state x")

#define VI_ENUMERATIONS(E) E(Method, "how to advance")
#define VI_ITEMS_Method(I) I(Method, exact, 1)

VI_TABLE_DECLARE

#endif
