!> Unit tests of the particle package's foundation (modules/particles):
!> seeding (`particles_seed`), shape functions and the inverse map
!> (`particles_shape`), ordering and binning (`particles_state`).
!>  1. A box aligned with cell faces: exactly n^3 particles in every covered
!>     cell, none elsewhere; volume and mass exact to round-off.
!>  2. A sphere: the seeded volume converges to 4/3 pi R^3; the RMS error
!>     over random sphere centres falls at second order in n (module notes
!>     of particles_seed), and never exceeds the first-order band bound.
!>  3. Rigid rotation about z: velocities exact (bit for bit).
!>  4. A randomly perturbed grid: the host cell and natural coordinates the
!>     locator finds for every seeded position map back to it to round-off,
!>     and are the seeding cell and sub-box centre; sub-box volumes add up to
!>     the cell volumes.
!>  5. Ordering by (material, cell) and the cell binning.
program test_particles
  use base_kinds, only: wp, i8
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use mesh_grid, only: grid_t, grid_init_box, grid_init_nodes, grid_index_block
  use mesh_geometry, only: hex_volume
  use mesh_shapes, only: shape_t, SHAPE_BOX, SHAPE_SPHERE, SHAPE_ALL
  use particles_shape, only: particles_shape_values, particles_shape_gradients, particles_map, particles_locate
  use particles_seed, only: seed_shape, rigid_velocity
  use particles_state, only: particles_t, particles_allocate, particles_order, particles_select
  use test_assert, only: check, check_close, check_summary
  implicit none
  real(wp), parameter :: pi = acos(-1.0_wp)

  call test_shape_functions()
  call test_box_exact()
  call test_sphere_convergence()
  call test_hollow_sphere()
  call test_rigid_rotation()
  call test_distorted_locate()
  call test_order_bin()
  call check_summary('test_particles')

