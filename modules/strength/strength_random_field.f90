!> Spatially correlated Gaussian random fields for the initial void fraction
!> of Gurson particles (PARTICLES.md §3; the paper's Table 5 gives a mean
!> and a standard deviation, not a correlation length). The project's only
!> user of FFTW: every FFTW call is in this module.
!>
!> Method (circulant embedding, exact for a nonnegative spectrum):
!>  1. a periodic grid of n(1) x n(2) x n(3) points with spacing dx covers
!>     the points' bounding box plus a padding (default 3 ell) on each side:
!>     the periodic (minimum-image) distance of two points in the box is
!>     their distance, or else both are at least 2 x padding, so every
!>     covariance is exact or both it and the periodic one are below
!>     C(6 ell) (exp(-36) Gaussian, 0.0025 exponential);
!>     dx = spacing / ceiling(spacing per_ell / ell) <= the
!>     caller's point spacing and <= ell/per_ell (per_ell default 4), and the
!>     grid has a node at lo, so points on the lattice lo + k spacing sit on
!>     nodes; each n is rounded up to a product of 2, 3, 5 and 7 (fast FFT).
!>     A direction whose extent is below the spacing gets one grid point: a
!>     one-cell-thick plane-strain model (pass lo(3) = hi(3)) gets a 2D
!>     field, constant through the thickness;
!>  2. c_j = C(r_j) on the grid, r_j the minimum-image distance of node j to
!>     node 1, with C(r) = exp(-r^2/ell^2) ('gaussian') or exp(-r/ell)
!>     ('exponential'); lambda = DFT(c) is real (c is even); negative
!>     lambda (measured: 3e-16 Gaussian, 0 to 2e-7 exponential) are set
!>     to 0 and their share of the variance, sum |lambda_-| / N, is returned
!>     as `clipped` so the caller can report it (the field variance is then
!>     1 + clipped);
!>  3. white noise w_j ~ N(0,1) from our own seeded generator (below), drawn
!>     on the whole grid in one fixed order (first index fastest), then
!>     g = IDFT(sqrt(lambda) DFT(w)) / N with FFTW's unnormalised r2c / c2r
!>     transforms: with F the unnormalised DFT (F^H F = N I) and the
!>     circulant covariance K = F^H diag(lambda) F / N,
!>     cov(g) = F^H Lambda^(1/2) F F^H Lambda^(1/2) F / N^2 = K: mean 0,
!>     variance 1, correlation C(r);
!>  4. sampling at a point: trilinear interpolation of the 8 surrounding
!>     nodes divided by the standard deviation of that interpolant,
!>     sqrt(sum_ab w_a w_b C(x_a - x_b)), so every sample is exactly N(0,1)
!>     (plain interpolation would lower the variance between nodes, by up to
!>     30 % in 3D with 2 nodes per ell). Points on nodes get the node values;
!>     between nodes the interpolation smooths the field, which raises the
!>     correlation at lag ell above exp(-1) = 0.368. In 2D, averaged over
!>     the offset from the nodes (worst case, half way, in brackets):
!>         per_ell          2              4              8
!>         gaussian     0.425 (0.455)  0.383 (0.391)  0.372 (0.374)
!>         exponential  0.481 (0.539)  0.424 (0.451)  0.396 (0.408)
!>     Hence the default per_ell = 4 (particles on a curvilinear grid are
!>     not on a lattice); the exponential field is rough at every scale and
!>     needs per_ell = 8 for the same fidelity. test_random_field checks the
!>     half-way values.
!>  The Gaussian covariance is built without the 3D transform, by the
!>  separable square root of its covariance (`random_field_build`'s
!>  box_lo, box_hi; `kernel_1d`, `build_separable`): the same white noise
!>  convolved along x, y and z with factors exp(-2 (m dx/ell)^2), on the
!>  nodes around the points a caller samples, so a decomposed run's block
!>  builds its own part. Steps 1 (the grid), 3 (the noise's order) and 4
!>  are the same; step 2's spectrum is that of the kernel, positive.
!>  ell = 0 or covariance 'none' is the uncorrelated limit (Uintah, Yang et
!>  al.): no grid; sampling gives i.i.d. N(0,1) values, the p-th point the
!>  p-th normal of the seeded stream.
!>
!> Reproducibility: the normal generator is xoshiro256** (Blackman and
!> Vigna) seeded through splitmix64, written with 32-bit halves so that no
!> signed integer overflows, and normals by Marsaglia's polar method (one
!> log and one sqrt per pair, no sin/cos): the same seed gives the same
!> white noise on any build and thread count, not the compiler's
!> random_number (the only library call, log, is the C library's). The
!> FFTs use FFTW_ESTIMATE plans on FFTW-allocated (SIMD-aligned) buffers,
!> so a build on one machine gives the same bits on every run (and here the
!> Debug and Release builds agree bit for bit); another CPU, or
!> -march=native with fused multiply-adds, may differ in the last bits. The
!> threaded loops (covariance, spectrum, sampling, void fractions) write
!> each value from the same operands in the same order, and sums are taken
!> per plane and then serially: the result is bit-identical for any
!> OMP_NUM_THREADS (random_field_threads checks 1 against 2).
!>
!> How a caller (the Gurson set-up) uses it, once, before step 0:
!>
!>     type(random_field_t) :: field
!>     real(wp) :: clipped
!>     real(wp), allocatable :: g(:), f0(:)
!>     integer :: ntrunc
!>     ! lo, hi: the bounding box of all (global) Gurson particles; for a
!>     ! plane-strain model set lo(3) = hi(3); spacing: the particle spacing
!>     ! (ell = 0 or 'none': i.i.d.; per_ell = 8 for 'exponential' off a
!>     ! lattice, see 4. above)
!>     call random_field_build(lo, hi, spacing, ell, 'gaussian', seed, field, clipped, err)
!>     if (allocated(err)) return
!>     allocate(g(np), f0(np), stat=...)
!>     call random_field_sample(field, x, g, err)      ! x(3, np), particles in
!>     if (allocated(err)) return                       ! global-id order
!>     call void_fraction_from_field(g, f_mean, f_std, 'normal', f0, ntrunc, err)
!>     ! ('lognormal': same mean and std, positive; optional f_min, f_max)
!>     ! the driver logs clipped (a fraction of the variance) and
!>     ! ntrunc/np (particles clipped to [f_min, f_max]); f0 goes in the
!>     ! particles' history and in restarts (the field itself is not kept).
!>
!> Call random_field_build outside OpenMP parallel regions (FFTW's planner
!> is not thread-safe; the routine returns an error inside one). With MPI,
!> every rank builds from the global bounding box (lo, hi), each the part
!> around its own points (box_lo, box_hi) for the Gaussian covariance,
!> else the whole field on one rank that samples for all (the Gurson
!> set-up), so the field does not depend on the rank count; in the
!> uncorrelated limit pass the points in global order.
module strength_random_field
  use, intrinsic :: iso_c_binding, only: c_char, c_double, c_double_complex, c_float, c_float_complex, c_funptr, c_int32_t, &
                                         c_int, c_intptr_t, c_ptr, c_size_t, c_f_pointer, c_associated
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use base_kinds, only: wp, i8
  use base_errors, only: error_no_memory, error_t, error_set, ERR_INPUT
  !$ use omp_lib, only: omp_in_parallel
  implicit none
  private
  public :: random_field_t, random_field_build, random_field_sample, void_fraction_from_field, &
            random_field_correlated, random_field_covariances, void_fraction_distributions, &
            random_normal_t, random_normal_seed, random_normal_next, random_bits_next

  include 'fftw3.f03'

  !> The covariance names random_field_build knows.
  character(len=*), parameter :: random_field_covariances(3) = [character(len=11) :: 'gaussian', 'exponential', 'none']
  !> The distribution names void_fraction_from_field knows.
  character(len=*), parameter :: void_fraction_distributions(2) = [character(len=9) :: 'normal', 'lognormal']

  !> The largest grid random_field_build makes (2^30 nodes: 8 GiB per real
  !> array); a larger one is a deck mistake (ell or the spacing far too small).
  integer(i8), parameter :: max_nodes = 2_i8**30

  !> The low 32 bits of a 64-bit integer.
  integer(i8), parameter :: mask32 = int(z'FFFFFFFF', i8)
  !> splitmix64's constants (0x9E3779B97F4A7C15, 0xBF58476D1CE4E5B9,
  !> 0x94D049BB133111EB), assembled from 32-bit halves.
  integer(i8), parameter :: sm_gamma = ior(shiftl(int(z'9E3779B9', i8), 32), int(z'7F4A7C15', i8))
  integer(i8), parameter :: sm_mul1 = ior(shiftl(int(z'BF58476D', i8), 32), int(z'1CE4E5B9', i8))
  integer(i8), parameter :: sm_mul2 = ior(shiftl(int(z'94D049BB', i8), 32), int(z'133111EB', i8))

  !> A stream of N(0,1) numbers: xoshiro256** state and the second normal of
  !> the last polar pair, if not yet used.
  type :: random_normal_t
    integer(i8) :: s(4) = 0_i8
    logical :: have_spare = .false.
    real(wp) :: spare = 0.0_wp
  end type random_normal_t

  !> A unit-variance, zero-mean Gaussian random field on a regular grid, or
  !> (correlated = .false.) the recipe for i.i.d. samples.
  type :: random_field_t
    logical :: correlated = .false.          !< .false.: uncorrelated limit, no grid
    character(len=11) :: covariance = 'none' !< 'gaussian', 'exponential' or 'none'
    real(wp) :: ell = 0.0_wp                 !< correlation length (length)
    integer :: seed = 0                      !< the seed of the white noise
    real(wp) :: origin(3) = 0.0_wp           !< position of node (1,1,1) (length)
    real(wp) :: dx = 0.0_wp                  !< grid spacing, the same in all directions (length)
    integer :: n(3) = 1                      !< nodes per direction (1: field constant along it)
    real(wp) :: cm(0:3) = 1.0_wp             !< C(dx sqrt(m)): covariance of nodes m edges apart
    !> the nodes held: values(i, j, k) is node (first(1) + i - 1, ...) of
    !> the n(1) x n(2) x n(3) grid (the whole grid, first = 1, or the part a
    !> caller's points need: `random_field_build`'s box_lo, box_hi)
    integer :: first(3) = 1
    real(wp), allocatable :: values(:, :, :)
  end type random_field_t

  !> One direction's factor of a Gaussian field's kernel (`kernel_1d`):
  !> k(m) for the offsets m = mlo..mhi (node j takes k(m) times the noise
  !> of node j - m, periodic)
  type :: kernel_1d_t
    integer :: mlo = 0, mhi = 0
    real(wp), allocatable :: k(:)
  end type kernel_1d_t

  !> A kernel factor's taps reach this many ell (`kernel_1d`): beyond it
  !> exp(-2 (m dx/ell)^2) < 1e-17, below the round-off of a value of unit
  !> variance.
  real(wp), parameter :: kernel_reach = 4.42_wp

