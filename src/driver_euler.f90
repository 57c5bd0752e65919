!> The Euler phase in the time loop: when to run it (the paper's triggers,
!> or an interval), the rezone (back to the initial grid, with moving faces
!> followed (`rezone_global`), or smoothing of the
!> distorted subdomains (LSSM) or of the whole grid), the remap
!> (`remap_euler`), the material state after it, the conservation check and
!> the log.
module driver_euler
  use base_kinds, only: wp
  use base_build, only: build_checks
  use mesh_grid, only: grid_t, grid_unflagged_move
  use mesh_halo, only: halo_t
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t, error_set, error_no_memory, ERR_RUNTIME
  use base_timers, only: timer_t, wall_seconds
  use base_registry, only: registry_t, LOWER_NONNEGATIVE
  use rezone_config, only: rezone_config_t
  use rezone_global, only: global_face_rule, GLOBAL_FACE_MOVE
  use rezone_lssm, only: lssm_report_t, LSSM_SKIPPED, LSSM_SNAPPED
  use rezone_driver, only: rezone_state_t, rezone_state_init, rezone_standard_ratios, rezone_grid, &
                           rezone_due, rezone_rearm, rezone_worst_cells
  use lagrange_centroids, only: centroid_stats_t
  use hydro_state, only: hydro_totals
  use remap_euler, only: remap_params_t, remap_stats_t, remap_work_t, remap_work_ready
  use remap_lattice, only: lattice_nodes
  use remap_after, only: remap_after_state
  use remap_way, only: remap_way_t, parts_state_t, remap_way_step
  use io_log, only: log_t, log_line
  use mesh_boundary, only: bc_t
  use base_share, only: share_t
  use base_xsum, only: xsum_value
  use driver_state, only: state_t
  use particles_euler, only: particles_euler_t, particles_euler_save
  use driver_particles, only: particles_euler_preposition, particles_euler_fill, particles_euler_finish
  use parallel_comm, only: comm_t
  use parallel_euler, only: rezone_balance_t, rezone_balanced
  implicit none
  private
  public :: euler_state_t, euler_start_t, euler_init, euler_standard_ratios, euler_register_restart, euler_due, &
            euler_due_where, euler_step, euler_begin, euler_rezone, euler_finish, euler_report, remap_params, &
            euler_preposition, euler_start_totals, cuts_text

  !> The Euler phase's own state (only with &rezone mode other than 'none').
  type :: euler_state_t
    logical :: on = .false.                  !< an Euler phase is configured
    !> what the rezone keeps (`rezone_driver`; with the triggers' bounds and
    !> the next interval time, restart state)
    type(rezone_state_t) :: rez
    !> a decomposed run's smoothing on blocks cut for its work
    !> (`parallel_euler`), kept from one Euler step to the next
    type(rezone_balance_t) :: bal
    integer :: n = 0                         !< Euler steps so far (restart state)
    integer :: cells = 0, mof = 0, mof_carried = 0, mof_iterations = 0   !< this segment's totals
    !> this segment's totals by the remap's path (`euler_report`): the
    !> cells remapped by swept faces; the Euler steps that remapped some
    !> cell by intersection, those steps' cells and their remap's wall time
    !> (s), and the remap's wall time of all steps
    integer :: cells_swept = 0, n_intersecting = 0, cells_intersecting = 0
    real(wp) :: t_remap_intersecting = 0.0_wp, t_remap = 0.0_wp
    real(wp) :: ke = 0.0_wp                  !< kinetic energy returned to internal energy, this segment
    real(wp) :: t_rezone_total = 0.0_wp      !< of the Euler time, the rezone's part (s)
    type(timer_t) :: timer                   !< wall time of the Euler steps
    !> of it, the coupled particles' part (placed in the standard grid, the
    !> fluid under them filled, their nodal share saved, relocated and
    !> coupled again; one process or the whole grid, not the windows)
    type(timer_t) :: t_particles
    character(len=160) :: trigger_note = ''  !< what made the next Euler step due (for its log line)
    !> the remap's work arrays, kept from one Euler step to the next
    type(remap_work_t) :: work
    !> this segment's fits of the mixed cells' interface planes after the
    !> remaps, and refreshes of their centroids before them (and dumps)
    type(centroid_stats_t) :: centroids
  end type euler_state_t

  !> What an Euler step starts from: the totals it must conserve (mass,
  !> momentum, internal and kinetic energy), the scale of its momentum
  !> (sum of |m u| over the nodes) and its rezone's wall time. With exact
  !> false there are no totals: the remap of a whole grid reports what it
  !> changed itself and the scales of the check (`remap_stats_t` change and
  !> scale).
  type :: euler_start_t
    real(wp) :: mass = 0.0_wp, momentum(3) = 0.0_wp, internal = 0.0_wp, kinetic = 0.0_wp, pscale = 0.0_wp
    real(wp) :: t_rezone = 0.0_wp
    logical :: exact = .true.
  end type euler_start_t

