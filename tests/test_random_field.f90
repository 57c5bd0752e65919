!> Unit tests of strength_random_field (PARTICLES.md §3): the generator
!> against the reference C implementation, the statistics of correlated
!> fields against their exact sampling errors, the uncorrelated limit, the
!> one-cell-thick (2D) box, reproducibility and the void-fraction maps;
!> and base_random's jump over n draws against n draws.
!>
!> Tolerances. A field sampled on a lattice of N points is one Gaussian
!> vector with known covariance C, so the sampling errors of the statistics
!> are exact sums over the lattice's lags a (the number of point pairs at
!> lag a is prod_d (m_d - |a_d|) for m_d points per direction), using
!> Isserlis' theorem for the fourth moments:
!>  - sample mean: var = sum_pq C_pq / N^2 (so N_eff = N^2 / sum_pq C_pq;
!>    about V/(pi^(d/2) ell^d) for the Gaussian covariance, the brief's
!>    "volume/ell^d" with the right constant);
!>  - B = <g^2> (mean known to be 0): var = 2 sum_pq C_pq^2 / N^2, and the
!>    rms sqrt(B) has sigma = sigma_B / 2;
!>  - A = <g_p g_p+h> over the M pairs at lag h:
!>    var = sum_pq (C_pq^2 + C_pq+h C_pq-h) / M^2 and
!>    cov(A, B) = 2 sum_pq C_pq C_pq-h / (M N) (p over the pairs, q over
!>    all points); the correlation rho = A/B, linearised about B = 1, has
!>    var = var_A - 2 rho cov(A, B) + rho^2 var_B (A and B are strongly
!>    correlated: this is several times below sigma_A + rho sigma_B).
!> Each check allows 3 sigma: a correct generator fails one with a
!> probability below 0.3 % for a random seed (the seeds here are fixed, so
!> the outcome is deterministic).
program test_random_field
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use base_kinds, only: wp, i8
  use base_errors, only: error_t, ERR_INPUT
  use test_assert, only: check, check_close, check_summary
  use strength_random_field, only: random_field_t, random_field_build, random_field_sample, void_fraction_from_field, &
                                   random_normal_t, random_normal_seed, random_normal_next, random_bits_next
  use base_random, only: rng_t, rng_seed, rng_uniform, rng_jump, rng_apply
  implicit none

  call test_generator()
  call test_gaussian_3d()
  call test_separable()
  call test_between_nodes()
  call test_exponential_2d()
  call test_uncorrelated()
  call test_reproducible()
  call test_lognormal()
  call test_truncation()
  call test_errors()
  call test_rng_jump()
  call check_summary('test_random_field')

