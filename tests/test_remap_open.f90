!> Unit tests of the remap at open faces (`remap_euler`) when the old grid's
!> open face lies several cells from the new one, and of the bins that find
!> the old cells a new cell can meet (`remap_bins`).
!>
!> A box of 10 x 3 x 2 cells (cell length 0.1 along x) is remapped onto
!> itself from an old grid whose xhi face moved by 2.5 cells:
!>   - in (a gap 2.5 cells deep at an outflow face): no error; the gap is
!>     filled with the state of the old cell at the face on the same index
!>     line (a uniform state stays uniform; in a linear state the cells
!>     wholly in the gap get the boundary cell's density); what came in is
!>     rho times the gap's volume; mass, momentum and energy balance with it;
!>   - out (2.5 cells of old grid beyond an outflow face): no error; what
!>     lies beyond has left (rho times its volume) and the rest balances;
!>   - the same moves at a wall: still errors (a gap there, or old cells
!>     wholly outside, is a real failure).
!> Then the bins' reach against a search of every cell, and the same reach
!> found by a window's remap from its own bins and the far cells other
!> blocks send it (`remap_zone_far`).
program test_remap_open
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use test_assert, only: check, check_summary
  use mesh_grid, only: grid_t, grid_init_box, block_gather
  use mesh_geometry, only: hex_volume
  use mesh_boundary, only: bc_t, bc_init, BC_SYMMETRY, BC_WALL, BC_OUTFLOW
  use material_mixed, only: mixed_t
  use mesh_halo, only: halo_t
  use hydro_state, only: hydro_t, hydro_allocate, hydro_totals, hydro_subcell_masses
  use remap_euler, only: remap_params_t, remap_stats_t, remap_euler_step, remap_zone_t, remap_zone_wants, &
                         remap_zone_far
  use remap_bins, only: remap_bins_t, remap_bins_build, remap_bins_reach, remap_bins_cells, remap_boxes_reach
  implicit none
  integer, parameter :: ni = 10, nj = 3, nk = 2, nc = ni*nj*nk, nn = (ni + 1)*(nj + 1)*(nk + 1)
  real(wp), parameter :: xmax(3) = [1.0_wp, 0.3_wp, 0.2_wp], u0(3) = [-0.5_wp, 0.0_wp, 0.0_wp]
  real(wp), parameter :: area = 0.3_wp*0.2_wp
  type(grid_t) :: g
  type(hydro_t) :: h
  type(mixed_t) :: mx
  type(bc_t) :: bc
  type(remap_params_t) :: par
  type(remap_stats_t) :: st
  type(error_t), allocatable :: err
  real(wp) :: x0(3, nn), xold(3, nn), m0, p0(3), ie0, ke0, m1, p1(3), ie1, ke1, rho_b, dmax
  integer :: c, n, j, k

  call grid_init_box(g, ni, nj, nk, [0.0_wp, 0.0_wp, 0.0_wp], xmax, err)
  x0 = g%x

  ! (a) the xhi outflow face moved in by 2.5 cells: x_old = 0.75 x0
  xold = x0
  xold(1, :) = 0.75_wp*x0(1, :)
  call setup(BC_OUTFLOW, 'uniform')
  call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
  call remap_euler_step(g, h, mx, 1, bc, x0, par, st, err)
  call check(.not. allocated(err), 'gap 2.5 cells deep at an outflow face: remapped')
  if (allocated(err)) write(*, '(a)') 'message: '//err%msg
  call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
  write(*, '(a,es12.5,a,es12.5,a,i0)') 'gap: mass in ', st%mass_in, ' (rho V_gap ', 2.0_wp*0.25_wp*area, &
    '), window ', st%reach
  call check(abs(st%mass_in - 2.0_wp*0.25_wp*area) <= 1.0e-13_wp, 'gap: what came in is rho V_gap')
  call check(abs(m1 - m0 - st%mass_in + st%mass_out) <= 1.0e-13_wp*m0, 'gap: mass balances')
  call check(norm2(p1 - p0 - st%momentum_in + st%momentum_out) <= 1.0e-13_wp*norm2(p0), 'gap: momentum balances')
  call check(abs(ie1 + ke1 - ie0 - ke0 - st%energy_in + st%energy_out) <= 1.0e-13_wp*(ie0 + ke0), &
             'gap: energy balances')
  call check(maxval(abs(h%rho - 2.0_wp)) <= 1.0e-13_wp .and. maxval(abs(h%e - 3.0_wp)) <= 1.0e-13_wp, &
             'gap: a uniform state stays uniform')
  dmax = 0.0_wp
  do n = 1, nn
    dmax = max(dmax, maxval(abs(h%u(:, n) - u0)))
  end do
  call check(dmax <= 1.0e-13_wp, 'gap: a uniform velocity stays uniform')

  ! the same gap, a density linear in x: the cells wholly in the gap (the
  ! last two along x) get the old boundary cell's density (zero gradient)
  call setup(BC_OUTFLOW, 'linear')
  rho_b = h%rho(g%cell(ni, 2, 1))
  call remap_euler_step(g, h, mx, 1, bc, x0, par, st, err)
  call check(.not. allocated(err), 'gap, linear density: remapped')
  dmax = 0.0_wp
  do k = 1, nk
    do j = 1, nj
      dmax = max(dmax, abs(h%rho(g%cell(ni, j, k)) - rho_b), abs(h%rho(g%cell(ni - 1, j, k)) - rho_b))
    end do
  end do
  write(*, '(a,f8.5,a,es10.3)') 'gap: old boundary density ', rho_b, ', largest difference in the gap ', dmax
  call check(dmax <= 1.0e-13_wp, 'gap: the cells in the gap take the old boundary cell''s state')

  ! (b) the xhi outflow face moved out by 2.5 cells: x_old = 1.25 x0
  xold = x0
  xold(1, :) = 1.25_wp*x0(1, :)
  call setup(BC_OUTFLOW, 'uniform')
  call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
  call remap_euler_step(g, h, mx, 1, bc, x0, par, st, err)
  call check(.not. allocated(err), '2.5 cells of old grid beyond an outflow face: remapped')
  if (allocated(err)) write(*, '(a)') 'message: '//err%msg
  call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
  write(*, '(a,es12.5,a,es12.5,a)') 'beyond: mass out ', st%mass_out, ' (rho V_beyond ', 2.0_wp*0.25_wp*area, ')'
  call check(abs(st%mass_out - 2.0_wp*0.25_wp*area) <= 1.0e-13_wp .and. .not. st%mass_in > 0.0_wp, &
             'beyond: what left is rho V_beyond')
  call check(abs(m1 - m0 + st%mass_out) <= 1.0e-13_wp*m0, 'beyond: mass balances')
  call check(norm2(p1 - p0 + st%momentum_out) <= 1.0e-13_wp*norm2(p0), 'beyond: momentum balances')
  call check(abs(ie1 + ke1 - ie0 - ke0 + st%energy_out) <= 1.0e-13_wp*(ie0 + ke0), 'beyond: energy balances')
  call check(maxval(abs(h%rho - 2.0_wp)) <= 1.0e-13_wp, 'beyond: a uniform state stays uniform')

  ! (c) the same moves at a wall: real failures
  xold = x0
  xold(1, :) = 0.75_wp*x0(1, :)
  call setup(BC_WALL, 'uniform')
  call remap_euler_step(g, h, mx, 1, bc, x0, par, st, err)
  call check(allocated(err), 'a gap at a wall: an error')
  if (allocated(err)) write(*, '(a)') 'message: '//err%msg
  if (allocated(err)) deallocate(err)
  xold = x0
  xold(1, :) = 1.25_wp*x0(1, :)
  call setup(BC_WALL, 'uniform')
  call remap_euler_step(g, h, mx, 1, bc, x0, par, st, err)
  call check(allocated(err), 'old cells wholly outside a wall: an error')
  if (allocated(err)) write(*, '(a)') 'message: '//err%msg
  if (allocated(err)) deallocate(err)

  call test_cold()
  call test_bins()
  call check_summary('test_remap_open')

contains

  !> The old state on xold: density 2 (or linear in x), energy 3, velocity
  !> u0; xhi of kind `kind_hi`, xlo outflow (it does not move), y and z
  !> symmetry.
  subroutine setup(kind_hi, field)
    integer, intent(in) :: kind_hi
    character(len=*), intent(in) :: field
    real(wp) :: xn(3, 8)
    integer :: cc
    h = hydro_t()
    mx = mixed_t()
    bc = bc_t()
    bc%kind = BC_SYMMETRY
    bc%kind(1) = BC_OUTFLOW
    bc%kind(2) = kind_hi
    call bc_init(bc, g, err)
    g%x = xold
    call hydro_allocate(h, nc, nn, err)
    h%mat = 1
    h%e = 3.0_wp
    do cc = 1, nc
      call g%gather(cc, xold, xn)
      h%vol(cc) = hex_volume(xn)
      h%rho(cc) = 2.0_wp
      if (field == 'linear') h%rho(cc) = 1.0_wp + sum(xn(1, :))/8.0_wp
      h%mass(cc) = h%rho(cc)*h%vol(cc)
    end do
    call hydro_subcell_masses(g, xold, h%rho, h%mnode, h%mcorner)
    do n = 1, nn
      h%u(:, n) = u0
    end do
  end subroutine setup

  !> Kinetic energy in cold gas: e = 0 for x < 0.5, 0.5 beyond, a density
  !> gradient, a shear flow of size ~1, remapped from a perturbed grid onto
  !> the box. The energy a node returns is counted about its new velocity
  !> (a sum of squares), so with no velocity condition acting no node ends
  !> with more kinetic energy than its corners brought: no deficit arises
  !> (before that count, deficits arose here and the nearest cells with
  !> energy had to pay them); no cell goes below zero and total energy is
  !> kept.
  subroutine test_cold()
    type(rng_t) :: rng
    real(wp) :: xn(3, 8), hh(3)
    integer :: cc, ii, jj, kk, d
    hh = xmax/real([ni, nj, nk], wp)
    call rng_seed(rng, 5)
    do kk = 0, nk
      do jj = 0, nj
        do ii = 0, ni
          n = g%node(ii, jj, kk)
          xold(:, n) = x0(:, n)
          if (ii > 0 .and. ii < ni .and. jj > 0 .and. jj < nj .and. kk > 0 .and. kk < nk) then
            do d = 1, 3
              xold(d, n) = xold(d, n) + 0.3_wp*hh(d)*(2.0_wp*rng_uniform(rng) - 1.0_wp)
            end do
          end if
        end do
      end do
    end do
    ! (open faces at x, symmetry planes in y and z: no condition acts on a
    ! velocity along x, so none adds energy)
    call setup(BC_OUTFLOW, 'uniform')
    do cc = 1, nc
      call g%gather(cc, xold, xn)
      h%rho(cc) = 1.0_wp + 2.0_wp*sum(xn(1, :))/8.0_wp
      h%mass(cc) = h%rho(cc)*h%vol(cc)
      h%e(cc) = merge(0.0_wp, 0.5_wp, sum(xn(1, :))/8.0_wp < 0.5_wp)
    end do
    call hydro_subcell_masses(g, xold, h%rho, h%mnode, h%mcorner)
    do n = 1, nn
      ! a shear flow along x
      h%u(:, n) = [-1.0_wp - 0.5_wp*sin(7.0_wp*xold(1, n))*cos(9.0_wp*xold(2, n) + 5.0_wp*xold(3, n)), 0.0_wp, 0.0_wp]
    end do
    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    call remap_euler_step(g, h, mx, 1, bc, x0, par, st, err)
    call check(.not. allocated(err), 'cold gas: remapped')
    if (allocated(err)) write(*, '(a)') 'message: '//err%msg
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    write(*, '(a,i0,a,es10.3,a,es10.3,a,es10.3,a,es10.3)') 'cold gas: deficits of ', st%cells_deficit, &
      ' cells (', st%deficit_moved, ') moved, ', st%deficit_by_mass, ' by mass; smallest energy ', minval(h%e), &
      ', energy change ', (ie1 + ke1 - ie0 - ke0)/(ie0 + ke0)
    call check(st%cells_deficit == 0 .and. .not. st%deficit_by_mass > 0.0_wp, &
               'cold gas: no kinetic energy deficit without a velocity condition')
    call check(minval(h%e) >= 0.0_wp, 'cold gas: no cell below zero internal energy')
    call check(abs(ie1 + ke1 - ie0 - ke0) <= 1.0e-13_wp*(ie0 + ke0), 'cold gas: total energy kept (1e-13)')
  end subroutine test_cold

  !> remap_bins_reach against every cell's bounding box, on a perturbed grid
  !> and boxes scattered over and beyond it.
  subroutine test_bins()
    integer, parameter :: bi = 7, bj = 6, bk = 5, bn = (bi + 1)*(bj + 1)*(bk + 1), bc_ = bi*bj*bk
    real(wp) :: xb(3, bn), lo(3), hi(3), xn(3, 8), olo(3), ohi(3)
    logical :: use(bc_)
    type(remap_bins_t) :: bins
    type(rng_t) :: rng
    integer :: ii, jj, kk, d, q, r_bins, r_all, oi, oj, ok_, nbad, ci, cj, ck, nlist, nbad_list
    integer, allocatable :: list(:)
    call rng_seed(rng, 17)
    nbad_list = 0
    do kk = 0, bk
      do jj = 0, bj
        do ii = 0, bi
          n = 1 + ii + (bi + 1)*(jj + (bj + 1)*kk)
          xb(:, n) = real([ii, jj, kk], wp)
          do d = 1, 3
            xb(d, n) = xb(d, n) + 0.45_wp*(2.0_wp*rng_uniform(rng) - 1.0_wp)
          end do
        end do
      end do
    end do
    do c = 1, bc_
      use(c) = rng_uniform(rng) < 0.8_wp
    end do
    call remap_bins_build(bi, bj, bk, xb, use, bins, err)
    call check(.not. allocated(err), 'bins built')
    nbad = 0
    do q = 1, 400
      ci = 1 + int(bi*rng_uniform(rng))
      cj = 1 + int(bj*rng_uniform(rng))
      ck = 1 + int(bk*rng_uniform(rng))
      do d = 1, 3
        lo(d) = -2.0_wp + 11.0_wp*rng_uniform(rng)
        hi(d) = lo(d) + 3.0_wp*rng_uniform(rng)
      end do
      r_bins = remap_bins_reach(bins, ci, cj, ck, lo, hi)
      call remap_bins_cells(bins, lo, hi, list, nlist)
      if (nlist < 0) nbad_list = nbad_list + 1
      if (nlist > 1) then
        if (any(list(2:nlist) <= list(1:nlist - 1))) nbad_list = nbad_list + 1
      end if
      r_all = -1
      do ok_ = 1, bk
        do oj = 1, bj
          do oi = 1, bi
            if (.not. use(oi + bi*((oj - 1) + bj*(ok_ - 1)))) cycle
            call block_gather(bi, bj, oi, oj, ok_, xb, xn)
            olo = minval(xn, 2)
            ohi = maxval(xn, 2)
            if (any(ohi < lo) .or. any(olo > hi)) cycle
            r_all = max(r_all, abs(oi - ci), abs(oj - cj), abs(ok_ - ck))
            if (nlist <= 0) then
              nbad_list = nbad_list + 1
            else if (.not. any(list(1:nlist) == oi + bi*((oj - 1) + bj*(ok_ - 1)))) then
              nbad_list = nbad_list + 1
            end if
          end do
        end do
      end do
      ! (the bins may add cells within their padding of 1e-9: never fewer)
      if (r_bins < r_all) nbad = nbad + 1
    end do
    call check(nbad == 0, 'bins: the reach holds every cell whose box meets the query (400 queries)')
    call check(nbad_list == 0, 'bins: the cell list holds every cell whose box meets the query, each once, '// &
               'in increasing order (400 queries)')
    call test_window(xb, use, bins)
  end subroutine test_bins

  !> A window of the bins' grid (cells 2..6 x 2..5 x 1..5): the reach of
  !> a query from one of its cells, as a window's remap finds it (its own
  !> bins, in its indices, and the far cells: every used cell outside it,
  !> as candidates that `remap_zone_far` filters, in whole-grid indices),
  !> against the whole grid's bins, bit for bit.
  subroutine test_window(xb, use, bins)
    integer, parameter :: bi = 7, bj = 6, bk = 5, off(3) = [1, 1, 0], wn(3) = [5, 4, 5]
    integer, parameter :: wnn = (wn(1) + 1)*(wn(2) + 1)*(wn(3) + 1)
    real(wp), intent(in) :: xb(:, :)
    logical, intent(in) :: use(:)
    type(remap_bins_t), intent(in) :: bins
    type(remap_bins_t) :: wbins
    type(remap_zone_t) :: zone
    type(rng_t) :: rng
    real(wp) :: xw(3, wnn), lo(3), hi(3), xn(3, 8), r(12), cand_box(6, bi*bj*bk)
    logical :: wuse(product(wn))
    integer :: cand(3, bi*bj*bk), ii, jj, kk, d, q, ncand, nbad, ci, cj, ck, r_whole, r_win, nfar, nby_far
    do kk = 0, wn(3)
      do jj = 0, wn(2)
        do ii = 0, wn(1)
          xw(:, 1 + ii + (wn(1) + 1)*(jj + (wn(2) + 1)*kk)) = &
            xb(:, 1 + ii + off(1) + (bi + 1)*(jj + off(2) + (bj + 1)*(kk + off(3))))
        end do
      end do
    end do
    ncand = 0
    do kk = 1, bk
      do jj = 1, bj
        do ii = 1, bi
          c = ii + bi*((jj - 1) + bj*(kk - 1))
          if (all([ii, jj, kk] > off .and. [ii, jj, kk] <= off + wn)) then
            wuse(ii - off(1) + wn(1)*((jj - off(2) - 1) + wn(2)*(kk - off(3) - 1))) = use(c)
          else if (use(c)) then
            ncand = ncand + 1
            cand(:, ncand) = [ii, jj, kk]
            call block_gather(bi, bj, ii, jj, kk, xb, xn)
            cand_box(:, ncand) = [minval(xn, 2), maxval(xn, 2)]
          end if
        end do
      end do
    end do
    call remap_bins_build(wn(1), wn(2), wn(3), xw, wuse, wbins, err)
    call check(.not. allocated(err), 'window bins built')
    ! (the window's description: its index range, and a box that holds
    ! every query below)
    r = [real(off + 1, wp), real(off + wn, wp), [-2.0_wp, -2.0_wp, -2.0_wp], [12.0_wp, 12.0_wp, 12.0_wp]]
    call remap_zone_far(zone, r, cand(:, 1:ncand), cand_box(:, 1:ncand))
    nfar = size(zone%far_ijk, 2)
    call check(nfar == ncand .and. count([(remap_zone_wants(r, [ii, 2, 2], [0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, &
               1.0_wp, 1.0_wp]), ii = 2, 6)]) == 0, 'far cells: those outside the window kept, those inside not')
    call rng_seed(rng, 23)
    nbad = 0
    nby_far = 0
    do q = 1, 400
      ci = off(1) + 1 + int(wn(1)*rng_uniform(rng))
      cj = off(2) + 1 + int(wn(2)*rng_uniform(rng))
      ck = off(3) + 1 + int(wn(3)*rng_uniform(rng))
      do d = 1, 3
        lo(d) = -2.0_wp + 11.0_wp*rng_uniform(rng)
        hi(d) = lo(d) + 3.0_wp*rng_uniform(rng)
      end do
      r_whole = remap_bins_reach(bins, ci, cj, ck, lo, hi)
      r_win = max(remap_bins_reach(wbins, ci - off(1), cj - off(2), ck - off(3), lo, hi), &
                  remap_boxes_reach(zone%far_ijk, zone%far_box, ci, cj, ck, lo, hi))
      if (r_win /= r_whole) nbad = nbad + 1
      if (r_whole > remap_bins_reach(wbins, ci - off(1), cj - off(2), ck - off(3), lo, hi)) nby_far = nby_far + 1
    end do
    write(*, '(a,i0,a)') 'window: ', nby_far, ' of 400 queries take their reach from a far cell'
    call check(nby_far > 0, 'window: some queries reach a far cell')
    call check(nbad == 0, 'window: its bins and the far cells give the whole grid''s reach (400 queries)')
    ! (a window that wants nothing: a box its cells' cannot meet)
    r(7:12) = [20.0_wp, 20.0_wp, 20.0_wp, 21.0_wp, 21.0_wp, 21.0_wp]
    call remap_zone_far(zone, r, cand(:, 1:ncand), cand_box(:, 1:ncand))
    call check(size(zone%far_ijk, 2) == 0 .and. size(zone%far_box, 2) == 0, 'far cells: none whose box is elsewhere')
  end subroutine test_window
end program test_remap_open
