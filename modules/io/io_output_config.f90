!> The &output group: where outputs go, when frames and gauge rows are
!> written, the gauge points and the track points (each names the particle
!> nearest to it at t = 0, whose history is written on the gauge schedule),
!> the tracer points (massless material points, `io_tracers`), and what a
!> frame holds and how it is stored (`fields`, `particle_fields`,
!> `precision`, `compress`: `frame_options_t`).
module io_output_config
  use base_kinds, only: wp
  use base_config, only: max_line, no_echo, problem_long, problem_add, problem_bad, problem_badi, problem_nml
  use io_deck, only: deck_stem
  use base_strings, only: itoa
  use io_files, only: io_is_dir
  use io_output, only: frame_options_t, frame_grid_fields, frame_particle_fields
  use strength_models, only: strength_fields
  implicit none
  private
  public :: output_config_t, output_config_read, output_config_changes, max_gauges, max_tracks, max_fields, max_tracers

  integer, parameter :: max_gauges = 256      !< gauge points in all (given one by one and along lines)
  integer, parameter :: max_gauge_points = 64 !< given one by one (`gauge`)
  integer, parameter :: max_gauge_lines = 8   !< lines of gauges (`gauge_line`, `gauge_count`)
  integer, parameter :: max_tracks = 64
  integer, parameter :: max_tracers = 64  !< tracer points (`tracer`)
  integer, parameter :: max_fields = 32   !< entries of `fields` and of `particle_fields`

  !> The resolved &output group; the initial values are the defaults.
  type :: output_config_t
    character(len=256) :: dir = 'out'                 !< output directory
    character(len=256) :: name = ''                   !< base name; '' becomes the deck's file stem
    real(wp) :: frame_dt = 0.0_wp                     !< time between frames (time; 0: first and last)
    integer :: frame_steps = 0                        !< also a frame every this many steps (0: off)
    real(wp) :: gauge_dt = 0.0_wp                     !< time between gauge rows (time; 0: every step)
    real(wp) :: history_dt = 0.0_wp                   !< time between energy-history rows (time; 0: off)
    integer :: ngauge = 0                             !< number of gauge points
    real(wp) :: gauges(3, max_gauges) = huge(1.0_wp)  !< gauge points (length); huge: unset
    integer :: ntrack = 0                             !< number of track points
    real(wp) :: tracks(3, max_tracks) = huge(1.0_wp)  !< track points (length); huge: unset
    integer :: ntracer = 0                            !< number of tracers
    real(wp) :: tracers(3, max_tracers) = huge(1.0_wp) !< tracer starting points (length); huge: unset
    !> each cell's largest pressure so far is kept (state `p_max`) and
    !> written: `fields` names 'max_pressure'
    logical :: max_pressure = .false.
    !> the frames' fields and storage (defaults: all fields, doubles, uncompressed)
    type(frame_options_t) :: frame
  end type output_config_t

