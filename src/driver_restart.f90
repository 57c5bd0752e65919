!> Restarts for the driver: what is registered, when and where dumps go,
!> reading one back, and refusing a restart whose deck changes the state.
module driver_restart
  use base_kinds, only: wp, i8
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t
  use base_timers, only: wall_seconds
  use material_table, only: material_index_cells
  use material_mixed, only: mixed_t, mixed_allocate
  use io_input, only: config_t, input_read, input_state_changes
  use io_log, only: log_line
  use io_hdf5, only: hdf5_start
  use io_restart, only: restart_write, restart_read, restart_read_deck, restart_read_int_scalar
  use driver_state, only: run, refuse, refuse_one, fatal, report_conservation
  implicit none
  private
  public :: check_restart_deck, register_restart, restart_path, write_restart, read_restart

contains

  !> A restart may change time, output, dump and numerical settings, but not
  !> what the state depends on: compare the deck stored in the restart file
  !> with this one and refuse, naming each changed variable.
  subroutine check_restart_deck()
    type(error_t), allocatable :: err
    character(len=:), allocatable :: text, tmp
    character(len=1024), allocatable :: problems(:)
    type(config_t) :: old
    integer :: u, ios

    call hdf5_start(err)
    if (.not. allocated(err)) call restart_read_deck(trim(run%cfg%restart_from), text, err)
    if (allocated(err)) call refuse_one('&run restart_from: '//err%msg, 'cannot restart')
    ! the stored deck is namelist text: read it back through the same reader
    tmp = trim(run%cfg%restart_from)//'.deck.tmp'
    open(newunit=u, file=tmp, status='replace', action='write', iostat=ios)
    if (ios /= 0) call refuse_one('cannot write '//tmp, 'cannot restart')
    write(u, '(a)') text
    close(u)
    call input_read(tmp, old, problems)
    open(newunit=u, file=tmp, status='old', iostat=ios)
    if (ios == 0) close(u, status='delete')
    if (size(problems) > 0) call refuse(problems, 'the deck stored in '// &
      trim(run%cfg%restart_from)//' cannot be read back')
    call input_state_changes(old, run%cfg, problems)
    if (size(problems) > 0) call refuse(problems, 'a restart cannot change what the state '// &
      'depends on; undo these changes or start a new run')
  end subroutine check_restart_deck

  !> Registers everything a restart must hold (after allocation; any earlier
  !> registration is forgotten first). The mixed cells are always registered,
  !> as zero-size arrays when there are none, with their sizes as the scalars
  !> mixed_n and mixed_nslot: a restart file then holds its own mixed-cell
  !> sizes, which may differ from those the deck builds (after a remap).
  subroutine register_restart()
    call run%reg%clear()
    associate (r => run%reg, h => run%h)
      call r%add('x', 'length', run%g%x)
      call r%add('velocity', 'length/time', h%u)
      call r%add('node_mass', 'mass', h%mnode)
      call r%add('mass', 'mass', h%mass)
      call r%add('volume', 'length^3', h%vol)
      call r%add('density', 'mass/length^3', h%rho)
      call r%add('energy', 'energy/mass', h%e)
      call r%add('pressure', 'pressure', h%p)
      call r%add('sound_speed', 'length/time', h%cs)
      call r%add('viscosity', 'pressure', h%q)
      call r%add('material', '1', h%mat)
      call r%add('mixed_n', '1', run%mx%n)
      call r%add('mixed_nslot', '1', run%mx%nslot)
      call r%add('mixed_cell', '1', run%mx%cell)
      call r%add('mixed_start', '1', run%mx%start)
      call r%add('mixed_material', '1', run%mx%mat)
      call r%add('mixed_volume_fraction', '1', run%mx%vf)
      call r%add('mixed_mass', 'mass', run%mx%mass)
      call r%add('mixed_energy', 'energy/mass', run%mx%e)
      call r%add('mixed_density', 'mass/length^3', run%mx%rho)
      call r%add('mixed_pressure', 'pressure', run%mx%p)
      call r%add('mixed_sound_speed', 'length/time', run%mx%cs)
      call r%add('mixed_centroid', 'natural coordinates', run%mx%xi)
      call r%add('time', 'time', run%t)
      call r%add('dt', 'time', run%dt)
      call r%add('step', '1', run%step)
      call r%add('boundary_work', 'energy', run%tot%boundary_work)
      call r%add('initial_energy', 'energy', run%tot%energy_initial)
      call r%add('t_next_frame', 'time', run%t_next_frame)
      call r%add('t_next_gauge', 'time', run%t_next_gauge)
      call r%add('t_next_dump', 'time', run%t_next_dump)
      call r%add('steps_since_frame', '1', run%steps_since_frame)
      call r%add('nframe', '1', run%out%nframe)
      call r%add('rng_state', 'bits', run%rng_bits)
      call r%add('t_next_euler', 'time', run%t_next_euler)
      call r%add('n_euler', '1', run%n_euler)
    end associate
  end subroutine register_restart

  function restart_path(step) result(path)
    integer, intent(in) :: step
    character(len=:), allocatable :: path
    character(len=16) :: buf
    write(buf, '(i8.8)') step
    path = run%out%dir//'/'//run%out%name//'_restart_'//trim(buf)//'.h5'
  end function restart_path

  !> Writes a restart dump and keeps only the last dump_keep of this run.
  subroutine write_restart()
    type(error_t), allocatable :: err
    character(len=:), allocatable :: path
    character(len=256) :: entry
    real(wp) :: w0
    integer :: u, ios

    w0 = wall_seconds()
    call run%t_output%start()
    path = restart_path(run%step)
    run%rng_bits = transfer(run%rng%s, 1.0_wp)
    ! the registry holds pointers, and an Euler step may have reallocated
    ! the mixed cells since the last dump
    call register_restart()
    if (.not. allocated(run%out%frames)) allocate(run%out%frames(0), run%out%times(0))
    call restart_write(path, run%reg, run%cfg%echo, run%out%frames, run%out%times, err)
    call run%t_output%stop()
    if (allocated(err)) call fatal(err%where, err%msg)
    run%dump_wall = wall_seconds() - w0
    call log_line('restart '//path//' at step '//itoa(run%step)//', t = '//rtoa(run%t))
    if (.not. allocated(run%dumps)) allocate(run%dumps(0))
    entry = path
    run%dumps = [run%dumps, entry]
    do while (size(run%dumps) > run%cfg%dump_keep)
      open(newunit=u, file=trim(run%dumps(1)), status='old', iostat=ios)
      if (ios == 0) close(u, status='delete')
      run%dumps = run%dumps(2:)
    end do
  end subroutine write_restart

  !> The next output time after a restart: the stored one if the interval is
  !> unchanged, none if the interval is now off, else the next multiple of it.
  real(wp) function next_time(stored, interval)
    real(wp), intent(in) :: stored, interval
    if (interval <= 0.0_wp) then
      next_time = huge(1.0_wp)
    else if (stored < huge(1.0_wp)) then
      next_time = stored
    else
      next_time = (aint(run%t/interval) + 1.0_wp)*interval
    end if
  end function next_time

  !> Replaces the state built from the deck by the one in the restart file.
  !> The file's mixed cells may be more or fewer than the deck's (a remap
  !> changes them): their storage is first reallocated to the stored sizes.
  subroutine read_restart()
    type(error_t), allocatable :: err
    character(len=256), allocatable :: frames(:)
    real(wp), allocatable :: times(:)
    character(len=:), allocatable :: path
    integer :: n, nslot

    path = trim(run%cfg%restart_from)
    call restart_read_int_scalar(path, 'mixed_n', n, err)
    if (.not. allocated(err)) call restart_read_int_scalar(path, 'mixed_nslot', nslot, err)
    if (allocated(err)) call refuse_one('&run restart_from: '//err%msg, 'cannot restart')
    if (n < 0 .or. nslot < n) call refuse_one('&run restart_from: '//path//' is damaged: mixed_n = '// &
      itoa(n)//', mixed_nslot = '//itoa(nslot), 'cannot restart')
    if (n /= run%mx%n .or. nslot /= run%mx%nslot) then
      run%mx = mixed_t()   ! frees the deck's storage
      call mixed_allocate(run%mx, n, nslot, err)
      if (allocated(err)) then
        run%mx = mixed_t()
        call fatal(err%where, err%msg)
      end if
      call log_line('restart: '//itoa(n)//' mixed cells ('//itoa(nslot)//' material slots)')
    end if
    call register_restart()
    call restart_read(path, run%reg, frames, times, err)
    if (allocated(err)) call refuse_one('&run restart_from: '//err%msg, 'cannot restart')
    call check_mixed(path)
    run%rng%s = transfer(run%rng_bits, 1_i8)
    ! the frame list continues the XDMF series where it was
    run%out%frames = frames
    run%out%times = times
    call material_index_cells(run%mats, run%h%mat, run%mx, err)
    if (allocated(err)) call fatal(err%where, err%msg)
    ! settings a restart may change: frame and dump intervals
    run%t_next_frame = next_time(run%t_next_frame, run%cfg%frame_dt)
    run%t_next_dump = next_time(run%t_next_dump, run%cfg%dump_dt)
    run%step_start = run%step
    call log_line('restarted from '//path//' at step '//itoa(run%step)//', t = '//rtoa(run%t))
    call report_conservation('restart')
  end subroutine read_restart

  !> Refuses a restart whose mixed cells do not index the grid and the
  !> materials consistently (a damaged file; later code would index out of
  !> bounds): mixed cell k is the cell whose material is -k, and no other
  !> cell has a material <= 0.
  subroutine check_mixed(path)
    character(len=*), intent(in) :: path
    integer :: k, c
    logical :: ok
    associate (mx => run%mx)
      ok = mx%start(1) == 1 .and. mx%start(mx%n + 1) == mx%nslot + 1
      if (mx%nslot > 0) ok = ok .and. all(mx%mat >= 1 .and. mx%mat <= size(run%mats))
      do k = 1, mx%n
        c = mx%cell(k)
        if (.not. ok) exit
        ok = mx%start(k + 1) > mx%start(k) .and. c >= 1 .and. c <= run%g%ncell
        if (ok) ok = run%h%mat(c) == -k
      end do
      ok = ok .and. count(run%h%mat <= 0) == mx%n
    end associate
    if (.not. ok) call refuse_one('&run restart_from: '//path//' is damaged: its mixed cells do not '// &
      'match its cell materials', 'cannot restart')
  end subroutine check_mixed
end module driver_restart
