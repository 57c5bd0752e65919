!> A hydro state built by hand for the unit tests of the Lagrangian kernels:
!> an ideal gas (gamma 1.4) filling a grid with given cell densities and
!> specific energies, at rest.
module test_scene
  use base_kinds, only: wp
  use base_errors, only: error_t
  use eos_factory, only: eos_params_t, eos_create
  use mesh_grid, only: grid_t
  use mesh_geometry, only: hex_volume
  use material_table, only: material_t, material_index_cells, material_eval_eos
  use material_mixed, only: mixed_t
  use hydro_state, only: hydro_t, hydro_allocate, hydro_subcell_masses
  use check_support, only: check_fail
  implicit none
  private
  public :: ideal_gas_state

contains

  !> h (re)allocated for g and filled with densities rho and specific
  !> energies e of the one material mats(1): volumes, masses, nodal masses
  !> (Eq. 16), pressures and sound speeds; velocities zero.
  subroutine ideal_gas_state(g, rho, e, h, mats, mx)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: rho(:), e(:)
    type(hydro_t), intent(inout) :: h
    type(material_t), intent(inout) :: mats(:)
    type(mixed_t), intent(inout) :: mx
    type(error_t), allocatable :: err
    type(eos_params_t) :: par
    real(wp) :: xn(3, 8)
    integer :: c

    if (allocated(h%u)) h = hydro_t()
    call hydro_allocate(h, g%ncell, g%nnode, err)
    if (allocated(err)) call check_fail('hydro_allocate: '//err%msg)
    par%gamma = 1.4_wp
    mats(1)%name = 'gas'
    call eos_create('ideal_gas', par, mats(1)%eos, err)
    if (allocated(err)) call check_fail('eos_create: '//err%msg)
    h%mat = 1
    call material_index_cells(mats, h%mat, mx, err)
    if (allocated(err)) call check_fail('material_index_cells: '//err%msg)
    do c = 1, g%ncell
      call g%gather(c, g%x, xn)
      h%vol(c) = hex_volume(xn)
      h%rho(c) = rho(c)
      h%e(c) = e(c)
      h%mass(c) = h%rho(c)*h%vol(c)
    end do
    call hydro_subcell_masses(g, g%x, h%rho, h%mnode, h%mcorner)
    call material_eval_eos(mats, h%rho, h%e, h%p, h%cs, mx)
    h%u = 0.0_wp
  end subroutine ideal_gas_state
end module test_scene
