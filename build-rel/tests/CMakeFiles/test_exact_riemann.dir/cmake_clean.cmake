file(REMOVE_RECURSE
  "CMakeFiles/test_exact_riemann.dir/test_exact_riemann.f90.o"
  "test_exact_riemann"
  "test_exact_riemann.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang Fortran)
  include(CMakeFiles/test_exact_riemann.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
