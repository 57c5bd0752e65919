!> Working precision and the few constants every module shares.
module base_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int64
  implicit none
  private
  public :: wp, i8, pi, tiny_wp, huge_wp

  !> Working real kind (IEEE double).
  integer, parameter :: wp = real64
  !> 64-bit integer kind for counters that can exceed 2**31.
  integer, parameter :: i8 = int64
  !> pi to working precision.
  real(wp), parameter :: pi = 3.141592653589793238462643383279502884_wp
  !> Smallest positive normal number, for guarding divisions.
  real(wp), parameter :: tiny_wp = tiny(1.0_wp)
  !> Largest finite number, for initialising minimum searches.
  real(wp), parameter :: huge_wp = huge(1.0_wp)
end module base_kinds
