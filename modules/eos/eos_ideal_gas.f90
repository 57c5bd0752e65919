!> Ideal gas, p = (gamma - 1) rho e, c^2 = gamma p / rho.
module eos_ideal_gas
  use base_kinds, only: wp
  use eos_base, only: eos_t
  implicit none
  private
  public :: ideal_gas_t, ideal_gas_pressure, ideal_gas_sound_speed

  !> Ideal gas with constant ratio of specific heats `gamma` (> 1).
  type, extends(eos_t) :: ideal_gas_t
    real(wp) :: gamma = 1.4_wp
  contains
    procedure :: eval => ideal_gas_eval
    procedure :: energy => ideal_gas_energy
  end type ideal_gas_t

contains

  !> Pressure of an ideal gas.
  elemental function ideal_gas_pressure(gamma, rho, e) result(p)
    real(wp), intent(in) :: gamma, rho, e
    real(wp) :: p
    p = (gamma - 1.0_wp)*rho*e
  end function ideal_gas_pressure

  !> Sound speed sqrt(gamma (gamma-1) e); a negative energy gives zero.
  elemental function ideal_gas_sound_speed(gamma, e) result(cs)
    real(wp), intent(in) :: gamma, e
    real(wp) :: cs
    cs = sqrt(gamma*(gamma - 1.0_wp)*max(e, 0.0_wp))
  end function ideal_gas_sound_speed

  subroutine ideal_gas_eval(this, rho, e, p, cs)
    class(ideal_gas_t), intent(in) :: this
    real(wp), intent(in) :: rho(:), e(:)
    real(wp), intent(out) :: p(:), cs(:)
    integer :: i
    !$omp parallel do default(none) shared(this, rho, e, p, cs) private(i) schedule(static)
    do i = 1, size(rho)
      p(i) = ideal_gas_pressure(this%gamma, rho(i), e(i))
      cs(i) = ideal_gas_sound_speed(this%gamma, e(i))
    end do
    !$omp end parallel do
  end subroutine ideal_gas_eval

  pure function ideal_gas_energy(this, rho, p) result(e)
    class(ideal_gas_t), intent(in) :: this
    real(wp), intent(in) :: rho, p
    real(wp) :: e
    e = p/((this%gamma - 1.0_wp)*rho)
  end function ideal_gas_energy

end module eos_ideal_gas
