!> Unit tests of decks that compose (issue 38): the arithmetic of
!> `&parameters` and `${...}` (io_deck_expr: precedence, Fortran number
!> forms, every error refused without a floating-point trap, numbers
!> written back exactly) and the expansion (io_deck_expand through
!> io_deck: nested includes relative to the including file, parameters
!> across files, file:line in every message, cycles and missing files).
program test_io_deck_expand
  use base_kinds, only: wp
  use base_config, only: max_line
  use io_deck_expr, only: expr_eval, expr_number_text
  use io_deck, only: deck_t, deck_read, deck_from_lines, deck_count, deck_text, deck_where
  use test_assert, only: check, check_summary
  implicit none
  character(len=8), parameter :: known(4) = [character(len=8) :: 'run', 'grid', 'material', 'region']
  character(len=8), parameter :: rep(2) = [character(len=8) :: 'material', 'region']
  character(len=max_line), allocatable :: problems(:), text(:)
  character(len=max_line) :: lines(4)
  type(deck_t) :: deck
  integer :: k
  real(wp) :: v
  character(len=:), allocatable :: msg

  ! ---- arithmetic: each expression against the value Fortran computes ----
  call value_is('4.184*0.023', 4.184_wp*0.023_wp)
  call value_is('1d3', 1000.0_wp)
  call value_is('1.5e-2', 1.5e-2_wp)
  call value_is('1.5D-2', 1.5e-2_wp)
  call value_is('.5 + 2.', 2.5_wp)
  call value_is('2**3**2', 512.0_wp)            ! ** from the right
  call value_is('-2**2', -4.0_wp)               ! unary minus below **, as in Fortran
  call value_is('2*-3', -6.0_wp)
  call value_is('(1 + 2)*3', 9.0_wp)
  call value_is('1 + 2*3', 7.0_wp)
  call value_is('1 - 2 - 3', -4.0_wp)           ! from the left
  call value_is('8/2/2', 2.0_wp)
  call value_is('7/2', 3.5_wp)                  ! real division (no integer truncation)
  call value_is('2**-1', 0.5_wp)
  call value_is('(-2)**3', -8.0_wp)             ! negative base, integer power
  call value_is('2**0.5', sqrt(2.0_wp))
  call value_is(' R * 2 + r_2 ', 0.5_wp*2.0_wp + 3.0_wp)   ! names: any case
  call value_is('1e-300*1e-300', 0.0_wp)        ! underflow is not an error
  ! ---- every mistake refused with a message, never a trap ----
  call refused('2*q', 'unknown name ''q''')
  call refused('1/0', 'division by zero in ''1/0''')
  call refused('1/(r - 0.5)', 'division by zero')
  call refused('0**-1', 'division by zero')
  call refused('1e29**11', 'overflow')
  call refused('1/1e-29/1e-29/1e-29/1e-29/1e-29/1e-29/1e-29/1e-29/1e-29/1e-29/1e-29', 'overflow')
  call refused('1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20*1e20', 'overflow')
  call refused('(-8)**(1/3)', 'negative number to a non-integer power')
  call refused('1e30', 'magnitudes of 1e30 or more are refused')
  call refused('2 +', 'ends where a number')
  call refused('(1 + 2', 'is not closed')
  call refused('2 3', 'unexpected ''3''')
  call refused('2 * * 3', 'expected a number, a name or ''('' at ''* 3''')
  call refused('nan', 'unknown name ''nan''')
  call refused('', 'ends where a number')
  ! ---- values written back: integers as integers, others exactly ----
  call check(expr_number_text(100.0_wp) == '100', 'an integer value is written as one: '//expr_number_text(100.0_wp))
  call check(expr_number_text(-3.0_wp) == '-3', '-3 as -3: '//expr_number_text(-3.0_wp))
  call check(expr_number_text(0.1_wp) == '1e-1', '0.1 in the shortest form: '//expr_number_text(0.1_wp))
  call check(expr_number_text(1.4_wp) == '1.4', '1.4 as 1.4: '//expr_number_text(1.4_wp))
  call round_trip(4.184_wp*0.023_wp)
  call round_trip(1.0_wp/3.0_wp)
  call round_trip(-2.5e-7_wp)
  call round_trip(1.0e15_wp)
  call round_trip(nearest(1.0_wp, 2.0_wp))
  call round_trip(6.02214076e23_wp)

  ! ---- expansion through the deck reader ----
  call execute_command_line('rm -rf test_expand && mkdir -p test_expand/materials test_expand/common')
  call write_file('test_expand/deck.nml', [character(len=80) :: &
    '! a deck that composes', &
    '&parameters n = 10, len = 2,   ! blanks, commas and lines separate', &
    '   h = len/n', &
    '   half = ${len}/2 /', &
    '&run t_end = ${0.1*len} /  ! ${not_evaluated}', &
    "&grid ni = ${n}, nj = 1, nk = 1, xmax = ${len}, ${h}, ${h}, file = '${x}' /", &
    "&include file = 'materials/gas.nml' /", &
    '&region density = ${rho_gas}, pressure = 1 /'])
  call write_file('test_expand/materials/gas.nml', [character(len=80) :: &
    '! gas, included from the deck', &
    "&include file = '../common/air.nml'   /   ! relative to this file's folder", &
    "&material name = 'gas', gamma = ${gamma} /"])
  call write_file('test_expand/common/air.nml', [character(len=80) :: &
    '&parameters gamma = 1.4, rho_gas = 1.2*half /'])
  problems = [character(len=max_line) ::]
  call deck_read('test_expand/deck.nml', known, rep, deck, problems)
  call check(size(problems) == 0, 'the composed deck reads without problems')
  do k = 1, size(problems)
    write(*, '(a)') '  problem: '//trim(problems(k))
  end do
  call check(deck_count(deck, 'material') == 1 .and. deck_count(deck, 'region') == 1, 'the included group is there')
  allocate(text(0))   ! (else gfortran warns of the descriptor of an unallocated array)
  text = deck_text(deck, 'grid')
  call check(index(text(1), 'ni = 10, nj = 1, nk = 1, xmax = 2, 2e-1, 2e-1') > 0, &
             'parameters substituted: '//trim(text(1)))
  call check(index(text(1), "file = '${x}'") > 0, 'a quoted ${...} is left as it is')
  text = deck_text(deck, 'run')
  call check(index(text(1), 't_end = 2e-1 /') > 0, 'an expression substituted: '//trim(text(1)))
  text = deck_text(deck, 'material')
  call check(index(text(1), 'gamma = 1.4 /') > 0, 'a parameter of a file two includes deep: '//trim(text(1)))
  text = deck_text(deck, 'region')
  call check(index(text(1), 'density = 1.2,') > 0, 'a parameter defined in an include from one of the deck: '// &
             trim(text(1)))
  call check(deck_where(deck, 'material') == 'test_expand/materials/gas.nml:3', &
             'an included group is placed in its own file: '//deck_where(deck, 'material'))
  call check(deck_where(deck, 'region') == 'test_expand/deck.nml:8', &
             'the deck''s own groups keep their lines: '//deck_where(deck, 'region'))
  call check(index(deck%notes, '! included: test_expand/materials/../common/air.nml') > 0 .and. &
             index(deck%notes, '! parameter h = 2e-1   (test_expand/deck.nml:3)') > 0, &
             'the notes name the includes and the parameters: '//deck%notes)

  ! ---- refusals, each with file:line ----
  call write_file('test_expand/cycle_a.nml', [character(len=80) :: '! a', "&include file = 'cycle_b.nml' /"])
  call write_file('test_expand/cycle_b.nml', [character(len=80) :: "&include file = './cycle_a.nml' /"])
  call refused_deck('test_expand/cycle_a.nml', 'test_expand/cycle_b.nml:1: &include: ''test_expand/./cycle_a.nml'' '// &
                    'includes itself (test_expand/cycle_a.nml -> test_expand/cycle_b.nml -> test_expand/./cycle_a.nml)')
  call write_file('test_expand/missing.nml', [character(len=80) :: '', "  &INCLUDE file = 'nowhere.nml' /"])
  call refused_deck('test_expand/missing.nml', 'test_expand/missing.nml:2: &include: file '// &
                    '''test_expand/nowhere.nml'' does not exist')
  call write_file('test_expand/bad_inc.nml', [character(len=80) :: "&include 'x.nml' /"])
  call refused_deck('test_expand/bad_inc.nml', "test_expand/bad_inc.nml:1: &include: write it as")
  call write_file('test_expand/mid.nml', [character(len=80) :: "&run t_end = 1 / &include file = 'x.nml' /"])
  call refused_deck('test_expand/mid.nml', 'test_expand/mid.nml:1: &include must start its line')
  call write_file('test_expand/unknown.nml', [character(len=80) :: "&include file = 'materials/bad.nml' /"])
  call write_file('test_expand/materials/bad.nml', [character(len=80) :: '!', '!', '&run t_end = ${tend} /'])
  call refused_deck('test_expand/unknown.nml', 'test_expand/materials/bad.nml:3: ${tend}: unknown name ''tend''')
  call write_file('test_expand/div.nml', [character(len=80) :: '&parameters a = 1,', '  b = 2/(a - 1) /'])
  call refused_deck('test_expand/div.nml', 'test_expand/div.nml:2: &parameters: b: division by zero in ''2/(a - 1)''')
  call write_file('test_expand/twice.nml', [character(len=80) :: '&parameters a = 1 /', '', '&parameters A = 2 /'])
  call refused_deck('test_expand/twice.nml', 'test_expand/twice.nml:3: &parameters: a is already defined '// &
                    '(at test_expand/twice.nml:1)')
  call write_file('test_expand/open.nml', [character(len=80) :: '&parameters a = 1', '  b = 2'])
  call refused_deck('test_expand/open.nml', 'test_expand/open.nml:1: &parameters: the text ends before the group '// &
                    'does (the group has no closing ''/'')')
  call write_file('test_expand/brace.nml', [character(len=80) :: '&run t_end = ${1 + 2 /'])
  call refused_deck('test_expand/brace.nml', 'test_expand/brace.nml:1: ''${'' without its ''}''')

  ! ---- a deck given as lines (the stored deck of a restart, tests) ----
  lines(1) = '&parameters a = 3 /'
  lines(2) = '&run t_end = ${a/2} /'
  lines(3) = "&material name = 'x${a}' /"
  lines(4) = '! ${a}'
  problems = [character(len=max_line) ::]
  call deck_from_lines(lines, 'lines.nml', known, rep, deck, problems)
  text = deck_text(deck, 'run')
  call check(size(problems) == 0 .and. index(text(1), 't_end = 1.5 /') > 0, 'lines are expanded too: '//trim(text(1)))

  call check_summary('test_io_deck_expand')

contains

  subroutine value_is(expr, expected)
    character(len=*), intent(in) :: expr
    real(wp), intent(in) :: expected
    character(len=8), parameter :: names(2) = [character(len=8) :: 'r', 'r_2']
    call expr_eval(expr, names, [0.5_wp, 3.0_wp], v, msg)
    if (len(msg) > 0) then
      call check(.false., ''''//expr//''' evaluates: '//msg)
    else
      call check(abs(v - expected) <= 0.0_wp, ''''//expr//''' = '//expr_number_text(v)//', expected '// &
                 expr_number_text(expected)//' (exactly)')
    end if
  end subroutine value_is

  subroutine refused(expr, what)
    character(len=*), intent(in) :: expr, what
    character(len=8), parameter :: names(1) = [character(len=8) :: 'r']
    call expr_eval(expr, names, [0.5_wp], v, msg)
    call check(index(msg, what) > 0, ''''//expr//''' refused: "'//msg//'" (expected "'//what//'")')
  end subroutine refused

  subroutine round_trip(x)
    real(wp), intent(in) :: x
    real(wp) :: back
    integer :: ios
    character(len=40) :: t
    t = expr_number_text(x)
    read(t, *, iostat=ios) back
    call check(ios == 0 .and. abs(back - x) <= 0.0_wp, expr_number_text(x)//' reads back to the very same double')
  end subroutine round_trip

  subroutine write_file(path, lines)
    character(len=*), intent(in) :: path, lines(:)
    integer :: u, i
    open(newunit=u, file=path, status='replace', action='write')
    do i = 1, size(lines)
      write(u, '(a)') trim(lines(i))
    end do
    close(u)
  end subroutine write_file

  !> The deck at `path` is refused, and one problem starts with `what`.
  subroutine refused_deck(path, what)
    character(len=*), intent(in) :: path, what
    integer :: i
    logical :: found
    problems = [character(len=max_line) ::]
    call deck_read(path, known, rep, deck, problems)
    found = .false.
    do i = 1, size(problems)
      found = found .or. index(problems(i), what) == 1
    end do
    if (size(problems) == 0) then
      call check(.false., path//' refused ("'//what//'"): no problem reported')
    else
      call check(found, path//' refused: "'//trim(problems(1))//'" (expected "'//what//'")')
    end if
  end subroutine refused_deck
end program test_io_deck_expand