contains

  !> Partition of unity, the Kronecker property at the corners and the
  !> gradients against central differences (N is trilinear: exact to
  !> round-off).
  subroutine test_shape_functions()
    real(wp) :: xi(3), n(8), dn(8, 3), e(3), fd, np1(8), nm1(8)
    integer :: a, d
    xi = [0.3_wp, 0.7_wp, 0.1_wp]
    n = particles_shape_values(xi)
    call check(abs(sum(n) - 1.0_wp) <= 4.0_wp*epsilon(1.0_wp), 'shape functions sum to 1')
    do a = 1, 8
      n = particles_shape_values(real([ibits(a - 1, 0, 1), ibits(a - 1, 1, 1), ibits(a - 1, 2, 1)], wp))
      call check(same(n(a), 1.0_wp) .and. count(abs(n) > 0.0_wp) == 1, 'N_a is 1 at corner a and 0 at the others')
    end do
    dn = particles_shape_gradients(xi)
    do d = 1, 3
      e = 0.0_wp
      e(d) = 1.0e-3_wp
      np1 = particles_shape_values(xi + e)
      nm1 = particles_shape_values(xi - e)
      do a = 1, 8
        fd = np1(a) - nm1(a)
        call check(abs(fd/2.0e-3_wp - dn(a, d)) <= 1.0e-12_wp, 'shape gradient = central difference')
      end do
    end do
  end subroutine test_shape_functions

  !> A box whose faces lie on grid planes, at n = 1..4.
  subroutine test_box_exact()
    type(grid_t) :: g
    type(shape_t) :: sh
    type(error_t), allocatable :: err
    integer, allocatable :: cell(:), per(:)
    real(wp), allocatable :: xi(:, :), x(:, :), vol(:)
    real(wp) :: vbox, rho, tol
    integer :: n, c, i, j, k, covered
    logical :: ok

    ! 10 x 8 x 6 cells of h = (0.1, 0.125, 1/6): the box covers cells
    ! 3..7 x 2..5 x 2..4 (faces on grid planes; h = 1/6 is not a binary
    ! fraction, so the box's faces are the nodes' own values)
    call grid_init_box(g, 10, 8, 6, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
    call check(.not. allocated(err), 'grid_init_box')
    sh%kind = SHAPE_BOX
    sh%lo = g%x(:, g%node(2, 1, 1))
    sh%hi = g%x(:, g%node(7, 5, 4))
    vbox = product(sh%hi - sh%lo)
    rho = 7.85_wp
    covered = 5*4*3
    do n = 1, 4
      call seed_shape(g, sh, n, cell, xi, x, vol, err)
      call check(.not. allocated(err), 'seed_shape (box)')
      allocate(per(g%ncell), source=0)
      do i = 1, size(cell)
        per(cell(i)) = per(cell(i)) + 1
      end do
      ok = .true.
      do k = 1, g%nk
        do j = 1, g%nj
          do i = 1, g%ni
            c = g%cell(i, j, k)
            if (i >= 3 .and. i <= 7 .and. j >= 2 .and. j <= 5 .and. k >= 2 .and. k <= 4) then
              ok = ok .and. per(c) == n**3
            else
              ok = ok .and. per(c) == 0
            end if
          end do
        end do
      end do
      call check(ok, 'box: exactly n^3 particles in every covered cell and none elsewhere')
      call check(size(cell) == covered*n**3, 'box: particle count = covered cells x n^3')
      ! round-off: a sum of N = covered n^3 terms, each with a few roundings
      ! of its own: |error| <= N eps bounds the sum's relative error
      tol = real(size(vol), wp)*epsilon(1.0_wp)
      call check_close('box: seeded volume / box volume - 1, n = '//char(48 + n), sum(vol)/vbox - 1.0_wp, &
                       0.0_wp, tol)
      call check_close('box: seeded mass / (rho box volume) - 1', sum(rho*vol)/(rho*vbox) - 1.0_wp, 0.0_wp, tol)
      deallocate(per)
    end do
  end subroutine test_box_exact

  !> A sphere of radius R = 0.31 on a 12^3 grid of the unit cube (h = 1/12,
  !> R = 3.7 h), at n = 2, 4, 8, for 12 random centres: the RMS relative
  !> volume error must fall at least 3x per doubling of n (second order:
  !> 4x; a lattice-count discrepancy averaged over offsets fluctuates, so
  !> 3x), and every error must lie within the first-order band bound
  !> A sqrt(3) h/(2n)/V.
  subroutine test_sphere_convergence()
    integer, parameter :: ntrial = 12, nlev = 3
    integer, parameter :: ns(nlev) = [2, 4, 8]
    type(grid_t) :: g
    type(shape_t) :: sh
    type(error_t), allocatable :: err
    type(rng_t) :: rng
    integer, allocatable :: cell(:)
    real(wp), allocatable :: xi(:, :), x(:, :), vol(:)
    real(wp) :: r, vexact, rms(nlev), e, bound, h
    integer :: t, l, d
    character(len=80) :: line

    call grid_init_box(g, 12, 12, 12, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
    h = 1.0_wp/12.0_wp
    r = 0.31_wp
    vexact = 4.0_wp/3.0_wp*pi*r**3
    call rng_seed(rng, 11)
    sh%kind = SHAPE_SPHERE
    sh%radius = r
    rms = 0.0_wp
    do t = 1, ntrial
      do d = 1, 3
        sh%center(d) = 0.5_wp + h*(rng_uniform(rng) - 0.5_wp)
      end do
      do l = 1, nlev
        call seed_shape(g, sh, ns(l), cell, xi, x, vol, err)
        e = abs(sum(vol) - vexact)/vexact
        bound = 4.0_wp*pi*r**2*sqrt(3.0_wp)*h/(2.0_wp*ns(l))/vexact
        call check(e <= bound, 'sphere: error within the first-order band bound')
        rms(l) = rms(l) + e**2
      end do
    end do
    rms = sqrt(rms/ntrial)
    do l = 1, nlev
      write(line, '(a,i0,a,es10.3)') 'sphere: RMS relative volume error at n = ', ns(l), ': ', rms(l)
      write(*, '(a)') trim(line)
    end do
    do l = 1, nlev - 1
      write(line, '(a,i0,a,i0)') 'sphere: error ratio (>= 3, second order 4) from n = ', ns(l), ' to ', ns(l + 1)
      call check_close(trim(line), rms(l)/rms(l + 1), 100.0_wp, 97.0_wp)
    end do
  end subroutine test_sphere_convergence

  !> A hollow sphere (inner_radius 0.17, radius 0.31) seeded as above at
  !> n = 4 and 8: its volume within the first-order band bound of both
  !> surfaces, A_out + A_in times sqrt(3) h/(2n), and every particle in
  !> the shell (inner_radius <= r <= radius).
  subroutine test_hollow_sphere()
    type(grid_t) :: g
    type(shape_t) :: sh
    type(error_t), allocatable :: err
    integer, allocatable :: cell(:)
    real(wp), allocatable :: xi(:, :), x(:, :), vol(:), r(:)
    real(wp) :: h, vexact, bound
    integer :: n, k
    call grid_init_box(g, 12, 12, 12, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
    h = 1.0_wp/12.0_wp
    sh%kind = SHAPE_SPHERE
    sh%center = [0.51_wp, 0.49_wp, 0.5_wp]
    sh%radius = 0.31_wp
    sh%inner_radius = 0.17_wp
    vexact = 4.0_wp/3.0_wp*pi*(sh%radius**3 - sh%inner_radius**3)
    do n = 4, 8, 4
      call seed_shape(g, sh, n, cell, xi, x, vol, err)
      bound = 4.0_wp*pi*(sh%radius**2 + sh%inner_radius**2)*sqrt(3.0_wp)*h/(2.0_wp*n)/vexact
      call check(abs(sum(vol) - vexact)/vexact <= bound, 'hollow sphere: volume within the band bound')
      r = [(norm2(x(:, k) - sh%center), k = 1, size(vol))]
      call check(all(r >= sh%inner_radius .and. r <= sh%radius), 'hollow sphere: every particle in the shell')
    end do
  end subroutine test_hollow_sphere

  !> v = omega z x (x - c): exactly (-omega (y - cy), omega (x - cx), 0) +
  !> v0 (the same operations, so bit for bit), and |v - v0| = |omega| r.
  subroutine test_rigid_rotation()
    type(grid_t) :: g
    type(shape_t) :: sh
    type(error_t), allocatable :: err
    integer, allocatable :: cell(:)
    real(wp), allocatable :: xi(:, :), x(:, :), vol(:)
    real(wp) :: v(3), c(3), v0(3), omega, rr, worst
    integer :: k
    logical :: exact

    call grid_init_box(g, 6, 6, 6, [-1.0_wp, -1.0_wp, -1.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
    sh%kind = SHAPE_SPHERE
    sh%center = [0.1_wp, -0.2_wp, 0.05_wp]
    sh%radius = 0.7_wp
    call seed_shape(g, sh, 3, cell, xi, x, vol, err)
    c = sh%center
    v0 = [0.5_wp, 0.0_wp, -0.25_wp]
    omega = 2.0_wp
    exact = .true.
    worst = 0.0_wp
    do k = 1, size(cell)
      v = rigid_velocity(v0, omega, [0.0_wp, 0.0_wp, 1.0_wp], c, x(:, k))
      exact = exact .and. same(v(1), v0(1) + omega*(-(x(2, k) - c(2)))) .and. &
              same(v(2), v0(2) + omega*(x(1, k) - c(1))) .and. same(v(3), v0(3))
      rr = sqrt((x(1, k) - c(1))**2 + (x(2, k) - c(2))**2)
      worst = max(worst, abs(norm2(v(1:2) - v0(1:2)) - abs(omega)*rr))
    end do
    call check(size(cell) > 0 .and. exact, 'rigid rotation about z: velocities exact')
    call check_close('rigid rotation: max | |v - v0| - omega r |', worst, 0.0_wp, 8.0_wp*epsilon(1.0_wp))
  end subroutine test_rigid_rotation

  !> A 7 x 6 x 5 grid with every interior node moved at random by up to
  !> 0.2 h per direction (faces stay flat): the whole grid seeded at n = 3;
  !> the locator, started from cell 1 for every particle, must return the
  !> seeding cell and sub-box centre, and the map must give back the
  !> position to round-off (1e-13 h: ~10 roundings of O(h) terms).
  subroutine test_distorted_locate()
    type(grid_t) :: g, box
    type(shape_t) :: sh
    type(error_t), allocatable :: err
    type(rng_t) :: rng
    integer, allocatable :: cell(:)
    real(wp), allocatable :: xi(:, :), x(:, :), vol(:), xnodes(:, :)
    real(wp) :: xn(3, 8), xi2(3), h, worst_x, worst_xi, vcells
    integer :: i, j, k, n, c, d, found_wrong, nijk(3), ijk(3)
    logical :: found, all_found

    call grid_init_box(box, 7, 6, 5, [0.0_wp, 0.0_wp, 0.0_wp], [0.7_wp, 0.6_wp, 0.5_wp], err)
    h = 0.1_wp
    xnodes = box%x
    call rng_seed(rng, 3)
    nijk = [7, 6, 5]
    do k = 0, 5
      do j = 0, 6
        do i = 0, 7
          n = box%node(i, j, k)
          ijk = [i, j, k]
          do d = 1, 3
            if (ijk(d) > 0 .and. ijk(d) < nijk(d)) &
              xnodes(d, n) = xnodes(d, n) + 0.4_wp*h*(rng_uniform(rng) - 0.5_wp)
          end do
        end do
      end do
    end do
    call grid_init_nodes(g, 7, 6, 5, xnodes, err)
    call check(.not. allocated(err), 'grid_init_nodes (perturbed)')
    sh%kind = SHAPE_ALL
    call seed_shape(g, sh, 3, cell, xi, x, vol, err)
    call check(size(cell) == 27*g%ncell, 'perturbed grid: 27 particles per cell')
    vcells = 0.0_wp
    do c = 1, g%ncell
      call g%gather(c, g%x, xn)
      vcells = vcells + hex_volume(xn)
    end do
    call check_close('perturbed grid: sub-box volumes / cell volumes', sum(vol)/vcells, 1.0_wp, 1.0e-13_wp)
    worst_x = 0.0_wp
    worst_xi = 0.0_wp
    found_wrong = 0
    all_found = .true.
    do k = 1, size(cell)
      call particles_locate(g, x(:, k), 1, c, xi2, found)
      all_found = all_found .and. found
      if (.not. found) cycle
      if (c /= cell(k)) found_wrong = found_wrong + 1
      call g%gather(c, g%x, xn)
      worst_x = max(worst_x, maxval(abs(particles_map(xn, xi2) - x(:, k))))
      worst_xi = max(worst_xi, maxval(abs(xi2 - xi(:, k))))
    end do
    call check(all_found, 'perturbed grid: every seeded position is located')
    call check(found_wrong == 0, 'perturbed grid: the located cell is the seeding cell')
    call check_close('perturbed grid: max |x(cell, xi) - x_p| / h', worst_x/h, 0.0_wp, 1.0e-13_wp)
    call check_close('perturbed grid: max |xi - xi_seed|', worst_xi, 0.0_wp, 1.0e-12_wp)
    ! a point outside the grid is not found
    call particles_locate(g, [2.0_wp, 0.3_wp, 0.3_wp], 1, c, xi2, found)
    call check(.not. found .and. c == 0, 'a point outside the grid is not located')
    call block_walks(g, xnodes, x)
  end subroutine test_distorted_locate

  !> A block of the perturbed grid g (whole nodes xw) that owns cells i = 3..5
  !> and stores one ghost layer on each side (i = 2..6): every point x walked
  !> from the owned cell (4, j, k) with the block's cuts finds the cell and
  !> natural coordinates the whole grid's walk from the same cell finds, bit
  !> for bit, or is undecided (-1); a point whose host is not stored (i = 1
  !> or 7) is always undecided. Both outcomes occur.
  subroutine block_walks(g, xw, x)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: xw(:, :), x(:, :)
    type(grid_t) :: b
    type(error_t), allocatable :: err
    real(wp) :: xib(3), xiw(3)
    integer :: q, cb, cw, i, j, k, iw, jw, kw, nfound, nundecided, wrong, missed, d
    logical :: fb, fw
    call grid_init_nodes(b, 7, 6, 5, xw, err, grid_index_block([3, 6, 5], [1, 0, 0], [1, 0, 0], [2, 0, 0], [7, 6, 5]))
    call check(.not. allocated(err), 'block of the perturbed grid')
    nfound = 0
    nundecided = 0
    wrong = 0
    missed = 0
    do q = 1, size(x, 2)
      ! (the start: the owned cell (4, j, k) of the point's row)
      call particles_locate(g, x(:, q), 1, cw, xiw, fw)
      call g%cell_ijk(cw, iw, jw, kw)
      call particles_locate(g, x(:, q), g%cell(4, jw, kw), cw, xiw, fw)
      call particles_locate(b, x(:, q), b%cell(4 - 2, jw, kw), cb, xib, fb, cut=[b%glo > 0, b%ghi > 0])
      if (cb > 0) then
        nfound = nfound + 1
        call b%cell_ijk(cb, i, j, k)
        if (g%cell(i + 2, j, k) /= cw .or. .not. all([(same(xib(d), xiw(d)), d = 1, 3)])) wrong = wrong + 1
      else
        nundecided = nundecided + 1
        if (cb /= -1 .or. fb) wrong = wrong + 1
      end if
      if ((iw == 1 .or. iw == 7) .and. cb > 0) missed = missed + 1
    end do
    call check(wrong == 0, 'block walk: each cell found is the whole grid''s, natural coordinates bit for bit')
    call check(missed == 0, 'block walk: a host beyond the stored cells is undecided')
    write(*, '(a,i0,a,i0,a)') 'block walk: ', nfound, ' points found, ', nundecided, ' undecided'
    call check(nfound > 0 .and. nundecided > 0, 'block walk: points found and points undecided')
  end subroutine block_walks

  !> Two materials seeded interleaved: sorted by (material, cell, id),
  !> mat_start and the cell binning consistent; the same order from the
  !> particles in reverse.
  subroutine test_order_bin()
    type(particles_t) :: p
    type(error_t), allocatable :: err
    integer :: k, c, q, ncell
    logical :: ok
    ncell = 5
    call particles_allocate(p, 12, 2, 0, err)
    call check(.not. allocated(err), 'particles_allocate')
    p%mat = [2, 1, 2, 1, 1, 2, 2, 1, 1, 2, 1, 2]
    p%cell = [5, 3, 1, 3, 2, 5, 1, 4, 3, 2, 1, 5]
    p%m = real(p%id, wp)
    call particles_order(p, ncell, err)
    call check(.not. allocated(err), 'particles_order')
    call check(all(p%mat == [1, 1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 2]), 'sorted by material')
    call check(all(p%cell == [1, 2, 3, 3, 3, 4, 1, 1, 2, 5, 5, 5]), 'then by cell')
    call check(all(p%id == [11, 5, 2, 4, 9, 8, 3, 7, 10, 1, 6, 12]), 'by id within a key')
    call check(all(abs(p%m - real(p%id, wp)) <= 0.0_wp), 'fields follow their particle')
    call check(all(p%mat_start == [1, 7, 13]), 'mat_start')
    ok = p%cell_start(1) == 1 .and. p%cell_start(ncell + 1) == 13
    do c = 1, ncell
      do q = p%cell_start(c), p%cell_start(c + 1) - 1
        ok = ok .and. p%cell(p%perm(q)) == c
        if (q > p%cell_start(c)) ok = ok .and. p%perm(q) > p%perm(q - 1)
      end do
    end do
    call check(ok, 'cell binning: every cell''s range holds its particles, in array order')
    call check(all([(count(p%perm == k), k = 1, 12)] == 1), 'binning is a permutation')
    ! the order depends on the keys alone: the same particles arriving in
    ! reverse (as a block receives them from its neighbours) sort the same
    call particles_select(p, [(k, k = 12, 1, -1)])
    call particles_order(p, ncell, err)
    call check(all(p%id == [11, 5, 2, 4, 9, 8, 3, 7, 10, 1, 6, 12]), 'by id within a key, whatever the arrival order')
    call check(all(abs(p%m - real(p%id, wp)) <= 0.0_wp), 'fields follow their particle after the second sort')
  end subroutine test_order_bin

  !> a and b have the same bits.
  pure logical function same(a, b)
    real(wp), intent(in) :: a, b
    same = transfer(a, 1_i8) == transfer(b, 1_i8)
  end function same
end program test_particles
