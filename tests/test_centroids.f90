!> Unit tests of the mixed cells' material centroids and time step:
!>  - initial fractions and centroids of region shapes in a cell
!>    (`geometry_shapes`) against exact values: a box cut and an oblique
!>    half-space corner in a sheared cell (exact to round-off), a sphere
!>    octant (the tangent-plane error model);
!>  - centroids kept consistent through Lagrangian steps whose closure
!>    changes the volume fractions (`lagrange_centroids`): the remap's MoF
!>    reproduces the refreshed centroids, not the stale ones, with no
!>    iteration from the carried planes, and the fits after a remap start
!>    from the planes remembered by cell and material;
!>  - the time step of a mixed cell holding a soft material in a stiff one
!>    (`mixed_volume_gain`, `lagrange_strain_rates`): the soft material
!>    changes by dv_max per step, where the cell's own limit would crush it.
program test_centroids
  use base_kinds, only: wp
  use base_errors, only: error_t
  use test_assert, only: check, check_close, check_summary
  use eos_factory, only: eos_params_t, eos_create
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_volume, hex_trilinear, hex_natural
  use mesh_boundary, only: bc_t, bc_init, BC_WALL
  use material_table, only: material_t, material_index_cells, material_eval_eos
  use material_mixed, only: mixed_t, mixed_allocate, mixed_cell_state, mixed_save_step_start, mixed_split, &
                            mixed_volume_gain
  use hydro_state, only: hydro_t, hydro_params_t, hydro_allocate, hydro_subcell_masses
  use lagrange_forces, only: lagrange_strain_rates
  use lagrange_integrator, only: lagrange_step
  use lagrange_centroids, only: centroid_stats_t, centroids_fit_planes, centroids_refresh, plane_normals, &
                                centroids_remember, plane_memory_t
  use geometry_mof, only: mof_reconstruct_nested, mof_plane_for_volume, mof_cut_volume
  use geometry_shapes, only: shape_t, shapes_cell_moments, SHAPE_ALL, SHAPE_BOX, SHAPE_SPHERE, SHAPE_HALF_SPACE
  implicit none

  real(wp), parameter :: pi = 4.0_wp*atan(1.0_wp)

  call initial_box_cut()
  call initial_half_space_corner()
  call initial_sphere_octant()
  call lagrangian_consistency()
  call dt_soft_material()
  call check_summary('test_centroids')

