!> Exact sums of reals, the same whatever the order of the terms: each term
!> is added exactly to a long fixed-point integer (limbs of 32 bits held in
!> 64-bit integers, covering every binary64 exponent), so the result depends
!> only on the set of terms. Blocks of a decomposition sum their own terms
!> and add their accumulators limb by limb (an integer sum, exact in any
!> order); `xsum_value` then rounds the one exact total to a real. This
!> makes global totals identical on any number of ranks and threads.
!>
!> A NaN or an infinity has no place in the accumulator: such a term is not
!> added but marks the sum as not finite (`finite`), and so does a total too
!> large for a real; the value of such a sum is a NaN (`xsum_value`), and
!> the caller that must not go on with it asks `xsum_finite`.
module base_xsum
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use base_kinds, only: wp, i8
  implicit none
  private
  public :: xsum_t, xsum_add, xsum_value, xsum_finite, xsum_normalize, XSUM_LIMBS

  integer, parameter :: XSUM_LIMBS = 72       !< 32-bit limbs: 2304 bits
  integer, parameter :: BIAS = 1200           !< bit 0 of limb 0 is 2^-BIAS
  integer, parameter :: ROOM = 2**30          !< terms between carry passes
  integer(i8), parameter :: MASK32 = 4294967295_i8
  integer(i8), parameter :: MANT52 = 4503599627370495_i8   !< 2^52 - 1: a binary64's fraction bits
  integer(i8), parameter :: HIDDEN = 4503599627370496_i8   !< 2^52: its hidden bit

  !> An exact running sum.
  type :: xsum_t
    integer(i8) :: limb(0:XSUM_LIMBS - 1) = 0_i8
    integer :: terms = 0   !< terms since the last carry pass
    logical :: finite = .true.   !< no NaN or infinity among the terms
  end type xsum_t

contains

  !> Adds x exactly (a NaN or an infinity marks the sum as not finite).
  pure subroutine xsum_add(s, x)
    type(xsum_t), intent(inout) :: s
    real(wp), intent(in) :: x
    integer(i8) :: m, a, r, bits
    integer :: b, l, sh, ebits
    ! x = m 2^(b - BIAS), m < 2^53 an integer, read from the binary64 bits
    ! (the exponent field, and the fraction with its hidden bit unless x is
    ! subnormal); the same value as scale(fraction(x), 53) 2^(exponent(x) -
    ! 53), without the library calls (exact totals are taken every Euler step)
    bits = transfer(x, bits)
    ebits = int(iand(ishft(bits, -52), 2047_i8))
    if (ebits == 2047) then
      s%finite = .false.
      return
    end if
    m = iand(bits, MANT52)
    if (ebits > 0) then
      m = ior(m, HIDDEN)
    else
      if (m == 0_i8) return
      ebits = 1
    end if
    b = ebits - 1075 + BIAS
    l = b/32
    sh = mod(b, 32)
    ! the bits of m that fall in limb l, and the rest for limbs l+1, l+2
    a = ishft(iand(m, ishft(1_i8, 32 - sh) - 1_i8), sh)
    r = ishft(m, -(32 - sh))
    if (bits >= 0_i8) then
      s%limb(l) = s%limb(l) + a
      s%limb(l + 1) = s%limb(l + 1) + iand(r, MASK32)
      s%limb(l + 2) = s%limb(l + 2) + ishft(r, -32)
    else
      s%limb(l) = s%limb(l) - a
      s%limb(l + 1) = s%limb(l + 1) - iand(r, MASK32)
      s%limb(l + 2) = s%limb(l + 2) - ishft(r, -32)
    end if
    s%terms = s%terms + 1
    if (s%terms >= ROOM) call xsum_normalize(s)
  end subroutine xsum_add

  !> Carries: every limb but the last in [0, 2^32), the last holds the sign.
  pure subroutine xsum_normalize(s)
    type(xsum_t), intent(inout) :: s
    integer(i8) :: c
    integer :: l
    do l = 0, XSUM_LIMBS - 2
      c = shifta(s%limb(l), 32)
      s%limb(l) = s%limb(l) - ishft(c, 32)
      s%limb(l + 1) = s%limb(l + 1) + c
    end do
    s%terms = 0
  end subroutine xsum_normalize

  !> False if a term was a NaN or an infinity, or the total is too large
  !> for a real.
  pure logical function xsum_finite(s)
    type(xsum_t), intent(in) :: s
    real(wp) :: v
    logical :: big
    call total(s, v, big)
    xsum_finite = s%finite .and. .not. big
  end function xsum_finite

  !> The sum correctly rounded to the nearest real (ties to even): a
  !> function of the exact total only, so it commutes with scaling by a
  !> power of two and does not depend on how the terms were grouped. A NaN
  !> if the sum is not finite (`xsum_finite`).
  pure real(wp) function xsum_value(s) result(v)
    type(xsum_t), intent(in) :: s
    logical :: big
    call total(s, v, big)
    if (.not. s%finite .or. big) v = ieee_value(v, ieee_quiet_nan)
  end function xsum_value

  !> v: the rounded total of the finite terms; big: it is too large for a
  !> real (v is then 0).
  pure subroutine total(s0, v, big)
    type(xsum_t), intent(in) :: s0
    real(wp), intent(out) :: v
    logical, intent(out) :: big
    type(xsum_t) :: s
    integer, parameter :: W = 55            ! 53 digits, a guard and a round bit
    integer(i8) :: q
    integer :: l, h, top, b, low
    logical :: sticky, negative
    s = s0
    call xsum_normalize(s)
    negative = s%limb(XSUM_LIMBS - 1) < 0_i8
    if (negative) then
      s%limb = -s%limb
      call xsum_normalize(s)
    end if
    h = -1
    do l = XSUM_LIMBS - 1, 0, -1
      if (s%limb(l) /= 0_i8) then
        h = l
        exit
      end if
    end do
    v = 0.0_wp
    big = .false.
    if (h < 0) return
    top = 32*h + 63 - leadz(s%limb(h))      ! the leading bit of the total
    ! the W bits from `top` down, and whether any bit below them is set
    low = top - W + 1
    q = 0_i8
    do b = top, max(low, 0), -1
      q = ishft(q, 1)
      if (btest(s%limb(b/32), mod(b, 32))) q = q + 1_i8
    end do
    if (low < 0) q = ishft(q, -low)
    sticky = .false.
    if (low > 0) then
      sticky = iand(s%limb(low/32), ishft(1_i8, mod(low, 32)) - 1_i8) /= 0_i8
      do l = 0, low/32 - 1
        sticky = sticky .or. s%limb(l) /= 0_i8
      end do
    end if
    ! round the 53 leading bits to nearest, ties to even
    if (btest(q, 1) .and. (btest(q, 0) .or. sticky .or. btest(q, 2))) q = q + 4_i8
    q = ishft(q, -2)
    ! (2^53 after rounding up is 2^52 one place higher)
    if (top - BIAS + merge(1, 0, q == ishft(1_i8, 53)) > maxexponent(v) - 1) then
      big = .true.
      return
    end if
    v = scale(real(q, wp), low + 2 - BIAS)
    if (negative) v = -v
  end subroutine total
end module base_xsum