contains

  !> Keeps the initial grid (the global rezone's target, the smoothers'
  !> standard grid) and the first interval time, on the grid g the rezone
  !> works on (one process's; a decomposed run's block, or with &rezone mode
  !> 'global' the whole grid's node positions on every rank). Call after
  !> the scene is built, before a restart is read.
  subroutine euler_init(rz, g, bc, one_process, es, err)
    type(rezone_config_t), intent(in) :: rz
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    !> a run on one process (a decomposed run's blocks return to their own
    !> x0 in `driver_whole` and keep no target array)
    logical, intent(in) :: one_process
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    integer :: f, stat
    character(len=200) :: msg
    es%on = trim(rz%mode) /= 'none'
    if (.not. es%on) return
    call rezone_state_init(g, es%rez, err)
    if (one_process .and. .not. allocated(err)) call remap_work_ready(es%work, g%ncell, g%nnode, err)
    if (allocated(err)) return
    ! a global rezone without moving faces returns to x0 at every Euler
    ! step: its target array (x0 itself) and whether x0 is a lattice are
    ! set up here with the grid, so that the first Euler step, like every
    ! other, costs what the cells it changes cost, not a grid-sized copy
    ! and first touch (at 80^3 about 7 ms, five times what its remap costs)
    if (one_process .and. trim(rz%mode) == 'global' .and. &
        all([(global_face_rule(bc%kind(f)), f = 1, 6)] /= GLOBAL_FACE_MOVE)) then
      allocate(es%rez%xkeep, source=es%rez%x0, stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'euler_init', error_no_memory('the global rezone''s target grid'))
        return
      end if
      es%rez%xkeep_x0 = .true.
      es%rez%x0_lattice = merge(1, 0, lattice_nodes(g, es%rez%x0))
    end if
    es%rez%t_next = huge(1.0_wp)
    if (rz%interval_time > 0.0_wp) es%rez%t_next = rz%interval_time
    es%rez%ratio_bound = rz%side_ratio
    es%rez%cos_bound = rz%cos_angle
  end subroutine euler_init

  !> The cells' standard side ratios from the block g's nodes as the deck
  !> set them (`rezone_standard_ratios`; before a restart is read).
  subroutine euler_standard_ratios(g, es, err)
    type(grid_t), intent(in) :: g
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    if (es%on) call rezone_standard_ratios(g, es%rez, err)
  end subroutine euler_standard_ratios

  !> Registers the Euler phase's restart quantities.
  subroutine euler_register_restart(es, reg)
    type(euler_state_t), intent(inout), target :: es
    type(registry_t), intent(inout) :: reg
    call reg%add('t_next_euler', 'time', es%rez%t_next, lower=LOWER_NONNEGATIVE)
    call reg%add('n_euler', '1', es%n, lower=LOWER_NONNEGATIVE)
    call reg%add('euler_ratio_bound', '1', es%rez%ratio_bound, mandatory=.false., lower=LOWER_NONNEGATIVE)
    call reg%add('euler_cos_bound', '1', es%rez%cos_bound, mandatory=.false., lower=LOWER_NONNEGATIVE)
    call reg%add('euler_bound_n', '1', es%rez%bound_n, mandatory=.false., lower=LOWER_NONNEGATIVE)
  end subroutine euler_register_restart

  !> `due` when an Euler step is due after the step just taken
  !> (`rezone_due`: an interval, or the grid's shape against the triggers'
  !> bounds), and the note its log line gives. With `shape` (a decomposed
  !> run: the largest side ratio and smallest cosine of all blocks,
  !> `rezone_shape` and a global reduction) the grid in st is not read, and
  !> the note of where the grid is worst is the caller's (`euler_due_where`).
  subroutine euler_due(rz, st, es, due, shape)
    type(rezone_config_t), intent(in) :: rz
    type(state_t), intent(in) :: st
    type(euler_state_t), intent(inout) :: es
    logical, intent(out) :: due
    real(wp), intent(in), optional :: shape(2)
    logical :: by_shape
    due = .false.
    if (.not. es%on) return
    call rezone_due(rz, es%rez, st%g, st%step, st%t, es%n, due, by_shape, shape)
    es%trigger_note = trim(merge('shape   ', 'interval', by_shape))
    if (by_shape .and. .not. present(shape)) call euler_due_where(st%g, st%halo, es, [es%rez%shape_mine(1), es%rez%shape_mine(2)])
  end subroutine euler_due

  !> The log's note of a step due by the grid's shape (largest side ratio
  !> and smallest cosine, shape, the whole grid's, and the bounds in force,
  !> which &rezone hysteresis may have moved on): the worst cell of each
  !> measure (`rezone_worst_cells`: the one of one process).
  subroutine euler_due_where(g, halo, es, shape)
    type(grid_t), intent(in) :: g
    class(halo_t), intent(in) :: halo
    type(euler_state_t), intent(inout) :: es
    real(wp), intent(in) :: shape(2)
    integer :: ijk(3, 2)
    if (es%trigger_note /= 'shape') return
    ijk = rezone_worst_cells(g, halo, es%rez, shape)
    write(es%trigger_note, '("side ratio ",f0.2," in cell (",i0,",",i0,",",i0,"), cosine ",f0.3," in cell (", &
      &i0,",",i0,",",i0,") (bounds ",f0.4,", ",f0.4,")")') shape(1), ijk(:, 1), shape(2), ijk(:, 2), &
      es%rez%ratio_bound, es%rez%cos_bound
  end subroutine euler_due_where

  !> One Euler step: rezone, remap, new material states; checks
  !> conservation in every build (a breach beyond &rezone conservation_tol
  !> is a runtime failure, never a log line followed by NaN) and logs. With
  !> xrezoned the grid is rezoned already (a decomposed run's, on the whole
  !> grid's node positions: `driver_whole`) and e0 holds what the step
  !> started from (`euler_begin` done).
  subroutine euler_step(rz, st, es, log, err, xrezoned, e0, pe0, single, resume, before)
    type(rezone_config_t), intent(in) :: rz
    type(state_t), intent(inout) :: st
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: xrezoned(:, :)
    type(euler_start_t), intent(in), optional :: e0
    !> with xrezoned: the particles' pre-positioning done with the rezone
    type(particles_euler_t), intent(in), optional :: pe0
    !> one remap, neither in parts nor hybrid (a decomposed run's second
    !> remap of a hybrid step, when it needs the whole grid)
    logical, intent(in), optional :: single
    !> with xrezoned: a step in parts of the way whose first parts the
    !> windows of a decomposed run took (the blocks hold their state), to
    !> go on from there
    type(parts_state_t), intent(in), optional :: resume
    !> with single: what a decomposed run's windows remapped first (the
    !> blocks hold its state), added to this step's statistics
    type(remap_stats_t), intent(in), optional :: before
    type(euler_start_t) :: start
    type(remap_params_t) :: par
    type(remap_stats_t) :: rs
    type(particles_euler_t) :: pe
    type(remap_way_t) :: way
    logical :: done
    real(wp), allocatable :: xnew(:, :)
    integer, allocatable :: written(:)
    integer :: nfar, f
    logical :: one, at_x0, rows, resumed

    if (present(xrezoned)) then
      start = e0
      xnew = xrezoned
      if (present(pe0)) pe = pe0
    else
      ! (st holds the whole grid: its remap reports what it changed)
      call euler_begin(st, es, log, start, scales=.true.)
      call euler_preposition(rz, st, es, pe, err)
      if (allocated(err)) return
      ! (pe%occupied unallocated without particles: absent)
      call euler_rezone(rz, st%g, st%bc, st%share, st%halo, st%step, st%t, es, log, start, xnew, done, err, &
                        pe%occupied)
      if (allocated(err) .or. .not. done) return
      ! the fluid under the solid as the fluid around it (a decomposed run
      ! fills its blocks before their remap)
      if (rz%virtual_layers > 0 .and. st%pt%np > 0 .and. allocated(st%pt%mvf)) then
        call es%t_particles%start()
        call particles_euler_fill(st, rz%virtual_layers, log, nfar, err)
        call es%t_particles%stop()
        if (allocated(err)) then
          call es%timer%stop()
          return
        end if
      end if
    end if
    par = remap_params(rz)
    ! (every rank holds this grid whole: the count and the lattice test are
    ! the whole grid's; only a global rezone returns to a box grid)
    par%lattice = trim(rz%mode) == 'global'
    if (par%lattice .and. all([(global_face_rule(st%bc%kind(f)), f = 1, 6)] /= GLOBAL_FACE_MOVE) .and. &
        size(es%rez%x0, 2) == st%g%nnode) then
      ! (no face moves: the rezone returned x0 itself, tested once)
      if (es%rez%x0_lattice < 0) es%rez%x0_lattice = merge(1, 0, lattice_nodes(st%g, es%rez%x0))
      par%lattice = es%rez%x0_lattice == 1
    else if (par%lattice) then
      par%lattice = lattice_nodes(st%g, xnew)
    end if
    ! (a global rezone without moving faces returns to x0, the grid the
    ! last such Euler step left: where g%moved_rows is kept, only the rows
    ! of nodes the Lagrangian steps moved since are compared; a Debug build
    ! checks every other node)
    at_x0 = .not. present(xrezoned) .and. trim(rz%mode) == 'global' .and. &
            all([(global_face_rule(st%bc%kind(f)), f = 1, 6)] /= GLOBAL_FACE_MOVE) .and. size(es%rez%x0, 2) == st%g%nnode
    rows = at_x0 .and. allocated(st%g%moved_rows)
    if (rows .and. build_checks) call rows_check(st%g, xnew, err)
    if (allocated(err)) then
      call es%timer%stop()
      return
    end if
    ! coupled particles: their share of the nodal momentum goes with them,
    ! taken before the step's first remap (a decomposed run's whole grid
    ! that goes on from the windows' first parts has the windows' share)
    if (allocated(st%pt%mvf)) then
      resumed = .false.
      if (present(resume)) resumed = resume%on .and. resume%plan%ntaken > 0
      if (.not. resumed) then
        call es%t_particles%start()
        call particles_euler_save(st%g, st%h, st%pt, st%pw, st%halo, pe)
        call es%t_particles%stop()
        if (present(pe0)) then
          pe%ke_solid = pe0%ke_solid
          pe%p_solid = pe0%p_solid
        end if
      end if
    end if
    one = .false.
    if (present(single)) one = single
    way = remap_way_t(swept_parts=rz%swept_parts, swept_hybrid=rz%swept_hybrid, global=trim(rz%mode) == 'global')
    call remap_way_step(way, st%g, st%h, st%mx, st%mats, st%bc, st%share, xnew, par, es%work, es%centroids, rs, &
                        written, err, rows, one, resume, before)
    if (allocated(err)) then
      call es%timer%stop()
      return
    end if
    ! (the grid is at xnew: at x0 in every row, or not known to be)
    if (allocated(st%g%moved_rows)) st%g%moved_rows = .not. at_x0
    call remap_after_state(st%mats, st%h, st%mx, written, st%t)
    call euler_finish(rz, st, es, log, start, rs, err)
    ! the particles in the new grid and their share of the nodes rebuilt
    ! (after the fluid's check: the fluid's remap conserves by itself)
    if (.not. allocated(err) .and. st%pt%np > 0) then
      call es%timer%start()
      call es%t_particles%start()
      call particles_euler_finish(st, pe, log, err)
      call es%t_particles%stop()
      call es%timer%stop()
    end if
    ! (the rezoned grid's array for the next step: `euler_state_t` xkeep)
    if (.not. present(xrezoned)) call move_alloc(xnew, es%rez%xkeep)

  end subroutine euler_step

  !> (Debug) Every node of g in a row g%moved_rows does not flag is at
  !> xnew: the Lagrangian steps noted every node they moved.
  subroutine rows_check(g, xnew, err)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: xnew(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer :: bad
    bad = grid_unflagged_move(g, xnew)
    if (bad < 0) then
      call error_set(err, 'euler_step', 'the moved-row flags do not match the grid')
    else if (bad > 0) then
      call error_set(err, 'euler_step', 'node '//itoa(bad)//' moved, but its row was not noted as moved')
    end if
  end subroutine rows_check

  !> Remark 2 (Sect. 5.2), before a smoothing rezone (lssm, smooth): the
  !> particles of st (the whole grid's) placed in the standard grid (es%rez%x0,
  !> or x0 given: a decomposed run's whole grid); the cells they occupy
  !> there (pe%occupied) are the smoothing's fixed inner boundary. On an
  !> error the Euler step's timer stops.
  subroutine euler_preposition(rz, st, es, pe, err, x0)
    type(rezone_config_t), intent(in) :: rz
    type(state_t), intent(in) :: st
    type(euler_state_t), intent(inout) :: es
    type(particles_euler_t), intent(inout) :: pe
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: x0(:, :)
    if (st%pt%np == 0 .or. .not. (trim(rz%mode) == 'lssm' .or. trim(rz%mode) == 'smooth')) return
    call es%t_particles%start()
    if (present(x0)) then
      call particles_euler_preposition(st, x0, pe, err)
    else
      call particles_euler_preposition(st, es%rez%x0, pe, err)
    end if
    call es%t_particles%stop()
    if (allocated(err)) call es%timer%stop()
  end subroutine euler_preposition

  !> How the log's Euler line says which path the remap took.
  function swept_text(rs) result(text)
    type(remap_stats_t), intent(in) :: rs
    character(len=:), allocatable :: text
    if (rs%hybrid) then
      text = ' in two remaps ('//itoa(rs%cells_swept)//' by swept faces, then '// &
             itoa(rs%cells_remapped - rs%cells_swept)//' by intersection: the '//itoa(rs%swept_blockers)// &
             ' that could not sweep and the cells around them)'
    else if (rs%swept_parts > 1) then
      text = ' in '//itoa(rs%swept_parts)//' parts of the way ('//itoa(rs%cells_swept)//' by swept faces; '// &
             itoa(rs%swept_blockers)//' could not sweep it at once; '//itoa(rs%swept_splits)// &
             ' parts split for a broken bound'
      if (rs%swept_rescued > 0) text = text//'; '//itoa(rs%swept_rescued)// &
        ' parts intersected only around the cells that could not sweep them'
      text = text//')'
    else if (rs%cells_swept > 0) then
      text = ' by swept faces'
    else if (rs%swept_unbounded > 0) then
      text = ' by intersection (by swept faces '//itoa(rs%swept_unbounded)//' broke a material''s bounds)'
    else if (rs%swept_blockers > 0 .and. rs%cells_remapped > 0) then
      text = ' by intersection ('//itoa(rs%swept_blockers)//' could not sweep)'
    else
      text = ' by intersection'
    end if
  end function swept_text

  !> The remap's settings from the deck.
  function remap_params(rz) result(par)
    type(rezone_config_t), intent(in) :: rz
    type(remap_params_t) :: par
    par%linear = trim(rz%reconstruction) == 'linear'
    par%mof_max_iter = rz%mof_max_iter
    par%swept_max = rz%swept_max
    par%swept_mixed = rz%swept_mixed
    par%swept_vf_min = rz%swept_vf_min
  end function remap_params

  !> An Euler step begins: its log line, its timer, and the totals it must
  !> conserve (st: the whole grid, or a block of a decomposed run; the
  !> totals are exact sums, the same on any rank count).
  subroutine euler_begin(st, es, log, e0, scales)
    type(state_t), intent(in) :: st
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    type(euler_start_t), intent(out) :: e0
    !> true: no totals (`euler_start_t`; st a whole grid, whose remap
    !> reports its changes and scales); absent: exact totals
    logical, intent(in), optional :: scales
    call log_line(log, 'euler '//itoa(es%n + 1)//' due at step '//itoa(st%step)//': '//trim(es%trigger_note))
    call es%timer%start()
    if (present(scales)) e0%exact = .not. scales
    if (e0%exact) call euler_start_totals(st, e0)
  end subroutine euler_begin

  !> The exact totals an Euler step's conservation check compares with
  !> (`euler_begin`), of st as it is now.
  subroutine euler_start_totals(st, e0)
    type(state_t), intent(in) :: st
    type(euler_start_t), intent(inout) :: e0
    call hydro_totals(st%g, st%h, st%halo, e0%mass, e0%momentum, e0%internal, e0%kinetic, e0%pscale)
  end subroutine euler_start_totals

  !> The rezone of an Euler step: back to the initial grid, with moving
  !> faces followed (&rezone mode 'global'), or smoothing ('lssm',
  !> 'smooth'), of the grid g: one process's, a decomposed run's block
  !> (halo: its ghosts and global reductions; the smoothing only), or the
  !> whole grid's node positions on every rank (share: the ranks that share
  !> its quality measures). occupied: g's cells that particles occupy in
  !> the standard grid. xnew: the rezoned grid; done false (the step
  !> skipped, its interval used up, its timer stopped) if no cell needs it,
  !> or on an error. pc: a decomposed run's ranks, whose blocks' smoothing
  !> runs on blocks cut for its work (`rezone_balanced`; collective).
  subroutine euler_rezone(rz, g, bc, share, halo, step, t, es, log, e0, xnew, done, err, occupied, standard, pc)
    type(rezone_config_t), intent(in) :: rz
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    class(share_t), intent(in), optional :: share
    class(halo_t), intent(inout) :: halo
    integer, intent(in) :: step
    real(wp), intent(in) :: t
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    type(euler_start_t), intent(inout) :: e0
    real(wp), allocatable, intent(out) :: xnew(:, :)
    logical, intent(out) :: done
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: occupied(:)
    !> a block's standard grid where faces move (`rezone_grid`)
    real(wp), intent(in), optional :: standard(:, :)
    type(comm_t), intent(in), optional :: pc
    integer :: nmove
    type(lssm_report_t) :: rep

    e0%t_rezone = wall_seconds()
    if (present(pc)) then
      call rezone_balanced(pc, rz, g, bc, halo, step, es%rez, es%bal, xnew, rep, nmove, done, err, occupied, standard)
    else
      call rezone_grid(rz, g, bc, share, halo, step, es%rez, xnew, rep, nmove, done, err, occupied, standard)
    end if
    if (.not. allocated(err)) then
      if (present(pc) .and. done) then
        if (es%bal%taken) call log_line(log, 'lssm: smoothed on blocks cut for its work ('//cuts_text(pc, es%bal%cuts)//')')
      end if
      if (trim(rz%mode) == 'lssm' .or. trim(rz%mode) == 'smooth') then
        call lssm_log(rz, rep, step, log)
      else if (nmove > 0) then
        call log_line(log, 'global rezone: '//itoa(nmove)//' nodes of moving faces kept where they are, '// &
                      'the others back to the initial grid plus the TFI of their displacement')
      end if
    end if
    if (allocated(err) .or. .not. done) then
      ! a skipped step still uses up its interval (else the interval
      ! trigger fires, and is skipped, at every following step)
      call rezone_rearm(rz, es%rez, t)
      call es%timer%stop()
      done = .false.
      return
    end if
    e0%t_rezone = wall_seconds() - e0%t_rezone
    es%t_rezone_total = es%t_rezone_total + e0%t_rezone
  end subroutine euler_rezone

  !> The cuts (as comm_t%cuts) of the directions pc's layout cuts, for the
  !> log: 'k planes 0 9 24' and the like.
  function cuts_text(pc, cuts) result(text)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: cuts(:)
    character(len=:), allocatable :: text
    integer :: d, b, c0
    text = ''
    c0 = 0
    do d = 1, 3
      if (pc%dims(d) > 1) then
        if (len(text) > 0) text = text//', '
        text = text//'ijk'(d:d)//' planes'
        do b = 0, pc%dims(d)
          text = text//' '//itoa(cuts(c0 + 1 + b))
        end do
      end if
      c0 = c0 + pc%dims(d) + 1
    end do
  end function cuts_text

  !> An Euler step's end, once the remapped state is in st (the whole grid,
  !> or a decomposed run's blocks) and rs says what the remap did (on a
  !> decomposed run: summed over the ranks): its count, the next interval,
  !> the log and the conservation check against e0.
  subroutine euler_finish(rz, st, es, log, e0, rs, err)
    type(rezone_config_t), intent(in) :: rz
    type(state_t), intent(inout) :: st
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    type(euler_start_t), intent(in) :: e0
    type(remap_stats_t), intent(in) :: rs
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: m0, e0tot, m1, p1(3), ie1, ke1, pscale, dm, de, dp(3)
    character(len=1000) :: line
    character(len=40) :: shared, scales

    es%n = es%n + 1
    call rezone_rearm(rz, es%rez, st%t)
    call es%timer%stop()
    ! the check's scales: the totals, or the magnitudes of what the remap
    ! wrote (then the change relative to what was remapped)
    m0 = e0%mass
    e0tot = e0%internal + e0%kinetic
    pscale = e0%pscale
    scales = ''
    if (rs%change_known) then
      m0 = rs%scale(1)
      e0tot = rs%scale(2)
      pscale = rs%scale(3)
      scales = ' (of what was remapped)'
    end if
    shared = ''
    if (rs%parts > 1) shared = ' shared by '//itoa(rs%parts)//' ranks'
    if (rs%parts < 0) shared = ' in '//itoa(-rs%parts)//' windows'
    ! what came in and went out through open faces is external work
    st%tot%boundary_work = st%tot%boundary_work + rs%energy_in - rs%energy_out
    ! the changes of mass, total energy and momentum
    if (rs%change_known) then
      ! (what the remap wrote, before and after: `remap_stats_t`)
      dm = xsum_value(rs%change(1))
      dp = [xsum_value(rs%change(2)), xsum_value(rs%change(3)), xsum_value(rs%change(4))]
      de = xsum_value(rs%change(5)) + xsum_value(rs%change(6))
    else if (e0%exact) then
      call hydro_totals(st%g, st%h, st%halo, m1, p1, ie1, ke1)
      dm = m1 - m0
      dp = p1 - e0%momentum
      de = ie1 + ke1 - e0tot
    else
      call error_set(err, 'euler_finish', 'internal: a window''s remap after an Euler step begun without totals')
      return
    end if
    dm = dm - rs%mass_in + rs%mass_out
    de = de - rs%energy_in + rs%energy_out
    dp = dp + rs%momentum_constrained - rs%momentum_in + rs%momentum_out
    write(line, '("euler ",i0," at step ",i0,", t = ",es12.5,": ",i0," cells remapped",a,", ",i0," copied, reach ",i0, &
      &", volume defect ",es8.1,", old-cell defect ",es8.1," (",i0," rescaled), ",i0," slivers merged", &
      &"; MoF ",i0," cells (",i0," by their carried planes), ",f5.2," iterations, ",i0, &
      &" capped, centroid error/size ",es8.1, &
      &"; KE to internal ",es10.3,"; rezone ",f8.3," s, remap ",f8.3," s (prepare ",f7.3,", intersect ",f7.3, &
      &a,", assemble ",f7.3,"), ",f0.2," us per remapped cell")') &
      es%n, st%step, st%t, rs%cells_remapped, swept_text(rs), &
      rs%cells_copied, rs%reach, rs%volume_defect, &
      rs%given_defect, rs%regions_rescaled, rs%slivers_merged, rs%mof_cells, rs%mof_carried, &
      real(rs%mof_iterations, wp)/real(max(rs%mof_cells - rs%mof_carried, 1), wp), rs%mof_not_converged, &
      rs%mof_err_max, &
      rs%ke_to_internal, e0%t_rezone, rs%t_prepare + rs%t_intersect + rs%t_assemble, rs%t_prepare, rs%t_intersect, &
      trim(shared), &
      rs%t_assemble, 1.0e6_wp*(rs%t_prepare + rs%t_intersect + rs%t_assemble)/real(max(rs%cells_remapped, 1), wp)
    call log_line(log, trim(line))
    write(line, '("  conservation: relative change of mass ",es9.2,", momentum ",es9.2,", total energy ",es9.2,a, &
      &"; momentum taken by velocity conditions ",3es10.2)') abs(dm)/max(m0, tiny(1.0_wp)), &
      norm2(dp)/max(pscale, tiny(1.0_wp)), abs(de)/max(abs(e0tot), tiny(1.0_wp)), trim(scales), &
      rs%momentum_constrained
    call log_line(log, trim(line))
    if (rs%cells_deficit > 0) then
      write(line, '("  kinetic energy deficits beyond the energy around their nodes: ",i0," cells, ",es10.3, &
        &" taken from the nearest cells with energy, ",es10.3," by mass")') rs%cells_deficit, &
        rs%deficit_moved - rs%deficit_by_mass, rs%deficit_by_mass
      call log_line(log, trim(line))
    end if
    if (rs%mass_in > 0.0_wp .or. abs(rs%mass_out) > 0.0_wp) then
      write(line, '("  open faces: mass in ",es12.5," out ",es12.5,"; energy in ",es12.5," out ",es12.5)') &
        rs%mass_in, rs%mass_out, rs%energy_in, rs%energy_out
      call log_line(log, trim(line))
    end if
    es%cells = es%cells + rs%cells_remapped
    es%cells_swept = es%cells_swept + rs%cells_swept
    es%t_remap = es%t_remap + (rs%t_prepare + rs%t_intersect + rs%t_assemble)
    if (rs%cells_remapped > rs%cells_swept) then
      es%n_intersecting = es%n_intersecting + 1
      es%cells_intersecting = es%cells_intersecting + rs%cells_remapped
      es%t_remap_intersecting = es%t_remap_intersecting + (rs%t_prepare + rs%t_intersect + rs%t_assemble)
    end if
    es%mof = es%mof + rs%mof_cells
    es%mof_carried = es%mof_carried + rs%mof_carried
    es%mof_iterations = es%mof_iterations + rs%mof_iterations
    es%ke = es%ke + rs%ke_to_internal
    ! (not .not. <=: a NaN total fails too)
    if (.not. abs(dm) <= rz%conservation_tol*m0) then
      call error_set(err, 'euler_step', 'Euler step '//itoa(es%n)//' did not conserve mass: change '//rtoa(dm)// &
                     ' of '//rtoa(m0)//trim(scales)//' (&rezone conservation_tol '//rtoa(rz%conservation_tol)//')', &
                     ERR_RUNTIME)
    else if (.not. abs(de) <= rz%conservation_tol*abs(e0tot)) then
      call error_set(err, 'euler_step', 'Euler step '//itoa(es%n)//' did not conserve total energy: change '// &
                     rtoa(de)//' of '//rtoa(e0tot)//trim(scales)//' (&rezone conservation_tol '// &
                     rtoa(rz%conservation_tol)//')', ERR_RUNTIME)
    else if (.not. norm2(dp) <= rz%conservation_tol*max(pscale, tiny(1.0_wp))) then
      call error_set(err, 'euler_step', 'Euler step '//itoa(es%n)//' did not conserve momentum: change '// &
                     rtoa(norm2(dp))//' of '//rtoa(pscale)//trim(scales)//' (&rezone conservation_tol '// &
                     rtoa(rz%conservation_tol)//')', ERR_RUNTIME)
    end if
  end subroutine euler_finish

  !> The log's line of a smoothing rezone at step `step` (`lssm_rezone`).
  subroutine lssm_log(rz, rep, step, log)
    type(rezone_config_t), intent(in) :: rz
    type(lssm_report_t), intent(in) :: rep
    integer, intent(in) :: step
    type(log_t), intent(in) :: log
    character(len=600) :: line
    character(len=60) :: kept, grown
    grown = ''
    if (rep%ngrown > 0) write(grown, '(" (",i0," of them beside a cell a snap inverted)")') rep%ngrown
    select case (rep%outcome)
    case (LSSM_SNAPPED)
      call log_line(log, trim(rz%mode)//' at step '//itoa(step)//': no cell to smooth; '//itoa(rep%snapped)// &
                    ' nodes put back on the standard grid'//trim(grown))
    case (LSSM_SKIPPED)
      if (rep%box) then
        call log_line(log, 'euler step skipped at step '//itoa(step)//': no cell fails the triggers'' tests')
      else
        call log_line(log, 'euler step skipped at step '//itoa(step)//': no cell has Q < '//rtoa(rz%quality))
      end if
    case default
      kept = ''
      if (rz%move_min > 0.0_wp) write(kept, '("; ",i0," nodes moved < move_min kept")') rep%kept
      write(line, '(a," at step ",i0,": ",i0," distorted cells, ",i0," subdomains, ",i0," cells smoothed (Q_min ", &
        &f7.4," -> ",f7.4," after ",i0," iterations",a,")",a,"; untangling guard: ",i0," moves halved, ",i0, &
        &" nodes put back, ",i0," node moves untangling first; ",i0," nodes back on the standard grid first",a)') &
        trim(rz%mode), step, rep%distorted, rep%subdomains, rep%smoothed, rep%q_min0, rep%q_min, rep%iterations, &
        trim(merge(', then TFI', '          ', rep%tfi)), trim(kept), rep%guarded, rep%reverted, rep%untangled, &
        rep%snapped, trim(grown)
      call log_line(log, trim(line))
    end select
  end subroutine lssm_log



  !> Summary line of the run's Euler steps.
  subroutine euler_report(es, log)
    type(euler_state_t), intent(in) :: es
    type(log_t), intent(in) :: log
    character(len=300) :: line
    if (.not. es%on) return
    write(line, '("euler steps: ",i0,", cells remapped ",i0," (",es10.3," per second of remap), MoF ",i0, &
      &" cells (",i0," by their carried planes, the others ",f5.2," iterations), KE returned to internal energy ", &
      &es10.3,"; rezone ",f9.3," s")') &
      es%n, es%cells, real(es%cells, wp)/max(es%timer%total - es%t_rezone_total, tiny(1.0_wp)), es%mof, &
      es%mof_carried, real(es%mof_iterations, wp)/real(max(es%mof - es%mof_carried, 1), wp), es%ke, es%t_rezone_total
    call log_line(log, trim(line))
    ! where the remap's time went: the steps that intersected some cells
    ! cost one to two orders of magnitude more per cell than swept faces
    write(line, '("euler paths: ",i0," cells by swept faces, ",i0," by intersection; ",i0, &
      &" of the ",i0," Euler steps intersected some cells (",i0," cells remapped in them,",f9.3, &
      &" s of the remap''s",f9.3," s)")') es%cells_swept, es%cells - es%cells_swept, es%n_intersecting, es%n, &
      es%cells_intersecting, es%t_remap_intersecting, es%t_remap
    call log_line(log, trim(line))
    if (es%t_particles%total > 0.0_wp) then
      write(line, '("euler particles: ",f9.3," s of the Euler phase''s",f9.3," s (placed, fluid under them filled, ", &
        &"their nodal share saved, relocated, coupled)")') es%t_particles%total, es%timer%total
      call log_line(log, trim(line))
    end if
  end subroutine euler_report
end module driver_euler
