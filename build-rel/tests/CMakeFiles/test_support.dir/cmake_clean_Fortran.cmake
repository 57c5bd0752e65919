# Remove fortran modules provided by this target.
FILE(REMOVE
  "../mod/exact_riemann.mod"
  "../mod/EXACT_RIEMANN.mod"
  "CMakeFiles/test_support.dir/exact_riemann.mod.stamp"
  )
