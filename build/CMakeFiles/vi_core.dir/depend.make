# Empty dependencies file for vi_core.
# This may be replaced when dependencies are built.
