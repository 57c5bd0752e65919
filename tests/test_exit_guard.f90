!> The exit guard: with it installed, a Fortran runtime error (here a read
!> of a bad integer without iostat=, which gfortran ends with status 2, the
!> status of "bad input") ends with EXIT_INTERNAL (5) instead; an announced
!> stop keeps its status. Run by ctest with the expected status as argument:
!> `test_exit_guard runtime` must exit 5, `test_exit_guard planned` 2.
program test_exit_guard
  use base_exit, only: exit_guard_install, exit_planned
  implicit none
  character(len=16) :: how
  character(len=2) :: text
  integer :: i
  call get_command_argument(1, how)
  call exit_guard_install()
  if (how == 'planned') then
    call exit_planned()
    stop 2
  end if
  text = 'x7'
  read(text, '(i2)') i
  write(*, '(i0)') i
end program test_exit_guard
