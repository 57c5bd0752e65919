file(REMOVE_RECURSE
  "CMakeFiles/lsalepm_lib.dir/modules/base/base_errors.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/base/base_kinds.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/base/base_random.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/base/base_timers.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/eos/eos_base.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/eos/eos_factory.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/eos/eos_ideal_gas.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/io/io_gauges.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/io/io_hdf5.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/io/io_input.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/io/io_log.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/io/io_output.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/io/io_xdmf.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/lagrange/lagrange_forces.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/lagrange/lagrange_integrator.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/lagrange/lagrange_state.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/material/material_table.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/mesh/mesh_boundary.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/mesh/mesh_geometry.f90.o"
  "CMakeFiles/lsalepm_lib.dir/modules/mesh/mesh_grid.f90.o"
  "liblsalepm_lib.a"
  "liblsalepm_lib.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang Fortran)
  include(CMakeFiles/lsalepm_lib.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
