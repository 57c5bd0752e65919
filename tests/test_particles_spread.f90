!> Unit tests of the particles' supports spread over the cells they overlap
!> (modules/particles/particles_spread, &hydro particle_support = 'gimp'):
!> a row of 6 x 1 x 1 unit cells holding particles two across in y and z
!> and, along x, compressed to a spacing s = 0.45 from x = 0.025, so that
!> cells hold two or three of them (the state linear shape functions see
!> after particles crossed faces at an Euler step).
!>  1. The seeding width: particles two per cell per direction in a box
!>     cell get half-width 1/4 (`particles_support_widths`).
!>  2. Each particle's pieces add up to one (round-off), and a piece lies in
!>     the host or a face neighbour.
!>  3. A linear field interpolated at the particles (`particles_interpolate`)
!>     is its value at the particle, to round-off (the mean of a linear field
!>     over a domain is its value at the centre).
!>  4. The crossing error: with the domains tiling the row (half-width s/2)
!>     a uniform stress gives no force at the interior nodes whose supports
!>     the domains cover (x = 2 .. 4: their integral of grad N_I vanishes) to round-off,
!>     where linear shape functions give a force of the order of the stress
!>     times the node's area (a cell with three particles next to one with
!>     two: sigma V (3 - 2) / h).
!>  5. The body's surface: in a row of 3 unit cells whose third hosts no
!>     particle, a domain that reaches into the first (which hosts one)
!>     spreads there, one that reaches into the third does not (no piece
!>     there: the particle keeps its point weights along x).
program test_particles_spread
  use base_kinds, only: wp
  use base_errors, only: error_t
  use mesh_grid, only: grid_t, grid_init_box
  use particles_state, only: particles_t, particles_allocate, particles_order
  use particles_spread, only: particles_spread_pieces, particles_support_widths
  use particles_lagrange, only: particles_nodal_force, particles_interpolate
  use base_strings, only: itoa, rtoa
  use test_assert, only: check, check_close, check_summary
  implicit none
  real(wp), parameter :: eps = epsilon(1.0_wp), s = 0.45_wp, sigma = -3.0_wp

  call test_width()
  call test_row()
  call test_surface()
  call check_summary('test_particles_spread')

