# Remove fortran modules provided by this target.
FILE(REMOVE
  "../mod/check_support.mod"
  "../mod/CHECK_SUPPORT.mod"
  "CMakeFiles/check_scene.dir/check_support.mod.stamp"
  )
