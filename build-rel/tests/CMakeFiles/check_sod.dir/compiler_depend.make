# Empty compiler generated dependencies file for check_sod.
# This may be replaced when dependencies are built.
