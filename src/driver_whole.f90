!> What a decomposed run's Euler phase and particles need beyond each
!> rank's block.
!>
!> Euler steps on windows: each rank holds a window, its block widened by
!> the cells its remap reads (a box of the whole grid, built from the deck
!> once). At an Euler step each block smooths its own nodes (`lssm_rezone`
!> with the block's halo: LSSM's subdomains seeded from all blocks'
!> distorted cells, the ghosts refreshed after every pass) or takes its
!> own nodes' target of the global rezone (its initial nodes, or from the
!> grid's faces gathered where a face moves: `window_global_target`), then
!> every rank gathers its window's new nodes and old state from the blocks
!> that own them (`gather_box`), remaps it (`remap_zone_t`) and takes its
!> block back from it; a step in parts of the way (&rezone swept_parts)
!> does so part by part, each part's grid decided from the blocks' owned
!> cells as one process decides it on the whole grid (`window_part`).
!> Kinetic energy deficits are repaired over the windows
!> (`window_deficits`), and a search that went further than the windows
!> reach is done again on windows widened until it fits. A step that needs
!> more than that (an old region the new grid does not cover, swept faces
!> that broke a material's bounds, deficits with either) is done on the
!> whole grid instead (a step in parts from the part that needed it): every
!> rank builds the whole state for it, computes the step alike (the
!> intersections and MoF shared over the ranks, `base_share`), takes its
!> block back and lets the whole state go. Either way the result is the
!> single process's, bit for bit.
!>
!> Open faces: each window bins its own moved old cells for the gap
!> search, the open faces' innermost points are the blocks' extremes
!> reduced, and the far old cells that reach past an open face are sent
!> only to the windows that may want them (`window_zone_open`); the flows
!> through the faces are exact sums added over the ranks.
!>
!> Particles at an Euler step: each block places the ones it holds in the
!> standard grid (Remark 2: the cells they occupy freeze the smoothing),
!> relocates them in its rezoned cells and sends them to the blocks that
!> hold their new hosts (`particles_euler_blocks`), then couples them to
!> its nodes (`particles_euler_couple`: the nodal sums of its owned nodes
!> are complete, its ghost nodes get their owners' values), the energy sums
!> exact over the blocks. A walk that would step past a block's cut is
!> taken on by the blocks beyond (`parallel_walks`); where such a walk
!> ends in no cell every rank gathers the particles in the whole run's
!> order, with the whole grid's node positions, and relocates them alike
!> (`window_particles`).
!>
!> Restart dumps: the ranks write their blocks into one file together
!> (`whole_dump`), the file of one process, so a dump written on P ranks
!> continues on any Q; each rank reads its block from it (`read_restart`).
!>
!> What is copied is what a restart holds (the quantities the packages
!> register, `base_registry`), then what a restart read rebuilds from them
!> (`state_after_read`, the materials' cell lists): a state made this way
!> continues exactly as the one it was copied from, which the restart tests
!> check for every registered quantity. Node and cell arrays go through the
!> blocks' owned ranges (`parallel_gather`); the mixed cells through their
!> owned cells, renumbered and put back in cell order (the order one
!> process keeps them in).
module driver_whole
  use base_sort, only: sort_order, sorted_runs
  use base_timers, only: wall_seconds
  use lagrange_centroids, only: centroid_stats_t, centroids_refresh
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set, error_no_memory
  use base_registry, only: registry_t, registry_entry_t, LOC_GLOBAL, LOC_NODE, LOC_CELL, K_REAL, K_INT, &
                           K_REAL_SCALAR, K_INT_SCALAR, LOC_MIXED_CELL, LOC_MIXED_SLOT, LOC_PARTICLE
  use material_mixed, only: mixed_t, mixed_allocate, mixed_subset
  use mesh_halo, only: halo_t
  use material_table, only: material_index_cells
  use io_log, only: log_t, log_line
  use base_strings, only: itoa
  use particles_state, only: particles_t, particles_index
  use driver_particles, only: build_particles, particles_gathered, particles_blocks_share, particles_take, &
                              particles_euler_relocate, particles_euler_couple, count_hosts, particles_euler_fill, &
                              particles_euler_blocks, particles_preposition_blocks, particles_euler_preposition
  use particles_lagrange, only: strength_slot_t
  use particles_euler, only: particles_euler_t, particles_euler_save
  use parallel_comm, only: comm_t, parallel_sum, parallel_max, parallel_min, parallel_nomem, parallel_send, parallel_recv, &
                           parallel_balance, parallel_block
  use parallel_share, only: mpi_share_t, mpi_share_init
  use parallel_gather, only: gather_nodes, gather_box, gather_box_fields, gather_field_t, gather_concat, exchange_lists, cell_prefix
  use mesh_grid, only: grid_t, grid_index_t, grid_index, grid_index_block, grid_rows, grid_copy_rows_real, &
                       grid_copy_rows_int
  use mesh_boundary, only: BC_INFLOW, BC_OUTFLOW
  use rezone_driver, only: rezone_shape, rezone_interval_due
  use rezone_global, only: global_face_rule, GLOBAL_FACE_MOVE, global_surface_init, global_face_box, &
                           global_face_parameters, global_surface_solve, global_block_target, global_target_check, &
                           global_line_sums, global_line_scale
  use remap_lattice, only: lattice_nodes
  use remap_euler, only: remap_zone_t, remap_stats_t, remap_params_t, remap_euler_step, remap_zone_open, &
                         remap_zone_block, remap_zone_beyond, remap_zone_reach_box, remap_zone_wants, remap_zone_far, &
                         remap_hybrid_target, remap_stats_add, remap_stats_flows, remap_swept_blockers, &
                         remap_part_target, remap_part_folded, remap_part_uniform, remap_change_rings
  use lagrange_centroids, only: centroids_remember, plane_memory_t
  use remap_after, only: remap_after_planes, remap_after_state
  use remap_parts, only: remap_parts_t
  use driver_config, only: config_t
  use driver_state, only: state_t, state_register_restart, state_after_read, state_totals
  use driver_scene, only: build_scene
  use driver_euler, only: euler_state_t, euler_start_t, euler_due, euler_due_where, euler_step, euler_begin, &
                          euler_rezone, euler_finish, remap_params, euler_preposition, cuts_text
  use remap_way, only: parts_state_t
  use parallel_euler, only: remap_work, cut_plane_cells, balance_planes, active_window
  use driver_output, only: schedule_t, report_conservation
  use driver_parallel, only: agree_error
  use io_restart, only: restart_part_t
  use driver_restart, only: write_restart, read_restart, mixed_of_block, mixed_numbers
  implicit none
  private
  public :: whole_build, whole_euler, whole_dump, whole_restart, whole_gather, whole_scatter, global_whole

  !> The windows of an Euler step on several ranks (`window_euler`) first
  !> hold a search for a new cell's old cells within this many index steps
  !> (doubled, and the windows widened, when a step needs more).
  integer, parameter :: window_reach_first = 2

contains

  !> What a decomposed run needs beyond its blocks before its first step
  !> (nothing on one process): its particles, seeded on the blocks
  !> (`build_particles`; a restart then reads them on the blocks,
  !> `read_restart`, and tracked particles are chosen over the blocks,
  !> `tracks_init`), and the windows of its Euler steps (`window_build`).
  subroutine whole_build(cfg, pc, st, log, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    if (pc%nranks == 1) return
    if (size(cfg%particles) > 0) then
      call build_particles(cfg, st, log, err, pc)
      if (.not. allocated(err)) call state_totals(st)
      st%tot%energy_initial = st%tot%internal + st%tot%kinetic
      call agree_error(pc, err)
    end if
    if (.not. allocated(err) .and. trim(cfg%rezone%mode) /= 'none') call window_build(cfg, pc, st, err)
  end subroutine whole_build

  !> st%whole built from the deck on the whole grid, its Euler steps' work
  !> shared by the ranks.
  subroutine whole_state_build(cfg, pc, st, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(error_t), allocatable, intent(inout) :: err
    type(log_t) :: silent
    type(mpi_share_t) :: share
    integer :: stat
    allocate(st%whole, stat=stat)
    if (stat /= 0) then
      call error_set(err, 'whole_build', 'out of memory for the whole grid''s state')
      return
    end if
    silent%quiet = .true.   ! (the blocks' scene has been logged)
    ! (a &prerun's 1D run is the blocks')
    if (allocated(st%pre1d)) then
      allocate(st%whole%pre1d, source=st%pre1d, stat=stat)
      if (stat /= 0) then
        call error_set(err, 'whole_build', 'out of memory for the whole grid''s state')
        return
      end if
    end if
    call build_scene(cfg, st%whole, silent, err, remap_only=.true.)
    if (.not. allocated(err)) then
      ! the ranks share the Euler step's intersections on the whole grid
      call mpi_share_init(share, pc)
      allocate(st%whole%share, source=share, stat=stat)
      if (stat /= 0) call error_set(err, 'whole_build', 'out of memory')
    end if
  end subroutine whole_state_build

  !> The Euler phase of a decomposed run works on windows (`window_euler`):
  !> st%win (`window_resize`), st%gw (the
  !> whole grid's index; its node positions gathered where particles need
  !> them, `window_euler`) and st%share.
  subroutine window_build(cfg, pc, st, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(error_t), allocatable, intent(inout) :: err
    type(mpi_share_t) :: share
    integer :: stat
    allocate(st%gw, stat=stat)
    if (stat /= 0) then
      call error_set(err, 'window_build', 'out of memory for the Euler phase''s window')
      return
    end if
    st%win_block = st%g%grid_index_t
    st%win_cuts = pc%cuts
    call window_resize(cfg, st, window_reach_first, err)
    call agree_error(pc, err)
    if (allocated(err)) return
    st%gw%grid_index_t = grid_index(st%g%gn(1), st%g%gn(2), st%g%gn(3))
    call mpi_share_init(share, pc)
    allocate(st%share, source=share, stat=stat)
    if (stat /= 0) call error_set(err, 'window_build', 'out of memory')
  end subroutine window_build

  !> st%win, this rank's window for a search within `reach` index steps:
  !> its block (st%win_block) widened by window_margin(ng, reach) cells
  !> (within the grid; `window_full`), or the part of it from box(:, 1) to
  !> box(:, 2) (`window_active`), built from the deck as a single block at
  !> its place in the whole grid; st%win_back the block's stored cells.
  subroutine window_resize(cfg, st, reach, err, box)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout), target :: st
    integer, intent(in) :: reach
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: box(3, 2)
    type(log_t) :: silent
    type(grid_index_t) :: ix
    integer :: stat, w(3, 2)
    w = window_full(st%win_block, reach)
    if (present(box)) w = box
    ix = grid_index_block(w(:, 2) - w(:, 1) + 1, [0, 0, 0], [0, 0, 0], w(:, 1) - 1, st%g%gn)
    st%win_back = window_kept(st%win_block)
    if (allocated(st%win)) deallocate(st%win)
    allocate(st%win, stat=stat)
    if (stat /= 0) then
      call error_set(err, 'window_resize', 'out of memory for the Euler phase''s window')
      return
    end if
    st%win_reach = reach
    silent%quiet = .true.   ! (the blocks' scene has been logged)
    call build_scene(cfg, st%win, silent, err, ix, fluid_only=.true.)
  end subroutine window_resize

  !> The cells (whole-grid indices, lo then hi) of the window around block
  !> b for a search within reach: b's owned cells widened by
  !> window_margin(ng, reach) cells, within the grid.
  pure function window_full(b, reach) result(w)
    type(grid_index_t), intent(in) :: b
    integer, intent(in) :: reach
    integer :: w(3, 2)
    w(:, 1) = max(1, b%clo + b%off - window_margin(b%ng, reach))
    w(:, 2) = min(b%gn, b%chi + b%off + window_margin(b%ng, reach))
  end function window_full

  !> The new cells of a window computed around the block: its ghost layers
  !> and the cells around their nodes (one more layer), and the reach of
  !> the search (every new cell an owned old cell may give to).
  pure integer function window_compute(ng, reach)
    integer, intent(in) :: ng, reach
    window_compute = max(ng + 1, reach)
  end function window_compute

  !> A window's width around its block: the computed cells, the old cells
  !> within reach of them and the stencils of their gradients (two layers).
  pure integer function window_margin(ng, reach)
    integer, intent(in) :: ng, reach
    window_margin = window_compute(ng, reach) + reach + 2
  end function window_margin

  !> The Euler phase of a decomposed run after a Lagrangian step: whether it
  !> is due (the quality triggers from each block's owned cells, reduced:
  !> a maximum and a minimum, exact in any order), then the Euler step on
  !> the ranks' windows (`window_euler`), each block taken back from it.
  subroutine whole_euler(cfg, pc, st, es, log, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: shape(2)
    logical :: due
    if (.not. es%on) return
    shape = [0.0_wp, 1.0_wp]
    ! (as one process: no look when an interval makes the step due,
    ! `rezone_interval_due`)
    if ((cfg%rezone%side_ratio > 0.0_wp .or. cfg%rezone%cos_angle > 0.0_wp) .and. &
        .not. rezone_interval_due(cfg%rezone, es%rez, st%step, st%t)) then
      call rezone_shape(cfg%rezone, st%g, st%step, es%rez)
      shape = es%rez%shape_mine
      call parallel_max(pc, shape(1:1))
      call parallel_min(pc, shape(2:2))
    end if
    call euler_due(cfg%rezone, st, es, due, shape)
    if (due) call window_euler(cfg, pc, st, es, log, shape, err)
  end subroutine whole_euler

  !> An Euler step on windows (module header). Each block smooths its nodes
  !> (&rezone mode 'lssm' or 'smooth': `lssm_rezone` on the block, its
  !> ghosts refreshed after every pass), or every rank rezones the whole
  !> grid's node positions (gathered; mode 'global'); then each rank remaps
  !> its window: the new cells of its block and window_compute layers
  !> around it, whose results are right when the old cells within
  !> st%win_reach of them are in the window. When a remap needs more than
  !> the windows hold, on any rank, the step is done on the whole grid
  !> instead (`whole_gather`, the whole state built for it and let go
  !> after), and if the search fell short the windows are widened (its reach
  !> doubled). Particles: each block places the ones it owns in its
  !> standard cells before a smoothing rezone (Remark 2: the cells they
  !> occupy are the smoothing's fixed inner boundary,
  !> `particles_preposition_blocks`), relocates them in its rezoned cells
  !> after the remap and sends them to the blocks that hold their new hosts
  !> (`particles_euler_blocks`; those that leave through an open face leave
  !> there; walks past a block's cut are taken on by the blocks beyond);
  !> where a walk taken on ends in no cell every rank gathers them all (in
  !> the whole run's order), relocates them in the rezoned grid, the same on
  !> every rank, and each block takes its own (`window_particles`). The
  !> whole grid's node positions are gathered only then.
  subroutine window_euler(cfg, pc, st, es, log, shape, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    real(wp), intent(in) :: shape(2)
    type(error_t), allocatable, intent(inout) :: err
    type(euler_start_t) :: e0
    type(particles_euler_t) :: pe
    type(parts_state_t) :: ps
    type(state_t) :: sw
    real(wp), allocatable :: xnew(:, :), xb(:, :), x(:, :), xs(:, :)
    logical, allocatable :: occupied(:)
    type(remap_stats_t) :: first
    logical :: done, redo, wider, parts, global, moving, whole_x
    integer :: retry
    integer :: c, f, nfill, one

    global = trim(cfg%rezone%mode) == 'global'
    moving = global_whole(cfg, st)
    parts = st%pblocks
    ! a smoothing rezone's pre-positioning (Remark 2) on the blocks, else
    ! on the whole grid's particles and nodes, on every rank (whole_x)
    whole_x = .false.
    if (parts .and. .not. global) then
      call particles_preposition_blocks(pc, st, es%rez%x0, pe, log, done)
      whole_x = .not. done
      if (whole_x) call log_line(log, '  particles: placed in the standard grid and relocated on the whole grid (a '// &
                                 'walk ended in no cell of the whole grid, and not out through an open face)')
    end if
    if (whole_x) then
      call gather_nodes(pc, st%g%grid_index_t, st%g%x, x, all=.true.)
      call move_alloc(x, st%gw%x)
    end if
    call euler_due_where(st%g, st%halo, es, shape)
    ! (no totals: the windows' remaps report what they changed, summed over
    ! the blocks, and so does the whole grid's where it takes over)
    call euler_begin(st, es, log, e0, scales=.true.)
    if (whole_x) then
      ! (sw: the whole grid's nodes and particles, on every rank, placed in
      ! the standard grid, whole)
      call whole_particles(pc, st, sw, err)
      if (.not. allocated(err)) then
        call gather_nodes(pc, st%g%grid_index_t, es%rez%x0, x, all=.true.)
        call euler_preposition(cfg%rezone, sw, es, pe, err, x)
      end if
      call agree_error(pc, err)
      if (allocated(err)) return
    end if
    if (moving) then
      ! (each block's target, from the grid's faces)
      call window_global_target(pc, st, es, log, e0, xb, err)
      done = .true.
      if (.not. allocated(err) .and. whole_x) call gather_nodes(pc, st%g%grid_index_t, xb, xnew, all=.true.)
    else if (global) then
      ! (back to the initial grid: each block's own, es%rez%x0)
      xb = es%rez%x0
      done = .true.
      e0%t_rezone = 0.0_wp
      if (whole_x) call gather_nodes(pc, st%g%grid_index_t, xb, xnew, all=.true.)
    else
      if (pe%on_blocks) then
        occupied = pe%occupied
      else if (allocated(pe%occupied)) then
        occupied = [(pe%occupied(st%g%global_cell(c)), c = 1, st%g%ncell)]
      end if
      ! (with faces that move with the material the smoothing's standard
      ! places follow them: each block's part of the global rezone's
      ! target, `rezone_grid`)
      done = .false.
      if (any([(global_face_rule(st%bc%kind(f)), f = 1, 6)] == GLOBAL_FACE_MOVE)) &
        call window_global_target(pc, st, es, log, e0, xs, err, report=.false.)
      if (.not. allocated(err)) &
        call euler_rezone(cfg%rezone, st%g, st%bc, halo=st%halo, step=st%step, t=st%t, es=es, log=log, e0=e0, &
                          xnew=xb, done=done, err=err, occupied=occupied, standard=xs, pc=pc)
      if (done .and. whole_x) call gather_nodes(pc, st%g%grid_index_t, xb, xnew, all=.true.)
    end if
    call agree_error(pc, err)
    if (allocated(err) .or. .not. done) return
    ! (without particles, a smoothing rezone's remap on windows around
    ! blocks cut for its work)
    if (.not. (parts .or. global)) call window_balance(cfg, pc, st, xb, log, err)
    if (allocated(err)) return
    if (parts .and. cfg%rezone%virtual_layers > 0 .and. allocated(st%pt%mvf)) then
      ! the fluid under the solid as the fluid around it, on the blocks; the
      ! remap's check from the state so changed
      call particles_euler_fill(st, cfg%rezone%virtual_layers, log, nfill, err)
      call agree_error(pc, err)
      if (allocated(err)) return
      ! (the gathered particles' virtual-fluid masses so changed)
      if (nfill > 0 .and. whole_x) call whole_particles(pc, st, sw, err)
      call agree_error(pc, err)
      if (allocated(err)) return
    end if
    if (parts .and. allocated(st%pt%mvf)) call particles_euler_save(st%g, st%h, st%pt, st%pw, st%halo, pe)
    one = 0
    call window_remap(cfg, pc, st, es, log, xnew, xb, e0, redo, wider, one, ps, retry, err)
    do
      if (allocated(err)) return
      if (.not. redo) then
        if (parts) call window_particles(pc, st, es, sw, xnew, .not. whole_x, pe, log, err)
        return
      end if
      ! (a search that went further than the windows reach, and nothing
      ! else: the step, or a hybrid step's second remap, again on windows
      ! widened until it fits, while they do not hold the whole grid)
      if (retry == 0) exit
      if (windows_whole(pc, st%win%g)) exit
      call window_wider(cfg, pc, st, log, trim(merge(' (the step again on them)        ', &
                                                     ' (the second remap again on them)', retry == 1)), err)
      if (allocated(err)) return
      if (retry == 1) then
        call window_remap(cfg, pc, st, es, log, xnew, xb, e0, redo, wider, one, ps, retry, err)
      else
        first = ps%rs
        call window_remap(cfg, pc, st, es, log, xnew, xb, e0, redo, wider, one, ps, retry, err, first)
      end if
    end do
    call log_line(log, 'euler '//itoa(es%n + 1)//': remapped on the whole grid')
    if (.not. allocated(xnew)) call gather_nodes(pc, st%g%grid_index_t, xb, xnew, all=.true.)
    if (.not. allocated(st%whole)) call whole_state_build(cfg, pc, st, err)
    call agree_error(pc, err)
    if (.not. allocated(err)) call whole_gather(pc, st, err)
    ! (the particles placed in the standard grid again, whole: the blocks'
    ! places are numbered on them)
    if (.not. allocated(err) .and. pe%on_blocks) call whole_preposition(pc, st, st%whole, es, pe, err)
    if (.not. allocated(err)) then
      if (ps%on) then
        call euler_step(cfg%rezone, st%whole, es, log, err, xnew, e0, pe, resume=ps)
      else if (one == 1) then
        ! (the windows' first remap is the blocks': its changes count too)
        call euler_step(cfg%rezone, st%whole, es, log, err, xnew, e0, pe, .true., before=ps%rs)
      else
        call euler_step(cfg%rezone, st%whole, es, log, err, xnew, e0, pe)
      end if
    end if
    if (.not. allocated(err)) call whole_scatter(st, err)
    if (.not. allocated(err)) deallocate(st%whole)
    ! (the next steps' search as far as this one's went)
    if (.not. allocated(err) .and. wider) call window_wider(cfg, pc, st, log, '', err)
  end subroutine window_euler

  !> The windows of an Euler step whose rezone moved the blocks' nodes to xb
  !> (collective), built around blocks cut for the remap's work where it
  !> concentrates: near a corner charge most of the cells a smoothing moves
  !> lie in one block, and the other ranks would wait for its remap. Once
  !> a rezone moved the nodes of at least balance_planes cut planes' worth
  !> of cells, the windows are built around the blocks of the ranks' layout
  !> whose cuts balance the work of each plane of cells normal to a cut
  !> direction (one per cell, the window's copies, and remap_weight more
  !> per cell with a moved node) and kept while within tolerance of the
  !> best (`parallel_balance`). The remap's answer depends on no window
  !> (each computes its block's cells as one process does), so the cuts
  !> change the time, not the numbers. Windows around the ranks' own blocks
  !> are then cut down to what the step may change (`window_active`).
  subroutine window_balance(cfg, pc, st, xb, log, err)
    !> measured on one process (the Comp B cylinder at 40 x 40 x 48, 90
    !> Euler steps): about 19 us per remapped cell in the remap and its MoF
    !> fits, about 1 us per window cell in the windows' copies
    real(wp), parameter :: remap_weight = 20.0_wp, tolerance = 0.2_wp
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    real(wp), intent(in) :: xb(:, :)
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: w(:)
    integer, allocatable :: cuts(:)
    integer :: moved, box(3, 2)

    call remap_work(pc, st%g, xb, remap_weight, w, moved, box)
    associate (g => st%g)
      if (real(moved, wp) >= balance_planes*cut_plane_cells(pc, g%gn) .or. .not. window_own_block(pc, st)) then
        cuts = parallel_balance(pc, g%gn, max(g%ng, 1), w, st%win_cuts, tolerance)
        if (any(cuts /= st%win_cuts)) then
          st%win_cuts = cuts
          st%win_block = parallel_block(pc, g%gn, g%ng, cuts)
          call window_resize(cfg, st, st%win_reach, err)
          call agree_error(pc, err)
          if (allocated(err)) return
          if (window_own_block(pc, st)) then
            call log_line(log, 'euler windows built around the ranks'' own blocks again')
          else
            call log_line(log, 'euler windows built around blocks cut for the remap''s work ('//cuts_text(pc, cuts)// &
                          ')')
          end if
        end if
      end if
    end associate
    if (window_own_block(pc, st) .and. .not. any(st%win%bc%kind == BC_INFLOW .or. st%win%bc%kind == BC_OUTFLOW)) &
      call window_active(cfg, pc, st, box, log, err)
  end subroutine window_balance

  !> The window around this rank's own block cut down to what an Euler step
  !> that changes few cells needs (collective; `active_window`: box, the
  !> block's owned cells with a moved node): the window's copies and its
  !> remap then cost what the step changes, not the block. The window is
  !> rebuilt (a little wider, to serve the next steps) when it does not
  !> hold that part or holds more than twice its cells; st%win_back is the
  !> part of the block taken back.
  subroutine window_active(cfg, pc, st, box, log, err)
    !> the cells added on each side of a rebuilt window
    integer, parameter :: slack = 6
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    integer, intent(in) :: box(3, 2)
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    integer :: full(3, 2), now(3, 2), back(3, 2), wide(3, 2), lo(3), hi(3), n(3)
    full = window_full(st%win_block, st%win_reach)
    associate (wg => st%win%g)
      now(:, 1) = wg%off + 1
      now(:, 2) = wg%off + [wg%ni, wg%nj, wg%nk]
    end associate
    call active_window(pc, st%g, box, st%mx%cell(1:st%mx%n), remap_change_rings, &
                       window_margin(st%g%ng, st%win_reach), full, lo, hi, back)
    wide = reshape([max(lo - slack, full(:, 1)), min(hi + slack, full(:, 2))], [3, 2])
    n = 0
    if (any(now(:, 1) > lo .or. now(:, 2) < hi) .or. &
        product(real(now(:, 2) - now(:, 1) + 1, wp)) > 2.0_wp*product(real(wide(:, 2) - wide(:, 1) + 1, wp))) then
      call window_resize(cfg, st, st%win_reach, err, wide)
      n(1) = 1
    end if
    call agree_error(pc, err)
    if (allocated(err)) return
    st%win_back = back
    ! (the log says when a window was rebuilt, and how many cells the
    ! windows then hold against those around the blocks)
    n(2:3) = [st%win%g%ncell, product(full(:, 2) - full(:, 1) + 1)]
    call parallel_sum(pc, n)
    if (n(1) > 0) call log_line(log, 'euler windows cut down to the cells the step may change and what they read: '// &
                                itoa(n(2))//' cells on the ranks, of '//itoa(n(3))//' around their blocks')
  end subroutine window_active

  !> The windows widened: their search twice as far (`window_resize`),
  !> logged with note.
  subroutine window_wider(cfg, pc, st, log, note, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(log_t), intent(in) :: log
    character(len=*), intent(in) :: note
    type(error_t), allocatable, intent(inout) :: err
    call window_resize(cfg, st, 2*st%win_reach, err)
    call agree_error(pc, err)
    if (.not. allocated(err)) call log_line(log, 'euler windows widened: search within '//itoa(st%win_reach)// &
                                            ' cells, '//itoa(window_margin(st%g%ng, st%win_reach))// &
                                            ' cells around each block'//note)
  end subroutine window_wider

  !> Whether every rank's window wg holds the whole grid (collective).
  logical function windows_whole(pc, wg)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: wg
    integer :: n(1)
    n = merge(1, 0, all(wg%off == 0 .and. [wg%ni, wg%nj, wg%nk] == wg%gn))
    call parallel_min(pc, n)
    windows_whole = n(1) == 1
  end function windows_whole

  !> The global rezone's target with a moving face on a decomposed run,
  !> each block's stored nodes xb, bit for bit as `global_target` gives them
  !> on the whole grid (collective): the grid's faces gathered (their
  !> initial nodes and line parameters at the first such Euler step, the
  !> moving faces' nodes at each), the block's line parameters once (each
  !> line's running arc length passed from block to block along its
  !> direction, then its total back), the owned nodes' targets, and the
  !> ghosts' from the neighbours.
  subroutine window_global_target(pc, st, es, log, e0, xb, err, report)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    type(euler_start_t), intent(inout) :: e0
    real(wp), allocatable, intent(out) :: xb(:, :)
    type(error_t), allocatable, intent(inout) :: err
    !> false: neither logged nor timed as the step's rezone (the smoothing's
    !> standard grid, which `euler_rezone` times with the smoothing)
    logical, intent(in), optional :: report
    real(wp), allocatable :: w(:, :), start(:), finish(:)
    integer :: f, a, b, c, lo(3), hi(3), nb(3), stat
    associate (g => st%g, sf => es%rez%surface)
      e0%t_rezone = wall_seconds()
      if (.not. allocated(es%rez%xline)) then
        call global_surface_init(sf, g%gn, [(global_face_rule(st%bc%kind(f)), f = 1, 6)], err)
        if (.not. allocated(err)) allocate(es%rez%xline(3, g%nnode), stat=stat)
        if (.not. allocated(err) .and. stat /= 0) call error_set(err, 'window_global_target', 'out of memory')
        call agree_error(pc, err)
        if (allocated(err)) return
        do f = 1, 6
          call global_face_box(sf, f, lo, hi)
          call gather_box(pc, g%grid_index_t, es%rez%x0, lo, hi, w, .true.)
          sf%f(f)%x0 = w
          call global_face_parameters(sf, f)
        end do
        es%rez%xline = 0.0_wp
        nb = [g%ni, g%nj, g%nk] + 1
        do a = 1, 3
          b = merge(2, 1, a == 1)
          c = merge(2, 3, a == 3)
          allocate(start(nb(b)*nb(c)), finish(nb(b)*nb(c)), stat=stat)
          call parallel_nomem(stat, 'the line parameters')
          start = 0.0_wp
          call parallel_recv(pc, pc%nbr(2*a - 1), start)
          call global_line_sums(g%grid_index_t, a, es%rez%x0, start, es%rez%xline, finish)
          call parallel_send(pc, pc%nbr(2*a), finish)
          ! (the totals: the last block's finish, passed back)
          call parallel_recv(pc, pc%nbr(2*a), finish)
          call parallel_send(pc, pc%nbr(2*a - 1), finish)
          call global_line_scale(g%grid_index_t, a, finish, g%gn(a), es%rez%xline)
          deallocate(start, finish)
        end do
      end if
      do f = 1, 6
        if (sf%rule(f) /= GLOBAL_FACE_MOVE) cycle
        call global_face_box(sf, f, lo, hi)
        call gather_box(pc, g%grid_index_t, g%x, lo, hi, w, .true.)
        sf%f(f)%x = w
      end do
      call global_surface_solve(sf)
      allocate(xb, mold=g%x, stat=stat)
      call parallel_nomem(stat, 'the rezoned grid')
      call global_block_target(sf, g%grid_index_t, es%rez%xline, es%rez%x0, g%x, xb)
      call st%halo%nodes(xb)
      call global_target_check(g%grid_index_t, xb, g%off, err)
      call agree_error(pc, err)
      if (allocated(err)) return
      if (present(report)) then
        if (.not. report) return
      end if
      if (sf%nmove > 0) call log_line(log, 'global rezone: '//itoa(sf%nmove)//' nodes of moving faces kept where '// &
                                      'they are, the others back to the initial grid plus the TFI of their displacement')
      e0%t_rezone = wall_seconds() - e0%t_rezone
      es%t_rezone_total = es%t_rezone_total + e0%t_rezone
    end associate
  end subroutine window_global_target

  !> After the windows' remap, the particles (`window_euler`'s notes): with
  !> the global rezone (blocks) on the blocks (`particles_euler_blocks`),
  !> else, or where that cannot, on the whole grid's particles sw (gathered
  !> here if the blocks tried first) in the rezoned whole grid (xnew, or
  !> gathered from the blocks' nodes), each block then taking its own.
  subroutine window_particles(pc, st, es, sw, xnew, blocks, pe, log, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(euler_state_t), intent(inout) :: es
    type(state_t), intent(inout) :: sw
    real(wp), allocatable, intent(inout) :: xnew(:, :)
    logical, intent(in) :: blocks
    type(particles_euler_t), intent(inout) :: pe
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    type(strength_slot_t), allocatable :: models(:)
    logical :: done
    call es%timer%start()
    done = .false.
    if (blocks) then
      call particles_euler_blocks(pc, st, pe, log, done, err)
      call agree_error(pc, err)
      if (.not. (done .or. allocated(err))) then
        call log_line(log, '  particles: relocated on the whole grid (a walk ended in no cell of the whole grid, and '// &
                      'not out through an open face)')
        call whole_particles(pc, st, sw, err)
        if (.not. allocated(err) .and. pe%on_blocks) call whole_preposition(pc, st, sw, es, pe, err)
      end if
      if (.not. (done .or. allocated(err) .or. allocated(xnew))) &
        call gather_nodes(pc, st%g%grid_index_t, st%g%x, xnew, all=.true.)
      call agree_error(pc, err)
    end if
    if (.not. (done .or. allocated(err))) then
      call move_alloc(xnew, sw%g%x)
      ! (those that leave through open faces take their energy from the
      ! boundary work, alike on every rank)
      sw%tot = st%tot
      call particles_euler_relocate(sw, pe, log, err)
      call agree_error(pc, err)
      if (.not. allocated(err)) then
        st%tot%boundary_work = sw%tot%boundary_work
        if (allocated(st%pw%models)) models = st%pw%models
        call particles_take(st, sw%pt, sw%g%grid_index_t, models, err)
      end if
      call agree_error(pc, err)
      if (.not. allocated(err)) call particles_euler_couple(st, pe, sw%pt%np, count_hosts(sw%pt, sw%g%ncell), log)
    end if
    call es%timer%stop()
  end subroutine window_particles

  !> The particles of the whole grid's sw placed in the standard grid (the
  !> blocks' (st) es%rez%x0, gathered), their standard hosts in pe numbered on sw
  !> (`particles_euler_preposition`); pe's balance kept. Collective.
  subroutine whole_preposition(pc, st, sw, es, pe, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(in) :: st
    type(state_t), intent(inout) :: sw
    type(euler_state_t), intent(in) :: es
    type(particles_euler_t), intent(inout) :: pe
    type(error_t), allocatable, intent(inout) :: err
    type(particles_euler_t) :: pw
    real(wp), allocatable :: x0(:, :)
    call gather_nodes(pc, st%g%grid_index_t, es%rez%x0, x0, all=.true.)
    pw%ke_solid = pe%ke_solid
    pw%p_solid = pe%p_solid
    call particles_euler_preposition(sw, x0, pw, err)
    pe = pw
  end subroutine whole_preposition

  !> sw: the whole grid's index, boundaries and (one block's: every rank
  !> the same) halo, and the blocks' particles gathered in the whole run's
  !> order (on every rank; collective).
  subroutine whole_particles(pc, st, sw, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(state_t), intent(inout) :: sw
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    sw%g = st%gw
    sw%bc = st%bc
    if (.not. allocated(sw%halo)) then
      allocate(halo_t :: sw%halo, stat=stat)
      call parallel_nomem(stat, 'the whole grid''s particles')
    end if
    call particles_gathered(pc, st, sw%pt, err)
    if (.not. allocated(err)) call particles_index(sw%pt, sw%g%ncell, err)
  end subroutine whole_particles

  !> The remap of an Euler step on this rank's window (`window_euler`),
  !> from the blocks' state to the rezoned grid: xnew (the whole grid's
  !> nodes) if allocated, else the blocks' xb (each block's stored nodes),
  !> and each block taken from its window; redo if it needs more than a
  !> window holds, on some rank (nothing changed then but st%win, unless
  !> the blocks took the step's first remaps: ps, single). retry: 1, only
  !> the search went further than the windows, nothing taken; 2, the same
  !> in a hybrid step's second remap (or the one remap after `before`),
  !> the first taken (ps%rs its statistics); else 0. before: the
  !> statistics of a first remap the blocks took (then single = 1).
  subroutine window_remap(cfg, pc, st, es, log, xnew, xb, e0, redo, wider, single, ps, retry, err, before)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    real(wp), allocatable, intent(in) :: xnew(:, :), xb(:, :)
    type(euler_start_t), intent(in) :: e0
    logical, intent(out) :: redo, wider
    !> 1: one remap, neither in parts nor hybrid (the second remap of a
    !> hybrid step); set to 1 when a hybrid step's second remap needs the
    !> whole grid
    integer, intent(inout) :: single
    !> a step in parts of the way: where it stands when redo (the whole grid
    !> goes on from there)
    type(parts_state_t), intent(out) :: ps
    integer, intent(out) :: retry
    type(error_t), allocatable, intent(inout) :: err
    type(remap_stats_t), intent(in), optional :: before
    type(centroid_stats_t) :: cs, others
    type(plane_memory_t) :: memory
    type(remap_zone_t) :: zone
    type(remap_stats_t) :: rs, rk
    type(remap_params_t) :: par
    real(wp), allocatable :: xw(:, :), xk(:, :), xfinal(:, :), xpart(:, :), xh(:, :)
    logical, allocatable :: owned(:), fit(:)
    character(len=:), allocatable :: why
    integer, allocatable :: moved(:), blockers(:), cells(:), wrote(:), broke(:)
    integer :: n(4), k, nblock, nparts, stage, taken, dphase
    logical :: hybrid, lattice, again, arrived, next, kept, start

    redo = .false.
    wider = .false.
    retry = 0
    call copy_gather(pc, st, .true., err, cs)
    associate (w => st%win, wg => st%win%g)
      if (.not. allocated(err)) call window_zone(st%win_block, wg%grid_index_t, st%win_reach, zone, err)
      if (allocated(xnew)) then
        ! (the window's nodes of the whole grid's)
        if (.not. allocated(err)) call block_nodes(wg, st%gw, xnew, xw, err)
      else
        ! (collective: every rank's window from the blocks)
        call gather_box(pc, st%g%grid_index_t, xb, wg%off + 1, wg%off + [wg%ni, wg%nj, wg%nk], xw, .true.)
      end if
      if (any(w%bc%kind == BC_INFLOW .or. w%bc%kind == BC_OUTFLOW)) then
        call agree_error(pc, err)
        if (allocated(err)) then
          call es%timer%stop()
          return
        end if
        call window_zone_open(pc, st, zone, xw, err)
      end if
      ! the swept-face path where no changed cell of any block blocks it
      ! (collective: a rank with an error counts one)
      par = remap_params(cfg%rezone)
      nblock = 1
      nparts = 0
      if (.not. allocated(err)) nblock = remap_swept_blockers(wg, w%h, w%bc, xw, par%swept_max, par%swept_mixed, &
                                                              zone%own, nparts, moved=moved, blockers=blockers)
      n(1:3) = [nblock, 0, merge(1, 0, allocated(err))]
      if (allocated(moved)) n(2) = count(zone%own(moved))
      call parallel_sum(pc, n(1:3))
      nblock = n(1)
      ! (not after an error on any rank: the caller stops)
      hybrid = cfg%rezone%swept_hybrid .and. single == 0 .and. nblock > 0 .and. nblock < n(2) .and. n(3) == 0
      par%swept = nblock == 0
      ! the lattice path where the whole new grid is a lattice (every
      ! block's nodes are, and they share the nodes between them; only a
      ! global rezone returns to a box grid)
      if (trim(cfg%rezone%mode) /= 'global') then
        par%lattice = .false.
      else if (allocated(xnew)) then
        par%lattice = lattice_nodes(st%gw, xnew)
      else
        n(1) = merge(1, 0, lattice_nodes(st%g, xb))
        call parallel_min(pc, n(1:1))
        par%lattice = n(1) == 1
      end if
      lattice = par%lattice
      ! a step remapped in parts of the way (`euler_step`), each part on the
      ! windows (n(1): the most parts a window needs, n(2): a window that
      ! cannot)
      n(1:2) = [nparts, merge(1, 0, nparts == 0)]
      call parallel_max(pc, n(1:2))
      ps%on = single == 0 .and. nblock > 0 .and. n(2) == 0 .and. n(1) >= 2 .and. n(1) <= cfg%rezone%swept_parts .and. &
              n(3) == 0
      if (ps%on) then
        hybrid = .false.
        ps%nblock = nblock
        call move_alloc(xw, xfinal)
        call move_alloc(moved, cells)
      end if
      ! a hybrid step (`euler_step`): the first remap to the grid whose
      ! blockers' nodes stay (those of every block: gathered)
      if (hybrid) then
        call remap_hybrid_target(wg, xw, windows_cells(pc, wg, blockers), xk)
        n(1:2) = [remap_swept_blockers(wg, w%h, w%bc, xk, par%swept_max, par%swept_mixed, zone%own, moved=moved), 0]
        n(2) = count(zone%own(moved))
        call parallel_sum(pc, n(1:2))
        hybrid = n(1) == 0 .and. n(2) > 0
        if (hybrid .and. zone%open) call window_zone_open(pc, st, zone, xk, err)
      end if
    end associate
    if (.not. allocated(cells)) cells = [integer ::]
    stage = 0
    taken = 0
    ! (the parts' plan, as `euler_step` makes it)
    ps%plan = remap_parts_t(nmax=cfg%rezone%swept_parts, hybrid=cfg%rezone%swept_hybrid)
    dphase = 0
    ! (a rescue's grids: set when it begins; allocated empty here, which
    ! also keeps GCC from taking their bounds for uninitialized)
    allocate(xpart(3, 0), xh(3, 0), stat=k)
    call parallel_nomem(k, 'the parts'' grids')
    if (present(before)) then
      rs = before
      taken = 1
    end if
    again = .false.
    kept = .false.
    arrived = .true.
    do
      if (again) then
        ! (the window's state from the blocks, as the last remap left them:
        ! the window computed its cells around the block as the blocks did, so
        ! only the others are gathered, unless the remap stopped short)
        if (kept) then
          call copy_gather(pc, st, .true., err, cs, st%win_back)
        else
          call copy_gather(pc, st, .true., err, cs)
        end if
        if (zone%open .and. hybrid .and. dphase == 0) then
          ! (the second remap's: to the final grid)
          call agree_error(pc, err)
          if (.not. allocated(err)) call window_zone_open(pc, st, zone, xfinal, err)
        end if
        again = .false.
      end if
      if (dphase > 0) then
        ! (the same remap again, its deficits' repair going on:
        ! `window_deficits`)
      else if (ps%on .and. ps%plan%rescue > 0) then
        ! a stage of a part's rescue (`window_rescue`)
        call window_rescue(cfg, pc, st, zone, par, xpart, xh, ps%plan, xw, next, err)
        if (allocated(err)) then
          call es%timer%stop()
          return
        end if
        if (next) cycle
      else if (ps%on) then
        ! the next part's grid, as `euler_step` takes it (the decisions from
        ! the blocks' owned cells, reduced)
        call window_part(cfg, pc, st, zone, par, xfinal, cells, xw, ps, arrived, next, err, start, xh)
        if (allocated(err)) then
          call es%timer%stop()
          return
        end if
        if (start) then
          ! (a part some cells cannot sweep, with no split left: taken
          ! around them, `window_rescue`)
          xpart = xw
          ps%plan%rescue = 1
          cycle
        end if
        if (next) cycle
      else
        stage = stage + 1
      end if
      associate (w => st%win, wg => st%win%g)
        if (dphase > 0) then
          ! (as the first time)
        else if (hybrid .and. stage == 1) then
          par%swept = .true.
          par%lattice = .false.
          call move_alloc(xw, xfinal)
          call move_alloc(xk, xw)
        else if (hybrid) then
          call move_alloc(xfinal, xw)
          n(1) = 1
          if (.not. allocated(err)) n(1) = remap_swept_blockers(wg, w%h, w%bc, xw, par%swept_max, par%swept_mixed, &
                                                                zone%own)
          call parallel_sum(pc, n(1:1))
          par%swept = n(1) == 0
          par%lattice = lattice
        end if
        ! (the planes the fits after the remap start from)
        call centroids_remember(w%mx, memory)
        if (.not. allocated(err)) call remap_euler_step(wg, w%h, w%mx, size(w%mats), w%bc, xw, par, rk, err, &
                                                        zone=zone, written=wrote, broke=broke)
        rk%swept_blockers = nblock
        ! (the block's owned cells outside a window cut down to what the
        ! step changes are copied too: `window_active`)
        associate (b => st%win_block)
          rk%cells_copied = rk%cells_copied + product(b%chi - b%clo + 1) - count(zone%own)
        end associate
        call agree_error(pc, err)
        if (allocated(err)) then
          call es%timer%stop()
          return
        end if
        n = [rk%cells_short, rk%regions_uncovered, rk%cells_deficit, rk%swept_unbounded]
        call parallel_sum(pc, n(1:4))
        if (n(3) > 0 .and. all(n([1, 2, 4]) == 0) .and. dphase < 2) then
          ! (kinetic energy deficits: the remap again, twice, with every
          ! window's deficit cells and then their donors' energies; the
          ! window gathered again)
          call window_deficits(pc, zone, dphase, n(3), es%n + 1, log)
          again = .true.
          kept = .false.
          cycle
        end if
        if (dphase == 2) then
          ! (the deficits repaired, counted in rk)
          n(3) = 0
          dphase = 0
          deallocate(zone%deficit_cells, zone%patch%id, zone%patch%v)
        end if
        if (ps%on .and. par%swept_only .and. n(4) > 0 .and. all(n(1:3) == 0)) then
          ! (nothing remapped: the first part again half as far, or the rest
          ! of the way in twice the parts; with no split left, the part
          ! around the cells that broke a bound, `window_rescue`; the window
          ! gathered again, as the remap may have left it part way)
          if (ps%plan%unbounded()) then
            xpart = xw
            call remap_hybrid_target(wg, xw, windows_cells(pc, wg, pack(broke, zone%own(broke))), xh)
          end if
          again = .true.
          kept = .false.
          cycle
        end if
        if (any(n > 0)) then
          redo = .true.
          wider = n(1) > 0
          ! (the blocks hold the first remap's state: the whole grid does the
          ! second alone, or the rest of the parts)
          if (stage == 2) single = 1
          if (ps%on .or. stage == 2 .or. present(before)) ps%rs = rs
          ! (a window whose new cells fall short leaves the old regions
          ! they reach, here or in a neighbour's window, giving less than
          ! their volume, and their kinetic energy deficits unplaced: what
          ! n(2:3) count then may be the shortfall's, and wider windows
          ! decide it)
          if (wider .and. n(4) == 0 .and. .not. ps%on) then
            if (taken == 0) retry = 1
            if (stage == 2 .or. present(before)) retry = 2
          end if
          why = ''
          if (n(1) > 0) why = ', new cells whose old cells lie further than '//itoa(zone%reach_max)//' cells'
          if (n(2) > 0) why = why//', old regions the new grid does not cover'
          if (n(3) > 0) why = why//', kinetic energy deficits to move'
          if (n(4) > 0) why = why//', swept faces that broke a material''s bounds'
          call log_line(log, 'euler '//itoa(es%n + 1)//' needs more than the ranks'' windows hold ('//why(3:)//')')
          return
        end if
        ! the new mixed cells' planes (`euler_step`), those of the block's
        ! owned cells first: the log counts them
        owned = [(zone%own(w%mx%cell(k)), k = 1, w%mx%n)]
        ! (the others only where the blocks take them from this window: the
        ! block's ghosts, for a window around the rank's own block; none
        ! for one around a block cut for the work, whose owned cells alone
        ! go back; the window's other cells are gathered again before they
        ! are read)
        fit = [(window_keeps(st%win_block, wg, w%mx%cell(k)), k = 1, w%mx%n)]
        if (.not. window_own_block(pc, st)) fit = .false.
        call remap_after_planes(wg, w%mats, w%h%mat, w%mx, cfg%rezone%mof_max_iter, memory, cs, err, owned, others, &
                                kept=fit)
        ! (the other cells' states, and so pressures, are as the blocks hold
        ! them: `euler_step`)
        if (.not. allocated(err)) call remap_after_state(w%mats, w%h, w%mx, wrote, st%t)
      end associate
      ! (the blocks from the windows: each its own, or from those whose
      ! blocks own its cells)
      if (window_own_block(pc, st)) then
        if (.not. allocated(err)) call block_from(st, .true., err)
      else
        call agree_error(pc, err)
        if (.not. allocated(err)) call copy_gather(pc, st, .true., err, back=.true.)
      end if
      call agree_error(pc, err)
      if (allocated(err)) then
        call es%timer%stop()
        return
      end if
      call st%halo%sums(rk%flow)
      call st%halo%sums(rk%change)
      call remap_stats_flows(rk)
      call remap_stats_reduce(pc, rk)
      taken = taken + 1
      if (taken == 1) then
        rs = rk
      else
        call remap_stats_add(rs, rk)
      end if
      rs%hybrid = hybrid .or. rs%hybrid
      again = .true.
      kept = .true.
      if (ps%on) then
        next = ps%plan%taken()
        rs%swept_splits = ps%plan%nsplit
        rs%swept_rescued = ps%plan%nrescue
        ! (a rescue's second stage)
        if (next) cycle
        if (arrived) exit
      else if (stage == merge(2, 1, hybrid)) then
        exit
      end if
    end do
    call centroids_count(pc, cs, es%centroids)
    call euler_finish(cfg%rezone, st, es, log, e0, rs, err)
  end subroutine window_remap

  !> The grid of the next part of an Euler step remapped in parts on the
  !> windows (`window_remap`), as `euler_step` takes it on the whole grid:
  !> xw, the window's nodes (xfinal: its rezoned grid; cells: the window's
  !> cells that move to it from the step's start), par's swept, swept_only
  !> and lattice, and arrived (the last part); next: no remap, the parts
  !> split (ps); rescue: no remap, the part (xw) is to be taken around the
  !> cells that cannot sweep it (no split left), xh its first stage's grid
  !> (`window_rescue`). Each decision from the blocks' owned cells, reduced
  !> over the ranks (collective); open faces' gap search as the windows'
  !> remaps take it (`window_zone_open`).
  subroutine window_part(cfg, pc, st, zone, par, xfinal, cells, xw, ps, arrived, next, err, rescue, xh)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(remap_zone_t), intent(inout) :: zone
    type(remap_params_t), intent(inout) :: par
    real(wp), intent(in) :: xfinal(:, :)
    integer, intent(in) :: cells(:)
    real(wp), allocatable, intent(inout) :: xw(:, :)
    type(parts_state_t), intent(inout) :: ps
    logical, intent(out) :: arrived, next, rescue
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable, intent(inout) :: xh(:, :)
    real(wp) :: r(1)
    integer :: n(2)
    integer, allocatable :: moved(:), broke(:)
    logical :: global
    global = trim(cfg%rezone%mode) == 'global'
    next = .false.
    rescue = .false.
    arrived = .true.
    associate (w => st%win, wg => st%win%g)
      if (ps%plan%first()) then
        call remap_part_target(wg, xfinal, ps%plan%fac*par%swept_max, cells, xw, arrived, r(1), err, zone%own)
        call agree_error(pc, err)
        if (allocated(err)) return
        n(1) = merge(1, 0, arrived)
        call parallel_min(pc, n(1:1))
        call parallel_min(pc, r(1:1))
        arrived = n(1) == 1
        if (.not. arrived) then
          n(1) = merge(1, 0, remap_part_folded(wg, cells, xw, zone%own))
          call parallel_max(pc, n(1:1))
          if (n(1) == 1) call remap_part_uniform(wg, xfinal, cells, r(1), xw)
        end if
      else
        if (ps%plan%nleft == 0) ps%plan%nleft = window_parts(pc, st, zone, par, xfinal)
        xw = xfinal
        if (ps%plan%nleft > 1) xw = wg%x + (xfinal - wg%x)/real(ps%plan%nleft, wp)
        arrived = ps%plan%nleft == 1
      end if
      if (ps%plan%last(arrived)) then
        xw = xfinal
        arrived = .true.
      end if
      if (global) call window_lattice(pc, st, xw, par, err)
      if (allocated(err)) return
      n(1) = remap_swept_blockers(wg, w%h, w%bc, xw, par%swept_max, par%swept_mixed, zone%own, moved=moved, &
                                  blockers=broke)
      n(2) = count(zone%own(moved))
      call parallel_sum(pc, n(1:2))
      par%swept = n(1) == 0
      par%swept_only = ps%plan%swept_only(par%swept)
      ! (as `euler_step` decides its rescue of such a part: around the
      ! cells that cannot sweep it, every block's)
      rescue = ps%plan%wants_rescue(par%swept, arrived, n(1), n(2))
      if (rescue) then
        call remap_hybrid_target(wg, xw, windows_cells(pc, wg, broke), xh)
        return
      end if
      if (ps%plan%wants_split(par%swept, arrived)) then
        ! (a part the swept faces cannot take: shorter parts)
        if (ps%plan%nleft == 0) ps%plan%nleft = window_parts(pc, st, zone, par, xfinal)
        call ps%plan%split()
        next = .true.
        return
      end if
      if (zone%open) call window_zone_open(pc, st, zone, xw, err)
    end associate
  end subroutine window_part

  !> A window remap's kinetic energy deficits (ncell cells with one, over
  !> the blocks), repaired over the windows in two more remaps of the same
  !> step (`remap_zone_t`; collective): after the first (phase 0), every
  !> window's deficit cells gathered, after the second (phase 1) the
  !> energies of the cells around them (the patch, logged); phase moved on.
  subroutine window_deficits(pc, zone, phase, ncell, step, log)
    type(comm_t), intent(in) :: pc
    type(remap_zone_t), intent(inout) :: zone
    integer, intent(inout) :: phase
    integer, intent(in) :: ncell, step
    type(log_t), intent(in) :: log
    integer, allocatable :: all(:), order(:)
    real(wp), allocatable :: v(:)
    integer :: stat, np
    if (phase == 0) then
      if (.not. allocated(zone%deficit_mine)) zone%deficit_mine = [integer ::]
      call gather_concat(pc, zone%deficit_mine, all)
      allocate(order(size(all)), stat=stat)
      call parallel_nomem(stat, 'the deficits'' cells')
      call sort_order(all, order, stat)
      call parallel_nomem(stat, 'the deficits'' cells')
      zone%deficit_cells = all(order)
    else
      if (.not. allocated(zone%donors%id)) allocate(zone%donors%id(0), zone%donors%v(4, 0), stat=stat)
      call gather_concat(pc, zone%donors%id, all)
      call gather_concat(pc, reshape(zone%donors%v, [size(zone%donors%v)]), v)
      np = size(all)
      allocate(order(np), stat=stat)
      call parallel_nomem(stat, 'the deficits'' patch')
      call sort_order(all, order, stat)
      call parallel_nomem(stat, 'the deficits'' patch')
      zone%patch%id = all(order)
      zone%patch%v = reshape(v, [4, np])
      zone%patch%v = zone%patch%v(:, order)
      call log_line(log, 'euler '//itoa(step)//': kinetic energy deficits in '//itoa(ncell)// &
                    ' cells, repaired over the windows from the '//itoa(np)//' cells around them')
    end if
    phase = phase + 1
  end subroutine window_deficits

  !> The grid of a rescue's stage (`window_part`'s rescue, as `euler_step`
  !> takes it on the whole grid) in xw: 1, by swept faces to xh (the part's
  !> grid xpart less the moves of the nodes around the cells that cannot
  !> sweep it); 2, the rest of the way to xpart; 3, the whole part by
  !> intersection (stage 1 cannot sweep, or broke a bound). par's swept,
  !> swept_only and lattice from the blocks' owned cells, reduced
  !> (collective); next: no remap, rescue moved on to another stage.
  subroutine window_rescue(cfg, pc, st, zone, par, xpart, xh, plan, xw, next, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(remap_zone_t), intent(inout) :: zone
    type(remap_params_t), intent(inout) :: par
    real(wp), intent(in) :: xpart(:, :), xh(:, :)
    type(remap_parts_t), intent(inout) :: plan
    real(wp), allocatable, intent(inout) :: xw(:, :)
    logical, intent(out) :: next
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: moved(:)
    integer :: n(2)
    next = .false.
    xw = xpart
    if (plan%rescue == 1) xw = xh
    if (trim(cfg%rezone%mode) == 'global') call window_lattice(pc, st, xw, par, err)
    if (allocated(err)) return
    associate (w => st%win, wg => st%win%g)
      n(1) = remap_swept_blockers(wg, w%h, w%bc, xw, par%swept_max, par%swept_mixed, zone%own, moved=moved)
      n(2) = count(zone%own(moved))
    end associate
    call parallel_sum(pc, n)
    par%swept = n(1) == 0
    next = plan%rescue_next(par%swept, n(2))
    if (next) return
    par%swept_only = plan%rescue == 1
    if (zone%open) call window_zone_open(pc, st, zone, xw, err)
  end subroutine window_rescue

  !> par%lattice: whether the windows' new grid xw is a lattice (a global
  !> rezone's), from the blocks' stored nodes (within the windows' computed
  !> cells, where xw is the whole grid's), reduced (collective).
  subroutine window_lattice(pc, st, xw, par, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(in), target :: st
    real(wp), intent(in) :: xw(:, :)
    type(remap_params_t), intent(inout) :: par
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: xb(:, :)
    integer :: n(1)
    call block_nodes(st%g, st%win%g, xw, xb, err)
    call agree_error(pc, err)
    if (allocated(err)) return
    n(1) = merge(1, 0, lattice_nodes(st%g, xb))
    call parallel_min(pc, n)
    par%lattice = n(1) == 1
  end subroutine window_lattice

  !> The cells of the window wg among those the blocks name (each block its
  !> own cells `mine`, of wg): their whole-grid numbers gathered
  !> (collective).
  function windows_cells(pc, wg, mine) result(list)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: wg
    integer, intent(in) :: mine(:)
    integer, allocatable :: list(:)
    integer, allocatable :: every(:)
    integer :: i
    call gather_concat(pc, [(wg%global_cell(mine(i)), i = 1, size(mine))], every)
    list = window_cells(wg, every)
  end function windows_cells

  !> Makes zone ready for the remap of this rank's window with open faces
  !> to its new nodes xw (`remap_zone_open`; collective, on every rank
  !> alike): the open faces' innermost points over the whole grid (the
  !> blocks' extremes reduced, the low faces' as minima of their negatives:
  !> exact in any order), then the far cells of each window, which the
  !> blocks that own them send only where some window's description
  !> (`remap_zone_reach_box`, gathered) may want them: none at all while no
  !> cell moves further than a window's margin.
  subroutine window_zone_open(pc, st, zone, xw, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(in), target :: st
    type(remap_zone_t), intent(inout) :: zone
    real(wp), intent(in) :: xw(:, :)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: box(:, :), every(:), sent(:), got(:)
    integer, allocatable :: ijk(:, :)
    real(wp) :: b(12), sgn(12), r(12)
    integer :: q, p, n, stat
    associate (w => st%win, wg => st%win%g)
      call remap_zone_open(zone, wg%grid_index_t, w%bc, wg%x, xw, err)
      call agree_error(pc, err)
      if (allocated(err)) return
      sgn = [(merge(1.0_wp, -1.0_wp, mod(q, 2) == 0), q = 1, 12)]
      b = sgn*[zone%bold, zone%bnew]
      call parallel_min(pc, b)
      zone%bold = sgn(1:6)*b(1:6)
      zone%bnew = sgn(7:12)*b(7:12)
      call remap_zone_beyond(zone, wg%grid_index_t, w%bc, wg%x, xw, ijk, box, err)
      call agree_error(pc, err)
      if (allocated(err)) return
      r = remap_zone_reach_box(zone, wg%grid_index_t, xw)
      call gather_concat(pc, r, every)
      ! (each candidate as 9 reals: its indices, exact, and its box)
      allocate(sent(9*size(ijk, 2)), stat=stat)
      call parallel_nomem(stat, 'the open faces'' far cells')
      n = 0
      do q = 1, size(ijk, 2)
        do p = 0, pc%nranks - 1
          if (remap_zone_wants(every(12*p + 1:12*p + 12), ijk(:, q), box(:, q))) then
            sent(9*n + 1:9*n + 9) = [real(ijk(:, q), wp), box(:, q)]
            n = n + 1
            exit
          end if
        end do
      end do
      call gather_concat(pc, sent(1:9*n), got)
      n = size(got)/9
      call remap_zone_far(zone, r, nint(reshape([(got(9*q + 1:9*q + 3), q = 0, n - 1)], [3, n])), &
                          reshape([(got(9*q + 4:9*q + 9), q = 0, n - 1)], [6, n]))
    end associate
  end subroutine window_zone_open

  !> The equal parts of the way from the window's grid to xfinal that keep
  !> every changed cell within swept_max, as `euler_step` counts them on
  !> the whole grid (`remap_swept_blockers`' parts over the blocks' owned
  !> cells, reduced; 1 where a cell of another material is in the way).
  integer function window_parts(pc, st, zone, par, xfinal) result(nleft)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(in), target :: st
    type(remap_zone_t), intent(in) :: zone
    type(remap_params_t), intent(in) :: par
    real(wp), intent(in) :: xfinal(:, :)
    integer :: n(2), nfar
    nfar = remap_swept_blockers(st%win%g, st%win%h, st%win%bc, xfinal, par%swept_max, par%swept_mixed, zone%own, &
                                parts=n(1))
    n(2) = merge(1, 0, n(1) == 0)
    call parallel_max(pc, n(1:2))
    nleft = merge(1, max(n(1), 1), n(2) == 1)
  end function window_parts

  !> The values at the block g's stored nodes of xw, a node array of the
  !> window wg that holds them.
  subroutine block_nodes(g, wg, xw, xb, err)
    type(grid_t), intent(in) :: g, wg
    real(wp), intent(in) :: xw(:, :)
    real(wp), allocatable, intent(out) :: xb(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: to(:), from(:)
    integer :: len, stat
    call grid_rows(g, wg, .true., size(xw, 1), to, from, len, stat)
    if (stat == 0) allocate(xb(size(xw, 1), g%nnode), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'block_nodes', 'out of memory')
      return
    end if
    call grid_copy_rows_real(to, from, len, xw, xb)
  end subroutine block_nodes

  !> The cells of the window wg among the whole grid's cells cells (its
  !> single-block order), as wg's cells.
  pure function window_cells(wg, cells) result(list)
    type(grid_t), intent(in) :: wg
    integer, intent(in) :: cells(:)
    integer, allocatable :: list(:)
    integer :: q, ijk(3), at(size(cells))
    logical :: inside(size(cells))
    do q = 1, size(cells)
      ijk(1) = mod(cells(q) - 1, wg%gn(1)) + 1
      ijk(2) = mod((cells(q) - 1)/wg%gn(1), wg%gn(2)) + 1
      ijk(3) = (cells(q) - 1)/(wg%gn(1)*wg%gn(2)) + 1
      ijk = ijk - wg%off
      inside(q) = all(ijk >= 1 .and. ijk <= [wg%ni, wg%nj, wg%nk])
      at(q) = 0
      if (inside(q)) at(q) = wg%cell(ijk(1), ijk(2), ijk(3))
    end do
    list = pack(at, inside)
  end function window_cells

  !> Whether the global rezone of a decomposed run needs the whole grid's
  !> node positions: a face that moves with the material (TFI of its
  !> displacement over the whole grid, `global_target`); else each block's
  !> target is its own initial nodes.
  logical function global_whole(cfg, st)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    integer :: f
    global_whole = trim(cfg%rezone%mode) == 'global' .and. &
                   any([(global_face_rule(st%bc%kind(f)), f = 1, 6)] == GLOBAL_FACE_MOVE)
  end function global_whole

  !> The block g's stored cells (owned and ghost), as whole-grid indices
  !> lo (:, 1) to hi (:, 2): after a remap its window holds there what the
  !> blocks hold (`block_from` took them from it).
  pure function window_kept(g) result(keep)
    type(grid_index_t), intent(in) :: g
    integer :: keep(3, 2)
    keep(:, 1) = g%slo + g%off
    keep(:, 2) = g%shi + g%off
  end function window_kept

  !> The cells and nodes of st%win (its layout) with those of the block it
  !> is built around (st%win_block) as its own: the window's layout as a
  !> block whose ghost layers are the rest of it.
  function window_owned(st) result(ix)
    type(state_t), intent(in) :: st
    type(grid_index_t) :: ix
    associate (b => st%win_block, w => st%win%g)
      ix = grid_index_block([b%ni, b%nj, b%nk], b%off - w%off, &
                            w%off + [w%ni, w%nj, w%nk] - b%off - [b%ni, b%nj, b%nk], b%off, b%gn)
    end associate
  end function window_owned

  !> Whether cell c of window wg lies in the block b's stored cells.
  pure logical function window_keeps(b, wg, c)
    type(grid_index_t), intent(in) :: b
    type(grid_t), intent(in) :: wg
    integer, intent(in) :: c
    integer :: ijk(3)
    call wg%cell_ijk(c, ijk(1), ijk(2), ijk(3))
    ijk = ijk + wg%off - b%off
    window_keeps = all(ijk >= b%slo .and. ijk <= b%shi)
  end function window_keeps

  !> Whether every rank's window is built around the rank's own block (the
  !> same answer on every rank).
  logical function window_own_block(pc, st)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(in) :: st
    window_own_block = all(st%win_cuts == pc%cuts)
  end function window_own_block

  !> The zone of this rank's window wg (`remap_zone_t`) around its block g:
  !> own its owned cells and the nodes it counts, compute those and
  !> window_compute layers around them.
  subroutine window_zone(g, wg, reach, zone, err)
    type(grid_index_t), intent(in) :: g, wg
    integer, intent(in) :: reach
    type(remap_zone_t), intent(out) :: zone
    type(error_t), allocatable, intent(inout) :: err
    call remap_zone_block(zone, g, wg, window_compute(g%ng, reach), reach, err)
  end subroutine window_zone

  !> What the ranks' window remaps did, as one remap of the whole grid:
  !> counts and energies summed, largest values the largest (rs%parts
  !> minus the number of windows, for the log).
  subroutine remap_stats_reduce(pc, rs)
    type(comm_t), intent(in) :: pc
    type(remap_stats_t), intent(inout) :: rs
    integer :: ni(9), nx(1)
    real(wp) :: r(9), x(6)
    ni = [rs%cells_remapped, rs%cells_copied, rs%mof_cells, rs%mof_iterations, rs%mof_not_converged, &
          rs%slivers_merged, rs%cells_swept, rs%mof_carried, rs%cells_deficit]
    nx = [rs%reach]
    r = [rs%ke_to_internal, rs%momentum_constrained, rs%scale, rs%deficit_moved, rs%deficit_by_mass]
    x = [rs%volume_defect, rs%given_defect, rs%mof_err_max, rs%t_prepare, rs%t_intersect, rs%t_assemble]
    call parallel_sum(pc, ni(1:9))
    call parallel_max(pc, nx(1:1))
    call parallel_sum(pc, r(1:9))
    call parallel_max(pc, x(1:6))
    rs%cells_remapped = ni(1); rs%cells_copied = ni(2); rs%mof_cells = ni(3); rs%mof_iterations = ni(4)
    rs%mof_not_converged = ni(5); rs%slivers_merged = ni(6); rs%cells_swept = ni(7); rs%mof_carried = ni(8)
    rs%cells_deficit = ni(9); rs%deficit_moved = r(8); rs%deficit_by_mass = r(9)
    rs%reach = nx(1)
    rs%ke_to_internal = r(1); rs%momentum_constrained = r(2:4); rs%scale = r(5:7)
    rs%volume_defect = x(1); rs%given_defect = x(2); rs%mof_err_max = x(3)
    rs%t_prepare = x(4); rs%t_intersect = x(5); rs%t_assemble = x(6)
    rs%parts = -pc%nranks
  end subroutine remap_stats_reduce

  !> The blocks' fits or refreshes of their owned mixed cells (cs) added to
  !> the run's count (total) as one of the whole grid's.
  subroutine centroids_count(pc, cs, total)
    type(comm_t), intent(in) :: pc
    type(centroid_stats_t), intent(in) :: cs
    type(centroid_stats_t), intent(inout) :: total
    integer :: n(5)
    real(wp) :: e(1)
    n = [cs%fitted, cs%iterations, cs%capped, cs%moved, cs%failed]
    call parallel_sum(pc, n(1:5))
    e = cs%err_max
    call parallel_max(pc, e)
    total%fitted = total%fitted + n(1)
    total%iterations = total%iterations + n(2)
    total%capped = total%capped + n(3)
    total%moved = total%moved + n(4)
    total%failed = total%failed + n(5)
    total%err_max = max(total%err_max, e(1))
  end subroutine centroids_count

  !> A restart dump of a decomposed run, written by the ranks together
  !> (`write_restart`, `restart_write`): each block its owned nodes and cells
  !> of the node and cell quantities, its owned mixed cells (their centroids
  !> refreshed) and its owned particles at their places in the whole run's
  !> lists (`restart_part_t`: the mixed cells in cell order, placed by a
  !> prefix sum over the cells, `cell_prefix`; the particles by
  !> `particles_blocks_share`), rank 0 the rest. A mixed cell's material
  !> (minus its number) is its number in the whole run's list, its cell
  !> and slots those of the whole grid's. The file is the one a single
  !> process writes; no rank holds more than its block.
  subroutine whole_dump(cfg, pc, st, sch, es, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    type(mixed_t) :: own, mb
    type(particles_t) :: pw, pb
    type(centroid_stats_t) :: cs
    type(restart_part_t) :: parts(3)
    integer, allocatable :: mat(:), keep(:), cnt(:, :), before(:, :), at(:)
    integer :: k, c, s, tot(2), stat, st1, st2, np

    call mixed_owned(st%g%grid_index_t, st%mx, own, err)
    if (.not. allocated(err)) then
      call centroids_refresh(st%g, own, cs)
      allocate(cnt(2, st%g%ncell), at(own%nslot), stat=stat)
      if (stat /= 0) call error_set(err, 'whole_dump', error_no_memory('the dump''s mixed cells'))
    end if
    call agree_error(pc, err)
    if (allocated(err)) return
    call centroids_count(pc, cs, es%centroids)
    cnt = 0
    do k = 1, own%n
      cnt(:, own%cell(k)) = [1, own%start(k + 1) - own%start(k)]
    end do
    call cell_prefix(pc, st%g%grid_index_t, cnt, before, tot)
    ! the owned mixed cells' places in the whole run's list and their
    ! slots' (increasing: own is in cell order)
    parts(1)%location = LOC_MIXED_CELL
    parts(1)%total = tot(1)
    parts(2)%location = LOC_MIXED_SLOT
    parts(2)%total = tot(2)
    do k = 1, own%n
      c = own%cell(k)
      at(own%start(k):own%start(k + 1) - 1) = [(before(2, c) + s, s = 0, own%start(k + 1) - own%start(k) - 1)]
    end do
    call sorted_runs(at, parts(2)%runs, st2)
    at = [(before(1, own%cell(k)), k = 1, own%n)]
    call sorted_runs(at, parts(1)%runs, st1)
    stat = max(st1, st2)
    ! (the starts, one more: the last by the rank that holds the last mixed
    ! cell, by rank 0 when there is none)
    if (any(at == tot(1) - 1) .or. (tot(1) == 0 .and. pc%rank == 0)) at = [at, tot(1)]
    call sorted_runs(at, parts(1)%plus, st1)
    call parallel_nomem(max(stat, st1), 'the dump''s mixed cells')
    ! the file's numbers: the material of a mixed cell's cell, its cell,
    ! its first slot, the counts (the arrays stay this block's part)
    mat = st%h%mat
    do k = 1, own%n
      c = own%cell(k)
      mat(c) = -(before(1, c) + 1)
      own%cell(k) = st%g%global_cell(c)
      own%start(k) = before(2, c) + 1
    end do
    own%start(own%n + 1) = tot(2) + 1
    own%n = tot(1)
    own%nslot = tot(2)
    np = 2
    if (st%pblocks) then
      np = 3
      parts(3)%location = LOC_PARTICLE
      call particles_blocks_share(pc, st, pw, parts(3)%runs, parts(3)%total, err)
      call agree_error(pc, err)
      if (allocated(err)) return
      pb = st%pt
      st%pt = pw
    end if
    mb = st%mx
    st%mx = own
    call move_alloc(st%h%mat, keep)
    call move_alloc(mat, st%h%mat)
    call write_restart(cfg, st, sch, es, err, parts(:np))
    ! the block's own again
    call move_alloc(keep, st%h%mat)
    st%mx = mb
    if (st%pblocks) st%pt = pb
  end subroutine whole_dump

  !> A decomposed run's restart: each rank reads its block (`read_restart`).
  subroutine whole_restart(cfg, st, sch, es, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout), target :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    call read_restart(cfg, st, sch, es, err, block=.true.)
    ! (a block's file may be damaged where another's is not)
    call agree_error(sch%pc, err)
    if (.not. allocated(err)) call report_conservation(st, sch%log, 'restart')
  end subroutine whole_restart

  !> Every rank's st%whole: the whole grid's state assembled from the
  !> blocks' st (st%whole built from the deck on the whole grid first,
  !> `build_scene` without a block).
  subroutine whole_gather(pc, st, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(error_t), allocatable, intent(inout) :: err
    if (st%pblocks) then
      call particles_gathered(pc, st, st%whole%pt, err)
      if (.not. allocated(err)) call particles_index(st%whole%pt, st%whole%g%ncell, err)
      if (allocated(err)) return
      st%whole%pw%mass_ready = .false.
    end if
    call copy_gather(pc, st, .false., err)
  end subroutine whole_gather

  !> The state of a box of the whole grid, st%whole or (window) st%win,
  !> assembled from the blocks' st (built from the deck first): the node
  !> and cell quantities a restart holds, gathered from the blocks that own
  !> them (`gather_box`), the mixed cells in the box (`mixed_gather`, with
  !> `refreshed` their centroids refreshed first), the quantities of the
  !> whole run copied, and what a restart read rebuilds. back (window): the
  !> other way, each block st (its owned and ghost cells and nodes) from the
  !> windows whose blocks own them (st%win_block: a window built around a
  !> block cut for the remap's work, `window_balance`).
  subroutine copy_gather(pc, st, window, err, refreshed, keep, back)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    logical, intent(in) :: window
    type(error_t), allocatable, intent(inout) :: err
    type(centroid_stats_t), intent(inout), optional :: refreshed
    !> (window) the cells keep(:, 1)..keep(:, 2) (whole-grid indices) and
    !> their nodes hold the blocks' values already: they are not gathered
    !> (the mixed cells are, all of them)
    integer, intent(in), optional :: keep(3, 2)
    logical, intent(in), optional :: back
    !> (an integer quantity as reals, exact: material indices)
    type :: as_reals_t
      real(wp), allocatable :: a(:, :), w(:, :)
    end type as_reals_t
    type(state_t), pointer :: d, src
    type(grid_index_t) :: six
    type(registry_t) :: rb, rw
    type(mixed_t) :: mw
    type(as_reals_t), allocatable, target :: ints(:)
    type(gather_field_t), allocatable :: f(:)
    integer, allocatable :: pick(:), map(:), at(:)
    integer :: e, m, n, nw, lo(3), hi(3), hole(3, 2), nf, ni, k, pass, stat
    logical :: nodes

    ! (src: what is gathered from, six its cells and nodes and those of
    ! them each rank owns; d: where to)
    src => st
    six = st%g%grid_index_t
    if (present(back)) then
      if (back) then
        src => st%win
        six = window_owned(st)
      end if
    end if
    if (.not. associated(src, st)) then
      d => st
    else if (window) then
      d => st%win
    else
      d => st%whole
    end if
    d%t = st%t
    d%dt = st%dt
    d%step = st%step
    call mixed_gather(pc, src%g, six, src%mx, d%g%off + d%g%slo, d%g%off + d%g%shi, mw, err, refreshed)
    if (.not. allocated(err)) call mixed_of_block(d%g, mw, d%mx, err, pick)
    if (allocated(err)) return
    lo = d%g%off + d%g%slo
    hi = d%g%off + d%g%shi
    call state_register_restart(src, rb)
    call state_register_restart(d, rw)
    map = entry_map(rb, rw)
    ! the node quantities, then the cell ones, each in one gather; an
    ! integer one through reals (at(e): its slot in ints)
    allocate(f(rb%n), ints(rb%n), at(rb%n), stat=stat)
    ! (the other ranks are about to gather with this one: all end)
    call parallel_nomem(stat, 'copy_gather')
    do pass = 1, 2
      nodes = pass == 1
      hole(:, 1) = [1, 1, 1]
      hole(:, 2) = [0, 0, 0]
      if (present(keep)) then
        hole = keep
        if (nodes) hole(:, 1) = keep(:, 1) - 1
      end if
      nf = 0
      ni = 0
      do e = 1, rb%n
        if (map(e) == 0) cycle
        associate (b => rb%e(e), v => rw%e(map(e)))
          if (b%location /= merge(LOC_NODE, LOC_CELL, nodes)) cycle
          m = product(b%dims(1:size(b%dims) - 1))
          n = b%dims(size(b%dims))
          nw = v%dims(size(v%dims))
          nf = nf + 1
          if (b%kind == K_REAL) then
            f(nf)%a(1:m, 1:n) => b%r
            f(nf)%w(1:m, 1:nw) => v%r
          else
            ni = ni + 1
            at(e) = ni
            ints(ni)%a = reshape(real(b%i, wp), [m, n])
            ints(ni)%w = reshape(real(v%i, wp), [m, nw])
            f(nf)%a => ints(ni)%a
            f(nf)%w => ints(ni)%w
          end if
        end associate
      end do
      call gather_box_fields(pc, six, f(1:nf), lo, hi, nodes, hole(:, 1), hole(:, 2))
      do e = 1, rb%n
        if (map(e) == 0) cycle
        associate (b => rb%e(e), v => rw%e(map(e)))
          if (b%location /= merge(LOC_NODE, LOC_CELL, nodes) .or. b%kind == K_REAL) cycle
          k = at(e)
          v%i = nint(reshape(ints(k)%w, [size(ints(k)%w)]))
        end associate
      end do
    end do
    do e = 1, rb%n
      if (map(e) == 0) cycle
      if (rb%e(e)%location == LOC_GLOBAL .and. .not. mixed_entry(rb%e(e))) call copy_global(rb%e(e), rw%e(map(e)))
    end do
    call mixed_numbers(d)
    call state_after_read(d)
    call material_index_cells(d%mats, d%h%mat, d%mx, err)
  end subroutine copy_gather

  !> For each entry of registry a, the entry of b with its name (0: none; a
  !> window holds no particles).
  function entry_map(a, b) result(map)
    type(registry_t), intent(in) :: a, b
    integer :: map(a%n)
    integer :: e, f
    map = 0
    do e = 1, a%n
      do f = 1, b%n
        if (a%e(e)%name == b%e(f)%name) then
          map(e) = f
          exit
        end if
      end do
    end do
  end function entry_map

  !> The counts of the mixed cells (copied with the cells themselves).
  logical function mixed_entry(e)
    type(registry_entry_t), intent(in) :: e
    mixed_entry = e%name(1:6) == 'mixed_'
  end function mixed_entry

  !> This rank's block st (owned and ghost cells and nodes) taken from the
  !> whole grid's state st%whole.
  subroutine whole_scatter(st, err)
    type(state_t), intent(inout), target :: st
    type(error_t), allocatable, intent(inout) :: err
    if (allocated(st%whole%pt%id)) then
      call particles_take(st, st%whole%pt, st%whole%g%grid_index_t, st%whole%pw%models, err)
      if (allocated(err)) return
    end if
    call block_from(st, .false., err)
  end subroutine whole_scatter

  !> This rank's block st (owned and ghost cells and nodes) taken from the
  !> state of a box of the whole grid that holds it: st%whole, or (window)
  !> the cells st%win_back and their nodes from st%win (the block's mixed
  !> cells are all in them).
  subroutine block_from(st, window, err)
    type(state_t), intent(inout), target :: st
    logical, intent(in) :: window
    type(error_t), allocatable, intent(inout) :: err
    type(state_t), pointer :: src
    type(registry_t) :: rb, rw
    type(mixed_t) :: mw
    integer, allocatable :: pick(:), map(:), to(:), from(:)
    integer :: e, k, len, stat, box(3, 2)

    box(:, 1) = st%g%slo
    box(:, 2) = st%g%shi
    if (window) then
      src => st%win
      box = st%win_back - spread(st%g%off, 2, 2)
    else
      src => st%whole
    end if
    ! the mixed cells the block stores, in cell order (numbered in the whole grid)
    mw = src%mx
    do k = 1, mw%n
      mw%cell(k) = src%g%global_cell(mw%cell(k))
    end do
    call mixed_of_block(st%g, mw, st%mx, err, pick)
    if (allocated(err)) return
    call state_register_restart(st, rb)
    call state_register_restart(src, rw)
    map = entry_map(rb, rw)
    do e = 1, rb%n
      if (map(e) == 0) cycle
      associate (b => rb%e(e), v => rw%e(map(e)), g => st%g, wg => src%g)
        select case (b%location)
        case (LOC_NODE, LOC_CELL)
          call grid_rows(g, wg, b%location == LOC_NODE, product(b%dims(1:size(b%dims) - 1)), to, from, len, stat, box)
          if (stat /= 0) then
            call error_set(err, 'block_from', 'out of memory')
            return
          end if
          if (b%kind == K_REAL) then
            call grid_copy_rows_real(to, from, len, v%r, b%r)
          else
            call grid_copy_rows_int(to, from, len, v%i, b%i)
          end if
        case (LOC_GLOBAL)
          if (.not. mixed_entry(b)) call copy_global(v, b)
        end select
      end associate
    end do
    call mixed_numbers(st)
    call state_after_read(st)
    call material_index_cells(st%mats, st%h%mat, st%mx, err)
  end subroutine block_from

  !> A quantity of the whole run (time, step, energy bookkeeping, the random
  !> numbers' state): the same on every rank, copied.
  subroutine copy_global(from, to)
    type(registry_entry_t), intent(in) :: from
    type(registry_entry_t), intent(inout) :: to
    select case (from%kind)
    case (K_REAL); to%r = from%r
    case (K_INT); to%i = from%i
    case (K_REAL_SCALAR); to%rs = from%rs
    case (K_INT_SCALAR); to%is = from%is
    end select
  end subroutine copy_global

  !> own: the owned mixed cells of mx, the mixed cells of a block of index
  !> ix (cells numbered in the block), in cell order.
  subroutine mixed_owned(ix, mx, own, err)
    type(grid_index_t), intent(in) :: ix
    type(mixed_t), intent(in) :: mx
    type(mixed_t), intent(inout) :: own
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: pick(:), order(:)
    integer :: k, m, stat, ijk(3)
    allocate(pick(mx%n), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'mixed_owned', error_no_memory('the owned mixed cells'))
      return
    end if
    m = 0
    do k = 1, mx%n
      call ix%cell_ijk(mx%cell(k), ijk(1), ijk(2), ijk(3))
      if (.not. ix%owns_cell(ijk(1), ijk(2), ijk(3))) cycle
      m = m + 1
      pick(m) = k
    end do
    allocate(order(m), stat=stat)
    if (stat == 0) call sort_order(mx%cell(pick(:m)), order, stat)
    if (stat /= 0) then
      call error_set(err, 'mixed_owned', error_no_memory('the owned mixed cells'))
      return
    end if
    pick(:m) = pick(order)
    call mixed_subset(mx, pick(:m), mx%cell(pick(:m)), own, err)
  end subroutine mixed_owned

  !> mw: the mixed cells of the whole grid in the box of cells lo..hi
  !> (whole-grid indices; each rank its own), in cell order, from the
  !> blocks that own them (each rank's mixed cells mx of its block of index
  !> ix, the owned ones, their centroids refreshed first on the grid g with
  !> `refreshed`): each block sends a rank only
  !> those in its box, a record of reals per cell (exact: its cell, its
  !> slots, each slot's material, fractions, states, centroid and plane).
  subroutine mixed_gather(pc, g, ix, mx, lo, hi, mw, err, refreshed)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    type(grid_index_t), intent(in) :: ix
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: lo(3), hi(3)
    type(mixed_t), intent(inout) :: mw
    type(error_t), allocatable, intent(inout) :: err
    type(centroid_stats_t), intent(inout), optional :: refreshed
    integer, parameter :: per_slot = 14
    type(mixed_t) :: own, cat
    integer, allocatable :: pick(:), boxes(:), scounts(:), gijk(:, :)
    real(wp), allocatable :: sbuf(:), rbuf(:)
    integer :: k, m, r, s, q, n, nslot, stat, ijk(3), box(6)

    call mixed_owned(ix, mx, own, err)
    if (allocated(err)) return
    if (present(refreshed)) call centroids_refresh(g, own, refreshed)
    ! (every rank's box; each own cell's whole-grid index)
    box = [lo, hi]
    call gather_concat(pc, box, boxes)
    allocate(gijk(3, own%n), scounts(0:pc%nranks - 1), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'mixed_gather', 'out of memory')
      return
    end if
    do k = 1, own%n
      call ix%cell_ijk(own%cell(k), ijk(1), ijk(2), ijk(3))
      gijk(:, k) = ijk + ix%off
    end do
    ! the records for rank 0, 1, ... in turn
    do q = 1, 2
      n = 0
      do r = 0, pc%nranks - 1
        if (q == 2) scounts(r) = n
        do k = 1, own%n
          if (any(gijk(:, k) < boxes(6*r + 1:6*r + 3) .or. gijk(:, k) > boxes(6*r + 4:6*r + 6))) cycle
          nslot = own%start(k + 1) - own%start(k)
          if (q == 2) then
            sbuf(n + 1) = real(ix%global_cell(own%cell(k)), wp)
            sbuf(n + 2) = real(nslot, wp)
            do s = own%start(k), own%start(k + 1) - 1
              sbuf(n + 3 + per_slot*(s - own%start(k)):n + 2 + per_slot*(s - own%start(k) + 1)) = &
                [real(own%mat(s), wp), own%vf(s), own%mass(s), own%e(s), own%rho(s), own%p(s), own%cs(s), &
                 own%xi(:, s), own%plane(:, s)]
            end do
          end if
          n = n + 2 + per_slot*nslot
        end do
        if (q == 2) scounts(r) = n - scounts(r)
      end do
      if (q == 1) then
        allocate(sbuf(n), stat=stat)
        call parallel_nomem(stat, 'the mixed cells'' records')
      end if
    end do
    call exchange_lists(pc, sbuf, scounts, rbuf)
    ! the records received, into one list
    n = 0
    m = 0
    nslot = 0
    do while (n < size(rbuf))
      m = m + 1
      nslot = nslot + nint(rbuf(n + 2))
      n = n + 2 + per_slot*nint(rbuf(n + 2))
    end do
    call mixed_allocate(cat, m, nslot, err)
    if (allocated(err)) return
    n = 0
    do k = 1, m
      cat%cell(k) = nint(rbuf(n + 1))
      cat%start(k + 1) = cat%start(k) + nint(rbuf(n + 2))
      n = n + 2
      do s = cat%start(k), cat%start(k + 1) - 1
        cat%mat(s) = nint(rbuf(n + 1))
        cat%vf(s) = rbuf(n + 2)
        cat%mass(s) = rbuf(n + 3)
        cat%e(s) = rbuf(n + 4)
        cat%rho(s) = rbuf(n + 5)
        cat%p(s) = rbuf(n + 6)
        cat%cs(s) = rbuf(n + 7)
        cat%xi(:, s) = rbuf(n + 8:n + 10)
        cat%plane(:, s) = rbuf(n + 11:n + 14)
        n = n + per_slot
      end do
    end do
    ! in cell order (each cell is owned by one block)
    allocate(pick(cat%n), stat=stat)
    if (stat == 0) call sort_order(cat%cell, pick, stat)
    if (stat /= 0) then
      call error_set(err, 'mixed_gather', 'out of memory')
      return
    end if
    call mixed_subset(cat, pick, cat%cell(pick), mw, err)
  end subroutine mixed_gather
end module driver_whole
