# Empty custom commands generated dependencies file for fmu.
# This may be replaced when dependencies are built.
