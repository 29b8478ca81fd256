/* vi_variables.c - descriptor table and defaults generated from VI_VARIABLES. */
#include "vi_variables.h"

#include <string.h>

#define VI_GROUP_OF_(caus) \
    VI_IF_PAR_##caus(VI_GROUP_PARAMETERS) VI_IF_IN_##caus(VI_GROUP_INPUTS) VI_IF_OUT_##caus(VI_GROUP_OUTPUTS)
#define VI_OFFSET_OF_(caus, name)                                                      \
    VI_IF_PAR_##caus(offsetof(vi_parameters, name)) VI_IF_IN_##caus(offsetof(vi_inputs, name)) \
        VI_IF_OUT_##caus(offsetof(vi_outputs, name))

#define VI_ROW_(name, type, en, caus, var, init, start, unit, desc) \
    {#name, VI_##type, #en, #caus, #var, #init, VI_START_NUM_##type(start), VI_START_STR_##type(start), unit, desc, \
     VI_GROUP_OF_(caus), VI_OFFSET_OF_(caus, name)},
const vi_variable vi_variable_table[VI_NVARS] = {VI_VARIABLES(VI_ROW_)};

#define VI_ITEM_ROW_(T, n, v) {#T, #n, v},
#define VI_TYPE_ITEMS_(T, d) VI_ITEMS_##T(VI_ITEM_ROW_)
const vi_enum_item vi_enum_items[] = {VI_ENUMERATIONS(VI_TYPE_ITEMS_)};
const int vi_enum_item_count = (int)(sizeof vi_enum_items / sizeof vi_enum_items[0]);

/* Assign a start value; a String start value must fit (checked at compile time). */
#define VI_ASSIGN_Real(lhs, v) lhs = v;
#define VI_ASSIGN_Integer(lhs, v) lhs = v;
#define VI_ASSIGN_Boolean(lhs, v) lhs = v;
#define VI_ASSIGN_Enumeration(lhs, v) lhs = v;
#define VI_ASSIGN_String(lhs, v) { _Static_assert(sizeof(v) <= sizeof(lhs), "String start value too long"); memcpy(lhs, v, sizeof(v)); }
#define VI_DEFAULT_PAR_(name, type, en, caus, var, init, start, ...) VI_IF_PAR_##caus(VI_ASSIGN_##type(p->name, start))
#define VI_DEFAULT_IN_(name, type, en, caus, var, init, start, ...) VI_IF_IN_##caus(VI_ASSIGN_##type(in->name, start))

/* String outputs would need storage that outlives fmi2GetString: not supported. */
#define VI_NO_STRING_OUT_Real
#define VI_NO_STRING_OUT_Integer
#define VI_NO_STRING_OUT_Boolean
#define VI_NO_STRING_OUT_Enumeration
#define VI_NO_STRING_OUT_String _Static_assert(0, "String outputs are not supported");
#define VI_CHECK_OUT_(name, type, en, caus, ...) VI_IF_OUT_##caus(VI_NO_STRING_OUT_##type)
VI_VARIABLES(VI_CHECK_OUT_)
void vi_parameters_default(vi_parameters *p) { VI_VARIABLES(VI_DEFAULT_PAR_) }
void vi_inputs_default(vi_inputs *in) { VI_VARIABLES(VI_DEFAULT_IN_) }
