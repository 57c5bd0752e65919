!> What a run writes and when: the log, frames (HDF5 + XDMF), gauge rows,
!> the energy history, tracked-particle rows, tracer rows, progress lines and the conservation report, with the
!> schedule of frames, gauges, history rows and restart dumps and the phase
!> timers.
module driver_output
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_value, ieee_quiet_nan
  use base_kinds, only: wp
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_no_memory, error_t, error_set, ERR_IO, ERR_RUNTIME, ERR_INPUT
  use base_timers, only: timer_t, wall_seconds
  use base_registry, only: registry_t, LOWER_NONNEGATIVE
  use base_build, only: code_version, build_type
  use io_log, only: log_t, log_open, log_line, log_identity
  use io_output, only: output_t, output_frame, frame_meta_t, units_none, units_density, units_specific_energy, &
                       units_pressure, units_temperature, frame_wants
  use io_gauges, only: gauges_t, gauges_open, gauges_write, text_rows_trim
  use io_tracers, only: tracers_t, tracers_start, tracers_open, tracers_write, tracers_close, tracers_register_restart
  use io_hdf5, only: hdf5_version
  use strength_models, only: strength_fields
  use io_files, only: io_make_dirs
  use particles_track, only: particles_nearest_ids, particles_index_of_ids, particles_track_values, track_nfield, &
                             track_field_names
  use driver_config, only: config_t
  use parallel_comm, only: comm_t, parallel_bcast_text, parallel_min, parallel_sum
  use driver_parallel, only: agree_error
  use driver_state, only: state_t, state_totals, energy_drift, budget_residual, totals_not_finite
  use driver_particles, only: particles_blocks_share
  use driver_matsum, only: matsum_t, matsum_compute, matsum_header, matsum_rows
  use io_blast, only: blast_t, blast_answers, blast_read_gauges, blast_detection
  use particles_state, only: particles_t, particles_select
  implicit none
  private
  public :: schedule_t, schedule_init, schedule_register_restart, open_outputs, write_frame, frame_out, &
            gauge_output, progress, report_conservation, frame_due, dump_due, advance_schedule, &
            history_output, outputs_after_restart, step_limit_text, tracks_init, tracks_close, blast_report, &
            tracers_init, tracers_end

  !> The output schedule and bookkeeping of this run segment.
  type :: schedule_t
    type(log_t) :: log
    type(comm_t) :: pc                             !< the MPI ranks (one without mpirun)
    type(output_t) :: out                          !< frame names and times
    type(gauges_t) :: gauges
    type(tracers_t) :: tracers                     !< the tracers (on every rank; rank 0 has the file)
    real(wp) :: t_next_frame = 0.0_wp, t_next_gauge = 0.0_wp, t_next_dump = 0.0_wp
    integer :: steps_since_frame = 0
    integer :: step_start = 0                      !< first step of this segment (after a restart)
    !> simulated time and wall time (since the run started) of the last
    !> progress line, or of this segment's start: the time left is estimated
    !> from the rate since then (`progress`)
    real(wp) :: eta_t = -1.0_wp, eta_wall = 0.0_wp
    logical :: restarting = .false.
    character(len=256), allocatable :: dumps(:)    !< this segment's dumps, oldest first
    real(wp) :: step_wall = 0.0_wp, dump_wall = 0.0_wp   !< wall time of the last step, last dump
    type(timer_t) :: t_setup, t_lagrange, t_output, t_total
    integer :: history_unit = -1                   !< the energy history file (-1: none)
    integer :: matsum_unit = -1                    !< the material and body sums file (-1: none)
    !> rows still to come (on every rank: a row's totals are summed by all)
    logical :: history_on = .false.
    real(wp) :: t_next_history = huge(1.0_wp)      !< time of the next history row
    integer :: dt_cell = 0                         !< cell with the smallest stable step (0: none)
    logical :: dt_by_cell = .false.                !< that cell set the last step (else the controller did)
    integer :: dt_particle = 0                     !< the id of the particle whose stable step set the last step
    integer :: track_unit = -1                     !< the tracked-particle file (-1: none)
    integer, allocatable :: track_id(:)            !< (ntrack) seeding id of each tracked particle
    integer, allocatable :: track_mat(:)           !< (ntrack) its solid
    integer, allocatable :: track_idx(:)           !< (ntrack) its array index at the last row
  end type schedule_t

contains

  !> The first frame and dump times of a new run.
  subroutine schedule_init(cfg, sch, t0)
    type(config_t), intent(in) :: cfg
    type(schedule_t), intent(inout) :: sch
    real(wp), intent(in) :: t0   !< the start time (0, or a &prerun's mapping time)
    sch%t_next_frame = huge(1.0_wp)
    if (cfg%output%frame_dt > 0.0_wp) sch%t_next_frame = next_multiple(t0, cfg%output%frame_dt)
    sch%t_next_dump = huge(1.0_wp)
    if (cfg%control%dump_dt > 0.0_wp) sch%t_next_dump = next_multiple(t0, cfg%control%dump_dt)
    sch%t_next_history = huge(1.0_wp)
    if (cfg%output%history_dt > 0.0_wp) sch%t_next_history = t0
  end subroutine schedule_init

  !> Registers the schedule's restart quantities.
  subroutine schedule_register_restart(sch, reg)
    type(schedule_t), intent(inout), target :: sch
    type(registry_t), intent(inout) :: reg
    call reg%add('t_next_frame', 'time', sch%t_next_frame, lower=LOWER_NONNEGATIVE)
    call reg%add('t_next_gauge', 'time', sch%t_next_gauge, lower=LOWER_NONNEGATIVE)
    call reg%add('t_next_dump', 'time', sch%t_next_dump, lower=LOWER_NONNEGATIVE)
    call reg%add('steps_since_frame', '1', sch%steps_since_frame, lower=LOWER_NONNEGATIVE)
    call reg%add('nframe', '1', sch%out%nframe, lower=LOWER_NONNEGATIVE)
    ! not mandatory: a restart written before the history existed continues
    ! with the next multiple of history_dt (outputs_after_restart)
    call reg%add('t_next_history', 'time', sch%t_next_history, mandatory=.false.)
    call tracers_register_restart(sch%tracers, reg)
  end subroutine schedule_register_restart

  !> Creates the output directory, opens the log (appending on a restart),
  !> writes the run's identity, echoes the resolved deck, starts HDF5 and
  !> opens the gauge and energy history files (on a restart they are opened
  !> by `outputs_after_restart`, once the restart time is known).
  subroutine open_outputs(cfg, sch, err)
    type(config_t), intent(in) :: cfg
    type(schedule_t), intent(inout) :: sch
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: dir, base
    character(len=512) :: msg
    logical :: ok

    dir = trim(cfg%output%dir)
    base = trim(cfg%output%name)
    sch%out%dir = dir
    sch%out%name = base
    sch%history_on = cfg%output%history_dt > 0.0_wp
    ! rank 0 writes the log and the files of the whole grid (the other ranks
    ! sample the gauges with it)
    if (sch%pc%rank /= 0) then
      call gauges_open(sch%gauges, gauges_path(sch), cfg%output%gauges(:, 1:cfg%output%ngauge), .false., err, &
                       file=.false.)
      return
    end if
    call io_make_dirs(dir, err)
    if (allocated(err)) return
    msg = ''
    call log_open(sch%log, dir//'/'//base//'.log', sch%restarting, ok, msg)
    if (.not. ok) then
      call error_set(err, 'open_outputs', 'cannot open the log: '//trim(msg), ERR_IO)
      return
    end if
    call log_identity(sch%log, code_version, build_type, hdf5_version())
    call log_line(sch%log, 'lsalepm: '//trim(cfg%control%title))
    call log_line(sch%log, 'deck: '//cfg%deck_path)
    call log_line(sch%log, 'resolved input:')
    call log_line(sch%log, cfg%echo)
    if (.not. sch%restarting) call open_histories(cfg, sch, .false., err)
    if (allocated(err)) err%category = ERR_IO
  end subroutine open_outputs

  !> Opens the gauge file and, with &output history_dt > 0, the energy
  !> history `<dir>/<name>_history.txt`: new files with their headers, or
  !> (append) the existing ones to add rows.
  subroutine open_histories(cfg, sch, append, err)
    type(config_t), intent(in) :: cfg
    type(schedule_t), intent(inout) :: sch
    logical, intent(in) :: append
    type(error_t), allocatable, intent(inout) :: err
    character(len=200) :: head(3)
    integer :: i

    call gauges_open(sch%gauges, gauges_path(sch), cfg%output%gauges(:, 1:cfg%output%ngauge), append, err)
    if (allocated(err) .or. .not. cfg%output%history_dt > 0.0_wp) return
    call open_text(sch%history_unit, history_path(sch), append, err)
    if (allocated(err)) return
    call open_text(sch%matsum_unit, matsum_path(sch), append, err)
    if (allocated(err) .or. append) return
    write(sch%history_unit, '(a)') '# energy history (lsalepm): a row every &output history_dt = '// &
      rtoa(cfg%output%history_dt)//' and at the end; total = kinetic + internal; drift = (total - '// &
      'initial total - boundary work)/|initial total|; energies in the deck''s units'
    write(sch%history_unit, '(a)') '# time kinetic internal boundary_work total drift'
    flush(sch%history_unit)
    head = matsum_header(rtoa(cfg%output%history_dt))
    write(sch%matsum_unit, '(a)') (trim(head(i)), i = 1, size(head))
    flush(sch%matsum_unit)
  end subroutine open_histories

  !> Opens the text file `path` for writing: a new file, or (append) the
  !> existing one to add rows; unit -1 and an I/O error if it cannot.
  subroutine open_text(unit, path, append, err)
    integer, intent(out) :: unit
    character(len=*), intent(in) :: path
    logical, intent(in) :: append
    type(error_t), allocatable, intent(inout) :: err
    character(len=512) :: msg
    integer :: ios
    if (append) then
      open(newunit=unit, file=path, status='unknown', position='append', action='write', iostat=ios, iomsg=msg)
    else
      open(newunit=unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
    end if
    if (ios /= 0) then
      unit = -1
      call error_set(err, 'open_outputs', 'cannot open '''//path//''': '//trim(msg), ERR_IO)
    end if
  end subroutine open_text

  function gauges_path(sch) result(path)
    type(schedule_t), intent(in) :: sch
    character(len=:), allocatable :: path
    path = sch%out%dir//'/'//sch%out%name//'_gauges.txt'
  end function gauges_path

  function tracers_path(sch) result(path)
    type(schedule_t), intent(in) :: sch
    character(len=:), allocatable :: path
    path = sch%out%dir//'/'//sch%out%name//'_tracers.txt'
  end function tracers_path

  !> The &output tracers at their starting points on the grid just built
  !> (on every rank: each block places those in its cells), and for a new
  !> run the file `<dir>/<name>_tracers.txt` opened by rank 0 with its
  !> header (on a restart, which reads where they are from the dump,
  !> `outputs_after_restart` opens it). Nothing without tracers.
  subroutine tracers_init(cfg, st, sch, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(inout) :: sch
    type(error_t), allocatable, intent(inout) :: err
    integer :: n
    n = cfg%output%ntracer
    if (n == 0) return
    call tracers_start(sch%tracers, st%g, st%halo, cfg%output%tracers(:, 1:n), err)
    if (allocated(err)) return
    call log_line(sch%log, 'tracers: '//itoa(n)//', written to '//tracers_path(sch)//' on the gauge schedule')
    if (.not. sch%restarting .and. sch%pc%rank == 0) &
      call tracers_open(sch%tracers, tracers_path(sch), cfg%output%tracers(:, 1:n), .false., err)
    if (allocated(err)) err%category = ERR_IO
  end subroutine tracers_init

  !> Closes the tracers' file.
  subroutine tracers_end(sch)
    type(schedule_t), intent(inout) :: sch
    call tracers_close(sch%tracers)
  end subroutine tracers_end

  function tracks_path(sch) result(path)
    type(schedule_t), intent(in) :: sch
    character(len=:), allocatable :: path
    path = sch%out%dir//'/'//sch%out%name//'_tracks.txt'
  end function tracks_path

  !> The particles named by the &output track points (the nearest to each at
  !> t = 0, by seeding id: `particles_track`), chosen on the seeded particles
  !> (a restart seeds the same ones before it reads the dump, so it names the
  !> same particles; a decomposed run's blocks choose among their owned ones,
  !> the whole run's choice),
  !> logged, and for a new run the file `<dir>/<name>_tracks.txt` opened by
  !> rank 0 with its header (on a restart `outputs_after_restart` opens it).
  !> Call after the scene is built.
  subroutine tracks_init(cfg, st, sch, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(inout) :: sch
    type(error_t), allocatable, intent(inout) :: err
    type(particles_t) :: own
    real(wp) :: d(1), key, vals(4)
    integer :: n, k, stat, q, np(1), id(1)
    character(len=200) :: msg
    n = cfg%output%ntrack
    if (n == 0) return
    ! (a decomposed run's blocks: their owned particles, the choice the whole
    ! run's: the nearest, of those equally near the smallest id)
    own = st%pt
    if (st%pblocks) call particles_select(own, pack([(q, q = 1, st%pt%np)], st%pw%owned))
    np(1) = own%np
    call parallel_sum(sch%pc, np)
    if (np(1) == 0) then     ! (the deck check refuses this before; kept for callers that skip it)
      call error_set(err, 'tracks_init', '&output track points but no particles', ERR_INPUT)
      return
    end if
    allocate(sch%track_id(n), sch%track_idx(n), sch%track_mat(n), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'tracks_init', error_no_memory('the tracked particles'))
      return
    end if
    call particles_nearest_ids(own, cfg%output%tracks(:, 1:n), sch%track_id)
    call particles_index_of_ids(own, sch%track_id, sch%track_idx)
    do k = 1, n
      q = sch%track_idx(k)
      d = huge(1.0_wp)
      if (q > 0) d = sum((own%x(:, q) - cfg%output%tracks(:, k))**2)
      call parallel_min(sch%pc, d)
      id = huge(1)
      if (q > 0) then
        if (.not. sum((own%x(:, q) - cfg%output%tracks(:, k))**2) > d(1)) id = own%id(q)
      end if
      call parallel_min(sch%pc, id)
      sch%track_id(k) = id(1)
      ! (the values of the block that owns it)
      key = 1.0_wp
      vals = 0.0_wp
      if (q > 0) then
        if (own%id(q) == sch%track_id(k)) then
          key = 0.0_wp
          vals = [own%x(:, q), real(own%mat(q), wp)]
        end if
      end if
      call st%halo%choose(key, vals)
      sch%track_mat(k) = nint(vals(4))
      call log_line(sch%log, 'track '//itoa(k)//': particle id '//itoa(sch%track_id(k))//' seeded at '// &
        xyz_text(vals(1:3))//', nearest to '//xyz_text(cfg%output%tracks(:, k)))
    end do
    if (.not. sch%restarting .and. sch%pc%rank == 0) call tracks_open(cfg, st%pt%nhist, sch, .false., err)
  end subroutine tracks_init

  function xyz_text(x) result(text)
    real(wp), intent(in) :: x(3)
    character(len=:), allocatable :: text
    text = '('//rtoa(x(1))//', '//rtoa(x(2))//', '//rtoa(x(3))//')'
  end function xyz_text

  !> Opens the tracked-particle file: a new one with its header (comment
  !> lines starting with '#', the last naming every column), or (append, on
  !> a restart) the existing one to add rows (a new one if it is missing).
  !> nhist: the particles' history variables (a plastic strain column if
  !> any).
  subroutine tracks_open(cfg, nhist, sch, append, err)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: nhist
    type(schedule_t), intent(inout) :: sch
    logical, intent(in) :: append
    type(error_t), allocatable, intent(inout) :: err
    character(len=512) :: msg
    character(len=:), allocatable :: names
    integer :: ios, k, f, nf
    logical :: exists, new

    inquire(file=tracks_path(sch), exist=exists)
    new = .not. (append .and. exists)
    if (new) then
      open(newunit=sch%track_unit, file=tracks_path(sch), status='replace', action='write', iostat=ios, iomsg=msg)
    else
      open(newunit=sch%track_unit, file=tracks_path(sch), status='old', position='append', action='write', &
           iostat=ios, iomsg=msg)
    end if
    if (ios /= 0) then
      sch%track_unit = -1
      call error_set(err, 'open_outputs', 'cannot open '''//tracks_path(sch)//''': '//trim(msg), ERR_IO)
      return
    end if
    if (.not. new) return
    nf = track_nfield + merge(1, 0, nhist > 0)
    write(sch%track_unit, '(a)') '# tracked particles (lsalepm): a row on the gauge schedule (&output gauge_dt); '// &
      'for each track point k the particle nearest to it at t = 0, by seeding id (id_k): position, velocity, '// &
      'Cauchy stress (Voigt xx yy zz yz xz xy, tension positive), pressure -trace/3, von Mises stress, specific '// &
      'internal energy'//trim(merge(', plastic strain', '                ', nf > track_nfield))// &
      '; the last header row names the columns'
    do k = 1, size(sch%track_id)
      write(sch%track_unit, '(a,i0,a,3es25.16e3,a,i0,a)') '# track ', k, ' at ', cfg%output%tracks(:, k), &
        ': particle id ', sch%track_id(k), ' of solid '''//trim(cfg%solids(sch%track_mat(k))%name)//''''
    end do
    names = '# time'
    do k = 1, size(sch%track_id)
      names = names//' id_'//itoa(k)
      do f = 1, nf
        names = names//' '//trim(track_field_names(f))//'_'//itoa(k)
      end do
    end do
    write(sch%track_unit, '(a)') names
    flush(sch%track_unit)
  end subroutine tracks_open

  !> Appends a tracked-particle row at st%t: each tracked particle found by
  !> its id (`particles_index_of_ids`, afresh: the particles may have been
  !> re-sorted since the last row); on a decomposed run the
  !> block that owns it gives its values (`halo%choose`) and rank 0 writes.
  subroutine tracks_write(st, sch)
    type(state_t), intent(in) :: st
    type(schedule_t), intent(inout) :: sch
    real(wp) :: vals(track_nfield + 1), key
    integer :: k, nf, q
    character(len=32) :: fmt
    if (.not. allocated(sch%track_id)) return
    nf = track_nfield + merge(1, 0, st%pt%nhist > 0)
    write(fmt, '(a,i0,a)') '(1x,i0,', nf, 'es25.16e3)'
    call particles_index_of_ids(st%pt, sch%track_id, sch%track_idx)
    if (sch%track_unit /= -1) write(sch%track_unit, '(es25.16e3)', advance='no') st%t
    do k = 1, size(sch%track_id)
      ! (key 0 on the block that owns the particle, 1 elsewhere)
      q = sch%track_idx(k)
      key = 1.0_wp
      vals = 0.0_wp
      if (q > 0) then
        key = 0.0_wp
        if (allocated(st%pw%owned)) key = merge(0.0_wp, 1.0_wp, st%pw%owned(q))
      end if
      if (q > 0) call particles_track_values(st%pt, q, vals(1:nf))
      call st%halo%choose(key, vals(1:nf))
      ! (held by no block: the particle left the grid through an open face)
      if (key > 0.0_wp) vals = ieee_value(1.0_wp, ieee_quiet_nan)
      if (sch%track_unit /= -1) write(sch%track_unit, fmt, advance='no') sch%track_id(k), vals(1:nf)
    end do
    if (sch%track_unit == -1) return
    write(sch%track_unit, '(a)') ''
    flush(sch%track_unit)
  end subroutine tracks_write

  !> Closes the tracked-particle file.
  subroutine tracks_close(sch)
    type(schedule_t), intent(inout) :: sch
    if (sch%track_unit /= -1) close(sch%track_unit)
    sch%track_unit = -1
  end subroutine tracks_close

  function history_path(sch) result(path)
    type(schedule_t), intent(in) :: sch
    character(len=:), allocatable :: path
    path = sch%out%dir//'/'//sch%out%name//'_history.txt'
  end function history_path

  function matsum_path(sch) result(path)
    type(schedule_t), intent(in) :: sch
    character(len=:), allocatable :: path
    path = sch%out%dir//'/'//sch%out%name//'_matsum.txt'
  end function matsum_path

  !> At the end of a run with gauges (rank 0): the blast answers of each
  !> gauge from its whole history (`io_blast`; the gauge file, which a
  !> restart continues), in `<dir>/<name>_blast.txt` and the log. A failure
  !> to read or write them is logged, not fatal (the run is done).
  subroutine blast_report(cfg, sch)
    type(config_t), intent(in) :: cfg
    type(schedule_t), intent(inout) :: sch
    type(error_t), allocatable :: err
    real(wp), allocatable :: t(:), p(:, :)
    type(blast_t) :: b
    character(len=400) :: row
    character(len=:), allocatable :: path
    integer :: g, u, ios

    if (sch%pc%rank /= 0 .or. cfg%output%ngauge == 0) return
    call blast_read_gauges(gauges_path(sch), cfg%output%ngauge, t, p, err)
    if (allocated(err)) then
      call log_line(sch%log, 'blast answers not computed: '//err%msg)
      return
    end if
    path = sch%out%dir//'/'//sch%out%name//'_blast.txt'
    open(newunit=u, file=path, status='replace', action='write', iostat=ios)
    if (ios == 0) then
      write(u, '(a)', iostat=ios) '# blast answers at the gauges (lsalepm; io_blast): overpressure over the first '// &
        'row''s pressure; arrival when it first reaches half its peak; positive phase to its first return to 0 '// &
        'after the peak (ended 0: still positive at the end, duration and impulse up to it); deck units'
      write(u, '(a)', iostat=ios) '# gauge x y z ambient_pressure arrival peak_overpressure peak_time '// &
        'positive_duration positive_impulse ended'
    end if
    call log_line(sch%log, 'blast answers (also '//path//'): gauge, arrival, peak overpressure, '// &
                  'positive duration, positive impulse')
    do g = 1, cfg%output%ngauge
      b = blast_answers(t, p(:, g))
      write(row, '(i0,9es25.16e3,1x,i0)') g, cfg%output%gauges(:, g), b%ambient, b%arrival, b%peak, b%peak_time, &
        b%duration, b%impulse, merge(1, 0, b%ended)
      if (ios == 0) write(u, '(a)', iostat=ios) trim(row)
      if (.not. b%arrived .and. b%peak > 0.0_wp) then
        call log_line(sch%log, '  gauge '//itoa(g)//': no arrival (largest overpressure '//rtoa(b%peak)// &
                      ', under the detection level of '//rtoa(blast_detection)//' of the ambient pressure)')
      else if (.not. b%arrived) then
        call log_line(sch%log, '  gauge '//itoa(g)//': no overpressure')
      else
        call log_line(sch%log, '  gauge '//itoa(g)//': '//rtoa(b%arrival)//'  '//rtoa(b%peak)//'  '// &
                      rtoa(b%duration)//'  '//rtoa(b%impulse)//trim(merge('             ', '  (not ended)', b%ended)))
      end if
    end do
    if (ios == 0) close(u, iostat=ios)
    if (ios /= 0) call log_line(sch%log, 'blast answers: cannot write '//path)
  end subroutine blast_report

  !> After a restart has been read (st%t is the restart time): drops from the
  !> gauge, tracked-particle, tracer and history files the rows the earlier run wrote after this time
  !> (it may have run on past the dump), then opens both to append, so that a
  !> run split by a restart leaves the same files as the straight run. A
  !> history_dt set only now starts at the next multiple of it.
  subroutine outputs_after_restart(cfg, st, sch, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(inout) :: sch
    type(error_t), allocatable, intent(inout) :: err

    if (cfg%output%history_dt > 0.0_wp) then
      if (.not. sch%t_next_history <= st%t + cfg%output%history_dt) &
        sch%t_next_history = next_multiple(st%t, cfg%output%history_dt)
    end if
    if (sch%pc%rank /= 0) return   ! (rank 0 writes the files)
    if (cfg%output%ngauge > 0) call text_rows_trim(gauges_path(sch), st%t, err)
    if (.not. allocated(err) .and. cfg%output%ntrack > 0) then
      call text_rows_trim(tracks_path(sch), st%t, err)
      if (.not. allocated(err)) call tracks_open(cfg, st%pt%nhist, sch, .true., err)
    end if
    if (.not. allocated(err) .and. cfg%output%ntracer > 0) then
      call text_rows_trim(tracers_path(sch), st%t, err)
      if (.not. allocated(err)) call tracers_open(sch%tracers, tracers_path(sch), &
                                                  cfg%output%tracers(:, 1:cfg%output%ntracer), .true., err)
    end if
    if (.not. allocated(err) .and. cfg%output%history_dt > 0.0_wp) call text_rows_trim(history_path(sch), st%t, err)
    if (.not. allocated(err) .and. cfg%output%history_dt > 0.0_wp) call text_rows_trim(matsum_path(sch), st%t, err)
    if (.not. allocated(err)) call open_histories(cfg, sch, .true., err)
    if (allocated(err)) err%category = ERR_IO
  end subroutine outputs_after_restart

  !> The first whole multiple of `interval` after t (time). An interval
  !> below the resolution of t gives t itself (a row every step), so no
  !> interval, however small, makes a loop or an overflow.
  pure real(wp) function next_multiple(t, interval) result(tn)
    real(wp), intent(in) :: t, interval
    if (interval <= 4.0_wp*epsilon(1.0_wp)*abs(t)) then
      tn = t
    else
      tn = (aint(t/interval) + 1.0_wp)*interval
    end if
  end function next_multiple

  !> An energy history row, if one is due (at history_dt intervals from
  !> t = 0, and at the end time), and closes the file at the end time.
  subroutine history_output(cfg, st, sch)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    real(wp) :: eps_t
    logical :: last
    character(len=160) :: row
    type(matsum_t) :: ms

    if (.not. sch%history_on) return
    eps_t = 1.0e-12_wp*cfg%control%t_end
    last = .not. (st%t < cfg%control%t_end - eps_t)
    if (st%t < sch%t_next_history - eps_t .and. .not. last) return
    call sch%t_output%start()
    call state_totals(st)
    write(row, '(6es25.16e3)') st%t, st%tot%kinetic, st%tot%internal, st%tot%boundary_work, &
      st%tot%kinetic + st%tot%internal, energy_drift(st%tot)
    call matsum_compute(st, ms)
    if (sch%history_unit /= -1) then   ! (rank 0)
      write(sch%history_unit, '(a)') trim(row)
      flush(sch%history_unit)
      call write_rows(sch%matsum_unit, matsum_rows(st%t, ms, material_names(st)))
    end if
    sch%t_next_history = next_multiple(st%t + eps_t, cfg%output%history_dt)
    if (last) then
      if (sch%history_unit /= -1) close(sch%history_unit)
      if (sch%matsum_unit /= -1) close(sch%matsum_unit)
      sch%history_unit = -1
      sch%matsum_unit = -1
      sch%history_on = .false.
    end if
    call sch%t_output%stop()
  end subroutine history_output

  !> Writes `rows` (trimmed) to `unit` and flushes it.
  subroutine write_rows(unit, rows)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: rows(:)
    integer :: i
    if (unit == -1) return
    write(unit, '(a)') (trim(rows(i)), i = 1, size(rows))
    flush(unit)
  end subroutine write_rows

  !> The materials' names, as an array.
  function material_names(st) result(names)
    type(state_t), intent(in) :: st
    character(len=64) :: names(size(st%mats))
    integer :: m
    do m = 1, size(st%mats)
      names(m) = st%mats(m)%name
    end do
  end function material_names

  !> Writes a frame with each cell's material (the largest by volume in a
  !> mixed cell) and, with several materials, each material's fields: its
  !> volume fraction vf_<name>, density density_<name>, specific internal
  !> energy energy_<name> and pressure pressure_<name>. In a cell the
  !> material fills these are the cell's values, in a mixed cell its slot's
  !> values, elsewhere 0. Then, when the deck keeps it (&output fields names
  !> it), each cell's largest pressure so far, max_pressure (`state_note_pressure`).
  subroutine frame_out(cfg, st, sch, path, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout), target :: st
    type(schedule_t), intent(inout) :: sch
    character(len=:), allocatable, intent(out) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer, parameter :: nper = 4          ! fields per material: vf, density, energy, pressure
    ! their names in &output fields
    character(len=*), parameter :: per_key(nper) = [character(len=17) :: 'vf', 'material_density', &
                                                    'material_energy', 'material_pressure']
    integer :: nmat, nf, c, k, s, m, stat, nx, ptotal
    integer, allocatable :: keep(:), pfailed(:), pruns(:, :)
    character(len=32), allocatable :: punits(:)
    integer, allocatable, target :: cellmat(:)
    integer, pointer :: frame_mat(:)
    real(wp), allocatable :: fld(:, :), pfld(:, :), nmass(:)
    character(len=80), allocatable :: names(:), owner(:)
    character(len=32), allocatable :: units(:)
    character(len=16), allocatable :: pnames(:)
    type(frame_meta_t) :: meta
    type(particles_t) :: pt
    character(len=200) :: msg

    nmat = size(st%mats)
    nf = merge(nper*nmat, 0, nmat > 1)
    ! (and after them, when kept, each cell's largest pressure so far)
    nx = merge(1, 0, allocated(st%p_max))
    ! (one material: each cell's material is h%mat, written as it is)
    allocate(cellmat(merge(st%g%ncell, 0, nmat > 1)), fld(st%g%ncell, nf + nx), names(nf + nx), owner(nf + nx), &
             units(nf + nx), meta%materials(nmat), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'frame_out', error_no_memory('the frame''s cell fields'))
      return
    end if
    frame_mat => st%h%mat
    do m = 1, nmat
      meta%materials(m) = st%mats(m)%name
    end do
    meta%title = trim(cfg%control%title)
    meta%unit_system = trim(cfg%control%units)
    if (nmat > 1) then
      cellmat = st%h%mat
      frame_mat => cellmat
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
    if (nx > 0) then
      names(nf + 1) = 'max_pressure'
      units(nf + 1) = units_pressure
      owner(nf + 1) = ''
      fld(:, nf + 1) = st%p_max
    end if
    if (allocated(st%pt%id)) meta%solids = [(cfg%solids(m)%name, m = 1, size(cfg%solids))]
    ! the particles in the whole run's order (blocks that hold their
    ! particles each write their owned ones, at their places among all)
    if (st%pblocks) then
      call particles_blocks_share(sch%pc, st, pt, pruns, ptotal, err)
      call agree_error(sch%pc, err)
      if (allocated(err)) return
    else
      pt = st%pt
    end if
    if (pt%nhist > 0) then
      ! the strength models' history fields (temperature in the deck's
      ! temperature unit, the others dimensionless) and failure flags (1 failed)
      allocate(pfld(size(strength_fields), pt%np), pfailed(pt%np), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'frame_out', error_no_memory('the frame''s particle fields'))
        return
      end if
      do k = 1, pt%np
        associate (model => st%pw%models(pt%mat(k))%m)
          do m = 1, size(strength_fields)
            pfld(m, k) = model%field(trim(strength_fields(m)), pt%hist(:, k))
          end do
          pfailed(k) = merge(1, 0, model%failed(pt%hist(:, k)))
        end associate
      end do
      pnames = [character(len=16) :: strength_fields]
    else
      allocate(pfld(0, pt%np), pnames(0), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'frame_out', error_no_memory('the particles'' names'))
        return
      end if
    end if
    punits = [character(len=32) :: (units_none, k = 1, size(pnames))]
    where (pnames == 'temperature') punits = units_temperature
    ! the per-material columns the deck chose (&output fields)
    keep = [integer ::]
    do k = 1, nf
      if (frame_wants(cfg%output%frame%fields, per_key(mod(k - 1, nper) + 1))) keep = [keep, k]
    end do
    if (nx > 0) keep = [keep, nf + 1]
    ! the kept columns moved to the front (keep increases, so in place):
    ! fld(:, keep) would be a hidden copy of the kept fields, which a
    ! failure frame written when memory has run out cannot afford
    do k = 1, size(keep)
      if (keep(k) == k) cycle
      do c = 1, size(fld, 1)
        fld(c, k) = fld(c, keep(k))
      end do
      names(k) = names(keep(k))
      units(k) = units(keep(k))
      owner(k) = owner(keep(k))
    end do
    nf = size(keep)
    ! the nodal mass of the kinetic energy: with coupled particles the
    ! particles' share too (`state_totals`; without, nmass is not allocated,
    ! so not present: the frame takes the hydro's own)
    if (allocated(st%pw%mp)) nmass = st%h%mnode + st%pw%mp
    if (st%pblocks) then   ! (the ranks write the frame together, each its particles)
      call output_frame(sch%out, st%g, st%h, frame_mat, names(:nf), units(:nf), owner(:nf), fld(:, :nf), st%t, &
                        st%step, st%tot, cfg%echo, meta, path, err, pt=pt, pnames=pnames, pfields=pfld, &
                        comm=sch%pc%world, node_mass=nmass, opts=cfg%output%frame, punits=punits, pfailed=pfailed, &
                        ptotal=ptotal, pruns=pruns)
    else if (sch%pc%nranks > 1) then   ! (the ranks write the frame together)
      call output_frame(sch%out, st%g, st%h, frame_mat, names(:nf), units(:nf), owner(:nf), fld(:, :nf), st%t, &
                        st%step, st%tot, cfg%echo, meta, path, err, pt=pt, pnames=pnames, pfields=pfld, &
                        comm=sch%pc%world, node_mass=nmass, opts=cfg%output%frame, punits=punits, pfailed=pfailed)
    else
      call output_frame(sch%out, st%g, st%h, frame_mat, names(:nf), units(:nf), owner(:nf), fld(:, :nf), st%t, &
                        st%step, st%tot, cfg%echo, meta, path, err, pt=pt, pnames=pnames, pfields=pfld, &
                        node_mass=nmass, opts=cfg%output%frame, punits=punits, pfailed=pfailed)
    end if
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
    call agree_error(sch%pc, err)
    call sch%t_output%stop()
    if (.not. allocated(err)) call log_line(sch%log, 'frame '//path//' at t = '//rtoa(st%t))
  end subroutine write_frame

  !> A gauge row, a tracked-particle row and a tracer row, if due (all on
  !> the gauge schedule, so that their time columns agree).
  subroutine gauge_output(cfg, st, sch)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(in) :: st
    type(schedule_t), intent(inout) :: sch
    if (sch%gauges%n == 0 .and. .not. allocated(sch%track_id) .and. sch%tracers%n == 0) return
    if (st%t < sch%t_next_gauge .and. st%t < cfg%control%t_end) return
    call sch%t_output%start()
    call gauges_write(sch%gauges, st%g, st%h, st%t, st%halo)
    call tracks_write(st, sch)
    call tracers_write(sch%tracers, st%g, st%h, st%t, st%halo)
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

  !> One progress line: step, time, dt and what set it (the cell (i,j,k)
  !> and material with the smallest stable step, or the step controller:
  !> growth limit, dt_max, end or output time), wall time, estimated time
  !> left, and the energy balance. A NaN anywhere in the state shows up here.
  subroutine progress(cfg, st, sch, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(schedule_t), intent(inout) :: sch
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: wall, left, drift
    character(len=256) :: line

    call state_totals(st)
    if (len(totals_not_finite(st%tot)) > 0) then
      call error_set(err, 'time_loop', 'the state is not finite: its total '//totals_not_finite(st%tot)// &
                     ' is a NaN or an infinity, or too large for a real', ERR_RUNTIME)
      return
    end if
    drift = energy_drift(st%tot)
    if (ieee_is_nan(drift)) then
      call error_set(err, 'time_loop', 'the state has a NaN (energy balance is NaN)', ERR_RUNTIME)
      return
    end if
    wall = wall_seconds() - sch%t_total%t0
    ! the time left at the rate since the last progress line (the cost per
    ! unit of simulated time drifts: a blast's steps grow, Euler steps come
    ! and go), or since this segment started
    if (sch%eta_t < 0.0_wp) sch%eta_t = 0.0_wp
    left = 0.0_wp
    if (st%t > sch%eta_t) left = (wall - sch%eta_wall)*(cfg%control%t_end - st%t)/(st%t - sch%eta_t)
    sch%eta_t = st%t
    sch%eta_wall = wall
    write(line, '("step ",i8,"  t ",es12.5,"  dt ",es10.3,"  wall ",f9.2," s  left ",f9.2, &
      &" s  energy drift ",es10.2)') st%step, st%t, st%dt, wall, left, drift
    if (allocated(st%pw%mp)) then
      ! (the part of it the coupling's booked errors explain: decoupling
      ! work and Euler-step transfer, the budget line's terms)
      write(line, '(a," (coupling ",es9.2,")")') trim(line), drift - budget_residual(st%tot)
    end if
    call log_line(sch%log, trim(line)//'  dt by '//step_limit_text(st, sch))
  end subroutine progress

  !> What set the last step: 'cell (i,j,k) <material>' when the stable step
  !> of that cell did, else 'controller' (growth limit, dt_max, dt_init, end
  !> or output time) followed by the cell with the smallest stable step.
  !> On several ranks every rank calls this and gets the same text.
  function step_limit_text(st, sch) result(text)
    type(state_t), intent(in) :: st
    type(schedule_t), intent(in) :: sch
    character(len=:), allocatable :: text
    integer :: k, best(1)
    logical :: here
    k = 0
    if (sch%dt_particle > 0 .and. st%pt%np > 0) k = findloc(st%pt%id, sch%dt_particle, 1)
    here = k > 0 .or. (sch%dt_particle == 0 .and. sch%dt_cell >= 1 .and. sch%dt_cell <= st%g%ncell)
    if (k > 0) then
      text = 'particle id '//itoa(sch%dt_particle)//' (solid '//itoa(st%pt%mat(k))//', cell '// &
             cell_text(st, st%pt%cell(k))//')'
    else if (sch%dt_particle > 0) then
      text = 'particle id '//itoa(sch%dt_particle)
    else if (.not. here) then
      text = 'controller'
    else if (sch%dt_by_cell) then
      text = 'cell '//cell_text(st, sch%dt_cell)
    else
      text = 'controller (smallest stable step: cell '//cell_text(st, sch%dt_cell)//')'
    end if
    if (sch%pc%nranks == 1) return
    ! (a decomposed run, every rank calling: the text of the block holding
    ! the limiting cell or particle, the lowest rank's if none does)
    best = merge(0, sch%pc%nranks, here) + sch%pc%rank
    call parallel_min(sch%pc, best)
    call parallel_bcast_text(sch%pc, text, mod(best(1), sch%pc%nranks))
  end function step_limit_text

  !> '(i,j,k) <material>' of cell c (its indices in the whole grid); a
  !> mixed cell names its materials.
  function cell_text(st, c) result(text)
    type(state_t), intent(in) :: st
    integer, intent(in) :: c
    character(len=:), allocatable :: text
    integer :: i, j, k, m, s
    call st%g%cell_ijk(c, i, j, k)
    i = i + st%g%off(1); j = j + st%g%off(2); k = k + st%g%off(3)
    text = '('//itoa(i)//','//itoa(j)//','//itoa(k)//') '
    m = st%h%mat(c)
    if (m > 0 .and. m <= size(st%mats)) then
      text = text//st%mats(m)%name
    else if (m < 0 .and. -m <= st%mx%n) then
      text = text//'mixed'
      do s = st%mx%start(-m), st%mx%start(-m + 1) - 1
        text = text//merge(' (', ', ', s == st%mx%start(-m))//st%mats(st%mx%mat(s))%name
      end do
      text = text//')'
    else
      text = text//'material '//itoa(m)
    end if
  end function cell_text

  !> The conservation report: mass, momentum, energies, boundary work,
  !> drift, then mass, internal and kinetic energy and momentum of each
  !> material and particle body (`driver_matsum`).
  subroutine report_conservation(st, log, label)
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    character(len=*), intent(in) :: label
    character(len=256) :: line
    real(wp) :: e0
    type(matsum_t) :: ms
    integer :: m
    call state_totals(st)
    write(line, '("conservation (",a,"): mass ",es22.15,"  momentum ",3es23.15)') &
      label, st%tot%mass, st%tot%momentum
    call log_line(log, trim(line))
    write(line, '("  energy: internal ",es22.15,"  kinetic ",es22.15,"  total ",es22.15)') &
      st%tot%internal, st%tot%kinetic, st%tot%internal + st%tot%kinetic
    call log_line(log, trim(line))
    write(line, '("  boundary work ",es22.15,"  relative energy drift ",es10.3)') &
      st%tot%boundary_work, energy_drift(st%tot)
    call log_line(log, trim(line))
    if (allocated(st%pw%mp)) then
      write(line, '("  particles: internal energy ",es22.15,"  virtual-fluid work ",es22.15, &
        &"  decoupling work ",es22.15,"  Euler-step transfer ",es22.15,"  erosion (in internal) ",es22.15)') &
        st%tot%particle_internal, st%tot%vf_work, st%tot%decoupling_work, st%tot%transfer_energy, st%tot%erosion_energy
      call log_line(log, trim(line))
      ! the change of the total, term by term: boundary work (physics), the
      ! coupling's errors (decoupling work, Euler-step transfer), and what
      ! is left unexplained (round-off when every term is booked)
      e0 = max(abs(st%tot%energy_initial), tiny(1.0_wp))
      write(line, '("  energy budget over |E0|: total change ",es11.3," = boundary work ",es11.3, &
        &" - decoupling work ",es11.3," + Euler-step transfer ",es11.3," + residual ",es10.2)') &
        energy_drift(st%tot) + st%tot%boundary_work/e0, st%tot%boundary_work/e0, st%tot%decoupling_work/e0, &
        st%tot%transfer_energy/e0, budget_residual(st%tot)
      call log_line(log, trim(line))
    end if
    call matsum_compute(st, ms)
    do m = 1, size(st%mats)
      write(line, '("  material ",i0," ",a,": mass ",es22.15,"  internal energy ",es22.15, &
        &"  kinetic energy ",es22.15,"  momentum ",3es23.15)') &
        m, st%mats(m)%name, ms%mat(1, m), ms%mat(6, m), ms%mat(5, m), ms%mat(2:4, m)
      call log_line(log, trim(line))
    end do
    do m = 1, size(ms%body, 2)
      write(line, '("  particle body ",i0,": mass ",es22.15,"  internal energy ",es22.15, &
        &"  kinetic energy ",es22.15,"  momentum ",3es23.15)') m, ms%body(1, m), ms%body(6, m), ms%body(5, m), &
        ms%body(2:4, m)
      call log_line(log, trim(line))
    end do
  end subroutine report_conservation
end module driver_output
