!> The Johnson-Cook flow stress (paper Eq. 59 and its full form with
!> thermal softening; PARTICLES.md §2.3), shared by the Johnson-Cook model
!> and as the matrix of the Gurson model:
!>   sigma_y = (A + B eps_p^n) (1 + C ln max(eps_dot/eps_dot0, 1)) (1 - T*^m),
!>   T* = (T - T_room)/(T_melt - T_room) clamped to [0, 1].
!> The rate term is guarded (rates below eps_dot0 do not soften below the
!> static curve, as LS-DYNA does) and m = 0 (the default) switches thermal
!> softening off (factor 1 at any T). The slope d sigma_y/d eps_p is
!> singular at eps_p = 0 for n < 1: `jc_flow_slopes` returns it at
!> max(eps_p, eps_floor), and a Newton on it must bracket its root.
module strength_jc_flow
  use base_kinds, only: wp
  implicit none
  private
  public :: jc_flow_t, jc_flow, jc_flow_slopes, thermal_factor

  !> eps_p floor of the slope (module notes).
  real(wp), parameter :: eps_floor = 1.0e-12_wp

  !> The Johnson-Cook parameters (stresses in pressure units, rates in
  !> 1/time, temperatures in the deck's temperature unit).
  type :: jc_flow_t
    real(wp) :: a = 0.0_wp        !< A, initial yield stress
    real(wp) :: b = 0.0_wp        !< B, hardening modulus
    real(wp) :: n = 1.0_wp        !< n, hardening exponent
    real(wp) :: c = 0.0_wp        !< C, rate sensitivity
    real(wp) :: eps0 = 1.0_wp     !< eps_dot0, reference plastic strain rate
    real(wp) :: m = 0.0_wp        !< m, thermal softening exponent (0: none)
    real(wp) :: t_room = 0.0_wp   !< T_room
    real(wp) :: t_melt = 1.0_wp   !< T_melt (> T_room)
  end type jc_flow_t

contains

  !> The rate factor 1 + C ln max(rate/eps0, 1).
  pure real(wp) function rate_factor(jc, rate) result(r)
    type(jc_flow_t), intent(in) :: jc
    real(wp), intent(in) :: rate
    r = 1.0_wp + jc%c*log(max(rate/jc%eps0, 1.0_wp))
  end function rate_factor

  !> The thermal factor 1 - T*^m (1 without softening, 0 at and above melt).
  pure real(wp) function thermal_factor(jc, t) result(f)
    type(jc_flow_t), intent(in) :: jc
    real(wp), intent(in) :: t
    real(wp) :: ts
    f = 1.0_wp
    if (.not. jc%m > 0.0_wp) return
    ts = max(0.0_wp, min(1.0_wp, (t - jc%t_room)/(jc%t_melt - jc%t_room)))
    f = 1.0_wp - ts**jc%m
  end function thermal_factor

  !> sigma_y(eps_p, rate, t) (module notes).
  pure real(wp) function jc_flow(jc, eps_p, rate, t) result(sy)
    type(jc_flow_t), intent(in) :: jc
    real(wp), intent(in) :: eps_p, rate, t
    sy = (jc%a + jc%b*max(eps_p, 0.0_wp)**jc%n)*rate_factor(jc, rate)*thermal_factor(jc, t)
  end function jc_flow

  !> sigma_y (`jc_flow`) with its slopes in one evaluation (each power and
  !> logarithm once, the same expressions), at the thermal factor tf
  !> (`thermal_factor` of the temperature, which a return holds fixed: its
  !> caller takes it once): h = d sigma_y/d eps_p at max(eps_p, eps_floor)
  !> (module notes), hr = d sigma_y/d rate = (A + B eps_p^n) C/rate (1 -
  !> T*^m) above eps0, 0 below.
  pure subroutine jc_flow_slopes(jc, eps_p, rate, tf, sy, h, hr)
    type(jc_flow_t), intent(in) :: jc
    real(wp), intent(in) :: eps_p, rate, tf
    real(wp), intent(out) :: sy, h, hr
    real(wp) :: hard, rf
    hard = jc%a + jc%b*max(eps_p, 0.0_wp)**jc%n
    rf = rate_factor(jc, rate)
    sy = hard*rf*tf
    h = jc%b*jc%n*max(eps_p, eps_floor)**(jc%n - 1.0_wp)*rf*tf
    hr = 0.0_wp
    if (rate > jc%eps0) hr = hard*jc%c/rate*tf
  end subroutine jc_flow_slopes
end module strength_jc_flow
