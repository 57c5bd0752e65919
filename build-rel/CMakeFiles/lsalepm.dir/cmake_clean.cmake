file(REMOVE_RECURSE
  "CMakeFiles/lsalepm.dir/src/driver.f90.o"
  "CMakeFiles/lsalepm.dir/src/main.f90.o"
  "lsalepm"
  "lsalepm.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang Fortran)
  include(CMakeFiles/lsalepm.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
