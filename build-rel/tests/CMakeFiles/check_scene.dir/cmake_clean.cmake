file(REMOVE_RECURSE
  "CMakeFiles/check_scene.dir/check_scene.f90.o"
  "CMakeFiles/check_scene.dir/check_support.f90.o"
  "check_scene"
  "check_scene.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang Fortran)
  include(CMakeFiles/check_scene.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
