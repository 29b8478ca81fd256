# Empty dependencies file for VibroImpact.
# This may be replaced when dependencies are built.
