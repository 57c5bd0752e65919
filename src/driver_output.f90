!> What a run writes and when: the log, frames (HDF5 + XDMF), gauge rows,
!> progress lines and the conservation report, with the schedule of frames,
!> gauges and restart dumps and the phase timers.
module driver_output
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t, error_set, ERR_IO, ERR_RUNTIME
  use base_timers, only: timer_t, wall_seconds
  use base_registry, only: registry_t
  use io_log, only: log_t, log_open, log_line
  use io_output, only: output_t, output_frame, frame_meta_t, units_none, units_density, units_specific_energy, &
                       units_pressure
  use io_gauges, only: gauges_t, gauges_open, gauges_write
  use io_hdf5, only: hdf5_start
  use io_files, only: io_make_dirs
  use driver_config, only: config_t
  use driver_state, only: state_t, state_totals, energy_drift
  implicit none
  private
  public :: schedule_t, schedule_init, schedule_register_restart, open_outputs, write_frame, frame_out, &
            gauge_output, progress, report_conservation, frame_due, dump_due, advance_schedule

  !> The output schedule and bookkeeping of this run segment.
  type :: schedule_t
    type(log_t) :: log
    type(output_t) :: out                          !< frame names and times
    type(gauges_t) :: gauges
    real(wp) :: t_next_frame = 0.0_wp, t_next_gauge = 0.0_wp, t_next_dump = 0.0_wp
    integer :: steps_since_frame = 0
    integer :: step_start = 0                      !< first step of this segment (after a restart)
    logical :: restarting = .false.
    character(len=256), allocatable :: dumps(:)    !< this segment's dumps, oldest first
    real(wp) :: step_wall = 0.0_wp, dump_wall = 0.0_wp   !< wall time of the last step, last dump
    type(timer_t) :: t_setup, t_lagrange, t_output, t_total
  end type schedule_t

