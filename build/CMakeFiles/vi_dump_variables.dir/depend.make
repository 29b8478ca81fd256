# Empty dependencies file for vi_dump_variables.
# This may be replaced when dependencies are built.