contains

  !> Test 1: one cell, eight particles at its quarter points.
  subroutine test_width()
    type(grid_t) :: g
    type(particles_t) :: p
    type(error_t), allocatable :: err
    integer :: a
    call grid_init_box(g, 1, 1, 1, [0.0_wp, 0.0_wp, 0.0_wp], [2.0_wp, 2.0_wp, 2.0_wp], err)
    call particles_allocate(p, 8, 1, 0, err)
    do a = 1, 8
      p%xi(:, a) = 0.25_wp + 0.5_wp*real([ibits(a - 1, 0, 1), ibits(a - 1, 1, 1), ibits(a - 1, 2, 1)], wp)
    end do
    p%vol = 1.0_wp
    call particles_support_widths(g, p)
    call check_close('half-width of two particles per cell per direction', maxval(abs(p%lsup - 0.25_wp)), &
                     0.0_wp, 4*eps)
  end subroutine test_width

  !> Tests 2-4 on the row (module notes).
  subroutine test_row()
    type(grid_t) :: g
    type(particles_t) :: p
    type(error_t), allocatable :: err
    real(wp), allocatable :: f(:, :), fvf(:, :), u(:, :), zero(:, :), pc(:)
    real(wp) :: x, err_pu, err_lin, flin, fgimp, share
    integer :: nx, k, i, j, l, n, bad, q
    logical :: near
    nx = int((6.0_wp - 0.025_wp)/s)
    call grid_init_box(g, 6, 1, 1, [0.0_wp, 0.0_wp, 0.0_wp], [6.0_wp, 1.0_wp, 1.0_wp], err)
    call particles_allocate(p, 4*nx, 1, 0, err)
    call check(.not. allocated(err), 'row of particles')
    n = 0
    do i = 1, nx
      x = 0.025_wp + s*(real(i, wp) - 0.5_wp)
      do l = 0, 1
        do j = 0, 1
          n = n + 1
          p%x(:, n) = [x, 0.25_wp + 0.5_wp*j, 0.25_wp + 0.5_wp*l]
          p%cell(n) = int(x) + 1
          p%xi(:, n) = [x - int(x), p%x(2, n), p%x(3, n)]
        end do
      end do
    end do
    p%vol = 0.25_wp*s
    p%m = p%vol
    p%rho = 1.0_wp
    p%stress = 0.0_wp
    p%stress(1:3, :) = sigma
    allocate(f(3, g%nnode), fvf(3, g%nnode), u(3, g%nnode), zero(3, g%nnode), pc(g%ncell))
    pc = 0.0_wp
    zero = 0.0_wp
    ! linear shape functions first
    call particles_order(p, g%ncell, err)
    call particles_nodal_force(g, g%x, p, pc, f, fvf, bad)
    flin = interior_force(g, f)
    ! spread, the domains tiling the row along x
    p%spread = .true.
    p%lsup = 0.5_wp*s
    call particles_order(p, g%ncell, err)
    call particles_spread_pieces(g, p)
    err_pu = 0.0_wp
    near = .true.
    do k = 1, p%np
      share = 0.0_wp
      do q = p%pfirst(k), p%pfirst(k + 1) - 1
        share = share + p%pw(q)
        near = near .and. abs(p%pcell(q) - p%cell(k)) <= 1
      end do
      err_pu = max(err_pu, abs(share - 1.0_wp))
    end do
    call check(p%npc > p%np, 'some particles spread over two cells ('//itoa(p%npc)//' pieces of '// &
               itoa(p%np)//' particles)')
    call check_close('pieces of a particle add up to one', err_pu, 0.0_wp, 4*eps)
    call check(near, 'pieces lie in the host or a face neighbour')
    do n = 1, g%nnode
      u(:, n) = [1.5_wp + 0.7_wp*g%x(1, n) - 0.2_wp*g%x(2, n), 0.3_wp*g%x(3, n), -g%x(1, n)]
    end do
    err_lin = 0.0_wp
    do k = 1, p%np
      err_lin = max(err_lin, maxval(abs(particles_interpolate(g, p, k, u, zero) - &
                    [1.5_wp + 0.7_wp*p%x(1, k) - 0.2_wp*p%x(2, k), 0.3_wp*p%x(3, k), -p%x(1, k)])))
    end do
    call check_close('a linear field interpolated at the particles', err_lin, 0.0_wp, 64*eps)
    call particles_nodal_force(g, g%x, p, pc, f, fvf, bad)
    fgimp = interior_force(g, f)
    ! (a node's area is 1/4 of the section: sigma times it is 0.75)
    call check(flin > 0.1_wp*abs(sigma)*0.25_wp, 'linear: a force at the interior nodes of a uniform stress (' // &
               rtoa(flin)//')')
    call check_close('spread: no force at the interior nodes of a uniform stress', fgimp, 0.0_wp, &
                     64*eps*abs(sigma))
  end subroutine test_row

  !> Test 5 (module notes): particles at x = 0.75 (cell 1), 1.1 (cell 2,
  !> its domain reaching into cell 1) and 1.9 (cell 2, reaching into cell
  !> 3), four of each across y and z, half-width 1/4.
  subroutine test_surface()
    type(grid_t) :: g
    type(particles_t) :: p
    type(error_t), allocatable :: err
    real(wp), parameter :: xs(3) = [0.75_wp, 1.1_wp, 1.9_wp]
    integer :: i, j, l, n, q
    logical :: third, back, point
    call grid_init_box(g, 3, 1, 1, [0.0_wp, 0.0_wp, 0.0_wp], [3.0_wp, 1.0_wp, 1.0_wp], err)
    call particles_allocate(p, 12, 1, 0, err)
    call check(.not. allocated(err), 'three rows of particles')
    n = 0
    do i = 1, 3
      do l = 0, 1
        do j = 0, 1
          n = n + 1
          p%x(:, n) = [xs(i), 0.25_wp + 0.5_wp*j, 0.25_wp + 0.5_wp*l]
          p%cell(n) = int(xs(i)) + 1
          p%xi(:, n) = [xs(i) - int(xs(i)), p%x(2, n), p%x(3, n)]
        end do
      end do
    end do
    p%vol = 0.125_wp
    p%m = p%vol
    p%rho = 1.0_wp
    p%spread = .true.
    p%lsup = 0.25_wp
    call particles_order(p, g%ncell, err)
    call particles_spread_pieces(g, p)
    third = .false.
    back = .true.
    point = .true.
    do n = 1, p%np
      do q = p%pfirst(n), p%pfirst(n + 1) - 1
        third = third .or. p%pcell(q) == 3
      end do
      if (abs(p%x(1, n) - xs(2)) < 0.01_wp) back = back .and. p%pfirst(n + 1) - p%pfirst(n) == 2 .and. &
                                                any(p%pcell(p%pfirst(n):p%pfirst(n + 1) - 1) == 1)
      if (abs(p%x(1, n) - xs(3)) < 0.01_wp) point = point .and. p%pfirst(n + 1) - p%pfirst(n) == 1 .and. &
                                                 .not. abs(p%pw(p%pfirst(n)) - 1.0_wp) > 0.0_wp
    end do
    call check(back, 'a domain spreads into a neighbour that hosts a particle')
    call check(.not. third, 'no piece in a cell that hosts no particle')
    call check(point, 'a domain reaching into a cell that hosts no particle keeps its point weights')
  end subroutine test_surface

  !> max |f_x| over the row's nodes at x = 2 .. 4 (supports covered: the
  !> domains cover 0.025 < x < 5.875).
  real(wp) function interior_force(g, f) result(fmax)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: f(:, :)
    integer :: ii, jj, kk
    fmax = 0.0_wp
    do kk = 0, 1
      do jj = 0, 1
        do ii = 2, 4
          fmax = max(fmax, abs(f(1, g%node(ii, jj, kk))))
        end do
      end do
    end do
  end function interior_force
end program test_particles_spread
