!> The process's exit status when the program did not choose it. gfortran's
!> runtime library ends a program that hits a runtime error (a bug: an
!> array bound, an I/O statement without iostat=) with exit status 2, the
!> status this code documents for "bad input". `exit_guard_install` registers
!> a C `atexit` handler; the one place that ends a run (`driver_halt`) calls
!> `exit_planned` just before it stops, and any other exit is turned into
!> EXIT_INTERNAL by the handler. The mark lives in the process environment
!> (LSALEPM_EXIT_PLANNED), so no module keeps state.
module base_exit
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_funptr, c_funloc, c_null_char
  implicit none
  private
  public :: exit_guard_install, exit_planned, EXIT_INTERNAL

  !> Exit status of a run that ended without choosing its status (a bug).
  integer, parameter :: EXIT_INTERNAL = 5

  character(len=*), parameter :: mark = 'LSALEPM_EXIT_PLANNED'

  interface
    function c_atexit(handler) bind(c, name='atexit') result(status)
      import :: c_int, c_funptr
      type(c_funptr), value, intent(in) :: handler
      integer(c_int) :: status
    end function c_atexit
    function c_setenv(name, value, overwrite) bind(c, name='setenv') result(status)
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: name(*), value(*)
      integer(c_int), value, intent(in) :: overwrite
      integer(c_int) :: status
    end function c_setenv
    subroutine c_exit_now(status) bind(c, name='_exit')
      import :: c_int
      integer(c_int), value, intent(in) :: status
    end subroutine c_exit_now
  end interface

contains

  !> From now on an exit not announced by `exit_planned` ends with status
  !> EXIT_INTERNAL.
  subroutine exit_guard_install()
    integer(c_int) :: status
    status = c_setenv(mark//c_null_char, '0'//c_null_char, 1_c_int)
    status = c_atexit(c_funloc(on_exit))
  end subroutine exit_guard_install

  !> Announces that the program now ends with the status it chose.
  subroutine exit_planned()
    integer(c_int) :: status
    status = c_setenv(mark//c_null_char, '1'//c_null_char, 1_c_int)
  end subroutine exit_planned

  !> The atexit handler: an unannounced exit becomes EXIT_INTERNAL.
  subroutine on_exit() bind(c)
    character(len=1) :: value
    integer :: length, status
    call get_environment_variable(mark, value, length, status)
    if (status == 0 .and. value == '1') return
    call c_exit_now(int(EXIT_INTERNAL, c_int))
  end subroutine on_exit
end module base_exit
