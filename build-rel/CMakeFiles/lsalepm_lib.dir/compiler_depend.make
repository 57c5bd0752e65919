# Empty compiler generated dependencies file for lsalepm_lib.
# This may be replaced when dependencies are built.
