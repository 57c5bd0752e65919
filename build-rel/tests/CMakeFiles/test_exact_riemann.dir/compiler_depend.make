# Empty compiler generated dependencies file for test_exact_riemann.
# This may be replaced when dependencies are built.
