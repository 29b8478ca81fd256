/* Print the variable table (vi_variables.h) as tab-separated text for fmu-test/test_interface.py:
 *   guid <GUID>
 *   var <vr> <name> <type> <enumeration> <causality> <variability> <initial> <start> <unit> <description>
 *       (<start> of a String is the string itself)
 *   enum <type> <item> <value>                                                                       */
#include <stdio.h>

#include "vi_variables.h"

int main(void)
{
    static const char *const types[] = {"Real", "Integer", "Boolean", "Enumeration", "String"};
    printf("guid\t%s\n", VI_GUID);
    for (int vr = 0; vr < VI_NVARS; vr++) {
        const vi_variable *v = &vi_variable_table[vr];
        char start[64];
        snprintf(start, sizeof start, "%.17g", v->start);
        printf("var\t%d\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", vr, v->name, types[v->type], v->enumeration,
               v->causality, v->variability, v->initial, v->type == VI_String ? v->start_string : start, v->unit,
               v->description);
    }
    for (int i = 0; i < vi_enum_item_count; i++)
        printf("enum\t%s\t%s\t%d\n", vi_enum_items[i].type, vi_enum_items[i].name, vi_enum_items[i].value);
    return 0;
}
