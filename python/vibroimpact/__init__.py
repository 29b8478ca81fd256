"""VibroImpact: the FMU of dynamic unilateral elasto-plastic contact and the Python around it."""
