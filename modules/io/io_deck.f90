!> The deck file: finds its namelist groups and hands each package the text
!> of its group(s). It knows no group's variables; each package's config
!> module reads, validates and echoes its own group (`base_config`).
!>
!> A group starts at a line whose first non-blank character is `&` and ends
!> at the first `/` outside quotes and `!` comments (or where the next group
!> starts, so a missing `/` is reported for the group that lacks it).
module io_deck
  use base_config, only: max_line, no_echo, problem_add
  implicit none
  private
  public :: deck_t, deck_group_t, deck_read, deck_from_lines, text_lines, deck_count, deck_text, deck_stem, echo_open, echo_text

  !> One group of the deck: its name (lower case), first line and text.
  type :: deck_group_t
    character(len=32) :: name = ''
    integer :: line = 0
    character(len=max_line), allocatable :: text(:)
  end type deck_group_t

  !> The groups of a deck file, in file order.
  type :: deck_t
    character(len=:), allocatable :: path
    type(deck_group_t), allocatable :: groups(:)
  end type deck_t

contains

  !> Reads the deck at `path` and finds its groups; a group whose name is not
  !> in `known` is a problem (the list of valid names is given).
  subroutine deck_read(path, known, deck, problems)
    character(len=*), intent(in) :: path, known(:)
    type(deck_t), intent(out) :: deck
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=max_line), allocatable :: lines(:)
    character(len=max_line) :: msg
    integer :: unit, ios
    logical :: exists

    deck%path = path
    deck%groups = [deck_group_t ::]
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call problem_add(problems, 'deck file '''//trim(path)//''' does not exist')
      return
    end if
    open(newunit=unit, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_add(problems, 'cannot open deck '''//trim(path)//''': '//trim(msg))
      return
    end if
    call read_lines(unit, lines, ios, msg)
    close(unit)
    if (ios /= 0) then
      call problem_add(problems, 'cannot read deck '''//trim(path)//''': '//trim(msg))
      return
    end if
    call deck_from_lines(lines, path, known, deck, problems)
  end subroutine deck_read

  !> The groups of a deck given as its lines (`path` names it in messages).
  subroutine deck_from_lines(lines, path, known, deck, problems)
    character(len=*), intent(in) :: lines(:), path, known(:)
    type(deck_t), intent(out) :: deck
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=:), allocatable :: valid
    integer :: i, k

    deck%path = path
    deck%groups = [deck_group_t ::]
    call split_groups(lines, deck%groups)
    valid = ''
    do k = 1, size(known)
      valid = valid//merge(', ', '  ', k > 1)//'&'//trim(known(k))
    end do
    valid = valid(3:)
    do i = 1, size(deck%groups)
      if (any(known == deck%groups(i)%name)) cycle
      call problem_add(problems, trim(path)//': group &'//trim(deck%groups(i)%name)// &
                       ' is not known; valid: '//valid)
    end do
  end subroutine deck_from_lines

  !> A text cut at its newlines into lines.
  function text_lines(text) result(lines)
    character(len=*), intent(in) :: text
    character(len=max_line), allocatable :: lines(:)
    character(len=max_line) :: line
    integer :: i, j
    lines = [character(len=max_line) ::]
    i = 1
    do while (i <= len(text))
      j = index(text(i:), new_line('a'))
      if (j == 0) j = len(text) - i + 2
      line = text(i:i + j - 2)
      lines = [lines, line]
      i = i + j
    end do
  end function text_lines

  !> Number of groups called `name` in the deck.
  integer function deck_count(deck, name)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    deck_count = count(deck%groups%name == name)
  end function deck_count

  !> The text of the k-th group called `name` (default the first); an empty
  !> array if there is none.
  function deck_text(deck, name, k) result(text)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: k
    character(len=max_line), allocatable :: text(:)
    integer :: i, seen, want
    want = 1
    if (present(k)) want = k
    seen = 0
    do i = 1, size(deck%groups)
      if (deck%groups(i)%name /= name) cycle
      seen = seen + 1
      if (seen == want) then
        text = deck%groups(i)%text
        return
      end if
    end do
    text = [character(len=max_line) ::]
  end function deck_text

  !> Cuts the lines into groups (see the module header).
  subroutine split_groups(lines, groups)
    character(len=*), intent(in) :: lines(:)
    type(deck_group_t), allocatable, intent(inout) :: groups(:)
    character(len=:), allocatable :: name
    integer :: i, first
    logical :: closed

    first = 0
    do i = 1, size(lines)
      name = group_at(lines(i))
      if (len(name) > 0) then
        if (first > 0) call append(first, i - 1)
        first = i
      end if
      if (first > 0) then
        ! the line that starts the group: look for `/` after its name
        if (i == first) then
          closed = ends_group(lines(i), index(lines(i), '&') + len(name) + 1)
        else
          closed = ends_group(lines(i), 1)
        end if
        if (closed) then
          call append(first, i)
          first = 0
        end if
      end if
    end do
    if (first > 0) call append(first, size(lines))

  contains

    subroutine append(l0, l1)
      integer, intent(in) :: l0, l1
      type(deck_group_t) :: grp
      grp%name = group_at(lines(l0))
      grp%line = l0
      grp%text = lines(l0:l1)
      groups = [groups, grp]
    end subroutine append
  end subroutine split_groups

  !> True if `line` has a `/` outside quotes and comments at or after `from`.
  pure logical function ends_group(line, from)
    character(len=*), intent(in) :: line
    integer, intent(in) :: from
    character :: q
    integer :: i
    ends_group = .false.
    q = ' '
    do i = max(from, 1), len_trim(line)
      if (q /= ' ') then
        if (line(i:i) == q) q = ' '
      else if (line(i:i) == '''' .or. line(i:i) == '"') then
        q = line(i:i)
      else if (line(i:i) == '!') then
        return
      else if (line(i:i) == '/') then
        ends_group = .true.
        return
      end if
    end do
  end function ends_group

  !> The group name that line starts, lower case, or '' if none.
  pure function group_at(line) result(name)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: name
    character(len=:), allocatable :: s
    integer :: i, j
    s = adjustl(line)
    name = ''
    if (len(s) < 2) return
    if (s(1:1) /= '&') return
    j = 1
    do i = 2, len_trim(s)
      if (scan(s(i:i), ' /!,') > 0) exit
      j = i
    end do
    name = lower(s(2:j))
  end function group_at

  !> Reads all records of an open unit.
  subroutine read_lines(unit, lines, ios, msg)
    integer, intent(in) :: unit
    character(len=max_line), allocatable, intent(out) :: lines(:)
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    character(len=max_line) :: buf
    character(len=max_line), allocatable :: tmp(:)
    integer :: n

    allocate(lines(64), stat=ios, errmsg=msg)
    if (ios /= 0) return
    n = 0
    rewind(unit)
    do
      read(unit, '(a)', iostat=ios, iomsg=msg) buf
      if (ios /= 0) exit
      n = n + 1
      if (n > size(lines)) then
        allocate(tmp(2*size(lines)), stat=ios, errmsg=msg)
        if (ios /= 0) return
        tmp(1:n - 1) = lines(1:n - 1)
        call move_alloc(tmp, lines)
      end if
      lines(n) = buf
    end do
    if (ios < 0) ios = 0
    lines = lines(1:n)
  end subroutine read_lines

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
  function echo_text(unit) result(text)
    integer, intent(in) :: unit
    character(len=:), allocatable :: text
    character(len=max_line), allocatable :: lines(:)
    character(len=max_line) :: msg
    integer :: ios, i
    text = ''
    if (unit == no_echo) return
    rewind(unit)
    call read_lines(unit, lines, ios, msg)
    close(unit)
    do i = 1, size(lines)
      text = text//squeeze_quoted(trim(lines(i)))//new_line('a')
    end do
  end function echo_text

  !> Drops the blanks that list-directed namelist output pads inside quoted
  !> strings ("out/sedov3d      " becomes "out/sedov3d").
  pure function squeeze_quoted(line) result(t)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: t
    integer :: i
    logical :: inq
    t = ''
    inq = .false.
    do i = 1, len(line)
      if (line(i:i) == '"') then
        if (inq) t = trim(t)
        inq = .not. inq
      end if
      t = t//line(i:i)
    end do
  end function squeeze_quoted

  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    t = s
    do i = 1, len(s)
      if (s(i:i) >= 'A' .and. s(i:i) <= 'Z') t(i:i) = achar(iachar(s(i:i)) + 32)
    end do
  end function lower

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
