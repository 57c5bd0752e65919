!> The coupled particles' Lagrangian step (`particles_lagrange_step`) and
!> the particles as a nodal contributor of the grid's (`lagrange_nodal`):
!> their share of the nodal mass pw%mp (Eq. 16, frozen
!> for the phase) is the extra mass, and their force (Eq. 17) is evaluated
!> in each stage with the host pressure and grad N of the stage: sigma^n,
!> V^n (x^n and p^n in the predictor), the corrector's with the particles'
!> trial stress and volume at n+1/2 (`trial_state`, PARTICLES.md §1.8 step
!> 2) at x^{n+1/2} and p^{n+1/2}. The virtual-fluid part of that force
!> (-V_p P_c grad N_Ip) does work on the nodes that the corner forces had
!> put into the cells' virtual fluid: in each stage the host cell's internal
!> energy gives it back (`particles_vf_energy`, PARTICLES.md §1.12), so that
!> the step's nodal work less the cells' (the corrector's) is the
!> particle-stress work. `bad` names a particle whose host has det J <= 0
!> at it or whose trial volume is not positive. With &hydro
!> particle_viscosity = 'scaled' the artificial viscosity of a cell hosting
!> particles is scaled by 1 - theta_c (PARTICLES.md §1.7,
!> `particles_cell_fraction`), theta_c from the particles' and the cells'
!> volumes at the start of the step, in both stages: inside a solid the
!> virtual fluid's viscosity would damp the solid (risk R2). The hourglass
!> control is kept: a solid of one particle per cell does not resist the
!> hourglass modes of its host.
!> In a block the particles of its owned cells and of one ghost layer take
!> part (what every owned node needs); the ghost nodes are taken from the
!> neighbours after each stage, as without particles.
module particles_nodal
  use base_kinds, only: wp
  use base_xsum, only: xsum_t
  use mesh_grid, only: grid_t
  use mesh_halo, only: halo_t
  use mesh_boundary, only: bc_t
  use hydro_state, only: hydro_t, hydro_params_t
  use material_table, only: material_t
  use material_mixed, only: mixed_t
  use lagrange_nodal, only: nodal_part_t
  use lagrange_integrator, only: lagrange_step
  use particles_state, only: particles_t
  use particles_lagrange, only: particles_work_t, particles_nodal_force, particles_vf_energy, particles_half_velocity, &
                                particles_step_gradients, particles_stress_arrays, particles_cell_fraction, &
                                particles_viscosity, particles_phase_mass, particles_stable_dt, particles_g2p, &
                                particles_stress_update, particles_q_heating, particles_internal_energy
  implicit none
  private
  public :: particles_nodal_t, particles_budget_t, particles_lagrange_step

  !> The particles pt and their work arrays pw, for one step.
  type, extends(nodal_part_t) :: particles_nodal_t
    type(particles_t), pointer :: pt => null()
    type(particles_work_t), pointer :: pw => null()
  contains
    procedure :: start => nodal_start
    procedure :: visc_scale => nodal_visc_scale
    procedure :: forces => nodal_forces
    procedure :: cells => nodal_cells
    procedure :: arrays => nodal_arrays
  end type particles_nodal_t

  !> A particle step's energies for the run's bookkeeping (PARTICLES.md
  !> §1.12), summed over the blocks: the particle forces' work on the nodes
  !> is the virtual-fluid part (given to the host cells) plus the
  !> particle-stress part -dt sum_p V_p sigma_p : D_real; the constitutive
  !> work dt sum_p V_p sigma_p : D_virtual is the change of the particles'
  !> internal energy; the decoupling work is their difference dt sum_p V_p
  !> sigma_p : (D_real - D_virtual), -(nodal_work - vf_work) -
  !> internal_change, which the constitutive update does not see (with the
  !> time-integration difference of the corrector's trial stress at n+1/2
  !> and the trapezoid).
  type :: particles_budget_t
    real(wp) :: nodal_work = 0.0_wp       !< the particle forces' work on the nodes (the corrector's)
    real(wp) :: vf_work = 0.0_wp          !< its virtual-fluid part, given to the host cells
    real(wp) :: internal_change = 0.0_wp  !< the particles' internal energy change in the stress update
    real(wp) :: eroded = 0.0_wp           !< the internal energy of the particles eroded in it
  end type particles_budget_t

