!> The deck file: finds its namelist groups and hands each package the text
!> of its group(s). It knows no group's variables; each package's config
!> module reads, validates and echoes its own group (`base_config`).
!>
!> A group starts at a line whose first non-blank character is `&` and ends
!> at the first `/` outside quotes and `!` comments (or where the next group
!> starts, so a missing `/` is reported for the group that lacks it).
!> The deck's text is first expanded (`io_deck_expand`: `&include`,
!> `&parameters`, `${...}`); every line keeps the file and line it came
!> from, and each problem names them ("file:line: ...").
module io_deck
  use base_config, only: max_line, no_echo, problem_add
  use base_strings, only: itoa, lower, number_ok
  use io_files, only: io_is_dir
  use io_deck_expand, only: deck_source_t, deck_expand_file, deck_expand_lines, deck_source_notes
  implicit none
  private
  public :: deck_t, deck_group_t, deck_read, deck_from_lines, text_lines, deck_count, deck_text, deck_line, deck_stem, &
            deck_where, echo_open, echo_text

  !> One group of the deck: its name (lower case), first line and text (as
  !> long as its longest line: decks of many small groups stay small).
  type :: deck_group_t
    character(len=32) :: name = ''
    integer :: line = 0
    integer :: file = 1     !< where it is written: deck_t%files(file), line `line`
    character(len=:), allocatable :: text(:)
  end type deck_group_t

  !> The groups of a deck file, in file order, and an index by name (so
  !> that finding the k-th group of a name costs nothing like a scan of the
  !> deck: a deck may hold tens of thousands of &region groups).
  type :: deck_t
    character(len=:), allocatable :: path
    !> the deck (1) and the files it includes, in the order of inclusion
    character(len=max_line), allocatable :: files(:)
    !> comments for the echo: the files included and the parameters' values
    character(len=:), allocatable :: notes
    type(deck_group_t), allocatable :: groups(:)
    character(len=32), allocatable :: names(:)   !< the distinct group names, in order of first appearance
    integer, allocatable :: first(:)             !< groups called names(u): members(first(u):first(u+1)-1)
    integer, allocatable :: members(:)           !< indices in groups, by name, in file order within a name
    !> a value is NaN, infinite or huge: the groups must not be read (their
    !> checks would trap or overflow)
    logical :: unsafe = .false.
  end type deck_t

