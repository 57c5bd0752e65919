!> The physical state of a run: grid, hydro state, boundaries, materials,
!> mixed cells, particles, time and step, the conservation totals and
!> the random-number state, with what it registers for restarts; and, when
!> the deck's frames ask for it, each cell's largest pressure so far.
module driver_state
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use base_kinds, only: wp, i8
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use base_random, only: rng_t
  use base_registry, only: registry_t, LOWER_NONNEGATIVE, LOC_CELL
  use mesh_grid, only: grid_t, grid_index_t, grid_register_restart
  use mesh_boundary, only: bc_t
  use material_table, only: material_t
  use material_mixed, only: mixed_t, mixed_register_restart
  use hydro_state, only: hydro_t, hydro_totals, hydro_register_restart
  use mesh_halo, only: halo_t
  use base_share, only: share_t
  use lagrange_centroids, only: centroid_stats_t
  use particles_state, only: particles_t, particles_register_restart
  use particles_lagrange, only: particles_work_t, particles_phase_mass, particles_internal_energy
  use io_output, only: totals_t
  use driver_prerun, only: prerun_t
  implicit none
  private
  public :: state_t, state_totals, energy_drift, budget_residual, totals_not_finite, &
            state_register_restart, &
            state_after_read, centroid_text, state_note_pressure

  !> The physical state.
  type :: state_t
    type(grid_t) :: g
    type(hydro_t) :: h
    type(bc_t) :: bc
    type(material_t), allocatable :: mats(:)
    type(mixed_t) :: mx
    type(particles_t) :: pt               !< MPM particles (np = 0, nothing allocated, without &particles)
    type(particles_work_t) :: pw          !< their coupling work arrays and strength models (if coupled)
    !> (ncell) each cell's largest pressure so far, over the states after
    !> every Lagrangian step, after every Euler step and the initial one: a
    !> field at a place, kept cell by cell through Euler steps (not
    !> remapped), as LS-DYNA's maximum pressure. Allocated only when
    !> &output fields names 'max_pressure'.
    real(wp), allocatable :: p_max(:)
    real(wp) :: t = 0.0_wp                !< time
    real(wp) :: dt = 0.0_wp               !< last step
    !> the step the growth limit (&run dt_growth) grows from: the last step
    !> not shortened to land on a frame or the end time (0: not yet known,
    !> then dt; a restart written before it was kept)
    real(wp) :: dt_grow = 0.0_wp
    integer :: step = 0
    type(totals_t) :: tot                 !< integrals; boundary work and E0 are state
    type(rng_t) :: rng
    real(wp) :: rng_bits = 0.0_wp         !< rng state as stored in restarts
    logical :: ready = .false.            !< complete enough to be written
    class(halo_t), allocatable :: halo    !< this block's halo and global reductions (`mesh_halo`)
    !> on a decomposed run with particles, or Euler steps that a window
    !> cannot hold: the whole grid's state, the same on every rank
    !> (`driver_whole`)
    type(state_t), allocatable :: whole
    !> on a decomposed run with Euler steps (`driver_whole`): the whole
    !> grid's index, with its node positions when an Euler step needs them
    !> (the global rezone, particles, open faces), and this rank's window,
    !> its block widened by the cells its Euler step reads
    type(grid_t), allocatable :: gw
    type(state_t), allocatable :: win
    integer :: win_reach = 0              !< how far from a new cell the window's remap looks
    !> the block the window is built around: this rank's (g's index), or
    !> one of blocks cut for the remap's work (their cuts win_cuts, as
    !> comm_t%cuts: `window_balance`)
    type(grid_index_t) :: win_block
    integer, allocatable :: win_cuts(:)
    !> the cells (whole-grid indices, lo then hi) each Euler step takes back
    !> from the window (`block_from`): the block's stored cells, or where a
    !> window holds only what its step changes the part of them it may
    !> change (`window_active`)
    integer :: win_back(3, 2) = 0
    !> the ranks that share the work of an Euler step on st (allocated on
    !> st%whole of a decomposed run, and on the blocks for the global rezone
    !> of the whole grid's node positions: `base_share`; else absent)
    class(share_t), allocatable :: share
    !> a decomposed run's particles: the block holds those of its owned
    !> cells (pw%owned) and of the ghost layers around them, in the order one
    !> process holds them (`particles_order`)
    logical :: pblocks = .false.
    !> a &prerun's 1D run, mapped in when the scene is built (`driver_prerun`)
    type(prerun_t), allocatable :: pre1d
  end type state_t

contains

  !> What fitting and refreshing the mixed cells' interface planes did
  !> (`lagrange_centroids`), for the log.
  function centroid_text(cs) result(text)
    type(centroid_stats_t), intent(in) :: cs
    character(len=:), allocatable :: text
    character(len=300) :: line
    write(line, '(i0," cells fitted by MoF (",f5.2," iterations, ",i0," capped, centroid error/size ",es8.1, &
      &"), centroids refreshed ",i0," times, ",i0," not fitted or refreshed")') cs%fitted, &
      real(cs%iterations, wp)/real(max(cs%fitted, 1), wp), cs%capped, cs%err_max, cs%moved, cs%failed
    text = trim(line)
  end function centroid_text

  !> Mass, momentum, internal and kinetic energy of the state into st%tot.
  !> With coupled particles the kinetic energy and momentum take the full
  !> nodal mass (cells' plus the particles' share m_p - m'_p, Eq. 16: the
  !> mass the nodes move with) and the internal energy adds sum_p m_p e_p
  !> (PARTICLES.md §1.12).
  subroutine state_totals(st)
    type(state_t), intent(inout) :: st
    type(xsum_t) :: acc(4)
    integer :: n, i, j, k, d
    call hydro_totals(st%g, st%h, st%halo, st%tot%mass, st%tot%momentum, st%tot%internal, st%tot%kinetic)
    st%tot%particle_internal = 0.0_wp
    if (.not. allocated(st%pw%mp)) return
    call particles_phase_mass(st%g, st%pt, st%pw, st%h%mnode)
    ! the particles' share of the nodal mass, at the nodes the block counts
    do k = st%g%ulo(3), st%g%nhi(3)
      do j = st%g%ulo(2), st%g%nhi(2)
        do i = st%g%ulo(1), st%g%nhi(1)
          n = st%g%node(i, j, k)
          do d = 1, 3
            call xsum_add(acc(d), st%pw%mp(n)*st%h%u(d, n))
          end do
          call xsum_add(acc(4), 0.5_wp*st%pw%mp(n)*dot_product(st%h%u(:, n), st%h%u(:, n)))
        end do
      end do
    end do
    call st%halo%sums(acc)
    st%tot%momentum = st%tot%momentum + [xsum_value(acc(1)), xsum_value(acc(2)), xsum_value(acc(3))]
    st%tot%kinetic = st%tot%kinetic + xsum_value(acc(4))
    ! (the particles' internal energy sum_p m_p e_p over those the blocks
    ! own, exact: the same on any rank count)
    st%tot%particle_internal = particles_internal_energy(st%pt, st%pw%owned, st%halo)
    st%tot%internal = st%tot%internal + st%tot%particle_internal
  end subroutine state_totals

  !> Total energy change not explained by the boundary work W, over the
  !> initial energy: (E - E0 - W)/|E0|. Round-off for the gas alone; with
  !> coupled particles it also holds the energy errors of the coupling that
  !> `budget_residual` books (decoupling work, Euler-step transfer).
  pure real(wp) function energy_drift(tot)
    type(totals_t), intent(in) :: tot
    energy_drift = (tot%internal + tot%kinetic - tot%energy_initial - tot%boundary_work)/ &
                   max(abs(tot%energy_initial), tiny(1.0_wp))
  end function energy_drift

  !> What the energy budget leaves unexplained, over the initial energy:
  !> (E - E0 - W + D - T)/|E0|, with the decoupling work D (the particles'
  !> stress power on the real grid less the constitutive, virtual-strain
  !> power that their internal energy books) and the kinetic energy T that
  !> the particles' transfer at Euler steps changes; round-off when every
  !> term is booked (the virtual-fluid work is in the host cells' internal
  !> energy).
  pure real(wp) function budget_residual(tot)
    type(totals_t), intent(in) :: tot
    budget_residual = (tot%internal + tot%kinetic - tot%energy_initial - tot%boundary_work + tot%decoupling_work - &
                       tot%transfer_energy)/max(abs(tot%energy_initial), tiny(1.0_wp))
  end function budget_residual


  !> The names of the totals that are not finite ('' if all are): a NaN or
  !> an infinity in the state, or a sum too large for a real (`base_xsum`).
  pure function totals_not_finite(tot) result(names)
    type(totals_t), intent(in) :: tot
    character(len=:), allocatable :: names
    names = ''
    if (.not. ieee_is_finite(tot%mass)) names = names//', mass'
    if (.not. all(ieee_is_finite(tot%momentum))) names = names//', momentum'
    if (.not. ieee_is_finite(tot%internal)) names = names//', internal energy'
    if (.not. ieee_is_finite(tot%kinetic)) names = names//', kinetic energy'
    if (.not. ieee_is_finite(tot%particle_internal)) names = names//', particles'' internal energy'
    if (len(names) > 0) names = names(3:)
  end function totals_not_finite


  !> Registers the state's restart quantities: each package its own fields,
  !> then time, step, the energy bookkeeping and the random numbers.
  subroutine state_register_restart(st, reg)
    type(state_t), intent(inout), target :: st
    type(registry_t), intent(inout) :: reg
    st%rng_bits = transfer(st%rng%s, 1.0_wp)
    call grid_register_restart(st%g, reg)
    call hydro_register_restart(st%h, reg)
    call mixed_register_restart(st%mx, reg)
    call particles_register_restart(st%pt, reg)
    if (allocated(st%p_max)) call reg%add('max_pressure', 'pressure', LOC_CELL, st%p_max)
    call reg%add('time', 'time', st%t, lower=LOWER_NONNEGATIVE)
    call reg%add('dt', 'time', st%dt, lower=LOWER_NONNEGATIVE)
    call reg%add('dt_grow', 'time', st%dt_grow, lower=LOWER_NONNEGATIVE, mandatory=.false.)
    call reg%add('step', '1', st%step, lower=LOWER_NONNEGATIVE)
    call reg%add('boundary_work', 'energy', st%tot%boundary_work)
    call reg%add('initial_energy', 'energy', st%tot%energy_initial)
    if (allocated(st%pt%id)) then
      call reg%add('virtual_fluid_work', 'energy', st%tot%vf_work)
      call reg%add('decoupling_work', 'energy', st%tot%decoupling_work)
      call reg%add('particle_transfer_energy', 'energy', st%tot%transfer_energy)
      call reg%add('erosion_energy', 'energy', st%tot%erosion_energy, mandatory=.false.)
    end if
    call reg%add('rng_state', 'bits', st%rng_bits)
  end subroutine state_register_restart

  !> After a Lagrangian or an Euler step: each cell's largest pressure so
  !> far (if kept).
  subroutine state_note_pressure(st)
    type(state_t), intent(inout) :: st
    integer :: c
    if (.not. allocated(st%p_max)) return
    do c = 1, st%g%ncell
      ! (a NaN pressure is not taken: the run stops on it at its next check)
      if (st%h%p(c) > st%p_max(c)) st%p_max(c) = st%h%p(c)
    end do
  end subroutine state_note_pressure

  !> After a restart read: quantities stored in another form.
  subroutine state_after_read(st)
    type(state_t), intent(inout) :: st
    st%rng%s = transfer(st%rng_bits, 1_i8)
  end subroutine state_after_read
end module driver_state
