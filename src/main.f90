!> lsalepm: runs a deck. `lsalepm deck.nml` runs it; `lsalepm --restart
!> FILE deck.nml` continues the run from the restart FILE; `lsalepm --check
!> deck.nml` only reads and validates it; `--defaults`, `--version` and
!> `--help` print what they say (see `usage`).
program main
  use driver, only: driver_run, driver_check, driver_print_defaults, driver_print_version
  use driver_halt, only: halt
  use io_log, only: log_t
  use, intrinsic :: iso_fortran_env, only: error_unit
  implicit none
  character(len=:), allocatable :: arg, deck, restart, action
  integer :: k, nargs

  nargs = command_argument_count()
  deck = ''
  restart = ''
  action = 'run'
  k = 1
  do while (k <= nargs)
    arg = argument(k)
    select case (arg)
    case ('--help', '-h')
      call one_action('help')
    case ('--version')
      call one_action('version')
    case ('--defaults')
      call one_action('defaults')
    case ('--check')
      call one_action('check')
    case ('--restart')
      if (k == nargs) call wrong_usage('--restart needs the restart file: lsalepm --restart FILE deck.nml')
      if (len(restart) > 0) call wrong_usage('--restart given twice')
      k = k + 1
      restart = argument(k)
      if (len(restart) == 0) call wrong_usage('--restart needs the restart file: lsalepm --restart FILE deck.nml')
    case default
      if (len(arg) > 0) then
        if (arg(1:1) == '-') call wrong_usage('unknown option '//arg)
      end if
      if (len(deck) > 0) call wrong_usage('one deck at a time: '''//deck//''' and '''//arg//'''')
      deck = arg
    end select
    k = k + 1
  end do
  select case (action)
  case ('help')
    call usage()
  case ('version')
    if (nargs > 1) call wrong_usage('--version takes no other argument')
    call driver_print_version()
  case ('defaults')
    if (nargs > 1) call wrong_usage('--defaults takes no other argument')
    call driver_print_defaults()
  case ('check')
    if (len(restart) > 0) call wrong_usage('--check and --restart do not go together')
    if (len(deck) == 0) call wrong_usage('--check needs a deck: lsalepm --check deck.nml')
    call driver_check(deck)
  case default
    if (len(deck) == 0) deck = 'input/sedov3d.nml'
    if (len(restart) > 0) then
      call driver_run(deck, restart)
    else
      call driver_run(deck)
    end if
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

  !> --check, --defaults and --version exclude each other.
  subroutine one_action(what)
    character(len=*), intent(in) :: what
    if (action /= 'run') call wrong_usage('--'//action//' and --'//what//' do not go together')
    action = what
  end subroutine one_action

  subroutine usage()
    write(*, '(a)') 'usage: lsalepm [deck.nml]          run a deck (default input/sedov3d.nml)', &
                    '       lsalepm --restart FILE [deck.nml]', &
                    '                                   continue the deck''s run from the restart FILE (as', &
                    '                                   &run restart_from = ''FILE'', which it overrides)', &
                    '       lsalepm --check deck.nml    read and validate a deck, print it resolved; exit 0 or 2', &
                    '       lsalepm --defaults          every namelist group with its defaults (! required: no default)', &
                    '       lsalepm --version           version, build type, compiler and libraries', &
                    '       lsalepm --help              this text', &
                    'exit status: 0 done, 1 runtime failure, 2 bad input, 3 stopped with a restart written (wall-time '// &
                    'limit, stop file <dir>/<name>.stop, SIGTERM or SIGUSR1), ' // &
                    '4 output could not be written, 5 internal error (a bug)', &
                    'decks: input/README.md; outputs go to the &output dir (default out/)'
  end subroutine usage

  !> A command line that means nothing: say what is wrong and how to call
  !> the program, exit status 2.
  subroutine wrong_usage(what)
    character(len=*), intent(in) :: what
    type(log_t) :: log
    write(error_unit, '(a)') 'ERROR: '//what
    call usage()
    call halt(log, 2)
  end subroutine wrong_usage
end program main
