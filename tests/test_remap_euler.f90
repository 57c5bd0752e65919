!> Unit tests of the Euler-phase remap (`remap_euler`) between two different
!> randomly perturbed grids of one box: conservation of mass, momentum and
!> total energy to round-off, constant and uniform states kept exactly, a
!> linear density reproduced exactly away from the boundary, a planar
!> material interface carried exactly through MoF, and unchanged cells
!> copied bit for bit; the swept-face path: the swept region's closed form,
!> the same properties, and every new density and energy within the old
!> neighbourhood's bounds.
program test_remap_euler
  use base_kinds, only: wp, i8
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use base_timers, only: wall_seconds
  use test_assert, only: check, check_summary
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_volume, hex_natural
  use mesh_boundary, only: bc_t, bc_init, bc_constrain, BC_VELOCITY
  use material_mixed, only: mixed_t, mixed_allocate
  use mesh_halo, only: halo_t
  use hydro_state, only: hydro_t, hydro_allocate, hydro_totals, hydro_subcell_masses
  use geometry_cells, only: cell_moments
  use geometry_mof, only: mof_cut_volume
  use remap_euler, only: remap_params_t, remap_stats_t, remap_euler_step, remap_swept_blockers, remap_part_target, &
                         remap_part_folded
  use remap_swept, only: swept_triangle
  use remap_lattice, only: lattice_t, lattice_nodes, lattice_build, lattice_tet
  use base_xsum, only: xsum_value
  implicit none
  integer, parameter :: ni = 6, nj = 5, nk = 4, nc = ni*nj*nk, nn = (ni + 1)*(nj + 1)*(nk + 1)
  real(wp), parameter :: lin(4) = [1.0_wp, 0.3_wp, -0.4_wp, 0.5_wp]
  real(wp), parameter :: plane_n(3) = [0.8_wp, 0.36_wp, 0.48_wp], plane_d = 0.62_wp
  real(wp) :: xa(3, nn), xb(3, nn), vb(nc), cb(3, nc), err_max
  type(grid_t) :: g
  type(hydro_t) :: h
  type(mixed_t) :: mx
  type(bc_t) :: bc
  type(remap_params_t) :: par
  type(remap_params_t), parameter :: dflt = remap_params_t()
  type(remap_stats_t) :: st
  type(error_t), allocatable :: err
  real(wp) :: m0, p0(3), ie0, ke0, m1, p1(3), ie1, ke1, t0, ma0, mb0, ma1, mb1
  integer :: c, n, interior
  logical :: ok

  call make_grid(xa, 11, 0.2_wp)
  call make_grid(xb, 23, 0.2_wp)
  call cell_moments(ni, nj, nk, xb, vb, cb)

  ! 1. constant density and energy, uniform velocity: kept exactly
  call setup(xa, 'constant')
  call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
  call remap_euler_step(g, h, mx, 1, bc, xb, par, st, err)
  call check(.not. allocated(err), 'remap of a uniform state runs')
  call check(maxval(abs(h%rho - 2.0_wp)) < 1e-13_wp, 'constant density kept')
  call check(maxval(abs(h%e - 3.0_wp)) < 1e-13_wp, 'constant energy kept')
  err_max = 0.0_wp
  do n = 1, nn
    err_max = max(err_max, maxval(abs(h%u(:, n) - [0.7_wp, -0.2_wp, 0.1_wp])))
  end do
  call check(err_max < 1e-14_wp, 'uniform velocity kept')
  call check(st%cells_remapped == nc, 'every cell moved and was remapped')
  write(*, '(a,es10.3,a,i0)') 'uniform state: largest volume defect ', st%volume_defect, ', reach ', st%reach

  ! 2. linear density and velocity: conservation, and exact linear density
  ! in cells whose old neighbourhood is interior (at the boundary the
  ! limiter may cut a gradient: boundary nodes lie outside the range of the
  ! neighbouring centroids)
  call setup(xa, 'linear')
  call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
  t0 = wall_seconds()
  call remap_euler_step(g, h, mx, 1, bc, xb, par, st, err)
  write(*, '(a,f9.2,a)') 'remap: ', 1.0e6_wp*(wall_seconds() - t0)/nc, ' us per cell (this build)'
  call check(.not. allocated(err), 'remap of a linear state runs')
  call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
  write(*, '(a,3es10.2)') 'linear state: relative change of mass, momentum, energy: ', &
    abs(m1 - m0)/m0, norm2(p1 - p0)/norm2(p0), abs(ie1 + ke1 - ie0 - ke0)/(ie0 + ke0)
  call check(abs(m1 - m0) <= 1e-13_wp*m0, 'mass conserved to 1e-13')
  call check(norm2(p1 - p0) <= 1e-13_wp*norm2(p0), 'momentum conserved to 1e-13')
  call check(abs(ie1 + ke1 - ie0 - ke0) <= 1e-13_wp*(ie0 + ke0), 'total energy conserved to 1e-13')
  call check(ke1 <= ke0*(1.0_wp + 1e-14_wp), 'kinetic energy does not grow')
  err_max = 0.0_wp
  interior = 0
  do c = 1, nc
    if (.not. deep(c)) cycle
    interior = interior + 1
    err_max = max(err_max, abs(h%rho(c) - (lin(1) + dot_product(lin(2:4), cb(:, c)))))
  end do
  write(*, '(a,i0,a,es10.3)') 'linear density in ', interior, ' deep cells: largest error ', err_max
  call check(interior > 0 .and. err_max < 1e-12_wp, 'linear density reproduced exactly away from the boundary')

  ! 3. two materials split by a plane: MoF finds it, the new volume
  ! fractions are the plane's exact cuts of the new cells; each material's
  ! mass is conserved
  call setup(xa, 'plane')
  call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
  call material_masses(ma0, mb0)
  call remap_euler_step(g, h, mx, 2, bc, xb, par, st, err)
  call check(.not. allocated(err), 'remap of two materials runs')
  call check(st%mof_not_converged == 0 .and. st%mof_cells > 0, 'MoF converged in every mixed cell')
  write(*, '(a,i0,a,f6.2,a,es10.3)') 'plane: ', st%mof_cells, ' MoF cells, mean iterations ', &
    real(st%mof_iterations, wp)/real(max(st%mof_cells, 1), wp), ', largest centroid error/size ', st%mof_err_max
  call material_masses(ma1, mb1)
  call check(abs(ma1 - ma0) <= 1e-13_wp*ma0 .and. abs(mb1 - mb0) <= 1e-13_wp*mb0, &
             'each material''s mass conserved to 1e-13')
  err_max = plane_error()
  write(*, '(a,es10.3)') 'plane: largest volume-fraction error of a new cell ', err_max
  call check(err_max < 1e-9_wp, 'new volume fractions are the exact cuts of the plane')
  call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
  call check(abs(ie1 + ke1 - ie0 - ke0) <= 1e-13_wp*(ie0 + ke0), 'two materials: total energy conserved')

  ! 4. only some nodes move: cells away from them are copied bit for bit and
  ! nodes among unchanged cells keep their velocity exactly
  call setup(xa, 'linear')
  xb = xa
  xb(:, node(3, 3, 2)) = xa(:, node(3, 3, 2)) + [0.05_wp, -0.03_wp, 0.02_wp]
  block
    real(wp) :: rho0(nc), u0(3, nn)
    rho0 = h%rho
    u0 = h%u
    call remap_euler_step(g, h, mx, 1, bc, xb, par, st, err)
    call check(.not. allocated(err) .and. st%cells_remapped == 8, 'one moved node: eight cells remapped')
    ok = .true.
    do c = 1, nc
      if (far(c)) ok = ok .and. abs(h%rho(c) - rho0(c)) <= 0.0_wp
    end do
    call check(ok, 'unchanged cells copied bit for bit')
    call check(all(abs(h%u(:, node(0, 0, 0)) - u0(:, node(0, 0, 0))) <= 0.0_wp) .and. &
               all(abs(h%u(:, node(6, 5, 4)) - u0(:, node(6, 5, 4))) <= 0.0_wp), 'nodes among unchanged cells keep u')
  end block

  ! 4b. what the remap reports it changed (`remap_stats_t` change: the cells
  ! and nodes it wrote, summed exactly before and after) is the change of
  ! the whole grid's exact totals: one node moved, all cells moved, two
  ! materials, and deficits repaired beyond the changed cells
  call setup(xa, 'linear')
  call check_change(xb, 1, 'one moved node')
  call make_grid(xb, 23, 0.2_wp)
  call setup(xa, 'linear')
  call check_change(xb, 1, 'every cell moved')
  call setup(xa, 'plane')
  call check_change(xb, 2, 'two materials')
  ! (a velocity condition on xlo raises its nodes' kinetic energy; the cold
  ! cells there (x < 0.8: the changed cells and two layers beyond) cannot
  ! pay for it, so warm cells beyond the near ones do: `assemble`'s wide
  ! path, whose cells' energies the change must include)
  block
    real(wp) :: xm(3, nn)
    call setup(xa, 'linear')
    call cell_moments(ni, nj, nk, xa, vb, cb)
    where (cb(1, :) < 0.8_wp) h%e = 0.0_wp
    do n = 1, nn
      h%u(:, n) = [0.1_wp, 0.0_wp, 0.0_wp]
    end do
    bc%kind(1) = BC_VELOCITY
    bc%velocity(:, 1) = [0.5_wp, 0.0_wp, 0.0_wp]
    call bc_init(bc, g, err)
    ! (the face's nodes meet the condition already, as after a Lagrangian step)
    call bc_constrain(bc, h%u)
    xm = xa
    xm(:, node(1, 2, 2)) = xa(:, node(1, 2, 2)) + [0.03_wp, -0.02_wp, 0.01_wp]
    call check_change(xm, 1, 'piston on cold gas')
    write(*, '(a,i0,2es12.4)') 'piston on cold gas: deficit cells, taken from cells around, by mass ', &
      st%cells_deficit, st%deficit_moved - st%deficit_by_mass, st%deficit_by_mass
    write(*, '(a,i0)') 'piston on cold gas: warm cells (x > 0.8, beyond the near ones) that paid: ', &
      count(cb(1, :) > 0.8_wp .and. h%e < 3.0_wp)
    call check(st%cells_deficit > 0 .and. st%deficit_moved > st%deficit_by_mass .and. &
               count(cb(1, :) > 0.8_wp .and. h%e < 3.0_wp) > 0, &
               'piston on cold gas: deficits paid by warm cells beyond the near ones (the wide path)')
    bc = bc_t()
    call cell_moments(ni, nj, nk, xb, vb, cb)
  end block

  ! 4c. an overlap beyond the first window that is small but not round-off:
  ! new cell i = 1 ends 2e-11 past old node plane i = 2 (old planes x = 0,
  ! 0.1, 0.3, ...; new x = 0, 0.3 + 2e-11, ...), so it meets old cell 3 two
  ! index steps away in a sliver of 7e-11 of its volume; its window is
  ! widened (no volume missing, no old region rescaled) and the remap
  ! conserves (a window kept while 1e-9 was missing rescaled old cell 3,
  ! whose subcells then no longer gave their own momentum)
  block
    real(wp), parameter :: xold(0:ni) = [0.0_wp, 0.1_wp, 0.3_wp, 0.6_wp, 0.8_wp, 1.0_wp, 1.2_wp], &
                           xnew(0:ni) = [0.0_wp, 0.3_wp + 2.0e-11_wp, 0.5_wp, 0.7_wp, 0.9_wp, 1.05_wp, 1.2_wp]
    real(wp) :: xo(3, nn), xw(3, nn)
    integer :: i, j, k
    do k = 0, nk
      do j = 0, nj
        do i = 0, ni
          xo(:, node(i, j, k)) = [xold(i), 0.2_wp*j, 0.2_wp*k]
          xw(:, node(i, j, k)) = [xnew(i), 0.2_wp*j, 0.2_wp*k]
        end do
      end do
    end do
    call setup(xo, 'linear')
    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    call remap_euler_step(g, h, mx, 1, bc, xw, par, st, err)
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    write(*, '(a,es10.2,a,i0,a,i0,a,3es10.2)') 'sliver two cells away: volume defect ', st%volume_defect, ', reach ', &
      st%reach, ', regions rescaled ', st%regions_rescaled, ', relative change of mass, momentum, energy ', &
      abs(m1 - m0)/m0, norm2(p1 - p0)/norm2(p0), abs(ie1 + ke1 - ie0 - ke0)/(ie0 + ke0)
    call check(.not. allocated(err) .and. st%volume_defect < 1e-13_wp .and. st%regions_rescaled == 0 .and. &
               st%reach == 2, 'sliver two cells away: found by a wider window')
    call check(abs(m1 - m0) <= 1e-14_wp*m0 .and. norm2(p1 - p0) <= 1e-14_wp*norm2(p0) .and. &
               abs(ie1 + ke1 - ie0 - ke0) <= 1e-14_wp*(ie0 + ke0), 'sliver two cells away: conservation to 1e-14')
  end block

  ! 5. to the box grid (the global rezone's target: new cells split into
  ! octant boxes instead of half tetrahedra): the same properties
  call make_grid(xb, 23, 0.0_wp)
  call cell_moments(ni, nj, nk, xb, vb, cb)
  call setup(xa, 'linear')
  call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
  call remap_euler_step(g, h, mx, 1, bc, xb, par, st, err)
  call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
  call check(.not. allocated(err) .and. abs(m1 - m0) <= 1e-13_wp*m0 .and. norm2(p1 - p0) <= 1e-13_wp*norm2(p0) .and. &
             abs(ie1 + ke1 - ie0 - ke0) <= 1e-13_wp*(ie0 + ke0), 'to the box grid: conservation to 1e-13')
  err_max = 0.0_wp
  do c = 1, nc
    if (deep(c)) err_max = max(err_max, abs(h%rho(c) - (lin(1) + dot_product(lin(2:4), cb(:, c)))))
  end do
  write(*, '(a,es10.3)') 'to the box grid: linear density, largest error in deep cells ', err_max
  call check(err_max < 1e-12_wp, 'to the box grid: linear density reproduced exactly')
  call setup(xa, 'plane')
  call remap_euler_step(g, h, mx, 2, bc, xb, par, st, err)
  err_max = plane_error()
  write(*, '(a,es10.3)') 'to the box grid: plane, largest volume-fraction error ', err_max
  call check(.not. allocated(err) .and. err_max < 1e-9_wp, 'to the box grid: plane interface exact')

  ! 5b. the lattice path (the box grid is a lattice: each old half clipped
  ! once by the half-cells it reaches): the same remap as clipping per new
  ! cell, to round-off, with the same conservation
  ok = lattice_nodes(g, xb)
  call check(ok, 'the box grid is a lattice')
  ok = lattice_nodes(g, xa)
  call check(.not. ok, 'a perturbed grid is not a lattice')
  call test_lattice_tet()
  call compare_lattice('linear', 1)
  call compare_lattice('plane', 2)

  ! 6. consistency: a curved velocity field on a grid moved by 1e-6 of a
  ! cell changes at the nodes by O(1e-6), not by a fixed smoothing error
  ! (a velocity fitted over whole cells would move interior nodes of this
  ! field by ~4e-3 whatever the displacement)
  call setup(xa, 'curved')
  block
    real(wp) :: u0(3, nn), xm(3, nn)
    integer :: i, j, k
    u0 = h%u
    xm = xa
    do k = 1, nk - 1
      do j = 1, nj - 1
        do i = 1, ni - 1
          xm(:, node(i, j, k)) = xa(:, node(i, j, k)) + 1.0e-6_wp*[0.3_wp, -0.2_wp, 0.25_wp]*real(1 + mod(i + j + k, 3), wp)
        end do
      end do
    end do
    call remap_euler_step(g, h, mx, 1, bc, xm, par, st, err)
    err_max = 0.0_wp
    do k = 1, nk - 1
      do j = 1, nj - 1
        do i = 1, ni - 1
          err_max = max(err_max, maxval(abs(h%u(:, node(i, j, k)) - u0(:, node(i, j, k)))))
        end do
      end do
    end do
  end block
  write(*, '(a,es10.3)') 'curved velocity, grid moved by 1e-6: largest change at an interior node ', err_max
  call check(.not. allocated(err) .and. err_max < 1.0e-4_wp, 'velocity remap is consistent (tends to identity)')

  call test_swept()
  call test_parts()

  call check_summary('test_remap_euler')

contains

  !> Remaps the state set up from xa to x (nm materials) and checks that the
  !> change the remap reports equals the change of hydro_totals (both exact
  !> sums: to a few units in the last place of the totals).
  subroutine check_change(x, nm, what)
    real(wp), intent(in) :: x(3, nn)
    integer, intent(in) :: nm
    character(len=*), intent(in) :: what
    real(wp) :: mb, pb(3), ieb, keb, ma, pa(3), iea, kea, dev(6), scale(6)
    integer :: q
    call hydro_totals(g, h, halo_t(), mb, pb, ieb, keb)
    call remap_euler_step(g, h, mx, nm, bc, x, par, st, err)
    call check(.not. allocated(err) .and. st%change_known, what//': the remap runs and reports its change')
    if (allocated(err)) deallocate(err)
    call hydro_totals(g, h, halo_t(), ma, pa, iea, kea)
    dev = [ma - mb, pa - pb, iea - ieb, kea - keb]
    scale = [mb, norm2(pb), norm2(pb), norm2(pb), ieb + keb, ieb + keb]
    do q = 1, 6
      dev(q) = abs(dev(q) - xsum_value(st%change(q)))/scale(q)
    end do
    write(*, '(a,i0,a,6es10.2)') what//': ', st%cells_remapped, ' cells remapped; |reported - totals'' change| '// &
      '/ total (mass, momentum, IE, KE): ', dev
    call check(all(dev <= 1.0e-15_wp), what//': the reported change is the totals'' change (to 1e-15)')
  end subroutine check_change

  !> The remap of state `kind` (nmat materials) from xa to the box grid xb
  !> with and without the lattice path: densities, energies, velocities
  !> and volume fractions within 1e-12 of each other (relative), and the
  !> lattice run's conservation to 1e-13.
  subroutine compare_lattice(kind, nmat)
    character(len=*), intent(in) :: kind
    integer, intent(in) :: nmat
    real(wp) :: rho0(nc), e0(nc), u0(3, nn), d
    real(wp), allocatable :: vf0(:)
    integer :: ist
    call setup(xa, kind)
    par%lattice = .false.
    call remap_euler_step(g, h, mx, nmat, bc, xb, par, st, err)
    rho0 = h%rho
    e0 = h%e
    u0 = h%u
    allocate(vf0(mx%nslot), stat=ist)
    call check(ist == 0, 'lattice path: memory')
    vf0 = mx%vf(1:mx%nslot)
    call setup(xa, kind)
    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    par%lattice = .true.
    call remap_euler_step(g, h, mx, nmat, bc, xb, par, st, err)
    par%lattice = .false.
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    call check(.not. allocated(err), 'lattice path ('//kind//') runs')
    d = max(maxval(abs(h%rho - rho0)/abs(rho0)), maxval(abs(h%e - e0)/abs(e0)), &
            maxval(abs(h%u - u0))/maxval(abs(u0)))
    if (size(vf0) > 0) d = max(d, maxval(abs(mx%vf(1:mx%nslot) - vf0)))
    write(*, '(a,a,a,es10.3,a,i0,a)') 'lattice path (', kind, '): largest relative difference from the per-cell ', d, &
      ' (', mx%nslot, ' mixed slots)'
    call check(d < 1e-12_wp .and. size(vf0) == mx%nslot, 'lattice path ('//kind//') equals the per-cell clipping')
    call check(abs(m1 - m0) <= 1e-13_wp*m0 .and. norm2(p1 - p0) <= 1e-13_wp*norm2(p0) .and. &
               abs(ie1 + ke1 - ie0 - ke0) <= 1e-13_wp*(ie0 + ke0), 'lattice path ('//kind//'): conservation to 1e-13')
  end subroutine compare_lattice

  !> A tetrahedron across several half-cells of a graded lattice, cut by
  !> a plane first: its parts add up to the clipped tetrahedron's volume
  !> and first moment (the whole tetrahedron's where the plane misses it),
  !> and each part's centroid lies in its half-cell.
  subroutine test_lattice_tet()
    type(lattice_t) :: lt
    type(grid_t) :: gl
    real(wp) :: t(3, 4), oo(3), v, m(3), cen(3), vt
    real(wp), allocatable :: acc(:, :)
    integer(i8), allocatable :: code(:)
    integer :: n, e, q(3), i, j, k, d
    logical :: inside
    call grid_init_box(gl, 5, 4, 3, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
    ! grade it: x planes at (i/5)^1.3, y at (j/4)^0.8
    do k = 0, 3
      do j = 0, 4
        do i = 0, 5
          gl%x(1, gl%node(i, j, k)) = (real(i, wp)/5.0_wp)**1.3_wp
          gl%x(2, gl%node(i, j, k)) = (real(j, wp)/4.0_wp)**0.8_wp
        end do
      end do
    end do
    call check(lattice_nodes(gl, gl%x), 'a graded box grid is a lattice')
    call lattice_build(gl, gl%x, lt)
    t = reshape([0.12_wp, 0.1_wp, 0.2_wp, 0.85_wp, 0.3_wp, 0.15_wp, 0.4_wp, 0.9_wp, 0.3_wp, 0.3_wp, 0.4_wp, 0.95_wp], &
                [3, 4])
    oo = [0.4_wp, 0.5_wp, 0.45_wp]
    do i = 1, 4
      t(:, i) = t(:, i) - oo
    end do
    vt = abs(det3(t(:, 2) - t(:, 1), t(:, 3) - t(:, 1), t(:, 4) - t(:, 1)))/6.0_wp
    code = [(0_i8, i = 1, 4)]
    acc = reshape([(0.0_wp, i = 1, 16)], [4, 4])
    n = 0
    call lattice_tet(lt, oo, [2, 2, 2], t, reshape([real(wp) ::], [3, 0]), [real(wp) ::], 1.0_wp, 0, n, code, acc)
    v = sum(acc(1, 1:n))
    m = sum(acc(2:4, 1:n), 2)
    write(*, '(a,i0,a,2es10.2)') 'lattice tet: ', n, ' half-cells; volume and moment errors ', abs(v - vt)/vt, &
      maxval(abs(m - vt*sum(t, 2)/4.0_wp))/vt
    call check(n > 8 .and. abs(v - vt) <= 1e-14_wp*vt .and. maxval(abs(m - vt*sum(t, 2)/4.0_wp)) <= 1e-14_wp*vt, &
               'lattice tet: the parts add up to the tetrahedron')
    inside = .true.
    do e = 1, n
      q = int([mod(code(e), int(lt%nq(1), i8)), mod(code(e)/lt%nq(1), int(lt%nq(2), i8)), code(e)/(lt%nq(1)*lt%nq(2))])
      cen = acc(2:4, e)/acc(1, e) + oo
      do d = 1, 3
        inside = inside .and. cen(d) >= lt%plane(q(d) + 1, d) .and. cen(d) <= lt%plane(q(d) + 2, d)
      end do
    end do
    call check(inside, 'lattice tet: each part in its half-cell')
    ! cut by the plane x + y = 0.1 about oo (keep x + y <= 0.1): the parts
    ! add up to what a clip of the whole gives
    n = 0
    call lattice_tet(lt, oo, [2, 2, 2], t, reshape([1.0_wp, 1.0_wp, 0.0_wp], [3, 1]), [0.1_wp], -1.0_wp, 0, n, code, &
                     acc)
    call clipped_tet(t, [1.0_wp, 1.0_wp, 0.0_wp], 0.1_wp, v, m)
    call check(n > 0 .and. abs(sum(acc(1, 1:n)) + v) <= 1e-14_wp*vt .and. &
               maxval(abs(sum(acc(2:4, 1:n), 2) + m)) <= 1e-14_wp*vt, 'lattice tet: cut by a plane, with its sign')
  end subroutine test_lattice_tet

  pure real(wp) function det3(a, b, c)
    real(wp), intent(in) :: a(3), b(3), c(3)
    det3 = a(1)*(b(2)*c(3) - b(3)*c(2)) - a(2)*(b(1)*c(3) - b(3)*c(1)) + a(3)*(b(1)*c(2) - b(2)*c(1))
  end function det3

  !> Volume and first moment of tetrahedron t where n.x <= d.
  subroutine clipped_tet(t, n_, d_, v, m)
    use geometry_polyhedron, only: poly_t, poly_set_tet, poly_clip, poly_first_moments
    real(wp), intent(in) :: t(3, 4), n_(3), d_
    real(wp), intent(out) :: v, m(3)
    type(poly_t) :: pp
    call poly_set_tet(pp, t)
    call poly_clip(pp, n_, d_)
    call poly_first_moments(pp, v, m)
  end subroutine clipped_tet

  !> The swept-face path: a translated triangle against its closed form;
  !> between two grids moved by up to 0.05 of a cell from the box (the path
  !> taken), conservation to round-off, the fragments adding up to every new
  !> cell and every old cell giving away its volume (the closed surfaces of
  !> swept triangles), a uniform state and a linear density kept exactly;
  !> random densities and energies under a uniform velocity: each new cell's
  !> density and specific energy within the bounds of its old 3 x 3 x 3
  !> neighbourhood (where every region it takes from lies); and what
  !> blocks the path (a node moved 0.4 of a cell, two materials).
  subroutine test_swept()
    real(wp) :: p(3, 3), q(3, 3), dv(3), v, m(3), area(3), xs(3, nn), xt(3, nn), lo(nc), hi(nc), elo(nc), ehi(nc), &
                emax, vol(nc), cen(3, nc)
    type(rng_t) :: rng
    integer :: cc, i0, j0, k0, oi, oj, ok_, nb
    logical :: inb

    p = reshape([0.1_wp, 0.2_wp, 0.3_wp, 1.1_wp, 0.4_wp, 0.2_wp, 0.3_wp, 0.9_wp, 0.5_wp], [3, 3])
    dv = [0.05_wp, -0.02_wp, 0.07_wp]
    q = p + spread(dv, 2, 3)
    call swept_triangle(p(:, 1), p(:, 2), p(:, 3), q(:, 1), q(:, 2), q(:, 3), v, m)
    area = 0.5_wp*[(p(2, 2) - p(2, 1))*(p(3, 3) - p(3, 1)) - (p(3, 2) - p(3, 1))*(p(2, 3) - p(2, 1)), &
                   (p(3, 2) - p(3, 1))*(p(1, 3) - p(1, 1)) - (p(1, 2) - p(1, 1))*(p(3, 3) - p(3, 1)), &
                   (p(1, 2) - p(1, 1))*(p(2, 3) - p(2, 1)) - (p(2, 2) - p(2, 1))*(p(1, 3) - p(1, 1))]
    call check(abs(v - dot_product(area, dv)) <= 1e-15_wp .and. &
               maxval(abs(m - v*(sum(p, 2)/3.0_wp + 0.5_wp*dv))) <= 1e-15_wp, &
               'swept triangle: a translation sweeps area.d, centroid at the mid position')

    call make_grid(xs, 31, 0.05_wp)
    call make_grid(xt, 37, 0.05_wp)
    call cell_moments(ni, nj, nk, xt, vol, cen)
    par%swept = .true.
    call setup(xs, 'linear')
    call check(remap_swept_blockers(g, h, bc, xt, par%swept_max, .false.) == 0, 'swept: no cell blocks a 0.05-cell move')
    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    call remap_euler_step(g, h, mx, 1, bc, xt, par, st, err)
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    write(*, '(a,2es10.2,a,3es10.2)') 'swept: volume and old-cell defects ', st%volume_defect, st%given_defect, &
      '; relative change of mass, momentum, energy ', abs(m1 - m0)/m0, norm2(p1 - p0)/norm2(p0), &
      abs(ie1 + ke1 - ie0 - ke0)/(ie0 + ke0)
    call check(.not. allocated(err) .and. st%cells_swept == nc, 'swept: every cell by its swept faces')
    call check(st%volume_defect < 1e-13_wp .and. st%given_defect < 1e-13_wp, &
               'swept: fragments add up to each new cell, each old cell gives its volume (1e-13)')
    call check(abs(m1 - m0) <= 1e-13_wp*m0 .and. norm2(p1 - p0) <= 1e-13_wp*norm2(p0) .and. &
               abs(ie1 + ke1 - ie0 - ke0) <= 1e-13_wp*(ie0 + ke0), 'swept: conservation to 1e-13')
    emax = 0.0_wp
    do cc = 1, nc
      if (deep(cc)) emax = max(emax, abs(h%rho(cc) - (lin(1) + dot_product(lin(2:4), cen(:, cc)))))
    end do
    call check(emax < 1e-12_wp, 'swept: linear density reproduced exactly away from the boundary')

    call setup(xs, 'constant')
    call remap_euler_step(g, h, mx, 1, bc, xt, par, st, err)
    emax = 0.0_wp
    do nb = 1, nn
      emax = max(emax, maxval(abs(h%u(:, nb) - [0.7_wp, -0.2_wp, 0.1_wp])))
    end do
    call check(.not. allocated(err) .and. maxval(abs(h%rho - 2.0_wp)) < 1e-13_wp .and. &
               maxval(abs(h%e - 3.0_wp)) < 1e-13_wp .and. emax < 1e-14_wp, 'swept: uniform state kept')

    ! random densities and energies, uniform velocity
    call setup(xs, 'constant')
    call rng_seed(rng, 5)
    do cc = 1, nc
      h%rho(cc) = 1.0_wp + 9.0_wp*rng_uniform(rng)
      h%e(cc) = 1.0_wp + 4.0_wp*rng_uniform(rng)
      h%mass(cc) = h%rho(cc)*h%vol(cc)
    end do
    call hydro_subcell_masses(g, xs, h%rho, h%mnode, h%mcorner)
    do cc = 1, nc
      call g%cell_ijk(cc, i0, j0, k0)
      lo(cc) = huge(1.0_wp)
      hi(cc) = -huge(1.0_wp)
      elo(cc) = huge(1.0_wp)
      ehi(cc) = -huge(1.0_wp)
      do ok_ = max(1, k0 - 1), min(nk, k0 + 1)
        do oj = max(1, j0 - 1), min(nj, j0 + 1)
          do oi = max(1, i0 - 1), min(ni, i0 + 1)
            nb = g%cell(oi, oj, ok_)
            lo(cc) = min(lo(cc), h%rho(nb))
            hi(cc) = max(hi(cc), h%rho(nb))
            elo(cc) = min(elo(cc), h%e(nb))
            ehi(cc) = max(ehi(cc), h%e(nb))
          end do
        end do
      end do
    end do
    call remap_euler_step(g, h, mx, 1, bc, xt, par, st, err)
    inb = .true.
    do cc = 1, nc
      inb = inb .and. h%rho(cc) >= lo(cc)*(1.0_wp - 1e-12_wp) .and. h%rho(cc) <= hi(cc)*(1.0_wp + 1e-12_wp) .and. &
            h%e(cc) >= elo(cc)*(1.0_wp - 1e-12_wp) .and. h%e(cc) <= ehi(cc)*(1.0_wp + 1e-12_wp)
    end do
    call check(.not. allocated(err) .and. st%cells_swept == nc .and. inb, &
               'swept: new densities and energies within the old neighbourhood''s bounds')

    ! what blocks the path
    xt(:, node(3, 3, 2)) = xs(:, node(3, 3, 2)) + [0.08_wp, 0.0_wp, 0.0_wp]
    call setup(xs, 'constant')
    nb = remap_swept_blockers(g, h, bc, xt, par%swept_max, .false.)
    call check(nb == 8, 'swept: a node moved 0.4 of a cell blocks its eight cells')

    ! two materials split by a plane: the regions swept from mixed cells are
    ! shared by their MoF planes (the plane itself, exactly reconstructed).
    ! Measured: 3.4e-14 until twisted prisms' parts against their region's
    ! sign were dropped (`swept_split`: a material that is not there, given
    ! away; on a TNT charge at 32^3 it left negative slivers), 4.9e-4 since
    ! (slivers merged at vf_min only: no material's mass moves to another)
    par%swept_vf_min = par%vf_min
    call make_grid(xt, 37, 0.05_wp)
    call setup(xs, 'plane')
    call check(remap_swept_blockers(g, h, bc, xt, par%swept_max, .false.) > 0, &
               'swept: mixed cells and their neighbours block it (swept_mixed off)')
    call check(remap_swept_blockers(g, h, bc, xt, par%swept_max, .true.) == 0, 'swept: not with swept_mixed')
    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    call material_masses(ma0, mb0)
    call remap_euler_step(g, h, mx, 2, bc, xt, par, st, err)
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    call material_masses(ma1, mb1)
    emax = plane_error()
    write(*, '(a,2es10.2,a,es10.3)') 'swept, plane: volume and old-cell defects ', st%volume_defect, st%given_defect, &
      '; largest volume-fraction error ', emax
    call check(.not. allocated(err) .and. st%cells_swept == nc, 'swept, plane: every cell by its swept faces')
    call check(abs(ma1 - ma0) <= 1e-13_wp*ma0 .and. abs(mb1 - mb0) <= 1e-13_wp*mb0 .and. &
               abs(ie1 + ke1 - ie0 - ke0) <= 1e-13_wp*(ie0 + ke0), 'swept, plane: each material''s mass and the '// &
               'total energy conserved to 1e-13')
    call check(st%volume_defect < 1e-13_wp .and. st%given_defect < 1e-13_wp, 'swept, plane: defects below 1e-13')
    call check(emax < 1e-3_wp, 'swept, plane: new volume fractions within 1e-3 of the plane''s cuts')

    ! mixed cells whose MoF planes disagree from cell to cell (the material
    ! centroids moved at random: a rough interface): regions swept out of a
    ! mixed cell are shared by its planes past it. Before the mixed cells'
    ! budgets (`swept_budgets`) this broke a material's bounds (a thin
    ! layer gave more than it held) and the step fell back to intersection;
    ! now the swept step must keep them, and conserve each material's mass
    ! and the total energy
    ! (slivers merged at vf_min only, as above: the default swept_vf_min's
    ! merges are checked below)
    call make_grid(xs, 31, 0.2_wp)
    call make_grid(xt, 37, 0.2_wp)
    par%swept = .true.
    call setup_rough(xs)
    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    call material_masses(ma0, mb0)
    call remap_euler_step(g, h, mx, 2, bc, xt, par, st, err)
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    call material_masses(ma1, mb1)
    write(*, '(a,i0,a,i0,a)') 'swept, rough interface: ', st%swept_unbounded, ' cells broke a bound, ', &
      st%slivers_merged, ' slivers merged'
    call check(.not. allocated(err) .and. st%swept_unbounded == 0 .and. st%cells_swept == nc, &
               'swept, rough interface: every cell by its swept faces, within the bounds')
    call check(abs(ma1 - ma0) <= 1e-13_wp*ma0 .and. abs(mb1 - mb0) <= 1e-13_wp*mb0 .and. &
               abs(ie1 + ke1 - ie0 - ke0) <= 1e-13_wp*(ie0 + ke0), 'swept, rough interface: each material''s '// &
               'mass and the total energy conserved to 1e-13')
    ! the same with the default swept_vf_min: the slivers below it merged
    ! into their cells' other material, the total mass and energy conserved
    par%swept_vf_min = dflt%swept_vf_min
    call setup_rough(xs)
    call remap_euler_step(g, h, mx, 2, bc, xt, par, st, err)
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    call material_masses(ma1, mb1)
    write(*, '(a,i0,a,2es10.2)') 'swept, rough interface, default swept_vf_min: ', st%slivers_merged, &
      ' merged; material mass changes ', (ma1 - ma0)/ma0, (mb1 - mb0)/mb0
    call check(.not. allocated(err) .and. st%swept_unbounded == 0 .and. abs(m1 - m0) <= 1e-13_wp*m0 .and. &
               abs(ie1 + ke1 - ie0 - ke0) <= 1e-13_wp*(ie0 + ke0), 'swept, rough interface, slivers merged: '// &
               'the total mass and energy conserved to 1e-13')
    par%swept = .false.
  end subroutine test_swept

  !> The first part of the way of an Euler step (`remap_part_target`,
  !> &rezone swept_parts) on the box grid of spacing 0.2: every interior node
  !> moves by 0.005, one node by 0.13 in x (towards its neighbour, which it
  !> comes within 0.07 of). With swept_max = 0.25 a node may move 0.05:
  !> all but that node arrive in the first part. Called again from the grid
  !> each part leaves, it moves only that node, each time by a quarter of
  !> the shortest edge around it as it is then (0.05, 0.0375, 0.028, then
  !> the last 0.014: four parts). Every part passes the swept path's own
  !> distance test, and no part folds a cell. A window's call (own: the
  !> cells its block owns, here none) limits the same nodes but leaves
  !> arrived and the fraction r to the blocks that own them.
  subroutine test_parts()
    real(wp) :: x0(3, nn), xt(3, nn), r, r1
    real(wp), allocatable :: xk(:, :), xo(:, :)
    integer, allocatable :: moved(:)
    integer :: i, j, k, nparts, nblock, nmove(8)
    logical :: arrived, first_ok, folded, own_ok
    call make_grid(x0, 1, 0.0_wp)
    call setup(x0, 'constant')
    xt = x0
    do k = 1, nk - 1
      do j = 1, nj - 1
        do i = 1, ni - 1
          xt(:, node(i, j, k)) = x0(:, node(i, j, k)) + 0.005_wp*[1.0_wp, -1.0_wp, 0.5_wp]
        end do
      end do
    end do
    xt(1, node(3, 2, 2)) = x0(1, node(3, 2, 2)) + 0.13_wp
    nparts = 0
    first_ok = .true.
    nblock = 0
    nmove = 0
    arrived = .false.
    ! (the whole way: the eight cells around the far node block it)
    nblock = remap_swept_blockers(g, h, bc, xt, 0.25_wp, .false., moved=moved)
    call check(nblock == 8, 'parts of the way: the whole way blocks the swept path')
    nblock = 0
    folded = .false.
    own_ok = .true.
    r1 = 0.0_wp
    do while (.not. arrived .and. nparts < 8)
      ! (the cells still to move)
      if (nparts > 0) i = remap_swept_blockers(g, h, bc, xt, 0.25_wp, .false., moved=moved)
      call remap_part_target(g, xt, 0.25_wp, moved, xo, arrived, r, err, own=[(.false., i = 1, g%ncell)])
      own_ok = own_ok .and. arrived .and. abs(r - 1.0_wp) <= 0.0_wp
      call remap_part_target(g, xt, 0.25_wp, moved, xk, arrived, r, err)
      if (allocated(err)) exit
      own_ok = own_ok .and. all(abs(xo - xk) <= 0.0_wp)
      if (.not. arrived) folded = folded .or. remap_part_folded(g, moved, xk)
      nparts = nparts + 1
      if (nparts == 1) r1 = r
      ! (the nodes that did not arrive)
      nmove(nparts) = count(any(abs(xk - xt) > 0.0_wp, 1))
      nblock = nblock + remap_swept_blockers(g, h, bc, xk, 0.25_wp, .false.)
      if (nparts == 1) first_ok = nmove(1) == 1 .and. any(abs(xk(:, node(3, 2, 2)) - xt(:, node(3, 2, 2))) > 0.0_wp)
      g%x = xk
    end do
    write(*, '(a,i0,a,8(1x,i0))') 'parts of the way: ', nparts, ' parts; nodes still to go after each:', &
      nmove(1:nparts)
    call check(.not. allocated(err) .and. arrived .and. nparts == 4, 'parts of the way: four parts')
    call check(first_ok, 'parts of the way: every node but the far one arrives in the first part')
    ! (the far node's first part: 0.05 of its way, 0.13 in x and the
    ! others' -0.005 and 0.0025 in y and z)
    call check(abs(r1 - 0.05_wp/norm2([0.13_wp, -0.005_wp, 0.0025_wp])) <= 1.0e-8_wp .and. .not. folded, &
               'parts of the way: the first part''s fraction 0.05 over the far node''s way, no cell folded')
    call check(own_ok, 'parts of the way: a window that owns none of the cells limits the same nodes, '// &
               'and leaves arrived and r to their owners')
    call check(nblock == 0, 'parts of the way: no part blocks the swept path')
    call check(all(abs(g%x - xt) <= 0.0_wp), 'parts of the way: the last part ends on the rezoned grid')
  end subroutine test_parts

  !> The 'plane' state on the grid x with each mixed cell's material
  !> centroids moved by up to a quarter of the cell at random (the same
  !> draws each call).
  subroutine setup_rough(x)
    real(wp), intent(in) :: x(3, nn)
    type(rng_t) :: rr
    integer :: kk, ss
    call setup(x, 'plane')
    call rng_seed(rr, 17)
    do kk = 1, mx%n
      do ss = mx%start(kk), mx%start(kk + 1) - 1
        mx%xi(:, ss) = mx%xi(:, ss) + 0.5_wp*[rng_uniform(rr), rng_uniform(rr), rng_uniform(rr)] - 0.25_wp
      end do
    end do
  end subroutine setup_rough

  integer function node(i, j, k)
    integer, intent(in) :: i, j, k
    node = 1 + i + (ni + 1)*(j + (nj + 1)*k)
  end function node

  !> Cell c is at least two cells from every boundary.
  logical function deep(c)
    integer, intent(in) :: c
    integer :: ci, cj, ck
    ci = 1 + mod(c - 1, ni); cj = 1 + mod((c - 1)/ni, nj); ck = 1 + (c - 1)/(ni*nj)
    deep = ci > 2 .and. ci < ni - 1 .and. cj > 2 .and. cj < nj - 1 .and. ck > 1 .and. ck < nk
  end function deep

  !> Cell c has no node within two index steps of node (3,3,2).
  logical function far(c)
    integer, intent(in) :: c
    integer :: ci, cj, ck
    ci = 1 + mod(c - 1, ni); cj = 1 + mod((c - 1)/ni, nj); ck = 1 + (c - 1)/(ni*nj)
    far = abs(ci - 3.5_wp) > 1.0_wp .or. abs(cj - 3.5_wp) > 1.0_wp .or. abs(ck - 2.5_wp) > 1.0_wp
  end function far

  !> Mass of material 1 (m1) and 2 (m2).
  subroutine material_masses(m1_, m2_)
    real(wp), intent(out) :: m1_, m2_
    integer :: cc, s
    m1_ = 0.0_wp
    m2_ = 0.0_wp
    do cc = 1, nc
      if (h%mat(cc) == 1) m1_ = m1_ + h%mass(cc)
      if (h%mat(cc) == 2) m2_ = m2_ + h%mass(cc)
    end do
    do s = 1, mx%nslot
      if (mx%mat(s) == 1) m1_ = m1_ + mx%mass(s)
      if (mx%mat(s) == 2) m2_ = m2_ + mx%mass(s)
    end do
  end subroutine material_masses

  !> Largest |vf_1 - exact cut of the plane| over the new cells.
  real(wp) function plane_error() result(e)
    real(wp) :: xn(3, 8), v, cen(3), f
    integer :: cc, s, k
    e = 0.0_wp
    do cc = 1, nc
      call g%gather(cc, g%x, xn)
      call mof_cut_volume(xn, plane_n, plane_d, v, cen)
      v = v/hex_volume(xn)
      f = merge(1.0_wp, 0.0_wp, h%mat(cc) == 1)
      if (h%mat(cc) <= 0) then
        k = -h%mat(cc)
        do s = mx%start(k), mx%start(k + 1) - 1
          if (mx%mat(s) == 1) f = mx%vf(s)
        end do
      end if
      e = max(e, abs(f - v))
    end do
  end function plane_error

  !> The state on the grid x: 'constant' (rho 2, e 3, u uniform), 'linear'
  !> (rho and u linear in x, e 3) or 'plane' (material 1 below the plane,
  !> density 2, material 2 above it, density 0.5, mixed cells cut exactly).
  subroutine setup(x, kind)
    real(wp), intent(in) :: x(3, nn)
    character(len=*), intent(in) :: kind
    real(wp) :: xn(3, 8), v1, c1(3), vol(nc), cen(3, nc), vcell
    integer :: cc, nmix, s

    h = hydro_t()
    mx = mixed_t()

    call grid_init_box(g, ni, nj, nk, [0.0_wp, 0.0_wp, 0.0_wp], [1.2_wp, 1.0_wp, 0.8_wp], err)
    g%x = x
    call hydro_allocate(h, nc, nn, err)
    call cell_moments(ni, nj, nk, x, vol, cen)
    h%mat = 1
    h%e = 3.0_wp
    nmix = 0
    do cc = 1, nc
      call g%gather(cc, x, xn)
      h%vol(cc) = hex_volume(xn)
      select case (kind)
      case ('linear')
        h%rho(cc) = lin(1) + dot_product(lin(2:4), cen(:, cc))
      case ('plane')
        call mof_cut_volume(xn, plane_n, plane_d, v1, c1)
        if (v1 > 1e-12_wp*h%vol(cc) .and. v1 < (1.0_wp - 1e-12_wp)*h%vol(cc)) then
          nmix = nmix + 1
          h%mat(cc) = -nmix
        else
          h%mat(cc) = merge(1, 2, v1 > 0.5_wp*h%vol(cc))
        end if
        h%rho(cc) = merge(2.0_wp, 0.5_wp, h%mat(cc) == 1)
      case default
        h%rho(cc) = 2.0_wp
      end select
      h%mass(cc) = h%rho(cc)*vol(cc)
    end do
    call mixed_allocate(mx, nmix, 2*nmix, err)
    if (kind == 'plane') then
      nmix = 0
      do cc = 1, nc
        if (h%mat(cc) > 0) cycle
        call g%gather(cc, x, xn)
        vcell = h%vol(cc)
        call mof_cut_volume(xn, plane_n, plane_d, v1, c1)
        nmix = nmix + 1
        mx%cell(nmix) = cc
        mx%start(nmix + 1) = mx%start(nmix) + 2
        s = mx%start(nmix)
        mx%mat(s:s + 1) = [1, 2]
        mx%vf(s:s + 1) = [v1/vcell, 1.0_wp - v1/vcell]
        mx%rho(s:s + 1) = [2.0_wp, 0.5_wp]
        mx%mass(s:s + 1) = mx%rho(s:s + 1)*mx%vf(s:s + 1)*vcell
        mx%e(s:s + 1) = [3.0_wp, 5.0_wp]
        mx%xi(:, s) = hex_natural(xn, c1)
        mx%xi(:, s + 1) = hex_natural(xn, (cen(:, cc)*vol(cc) - c1*v1)/(vol(cc) - v1))
        h%mass(cc) = sum(mx%mass(s:s + 1))
        h%rho(cc) = h%mass(cc)/vcell
        h%e(cc) = dot_product(mx%mass(s:s + 1), mx%e(s:s + 1))/h%mass(cc)
      end do
      where (h%mat == 2) h%e = 5.0_wp
    end if
    call hydro_subcell_masses(g, x, h%rho, h%mnode, h%mcorner)
    do n = 1, nn
      if (kind == 'linear') then
        h%u(:, n) = [0.3_wp*x(1, n) - 0.1_wp, 0.2_wp*x(2, n) + 0.1_wp*x(3, n), 0.5_wp - 0.4_wp*x(1, n)]
      else if (kind == 'curved') then
        h%u(:, n) = [x(1, n)**2, x(2, n)*x(3, n), sin(3.0_wp*x(1, n))]
      else
        h%u(:, n) = [0.7_wp, -0.2_wp, 0.1_wp]
      end if
    end do
  end subroutine setup

  !> A grid on [0,1.2]x[0,1]x[0,0.8] with interior nodes moved randomly by up
  !> to amp of a cell (boundary nodes fixed, so both grids cover one box).
  subroutine make_grid(x, seed, amp)
    real(wp), intent(out) :: x(3, nn)
    integer, intent(in) :: seed
    real(wp), intent(in) :: amp
    type(rng_t) :: rng
    integer :: i, j, kk, d
    real(wp) :: hh(3)
    hh = [1.2_wp/ni, 1.0_wp/nj, 0.8_wp/nk]
    call rng_seed(rng, seed)
    do kk = 0, nk
      do j = 0, nj
        do i = 0, ni
          n = node(i, j, kk)
          x(:, n) = hh*real([i, j, kk], wp)
          if (i > 0 .and. i < ni .and. j > 0 .and. j < nj .and. kk > 0 .and. kk < nk) then
            do d = 1, 3
              x(d, n) = x(d, n) + amp*hh(d)*(2.0_wp*rng_uniform(rng) - 1.0_wp)
            end do
          end if
        end do
      end do
    end do
  end subroutine make_grid
end program test_remap_euler
