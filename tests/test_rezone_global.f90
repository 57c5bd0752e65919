!> Unit tests of the global rezone's target (`rezone_global`): the initial
!> grid bit for bit when no face moves; a piston face kept where it is and
!> its displacement carried into the block by TFI (exactly linear along
!> straight lines, symmetry planes and walls kept); valid cells for an
!> uneven piston on a perturbed grid and for two moving faces that meet; a
!> piston past the far side refused; the same target from the grid's faces
!> and 3 x 2 blocks' own nodes (as a decomposed run computes it), bit for bit.
program test_rezone_global
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use test_assert, only: check, check_summary
  use mesh_grid, only: grid_index_t, grid_index, grid_index_block, block_gather
  use mesh_geometry, only: hex_volume
  use mesh_boundary, only: BC_SYMMETRY, BC_WALL, BC_VELOCITY, BC_PRESSURE, BC_INFLOW, BC_OUTFLOW
  use rezone_global, only: global_target, global_face_rule, GLOBAL_FACE_SLIDE, GLOBAL_FACE_FIX, GLOBAL_FACE_MOVE, &
                           global_surface_t, global_surface_init, global_face_box, global_face_parameters, &
                           global_surface_solve, global_block_target, global_line_sums, global_line_scale
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

  call test_blocks()

  call check_summary('test_rezone_global')

