!> Asking a running job to stop: SIGTERM (what batch systems send before
!> they kill a job) and SIGUSR1 (what `mpirun` passes on to its processes)
!> are caught and remembered, and a stop file can be looked for. The driver
!> asks at each step's end and, if asked, writes a restart and stops with
!> exit status 3, as at the wall-time limit.
!>
!> The handler only stores the signal's number (the one thing a signal
!> handler may safely do); libc's `signal` keeps it installed and restarts
!> interrupted system calls (glibc's BSD semantics), so a signal during
!> output or MPI communication does not disturb them.
module base_stop
  use, intrinsic :: iso_c_binding, only: c_int, c_funptr, c_funloc
  implicit none
  private
  public :: stop_signals_install, stop_signal_caught, stop_signal_name, stop_file_present, stop_file_remove

  !> Linux's numbers of the signals caught.
  integer(c_int), parameter :: sigusr1 = 10, sigterm = 15

  !> The last signal caught (0: none). Volatile: set by the handler, read by
  !> the time loop.
  integer(c_int), volatile, save :: caught = 0

  interface
    !> sighandler_t signal(int signum, sighandler_t handler)
    function c_signal(signum, handler) bind(c, name='signal') result(previous)
      import :: c_int, c_funptr
      integer(c_int), value, intent(in) :: signum
      type(c_funptr), value, intent(in) :: handler
      type(c_funptr) :: previous
    end function c_signal
  end interface

contains

  !> Catches SIGTERM and SIGUSR1 from now on.
  subroutine stop_signals_install()
    type(c_funptr) :: previous
    previous = c_signal(sigterm, c_funloc(on_signal))
    previous = c_signal(sigusr1, c_funloc(on_signal))
  end subroutine stop_signals_install

  !> The handler: remembers the signal.
  subroutine on_signal(signum) bind(c)
    integer(c_int), value, intent(in) :: signum
    caught = signum
  end subroutine on_signal

  !> The number of the last signal caught; 0 if none.
  integer function stop_signal_caught()
    stop_signal_caught = int(caught)
  end function stop_signal_caught

  !> A signal's name (SIGTERM, SIGUSR1, or "signal N").
  function stop_signal_name(signum) result(name)
    integer, intent(in) :: signum
    character(len=:), allocatable :: name
    character(len=12) :: buf
    select case (signum)
    case (sigterm)
      name = 'SIGTERM'
    case (sigusr1)
      name = 'SIGUSR1'
    case default
      write(buf, '(i0)') signum
      name = 'signal '//trim(buf)
    end select
  end function stop_signal_name

  !> True if the file `path` exists.
  logical function stop_file_present(path)
    character(len=*), intent(in) :: path
    inquire(file=path, exist=stop_file_present)
  end function stop_file_present

  !> Removes the file `path` (honoured: the next run must not stop at once);
  !> ok: it is gone.
  subroutine stop_file_remove(path, ok)
    character(len=*), intent(in) :: path
    logical, intent(out) :: ok
    integer :: unit, ios
    open(newunit=unit, file=path, status='old', action='read', iostat=ios)
    if (ios == 0) close(unit, status='delete', iostat=ios)
    ok = .not. stop_file_present(path)
  end subroutine stop_file_remove
end module base_stop
