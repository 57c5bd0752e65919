!> The abstract equation of state: pressure and sound speed from density and
!> specific internal energy, and the inverse e(rho, p).
!>
!> A material holds one `eos_t`; the driver dispatches once per material and
!> hands the EOS contiguous arrays of that material's cells, so no type
!> selection happens inside a per-cell loop (ARCHITECTURE.md §3).
module eos_base
  use base_kinds, only: wp
  implicit none
  private
  public :: eos_t

  !> An equation of state p(rho, e).
  type, abstract :: eos_t
  contains
    !> Pressure p and sound speed cs for arrays rho, e (user units).
    procedure(eos_eval_i), deferred :: eval
    !> Specific internal energy for a given density and pressure.
    procedure(eos_energy_i), deferred :: energy
  end type eos_t

  abstract interface
    subroutine eos_eval_i(this, rho, e, p, cs)
      import :: eos_t, wp
      class(eos_t), intent(in) :: this
      real(wp), intent(in) :: rho(:), e(:)
      real(wp), intent(out) :: p(:), cs(:)
    end subroutine eos_eval_i

    pure function eos_energy_i(this, rho, p) result(e)
      import :: eos_t, wp
      class(eos_t), intent(in) :: this
      real(wp), intent(in) :: rho, p
      real(wp) :: e
    end function eos_energy_i
  end interface
end module eos_base
