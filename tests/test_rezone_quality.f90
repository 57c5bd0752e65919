!> Unit tests of the grid quality (Eq. 46) and the Euler-step triggers.
program test_rezone_quality
  use base_kinds, only: wp
  use base_random, only: rng_t, rng_seed, rng_uniform
  use mesh_geometry, only: hex_corner
  use test_assert, only: check, check_summary
  use rezone_quality, only: hex_quality, quad_quality, hex_shape, grid_quality
  implicit none
  real(wp) :: cube(3, 8), xn(3, 8), sq(2, 4), r, cs, q_min, ratio_max, cos_min, a(3, 3)
  real(wp), allocatable :: x(:, :), q(:)
  type(rng_t) :: rng
  integer :: i, j, k, n, d
  integer, parameter :: m = 50

  cube = real(hex_corner, wp)
  call check(abs(hex_quality(cube) - 1.0_wp) < 1e-15_wp, 'Q = 1 for a cube')
  call check(abs(hex_quality(3.7_wp*cube + 1.0_wp) - 1.0_wp) < 1e-14_wp, 'Q = 1 for any cube')
  sq = reshape([0.0_wp, 0.0_wp, 2.0_wp, 0.0_wp, 2.0_wp, 2.0_wp, 0.0_wp, 2.0_wp], [2, 4])
  call check(abs(quad_quality(sq) - 1.0_wp) < 1e-15_wp, 'Q = 1 for a square')

  ! a box of sides 1, 1, 2: V = 2, L = 4 (1 + 1 + 2) = 16, Q = 1728 * 2 / 16^3
  xn = cube
  xn(3, 5:8) = 2.0_wp
  call check(abs(hex_quality(xn) - 1728.0_wp*2.0_wp/16.0_wp**3) < 1e-15_wp, 'Q of a 1x1x2 box')
  call hex_shape(xn, r, cs)
  call check(abs(r - 2.0_wp) < 1e-15_wp .and. abs(cs - 1.0_wp) < 1e-15_wp, 'side ratio 2, no inclination')

  ! a cube sheared by 45 degrees in x along z: the z-edges lean by 45 degrees
  a = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp], [3, 3])
  xn = matmul(a, cube)
  call hex_shape(xn, r, cs)
  call check(abs(cs - sqrt(0.5_wp)) < 1e-15_wp, 'cos of the inclined angle of a 45-degree shear')
  call check(abs(r - sqrt(2.0_wp)) < 1e-15_wp, 'side ratio of the sheared cube')
  ! shear keeps the volume; L grows from 12 to 8 + 4 sqrt(2)
  call check(abs(hex_quality(xn) - 1728.0_wp/(8.0_wp + 4.0_wp*sqrt(2.0_wp))**3) < 1e-14_wp, 'Q of the sheared cube')

  ! an inverted cell has Q < 0
  xn = cube
  xn(:, 8) = [-0.5_wp, -0.5_wp, -0.5_wp]
  call check(hex_quality(xn) < 1.0_wp, 'a folded corner lowers Q')

  ! the paper's smoothing benchmark grid: 50^3 unit cells, interior nodes
  ! moved by up to 0.399 in each direction: worst Q about 0.30 (Sect. 7.1;
  ! the worst of 125000 random cells depends on the draw: 0.346 with this seed)
  allocate(x(3, (m + 1)**3), q(m**3))
  call rng_seed(rng, 2024)
  do k = 0, m
    do j = 0, m
      do i = 0, m
        n = 1 + i + (m + 1)*(j + (m + 1)*k)
        x(:, n) = real([i, j, k], wp)
        if (i > 0 .and. i < m .and. j > 0 .and. j < m .and. k > 0 .and. k < m) then
          do d = 1, 3
            x(d, n) = x(d, n) + 0.798_wp*(rng_uniform(rng) - 0.5_wp)
          end do
        end if
      end do
    end do
  end do
  call grid_quality(m, m, m, x, q, q_min, ratio_max, cos_min)
  write(*, '(a,f7.4,a,f7.3,a,f7.4)') 'benchmark grid: Q_min ', q_min, ', largest side ratio ', ratio_max, &
    ', smallest inclined-angle cosine ', cos_min
  call check(q_min > 0.2_wp .and. q_min < 0.4_wp, 'benchmark grid Q_min near the paper''s 0.30')
  call check(abs(minval(q) - q_min) < 1e-15_wp, 'grid minimum is the minimum of the cells')

  call check_summary('test_rezone_quality')
end program test_rezone_quality
