!> The deck file: finds its namelist groups and hands each package the text
!> of its group(s). It knows no group's variables; each package's config
!> module reads, validates and echoes its own group (`base_config`).
!>
!> A group starts at a line whose first non-blank character is `&` and ends
!> at the first `/` outside quotes and `!` comments (or where the next group
!> starts, so a missing `/` is reported for the group that lacks it).
module io_deck
  use base_config, only: max_line, no_echo, problem_add
  use base_strings, only: itoa
  use io_files, only: io_is_dir
  implicit none
  private
  public :: deck_t, deck_group_t, deck_read, deck_from_lines, text_lines, deck_count, deck_text, deck_line, deck_stem, &
            echo_open, echo_text

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
    if (io_is_dir(path)) then
      call problem_add(problems, ''''//trim(path)//''' is a directory, not a deck file')
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
    call deck_from_lines(lines, path, known, repeatable, deck, problems)
  end subroutine deck_read

  !> The groups of a deck given as its lines (`path` names it in messages).
  !> Only the groups in `repeatable` may appear more than once. Tabs count
  !> as blanks and a UTF-8 byte-order mark is skipped.
  subroutine deck_from_lines(lines, path, known, repeatable, deck, problems)
    character(len=*), intent(in) :: lines(:), path, known(:), repeatable(:)
    type(deck_t), intent(out) :: deck
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=max_line), allocatable :: clean(:)
    character(len=:), allocatable :: valid
    character(len=*), parameter :: bom = char(239)//char(187)//char(191)
    integer :: i, k

    deck%path = path
    deck%groups = [deck_group_t ::]
    clean = lines
    do i = 1, size(clean)
      do k = 1, len_trim(clean(i))
        if (clean(i)(k:k) == achar(9)) clean(i)(k:k) = ' '
      end do
    end do
    if (size(clean) > 0) then
      if (clean(1)(1:3) == bom) clean(1) = clean(1)(4:)
    end if
    call split_groups(clean, path, deck%groups, problems)
    valid = ''
    do k = 1, size(known)
      valid = valid//merge(', ', '  ', k > 1)//'&'//trim(known(k))
    end do
    valid = valid(3:)
    do i = 1, size(deck%groups)
      if (any(known == deck%groups(i)%name)) cycle
      call problem_add(problems, trim(path)//':'//itoa(deck%groups(i)%line)//': group &'// &
                       trim(deck%groups(i)%name)//' is not known; valid: '//valid)
    end do
    do i = 1, size(deck%groups)
      if (.not. values_ok(deck%groups(i), path, problems)) deck%unsafe = .true.
    end do
    do i = 1, size(deck%groups)
      associate (gi => deck%groups(i))
        if (any(repeatable == gi%name)) cycle
        do k = 1, i - 1
          if (deck%groups(k)%name /= gi%name) cycle
          call problem_add(problems, trim(path)//':'//itoa(gi%line)//': a second &'//trim(gi%name)// &
                           ' group (the first is at line '//itoa(deck%groups(k)%line)//'); only &material, '// &
                           '&region and &source may repeat')
          exit
        end do
      end associate
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

  !> Index in deck%groups of the k-th group called `name` (default the
  !> first); 0 if there is none.
  integer function group_index(deck, name, k) result(i)
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: k
    integer :: seen, want
    want = 1
    if (present(k)) want = k
    seen = 0
    do i = 1, size(deck%groups)
      if (deck%groups(i)%name /= name) cycle
      seen = seen + 1
      if (seen == want) return
    end do
    i = 0
  end function group_index

  !> Cuts the lines into groups (see the module header), scanning the text
  !> as a stream: a group may start anywhere outside another group (several
  !> on one line) and ends at its `/`. Text outside groups that is not blank
  !> or a `!` comment is a problem (a group that lost its `&`, a stray
  !> assignment): gfortran would skip it silently.
  subroutine split_groups(lines, path, groups, problems)
    character(len=*), intent(in) :: lines(:), path
    type(deck_group_t), allocatable, intent(inout) :: groups(:)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    type(deck_group_t) :: grp
    character(len=max_line), allocatable :: pieces(:)
    character(len=max_line) :: line
    character :: q
    integer :: i, j, k, from
    logical :: in_group

    in_group = .false.
    q = ' '
    ! (allocated, not assigned an empty constructor: gfortran -O3 then warns
    ! of the descriptor of an unallocated array)
    allocate(pieces(0), stat=k)
    do i = 1, size(lines)
      line = lines(i)
      from = 1
      j = 0
      scan: do while (j < len_trim(line))
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
          grp%line = i
          from = j
          j = j + len_trim(grp%name)
        else if (in_group .and. line(j:j) == '/') then
          call finish(line(from:j))
          in_group = .false.
        else if (.not. in_group .and. line(j:j) /= ' ') then
          k = index(line(j:), '!')
          if (k == 0) k = len_trim(line(j:)) + 1
          call problem_add(problems, trim(path)//':'//itoa(i)//': text outside any group: '''// &
                           trim(line(j:j + k - 2))//''' (a group starts with &name and ends with /)')
          exit scan
        end if
      end do scan
      if (in_group) then
        line = line(from:)
        pieces = [pieces, line]
      end if
    end do
    if (in_group) call finish('')

  contains

    !> Ends the current group with `last` as its last piece.
    subroutine finish(last)
      character(len=*), intent(in) :: last
      character(len=max_line) :: piece
      piece = last
      if (len_trim(last) > 0) pieces = [pieces, piece]
      grp%text = pieces
      groups = [groups, grp]
      pieces = [character(len=max_line) ::]
    end subroutine finish
  end subroutine split_groups

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
  logical function values_ok(grp, path, problems) result(ok)
    type(deck_group_t), intent(in) :: grp
    character(len=*), intent(in) :: path
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=max_line) :: line
    character :: q
    integer :: i, j, k, n
    ok = .true.
    q = ' '
    do i = 1, size(grp%text)
      line = grp%text(i)
      j = 0
      do while (j < len_trim(line))
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
        do while (k < len_trim(line))
          if (scan(line(k + 1:k + 1), ' ,=*()/&!') > 0) exit
          k = k + 1
        end do
        n = k
        ! the next non-blank after the token: '=' or '(' makes it a name
        do while (n < len_trim(line))
          if (line(n + 1:n + 1) /= ' ') exit
          n = n + 1
        end do
        if (n < len_trim(line)) then
          if (scan(line(n + 1:n + 1), '=(') > 0) then
            j = k
            cycle
          end if
        end if
        if (.not. number_ok(lower(line(j:k)))) then
          call problem_add(problems, trim(path)//':'//itoa(grp%line)//': &'//trim(grp%name)//': the value '''// &
                           line(j:k)//''' is not allowed (NaN, infinity and magnitudes of 1e30 or more are refused)')
          ok = .false.
        end if
        j = k
      end do
    end do
  end function values_ok

  !> False for NaN, Inf, Infinity (any sign and case) and for a real literal
  !> of magnitude >= 1e30 other than the largest double (+-1.7976931348623157e308);
  !> true for anything else (other numbers, logicals, names).
  pure logical function number_ok(tok) result(ok)
    character(len=*), intent(in) :: tok
    character(len=:), allocatable :: t, mant, digits
    integer :: e, p, ios, ndig, lead
    ok = .true.
    if (len(tok) == 0) return
    if (tok(1:1) == '+' .or. tok(1:1) == '-') then
      t = tok(2:)
    else
      t = tok
    end if
    if (t == 'nan' .or. t == 'inf' .or. t == 'infinity' .or. t(1:min(4, len(t))) == 'nan(') then
      ok = .false.
      return
    end if
    if (len(t) == 0) return
    if (verify(t(1:1), '0123456789.') /= 0) return
    if (verify(t, '0123456789.ed+-') /= 0) return
    p = scan(t, 'ed')
    e = 0
    mant = t
    if (p > 0) then
      mant = t(1:p - 1)
      read(t(p + 1:), *, iostat=ios) e
      if (ios /= 0) return
    end if
    ! decimal exponent of the leading digit: digits before the point (less
    ! leading zeros) - 1, or minus the zeros after the point
    digits = mant
    p = index(mant, '.')
    if (p > 0) digits = mant(1:p - 1)//mant(p + 1:)
    lead = verify(digits, '0')
    if (lead == 0) return                        ! zero
    if (p > 0) then
      ndig = p - 1 - (lead - 1)
    else
      ndig = len(digits) - (lead - 1)
    end if
    if (e + ndig - 1 < 30) return
    ok = e + ndig - 1 == 308 .and. digits(lead:min(len(digits), lead + 16)) == '17976931348623157'
  end function number_ok

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
