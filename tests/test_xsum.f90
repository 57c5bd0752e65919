!> Exact sums (`base_xsum`): the rounded total is the correctly rounded
!> exact sum, whatever the order or grouping of the terms.
!> - Terms that cancel in floating point (1e16 + 1 - 1e16 ...) give the exact
!>   integer answer.
!> - Ties round to even: 2^53 + 1 (exactly halfway) rounds to 2^53, and
!>   2^53 + 3 to 2^53 + 4; a tiny term past the tie decides it upward.
!> - A set of random terms summed forwards, backwards and in two halves
!>   whose accumulators are added limb by limb (as ranks do) gives the same
!>   bits, and scaling every term by 2^k scales the total by exactly 2^k
!>   (the dimension tests rely on this).
!> - The result agrees with a compensated (Neumaier) sum to 1 ulp.
!> - A NaN or an infinity among the terms, or a total beyond the largest
!>   real (two terms of huge), marks the sum as not finite and its value a
!>   NaN, without touching memory outside the accumulator (the debug build's
!>   bounds checks); a total of huge and -huge/2 terms that comes back in
!>   range, and the largest real itself, stay finite and exact.
!> - Subnormal terms are exact too (their bits have no hidden bit).
program test_xsum
  use base_kinds, only: wp, i8
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, ieee_negative_inf, ieee_is_nan
  use base_xsum, only: xsum_t, xsum_add, xsum_value, xsum_normalize, xsum_finite
  use test_assert, only: check, check_summary
  implicit none
  integer, parameter :: n = 20000
  type(xsum_t) :: a, b, c, d, e
  real(wp) :: x(n), t, s, comp, y, two53
  integer :: i, k

  two53 = 2.0_wp**53
  call xsum_add(a, 1.0e16_wp)
  call xsum_add(a, 1.0_wp)
  call xsum_add(a, -1.0e16_wp)
  call xsum_add(a, 0.5_wp)
  call check(same(xsum_value(a), 1.5_wp), 'cancellation: 1e16 + 1 - 1e16 + 0.5 = 1.5')

  a = xsum_t()
  call xsum_add(a, two53)
  call xsum_add(a, 1.0_wp)
  call check(same(xsum_value(a), two53), 'tie 2^53 + 1 rounds to even (2^53)')
  call xsum_add(a, 2.0_wp)
  call check(same(xsum_value(a), two53 + 4.0_wp), 'tie 2^53 + 3 rounds to even (2^53 + 4)')
  a = xsum_t()
  call xsum_add(a, two53)
  call xsum_add(a, 1.0_wp)
  call xsum_add(a, 2.0_wp**(-900))
  call check(same(xsum_value(a), two53 + 2.0_wp), 'past the tie by 2^-900: rounds up')
  a = xsum_t()
  call xsum_add(a, -3.0_wp)
  call xsum_add(a, 2.0_wp**(-1000))
  call check(same(xsum_value(a), -3.0_wp), 'negative total: -3 + 2^-1000 rounds to -3')
  call check(same(xsum_value(xsum_t()), 0.0_wp), 'empty sum is 0')

  call random_seed(put=[(12345 + i, i = 1, 64)])
  call random_number(x)
  do i = 1, n
    x(i) = (x(i) - 0.3_wp)*10.0_wp**(mod(i, 13) - 6)
  end do
  a = xsum_t(); b = xsum_t(); c = xsum_t(); d = xsum_t()
  s = 0.0_wp; comp = 0.0_wp
  do i = 1, n
    call xsum_add(a, x(i))
    call xsum_add(b, x(n + 1 - i))
    if (3*i <= n) then
      call xsum_add(c, x(i))
    else
      call xsum_add(d, x(i))
    end if
    t = s + x(i)
    if (abs(s) >= abs(x(i))) then
      comp = comp + ((s - t) + x(i))
    else
      comp = comp + ((x(i) - t) + s)
    end if
    s = t
  end do
  call xsum_normalize(c)
  call xsum_normalize(d)
  c%limb = c%limb + d%limb
  y = xsum_value(a)
  call check(same(y, xsum_value(b)), 'forwards and backwards: same bits')
  call check(same(y, xsum_value(c)), 'two accumulators added limb by limb: same bits')
  call check(abs(y - (s + comp)) <= spacing(y), 'agrees with a compensated sum to 1 ulp')
  do k = -40, 40, 7
    e = xsum_t()
    do i = 1, n
      call xsum_add(e, scale(x(i), k))
    end do
    call check(same(xsum_value(e), scale(y, k)), 'terms scaled by 2^k: total scaled by exactly 2^k')
  end do

  ! not finite: a NaN, an infinity of either sign, an overflowing total
  do k = 1, 4
    a = xsum_t()
    call xsum_add(a, 1.0_wp)
    select case (k)
    case (1); call xsum_add(a, ieee_value(t, ieee_quiet_nan))
    case (2); call xsum_add(a, ieee_value(t, ieee_positive_inf))
    case (3); call xsum_add(a, ieee_value(t, ieee_negative_inf))
    case (4); call xsum_add(a, huge(t)); call xsum_add(a, huge(t))
    end select
    call xsum_add(a, 2.0_wp)
    call check(.not. xsum_finite(a) .and. ieee_is_nan(xsum_value(a)), 'not finite: case '//achar(48 + k))
  end do
  a = xsum_t()
  call xsum_add(a, huge(t))
  call check(xsum_finite(a) .and. same(xsum_value(a), huge(t)), 'the largest real is finite and exact')
  call xsum_add(a, huge(t))
  call xsum_add(a, -huge(t)/2)
  call xsum_add(a, -huge(t)/2)
  call xsum_add(a, -huge(t)/2)
  call check(xsum_finite(a) .and. same(xsum_value(a), huge(t)/2), 'huge + huge - 3 huge/2 comes back in range')
  a = xsum_t()
  call xsum_add(a, -huge(t))
  call xsum_add(a, -huge(t))
  call check(.not. xsum_finite(a), '-2 huge is not finite')
  ! subnormal terms (read from their bits without the hidden bit): 2^10
  ! halves of 2^-10 tiny add up to tiny exactly, the smallest subnormal
  ! survives beside a normal term's cancellation, and -0 adds nothing
  a = xsum_t()
  do i = 1, 2048
    call xsum_add(a, tiny(t)*2.0_wp**(-11))
  end do
  call check(same(xsum_value(a), tiny(t)), 'subnormal terms add up exactly to tiny')
  a = xsum_t()
  call xsum_add(a, 1.0_wp)
  call xsum_add(a, -0.0_wp)
  call xsum_add(a, 2.0_wp**(-1074))
  call xsum_add(a, -1.0_wp)
  call check(same(xsum_value(a), 2.0_wp**(-1074)), 'the smallest subnormal beside a cancelled 1')
  call xsum_add(a, -2.0_wp**(-1074))
  call check(same(xsum_value(a), 0.0_wp), 'a subnormal and its negative cancel')
  call check_summary('test_xsum')
contains
  !> The same bits.
  logical function same(a, b)
    real(wp), intent(in) :: a, b
    same = transfer(a, 0_i8) == transfer(b, 0_i8)
  end function same
end program test_xsum
