# Empty compiler generated dependencies file for lsalepm.
# This may be replaced when dependencies are built.
