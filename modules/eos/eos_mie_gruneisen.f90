!> Mie-Gruneisen equation of state for solids, referred to the Hugoniot of a
!> linear shock-speed / particle-speed relation Us = c0 + s1 up (the paper's
!> 1045 steel shell of Section 7.6: c0, s1, gamma0).
!>
!> With mu = rho/rho0 - 1 and Gamma rho = gamma0 rho0 (constant),
!>
!>   p = p_H(mu) + gamma0 rho0 (e - e_H(mu)) = K(mu) + gamma0 rho0 e,
!>
!> which is the Mie-Gruneisen form rho e = f p + g of Eq. (11) with
!> f = rho/(gamma0 rho0), g = -rho K/(gamma0 rho0).
!>
!> Reference curve K(mu), for compression (mu >= 0): mass and momentum across a
!> shock from (rho0, p = 0, e = 0) give up/Us = mu/(1+mu) and p_H = rho0 Us up;
!> with Us = c0 + s1 up,
!>   p_H = rho0 c0^2 mu (1+mu) / (1 - (s1-1) mu)^2,
!> and the Rankine-Hugoniot energy e_H = p_H (1/rho0 - 1/rho)/2 is
!>   e_H = p_H mu / (2 rho0 (1+mu)),
!> so K = p_H (1 - gamma0 mu / (2 (1+mu))).
!>
!> Singularity: 1 - (s1-1) mu -> 0 at mu = 1/(s1-1) (Us -> infinity). We use the
!> formula up to mu_max = (1 - d_min)/(s1-1), where the denominator is d_min =
!> 0.1 (for steel, s1 = 1.92, mu_max = 0.978, rho = 1.98 rho0, p_H ~ 190 rho0
!> c0^2, far beyond any state a hydrocode should see); beyond mu_max, K continues
!> along its tangent. For s1 <= 1 there is no singularity and no limit.
!>
!> Tension (mu < 0): K = rho0 c0^2 mu, the linear extension. K and dK/dmu are
!> both continuous at mu = 0 (p_H'(0) = rho0 c0^2, e_H'(0) = 0), so p and c are
!> continuous there. No tensile cut-off is applied here: spall is the
!> material model's business.
!>
!> Units are the deck's (e.g. paper: rho0 g/mm^3, c0 mm/ms, p MPa, e mJ/g).
module eos_mie_gruneisen
  use base_kinds, only: wp, tiny_wp, huge_wp
  use eos_base, only: eos_t
  implicit none
  private
  public :: mie_gruneisen_t, mie_gruneisen_state, mie_gruneisen_reference

  !> Smallest denominator 1 - (s1-1) mu where the Hugoniot formula is used [-].
  real(wp), parameter :: d_min = 0.1_wp

  !> Linear Us-up Mie-Gruneisen parameters.
  type, extends(eos_t) :: mie_gruneisen_t
    real(wp) :: rho0    !< reference density [density]
    real(wp) :: c0      !< bulk sound speed, intercept of Us(up) [velocity]
    real(wp) :: s1      !< slope of Us(up) [-]
    real(wp) :: gamma0  !< Gruneisen coefficient at rho0 [-]
  contains
    procedure :: eval => mie_gruneisen_eval
    procedure :: energy => mie_gruneisen_energy
  end type mie_gruneisen_t

contains

  !> Reference curve K [pressure] and dK/dmu [pressure] at density rho
  !> [density]: p = K + gamma0 rho0 e (see the module header).
  elemental subroutine mie_gruneisen_reference(this, rho, k, dk)
    type(mie_gruneisen_t), intent(in) :: this
    real(wp), intent(in) :: rho
    real(wp), intent(out) :: k, dk
    real(wp) :: mu, mc, mu_max, bulk, d, ph, dph, h, dh
    bulk = this%rho0*this%c0**2
    mu = rho/this%rho0 - 1.0_wp
    if (mu < 0.0_wp) then
      ! tension: linear extension, C1 at mu = 0
      k = bulk*mu
      dk = bulk
      return
    end if
    if (this%s1 > 1.0_wp) then
      mu_max = (1.0_wp - d_min)/(this%s1 - 1.0_wp)
    else
      mu_max = huge_wp
    end if
    mc = min(mu, mu_max)
    d = 1.0_wp - (this%s1 - 1.0_wp)*mc
    ! Hugoniot pressure and its derivative, d p_H/d mu = rho0 c0^2 (1 + (s1+1) mu)/d^3
    ph = bulk*mc*(1.0_wp + mc)/d**2
    dph = bulk*(1.0_wp + (this%s1 + 1.0_wp)*mc)/d**3
    ! K = p_H - gamma0 rho0 e_H = p_H h(mu)
    h = 1.0_wp - this%gamma0*mc/(2.0_wp*(1.0_wp + mc))
    dh = -this%gamma0/(2.0_wp*(1.0_wp + mc)**2)
    dk = dph*h + ph*dh
    ! beyond mu_max: the tangent line (mu - mc = 0 below mu_max)
    k = ph*h + dk*(mu - mc)
  end subroutine mie_gruneisen_reference

  !> Pressure p [pressure] and sound speed cs [velocity] at density rho
  !> [density] and specific internal energy e [velocity^2].
  !>
  !> c^2 = dp/drho|_e + (p/rho^2) dp/de|_rho = K'(mu)/rho0 + gamma0 rho0 p/rho^2.
  !> In strong tension (p < 0, small rho) c^2 can turn negative; it is floored
  !> at tiny_wp so that cs is always real and > 0.
  elemental subroutine mie_gruneisen_state(this, rho, e, p, cs)
    type(mie_gruneisen_t), intent(in) :: this
    real(wp), intent(in) :: rho, e
    real(wp), intent(out) :: p, cs
    real(wp) :: k, dk, c2
    call mie_gruneisen_reference(this, rho, k, dk)
    p = k + this%gamma0*this%rho0*e
    c2 = dk/this%rho0 + this%gamma0*this%rho0*p/rho**2
    cs = sqrt(max(c2, tiny_wp))
  end subroutine mie_gruneisen_state

  subroutine mie_gruneisen_eval(this, rho, e, p, cs)
    class(mie_gruneisen_t), intent(in) :: this
    real(wp), intent(in) :: rho(:), e(:)
    real(wp), intent(out) :: p(:), cs(:)
    integer :: i
    !$omp parallel do default(none) shared(this, rho, e, p, cs) private(i) schedule(static)
    do i = 1, size(rho)
      call mie_gruneisen_state(this, rho(i), e(i), p(i), cs(i))
    end do
    !$omp end parallel do
  end subroutine mie_gruneisen_eval

  !> Inverse: e = (p - K(mu)) / (gamma0 rho0).
  pure function mie_gruneisen_energy(this, rho, p) result(e)
    class(mie_gruneisen_t), intent(in) :: this
    real(wp), intent(in) :: rho, p
    real(wp) :: e
    real(wp) :: k, dk
    call mie_gruneisen_reference(this, rho, k, dk)
    e = (p - k)/(this%gamma0*this%rho0)
  end function mie_gruneisen_energy

end module eos_mie_gruneisen