contains

  !> One Lagrangian step with coupled particles (PARTICLES.md §1.8): the
  !> particles' share of the nodal mass (once per phase: here once per run
  !> or restart, from the frozen m'_p), their stable step (§1.11) on top of
  !> the cells', the predictor-corrector with their forces (Eq. 17,
  !> `lagrange_step` with them as its nodal contributor), then their
  !> velocity and position (Eqs. 23-25), the strain and spin increments on
  !> the virtual solid grid (Eqs. 29-32, with the kinematic conditions
  !> applied to it) or from the mixed nodal velocities (&hydro
  !> stress_update = 'original', Eqs. 26-27), both with grad N at
  !> x^{n+1/2}, and the stress, volume and density update.
  !> dt as in `lagrange_step`; bad_particle > 0 names a particle whose host
  !> is inverted at it or whose volume would not stay positive (-1: one on
  !> another block); dt_particle the id of the particle whose stable step
  !> was taken (0 if the cells or the caller set the step); budget the
  !> step's energy bookkeeping (all zero where the step stopped before the
  !> particles' update).
  subroutine particles_lagrange_step(g, h, bc, mats, mx, par, pt, pw, halo, dt, work, bad_cell, bad_particle, budget, &
                                     dt_cell, dt_particle)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    type(bc_t), intent(inout) :: bc
    type(material_t), intent(inout) :: mats(:)
    type(mixed_t), intent(inout) :: mx
    type(hydro_params_t), intent(in) :: par
    type(particles_t), intent(inout), target :: pt
    type(particles_work_t), intent(inout), target :: pw
    class(halo_t), intent(inout) :: halo
    real(wp), intent(inout) :: dt
    real(wp), intent(out) :: work
    integer, intent(out) :: bad_cell, bad_particle
    type(particles_budget_t), intent(out) :: budget
    integer, intent(out), optional :: dt_cell, dt_particle
    real(wp) :: dtp, dt_in, e_old, e_new, key(1), dt_own
    integer :: kp, kid, first, place, nodal, i, j, k
    type(particles_nodal_t) :: contrib
    contrib%pt => pt
    contrib%pw => pw
    call particles_phase_mass(g, pt, pw, h%mnode)
    call particles_stable_dt(g, g%x, pt, pw%owned, pw%models, par%cfl, h%mnode, pw%mp, pw%ms, dtp, kp, &
                             par%particle_q, nodal, h%p, pw%f, pw%fvf, pw%f_bad)
    pw%f_ready = .true.
    ! the blocks' smallest (the particle's id with it; of blocks that tie
    ! exactly, the one one process takes: a particle's own step before a
    ! node's guard (which must be smaller to count), of particles the
    ! first in the whole run's order (by material and host cell; each
    ! block's kp its first of a cell, by id), of nodes the first in the
    ! whole grid's node order)
    key(1) = 0.0_wp
    if (kp > 0) key(1) = real(pt%id(kp), wp)
    dt_own = dtp
    call halo%choose(dtp, key)
    place = huge(1)
    if (nodal > 0) then
      call g%node_ijk(nodal, i, j, k)
      place = pt%nsolid*product(g%gn) + (i + g%off(1)) + (g%gn(1) + 1)*((j + g%off(2)) + (g%gn(2) + 1)*(k + g%off(3)))
    else if (kp > 0) then
      place = (pt%mat(kp) - 1)*product(g%gn) + g%global_cell(pt%cell(kp))
    end if
    first = -huge(1)
    if (kp > 0 .and. .not. dt_own > dtp) first = -place
    call halo%max_int(first)
    kid = -huge(1)
    if (first > -huge(1) .and. place == -first) kid = pt%id(kp)
    call halo%max_int(kid)
    if (kid > -huge(1)) key(1) = real(kid, wp)
    dt_in = dt
    dt = min(dt, dtp)
    call lagrange_step(g, h, bc, mats, mx, par, dt, work, bad_cell, dt_cell=dt_cell, nodal=contrib, &
                       work_nodal=budget%nodal_work, work_cells=budget%vf_work, halo=halo)
    pw%f_ready = .false.
    bad_particle = contrib%bad
    if (present(dt_particle)) dt_particle = merge(nint(key(1)), 0, dtp < dt_in .and. .not. dt < dtp)
    call agree_bad(bad_particle)
    if (bad_cell /= 0 .or. bad_particle /= 0) then
      ! (nothing to book: the step is not taken)
      budget = particles_budget_t()
      return
    end if
    call particles_g2p(g, pt, h%un, h%u, g%x, pw%vh)
    call particles_step_gradients(g, bc, pt, pw, par%stress_decoupled, h%xn, g%x, h%uh, h%mnode, halo)
    e_old = particles_internal_energy(pt, pw%owned, halo)
    call particles_stress_update(pt, pw%models, pw%lgrad, dt, bad_particle, pw%eroded)
    call agree_bad(bad_particle)
    ! the artificial viscosity's work (the corrector's q) heats the particles
    if (par%particle_q > 0.0_wp) call particles_q_heating(pt, pw%q, pw%lgrad, dt)
    e_new = particles_internal_energy(pt, pw%owned, halo, pw%eroded, budget%eroded)
    budget%internal_change = e_new - e_old
  contains
    !> Every block stops where one found a bad particle: -1 on the others.
    subroutine agree_bad(bad)
      integer, intent(inout) :: bad
      integer :: k
      k = merge(1, 0, bad /= 0)
      call halo%max_int(k)
      if (k /= 0 .and. bad == 0) bad = -1
    end subroutine agree_bad
  end subroutine particles_lagrange_step

  subroutine nodal_start(self, g, h, par)
    class(particles_nodal_t), intent(inout) :: self
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(hydro_params_t), intent(in) :: par
    self%bad = 0
    if (par%particle_visc_scaled) call particles_cell_fraction(g, self%pt, self%pt%vol, h%vol, self%pw%vscale)
  end subroutine nodal_start

  subroutine nodal_visc_scale(self, par, scaled, scale)
    class(particles_nodal_t), intent(in), target :: self
    type(hydro_params_t), intent(in) :: par
    logical, intent(out) :: scaled
    real(wp), pointer, intent(out) :: scale(:)
    scaled = par%particle_visc_scaled
    scale => self%pw%vscale
  end subroutine nodal_visc_scale

  subroutine nodal_arrays(self, f, m)
    class(particles_nodal_t), intent(in), target :: self
    real(wp), pointer, contiguous, intent(out) :: f(:, :), m(:)
    f => self%pw%f
    m => self%pw%mp
  end subroutine nodal_arrays

  !> The particles' nodal forces of a stage: the predictor's (1) from
  !> sigma^n and V^n, the corrector's (2) from the trial state at n+1/2,
  !> made first, with the particles' viscosity if asked; the corrector
  !> keeps its positions x^{n+1/2} (pw%xc) for the virtual fluid's energy.
  subroutine nodal_forces(self, stage, g, h, bc, par, dt, halo)
    class(particles_nodal_t), intent(inout) :: self
    integer, intent(in) :: stage
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(bc_t), intent(in) :: bc
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(in) :: dt
    class(halo_t), intent(inout), optional :: halo
    integer :: badp
    associate (pt => self%pt, pw => self%pw)
      if (stage == 1) then
        ! (no viscosity: it needs this step's velocity gradients, which
        ! only the corrector has; the last step's are not the particles'
        ! state, and an Euler step, a restart or a move between blocks
        ! would not carry them; made with the stable step at the same x)
        if (pw%f_ready) then
          badp = pw%f_bad
          pw%f_ready = .false.
        else
          call particles_nodal_force(g, g%x, pt, h%p, pw%f, pw%fvf, badp)
        end if
      else
        call trial_state(self, g, h, bc, par, dt, halo)
        pw%xc = g%x
        if (par%particle_q > 0.0_wp) then
          call particles_viscosity(g, g%x, pt, pw%models, pw%lgrad, pw%vol_h, pw%rho_h, par%particle_q, pw%q)
          call particles_nodal_force(g, g%x, pt, h%p, pw%f, pw%fvf, badp, pw%stress_h, pw%vol_h, pw%q)
        else
          call particles_nodal_force(g, g%x, pt, h%p, pw%f, pw%fvf, badp, pw%stress_h, pw%vol_h)
        end if
      end if
    end associate
    if (self%bad == 0) self%bad = badp
  end subroutine nodal_forces

  !> The virtual fluid's energy given back by the host cells after a
  !> stage's cell update: over dt/2 from x^n with V^n (1), over dt from
  !> x^{n+1/2} with the trial volumes (2).
  subroutine nodal_cells(self, stage, g, h, dt, acc)
    class(particles_nodal_t), intent(inout) :: self
    integer, intent(in) :: stage
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: dt
    type(xsum_t), intent(inout) :: acc
    associate (pt => self%pt, pw => self%pw)
      if (stage == 1) then
        call particles_vf_energy(g, h%xn, pt, pt%vol, h%p, h%uh, 0.5_wp*dt, h%mass, h%e, pw%wcell, acc)
      else
        call particles_vf_energy(g, pw%xc, pt, pw%vol_h, h%p, h%uh, dt, h%mass, h%e, pw%wcell, acc)
      end if
    end associate
  end subroutine nodal_cells

  !> The particles' trial state at n+1/2 for the corrector (PARTICLES.md
  !> §1.8 step 2), on copies: velocities from the predicted nodal
  !> accelerations, strain and spin increments over dt/2 from the virtual
  !> solid grid (or the predictor's nodal velocities u*^{1/2}, original
  !> scheme) with grad N at x^{n+1/4}, the constitutive update. Without it
  !> the corrector's particle forces would use sigma^n, and an undamped
  !> elastic wave would grow (the amplification of x' = x + h v', v' = v - h x
  !> with the trapezoid velocity has determinant 1 + h^2/2).
  subroutine trial_state(self, g, h, bc, par, dt, halo)
    class(particles_nodal_t), intent(inout) :: self
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(bc_t), intent(in) :: bc
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(in) :: dt
    class(halo_t), intent(inout), optional :: halo
    integer :: bad_h   ! (the trial update's erosion, pw%eroded, is not booked)
    associate (pt => self%pt, pw => self%pw)
      if (par%stress_decoupled) call particles_half_velocity(g, pt, h%un, h%u, pw%vh)
      call particles_step_gradients(g, bc, pt, pw, par%stress_decoupled, h%xn, g%x, h%uh, h%mnode, halo)
      pw%stress_h = pt%stress
      pw%hist_h = pt%hist
      pw%vol_h = pt%vol
      pw%rho_h = pt%rho
      pw%e_h = pt%e
      call particles_stress_arrays(pt%mat_start, pt%m, pw%models, pw%lgrad, 0.5_wp*dt, pw%stress_h, pw%hist_h, &
                                   pw%vol_h, pw%rho_h, bad_h, pw%e_h, pw%eroded)
    end associate
    if (self%bad == 0) self%bad = bad_h
  end subroutine trial_state
end module particles_nodal
