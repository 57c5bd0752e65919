!> The particles in the Lagrangian phase (PARTICLES.md §1.6-1.11): their
!> share of the nodal mass and force (Eqs. 16-17), velocity and position
!> from the nodes (Eqs. 23-25 with constant natural coordinates), the strain
!> and spin increments from the virtual solid grid (Eqs. 29-32) or from the
!> mixed nodal velocities (original scheme, Eqs. 26-27), the stress update
!> through the strength models, volume and density (§1.10) and the stable
!> step (§1.11).
!>
!> Solids with an equation of state (&solid eos = 'mie_gruneisen', §2.0
!> step 2): the strength model updates the deviator only (its k is 0) and
!> the pressure is p(rho, e) of the EOS (`eos_mie_gruneisen`, the fluid's
!> kernel), with the energy of the step from the trapezoid of §1.12,
!> m Delta e = 1/2 Vbar (s^n + s^{n+1}) : Delta eps - 1/2 (p^n + p^{n+1})
!> Delta V, in which the implicit p^{n+1} = K(rho^{n+1}) + gamma0 rho0 e^{n+1}
!> is linear in e^{n+1} and solved in closed form. Sound speed for the step:
!> c^2 = c_EOS^2 + 4G/(3 rho).
!>
!> The virtual fluid's artificial viscosity (§1.7, risk R2): the host
!> cells' coverage theta_c = sum_p V_p / V_c (`particles_cell_fraction`)
!> scales it by 1 - theta_c (&hydro particle_viscosity = 'scaled').
!>
!> Determinism (1 and 2 threads bit-identical): every particle-to-node sum
!> loops over the cells in 8 colours (parity of i, j, k; cells of one colour
!> share no node), the cells of a colour in parallel, the particles of a
!> cell in array order (the CSR binning of `particles_state`). A node's sum
!> is therefore always taken in the same order, whatever the thread count.
!>
!> Shape-function gradients (§1.6): grad N_a = J^{-T} dN_a/dxi with
!> J_ij = sum_a x_a,i dN_a/dxi_j at the particle's xi, in the configuration
!> the caller passes (x^n in the predictor, x^{n+1/2} in the corrector and
!> for the strain increments).
module particles_lagrange
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use mesh_grid, only: grid_t
  use mesh_halo, only: halo_t
  use mesh_boundary, only: bc_t, bc_constrain
  use mesh_geometry, only: hex_volume, hex_median_areas
  use particles_state, only: particles_t
  use particles_shape, only: particles_shape_values, particles_shape_gradients
  use particles_spread, only: particles_spread_pieces
  use strength_models, only: strength_t, strength_point_t
  use eos_mie_gruneisen, only: mie_gruneisen_t, mie_gruneisen_state, mie_gruneisen_reference
  implicit none
  private
  public :: particles_work_t, strength_slot_t, particles_work_init, particles_work_resize, &
            particles_gradients, particles_nodal_mass, &
            particles_nodal_force, particles_vf_energy, particles_g2p, particles_virtual_grid, particles_velocity_gradients, &
            particles_step_gradients, &
            particles_stress_update, particles_stress_arrays, particles_half_velocity, particles_stable_dt, mass_guard, &
            particles_cell_fraction, particles_interpolate, particles_phase_mass, particles_viscosity, &
            particles_virtual_masses, particles_blend_velocities, particles_q_heating, particles_slot_start, &
            particles_internal_energy

  !> Guard of §1.7: a node's mass is at least mass_guard times its cell
  !> (virtual-fluid included) plus solid mass.
  real(wp), parameter :: mass_guard = 1.0e-3_wp
  !> `particles_step_gradients`: the decoupled update takes the grid's
  !> velocity at a node only where the real fluid's share of its coupled
  !> mass is below this (fully where none), the paper's virtual velocity
  !> where it is above. Taking it wherever the solid held most of a node
  !> (phi = its share) let the detonation products' velocity into the
  !> steel shell's strain (input/steel_shell.nml: the first crack 15.5 us
  !> against 13.0 with this and 10.5 without any; experiment 8.8)
  real(wp), parameter :: fluid_share_max = 0.01_wp

  !> One solid's strength model (a slot, so that an array can hold models of
  !> different types) and, if its pressure comes from an EOS, that EOS (the
  !> model's k is then 0: module notes).
  type :: strength_slot_t
    class(strength_t), allocatable :: m
    type(mie_gruneisen_t), allocatable :: eos
  end type strength_slot_t

  !> Node work arrays of the coupling, allocated once (nnode) and the
  !> particles' per-step kinematics (np).
  type :: particles_work_t
    logical :: mass_ready = .false.             !< mp holds this phase's particle mass term
    !> f and fvf hold the coming step's predictor force (made with the
    !> stable step, `particles_stable_dt`), f_bad its bad particle
    logical :: f_ready = .false.
    integer :: f_bad = 0
    real(wp), allocatable :: mp(:)              !< (nnode) sum_p (m_p - m'_p) N_Ip, guarded (Eq. 16)
    real(wp), allocatable :: f(:, :)            !< (3, nnode) particle force (Eq. 17)
    real(wp), allocatable :: fvf(:, :)          !< (3, nnode) its virtual-fluid part -sum_p V_p P_c grad N_Ip
    real(wp), allocatable :: ms(:)              !< (nnode) virtual solid grid mass (Eq. 29)
    real(wp), allocatable :: vs(:, :)           !< (3, nnode) virtual solid grid velocity (Eq. 30)
    real(wp), allocatable :: xh(:, :)           !< (3, nnode) x^{n+1/2}
    real(wp), allocatable :: xc(:, :)           !< (3, nnode) the grid of the corrector's forces
    real(wp), allocatable :: vh(:, :)           !< (3, np) particle v^{n+1/2} (Eq. 24)
    real(wp), allocatable :: lgrad(:, :, :)     !< (3, 3, np) velocity gradient L_ij = dv_i/dx_j
    real(wp), allocatable :: stress_h(:, :)     !< (6, np) trial stress at n+1/2 (corrector)
    real(wp), allocatable :: hist_h(:, :)       !< (nhist, np) trial history at n+1/2
    real(wp), allocatable :: vol_h(:), rho_h(:) !< (np) trial volume and density at n+1/2
    real(wp), allocatable :: e_h(:)             !< (np) trial specific internal energy at n+1/2
    real(wp), allocatable :: vscale(:)          !< (ncell) viscosity scale 1 - theta_c of the cells
    real(wp), allocatable :: wcell(:)           !< (ncell) virtual-fluid work of each cell (work)
    real(wp), allocatable :: eroded(:)          !< (np) energy each particle's failure removed this step
    real(wp), allocatable :: q(:)               !< (np) artificial viscosity of the last force (`particles_viscosity`)
    !> (np) true for the particles whose host cell this block owns (all on
    !> one process): the ones it counts in the totals; the others are the
    !> copies of its neighbours' particles in its ghost cells
    logical, allocatable :: owned(:)
    type(strength_slot_t), allocatable :: models(:)  !< (nsolid) strength models
  end type particles_work_t

contains

  !> Allocates the work arrays for nnode nodes, ncell cells and np particles
  !> with nhist history variables each.
  subroutine particles_work_init(w, nnode, ncell, np, nhist, err)
    type(particles_work_t), intent(inout) :: w
    integer, intent(in) :: nnode, ncell, np, nhist
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    character(len=200) :: msg
    allocate(w%mp(nnode), w%f(3, nnode), w%fvf(3, nnode), w%ms(nnode), w%vs(3, nnode), w%xh(3, nnode), w%xc(3, nnode), &
             w%vscale(ncell), w%wcell(ncell), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'particles_work_init', error_no_memory('the coupling arrays'))
      return
    end if
    w%mp = 0.0_wp; w%f = 0.0_wp; w%fvf = 0.0_wp; w%ms = 0.0_wp; w%vs = 0.0_wp; w%xh = 0.0_wp; w%xc = 0.0_wp
    w%vscale = 1.0_wp
    w%wcell = 0.0_wp
    call particles_work_resize(w, np, nhist, err)
  end subroutine particles_work_init

  !> The per-particle work arrays sized anew for np particles with nhist
  !> history variables (after particles left the grid, or a restart read
  !> another count); all particles owned, the nodal mass term to rebuild.
  subroutine particles_work_resize(w, np, nhist, err)
    type(particles_work_t), intent(inout) :: w
    integer, intent(in) :: np, nhist
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    character(len=200) :: msg
    if (allocated(w%vh)) deallocate(w%vh, w%lgrad, w%stress_h, w%hist_h, w%vol_h, w%rho_h, w%e_h, w%eroded, w%owned, w%q)
    allocate(w%vh(3, np), w%lgrad(3, 3, np), w%stress_h(6, np), w%hist_h(nhist, np), w%vol_h(np), w%rho_h(np), &
             w%e_h(np), w%eroded(np), w%owned(np), w%q(np), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'particles_work_resize', error_no_memory('the coupling arrays'))
      return
    end if
    w%vh = 0.0_wp; w%lgrad = 0.0_wp
    w%stress_h = 0.0_wp; w%hist_h = 0.0_wp; w%vol_h = 0.0_wp; w%rho_h = 0.0_wp; w%e_h = 0.0_wp
    w%eroded = 0.0_wp
    w%q = 0.0_wp
    w%owned = .true.
    w%mass_ready = .false.
  end subroutine particles_work_resize

  !> grad N_a (3, 8) (1/length) at natural coordinates xi of the hex xn(3,8)
  !> and det J (length^3 per unit natural volume): grad N_a = J^{-T} dN_a/dxi.
  pure subroutine particles_gradients(xn, xi, gradn, detj)
    real(wp), intent(in) :: xn(3, 8), xi(3)
    real(wp), intent(out) :: gradn(3, 8), detj
    real(wp) :: dn(8, 3), jac(3, 3), cof(3, 3)
    integer :: a, d
    dn = particles_shape_gradients(xi)
    jac = 0.0_wp
    do d = 1, 3
      do a = 1, 8
        jac(:, d) = jac(:, d) + dn(a, d)*xn(:, a)
      end do
    end do
    ! cofactors: J^{-1} = cof^T / det, so J^{-T} = cof / det
    cof(1, 1) = jac(2, 2)*jac(3, 3) - jac(2, 3)*jac(3, 2)
    cof(1, 2) = jac(2, 3)*jac(3, 1) - jac(2, 1)*jac(3, 3)
    cof(1, 3) = jac(2, 1)*jac(3, 2) - jac(2, 2)*jac(3, 1)
    cof(2, 1) = jac(1, 3)*jac(3, 2) - jac(1, 2)*jac(3, 3)
    cof(2, 2) = jac(1, 1)*jac(3, 3) - jac(1, 3)*jac(3, 1)
    cof(2, 3) = jac(1, 2)*jac(3, 1) - jac(1, 1)*jac(3, 2)
    cof(3, 1) = jac(1, 2)*jac(2, 3) - jac(1, 3)*jac(2, 2)
    cof(3, 2) = jac(1, 3)*jac(2, 1) - jac(1, 1)*jac(2, 3)
    cof(3, 3) = jac(1, 1)*jac(2, 2) - jac(1, 2)*jac(2, 1)
    detj = jac(1, 1)*cof(1, 1) + jac(1, 2)*cof(1, 2) + jac(1, 3)*cof(1, 3)
    do a = 1, 8
      gradn(:, a) = matmul(cof, dn(a, :))/detj
    end do
  end subroutine particles_gradients

  !> At the start of a Lagrangian phase (w%mass_ready false): the particles'
  !> pieces spread for their hosts in g (`particles_spread`, if p%spread)
  !> and the phase's nodal mass term (`particles_nodal_mass`, from p%mvf).
  subroutine particles_phase_mass(g, p, w, mnode)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout) :: p
    type(particles_work_t), intent(inout) :: w
    real(wp), intent(in) :: mnode(:)
    if (w%mass_ready) return
    call particles_spread_pieces(g, p)
    call particles_nodal_mass(g, p, p%mvf, mnode, w%mp, w%ms)
    w%mass_ready = .true.
  end subroutine particles_phase_mass

  !> The virtual-fluid masses m'_p = host density x V_p (Eq. 16, §1.7),
  !> from the cells' densities rho: at the coupling's start and after each
  !> remap (new hosts, new densities).
  subroutine particles_virtual_masses(p, rho)
    type(particles_t), intent(inout) :: p
    real(wp), intent(in) :: rho(:)
    integer :: k
    do k = 1, p%np
      p%mvf(k) = rho(p%cell(k))*p%vol(k)
    end do
  end subroutine particles_virtual_masses

  !> At each node the particles reach (ms > 0), the velocity u = (m_f u +
  !> m_p,I vbar_I)/(m_f + m_p,I): m_f the fluid's nodal mass mnode, m_p,I
  !> the particles' share mp, vbar_I their mass-weighted mean velocity vs
  !> (Eq. 30 with v_p).
  subroutine particles_blend_velocities(ms, mnode, mp, vs, u)
    real(wp), intent(in) :: ms(:), mnode(:), mp(:), vs(:, :)
    real(wp), intent(inout) :: u(:, :)
    integer :: n
    do n = 1, size(ms)
      if (.not. ms(n) > 0.0_wp) cycle
      u(:, n) = (mnode(n)*u(:, n) + mp(n)*vs(:, n))/(mnode(n) + mp(n))
    end do
  end subroutine particles_blend_velocities

  !> The artificial viscosity's work over dt heats the particles: e_p -=
  !> dt q_p V_p tr(L_p)/m_p (q the corrector's particle viscosity, lgrad
  !> the velocity gradients).
  subroutine particles_q_heating(p, q, lgrad, dt)
    type(particles_t), intent(inout) :: p
    real(wp), intent(in) :: q(:), lgrad(:, :, :), dt
    integer :: n
    do n = 1, p%np
      p%e(n) = p%e(n) - dt*q(n)*p%vol(n)*(lgrad(1, 1, n) + lgrad(2, 2, n) + lgrad(3, 3, n))/p%m(n)
    end do
  end subroutine particles_q_heating

  !> The particles of solid s start with their strength model's history
  !> variables (slot%m), and with an EOS in the slot their specific energy
  !> from it at their density and the pressure of their initial stress.
  subroutine particles_slot_start(p, s, slot)
    type(particles_t), intent(inout) :: p
    integer, intent(in) :: s
    type(strength_slot_t), intent(in) :: slot
    real(wp) :: p0
    integer :: k
    do k = p%mat_start(s), p%mat_start(s + 1) - 1
      call slot%m%hist_init(p%hist(:, k))
    end do
    if (.not. allocated(slot%eos)) return
    do k = p%mat_start(s), p%mat_start(s + 1) - 1
      p0 = -(p%stress(1, k) + p%stress(2, k) + p%stress(3, k))/3.0_wp
      p%e(k) = slot%eos%energy(p%rho(k), p0)
    end do
  end subroutine particles_slot_start

  !> The internal energy sum_p m_p e_p of the particles the block owns
  !> (owned), exact over all blocks (halo); with each, total its sum over
  !> the same particles.
  real(wp) function particles_internal_energy(p, owned, halo, each, total) result(ep)
    type(particles_t), intent(in) :: p
    logical, intent(in) :: owned(:)
    class(halo_t), intent(in) :: halo
    real(wp), intent(in), optional :: each(:)
    real(wp), intent(out), optional :: total
    type(xsum_t) :: acc(2)
    integer :: k
    do k = 1, p%np
      if (.not. owned(k)) cycle
      call xsum_add(acc(1), p%m(k)*p%e(k))
      if (present(each)) call xsum_add(acc(2), each(k))
    end do
    call halo%sums(acc)
    ep = xsum_value(acc(1))
    if (present(total)) total = xsum_value(acc(2))
  end function particles_internal_energy

  !> The particles' share of the nodal mass (Eq. 16), mp = sum_p (m_p - mvf_p)
  !> N_Ip, raised where needed so that mnode + mp >= mass_guard (mnode +
  !> sum_p m_p N_Ip) (§1.7: the particle quadrature of the virtual fluid can
  !> exceed the subcell masses in covered cells). mvf: virtual-fluid masses
  !> m'_p, frozen for the Lagrangian phase. ms is work (nnode).
  subroutine particles_nodal_mass(g, p, mvf, mnode, mp, ms)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: p
    real(wp), intent(in) :: mvf(:), mnode(:)
    real(wp), intent(out) :: mp(:), ms(:)
    integer :: col, ci, cj, ck, c, q, k, a, n0, lo(3), hi(3), f0(3)
    real(wp) :: sh(8)
    mp = 0.0_wp
    ms = 0.0_wp
    call g%cells_around(1, lo, hi)
    do col = 0, 7
      f0 = g%colour_first(lo, col)
      !$omp parallel do default(none) shared(g, p, mvf, mp, ms, f0, hi) private(ci, cj, ck, c, q, k, a, n0, sh) &
      !$omp collapse(2) schedule(static)
      do ck = f0(3), hi(3), 2
      do cj = f0(2), hi(2), 2
      do ci = f0(1), hi(1), 2
        c = g%cell(ci, cj, ck)
        n0 = g%cell_node0(ci, cj, ck)
        do q = p%pc_start(c), p%pc_start(c + 1) - 1
          k = p%cpart(q)
          sh = particles_shape_values(p%cxi(:, q))*p%cw(q)
          do a = 1, 8
            mp(n0 + g%corner_offset(a)) = mp(n0 + g%corner_offset(a)) + (p%m(k) - mvf(k))*sh(a)
            ms(n0 + g%corner_offset(a)) = ms(n0 + g%corner_offset(a)) + p%m(k)*sh(a)
          end do
        end do
      end do
      end do
      end do
      !$omp end parallel do
    end do
    ! the guard of §1.7
    mp = max(mp, mass_guard*(mnode + ms) - mnode)
  end subroutine particles_nodal_mass

  !> The particles' nodal force (Eq. 17): f_I = -sum_p V_p (sigma_p + P_c I)
  !> . grad N_Ip, grad N in the grid x (3, nnode), P_c = pcell of the host
  !> (the virtual fluid's stress -P_c I that the corner forces already put on
  !> the particle's volume), with the particles' stress and volume, or with
  !> `stress` (6, np) and `vol` (np) if given (the trial state at n+1/2);
  !> fvf: its virtual-fluid part -sum_p V_p P_c grad N_Ip (for the energy
  !> accounting of §1.12). bad: the first particle whose host has det J <= 0
  !> at it (0 if none). q (np), if given: the particles' artificial
  !> viscosity, -q I added to the stress (`particles_viscosity`).
  subroutine particles_nodal_force(g, x, p, pcell, f, fvf, bad, stress, vol, q)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), pcell(:)
    type(particles_t), intent(in) :: p
    real(wp), intent(out) :: f(:, :), fvf(:, :)
    integer, intent(out) :: bad
    real(wp), intent(in), optional :: stress(:, :), vol(:), q(:)
    real(wp), allocatable :: sq(:, :)
    integer :: d
    if (present(q)) then
      ! the artificial viscosity, -q I on top of the stress (not stored)
      if (present(stress)) then
        sq = stress
      else
        sq = p%stress
      end if
      do d = 1, 3
        sq(d, :) = sq(d, :) - q
      end do
      if (present(vol)) then
        call force_kernel(g, x, p, sq, vol, pcell, f, fvf, bad)
      else
        call force_kernel(g, x, p, sq, p%vol, pcell, f, fvf, bad)
      end if
    else if (present(stress) .and. present(vol)) then
      call force_kernel(g, x, p, stress, vol, pcell, f, fvf, bad)
    else
      call force_kernel(g, x, p, p%stress, p%vol, pcell, f, fvf, bad)
    end if
  end subroutine particles_nodal_force

  !> The loop of `particles_nodal_force` (module notes: cell colours).
  subroutine force_kernel(g, x, p, stress, vol, pcell, f, fvf, bad)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), pcell(:), stress(:, :), vol(:)
    type(particles_t), intent(in) :: p
    real(wp), intent(out) :: f(:, :), fvf(:, :)
    integer, intent(out) :: bad
    integer :: col, ci, cj, ck, c, q, k, a, n0, lo(3), hi(3), f0(3)
    real(wp) :: xn(3, 8), gradn(3, 8), detj
    f = 0.0_wp
    fvf = 0.0_wp
    bad = huge(1)
    call g%cells_around(1, lo, hi)
    do col = 0, 7
      f0 = g%colour_first(lo, col)
      !$omp parallel do default(none) shared(g, p, x, pcell, f, fvf, f0, hi, stress, vol) &
      !$omp private(ci, cj, ck, c, q, k, a, n0, xn, gradn, detj) reduction(min: bad) collapse(2) &
      !$omp schedule(static)
      do ck = f0(3), hi(3), 2
      do cj = f0(2), hi(2), 2
      do ci = f0(1), hi(1), 2
        c = g%cell(ci, cj, ck)
        n0 = g%cell_node0(ci, cj, ck)
        if (p%pc_start(c + 1) == p%pc_start(c)) cycle
        do a = 1, 8
          xn(:, a) = x(1:3, n0 + g%corner_offset(a))
        end do
        do q = p%pc_start(c), p%pc_start(c + 1) - 1
          k = p%cpart(q)
          call particles_gradients(xn, p%cxi(:, q), gradn, detj)
          if (.not. detj > 0.0_wp) bad = min(bad, k)
          call piece_force(g, n0, gradn, stress(:, k), vol(k)*p%cw(q), pcell(c), f, fvf)
        end do
      end do
      end do
      end do
      !$omp end parallel do
    end do
    if (bad == huge(1)) bad = 0
  end subroutine force_kernel

  !> One piece's part of the nodal force (Eq. 17) at the corners n0 +
  !> corner_offset of its host: stress sk (6) of its particle plus the
  !> host's pressure pc, over its share vk of the particle's volume (grad N
  !> gradn); fvf its virtual-fluid part.
  pure subroutine piece_force(g, n0, gradn, sk, vk, pc, f, fvf)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: n0
    real(wp), intent(in) :: gradn(3, 8), sk(6), vk, pc
    real(wp), intent(inout) :: f(:, :), fvf(:, :)
    real(wp) :: s(6)
    integer :: a, n
    s = sk
    s(1:3) = s(1:3) + pc
    do a = 1, 8
      n = n0 + g%corner_offset(a)
      f(1, n) = f(1, n) - vk*(s(1)*gradn(1, a) + s(6)*gradn(2, a) + s(5)*gradn(3, a))
      f(2, n) = f(2, n) - vk*(s(6)*gradn(1, a) + s(2)*gradn(2, a) + s(4)*gradn(3, a))
      f(3, n) = f(3, n) - vk*(s(5)*gradn(1, a) + s(4)*gradn(2, a) + s(3)*gradn(3, a))
      fvf(1:3, n) = fvf(1:3, n) - vk*pc*gradn(:, a)
    end do
  end subroutine piece_force

  !> The virtual-fluid pressure work given to the host cells (PARTICLES.md
  !> §1.12): the part -V_p P_c grad N_Ip of the particle force (grid x,
  !> volumes vol) does the work dt sum_I (-V_p P_c grad N_Ip) . u_I on the
  !> nodes (u the stage's half-step velocities), which the host's internal
  !> energy gives back: m_c e_c -= that work, on top of the compatible update
  !> (a mixed cell's total, which `mixed_split` then shares). Cells in
  !> parallel, the particles of a cell in array order. wc (ncell): each
  !> cell's work; wsum: their exact sum over the owned cells (`base_xsum`).
  subroutine particles_vf_energy(g, x, p, vol, pcell, u, dt, mass, e, wc, wsum)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), vol(:), pcell(:), u(:, :), dt, mass(:)
    type(particles_t), intent(in) :: p
    real(wp), intent(inout) :: e(:)
    real(wp), intent(out) :: wc(:)
    type(xsum_t), intent(out) :: wsum
    integer :: c, q, k, a, n0, i, j, l
    real(wp) :: xn(3, 8), un(3, 8), gradn(3, 8), detj, w
    !$omp parallel do default(none) shared(g, p, x, vol, pcell, u, dt, mass, e, wc) &
    !$omp private(c, q, k, a, n0, xn, un, gradn, detj, w) schedule(static)
    do c = 1, g%ncell
      wc(c) = 0.0_wp
      if (p%pc_start(c + 1) == p%pc_start(c)) cycle
      n0 = g%node0(c)
      do a = 1, 8
        xn(:, a) = x(1:3, n0 + g%corner_offset(a))
        un(:, a) = u(:, n0 + g%corner_offset(a))
      end do
      w = 0.0_wp
      do q = p%pc_start(c), p%pc_start(c + 1) - 1
        k = p%cpart(q)
        call particles_gradients(xn, p%cxi(:, q), gradn, detj)
        do a = 1, 8
          w = w - dt*(vol(k)*p%cw(q))*pcell(c)*dot_product(gradn(:, a), un(:, a))
        end do
      end do
      e(c) = e(c) - w/mass(c)
      wc(c) = w
    end do
    !$omp end parallel do
    do l = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          c = g%cell(i, j, l)
          if (p%pc_start(c + 1) > p%pc_start(c)) call xsum_add(wsum, wc(c))
        end do
      end do
    end do
  end subroutine particles_vf_energy

  !> Particle velocity and position from the nodes (Eqs. 23-25): with the
  !> nodal increments du_I = u_I^{n+1} - u_I^n = dt a_I,
  !> v_p^{n+1} = v_p^n + sum_I du_I N_Ip (Eq. 23), vh = v_p^n + 1/2 sum_I du_I
  !> N_Ip (Eq. 24), x_p = sum_I N_Ip x_I^{n+1} (Eq. 25 with constant xi, §1.4).
  subroutine particles_g2p(g, p, un, u, x, vh)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout) :: p
    real(wp), intent(in) :: un(:, :), u(:, :), x(:, :)
    real(wp), intent(out) :: vh(:, :)
    integer :: k, a, n0
    real(wp) :: sh(8), dv(3), xp(3)
    !$omp parallel do default(none) shared(g, p, un, u, x, vh) private(k, a, n0, sh, dv, xp) schedule(static)
    do k = 1, p%np
      dv = particles_interpolate(g, p, k, u, un)
      sh = particles_shape_values(p%xi(:, k))
      n0 = g%node0(p%cell(k))
      xp = 0.0_wp
      do a = 1, 8
        xp = xp + sh(a)*x(1:3, n0 + g%corner_offset(a))
      end do
      vh(:, k) = p%v(:, k) + 0.5_wp*dv
      p%v(:, k) = p%v(:, k) + dv
      p%x(:, k) = xp
    end do
    !$omp end parallel do
  end subroutine particles_g2p

  !> The virtual solid grid (Eqs. 29-30): ms_I = sum_p m_p N_Ip, vs_I =
  !> sum_p m_p vh_p N_Ip / ms_I (0 where no particle reaches the node).
  subroutine particles_virtual_grid(g, p, vh, ms, vs)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: p
    real(wp), intent(in) :: vh(:, :)
    real(wp), intent(out) :: ms(:), vs(:, :)
    integer :: col, ci, cj, ck, c, q, k, a, n, n0, lo(3), hi(3), f0(3)
    real(wp) :: sh(8)
    ms = 0.0_wp
    vs = 0.0_wp
    call g%cells_around(1, lo, hi)
    do col = 0, 7
      f0 = g%colour_first(lo, col)
      !$omp parallel do default(none) shared(g, p, vh, ms, vs, f0, hi) private(ci, cj, ck, c, q, k, a, n, n0, sh) &
      !$omp collapse(2) schedule(static)
      do ck = f0(3), hi(3), 2
      do cj = f0(2), hi(2), 2
      do ci = f0(1), hi(1), 2
        c = g%cell(ci, cj, ck)
        n0 = g%cell_node0(ci, cj, ck)
        do q = p%pc_start(c), p%pc_start(c + 1) - 1
          k = p%cpart(q)
          sh = particles_shape_values(p%cxi(:, q))*p%cw(q)
          do a = 1, 8
            n = n0 + g%corner_offset(a)
            ms(n) = ms(n) + p%m(k)*sh(a)
            vs(1:3, n) = vs(1:3, n) + p%m(k)*sh(a)*vh(1:3, k)
          end do
        end do
      end do
      end do
      end do
      !$omp end parallel do
    end do
    do n = 1, size(ms)
      if (ms(n) > 0.0_wp) vs(:, n) = vs(:, n)/ms(n)
    end do
  end subroutine particles_virtual_grid

  !> Velocity gradient at every particle, L_ij = sum_I v_I,i dN_I/dx_j (Eqs.
  !> 31-32 with the virtual-grid velocities, Eqs. 26-27 with the mixed nodal
  !> ones), grad N in the grid x (x^{n+1/2}).
  subroutine particles_velocity_gradients(g, p, x, v, lgrad)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: p
    real(wp), intent(in) :: x(:, :), v(:, :)
    real(wp), intent(out) :: lgrad(:, :, :)
    integer :: k, a, n, n0, j, q
    real(wp) :: xn(3, 8), gradn(3, 8), detj, lk(3, 3)
    !$omp parallel do default(none) shared(g, p, x, v, lgrad) private(k, a, n, n0, j, q, xn, gradn, detj, lk) &
    !$omp schedule(static)
    do k = 1, p%np
      lk = 0.0_wp
      do q = p%pfirst(k), p%pfirst(k + 1) - 1
        n0 = g%node0(p%pcell(q))
        do a = 1, 8
          xn(:, a) = x(1:3, n0 + g%corner_offset(a))
        end do
        call particles_gradients(xn, p%pxi(:, q), gradn, detj)
        gradn = gradn*p%pw(q)
        do a = 1, 8
          n = n0 + g%corner_offset(a)
          do j = 1, 3
            lk(1:3, j) = lk(1:3, j) + v(1:3, n)*gradn(j, a)
          end do
        end do
      end do
      lgrad(:, :, k) = lk
    end do
    !$omp end parallel do
  end subroutine particles_velocity_gradients

  !> The particles' velocity gradients of a stage (PARTICLES.md §1.8), in
  !> pw%lgrad: grad N in the grid midway between xn and x (kept in pw%xh),
  !> the velocities those of the virtual solid grid made from the
  !> particles' half-step velocities pw%vh (decoupled, Eqs. 29-32: its
  !> nodes under the boundary's constraints, its ghost nodes from the
  !> neighbouring blocks' through halo; each node's velocity blended with
  !> the grid's uh by the particles' share of the coupled nodal mass
  !> mnode + pw%mp, docs/PARTICLES.md 1.9) or the mixed nodal ones uh
  !> (original, Eqs. 26-27). The trial state of the corrector and the
  !> step's stress update both take it.
  subroutine particles_step_gradients(g, bc, p, pw, decoupled, xn, x, uh, mnode, halo)
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    type(particles_t), intent(in) :: p
    type(particles_work_t), intent(inout) :: pw
    logical, intent(in) :: decoupled
    real(wp), intent(in) :: xn(:, :), x(:, :), uh(:, :)
    !> the fluid's nodal mass (with pw%mp the coupled nodal mass, Eq. 16)
    real(wp), intent(in) :: mnode(:)
    class(halo_t), intent(inout), optional :: halo
    integer :: n
    real(wp) :: phi
    do n = 1, g%nnode
      pw%xh(:, n) = 0.5_wp*(xn(:, n) + x(:, n))
    end do
    if (decoupled) then
      call particles_virtual_grid(g, p, pw%vh, pw%ms, pw%vs)
      ! (at a node the solid holds alone the grid's velocity is the
      ! solid's, and the particles' own velocities would carry what FLIP
      ! keeps of a jump between bodies that met there: it takes the grid's
      ! velocity, phi = 1; where the real fluid's share f of the node's
      ! coupled mass (Eq. 16) reaches fluid_share_max the paper's virtual
      ! velocity stands, Eqs. 39-45, phi = 0, so that the fluid's velocity
      ! never enters the solid's strain; linear in f between)
      do n = 1, g%nnode
        if (pw%ms(n) > 0.0_wp .and. mnode(n) + pw%mp(n) > 0.0_wp) then
          phi = max(0.0_wp, 1.0_wp - max(0.0_wp, 1.0_wp - pw%ms(n)/(mnode(n) + pw%mp(n)))/fluid_share_max)
          pw%vs(:, n) = phi*uh(:, n) + (1.0_wp - phi)*pw%vs(:, n)
        end if
      end do
      call bc_constrain(bc, pw%vs)
      if (present(halo)) call halo%nodes(pw%vs)
      call particles_velocity_gradients(g, p, pw%xh, pw%vs, pw%lgrad)
    else
      call particles_velocity_gradients(g, p, pw%xh, uh, pw%lgrad)
    end if
  end subroutine particles_step_gradients

  !> The stress update of every particle over dt (PARTICLES.md §2.0) with
  !> the velocity gradients lgrad: deps = sym(L) dt, dw = skew(L) dt, the
  !> model of the particle's solid (dispatched once per solid: the particles
  !> are sorted by solid), then V_p *= J and rho_p = m_p/V_p (§1.10), with
  !> J = det(I + dt L/2)/det(I - dt L/2): L is taken in the mid-step grid
  !> x^{n+1/2}, so that dx^{n+1} = (I + dt L/2) dx^{n+1/2} and dx^n =
  !> (I - dt L/2) dx^{n+1/2} and J is the exact volume ratio of the linear
  !> motion; it equals det(I + dt L) to second order and is exactly 1 for a
  !> rigid rotation (det(I + dt L) would grow the volume by (omega dt)^2 per
  !> step). bad: the first particle whose volume would not stay positive.
  subroutine particles_stress_update(p, models, lgrad, dt, bad, eroded)
    type(particles_t), intent(inout) :: p
    type(strength_slot_t), intent(in) :: models(:)
    real(wp), intent(in) :: lgrad(:, :, :), dt
    integer, intent(out) :: bad
    real(wp), intent(out), optional :: eroded(:)
    real(wp) :: er(p%np)
    call particles_stress_arrays(p%mat_start, p%m, models, lgrad, dt, p%stress, p%hist, p%vol, p%rho, bad, p%e, er)
    if (present(eroded)) eroded = er
  end subroutine particles_stress_update

  !> `particles_stress_update` on given arrays (stress (6, np), hist
  !> (nhist, np), vol, rho, e (np)) of particles sorted by solid (mat_start)
  !> with masses m: the trial state at n+1/2 is updated so, on copies. The
  !> specific internal energy e takes the constitutive work of the step
  !> (trapezoid, PARTICLES.md §1.12): without an EOS m_p Delta e_p = 1/2
  !> (sigma^n + sigma^{n+1}) : Delta eps 1/2 (V^n + V^{n+1}); with one
  !> (`eos_update`) the pressure part is -1/2 (p^n + p^{n+1}) Delta V.
  !> eroded (np): the energy each particle's failure removed from its stress
  !> in this step (the model's eroded x volume; it stays in e as heat).
  subroutine particles_stress_arrays(mat_start, m, models, lgrad, dt, stress, hist, vol, rho, bad, e, eroded)
    integer, intent(in) :: mat_start(:)
    real(wp), intent(in) :: m(:)
    type(strength_slot_t), intent(in) :: models(:)
    real(wp), intent(in) :: lgrad(:, :, :), dt
    real(wp), intent(inout) :: stress(:, :), hist(:, :), vol(:), rho(:), e(:)
    integer, intent(out) :: bad
    real(wp), intent(out) :: eroded(:)
    integer :: s, k
    bad = huge(1)
    eroded = 0.0_wp
    do s = 1, size(mat_start) - 1
      if (allocated(models(s)%eos)) then
        do k = mat_start(s), mat_start(s + 1) - 1
          call eos_update(models(s)%m, models(s)%eos, lgrad(:, :, k)*dt, dt, m(k), stress(:, k), hist(:, k), &
                          vol(k), rho(k), e(k), eroded(k))
          if (.not. vol(k) > 0.0_wp) bad = min(bad, k)
        end do
      else
        call update_range(models(s)%m, mat_start(s), mat_start(s + 1) - 1)
      end if
    end do
    if (bad == huge(1)) bad = 0
  contains
    subroutine update_range(model, k1, k2)
      class(strength_t), intent(in) :: model
      integer, intent(in) :: k1, k2
      integer :: k
      real(wp) :: f(3, 3), deps(3, 3), dw(3, 3), detf, s0(6), sm(6), work
      type(strength_point_t) :: pt
      ! (a contained procedure: the loop is serial, it sees the host's bad)
      do k = k1, k2
        f = lgrad(:, :, k)*dt
        deps = 0.5_wp*(f + transpose(f))
        dw = 0.5_wp*(f - transpose(f))
        s0 = stress(:, k)
        detf = det3(half_step(f, 1.0_wp))/det3(half_step(f, -1.0_wp))
        if (.not. detf > 0.0_wp) then
          bad = min(bad, k)
          cycle
        end if
        pt = strength_point_t(dt=dt, rho=m(k)/(vol(k)*detf))
        if (model%wants_length) pt%length = (vol(k)*detf)**(1.0_wp/3.0_wp)
        call model%update(deps, dw, pt, stress(:, k), hist(:, k))
        eroded(k) = pt%eroded*vol(k)*detf
        sm = 0.5_wp*(s0 + stress(:, k))
        work = sm(1)*deps(1, 1) + sm(2)*deps(2, 2) + sm(3)*deps(3, 3) &
             + 2.0_wp*(sm(4)*deps(2, 3) + sm(5)*deps(1, 3) + sm(6)*deps(1, 2))
        e(k) = e(k) + work*0.5_wp*vol(k)*(1.0_wp + detf)/m(k)
        vol(k) = vol(k)*detf
        rho(k) = m(k)/vol(k)
      end do
    end subroutine update_range
  end subroutine particles_stress_arrays

  !> One particle of a solid with an EOS over the increment f = L dt
  !> (module notes): the model (k = 0) advances the deviator; V^{n+1} = V^n J
  !> (J as in `particles_stress_update`; a non-positive J leaves vol = 0
  !> and the rest unchanged: the caller flags it); the energy from the
  !> trapezoid, m (e^{n+1} - e^n) = W_dev - 1/2 (p^n + p^{n+1}) Delta V with
  !> W_dev = 1/2 (s^n + s^{n+1}) : Delta eps 1/2 (V^n + V^{n+1}) and
  !> p^{n+1} = K(rho^{n+1}) + B e^{n+1}, B = gamma0 rho0, so that
  !>   e^{n+1} = (e^n + (W_dev - 1/2 (p^n + K) Delta V)/m) / (1 + B Delta V/(2m));
  !> then the mean stress is -p^{n+1}. Units: m mass, vol length^3, rho
  !> density, e velocity^2, stress pressure.
  pure subroutine eos_update(model, eos, f, dt, m, stress, hist, vol, rho, e, eroded)
    class(strength_t), intent(in) :: model
    type(mie_gruneisen_t), intent(in) :: eos
    real(wp), intent(in) :: f(3, 3), dt, m
    real(wp), intent(inout) :: stress(6), hist(:), vol, rho, e
    real(wp), intent(out) :: eroded
    real(wp) :: deps(3, 3), dw(3, 3), detf, s0(6), sm(6), p0, pm, vnew, dvol, wdev, kref, dk, b, pnew, e0
    type(strength_point_t) :: pt
    deps = 0.5_wp*(f + transpose(f))
    dw = 0.5_wp*(f - transpose(f))
    s0 = stress
    p0 = -(s0(1) + s0(2) + s0(3))/3.0_wp
    eroded = 0.0_wp
    detf = det3(half_step(f, 1.0_wp))/det3(half_step(f, -1.0_wp))
    if (.not. detf > 0.0_wp) then
      vol = 0.0_wp
      return
    end if
    vnew = vol*detf
    dvol = vnew - vol
    ! the model sees the EOS pressure predicted with e^n
    call mie_gruneisen_reference(eos, m/vnew, kref, dk)
    pt = strength_point_t(dt=dt, rho=m/vnew, p=kref + eos%gamma0*eos%rho0*e)
    if (model%wants_length) pt%length = vnew**(1.0_wp/3.0_wp)
    call model%update(deps, dw, pt, stress, hist)
    eroded = pt%eroded*vnew
    ! the deviatoric stress work (s^n and s^{n+1} deviators: s : deps = s : dev(deps))
    sm = 0.5_wp*(s0 + stress)
    pm = (sm(1) + sm(2) + sm(3))/3.0_wp
    sm(1:3) = sm(1:3) - pm
    wdev = (sm(1)*deps(1, 1) + sm(2)*deps(2, 2) + sm(3)*deps(3, 3) &
         + 2.0_wp*(sm(4)*deps(2, 3) + sm(5)*deps(1, 3) + sm(6)*deps(1, 2)))*0.5_wp*(vol + vnew)
    rho = m/vnew
    b = eos%gamma0*eos%rho0
    pm = (stress(1) + stress(2) + stress(3))/3.0_wp
    e0 = e
    e = (e + (wdev - 0.5_wp*(p0 + kref)*dvol)/m)/(1.0_wp + 0.5_wp*b*dvol/m)
    pnew = kref + b*e
    ! a failed particle carries no tension (module notes of strength_models):
    ! p^{n+1} = 0 in the trapezoid then
    if (model%failed(hist) .and. pnew < 0.0_wp) then
      pnew = 0.0_wp
      e = e0 + (wdev - 0.5_wp*p0*dvol)/m
    end if
    stress(1:3) = stress(1:3) - pm - pnew
    vol = vnew
  end subroutine eos_update

  !> The viscosity scale of the cells (PARTICLES.md §1.7, risk R2): 1 -
  !> theta_c with theta_c = sum_p V_p / V_c (vol the particles' volumes,
  !> vcell the cells'), clamped to [0, 1]; 1 in cells without particles.
  !> Cells in parallel, the particles of a cell in array order.
  subroutine particles_cell_fraction(g, p, vol, vcell, vscale)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: p
    real(wp), intent(in) :: vol(:), vcell(:)
    real(wp), intent(out) :: vscale(:)
    integer :: c, q
    real(wp) :: vp
    !$omp parallel do default(none) shared(g, p, vol, vcell, vscale) private(c, q, vp) schedule(static)
    do c = 1, g%ncell
      vscale(c) = 1.0_wp
      if (p%pc_start(c + 1) == p%pc_start(c)) cycle
      vp = 0.0_wp
      do q = p%pc_start(c), p%pc_start(c + 1) - 1
        vp = vp + vol(p%cpart(q))*p%cw(q)
      end do
      vscale(c) = 1.0_wp - max(0.0_wp, min(1.0_wp, vp/vcell(c)))
    end do
    !$omp end parallel do
  end subroutine particles_cell_fraction

  !> Particle velocities at n+1/2 predicted from the nodes' predictor
  !> velocities u* (Eq. 24 with the predicted accelerations, PARTICLES.md
  !> §1.8 step 2): vh = v_p^n + 1/2 sum_I (u*_I - u^n_I) N_Ip; the particles
  !> are not changed.
  subroutine particles_half_velocity(g, p, un, u, vh)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: p
    real(wp), intent(in) :: un(:, :), u(:, :)
    real(wp), intent(out) :: vh(:, :)
    integer :: k
    !$omp parallel do default(none) shared(g, p, un, u, vh) private(k) schedule(static)
    do k = 1, p%np
      vh(:, k) = p%v(:, k) + 0.5_wp*particles_interpolate(g, p, k, u, un)
    end do
    !$omp end parallel do
  end subroutine particles_half_velocity

  !> The particles' artificial viscosity (a pressure, added to -sigma in the
  !> force only): q_p = -coef rho_p c_p l_p tr(L_p), for compression and
  !> expansion alike (it damps the ringing behind elastic fronts, which a
  !> compression-only form would leave behind a release wave), c_p the
  !> particle's sound speed (`particles_sound_speed`), l_p its spacing: the
  !> host's length (volume over the largest median area, grid x) times
  !> (V_p/V_c)^(1/3). A linear viscosity spreads a linear (elastic) front
  !> over sqrt(coef c l t) (a diffusion): its overshoot falls with coef, its
  !> width grows.
  subroutine particles_viscosity(g, x, p, models, lgrad, vol, rho, coef, q)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), lgrad(:, :, :), vol(:), rho(:), coef
    type(particles_t), intent(in) :: p
    type(strength_slot_t), intent(in) :: models(:)
    real(wp), intent(out) :: q(:)
    real(wp) :: xn(3, 8), sarea(3, 3), vc, l
    integer :: k, a, n0
    !$omp parallel do default(none) shared(g, x, p, models, lgrad, vol, rho, coef, q) private(k, a, n0, xn, sarea, vc, l) &
    !$omp schedule(static)
    do k = 1, p%np
      n0 = g%node0(p%cell(k))
      do a = 1, 8
        xn(:, a) = x(:, n0 + g%corner_offset(a))
      end do
      call hex_median_areas(xn, sarea)
      vc = hex_volume(xn)
      l = vc/max(norm2(sarea(:, 1)), norm2(sarea(:, 2)), norm2(sarea(:, 3)))*(vol(k)/vc)**(1.0_wp/3.0_wp)
      q(k) = -coef*rho(k)*particles_sound_speed(models(p%mat(k)), rho(k), p%e(k))*l* &
             (lgrad(1, 1, k) + lgrad(2, 2, k) + lgrad(3, 3, k))
    end do
    !$omp end parallel do
  end subroutine particles_viscosity

  !> The sound speed of a particle of a solid with model slot m at density
  !> rho and specific energy e: sqrt(wave modulus / rho), with the EOS's
  !> c^2 added for a solid with an EOS (module notes).
  pure real(wp) function particles_sound_speed(m, rho, e) result(c)
    type(strength_slot_t), intent(in) :: m
    real(wp), intent(in) :: rho, e
    real(wp) :: pe, ce, c2
    c2 = m%m%wave_modulus()/rho
    if (allocated(m%eos)) then
      call mie_gruneisen_state(m%eos, rho, e, pe, ce)
      c2 = c2 + ce*ce
    end if
    c = sqrt(c2)
  end function particles_sound_speed

  !> sum_I S_Ip (u_I - un_I) at particle k: its pieces' shares of the
  !> shape functions at their centres (`particles_state`), the nodal
  !> increments of Eqs. 23-24 (or, with un the particles' mean, the change
  !> a rebuild made).
  pure function particles_interpolate(g, p, k, u, un) result(dv)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: p
    integer, intent(in) :: k
    real(wp), intent(in) :: u(:, :), un(:, :)
    real(wp) :: dv(3)
    real(wp) :: sh(8)
    integer :: q, a, n, n0
    dv = 0.0_wp
    do q = p%pfirst(k), p%pfirst(k + 1) - 1
      sh = particles_shape_values(p%pxi(:, q))*p%pw(q)
      n0 = g%node0(p%pcell(q))
      do a = 1, 8
        n = n0 + g%corner_offset(a)
        dv = dv + sh(a)*(u(1:3, n) - un(1:3, n))
      end do
    end do
  end function particles_interpolate

  !> I + sgn f/2.
  pure function half_step(f, sgn) result(a)
    real(wp), intent(in) :: f(3, 3), sgn
    real(wp) :: a(3, 3)
    a = 0.5_wp*sgn*f
    a(1, 1) = a(1, 1) + 1.0_wp
    a(2, 2) = a(2, 2) + 1.0_wp
    a(3, 3) = a(3, 3) + 1.0_wp
  end function half_step

  !> Determinant of a 3x3 matrix.
  pure real(wp) function det3(a)
    real(wp), intent(in) :: a(3, 3)
    det3 = a(1, 1)*(a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)) - a(1, 2)*(a(2, 1)*a(3, 3) - a(2, 3)*a(3, 1)) &
         + a(1, 3)*(a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1))
  end function det3

  !> Stable step of the particles (§1.11): min_p cfl L_c/(c_p + |v_p|), L_c
  !> the host cell's volume over its largest median-surface area (grid x),
  !> c_p^2 = (K + 4G/3)/rho_p, or c_EOS^2 + 4G/(3 rho_p) for a solid with
  !> an EOS (c_EOS at rho_p, e_p); huge if there are none. kmin: the particle
  !> that sets it (the host particle of the node when the guard below does).
  !>
  !> Guard for light nodes next to stiff particles (§1.11, risk R1): at each
  !> node, dt_I = 2 cfl sqrt(m_I/k_I) with m_I = mnode + mp (the coupled
  !> nodal mass) and k_I = sum_p V_p (K + 4G/3)_p |grad N_Ip|^2 (Gershgorin
  !> bound of the particles' stiffness at the node; rho_p c_EOS^2 for K with
  !> an EOS; for spread particles |grad S_Ip|^2 bounded by n_p sum_q w_q^2
  !> |grad N_I(q)|^2 over its n_p pieces q); k_I is summed in the
  !> cell colours, so the result does not depend on the thread count. kw
  !> (nnode) is work.
  !>
  !> With pcell, f, fvf and bad: also the predictor's nodal force at x
  !> (`particles_nodal_force` with the particles' stress and volume, the
  !> hosts' pressures pcell), from the same grad N and in the same order, so
  !> bit for bit the same (the step's predictor then takes it: one
  !> evaluation of grad N at x^n less per piece).
  subroutine particles_stable_dt(g, x, p, owned, models, cfl, mnode, mp, kw, dt, kmin, qcoef, nodal, pcell, f, fvf, bad)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), cfl, mnode(:), mp(:)
    !> the particles this block owns (`particles_work_t`): only theirs count
    !> in the particle step (a copy in a far ghost cell may have its support
    !> cut at the block's stored cells, and its velocity with it)
    logical, intent(in) :: owned(:)
    !> the artificial viscosity's coefficient (`particles_viscosity`): the
    !> sound speed is taken times sqrt(1 + qcoef^2) + qcoef (the stable step
    !> of a damped oscillator under the central difference)
    real(wp), intent(in), optional :: qcoef
    type(particles_t), intent(in) :: p
    type(strength_slot_t), intent(in) :: models(:)
    real(wp), intent(out) :: kw(:)
    real(wp), intent(out) :: dt
    integer, intent(out) :: kmin
    !> the node whose guard set dt (kmin then the first particle with a
    !> piece at it), 0 if a particle's own step did
    integer, intent(out), optional :: nodal
    real(wp), intent(in), optional :: pcell(:)
    real(wp), intent(out), optional :: f(:, :), fvf(:, :)
    integer, intent(out), optional :: bad
    integer :: k, a, n0, n, col, ci, cj, ck, c, q, nmin, lo(3), hi(3), f0(3), i, j, l, badf
    real(wp) :: xn(3, 8), sarea(3, 3), len_c, dtk, gradn(3, 8), detj, mw, damp
    logical :: forces
    dt = huge(1.0_wp)
    damp = 1.0_wp
    if (present(qcoef)) damp = sqrt(1.0_wp + qcoef*qcoef) + qcoef
    kmin = 0
    do k = 1, p%np
      if (.not. owned(k)) cycle
      n0 = g%node0(p%cell(k))
      do a = 1, 8
        xn(:, a) = x(1:3, n0 + g%corner_offset(a))
      end do
      call hex_median_areas(xn, sarea)
      len_c = hex_volume(xn)/max(norm2(sarea(:, 1)), norm2(sarea(:, 2)), norm2(sarea(:, 3)))
      dtk = cfl*len_c/(particles_sound_speed(models(p%mat(k)), p%rho(k), p%e(k))*damp + norm2(p%v(:, k)))
      if (dtk < dt) then
        dt = dtk
        kmin = k
      end if
    end do
    ! the nodal guard
    kw = 0.0_wp
    forces = present(f)
    if (forces) then
      f = 0.0_wp
      fvf = 0.0_wp
    end if
    badf = huge(1)
    call g%cells_around(1, lo, hi)
    do col = 0, 7
      f0 = g%colour_first(lo, col)
      !$omp parallel do default(none) shared(g, p, x, models, kw, f0, hi, forces, pcell, f, fvf) &
      !$omp private(ci, cj, ck, c, q, k, a, n0, xn, gradn, detj, mw) reduction(min: badf) collapse(2) &
      !$omp schedule(static)
      do ck = f0(3), hi(3), 2
      do cj = f0(2), hi(2), 2
      do ci = f0(1), hi(1), 2
        c = g%cell(ci, cj, ck)
        n0 = g%cell_node0(ci, cj, ck)
        if (p%pc_start(c + 1) == p%pc_start(c)) cycle
        do a = 1, 8
          xn(:, a) = x(1:3, n0 + g%corner_offset(a))
        end do
        ! (a piece's share of the stiffness: n sum_q w_q^2 |grad N(q)|^2,
        ! n the particle's pieces, bounds |sum_q w_q grad N(q)|^2 (Cauchy-
        ! Schwarz); a piece of small share w adds w N to a node's mass and
        ! w^2 |grad N|^2 to its stiffness)
        do q = p%pc_start(c), p%pc_start(c + 1) - 1
          k = p%cpart(q)
          call particles_gradients(xn, p%cxi(:, q), gradn, detj)
          mw = p%vol(k)*models(p%mat(k))%m%wave_modulus()
          if (allocated(models(p%mat(k))%eos)) mw = mw + p%vol(k)*p%rho(k)*eos_c2(models(p%mat(k))%eos, p%rho(k), p%e(k))
          mw = mw*(p%cw(q)*p%cw(q)*(p%pfirst(k + 1) - p%pfirst(k)))
          do a = 1, 8
            kw(n0 + g%corner_offset(a)) = kw(n0 + g%corner_offset(a)) + mw*sum(gradn(:, a)**2)
          end do
          if (forces) then
            if (.not. detj > 0.0_wp) badf = min(badf, k)
            call piece_force(g, n0, gradn, p%stress(:, k), p%vol(k)*p%cw(q), pcell(c), f, fvf)
          end if
        end do
      end do
      end do
      end do
      !$omp end parallel do
    end do
    if (present(bad)) bad = merge(0, badf, badf == huge(1))
    ! (the owned nodes: a block has every particle around them)
    nmin = 0
    do l = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        do i = g%nlo(1), g%nhi(1)
          n = g%node(i, j, l)
          if (.not. kw(n) > 0.0_wp) cycle
          dtk = 2.0_wp*cfl*sqrt((mnode(n) + mp(n))/kw(n))
          if (dtk < dt) then
            dt = dtk
            nmin = n
          end if
        end do
      end do
    end do
    if (nmin > 0) kmin = node_particle(nmin)
    if (present(nodal)) nodal = nmin
  contains
    !> The EOS sound speed squared at rho, e.
    pure real(wp) function eos_c2(eos, rho, e) result(c2)
      type(mie_gruneisen_t), intent(in) :: eos
      real(wp), intent(in) :: rho, e
      real(wp) :: pe, ce
      call mie_gruneisen_state(eos, rho, e, pe, ce)
      c2 = ce*ce
    end function eos_c2

    !> A particle with a piece in a cell that has node n as a corner (the
    !> first in piece order): the smallest piece index among the pieces of
    !> the (up to 8) stored cells around n.
    integer function node_particle(n) result(kp)
      integer, intent(in) :: n
      integer :: i, j, l, ci, cj, ck, c, q, first
      call g%node_ijk(n, i, j, l)
      first = huge(1)
      do ck = max(l, g%slo(3)), min(l + 1, g%shi(3))
        do cj = max(j, g%slo(2)), min(j + 1, g%shi(2))
          do ci = max(i, g%slo(1)), min(i + 1, g%shi(1))
            c = g%cell(ci, cj, ck)
            do q = p%pc_start(c), p%pc_start(c + 1) - 1
              first = min(first, p%pc_perm(q))
            end do
          end do
        end do
      end do
      kp = 0
      if (first < huge(1)) kp = p%ppart(first)
    end function node_particle
  end subroutine particles_stable_dt
end module particles_lagrange
