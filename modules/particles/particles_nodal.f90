!> The coupled particles as a nodal contributor of the Lagrangian step
!> (`lagrange_nodal`): their share of the nodal mass pw%mp (Eq. 16, frozen
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
  use lagrange_nodal, only: nodal_part_t
  use particles_state, only: particles_t
  use particles_lagrange, only: particles_work_t, particles_nodal_force, particles_vf_energy, particles_half_velocity, &
                                particles_step_gradients, particles_stress_arrays, particles_cell_fraction, &
                                particles_viscosity
  implicit none
  private
  public :: particles_nodal_t

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

contains

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
    real(wp), pointer, intent(out) :: f(:, :), m(:)
    f => self%pw%f
    m => self%pw%mp
  end subroutine nodal_arrays

  !> The particles' nodal forces of a stage, with their viscosity if asked:
  !> the predictor's (1) from sigma^n and V^n with the last step's velocity
  !> gradients, the corrector's (2) from the trial state at n+1/2, made
  !> first; the corrector keeps its positions x^{n+1/2} (pw%xc) for the
  !> virtual fluid's energy.
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
        if (par%particle_q > 0.0_wp) then
          call particles_viscosity(g, g%x, pt, pw%models, pw%lgrad, pt%vol, pt%rho, par%particle_q, pw%q)
          call particles_nodal_force(g, g%x, pt, h%p, pw%f, pw%fvf, badp, q=pw%q)
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
      call particles_step_gradients(g, bc, pt, pw, par%stress_decoupled, h%xn, g%x, h%uh, halo)
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
