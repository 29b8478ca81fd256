/* vi_variables.c - descriptor table and defaults generated from VI_VARIABLES (vi_table.h). */
#include "vi_variables.h"

VI_TABLE_DEFINE
