!> Arithmetic in decks: the expressions of `&parameters` groups and of
!> `${...}` in values (`io_deck_expand`). Numbers in Fortran forms (2, 0.5,
!> .5, 1d3, 1.5e-2), names of parameters defined earlier, `+ - * / **`,
!> parentheses and unary signs, with Fortran's precedence: `**` binds
!> tightest and from the right, then `*` and `/`, then `+` and `-` (so
!> `-2**2` is -4 and `2**3**2` is 512). Everything is done in real(wp).
!>
!> Nothing here may trap in the Debug build (floating-point traps on
!> invalid, zero and overflow): a division by zero, a result beyond 1e300
!> in magnitude (overflow), a negative number to a non-integer power and
!> 0 to a negative power are reported before they are computed, as is a
!> literal of magnitude 1e30 or more (the deck's rule for every number).
module io_deck_expr
  use base_kinds, only: wp, i8
  use base_strings, only: lower, number_ok
  implicit none
  private
  public :: expr_parse, expr_eval, expr_number_text, expr_name_ok

  !> Largest magnitude of any intermediate result (well inside the doubles:
  !> the checks below compare logarithms, which are not exact).
  real(wp), parameter :: big = 1.0e300_wp

  !> A parse in progress: the text, the position of the next character, and
  !> the first problem found ('' while there is none); `ended`: the problem
  !> is that the text ended inside the expression.
  type :: parser_t
    character(len=:), allocatable :: text
    integer :: pos = 1
    integer :: start = 1     !< where the expression starts (for messages)
    character(len=:), allocatable :: msg
    logical :: ended = .false.
  end type parser_t

contains

  !> Evaluates the whole of `text` (blanks allowed anywhere between tokens).
  !> names(:), values(:): the parameters known (names in lower case). On
  !> return `msg` is '' and `value` the result, or `msg` says what is wrong.
  pure subroutine expr_eval(text, names, values, value, msg)
    character(len=*), intent(in) :: text, names(:)
    real(wp), intent(in) :: values(:)
    real(wp), intent(out) :: value
    character(len=:), allocatable, intent(out) :: msg
    integer :: pos
    logical :: ended
    pos = 1
    call expr_parse(text, pos, names, values, value, msg, ended)
    if (len(msg) > 0) return
    call skip_blanks(text, pos)
    if (pos <= len(text)) msg = 'unexpected '''//text(pos:)//''' after the expression '''//trim(text(1:pos - 1))//''''
  end subroutine expr_eval

  !> Parses the longest expression starting at text(pos:) and moves `pos`
  !> past it (the caller says what may follow). A `/` followed by something
  !> that cannot start an operand (a blank end, a `&`) is left unread: it
  !> ends the namelist group the expression stands in. `ended`: `msg` says
  !> the text ended before the expression did (more lines may complete it).
  pure subroutine expr_parse(text, pos, names, values, value, msg, ended)
    character(len=*), intent(in) :: text, names(:)
    integer, intent(inout) :: pos
    real(wp), intent(in) :: values(:)
    real(wp), intent(out) :: value
    character(len=:), allocatable, intent(out) :: msg
    logical, intent(out) :: ended
    type(parser_t) :: p
    p%text = text
    p%pos = pos
    p%start = pos
    p%msg = ''
    call parse_sum(p, names, values, value)
    pos = p%pos
    msg = p%msg
    ended = p%ended
  end subroutine expr_parse

  !> sum := product { (+|-) product }
  pure recursive subroutine parse_sum(p, names, values, v)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: names(:)
    real(wp), intent(in) :: values(:)
    real(wp), intent(out) :: v
    real(wp) :: w
    character :: op
    call parse_product(p, names, values, v)
    do while (len(p%msg) == 0)
      call skip_blanks(p%text, p%pos)
      if (p%pos > len(p%text)) return
      op = p%text(p%pos:p%pos)
      if (op /= '+' .and. op /= '-') return
      p%pos = p%pos + 1
      call parse_product(p, names, values, w)
      if (len(p%msg) > 0) return
      if (op == '-') w = -w
      ! (|v| and |w| are below 1e300: the sum cannot overflow)
      v = v + w
    end do
  end subroutine parse_sum

  !> product := signed { (*|/) signed }; a `/` not followed by an operand
  !> is not a division (see expr_parse).
  pure recursive subroutine parse_product(p, names, values, v)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: names(:)
    real(wp), intent(in) :: values(:)
    real(wp), intent(out) :: v
    real(wp) :: w
    character :: op
    integer :: q
    call parse_signed(p, names, values, v)
    do while (len(p%msg) == 0)
      call skip_blanks(p%text, p%pos)
      if (p%pos > len(p%text)) return
      op = p%text(p%pos:p%pos)
      if (op == '*') then
        if (p%pos < len(p%text)) then
          if (p%text(p%pos + 1:p%pos + 1) == '*') return   ! (a power: the caller's)
        end if
      else if (op == '/') then
        q = p%pos + 1
        call skip_blanks(p%text, q)
        if (q > len(p%text)) return
        if (scan(p%text(q:q), '0123456789.(+-abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ') == 0) return
      else
        return
      end if
      p%pos = p%pos + 1
      call parse_signed(p, names, values, w)
      if (len(p%msg) > 0) return
      if (op == '*') then
        if (abs(v) > 0.0_wp .and. abs(w) > 0.0_wp) then
          if (log10(abs(v)) + log10(abs(w)) > 300.0_wp) then
            call fail(p, 'overflow in '''//sofar(p)//''' (beyond 1e300)')
            return
          end if
        end if
        v = v*w
      else
        if (abs(w) <= 0.0_wp) then
          call fail(p, 'division by zero in '''//sofar(p)//'''')
          return
        end if
        if (abs(v) > 0.0_wp) then
          if (log10(abs(v)) - log10(abs(w)) > 300.0_wp) then
            call fail(p, 'overflow in '''//sofar(p)//''' (beyond 1e300)')
            return
          end if
        end if
        v = v/w
      end if
    end do
  end subroutine parse_product

  !> signed := (+|-) signed | power   (so -2**2 = -(2**2), as in Fortran)
  pure recursive subroutine parse_signed(p, names, values, v)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: names(:)
    real(wp), intent(in) :: values(:)
    real(wp), intent(out) :: v
    logical :: minus
    v = 0.0_wp
    call skip_blanks(p%text, p%pos)
    if (p%pos <= len(p%text)) then
      if (p%text(p%pos:p%pos) == '-' .or. p%text(p%pos:p%pos) == '+') then
        minus = p%text(p%pos:p%pos) == '-'
        p%pos = p%pos + 1
        call parse_signed(p, names, values, v)
        if (minus) v = -v
        return
      end if
    end if
    call parse_power(p, names, values, v)
  end subroutine parse_signed

  !> power := primary [ ** signed ]   (right to left: 2**3**2 = 2**9)
  pure recursive subroutine parse_power(p, names, values, v)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: names(:)
    real(wp), intent(in) :: values(:)
    real(wp), intent(out) :: v
    real(wp) :: w, mag
    integer :: n
    call parse_primary(p, names, values, v)
    if (len(p%msg) > 0) return
    call skip_blanks(p%text, p%pos)
    if (p%pos + 1 > len(p%text)) return
    if (p%text(p%pos:p%pos + 1) /= '**') return
    p%pos = p%pos + 2
    call parse_signed(p, names, values, w)
    if (len(p%msg) > 0) return
    if (abs(v) <= 0.0_wp) then
      if (w < 0.0_wp) then
        call fail(p, 'division by zero in '''//sofar(p)//''' (0 to a negative power)')
      else if (abs(w) <= 0.0_wp) then
        v = 1.0_wp
      end if
      return
    end if
    mag = w*log10(abs(v))
    if (mag > 300.0_wp) then
      call fail(p, 'overflow in '''//sofar(p)//''' (beyond 1e300)')
      return
    end if
    if (abs(w - aint(w)) <= 0.0_wp .and. abs(w) < 1.0e9_wp) then
      ! an integer power: repeated multiplication, as Fortran's x**n
      n = int(w)
      if (mag < -300.0_wp) then
        v = 0.0_wp
      else
        v = v**n
      end if
    else if (v < 0.0_wp) then
      call fail(p, 'a negative number to a non-integer power in '''//sofar(p)//'''')
    else if (mag < -300.0_wp) then
      v = 0.0_wp
    else
      v = v**w
    end if
  end subroutine parse_power

  !> primary := number | name | ( sum )
  pure recursive subroutine parse_primary(p, names, values, v)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: names(:)
    real(wp), intent(in) :: values(:)
    real(wp), intent(out) :: v
    character :: c
    integer :: k, m
    v = 0.0_wp
    call skip_blanks(p%text, p%pos)
    if (p%pos > len(p%text)) then
      call fail(p, 'the expression '''//trim(adjustl(p%text(p%start:)))//''' ends where a number, a name or ''('' is expected')
      p%ended = .true.
      return
    end if
    c = p%text(p%pos:p%pos)
    if (c == '(') then
      p%pos = p%pos + 1
      call parse_sum(p, names, values, v)
      if (len(p%msg) > 0) return
      call skip_blanks(p%text, p%pos)
      if (p%pos > len(p%text)) then
        call fail(p, 'a ''('' is not closed in '''//trim(adjustl(p%text(p%start:)))//'''')
        p%ended = .true.
      else if (p%text(p%pos:p%pos) /= ')') then
        call fail(p, 'expected '')'' at '''//p%text(p%pos:)//'''')
      else
        p%pos = p%pos + 1
      end if
    else if (scan(c, '0123456789.') > 0) then
      k = number_end(p%text, p%pos)
      if (k < p%pos) then
        call fail(p, 'not a number: '''//p%text(p%pos:)//'''')
        return
      end if
      call read_number(p, p%text(p%pos:k), v)
      p%pos = k + 1
    else if (is_letter(c)) then
      k = p%pos
      do while (k < len(p%text))
        if (.not. is_name_char(p%text(k + 1:k + 1))) exit
        k = k + 1
      end do
      m = 0
      if (k - p%pos + 1 <= len(names)) then
        do m = size(names), 1, -1
          if (names(m) == lower(p%text(p%pos:k))) exit
        end do
      end if
      if (m == 0) then
        call fail(p, 'unknown name '''//p%text(p%pos:k)//''' (a parameter must be defined before it is used)')
        return
      end if
      v = values(m)
      p%pos = k + 1
    else
      call fail(p, 'expected a number, a name or ''('' at '''//p%text(p%pos:)//'''')
    end if
  end subroutine parse_primary

  !> The last position of the number that starts at text(i:): digits with
  !> at most one point, then an optional exponent e/d with a sign; i - 1 if
  !> there is no digit.
  pure integer function number_end(text, i) result(k)
    character(len=*), intent(in) :: text
    integer, intent(in) :: i
    integer :: j, ndig
    logical :: point
    k = i - 1
    ndig = 0
    point = .false.
    j = i
    do while (j <= len(text))
      if (scan(text(j:j), '0123456789') > 0) then
        ndig = ndig + 1
      else if (text(j:j) == '.' .and. .not. point) then
        point = .true.
      else
        exit
      end if
      j = j + 1
    end do
    if (ndig == 0) return
    k = j - 1
    ! an exponent: e or d, an optional sign, at least one digit
    if (j > len(text)) return
    if (scan(text(j:j), 'eEdD') == 0) return
    j = j + 1
    if (j <= len(text)) then
      if (scan(text(j:j), '+-') > 0) j = j + 1
    end if
    if (j > len(text)) return
    if (scan(text(j:j), '0123456789') == 0) return
    do while (j <= len(text))
      if (scan(text(j:j), '0123456789') == 0) exit
      j = j + 1
    end do
    k = j - 1
  end function number_end

  !> A number token's value (the deck's magnitude rule first: a literal of
  !> 1e30 or more is refused, as anywhere in a deck).
  pure subroutine read_number(p, tok, v)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: tok
    real(wp), intent(out) :: v
    character(len=len(tok)) :: t
    integer :: ios, j
    v = 0.0_wp
    t = lower(tok)
    do j = 1, len(t)
      if (t(j:j) == 'd') t(j:j) = 'e'
    end do
    if (.not. number_ok(t)) then
      call fail(p, 'the number '''//tok//''' is not allowed (magnitudes of 1e30 or more are refused)')
      return
    end if
    read(t, *, iostat=ios) v
    if (ios /= 0) call fail(p, 'not a number: '''//tok//'''')
  end subroutine read_number

  !> The expression read so far (for messages).
  pure function sofar(p) result(t)
    type(parser_t), intent(in) :: p
    character(len=:), allocatable :: t
    t = trim(adjustl(p%text(p%start:p%pos - 1)))
  end function sofar

  !> Records the first problem of a parse.
  pure subroutine fail(p, msg)
    type(parser_t), intent(inout) :: p
    character(len=*), intent(in) :: msg
    if (len(p%msg) == 0) p%msg = msg
  end subroutine fail

  pure subroutine skip_blanks(text, pos)
    character(len=*), intent(in) :: text
    integer, intent(inout) :: pos
    do while (pos <= len(text))
      if (text(pos:pos) /= ' ') exit
      pos = pos + 1
    end do
  end subroutine skip_blanks

  pure logical function is_letter(c)
    character, intent(in) :: c
    is_letter = (c >= 'a' .and. c <= 'z') .or. (c >= 'A' .and. c <= 'Z')
  end function is_letter

  pure logical function is_name_char(c)
    character, intent(in) :: c
    is_name_char = is_letter(c) .or. (c >= '0' .and. c <= '9') .or. c == '_'
  end function is_name_char

  !> True for a valid parameter name: a letter, then letters, digits and
  !> underscores, at most `maxlen` characters.
  pure logical function expr_name_ok(name, maxlen) result(ok)
    character(len=*), intent(in) :: name
    integer, intent(in) :: maxlen
    integer :: j
    ok = len(name) >= 1 .and. len(name) <= maxlen
    if (.not. ok) return
    ok = is_letter(name(1:1))
    do j = 2, len(name)
      ok = ok .and. is_name_char(name(j:j))
    end do
  end function expr_name_ok

  !> A value as deck text that reads back to the very same double: an
  !> integer when it is one (below 1e15: `ni = ${n}` reads as an integer),
  !> else the shortest scientific form that reads back exactly (at most 17
  !> significant digits).
  pure function expr_number_text(v) result(s)
    real(wp), intent(in) :: v
    character(len=:), allocatable :: s
    character(len=40) :: buf
    character(len=16) :: fmt
    character(len=:), allocatable :: mant
    real(wp) :: back
    integer :: d, ios, k, e
    if (abs(v - aint(v)) <= 0.0_wp .and. abs(v) < 1.0e15_wp) then
      write(buf, '(i0)') int(v, i8)
      s = trim(buf)
      return
    end if
    do d = 1, 17
      write(fmt, '("(es",i0,".",i0,"e3)")') d + 8, d - 1
      write(buf, fmt) v
      read(buf, *, iostat=ios) back
      if (ios == 0 .and. abs(back - v) <= 0.0_wp) exit
    end do
    ! 1.25E-001 as 1.25e-1, 1.4E+000 as 1.4, 1.E+020 as 1e20
    buf = adjustl(buf)
    k = index(buf, 'E')
    read(buf(k + 1:), *) e
    mant = trim(buf(1:k - 1))
    if (mant(len(mant):len(mant)) == '.') mant = mant(1:len(mant) - 1)
    if (e == 0) then
      s = mant
    else
      write(buf, '(i0)') e
      s = mant//'e'//trim(buf)
    end if
  end function expr_number_text
end module io_deck_expr
