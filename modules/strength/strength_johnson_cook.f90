!> The Johnson-Cook strength model (paper Eq. 59 and its full form with
!> thermal softening and plastic heating; PARTICLES.md §2.3): hypoelastic
!> trial (`strength_trial`, §2.0 steps 1-3), then a radial return of the
!> deviator onto the flow stress of `strength_jc_flow`,
!>   sigma_y = (A + B eps_p^n) (1 + C ln max(eps_dot_p/eps_dot0, 1)) (1 - T*^m).
!>
!> The return solves for the plastic increment dp of the step
!>   g(dp) = q* - 3G dp - sigma_y(eps_p + dp, dp/dt, T) = 0,
!> q* the trial von Mises stress. g is continuous and strictly decreasing
!> (sigma_y grows with eps_p and with the rate), g(0) = q* - sigma_y(eps_p,
!> 0, T) > 0 when the trial is plastic, and g(q*/(3G)) = -sigma_y <= 0, so
!> the root is bracketed in [0, q*/(3G)]; the perfectly plastic estimate
!> dp0 = g(0)/(3G) is a tighter upper end (g(dp0) = sigma_y(eps_p, 0) -
!> sigma_y(eps_p + dp0, dp0/dt) <= 0). A scalar Newton with
!>   g' = -3G - d sigma_y/d eps_p - (1/dt) d sigma_y/d eps_dot
!> runs inside the bracket, which every evaluation shrinks; a step that
!> would leave it is replaced by bisection (the slope is infinite at eps_p
!> = 0 for n < 1 and the rate slope C/rate is infinite at rate 0+, so
!> Newton alone cannot be trusted near dp = 0; `jc_flow_slopes` evaluates the
!> strain slope at a floor, never dividing by zero). A trial with g(0) <=
!> tol q* is elastic (dp = 0). Converged when |g| <=
!> tol q* (tol = 1e-12), the bracket is a few ulps wide, or its upper end
!> is below 1e-30: the root then is a plastic strain increment of no
!> consequence (for n << 1 it may lie below the smallest representable
!> number: B dp^0.01 is still 0.19 B at dp = 5e-324), and the step is
!> taken as elastic (dp = 0, the trial a hair above the flow stress stays,
!> as with g(0) <= tol q*). While the bracket
!> spans more than three decades the fallback is its geometric midpoint,
!> so a tiny root is reached in tens of steps, not thousands. The rate guard
!> (rates below eps_dot0 give factor 1) is `jc_flow`'s.
!>
!> Temperature (hist(2), initially T_room): the flow stress of a step is
!> taken at the temperature at its start (explicit in T), then plastic
!> heating Delta T = chi sigma_y Delta eps_p/(rho c_p) with rho the density
!> at the end of the step (pt%rho), chi the Taylor-Quinney coefficient and
!> c_p the specific heat; c_p = 0 means no heating (T stays T_room). The
!> plastic work itself is already in the particle's internal energy (the
!> stress work of `particles_lagrange`): T is the model's own state.
!> hist(1) is the equivalent plastic strain. With an EOS (k = 0) the trial
!> keeps the mean stress and the caller sets the pressure.
module strength_johnson_cook
  use base_kinds, only: wp
  use strength_models, only: strength_t, strength_point_t, strength_trial, strength_mises
  use strength_jc_flow, only: jc_flow_t, jc_flow, jc_flow_slopes, thermal_factor
  implicit none
  private
  public :: strength_johnson_cook_t, jc_return, jc_tol

  !> Relative tolerance of the return on g (times q*).
  real(wp), parameter :: jc_tol = 1.0e-12_wp
  !> Most iterations of the return (bisection alone halves a bracket of
  !> relative width 1 to 1e-16 in 54).
  integer, parameter :: max_iter = 200
  !> Plastic increments below this are zero: a root below it (n << 1 and a
  !> trial a hair above the flow stress: dp = (r/B)^(1/n) may not even be
  !> representable) ends the iteration with the bracket [0, dp_floor].
  real(wp), parameter :: dp_floor = 1.0e-30_wp

  !> Johnson-Cook: the flow stress, the Taylor-Quinney coefficient chi and
  !> the specific heat cp (energy per mass and temperature; 0: no heating).
  type, extends(strength_t) :: strength_johnson_cook_t
    type(jc_flow_t) :: jc
    real(wp) :: chi = 0.9_wp
    real(wp) :: cp = 0.0_wp
  contains
    procedure :: update => jc_update
    procedure :: nhist => jc_nhist
    procedure :: hist_init => jc_hist_init
    procedure :: field => jc_field
  end type strength_johnson_cook_t

