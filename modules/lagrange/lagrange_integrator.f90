!> One Lagrangian step: predictor-corrector (Eqs. 20-22) with the compatible
!> energy update (Eq. 19).
!>
!> Predictor: corner forces F^n from (x^n, u^n, p^n); u* = u^n + dt F^n/m;
!> u*^{1/2} = (u^n + u*)/2; x^{1/2} = x^n + dt/2 u*^{1/2};
!> e^{1/2} = e^n - dt/(2 m_c) sum_a F^n_a . u*^{1/2}_a; p^{1/2} from the EOS.
!> Corrector: F^{1/2} from (x^{1/2}, u*^{1/2}, p^{1/2});
!> u^{n+1} = u^n + dt F^{1/2}/m (Eq. 20), u^{n+1/2} = (u^n + u^{n+1})/2 (Eq. 21),
!> x^{n+1} = x^n + dt u^{n+1/2} (Eq. 22), e^{n+1} = e^n - dt/m_c sum_a F^{1/2}_a . u^{n+1/2}_a.
!> Because the same corner forces move the nodes and heat the cells, kinetic
!> plus internal energy is conserved to round-off (less the boundary work).
module lagrange_integrator
  use base_kinds, only: wp
  use mesh_grid, only: grid_t, nodes_moved
  use mesh_halo, only: halo_t
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use mesh_geometry, only: hex_volume, hex_volume_gradient, hex_median_areas
  use mesh_boundary, only: bc_t, bc_pressure_forces, bc_apply, bc_constrain
  use material_table, only: material_t, material_eval_eos, material_burn_at
  use material_mixed, only: mixed_t, mixed_save_step_start, mixed_split, mixed_cell_state, mixed_volume_gain
  use hydro_state, only: hydro_t, hydro_params_t
  use lagrange_forces, only: lagrange_strain_rates, lagrange_corner_forces, lagrange_cell_rates, lagrange_area_sizes
  use particles_state, only: particles_t
  use particles_lagrange, only: particles_work_t, particles_nodal_force, particles_vf_energy, particles_half_velocity, &
                                particles_virtual_grid, particles_velocity_gradients, particles_stress_arrays, &
                                particles_cell_fraction, particles_viscosity
  implicit none
  private
  public :: lagrange_step, lagrange_stable_dt, lagrange_update_cells

