!> Unit tests of the Lagrangian kernels (`lagrange_forces`, `lagrange_integrator`)
!> on small boxes of an ideal gas built by hand: corner forces sum to zero
!> cell by cell, one step conserves internal plus kinetic energy less the
!> boundary work, one step is Galilean invariant, boundary conditions hold,
!> and a prescribed nodal contributor (`lagrange_nodal`: force f, mass m_ext) accelerates the
!> nodes by f / (m + m_ext), and the rows of nodes a step notes as moved
!> (`grid_t`'s moved_rows) are those where a node moved. Also checks what the step's reuse of geometry
!> relies on: `hex_volume` and the volume of `hex_volume_gradient` agree bit
!> for bit.
program test_lagrange
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use test_assert, only: check, check_close, check_summary
  use test_scene, only: ideal_gas_state
  use eos_factory, only: eos_params_t, eos_create
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_volume, hex_volume_gradient, hex_corner, hex_median_areas
  use mesh_boundary, only: bc_t, bc_init, bc_constrain, BC_SYMMETRY, BC_WALL, BC_VELOCITY, BC_PRESSURE
  use material_table, only: material_t, material_index_cells, material_eval_eos
  use material_mixed, only: mixed_t
  use mesh_halo, only: halo_t
  use hydro_state, only: hydro_t, hydro_params_t, hydro_allocate, hydro_totals, hydro_subcell_masses, &
                            VISC_EDGE, VISC_TENSOR
  use lagrange_forces, only: lagrange_strain_rates, lagrange_corner_forces, limiter_step
  use lagrange_integrator, only: lagrange_step, lagrange_stable_dt
  use lagrange_nodal, only: nodal_part_t
  implicit none

  real(wp), parameter :: eps = epsilon(1.0_wp)
  integer, parameter :: n = 6
  type(grid_t) :: g
  type(hydro_t) :: h
  type(bc_t) :: bc
  type(material_t) :: mats(1)
  type(mixed_t) :: mx
  type(rng_t) :: rng

  call volumes_agree()
  call corner_forces_sum_to_zero()
  call energy_balance()
  call galilean_invariance()
  call boundary_conditions()
  call extra_force_and_mass()
  call limiter_neighbours()
  call moved_rows_noted()
  call check_summary('test_lagrange')

contains

  !> A box [0,1]^3 of n^3 cells, interior nodes moved at random by up to
  !> amp of a cell, density and energy random in [1,2) (so the pressure
  !> varies), node velocities random in (-vel, vel) then constrained by the
  !> face kinds `kinds` (external pressure p_ext on pressure faces).
  subroutine build(seed, amp, vel, kinds, p_ext, uniform)
    integer, intent(in) :: seed, kinds(6)
    real(wp), intent(in) :: amp, vel, p_ext
    logical, intent(in), optional :: uniform
    type(error_t), allocatable :: err
    real(wp), allocatable :: rho(:), e(:)
    integer :: c, i, j, k, d, m
    logical :: same

    same = .false.
    if (present(uniform)) same = uniform
    call rng_seed(rng, seed)
    call grid_init_box(g, n, n, n, [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], err)
    call check(.not. allocated(err), 'grid_init_box')
    do k = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        do i = g%nlo(1), g%nhi(1)
          if (g%node_faces(i, j, k) /= 0) cycle
          m = g%node(i, j, k)
          do d = 1, 3
            g%x(d, m) = g%x(d, m) + amp*(2.0_wp*rng_uniform(rng) - 1.0_wp)/real(n, wp)
          end do
        end do
      end do
    end do
    allocate(rho(g%ncell), e(g%ncell))
    do c = 1, g%ncell
      if (same) then
        rho(c) = 1.0_wp
        e(c) = 2.5_wp
      else
        rho(c) = 1.0_wp + rng_uniform(rng)
        e(c) = 1.0_wp + rng_uniform(rng)
      end if
    end do
    call ideal_gas_state(g, rho, e, h, mats, mx)
    do m = 1, g%nnode
      do d = 1, 3
        h%u(d, m) = vel*(2.0_wp*rng_uniform(rng) - 1.0_wp)
      end do
    end do
    bc = bc_t()
    bc%kind = kinds
    bc%pressure = p_ext
    call bc_init(bc, g, err)
    call check(.not. allocated(err), 'bc_init')
    call bc_constrain(bc, h%u)
  end subroutine build

  !> The step takes its cell volumes from hex_volume_gradient where the old
  !> code called hex_volume: both evaluate the same sum in the same order,
  !> and must agree bit for bit on any cell (here 10^5 random ones, shifted
  !> far from the origin to exercise the rounding of the centring).
  subroutine volumes_agree()
    real(wp) :: xn(3, 8), b(3, 8), v, off(3)
    integer :: it, a, d, ndiff
    call rng_seed(rng, 7)
    ndiff = 0
    do it = 1, 100000
      do d = 1, 3
        off(d) = 100.0_wp*rng_uniform(rng)
      end do
      do a = 1, 8
        do d = 1, 3
          xn(d, a) = real(hex_corner(d, a), wp) + 0.3_wp*(rng_uniform(rng) - 0.5_wp) + off(d)
        end do
      end do
      call hex_volume_gradient(xn, v, b)
      if (.not. abs(v - hex_volume(xn)) <= 0.0_wp) ndiff = ndiff + 1
    end do
    call check_close('hex_volume = vol of hex_volume_gradient (cells that differ)', real(ndiff, wp), 0.0_wp, 0.0_wp)
  end subroutine volumes_agree

  !> (1) Every cell's eight corner forces sum to zero: pressure, viscosity
  !> (both forms) and hourglass parts apart. Each sum adds 8 computed
  !> forces whose exact sum is 0; the bound 64 eps of the sum of their
  !> magnitudes allows a few roundings per term (the gradient b_a is itself
  !> a sum of 6 face terms).
  subroutine corner_forces_sum_to_zero()
    type(hydro_params_t) :: par
    real(wp) :: dt, worst
    integer :: part
    character(len=*), parameter :: label(4) = [character(len=24) :: 'pressure', 'tensor viscosity', &
                                                'edge viscosity', 'hourglass']

    do part = 1, 4
      call build(11, 0.3_wp, 1.0_wp, [(BC_PRESSURE, part = 1, 6)], 0.0_wp)
      par = hydro_params_t()
      par%q_linear = 0.0_wp; par%q_quad = 0.0_wp; par%hourglass = 0.0_wp
      select case (part)
      case (1)
      case (2, 3)
        h%p = 0.0_wp
        par%q_linear = 0.5_wp; par%q_quad = 1.5_wp
        par%viscosity = merge(VISC_TENSOR, VISC_EDGE, part == 2)
      case (4)
        h%p = 0.0_wp
        par%hourglass = 0.1_wp
      end select
      call lagrange_strain_rates(g, g%x, h%u, h, par, dt)
      call lagrange_corner_forces(g, g%x, h%u, h, par)
      worst = worst_cell_sum()
      call check_close('corner forces sum to zero per cell, '//trim(label(part))//' (relative)', worst, 0.0_wp, &
                       64.0_wp*eps)
      call check(maxval(abs(h%fc)) > 0.0_wp, 'corner forces present: '//trim(label(part)))
    end do
  end subroutine corner_forces_sum_to_zero

  !> Largest |sum_a f_a| / sum_a |f_a| over the cells.
  real(wp) function worst_cell_sum() result(w)
    integer :: c, d
    real(wp) :: s, m
    w = 0.0_wp
    do c = 1, g%ncell
      do d = 1, 3
        s = sum(h%fc(d, :, c))
        m = sum(abs(h%fc(d, :, c)))
        if (m > 0.0_wp) w = max(w, abs(s)/m)
      end do
    end do
  end function worst_cell_sum

  !> (2) One full step: the change of internal plus kinetic energy equals
  !> the boundary work, in a closed box with walls (no work) and in one with
  !> an external pressure on every face. The step's compatible update is
  !> exact in exact arithmetic; what is left is round-off of sums over the
  !> n^3 cells and (n+1)^3 nodes of O(E) terms: bounded by 1e3 eps E.
  subroutine energy_balance()
    type(hydro_params_t) :: par
    real(wp) :: dt, work, m0, p0(3), ie0, ke0, m1, p1(3), ie1, ke1
    integer :: bad, f, kind

    do kind = 1, 2
      if (kind == 1) then
        call build(21, 0.3_wp, 0.5_wp, [(BC_WALL, f = 1, 6)], 0.0_wp)
      else
        call build(22, 0.3_wp, 0.5_wp, [(BC_PRESSURE, f = 1, 6)], 0.7_wp)
      end if
      call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
      dt = huge(1.0_wp)
      call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad)
      call check(bad == 0, 'energy balance: step valid')
      call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
      call check_close(merge('energy balance, walls: dE - work   ', 'energy balance, pressure: dE - work', kind == 1), &
                       (ie1 + ke1) - (ie0 + ke0) - work, 0.0_wp, 1.0e3_wp*eps*(ie0 + ke0))
      if (kind == 2) call check(abs(work) > 1.0e3_wp*eps*(ie0 + ke0), 'the pressure faces do work')
    end do
  end subroutine energy_balance

  !> (3) Adding a uniform velocity U to every node (free faces: pressure 0,
  !> nothing constrains the nodes) leaves the internal energy change of a
  !> step unchanged and shifts the new velocities by U. Only round-off
  !> differs: positions translated by U dt round differently (relative eps
  !> of the coordinates, ~n eps of a cell), and that carries into forces and
  !> energies: bounds 1e3 eps of the energy change scale and of |u|.
  subroutine galilean_invariance()
    type(hydro_params_t) :: par
    real(wp), parameter :: ushift(3) = [0.7_wp, -0.4_wp, 0.3_wp]
    real(wp) :: dt, dt0, work, m0, p0(3), ie0, ke0, m1, p1(3), ie1, ke1, die(2), du
    real(wp) :: u1(3, (n + 1)**3)
    integer :: bad, f, run, i

    do run = 1, 2
      call build(31, 0.3_wp, 0.5_wp, [(BC_PRESSURE, f = 1, 6)], 0.0_wp)
      if (run == 1) call lagrange_stable_dt(g, h, par, dt0)
      if (run == 2) then
        do i = 1, g%nnode
          h%u(:, i) = h%u(:, i) + ushift
        end do
      end if
      call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
      dt = 0.5_wp*dt0
      call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad)
      call check(bad == 0 .and. abs(dt - 0.5_wp*dt0) <= 0.0_wp, 'galilean: step valid, same dt')
      call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
      die(run) = ie1 - ie0
      if (run == 1) u1 = h%u
    end do
    du = 0.0_wp
    do i = 1, g%nnode
      du = max(du, maxval(abs(h%u(:, i) - ushift - u1(:, i))))
    end do
    call check(abs(die(1)) > 0.0_wp, 'galilean: the step changes the internal energy')
    call check_close('galilean: internal energy change with U - without', die(2) - die(1), 0.0_wp, &
                     1.0e3_wp*eps*ie0)
    call check_close('galilean: max |u(with U) - U - u(without)|', du, 0.0_wp, 1.0e3_wp*eps*norm2(ushift))
  end subroutine galilean_invariance

  !> (4) After a step, symmetry faces have zero normal velocity, wall nodes
  !> zero velocity and nodes of a prescribed-velocity face (on no other
  !> constrained face) that velocity, exactly.
  subroutine boundary_conditions()
    type(hydro_params_t) :: par
    real(wp), parameter :: vpre(3) = [0.1_wp, 0.05_wp, -0.2_wp]
    real(wp) :: dt, work, sym, wall, vel
    integer :: bad, b, m, msk

    ! xlo symmetry, xhi wall, ylo velocity, yhi symmetry, zlo symmetry, zhi pressure
    call build(41, 0.3_wp, 0.5_wp, [BC_SYMMETRY, BC_WALL, BC_VELOCITY, BC_SYMMETRY, BC_SYMMETRY, BC_PRESSURE], 0.3_wp)
    bc%velocity(:, 3) = vpre
    call bc_constrain(bc, h%u)
    dt = huge(1.0_wp)
    call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad)
    call check(bad == 0, 'boundaries: step valid')
    sym = 0.0_wp; wall = 0.0_wp; vel = 0.0_wp
    do b = 1, bc%nb
      m = bc%node(b)
      msk = bc%mask(b)
      if (btest(msk, 0)) sym = max(sym, abs(h%u(1, m)))
      if (btest(msk, 3)) sym = max(sym, abs(h%u(2, m)))
      if (btest(msk, 4)) sym = max(sym, abs(h%u(3, m)))
      if (btest(msk, 1)) wall = max(wall, maxval(abs(h%u(:, m))))
      if (msk == ibset(0, 2) .or. msk == ior(ibset(0, 2), ibset(0, 5))) vel = max(vel, maxval(abs(h%u(:, m) - vpre)))
    end do
    call check_close('boundaries: max normal velocity on symmetry faces', sym, 0.0_wp, 0.0_wp)
    call check_close('boundaries: max velocity on the wall', wall, 0.0_wp, 0.0_wp)
    call check_close('boundaries: max |u - v_prescribed| on the velocity face', vel, 0.0_wp, 0.0_wp)
  end subroutine boundary_conditions

  !> (5) A box of uniform gas at rest held by an equal external pressure on
  !> every face is in equilibrium; a uniform extra force f on every node with
  !> extra masses m_ext then gives u = dt f / (m + m_ext). Viscosity and
  !> hourglass control are off and dt is 1e-6 of the stable step, so that
  !> the pressure changes of the unequal accelerations (second order in dt,
  !> 1e-12 relative) stay below the bound 1e3 eps. Then, over a full-size
  !> step, the energy balance with the combined nodal mass must close with
  !> the contributor's work (work_nodal) to round-off (1e3 eps E, as in energy_balance).
  subroutine extra_force_and_mass()
    type(hydro_params_t) :: par
    real(wp), parameter :: fext(3) = [0.3_wp, -0.2_wp, 0.5_wp]
    real(wp), allocatable :: f_ext(:, :), m_ext(:)
    type(nodal_part_t) :: ext
    real(wp) :: dt, dt0, work, wext, worst, m0, p0(3), ie0, ke0, m1, p1(3), ie1, ke1, kx0, kx1, p_gas
    integer :: bad, f, i

    p_gas = 0.4_wp*1.0_wp*2.5_wp
    call build(51, 0.3_wp, 0.0_wp, [(BC_PRESSURE, f = 1, 6)], p_gas, uniform=.true.)
    par%q_linear = 0.0_wp; par%q_quad = 0.0_wp; par%hourglass = 0.0_wp
    allocate(f_ext(3, g%nnode), m_ext(g%nnode))
    do i = 1, g%nnode
      f_ext(:, i) = fext
      m_ext(i) = 0.5_wp*h%mnode(i)*(1.0_wp + rng_uniform(rng))
    end do
    ! (a prescribed force: the contributor's own arrays)
    ext%f = f_ext
    ext%m = m_ext
    ! equilibrium without the extra force
    call lagrange_stable_dt(g, h, par, dt0)
    dt = 1.0e-6_wp*dt0
    call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad)
    call check_close('uniform box at rest: max |u| / (dt p / (rho h))', maxval(abs(h%u))/(dt*p_gas*n), 0.0_wp, &
                     1.0e3_wp*eps)
    h%u = 0.0_wp
    dt = 1.0e-6_wp*dt0
    call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad, nodal=ext, work_nodal=wext)
    call check(bad == 0 .and. abs(dt - 1.0e-6_wp*dt0) <= 0.0_wp, 'extra force: step valid')
    worst = 0.0_wp
    do i = 1, g%nnode
      worst = max(worst, maxval(abs(h%u(:, i)*(h%mnode(i) + m_ext(i))/dt - fext))/norm2(fext))
    end do
    call check_close('extra force: max |u (m + m_ext)/dt - f| / |f|', worst, 0.0_wp, 1.0e3_wp*eps)

    ! energy accounting over a full-size step from the current state
    call hydro_totals(g, h, halo_t(), m0, p0, ie0, ke0)
    kx0 = ext_kinetic(m_ext)
    dt = 0.5_wp*dt0
    call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad, nodal=ext, work_nodal=wext)
    call check(bad == 0, 'extra force: full step valid')
    call hydro_totals(g, h, halo_t(), m1, p1, ie1, ke1)
    kx1 = ext_kinetic(m_ext)
    call check(abs(wext) > 1.0e3_wp*eps*(ie0 + ke0 + kx0), 'extra force: f_ext does work')
    call check_close('extra force: dE (kinetic with m + m_ext) - work - work_ext', &
                     (ie1 + ke1 + kx1) - (ie0 + ke0 + kx0) - work - wext, 0.0_wp, 1.0e3_wp*eps*(ie0 + ke0 + kx0))
  end subroutine extra_force_and_mass

  !> Kinetic energy of extra nodal masses m_ext moving with the nodes.
  real(wp) function ext_kinetic(m_ext) result(k)
    real(wp), intent(in) :: m_ext(:)
    integer :: nd
    k = 0.0_wp
    do nd = 1, g%nnode
      k = k + 0.5_wp*m_ext(nd)*dot_product(h%u(:, nd), h%u(:, nd))
    end do
  end function ext_kinetic
  !> The viscosity limiter's neighbour along a direction is found in the
  !> cell's own logical axes (`limiter_step`): on an axis-aligned cube the
  !> nearest of the 26 by the direction itself; on a cell 10 times longer in
  !> y, a direction at 53 degrees from x still crosses cells in x first; on
  !> a cube turned 45 degrees about z, its own i axis is the step (1,0,0),
  !> which the coordinate axes would read as the diagonal (1,1,0); on a
  !> sheared cell (i and j axes at 30 degrees), the direction of i + j is
  !> the diagonal step.
  subroutine limiter_neighbours()
    real(wp) :: xn(3, 8), s(3, 3), c, r
    integer :: a
    c = cos(atan(1.0_wp))
    call box_cell([1.0_wp, 1.0_wp, 1.0_wp], xn)
    call hex_median_areas(xn, s)
    call check(all(limiter_step(s, [c, c, 0.0_wp]) == [1, 1, 0]) .and. all(limiter_step(s, [0.0_wp, 0.0_wp, -1.0_wp]) &
               == [0, 0, -1]), 'limiter step on a cube: the nearest neighbour to the direction')
    call box_cell([1.0_wp, 10.0_wp, 1.0_wp], xn)
    call hex_median_areas(xn, s)
    call check(all(limiter_step(s, [0.6_wp, 0.8_wp, 0.0_wp]) == [1, 0, 0]), &
               'limiter step on a long cell: along x, not the diagonal')
    call box_cell([1.0_wp, 1.0_wp, 1.0_wp], xn)
    do a = 1, 8
      xn(1:2, a) = [c*(xn(1, a) - xn(2, a)), c*(xn(1, a) + xn(2, a))]
    end do
    call hex_median_areas(xn, s)
    call check(all(limiter_step(s, [c, c, 0.0_wp]) == [1, 0, 0]) .and. all(limiter_step(s, [-c, c, 0.0_wp]) == [0, 1, 0]), &
               'limiter step on a turned cube: its own axes')
    call box_cell([1.0_wp, 1.0_wp, 1.0_wp], xn)
    r = sqrt(3.0_wp)/2.0_wp
    do a = 1, 8
      xn(1:2, a) = [xn(1, a) + r*xn(2, a), 0.5_wp*xn(2, a)]
    end do
    call hex_median_areas(xn, s)
    call check(all(limiter_step(s, [1.0_wp + r, 0.5_wp, 0.0_wp]/norm2([1.0_wp + r, 0.5_wp])) == [1, 1, 0]) .and. &
               all(limiter_step(s, [0.0_wp, 1.0_wp, 0.0_wp]) == [-1, 1, 0]), 'limiter step on a sheared cell: its own axes')
  end subroutine limiter_neighbours

  !> (7) The rows of nodes a step notes in g%moved_rows (what lets an Euler
  !> step compare only those rows' nodes with its target) hold every node
  !> the step moved, and each holds one: a uniform gas at rest with one
  !> inner node set moving, a prescribed-velocity face and a pressure face
  !> (their nodes move after the face conditions), symmetry faces (the
  !> round-off normal velocity they remove is no move), a wall.
  subroutine moved_rows_noted()
    type(hydro_params_t) :: par
    real(wp), allocatable :: x0(:, :)
    logical, allocatable :: moved(:)
    real(wp) :: dt, work
    integer :: bad, m, nrow

    call build(43, 0.0_wp, 0.0_wp, [BC_SYMMETRY, BC_WALL, BC_VELOCITY, BC_SYMMETRY, BC_SYMMETRY, BC_PRESSURE], 0.3_wp, &
               uniform=.true.)
    bc%velocity(:, 3) = [0.0_wp, 0.05_wp, 0.0_wp]
    h%u(:, g%node(2, 3, 2)) = [0.1_wp, 0.0_wp, 0.0_wp]
    call bc_constrain(bc, h%u)
    nrow = g%nnode/g%sx
    allocate(g%moved_rows(nrow), moved(nrow))
    g%moved_rows = .false.
    x0 = g%x
    dt = huge(1.0_wp)
    call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad)
    call check(bad == 0, 'moved rows: step valid')
    moved = .false.
    do m = 1, g%nnode
      if (any(abs(g%x(:, m) - x0(:, m)) > 0.0_wp)) moved((m - 1)/g%sx + 1) = .true.
    end do
    call check(all(moved .eqv. g%moved_rows), 'moved rows: noted exactly where a node moved')
    call check(count(moved) > 0 .and. count(moved) < nrow, 'moved rows: some rows moved, some did not')
    deallocate(g%moved_rows)
  end subroutine moved_rows_noted

  !> The corners of the box [0, d(1)] x [0, d(2)] x [0, d(3)] in `hex_corner` order.
  subroutine box_cell(d, xn)
    real(wp), intent(in) :: d(3)
    real(wp), intent(out) :: xn(3, 8)
    integer :: a
    do a = 1, 8
      xn(:, a) = d*real(hex_corner(:, a), wp)
    end do
  end subroutine box_cell

end program test_lagrange
