!> Unit tests of the limited least-squares gradients (remap_gradient): linear
!> fields are exact, several fields at once equal one at a time, a step stays
!> in its neighbours' bounds, thin grids give no NaN, cells without the
!> quantity are never read, cells not needed are left alone, and the result does not
!> depend on the thread count. Also prints the cost per cell on a 40^3 grid.
program test_remap_gradient
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  !$ use omp_lib, only: omp_get_max_threads, omp_set_num_threads
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use base_timers, only: wall_seconds
  use mesh_grid, only: block_gather
  use geometry_cells, only: cell_moments
  use remap_gradient, only: remap_limited_gradients
  use test_assert, only: check, check_summary
  implicit none
  integer, parameter :: ni = 6, nj = 5, nk = 4, nc = ni*nj*nk, nn = (ni + 1)*(nj + 1)*(nk + 1)
  real(wp) :: x(3, nn), vol(nc), cen(3, nc), q(2, nc), grad(3, 2, nc), gneed(3, 2, nc), g1(3, 1, nc), g2(3, 1, nc)
  real(wp) :: qa(1, nc), qb(1, nc), posa(3, nc), posb(3, nc), ga(3, 1, nc), gb(3, 1, nc)
  real(wp) :: lin(4), err_max, xn(3, 8), qn, qmin, qmax, scale, overshoot
  logical :: has(nc), need(nc), all_has(nc), ok
  type(error_t), allocatable :: err
  type(rng_t) :: rng
  integer :: c, ci, cj, ck, a, co, oi, oj, ok_, nthreads

  call make_grid(ni, nj, nk, x, 11)
  call cell_moments(ni, nj, nk, x, vol, cen)
  all_has = .true.

  ! 1. A linear field sampled at the centroids: least squares reproduces it
  ! exactly (zero residual), so grad = b up to round-off (~1e-15 times the
  ! conditioning of a 26x3 system of unit rows; 1e-12 leaves a wide margin).
  ! Only cells whose 26 neighbours all exist are checked: a boundary cell's
  ! outer nodes lie outside the hull of its neighbours' centroids, so a
  ! linear field exceeds the neighbourhood's range there and the limiter
  ! rightly scales the gradient down. In interior cells every node lies
  ! inside the hull of the 8 centroids around it, so phi = 1.
  lin = [1.0_wp, 0.3_wp, -0.7_wp, 1.9_wp]
  do c = 1, nc
    q(1, c) = lin(1) + dot_product(lin(2:4), cen(:, c))
    ! a jump of 2 across x = 0.55 on a ramp of slope 0.5, used below (a
    ! pure two-valued step would be limited to zero gradient everywhere,
    ! every cell being a local extreme of its neighbourhood)
    q(2, c) = merge(1.0_wp, 3.0_wp, cen(1, c) < 0.55_wp) + 0.5_wp*cen(1, c)
  end do
  call remap_limited_gradients(ni, nj, nk, x, q(1:1, :), cen, all_has, all_has, g1, err)
  call check(.not. allocated(err), 'linear field: no error')
  err_max = 0.0_wp
  do ck = 2, nk - 1
    do cj = 2, nj - 1
      do ci = 2, ni - 1
        c = ci + ni*((cj - 1) + nj*(ck - 1))
        err_max = max(err_max, maxval(abs(g1(:, 1, c) - lin(2:4))))
      end do
    end do
  end do
  write(*, '(a,es10.3)') 'linear field, largest gradient error in interior cells: ', err_max
  call check(err_max < 1e-12_wp, 'linear field: exact unlimited gradient in interior cells')

  ! 2. Two fields at once equal one at a time. Same arithmetic on the same
  ! geometry matrix; LAPACK may apply the SVD to one or two right-hand sides
  ! through different BLAS kernels (gemv vs gemm), so allow round-off:
  ! 1e-13 relative to the largest gradient (about 2 here, the step's ~20).
  call remap_limited_gradients(ni, nj, nk, x, q, cen, all_has, all_has, grad, err)
  call remap_limited_gradients(ni, nj, nk, x, q(2:2, :), cen, all_has, all_has, g2, err)
  call check(.not. allocated(err), 'two fields: no error')
  call check(maxval(abs(grad(:, 1, :) - g1(:, 1, :))) <= 1e-13_wp*maxval(abs(g1)), &
             'two fields at once: the first equals its own run')
  call check(maxval(abs(grad(:, 2, :) - g2(:, 1, :))) <= 1e-13_wp*maxval(abs(g2)), &
             'two fields at once: the second equals its own run')
  ! The limiter must cut the jump, not zero everything: next to it some cell
  ! keeps a slope well above the ramp's 0.5 (measured 0.98; 0.75 asserted),
  ! and away from it the ramp is kept exactly.
  write(*, '(a,f8.4)') 'step field, steepest limited x-gradient: ', maxval(abs(g2(1, 1, :)))
  call check(maxval(abs(g2(1, 1, :))) > 0.75_wp, 'step field: steeper-than-ramp gradients next to the jump')
  ! (interior cells ci = 2 and 5 at cj = ck = 2: centroids within 0.04 of
  ! the lattice's, so their neighbourhoods lie on one side of x = 0.55)
  call check(maxval(abs(g2(:, 1, 2 + ni*(1 + nj)) - [0.5_wp, 0.0_wp, 0.0_wp])) < 1e-12_wp .and. &
             maxval(abs(g2(:, 1, 5 + ni*(1 + nj)) - [0.5_wp, 0.0_wp, 0.0_wp])) < 1e-12_wp, &
             'step field: the ramp kept away from the jump')

  ! 3. The step: at every node of every cell the limited reconstruction lies
  ! in [qmin, qmax] of the cell and its 26 neighbours. The limiter ignores
  ! node deviations below 1e-15 of the field's size, and evaluating the
  ! reconstruction rounds at ~1e-16 of it, so 1e-14 relative is the bound.
  overshoot = 0.0_wp
  do ck = 1, nk
    do cj = 1, nj
      do ci = 1, ni
        c = ci + ni*((cj - 1) + nj*(ck - 1))
        qmin = q(2, c)
        qmax = q(2, c)
        do ok_ = max(1, ck - 1), min(nk, ck + 1)
          do oj = max(1, cj - 1), min(nj, cj + 1)
            do oi = max(1, ci - 1), min(ni, ci + 1)
              co = oi + ni*((oj - 1) + nj*(ok_ - 1))
              qmin = min(qmin, q(2, co))
              qmax = max(qmax, q(2, co))
            end do
          end do
        end do
        scale = max(abs(qmin), abs(qmax))
        call block_gather(ni, nj, ci, cj, ck, x, xn)
        do a = 1, 8
          qn = q(2, c) + dot_product(grad(:, 2, c), xn(:, a) - cen(:, c))
          overshoot = max(overshoot, (qn - qmax)/scale, (qmin - qn)/scale)
        end do
      end do
    end do
  end do
  write(*, '(a,es10.3)') 'step field, largest relative overshoot at a node: ', overshoot
  call check(overshoot <= 1e-14_wp, 'step field: node values within the neighbours'' bounds')

  ! 4. A 1-cell-thick grid and a lone cell: no NaN, zero gradient where no
  ! neighbour gives a slope.
  call thin_grid_case()

  ! 5. has: cells without the quantity are never read. Two runs that differ
  ! only there (values and points 1e300 in one: any use would overflow and
  ! trap in the debug build) give bit-identical results, and those cells get
  ! zero.
  call rng_seed(rng, 5)
  do c = 1, nc
    has(c) = rng_uniform(rng) < 0.5_wp
  end do
  do c = 1, nc
    if (has(c)) then
      qa(1, c) = q(2, c) + 0.1_wp*q(1, c)
      posa(:, c) = cen(:, c)
      qb(1, c) = qa(1, c)
      posb(:, c) = cen(:, c)
    else
      qa(1, c) = 1.0e300_wp
      posa(:, c) = 1.0e300_wp
      qb(1, c) = -7.0_wp
      posb(:, c) = cen(:, c) + 0.01_wp
    end if
  end do
  call remap_limited_gradients(ni, nj, nk, x, qa, posa, has, all_has, ga, err)
  call remap_limited_gradients(ni, nj, nk, x, qb, posb, has, all_has, gb, err)
  call check(.not. allocated(err), 'has mask: no error')
  call check(all(abs(ga - gb) <= 0.0_wp), 'has mask: values in cells without the quantity are not used')
  ok = .true.
  do c = 1, nc
    if (.not. has(c)) ok = ok .and. all(abs(ga(:, 1, c)) <= 0.0_wp)
  end do
  call check(ok, 'has mask: cells without the quantity get a zero gradient')
  call check(maxval(abs(ga)) > 0.1_wp, 'has mask: non-zero gradients in cells with it')

  ! 6. need: unneeded cells are left as they were (a remap that moves a few
  ! cells of a large grid pays for those only); needed ones are exactly as
  ! in a full run (each cell is computed on its own).
  do c = 1, nc
    need(c) = rng_uniform(rng) < 0.3_wp
  end do
  gneed = 7.0_wp
  call remap_limited_gradients(ni, nj, nk, x, q, cen, all_has, need, gneed, err)
  call remap_limited_gradients(ni, nj, nk, x, q, cen, all_has, all_has, grad, err)
  call check(.not. allocated(err), 'need mask: no error')
  ok = .true.
  do c = 1, nc
    if (need(c)) then
      ok = ok .and. all(abs(gneed(:, :, c) - grad(:, :, c)) <= 0.0_wp)
    else
      ok = ok .and. all(abs(gneed(:, :, c) - 7.0_wp) <= 0.0_wp)
    end if
  end do
  call check(ok, 'need mask: untouched where not needed, the full-run value where needed')

  ! Sizes that do not match the block are reported, not crashed on.
  call remap_limited_gradients(ni, nj, nk + 1, x, q, cen, all_has, all_has, grad, err)
  call check(allocated(err), 'mismatched sizes are reported as an error')
  if (allocated(err)) deallocate(err)

  ! Thread invariance: cells are independent, so 1 and 2 threads agree bit
  ! for bit (a work array shared by mistake would break this).
  nthreads = 1
  !$ nthreads = omp_get_max_threads()
  !$ call omp_set_num_threads(1)
  call remap_limited_gradients(ni, nj, nk, x, q, cen, all_has, all_has, grad, err)
  !$ call omp_set_num_threads(2)
  call remap_limited_gradients(ni, nj, nk, x, q, cen, all_has, all_has, gneed)   ! err is optional
  !$ call omp_set_num_threads(nthreads)
  call check(all(abs(grad - gneed) <= 0.0_wp), '1 and 2 threads give identical gradients')

  call timing_case()

  call check_summary('test_remap_gradient')

contains

  !> 4. ni=8, nj=nk=1 with node planes moved randomly in x (cells stay boxes,
  !> so all centroids share y and z up to round-off): a field linear in x has
  !> gradient (b1, 0, 0); the y and z directions are dropped by the SVD cut.
  !> Interior cells (ci = 2..7) are exact to round-off (1e-12, as in 1.).
  !> A lone cell (1x1x1) has no neighbour: zero gradient.
  subroutine thin_grid_case()
    integer, parameter :: mi = 8, mc = mi, mn = (mi + 1)*4
    real(wp) :: xt(3, mn), vt(mc), ct(3, mc), qt(1, mc), gt(3, 1, mc), shift(0:mi), x1(3, 8), v1(1), c1(3, 1), &
                q1(1, 1), gl(3, 1, 1)
    logical :: ht(mc), h1(1)
    type(rng_t) :: r
    integer :: i, j, k, cc
    call rng_seed(r, 7)
    shift = 0.0_wp
    do i = 1, mi - 1
      shift(i) = 0.4_wp*0.125_wp*(rng_uniform(r) - 0.5_wp)
    end do
    do k = 0, 1
      do j = 0, 1
        do i = 0, mi
          xt(:, 1 + i + (mi + 1)*(j + 2*k)) = [0.125_wp*i + shift(i), 0.1_wp*j, 0.1_wp*k]
        end do
      end do
    end do
    call cell_moments(mi, 1, 1, xt, vt, ct)
    qt(1, :) = 2.0_wp - 1.3_wp*ct(1, :)
    ht = .true.
    call remap_limited_gradients(mi, 1, 1, xt, qt, ct, ht, ht, gt, err)
    call check(.not. allocated(err), 'thin grid: no error')
    call check(all(ieee_is_finite(gt)), 'thin grid: no NaN or Inf')
    err_max = 0.0_wp
    do cc = 2, mi - 1
      err_max = max(err_max, maxval(abs(gt(:, 1, cc) - [-1.3_wp, 0.0_wp, 0.0_wp])))
    end do
    write(*, '(a,es10.3)') 'thin grid, largest gradient error in interior cells: ', err_max
    call check(err_max < 1e-12_wp, 'thin grid: gradient (b1, 0, 0) in interior cells')

    do cc = 1, 8
      x1(:, cc) = real([mod(cc - 1, 2), mod((cc - 1)/2, 2), (cc - 1)/4], wp)
    end do
    call cell_moments(1, 1, 1, x1, v1, c1)
    q1 = 4.0_wp
    h1 = .true.
    call remap_limited_gradients(1, 1, 1, x1, q1, c1, h1, h1, gl, err)
    call check(.not. allocated(err) .and. all(abs(gl) <= 0.0_wp), 'lone cell: zero gradient, no error')
  end subroutine thin_grid_case

  !> Cost of one call on a 40^3 grid with two fields (printed, not checked:
  !> timings depend on the machine and the build).
  subroutine timing_case()
    integer, parameter :: m = 40, mc = m**3, mn = (m + 1)**3
    real(wp), allocatable :: xt(:, :), vt(:), ct(:, :), qt(:, :), gt(:, :, :)
    logical, allocatable :: ht(:)
    real(wp) :: t0, t1, best
    integer :: cc, rep
    allocate(xt(3, mn), vt(mc), ct(3, mc), qt(2, mc), gt(3, 2, mc), ht(mc))
    call make_grid(m, m, m, xt, 3)
    call cell_moments(m, m, m, xt, vt, ct)
    do cc = 1, mc
      qt(1, cc) = 1.0_wp + dot_product([0.3_wp, -0.7_wp, 1.9_wp], ct(:, cc))
      qt(2, cc) = merge(1.0_wp, 3.0_wp, sum((ct(:, cc) - 0.5_wp)**2) < 0.1_wp)
    end do
    ht = .true.
    best = huge(1.0_wp)
    do rep = 1, 3
      t0 = wall_seconds()
      call remap_limited_gradients(m, m, m, xt, qt, ct, ht, ht, gt, err)
      t1 = wall_seconds()
      best = min(best, t1 - t0)
    end do
    call check(.not. allocated(err), '40^3 grid: no error')
    nthreads = 1
    !$ nthreads = omp_get_max_threads()
    write(*, '(a,f9.3,a,i0,a)') 'gradients, 40^3 cells, 2 fields: ', 1.0e6_wp*best/mc, &
      ' us per cell (best of 3, ', nthreads, ' thread(s), this build)'
  end subroutine timing_case

  !> A grid of a x b x c cells on [0,1.2]x[0,1]x[0,0.8] with interior nodes
  !> moved randomly by up to 0.2 of a cell (as in test_remap_cells).
  subroutine make_grid(a, b, c, xg, seed)
    integer, intent(in) :: a, b, c, seed
    real(wp), intent(out) :: xg(:, :)
    type(rng_t) :: r
    integer :: i, j, kk, n, d
    real(wp) :: h(3)
    h = [1.2_wp/a, 1.0_wp/b, 0.8_wp/c]
    call rng_seed(r, seed)
    do kk = 0, c
      do j = 0, b
        do i = 0, a
          n = 1 + i + (a + 1)*(j + (b + 1)*kk)
          xg(:, n) = h*real([i, j, kk], wp)
          if (i > 0 .and. i < a .and. j > 0 .and. j < b .and. kk > 0 .and. kk < c) then
            do d = 1, 3
              xg(d, n) = xg(d, n) + 0.4_wp*h(d)*(rng_uniform(r) - 0.5_wp)
            end do
          end if
        end do
      end do
    end do
  end subroutine make_grid
end program test_remap_gradient
