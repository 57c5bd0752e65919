!> Unit tests of the global rezone's target (`rezone_global`): the initial
!> grid bit for bit when no face moves; a piston face kept where it is and
!> its displacement carried into the block by TFI (exactly linear along
!> straight lines, symmetry planes and walls kept); valid cells for an
!> uneven piston on a perturbed grid and for two moving faces that meet; a
!> piston past the far side refused.
program test_rezone_global
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use test_assert, only: check, check_summary
  use mesh_grid, only: grid_index_t, grid_index, block_gather
  use mesh_geometry, only: hex_volume
  use mesh_boundary, only: BC_SYMMETRY, BC_WALL, BC_VELOCITY, BC_PRESSURE, BC_INFLOW, BC_OUTFLOW
  use rezone_global, only: global_target, global_face_rule, GLOBAL_FACE_SLIDE, GLOBAL_FACE_FIX, GLOBAL_FACE_MOVE
  implicit none
  integer, parameter :: ni = 8, nj = 5, nk = 4, nn = (ni + 1)*(nj + 1)*(nk + 1)
  real(wp), parameter :: len(3) = [2.0_wp, 1.0_wp, 1.0_wp]
  integer, parameter :: S = GLOBAL_FACE_SLIDE, F = GLOBAL_FACE_FIX, M = GLOBAL_FACE_MOVE
  type(grid_index_t) :: ix
  real(wp) :: x0(3, nn), x(3, nn), xt(3, nn), e_lin, e_tan, dxy
  type(error_t), allocatable :: err
  integer :: i, j, k, n, nmove
  logical :: ok

  ix = grid_index(ni, nj, nk)

  ! 0. the rules of the boundary kinds
  call check(global_face_rule(BC_VELOCITY) == M .and. global_face_rule(BC_PRESSURE) == M, &
             'velocity and pressure faces move with the material')
  call check(global_face_rule(BC_WALL) == F, 'walls are fixed')
  call check(global_face_rule(BC_SYMMETRY) == S .and. global_face_rule(BC_INFLOW) == S .and. &
             global_face_rule(BC_OUTFLOW) == S, 'symmetry and open faces slide')

  ! 1. no moving face: the initial grid, bit for bit
  call box(x0, 0.0_wp, 1)
  call box(x, 0.3_wp, 2)
  call global_target(ni, nj, nk, [S, F, S, S, F, S], x0, x, xt, nmove, err)
  call check(.not. allocated(err) .and. nmove == 0, 'no moving face: no error, no node kept')
  call check(same(xt, x0), 'no moving face: the target is the initial grid bit for bit')

  ! 2. a piston (xlo) moved by 0.5 on a uniform box, y and z symmetry, a wall
  ! at xhi; the interior of the Lagrangian grid perturbed (the target must
  ! not depend on it)
  call box(x, 0.3_wp, 3)
  do k = 0, nk
    do j = 0, nj
      n = ix%node(0, j, k)
      x(:, n) = x0(:, n) + [0.5_wp, 0.0_wp, 0.0_wp]
    end do
  end do
  call global_target(ni, nj, nk, [M, F, S, S, S, S], x0, x, xt, nmove, err)
  call check(.not. allocated(err) .and. nmove == (nj + 1)*(nk + 1), 'piston: no error, its face''s nodes kept')
  ok = .true.
  e_lin = 0.0_wp
  e_tan = 0.0_wp
  do k = 0, nk
    do j = 0, nj
      do i = 0, ni
        n = ix%node(i, j, k)
        if (i == 0) ok = ok .and. same(xt(:, n:n), x(:, n:n))
        if (i == ni) ok = ok .and. same(xt(:, n:n), x0(:, n:n))
        ! exactly linear: each cell keeps (1 - d/L) of its length
        e_lin = max(e_lin, abs(xt(1, n) - (x0(1, n) + 0.5_wp*(1.0_wp - x0(1, n)/len(1)))))
        e_tan = max(e_tan, maxval(abs(xt(2:3, n) - x0(2:3, n))))
      end do
    end do
  end do
  write(*, '(a,es10.3,a,es10.3)') 'piston: largest departure from the linear compression ', e_lin, &
    ', largest tangential move ', e_tan
  call check(ok, 'piston: its face where the Lagrangian step put it, the wall at its initial place, bit for bit')
  call check(e_lin < 1.0e-14_wp, 'piston: the block compressed linearly in front of it (1e-14)')
  call check(.not. e_tan > 0.0_wp, 'piston: no tangential move (symmetry planes kept exactly)')
  call check(all_valid(xt), 'piston: every cell valid')

  ! 3. an uneven piston on a perturbed initial grid: face nodes displaced
  ! by 0.3 to 0.7 in x (edges on the y and z symmetry planes stay in them)
  call box(x0, 0.25_wp, 4)
  call box(x, 0.25_wp, 5)
  do k = 0, nk
    do j = 0, nj
      n = ix%node(0, j, k)
      x(:, n) = x0(:, n)
      x(1, n) = x0(1, n) + 0.5_wp + 0.2_wp*sin(2.0_wp*x0(2, n) + 3.0_wp*x0(3, n))
      if (j > 0 .and. j < nj .and. k > 0 .and. k < nk) x(2, n) = x0(2, n) + 0.05_wp*cos(3.0_wp*x0(3, n))
    end do
  end do
  call global_target(ni, nj, nk, [M, S, S, S, S, S], x0, x, xt, nmove, err)
  call check(.not. allocated(err), 'uneven piston: no error')
  call check(all_valid(xt), 'uneven piston on a perturbed grid: every cell valid')
  ok = .true.
  dxy = 0.0_wp
  do k = 0, nk
    do j = 0, nj
      do i = 0, ni
        n = ix%node(i, j, k)
        if (i == 0) ok = ok .and. same(xt(:, n:n), x(:, n:n))
        ! slide faces keep their normal coordinate exactly
        if (i == ni) ok = ok .and. .not. abs(xt(1, n) - x0(1, n)) > 0.0_wp
        if (i > 0 .and. (j == 0 .or. j == nj)) ok = ok .and. .not. abs(xt(2, n) - x0(2, n)) > 0.0_wp
        if (i > 0 .and. (k == 0 .or. k == nk)) ok = ok .and. .not. abs(xt(3, n) - x0(3, n)) > 0.0_wp
        if (i > 0) dxy = max(dxy, abs(xt(1, n) - x0(1, n)))
      end do
    end do
  end do
  call check(ok, 'uneven piston: its face kept, the other faces in their planes, bit for bit')
  call check(dxy > 0.3_wp .and. dxy < 0.7_wp, 'uneven piston: the interior follows it')

  ! 4. two moving faces that meet (a piston at xlo, a free surface at yhi)
  call box(x0, 0.0_wp, 1)
  call box(x, 0.0_wp, 1)
  do k = 0, nk
    do j = 0, nj
      do i = 0, ni
        n = ix%node(i, j, k)
        ! (the free surface's nodes compressed along x with the piston, as
        ! a Lagrangian step would leave them, and lifted)
        if (i == 0 .or. j == nj) x(1, n) = x(1, n) + 0.4_wp*(1.0_wp - x0(1, n)/len(1))
        if (j == nj) x(2, n) = x(2, n) + 0.2_wp*(1.0_wp - x0(1, n)/len(1))
      end do
    end do
  end do
  call global_target(ni, nj, nk, [M, F, S, M, S, S], x0, x, xt, nmove, err)
  call check(.not. allocated(err) .and. all_valid(xt), 'piston and free surface: no error, every cell valid')
  ok = .true.
  do k = 0, nk
    do j = 0, nj
      do i = 0, ni
        n = ix%node(i, j, k)
        if (i == 0 .or. j == nj) ok = ok .and. same(xt(:, n:n), x(:, n:n))
      end do
    end do
  end do
  call check(ok, 'piston and free surface: both faces kept bit for bit')

  ! 5. a piston past the far side: refused
  call box(x0, 0.0_wp, 1)
  x = x0
  do k = 0, nk
    do j = 0, nj
      x(1, ix%node(0, j, k)) = 2.5_wp
    end do
  end do
  call global_target(ni, nj, nk, [M, F, S, S, S, S], x0, x, xt, nmove, err)
  call check(allocated(err), 'a piston past the far side: an error')
  if (allocated(err)) write(*, '(a)') 'message: '//err%msg

  call check_summary('test_rezone_global')