contains

  !> The first frame and dump times of a new run.
  subroutine schedule_init(cfg, sch)
    type(config_t), intent(in) :: cfg
    type(schedule_t), intent(inout) :: sch
    sch%t_next_frame = huge(1.0_wp)
    if (cfg%output%frame_dt > 0.0_wp) sch%t_next_frame = cfg%output%frame_dt
    sch%t_next_dump = huge(1.0_wp)
    if (cfg%control%dump_dt > 0.0_wp) sch%t_next_dump = cfg%control%dump_dt
  end subroutine schedule_init

  !> Registers the schedule's restart quantities.
  subroutine schedule_register_restart(sch, reg)
    type(schedule_t), intent(inout), target :: sch
    type(registry_t), intent(inout) :: reg
    call reg%add('t_next_frame', 'time', sch%t_next_frame)
    call reg%add('t_next_gauge', 'time', sch%t_next_gauge)
    call reg%add('t_next_dump', 'time', sch%t_next_dump)
    call reg%add('steps_since_frame', '1', sch%steps_since_frame)
    call reg%add('nframe', '1', sch%out%nframe)
  end subroutine schedule_register_restart

  !> Creates the output directory, opens the log (appending on a restart),
  !> echoes the resolved deck, starts HDF5 and opens the gauge file.
  subroutine open_outputs(cfg, sch, err)
    type(config_t), intent(in) :: cfg
    type(schedule_t), intent(inout) :: sch
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: dir, base
    character(len=512) :: msg
    logical :: ok

    dir = trim(cfg%output%dir)
    base = trim(cfg%output%name)
    call io_make_dirs(dir, err)
    if (allocated(err)) return
    msg = ''
    call log_open(sch%log, dir//'/'//base//'.log', sch%restarting, ok, msg)
    if (.not. ok) then
      call error_set(err, 'open_outputs', 'cannot open the log: '//trim(msg), ERR_IO)
      return
    end if
    call log_line(sch%log, 'lsalepm: '//trim(cfg%control%title))
    call log_line(sch%log, 'deck: '//cfg%deck_path)
    call log_line(sch%log, 'resolved input:')
    call log_line(sch%log, cfg%echo)
    sch%out%dir = dir
    sch%out%name = base
    call hdf5_start(err)
    if (.not. allocated(err)) call gauges_open(sch%gauges, dir//'/'//base//'_gauges.txt', &
                                               cfg%output%gauges(:, 1:cfg%output%ngauge), sch%restarting, err)
    if (allocated(err)) err%category = ERR_IO
  end subroutine open_outputs

  !> Writes a frame with each cell's material (the largest by volume in a
  !> mixed cell) and, with several materials, each material's fields: its
  !> volume fraction vf_<name>, density density_<name>, specific internal
  !> energy energy_<name> and pressure pressure_<name>. In a cell the
  !> material fills these are the cell's values, in a mixed cell its slot's
  !> values, elsewhere 0.
  subroutine frame_out(cfg, st, sch, path, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(inout) :: sch
    character(len=:), allocatable, intent(out) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer, parameter :: nper = 4          ! fields per material: vf, density, energy, pressure
    integer :: nmat, nf, c, k, s, m, stat
    integer, allocatable :: cellmat(:)
    real(wp), allocatable :: fld(:, :)
    character(len=80), allocatable :: names(:), owner(:)
    character(len=32), allocatable :: units(:)
    type(frame_meta_t) :: meta
    character(len=200) :: msg

    nmat = size(st%mats)
    nf = merge(nper*nmat, 0, nmat > 1)
    allocate(cellmat(st%g%ncell), fld(st%g%ncell, nf), names(nf), owner(nf), units(nf), &
             meta%materials(nmat), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'frame_out', 'cannot allocate the frame''s cell fields: '//trim(msg))
      return
    end if
    cellmat = st%h%mat
    do m = 1, nmat
      meta%materials(m) = st%mats(m)%name
    end do
    meta%title = trim(cfg%control%title)
    meta%unit_system = trim(cfg%control%units)
    if (nmat > 1) then
      ! columns of material m: vf, density, energy, pressure at nper*(m-1) + 1..4
      do m = 1, nmat
        k = nper*(m - 1)
        names(k + 1:k + nper) = [character(len=80) :: 'vf_'//st%mats(m)%name, 'density_'//st%mats(m)%name, &
                                 'energy_'//st%mats(m)%name, 'pressure_'//st%mats(m)%name]
        units(k + 1:k + nper) = [character(len=32) :: units_none, units_density, units_specific_energy, &
                                 units_pressure]
        owner(k + 1:k + nper) = st%mats(m)%name
        do c = 1, st%g%ncell
          if (st%h%mat(c) == m) then
            fld(c, k + 1:k + nper) = [1.0_wp, st%h%rho(c), st%h%e(c), st%h%p(c)]
          else
            fld(c, k + 1:k + nper) = 0.0_wp
          end if
        end do
      end do
      do k = 1, st%mx%n
        c = st%mx%cell(k)
        do s = st%mx%start(k), st%mx%start(k + 1) - 1
          m = nper*(st%mx%mat(s) - 1)
          fld(c, m + 1:m + nper) = [st%mx%vf(s), st%mx%rho(s), st%mx%e(s), st%mx%p(s)]
        end do
        cellmat(c) = maxloc(fld(c, 1:nf:nper), 1)
      end do
    end if
    call output_frame(sch%out, st%g, st%h, cellmat, names, units, owner, fld, st%t, st%step, st%tot, cfg%echo, &
                      meta, path, err)
    if (allocated(err)) err%category = ERR_IO
  end subroutine frame_out

  !> Updates the totals, writes a frame and logs it.
  subroutine write_frame(cfg, st, sch, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: path
    call sch%t_output%start()
    call state_totals(st)
    call frame_out(cfg, st, sch, path, err)
    call sch%t_output%stop()
    if (.not. allocated(err)) call log_line(sch%log, 'frame '//path//' at t = '//rtoa(st%t))
  end subroutine write_frame

  !> A gauge row, if one is due.
  subroutine gauge_output(cfg, st, sch)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(inout) :: sch
    if (sch%gauges%n == 0) return
    if (st%t < sch%t_next_gauge .and. st%t < cfg%control%t_end) return
    call sch%t_output%start()
    call gauges_write(sch%gauges, st%g, st%h, st%t)
    call sch%t_output%stop()
    if (cfg%output%gauge_dt > 0.0_wp) then
      do while (sch%t_next_gauge <= st%t)
        sch%t_next_gauge = sch%t_next_gauge + cfg%output%gauge_dt
      end do
    end if
  end subroutine gauge_output

  !> True when a frame is due after the step just taken (not the last).
  logical function frame_due(cfg, st, sch, eps_t)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(in) :: sch
    real(wp), intent(in) :: eps_t
    frame_due = st%t >= sch%t_next_frame - eps_t .or. &
                (cfg%output%frame_steps > 0 .and. sch%steps_since_frame >= cfg%output%frame_steps)
  end function frame_due

  !> True when a restart dump is due after the step just taken.
  logical function dump_due(cfg, st, sch, eps_t)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(in) :: sch
    real(wp), intent(in) :: eps_t
    dump_due = (cfg%control%dump_steps > 0 .and. mod(st%step, max(cfg%control%dump_steps, 1)) == 0) .or. &
               st%t >= sch%t_next_dump - eps_t
  end function dump_due

  !> Moves a next-output time past t by whole intervals.
  subroutine advance_schedule(t_next, t, interval, eps_t)
    real(wp), intent(inout) :: t_next
    real(wp), intent(in) :: t, interval, eps_t
    do while (t_next <= t + eps_t)
      t_next = t_next + interval
    end do
  end subroutine advance_schedule

  !> One progress line: step, time, dt, wall time, estimated time left, and
  !> the energy balance. A NaN anywhere in the state shows up here.
  subroutine progress(cfg, st, sch, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(in) :: sch
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: wall, left, drift
    character(len=256) :: line

    call state_totals(st)
    drift = energy_drift(st%tot)
    if (ieee_is_nan(drift)) then
      call error_set(err, 'time_loop', 'the state has a NaN (energy balance is NaN)', ERR_RUNTIME)
      return
    end if
    wall = wall_seconds() - sch%t_total%t0
    left = 0.0_wp
    if (st%t > 0.0_wp) left = wall*(cfg%control%t_end - st%t)/st%t
    write(line, '("step ",i8,"  t ",es12.5,"  dt ",es10.3,"  wall ",f9.2," s  left ",f9.2, &
      &" s  energy drift ",es10.2)') st%step, st%t, st%dt, wall, left, drift
    call log_line(sch%log, trim(line))
  end subroutine progress

  !> The conservation report: mass, momentum, energies, boundary work, drift.
  subroutine report_conservation(st, log, label)
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    character(len=*), intent(in) :: label
    character(len=256) :: line
    call state_totals(st)
    write(line, '("conservation (",a,"): mass ",es22.15,"  momentum ",3es12.4)') &
      label, st%tot%mass, st%tot%momentum
    call log_line(log, trim(line))
    write(line, '("  energy: internal ",es22.15,"  kinetic ",es22.15,"  total ",es22.15)') &
      st%tot%internal, st%tot%kinetic, st%tot%internal + st%tot%kinetic
    call log_line(log, trim(line))
    write(line, '("  boundary work ",es22.15,"  relative energy drift ",es10.3)') &
      st%tot%boundary_work, energy_drift(st%tot)
    call log_line(log, trim(line))
  end subroutine report_conservation
end module driver_output