contains

  !> base_random's rng_jump(n) moves a generator on exactly as n draws do
  !> (the same state bits, then the same next numbers), for several seeds
  !> and lengths, 0 and powers of two among them.
  subroutine test_rng_jump()
    integer(i8), parameter :: lengths(7) = [0_i8, 1_i8, 2_i8, 63_i8, 64_i8, 1000_i8, 123457_i8]
    integer, parameter :: seeds(3) = [1, 12345, -7]
    type(rng_t) :: a, b
    integer :: s, l, k
    integer(i8) :: q
    real(wp) :: x
    do s = 1, size(seeds)
      do l = 1, size(lengths)
        call rng_seed(a, seeds(s))
        call rng_seed(b, seeds(s))
        do q = 1, lengths(l)
          x = rng_uniform(a)
        end do
        call rng_apply(rng_jump(lengths(l)), b)
        call check(a%s == b%s, 'rng_jump: the state after draws')
        do k = 1, 3
          call check(same_bits(rng_uniform(a), rng_uniform(b)), 'rng_jump: the draws after')
        end do
      end do
    end do
  end subroutine test_rng_jump

  !> A 64-bit pattern from its two 32-bit halves (hex digits as integers).
  pure integer(i8) function bits(hi, lo)
    integer(i8), intent(in) :: hi, lo
    bits = ior(shiftl(hi, 32), lo)
  end function bits

  !> a and b have the same bit pattern.
  elemental logical function same_bits(a, b)
    real(wp), intent(in) :: a, b
    same_bits = transfer(a, 0_i8) == transfer(b, 0_i8)
  end function same_bits

  !> Covariance of the test fields (ell = 1).
  pure real(wp) function cov(kind, r)
    character(len=*), intent(in) :: kind
    real(wp), intent(in) :: r
    if (kind == 'gaussian') then
      cov = exp(-r*r)
    else
      cov = exp(-r)
    end if
  end function cov

  !> The sum over the points p of a box of m1(3) lattice points and the
  !> points q of a box of m2(3) (both starting at point 1; spacing h) of
  !> F(q - p): F = C (mode 1), C^2 + C(. + lag) C(. - lag) (mode 2) or
  !> C C(. - lag) (mode 3), lag(3) in points.
  real(wp) function lag_sum(kind, m1, m2, h, mode, lag) result(s)
    character(len=*), intent(in) :: kind
    integer, intent(in) :: m1(3), m2(3), mode, lag(3)
    real(wp), intent(in) :: h
    integer :: a(3), a1, a2, a3, d
    real(wp) :: cnt, f, c0
    s = 0.0_wp
    do a3 = -(m1(3) - 1), m2(3) - 1
      do a2 = -(m1(2) - 1), m2(2) - 1
        do a1 = -(m1(1) - 1), m2(1) - 1
          a = [a1, a2, a3]
          cnt = 1.0_wp
          do d = 1, 3
            cnt = cnt*real(max(0, min(m1(d), m2(d) - a(d)) - max(1, 1 - a(d)) + 1), wp)
          end do
          c0 = cov(kind, h*norm2(real(a, wp)))
          select case (mode)
          case (1)
            f = c0
          case (2)
            f = c0**2 + cov(kind, h*norm2(real(a + lag, wp)))*cov(kind, h*norm2(real(a - lag, wp)))
          case default
            f = c0*cov(kind, h*norm2(real(a - lag, wp)))
          end select
          s = s + cnt*f
        end do
      end do
    end do
  end function lag_sum

  !> The correlation at lag h along x of the normalised interpolant of a
  !> field with covariance `kind` on nodes dx apart, at two points half way
  !> between nodes in the first nd directions: sum_ab w_a w_b C(x_a - x_b -
  !> h e_x) / sum_ab w_a w_b C(x_a - x_b) over the 2^nd corners, all w_a
  !> = 2^-nd (derived here independently of the module's code).
  real(wp) function half_way_rho(kind, dx, h, nd) result(rho)
    character(len=*), intent(in) :: kind
    real(wp), intent(in) :: dx, h
    integer, intent(in) :: nd
    integer :: a, b, d
    real(wp) :: num, den, da(3)
    num = 0.0_wp
    den = 0.0_wp
    do a = 0, 2**nd - 1
      do b = 0, 2**nd - 1
        do d = 1, 3
          da(d) = dx*real(ibits(a, d - 1, 1) - ibits(b, d - 1, 1), wp)
        end do
        num = num + cov(kind, norm2(da - [h, 0.0_wp, 0.0_wp]))
        den = den + cov(kind, norm2(da))
      end do
    end do
    rho = num/den
  end function half_way_rho

  !> The points of a lattice lo + (i-1, j-1, k-1) h, i = 1..m(1), ...,
  !> first index fastest, plus an offset (length).
  subroutine lattice(lo, h, m, offset, x)
    real(wp), intent(in) :: lo(3), h, offset(3)
    integer, intent(in) :: m(3)
    real(wp), allocatable, intent(out) :: x(:, :)
    integer :: i, j, k, p
    allocate(x(3, product(m)))
    p = 0
    do k = 1, m(3)
      do j = 1, m(2)
        do i = 1, m(1)
          p = p + 1
          x(:, p) = lo + h*real([i - 1, j - 1, k - 1], wp) + offset
        end do
      end do
    end do
  end subroutine lattice

  !> Mean, rms and the correlation at lag `lag` (points) along each
  !> direction of the lattice field g(m(1), m(2), m(3)) (mean known 0).
  subroutine stats(g, m, lag, mean, rms, rho)
    integer, intent(in) :: m(3), lag
    real(wp), intent(in) :: g(m(1), m(2), m(3))
    real(wp), intent(out) :: mean, rms, rho(3)
    real(wp) :: b
    b = sum(g**2)/real(size(g), wp)
    mean = sum(g)/real(size(g), wp)
    rms = sqrt(b)
    rho = 0.0_wp
    if (m(1) > lag) rho(1) = sum(g(1:m(1) - lag, :, :)*g(1 + lag:, :, :))/real(size(g(1 + lag:, :, :)), wp)/b
    if (m(2) > lag) rho(2) = sum(g(:, 1:m(2) - lag, :)*g(:, 1 + lag:, :))/real(size(g(:, 1 + lag:, :)), wp)/b
    if (m(3) > lag) rho(3) = sum(g(:, :, 1:m(3) - lag)*g(:, :, 1 + lag:))/real(size(g(:, :, 1 + lag:)), wp)/b
  end subroutine stats

  !> The sigmas of the program notes for a lattice of m points at spacing h
  !> with the correlation rho expected at lag (points, along x), and
  !> N_eff = N^2 / sum_pq C_pq.
  subroutine sigmas(kind, m, h, lag, rho, s_mean, s_rms, s_rho, n_eff)
    character(len=*), intent(in) :: kind
    integer, intent(in) :: m(3), lag
    real(wp), intent(in) :: h, rho
    real(wp), intent(out) :: s_mean, s_rms, s_rho, n_eff
    real(wp) :: n, mm, var_a, var_b, cov_ab
    integer :: mp(3)
    n = real(product(m), wp)
    mp = [m(1) - lag, m(2), m(3)]
    mm = real(product(mp), wp)
    n_eff = n**2/lag_sum(kind, m, m, h, 1, [0, 0, 0])
    s_mean = 1.0_wp/sqrt(n_eff)
    var_b = 2.0_wp*lag_sum(kind, m, m, h, 3, [0, 0, 0])/n**2
    s_rms = 0.5_wp*sqrt(var_b)
    var_a = lag_sum(kind, mp, mp, h, 2, [lag, 0, 0])/mm**2
    cov_ab = 2.0_wp*lag_sum(kind, mp, m, h, 3, [lag, 0, 0])/(mm*n)
    s_rho = sqrt(max(0.0_wp, var_a - 2.0_wp*rho*cov_ab + rho**2*var_b))
  end subroutine sigmas

  !> xoshiro256** seeded by splitmix64 gives the reference C code's bits
  !> (seed 12345: be6a36374160d49b 214aaa0637a688c6 f69d16de9954d388; seed
  !> -7 as uint64: f305399b3b63f2c2); the normals have mean 0 and variance 1
  !> (200000 values: sigmas 1/sqrt(N) and sqrt(2/N)).
  subroutine test_generator()
    type(random_normal_t) :: r
    integer(i8) :: b(3), expect(3)
    real(wp) :: z, s1, s2
    integer :: i
    integer, parameter :: n = 200000
    expect = [bits(int(z'be6a3637', i8), int(z'4160d49b', i8)), bits(int(z'214aaa06', i8), int(z'37a688c6', i8)), &
              bits(int(z'f69d16de', i8), int(z'9954d388', i8))]
    call random_normal_seed(r, 12345)
    do i = 1, 3
      call random_bits_next(r, b(i))
    end do
    call check(all(b == expect), 'xoshiro256** (seed 12345) matches the reference C implementation')
    call random_normal_seed(r, -7)
    call random_bits_next(r, b(1))
    call check(b(1) == bits(int(z'f305399b', i8), int(z'3b63f2c2', i8)), 'xoshiro256** (seed -7) matches the reference')
    call random_normal_seed(r, 2024)
    s1 = 0.0_wp
    s2 = 0.0_wp
    do i = 1, n
      call random_normal_next(r, z)
      s1 = s1 + z
      s2 = s2 + z*z
    end do
    call check_close('normal stream mean (3 sigma)', s1/n, 0.0_wp, 3.0_wp/sqrt(real(n, wp)))
    call check_close('normal stream variance (3 sigma)', s2/n, 1.0_wp, 3.0_wp*sqrt(2.0_wp/n))
  end subroutine test_generator

  !> 3D Gaussian covariance, ell = 1, the box [0,28]^3 sampled on its
  !> lattice of spacing 0.5 (57^3 points, on grid nodes): mean, rms and the
  !> correlation at lags ell (2 points: exp(-1)) and ell/2 (exp(-1/4)),
  !> averaged over the three directions (the average of three estimates
  !> has at most the sigma of one).
  subroutine test_gaussian_3d()
    type(random_field_t) :: f
    type(error_t), allocatable :: err
    real(wp), allocatable :: x(:, :), g(:)
    real(wp) :: clipped, mean, rms, rho(3), rho1(3), s_mean, s_rms, s_rho, s_rho1, n_eff
    integer, parameter :: m(3) = [57, 57, 57]
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [28.0_wp, 28.0_wp, 28.0_wp], 0.5_wp, 1.0_wp, 'gaussian', 7, f, &
                            clipped, err)
    call check(.not. allocated(err), 'gaussian 3D: build')
    if (allocated(err)) return
    write(*, '(a,3i5,a,f7.4,a,es10.3)') 'gaussian 3D: grid ', f%n, ', dx ', f%dx, ', clipped ', clipped
    call check(abs(f%dx - 0.25_wp) < 1e-15_wp .and. all(f%n >= 112 + 2*12 + 1), 'gaussian 3D: dx = ell/4, 3 ell padding')
    call check_close('gaussian 3D: clipped share of the variance (round-off)', clipped, 0.0_wp, 1.0e-12_wp)
    call lattice([0.0_wp, 0.0_wp, 0.0_wp], 0.5_wp, m, [0.0_wp, 0.0_wp, 0.0_wp], x)
    allocate(g(size(x, 2)))
    call random_field_sample(f, x, g, err)
    call check(.not. allocated(err), 'gaussian 3D: sample')
    call stats(g, m, 2, mean, rms, rho)
    call stats(g, m, 1, mean, rms, rho1)
    call sigmas('gaussian', m, 0.5_wp, 2, exp(-1.0_wp), s_mean, s_rms, s_rho, n_eff)
    call sigmas('gaussian', m, 0.5_wp, 1, exp(-0.25_wp), s_mean, s_rms, s_rho1, n_eff)
    write(*, '(a,f9.1,a,f9.1,a)') 'gaussian 3D: N_eff ', n_eff, ' (V/(pi^1.5 ell^3) = ', 28.0_wp**3/acos(-1.0_wp)**1.5_wp, ')'
    write(*, '(a,3f8.4)') 'gaussian 3D: correlation at lag ell along x, y, z: ', rho
    call check_close('gaussian 3D: mean (3 sigma)', mean, 0.0_wp, 3.0_wp*s_mean)
    call check_close('gaussian 3D: rms (3 sigma)', rms, 1.0_wp, 3.0_wp*s_rms)
    call check_close('gaussian 3D: correlation at lag ell (3 sigma)', sum(rho)/3, exp(-1.0_wp), 3.0_wp*s_rho)
    call check_close('gaussian 3D: correlation at lag ell/2 (3 sigma)', sum(rho1)/3, exp(-0.25_wp), 3.0_wp*s_rho1)
  end subroutine test_gaussian_3d

  !> The Gaussian field by its separable kernel (the default) against the
  !> same field by the three-dimensional transform (whole_fft: the same
  !> grid and noise; the square root of the same covariance) on a 3D box
  !> and a one-node-thick one: every node within 1e-5. The transform's
  !> eigenvalues carry round-off of eps lambda(0) (lambda(0) = the sum of
  !> the covariance over the grid, ~ (sqrt(pi) ell/dx)^3 = 356 here), which
  !> the square root raises to a noise of standard deviation about
  !> sqrt(eps lambda(0)) = 3e-7 at the nodes: 1e-5 is over 30 of those
  !> sigma; a wrong kernel (its width, scale or periodic sum) would differ
  !> by order one. And parts: a field built for a
  !> box within the whole holds the whole field's values at its nodes bit
  !> for bit (a decomposed run's blocks each build their own), and samples
  !> there give the same bits; a point outside the part is refused.
  subroutine test_separable()
    type(random_field_t) :: f, ref, part
    type(error_t), allocatable :: err
    real(wp) :: clipped, clipped_ref, diff, x(3, 3), g(3), gp(3)
    integer :: i, j, k, box
    logical :: same
    real(wp), parameter :: hi2(3, 2) = reshape([15.0_wp, 12.0_wp, 9.0_wp, 20.0_wp, 14.0_wp, 0.0_wp], [3, 2])
    do box = 1, 2
      call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], hi2(:, box), 0.5_wp, 1.0_wp, 'gaussian', 5, f, clipped, err)
      if (.not. allocated(err)) call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], hi2(:, box), 0.5_wp, 1.0_wp, &
                                                      'gaussian', 5, ref, clipped_ref, err, whole_fft=.true.)
      call check(.not. allocated(err), 'separable: build')
      if (allocated(err)) return
      call check(all(shape(f%values) == f%n) .and. all(f%first == 1) .and. all(shape(ref%values) == ref%n), &
                 'separable: the whole grid without a box')
      diff = maxval(abs(f%values - ref%values))
      write(*, '(a,i0,a,3i5,a,es10.3,a,2es10.3)') 'separable: box ', box, ', grid ', f%n, ', largest node difference ', &
        diff, ', clipped ', clipped, clipped_ref
      call check(diff < 1.0e-5_wp, 'separable: the 3D transform''s field within 1e-5 at every node')
      call check(.not. abs(clipped) > 0.0_wp, 'separable: no eigenvalue clipped')
      ! a part: the nodes around [3, 7] x [2, 9] x [1, 4] (in the 2D box, z = 0)
      call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], hi2(:, box), 0.5_wp, 1.0_wp, 'gaussian', 5, part, clipped, err, &
                              box_lo=[3.0_wp, 2.0_wp, min(1.0_wp, hi2(3, box))], box_hi=[7.0_wp, 9.0_wp, min(4.0_wp, hi2(3, box))])
      call check(.not. allocated(err), 'separable part: build')
      if (allocated(err)) return
      call check(all(shape(part%values) < f%n .or. f%n == 1), 'separable part: fewer nodes than the whole grid')
      same = .true.
      do k = 1, size(part%values, 3)
        do j = 1, size(part%values, 2)
          do i = 1, size(part%values, 1)
            same = same .and. same_bits(part%values(i, j, k), &
                                        f%values(part%first(1) + i - 1, part%first(2) + j - 1, part%first(3) + k - 1))
          end do
        end do
      end do
      call check(same, 'separable part: the whole field''s values bit for bit')
      x(:, 1) = [3.0_wp, 2.0_wp, min(1.0_wp, hi2(3, box))]
      x(:, 2) = [7.0_wp, 9.0_wp, min(4.0_wp, hi2(3, box))]
      x(:, 3) = [5.1234_wp, 4.321_wp, min(2.71_wp, hi2(3, box))]
      call random_field_sample(f, x, g, err)
      call random_field_sample(part, x, gp, err)
      call check(.not. allocated(err) .and. all(same_bits(g, gp)), 'separable part: the same samples bit for bit')
      x(:, 3) = [12.0_wp, 4.0_wp, 0.0_wp]
      call random_field_sample(part, x, gp, err)
      call check(allocated(err), 'separable part: a point outside the part is refused')
      if (allocated(err)) deallocate(err)
    end do
  end subroutine test_separable

  !> The same field sampled half way between nodes in every direction (a
  !> lattice shifted by dx/2 = 0.125): the normalised interpolant keeps unit
  !> variance there (plain trilinear interpolation would give rms
  !> ((1 + e^(-1/16))/2)^(3/2) = 0.955), and its correlation at lag ell
  !> along x is the smoothed value (half_way_rho: 0.3906 for dx = ell/4,
  !> the Gaussian being separable, (C(h) + (C(h+dx) + C(h-dx))/2) /
  !> (1 + C(dx)) in closed form). The sigmas are the
  !> lattice field's times 1.1: the smoothed covariance exceeds C by at
  !> most 6 % (at lag ell), so the sums in them grow by less.
  subroutine test_between_nodes()
    type(random_field_t) :: f
    type(error_t), allocatable :: err
    real(wp), allocatable :: x(:, :), g(:)
    real(wp) :: clipped, mean, rms, rho(3), s_mean, s_rms, s_rho, n_eff, expect, dx
    integer, parameter :: m(3) = [57, 57, 57]
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [28.0_wp, 28.0_wp, 28.0_wp], 0.5_wp, 1.0_wp, 'gaussian', 11, f, &
                            clipped, err)
    if (allocated(err)) then
      call check(.false., 'half-way: build')
      return
    end if
    dx = f%dx
    call lattice([0.0_wp, 0.0_wp, 0.0_wp], 0.5_wp, m, [0.5_wp, 0.5_wp, 0.5_wp]*dx, x)
    allocate(g(size(x, 2)))
    call random_field_sample(f, x, g, err)
    call check(.not. allocated(err), 'half-way: sample')
    call stats(g, m, 2, mean, rms, rho)
    call sigmas('gaussian', m, 0.5_wp, 2, exp(-1.0_wp), s_mean, s_rms, s_rho, n_eff)
    expect = half_way_rho('gaussian', dx, 1.0_wp, 3)
    write(*, '(a,3f8.4,a,f7.4)') 'half-way: correlation at lag ell along x, y, z: ', rho, '; expected ', expect
    call check_close('half-way: rms of the normalised interpolant (3 sigma)', rms, 1.0_wp, 3.3_wp*s_rms)
    call check_close('half-way: correlation at lag ell, smoothed (3 sigma)', sum(rho)/3, expect, 3.3_wp*s_rho)
  end subroutine test_between_nodes

  !> Exponential covariance in a one-cell-thick box (z extent 0.2 below
  !> the spacing 0.5): one node through the thickness, the same values on
  !> both faces, and the 2D statistics on the 201^2 lattice of [0,100]^2;
  !> then half way between nodes in x and y, where the smoothing of the
  !> interpolant is strongest for this rough field (half_way_rho: 0.4511;
  !> sigmas times 1.2, the smoothed covariance being up to 20 % above C).
  subroutine test_exponential_2d()
    type(random_field_t) :: f
    type(error_t), allocatable :: err
    real(wp), allocatable :: x(:, :), g(:), g2(:)
    real(wp) :: clipped, mean, rms, rho(3), s_mean, s_rms, s_rho, n_eff, expect
    integer, parameter :: m(3) = [201, 201, 1]
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [100.0_wp, 100.0_wp, 0.2_wp], 0.5_wp, 1.0_wp, 'exponential', 3, f, &
                            clipped, err)
    call check(.not. allocated(err), 'exponential 2D: build')
    if (allocated(err)) return
    write(*, '(a,3i5,a,f7.4,a,es10.3)') 'exponential 2D: grid ', f%n, ', dx ', f%dx, ', clipped ', clipped
    call check(f%n(3) == 1, 'exponential 2D: one node through the thickness')
    call check_close('exponential 2D: clipped share of the variance', clipped, 0.0_wp, 1.0e-12_wp)
    call lattice([0.0_wp, 0.0_wp, 0.0_wp], 0.5_wp, m, [0.0_wp, 0.0_wp, 0.0_wp], x)
    allocate(g(size(x, 2)), g2(size(x, 2)))
    call random_field_sample(f, x, g, err)
    x(3, :) = 0.2_wp
    call random_field_sample(f, x, g2, err)
    call check(.not. allocated(err), 'exponential 2D: sample')
    call check(all(same_bits(g, g2)), 'exponential 2D: the same values on both faces of the slab')
    call stats(g, m, 2, mean, rms, rho)
    call sigmas('exponential', m, 0.5_wp, 2, exp(-1.0_wp), s_mean, s_rms, s_rho, n_eff)
    write(*, '(a,f9.1,a,f9.1,a)') 'exponential 2D: N_eff ', n_eff, ' (V/(2 pi ell^2) = ', 1.0e4_wp/(2*acos(-1.0_wp)), ')'
    write(*, '(a,2f8.4)') 'exponential 2D: correlation at lag ell along x, y: ', rho(1:2)
    call check_close('exponential 2D: mean (3 sigma)', mean, 0.0_wp, 3.0_wp*s_mean)
    call check_close('exponential 2D: rms (3 sigma)', rms, 1.0_wp, 3.0_wp*s_rms)
    call check_close('exponential 2D: correlation at lag ell (3 sigma)', sum(rho(1:2))/2, exp(-1.0_wp), 3.0_wp*s_rho)
    x(1:2, :) = x(1:2, :) + 0.5_wp*f%dx
    call random_field_sample(f, x, g, err)
    call stats(g, m, 2, mean, rms, rho)
    expect = half_way_rho('exponential', f%dx, 1.0_wp, 2)
    write(*, '(a,2f8.4,a,f7.4)') 'exponential 2D half-way: correlation at lag ell along x, y: ', rho(1:2), &
      '; expected ', expect
    call check_close('exponential 2D half-way: rms (3 sigma)', rms, 1.0_wp, 3.6_wp*s_rms)
    call check_close('exponential 2D half-way: correlation at lag ell (3 sigma)', sum(rho(1:2))/2, expect, 3.6_wp*s_rho)
  end subroutine test_exponential_2d

  !> ell = 0 (and 'none'): i.i.d. N(0,1) in point order, the seed's stream;
  !> on a 100^2 lattice the correlation at lag one spacing is 0 within
  !> 3/sqrt(M) (M pairs, i.i.d.).
  subroutine test_uncorrelated()
    type(random_field_t) :: f, fnone
    type(error_t), allocatable :: err
    type(random_normal_t) :: r
    real(wp), allocatable :: x(:, :), g(:), gnone(:), ref(:)
    real(wp) :: clipped, mean, rms, rho(3), n
    integer :: p
    integer, parameter :: m(3) = [100, 100, 1]
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [49.5_wp, 49.5_wp, 0.0_wp], 0.5_wp, 0.0_wp, 'gaussian', 5, f, &
                            clipped, err)
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [49.5_wp, 49.5_wp, 0.0_wp], 0.5_wp, 2.0_wp, 'none', 5, fnone, &
                            clipped, err)
    call check(.not. allocated(err) .and. .not. f%correlated .and. .not. fnone%correlated, 'uncorrelated: build')
    call lattice([0.0_wp, 0.0_wp, 0.0_wp], 0.5_wp, m, [0.0_wp, 0.0_wp, 0.0_wp], x)
    allocate(g(size(x, 2)), gnone(size(x, 2)), ref(size(x, 2)))
    call random_field_sample(f, x, g, err)
    call random_field_sample(fnone, x, gnone, err)
    call random_normal_seed(r, 5)
    do p = 1, size(ref)
      call random_normal_next(r, ref(p))
    end do
    call check(all(same_bits(g, ref)) .and. all(same_bits(gnone, ref)), 'uncorrelated: the seed''s normal stream in point order')
    call stats(g, m, 1, mean, rms, rho)
    n = real(size(g), wp)
    write(*, '(a,2f8.4)') 'uncorrelated: correlation at lag one spacing along x, y: ', rho(1:2)
    call check_close('uncorrelated: mean (3 sigma)', mean, 0.0_wp, 3.0_wp/sqrt(n))
    call check_close('uncorrelated: rms (3 sigma)', rms, 1.0_wp, 1.5_wp*sqrt(2.0_wp/n))
    call check_close('uncorrelated: correlation at lag one spacing, x (3 sigma)', rho(1), 0.0_wp, 3.0_wp/sqrt(n - 100))
    call check_close('uncorrelated: correlation at lag one spacing, y (3 sigma)', rho(2), 0.0_wp, 3.0_wp/sqrt(n - 100))
  end subroutine test_uncorrelated

  !> The same seed gives the same field bit for bit; another seed another
  !> field (values differ by O(1)).
  subroutine test_reproducible()
    type(random_field_t) :: a, b, c
    type(error_t), allocatable :: err
    real(wp) :: clipped
    real(wp), parameter :: lo(3) = [0.0_wp, -1.0_wp, 2.0_wp], hi(3) = [6.0_wp, 4.0_wp, 5.0_wp]
    call random_field_build(lo, hi, 0.3_wp, 0.8_wp, 'gaussian', 99, a, clipped, err)
    call random_field_build(lo, hi, 0.3_wp, 0.8_wp, 'gaussian', 99, b, clipped, err)
    call random_field_build(lo, hi, 0.3_wp, 0.8_wp, 'gaussian', 100, c, clipped, err)
    call check(.not. allocated(err), 'reproducible: build')
    if (allocated(err)) return
    call check(all(same_bits(a%values, b%values)), 'reproducible: seed 99 twice, bit-identical fields')
    write(*, '(a,f8.4)') 'reproducible: max |seed 99 - seed 100| = ', maxval(abs(a%values - c%values))
    call check(maxval(abs(a%values - c%values)) > 1.0_wp, 'reproducible: seeds 99 and 100 give different fields')
  end subroutine test_reproducible

  !> Lognormal with the paper's mean 0.005 and a wide std 0.003 (s_ln^2 =
  !> ln 1.36), from 400000 i.i.d. normals: mean within 3 std/sqrt(N); std
  !> within 3 sigma, sigma = std sqrt((kurt - 1)/(4N)) with the lognormal
  !> kurtosis e^(4s^2) + 2e^(3s^2) + 3e^(2s^2) - 3 = 11.0; all positive, none
  !> truncated (the largest is far below f_max = 0.5).
  subroutine test_lognormal()
    type(random_normal_t) :: r
    type(error_t), allocatable :: err
    real(wp), allocatable :: g(:), f0(:)
    real(wp) :: mean, std, s2, kurt
    integer :: p, ntrunc
    integer, parameter :: n = 400000
    allocate(g(n), f0(n))
    call random_normal_seed(r, 8)
    do p = 1, n
      call random_normal_next(r, g(p))
    end do
    call void_fraction_from_field(g, 0.005_wp, 0.003_wp, 'lognormal', f0, ntrunc, err)
    call check(.not. allocated(err), 'lognormal: no error')
    mean = sum(f0)/n
    std = sqrt(sum((f0 - mean)**2)/(n - 1))
    s2 = log(1.0_wp + (0.003_wp/0.005_wp)**2)
    kurt = exp(4*s2) + 2*exp(3*s2) + 3*exp(2*s2) - 3
    call check_close('lognormal: mean (3 sigma)', mean, 0.005_wp, 3*0.003_wp/sqrt(real(n, wp)))
    call check_close('lognormal: std (3 sigma)', std, 0.003_wp, 3*0.003_wp*sqrt((kurt - 1)/(4*real(n, wp))))
    call check(ntrunc == 0 .and. minval(f0) > 0.0_wp, 'lognormal: positive, none truncated')
  end subroutine test_lognormal

  !> Normal with mean 0.005, std 0.003 and [f_min, f_max] = [1e-6, 0.009]:
  !> ntrunc is the count of mean + std g outside the bounds, the others are
  !> unchanged, and the truncated share is near its probability
  !> Phi(-(0.005 - 1e-6)/0.003) + Phi(-(0.009 - 0.005)/0.003) (3 binomial
  !> sigmas).
  subroutine test_truncation()
    type(random_normal_t) :: r
    type(error_t), allocatable :: err
    real(wp), allocatable :: g(:), f0(:), f(:)
    real(wp) :: prob
    integer :: p, ntrunc
    integer, parameter :: n = 100000
    allocate(g(n), f0(n), f(n))
    call random_normal_seed(r, 4)
    do p = 1, n
      call random_normal_next(r, g(p))
    end do
    call void_fraction_from_field(g, 0.005_wp, 0.003_wp, 'normal', f0, ntrunc, err, f_max=0.009_wp)
    call check(.not. allocated(err), 'truncation: no error')
    f = 0.005_wp + 0.003_wp*g
    call check(ntrunc == count(f < 1.0e-6_wp .or. f > 0.009_wp), 'truncation: ntrunc counts the values out of bounds')
    call check(all(f0 >= 1.0e-6_wp .and. f0 <= 0.009_wp), 'truncation: all in [f_min, f_max]')
    call check(all(same_bits(f0, f) .or. f < 1.0e-6_wp .or. f > 0.009_wp), 'truncation: values in bounds unchanged')
    prob = 0.5_wp*erfc((0.005_wp - 1.0e-6_wp)/0.003_wp/sqrt(2.0_wp)) + 0.5_wp*erfc((0.009_wp - 0.005_wp)/0.003_wp/sqrt(2.0_wp))
    write(*, '(a,i0,a,i0)') 'truncation: ', ntrunc, ' of ', n
    call check_close('truncation: truncated share (3 sigma)', real(ntrunc, wp)/n, prob, 3*sqrt(prob*(1 - prob)/n))
  end subroutine test_truncation

  !> Bad input comes back as an input error, not a stop.
  subroutine test_errors()
    type(random_field_t) :: f
    type(error_t), allocatable :: err
    real(wp) :: clipped, g(1), f0(1)
    integer :: ntrunc
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 0.1_wp, 0.5_wp, 'matern', 1, f, clipped, err)
    call check(allocated(err), 'errors: unknown covariance')
    if (allocated(err)) then
      call check(err%category == ERR_INPUT, 'errors: unknown covariance is an input error')
      write(*, '(a)') 'errors: '//err%where//': '//err%msg
      deallocate(err)
    end if
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 0.1_wp, 0.5_wp, 'gaussian', 1, f, clipped, err)
    call random_field_sample(f, reshape([0.5_wp, 0.5_wp, 9.0_wp], [3, 1]), g, err)
    call check(allocated(err), 'errors: a point outside the grid')
    if (allocated(err)) then
      write(*, '(a)') 'errors: '//err%where//': '//err%msg
      deallocate(err)
    end if
    call void_fraction_from_field([0.0_wp], 0.005_wp, 0.0003_wp, 'weibull', f0, ntrunc, err)
    call check(allocated(err), 'errors: unknown distribution')
    if (allocated(err)) deallocate(err)
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [1.0e3_wp, 1.0e3_wp, 1.0e3_wp], 0.1_wp, 0.5_wp, 'gaussian', 1, f, &
                            clipped, err)
    call check(allocated(err), 'errors: a grid above 2^30 nodes')
    if (allocated(err)) then
      write(*, '(a)') 'errors: '//err%where//': '//err%msg
      deallocate(err)
    end if
    ! absurd sizes give the same error, not an overflow (the debug build
    ! traps floating-point overflow and invalid conversions)
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 0.1_wp, 1.0e-300_wp, 'gaussian', 1, f, &
                            clipped, err)
    call check(allocated(err), 'errors: ell = 1e-300')
    if (allocated(err)) deallocate(err)
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [1.0e300_wp, 1.0_wp, 1.0_wp], 0.1_wp, 0.5_wp, 'gaussian', 1, f, &
                            clipped, err)
    call check(allocated(err), 'errors: a box 1e300 long')
    if (allocated(err)) deallocate(err)
    call random_field_build([0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 0.1_wp, 0.5_wp, 'gaussian', 1, f, clipped, err)
    call random_field_sample(f, reshape([0.5_wp, 0.5_wp, ieee_value(1.0_wp, ieee_quiet_nan)], [3, 1]), g, err)
    call check(allocated(err), 'errors: a NaN point')
  end subroutine test_errors
end program test_random_field
