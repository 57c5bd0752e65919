!> Jones-Wilkins-Lee (JWL) equation of state for detonation products,
!> in the Mie-Gruneisen form of Eqs. (11) and (13):
!>
!>   p = A (1 - omega rho/(R1 rho0)) exp(-R1 rho0/rho)
!>     + B (1 - omega rho/(R2 rho0)) exp(-R2 rho0/rho) + omega rho e,
!>
!> with e the specific internal energy (per unit mass) and rho0 the density of
!> the unreacted explosive. Eq. (11) reads rho e = f p + g with f = 1/omega and
!> g = -(cold terms)/omega, which solved for p gives the line above.
!>
!> The paper uses it for RHT-901 (Section 7.6) and TNT (Section 7.7).
!> Units are the deck's: A, B and p in one pressure unit, rho and rho0 in one
!> density unit, e in pressure/density (e.g. GPa, g/cm^3, kJ/g; or the paper's
!> MPa, g/mm^3, mJ/g).
module eos_jwl
  use base_kinds, only: wp, tiny_wp
  use eos_base, only: eos_t
  implicit none
  private
  public :: jwl_t, jwl_state, jwl_cold_pressure

  !> JWL parameters: A, B (pressure), R1, R2, omega (dimensionless), rho0 (density).
  type, extends(eos_t) :: jwl_t
    real(wp) :: a      !< coefficient of the first exponential [pressure]
    real(wp) :: b      !< coefficient of the second exponential [pressure]
    real(wp) :: r1     !< decay rate of the first exponential in rho0/rho [-]
    real(wp) :: r2     !< decay rate of the second exponential in rho0/rho [-]
    real(wp) :: omega  !< Gruneisen coefficient of the products, dp/de / rho [-]
    real(wp) :: rho0   !< reference (unreacted explosive) density [density]
  contains
    procedure :: eval => jwl_eval
    procedure :: energy => jwl_energy
  end type jwl_t

contains

  !> The part of p that does not depend on e (Eq. 13's -g/f) [pressure] at
  !> density rho [density].
  elemental function jwl_cold_pressure(this, rho) result(pc)
    type(jwl_t), intent(in) :: this
    real(wp), intent(in) :: rho
    real(wp) :: pc
    real(wp) :: ea, eb
    ea = this%a*exp(-this%r1*this%rho0/rho)
    eb = this%b*exp(-this%r2*this%rho0/rho)
    pc = ea*(1.0_wp - this%omega*rho/(this%r1*this%rho0)) &
       + eb*(1.0_wp - this%omega*rho/(this%r2*this%rho0))
  end function jwl_cold_pressure

  !> Pressure p [pressure] and sound speed cs [velocity] at density rho
  !> [density] and specific internal energy e [pressure/density].
  !>
  !> c^2 = dp/drho|_e + (p/rho^2) dp/de|_rho, the isentropic derivative, with
  !>   dp/drho|_e = sum_i A_i exp(-R_i rho0/rho) (R_i rho0/rho^2 - omega/(R_i rho0)
  !>                - omega/rho) + omega e,   dp/de|_rho = omega rho.
  !> c^2 turns negative only far out in expansion with e < 0 (no physical
  !> state); it is floored at tiny_wp so that cs is always real and > 0.
  elemental subroutine jwl_state(this, rho, e, p, cs)
    type(jwl_t), intent(in) :: this
    real(wp), intent(in) :: rho, e
    real(wp), intent(out) :: p, cs
    real(wp) :: ea, eb, dpc, c2
    ea = this%a*exp(-this%r1*this%rho0/rho)
    eb = this%b*exp(-this%r2*this%rho0/rho)
    ! Eq. (13): cold terms plus omega rho e
    p = ea*(1.0_wp - this%omega*rho/(this%r1*this%rho0)) &
      + eb*(1.0_wp - this%omega*rho/(this%r2*this%rho0)) + this%omega*rho*e
    dpc = ea*(this%r1*this%rho0/rho**2 - this%omega/(this%r1*this%rho0) - this%omega/rho) &
        + eb*(this%r2*this%rho0/rho**2 - this%omega/(this%r2*this%rho0) - this%omega/rho)
    c2 = dpc + this%omega*(e + p/rho)
    cs = sqrt(max(c2, tiny_wp))
  end subroutine jwl_state

  subroutine jwl_eval(this, rho, e, p, cs)
    class(jwl_t), intent(in) :: this
    real(wp), intent(in) :: rho(:), e(:)
    real(wp), intent(out) :: p(:), cs(:)
    integer :: i
    !$omp parallel do default(none) shared(this, rho, e, p, cs) private(i) schedule(static)
    do i = 1, size(rho)
      call jwl_state(this, rho(i), e(i), p(i), cs(i))
    end do
    !$omp end parallel do
  end subroutine jwl_eval

  !> Inverse of Eq. (13): e = (p - p_cold(rho)) / (omega rho).
  pure function jwl_energy(this, rho, p) result(e)
    class(jwl_t), intent(in) :: this
    real(wp), intent(in) :: rho, p
    real(wp) :: e
    e = (p - jwl_cold_pressure(this, rho))/(this%omega*rho)
  end function jwl_energy

end module eos_jwl
