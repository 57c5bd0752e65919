!> Number-to-text helpers for messages and logs.
module base_strings
  use base_kinds, only: wp, i8
  implicit none
  private
  public :: itoa, rtoa, lower, number_ok

  !> An integer (default or 64-bit) as text, without blanks.
  interface itoa
    module procedure itoa_default, itoa_i8
  end interface itoa

contains

  pure function itoa_default(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    s = itoa_i8(int(i, i8))
  end function itoa_default

  pure function itoa_i8(i) result(s)
    integer(i8), intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write(buf, '(i0)') i
    s = trim(buf)
  end function itoa_i8

  !> A real as text in scientific notation with 8 significant digits.
  pure function rtoa(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write(buf, '(es15.7e3)') x
    ! (two exponent digits where they suffice, as before: 1.0E+05)
    if (buf(len_trim(buf) - 2:len_trim(buf) - 2) == '0') buf = buf(1:len_trim(buf) - 3)//buf(len_trim(buf) - 1:)
    s = trim(adjustl(buf))
  end function rtoa

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

  !> s in lower case (ASCII letters).
  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    t = s
    do i = 1, len(s)
      if (s(i:i) >= 'A' .and. s(i:i) <= 'Z') t(i:i) = achar(iachar(s(i:i)) + 32)
    end do
  end function lower
end module base_strings
