!> A small reproducible random-number generator (Marsaglia's xorshift64), so that seeded
!> decks give the same numbers on every compiler and can be restarted.
module base_random
  use base_kinds, only: wp, i8
  implicit none
  private
  public :: rng_t, rng_seed, rng_uniform

  !> Generator state; never zero.
  type :: rng_t
    integer(i8) :: s = 88172645463325252_i8
  end type rng_t

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
    r%s = ieor(r%s, shiftr(r%s, 12))
    r%s = ieor(r%s, shiftl(r%s, 25))
    r%s = ieor(r%s, shiftr(r%s, 27))
    ! top 53 bits as a fraction (no integer overflow anywhere)
    x = real(shiftr(r%s, 11), wp)*2.0_wp**(-53)
  end function rng_uniform
end module base_random
