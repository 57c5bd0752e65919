file(REMOVE_RECURSE
  "CMakeFiles/test_io_hdf5.dir/test_io_hdf5.f90.o"
  "test_io_hdf5"
  "test_io_hdf5.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang Fortran)
  include(CMakeFiles/test_io_hdf5.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
