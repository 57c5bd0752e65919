
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  "Fortran"
  )
# The set of files for implicit dependencies of each language:
set(CMAKE_DEPENDS_CHECK_Fortran
  "/work/main/modules/base/base_errors.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/base/base_errors.f90.o"
  "/work/main/modules/base/base_kinds.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/base/base_kinds.f90.o"
  "/work/main/modules/base/base_random.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/base/base_random.f90.o"
  "/work/main/modules/base/base_timers.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/base/base_timers.f90.o"
  "/work/main/modules/eos/eos_base.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/eos/eos_base.f90.o"
  "/work/main/modules/eos/eos_factory.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/eos/eos_factory.f90.o"
  "/work/main/modules/eos/eos_ideal_gas.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/eos/eos_ideal_gas.f90.o"
  "/work/main/modules/io/io_gauges.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/io/io_gauges.f90.o"
  "/work/main/modules/io/io_hdf5.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/io/io_hdf5.f90.o"
  "/work/main/modules/io/io_input.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/io/io_input.f90.o"
  "/work/main/modules/io/io_log.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/io/io_log.f90.o"
  "/work/main/modules/io/io_output.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/io/io_output.f90.o"
  "/work/main/modules/io/io_xdmf.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/io/io_xdmf.f90.o"
  "/work/main/modules/lagrange/lagrange_forces.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/lagrange/lagrange_forces.f90.o"
  "/work/main/modules/lagrange/lagrange_integrator.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/lagrange/lagrange_integrator.f90.o"
  "/work/main/modules/lagrange/lagrange_state.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/lagrange/lagrange_state.f90.o"
  "/work/main/modules/material/material_table.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/material/material_table.f90.o"
  "/work/main/modules/mesh/mesh_boundary.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/mesh/mesh_boundary.f90.o"
  "/work/main/modules/mesh/mesh_geometry.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/mesh/mesh_geometry.f90.o"
  "/work/main/modules/mesh/mesh_grid.f90" "/work/main/build-rel/CMakeFiles/lsalepm_lib.dir/modules/mesh/mesh_grid.f90.o"
  )
set(CMAKE_Fortran_COMPILER_ID "GNU")
set(CMAKE_Fortran_SUBMODULE_SEP "@")
set(CMAKE_Fortran_SUBMODULE_EXT ".smod")

# The include file search paths:
set(CMAKE_Fortran_TARGET_INCLUDE_PATH
  "/usr/include/hdf5/serial"
  "mod"
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "/work/main/build-rel/mod")
