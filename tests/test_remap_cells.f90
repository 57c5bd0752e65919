!> Unit tests of the cell remap: overlaps partition both grids, constant and
!> linear density fields are remapped exactly, totals are conserved.
program test_remap_cells
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use base_timers, only: wall_seconds
  use test_assert, only: check, check_summary
  use remap_cells, only: overlap_t, remap_overlaps, remap_density, cell_moments
  implicit none
  integer, parameter :: ni = 6, nj = 5, nk = 4, nc = ni*nj*nk, nn = (ni + 1)*(nj + 1)*(nk + 1)
  real(wp) :: xa(3, nn), xb(3, nn), va(nc), vb(nc), ca(3, nc), cb(3, nc), q(nc), g(3, nc), rho(nc)
  real(wp) :: per_old(nc), lin(4), t0, t1, err_max
  type(overlap_t) :: ov
  type(error_t), allocatable :: err
  integer :: c, k

  call make_grid(xa, 11)
  call make_grid(xb, 23)
  call cell_moments(ni, nj, nk, xa, va, ca)
  call cell_moments(ni, nj, nk, xb, vb, cb)
  t0 = wall_seconds()
  call remap_overlaps(ni, nj, nk, xa, xb, 1, ov, err)
  t1 = wall_seconds()
  call check(.not. allocated(err), 'overlaps computed')
  write(*, '(a,f9.2,a)') 'overlaps: ', 1.0e6_wp*(t1 - t0)/nc, ' us per new cell (this build)'

  ! every new cell is covered exactly, every old cell is used exactly once
  per_old = 0.0_wp
  err_max = 0.0_wp
  do c = 1, nc
    err_max = max(err_max, abs(sum(ov%vol(1:ov%count(c), c)) - vb(c))/vb(c))
    do k = 1, ov%count(c)
      per_old(ov%old(k, c)) = per_old(ov%old(k, c)) + ov%vol(k, c)
    end do
  end do
  write(*, '(a,es10.3)') 'largest relative gap in a new cell: ', err_max
  call check(err_max < 1e-13_wp, 'the overlaps of each new cell add up to it')
  call check(maxval(abs(per_old - va)/va) < 1e-13_wp, 'the overlaps of each old cell add up to it')

  ! a constant density is remapped exactly
  g = 0.0_wp
  rho = 2.5_wp
  call remap_density(ov, rho, g, ca, q)
  call check(maxval(abs(q/vb - 2.5_wp)) < 1e-13_wp, 'constant density remapped exactly')

  ! a linear density with its exact gradient: the new cell means are exact
  lin = [1.0_wp, 0.3_wp, -0.7_wp, 1.9_wp]
  do c = 1, nc
    rho(c) = lin(1) + dot_product(lin(2:4), ca(:, c))
    g(:, c) = lin(2:4)
  end do
  call remap_density(ov, rho, g, ca, q)
  err_max = 0.0_wp
  do c = 1, nc
    err_max = max(err_max, abs(q(c)/vb(c) - (lin(1) + dot_product(lin(2:4), cb(:, c)))))
  end do
  write(*, '(a,es10.3)') 'linear field, largest error of a new cell mean: ', err_max
  call check(err_max < 1e-12_wp, 'linear density remapped exactly')
  call check(abs(sum(q) - dot_product(rho, va))/dot_product(rho, va) < 1e-13_wp, 'total conserved')

  call check_summary('test_remap_cells')

contains

  !> A grid on [0,1.2]x[0,1]x[0,0.8] with interior nodes moved randomly by up
  !> to 0.2 of a cell (boundary nodes fixed, so both grids cover one box).
  subroutine make_grid(x, seed)
    real(wp), intent(out) :: x(3, nn)
    integer, intent(in) :: seed
    type(rng_t) :: rng
    integer :: i, j, kk, n, d
    real(wp) :: h(3)
    h = [1.2_wp/ni, 1.0_wp/nj, 0.8_wp/nk]
    call rng_seed(rng, seed)
    do kk = 0, nk
      do j = 0, nj
        do i = 0, ni
          n = 1 + i + (ni + 1)*(j + (nj + 1)*kk)
          x(:, n) = h*real([i, j, kk], wp)
          if (i > 0 .and. i < ni .and. j > 0 .and. j < nj .and. kk > 0 .and. kk < nk) then
            do d = 1, 3
              x(d, n) = x(d, n) + 0.4_wp*h(d)*(rng_uniform(rng) - 0.5_wp)
            end do
          end if
        end do
      end do
    end do
  end subroutine make_grid
end program test_remap_cells