contains

  !> Largest stable step of the current state (no growth limit applied);
  !> `dt_cell` (optional) the cell that limits it (see `lagrange_strain_rates`).
  !> Mixed cells are limited with the material volume gains h%gain of the
  !> last `lagrange_step` (1 before any).
  subroutine lagrange_stable_dt(g, h, par, dt_stable, dt_cell)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(out) :: dt_stable
    integer, intent(out), optional :: dt_cell
    call lagrange_strain_rates(g, g%x, h%u, h, par, dt_stable, dt_cell)
  end subroutine lagrange_stable_dt

  !> Advances the state by one step. On entry `dt` is the largest step the
  !> caller allows (end time, output times, growth limit); on exit it is the
  !> step taken: the smaller of that and the stable step. `work` returns the
  !> work done by the boundaries; `bad_cell` is the first cell whose volume
  !> became non-positive (0 if none; -1 if only another block has one), in
  !> which case the state is not usable.
  !> With `halo` (a block of an MPI decomposition) the ghost nodes are
  !> refreshed after each stage's node update and the outer ghost cells'
  !> energy after its cell update; the stable step, the boundary work and a
  !> tangled cell are agreed over all blocks.
  !> `dt_cell` (optional) returns the cell whose stable step is the smallest
  !> (lowest index on a tie; 0 if none), whether or not that step was taken:
  !> the step was limited by it when `dt` came back smaller than it went in.
  !>
  !> Particles (Eq. 16-17) enter through two optional node arrays: `f_ext`
  !> (3, nnode), a force added to the assembled corner forces of each node in
  !> both stages (force units), and `m_ext` (nnode), a mass added to h%mnode in
  !> the velocity update (and in the boundary impulses), so the nodes move as
  !> u = u^n + dt (sum_c F_c + f_ext) / (m + m_ext). Energy accounting: the
  !> cells are heated only by their own corner forces (Eq. 19), so f_ext's
  !> work is not internal energy of the cells; it is returned separately in
  !> `work_ext` = dt sum_n f_ext_n . u_n^{n+1/2} (the same discrete work as the
  !> boundary pressure forces), and the balance that holds to round-off is
  !>   Delta [sum_c m_c e_c + sum_n (m_n + m_ext_n) |u_n|^2 / 2] = work + work_ext,
  !> the kinetic energy taken with the combined nodal mass (the caller owns
  !> the particles' share of it and the particles' internal energy, whose
  !> change is -work_ext for forces from particle stresses). The impulse of a
  !> kinematic boundary on f_ext is boundary work, as for the corner forces.
  !> Without f_ext and m_ext the step is unchanged bit for bit.
  !>
  !> Coupled MPM particles (`pt` with its work arrays `pw`, instead of f_ext
  !> and m_ext): pw%mp, their share of the nodal mass (Eq. 16, frozen for the
  !> phase), is the extra mass, and their force (Eq. 17) is evaluated in each
  !> stage with the host pressure and grad N of the stage: sigma^n, V^n
  !> (x^n and p^n in the predictor, x^{n+1/2} and p^{n+1/2} in the
  !> corrector), the corrector's with the particles' trial stress and volume
  !> at n+1/2 (`particle_trial_state`, PARTICLES.md §1.8 step 2).
  !> The virtual-fluid part of that force (-V_p P_c grad N_Ip) does work on
  !> the nodes that the corner forces had put into the cells' virtual fluid:
  !> in each stage the host cell's internal energy gives it back
  !> (`particles_vf_energy`, PARTICLES.md §1.12), so that work_ext - work_vf
  !> (the corrector's, returned in `work_vf`) is the particle-stress work.
  !> `bad_particle` (0 if none) names a particle whose host has det J <= 0
  !> at it or whose trial volume is not positive.
  !> With &hydro particle_viscosity = 'scaled' the artificial viscosity of a
  !> cell hosting particles is scaled by 1 - theta_c (PARTICLES.md §1.7,
  !> `particles_cell_fraction`), theta_c from the particles' and the cells'
  !> volumes at the start of the step, in both stages: inside a solid the
  !> virtual fluid's viscosity would damp the solid (risk R2). The hourglass
  !> control is kept: a solid of one particle per cell does not resist the
  !> hourglass modes of its host.
  !>
  !> Mixed cells: the stable step holds each material's volume change to
  !> dv_max of itself (`mixed_volume_gain`), and the closure shares the
  !> volume and energy changes in both stages. Their interface planes
  !> (natural coordinates) follow the grid untouched; the centroids that
  !> follow from them and the new fractions are computed where they are
  !> read (`lagrange_centroids`).
  subroutine lagrange_step(g, h, bc, mats, mx, par, dt, work, bad_cell, f_ext, m_ext, work_ext, dt_cell, pt, pw, &
                           bad_particle, work_vf, halo)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    type(bc_t), intent(inout) :: bc
    type(material_t), intent(inout) :: mats(:)
    type(mixed_t), intent(inout) :: mx
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(inout) :: dt
    real(wp), intent(out) :: work
    integer, intent(out) :: bad_cell
    real(wp), intent(in), optional :: f_ext(:, :)
    real(wp), intent(in), optional :: m_ext(:)
    real(wp), intent(out), optional :: work_ext
    integer, intent(out), optional :: dt_cell
    type(particles_t), intent(in), optional :: pt
    type(particles_work_t), intent(inout), optional :: pw
    integer, intent(out), optional :: bad_particle
    real(wp), intent(out), optional :: work_vf
    class(halo_t), intent(inout), optional :: halo
    real(wp) :: dt_stable, w_pred
    integer :: badp, dtc
    type(xsum_t) :: wacc(1)

    if (present(pt) .and. present(pw)) then
      call particle_step(pt, pw)
      return
    end if

    if (present(work_ext)) work_ext = 0.0_wp
    ! predictor
    call mixed_volume_gain(mx, par%relax, par%dv_vf_min, h%gain)
    call lagrange_strain_rates(g, g%x, h%u, h, par, dt_stable, dtc)
    if (present(halo)) call halo%min_step(dt_stable, dtc)
    if (present(dt_cell)) dt_cell = dtc
    dt = min(dt, dt_stable)
    call save_step_start(g, h)
    call mixed_save_step_start(mx, h%vol)
    call bc_pressure_forces(bc, g, g%x, h%p)
    call lagrange_corner_forces(g, g%x, h%u, h, par, dt=dt)
    call update_nodes(g, h, dt, 0.5_wp*dt, .false., f_ext, m_ext)
    call bc_apply(bc, dt, 0.5_wp*dt, h%mnode, h%un, h%xn, h%u, h%uh, g%x, w_pred, m_ext)
    call halo_nodes()
    ! the geometry of x^{1/2} (volumes, their gradients, median areas, strain
    ! rates for u*^{1/2}) is computed here once, for the densities and for the
    ! corrector
    call lagrange_update_cells(g, h, 0.5_wp*dt, bad_cell, geometry=.true.)
    call agree_bad()
    if (bad_cell /= 0) return
    if (present(halo)) call halo%cells(h%e)
    call update_materials(h, mats, mx, par, 0.5_wp*dt)

    ! corrector
    call bc_pressure_forces(bc, g, g%x, h%p)
    call lagrange_corner_forces(g, g%x, h%uh, h, par, dt=dt)
    call update_nodes(g, h, dt, dt, .true., f_ext, m_ext)
    call bc_apply(bc, dt, dt, h%mnode, h%un, h%xn, h%u, h%uh, g%x, work, m_ext, wacc(1))
    call note_boundary_moves(g, h)
    if (present(halo)) then
      call halo%sums(wacc)
      work = xsum_value(wacc(1))
    end if
    call halo_nodes()
    if (present(f_ext) .and. present(work_ext)) then
      call node_work(g, f_ext, h%uh, wacc(1))
      if (present(halo)) call halo%sums(wacc)
      work_ext = dt*xsum_value(wacc(1))
    end if
    call lagrange_update_cells(g, h, dt, bad_cell)
    call agree_bad()
    if (bad_cell /= 0) return
    if (present(halo)) call halo%cells(h%e)
    call update_materials(h, mats, mx, par, dt)
  contains
    !> Ghost nodes from the neighbouring blocks: positions, new and
    !> half-step velocities of the stage just taken.
    subroutine halo_nodes()
      if (.not. present(halo)) return
      call halo%nodes(g%x)
      call halo%nodes(h%u)
      call halo%nodes(h%uh)
    end subroutine halo_nodes

    !> Every block stops where one found a tangled cell: bad_cell = -1 on
    !> the blocks that did not.
    subroutine agree_bad()
      integer :: k
      if (.not. present(halo)) return
      k = merge(1, 0, bad_cell /= 0)
      call halo%max_int(k)
      if (k /= 0 .and. bad_cell == 0) bad_cell = -1
    end subroutine agree_bad

    !> The step with coupled particles (notes above). In a block the
    !> particles of its owned cells and of one ghost layer take part (what
    !> every owned node needs); the ghost nodes are taken from the
    !> neighbours after each stage, as without particles.
    subroutine particle_step(pt, pw)
      type(particles_t), intent(in) :: pt
      type(particles_work_t), intent(inout) :: pw
      type(xsum_t) :: acc(2)
      if (present(bad_particle)) bad_particle = 0
      if (present(work_ext)) work_ext = 0.0_wp
      if (present(work_vf)) work_vf = 0.0_wp
      call mixed_volume_gain(mx, par%relax, par%dv_vf_min, h%gain)
      call lagrange_strain_rates(g, g%x, h%u, h, par, dt_stable, dtc)
      if (present(halo)) call halo%min_step(dt_stable, dtc)
      if (present(dt_cell)) dt_cell = dtc
      dt = min(dt, dt_stable)
      call save_step_start(g, h)
      call mixed_save_step_start(mx, h%vol)
      if (par%particle_visc_scaled) call particles_cell_fraction(g, pt, pt%vol, h%vol, pw%vscale)
      call bc_pressure_forces(bc, g, g%x, h%p)
      call corner_forces(h%u)
      if (par%particle_q > 0.0_wp) then
        ! (the viscosity of the last step's velocity gradients)
        call particles_viscosity(g, g%x, pt, pw%models, pw%lgrad, pt%vol, pt%rho, par%particle_q, pw%q)
        call particles_nodal_force(g, g%x, pt, h%p, pw%f, pw%fvf, badp, q=pw%q)
      else
        call particles_nodal_force(g, g%x, pt, h%p, pw%f, pw%fvf, badp)
      end if
      if (present(bad_particle)) bad_particle = badp
      call update_nodes(g, h, dt, 0.5_wp*dt, .false., pw%f, pw%mp)
      call bc_apply(bc, dt, 0.5_wp*dt, h%mnode, h%un, h%xn, h%u, h%uh, g%x, w_pred, pw%mp)
      call halo_nodes()
      call lagrange_update_cells(g, h, 0.5_wp*dt, bad_cell, geometry=.true.)
      call agree_bad()
      if (bad_cell /= 0) return
      call particles_vf_energy(g, h%xn, pt, pt%vol, h%p, h%uh, 0.5_wp*dt, h%mass, h%e, pw%wcell, acc(2))
      if (present(halo)) call halo%cells(h%e)
      call update_materials(h, mats, mx, par, 0.5_wp*dt)
      call particle_trial_state(pt, pw)
      call bc_pressure_forces(bc, g, g%x, h%p)
      call corner_forces(h%uh)
      pw%xc = g%x
      if (par%particle_q > 0.0_wp) then
        ! (the trial's velocity gradients)
        call particles_viscosity(g, g%x, pt, pw%models, pw%lgrad, pw%vol_h, pw%rho_h, par%particle_q, pw%q)
        call particles_nodal_force(g, g%x, pt, h%p, pw%f, pw%fvf, badp, pw%stress_h, pw%vol_h, pw%q)
      else
        call particles_nodal_force(g, g%x, pt, h%p, pw%f, pw%fvf, badp, pw%stress_h, pw%vol_h)
      end if
      if (present(bad_particle)) then
        if (bad_particle == 0) bad_particle = badp
      end if
      call update_nodes(g, h, dt, dt, .true., pw%f, pw%mp)
      call bc_apply(bc, dt, dt, h%mnode, h%un, h%xn, h%u, h%uh, g%x, work, pw%mp, wacc(1))
      call note_boundary_moves(g, h)
      call node_work(g, pw%f, h%uh, acc(1))
      call halo_nodes()
      call lagrange_update_cells(g, h, dt, bad_cell)
      call agree_bad()
      if (bad_cell /= 0) return
      call particles_vf_energy(g, pw%xc, pt, pw%vol_h, h%p, h%uh, dt, h%mass, h%e, pw%wcell, acc(2))
      if (present(halo)) then
        call halo%cells(h%e)
        call halo%sums(wacc)
        call halo%sums(acc)
      end if
      work = xsum_value(wacc(1))
      if (present(work_ext)) work_ext = dt*xsum_value(acc(1))
      if (present(work_vf)) work_vf = xsum_value(acc(2))
      call update_materials(h, mats, mx, par, dt)
    end subroutine particle_step

    !> The corner forces for the velocities v, the viscosity scaled if asked.
    subroutine corner_forces(v)
      real(wp), intent(in) :: v(:, :)
      if (par%particle_visc_scaled) then
        call lagrange_corner_forces(g, g%x, v, h, par, pw%vscale, dt)
      else
        call lagrange_corner_forces(g, g%x, v, h, par, dt=dt)
      end if
    end subroutine corner_forces

    !> The particles' trial state at n+1/2 for the corrector (PARTICLES.md
    !> §1.8 step 2), on copies: velocities from the predicted nodal
    !> accelerations, strain and spin increments over dt/2 from the virtual
    !> solid grid (or the predictor's nodal velocities u*^{1/2}, original
    !> scheme) with grad N at x^{n+1/4}, the constitutive update. Without it
    !> the corrector's particle forces would use sigma^n, and an undamped
    !> elastic wave would grow (the amplification of x' = x + h v', v' = v - h x
    !> with the trapezoid velocity has determinant 1 + h^2/2).
    subroutine particle_trial_state(pt, pw)
      type(particles_t), intent(in) :: pt
      type(particles_work_t), intent(inout) :: pw
      integer :: n, bad_h   ! (the trial update's erosion, pw%eroded, is not booked)
      do n = 1, g%nnode
        pw%xh(:, n) = 0.5_wp*(h%xn(:, n) + g%x(:, n))
      end do
      if (par%stress_decoupled) then
        call particles_half_velocity(g, pt, h%un, h%u, pw%vh)
        call particles_virtual_grid(g, pt, pw%vh, pw%ms, pw%vs)
        call bc_constrain(bc, pw%vs)
        if (present(halo)) call halo%nodes(pw%vs)
        call particles_velocity_gradients(g, pt, pw%xh, pw%vs, pw%lgrad)
      else
        call particles_velocity_gradients(g, pt, pw%xh, h%uh, pw%lgrad)
      end if
      pw%stress_h = pt%stress
      pw%hist_h = pt%hist
      pw%vol_h = pt%vol
      pw%rho_h = pt%rho
      pw%e_h = pt%e
      call particles_stress_arrays(pt%mat_start, pt%m, pw%models, pw%lgrad, 0.5_wp*dt, pw%stress_h, pw%hist_h, &
                                   pw%vol_h, pw%rho_h, bad_h, pw%e_h, pw%eroded)
      if (present(bad_particle)) then
        if (bad_particle == 0) bad_particle = bad_h
      end if
    end subroutine particle_trial_state
  end subroutine lagrange_step

  !> acc: sum_n f(:,n) . u(:,n) over the nodes this block counts, exact
  !> (force x velocity; `base_xsum`).
  pure subroutine node_work(g, f, u, acc)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: f(:, :), u(:, :)
    type(xsum_t), intent(out) :: acc
    integer :: i, j, k, n
    do k = g%ulo(3), g%nhi(3)
      do j = g%ulo(2), g%nhi(2)
        do i = g%ulo(1), g%nhi(1)
          n = g%node(i, j, k)
          call xsum_add(acc, dot_product(f(:, n), u(:, n)))
        end do
      end do
    end do
  end subroutine node_work

  !> Material states after a stage: mixed cells share their volume and
  !> energy change among their materials (Tipton), every material's EOS is
  !> evaluated (explosives' burn fractions at the stage's time, dt_stage
  !> after the step's start), and mixed cells get their cell pressure and
  !> sound speed.
  subroutine update_materials(h, mats, mx, par, dt_stage)
    type(hydro_t), intent(inout) :: h
    type(material_t), intent(inout) :: mats(:)
    type(mixed_t), intent(inout) :: mx
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(in) :: dt_stage
    real(wp) :: pfloor(size(mats))
    pfloor = mats%p_min
    call mixed_split(mx, h%mass, h%vol, h%amed(1, :), h%en, h%e, par%relax, par%relax_length, dt_stage, par%dv_max, &
                     pfloor)
    call material_burn_at(mats, dt_stage)
    call material_eval_eos(mats, h%rho, h%e, h%p, h%cs, mx)
    call mixed_cell_state(mx, h%p, h%cs)
  end subroutine update_materials

  !> Keeps x^n, u^n, e^n for the two stages of the step.
  subroutine save_step_start(g, h)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    integer :: n, c
    !$omp parallel default(none) shared(g, h) private(n, c)
    !$omp do schedule(static)
    do n = 1, g%nnode
      h%xn(:, n) = g%x(:, n)
      h%un(:, n) = h%u(:, n)
    end do
    !$omp end do nowait
    !$omp do schedule(static)
    do c = 1, g%ncell
      h%en(c) = h%e(c)
    end do
    !$omp end do
    !$omp end parallel
  end subroutine save_step_start

  !> Sum of the corner forces fc(3,8,ncell) of the cells around node (i,j,k)
  !> of grid g (force); c0 is cell (i+1, j+1, k+1), used only where all
  !> eight cells are stored. The order of the terms is the same wherever the
  !> node lies in its block, so a node on a face between two blocks gets the
  !> same sum from both.
  pure function node_force(g, fc, i, j, k, c0) result(f)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: fc(:, :, :)
    integer, intent(in) :: i, j, k, c0
    real(wp) :: f(3)
    integer :: ii, jj, kk, ci, cj, ck, sj, sk

    if (i >= g%slo(1) .and. i < g%shi(1) .and. j >= g%slo(2) .and. j < g%shi(2) .and. &
        k >= g%slo(3) .and. k < g%shi(3)) then
      ! interior node: all eight cells exist (same order as below)
      sj = g%cx
      sk = g%cxy
      f = fc(:, 1, c0) + fc(:, 2, c0 - 1) + fc(:, 3, c0 - sj) + fc(:, 4, c0 - 1 - sj) &
        + fc(:, 5, c0 - sk) + fc(:, 6, c0 - 1 - sk) + fc(:, 7, c0 - sj - sk) &
        + fc(:, 8, c0 - 1 - sj - sk)
    else
      f = 0.0_wp
      ! node (i,j,k) is corner (ii,jj,kk) of cell (i+1-ii, j+1-jj, k+1-kk)
      do kk = 0, 1
        ck = k + 1 - kk
        if (ck < g%slo(3) .or. ck > g%shi(3)) cycle
        do jj = 0, 1
          cj = j + 1 - jj
          if (cj < g%slo(2) .or. cj > g%shi(2)) cycle
          do ii = 0, 1
            ci = i + 1 - ii
            if (ci < g%slo(1) .or. ci > g%shi(1)) cycle
            f = f + fc(:, 1 + ii + 2*jj + 4*kk, g%cell(ci, cj, ck))
          end do
        end do
      end do
    end if
  end function node_force

  !> Gathers the corner forces at each node and advances it (Eqs. 20-22):
  !> u = u^n + dt F/m, uh = (u^n + u)/2, x = x^n + dtx uh; with the extra
  !> force f_ext and mass m_ext of `lagrange_step` if present.
  subroutine update_nodes(g, h, dt, dtx, last, f_ext, m_ext)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: dt, dtx
    !> the step's last stage (its positions are the step's: `move_nodes`)
    logical, intent(in) :: last
    real(wp), intent(in), optional :: f_ext(:, :), m_ext(:)
    real(wp) :: no_f(3, 0), no_m(0)

    ! absent arguments as zero-size arrays: the node loop's OpenMP region
    ! cannot share an absent optional
    if (present(f_ext) .and. present(m_ext)) then
      call move_nodes(g, h, dt, dtx, last, f_ext, m_ext, .true., .true.)
    else if (present(f_ext)) then
      call move_nodes(g, h, dt, dtx, last, f_ext, no_m, .true., .false.)
    else if (present(m_ext)) then
      call move_nodes(g, h, dt, dtx, last, no_f, m_ext, .false., .true.)
    else
      call move_nodes(g, h, dt, dtx, last, no_f, no_m, .false., .false.)
    end if
  end subroutine update_nodes

  !> The node loop of `update_nodes`: an extra nodal force f_add (if has_f)
  !> and an extra nodal mass m_add (if has_m); the switches are the same for
  !> every node, so the branches cost nothing measurable.
  subroutine move_nodes(g, h, dt, dtx, last, f_add, m_add, has_f, has_m)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: dt, dtx
    logical, intent(in) :: last
    real(wp), intent(in) :: f_add(:, :), m_add(:)
    logical, intent(in) :: has_f, has_m
    integer :: n, i, j, k, c0, n0
    real(wp) :: f(3), m
    logical :: track

    ! (in the last stage, a row of nodes whose inner nodes leave x^n is
    ! noted in g%moved_rows: one thread takes each row, so each flag has
    ! one writer; the nodes on the block's faces are `note_boundary_moves`',
    ! after their conditions)
    track = last .and. allocated(g%moved_rows)
    !$omp parallel do default(none) shared(g, h, dt, dtx, f_add, m_add, has_f, has_m, track) collapse(2) &
    !$omp private(n, i, j, k, c0, f, m, n0) schedule(static)
    do k = g%nlo(3), g%nhi(3)
    do j = g%nlo(2), g%nhi(2)
    ! consecutive i are consecutive nodes and cells; c0 = cell (i+1, j+1, k+1)
    n = g%node(g%nlo(1), j, k) - 1
    c0 = g%cell(g%nlo(1) + 1, j + 1, k + 1) - 1
    n0 = n + 1
    do i = g%nlo(1), g%nhi(1)
      n = n + 1
      c0 = c0 + 1
      f = node_force(g, h%fc, i, j, k, c0)
      if (has_f) f = f + f_add(:, n)
      m = h%mnode(n)
      if (has_m) m = m + m_add(n)
      h%u(:, n) = h%un(:, n) + dt*f/m
      h%uh(:, n) = 0.5_wp*(h%un(:, n) + h%u(:, n))
      g%x(:, n) = h%xn(:, n) + dtx*h%uh(:, n)
    end do
    ! (the row's inner nodes n0+1 .. n-1, read again while they are in the
    ! cache: a loop of its own runs in the vector lanes)
    if (track .and. j > g%nlo(2) .and. j < g%nhi(2) .and. k > g%nlo(3) .and. k < g%nhi(3)) then
      if (n - n0 > 1) then
        if (nodes_moved(n - n0 - 1, g%x(:, n0 + 1:n - 1), h%xn(:, n0 + 1:n - 1))) &
          g%moved_rows((n - 1)/g%sx + 1) = .true.
      end if
    end if
    end do
    end do
    !$omp end parallel do
  end subroutine move_nodes

  !> Notes in g%moved_rows (if tracked) the rows of the nodes on the
  !> block's faces that the step (`move_nodes`, then the face conditions of
  !> `bc_apply`) left away from x^n: with `move_nodes`' notes of the inner
  !> nodes, every row in which a node ends the step elsewhere than it began
  !> it. (A face node's move before its condition, e.g. the round-off
  !> normal velocity a symmetry plane removes, is not a move.)
  subroutine note_boundary_moves(g, h)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(in) :: h
    integer :: j, k, n0, n1
    logical :: moved
    if (.not. allocated(g%moved_rows)) return
    do k = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        n0 = g%node(g%nlo(1), j, k)
        n1 = n0 + g%nhi(1) - g%nlo(1)
        ! (a row on a face whole, else its two end nodes)
        if (j == g%nlo(2) .or. j == g%nhi(2) .or. k == g%nlo(3) .or. k == g%nhi(3)) then
          moved = nodes_moved(n1 - n0 + 1, g%x(:, n0:n1), h%xn(:, n0:n1))
        else
          moved = nodes_moved(1, g%x(:, n0), h%xn(:, n0)) .or. nodes_moved(1, g%x(:, n1), h%xn(:, n1))
        end if
        if (moved) g%moved_rows((n0 - 1)/g%sx + 1) = .true.
      end do
    end do
  end subroutine note_boundary_moves

  !> Compatible energy update (Eq. 19) over dte with the half-step velocity,
  !> then new volume and density of every cell. bad_cell > 0 names the first
  !> owned cell with a non-positive volume. In a block with ghosts the energy
  !> is updated where the corner forces are known (`cells_around(1)`), the
  !> geometry in every stored cell; the outer ghost layer's energy comes
  !> from the halo. With `geometry` (default false), also
  !> leaves the geometry of the new positions and the strain rates of the
  !> half-step velocity h%uh in h (h%dvdx, h%amed, h%grad), as
  !> `lagrange_strain_rates` would for (g%x, h%uh), so that the forces of the
  !> next stage need not compute them again. The volume is then taken from
  !> `hex_volume_gradient`, which evaluates the same sum as `hex_volume` in
  !> the same order (tests/test_lagrange.f90 checks that both agree bit for bit).
  subroutine lagrange_update_cells(g, h, dte, bad_cell, geometry)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: dte
    integer, intent(out) :: bad_cell
    logical, intent(in), optional :: geometry
    integer :: c, a, n0, ci, cj, ck, lo(3), hi(3)
    real(wp) :: de, xn(3, 8), vn(3, 8), s(3, 3), area(3), dumax
    logical :: geom, forced

    geom = .false.
    if (present(geometry)) geom = geometry
    ! the cells whose corner forces are known (owned and one ghost layer)
    call g%cells_around(1, lo, hi)
    bad_cell = huge(1)
    !$omp parallel do default(none) shared(g, h, dte, geom, lo, hi) &
    !$omp private(c, a, n0, ci, cj, ck, de, xn, vn, s, area, dumax, forced) &
    !$omp reduction(min: bad_cell) collapse(2) schedule(static)
    do ck = g%slo(3), g%shi(3)
    do cj = g%slo(2), g%shi(2)
    ! consecutive i are consecutive cells and nodes
    c = g%cell(g%slo(1), cj, ck) - 1
    n0 = g%cell_node0(g%slo(1), cj, ck) - 1
    do ci = g%slo(1), g%shi(1)
      c = c + 1
      n0 = n0 + 1
      forced = ci >= lo(1) .and. ci <= hi(1) .and. cj >= lo(2) .and. cj <= hi(2) .and. ck >= lo(3) .and. ck <= hi(3)
      de = 0.0_wp
      do a = 1, 8
        if (forced) de = de - dot_product(h%fc(:, a, c), h%uh(:, n0 + g%corner_offset(a)))
        xn(:, a) = g%x(:, n0 + g%corner_offset(a))
      end do
      if (forced) h%e(c) = h%en(c) + dte*de/h%mass(c)
      if (geom) then
        do a = 1, 8
          vn(:, a) = h%uh(:, n0 + g%corner_offset(a))
        end do
        call hex_volume_gradient(xn, h%vol(c), h%dvdx(:, :, c))
        call hex_median_areas(xn, s)
      else
        h%vol(c) = hex_volume(xn)
      end if
      if (h%vol(c) > 0.0_wp) then
        h%rho(c) = h%mass(c)/h%vol(c)
        if (geom) then
          call lagrange_cell_rates(vn, s, h%vol(c), area, h%grad(:, c), dumax)
          h%amed(:, c) = lagrange_area_sizes(area)
        end if
      else if (g%owns_cell(ci, cj, ck)) then
        bad_cell = min(bad_cell, c)
      end if
    end do
    end do
    end do
    !$omp end parallel do
    if (bad_cell == huge(1)) bad_cell = 0
  end subroutine lagrange_update_cells
end module lagrange_integrator
