!> Decks that compose: the pre-pass that turns a deck file into the plain
!> namelist lines the groups are cut from (`io_deck`), each line with the
!> file and line it comes from (for messages).
!>
!> - `&include file = 'materials/tnt.nml' /`, on a line of its own, puts the
!>   lines of that file there (a relative name is read from the folder of
!>   the file that includes it). Includes may nest (16 deep); a file that
!>   includes itself, directly or not, and a missing file are refused.
!> - `&parameters r = 0.5, e0 = 4.184*0.023 /` defines named numbers, each
!>   an expression (`io_deck_expr`) of numbers and parameters defined
!>   before it. The group is consumed here: the packages never see it.
!> - `${expression}` anywhere in a line, outside quoted strings and `!`
!>   comments, is replaced by the expression's value, written so that it
!>   reads back to the very same double (`expr_number_text`).
!>
!> Every problem is one line "file:line: what is wrong".
module io_deck_expand
  use base_kinds, only: wp
  use base_config, only: max_line, problem_add
  use base_strings, only: itoa, lower
  use io_deck_expr, only: expr_parse, expr_eval, expr_number_text
  use io_files, only: io_is_dir
  implicit none
  private
  public :: source_line_t, deck_source_t, deck_expand_file, deck_expand_lines, deck_source_notes, dir_of

  !> Deepest nesting of includes (a cycle written with different spellings
  !> of one file's name ends here).
  integer, parameter :: max_depth = 16
  !> Longest parameter name.
  integer, parameter :: name_len = 32

  !> One line of the expanded deck and where it comes from.
  type :: source_line_t
    character(len=:), allocatable :: text
    integer :: file = 1     !< index in deck_source_t%files
    integer :: line = 0     !< line number in that file
  end type source_line_t

  !> The expanded deck: its lines, the files they come from (1: the deck;
  !> then each included file, in the order of inclusion) and the
  !> parameters defined, with where.
  type :: deck_source_t
    type(source_line_t), allocatable :: lines(:)
    integer :: n = 0
    character(len=max_line), allocatable :: files(:)
    character(len=name_len), allocatable :: names(:)
    real(wp), allocatable :: values(:)
    character(len=max_line), allocatable :: defined(:)   !< "file:line" of each parameter
  end type deck_source_t

contains

  !> Expands the deck file at `path` (which exists and is not a directory).
  subroutine deck_expand_file(path, src, problems)
    character(len=*), intent(in) :: path
    type(deck_source_t), intent(out) :: src
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=max_line) :: stack(1)
    call source_init(src, path)
    stack(1) = normal_path(path)
    call expand_file(path, 1, stack, src, problems)
  end subroutine deck_expand_file

  !> Expands a deck given as lines (`path` names it; includes are read
  !> from its folder); origin(:): each line's number (default 1, 2, ...).
  subroutine deck_expand_lines(lines, path, src, problems, origin)
    character(len=*), intent(in) :: lines(:), path
    type(deck_source_t), intent(out) :: src
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer, intent(in), optional :: origin(:)
    type(source_line_t), allocatable :: raw(:)
    character(len=max_line) :: stack(1)
    integer :: i
    call source_init(src, path)
    allocate(raw(size(lines)), stat=i)
    if (i /= 0) then
      call problem_add(problems, trim(path)//': out of memory for the deck''s lines')
      return
    end if
    do i = 1, size(lines)
      raw(i)%text = trim(lines(i))
      raw(i)%line = i
      if (present(origin)) raw(i)%line = origin(i)
    end do
    stack(1) = normal_path(path)
    call expand_raw(raw, path, 1, stack, src, problems)
  end subroutine deck_expand_lines

  !> What the expansion did, as deck comments for the echo: the files
  !> included and each parameter's value ('' if neither).
  function deck_source_notes(src) result(text)
    type(deck_source_t), intent(in) :: src
    character(len=:), allocatable :: text
    integer :: k
    text = ''
    do k = 2, size(src%files)
      text = text//'! included: '//trim(src%files(k))//new_line('a')
    end do
    do k = 1, size(src%names)
      text = text//'! parameter '//trim(src%names(k))//' = '//expr_number_text(src%values(k))//'   ('// &
             trim(src%defined(k))//')'//new_line('a')
    end do
  end function deck_source_notes

  subroutine source_init(src, path)
    type(deck_source_t), intent(out) :: src
    character(len=*), intent(in) :: path
    character(len=max_line) :: first
    allocate(src%lines(64), stat=src%n)
    src%n = 0   ! (an allocation that fails shows as the first add_line's)
    first = path
    src%files = [first]
    src%names = [character(len=name_len) ::]
    src%values = [real(wp) ::]
    src%defined = [character(len=max_line) ::]
  end subroutine source_init

  !> Reads the file `path` (file number `fidx`) and expands its lines;
  !> stack: the files being included, outermost first.
  recursive subroutine expand_file(path, fidx, stack, src, problems)
    character(len=*), intent(in) :: path, stack(:)
    integer, intent(in) :: fidx
    type(deck_source_t), intent(inout) :: src
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    type(source_line_t), allocatable :: raw(:)
    character(len=max_line) :: msg
    integer :: ios
    call read_raw(path, raw, ios, msg)
    if (ios /= 0) then
      call problem_add(problems, 'cannot read deck '''//trim(path)//''': '//trim(msg))
      return
    end if
    call expand_raw(raw, path, fidx, stack, src, problems)
  end subroutine expand_file

  !> Expands the lines `raw` of the file `path` (file number `fidx`).
  recursive subroutine expand_raw(raw, path, fidx, stack, src, problems)
    type(source_line_t), intent(inout) :: raw(:)
    character(len=*), intent(in) :: path, stack(:)
    integer, intent(in) :: fidx
    type(deck_source_t), intent(inout) :: src
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), parameter :: bom = char(239)//char(187)//char(191)
    character(len=:), allocatable :: first, here
    integer :: i, k
    do i = 1, size(raw)
      do k = 1, len(raw(i)%text)
        if (raw(i)%text(k:k) == achar(9)) raw(i)%text(k:k) = ' '
      end do
    end do
    if (size(raw) > 0) then
      if (len(raw(1)%text) >= 3) then
        if (raw(1)%text(1:3) == bom) raw(1)%text = raw(1)%text(4:)
      end if
    end if
    here = ''
    first = ''
    i = 1
    do while (i <= size(raw))
      here = trim(path)//':'//itoa(raw(i)%line)//': '
      first = lower(adjustl(raw(i)%text))
      if (starts_group(first, 'include')) then
        call include(raw(i)%text, here, path, stack, src, problems)
      else if (starts_group(first, 'parameters')) then
        call parameters(raw, i, path, src, problems)
      else
        k = misplaced(raw(i)%text)
        if (k > 0) then
          call problem_add(problems, here//'&'//trim(merge('include   ', 'parameters', k == 1))// &
                           ' must start its line (it is not a group the packages read)')
        else
          call add_line(src, substitute(raw(i)%text, here, src, problems), fidx, raw(i)%line, k)
          if (k /= 0) then
            call problem_add(problems, here//'out of memory for the deck''s lines')
            return
          end if
        end if
      end if
      i = i + 1
    end do
  end subroutine expand_raw

  !> `&include file = 'name' /` (then blanks or a comment): the named file's
  !> lines, expanded, in place of this one.
  recursive subroutine include(line, here, path, stack, src, problems)
    character(len=*), intent(in) :: line, here, path, stack(:)
    type(deck_source_t), intent(inout) :: src
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), parameter :: form = ': write it as  &include file = ''name.nml'' /  on a line of its own'
    character(len=:), allocatable :: name, full, chain
    character(len=max_line) :: norm
    character(len=max_line), allocatable :: deeper(:)
    integer :: j, k
    logical :: exists
    j = index(lower(line), '&include') + len('&include')
    call skip(line, j)
    if (lower(line(j:min(len(line), j + 3))) /= 'file') then
      call problem_add(problems, here//'&include'//form)
      return
    end if
    j = j + 4
    call skip(line, j)
    if (.not. at(line, j, '=')) then
      call problem_add(problems, here//'&include'//form)
      return
    end if
    j = j + 1
    call skip(line, j)
    if (.not. (at(line, j, '''') .or. at(line, j, '"'))) then
      call problem_add(problems, here//'&include'//form)
      return
    end if
    k = index(line(j + 1:), line(j:j))
    if (k == 0) then
      call problem_add(problems, here//'&include: the file name''s quote is not closed'//form)
      return
    end if
    name = line(j + 1:j + k - 1)
    j = j + k + 1
    call skip(line, j)
    if (.not. at(line, j, '/')) then
      call problem_add(problems, here//'&include'//form)
      return
    end if
    j = j + 1
    call skip(line, j)
    if (j <= len(line)) then
      if (line(j:j) /= '!') then
        call problem_add(problems, here//'&include: text after its ''/'': '''//line(j:)//''''//form)
        return
      end if
    end if
    if (len_trim(name) == 0) then
      call problem_add(problems, here//'&include: the file name is empty')
      return
    end if
    if (name(1:1) == '/') then
      full = name
    else
      full = dir_of(path)//name
    end if
    norm = normal_path(full)
    do k = 1, size(stack)
      if (stack(k) /= norm) cycle
      chain = ''
      do j = k, size(stack)
        chain = chain//trim(stack(j))//' -> '
      end do
      call problem_add(problems, here//'&include: '''//full//''' includes itself ('//chain//full//')')
      return
    end do
    if (size(stack) >= max_depth) then
      call problem_add(problems, here//'&include: includes nested more than '//itoa(max_depth)//' deep (a cycle?)')
      return
    end if
    inquire(file=full, exist=exists)
    if (.not. exists) then
      call problem_add(problems, here//'&include: file '''//full//''' does not exist')
      return
    end if
    if (io_is_dir(full)) then
      call problem_add(problems, here//'&include: '''//full//''' is a directory, not a deck file')
      return
    end if
    norm = full
    src%files = [src%files, norm]
    norm = normal_path(full)
    allocate(deeper(size(stack) + 1), stat=k)
    if (k /= 0) return
    deeper(1:size(stack)) = stack
    deeper(size(stack) + 1) = norm
    call expand_file(full, size(src%files), deeper, src, problems)
  end subroutine include

  !> A `&parameters` group starting at raw(i): its definitions, in order,
  !> each `name = expression`, separated by commas or blanks (or line
  !> breaks), up to the `/` that ends the group (one not followed by an
  !> operand: `1/3` divides). On return i is the group's last line.
  subroutine parameters(raw, i, path, src, problems)
    type(source_line_t), intent(in) :: raw(:)
    integer, intent(inout) :: i
    character(len=*), intent(in) :: path
    type(deck_source_t), intent(inout) :: src
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=:), allocatable :: text, msg
    integer, allocatable :: starts(:)
    integer :: m, status, pos, k, j
    integer, parameter :: done = 0, more = 1, bad = 2
    text = ''
    starts = [integer ::]
    m = i
    do
      starts = [starts, len(text) + 1]
      if (m == i) then
        j = index(lower(raw(m)%text), '&parameters') + len('&parameters')
        text = text//' '//braces(code_part(raw(m)%text(j:)))
      else
        text = text//' '//braces(code_part(raw(m)%text))
      end if
      call try_group(text, status, pos, msg)
      if (status == more .and. m < size(raw)) then
        m = m + 1
        cycle
      end if
      exit
    end do
    if (status == more) then
      call problem_add(problems, trim(path)//':'//itoa(raw(i)%line)//': &parameters: '//msg// &
                       ' (the group has no closing ''/'')')
      i = m
    else if (status == bad) then
      ! the line the problem is on
      do k = size(starts), 1, -1
        if (starts(k) <= pos) exit
      end do
      k = i + max(k, 1) - 1
      call problem_add(problems, trim(path)//':'//itoa(raw(k)%line)//': &parameters: '//msg)
      ! go on after the line that ends with a '/' (most likely its end)
      i = k
      do while (i < size(raw))
        if (ends_with_slash(raw(i)%text)) exit
        i = i + 1
      end do
    else
      i = m
    end if

  contains

    !> Parses and evaluates the group's text so far; done: the definitions
    !> are added to src; more: the text ended before the group did; bad:
    !> `msg` says what is wrong at `at`.
    subroutine try_group(text, status, at, msg)
      character(len=*), intent(in) :: text
      integer, intent(out) :: status, at
      character(len=:), allocatable, intent(out) :: msg
      character(len=name_len), allocatable :: names(:)
      real(wp), allocatable :: values(:)
      integer, allocatable :: where(:)
      character(len=:), allocatable :: name
      real(wp) :: v
      character(len=name_len) :: nm
      character(len=max_line) :: def
      integer :: p, q, n0, d, line_k
      logical :: ended
      allocate(names(0), values(0), where(0), stat=p)   ! (assigned below; else gfortran warns of unset bounds)
      names = src%names
      values = src%values
      n0 = size(names)
      msg = ''
      name = ''
      p = 1
      do
        do while (p <= len(text))
          if (text(p:p) /= ' ' .and. text(p:p) /= ',') exit
          p = p + 1
        end do
        at = p
        if (p > len(text)) then
          status = more
          msg = 'the text ends before the group does'
          return
        end if
        if (text(p:p) == '/') then
          q = p + 1
          call skip(text, q)
          if (q <= len(text)) then
            status = bad
            msg = 'text after the closing ''/'': '''//text(q:)//''''
            return
          end if
          exit
        end if
        q = p
        do while (q <= len(text))
          if (scan(lower(text(q:q)), 'abcdefghijklmnopqrstuvwxyz0123456789_') == 0) exit
          q = q + 1
        end do
        name = lower(text(p:q - 1))
        if (len(name) == 0 .or. scan(name(1:1), 'abcdefghijklmnopqrstuvwxyz') == 0) then
          status = bad
          msg = 'expected a parameter name at '''//text(p:)//''''
          return
        end if
        if (len(name) > name_len) then
          status = bad
          msg = 'the name '''//name//''' is longer than '//itoa(name_len)//' characters'
          return
        end if
        call skip(text, q)
        if (q > len(text)) then
          status = more
          msg = 'the text ends before the value of '''//name//''''
          return
        end if
        if (text(q:q) /= '=') then
          status = bad
          msg = 'expected ''='' after '''//name//''' at '''//text(q:)//''''
          return
        end if
        q = q + 1
        call expr_parse(text, q, names, values, v, msg, ended)
        if (len(msg) > 0) then
          status = merge(more, bad, ended)
          msg = name//': '//msg
          return
        end if
        do d = 1, size(names)
          if (names(d) /= name) cycle
          status = bad
          if (d <= n0) then
            msg = name//' is already defined (at '//trim(src%defined(d))//')'
          else
            msg = name//' is defined twice in the group'
          end if
          return
        end do
        nm = name   ! (assigned: gfortran 12 mishandles typed constructors of other lengths)
        names = [names, nm]
        values = [values, v]
        ! the line it is defined on
        do line_k = size(starts), 1, -1
          if (starts(line_k) <= p) exit
        end do
        where = [where, i + max(line_k, 1) - 1]
        p = q
        call skip(text, p)
        if (p > len(text)) then
          status = more
          msg = 'the text ends before the group does'
          return
        end if
        if (scan(text(p:p), ',/') == 0 .and. scan(lower(text(p:p)), 'abcdefghijklmnopqrstuvwxyz') == 0) then
          status = bad
          at = p
          msg = 'unexpected '''//text(p:)//''' after the value of '''//name//''''
          return
        end if
      end do
      status = done
      do d = n0 + 1, size(names)
        src%names = [src%names, names(d)]
        src%values = [src%values, values(d)]
        def = trim(path)//':'//itoa(raw(where(d - n0))%line)
        src%defined = [src%defined, def]
      end do
    end subroutine try_group
  end subroutine parameters

  !> The line with each `${expression}` outside quotes and comments
  !> replaced by its value; a problem (prefixed with `here`) for each that
  !> cannot be evaluated (it is replaced by 0).
  function substitute(line, here, src, problems) result(out)
    character(len=*), intent(in) :: line, here
    type(deck_source_t), intent(in) :: src
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=:), allocatable :: out, msg
    character :: q
    integer :: j, k
    real(wp) :: v
    if (index(line, '${') == 0) then
      out = line
      return
    end if
    out = ''
    q = ' '
    j = 1
    do while (j <= len(line))
      if (q /= ' ') then
        if (line(j:j) == q) q = ' '
      else if (line(j:j) == '''' .or. line(j:j) == '"') then
        q = line(j:j)
      else if (line(j:j) == '!') then
        out = out//line(j:)
        return
      else if (line(j:min(len(line), j + 1)) == '${') then
        k = index(line(j + 2:), '}')
        if (k == 0) then
          call problem_add(problems, here//'''${'' without its ''}'': '''//line(j:)//'''')
          out = out//'0'
          return
        end if
        call expr_eval(line(j + 2:j + k), src%names, src%values, v, msg)
        if (len(msg) > 0) then
          call problem_add(problems, here//'${'//line(j + 2:j + k)//'}: '//msg)
          out = out//'0'
        else
          out = out//expr_number_text(v)
        end if
        j = j + k + 2
        cycle
      end if
      out = out//line(j:j)
      j = j + 1
    end do
  end function substitute

  !> 1 if `&include`, 2 if `&parameters` starts a group somewhere in the
  !> line other than at its start (outside quotes and comments); else 0.
  pure integer function misplaced(line) result(k)
    character(len=*), intent(in) :: line
    character :: q
    integer :: j
    character(len=:), allocatable :: low
    k = 0
    if (index(line, '&') == 0) return
    low = lower(line)
    q = ' '
    do j = 1, len(line)
      if (q /= ' ') then
        if (line(j:j) == q) q = ' '
      else if (line(j:j) == '''' .or. line(j:j) == '"') then
        q = line(j:j)
      else if (line(j:j) == '!') then
        return
      else if (line(j:j) == '&') then
        if (starts_group(low(j:), 'include')) k = 1
        if (starts_group(low(j:), 'parameters')) k = 2
        if (k > 0) return
      end if
    end do
  end function misplaced

  !> True if `text` (lower case, no leading blanks) starts the group `name`.
  pure logical function starts_group(text, name)
    character(len=*), intent(in) :: text, name
    starts_group = .false.
    if (len(text) < len(name) + 1) return
    if (text(1:len(name) + 1) /= '&'//name) return
    starts_group = .true.
    if (len(text) > len(name) + 1) &
      starts_group = scan(text(len(name) + 2:len(name) + 2), 'abcdefghijklmnopqrstuvwxyz0123456789_') == 0
  end function starts_group

  !> The part of a line before its `!` comment (outside quotes).
  pure function code_part(line) result(t)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: t
    character :: q
    integer :: j
    q = ' '
    t = line
    do j = 1, len(line)
      if (q /= ' ') then
        if (line(j:j) == q) q = ' '
      else if (line(j:j) == '''' .or. line(j:j) == '"') then
        q = line(j:j)
      else if (line(j:j) == '!') then
        t = line(1:j - 1)
        return
      end if
    end do
  end function code_part

  !> `${x}` in a parameter's expression is `(x)`.
  pure function braces(text) result(t)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: t
    integer :: j
    t = ''
    j = 1
    do while (j <= len(text))
      if (text(j:min(j + 1, len(text))) == '${') then
        t = t//'('
        j = j + 2
        cycle
      end if
      if (text(j:j) == '}') then
        t = t//')'
      else
        t = t//text(j:j)
      end if
      j = j + 1
    end do
  end function braces

  pure logical function ends_with_slash(line)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: t
    t = trim(code_part(line))
    ends_with_slash = .false.
    if (len(t) > 0) ends_with_slash = t(len(t):len(t)) == '/'
  end function ends_with_slash

  pure subroutine skip(text, j)
    character(len=*), intent(in) :: text
    integer, intent(inout) :: j
    do while (j <= len(text))
      if (text(j:j) /= ' ') exit
      j = j + 1
    end do
  end subroutine skip

  pure logical function at(text, j, c)
    character(len=*), intent(in) :: text, c
    integer, intent(in) :: j
    at = .false.
    if (j <= len(text)) at = text(j:j) == c
  end function at

  !> The folder of a file's path, with its '/' ('' for a bare name).
  pure function dir_of(path) result(dir)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: dir
    dir = path(1:index(path, '/', back=.true.))
  end function dir_of

  !> A path with `./` parts and doubled `/` removed and `dir/../` folded
  !> (to compare the names of included files).
  pure function normal_path(path) result(t)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: t
    integer :: k, j
    t = trim(path)
    do
      k = index(t, '//')
      if (k == 0) exit
      t = t(1:k)//t(k + 2:)
    end do
    do
      k = index(t, '/./')
      if (k == 0) exit
      t = t(1:k)//t(k + 3:)
    end do
    do while (len(t) > 2)
      if (t(1:2) /= './') exit
      t = t(3:)
    end do
    do
      k = index(t, '/../')
      if (k <= 1) exit
      j = index(t(1:k - 1), '/', back=.true.)
      if (t(j + 1:k - 1) == '..') exit
      t = t(1:j)//t(k + 4:)
    end do
  end function normal_path

  !> Appends a line of the expanded deck (the array doubles when full).
  subroutine add_line(src, text, file, line, stat)
    type(deck_source_t), intent(inout) :: src
    character(len=*), intent(in) :: text
    integer, intent(in) :: file, line
    integer, intent(out) :: stat
    type(source_line_t), allocatable :: tmp(:)
    integer :: k
    stat = 0
    if (.not. allocated(src%lines)) then
      stat = 1
      return
    end if
    if (src%n == size(src%lines)) then
      allocate(tmp(max(2*src%n, 64)), stat=stat)
      if (stat /= 0) return
      do k = 1, src%n
        call move_alloc(src%lines(k)%text, tmp(k)%text)
        tmp(k)%file = src%lines(k)%file
        tmp(k)%line = src%lines(k)%line
      end do
      call move_alloc(tmp, src%lines)
    end if
    src%n = src%n + 1
    src%lines(src%n)%text = text
    src%lines(src%n)%file = file
    src%lines(src%n)%line = line
  end subroutine add_line

  !> Every line of the file `path`, each of any length, numbered.
  subroutine read_raw(path, raw, ios, msg)
    character(len=*), intent(in) :: path
    type(source_line_t), allocatable, intent(out) :: raw(:)
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    type(source_line_t), allocatable :: tmp(:)
    character(len=:), allocatable :: line
    character(len=4096) :: buf
    integer :: unit, n, got, k
    allocate(raw(64), stat=ios, errmsg=msg)
    if (ios /= 0) return
    open(newunit=unit, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) return
    n = 0
    do
      line = ''
      do
        read(unit, '(a)', advance='no', size=got, iostat=ios, iomsg=msg) buf
        line = line//buf(1:got)
        if (ios /= 0) exit
      end do
      if (is_iostat_end(ios)) exit
      if (.not. is_iostat_eor(ios)) then
        close(unit)
        return
      end if
      if (n == size(raw)) then
        allocate(tmp(2*n), stat=ios, errmsg=msg)
        if (ios /= 0) then
          close(unit)
          return
        end if
        do k = 1, n
          call move_alloc(raw(k)%text, tmp(k)%text)
          tmp(k)%line = raw(k)%line
        end do
        call move_alloc(tmp, raw)
      end if
      n = n + 1
      raw(n)%text = line
      raw(n)%line = n
    end do
    close(unit)
    ios = 0
    raw = raw(1:n)
  end subroutine read_raw
end module io_deck_expand