contains

  !> Nodes of the parallelepiped x0 + A xi', xi' in [0,1]^3 (a = 1 + i + 2j + 4k).
  pure function parallelepiped(x0, a) result(xn)
    real(wp), intent(in) :: x0(3), a(3, 3)
    real(wp) :: xn(3, 8)
    integer :: k
    do k = 1, 8
      xn(:, k) = x0 + matmul(a, real([mod(k - 1, 2), mod((k - 1)/2, 2), (k - 1)/4], wp))
    end do
  end function parallelepiped

  !> A box region over a unit cube far from the origin: the part
  !> [0.3,1] x [0,0.6] x [0,1] (volume 0.42, centroid (0.65, 0.3, 0.5)).
  !> Planar boundaries in a box cell are clipped exactly at the top level:
  !> round-off only (1e-14 of the cell; the sums are of a few terms of size
  !> 1 relative to the cell's centre), at any depth.
  subroutine initial_box_cut()
    type(shape_t) :: sh(2)
    real(wp) :: xn(3, 8), off(3), vol(0:2), mom(3, 0:2), c(3), id(3, 3)
    integer :: depth, i
    off = [10.0_wp, 20.0_wp, 30.0_wp]
    id = 0.0_wp
    do i = 1, 3
      id(i, i) = 1.0_wp
    end do
    xn = parallelepiped(off, id)
    sh(1)%kind = SHAPE_ALL
    sh(2)%kind = SHAPE_BOX
    sh(2)%lo = off + [0.3_wp, -1.0_wp, -1.0_wp]
    sh(2)%hi = off + [2.0_wp, 0.6_wp, 2.0_wp]
    do depth = 0, 4, 4
      call shapes_cell_moments(xn, sh, depth, vol, mom)
      c = off + 0.5_wp + mom(:, 2)/vol(2)
      call check_close('box cut: volume (depth '//achar(48 + depth)//')', vol(2), 0.42_wp, 1.0e-14_wp)
      call check_close('box cut: rest volume', vol(1), 0.58_wp, 1.0e-14_wp)
      call check_close('box cut: nothing uncovered', vol(0), 0.0_wp, 0.0_wp)
      call check_close('box cut: centroid error', norm2(c - (off + [0.65_wp, 0.3_wp, 0.5_wp])), 0.0_wp, 1.0e-14_wp)
    end do
  end subroutine initial_box_cut

  !> An oblique half-space cutting a corner tetrahedron off a sheared
  !> parallelepiped x = x0 + A xi': {w.xi' <= t} with intercepts
  !> t/w = 0.6, 0.3, 0.4, volume det(A) t^3/(6 w1 w2 w3) and centroid
  !> x0 + A (t/(4 w)). Affine cell, planar boundary: exact to round-off.
  subroutine initial_half_space_corner()
    type(shape_t) :: sh(2)
    real(wp) :: xn(3, 8), x0(3), a(3, 3), w(3), t, y(3), vol(0:2), mom(3, 0:2), xc(3), vex, cex(3), deta
    x0 = [1.0_wp, -2.0_wp, 0.5_wp]
    a = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.3_wp, 1.0_wp, 0.0_wp, 0.1_wp, 0.2_wp, 1.0_wp], [3, 3])
    xn = parallelepiped(x0, a)
    w = [1.0_wp, 2.0_wp, 1.5_wp]
    t = 0.6_wp
    ! physical normal A^-T w (A^T is lower triangular: forward substitution)
    y(1) = w(1)/a(1, 1)
    y(2) = (w(2) - a(1, 2)*y(1))/a(2, 2)
    y(3) = (w(3) - a(1, 3)*y(1) - a(2, 3)*y(2))/a(3, 3)
    sh(1)%kind = SHAPE_ALL
    sh(2)%kind = SHAPE_HALF_SPACE
    sh(2)%normal = -y
    sh(2)%center = x0 + matmul(a, [t/w(1), 0.0_wp, 0.0_wp])
    call shapes_cell_moments(xn, sh, 3, vol, mom)
    deta = a(1, 1)*a(2, 2)*a(3, 3)
    vex = deta*t**3/(6.0_wp*product(w))
    cex = x0 + matmul(a, t/(4.0_wp*w))
    xc = 0.125_wp*sum(xn, 2)
    call check_close('half-space corner: volume', vol(2), vex, 1.0e-14_wp)
    call check_close('half-space corner: cell volume', sum(vol), deta, 1.0e-14_wp)
    call check_close('half-space corner: centroid error', norm2(xc + mom(:, 2)/vol(2) - cex), 0.0_wp, 1.0e-14_wp)
  end subroutine initial_half_space_corner

  !> A sphere of radius r = 0.8 about a corner of the unit cube cell: the
  !> cell holds an eighth of the ball, volume pi r^3/6, centroid 3r/8 on
  !> each axis. At depth d the sphere is its tangent plane on leaves of
  !> hl = 2^-d, which hold the ball: the volume is too large by the mean
  !> sagitta hl^2/(12 r) over the surface pi r^2/2, a relative hl^2/(4 r^2)
  !> (3.8e-4 at d = 5), and the excess, a shell whose centroid is at r/2
  !> per axis against the ball's 3r/8, moves the centroid by that fraction
  !> of r/8 per axis (|dc| = sqrt(3) r/8 hl^2/(4 r^2) = 6.6e-5). Asserted:
  !> volume error in [0.5, 1.5] of the estimate and on the outside, centroid
  !> error below twice its estimate. For comparison the point sampling that
  !> this replaced (8^3 midpoints) is printed.
  subroutine initial_sphere_octant()
    type(shape_t) :: sh(2)
    real(wp) :: xn(3, 8), id(3, 3), vol(0:2), mom(3, 0:2), r, hl, vex, cex(3), est, c(3), p(3), vs, cs(3)
    integer :: i, j, k, depth
    character(len=120) :: line
    id = 0.0_wp
    do i = 1, 3
      id(i, i) = 1.0_wp
    end do
    xn = parallelepiped([0.0_wp, 0.0_wp, 0.0_wp], id)
    r = 0.8_wp
    sh(1)%kind = SHAPE_ALL
    sh(2)%kind = SHAPE_SPHERE
    sh(2)%center = 0.0_wp
    sh(2)%radius = r
    vex = pi*r**3/6.0_wp
    cex = 3.0_wp*r/8.0_wp
    do depth = 4, 5
      call shapes_cell_moments(xn, sh, depth, vol, mom)
      hl = 0.5_wp**depth
      est = hl**2/(4.0_wp*r**2)
      c = 0.5_wp + mom(:, 2)/vol(2)
      write(line, '("sphere octant, depth ",i0,": relative volume error / estimate")') depth
      call check_close(trim(line), (vol(2) - vex)/vex/est, 1.0_wp, 0.5_wp)
      call check(vol(2) >= vex, 'sphere octant: the tangent planes hold the ball')
      call check_close('sphere octant: centroid error', norm2(c - cex), 0.0_wp, 2.0_wp*sqrt(3.0_wp)*r/8.0_wp*est)
    end do
    ! the former point sampling, for the record
    vs = 0.0_wp
    cs = 0.0_wp
    do k = 1, 8
      do j = 1, 8
        do i = 1, 8
          p = (real([i, j, k], wp) - 0.5_wp)/8.0_wp
          if (sum(p**2) <= r**2) then
            vs = vs + 1.0_wp/512.0_wp
            cs = cs + p/512.0_wp
          end if
        end do
      end do
    end do
    write(*, '(a,es10.2,a,es10.2)') 'info  sphere octant, 8^3 point sampling: relative volume error ', &
      abs(vs - vex)/vex, ', centroid error ', norm2(cs/vs - cex)
  end subroutine initial_sphere_octant

  !> Two ideal gases in a 3^3 box of walls: the centre cell holds gas B
  !> (gamma 2, p = 4) below an oblique plane (30 % of the cell) and gas A
  !> (gamma 1.4, p = 1, the other cells too) above it. The closure expands B
  !> over 12 steps (from 30 % of the cell to 47 %). The remap's MoF (nested, slot order) is then given the
  !> fractions and (a) the centroids as the scene gave them, carried by the
  !> grid (what the code did before), (b) the centroids refreshed from the
  !> planes. (b) is reproduced by a plane to MoF's convergence (its turn
  !> tolerance 1e-8 rad leaves ~1e-16; hex_natural's round trip 1e-14 of the
  !> cell): bound 1e-9 of the cell size, and the fit must not be capped;
  !> (a) must miss by more than 1e-3 (else the test shows nothing).
  subroutine lagrangian_consistency()
    type(grid_t) :: g
    type(hydro_t) :: h
    type(bc_t) :: bc
    type(material_t) :: mats(2)
    type(mixed_t) :: mx
    type(hydro_params_t) :: par
    type(error_t), allocatable :: err
    type(eos_params_t) :: ep
    type(centroid_stats_t) :: cst
    real(wp) :: xn(3, 8), nrm(3), d, va, ca(3), ccell(3), v, vfb0, rho(2), pr(2), gam(2), dt, work
    real(wp) :: xi0(3, 2), cref(3, 2), pn(3, 2), pd(2), errc(2), e_stale, e_fresh, guess(3, 2), det, &
                pn2(3, 2), pd2(2), plane0(4, 2)
    integer :: c, k, its(2), bad, step
    logical :: ok
    type(plane_memory_t) :: mem

    call grid_init_box(g, 3, 3, 3, [0.0_wp, 0.0_wp, 0.0_wp], [3.0_wp, 3.0_wp, 3.0_wp], err)
    call check(.not. allocated(err), 'grid_init_box')
    call hydro_allocate(h, g%ncell, g%nnode, err)
    gam = [1.4_wp, 2.0_wp]
    rho = [1.0_wp, 0.5_wp]
    pr = [1.0_wp, 4.0_wp]
    do k = 1, 2
      ep%gamma = gam(k)
      mats(k)%name = achar(64 + k)
      call eos_create('ideal_gas', ep, mats(k)%eos, err)
    end do
    h%mat = 1
    do c = 1, g%ncell
      call g%gather(c, g%x, xn)
      h%vol(c) = hex_volume(xn)
      h%rho(c) = rho(1)
      h%e(c) = pr(1)/((gam(1) - 1.0_wp)*rho(1))
      h%mass(c) = h%rho(c)*h%vol(c)
    end do
    ! the centre cell: A is {-nrm.x <= d} with 70 % of the cell (slot 1,
    ! first in the nested dissection), B the rest
    c = g%cell(2, 2, 2)
    call g%gather(c, g%x, xn)
    nrm = [1.0_wp, 0.5_wp, 0.3_wp]
    vfb0 = 0.3_wp
    call mof_plane_for_volume(xn, -nrm, 1.0_wp - vfb0, d, ok)
    call check(ok, 'plane for the initial fractions')
    call mof_cut_volume(xn, -nrm, d, va, ca)
    v = hex_volume(xn)
    ccell = 0.125_wp*sum(xn, 2)
    call mixed_allocate(mx, 1, 2, err)
    mx%cell(1) = c
    mx%start = [1, 3]
    mx%mat = [1, 2]
    mx%vf = [1.0_wp - vfb0, vfb0]
    mx%rho = rho
    mx%mass = rho*mx%vf*v
    mx%e = pr/((gam - 1.0_wp)*rho)
    mx%xi(:, 1) = hex_natural(xn, ca)
    mx%xi(:, 2) = hex_natural(xn, (v*ccell - va*ca)/(v - va))
    h%mat(c) = -1
    h%mass(c) = sum(mx%mass)
    h%rho(c) = h%mass(c)/v
    h%e(c) = dot_product(mx%mass, mx%e)/h%mass(c)
    call material_index_cells(mats, h%mat, mx, err)
    call hydro_subcell_masses(g, g%x, h%rho, h%mnode, h%mcorner)
    call material_eval_eos(mats, h%rho, h%e, h%p, h%cs, mx)
    call mixed_cell_state(mx, h%p, h%cs)
    h%u = 0.0_wp
    bc%kind = BC_WALL
    call bc_init(bc, g, err)
    call check(.not. allocated(err), 'setup')

    call centroids_fit_planes(g, mx, cst)
    call check(cst%fitted == 1 .and. cst%capped == 0, 'the planes of the exact initial state are fitted')
    call check_close('fit of the initial plane: centroid error / size', cst%err_max, 0.0_wp, 1.0e-9_wp)
    xi0 = mx%xi
    do step = 1, 12
      dt = huge(1.0_wp)
      call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad)
      call check(bad == 0, 'step')
    end do
    write(*, '(a,f7.4,a,f7.4)') 'info  the closure took the fraction of B from ', vfb0, ' to ', mx%vf(2)
    call check(mx%vf(2) - vfb0 > 0.05_wp, 'the closure changed the fractions (else nothing is tested)')

    call g%gather(c, g%x, xn)
    ! (a) the centroids carried by the grid, not by the closure
    cref(:, 1) = hex_trilinear(xn, xi0(:, 1))
    cref(:, 2) = hex_trilinear(xn, xi0(:, 2))
    call mof_reconstruct_nested(xn, mx%vf/sum(mx%vf), cref, pn, pd, errc, its, ok)
    e_stale = maxval(errc)/hex_volume(xn)**(1.0_wp/3.0_wp)
    call check(e_stale > 1.0e-3_wp, 'stale centroids are not reproduced by a plane')
    write(*, '(a,es10.2,a,i0)') 'info  stale centroids: MoF centroid error / size ', e_stale, ', iterations ', sum(its)
    ! (b) refreshed from the planes
    call centroids_refresh(g, mx, cst)
    call check(cst%moved == 1 .and. cst%failed == 0, 'the centroids were refreshed')
    cref(:, 1) = hex_trilinear(xn, mx%xi(:, 1))
    cref(:, 2) = hex_trilinear(xn, mx%xi(:, 2))
    call mof_reconstruct_nested(xn, mx%vf/sum(mx%vf), cref, pn, pd, errc, its, ok)
    e_fresh = maxval(errc)/hex_volume(xn)**(1.0_wp/3.0_wp)
    call check(ok, 'MoF converges on the refreshed centroids (not capped)')
    call check_close('refreshed centroids: MoF centroid error / size', e_fresh, 0.0_wp, 1.0e-9_wp)
    write(*, '(a,i0)') 'info  refreshed centroids: MoF iterations ', sum(its)
    ! (c) the remap's MoF starts from the carried planes (`plane_normals`):
    ! they cut the refreshed centroids, so no iteration, the same plane
    call plane_normals(xn, mx%plane, guess, det)
    call check(det > 0.0_wp, 'plane_normals: the cell''s axes')
    call mof_reconstruct_nested(xn, mx%vf/sum(mx%vf), cref, pn2, pd2, errc, its, ok, guess=guess)
    call check(ok .and. sum(its) == 0, 'MoF from the carried planes: no iteration')
    call check_close('MoF from the carried planes: the cold fit''s normal', norm2(pn2(:, 1) - pn(:, 1)), 0.0_wp, &
                     1.0e-8_wp)
    call check_close('MoF from the carried planes: centroid error / size', &
                     maxval(errc)/hex_volume(xn)**(1.0_wp/3.0_wp), 0.0_wp, 1.0e-12_wp)
    ! (d) the fits after a remap start from the planes remembered by cell
    ! and material: no iteration for a cell whose plane still fits, none
    ! remembered for another cell
    call centroids_remember(mx, mem)
    call check(mem%n == 1 .and. mem%cell(1) == c, 'remembered: the mixed cell')
    mx%plane = 0.0_wp
    call centroids_fit_planes(g, mx, cst)
    plane0 = mx%plane
    mx%plane = 0.0_wp
    cst = centroid_stats_t()
    call centroids_fit_planes(g, mx, cst, memory=mem)
    call check(cst%fitted == 1 .and. cst%iterations == 0, 'fit from the remembered plane: no iteration')
    call check_close('fit from the remembered plane: the cold fit''s plane', maxval(abs(mx%plane - plane0)), 0.0_wp, &
                     1.0e-10_wp)
    mem%cell(1) = c + 1
    mx%plane = 0.0_wp
    cst = centroid_stats_t()
    call centroids_fit_planes(g, mx, cst, memory=mem)
    call check(cst%fitted == 1 .and. cst%iterations > 0, 'no plane remembered for the cell: a search')
    call check_close('no plane remembered: the cold fit''s plane', maxval(abs(mx%plane - plane0)), 0.0_wp, 1.0e-8_wp)
  end subroutine lagrangian_consistency

  !> One cell, 10 % air (ideal gas, rho 1e-3, p 1e-4) in water (Mie-
  !> Gruneisen, rho 1, the same pressure), compressed uniformly: div = -0.3.
  !> The closure gives the air almost all of the cell's volume change (its
  !> B = 1.4e-4 against the water's 2.2): gain = 1/(f_a + f_w B_a/B_w) = 9.99.
  !> The stable step is dv_max/(gain |div|) (it binds here: the CFL step is
  !> 0.2); with it the air loses dv_max = 10 % of its volume in the closure,
  !> with the cell's own limit dv_max/|div| it would lose all of it (the
  !> closure's cap then stops it at 90 %). The cell's sound speed is the
  !> water's (the largest), which sets the CFL step of a gently compressed cell.
  subroutine dt_soft_material()
    type(grid_t) :: g
    type(hydro_t) :: h
    type(material_t) :: mats(2)
    type(mixed_t) :: mx
    type(hydro_params_t) :: par
    type(error_t), allocatable :: err
    type(eos_params_t) :: ep
    real(wp) :: xn(3, 8), gain(1), ba, bw, fa, expect, dt, vol0, dtc(2), da, div, ceff
    integer :: n, k

    call grid_init_box(g, 1, 1, 1, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
    call hydro_allocate(h, g%ncell, g%nnode, err)
    ep%gamma = 1.4_wp
    mats(1)%name = 'air'
    call eos_create('ideal_gas', ep, mats(1)%eos, err)
    ep = eos_params_t(rho0=1.0_wp, c0=1.48_wp, s1=1.75_wp, gamma0=0.28_wp)
    mats(2)%name = 'water'
    call eos_create('mie_gruneisen', ep, mats(2)%eos, err)
    call check(.not. allocated(err), 'setup')
    call g%gather(1, g%x, xn)
    h%vol(1) = hex_volume(xn)
    fa = 0.1_wp
    call mixed_allocate(mx, 1, 2, err)
    mx%cell(1) = 1
    mx%start = [1, 3]
    mx%mat = [1, 2]
    mx%vf = [fa, 1.0_wp - fa]
    mx%rho = [1.0e-3_wp, 1.0_wp]
    mx%mass = mx%rho*mx%vf*h%vol(1)
    mx%e = [mats(1)%eos%energy(1.0e-3_wp, 1.0e-4_wp), mats(2)%eos%energy(1.0_wp, 1.0e-4_wp)]
    h%mat(1) = -1
    h%mass(1) = sum(mx%mass)
    h%rho(1) = h%mass(1)/h%vol(1)
    h%e(1) = dot_product(mx%mass, mx%e)/h%mass(1)
    call material_index_cells(mats, h%mat, mx, err)
    call material_eval_eos(mats, h%rho, h%e, h%p, h%cs, mx)
    call mixed_cell_state(mx, h%p, h%cs)
    call check_close('cell sound speed is the water''s', h%cs(1), mx%cs(2), 0.0_wp)
    ba = mx%rho(1)*mx%cs(1)**2
    bw = mx%rho(2)*mx%cs(2)**2
    gain = 1.0_wp
    call mixed_volume_gain(mx, par%relax, par%dv_vf_min, gain)
    expect = 1.0_wp/(fa + (1.0_wp - fa)*ba/bw)
    call check_close('gain of the air', gain(1), expect, 1.0e-12_wp*expect)
    h%gain = gain

    do k = 1, 2
      ! uniform compression about the centre: div = -3 eps
      do n = 1, g%nnode
        h%u(:, n) = -merge(0.1_wp, 1.0e-6_wp, k == 1)*(g%x(:, n) - 0.5_wp)
      end do
      call lagrange_strain_rates(g, g%x, h%u, h, par, dtc(k))
    end do
    div = -0.3_wp
    call check_close('dt of the compressed cell: dv_max/(gain |div|)', dtc(1), par%dv_max/(gain(1)*abs(div)), &
                     1.0e-12_wp*dtc(1))
    ! gently compressed: the CFL step with the largest sound speed
    ! (Wilkins' signal speed with the linear viscosity, dumax ~ 1e-6)
    ceff = par%q_linear*h%cs(1) + sqrt((par%q_linear*h%cs(1))**2 + h%cs(1)**2)
    call check_close('CFL step of the mixed cell (water''s sound speed)', dtc(2), par%cfl/ceff, 1.0e-5_wp*dtc(2))

    ! the closure over that step, and over the cell's own limit
    do k = 1, 2
      dt = par%dv_max/(gain(1)*abs(div))
      if (k == 2) dt = par%dv_max/abs(div)
      ! the cell's start state (the previous pass changed it)
      mx%vf = [fa, 1.0_wp - fa]
      mx%rho = [1.0e-3_wp, 1.0_wp]
      mx%e = [mats(1)%eos%energy(1.0e-3_wp, 1.0e-4_wp), mats(2)%eos%energy(1.0_wp, 1.0e-4_wp)]
      call material_eval_eos(mats, h%rho, h%e, h%p, h%cs, mx)
      h%e(1) = dot_product(mx%mass, mx%e)/h%mass(1)
      call mixed_cell_state(mx, h%p, h%cs)
      vol0 = h%vol(1)
      call mixed_save_step_start(mx, h%vol)
      h%en = h%e
      h%vol(1) = vol0*(1.0_wp + div*dt)
      ! the compatible heating of the cell, -p dV
      h%e(1) = h%en(1) - h%p(1)*(h%vol(1) - vol0)/h%mass(1)
      call mixed_split(mx, h%mass, h%vol, h%vol, h%en, h%e, par%relax, 0.0_wp, 0.0_wp, 1.0_wp)
      da = (mx%vf(1)*h%vol(1) - fa*vol0)/(fa*vol0)
      if (k == 1) then
        call check_close('air''s relative volume change at the new step', da, -par%dv_max, 1.0e-3_wp*par%dv_max)
      else
        call check_close('air''s relative volume change at the cell''s own limit (closure cap)', da, -0.9_wp, &
                         1.0e-9_wp)
      end if
      h%vol(1) = vol0
    end do

  end subroutine dt_soft_material
end program test_centroids
