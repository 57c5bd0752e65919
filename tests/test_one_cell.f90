!> The single-element set-up of the particle tests (issues 14 and 15): one
!> cell [0,1]^3 with eight particles at the quarter points, each of volume
!> 1/8 and density rho (default 1), stress zero, nhist history variables
!> (zero, or the model's hist_init), sorted and binned.
module test_one_cell
  use base_kinds, only: wp
  use base_errors, only: error_t
  use mesh_grid, only: grid_t, grid_init_box
  use particles_state, only: particles_t, particles_allocate, particles_order
  use strength_models, only: strength_t
  use test_assert, only: check
  implicit none
  private
  public :: one_cell

contains

  subroutine one_cell(g, p, nhist, rho, model)
    type(grid_t), intent(out) :: g
    type(particles_t), intent(out) :: p
    integer, intent(in) :: nhist
    real(wp), intent(in), optional :: rho
    class(strength_t), intent(in), optional :: model
    type(error_t), allocatable :: err
    integer :: a
    call grid_init_box(g, 1, 1, 1, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
    call particles_allocate(p, 8, 1, nhist, err)
    call check(.not. allocated(err), 'one cell, eight particles')
    do a = 1, 8
      p%xi(:, a) = 0.25_wp + 0.5_wp*real([ibits(a - 1, 0, 1), ibits(a - 1, 1, 1), ibits(a - 1, 2, 1)], wp)
      p%x(:, a) = p%xi(:, a)
      if (present(model)) call model%hist_init(p%hist(:, a))
    end do
    p%cell = 1
    p%vol = 0.125_wp
    p%rho = 1.0_wp
    if (present(rho)) p%rho = rho
    p%m = 0.125_wp*p%rho
    call particles_order(p, g%ncell, err)
  end subroutine one_cell
end module test_one_cell
