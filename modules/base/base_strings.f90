!> Number-to-text helpers for messages and logs.
module base_strings
  use base_kinds, only: wp
  implicit none
  private
  public :: itoa, rtoa

contains

  !> An integer as text, without blanks.
  pure function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write(buf, '(i0)') i
    s = trim(buf)
  end function itoa

  !> A real as text in scientific notation with 8 significant digits.
  pure function rtoa(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write(buf, '(es14.7)') x
    s = trim(adjustl(buf))
  end function rtoa
end module base_strings
