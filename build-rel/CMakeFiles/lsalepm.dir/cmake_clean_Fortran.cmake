# Remove fortran modules provided by this target.
FILE(REMOVE
  "mod/driver.mod"
  "mod/DRIVER.mod"
  "CMakeFiles/lsalepm.dir/driver.mod.stamp"
  )