contains

  !> Reads, validates and echoes the &output group (`text` empty: all
  !> defaults); gauges must lie in the grid box xmin..xmax.
  subroutine output_config_read(this, text, path, xmin, xmax, echo, problems)
    type(output_config_t), intent(out) :: this
    character(len=*), intent(in) :: text(:), path
    real(wp), intent(in) :: xmin(3), xmax(3)
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=256) :: dir, name
    real(wp) :: frame_dt, gauge_dt, history_dt, gauge(3, max_gauge_points), track(3, max_tracks), &
                gauge_line(6, max_gauge_lines), a(3), b(3), tracer(3, max_tracers)
    integer :: gauge_count(max_gauge_lines), l, k
    character(len=32) :: fields(max_fields), particle_fields(max_fields)
    character(len=16) :: precision
    integer :: frame_steps, ios, i, compress
    character(len=max_line) :: msg
    character(len=16) :: tag
    namelist /output/ dir, name, frame_dt, frame_steps, gauge_dt, gauge, gauge_line, gauge_count, history_dt, track, &
                      tracer, fields, particle_fields, precision, compress

    dir = this%dir; name = this%name; frame_dt = this%frame_dt; frame_steps = this%frame_steps
    gauge_dt = this%gauge_dt; history_dt = this%history_dt; gauge = huge(1.0_wp)
    gauge_line = huge(1.0_wp); gauge_count = 0
    track = this%tracks
    tracer = this%tracers
    fields = ''; particle_fields = ''; precision = 'double'; compress = 0
    if (size(text) > 0) then
      read(text, nml=output, iostat=ios, iomsg=msg)
      if (ios /= 0) call problem_nml(problems, path, 'output', ios, msg)
    end if
    call problem_long(problems, 'output', 'dir', dir)
    call problem_long(problems, 'output', 'name', name)
    call check_dir(problems, dir)
    if (len_trim(name) == 0) name = deck_stem(path)
    if (frame_dt < 0.0_wp) call problem_bad(problems, 'output', 'frame_dt', frame_dt, &
                                            'must be >= 0 (0: first and last frame only)')
    if (gauge_dt < 0.0_wp) call problem_bad(problems, 'output', 'gauge_dt', gauge_dt, 'must be >= 0 (0: every step)')
    if (.not. (history_dt >= 0.0_wp)) call problem_bad(problems, 'output', 'history_dt', history_dt, &
                                                       'must be >= 0 (0: off)')
    if (frame_steps < 0) call problem_badi(problems, 'output', 'frame_steps', frame_steps, 'must be >= 0')
    do i = 1, max_gauge_points
      if (any(gauge(:, i) > 0.5_wp*huge(1.0_wp))) exit
      this%ngauge = i
      this%gauges(:, i) = gauge(:, i)
      if (any(gauge(:, i) < xmin) .or. any(gauge(:, i) > xmax)) then
        write(tag, '(a,i0,a)') 'gauge(:,', i, ')'
        call problem_add(problems, '&output: '//trim(tag)//' is outside the grid box xmin..xmax')
      end if
    end do
    ! lines of gauges: gauge_count(l) points evenly from gauge_line(1:3, l)
    ! to gauge_line(4:6, l), both ends included, after the single points
    do l = 1, max_gauge_lines
      write(tag, '(a,i0,a)') 'gauge_line(:,', l, ')'
      if (any(gauge_line(:, l) > 0.5_wp*huge(1.0_wp))) then
        if (gauge_count(l) /= 0) call problem_add(problems, '&output: gauge_count('//itoa(l)//') is given but '// &
                                                  trim(tag)//' is not (x0, y0, z0, x1, y1, z1)')
        cycle
      end if
      a = gauge_line(1:3, l)
      b = gauge_line(4:6, l)
      if (any(a < xmin) .or. any(a > xmax) .or. any(b < xmin) .or. any(b > xmax)) &
        call problem_add(problems, '&output: '//trim(tag)//' runs outside the grid box xmin..xmax')
      if (gauge_count(l) < 2) then
        call problem_badi(problems, 'output', 'gauge_count('//itoa(l)//')', gauge_count(l), &
                          'must be >= 2 for a line of gauges (its two ends and the points between)')
        cycle
      end if
      if (this%ngauge + gauge_count(l) > max_gauges) then
        call problem_add(problems, '&output: more than '//itoa(max_gauges)//' gauges in all (points and lines)')
        exit
      end if
      do k = 0, gauge_count(l) - 1
        this%ngauge = this%ngauge + 1
        this%gauges(:, this%ngauge) = a + (b - a)*(real(k, wp)/real(gauge_count(l) - 1, wp))
      end do
    end do
    do i = 1, max_tracks
      if (any(track(:, i) > 0.5_wp*huge(1.0_wp))) exit
      this%ntrack = i
      this%tracks(:, i) = track(:, i)
      if (any(track(:, i) < xmin) .or. any(track(:, i) > xmax)) then
        write(tag, '(a,i0,a)') 'track(:,', i, ')'
        call problem_add(problems, '&output: '//trim(tag)//' is outside the grid box xmin..xmax')
      end if
    end do
    do i = 1, max_tracers
      if (any(tracer(:, i) > 0.5_wp*huge(1.0_wp))) exit
      this%ntracer = i
      this%tracers(:, i) = tracer(:, i)
      if (any(tracer(:, i) < xmin) .or. any(tracer(:, i) > xmax)) then
        write(tag, '(a,i0,a)') 'tracer(:,', i, ')'
        call problem_add(problems, '&output: '//trim(tag)//' is outside the grid box xmin..xmax')
      end if
    end do
    call field_choice(problems, 'fields', fields, frame_grid_fields, this%frame%fields)
    ! (named only: not among "all")
    if (allocated(this%frame%fields)) this%max_pressure = any(this%frame%fields == 'max_pressure')
    call field_choice(problems, 'particle_fields', particle_fields, &
                      [character(len=32) :: frame_particle_fields, strength_fields, 'failed'], this%frame%particle_fields)
    call problem_long(problems, 'output', 'precision', precision)
    select case (precision)
    case ('double')
      this%frame%single = .false.
    case ('single')
      this%frame%single = .true.
    case default
      call problem_add(problems, '&output: precision = '''//trim(precision)//''' is not known; valid: double, single')
    end select
    if (compress < 0 .or. compress > 9) then
      call problem_badi(problems, 'output', 'compress', compress, 'must be 0..9 (0: off, 1..9: the deflate level)')
    else
      this%frame%deflate = compress
    end if
    this%dir = dir; this%name = name; this%frame_dt = frame_dt
    this%frame_steps = frame_steps; this%gauge_dt = gauge_dt; this%history_dt = history_dt
    if (echo /= no_echo) write(echo, nml=output)
  end subroutine output_config_read

  !> A restart continues the frame series of the run it continues (its
  !> XDMF lists the earlier frames with the fields and precision of the new
  !> ones), so a restart's deck keeps `fields`, `particle_fields` and
  !> `precision`: one line in `changes` for each changed (`compress` may
  !> change: a reader does not see it). The tracers are state the restart
  !> holds (where each one is now): their starting points stay too.
  subroutine output_config_changes(old, new, changes)
    type(output_config_t), intent(in) :: old, new
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    call list_change('fields', old%frame%fields, new%frame%fields)
    call list_change('particle_fields', old%frame%particle_fields, new%frame%particle_fields)
    if (old%frame%single .neqv. new%frame%single) &
      call problem_add(changes, '&output precision changed from '''//trim(merge('single', 'double', old%frame%single))// &
                       ''' to '''//trim(merge('single', 'double', new%frame%single))//''' (the frames of one series '// &
                       'share their fields and precision)')
    if (old%ntracer /= new%ntracer) then
      call problem_add(changes, '&output tracer: '//itoa(old%ntracer)//' tracer point(s) before, '// &
                       itoa(new%ntracer)//' now (a restart continues the tracers it holds)')
    else if (any(abs(old%tracers(:, 1:old%ntracer) - new%tracers(:, 1:new%ntracer)) > 0.0_wp)) then
      call problem_add(changes, '&output tracer changed (a restart continues the tracers it holds)')
    end if
  contains
    !> A line if the chosen fields differ (as sets; unallocated: all).
    subroutine list_change(var, a, b)
      character(len=*), intent(in) :: var
      character(len=32), allocatable, intent(in) :: a(:), b(:)
      logical :: same
      integer :: k
      same = allocated(a) .eqv. allocated(b)
      if (same .and. allocated(a)) then
        same = size(a) == size(b)
        do k = 1, size(a)
          if (same) same = any(b == a(k))
        end do
      end if
      if (.not. same) call problem_add(changes, '&output '//var//' changed from '//text(a)//' to '//text(b)// &
                                       ' (the frames of one series share their fields and precision)')
    end subroutine list_change

    !> The list as the deck would give it ('' for all).
    function text(a) result(t)
      character(len=32), allocatable, intent(in) :: a(:)
      character(len=:), allocatable :: t
      integer :: k
      if (.not. allocated(a)) then
        t = "'' (all)"
        return
      end if
      if (size(a) == 0) then
        t = "'none'"
        return
      end if
      t = "'"//trim(a(1))//"'"
      do k = 2, size(a)
        t = t//", '"//trim(a(k))//"'"
      end do
    end function text
  end subroutine output_config_changes

  !> The fields chosen by the deck's list `given` (blank entries skipped;
  !> none given: `chosen` unallocated, all fields), each one of `valid`, or
  !> 'none' alone (`chosen` empty: the coordinates only); a name not known is
  !> a problem naming the valid ones.
  subroutine field_choice(problems, var, given, valid, chosen)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), intent(in) :: var, given(:), valid(:)
    character(len=32), allocatable, intent(out) :: chosen(:)
    character(len=max_line) :: list
    integer :: k, m, n
    n = count(len_trim(given) > 0)
    if (n == 0) return
    chosen = [character(len=32) ::]
    do k = 1, size(given)
      if (len_trim(given(k)) == 0) cycle
      call problem_long(problems, 'output', var, given(k))
      if (given(k) == 'none') then
        if (n > 1) call problem_add(problems, '&output: '//var//' = ''none'' (the coordinates only) '// &
                                    'cannot go with other names')
        cycle
      end if
      if (any(valid == given(k))) then
        if (.not. any(chosen == given(k))) chosen = [character(len=32) :: chosen, given(k)]
        cycle
      end if
      list = ''
      do m = 1, size(valid)
        list = trim(list)//' '//trim(valid(m))//','
      end do
      call problem_add(problems, '&output: '//var//' = '''//trim(given(k))//''' is not known; valid:'// &
                       trim(list)//' none')
    end do
  end subroutine field_choice

  !> A directory whose path runs through an existing file can never be made:
  !> a deck mistake, found before the run (other failures to create it are
  !> I/O failures of the run).
  subroutine check_dir(problems, dir)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), intent(in) :: dir
    integer :: i, j
    logical :: exists
    do i = 2, len_trim(dir)
      if (dir(i:i) /= '/' .and. i < len_trim(dir)) cycle
      j = i
      if (dir(i:i) == '/') j = i - 1
      inquire(file=dir(1:j), exist=exists)
      if (.not. exists) return
      if (.not. io_is_dir(dir(1:j))) then
        call problem_add(problems, '&output: dir = '''//trim(dir)//''' cannot be a directory: '''// &
                         dir(1:j)//''' is a file')
        return
      end if
    end do
  end subroutine check_dir
end module io_output_config
