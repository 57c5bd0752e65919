!> lsalepm: runs a deck. `lsalepm deck.nml` runs it; `lsalepm --check
!> deck.nml` only reads and validates it; `--defaults`, `--version` and
!> `--help` print what they say (see `usage`).
program main
  use driver, only: driver_run, driver_check, driver_print_defaults, driver_print_version
  use driver_halt, only: halt
  use io_log, only: log_t
  implicit none
  character(len=:), allocatable :: arg1, arg2
  integer :: nargs

  nargs = command_argument_count()
  arg1 = argument(1)
  arg2 = argument(2)
  select case (arg1)
  case ('')
    call driver_run('input/sedov3d.nml')
  case ('--help', '-h')
    call usage()
  case ('--version')
    call driver_print_version()
  case ('--defaults')
    call driver_print_defaults()
  case ('--check')
    if (nargs /= 2) call wrong_usage()
    call driver_check(arg2)
  case default
    if (arg1(1:1) == '-' .or. nargs > 1) call wrong_usage()
    call driver_run(arg1)
  end select

contains

  !> The k-th command-line argument, '' if there is none.
  function argument(k) result(text)
    integer, intent(in) :: k
    character(len=:), allocatable :: text
    integer :: n
    text = ''
    if (command_argument_count() < k) return
    call get_command_argument(k, length=n)
    text = repeat(' ', n)
    call get_command_argument(k, text)
  end function argument

  subroutine usage()
    write(*, '(a)') 'usage: lsalepm [deck.nml]          run a deck (default input/sedov3d.nml)', &
                    '       lsalepm --check deck.nml    read and validate a deck, print it resolved; exit 0 or 2', &
                    '       lsalepm --defaults          every namelist group with its defaults', &
                    '       lsalepm --version           version, build type, compiler and libraries', &
                    '       lsalepm --help              this text', &
                    'exit status: 0 done, 1 runtime failure, 2 bad input, 3 wall-time limit (restart written), ' // &
                    '4 output could not be written, 5 internal error (a bug)', &
                    'decks: input/README.md; outputs go to the &output dir (default out/)'
  end subroutine usage

  !> A command line that means nothing: say how to call it, exit status 2.
  subroutine wrong_usage()
    type(log_t) :: log
    call usage()
    call halt(log, 2)
  end subroutine wrong_usage
end program main
