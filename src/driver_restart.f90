!> Restarts for the driver: the registry of a dump (each owner registers its
!> own quantities), when and where dumps go, reading one back, and refusing a
!> restart whose deck changes the state or whose file is damaged.
!>
!> Reading back trusts nothing in the file: the checksums and shapes are
!> checked by `io_restart`; here, the stored sizes of the mixed cells are
!> checked against the grid and against the file's own dataset shapes before
!> storage is allocated to them, and after the read every quantity against
!> the range its owner registered (`check_ranges`: positive masses, volumes and
!> densities, times finite and not negative, counts not negative, material
!> indices of this deck, a generator state that is not zero, a frame counter
!> equal to the stored frame list's length). Any failure is an input error:
!> exit status 2, "cannot restart", a message naming the dataset and value.
!>
!> The frame schedule across a restart: a dump taken at the last step of a
!> run segment is written before the driver writes that segment's final
!> frame. The dump therefore records the schedule as it is after that frame
!> (`write_restart`): the frame is in the stored frame list, so a continued
!> run numbers its frames after it instead of overwriting it; and if the
!> frame was due by frame_dt or frame_steps, the schedule is advanced past
!> it, as the straight run does when it writes the same frame within its time
!> loop (otherwise the continued run would write it again one step later).
module driver_restart
  use, intrinsic :: iso_fortran_env, only: int64
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t, error_set, error_no_memory, ERR_INPUT, ERR_IO
  use base_sort, only: sorted_runs
  use base_config, only: max_line, problem_add
  use base_timers, only: wall_seconds
  use base_registry, only: registry_t, LOC_MIXED_CELL, LOC_MIXED_SLOT, LOC_PARTICLE, K_REAL, K_INT, K_REAL_SCALAR, K_INT_SCALAR, &
                           LOWER_POSITIVE, LOWER_NONNEGATIVE
  use material_table, only: material_index_cells
  use material_mixed, only: mixed_t, mixed_allocate, mixed_subset
  use mesh_grid, only: grid_t, grid_index_t, grid_index
  use particles_state, only: particles_t, particles_check, particles_index, particles_allocate
  use particles_shape, only: particles_shape_values
  use mesh_boundary, only: BC_INFLOW, BC_OUTFLOW
  use particles_lagrange, only: particles_work_resize, strength_slot_t
  use parallel_comm, only: comm_t, parallel_nomem, parallel_sum
  use parallel_particles, only: parallel_particles_ids
  use driver_parallel, only: agree_error
  use parallel_gather, only: gather_concat
  use driver_particles, only: particles_take
  use particles_spread, only: particles_support_widths
  use lagrange_centroids, only: centroids_refresh
  use io_log, only: log_line
  use io_hdf5, only: hdf5_start
  use io_restart, only: restart_part_t, restart_read_parts, restart_read_int_runs, restart_cell_runs, restart_write, restart_read, &
                        restart_read_deck, restart_read_int_scalar, &
                        restart_check_counts, restart_read_dims
  use driver_config, only: config_t, config_read, config_state_changes
  use io_output_config, only: output_config_changes
  use driver_state, only: state_t, state_register_restart, state_after_read
  use driver_output, only: schedule_t, schedule_register_restart, report_conservation, frame_due, advance_schedule
  use driver_euler, only: euler_state_t, euler_register_restart
  implicit none
  private
  public :: check_restart_deck, restart_path, write_restart, read_restart, mixed_of_block, mixed_numbers

contains

  !> A restart may change time, output, dump and numerical settings, but not
  !> what the state depends on, nor the frames' fields and precision (the
  !> series it continues lists its frames with one layout): compare the deck stored in the restart file
  !> with this one; `problems` names each changed variable (or why the file
  !> cannot be used) and `summary` says what follows.
  subroutine check_restart_deck(cfg, problems, summary)
    type(config_t), intent(in) :: cfg
    character(len=max_line), allocatable, intent(out) :: problems(:)
    character(len=:), allocatable, intent(out) :: summary
    type(error_t), allocatable :: err
    character(len=:), allocatable :: text
    type(config_t) :: old

    problems = [character(len=max_line) ::]
    summary = 'cannot restart'
    call hdf5_start(err)
    if (.not. allocated(err)) call restart_read_deck(trim(cfg%control%restart_from), text, err)
    if (allocated(err)) then
      call problem_add(problems, '&run restart_from: '//err%msg)
      return
    end if
    ! the stored deck is namelist text: read it back through the same reader
    ! (from memory: the restart's folder may be read-only)
    call config_read(cfg%deck_path, old, problems, text)
    if (size(problems) > 0) then
      summary = 'the deck stored in '//trim(cfg%control%restart_from)//' cannot be read back'
      return
    end if
    call config_state_changes(old, cfg, problems)
    call output_config_changes(old%output, cfg%output, problems)
    summary = 'a restart cannot change what the state depends on (nor the frames'' fields and precision); '// &
              'undo these changes or start a new run'
  end subroutine check_restart_deck

  !> Everything a restart must hold, each owner registering its own
  !> quantities (after allocation: the registry points at the storage).
  subroutine register_all(st, sch, es, reg)
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(registry_t), intent(out) :: reg
    call state_register_restart(st, reg)
    call schedule_register_restart(sch, reg)
    call euler_register_restart(es, reg)
  end subroutine register_all

  !> The file name of the dump of step `step`.
  function restart_path(sch, step) result(path)
    type(schedule_t), intent(in) :: sch
    integer, intent(in) :: step
    character(len=:), allocatable :: path
    character(len=16) :: buf
    write(buf, '(i8.8)') step
    path = sch%out%dir//'/'//sch%out%name//'_restart_'//trim(buf)//'.h5'
  end function restart_path

  !> Writes a restart dump and keeps only the last dump_keep of this run.
  !> On several ranks every rank calls this with its block, whose mixed
  !> cells and particles are then the whole run's (`whole_dump`): the ranks
  !> write the file together.
  subroutine write_restart(cfg, st, sch, es, err, parts)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    !> (a decomposed run's blocks: st%mx and st%pt this rank's share of
    !> the whole run's mixed cells and particles, written at the places the
    !> parts give, `restart_write`)
    type(restart_part_t), intent(in), optional :: parts(:)
    type(registry_t) :: reg
    character(len=:), allocatable :: path
    character(len=256) :: entry
    character(len=256), allocatable :: frames(:)
    real(wp), allocatable :: times(:)
    integer, allocatable :: nparts(:)
    real(wp) :: w0, eps_t, t_next_frame
    integer :: u, ios, nframe, steps_since_frame, k

    w0 = wall_seconds()
    call sch%t_output%start()
    ! the stored centroids: those of the mixed cells' planes now (what a
    ! remap would be given; the planes themselves are unchanged by this; a
    ! decomposed run's blocks were refreshed by the caller, `whole_dump`)
    if (sch%pc%nranks == 1) call centroids_refresh(st%g, st%mx, es%centroids)
    path = restart_path(sch, st%step)
    if (.not. allocated(sch%out%frames)) then
      sch%out%frames = [character(len=256) ::]
      sch%out%times = [real(wp) ::]
      sch%out%nparts = [integer ::]
    end if
    frames = sch%out%frames
    times = sch%out%times
    nparts = sch%out%nparts
    ! at the segment's last step: the schedule after its final frame (module
    ! notes), for this dump only (the driver writes that frame next)
    nframe = sch%out%nframe
    steps_since_frame = sch%steps_since_frame
    t_next_frame = sch%t_next_frame
    eps_t = 1.0e-12_wp*cfg%control%t_end          ! as the time loop's
    if (.not. (st%t < cfg%control%t_end - eps_t .and. st%step < cfg%control%max_steps)) then
      if (frame_due(cfg, st, sch, eps_t)) then
        sch%steps_since_frame = 0
        call advance_schedule(sch%t_next_frame, st%t, cfg%output%frame_dt, eps_t)
      end if
      frames = [character(len=256) :: frames, frame_name(sch, sch%out%nframe)]
      times = [times, st%t]
      k = 0
      if (present(parts)) k = findloc(parts%location, LOC_PARTICLE, 1)
      if (k > 0) then
        nparts = [nparts, parts(k)%total]
      else
        nparts = [nparts, st%pt%np]
      end if
      sch%out%nframe = sch%out%nframe + 1
    end if
    ! registered afresh: an Euler step may have reallocated the mixed cells
    call register_all(st, sch, es, reg)
    if (sch%pc%nranks > 1) then
      call restart_write(path, reg, cfg%echo, frames, times, err, nparts, comm=sch%pc%world, ix=st%g%grid_index_t, &
                         parts=parts)
    else
      call restart_write(path, reg, cfg%echo, frames, times, err, nparts)
    end if
    sch%out%nframe = nframe
    sch%steps_since_frame = steps_since_frame
    sch%t_next_frame = t_next_frame
    call sch%t_output%stop()
    if (allocated(err)) then
      err%category = ERR_IO
      return
    end if
    sch%dump_wall = wall_seconds() - w0
    write(entry, '(f12.3)') sch%dump_wall
    call log_line(sch%log, 'restart '//path//' at step '//itoa(st%step)//', t = '//rtoa(st%t)//' ('// &
                  trim(adjustl(entry))//' s)')
    entry = path
    if (allocated(sch%dumps)) then
      sch%dumps = [sch%dumps, entry]
    else
      sch%dumps = [entry]
    end if
    do while (size(sch%dumps) > cfg%control%dump_keep)
      if (sch%pc%rank == 0) then
        open(newunit=u, file=trim(sch%dumps(1)), status='old', iostat=ios)
        if (ios == 0) close(u, status='delete')
      end if
      sch%dumps = sch%dumps(2:)
    end do
  end subroutine write_restart

  !> The file name (without folder) of frame number `k`, as io_output names
  !> it.
  function frame_name(sch, k) result(name)
    type(schedule_t), intent(in) :: sch
    integer, intent(in) :: k
    character(len=256) :: name
    write(name, '(a,"_",i5.5,".h5")') sch%out%name, k
  end function frame_name

  !> The next output time after a restart: the stored one if the interval is
  !> on, none if the interval is now off, else the next multiple of it.
  pure real(wp) function next_time(stored, interval, t)
    real(wp), intent(in) :: stored, interval, t
    if (interval <= 0.0_wp) then
      next_time = huge(1.0_wp)
    else if (stored < huge(1.0_wp)) then
      next_time = stored
    else
      next_time = (aint(t/interval) + 1.0_wp)*interval
    end if
  end function next_time

  !> Replaces the state built from the deck by the one in the restart file.
  !> The file's mixed cells may be more or fewer than the deck's (a remap
  !> changes them): their storage is first reallocated to the stored sizes.
  !> A file that cannot be used is an input error.
  !>
  !> With `block` (a block of a decomposed run) each rank reads its block's
  !> nodes and cells from the file, and the mixed cells and particles of
  !> its cells only (`mixed_read_block`; the particles by their hosts,
  !> `restart_cell_runs`, checked against the particles the blocks seeded
  !> by id over the ranks, `parallel_particles_ids`, then those of its cells
  !> and ghost layers taken, `particles_take`); the conservation report is
  !> then the caller's.
  subroutine read_restart(cfg, st, sch, es, err, block)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: block
    type(registry_t) :: reg
    character(len=*), parameter :: mixed_damaged = ' is damaged: its mixed cells do not match its cell materials'
    logical :: blocks, ok, coupled
    character(len=256), allocatable :: frames(:)
    real(wp), allocatable :: times(:)
    character(len=:), allocatable :: path
    integer, allocatable :: dims(:), nparts(:), seed_body(:), seed_mat(:), seeded(:, :), pruns(:, :)
    integer :: n, nslot, nseed, nsolid, nhist, stat, k, n1(1), nread, bad(5)
    type(particles_t) :: whole_pt
    type(strength_slot_t), allocatable :: models(:)
    logical :: pblocks

    blocks = .false.
    if (present(block)) blocks = block
    path = trim(cfg%control%restart_from)
    call restart_read_int_scalar(path, 'mixed_n', n, err)
    if (.not. allocated(err)) call restart_read_int_scalar(path, 'mixed_nslot', nslot, err)
    if (allocated(err)) then
      call error_set(err, 'cannot restart', '&run restart_from: '//err%msg, ERR_INPUT)
      return
    end if
    ! the sizes, before anything is allocated to them: against the grid (a
    ! mixed cell is a grid cell with at least one slot), then against the
    ! shapes of the file's own mixed-cell arrays
    if (n < 0 .or. n > product(st%g%gn) .or. nslot < n) then
      call error_set(err, 'cannot restart', '&run restart_from: '//path//' is damaged: scalars/mixed_n = '// &
                     itoa(n)//', scalars/mixed_nslot = '//itoa(nslot)//' (the grid has '//itoa(product(st%g%gn))// &
                     ' cells; each mixed cell has at least one slot)', ERR_INPUT)
      return
    end if
    call register_all(st, sch, es, reg)
    call restart_check_counts(path, reg, LOC_MIXED_CELL, st%mx%n, n, 'scalars/mixed_n', err)
    if (.not. allocated(err)) call restart_check_counts(path, reg, LOC_MIXED_SLOT, st%mx%nslot, nslot, &
                                                        'scalars/mixed_nslot', err)
    if (allocated(err)) then
      call error_set(err, 'cannot restart', '&run restart_from: '//err%msg, ERR_INPUT)
      return
    end if
    ! (a block reads only its own, once its cells are read: `mixed_read_block`)
    if ((n /= st%mx%n .or. nslot /= st%mx%nslot) .and. .not. blocks) then
      st%mx = mixed_t()   ! frees the deck's storage
      call mixed_allocate(st%mx, n, nslot, err)
      if (allocated(err)) then
        st%mx = mixed_t()
        return
      end if
      call log_line(sch%log, 'restart: '//itoa(n)//' mixed cells ('//itoa(nslot)//' material slots)')
    end if
    ! the particles the file holds: fewer than the deck seeds once some left
    ! the grid through an open face
    nseed = st%pt%np
    ! (the blocks' seeded particles: each block its owned ones, and reads
    ! the file's of its cells only)
    pblocks = blocks .and. st%pblocks
    if (pblocks) then
      seeded = reshape([(st%pt%id(k), st%pt%body(k), st%pt%mat(k), k = 1, st%pt%np)], [3, st%pt%np])
      seeded = seeded(:, pack([(k, k = 1, st%pt%np)], st%pw%owned))
      n1 = size(seeded, 2)
      call parallel_sum(sch%pc, n1)
      nseed = n1(1)
    end if
    if (nseed > 0) then
      ! what each seeded particle is (a particle keeps its body and solid)
      if (.not. pblocks) then
        seed_body = st%pt%body
        seed_mat = st%pt%mat
        seed_body(st%pt%id) = st%pt%body
        seed_mat(st%pt%id) = st%pt%mat
      end if
      call restart_read_dims(path, 'particle_id', dims, err)
      if (.not. allocated(err)) then
        if (size(dims) /= 1) call error_set(err, 'restart_read', path//': state/particle_id has the wrong rank')
      end if
      if (.not. allocated(err)) then
        if (dims(1) > nseed) call error_set(err, 'restart_read', path//' holds '//itoa(dims(1))// &
                                            ' particles; the deck seeds '//itoa(nseed))
      end if
      if (.not. allocated(err)) then
        if (dims(1) < nseed .and. .not. any(st%bc%kind == BC_INFLOW .or. st%bc%kind == BC_OUTFLOW)) &
          call error_set(err, 'restart_read', path//' holds '//itoa(dims(1))//' particles; the deck seeds '// &
                         itoa(nseed)//' and none can leave (the deck has no open face)')
      end if
      if (.not. allocated(err)) call restart_check_counts(path, reg, LOC_PARTICLE, st%pt%np, dims(1), &
                                                          'the count of state/particle_id', err)
      if (allocated(err)) then
        call error_set(err, 'cannot restart', '&run restart_from: '//err%msg, ERR_INPUT)
        return
      end if
      nread = dims(1)
      if (pblocks) then
        ! (the file's particles hosted by the block's cells, owned or
        ! ghost: every rank scans the file's hosts, in pieces)
        associate (g => st%g)
          call restart_cell_runs(path, 'particle_cell', g%gn, g%slo + g%off, g%shi + g%off, g%clo + g%off, &
                                 g%chi + g%off, pruns, n1(1), err)
        end associate
        if (allocated(err)) then
          call error_set(err, 'cannot restart', '&run restart_from: '//err%msg, ERR_INPUT)
          return
        end if
        nread = sum(pruns(2, :))
      end if
      if (dims(1) /= nseed .or. pblocks) then
        coupled = allocated(st%pt%mvf)
        nsolid = st%pt%nsolid
        nhist = st%pt%nhist
        call particles_allocate(st%pt, nread, nsolid, nhist, err)
        st%pt%spread = cfg%hydro%particle_gimp
        if (.not. allocated(err) .and. coupled) then
          allocate(st%pt%mvf(nread), stat=stat)
          if (stat /= 0) call error_set(err, 'read_restart', 'out of memory for the particles')
        end if
        if (.not. allocated(err) .and. allocated(st%pw%vh) .and. .not. pblocks) &
          call particles_work_resize(st%pw, dims(1), nhist, err)
        if (allocated(err)) return
        if (dims(1) /= nseed) call log_line(sch%log, 'restart: '//itoa(dims(1))//' particles ('// &
                                            itoa(nseed - dims(1))//' of those seeded left the grid)')
      end if
    end if
    call register_all(st, sch, es, reg)
    ! (what a dump without the particles' support widths leaves: `huge`)
    if (st%pt%spread) st%pt%lsup = huge(1.0_wp)
    if (blocks) then
      ! (a block's mixed cells and particles: those of its cells only)
      call restart_read(path, reg, frames, times, err, nparts, st%g%grid_index_t, &
                        later=[LOC_MIXED_CELL, LOC_MIXED_SLOT, merge(LOC_PARTICLE, LOC_MIXED_SLOT, pblocks)])
      if (.not. allocated(err)) call mixed_read_block(path, st, sch, es, reg, n, nslot, ok, err)
      if (.not. (allocated(err) .or. ok)) call error_set(err, 'restart_read', path//mixed_damaged)
      if (.not. allocated(err) .and. pblocks .and. nseed > 0) &
        call restart_read_parts(path, reg, [restart_part_t(LOC_PARTICLE, dims(1), pruns)], err)
    else
      call restart_read(path, reg, frames, times, err, nparts)
    end if
    if (.not. allocated(err)) call check_ranges(reg, size(frames), path, err)
    if (.not. allocated(err)) call check_materials(st, path, err)
    ! the particles' indices, then their material ranges and cell binning
    ! (derived, not stored)
    if (pblocks) then
      ! (the block's share of the file's particles, host cells numbered in
      ! the whole grid: checked, against the seeded ones by id over the
      ! ranks, then the block's taken; collective, a block's damage every
      ! rank's)
      call agree_error(sch%pc, err)
      if (.not. allocated(err) .and. nseed > 0) then
        call particles_check(st%pt, product(st%g%gn), nseed, err, run_places(pruns))
        if (allocated(err)) call error_set(err, 'restart_read', path//' is damaged: '//err%msg)
      end if
      call agree_error(sch%pc, err)
      if (.not. allocated(err) .and. nseed > 0) then
        call parallel_particles_ids(sch%pc, nseed, seeded, owned_records(st, run_places(pruns)), bad)
        if (bad(1) > 0) call error_set(err, 'restart_read', path//' is damaged: '//bad_id(bad))
      end if
      if (.not. allocated(err)) then
        whole_pt = st%pt
        if (allocated(st%pw%models)) models = st%pw%models
        call particles_take(st, whole_pt, grid_index(st%g%gn(1), st%g%gn(2), st%g%gn(3)), models, err)
      end if
    end if
    if (.not. allocated(err)) then
      if (.not. pblocks) call particles_check(st%pt, st%g%ncell, nseed, err)
      if (.not. allocated(err) .and. st%pt%np > 0 .and. .not. pblocks) &
        call particles_as_seeded(st%pt, seed_body, seed_mat, err)
      if (.not. allocated(err)) call particles_hosted(st%g, st%pt, err)
      if (.not. allocated(err)) call particles_index(st%pt, st%g%ncell, err)
      if (allocated(err)) call error_set(err, 'restart_read', path//' is damaged: '//err%msg)
    end if
    if (.not. allocated(err) .and. st%pt%spread .and. st%pt%np > 0) then
      if (any(st%pt%lsup(1:st%pt%np) >= huge(1.0_wp))) then
        ! a dump of linear supports continued with spread ones: the
        ! particles' domains from their hosts now, as at a re-location
        call particles_support_widths(st%g, st%pt)
        call log_line(sch%log, 'restart: '//path//' has no particle support widths (written with '// &
                      'particle_support = ''linear''): the domains start from the particles'' hosts now')
      end if
    end if
    if (allocated(err)) then
      call error_set(err, 'cannot restart', '&run restart_from: '//err%msg, ERR_INPUT)
      return
    end if
    if (.not. mixed_consistent(st)) then
      call error_set(err, 'cannot restart', '&run restart_from: '//path//mixed_damaged, ERR_INPUT)
      return
    end if
    if (st%t >= cfg%control%t_end) then
      call error_set(err, 'cannot restart', '&run restart_from: '//path//' is at t = '//rtoa(st%t)// &
                     ', at or past &run t_end = '//rtoa(cfg%control%t_end)//': nothing to run (raise t_end to go on)', &
                     ERR_INPUT)
      return
    end if
    call state_after_read(st)
    ! the particles' hosts are the dump's (Euler steps relocate them): bin
    ! them again; the nodal mass term follows at the first step
    call particles_index(st%pt, st%g%ncell, err)
    if (allocated(err)) return
    st%pw%mass_ready = .false.
    ! the frame list continues the XDMF series where it was
    sch%out%frames = frames
    sch%out%times = times
    ! (a dump from before particles could leave: every frame had them all)
    if (.not. allocated(nparts)) nparts = [(st%pt%np, k = 1, size(times))]
    sch%out%nparts = nparts
    call material_index_cells(st%mats, st%h%mat, st%mx, err)
    if (allocated(err)) return
    ! settings a restart may change: frame and dump intervals
    sch%t_next_frame = next_time(sch%t_next_frame, cfg%output%frame_dt, st%t)
    sch%t_next_dump = next_time(sch%t_next_dump, cfg%control%dump_dt, st%t)
    sch%step_start = st%step
    sch%eta_t = st%t
    call log_line(sch%log, 'restarted from '//path//' at step '//itoa(st%step)//', t = '//rtoa(st%t))
    ! (its sums are the ranks' together: a block's caller reports once the
    ! ranks agree that every block was read)
    if (.not. blocks) call report_conservation(st, sch%log, 'restart')
  end subroutine read_restart

  !> Every registered scalar in the range its owner registered (`lower`)
  !> and held to the deck's magnitude rule (below 1e30, or the largest real,
  !> which marks "never"; io_restart holds the arrays to both), the
  !> generator state not zero (a xorshift generator stays at zero; its bits
  !> are not a number to compare) and the frame counter equal to the stored
  !> frame list's length. Values are finite here (io_restart), so the
  !> comparisons cannot trap.
  subroutine check_ranges(reg, nframes, path, err)
    type(registry_t), intent(in) :: reg
    integer, intent(in) :: nframes
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    real(wp), parameter :: too_big = 1.0e30_wp
    character(len=96) :: name
    integer :: k
    logical :: pos, nonneg

    do k = 1, reg%n
      associate (e => reg%e(k))
        pos = e%lower == LOWER_POSITIVE
        nonneg = e%lower == LOWER_NONNEGATIVE
        select case (e%kind)
        case (K_REAL_SCALAR)
          name = 'scalars/'//trim(e%name)
          if (e%units == 'bits') then
            if (e%name == 'rng_state' .and. transfer(e%rs, 0_int64) == 0_int64) call error_set(err, 'restart_read', path// &
              ' is damaged: '//trim(name)//' is zero (a random generator state never is)')
          else if (.not. (abs(e%rs) < too_big .or. abs(e%rs) >= huge(1.0_wp))) then
            call error_set(err, 'restart_read', path//' is damaged: '//trim(name)//' = '//rtoa(e%rs)// &
                           ' (magnitudes of 1e30 or more are refused)')
          else if ((pos .and. .not. e%rs > 0.0_wp) .or. (nonneg .and. .not. e%rs >= 0.0_wp)) then
            call error_set(err, 'restart_read', path//' is damaged: '//trim(name)//' = '//rtoa(e%rs)// &
                           trim(merge(' (must be > 0) ', ' (must be >= 0)', pos)))
          end if
        case (K_INT_SCALAR)
          name = 'scalars/'//trim(e%name)
          if (nonneg .and. e%is < 0) call error_set(err, 'restart_read', path//' is damaged: '// &
            trim(name)//' = '//itoa(e%is)//' (must be >= 0)')
          if (e%name == 'nframe' .and. e%is /= nframes .and. .not. allocated(err)) &
            call error_set(err, 'restart_read', path//' is damaged: '//trim(name)//' = '//itoa(e%is)// &
                           ', but output/frames lists '//itoa(nframes)//' frames')
        case (K_INT)
        end select
      end associate
      if (allocated(err)) return
    end do
  end subroutine check_ranges

  !> Each particle's body and solid those of the particle the deck seeds
  !> with its id (seed_body, seed_mat: by id); the message names the first
  !> that is not. (The ids were checked: 1..the number seeded.)
  subroutine particles_as_seeded(pt, seed_body, seed_mat, err)
    type(particles_t), intent(in) :: pt
    integer, intent(in) :: seed_body(:), seed_mat(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: k
    do k = 1, pt%np
      if (pt%body(k) /= seed_body(pt%id(k))) then
        call error_set(err, 'particles_check', 'state/particle_body = '//itoa(pt%body(k))//' at particle '// &
                       itoa(k)//' (the deck seeds particle '//itoa(pt%id(k))//' in body '// &
                       itoa(seed_body(pt%id(k)))//')')
      else if (pt%mat(k) /= seed_mat(pt%id(k))) then
        call error_set(err, 'particles_check', 'state/particle_material = '//itoa(pt%mat(k))//' at particle '// &
                       itoa(k)//' (the deck seeds particle '//itoa(pt%id(k))//' of solid '// &
                       itoa(seed_mat(pt%id(k)))//')')
      end if
      if (allocated(err)) return
    end do
  end subroutine particles_as_seeded

  !> The places in the file (1-based) of the entries read at runs
  !> (`restart_part_t`), in order.
  pure function run_places(runs) result(place)
    integer, intent(in) :: runs(:, :)
    integer :: place(sum(runs(2, :)))
    integer :: r, q, n
    n = 0
    do r = 1, size(runs, 2)
      place(n + 1:n + runs(2, r)) = [(runs(1, r) + q, q = 1, runs(2, r))]
      n = n + runs(2, r)
    end do
  end function run_places

  !> got(4, n): the id, body, solid and place in the file of each particle
  !> of the block's share of a restart file (hosts numbered in the whole
  !> grid) that the block owns.
  function owned_records(st, place) result(got)
    type(state_t), intent(in) :: st
    integer, intent(in) :: place(:)
    integer, allocatable :: got(:, :)
    integer :: k, m, c, ijk(3)
    logical :: mine(st%pt%np)
    associate (g => st%g, p => st%pt)
      do k = 1, p%np
        c = p%cell(k) - 1
        ijk = [mod(c, g%gn(1)), mod(c/g%gn(1), g%gn(2)), c/(g%gn(1)*g%gn(2))] + 1 - g%off
        mine(k) = g%owns_cell(ijk(1), ijk(2), ijk(3))
      end do
      got = reshape([(p%id(k), p%body(k), p%mat(k), place(k), k = 1, p%np)], [4, p%np])
      m = count(mine)
      got(:, :m) = got(:, pack([(k, k = 1, p%np)], mine))
      got = got(:, :m)
    end associate
  end function owned_records

  !> The message of a particle read that `parallel_particles_ids` found
  !> wrong (as `particles_check` and `particles_as_seeded` word it).
  function bad_id(bad) result(msg)
    integer, intent(in) :: bad(5)
    character(len=:), allocatable :: msg
    select case (bad(1))
    case (1)
      msg = 'state/particle_id = '//itoa(bad(2))//' at particle '//itoa(bad(3))//' (the id is repeated)'
    case (2)
      msg = 'state/particle_body = '//itoa(bad(4))//' at particle '//itoa(bad(3))//' (the deck seeds particle '// &
            itoa(bad(2))//' in body '//itoa(bad(5))//')'
    case default
      msg = 'state/particle_material = '//itoa(bad(4))//' at particle '//itoa(bad(3))//' (the deck seeds particle '// &
            itoa(bad(2))//' of solid '//itoa(bad(5))//')'
    end select
  end function bad_id


  !> Each particle near the point of its host cell that its natural
  !> coordinates name: within half the cell's size (its position is that
  !> point on the grid of some stage of the step, `particles_g2p`, which a
  !> step moves by less; a particle filed under another cell is a cell's
  !> size or more away); the message names the first that is not.
  subroutine particles_hosted(g, pt, err)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: pt
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: xn(3, 8), sh(8), xp(3), h
    integer :: k, a
    do k = 1, pt%np
      call g%gather(pt%cell(k), g%x, xn)
      sh = particles_shape_values(pt%xi(:, k))
      xp = 0.0_wp
      do a = 1, 8
        xp = xp + sh(a)*xn(:, a)
      end do
      h = maxval(maxval(xn, dim=2) - minval(xn, dim=2))
      if (maxval(abs(xp - pt%x(:, k))) <= 0.5_wp*h) cycle
      call error_set(err, 'particles_check', 'state/particle_x of particle '//itoa(k)//' is not in its host cell '// &
                     itoa(pt%cell(k))//' at state/particle_xi (off by '//rtoa(maxval(abs(xp - pt%x(:, k))))// &
                     ', the cell is '//rtoa(h)//' across)')
      return
    end do
  end subroutine particles_hosted

  !> Each cell's material is one of this deck's (1..nmat) or a mixed cell
  !> (-1..-mixed_n), and each mixed slot's material one of this deck's; the
  !> message names the first that is not.
  subroutine check_materials(st, path, err)
    type(state_t), intent(in) :: st
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer :: nmat, bad
    nmat = size(st%mats)
    bad = findloc(st%h%mat >= -st%mx%n .and. st%h%mat <= nmat .and. st%h%mat /= 0, .false., 1)
    if (bad > 0) then
      call error_set(err, 'restart_read', path//' is damaged: state/material = '//itoa(st%h%mat(bad))// &
                     ' in cell '//itoa(bad)//' (this deck has materials 1..'//itoa(nmat)//'; -1..-'// &
                     itoa(st%mx%n)//' are its mixed cells)')
      return
    end if
    if (st%mx%nslot == 0) return
    bad = findloc(st%mx%mat >= 1 .and. st%mx%mat <= nmat, .false., 1)
    if (bad > 0) call error_set(err, 'restart_read', path//' is damaged: state/mixed_material = '// &
                                itoa(st%mx%mat(bad))//' in slot '//itoa(bad)//' (this deck has materials 1..'// &
                                itoa(nmat)//')')
  end subroutine check_materials

  !> False for mixed cells that do not index the grid consistently (a
  !> damaged file; later code would index out of bounds; their materials are
  !> checked by check_materials):
  !> mixed cell k is the cell whose material is -k, and no other cell has a
  !> material <= 0.
  logical function mixed_consistent(st) result(ok)
    type(state_t), intent(in) :: st
    integer :: k
    ok = mixed_well_formed(st%mx, st%g%ncell)
    do k = 1, st%mx%n
      if (.not. ok) exit
      ok = st%h%mat(st%mx%cell(k)) == -k
    end do
    ok = ok .and. count(st%h%mat <= 0) == st%mx%n
  end function mixed_consistent

  !> True for mixed cells whose slots follow on from one another, at least
  !> one each, and whose cells are among the grid's ncell.
  logical function mixed_well_formed(mx, ncell) result(ok)
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: ncell
    integer :: k
    ok = mx%start(1) == 1 .and. mx%start(mx%n + 1) == mx%nslot + 1
    do k = 1, mx%n
      if (.not. ok) exit
      ok = mx%start(k + 1) > mx%start(k) .and. mx%cell(k) >= 1 .and. mx%cell(k) <= ncell
    end do
  end function mixed_well_formed

  !> A block's mixed cells from restart file `path`, whose mixed_n = ntot
  !> and mixed_nslot = nstot (its datasets' shapes checked already): the
  !> cells of the block (owned and ghost) whose material, read, is -K hold
  !> the file's mixed cell K, and only those cells and their slots are
  !> read (their starts first, `restart_read_int_runs`, then the rest,
  !> `restart_read_parts`), then numbered in the block (`mixed_numbers`);
  !> reg is registered again. A file whose cells and mixed cells do not
  !> match is damaged: ok false.
  subroutine mixed_read_block(path, st, sch, es, reg, ntot, nstot, ok, err)
    character(len=*), intent(in) :: path
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(registry_t), intent(inout) :: reg
    integer, intent(in) :: ntot, nstot
    logical, intent(out) :: ok
    type(error_t), allocatable, intent(inout) :: err
    type(restart_part_t) :: parts(2)
    integer, allocatable :: cells(:), keys(:), plus(:, :), sv(:), slots(:)
    integer :: m, k, r, j, q, c, stat

    cells = pack([(c, c = 1, st%g%ncell)], st%h%mat < 0)
    m = size(cells)
    keys = -st%h%mat(cells)
    ok = all(keys <= ntot)
    if (m > 1) ok = ok .and. all(keys(2:) > keys(:m - 1))
    if (.not. ok) return
    call sorted_runs(keys - 1, parts(1)%runs, stat)
    if (stat /= 0) call error_set(err, 'restart_read', error_no_memory('the block''s mixed cells'))
    if (allocated(err)) return
    ! each run's starts and the one after it
    plus = parts(1)%runs
    plus(2, :) = plus(2, :) + 1
    call restart_read_int_runs(path, 'mixed_start', ntot + 1, plus, sv, err)
    if (allocated(err)) return
    ! the block's starts, and its slots' places in the file
    keys = [1, (0, k = 1, m)]
    q = 0
    j = 0
    do r = 1, size(plus, 2)
      do k = 1, plus(2, r) - 1
        q = q + 1
        ok = ok .and. sv(j + k) >= 1 .and. sv(j + k + 1) > sv(j + k) .and. sv(j + k + 1) <= nstot + 1
        if (.not. ok) return
        keys(q + 1) = keys(q) + sv(j + k + 1) - sv(j + k)
      end do
      j = j + plus(2, r)
    end do
    allocate(slots(keys(m + 1) - 1), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'restart_read', error_no_memory('the block''s mixed cells'))
      return
    end if
    q = 0
    j = 0
    do r = 1, size(plus, 2)
      do k = 1, plus(2, r) - 1
        q = q + 1
        slots(keys(q):keys(q + 1) - 1) = [(c - 1, c = sv(j + k), sv(j + k + 1) - 1)]
      end do
      j = j + plus(2, r)
    end do
    if (size(slots) > 1) ok = all(slots(2:) > slots(:size(slots) - 1))
    if (.not. ok) return
    call sorted_runs(slots, parts(2)%runs, stat)
    if (stat /= 0) call error_set(err, 'restart_read', error_no_memory('the block''s mixed cells'))
    if (allocated(err)) return
    parts(1)%location = LOC_MIXED_CELL
    parts(1)%total = ntot
    parts(2)%location = LOC_MIXED_SLOT
    parts(2)%total = nstot
    st%mx = mixed_t()
    call mixed_allocate(st%mx, m, size(slots), err)
    if (allocated(err)) return
    st%mx%start = keys
    call reg%clear()
    call register_all(st, sch, es, reg)
    call restart_read_parts(path, reg, parts, err)
    if (allocated(err)) return
    ok = all(st%mx%cell == [(st%g%global_cell(cells(k)), k = 1, m)])
    if (.not. ok) return
    st%mx%cell = cells
    call mixed_numbers(st)
  end subroutine mixed_read_block

  !> The mixed cells mx of the block of grid g (its owned and ghost cells),
  !> in cell order and numbered in the block, from the whole grid's wx (in
  !> cell order, cells numbered in the whole grid); pick(q): the number of
  !> mixed cell q in wx.
  subroutine mixed_of_block(g, wx, mx, err, pick)
    type(grid_t), intent(in) :: g
    type(mixed_t), intent(in) :: wx
    type(mixed_t), intent(inout) :: mx
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable, intent(out) :: pick(:)
    type(grid_index_t) :: whole
    integer, allocatable :: cell(:)
    integer :: k, m, ijk(3), stat
    allocate(pick(wx%n), cell(wx%n), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'mixed_of_block', 'out of memory')
      return
    end if
    whole = grid_index(g%gn(1), g%gn(2), g%gn(3))
    m = 0
    do k = 1, wx%n
      call whole%cell_ijk(wx%cell(k), ijk(1), ijk(2), ijk(3))
      ijk = ijk - g%off
      if (any(ijk < g%slo .or. ijk > g%shi)) cycle
      m = m + 1
      pick(m) = k
      cell(m) = g%cell(ijk(1), ijk(2), ijk(3))
    end do
    pick = pick(:m)
    call mixed_subset(wx, pick, cell(:m), mx, err)
  end subroutine mixed_of_block

  !> A mixed cell's material is minus its mixed-cell number, which differs
  !> between a block and the whole grid: renumbered from the mixed cells.
  subroutine mixed_numbers(st)
    type(state_t), intent(inout) :: st
    integer :: k
    do k = 1, st%mx%n
      st%h%mat(st%mx%cell(k)) = -k
    end do
  end subroutine mixed_numbers
end module driver_restart
