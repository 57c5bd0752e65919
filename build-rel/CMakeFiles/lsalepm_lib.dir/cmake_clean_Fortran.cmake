# Remove fortran modules provided by this target.
FILE(REMOVE
  "mod/base_errors.mod"
  "mod/BASE_ERRORS.mod"
  "CMakeFiles/lsalepm_lib.dir/base_errors.mod.stamp"

  "mod/base_kinds.mod"
  "mod/BASE_KINDS.mod"
  "CMakeFiles/lsalepm_lib.dir/base_kinds.mod.stamp"

  "mod/base_random.mod"
  "mod/BASE_RANDOM.mod"
  "CMakeFiles/lsalepm_lib.dir/base_random.mod.stamp"

  "mod/base_timers.mod"
  "mod/BASE_TIMERS.mod"
  "CMakeFiles/lsalepm_lib.dir/base_timers.mod.stamp"

  "mod/eos_base.mod"
  "mod/EOS_BASE.mod"
  "CMakeFiles/lsalepm_lib.dir/eos_base.mod.stamp"

  "mod/eos_factory.mod"
  "mod/EOS_FACTORY.mod"
  "CMakeFiles/lsalepm_lib.dir/eos_factory.mod.stamp"

  "mod/eos_ideal_gas.mod"
  "mod/EOS_IDEAL_GAS.mod"
  "CMakeFiles/lsalepm_lib.dir/eos_ideal_gas.mod.stamp"

  "mod/io_gauges.mod"
  "mod/IO_GAUGES.mod"
  "CMakeFiles/lsalepm_lib.dir/io_gauges.mod.stamp"

  "mod/io_hdf5.mod"
  "mod/IO_HDF5.mod"
  "CMakeFiles/lsalepm_lib.dir/io_hdf5.mod.stamp"

  "mod/io_input.mod"
  "mod/IO_INPUT.mod"
  "CMakeFiles/lsalepm_lib.dir/io_input.mod.stamp"

  "mod/io_log.mod"
  "mod/IO_LOG.mod"
  "CMakeFiles/lsalepm_lib.dir/io_log.mod.stamp"

  "mod/io_output.mod"
  "mod/IO_OUTPUT.mod"
  "CMakeFiles/lsalepm_lib.dir/io_output.mod.stamp"

  "mod/io_xdmf.mod"
  "mod/IO_XDMF.mod"
  "CMakeFiles/lsalepm_lib.dir/io_xdmf.mod.stamp"

  "mod/lagrange_forces.mod"
  "mod/LAGRANGE_FORCES.mod"
  "CMakeFiles/lsalepm_lib.dir/lagrange_forces.mod.stamp"

  "mod/lagrange_integrator.mod"
  "mod/LAGRANGE_INTEGRATOR.mod"
  "CMakeFiles/lsalepm_lib.dir/lagrange_integrator.mod.stamp"

  "mod/lagrange_state.mod"
  "mod/LAGRANGE_STATE.mod"
  "CMakeFiles/lsalepm_lib.dir/lagrange_state.mod.stamp"

  "mod/material_table.mod"
  "mod/MATERIAL_TABLE.mod"
  "CMakeFiles/lsalepm_lib.dir/material_table.mod.stamp"

  "mod/mesh_boundary.mod"
  "mod/MESH_BOUNDARY.mod"
  "CMakeFiles/lsalepm_lib.dir/mesh_boundary.mod.stamp"

  "mod/mesh_geometry.mod"
  "mod/MESH_GEOMETRY.mod"
  "CMakeFiles/lsalepm_lib.dir/mesh_geometry.mod.stamp"

  "mod/mesh_grid.mod"
  "mod/MESH_GRID.mod"
  "CMakeFiles/lsalepm_lib.dir/mesh_grid.mod.stamp"
  )
