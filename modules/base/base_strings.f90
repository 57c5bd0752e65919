!> Number-to-text helpers for messages and logs.
module base_strings
  use base_kinds, only: wp, i8
  implicit none
  private
  public :: itoa, rtoa

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
end module base_strings
