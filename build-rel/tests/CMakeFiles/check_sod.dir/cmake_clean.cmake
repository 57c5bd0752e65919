file(REMOVE_RECURSE
  "CMakeFiles/check_sod.dir/check_sod.f90.o"
  "CMakeFiles/check_sod.dir/check_support.f90.o"
  "check_sod"
  "check_sod.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang Fortran)
  include(CMakeFiles/check_sod.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
