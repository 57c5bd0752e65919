!> Order of accuracy of the nodal velocity remap (`remap_euler`): a smooth
!> velocity on a uniform grid, remapped to a smoothly displaced grid (interior
!> nodes moved by up to 0.0375 at every resolution), against the field at
!> the new nodes.
!> The velocity linear about each node makes the error second order in the
!> cell size (piecewise constant in subcells it was first order: each node
!> took a mean of its old neighbours' velocities over what the move swept).
!> Also conservation of momentum and total energy to round-off, and (`warped`)
!> on a new cell warped so far that a corner's share of its volume is
!> negative (a first part of the way of a smoothing's Euler step met one:
!> its corner mass came out negative, the nodal kinetic energy's sums
!> skipped it, and the step lost 5e-10 of the energy it remapped).
program test_remap_velocity
  use base_kinds, only: wp
  use base_errors, only: error_t
  use test_assert, only: check, check_summary
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_volume, hex_subcell_volumes
  use mesh_boundary, only: bc_t
  use material_mixed, only: mixed_t
  use mesh_halo, only: halo_t
  use hydro_state, only: hydro_t, hydro_allocate, hydro_totals, hydro_subcell_masses
  use remap_euler, only: remap_params_t, remap_stats_t, remap_euler_step
  implicit none
  real(wp), parameter :: pi = acos(-1.0_wp)
  integer, parameter :: sizes(3) = [8, 16, 32]
  real(wp) :: errs(3), cons(2), order
  integer :: r

  do r = 1, 3
    call run(sizes(r), errs(r), cons)
    write(*, '(a,i3,a,es10.3,a,2es10.2)') 'N = ', sizes(r), ': largest velocity error at an interior node ', &
      errs(r), '; relative change of momentum, total energy ', cons
    call check(cons(1) < 1e-13_wp .and. cons(2) < 1e-13_wp, 'momentum and total energy conserved to 1e-13')
  end do
  call warped()
  order = log(errs(2)/errs(3))/log(2.0_wp)
  write(*, '(a,f6.2,a,f6.2)') 'observed order: 8 -> 16 ', log(errs(1)/errs(2))/log(2.0_wp), ', 16 -> 32 ', order
  ! second order (2) against first (1): 1.7 leaves room for the limiter at
  ! the extrema of the field
  call check(order > 1.7_wp, 'nodal velocity remap is second order')
  call check_summary('test_remap_velocity')

contains

  !> The velocity at x.
  pure function field(x) result(u)
    real(wp), intent(in) :: x(3)
    real(wp) :: u(3)
    u = [sin(pi*x(1))*cos(0.5_wp*pi*x(2)), 0.5_wp*cos(pi*x(1)*x(2)), 0.0_wp]
  end function field

  !> Remaps the field from the uniform n x n x 1 grid of [0,1]^2 x [0,1/n]
  !> to the displaced one; err: the largest error at nodes two cells from
  !> the boundary, cons: relative change of momentum and total energy.
  subroutine run(n, err_max, cons)
    integer, intent(in) :: n
    real(wp), intent(out) :: err_max, cons(2)
    type(grid_t) :: g
    type(hydro_t) :: h
    type(error_t), allocatable :: err
    real(wp), allocatable :: xnew(:, :), rho(:)
    real(wp) :: hh
    integer :: k, i, j, kk

    hh = 1.0_wp/n
    call grid_init_box(g, n, n, 1, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, hh], err)
    allocate(rho(g%ncell), source=1.0_wp)
    call gas(g, h, rho)
    do k = 1, g%nnode
      h%u(:, k) = field(g%x(:, k))
    end do
    ! interior nodes moved smoothly (x and y) by up to 0.0375, whatever the
    ! cell size (0.3 of a cell at N = 8, 1.2 cells at N = 32): with a move
    ! that shrank with the cells both orders would look alike
    xnew = g%x
    do kk = 0, 1
      do j = 1, n - 1
        do i = 1, n - 1
          k = g%node(i, j, kk)
          xnew(1:2, k) = g%x(1:2, k) + 0.0375_wp*sin(2.0_wp*pi*g%x(1, k))*sin(pi*g%x(2, k))*[1.0_wp, 0.7_wp]
        end do
      end do
    end do
    call remap_changes(g, h, xnew, cons)
    err_max = 0.0_wp
    do kk = 0, 1
      do j = 2, n - 2
        do i = 2, n - 2
          k = g%node(i, j, kk)
          err_max = max(err_max, maxval(abs(h%u(:, k) - field(g%x(:, k)))))
        end do
      end do
    end do
  end subroutine run

  !> The 2 x 2 x 2 unit cells of [0,2]^3, a non-uniform velocity, the centre
  !> node moved by 0.6 along the diagonal: past the centre of the cell
  !> [1,2]^3, whose corner there then has a share of -0.0063 of its volume
  !> (`hex_subcell_volumes`); every corner mass after the remap must be
  !> positive, and momentum and total energy conserved to round-off.
  subroutine warped()
    type(grid_t) :: g
    type(hydro_t) :: h
    type(error_t), allocatable :: err
    real(wp), allocatable :: xnew(:, :)
    real(wp) :: xn(3, 8), vs(8), cons(2)
    integer :: c, k, centre

    call grid_init_box(g, 2, 2, 2, [0.0_wp, 0.0_wp, 0.0_wp], [2.0_wp, 2.0_wp, 2.0_wp], err)
    call gas(g, h, [(1.0_wp + 0.1_wp*c, c = 1, g%ncell)])
    do k = 1, g%nnode
      h%u(:, k) = [g%x(2, k)**2, -g%x(1, k), 0.5_wp*g%x(3, k)*g%x(1, k)]
    end do
    centre = g%node(1, 1, 1)
    xnew = g%x
    xnew(:, centre) = g%x(:, centre) + 0.6_wp
    call g%gather(g%cell(2, 2, 2), xnew, xn)
    call hex_subcell_volumes(xn, vs)
    call check(minval(vs) < 0.0_wp .and. hex_volume(xn) > 0.0_wp, 'warped: a corner''s share is negative')
    call remap_changes(g, h, xnew, cons)
    write(*, '(a,2es10.2)') 'warped: relative change of momentum, total energy ', cons
    call check(all(h%mcorner > 0.0_wp), 'warped: every corner mass positive')
    call check(cons(1) < 1e-13_wp .and. cons(2) < 1e-13_wp, 'warped: momentum and total energy conserved to 1e-13')
  end subroutine warped

  !> A gas of density rho(c) and specific internal energy 1 on the grid g
  !> (velocities for the caller to set), with its corner masses (Eq. 16).
  subroutine gas(g, h, rho)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(out) :: h
    real(wp), intent(in) :: rho(:)
    type(error_t), allocatable :: err
    real(wp) :: xn(3, 8)
    integer :: c
    call hydro_allocate(h, g%ncell, g%nnode, err)
    h%mat = 1
    h%e = 1.0_wp
    do c = 1, g%ncell
      call g%gather(c, g%x, xn)
      h%vol(c) = hex_volume(xn)
      h%rho(c) = rho(c)
      h%mass(c) = rho(c)*h%vol(c)
    end do
    call hydro_subcell_masses(g, g%x, h%rho, h%mnode, h%mcorner)
  end subroutine gas

  !> Remaps h from the grid g to xnew (g moves there); cons: the relative
  !> change of momentum and of total energy.
  subroutine remap_changes(g, h, xnew, cons)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: xnew(:, :)
    real(wp), intent(out) :: cons(2)
    type(mixed_t) :: mx
    type(bc_t) :: bc
    type(remap_params_t) :: par
    type(remap_stats_t) :: st
    type(error_t), allocatable :: err
    real(wp) :: m0, p0(3), ie0, ke0, m1, p1(3), ie1, ke1
    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    call remap_euler_step(g, h, mx, 1, bc, xnew, par, st, err)
    call check(.not. allocated(err), 'remap runs')
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    cons = [norm2(p1 - p0)/norm2(p0), abs(ie1 + ke1 - ie0 - ke0)/(ie0 + ke0)]
  end subroutine remap_changes
end program test_remap_velocity
