# CMake generated Testfile for 
# Source directory: /work/main/tests
# Build directory: /work/main/build-rel/tests
# 
# This file includes the relevant testing commands required for 
# testing this directory and lists subdirectories to be tested as well.
add_test([=[test_io_hdf5]=] "/work/main/build-rel/tests/test_io_hdf5")
set_tests_properties([=[test_io_hdf5]=] PROPERTIES  LABELS "unit" _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;9;add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_exact_riemann]=] "/work/main/build-rel/tests/test_exact_riemann")
set_tests_properties([=[test_exact_riemann]=] PROPERTIES  LABELS "unit" _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;9;add_test;/work/main/tests/CMakeLists.txt;0;")
