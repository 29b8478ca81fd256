/* vi_variables.c - descriptor table and defaults generated from VI_VARIABLES. */
#include "vi_variables.h"

#define VI_GROUP_OF_(caus) \
    VI_IF_PAR_##caus(VI_GROUP_PARAMETERS) VI_IF_IN_##caus(VI_GROUP_INPUTS) VI_IF_OUT_##caus(VI_GROUP_OUTPUTS)
#define VI_OFFSET_OF_(caus, name)                                                      \
    VI_IF_PAR_##caus(offsetof(vi_parameters, name)) VI_IF_IN_##caus(offsetof(vi_inputs, name)) \
        VI_IF_OUT_##caus(offsetof(vi_outputs, name))

#define VI_ROW_(name, type, en, caus, var, init, start, unit, desc) \
    {#name, VI_##type, #en, #caus, #var, #init, (double)(start), unit, desc, \
     VI_GROUP_OF_(caus), VI_OFFSET_OF_(caus, name)},
const vi_variable vi_variable_table[VI_NVARS] = {VI_VARIABLES(VI_ROW_)};

#define VI_ITEM_ROW_(T, n, v) {#T, #n, v},
#define VI_TYPE_ITEMS_(T, d) VI_ITEMS_##T(VI_ITEM_ROW_)
const vi_enum_item vi_enum_items[] = {VI_ENUMERATIONS(VI_TYPE_ITEMS_)};
const int vi_enum_item_count = (int)(sizeof vi_enum_items / sizeof vi_enum_items[0]);

#define VI_DEFAULT_PAR_(name, type, en, caus, var, init, start, ...) VI_IF_PAR_##caus(p->name = start;)
#define VI_DEFAULT_IN_(name, type, en, caus, var, init, start, ...) VI_IF_IN_##caus(in->name = start;)
void vi_parameters_default(vi_parameters *p) { VI_VARIABLES(VI_DEFAULT_PAR_) }
void vi_inputs_default(vi_inputs *in) { VI_VARIABLES(VI_DEFAULT_IN_) }
