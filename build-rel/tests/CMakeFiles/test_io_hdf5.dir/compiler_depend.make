# Empty compiler generated dependencies file for test_io_hdf5.
# This may be replaced when dependencies are built.