contains

  !> The box [0,len] with interior nodes moved randomly by up to amp of a cell.
  subroutine box(xb, amp, seed)
    real(wp), intent(out) :: xb(3, nn)
    real(wp), intent(in) :: amp
    integer, intent(in) :: seed
    type(rng_t) :: rng
    real(wp) :: hh(3)
    integer :: ii, jj, kk, d
    hh = len/real([ni, nj, nk], wp)
    call rng_seed(rng, seed)
    do kk = 0, nk
      do jj = 0, nj
        do ii = 0, ni
          xb(:, ix%node(ii, jj, kk)) = hh*real([ii, jj, kk], wp)
          if (ii > 0 .and. ii < ni .and. jj > 0 .and. jj < nj .and. kk > 0 .and. kk < nk) then
            do d = 1, 3
              xb(d, ix%node(ii, jj, kk)) = xb(d, ix%node(ii, jj, kk)) + amp*hh(d)*(2.0_wp*rng_uniform(rng) - 1.0_wp)
            end do
          end if
        end do
      end do
    end do
  end subroutine box

  !> a and b equal bit for bit (as reals: -0 equals 0).
  pure logical function same(a, b)
    real(wp), intent(in) :: a(:, :), b(:, :)
    same = .not. any(abs(a - b) > 0.0_wp)
  end function same

  !> Every cell of xb has positive volume.
  logical function all_valid(xb)
    real(wp), intent(in) :: xb(3, nn)
    real(wp) :: xn(3, 8)
    integer :: ii, jj, kk
    all_valid = .true.
    do kk = 1, nk
      do jj = 1, nj
        do ii = 1, ni
          call block_gather(ni, nj, ii, jj, kk, xb, xn)
          all_valid = all_valid .and. hex_volume(xn) > 0.0_wp
        end do
      end do
    end do
  end function all_valid
end program test_rezone_global