contains

  ! ---------------------------------------------------------------- generator

  !> a + b modulo 2^64 on the bit patterns, without signed overflow.
  pure elemental integer(i8) function wrap_add(a, b) result(s)
    integer(i8), intent(in) :: a, b
    integer(i8) :: lo, hi
    lo = iand(a, mask32) + iand(b, mask32)
    hi = shiftr(a, 32) + shiftr(b, 32) + shiftr(lo, 32)
    s = ior(shiftl(hi, 32), iand(lo, mask32))
  end function wrap_add

  !> a b modulo 2^64 on the bit patterns, from 16-bit limbs (each partial
  !> product below 2^32), without signed overflow.
  pure integer(i8) function wrap_mul(a, b) result(p)
    integer(i8), intent(in) :: a, b
    integer(i8) :: al(0:3), bl(0:3)
    integer :: i, j
    do i = 0, 3
      al(i) = ibits(a, 16*i, 16)
      bl(i) = ibits(b, 16*i, 16)
    end do
    p = 0_i8
    do i = 0, 3
      do j = 0, 3 - i
        p = wrap_add(p, shiftl(al(i)*bl(j), 16*(i + j)))
      end do
    end do
  end function wrap_mul

  !> One splitmix64 step: advances x and gives the next output z.
  pure subroutine splitmix64_next(x, z)
    integer(i8), intent(inout) :: x
    integer(i8), intent(out) :: z
    x = wrap_add(x, sm_gamma)
    z = x
    z = wrap_mul(ieor(z, shiftr(z, 30)), sm_mul1)
    z = wrap_mul(ieor(z, shiftr(z, 27)), sm_mul2)
    z = ieor(z, shiftr(z, 31))
  end subroutine splitmix64_next

  !> Seeds a normal stream: xoshiro256**'s four words are the first four
  !> outputs of splitmix64 started at the seed (as Vigna recommends; never
  !> all zero).
  pure subroutine random_normal_seed(r, seed)
    type(random_normal_t), intent(out) :: r
    integer, intent(in) :: seed
    integer(i8) :: x
    integer :: i
    x = int(seed, i8)
    do i = 1, 4
      call splitmix64_next(x, r%s(i))
    end do
    r%have_spare = .false.
    r%spare = 0.0_wp
  end subroutine random_normal_seed

  !> The next 64 random bits b of xoshiro256** (the bit pattern of the
  !> reference C implementation's uint64_t output).
  pure subroutine random_bits_next(r, b)
    type(random_normal_t), intent(inout) :: r
    integer(i8), intent(out) :: b
    integer(i8) :: t, x
    ! rotl(s1 * 5, 7) * 9, the products as shift-and-add
    x = wrap_add(shiftl(r%s(2), 2), r%s(2))
    x = ishftc(x, 7)
    b = wrap_add(shiftl(x, 3), x)
    t = shiftl(r%s(2), 17)
    r%s(3) = ieor(r%s(3), r%s(1))
    r%s(4) = ieor(r%s(4), r%s(2))
    r%s(2) = ieor(r%s(2), r%s(3))
    r%s(1) = ieor(r%s(1), r%s(4))
    r%s(3) = ieor(r%s(3), t)
    r%s(4) = ishftc(r%s(4), 45)
  end subroutine random_bits_next

  !> The next N(0,1) number z of the stream (Marsaglia's polar method: u,
  !> v uniform in (-1,1), s = u^2 + v^2 in (0,1), then u and v times
  !> sqrt(-2 ln s / s) are two independent normals).
  pure subroutine random_normal_next(r, z)
    type(random_normal_t), intent(inout) :: r
    real(wp), intent(out) :: z
    real(wp) :: u, v, s, f
    integer(i8) :: bu, bv
    if (r%have_spare) then
      r%have_spare = .false.
      z = r%spare
      return
    end if
    do
      ! top 53 bits as a fraction in [0,1), mapped to [-1,1)
      call random_bits_next(r, bu)
      call random_bits_next(r, bv)
      u = 2.0_wp*real(shiftr(bu, 11), wp)*2.0_wp**(-53) - 1.0_wp
      v = 2.0_wp*real(shiftr(bv, 11), wp)*2.0_wp**(-53) - 1.0_wp
      s = u*u + v*v
      if (s < 1.0_wp .and. s > 0.0_wp) exit
    end do
    f = sqrt(-2.0_wp*log(s)/s)
    z = u*f
    r%spare = v*f
    r%have_spare = .true.
  end subroutine random_normal_next

  ! ---------------------------------------------------------------- field

  !> Covariance C(r) of the model `kind` ('gaussian' or 'exponential') at
  !> distance r for correlation length ell (r, ell: length).
  pure real(wp) function covariance_at(kind, r, ell) result(c)
    character(len=*), intent(in) :: kind
    real(wp), intent(in) :: r, ell
    real(wp) :: a
    if (kind == 'gaussian') then
      a = (r/ell)**2
    else
      a = r/ell
    end if
    ! beyond exp(-700) the value is below every tolerance (and would be
    ! subnormal)
    if (a > 700.0_wp) then
      c = 0.0_wp
    else
      c = exp(-a)
    end if
  end function covariance_at

  !> The smallest n >= m whose prime factors are 2, 3, 5 and 7 only.
  pure integer function fft_size(m) result(n)
    integer, intent(in) :: m
    integer :: k, p
    integer, parameter :: primes(4) = [2, 3, 5, 7]
    n = max(m, 1)
    do
      k = n
      do p = 1, 4
        do while (mod(k, primes(p)) == 0)
          k = k/primes(p)
        end do
      end do
      if (k == 1) exit
      n = n + 1
    end do
  end function fft_size

  !> Whether random_field_build builds a grid for this covariance and ell
  !> (a correlated field), rather than the uncorrelated limit (ell = 0 or
  !> covariance 'none': no grid, a seeded stream).
  pure logical function random_field_correlated(covariance, ell) result(yes)
    character(len=*), intent(in) :: covariance
    real(wp), intent(in) :: ell
    yes = covariance /= 'none' .and. ell > 0.0_wp
  end function random_field_correlated

  !> Builds the unit-variance Gaussian random field that covers the box
  !> [lo, hi] (length; the bounding box of all the points that will be
  !> sampled) with correlation length ell (length) and covariance
  !> 'gaussian' (C(r) = exp(-r^2/ell^2)), 'exponential' (exp(-r/ell)) or
  !> 'none', from the white noise of `seed` (module notes).
  !> spacing (length, > 0): the points' spacing; the grid spacing is at most
  !> spacing and ell/per_ell, and a direction with hi - lo < spacing gets a
  !> single node. ell = 0 or 'none': the uncorrelated limit (no grid).
  !> clipped: the share of the variance in the negative eigenvalues set to 0
  !> (0 for the Gaussian covariance up to round-off; report it).
  !> Optional: per_ell (default 4) grid nodes per ell at least, padding
  !> (length, default 3 ell) added on each side of the box (less than 3 ell
  !> makes covariances beyond about twice the padding inexact).
  !> box_lo, box_hi (length; both or neither; default: the whole grid):
  !> the points this caller will sample lie in this box. The Gaussian
  !> covariance is separable, and so is the square root of its circulant
  !> embedding: g = IDFT(sqrt(lambda) DFT(w)) / N is the periodic
  !> convolution of the noise with a kernel k1(m1) k2(m2) k3(m3), each
  !> factor exp(-2 (m dx/ell)^2) scaled to unit energy (`kernel_1d`; with
  !> dx <= ell/4, else the transform below). The field is then made by
  !> three passes of one-dimensional sums over the taps within
  !> kernel_reach ell, on the nodes around the box only
  !> (`build_separable`): a decomposed run's blocks each build the part
  !> their particles need, in memory that follows the block, not the whole
  !> grid. A node's value is the same sum of the same noise in the same
  !> order whatever the box, so every part holds the whole field's values
  !> bit for bit. whole_fft (default .false.): a Gaussian field by the
  !> three-dimensional transform instead (the exponential covariance's
  !> way), on the whole grid; the two differ by the transform's round-off
  !> of lambda raised by its square root, some 1e-7 (test_random_field).
  !> Errors (input): a value that is not finite, unknown covariance,
  !> spacing <= 0, ell < 0, hi < lo, per_ell < 1, a grid above 2^30 nodes;
  !> (runtime) allocation, FFTW planning, called inside an OpenMP parallel
  !> region.
  subroutine random_field_build(lo, hi, spacing, ell, covariance, seed, field, clipped, err, per_ell, padding, &
                                box_lo, box_hi, whole_fft)
    real(wp), intent(in) :: lo(3), hi(3), spacing, ell
    character(len=*), intent(in) :: covariance
    integer, intent(in) :: seed
    type(random_field_t), intent(out) :: field
    real(wp), intent(out) :: clipped
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: per_ell
    real(wp), intent(in), optional :: padding
    real(wp), intent(in), optional :: box_lo(3), box_hi(3)
    logical, intent(in), optional :: whole_fft
    character(len=*), parameter :: where = 'random_field_build'
    integer :: nper, d, npad, m, n1, n2, n3, nh, i, j, k, ii, jj, kk, stat
    integer(i8) :: ntot
    real(wp) :: pad, dx, ext, rx2, ry2, rz2, lam, w, scale, big, blo(3), bhi(3), t
    integer :: a(3), b(3)
    logical :: fft
    real(wp), allocatable :: sqlam(:, :, :), negk(:)
    type(c_ptr) :: preal, pcplx, plan_fwd, plan_bwd
    real(c_double), pointer, contiguous :: rbuf(:, :, :)
    complex(c_double_complex), pointer, contiguous :: cbuf(:, :, :)
    type(random_normal_t) :: rng
    character(len=320) :: msg, emsg

    clipped = 0.0_wp
    if (.not. (all(ieee_is_finite(lo)) .and. all(ieee_is_finite(hi)) .and. ieee_is_finite(spacing) .and. &
               ieee_is_finite(ell))) then
      call error_set(err, where, 'lo, hi, spacing and ell must be finite numbers', ERR_INPUT)
      return
    end if
    if (present(padding)) then
      if (.not. ieee_is_finite(padding)) then
        call error_set(err, where, 'padding must be a finite number', ERR_INPUT)
        return
      end if
    end if
    if (.not. any(random_field_covariances == covariance)) then
      call error_set(err, where, 'covariance = '''//trim(covariance)// &
                     ''' is not known; valid: gaussian, exponential, none', ERR_INPUT)
      return
    end if
    if (.not. (spacing > 0.0_wp)) then
      write(msg, '(a,es12.4,a)') 'spacing = ', spacing, ' must be > 0'
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    if (.not. (ell >= 0.0_wp)) then
      write(msg, '(a,es12.4,a)') 'ell = ', ell, ' must be >= 0'
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    if (.not. all(hi >= lo)) then
      call error_set(err, where, 'the box has hi < lo', ERR_INPUT)
      return
    end if
    nper = 4
    if (present(per_ell)) nper = per_ell
    if (nper < 1) then
      write(msg, '(a,i0,a)') 'per_ell = ', nper, ' must be >= 1'
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    field%covariance = covariance
    field%ell = ell
    field%seed = seed
    if (.not. random_field_correlated(covariance, ell)) then
      field%correlated = .false.
      return
    end if
    !$ if (omp_in_parallel()) then
    !$   call error_set(err, where, 'called inside an OpenMP parallel region (FFTW planning is not thread-safe)')
    !$   return
    !$ end if

    ! 1. the grid: dx divides spacing, a node at lo, npad nodes of padding.
    ! Sizes are compared in reals first, so that an absurd box or ell gives
    ! the error below, not an integer or floating-point overflow.
    big = real(max_nodes, wp)
    pad = 3.0_wp*ell
    if (present(padding)) pad = max(padding, 0.0_wp)
    ntot = max_nodes + 1_i8
    if (spacing*real(nper, wp) <= big*ell) then
      dx = spacing/real(max(1, ceiling(spacing*real(nper, wp)/ell)), wp)
      if (pad <= big*dx) then
        npad = ceiling(pad/dx)
        ntot = 1_i8
        do d = 1, 3
          ext = hi(d) - lo(d)
          if (ext < spacing) then
            field%n(d) = 1
            field%origin(d) = 0.5_wp*(lo(d) + hi(d))
          else
            if (ext > big*dx .or. ext/dx + 2.0_wp*real(npad, wp) + 1.0_wp > big) then
              ntot = max_nodes + 1_i8
              exit
            end if
            ! (the last lattice point may fall a rounding error beyond a
            ! node: one node more is harmless)
            m = ceiling(ext/dx)
            field%n(d) = fft_size(m + 2*npad + 1)
            field%origin(d) = lo(d) - real(npad, wp)*dx
          end if
          ntot = ntot*int(field%n(d), i8)
        end do
      end if
    end if
    if (ntot > max_nodes) then
      field%n = 1
      write(msg, '(a,es10.3,a,es10.3,a,es10.3,a)') 'the field grid for ell = ', ell, ' and spacing ', spacing, &
        ' would have more than ', big, &
        ' nodes (resolved to ell/N or finer and padded by 3 ell on each side): choose an ell nearer the size of'// &
        ' the particles'' box, or ell = 0'
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    field%dx = dx
    do m = 0, 3
      field%cm(m) = covariance_at(covariance, dx*sqrt(real(m, wp)), ell)
    end do

    ! (the separable kernel where its lattice aliasing is negligible:
    ! dx <= ell/4, as per_ell's default always gives)
    fft = covariance /= 'gaussian' .or. dx > 0.25_wp*ell*(1.0_wp + 1.0e-12_wp)
    if (present(whole_fft)) fft = fft .or. whole_fft
    if (.not. fft) then
      ! the nodes around the box: those a point in it interpolates from
      ! (`sample_one`), one more on each side against rounding
      ! (without a box: the whole grid)
      blo = lo
      bhi = hi
      if (present(box_lo)) blo = box_lo
      if (present(box_hi)) bhi = box_hi
      do d = 1, 3
        a(d) = 1
        b(d) = field%n(d)
        if (field%n(d) == 1 .or. .not. (present(box_lo) .and. present(box_hi))) cycle
        a(d) = field%n(d) - 1
        t = (blo(d) - field%origin(d))/dx
        if (ieee_is_finite(t)) a(d) = max(1, min(field%n(d) - 1, floor(max(t, 0.0_wp))))
        t = (bhi(d) - field%origin(d))/dx
        if (ieee_is_finite(t)) b(d) = min(field%n(d), floor(min(max(t, 0.0_wp), real(field%n(d), wp))) + 3)
        b(d) = max(a(d) + 1, b(d))
      end do
      call build_separable(field, a, b, clipped, err)
      return
    end if

    n1 = field%n(1)
    n2 = field%n(2)
    n3 = field%n(3)
    nh = n1/2 + 1
    ! (the field's own array comes once the transforms' complex buffer and
    ! sqrt(lambda) are let go: the peak is the two buffers and sqlam, about
    ! 20 bytes per node, not 28)
    allocate(sqlam(nh, n2, n3), negk(n3), stat=stat, errmsg=emsg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('the field grid''s arrays ('//trim(grid_text(field%n))//')'))
      return
    end if
    ! FFTW's own allocation: SIMD-aligned on every run, so the plan (and
    ! the bits) do not depend on where malloc happened to put an array
    preal = fftw_alloc_real(int(ntot, c_size_t))
    pcplx = fftw_alloc_complex(int(nh, c_size_t)*int(n2, c_size_t)*int(n3, c_size_t))
    if (.not. (c_associated(preal) .and. c_associated(pcplx))) then
      call fftw_free(preal)
      call fftw_free(pcplx)
      call error_set(err, where, error_no_memory('the FFT buffers ('//trim(grid_text(field%n))//')'))
      return
    end if
    call c_f_pointer(preal, rbuf, [n1, n2, n3])
    call c_f_pointer(pcplx, cbuf, [nh, n2, n3])
    ! Fortran's column-major a(n1,n2,n3) is FFTW's row-major (n3,n2,n1);
    ! r2c halves the first Fortran index. Plans first: planning may use
    ! the buffers.
    plan_fwd = fftw_plan_dft_r2c_3d(int(n3, c_int), int(n2, c_int), int(n1, c_int), rbuf, cbuf, FFTW_ESTIMATE)
    plan_bwd = fftw_plan_dft_c2r_3d(int(n3, c_int), int(n2, c_int), int(n1, c_int), cbuf, rbuf, FFTW_ESTIMATE)
    if (.not. (c_associated(plan_fwd) .and. c_associated(plan_bwd))) then
      if (c_associated(plan_fwd)) call fftw_destroy_plan(plan_fwd)
      if (c_associated(plan_bwd)) call fftw_destroy_plan(plan_bwd)
      call fftw_free(preal)
      call fftw_free(pcplx)
      call error_set(err, where, 'FFTW could not plan the transforms')
      return
    end if

    ! 2. c_j = C(minimum-image distance to node 1), then lambda = DFT(c)
    !$omp parallel do default(none) shared(rbuf, field, covariance, ell, dx, n1, n2, n3) &
    !$omp   private(i, j, k, ii, jj, kk, rx2, ry2, rz2)
    do k = 1, n3
      kk = min(k - 1, n3 - k + 1)
      rz2 = (real(kk, wp)*dx)**2
      do j = 1, n2
        jj = min(j - 1, n2 - j + 1)
        ry2 = (real(jj, wp)*dx)**2
        do i = 1, n1
          ii = min(i - 1, n1 - i + 1)
          rx2 = (real(ii, wp)*dx)**2
          rbuf(i, j, k) = covariance_at(covariance, sqrt(rx2 + ry2 + rz2), ell)
        end do
      end do
    end do
    !$omp end parallel do
    call fftw_execute_dft_r2c(plan_fwd, rbuf, cbuf)
    ! sqrt(lambda), negatives clipped; their sum per plane k (then summed
    ! serially, so the total does not depend on the threads). Each stored
    ! i other than 0 and the Nyquist index n1/2 stands for two modes.
    !$omp parallel do default(none) shared(cbuf, sqlam, negk, nh, n1, n2, n3) private(i, j, k, lam, w)
    do k = 1, n3
      negk(k) = 0.0_wp
      do j = 1, n2
        do i = 1, nh
          lam = real(cbuf(i, j, k), wp)
          if (lam < 0.0_wp) then
            w = 2.0_wp
            if (i == 1 .or. 2*(i - 1) == n1) w = 1.0_wp
            negk(k) = negk(k) - w*lam
            lam = 0.0_wp
          end if
          sqlam(i, j, k) = sqrt(lam)
        end do
      end do
    end do
    !$omp end parallel do
    do k = 1, n3
      clipped = clipped + negk(k)
    end do
    clipped = clipped/real(ntot, wp)

    ! 3. white noise in one fixed order (first index fastest), then
    ! g = IDFT(sqrt(lambda) DFT(w)) / N
    call random_normal_seed(rng, seed)
    do k = 1, n3
      do j = 1, n2
        do i = 1, n1
          call random_normal_next(rng, rbuf(i, j, k))
        end do
      end do
    end do
    call fftw_execute_dft_r2c(plan_fwd, rbuf, cbuf)
    !$omp parallel do default(none) shared(cbuf, sqlam, nh, n2, n3) private(i, j, k)
    do k = 1, n3
      do j = 1, n2
        do i = 1, nh
          cbuf(i, j, k) = cbuf(i, j, k)*sqlam(i, j, k)
        end do
      end do
    end do
    !$omp end parallel do
    call fftw_execute_dft_c2r(plan_bwd, cbuf, rbuf)
    call fftw_destroy_plan(plan_fwd)
    call fftw_destroy_plan(plan_bwd)
    call fftw_free(pcplx)
    deallocate(sqlam)
    allocate(field%values(n1, n2, n3), stat=stat, errmsg=emsg)
    if (stat /= 0) then
      call fftw_free(preal)
      call error_set(err, where, error_no_memory('the field grid''s values ('//trim(grid_text(field%n))//')'))
      return
    end if
    scale = 1.0_wp/real(ntot, wp)
    !$omp parallel do default(none) shared(rbuf, field, scale, n1, n2, n3) private(i, j, k)
    do k = 1, n3
      do j = 1, n2
        do i = 1, n1
          field%values(i, j, k) = rbuf(i, j, k)*scale
        end do
      end do
    end do
    !$omp end parallel do
    call fftw_free(preal)
    field%correlated = .true.
  end subroutine random_field_build

  !> The Gaussian field of `random_field_build` on the nodes a(d)..b(d) of
  !> its grid (field%n, dx set), as the periodic convolution of the white
  !> noise with the separable kernel k1 k2 k3 (`kernel_1d`): the noise is
  !> drawn in the one fixed order over the whole grid (each rank draws the
  !> whole stream and keeps what its nodes read), convolved along x as each
  !> plane is drawn (xs, on the rows the later passes read), then along y
  !> (ys) and z (field%values). clipped: 0 (the kernel's spectrum is
  !> positive).
  subroutine build_separable(field, a, b, clipped, err)
    type(random_field_t), intent(inout) :: field
    integer, intent(in) :: a(3), b(3)
    real(wp), intent(out) :: clipped
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: where = 'random_field_build'
    type(kernel_1d_t) :: kd(3)
    type(random_normal_t) :: rng
    real(wp) :: sm
    real(wp), allocatable :: plane(:, :), xs(:, :, :), ys(:, :, :), row(:)
    integer, allocatable :: jmap(:), kmap(:), jlist(:), klist(:)
    integer :: d, i, j, k, m, n1, n2, n3, nj, nk, stat, jj, kk, q

    clipped = 0.0_wp
    do d = 1, 3
      call kernel_1d(field, d, kd(d), err)
      if (allocated(err)) return
    end do
    n1 = field%n(1)
    n2 = field%n(2)
    n3 = field%n(3)
    ! the rows (j) and planes (k) the passes read: node j0 of a..b reads
    ! j0 - m for the taps m (periodic)
    call reach_rows(n2, a(2), b(2), kd(2), jmap, jlist, stat)
    if (stat == 0) call reach_rows(n3, a(3), b(3), kd(3), kmap, klist, stat)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('the field''s row lists'))
      return
    end if
    nj = size(jlist)
    nk = size(klist)
    allocate(row(a(1) - kd(1)%mhi:b(1) - kd(1)%mlo), plane(n1, nj), xs(b(1) - a(1) + 1, nj, nk), &
             field%values(b(1) - a(1) + 1, b(2) - a(2) + 1, b(3) - a(3) + 1), stat=stat)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('the field''s part ('//trim(grid_text(b - a + 1))//')'))
      return
    end if
    field%first = a
    call random_normal_seed(rng, field%seed)
    do k = 1, n3
      ! (every normal of the stream is drawn, in order; the rows kept are
      ! those the passes read)
      do j = 1, n2
        if (kmap(k) > 0 .and. jmap(j) > 0) then
          do i = 1, n1
            call random_normal_next(rng, plane(i, jmap(j)))
          end do
        else
          do i = 1, n1
            call random_normal_next(rng, sm)
          end do
        end if
      end do
      if (kmap(k) == 0) cycle
      kk = kmap(k)
      ! (each row unrolled over its period first: row(i) is node i, wrapped,
      ! for the i - m that nodes a..b read)
      !$omp parallel do default(none) shared(plane, xs, kd, a, b, n1, nj, kk) private(jj, i, m, sm, row) schedule(static)
      do jj = 1, nj
        do i = a(1) - kd(1)%mhi, b(1) - kd(1)%mlo
          row(i) = plane(modulo(i - 1, n1) + 1, jj)
        end do
        do i = a(1), b(1)
          sm = 0.0_wp
          do m = kd(1)%mlo, kd(1)%mhi
            sm = sm + kd(1)%k(m)*row(i - m)
          end do
          xs(i - a(1) + 1, jj, kk) = sm
        end do
      end do
      !$omp end parallel do
    end do
    deallocate(plane, row)
    allocate(ys(b(1) - a(1) + 1, b(2) - a(2) + 1, nk), stat=stat)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('the field''s part ('//trim(grid_text(b - a + 1))//')'))
      return
    end if
    !$omp parallel do default(none) shared(xs, ys, kd, jmap, a, b, n2, nk) private(q, j, i, m) schedule(static)
    do q = 1, nk
      do j = a(2), b(2)
        ys(:, j - a(2) + 1, q) = 0.0_wp
        do m = kd(2)%mlo, kd(2)%mhi
          do i = 1, b(1) - a(1) + 1
            ys(i, j - a(2) + 1, q) = ys(i, j - a(2) + 1, q) + kd(2)%k(m)*xs(i, jmap(modulo(j - m - 1, n2) + 1), q)
          end do
        end do
      end do
    end do
    !$omp end parallel do
    deallocate(xs)
    !$omp parallel do default(none) shared(ys, field, kd, kmap, a, b, n3) private(k, m) schedule(static)
    do k = a(3), b(3)
      field%values(:, :, k - a(3) + 1) = 0.0_wp
      do m = kd(3)%mlo, kd(3)%mhi
        field%values(:, :, k - a(3) + 1) = field%values(:, :, k - a(3) + 1) + kd(3)%k(m)*ys(:, :, kmap(modulo(k - m - 1, n3) + 1))
      end do
    end do
    !$omp end parallel do
    field%correlated = .true.
  end subroutine build_separable

  !> The indices j of a periodic line of n that nodes a..b read through the
  !> taps of kd (j0 - m, m = kd%mlo..kd%mhi, wrapped), in increasing order
  !> (list), and each one's place in the list (map(j), 0 if not read).
  !> stat: the allocations'.
  pure subroutine reach_rows(n, a, b, kd, map, list, stat)
    integer, intent(in) :: n, a, b
    type(kernel_1d_t), intent(in) :: kd
    integer, allocatable, intent(out) :: map(:), list(:)
    integer, intent(out) :: stat
    integer :: j, c
    allocate(map(n), stat=stat)
    if (stat /= 0) return
    map = 0
    if ((b - a) + (kd%mhi - kd%mlo) + 1 >= n) then
      map = 1
    else
      do j = a - kd%mhi, b - kd%mlo
        map(modulo(j - 1, n) + 1) = 1
      end do
    end if
    allocate(list(count(map > 0)), stat=stat)
    if (stat /= 0) return
    c = 0
    do j = 1, n
      if (map(j) == 0) cycle
      c = c + 1
      map(j) = c
      list(c) = j
    end do
  end subroutine reach_rows

  !> Direction d's factor of the Gaussian field's kernel on the periodic
  !> line of n = field%n(d) nodes: k(m) = exp(-2 (m dx/ell)^2), summed over
  !> the periods where the taps would span the line, scaled to
  !> sum_m k(m)^2 = 1. Its self-convolution is the covariance factor
  !> exp(-(r/ell)^2) (the product of two Gaussians of variance ell^2/4
  !> integrates to one of variance ell^2/2), up to the lattice's aliasing
  !> exp(-pi^2 ell^2/(4 dx^2)) (7e-18 at dx = ell/4, the largest spacing
  !> this path takes), and its spectrum is positive: it is the square root
  !> of the circulant covariance that the transform takes from the
  !> eigenvalues, without their round-off (eps lambda(0)), which the square
  !> root raises to a noise of some 1e-7 in the transform's field. Taps
  !> beyond kernel_reach ell (k below 1e-17) are left out. A single node:
  !> k = 1.
  subroutine kernel_1d(field, d, kd, err)
    type(random_field_t), intent(in) :: field
    integer, intent(in) :: d
    type(kernel_1d_t), intent(out) :: kd
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: h, norm
    integer :: n, m, p, reach, np, stat

    n = field%n(d)
    h = field%dx/field%ell
    reach = 0
    if (n > 1) reach = ceiling(kernel_reach/h)
    if (2*reach + 1 >= n) then
      kd%mlo = -((n - 1)/2)
      kd%mhi = n/2
    else
      kd%mlo = -reach
      kd%mhi = reach
    end if
    allocate(kd%k(kd%mlo:kd%mhi), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'random_field_build', error_no_memory('the kernel'))
      return
    end if
    ! (the periods whose taps reach the line: none beyond the nearest
    ! where the taps fit in it)
    np = 0
    if (2*reach + 1 >= n) np = reach/n + 1
    norm = 0.0_wp
    do m = kd%mlo, kd%mhi
      kd%k(m) = 0.0_wp
      do p = -np, np
        if (abs(m + p*n) <= reach) kd%k(m) = kd%k(m) + exp(-2.0_wp*(real(m + p*n, wp)*h)**2)
      end do
      norm = norm + kd%k(m)**2
    end do
    kd%k = kd%k/sqrt(norm)
  end subroutine kernel_1d

  !> Samples the field at the points x(3, np) (length) into g(np): unit
  !> variance interpolation of the 8 surrounding nodes (module notes); in
  !> the uncorrelated limit g(p) is the p-th normal of the seeded stream.
  !> Errors (input): shapes that do not match; a point outside the field's
  !> grid (the box given to random_field_build plus its padding).
  subroutine random_field_sample(field, x, g, err)
    type(random_field_t), intent(in) :: field
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: g(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: where = 'random_field_sample'
    type(random_normal_t) :: rng
    integer :: p, np, bad
    logical :: inside
    character(len=200) :: msg

    np = size(g)
    if (size(x, 1) /= 3 .or. size(x, 2) /= np) then
      write(msg, '(a,i0,a,i0,a,i0)') 'x has shape ', size(x, 1), ' x ', size(x, 2), '; expected 3 x ', np
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    if (.not. field%correlated) then
      call random_normal_seed(rng, field%seed)
      do p = 1, np
        call random_normal_next(rng, g(p))
      end do
      return
    end if
    if (.not. allocated(field%values)) then
      call error_set(err, where, 'the field has not been built')
      return
    end if
    bad = huge(1)
    !$omp parallel do default(none) shared(field, x, g, np) private(p, inside) reduction(min:bad)
    do p = 1, np
      call sample_one(field, x(:, p), g(p), inside)
      if (.not. inside) bad = min(bad, p)
    end do
    !$omp end parallel do
    if (bad /= huge(1)) then
      write(msg, '(a,i0,a,3es12.4,a)') 'point ', bad, ' at (', x(:, bad), ') lies outside the field''s grid'
      call error_set(err, where, trim(msg), ERR_INPUT)
    end if
  end subroutine random_field_sample

  !> The normalised trilinear interpolant of the field at x (length): the
  !> weighted sum of the 8 surrounding nodes divided by its standard
  !> deviation sqrt(sum_ab w_a w_b C(x_a - x_b)) (two corners that differ
  !> in m directions are dx sqrt(m) apart). inside is false if x is outside
  !> the grid (g is then still set, from the nearest cell).
  pure subroutine sample_one(field, x, g, inside)
    type(random_field_t), intent(in) :: field
    real(wp), intent(in) :: x(3)
    real(wp), intent(out) :: g
    logical, intent(out) :: inside
    ! a point a rounding error outside the end nodes is inside
    real(wp), parameter :: slack = 1.0e-9_wp
    integer :: d, i0(3), a, b, ia(3), ib(3), m
    real(wp) :: s, t, wt(0:1, 3), wa, wb, sum_g, var
    inside = .true.
    do d = 1, 3
      if (field%n(d) == 1) then
        i0(d) = 1
        wt(:, d) = [1.0_wp, 0.0_wp]
        cycle
      end if
      ! (a NaN is tested without comparing it, which would raise the
      ! invalid flag the debug build traps; a far point without dividing)
      s = -huge(1.0_wp)
      if (ieee_is_finite(x(d))) then
        if (abs(x(d) - field%origin(d)) <= real(field%n(d), wp)*field%dx) s = (x(d) - field%origin(d))/field%dx
      end if
      if (s < -slack .or. s > real(field%n(d) - 1, wp) + slack) then
        inside = .false.
        s = max(0.0_wp, min(real(field%n(d) - 1, wp), s))
      end if
      i0(d) = max(0, min(field%n(d) - 2, int(s)))
      t = max(0.0_wp, min(1.0_wp, s - real(i0(d), wp)))
      ! (the node in the stored part: a point beyond it is outside too)
      i0(d) = i0(d) + 2 - field%first(d)
      if (i0(d) < 1 .or. i0(d) + 1 > size(field%values, d)) then
        inside = .false.
        i0(d) = max(1, min(size(field%values, d) - 1, i0(d)))
      end if
      wt(:, d) = [1.0_wp - t, t]
    end do
    sum_g = 0.0_wp
    var = 0.0_wp
    do a = 0, 7
      ia = [iand(a, 1), iand(shiftr(a, 1), 1), iand(shiftr(a, 2), 1)]
      wa = wt(ia(1), 1)*wt(ia(2), 2)*wt(ia(3), 3)
      if (.not. (wa > 0.0_wp)) cycle   ! (weights are >= 0)
      sum_g = sum_g + wa*field%values(i0(1) + ia(1), i0(2) + ia(2), i0(3) + ia(3))
      do b = 0, 7
        ib = [iand(b, 1), iand(shiftr(b, 1), 1), iand(shiftr(b, 2), 1)]
        wb = wt(ib(1), 1)*wt(ib(2), 2)*wt(ib(3), 3)
        if (.not. (wb > 0.0_wp)) cycle
        m = count(ia /= ib)
        var = var + wa*wb*field%cm(m)
      end do
    end do
    g = sum_g/sqrt(var)
  end subroutine sample_one

  !> Initial void fractions f0(np) (-) from unit Gaussian values g(np):
  !> 'normal': f0 = mean + std g; 'lognormal': f0 = exp(mu + s g) with
  !> s^2 = ln(1 + std^2/mean^2) and mu = ln(mean) - s^2/2, which has the
  !> same mean and standard deviation and is always positive. Both are then
  !> truncated to [f_min, f_max] (defaults 1e-6 and 0.5); ntrunc is the
  !> number of values truncated (report it: truncation shifts the mean and
  !> lowers the standard deviation).
  !> Errors (input): unknown distribution, mean not in (0,1), std < 0,
  !> not 0 <= f_min < f_max <= 1, sizes that differ.
  subroutine void_fraction_from_field(g, mean, std, distribution, f0, ntrunc, err, f_min, f_max)
    real(wp), intent(in) :: g(:), mean, std
    character(len=*), intent(in) :: distribution
    real(wp), intent(out) :: f0(:)
    integer, intent(out) :: ntrunc
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: f_min, f_max
    character(len=*), parameter :: where = 'void_fraction_from_field'
    real(wp) :: lo, hi, s_ln, mu_ln, f
    integer :: p
    logical :: lognormal
    character(len=200) :: msg

    ntrunc = 0
    lo = 1.0e-6_wp
    hi = 0.5_wp
    if (present(f_min)) lo = f_min
    if (present(f_max)) hi = f_max
    if (.not. (ieee_is_finite(mean) .and. ieee_is_finite(std) .and. ieee_is_finite(lo) .and. ieee_is_finite(hi))) then
      call error_set(err, where, 'mean, std, f_min and f_max must be finite numbers', ERR_INPUT)
      return
    end if
    if (.not. any(void_fraction_distributions == distribution)) then
      call error_set(err, where, 'distribution = '''//trim(distribution)//''' is not known; valid: normal, lognormal', &
                     ERR_INPUT)
      return
    end if
    if (.not. (mean > 0.0_wp .and. mean < 1.0_wp)) then
      write(msg, '(a,es12.4,a)') 'mean = ', mean, ' must be in (0, 1)'
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    if (.not. (std >= 0.0_wp)) then
      write(msg, '(a,es12.4,a)') 'std = ', std, ' must be >= 0'
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    if (.not. (lo >= 0.0_wp .and. lo < hi .and. hi <= 1.0_wp)) then
      write(msg, '(a,es12.4,a,es12.4,a)') 'f_min = ', lo, ' and f_max = ', hi, ' must satisfy 0 <= f_min < f_max <= 1'
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    if (size(f0) /= size(g)) then
      write(msg, '(a,i0,a,i0)') 'f0 has ', size(f0), ' values, g has ', size(g)
      call error_set(err, where, trim(msg), ERR_INPUT)
      return
    end if
    lognormal = distribution == 'lognormal'
    s_ln = sqrt(log(1.0_wp + (std/mean)**2))
    mu_ln = log(mean) - 0.5_wp*s_ln**2
    !$omp parallel do default(none) shared(g, f0, mean, std, lognormal, lo, hi, s_ln, mu_ln) private(p, f) &
    !$omp   reduction(+:ntrunc)
    do p = 1, size(g)
      if (lognormal) then
        ! capped at e > f_max (it is then truncated and counted): no
        ! overflow for any g
        f = exp(min(mu_ln + s_ln*g(p), 1.0_wp))
      else
        f = mean + std*g(p)
      end if
      if (f < lo .or. f > hi) then
        ntrunc = ntrunc + 1
        f = max(lo, min(hi, f))
      end if
      f0(p) = f
    end do
    !$omp end parallel do
  end subroutine void_fraction_from_field

  !> 'n1 x n2 x n3 nodes' of a field grid, for a message.
  pure function grid_text(n) result(text)
    integer, intent(in) :: n(3)
    character(len=64) :: text
    write(text, '(i0," x ",i0," x ",i0," nodes")') n
  end function grid_text
end module strength_random_field