contains

  !> Two history variables: eps_p and T.
  pure integer function jc_nhist(this) result(n)
    class(strength_johnson_cook_t), intent(in) :: this
    n = 2
    if (this%g < 0.0_wp) n = 2   ! (this unused)
  end function jc_nhist

  !> eps_p = 0, T = T_room.
  pure subroutine jc_hist_init(this, hist)
    class(strength_johnson_cook_t), intent(in) :: this
    real(wp), intent(inout) :: hist(:)
    hist = 0.0_wp
    hist(2) = this%jc%t_room
  end subroutine jc_hist_init

  !> 'plastic_strain' (hist(1)) and 'temperature' (hist(2)); 0 otherwise.
  pure real(wp) function jc_field(this, name, hist) result(v)
    class(strength_johnson_cook_t), intent(in) :: this
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: hist(:)
    v = 0.0_wp
    select case (name)
    case ('plastic_strain')
      v = hist(1)
    case ('temperature')
      v = hist(2)
    end select
    if (this%g < 0.0_wp) v = 0.0_wp   ! (this unused)
  end function jc_field

  !> The return of the module notes: the plastic increment dp >= 0 of a
  !> trial von Mises stress q (pressure) for shear modulus g, plastic strain
  !> eps_p, step dt (time; dt <= 0: rate-independent) and temperature t;
  !> iters the evaluations used, ok false if the iteration did not converge
  !> (dp is then the bracket's midpoint). dp = 0 if q is not above the flow
  !> stress.
  pure subroutine jc_return(jc, g, q, eps_p, dt, t, dp, iters, ok)
    type(jc_flow_t), intent(in) :: jc
    real(wp), intent(in) :: g, q, eps_p, dt, t
    real(wp), intent(out) :: dp
    integer, intent(out) :: iters
    logical, intent(out) :: ok
    real(wp) :: lo, hi, r, dr, step, trial, tf
    iters = 0
    ok = .true.
    dp = 0.0_wp
    r = q - jc_flow(jc, eps_p, 0.0_wp, t)
    if (.not. r > jc_tol*q) return
    tf = thermal_factor(jc, t)
    lo = 0.0_wp
    ! the perfectly plastic estimate, an upper end (module notes)
    hi = min(r/(3.0_wp*g), q/(3.0_wp*g))
    dp = hi
    ok = .false.
    do iters = 1, max_iter
      call residual(dp, r, dr)
      if (abs(r) <= jc_tol*q) then
        ok = .true.
        exit
      end if
      if (r > 0.0_wp) then
        lo = dp
      else
        hi = dp
      end if
      if (hi - lo <= 4.0_wp*epsilon(1.0_wp)*hi) then
        ok = .true.
        exit
      end if
      if (hi <= dp_floor) then
        ! (the root is below the floor: no plastic increment; lo is 0 then)
        dp = lo
        ok = .true.
        exit
      end if
      ! Newton inside the bracket, else bisection (dr < 0 always), geometric
      ! while the bracket spans orders of magnitude (a root far below hi)
      step = -r/dr
      trial = dp + step
      if (trial > lo .and. trial < hi) then
        dp = trial
      else if (lo < 1.0e-3_wp*hi) then
        dp = sqrt(max(lo, 0.5_wp*dp_floor))*sqrt(hi)
      else
        dp = 0.5_wp*(lo + hi)
      end if
    end do
    if (.not. ok) dp = 0.5_wp*(lo + hi)
  contains
    !> g(x) and g'(x) (module notes).
    pure subroutine residual(x, gx, dgx)
      real(wp), intent(in) :: x
      real(wp), intent(out) :: gx, dgx
      real(wp) :: rate, sy, h, hr
      rate = 0.0_wp
      if (dt > 0.0_wp) rate = x/dt
      call jc_flow_slopes(jc, eps_p + x, rate, tf, sy, h, hr)
      gx = q - 3.0_wp*g*x - sy
      dgx = -3.0_wp*g - h
      if (dt > 0.0_wp) dgx = dgx - hr/dt
    end subroutine residual
  end subroutine jc_return

  !> The update (module notes): trial, return, heating.
  pure subroutine jc_update(this, deps, dw, pt, stress, hist)
    class(strength_johnson_cook_t), intent(in) :: this
    real(wp), intent(in) :: deps(3, 3), dw(3, 3)
    type(strength_point_t), intent(inout) :: pt
    real(wp), intent(inout) :: stress(6), hist(:)
    real(wp) :: s(6), p, q, dp, rate
    integer :: iters
    logical :: ok
    call strength_trial(this%k, this%g, deps, dw, stress)
    pt%eroded = 0.0_wp
    p = (stress(1) + stress(2) + stress(3))/3.0_wp
    s = stress
    s(1:3) = s(1:3) - p
    q = strength_mises(s)
    call jc_return(this%jc, this%g, q, hist(1), pt%dt, hist(2), dp, iters, ok)
    if (.not. dp > 0.0_wp) return
    ! (not converged: the bracket's midpoint, within a few ulps of the root
    ! after max_iter halvings; the radial scaling stays in [0, 1])
    s = s*max(0.0_wp, 1.0_wp - 3.0_wp*this%g*dp/q)
    stress = s
    stress(1:3) = stress(1:3) + p
    hist(1) = hist(1) + dp
    ! plastic heating with the flow stress at the root (T of the step's start)
    if (this%cp > 0.0_wp .and. pt%rho > 0.0_wp) then
      rate = 0.0_wp
      if (pt%dt > 0.0_wp) rate = dp/pt%dt
      hist(2) = hist(2) + this%chi*jc_flow(this%jc, hist(1), rate, hist(2))*dp/(pt%rho*this%cp)
    end if
  end subroutine jc_update
end module strength_johnson_cook
