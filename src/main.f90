!> lsalepm: runs the deck named on the command line (default
!> input/sedov3d.nml); `lsalepm --defaults` prints every namelist group with
!> its defaults.
program main
  use driver, only: driver_run, driver_print_defaults
  implicit none
  character(len=:), allocatable :: deck
  integer :: n

  if (command_argument_count() >= 1) then
    call get_command_argument(1, length=n)
    deck = repeat(' ', n)
    call get_command_argument(1, deck)
  else
    deck = 'input/sedov3d.nml'
  end if
  if (deck == '--defaults') then
    call driver_print_defaults()
  else
    call driver_run(deck)
  end if
end program main
