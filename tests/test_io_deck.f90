!> Unit tests of the deck reader (io_deck: groups found with quotes, comments,
!> repeats, a missing `/` and unknown names) and of a package's config life
!> cycle (read, validate every problem, echo, compare with a restart).
program test_io_deck
  use base_kinds, only: wp
  use base_config, only: max_line, no_echo
  use io_deck, only: deck_t, deck_read, deck_from_lines, deck_count, deck_text, deck_line, echo_open, echo_text
  use mesh_grid_config, only: grid_config_t, grid_config_read, grid_config_changes
  use rezone_config, only: rezone_config_t, rezone_config_read
  use test_assert, only: check, check_summary
  implicit none
  character(len=*), parameter :: path = 'test_io_deck.nml'
  character(len=*), parameter :: known(4) = [character(len=8) :: 'run', 'grid', 'material', 'rezone']
  type(deck_t) :: deck
  type(grid_config_t) :: g1, g2
  type(rezone_config_t) :: rz
  character(len=max_line), allocatable :: problems(:), text(:), changes(:)
  character(len=:), allocatable :: echo_txt
  character(len=max_line) :: line(1), lines(5)
  integer :: u, echo

  open(newunit=u, file=path, status='replace', action='write')
  write(u, '(a)') '! a comment with &run in it and a / too'
  write(u, '(a)') "&run title = 'a/b ! not a comment', t_end = 1 /"
  write(u, '(a)') '  &GRID ni = 10, nj = 2, ! a comment / with a slash'
  write(u, '(a)') '        nk = 3 /'
  write(u, '(a)') '&material name = ''one'' /'
  write(u, '(a)') '&material name = ''two'' /  ! trailing comment'
  write(u, '(a)') '&rezone mode = ''lssm'', cos_angle = 0.5'
  write(u, '(a)') '&bogus x = 1 /'
  close(u)

  problems = [character(len=max_line) ::]
  call deck_read(path, known, [character(len=8) :: 'material'], deck, problems)
  call check(size(deck%groups) == 6, 'six groups found')
  call check(deck_count(deck, 'material') == 2, 'two &material groups')
  call check(deck_count(deck, 'grid') == 1, 'upper-case &GRID found as grid')
  call check(size(problems) == 1, 'one problem: the unknown group')
  if (size(problems) == 1) call check(index(problems(1), 'group &bogus is not known; valid: &run, &grid, '// &
                                            '&material, &rezone') > 0, 'the problem names it: '//trim(problems(1)))
  allocate(text(0))   ! (else gfortran -O3 warns of the descriptor of an unallocated array)
  text = deck_text(deck, 'run')
  call check(size(text) == 1, 'a / inside quotes does not end &run')
  text = deck_text(deck, 'grid')
  call check(size(text) == 2, 'a / in a comment does not end &grid; the next line does')
  text = deck_text(deck, 'material', 2)
  call check(size(text) == 1 .and. index(text(1), 'two') > 0, 'the second &material is the second one')
  text = deck_text(deck, 'rezone')
  call check(size(text) == 1, 'an unterminated &rezone ends where the next group starts')
  text = deck_text(deck, 'output')
  call check(size(text) == 0, 'an absent group has no text')

  ! a package's life cycle: read and echo, the echo reads back to the same
  ! values, a restart comparison names what changed
  problems = [character(len=max_line) ::]
  call echo_open(echo, problems)
  call grid_config_read(g1, deck_text(deck, 'grid'), path, echo, problems)
  echo_txt = echo_text(echo)
  call check(size(problems) == 0, 'the &grid group is valid')
  call check(g1%ni == 10 .and. g1%nj == 2 .and. g1%nk == 3, '&grid sizes read')
  call check(all(abs(g1%xmax - 1.0_wp) <= 0.0_wp) .and. g1%subsamples == 16, '&grid defaults kept')
  call check(index(echo_txt, 'NI=10') > 0, 'the echo holds the group: '//echo_txt(1:min(40, len(echo_txt))))
  line(1) = echo_txt   ! assigned: gfortran 12 overruns typed constructors of other lengths
  call grid_config_read(g2, line, path, no_echo, problems)
  changes = [character(len=max_line) ::]
  call grid_config_changes(g1, g2, changes)
  call check(size(changes) == 0, 'the echo reads back to the very values')
  g2%ni = 20
  call grid_config_changes(g1, g2, changes)
  call check(size(changes) == 1, 'a changed ni is one change')
  if (size(changes) == 1) call check(trim(changes(1)) == '&grid ni changed from 10 to 20', &
                                     'the change names it: '//trim(changes(1)))

  ! a grid file: relative to the deck's folder, kept when absolute; the box
  ! may not be given with it; a restart names a changed file
  problems = [character(len=max_line) ::]
  line(1) = "&grid ni = 2, nj = 2, nk = 2, file = 'g.h5' /"
  call grid_config_read(g1, line, 'decks/sub/deck.nml', no_echo, problems)
  call check(size(problems) == 0, 'a &grid with a file is valid')
  call check(g1%file_path == 'decks/sub/g.h5', 'a relative grid file is in the deck''s folder: '//g1%file_path)
  call grid_config_read(g2, line, 'deck.nml', no_echo, problems)
  call check(g2%file_path == 'g.h5', 'a deck in the current folder: the file name as given: '//g2%file_path)
  line(1) = "&grid ni = 2, nj = 2, nk = 2, file = '/abs/g.h5' /"
  call grid_config_read(g2, line, 'decks/deck.nml', no_echo, problems)
  call check(g2%file_path == '/abs/g.h5', 'an absolute grid file stays: '//g2%file_path)
  changes = [character(len=max_line) ::]
  call grid_config_changes(g1, g2, changes)
  call check(size(changes) == 1, 'a changed grid file is one change')
  if (size(changes) == 1) call check(trim(changes(1)) == '&grid file changed', 'it is named: '//trim(changes(1)))
  line(1) = "&grid ni = 2, nj = 2, nk = 2, file = 'g.h5', xmax = 2, 1, 1 /"
  call grid_config_read(g2, line, 'deck.nml', no_echo, problems)
  call check(size(problems) == 1, 'a box given with a grid file is a problem')
  if (size(problems) == 1) call check(index(problems(1), 'xmin and xmax do not apply with file') > 0, &
                                      'it says so: '//trim(problems(1)))

  ! every problem of a group is collected, not just the first
  problems = [character(len=max_line) ::]
  line(1) = "&rezone mode = 'x', side_ratio = 0.5, quality = 2, mof_max_iter = 0 /"
  call rezone_config_read(rz, line, path, no_echo, problems)
  call check(size(problems) == 4, 'four &rezone problems reported')
  ! a missing / is an error of the group that lacks it
  problems = [character(len=max_line) ::]
  call rezone_config_read(rz, deck_text(deck, 'rezone'), path, no_echo, problems)
  call check(size(problems) == 1, 'the unterminated &rezone is one problem')
  if (size(problems) == 1) call check(index(problems(1), '&rezone: end of file') > 0, &
                                      'it says the group has no end: '//trim(problems(1)))
  ! a required group that is absent
  problems = [character(len=max_line) ::]
  call grid_config_read(g1, deck_text(deck, 'output'), path, no_echo, problems)
  call check(size(problems) == 1, 'an absent &grid is a problem')

  ! repeated groups interleaved with others: the k-th of a name is found
  ! through the index by name, with its line
  lines(1) = "&material name = 'a' /"
  lines(2) = "&region density = 1 /"
  lines(3) = "&material name = 'b' /  &region density = 2 /"
  lines(4) = "! a comment"
  lines(5) = "&material name = 'c' /"
  problems = [character(len=max_line) ::]
  call deck_from_lines(lines, path, [character(len=8) :: 'material', 'region'], &
                       [character(len=8) :: 'material', 'region'], deck, problems)
  call check(size(problems) == 0 .and. size(deck%groups) == 5, 'five groups, two names')
  call check(deck_count(deck, 'material') == 3 .and. deck_count(deck, 'region') == 2 .and. &
             deck_count(deck, 'run') == 0, 'counted by name')
  text = deck_text(deck, 'material', 3)
  call check(size(text) == 1 .and. index(text(1), "'c'") > 0, 'the third &material is the last group')
  text = deck_text(deck, 'region', 2)
  call check(size(text) == 1 .and. index(text(1), 'density = 2') > 0, 'the second &region shares a line')
  call check(deck_line(deck, 'region', 2) == 3 .and. deck_line(deck, 'material', 3) == 5, 'their lines')
  text = deck_text(deck, 'material', 4)
  call check(size(text) == 0 .and. deck_line(deck, 'material', 4) == 0, 'no fourth &material')

  open(newunit=u, file=path, status='old')
  close(u, status='delete')
  call check_summary('test_io_deck')
end program test_io_deck
