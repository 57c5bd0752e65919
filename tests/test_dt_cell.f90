!> The cell that limits the time step (`lagrange_strain_rates` dt_cell):
!> on a box of identical cells (unit cubes: every cell's step is the same
!> number) it is cell 1, the lowest index of the tie; a single hot cell is
!> found wherever it is; of two equally hot cells the lower index wins; and
!> all of this with 1 and 2 OpenMP threads (the 2-thread run splits the
!> rows, so the tie is then between threads). The step itself does not
!> change with the thread count.
program test_dt_cell
  use base_kinds, only: wp, i8
  use base_errors, only: error_t
  use test_assert, only: check, check_summary
  use test_scene, only: ideal_gas_state
  use eos_factory, only: eos_params_t, eos_create
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_volume
  use material_table, only: material_t, material_index_cells, material_eval_eos
  use material_mixed, only: mixed_t
  use hydro_state, only: hydro_t, hydro_params_t, hydro_allocate, hydro_subcell_masses
  use lagrange_forces, only: lagrange_strain_rates
  !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads
  implicit none

  integer, parameter :: n = 8
  type(grid_t) :: g
  type(hydro_t) :: h
  type(material_t) :: mats(1)
  type(mixed_t) :: mx
  type(hydro_params_t) :: par
  real(wp) :: dt(2)
  integer :: cell(2), threads, nthreads0, hot1, hot2
  character(len=80) :: what

  nthreads0 = 1
  !$ nthreads0 = omp_get_max_threads()
  hot1 = g_cell(3, 7, 6)
  hot2 = g_cell(6, 2, 2)
  do threads = 1, 2
    !$ call omp_set_num_threads(threads)
    write(what, '(a,i0,a)') ' (', threads, ' thread(s))'
    call build([integer ::])
    call lagrange_strain_rates(g, g%x, h%u, h, par, dt(threads), cell(threads))
    call check(cell(threads) == 1, 'identical cells: the limiting cell is cell 1'//trim(what))
    call build([hot1])
    call lagrange_strain_rates(g, g%x, h%u, h, par, dt(threads), cell(threads))
    call check(cell(threads) == hot1, 'one hot cell is the limiting cell'//trim(what))
    call build([hot2, hot1])
    call lagrange_strain_rates(g, g%x, h%u, h, par, dt(threads), cell(threads))
    call check(cell(threads) == min(hot1, hot2), 'two equally hot cells: the lower index'//trim(what))
  end do
  call check(transfer(dt(1), 1_i8) == transfer(dt(2), 1_i8), 'the stable step is the same with 1 and 2 threads')
  !$ call omp_set_num_threads(nthreads0)
  call check_summary('test_dt_cell')

contains

  pure integer function g_cell(i, j, k)
    integer, intent(in) :: i, j, k
    g_cell = i + n*(j - 1) + n*n*(k - 1)
  end function g_cell

  !> A box [0,n]^3 of unit cubes (exact coordinates) of an ideal gas at rest,
  !> density 1, specific energy 1, except the cells `hot` (energy 4).
  subroutine build(hot)
    integer, intent(in) :: hot(:)
    type(error_t), allocatable :: err
    real(wp), allocatable :: e(:)
    integer :: c

    call grid_init_box(g, n, n, n, [0.0_wp, 0.0_wp, 0.0_wp], [real(n, wp), real(n, wp), real(n, wp)], err)
    call check(.not. allocated(err), 'grid_init_box')
    allocate(e(g%ncell))
    e = 1.0_wp
    do c = 1, g%ncell
      if (any(hot == c)) e(c) = 4.0_wp
    end do
    call ideal_gas_state(g, [(1.0_wp, c = 1, g%ncell)], e, h, mats, mx)
  end subroutine build
end program test_dt_cell
