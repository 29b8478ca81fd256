/* Print the variable table of the FMU's model (vi_fmu_this_model) as tab-separated text, the one
 * source of both model descriptions (cmake/vi_model_description.py), of the variable table of the
 * FMU's documentation (cmake/vi_fmu_doc.py) and of the interface tests (fmu-test/test_interface.py):
 *   guid <GUID>
 *   model <model identifier> <description>
 *   experiment <start> <stop> <tolerance, empty: none> <step>
 *   interpolates_inputs <0|1>
 *   model_exchange <number of states> <number of event indicators> <directional derivatives 0|1>
 *   early_return <0|1>   (the model can end a Co-Simulation step at its events: advance_to_event)
 *   state <value reference of the state> <value reference of its derivative>   (in state order)
 *   var <vr> <name> <type> <enumeration> <causality> <variability> <initial> <start> <min> <max> <unit> <description>
 *       (<start> of a String is the string itself; <min> and <max> are the inclusive bounds that
 *       modelDescription.xml declares (vi_bound_inclusive), empty without a bound; the description of
 *       an Integer with enumeration items is followed by them, as modelDescription.xml gives it:
 *       "contact law: hertz=1, johnson=2")
 *   range <vr> <the range as messages write it, e.g. "m > 0">   (the variables that have one)
 *   nominal <vr> <nominal>                 (the Reals that have one)
 *   depends <vr> <names separated by spaces>  (every output and local)
 *   enumtype <type> <description>
 *   enum <type> <item> <value>
 * Numbers are written with 17 significant digits, so that they read back as the same double. */
#include <stdio.h>
#include <string.h>

#include "vi_fmu.h"
#include "vi_text.h"

static void print_model(const vi_fmu_model *m)
{
    const vi_fmu_experiment *e = &m->default_experiment;
    char start[32], stop[32], tolerance[32] = "", step[32];
    vi_snprintf(start, sizeof start, "%.17g", e->start_s);
    vi_snprintf(stop, sizeof stop, "%.17g", e->stop_s);
    if (e->tolerance > 0) vi_snprintf(tolerance, sizeof tolerance, "%.17g", e->tolerance);
    vi_snprintf(step, sizeof step, "%.17g", e->step_s);
    printf("guid\t%s\n", m->guid);
    printf("model\t%s\t%s\n", m->model_identifier, m->description);
    printf("experiment\t%s\t%s\t%s\t%s\n", start, stop, tolerance, step);
    printf("interpolates_inputs\t%d\n", m->can_interpolate_inputs ? 1 : 0);
    printf("model_exchange\t%d\t%d\t%d\n", m->n_states, m->n_indicators, m->directional_derivative != NULL);
    printf("early_return\t%d\n", m->advance_to_event != NULL);
    for (int i = 0; i < m->n_states; i++) printf("state\t%u\t%u\n", m->state_vrs[i], m->derivative_vrs[i]);
}

static void print_variable(const vi_fmu_model *m, int vr)
{
    static const char *const types[] = {"Real", "Integer", "Boolean", "Enumeration", "String"};
    const vi_variable *v = &m->variables[vr];
    char start[64], lo[64] = "", hi[64] = "", nominal[64], range[160];
    vi_snprintf(start, sizeof start, "%.17g", v->start);
    if (v->min.kind != VI_BOUND_NONE) vi_snprintf(lo, sizeof lo, "%.17g", vi_bound_inclusive(v->min, 0));
    if (v->max.kind != VI_BOUND_NONE) vi_snprintf(hi, sizeof hi, "%.17g", vi_bound_inclusive(v->max, 1));
    printf("var\t%d\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s", vr, v->name, types[v->type], v->enumeration,
           v->causality, v->variability, v->initial, v->type == VI_String ? v->start_string : start, lo, hi,
           v->unit, v->description);
    const char *sep = ": ";
    for (int i = 0; v->type == VI_Integer && i < m->n_enum_items; i++) {
        if (strcmp(m->enum_items[i].type, v->enumeration) != 0) continue;
        printf("%s%s=%d", sep, m->enum_items[i].name, m->enum_items[i].value);
        sep = ", ";
    }
    printf("\n");
    vi_range_text(v, range, sizeof range);
    if (range[0]) printf("range\t%d\t%s\n", vr, range);
    if (v->nominal != 0) {
        vi_snprintf(nominal, sizeof nominal, "%.17g", v->nominal);
        printf("nominal\t%d\t%s\n", vr, nominal);
    }
    if (strcmp(v->causality, "output") == 0 || strcmp(v->causality, "local") == 0 || v->depends[0] != '\0')
        printf("depends\t%d\t%s\n", vr, v->depends);
}

int main(void)
{
    const vi_fmu_model *m = &vi_fmu_this_model;
    print_model(m);
    for (int vr = 0; vr < m->nvariables; vr++) print_variable(m, vr);
    for (int i = 0; i < m->n_enum_types; i++)
        printf("enumtype\t%s\t%s\n", m->enum_types[i].name, m->enum_types[i].description);
    for (int i = 0; i < m->n_enum_items; i++)
        printf("enum\t%s\t%s\t%d\n", m->enum_items[i].type, m->enum_items[i].name, m->enum_items[i].value);
    return 0;
}