contains

  !> Reads the deck at `path` and finds its groups; a group whose name is not
  !> in `known` is a problem (the list of valid names is given).
  subroutine deck_read(path, known, repeatable, deck, problems)
    character(len=*), intent(in) :: path, known(:), repeatable(:)
    type(deck_t), intent(out) :: deck
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    type(deck_source_t) :: src
    integer :: n0
    logical :: exists

    deck%path = path
    deck%groups = [deck_group_t ::]
    allocate(deck%files(1), stat=n0)
    if (n0 /= 0) return
    deck%files(1) = path
    deck%notes = ''
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call problem_add(problems, 'deck file '''//trim(path)//''' does not exist')
      return
    end if
    if (io_is_dir(path)) then
      call problem_add(problems, ''''//trim(path)//''' is a directory, not a deck file')
      return
    end if
    n0 = size(problems)
    call deck_expand_file(path, src, problems)
    if (size(problems) > n0) return   ! (the groups of a deck that did not expand would only add confusion)
    call from_source(src, path, known, repeatable, deck, problems)
  end subroutine deck_read

  !> The groups of a deck given as its lines (`path` names it in messages).
  !> Only the groups in `repeatable` may appear more than once. Tabs count
  !> as blanks and a UTF-8 byte-order mark is skipped.
  !> `origin` (optional): the line of the deck each of `lines` comes from
  !> (a long line is cut into several, `text_lines`), for messages.
  subroutine deck_from_lines(lines, path, known, repeatable, deck, problems, origin)
    character(len=*), intent(in) :: lines(:), path, known(:), repeatable(:)
    type(deck_t), intent(out) :: deck
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer, intent(in), optional :: origin(:)
    type(deck_source_t) :: src
    integer :: n0
    deck%path = path
    deck%groups = [deck_group_t ::]
    allocate(deck%files(1), stat=n0)
    if (n0 /= 0) return
    deck%files(1) = path
    deck%notes = ''
    n0 = size(problems)
    call deck_expand_lines(lines, path, src, problems, origin)
    if (size(problems) > n0) return
    call from_source(src, path, known, repeatable, deck, problems)
  end subroutine deck_from_lines

  !> The groups of an expanded deck: its lines cut to deck lines of at most
  !> max_line characters (`append_line`), each with its file and line.
  subroutine from_source(src, path, known, repeatable, deck, problems)
    type(deck_source_t), intent(in) :: src
    character(len=*), intent(in) :: path, known(:), repeatable(:)
    type(deck_t), intent(out) :: deck
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=max_line), allocatable :: lines(:)
    integer, allocatable :: origin(:), at_line(:), at_file(:)
    integer :: g, n, stat
    logical :: forced
    character(len=200) :: msg

    n = 0
    allocate(lines(max(src%n, 16)), origin(max(src%n, 16)), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call problem_add(problems, trim(path)//': out of memory for the deck''s lines: '//trim(msg))
      return
    end if
    do g = 1, src%n
      call append_line(src%lines(g)%text, g, lines, origin, n, forced, stat)
      if (stat /= 0) then
        call problem_add(problems, trim(path)//': out of memory for the deck''s lines')
        return
      end if
      if (forced) call problem_add(problems, trim(src%files(src%lines(g)%file))//':'//itoa(src%lines(g)%line)// &
        ': a quoted string or a word longer than '//itoa(max_line - 2)//' characters (lines of any length are '// &
        'read, but each string or number in them must fit in '//itoa(max_line - 2)//')')
    end do
    allocate(at_line(n), at_file(n), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call problem_add(problems, trim(path)//': out of memory for the deck''s lines: '//trim(msg))
      return
    end if
    do g = 1, n
      at_line(g) = src%lines(origin(g))%line
      at_file(g) = src%lines(origin(g))%file
    end do
    call cut_deck(lines(1:n), path, known, repeatable, deck, problems, at_line, at_file, src%files)
    deck%notes = deck_source_notes(src)
  end subroutine from_source

  !> The groups of deck lines (changed in place: tabs to blanks, the BOM
  !> dropped); origin, ofile: the line and file (in `files`) of each.
  subroutine cut_deck(clean, path, known, repeatable, deck, problems, origin, ofile, files)
    character(len=*), intent(inout) :: clean(:)
    character(len=*), intent(in) :: path, known(:), repeatable(:), files(:)
    type(deck_t), intent(out) :: deck
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer, intent(in) :: origin(:), ofile(:)
    character(len=:), allocatable :: valid
    character(len=*), parameter :: bom = char(239)//char(187)//char(191)
    integer :: i, k

    deck%path = path
    deck%files = files
    deck%notes = ''
    deck%groups = [deck_group_t ::]
    do i = 1, size(clean)
      do k = 1, len_trim(clean(i))
        if (clean(i)(k:k) == achar(9)) clean(i)(k:k) = ' '
      end do
    end do
    if (size(clean) > 0) then
      if (clean(1)(1:3) == bom) clean(1) = clean(1)(4:)
    end if
    call split_groups(clean, deck%files, deck%groups, problems, origin, ofile)
    call index_groups(deck)
    valid = ''
    do k = 1, size(known)
      valid = valid//merge(', ', '  ', k > 1)//'&'//trim(known(k))
    end do
    valid = valid(3:)
    do i = 1, size(deck%groups)
      if (any(known == deck%groups(i)%name)) cycle
      call problem_add(problems, group_place(deck, i)//': group &'// &
                       trim(deck%groups(i)%name)//' is not known; valid: '//valid)
    end do
    do i = 1, size(deck%groups)
      if (.not. values_ok(deck%groups(i), group_place(deck, i), problems)) deck%unsafe = .true.
    end do
    do i = 1, size(deck%groups)
      associate (gi => deck%groups(i))
        if (any(repeatable == gi%name)) cycle
        do k = 1, i - 1
          if (deck%groups(k)%name /= gi%name) cycle
          call problem_add(problems, group_place(deck, i)//': a second &'//trim(gi%name)// &
                           ' group (the first is at '//first_place(k)//'); only &material, '// &
                           '&region and &source may repeat')
          exit
        end do
      end associate
    end do

  contains

    !> Where group k is: "line N" in the same file as group i, else "file:N".
    function first_place(k) result(t)
      integer, intent(in) :: k
      character(len=:), allocatable :: t
      if (deck%groups(k)%file == deck%groups(i)%file) then
        t = 'line '//itoa(deck%groups(k)%line)
      else
        t = group_place(deck, k)
      end if
    end function first_place
  end subroutine cut_deck

  !> A text cut at its newlines into lines, a line longer than max_line cut
  !> further (`cut_line`); `origin`: the line of the text each comes from.
  !> (stat: nonzero if memory ran out; the lines are then those read.)
  function text_lines(text, origin, stat) result(lines)
    character(len=*), intent(in) :: text
    integer, allocatable, intent(out), optional :: origin(:)
    integer, intent(out), optional :: stat
    character(len=max_line), allocatable :: lines(:)
    integer, allocatable :: from(:)
    integer :: i, j, n, nline, st
    logical :: broken
    n = 0
    nline = 0
    allocate(lines(16), from(16), stat=st)
    i = 1
    do while (i <= len(text) .and. st == 0)
      j = index(text(i:), new_line('a'))
      if (j == 0) j = len(text) - i + 2
      nline = nline + 1
      call append_line(text(i:i + j - 2), nline, lines, from, n, broken, st)
      i = i + j
    end do
    if (present(stat)) stat = st
    lines = lines(1:n)
    if (present(origin)) origin = from(1:n)
  end function text_lines

  !> Appends `line` (line `number` of a deck) to lines(1:n) and its number
  !> to origin(1:n), cut into pieces of at most max_line characters
  !> (`cut_line`; `broken`: a cut had to split a string or a word); both
  !> arrays double when full (stat: nonzero if memory ran out).
  subroutine append_line(line, number, lines, origin, n, broken, stat)
    character(len=*), intent(in) :: line
    integer, intent(in) :: number
    character(len=max_line), allocatable, intent(inout) :: lines(:)
    integer, allocatable, intent(inout) :: origin(:)
    integer, intent(inout) :: n
    logical, intent(out) :: broken
    integer, intent(out) :: stat
    character(len=max_line), allocatable :: tmp(:)
    integer, allocatable :: itmp(:)
    integer :: from, to
    logical :: forced
    from = 1
    broken = .false.
    stat = 0
    do
      call cut_line(line, from, to, forced)
      broken = broken .or. forced
      if (n == size(lines)) then
        allocate(tmp(2*n), itmp(2*n), stat=stat)
        if (stat /= 0) return
        tmp(1:n) = lines(1:n)
        itmp(1:n) = origin(1:n)
        call move_alloc(tmp, lines)
        call move_alloc(itmp, origin)
      end if
      n = n + 1
      origin(n) = number
      if (from > 1 .and. in_comment(line(1:from - 1))) then
        lines(n) = '!'//line(from:to)
      else
        lines(n) = line(from:to)
      end if
      if (to >= len_trim(line)) exit
      from = to + 1
    end do
  end subroutine append_line

  !> The piece line(from:to) of a line that fits a deck line of max_line
  !> characters (with room for a '!' that continues a comment): cut after
  !> the last blank or comma outside quotes before the limit, where a
  !> namelist read takes the line break as the same separator (or anywhere
  !> in a comment); at the limit if there is none (`forced`: a quoted
  !> string or a word longer than a line, which cannot be read back whole).
  subroutine cut_line(line, from, to, forced)
    character(len=*), intent(in) :: line
    integer, intent(in) :: from
    integer, intent(out) :: to
    logical, intent(out) :: forced
    character :: q
    logical :: comment
    integer :: j, last
    last = len_trim(line)
    forced = .false.
    if (last - from + 1 <= max_line - 1) then
      to = max(last, from - 1)
      return
    end if
    comment = in_comment(line(1:from - 1))
    q = ' '
    to = 0
    do j = from, from + max_line - 2
      if (comment) then
        to = j
      else if (q /= ' ') then
        if (line(j:j) == q) q = ' '
      else if (line(j:j) == "'" .or. line(j:j) == '"') then
        q = line(j:j)
      else if (line(j:j) == '!') then
        comment = .true.
        to = j - 1
      else if (line(j:j) == ' ' .or. line(j:j) == ',') then
        to = j
      end if
    end do
    forced = to < from
    if (forced) to = from + max_line - 2
  end subroutine cut_line

  !> Whether the end of `text` (the start of a line) lies in a `!` comment.
  pure logical function in_comment(text)
    character(len=*), intent(in) :: text
    character :: q
    integer :: j
    q = ' '
    in_comment = .false.
    do j = 1, len(text)
      if (q /= ' ') then
        if (text(j:j) == q) q = ' '
      else if (text(j:j) == "'" .or. text(j:j) == '"') then
        q = text(j:j)
      else if (text(j:j) == '!') then
        in_comment = .true.
        return
      end if
    end do
  end function in_comment

  !> Number of groups called `name` in the deck.
  integer function deck_count(deck, name)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer :: u
    deck_count = 0
    u = name_slot(deck, name)
    if (u > 0) deck_count = deck%first(u + 1) - deck%first(u)
  end function deck_count

  !> The text of the k-th group called `name` (default the first); an empty
  !> array if there is none.
  function deck_text(deck, name, k) result(text)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: k
    character(len=max_line), allocatable :: text(:)
    integer :: i
    i = group_index(deck, name, k)
    if (i > 0) then
      text = deck%groups(i)%text
    else
      text = [character(len=max_line) ::]
    end if
  end function deck_text

  !> The line where the k-th group called `name` (default the first) starts;
  !> 0 if there is none.
  integer function deck_line(deck, name, k)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: k
    integer :: i
    deck_line = 0
    i = group_index(deck, name, k)
    if (i > 0) deck_line = deck%groups(i)%line
  end function deck_line

  !> "file:line" where the k-th group called `name` (default the first)
  !> starts: the deck or the included file it is written in; '' if there
  !> is none.
  function deck_where(deck, name, k) result(place)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: k
    character(len=:), allocatable :: place
    integer :: i
    place = ''
    i = group_index(deck, name, k)
    if (i > 0) place = group_place(deck, i)
  end function deck_where

  !> "file:line" of deck%groups(i).
  function group_place(deck, i) result(place)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: i
    character(len=:), allocatable :: place
    place = trim(deck%files(deck%groups(i)%file))//':'//itoa(deck%groups(i)%line)
  end function group_place

  !> Index in deck%groups of the k-th group called `name` (default the
  !> first); 0 if there is none. (Through the index by name: the readers of
  !> repeated groups ask for each in turn, and a scan of the deck per
  !> group made reading a deck quadratic in its number of groups.)
  integer function group_index(deck, name, k) result(i)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: k
    integer :: want, u
    want = 1
    if (present(k)) want = k
    i = 0
    u = name_slot(deck, name)
    if (u == 0) return
    if (want < 1 .or. want > deck%first(u + 1) - deck%first(u)) return
    i = deck%members(deck%first(u) + want - 1)
  end function group_index

  !> Position of `name` in the deck's list of distinct group names; 0 if no
  !> group has it (or the deck has not been indexed: no groups).
  integer function name_slot(deck, name) result(u)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    u = 0
    if (.not. allocated(deck%names)) return
    do u = 1, size(deck%names)
      if (deck%names(u) == name) return
    end do
    u = 0
  end function name_slot

  !> Builds the deck's index by name (a counting sort of the groups by the
  !> order in which their names first appear: linear in the number of groups
  !> times the number of distinct names, which is small).
  subroutine index_groups(deck)
    type(deck_t), intent(inout) :: deck
    integer, allocatable :: slot(:), fill(:)
    integer :: i, u, nu, ng, stat
    character(len=32), allocatable :: names(:)
    character(len=200) :: msg
    ng = size(deck%groups)
    allocate(slot(ng), names(max(ng, 1)), stat=stat, errmsg=msg)
    if (stat /= 0) return   ! (then every group reads as absent; the problems say what is missing)
    nu = 0
    do i = 1, ng
      do u = nu, 1, -1
        if (names(u) == deck%groups(i)%name) exit
      end do
      if (u == 0) then
        nu = nu + 1
        names(nu) = deck%groups(i)%name
        u = nu
      end if
      slot(i) = u
    end do
    allocate(deck%names(nu), deck%first(nu + 1), deck%members(ng), fill(nu), stat=stat, errmsg=msg)
    if (stat /= 0) then
      if (allocated(deck%names)) deallocate(deck%names)
      return
    end if
    deck%names = names(1:nu)
    fill = 0
    do i = 1, ng
      fill(slot(i)) = fill(slot(i)) + 1
    end do
    deck%first(1) = 1
    do u = 1, nu
      deck%first(u + 1) = deck%first(u) + fill(u)
    end do
    fill = deck%first(1:nu)
    do i = 1, ng
      deck%members(fill(slot(i))) = i
      fill(slot(i)) = fill(slot(i)) + 1
    end do
  end subroutine index_groups

  !> Cuts the lines into groups (see the module header), scanning the text
  !> as a stream: a group may start anywhere outside another group (several
  !> on one line) and ends at its `/`. Text outside groups that is not blank
  !> or a `!` comment is a problem (a group that lost its `&`, a stray
  !> assignment): gfortran would skip it silently.
  subroutine split_groups(lines, files, groups, problems, origin, ofile)
    character(len=*), intent(in) :: lines(:), files(:)
    type(deck_group_t), allocatable, intent(inout) :: groups(:)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer, intent(in) :: origin(:), ofile(:)
    character(len=:), allocatable :: path
    type(deck_group_t) :: grp
    type(deck_group_t), allocatable :: found(:)
    character(len=max_line), allocatable :: pieces(:)
    character(len=max_line) :: line
    character :: q
    integer :: i, j, k, from, ngroup, npiece, last
    logical :: in_group
    character(len=200) :: msg

    in_group = .false.
    q = ' '
    ! The groups go to an array as large as the number of `&` in the deck
    ! (every group starts with one), the pieces of the current group to one
    ! that doubles when full: appending one at a time (`groups = [groups,
    ! grp]` copies every group, text and all) made the cut quadratic in the
    ! number of groups.
    path = trim(files(1))
    ngroup = 0
    npiece = 0
    k = 0
    do i = 1, size(lines)
      k = k + count_char(lines(i), '&')
    end do
    allocate(found(k), pieces(16), stat=k, errmsg=msg)
    if (k /= 0) then
      call problem_add(problems, trim(path)//': cannot cut the deck into groups: '//trim(msg))
      return
    end if
    do i = 1, size(lines)
      line = lines(i)
      last = len_trim(line)
      from = 1
      j = 0
      scan: do while (j < last)
        j = j + 1
        if (q /= ' ') then
          if (line(j:j) == q) q = ' '
        else if (line(j:j) == '!') then
          exit scan
        else if (in_group .and. (line(j:j) == "'" .or. line(j:j) == '"')) then
          q = line(j:j)
        else if (line(j:j) == '&' .and. is_name_start(line, j + 1)) then
          ! a group starts (and ends one that lacks its `/`)
          if (in_group) call finish(line(from:j - 1))
          in_group = .true.
          grp%name = name_at(line, j + 1)
          grp%line = origin(i)
          grp%file = ofile(i)
          from = j
          j = j + len_trim(grp%name)
        else if (in_group .and. line(j:j) == '/') then
          call finish(line(from:j))
          in_group = .false.
        else if (.not. in_group .and. line(j:j) /= ' ') then
          k = index(line(j:), '!')
          if (k == 0) k = len_trim(line(j:)) + 1
          call problem_add(problems, trim(files(ofile(i)))//':'//itoa(origin(i))// &
                           ': text outside any group: '''// &
                           trim(line(j:j + k - 2))//''' (a group starts with &name and ends with /)')
          exit scan
        end if
      end do scan
      if (in_group) call add_piece(line(from:))
    end do
    if (in_group) call finish('')
    ! the groups, exactly as many as were found
    if (allocated(groups)) deallocate(groups)
    allocate(groups(ngroup), stat=k, errmsg=msg)
    if (k /= 0) then
      call problem_add(problems, trim(path)//': cannot hold the deck''s groups: '//trim(msg))
      allocate(groups(0), stat=k, errmsg=msg)
      return
    end if
    do k = 1, ngroup
      call move_group(found(k), groups(k))
    end do

  contains

    !> Appends a line to the current group's pieces.
    subroutine add_piece(piece)
      character(len=*), intent(in) :: piece
      character(len=max_line), allocatable :: tmp(:)
      integer :: stat
      if (npiece == size(pieces)) then
        allocate(tmp(2*size(pieces)), stat=stat, errmsg=msg)
        if (stat /= 0) then
          call problem_add(problems, trim(path)//': cannot hold a group of '//itoa(npiece)//' lines: '//trim(msg))
          return
        end if
        tmp(1:npiece) = pieces(1:npiece)
        call move_alloc(tmp, pieces)
      end if
      npiece = npiece + 1
      pieces(npiece) = piece
    end subroutine add_piece

    !> Ends the current group with `last` as its last piece.
    subroutine finish(last)
      character(len=*), intent(in) :: last
      integer :: stat, m, width
      if (len_trim(last) > 0) call add_piece(last)
      width = 1
      do m = 1, npiece
        width = max(width, len_trim(pieces(m)))
      end do
      allocate(character(len=width) :: grp%text(npiece), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call problem_add(problems, trim(path)//': cannot hold a group of '//itoa(npiece)//' lines: '//trim(msg))
        return
      end if
      do m = 1, npiece
        grp%text(m) = pieces(m)(1:width)
      end do
      npiece = 0
      ngroup = ngroup + 1
      call move_group(grp, found(ngroup))
    end subroutine finish
  end subroutine split_groups

  !> Number of times character c occurs in line.
  pure integer function count_char(line, c) result(n)
    character(len=*), intent(in) :: line
    character, intent(in) :: c
    integer :: i, j
    n = 0
    i = 1
    do
      j = index(line(i:), c)
      if (j == 0) exit
      n = n + 1
      i = i + j
    end do
  end function count_char

  !> Moves a group (its text without a copy) from `a` to `b`.
  pure subroutine move_group(a, b)
    type(deck_group_t), intent(inout) :: a, b
    b%name = a%name
    b%line = a%line
    b%file = a%file
    if (allocated(b%text)) deallocate(b%text)
    if (allocated(a%text)) call move_alloc(a%text, b%text)
  end subroutine move_group

  !> True if a group name starts at position j of line.
  pure logical function is_name_start(line, j)
    character(len=*), intent(in) :: line
    integer, intent(in) :: j
    is_name_start = .false.
    if (j > len(line)) return
    is_name_start = scan(lower(line(j:j)), 'abcdefghijklmnopqrstuvwxyz') > 0
  end function is_name_start

  !> The group name (lower case) that starts at position j of line.
  pure function name_at(line, j) result(name)
    character(len=*), intent(in) :: line
    integer, intent(in) :: j
    character(len=32) :: name
    integer :: k
    k = j
    do while (k <= len(line))
      if (verify(lower(line(k:k)), 'abcdefghijklmnopqrstuvwxyz0123456789_') /= 0) exit
      k = k + 1
    end do
    name = lower(line(j:k - 1))
  end function name_at

  !> Checks the values in a group's text without converting them: a NaN or
  !> infinity, or a number of magnitude 1e30 or more (except the largest
  !> double, which stands for "none" in echoed decks), is a problem; such a
  !> value would reach comparisons and arithmetic that trap or overflow.
  !> Returns true if the group is clean.
  logical function values_ok(grp, place, problems) result(ok)
    type(deck_group_t), intent(in) :: grp
    character(len=*), intent(in) :: place   !< "file:line" of the group
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=max_line) :: line
    character :: q
    integer :: i, j, k, n, last
    ok = .true.
    q = ' '
    do i = 1, size(grp%text)
      line = grp%text(i)
      last = len_trim(line)
      j = 0
      do while (j < last)
        j = j + 1
        if (q /= ' ') then
          if (line(j:j) == q) q = ' '
          cycle
        end if
        if (line(j:j) == "'" .or. line(j:j) == '"') then
          q = line(j:j)
          cycle
        end if
        if (line(j:j) == '!') exit
        if (scan(line(j:j), ' ,=*()/&') > 0) cycle
        k = j
        do while (k < last)
          if (scan(line(k + 1:k + 1), ' ,=*()/&!') > 0) exit
          k = k + 1
        end do
        n = k
        ! the next non-blank after the token: '=' or '(' makes it a name
        do while (n < last)
          if (line(n + 1:n + 1) /= ' ') exit
          n = n + 1
        end do
        if (n < last) then
          if (scan(line(n + 1:n + 1), '=(') > 0) then
            j = k
            cycle
          end if
        end if
        if (.not. number_ok(lower(line(j:k)))) then
          call problem_add(problems, place//': &'//trim(grp%name)//': the value '''// &
                           line(j:k)//''' is not allowed (NaN, infinity and magnitudes of 1e30 or more are refused)')
          ok = .false.
        end if
        j = k
      end do
    end do
  end function values_ok

  !> Opens the scratch unit the packages write their resolved groups to.
  subroutine echo_open(unit, problems)
    integer, intent(out) :: unit
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer :: ios
    character(len=max_line) :: msg
    open(newunit=unit, status='scratch', action='readwrite', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      unit = no_echo
      call problem_add(problems, 'cannot open a scratch file for the deck echo: '//trim(msg))
    end if
  end subroutine echo_open

  !> The resolved deck written to the echo unit, as one text, and closes it.
  !> The lines are appended to a buffer that doubles when full (a deck of
  !> 40,000 regions echoes 600,000 lines: held as lines of max_line
  !> characters they took 600 MB, and appending to the text line by line
  !> copied it once per line).
  function echo_text(unit) result(text)
    integer, intent(in) :: unit
    character(len=:), allocatable :: text
    character(len=:), allocatable :: buf, tmp
    character(len=max_line) :: line
    integer :: ios, n, m
    text = ''
    if (unit == no_echo) return
    rewind(unit)
    buf = repeat(' ', 4096)
    n = 0
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      line = squeeze_quoted(trim(line))
      m = len_trim(line)
      if (n + m + 1 > len(buf)) then
        tmp = repeat(' ', max(2*len(buf), n + m + 1))
        tmp(1:n) = buf(1:n)
        call move_alloc(tmp, buf)
      end if
      buf(n + 1:n + m + 1) = line(1:m)//new_line('a')
      n = n + m + 1
    end do
    close(unit)
    text = buf(1:n)
  end function echo_text

  !> Drops the blanks that list-directed namelist output pads inside quoted
  !> strings ("out/sedov3d      " becomes "out/sedov3d").
  pure function squeeze_quoted(line) result(t)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: t
    character(len=len(line)) :: buf
    integer :: i, n
    logical :: inq
    inq = .false.
    n = 0
    buf = ''
    do i = 1, len(line)
      if (line(i:i) == '"') then
        if (inq) n = len_trim(buf(1:n))
        inq = .not. inq
      end if
      n = n + 1
      buf(n:n) = line(i:i)
    end do
    t = buf(1:n)
  end function squeeze_quoted

  !> File name of the deck without directory and extension.
  pure function deck_stem(path) result(stem)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: stem
    integer :: i, j
    i = index(path, '/', back=.true.)
    stem = path(i + 1:)
    j = index(stem, '.', back=.true.)
    if (j > 1) stem = stem(1:j - 1)
  end function deck_stem
end module io_deck
