!> The driver: reads the deck, builds the scene, runs the time loop, and owns
!> all input, output and the decision to stop.
module driver
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t
  use base_timers, only: wall_seconds
  use lagrange_integrator, only: lagrange_step
  use io_input, only: input_read
  use io_log, only: log_open, log_close, log_line
  use io_gauges, only: gauges_open, gauges_write, gauges_close
  use io_hdf5, only: hdf5_start, hdf5_stop
  use driver_state, only: run, refuse, totals, energy_drift, frame_out, fatal, report_conservation
  use driver_scene, only: build_scene
  use driver_restart, only: check_restart_deck, register_restart, restart_path, write_restart, read_restart
  use driver_euler, only: euler_init, euler_due, euler_step, euler_report
  implicit none
  private
  public :: driver_run

contains

  !> Runs the deck at `deck_path` to completion, or stops with a message.
  subroutine driver_run(deck_path)
    character(len=*), intent(in) :: deck_path
    type(error_t), allocatable :: err

    call run%t_total%start()
    call run%t_setup%start()
    call read_deck(deck_path)
    run%restarting = len_trim(run%cfg%restart_from) > 0
    if (run%restarting) call check_restart_deck()
    call open_outputs()
    call build_scene()
    call euler_init()
    call register_restart()
    if (run%restarting) then
      call read_restart()
    else
      run%t_next_frame = huge(1.0_wp)
      if (run%cfg%frame_dt > 0.0_wp) run%t_next_frame = run%cfg%frame_dt
      run%t_next_dump = huge(1.0_wp)
      if (run%cfg%dump_dt > 0.0_wp) run%t_next_dump = run%cfg%dump_dt
      call report_conservation('initial')
      call write_frame()
      call gauge_output()
    end if
    call run%t_setup%stop()
    call time_loop()
    call write_frame()
    call gauges_close(run%gauges)
    call run%t_total%stop()
    call report_end()
    call hdf5_stop(err)
    call log_close()
  end subroutine driver_run

  subroutine read_deck(path)
    character(len=*), intent(in) :: path
    character(len=1024), allocatable :: problems(:)

    call input_read(path, run%cfg, problems)
    if (size(problems) > 0) call refuse(problems, 'the deck has '//itoa(size(problems))// &
                                        ' problem(s); nothing was run')
  end subroutine read_deck

  subroutine open_outputs()
    character(len=:), allocatable :: dir, base
    character(len=512) :: msg
    integer :: stat
    logical :: ok
    type(error_t), allocatable :: err

    dir = trim(run%cfg%out_dir)
    base = trim(run%cfg%out_name)
    call execute_command_line('mkdir -p "'//dir//'"', exitstat=stat)
    if (stat /= 0) call fatal('open_outputs', 'cannot create the output directory '''//dir//'''')
    msg = ''
    call log_open(dir//'/'//base//'.log', run%restarting, ok, msg)
    if (.not. ok) call fatal('open_outputs', 'cannot open the log: '//trim(msg))
    call log_line('lsalepm: '//trim(run%cfg%title))
    call log_line('deck: '//run%cfg%deck_path)
    call log_line('resolved input:')
    call log_line(run%cfg%echo)
    run%out%dir = dir
    run%out%name = base
    call hdf5_start(err)
    if (allocated(err)) call fatal(err%where, err%msg)
    call gauges_open(run%gauges, dir//'/'//base//'_gauges.txt', &
                     run%cfg%gauges(:, 1:run%cfg%ngauge), run%restarting, err)
    if (allocated(err)) call fatal(err%where, err%msg)
  end subroutine open_outputs

  subroutine time_loop()
    real(wp) :: dt_cap, work, wall_last, wall_now, eps_t, w0
    integer :: bad_cell
    logical :: last

    eps_t = 1.0e-12_wp*run%cfg%t_end
    wall_last = wall_seconds()
    do while (run%t < run%cfg%t_end - eps_t .and. run%step < run%cfg%max_steps)
      if (near_wall_time_limit()) call stop_for_wall_time()
      ! the step the controller allows: growth limit, dt_max, end time, frames
      if (run%step == 0) then
        dt_cap = run%cfg%hydro%dt_max
        if (run%cfg%dt_init > 0.0_wp) dt_cap = min(dt_cap, run%cfg%dt_init)
      else
        dt_cap = min(run%cfg%hydro%dt_growth*run%dt, run%cfg%hydro%dt_max)
      end if
      dt_cap = min(dt_cap, run%cfg%t_end - run%t, run%t_next_frame - run%t)

      w0 = wall_seconds()
      call run%t_lagrange%start()
      call lagrange_step(run%g, run%h, run%bc, run%mats, run%mx, run%cfg%hydro, dt_cap, work, bad_cell)
      call run%t_lagrange%stop()
      run%step_wall = wall_seconds() - w0
      if (bad_cell /= 0) call fatal('lagrange_step', 'cell '//itoa(bad_cell)// &
        ' has a non-positive volume (tangled grid) at t = '//rtoa(run%t))
      if (dt_cap < run%cfg%dt_min) call fatal('time_loop', 'time step collapsed to '// &
        rtoa(dt_cap)//' (dt_min = '//rtoa(run%cfg%dt_min)//')')
      run%dt = dt_cap
      run%t = run%t + run%dt
      run%step = run%step + 1
      run%tot%boundary_work = run%tot%boundary_work + work
      if (euler_due()) call euler_step()
      last = .not. (run%t < run%cfg%t_end - eps_t .and. run%step < run%cfg%max_steps)

      call gauge_output()
      run%steps_since_frame = run%steps_since_frame + 1
      if (.not. last .and. (run%t >= run%t_next_frame - eps_t .or. &
          (run%cfg%frame_steps > 0 .and. run%steps_since_frame >= run%cfg%frame_steps))) then
        call write_frame()
        run%steps_since_frame = 0
        do while (run%t_next_frame <= run%t + eps_t)
          run%t_next_frame = run%t_next_frame + run%cfg%frame_dt
        end do
      end if
      if ((run%cfg%dump_steps > 0 .and. mod(run%step, max(run%cfg%dump_steps, 1)) == 0) .or. &
          run%t >= run%t_next_dump - eps_t) then
        call write_restart()
        do while (run%t_next_dump <= run%t + eps_t)
          run%t_next_dump = run%t_next_dump + run%cfg%dump_dt
        end do
      end if
      wall_now = wall_seconds()
      if ((run%cfg%progress_steps > 0 .and. mod(run%step, max(run%cfg%progress_steps, 1)) == 0) .or. &
          wall_now - wall_last >= run%cfg%progress_seconds .or. last) then
        call progress()
        wall_last = wall_now
      end if
    end do
  end subroutine time_loop

  !> True when the next step and a dump might not fit before the wall-time
  !> limit (a margin of two steps, two dumps and half a second).
  logical function near_wall_time_limit()
    real(wp) :: elapsed
    near_wall_time_limit = .false.
    if (run%cfg%wall_time_limit <= 0.0_wp) return
    elapsed = wall_seconds() - run%t_total%t0
    near_wall_time_limit = elapsed + 2.0_wp*(run%step_wall + run%dump_wall) + 0.5_wp >= &
                           run%cfg%wall_time_limit
  end function near_wall_time_limit

  !> Writes a restart (unless the last dump is of this very step) and stops
  !> with exit status 3, saying how to continue.
  subroutine stop_for_wall_time()
    character(len=:), allocatable :: path
    logical :: have
    path = restart_path(run%step)
    have = .false.
    if (allocated(run%dumps)) then
      if (size(run%dumps) > 0) have = (trim(run%dumps(size(run%dumps))) == path)
    end if
    if (.not. have) call write_restart()
    call progress()
    call log_line('wall-time limit of '//rtoa(run%cfg%wall_time_limit)//' s reached at step '// &
                  itoa(run%step)//', t = '//rtoa(run%t))
    call log_line('to continue, run the same deck with  &run restart_from = '''//path//''' /')
    call gauges_close(run%gauges)
    call log_close()
    stop 3
  end subroutine stop_for_wall_time

  subroutine gauge_output()
    if (run%gauges%n == 0) return
    if (run%t < run%t_next_gauge .and. run%t < run%cfg%t_end) return
    call run%t_output%start()
    call gauges_write(run%gauges, run%g, run%h, run%t)
    call run%t_output%stop()
    if (run%cfg%gauge_dt > 0.0_wp) then
      do while (run%t_next_gauge <= run%t)
        run%t_next_gauge = run%t_next_gauge + run%cfg%gauge_dt
      end do
    end if
  end subroutine gauge_output

  !> One progress line: step, time, dt, wall time, estimated time left, and
  !> the energy balance. A NaN anywhere in the state shows up here.
  subroutine progress()
    real(wp) :: wall, left, drift
    character(len=256) :: line

    call totals(run%tot)
    drift = energy_drift()
    if (ieee_is_nan(drift)) call fatal('time_loop', 'the state has a NaN (energy balance is NaN)')
    wall = wall_seconds() - run%t_total%t0
    left = 0.0_wp
    if (run%t > 0.0_wp) left = wall*(run%cfg%t_end - run%t)/run%t
    write(line, '("step ",i8,"  t ",es12.5,"  dt ",es10.3,"  wall ",f9.2," s  left ",f9.2, &
      &" s  energy drift ",es10.2)') run%step, run%t, run%dt, wall, left, drift
    call log_line(trim(line))
  end subroutine progress

  subroutine report_end()
    character(len=256) :: line
    real(wp) :: rate

    call report_conservation('final')
    rate = 0.0_wp
    if (run%t_lagrange%total > 0.0_wp) &
      rate = real(run%g%ncell, wp)*real(run%step - run%step_start, wp)/run%t_lagrange%total
    write(line, '("timers [s]: setup ",f9.3,"  lagrange ",f9.3,"  euler ",f9.3,"  output ",f9.3,"  total ",f9.3)') &
      run%t_setup%total, run%t_lagrange%total, run%t_euler%total, run%t_output%total, run%t_total%total
    call log_line(trim(line))
    write(line, '("throughput: ",es10.3," cell-cycles/s over ",i0," steps")') rate, &
      run%step - run%step_start
    call log_line(trim(line))
    call euler_report()
    call log_line('outputs: '//run%out%dir//'/'//run%out%name//'.xdmf (ParaView), '// &
                  run%out%dir//'/'//run%out%name//'.log')
    call log_line('done: t = '//rtoa(run%t)//' after '//itoa(run%step)//' steps')
  end subroutine report_end

  subroutine write_frame()
    type(error_t), allocatable :: err
    character(len=:), allocatable :: path
    call run%t_output%start()
    call totals(run%tot)
    call frame_out(path, err)
    call run%t_output%stop()
    if (allocated(err)) call fatal(err%where, err%msg)
    call log_line('frame '//path//' at t = '//rtoa(run%t))
  end subroutine write_frame
end module driver
