!> The driver: reads the deck, builds the scene, runs the time loop, and owns
!> all input, output and the decision to stop. The run is held in four
!> objects passed explicitly: the resolved configuration (read-only), the
!> physical state, the output schedule (with the log and timers) and the
!> Euler phase's state. Failures come back as `error_t` values and end the
!> run in one place (`fail`, then `driver_halt`).
module driver
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t, error_set, error_exit_status, error_is_no_memory, ERR_RUNTIME, ERR_INPUT
  use base_config, only: max_line
  use base_timers, only: wall_seconds
  use base_exit, only: exit_guard_install
  use base_stop, only: stop_signals_install, stop_signal_caught, stop_signal_name, stop_file_present, stop_file_remove
  use lagrange_integrator, only: lagrange_step
  use driver_particles, only: particles_step
  use io_log, only: log_t, log_line, log_error
  use io_gauges, only: gauges_close
  use io_hdf5, only: hdf5_start, hdf5_stop, hdf5_version
  use base_build, only: code_version, build_type
  use, intrinsic :: iso_fortran_env, only: compiler_version
  use material_table, only: material_burn_start
  use driver_halt, only: halt, refuse, EXIT_WALL_TIME
  use driver_config, only: config_t, config_read, config_defaults_text
  use driver_state, only: state_t, state_totals, centroid_text, state_note_pressure
  use driver_output, only: schedule_t, schedule_init, open_outputs, write_frame, frame_out, gauge_output, progress, &
                           report_conservation, frame_due, dump_due, advance_schedule, history_output, &
                           outputs_after_restart, step_limit_text, tracks_init, tracks_close, blast_report, &
                           tracers_init, tracers_end
  use io_tracers, only: tracers_place, tracers_relocate
  use driver_scene, only: build_scene
  use driver_prerun, only: prerun_write, prerun_report, prerun_gauge_rows
  use driver_restart, only: check_restart_deck, restart_path, write_restart, read_restart
  use driver_euler, only: euler_state_t, euler_init, euler_standard_ratios, euler_due, euler_step, euler_report
  use parallel_comm, only: comm_t, parallel_start
  use mesh_grid, only: grid_index_t
  use driver_parallel, only: parallel_blocks, agree_error
  use base_memory, only: memory_keep_freed, memory_peak_mib
  use driver_whole, only: whole_build, whole_euler, whole_dump, whole_restart
  implicit none
  private
  public :: driver_run, driver_check, driver_print_defaults, driver_print_version

  !> The environment variables in which MPI launchers give a process its
  !> rank (Open MPI, PMIx, MPICH and Slurm's PMI).
  character(len=*), parameter :: rank_variables(3) = [character(len=20) :: 'OMPI_COMM_WORLD_RANK', 'PMIX_RANK', 'PMI_RANK']

contains

  !> Runs the deck at `deck_path` to completion, or stops with a message.
  !> `restart` (the command line's `--restart FILE`): continue from that
  !> restart file (it replaces the deck's &run restart_from).
  subroutine driver_run(deck_path, restart)
    character(len=*), intent(in) :: deck_path
    character(len=*), intent(in), optional :: restart
    type(config_t) :: cfg
    type(state_t) :: st
    type(schedule_t) :: sch
    type(euler_state_t) :: es
    type(error_t), allocatable :: err
    character(len=max_line), allocatable :: problems(:)
    character(len=:), allocatable :: summary
    type(grid_index_t) :: block

    call exit_guard_install()
    ! freed work arrays kept for the next Euler step (`base_memory`)
    call memory_keep_freed()
    ! HDF5 starts before MPI: started after MPI_Init, parallel HDF5 would
    ! close itself inside MPI_Finalize, which crashes on a file whose close
    ! failed (a full disk) instead of leaving it to the OS (`hdf5_stop`)
    call hdf5_start(err)
    call parallel_start(sch%pc)
    ! (after MPI's start: SIGTERM and SIGUSR1 ask for a restart and a stop)
    call stop_signals_install()
    ! one rank speaks for all (each reads the deck and finds the same problems)
    sch%log%quiet = sch%pc%rank /= 0
    call sch%t_total%start()
    call sch%t_setup%start()
    call config_read(deck_path, cfg, problems, restart=restart)
    if (size(problems) > 0) call refuse(sch%log, problems, 'the deck has '//itoa(size(problems))// &
                                        ' problem(s); nothing was run')
    sch%restarting = len_trim(cfg%control%restart_from) > 0
    if (sch%restarting) then
      call check_restart_deck(cfg, problems, summary)
      if (size(problems) > 0) call refuse(sch%log, problems, summary)
    end if
    if (.not. allocated(err)) call open_outputs(cfg, sch, err)
    if (len_trim(cfg%control%restart_overridden) > 0) call log_line(sch%log, 'restart: --restart '// &
      trim(cfg%control%restart_from)//' replaces the deck''s restart_from = '''// &
      trim(cfg%control%restart_overridden)//'''')
    call agree_error(sch%pc, err)
    if (.not. allocated(err)) call parallel_blocks(cfg, sch%pc, block, st%halo, err)
    if (.not. allocated(err) .and. sch%pc%nranks > 1) &
      call log_line(sch%log, 'run: '//itoa(sch%pc%nranks)//' MPI ranks, blocks '//itoa(sch%pc%dims(1))//' x '// &
                    itoa(sch%pc%dims(2))//' x '//itoa(sch%pc%dims(3))//' (ghost layers '//itoa(block%ng)//'), '// &
                    cuts_text(sch%pc))
    if (.not. allocated(err)) call build_scene(cfg, st, sch%log, err, block)
    if (.not. allocated(err) .and. allocated(st%pre1d)) then
      call prerun_report(st%pre1d, sch%log)
      if (sch%pc%rank == 0) call prerun_write(st%pre1d, sch%out%dir//'/'//sch%out%name, err)
    end if
    call agree_error(sch%pc, err)
    if (allocated(err)) call fail(cfg, st, sch, err)
    if (cfg%pre1d%time > 0.0_wp .and. .not. cfg%control%t_end > cfg%pre1d%time .and. .not. sch%restarting) then
      ! (t_end <= &prerun time: the 1D run was the whole run)
      call log_line(sch%log, 'prerun: t_end <= &prerun time: the 1D run alone; its profile and gauges are in '// &
                    sch%out%dir//'/'//sch%out%name//'_prerun*.txt')
      call sch%t_total%stop()
      call hdf5_stop(err)
      call halt(sch%log, 0)
    end if
    call agree_error(sch%pc, err)
    if (.not. allocated(err)) call whole_build(cfg, sch%pc, st, sch%log, err)
    if (.not. allocated(err)) call tracks_init(cfg, st, sch, err)
    ! (on the blocks: a tracer's cell is the whole grid's index)
    if (.not. allocated(err)) call tracers_init(cfg, st, sch, err)
    if (.not. allocated(err)) then
      ! (on windows the blocks smooth their own nodes and return to their
      ! own initial nodes, or to their targets from the grid's faces)
      call euler_init(cfg%rezone, st%g, st%bc, sch%pc%nranks == 1, es, err)
      if (.not. allocated(err)) call euler_standard_ratios(st%g, es, err)
    end if
    call agree_error(sch%pc, err)
    if (allocated(err)) call fail(cfg, st, sch, err)
    if (sch%restarting) then
      if (sch%pc%nranks > 1) then
        call whole_restart(cfg, st, sch, es, err)
      else
        call read_restart(cfg, st, sch, es, err)
      end if
      if (.not. allocated(err)) call outputs_after_restart(cfg, st, sch, err)
      call agree_error(sch%pc, err)
      if (allocated(err)) call fail(cfg, st, sch, err)
    else
      call schedule_init(cfg, sch, st%t)
      call report_conservation(st, sch%log, 'initial')
      call write_frame(cfg, st, sch, err)
      if (allocated(err)) call fail(cfg, st, sch, err)
      ! (a mapped 1D run's gauge rows come first)
      if (allocated(st%pre1d)) call prerun_gauge_rows(st%pre1d, cfg%output%gauges(:, 1:cfg%output%ngauge), &
                                                       sch%gauges)
      call gauge_output(cfg, st, sch)
      call history_output(cfg, st, sch)
    end if
    call sch%t_setup%stop()
    call time_loop(cfg, st, sch, es)
    call write_frame(cfg, st, sch, err)
    if (allocated(err)) call fail(cfg, st, sch, err)
    call gauges_close(sch%gauges)
    call tracks_close(sch)
    call tracers_end(sch)
    call blast_report(cfg, sch)
    call sch%t_total%stop()
    call report_end(st, sch, es)
    call hdf5_stop(err)
    call halt(sch%log, 0)
  end subroutine driver_run

  !> The block cuts of a decomposed run for the log: the cell planes where
  !> the blocks meet in each direction that is cut, and what they balance.
  function cuts_text(pc) result(text)
    type(comm_t), intent(in) :: pc
    character(len=:), allocatable :: text
    character(len=1), parameter :: axis(3) = ['i', 'j', 'k']
    integer :: d, b, w0
    text = 'cut at'
    w0 = 0
    do d = 1, 3
      if (pc%dims(d) > 1) then
        text = text//' '//axis(d)//' ='
        do b = 1, pc%dims(d) - 1
          text = text//' '//itoa(pc%cuts(w0 + 1 + b))
        end do
      end if
      w0 = w0 + pc%dims(d) + 1
    end do
    if (pc%weighted) then
      text = text//' (balancing cells and particles: &run blocks_particle_weight)'
    else
      text = text//' (balancing cells)'
    end if
  end function cuts_text

  !> Reads and validates the deck at `deck_path` and prints it resolved
  !> (`lsalepm --check`): exit status 0 if it can run, else 2 with the
  !> problems. Nothing is written. Started by mpirun, every process checks
  !> (MPI is not started) and the first alone prints (its rank from the
  !> launcher's environment).
  subroutine driver_check(deck_path)
    character(len=*), intent(in) :: deck_path
    type(config_t) :: cfg
    type(log_t) :: log
    character(len=max_line), allocatable :: problems(:)
    character(len=16) :: rank
    integer :: k, stat
    call exit_guard_install()
    call config_read(deck_path, cfg, problems)
    do k = 1, 3
      call get_environment_variable(trim(rank_variables(k)), rank, status=stat)
      ! rank 0 alone reports and carries the status: an other rank's
      ! non-zero exit makes mpirun end the job before rank 0 has spoken
      if (stat == 0 .and. trim(rank) /= '0') call halt(log, 0)
    end do
    if (size(problems) > 0) call refuse(log, problems, 'the deck has '//itoa(size(problems))//' problem(s)')
    write(*, '(a)', advance='no') cfg%echo
    write(*, '(a)') 'deck '//deck_path//' is valid'
    call halt(log, 0)
  end subroutine driver_check

  !> Prints the version, the build and the libraries (`lsalepm --version`).
  subroutine driver_print_version()
    write(*, '(a)') 'lsalepm '//code_version//' ('//build_type//' build)', &
                    'compiler: '//compiler_version(), &
                    'HDF5 '//hdf5_version()
  end subroutine driver_print_version

  !> Prints every namelist group with its defaults (`lsalepm --defaults`).
  subroutine driver_print_defaults()
    write(*, '(a)', advance='no') config_defaults_text()
  end subroutine driver_print_defaults

  !> The cycle of ARCHITECTURE.md §1: stable step, Lagrangian phase, inspection and
  !> Euler phase, outputs.
  subroutine time_loop(cfg, st, sch, es)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable :: err
    real(wp) :: dt, work, wall_last, wall_now, eps_t, w0, dt_cap, dt_growth_cap, stop_checked
    integer :: bad_cell, bad_particle, report, stop_now, asked, n_euler, stat
    logical :: last, due

    eps_t = 1.0e-12_wp*cfg%control%t_end
    wall_last = wall_seconds()
    stop_checked = -huge(1.0_wp)
    do while (st%t < cfg%control%t_end - eps_t .and. st%step < cfg%control%max_steps)
      if (cfg%control%wall_time_limit > 0.0_wp) then
        ! (the ranks agree: each measures its own wall time)
        stop_now = merge(1, 0, near_wall_time_limit(cfg, sch))
        call st%halo%max_int(stop_now)
        if (stop_now == 1) call stop_for_wall_time(cfg, st, sch, es)
      end if

      ! LAGRANGE: the step the controller allows, cut to the stable step
      dt = step_cap(cfg, st, sch, dt_growth_cap)
      dt_cap = dt
      w0 = wall_seconds()
      call sch%t_lagrange%start()
      bad_particle = 0
      sch%dt_particle = 0
      call material_burn_start(st%mats, st%t)
      if (allocated(st%pw%mp)) then   ! (coupled particles; a block may hold none)
        call particles_step(cfg, st, dt, work, bad_cell, bad_particle, dt_cell=sch%dt_cell, &
                            dt_particle=sch%dt_particle)
      else
        call lagrange_step(st%g, st%h, st%bc, st%mats, st%mx, cfg%hydro, dt, work, bad_cell, dt_cell=sch%dt_cell, &
                           halo=st%halo)
      end if
      call sch%t_lagrange%stop()
      sch%step_wall = wall_seconds() - w0
      sch%dt_by_cell = dt < dt_cap .and. sch%dt_particle == 0
      if (bad_cell > 0) call error_set(err, 'lagrange_step', 'cell '//itoa(st%g%global_cell(bad_cell))// &
        ' has a non-positive volume (tangled grid) at t = '//rtoa(st%t)//lagrangian_hint(cfg), ERR_RUNTIME)
      if (.not. allocated(err) .and. bad_particle > 0) call error_set(err, 'particles_step', 'particle '// &
        itoa(bad_particle)//' (id '//itoa(st%pt%id(bad_particle))//') has an inverted host cell or a '// &
        'non-positive volume at t = '//rtoa(st%t), ERR_RUNTIME)
      if (bad_cell /= 0 .or. bad_particle /= 0) call agree_error(sch%pc, err)   ! (-1: on another rank)
      if (.not. allocated(err) .and. dt < cfg%control%dt_min) call error_set(err, 'time_loop', &
        'time step collapsed to '//rtoa(dt)//' (dt_min = '//rtoa(cfg%control%dt_min)//') at t = '// &
        rtoa(st%t)//', set by '//step_limit_text(st, sch)//lagrangian_hint(cfg), ERR_RUNTIME)
      if (allocated(err)) call fail(cfg, st, sch, err)
      st%dt = dt
      ! (a step shortened only to land on a frame or the end time does not
      ! hold back the next: the growth limit grows from the last full step)
      if (dt < dt_cap .or. .not. dt_cap < dt_growth_cap .or. .not. st%dt_grow > 0.0_wp) st%dt_grow = dt
      st%t = st%t + dt
      st%step = st%step + 1
      st%tot%boundary_work = st%tot%boundary_work + work
      call state_note_pressure(st)
      ! (the tracers where the Lagrangian phase took them: on each block
      ! those of its cells; shared and found on the new grid if it moves)
      call tracers_place(sch%tracers, st%g)
      n_euler = es%n

      ! INSPECT, EULER
      if (sch%pc%nranks > 1) then
        ! (a decomposed run: on windows or the whole grid, `driver_whole`)
        call whole_euler(cfg, sch%pc, st, es, sch%log, err)
        call agree_error(sch%pc, err)
        if (allocated(err)) call fail(cfg, st, sch, err)
      else
        ! (a global rezone's Euler step then compares only the rows of nodes
        ! the Lagrangian steps moved: `euler_step`; without the flags, every
        ! node)
        if (trim(cfg%rezone%mode) == 'global' .and. .not. allocated(st%g%moved_rows)) then
          allocate(st%g%moved_rows(st%g%nnode/st%g%sx), stat=stat)
          if (stat == 0) st%g%moved_rows = .true.
        end if
        call euler_due(cfg%rezone, st, es, due)
        if (due) then
          call euler_step(cfg%rezone, st, es, sch%log, err)
          if (allocated(err)) call fail(cfg, st, sch, err)
        end if
      end if
      if (es%n /= n_euler) then
        call tracers_relocate(sch%tracers, st%g, st%halo)
        ! (the remapped pressures too: what a frame shows never exceeds it)
        call state_note_pressure(st)
      end if
      last = .not. (st%t < cfg%control%t_end - eps_t .and. st%step < cfg%control%max_steps)

      ! OUTPUT
      call gauge_output(cfg, st, sch)
      call history_output(cfg, st, sch)
      sch%steps_since_frame = sch%steps_since_frame + 1
      if (.not. last .and. frame_due(cfg, st, sch, eps_t)) then
        call write_frame(cfg, st, sch, err)
        if (allocated(err)) call fail(cfg, st, sch, err)
        sch%steps_since_frame = 0
        call advance_schedule(sch%t_next_frame, st%t, cfg%output%frame_dt, eps_t)
      end if
      if (dump_due(cfg, st, sch, eps_t)) then
        ! (the schedule first: the dump holds the next dump's time, so a run
        ! continued from it does not write the same dump again at its first
        ! step)
        call advance_schedule(sch%t_next_dump, st%t, cfg%control%dump_dt, eps_t)
        call dump(cfg, st, sch, es, err)
        if (allocated(err)) call fail(cfg, st, sch, err)
      end if
      wall_now = wall_seconds()
      ! (the ranks agree on a progress line: it sums over all of them; and
      ! on a stop asked for, in the same reduction)
      report = merge(1, 0, wall_now - wall_last >= cfg%control%progress_seconds)
      asked = 0
      if (.not. last) asked = stop_asked(sch, wall_now, stop_checked)
      report = report + 2*asked
      if (sch%pc%nranks > 1) call st%halo%max_int(report)
      asked = report/2
      report = mod(report, 2)
      if ((cfg%control%progress_steps > 0 .and. mod(st%step, max(cfg%control%progress_steps, 1)) == 0) .or. &
          report == 1 .or. last) then
        call progress(cfg, st, sch, err)
        if (allocated(err)) call fail(cfg, st, sch, err)
        wall_last = wall_now
      end if
      if (asked > 0) call stop_with_restart(cfg, st, sch, es, asked)
    end do
  end subroutine time_loop

  !> What a purely Lagrangian run's failure message adds (a crushed or
  !> tangled grid is what Euler steps are for); '' with &rezone.
  function lagrangian_hint(cfg) result(text)
    type(config_t), intent(in) :: cfg
    character(len=:), allocatable :: text
    text = ''
    if (trim(cfg%rezone%mode) == 'none') text = ' (a purely Lagrangian run, no &rezone: the grid moves with the '// &
      'material until its cells are crushed or tangled; &rezone mode = ''lssm'' or ''global'' rezones and remaps them)'
  end function lagrangian_hint

  !> Whether this process has been asked to stop: the signal caught
  !> (SIGTERM, SIGUSR1: its number), or on rank 0 the stop file
  !> `<dir>/<name>.stop` (1), looked for at most once a wall second (the
  !> first time at step 1: a file made before the run stops it there);
  !> 0 if not. The ranks agree on it in the time loop's reduction.
  integer function stop_asked(sch, wall_now, checked) result(asked)
    type(schedule_t), intent(in) :: sch
    real(wp), intent(in) :: wall_now
    real(wp), intent(inout) :: checked
    asked = stop_signal_caught()
    if (asked > 0 .or. sch%pc%rank /= 0) return
    if (wall_now - checked < 1.0_wp) return
    checked = wall_now
    if (stop_file_present(stop_file(sch))) asked = 1
  end function stop_asked

  !> The stop file of the run: `<dir>/<name>.stop`.
  function stop_file(sch) result(path)
    type(schedule_t), intent(in) :: sch
    character(len=:), allocatable :: path
    path = sch%out%dir//'/'//sch%out%name//'.stop'
  end function stop_file

  !> The largest step the controller allows: the first step's cap, else the
  !> growth limit (from the last step that was not shortened to land on a
  !> frame or the end time: `state_t`'s dt_grow), and dt_max (growth: this
  !> much); then the end time and the next frame time (a restart written
  !> before dt_grow was kept grows from its last step).
  real(wp) function step_cap(cfg, st, sch, growth) result(dt)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(in) :: sch
    real(wp), intent(out) :: growth
    if (st%step == 0) then
      growth = cfg%hydro%dt_max
      if (cfg%control%dt_init > 0.0_wp) growth = min(growth, cfg%control%dt_init)
    else
      growth = min(cfg%hydro%dt_growth*merge(st%dt_grow, st%dt, st%dt_grow > 0.0_wp), cfg%hydro%dt_max)
    end if
    dt = min(growth, cfg%control%t_end - st%t, sch%t_next_frame - st%t)
  end function step_cap

  !> True when the next step and a dump might not fit before the wall-time
  !> limit (a margin of two steps, two dumps and half a second).
  logical function near_wall_time_limit(cfg, sch)
    type(config_t), intent(in) :: cfg
    type(schedule_t), intent(in) :: sch
    real(wp) :: elapsed
    near_wall_time_limit = .false.
    if (cfg%control%wall_time_limit <= 0.0_wp) return
    elapsed = wall_seconds() - sch%t_total%t0
    near_wall_time_limit = elapsed + 2.0_wp*(sch%step_wall + sch%dump_wall) + 0.5_wp >= cfg%control%wall_time_limit
  end function near_wall_time_limit

  !> A restart dump (written by all ranks together on a decomposed run,
  !> `whole_dump`), the ranks agreeing on its outcome.
  subroutine dump(cfg, st, sch, es, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    if (sch%pc%nranks > 1) then
      call whole_dump(cfg, sch%pc, st, sch, es, err)
      call agree_error(sch%pc, err)
    else
      call write_restart(cfg, st, sch, es, err)
    end if
  end subroutine dump

  !> The wall-time limit is near: a restart and exit status 3.
  subroutine stop_for_wall_time(cfg, st, sch, es)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    call stop_with_restart(cfg, st, sch, es, 0)
  end subroutine stop_for_wall_time

  !> Writes a restart (unless the last dump is of this very step) and stops
  !> with exit status 3, saying why and how to continue. why: 0 the
  !> wall-time limit, 1 the stop file (then removed), else the number of
  !> the signal caught.
  subroutine stop_with_restart(cfg, st, sch, es, why)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    integer, intent(in) :: why
    type(error_t), allocatable :: err
    character(len=:), allocatable :: path, at
    logical :: have, gone
    integer :: k
    path = restart_path(sch, st%step)
    have = .false.
    if (allocated(sch%dumps)) then
      if (size(sch%dumps) > 0) have = (trim(sch%dumps(size(sch%dumps))) == path)
    end if
    k = merge(1, 0, have)
    call st%halo%max_int(k)
    if (k == 0) call dump(cfg, st, sch, es, err)
    if (.not. allocated(err)) call progress(cfg, st, sch, err)
    if (allocated(err)) call fail(cfg, st, sch, err)
    at = ' at step '//itoa(st%step)//', t = '//rtoa(st%t)
    select case (why)
    case (0)
      call log_line(sch%log, 'wall-time limit of '//rtoa(cfg%control%wall_time_limit)//' s reached'//at)
    case (1)
      gone = .true.
      if (sch%pc%rank == 0) call stop_file_remove(stop_file(sch), gone)
      if (gone) then
        call log_line(sch%log, 'stop file '//stop_file(sch)//' found'//at//' (the file is removed)')
      else
        call log_line(sch%log, 'stop file '//stop_file(sch)//' found'//at//'; it could not be removed: '// &
                      'remove it before continuing')
      end if
    case default
      call log_line(sch%log, stop_signal_name(why)//' received'//at)
    end select
    call log_line(sch%log, 'restart written: '//path)
    call log_line(sch%log, 'to continue: lsalepm --restart '//path//' '//cfg%deck_path// &
                  '   (or run the same deck with  &run restart_from = '''//path//''' /)')
    call gauges_close(sch%gauges)
    call tracks_close(sch)
    call tracers_end(sch)
    call hdf5_stop(err)
    call halt(sch%log, EXIT_WALL_TIME)
  end subroutine stop_with_restart

  !> Ends the run on an error, with the exit status of its category. Bad
  !> input: one ERROR line with the problem and one with what follows
  !> (`where`). Otherwise a FATAL line naming the place, the step and the
  !> problem; a state complete enough to be written is written first (as the
  !> last frame) for diagnosis, and a failure to write it is logged too. HDF5
  !> is closed before the halt (io_hdf5: unless a file could not be closed).
  subroutine fail(cfg, st, sch, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(error_t), intent(in) :: err
    type(error_t), allocatable :: err2
    character(len=:), allocatable :: path
    character(len=max_line) :: line(1)

    if (err%category == ERR_INPUT) then
      line(1) = err%msg   ! assigned: gfortran 12 overruns a typed constructor of a longer string
      call refuse(sch%log, line, err%where)
    end if
    call log_error(sch%log, 'FATAL [rank '//itoa(err%rank)//', step '//itoa(st%step)//'] '//err%where//': '//err%msg)
    if (st%ready .and. allocated(sch%out%dir) .and. sch%pc%nranks > 1 .and. error_is_no_memory(err)) then
      ! (the ranks write a frame together, and a rank short of memory can
      ! fail alone inside the HDF5 library's collective calls, leaving the
      ! others waiting there for good: a hang, not a frame)
      call log_error(sch%log, 'the state at failure is not written: a rank ran out of memory')
    else if (st%ready .and. allocated(sch%out%dir)) then
      call state_totals(st)
      call frame_out(cfg, st, sch, path, err2)
      if (allocated(err2)) then
        call log_error(sch%log, 'the state at failure could not be written: '//err2%where//': '//err2%msg)
      else
        call log_error(sch%log, 'state at failure written to '//path)
      end if
    end if
    if (allocated(err2)) deallocate(err2)
    call hdf5_stop(err2)
    if (allocated(err2)) call log_error(sch%log, err2%where//': '//err2%msg)
    call halt(sch%log, error_exit_status(err%category))
  end subroutine fail

  subroutine report_end(st, sch, es)
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(in) :: sch
    type(euler_state_t), intent(in) :: es
    character(len=256) :: line
    real(wp) :: rate, rate_lag, cycles, per
    integer :: peak, most

    call report_conservation(st, sch%log, 'final')
    ! (every rank's peak: the largest, and rank 0's)
    peak = memory_peak_mib()
    most = peak
    call st%halo%max_int(most)
    if (sch%pc%nranks > 1) then
      call log_line(sch%log, 'memory: peak resident '//itoa(most)//' MiB on the most loaded of '// &
                    itoa(sch%pc%nranks)//' ranks ('//itoa(peak)//' MiB on rank 0)')
    else
      call log_line(sch%log, 'memory: peak resident '//itoa(peak)//' MiB')
    end if
    ! cell-cycles per second of the whole step (Lagrangian and Euler
    ! phases), then of each phase: what a run costs, and what an Euler step
    ! costs in Lagrangian steps
    cycles = real(product(st%g%gn), wp)*real(st%step - sch%step_start, wp)
    rate = 0.0_wp
    if (sch%t_lagrange%total + es%timer%total > 0.0_wp) rate = cycles/(sch%t_lagrange%total + es%timer%total)
    rate_lag = 0.0_wp
    if (sch%t_lagrange%total > 0.0_wp) rate_lag = cycles/sch%t_lagrange%total
    write(line, '("timers [s]: setup ",f9.3,"  lagrange ",f9.3,"  euler ",f9.3,"  output ",f9.3,"  total ",f9.3)') &
      sch%t_setup%total, sch%t_lagrange%total, es%timer%total, sch%t_output%total, sch%t_total%total
    call log_line(sch%log, trim(line))
    write(line, '("throughput: ",es10.3," cell-cycles/s over ",i0," steps (Lagrangian and Euler phases)")') rate, &
      st%step - sch%step_start
    call log_line(sch%log, trim(line))
    if (es%cells > 0) then
      per = es%timer%total/real(es%cells, wp)
      write(line, '("throughput by phase: Lagrangian ",es10.3," cell-cycles/s; Euler ",f10.3," s for ",i0, &
        &" remapped cells in ",i0," Euler steps: ",f10.2," us per remapped cell = ",f8.1," Lagrangian cell-cycles")') &
        rate_lag, es%timer%total, es%cells, es%n, 1.0e6_wp*per, per*rate_lag
    else
      write(line, '("throughput by phase: Lagrangian ",es10.3," cell-cycles/s; no Euler step")') rate_lag
    end if
    call log_line(sch%log, trim(line))
    if (sch%pc%nranks > 1 .and. st%step > sch%step_start) then
      ! rank 0's block (the one that writes the log)
      write(line, '("halo (rank 0): ",f9.3," s in exchanges and the global step (",f5.1," % of lagrange); per ", &
        &"step ",f7.1," messages, ",es10.3," bytes sent")') st%halo%seconds, &
        100.0_wp*st%halo%seconds/max(sch%t_lagrange%total, tiny(1.0_wp)), &
        real(st%halo%messages, wp)/real(st%step - sch%step_start, wp), &
        real(st%halo%bytes, wp)/real(st%step - sch%step_start, wp)
      call log_line(sch%log, trim(line))
    end if
    call euler_report(es, sch%log)
    if (es%centroids%fitted + es%centroids%moved + es%centroids%failed > 0) &
      call log_line(sch%log, 'mixed-cell planes after the remaps: '//centroid_text(es%centroids))
    call log_line(sch%log, 'outputs: '//sch%out%dir//'/'//sch%out%name//'.xdmf (ParaView), '// &
                  sch%out%dir//'/'//sch%out%name//'.log')
    if (allocated(sch%out%nparts)) then
      if (any(sch%out%nparts > 0)) call log_line(sch%log, 'particles: '//sch%out%dir//'/'//sch%out%name// &
                                                 '_particles.xdmf (ParaView: open it beside the grid''s)')
    end if
    call log_line(sch%log, 'done: t = '//rtoa(st%t)//' after '//itoa(st%step)//' steps')
  end subroutine report_end
end module driver
