!> The small assert module the unit tests share: count failures, report them,
!> and end with a non-zero exit status if any check failed.
module test_assert
  use base_kinds, only: wp
  implicit none
  private
  public :: check, check_close, check_summary

  integer, save :: nfail = 0

contains

  !> Records a failed check and prints what it was.
  subroutine check(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (.not. ok) then
      nfail = nfail + 1
      write(*, '(a)') 'FAIL: '//what
    end if
  end subroutine check

  !> Checks |value - expected| <= tol and prints the label, the value, the
  !> expected value and the tolerance, whether it passes or not.
  subroutine check_close(what, value, expected, tol)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: value, expected, tol
    logical :: ok
    ok = abs(value - expected) <= tol
    write(*, '(a,es12.4,a,es12.4,a,es10.2)') merge('ok    ', 'FAIL  ', ok)//what//': value ', value, &
      ', expected ', expected, ', tolerance ', tol
    if (.not. ok) nfail = nfail + 1
  end subroutine check_close

  !> Prints PASS or FAIL for the program `name`; stops with status 1 on failure.
  subroutine check_summary(name)
    character(len=*), intent(in) :: name
    if (nfail > 0) then
      write(*, '(a,i0,a)') 'FAIL '//name//': ', nfail, ' check(s) failed'
      error stop 1
    end if
    write(*, '(a)') 'PASS '//name
  end subroutine check_summary
end module test_assert