contains

  !> The target of two moving faces (xlo, yhi) on a perturbed initial grid
  !> and a perturbed current one, whole (`global_target`) and by 3 x 2 x 1
  !> blocks: the faces taken from the grid as a gather of their boxes would
  !> (`global_face_box`), each block's line parameters from the running
  !> sums of the one below along each direction and the totals of the last
  !> (`global_line_sums`, `global_line_scale`), its nodes' targets from them
  !> (`global_block_target`).
  subroutine test_blocks()
    integer, parameter :: cut(0:3, 3) = reshape([0, 3, 6, ni, 0, 2, nj, -1, 0, nk, -1, -1], [4, 3])
    integer, parameter :: nbk(3) = [3, 2, 1]
    type :: blk_t
      type(grid_index_t) :: ix
      real(wp), allocatable :: x0(:, :), x(:, :), s(:, :), xt(:, :), finish(:)
    end type blk_t
    type(blk_t) :: bl(3, 2, 1)
    type(global_surface_t) :: sf
    type(grid_index_t) :: bx
    real(wp) :: xp0(3, nn), xp(3, nn), xw(3, nn)
    real(wp), allocatable :: start(:)
    integer :: b(3), q(3), a, ff, lo(3), hi(3), ii, jj, kk, nb, nbad, rule(6), nm, ntot(3)
    rule = [M, F, S, M, S, S]
    ntot = [ni, nj, nk]
    if (allocated(err)) deallocate(err)
    call box(xp0, 0.2_wp, 11)
    call box(xp, 0.2_wp, 12)
    do kk = 0, nk
      do ii = 0, ni
        xp(:, ix%node(ii, nj, kk)) = xp0(:, ix%node(ii, nj, kk)) + [0.004_wp*ii, 0.03_wp + 0.005_wp*kk, 0.0_wp]
      end do
      do jj = 0, nj
        xp(:, ix%node(0, jj, kk)) = xp0(:, ix%node(0, jj, kk)) + [0.08_wp + 0.01_wp*jj, 0.005_wp*kk, 0.0_wp]
      end do
    end do
    call global_target(ni, nj, nk, rule, xp0, xp, xw, nm, err)
    call check(.not. allocated(err) .and. nm > 0, 'blocks: the whole grid''s target')
    if (allocated(err)) write(*, '(a)') 'message: '//err%msg
    ! the faces, as gathered
    call global_surface_init(sf, [ni, nj, nk], rule, err)
    do ff = 1, 6
      call global_face_box(sf, ff, lo, hi)
      bx = grid_index(hi(1) - lo(1) + 1, hi(2) - lo(2) + 1, hi(3) - lo(3) + 1)
      do kk = lo(3) - 1, hi(3)
        do jj = lo(2) - 1, hi(2)
          do ii = lo(1) - 1, hi(1)
            q = [ii, jj, kk] - lo + 1
            sf%f(ff)%x0(:, bx%node(q(1), q(2), q(3))) = xp0(:, ix%node(ii, jj, kk))
            sf%f(ff)%x(:, bx%node(q(1), q(2), q(3))) = xp(:, ix%node(ii, jj, kk))
          end do
        end do
      end do
      call global_face_parameters(sf, ff)
    end do
    call global_surface_solve(sf)
    call check(sf%nmove == nm, 'blocks: the faces'' moving nodes counted as the whole grid''s')
    ! the blocks and their nodes
    do kk = 1, nbk(3)
      do jj = 1, nbk(2)
        do ii = 1, nbk(1)
          b = [ii, jj, kk]
          lo = [cut(ii - 1, 1), cut(jj - 1, 2), cut(kk - 1, 3)]
          hi = [cut(ii, 1), cut(jj, 2), cut(kk, 3)]
          associate (k => bl(ii, jj, kk))
            k%ix = grid_index_block(hi - lo, [0, 0, 0], [0, 0, 0], lo, [ni, nj, nk])
            allocate(k%x0(3, k%ix%nnode), k%x(3, k%ix%nnode), k%s(3, k%ix%nnode), k%xt(3, k%ix%nnode))
            call copy_in(k%ix, xp0, k%x0)
            call copy_in(k%ix, xp, k%x)
          end associate
        end do
      end do
    end do
    ! each direction: the running sums block after block, then the totals back
    do a = 1, 3
      do kk = 1, nbk(3)
        do jj = 1, nbk(2)
          do ii = 1, nbk(1)
            b = [ii, jj, kk]
            associate (k => bl(ii, jj, kk))
              q = [k%ix%ni, k%ix%nj, k%ix%nk] + 1
              nb = product(q)/q(a)
              allocate(start(nb))
              start = 0.0_wp
              if (b(a) > 1) then
                q = b
                q(a) = q(a) - 1
                start = bl(q(1), q(2), q(3))%finish
              end if
              if (allocated(k%finish)) deallocate(k%finish)
              allocate(k%finish(nb))
              call global_line_sums(k%ix, a, k%x0, start, k%s, k%finish)
              deallocate(start)
            end associate
          end do
        end do
      end do
      do kk = 1, nbk(3)
        do jj = 1, nbk(2)
          do ii = 1, nbk(1)
            q = [ii, jj, kk]
            q(a) = nbk(a)
            call global_line_scale(bl(ii, jj, kk)%ix, a, bl(q(1), q(2), q(3))%finish, ntot(a), &
                                   bl(ii, jj, kk)%s)
          end do
        end do
      end do
    end do
    nbad = 0
    do kk = 1, nbk(3)
      do jj = 1, nbk(2)
        do ii = 1, nbk(1)
          associate (k => bl(ii, jj, kk))
            call global_block_target(sf, k%ix, k%s, k%x0, k%x, k%xt)
            call copy_in(k%ix, xw, k%x)
            if (.not. same(k%xt, k%x)) nbad = nbad + 1
          end associate
        end do
      end do
    end do
    call check(nbad == 0, 'blocks: each of the 6 blocks'' targets is the whole grid''s, bit for bit')
  end subroutine test_blocks

  !> The block k's nodes of a whole-grid node array w.
  subroutine copy_in(kx, w, xb)
    type(grid_index_t), intent(in) :: kx
    real(wp), intent(in) :: w(:, :)
    real(wp), intent(out) :: xb(:, :)
    integer :: ii, jj, kk
    do kk = 0, kx%nk
      do jj = 0, kx%nj
        do ii = 0, kx%ni
          xb(:, kx%node(ii, jj, kk)) = w(:, ix%node(ii + kx%off(1), jj + kx%off(2), kk + kx%off(3)))
        end do
      end do
    end do
  end subroutine copy_in

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
