!> A small reproducible random-number generator (Marsaglia's xorshift64), so that seeded
!> decks give the same numbers on every compiler and can be restarted.
module base_random
  use base_kinds, only: wp, i8
  implicit none
  private
  public :: rng_t, rng_seed, rng_uniform, rng_jump_t, rng_jump, rng_apply

  !> Generator state; never zero.
  type :: rng_t
    integer(i8) :: s = 88172645463325252_i8
  end type rng_t

  !> n draws at once (`rng_jump`): the generator's step is linear over
  !> GF(2) (shifts and exclusive ors of the state's bits), so n steps are a
  !> 64 x 64 bit matrix; col(c) is the image of the state with bit c alone.
  type :: rng_jump_t
    integer(i8) :: col(0:63) = 0_i8
  end type rng_jump_t

contains

  !> Seeds the generator (any integer; zero is mapped to a fixed non-zero state).
  pure subroutine rng_seed(r, seed)
    type(rng_t), intent(out) :: r
    integer, intent(in) :: seed
    r%s = ieor(int(seed, i8), 88172645463325252_i8)
    if (r%s == 0_i8) r%s = 88172645463325252_i8
  end subroutine rng_seed

  !> Uniform number in [0, 1).
  function rng_uniform(r) result(x)
    type(rng_t), intent(inout) :: r
    real(wp) :: x
    r%s = xorshift(r%s)
    ! top 53 bits as a fraction (no integer overflow anywhere)
    x = real(shiftr(r%s, 11), wp)*2.0_wp**(-53)
  end function rng_uniform

  !> The jump over n >= 0 draws (the step's matrix to the power n, by
  !> squaring): `rng_apply` then moves a generator on as n calls of
  !> `rng_uniform` would.
  pure function rng_jump(n) result(jm)
    integer(i8), intent(in) :: n
    type(rng_jump_t) :: jm, sq
    integer(i8) :: k
    integer :: c
    do c = 0, 63
      jm%col(c) = ibset(0_i8, c)
      sq%col(c) = xorshift(ibset(0_i8, c))
    end do
    k = n
    do while (k > 0_i8)
      if (btest(k, 0)) jm = composed(sq, jm)
      sq = composed(sq, sq)
      k = shiftr(k, 1)
    end do
  end function rng_jump

  !> Moves r on by the draws of jm.
  pure subroutine rng_apply(jm, r)
    type(rng_jump_t), intent(in) :: jm
    type(rng_t), intent(inout) :: r
    r%s = image(jm, r%s)
  end subroutine rng_apply

  !> One step of the generator's state.
  pure integer(i8) function xorshift(s0) result(s)
    integer(i8), intent(in) :: s0
    s = ieor(s0, shiftr(s0, 12))
    s = ieor(s, shiftl(s, 25))
    s = ieor(s, shiftr(s, 27))
  end function xorshift

  !> The state v moved on by jm.
  pure integer(i8) function image(jm, v)
    type(rng_jump_t), intent(in) :: jm
    integer(i8), intent(in) :: v
    integer :: c
    image = 0_i8
    do c = 0, 63
      if (btest(v, c)) image = ieor(image, jm%col(c))
    end do
  end function image

  !> a after b (powers of one step commute: either order).
  pure function composed(a, b) result(ab)
    type(rng_jump_t), intent(in) :: a, b
    type(rng_jump_t) :: ab
    integer :: c
    do c = 0, 63
      ab%col(c) = image(a, b%col(c))
    end do
  end function composed
end module base_random
