!> Unit tests of the grid quality (Eq. 46) and the Euler-step triggers.
program test_rezone_quality
  use base_kinds, only: wp
  use base_random, only: rng_t, rng_seed, rng_uniform
  use mesh_geometry, only: hex_corner, hex_jacobian
  use test_assert, only: check, check_summary
  use rezone_quality, only: hex_quality, quad_quality, hex_shape, grid_quality, hex_quality_box, hex_box_sides, &
                            grid_trigger_cells, standard_side_ratio
  implicit none
  real(wp) :: cube(3, 8), xn(3, 8), sq(2, 4), r, cs, q_min, ratio_max, cos_min, a(3, 3), b(3), c, qb
  real(wp), allocatable :: x(:, :), q(:), x0(:, :)
  logical :: fail(2)
  logical, allocatable :: fails(:), known(:), shape_fail(:), tang(:)
  type(rng_t) :: rng
  integer :: i, j, k, n, d, ntangled, njac
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

  ! Eq. (46) against the cell's own box: 1 for a box up to aspect_max,
  ! Eq. (46) itself with aspect_max = 1
  xn = cube
  xn(3, 5:8) = 2.0_wp
  call check(abs(hex_quality_box(xn, 2.0_wp) - 1.0_wp) < 1e-14_wp, 'box reading: Q = 1 for a 1x1x2 box, aspect_max 2')
  call check(.not. abs(hex_quality_box(xn, 1.0_wp) - hex_quality(xn)) > 0.0_wp, &
             'box reading with aspect_max 1 is Eq. (46)')
  xn = cube
  xn(3, 5:8) = 0.9_wp
  write(*, '(a,f8.5,a,f8.5)') 'box compressed by 10 %: Eq. (46) ', hex_quality(xn), ', against its own box ', &
    hex_quality_box(xn, 2.0_wp)
  call check(hex_quality(xn) < 0.999_wp .and. abs(hex_quality_box(xn, 2.0_wp) - 1.0_wp) < 1e-14_wp, &
             'a box compressed by 10 % fails q = 0.999 of Eq. (46), not against its own box')
  ! a 4:1 box with aspect_max 2: its own box has sides 4^(-1/6), 4^(-1/6), 4^(-2/3) (log spread halved)
  xn = cube
  xn(3, 5:8) = 0.25_wp
  b = hex_box_sides(xn, 2.0_wp)
  call check(all(abs(b - [4.0_wp**(-1.0_wp/6.0_wp), 4.0_wp**(-1.0_wp/6.0_wp), 4.0_wp**(-2.0_wp/3.0_wp)]) < 1e-14_wp), &
             'own box of a 4:1 box with aspect_max 2')
  qb = 27.0_wp*product(b)/sum(b)**3
  write(*, '(a,f7.4)') '4:1 box against its own box (aspect_max 2): ', hex_quality_box(xn, 2.0_wp)
  call check(abs(hex_quality_box(xn, 2.0_wp) - hex_quality(xn)/qb) < 1e-14_wp .and. &
             hex_quality_box(xn, 2.0_wp) < 0.7_wp, 'a 4:1 box is distorted against a box of aspect 2')
  ! the 45-degree shear: the same as Eq. (46) measured on the sheared unit cube's box
  a = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 1.0_wp], [3, 3])
  xn = matmul(a, cube)
  call check(abs(hex_quality_box(xn, 2.0_wp) - 1.0_wp/sqrt(2.0_wp)) < 1e-14_wp, &
             'box reading of the 45-degree shear: V / (a1 a2 a3) = 1/sqrt(2)')

  ! inclined angle: against the axis of the edge's direction. A cube
  ! compressed 4:1 along the face diagonal (1,1,0): each x- and y-edge turns
  ! by atan(c/2 / (1 - c/2)), c = 3/4 (cos 0.857); the angle between them is
  ! far from 90 degrees, but no edge is inclined by 45
  c = 0.75_wp
  a = reshape([1.0_wp - 0.5_wp*c, -0.5_wp*c, 0.0_wp, -0.5_wp*c, 1.0_wp - 0.5_wp*c, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], &
              [3, 3])
  xn = matmul(a, cube)
  call hex_shape(xn, r, cs, axis=.true.)
  call check(abs(cs - (1.0_wp - 0.5_wp*c)/sqrt((1.0_wp - 0.5_wp*c)**2 + 0.25_wp*c**2)) < 1e-14_wp .and. cs > 0.85_wp, &
             'inclined angle against the axes of the diagonal compression is the edges'' turn (cos 0.857)')
  call hex_shape(xn, r, cs)
  call check(abs(cs - 0.25_wp/((1.0_wp - 0.5_wp*c)**2 + 0.25_wp*c**2)) < 1e-14_wp .and. cs < 0.5_wp, &
             'between the edges it is sin of their angle (0.47)')
  call check(abs(r - 1.0_wp/sqrt((1.0_wp - 0.5_wp*c)**2 + 0.25_wp*c**2)) < 1e-14_wp, &
             'side ratio of the diagonal compression')
  ! a unit cube whose node 2 (x = 1, y = z = 0) is pushed back to x = -0.5:
  ! the cell folds through itself along x, every edge's |cos| against its
  ! axis still 0.55 or more (the folded x-edge exactly on it, turned back),
  ! so the signed cosine is -1 and trips any trigger
  xn = cube
  xn(1, 2) = -0.5_wp
  call hex_shape(xn, r, cs, axis=.true.)
  call check(abs(cs + 1.0_wp) < 1e-15_wp, 'an edge turned back against its axis: cosine -1')
  xn = cube
  call hex_shape(xn, r, cs, axis=.true.)
  call check(abs(cs - 1.0_wp) < 1e-15_wp, 'the cube against the axes: cosine 1')

  ! cells failing the triggers' tests: a 2 x 1 x 1 grid, the second cell
  ! 5 long (side ratio 5 >= 4); then its far corner folded back (tangled)
  allocate(x(3, 12))
  do k = 0, 1
    do j = 0, 1
      do i = 0, 2
        x(:, 1 + i + 3*(j + 2*k)) = [real(i, wp), real(j, wp), real(k, wp)]
      end do
    end do
  end do
  x(1, 3:12:3) = 6.0_wp
  call grid_trigger_cells(2, 1, 1, x, 4.0_wp, 0.7_wp, fail)
  call check(.not. fail(1) .and. fail(2), 'trigger cells: the 5:1 cell fails, the cube does not')
  call grid_trigger_cells(2, 1, 1, x, 0.0_wp, 0.7_wp, fail)
  call check(.not. any(fail), 'trigger cells: side-ratio test off')
  ! measured against the standard grid x0, where the second cell is 5 long
  ! (side ratio 5): as made, it does not fail; 19 long (19/5 = 3.8 < 4)
  ! neither; 20 long (4) it does; a cube is measured as before
  x0 = x
  call grid_trigger_cells(2, 1, 1, x, 4.0_wp, 0.7_wp, fail, x0=x0)
  call check(.not. any(fail), 'trigger cells against x0: the cell as long as made does not fail')
  x(1, 3:12:3) = 20.0_wp
  call grid_trigger_cells(2, 1, 1, x, 4.0_wp, 0.7_wp, fail, x0=x0)
  call check(.not. fail(1) .and. .not. fail(2), 'trigger cells against x0: 19 long against 5 (3.8) does not fail')
  x(1, 3:12:3) = 21.0_wp
  call grid_trigger_cells(2, 1, 1, x, 4.0_wp, 0.7_wp, fail, x0=x0)
  call check(.not. fail(1) .and. fail(2), 'trigger cells against x0: 20 long against 5 (4) fails')
  ! as long as made but its far corner folded back: tangled, it fails (the
  ! angle test off: the tangle test alone, on x)
  x(1, 3:12:3) = 6.0_wp
  x(:, 12) = [1.5_wp, 0.2_wp, 0.3_wp]
  call grid_trigger_cells(2, 1, 1, x, 4.0_wp, 0.0_wp, fail, x0=x0)
  call check(.not. fail(1) .and. fail(2), 'trigger cells against x0: a tangled cell as long as made fails')
  x(:, 12) = [6.0_wp, 1.0_wp, 1.0_wp]
  x0(1, 3:12:3) = 2.0_wp
  call grid_trigger_cells(2, 1, 1, x, 4.0_wp, 0.7_wp, fail, x0=x0)
  call check(.not. fail(1) .and. fail(2), 'trigger cells against a cube in x0: the 5:1 cell fails')
  xn = cube
  xn(3, 5:8) = 1.0_wp + 1.0e-12_wp
  r = standard_side_ratio(xn)
  cs = standard_side_ratio(cube)
  ! (exactly 1: neither above nor below)
  call check(.not. (r > 1.0_wp .or. r < 1.0_wp .or. cs > 1.0_wp .or. cs < 1.0_wp), &
             'standard side ratio: exactly 1 for a cube and for sides equal within 1e-9')
  xn(3, 5:8) = 1.5_wp
  call check(abs(standard_side_ratio(xn) - 1.5_wp) < 1e-15_wp, 'standard side ratio of a 1x1x1.5 box: 1.5')
  x(1, 3:12:3) = 2.0_wp
  x(:, 12) = [0.5_wp, 0.2_wp, 0.3_wp]
  call grid_trigger_cells(2, 1, 1, x, 0.0_wp, 0.0_wp, fail)
  call check(.not. fail(1) .and. fail(2), 'trigger cells: a tangled cell fails with both tests off')
  deallocate(x, x0)

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

  ! the trigger cells with the shape tests given (as the step's look at the
  ! grid takes them, `grid_shape_worst`) for the cells of the block
  ! (2:m-1)^3, taken again elsewhere: the same cells as all taken here, on
  ! the benchmark grid moved by up to 0.45 (some cells tangled: as many as
  ! have a corner Jacobian of the trilinear map not above zero)
  do k = 1, m - 1
    do j = 1, m - 1
      do i = 1, m - 1
        n = 1 + i + (m + 1)*(j + (m + 1)*k)
        x(:, n) = real([i, j, k], wp) + 0.9_wp*(rng_uniform_3() - 0.5_wp)
      end do
    end do
  end do
  allocate(fails(m**3), known(m**3), shape_fail(m**3), tang(m**3))
  njac = 0
  do k = 1, m
    do j = 1, m
      do i = 1, m
        n = i + m*(j - 1 + m*(k - 1))
        call cell_nodes(i, j, k)
        if (any([(hex_jacobian(xn, 2.0_wp*real(hex_corner(:, d), wp) - 1.0_wp) <= 0.0_wp, d = 1, 8)])) &
          njac = njac + 1
        call hex_shape(xn, r, cs, axis=.true.)
        shape_fail(n) = r >= 4.0_wp .or. cs <= 0.7_wp
        ! (outside the block: wrong on purpose, not to be read)
        if (any([i, j, k] < 2 .or. [i, j, k] > m - 1)) shape_fail(n) = .not. shape_fail(n)
      end do
    end do
  end do
  call grid_trigger_cells(m, m, m, x, 4.0_wp, 0.7_wp, fails)
  call grid_trigger_cells(m, m, m, x, 4.0_wp, 0.7_wp, known, shape_fail=shape_fail, lo=[2, 2, 2], hi=[m - 1, m - 1, m - 1])
  call grid_trigger_cells(m, m, m, x, 0.0_wp, 0.0_wp, tang)
  ntangled = count(tang)
  write(*, '(a,i0,a,i0,a,i0,a)') 'trigger cells of the grid moved by 0.45: ', count(fails), ' of them ', ntangled, &
    ' tangled (', njac, ' with a corner Jacobian <= 0)'
  call check(ntangled == njac, 'trigger cells: the tangled cells are those with a corner Jacobian <= 0')
  call check(ntangled > 100 .and. count(fails) > ntangled .and. count(fails) < m**3, &
             'trigger cells: the grid moved by 0.45 has tangled cells and cells failing only the shape tests')
  call check(all(fails .eqv. known), 'trigger cells: with the shape tests given, the same cells fail')

  call check_summary('test_rezone_quality')

contains

  !> Three uniform numbers of rng.
  function rng_uniform_3() result(u)
    real(wp) :: u(3)
    integer :: d_
    do d_ = 1, 3
      u(d_) = rng_uniform(rng)
    end do
  end function rng_uniform_3

  !> xn: the nodes of cell (i_, j_, k_) of the m^3 grid x.
  subroutine cell_nodes(i_, j_, k_)
    integer, intent(in) :: i_, j_, k_
    integer :: a_
    do a_ = 1, 8
      xn(:, a_) = x(:, 1 + (i_ - 1 + mod(a_ - 1, 2)) + (m + 1)*((j_ - 1 + mod((a_ - 1)/2, 2)) + &
                    (m + 1)*(k_ - 1 + (a_ - 1)/4)))
    end do
  end subroutine cell_nodes
end program test_rezone_quality
