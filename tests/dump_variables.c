/* Print the variable table of the FMU's model (vi_fmu_this_model) as tab-separated text for
 * fmu-test/test_interface.py:
 *   guid <GUID>
 *   var <vr> <name> <type> <enumeration> <causality> <variability> <initial> <start> <min> <max> <unit> <description>
 *       (<start> of a String is the string itself; <min> and <max> are the inclusive bounds that
 *       modelDescription.xml declares (vi_bound_inclusive), empty without a bound; the description of
 *       an Integer with enumeration items is followed by them, as modelDescription.xml gives it:
 *       "contact law: hertz=1, johnson=2")
 *   enum <type> <item> <value>                                                                       */
#include <stdio.h>
#include <string.h>

#include "vi_fmu.h"
#include "vi_text.h"

int main(void)
{
    static const char *const types[] = {"Real", "Integer", "Boolean", "Enumeration", "String"};
    const vi_fmu_model *m = &vi_fmu_this_model;
    printf("guid\t%s\n", m->guid);
    for (int vr = 0; vr < m->nvariables; vr++) {
        const vi_variable *v = &m->variables[vr];
        char start[64], lo[64] = "", hi[64] = "";
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
    }
    for (int i = 0; i < m->n_enum_items; i++)
        printf("enum\t%s\t%s\t%d\n", m->enum_items[i].type, m->enum_items[i].name, m->enum_items[i].value);
    return 0;
}
