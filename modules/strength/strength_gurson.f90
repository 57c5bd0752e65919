!> The Gurson-Tvergaard-Needleman porous-plasticity model with the TEPLA-F
!> failure criterion (PARTICLES.md §2.4), for the 1045 steel shell of the
!> paper (Sect. 7.6, Table 5).
!>
!> Yield (Cauchy stress, sigma_M the matrix flow stress, Johnson-Cook from
!> `strength_jc_flow`, at the matrix plastic strain eps_M and its rate):
!>   Phi = (q/sigma_M)^2 + 2 q1 f* cosh(3 q2 sigma_m/(2 sigma_M)) - (1 + q3 f*^2),
!>   q3 = q1^2, f* = f (f <= f_c), f_c + (1/q1 - f_c)/(f_F - f_c) (f - f_c) above;
!> sigma_m the mean stress (tension positive), q the von Mises stress.
!> Porosity: growth df = (1 - f) tr(deps_p), integrated exactly over a step
!> (1 - f = (1 - f_n) exp(-tr deps_p)), and strain-controlled nucleation
!> (Chu-Needleman) df = A(eps_M) deps_M, A the normal density f_N/(s_N
!> sqrt(2 pi)) exp(-((eps_M - eps_N)/s_N)^2/2), integrated exactly (the erf
!> of the step's end points). Matrix work equivalence: (1 - f) sigma_M
!> deps_M = sigma : deps_p.
!>
!> Returns (the model's k decides which):
!>  - own bulk modulus (k > 0, eos = 'none'): the full pressure-dependent
!>    return (Aravas type). Unknowns the volumetric and deviatoric plastic
!>    increments dv, dq: sigma_m = sigma_m* - K dv, q = q* - 3G dq, the
!>    deviator radial; yield Phi = 0 and normality dv dPhi/dq - dq
!>    dPhi/dsigma_m = 0 with f and eps_M updated inside. The 2x2 system is
!>    reduced to one bracketed scalar equation: for a mean stress sigma_m
!>    (so dv), Phi = 0 is solved for q together with the matrix work
!>    equivalence (a bracketed scalar solve for deps_M, giving f and
!>    sigma_M); the normality residual of that state changes sign between
!>    sigma_m = 0 and sigma_m = sigma_m* (the normal's volumetric part has
!>    the sign of sigma_m), and an Illinois false position with bisection
!>    every third step finds the root in that bracket: no divergence, any
!>    increment. Beyond the hydrostatic apex (no q carries that sigma_m) the
!>    residual is continued linearly, so the apex itself is found for pure
!>    hydrostatic loading. cosh/sinh arguments are clamped at |x| <= 30.
!>  - EOS pressure (k = 0, eos = 'mie_gruneisen'; PARTICLES.md §2.4 (a)):
!>    the mean stress is -pt%p; the deviator returns radially to the Gurson
!>    effective stress q_y = sigma_M sqrt(1 + q3 f*^2 - 2 q1 f* cosh(x)) at
!>    that pressure, with the same bracketed solve for deps_M, and the
!>    porosity grows from the volumetric strain while plastic, less its
!>    elastic part (sigma_m - sigma_m^n)/kv with kv the solid's reference
!>    bulk modulus (rho0 c0^2 or from E, nu; kv = 0: the total strain, as
!>    PARTICLES.md §2.4 (a) writes it; with the total strain the elastic
!>    compression of a 20 kbar wave, ~2 %, closes a 0.5 % porosity). A
!>    pressure beyond the apex (q_y undefined) cannot be carried: the
!>    particle fails; a compression beyond it (at the start or at the end
!>    of the step) crushes the voids (f = 0 and no nucleation in that step,
!>    the dense matrix until a tension grows voids again: a detonation-driven shell sees tens of
!>    sigma_M, and the symmetric cosh would otherwise leave it no strength).
!>
!> TEPLA-F: the particle fails when D = (f/f_c)^2 + (eps_M/eps_f)^2 >= 1
!> (eps_f = failure_strain; 0 leaves out the strain term). From then on its
!> deviator is 0 and it carries no tension (own K: sigma_m = min(sigma_m,
!> 0); with an EOS the caller clips the pressure); pt%eroded is the elastic
!> energy per unit volume of the removed stress, s:s/(4G) plus, with own
!> K, sigma_m^2/(2K) of removed tension.
!>
!> History: hist(1) eps_M ('plastic_strain'), hist(2) f ('porosity'),
!> hist(3) the initial f0 of the particle (restarts, outputs), hist(4) the
!> failed flag (0 or 1); 'damage' is D capped at 1.
module strength_gurson
  use base_kinds, only: wp
  use strength_models, only: strength_t, strength_point_t, strength_trial, strength_mises
  use strength_jc_flow, only: jc_flow_t, jc_flow
  implicit none
  private
  public :: strength_gurson_t, gurson_yield, gurson_fstar, gurson_tepla, gurson_nucleated

  !> History slots (module notes).
  integer, parameter, public :: gtn_eps = 1, gtn_f = 2, gtn_f0 = 3, gtn_failed = 4
  !> Largest |cosh argument| (GursonYield.cc's clamp).
  real(wp), parameter :: x_max = 30.0_wp
  !> Iteration caps of the bracketed solves.
  integer, parameter :: max_iter = 300

  !> The model (module notes); k, g from strength_t.
  type, extends(strength_t) :: strength_gurson_t
    type(jc_flow_t) :: jc             !< matrix flow stress
    real(wp) :: q1 = 1.5_wp, q2 = 1.0_wp
    real(wp) :: fn = 0.0_wp           !< nucleation: volume fraction f_N
    real(wp) :: epsn = 0.3_wp         !< nucleation: mean strain eps_N
    real(wp) :: sn = 0.1_wp           !< nucleation: standard deviation s_N
    real(wp) :: fc = 0.15_wp          !< coalescence / TEPLA-F porosity f_c
    real(wp) :: ff = 0.25_wp          !< final porosity f_F (> f_c)
    real(wp) :: eps_f = 0.0_wp        !< TEPLA-F failure strain (0: no strain term)
    real(wp) :: f0 = 0.0_wp           !< initial porosity (hist_init)
    real(wp) :: kv = 0.0_wp           !< EOS path: bulk modulus of the elastic volumetric strain (0: none)
  contains
    procedure :: update => gurson_update
    procedure :: nhist => gurson_nhist
    procedure :: hist_init => gurson_hist_init
    procedure :: field => gurson_field
    procedure :: failed => gurson_failed
  end type strength_gurson_t

contains

  pure integer function gurson_nhist(this) result(n)
    class(strength_gurson_t), intent(in) :: this
    n = 4
    if (this%g < 0.0_wp) n = 4   ! (this unused)
  end function gurson_nhist

  !> eps_M = 0, f = f0 = this%f0, not failed.
  pure subroutine gurson_hist_init(this, hist)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(inout) :: hist(:)
    hist = 0.0_wp
    hist(gtn_f) = this%f0
    hist(gtn_f0) = this%f0
  end subroutine gurson_hist_init

  pure real(wp) function gurson_field(this, name, hist) result(v)
    class(strength_gurson_t), intent(in) :: this
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: hist(:)
    select case (name)
    case ('plastic_strain')
      v = hist(gtn_eps)
    case ('porosity')
      v = hist(gtn_f)
    case ('damage')
      v = min(1.0_wp, gurson_tepla(this, hist(gtn_f), hist(gtn_eps)))
    case default
      v = 0.0_wp
    end select
  end function gurson_field

  pure logical function gurson_failed(this, hist) result(f)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: hist(:)
    f = hist(gtn_failed) > 0.5_wp
    if (this%g < 0.0_wp) f = .false.   ! (this unused)
  end function gurson_failed

  !> The TEPLA-F value (f/f_c)^2 + (eps_M/eps_f)^2 (no strain term if
  !> eps_f = 0).
  pure real(wp) function gurson_tepla(this, f, eps) result(d)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: f, eps
    d = (f/this%fc)**2
    if (this%eps_f > 0.0_wp) d = d + (eps/this%eps_f)**2
  end function gurson_tepla

  !> The effective porosity f* (coalescence, module notes).
  pure real(wp) function gurson_fstar(this, f) result(fs)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: f
    fs = f
    if (f > this%fc) fs = this%fc + (1.0_wp/this%q1 - this%fc)/(this%ff - this%fc)*(f - this%fc)
    fs = min(fs, 1.0_wp/this%q1)
  end function gurson_fstar

  !> Phi(q, sm, f*, sigma_M) (module notes).
  pure real(wp) function gurson_yield(this, q, sm, fs, sy) result(phi)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: q, sm, fs, sy
    phi = (q/sy)**2 + 2.0_wp*this%q1*fs*cosh(xarg(this, sm, sy)) - (1.0_wp + this%q1**2*fs**2)
  end function gurson_yield

  !> The porosity nucleated (Chu-Needleman, strain controlled) from eps_M
  !> = 0 to eps: f_N/2 [erf((eps - eps_N)/(sqrt2 s_N)) + erf(eps_N/(sqrt2 s_N))].
  pure real(wp) function gurson_nucleated(this, eps) result(df)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: eps
    df = 0.0_wp
    if (this%fn > 0.0_wp .and. this%sn > 0.0_wp) &
      df = 0.5_wp*this%fn*(erf((eps - this%epsn)/(sqrt(2.0_wp)*this%sn)) + erf(this%epsn/(sqrt(2.0_wp)*this%sn)))
  end function gurson_nucleated

  !> 3 q2 sm/(2 sigma_M), clamped (module notes).
  pure real(wp) function xarg(this, sm, sy) result(x)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: sm, sy
    x = max(-x_max, min(x_max, 1.5_wp*this%q2*sm/sy))
  end function xarg

  !> The mean stress of the hydrostatic apex (q = 0 carries it) at f*,
  !> sigma_M, on the side of sign_of (0 if f* = 0: no apex).
  pure real(wp) function apex(this, fs, sy, sign_of) result(sa)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: fs, sy, sign_of
    real(wp) :: u
    sa = 0.0_wp
    if (.not. fs > 0.0_wp) return
    u = (1.0_wp + this%q1**2*fs**2)/(2.0_wp*this%q1*fs)
    sa = sign(min(x_max, acosh(max(u, 1.0_wp))), sign_of)*2.0_wp*sy/(3.0_wp*this%q2)
  end function apex

  !> The state at the end of a plastic step for a given mean stress sm and
  !> plastic volumetric increment dv (module notes): the matrix increment
  !> dm from (1 - f) sigma_M dm = q dq + sm dv with q on the yield surface
  !> (q = sigma_M sqrt(rad), 0 beyond the apex: rad <= 0), dq = (q* -
  !> q)/(3G), f from growth and nucleation; a bracketed scalar solve on dm
  !> (the left side grows with dm, the right side is bounded).
  pure subroutine matrix_state(this, sm, dv, qs, eps_n, f_n, dt, dm, f, sy, q, rad)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: sm, dv, qs, eps_n, f_n, dt
    real(wp), intent(out) :: dm, f, sy, q, rad
    real(wp) :: a, b, ga, gb, c, gc, nuc_n
    integer :: it, side
    nuc_n = gurson_nucleated(this, eps_n)
    a = 0.0_wp
    call work_residual(this, a, sm, dv, qs, eps_n, f_n, nuc_n, dt, ga, f, sy, q, rad)
    if (.not. ga < 0.0_wp) then
      dm = 0.0_wp
      return
    end if
    ! an upper end: W <= q*^2/(12G) + |sm dv|, (1 - f) sigma_M >= (1 - f_max) sigma_M(eps_n)
    b = max(4.0_wp*(qs**2/(12.0_wp*this%g) + abs(sm*dv))/jc_flow(this%jc, eps_n, 0.0_wp, 0.0_wp), &
            1.0e-14_wp)
    call work_residual(this, b, sm, dv, qs, eps_n, f_n, nuc_n, dt, gb, f, sy, q, rad)
    do it = 1, 200
      if (gb > 0.0_wp) exit
      a = b
      ga = gb
      b = 4.0_wp*b
      call work_residual(this, b, sm, dv, qs, eps_n, f_n, nuc_n, dt, gb, f, sy, q, rad)
    end do
    side = 0
    c = b
    do it = 1, max_iter
      if (mod(it, 3) == 0) then
        c = 0.5_wp*(a + b)
      else
        c = b - gb*(b - a)/(gb - ga)
        if (.not. (c > min(a, b) .and. c < max(a, b))) c = 0.5_wp*(a + b)
      end if
      call work_residual(this, c, sm, dv, qs, eps_n, f_n, nuc_n, dt, gc, f, sy, q, rad)
      if (.not. abs(gc) > 0.0_wp) exit
      if (gc < 0.0_wp) then
        a = c
        ga = gc
        if (side == -1) gb = 0.5_wp*gb
        side = -1
      else
        b = c
        gb = gc
        if (side == 1) ga = 0.5_wp*ga
        side = 1
      end if
      if (b - a <= 4.0_wp*epsilon(1.0_wp)*b) exit
    end do
    dm = c
    call work_residual(this, dm, sm, dv, qs, eps_n, f_n, nuc_n, dt, gc, f, sy, q, rad)
  end subroutine matrix_state

  !> The work-equivalence residual g = (1 - f) sigma_M x - (q dq + sm dv)
  !> at the matrix increment x, and the state there (matrix_state; nuc_n
  !> the porosity nucleated up to eps_n).
  pure subroutine work_residual(this, x, sm, dv, qs, eps_n, f_n, nuc_n, dt, g, f, sy, q, rad)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: x, sm, dv, qs, eps_n, f_n, nuc_n, dt
    real(wp), intent(out) :: g, f, sy, q, rad
    real(wp) :: fs, rate, w
    f = 1.0_wp - (1.0_wp - f_n)*exp(-dv) + gurson_nucleated(this, eps_n + x) - nuc_n
    f = max(0.0_wp, min(f, this%ff))
    rate = 0.0_wp
    if (dt > 0.0_wp) rate = x/dt
    sy = jc_flow(this%jc, eps_n + x, rate, 0.0_wp)
    fs = gurson_fstar(this, f)
    rad = 1.0_wp + this%q1**2*fs**2 - 2.0_wp*this%q1*fs*cosh(xarg(this, sm, sy))
    q = sy*sqrt(max(rad, 0.0_wp))
    w = q*(qs - q)/(3.0_wp*this%g) + sm*dv
    g = (1.0_wp - f)*sy*x - w
  end subroutine work_residual

  !> One particle's step (module notes).
  pure subroutine gurson_update(this, deps, dw, pt, stress, hist)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: deps(3, 3), dw(3, 3)
    type(strength_point_t), intent(inout) :: pt
    real(wp), intent(inout) :: stress(6), hist(:)
    real(wp) :: s(6), sm, sm_n, qs, sy0, fs, tr, dv, dm, f, sy, q, rad, f_in
    logical :: fail, crushed
    type(strength_gurson_t) :: dense
    pt%eroded = 0.0_wp
    sm_n = (stress(1) + stress(2) + stress(3))/3.0_wp
    call strength_trial(this%k, this%g, deps, dw, stress)
    sm = (stress(1) + stress(2) + stress(3))/3.0_wp
    s = stress
    s(1:3) = s(1:3) - sm
    qs = strength_mises(s)
    ! own K: sm is the trial mean stress; with an EOS the caller's pressure
    if (.not. this%k > 0.0_wp) sm = -pt%p
    if (hist(gtn_failed) > 0.5_wp) then
      ! failed: no shear, no tension (with an EOS the caller sets and clips p)
      stress(4:6) = 0.0_wp
      if (this%k > 0.0_wp) then
        stress(1:3) = min(sm, 0.0_wp)
      else
        stress(1:3) = sm_n
      end if
      return
    end if
    tr = deps(1, 1) + deps(2, 2) + deps(3, 3)
    fs = gurson_fstar(this, hist(gtn_f))
    sy0 = jc_flow(this%jc, hist(gtn_eps), 0.0_wp, 0.0_wp)
    fail = .false.
    if (gurson_yield(this, qs, sm, fs, sy0) > 0.0_wp) then
      if (this%k > 0.0_wp) then
        call aravas_return(this, sm, qs, tr, sm_n, hist(gtn_eps), hist(gtn_f), pt%dt, dv, dm, f, sy, q, rad)
      else
        ! (a): the deviator at the EOS pressure, growth from the volumetric strain less
        ! its elastic part (the EOS pressure's change over kv)
        dv = tr
        if (this%kv > 0.0_wp) dv = tr - (sm - sm_n)/this%kv
        f_in = hist(gtn_f)
        crushed = sm < 0.0_wp .and. .not. 1.0_wp + this%q1**2*fs**2 - 2.0_wp*this%q1*fs*cosh(xarg(this, sm, sy0)) &
                  > 0.0_wp
        if (.not. crushed) then
          call matrix_state(this, sm, dv, qs, hist(gtn_eps), f_in, pt%dt, dm, f, sy, q, rad)
          ! a tension beyond the apex cannot be carried; a compression crushes the voids
          fail = sm > 0.0_wp .and. .not. rad > 0.0_wp
          crushed = sm <= 0.0_wp .and. .not. rad > 0.0_wp
        end if
        if (crushed) then
          ! the dense matrix's J2 return: no voids, none nucleated in this step
          dense = this
          dense%fn = 0.0_wp
          f_in = 0.0_wp
          dv = 0.0_wp
          call matrix_state(dense, sm, dv, qs, hist(gtn_eps), f_in, pt%dt, dm, f, sy, q, rad)
        end if
      end if
      ! the return only shrinks the deviator (near the apex q = sigma_M sqrt(rad) is
      ! the square root of round-off and may exceed a round-off qs); trace-free
      if (qs > 0.0_wp) then
        s = s*min(1.0_wp, q/qs)
        s(1:3) = s(1:3) - (s(1) + s(2) + s(3))/3.0_wp
      else
        s = 0.0_wp
      end if
      hist(gtn_eps) = hist(gtn_eps) + dm
      hist(gtn_f) = f
    end if
    fail = fail .or. gurson_tepla(this, hist(gtn_f), hist(gtn_eps)) >= 1.0_wp
    if (fail) then
      hist(gtn_failed) = 1.0_wp
      pt%eroded = (s(1)**2 + s(2)**2 + s(3)**2 + 2.0_wp*(s(4)**2 + s(5)**2 + s(6)**2))/(4.0_wp*this%g)
      s = 0.0_wp
      if (this%k > 0.0_wp .and. sm > 0.0_wp) then
        pt%eroded = pt%eroded + sm**2/(2.0_wp*this%k)
        sm = 0.0_wp
      end if
    end if
    stress = s
    if (this%k > 0.0_wp) then
      stress(1:3) = stress(1:3) + sm
    else
      ! with an EOS the mean stress is the caller's: keep the trial's (the rotation kept it)
      stress(1:3) = stress(1:3) + sm_n
    end if
  end subroutine gurson_update

  !> The full pressure-dependent return (module notes): the mean stress sm
  !> in [0, sm*] (or [sm*, 0]) where the normality residual vanishes, and
  !> the state there (matrix_state). sm: in the trial mean stress, out the
  !> returned one; tr the step's volumetric strain, sm_n the mean stress at
  !> the start of the step (dv = tr + (sm_n - sm)/K without cancellation).
  pure subroutine aravas_return(this, sm, qs, tr, sm_n, eps_n, f_n, dt, dv, dm, f, sy, q, rad)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(inout) :: sm
    real(wp), intent(in) :: qs, tr, sm_n, eps_n, f_n, dt
    real(wp), intent(out) :: dv, dm, f, sy, q, rad
    real(wp) :: a, b, ra, rb, c, rc, sms
    integer :: it, side
    sms = sm
    if (.not. (f_n > 0.0_wp .or. this%fn > 0.0_wp)) then
      ! no voids and none to nucleate: J2 (normality gives dv = 0 exactly; round-off
      ! would seed a porosity that the cosh term then grows)
      dv = 0.0_wp
      call matrix_state(this, sm, dv, qs, eps_n, f_n, dt, dm, f, sy, q, rad)
      return
    end if
    a = 0.0_wp
    call normality(this, a, qs, tr, sm_n, eps_n, f_n, dt, ra, dv, dm, f, sy, q, rad)
    if (.not. abs(ra) > 0.0_wp) then
      sm = a
      return
    end if
    b = sms
    call normality(this, b, qs, tr, sm_n, eps_n, f_n, dt, rb, dv, dm, f, sy, q, rad)
    if (.not. (abs(rb) > 0.0_wp .and. ra*rb < 0.0_wp)) then
      ! (no sign change: only round-off at f* = 0 or sm* = 0; the trial's mean stress)
      sm = b
      return
    end if
    side = 0
    c = b
    do it = 1, max_iter
      if (mod(it, 3) == 0) then
        c = 0.5_wp*(a + b)
      else
        c = b - rb*(b - a)/(rb - ra)
        if (.not. (c > min(a, b) .and. c < max(a, b))) c = 0.5_wp*(a + b)
      end if
      call normality(this, c, qs, tr, sm_n, eps_n, f_n, dt, rc, dv, dm, f, sy, q, rad)
      if (.not. abs(rc) > 0.0_wp) exit
      if (sign(1.0_wp, rc) > 0.0_wp .eqv. sign(1.0_wp, ra) > 0.0_wp) then
        a = c
        ra = rc
        if (side == -1) rb = 0.5_wp*rb
        side = -1
      else
        b = c
        rb = rc
        if (side == 1) ra = 0.5_wp*ra
        side = 1
      end if
      if (abs(b - a) <= 4.0_wp*epsilon(1.0_wp)*max(abs(a), abs(b))) exit
    end do
    sm = c
    call normality(this, c, qs, tr, sm_n, eps_n, f_n, dt, rc, dv, dm, f, sy, q, rad)
  end subroutine aravas_return

  !> The normality residual r = dv dPhi/dq - dq dPhi/dsm (times sigma_M)
  !> of the state at mean stress x (aravas_return), continued linearly
  !> beyond the apex, and that state.
  pure subroutine normality(this, x, qs, tr, sm_n, eps_n, f_n, dt, r, dv, dm, f, sy, q, rad)
    class(strength_gurson_t), intent(in) :: this
    real(wp), intent(in) :: x, qs, tr, sm_n, eps_n, f_n, dt
    real(wp), intent(out) :: r, dv, dm, f, sy, q, rad
    real(wp) :: fs, dq, sa
    dv = tr + (sm_n - x)/this%k
    call matrix_state(this, x, dv, qs, eps_n, f_n, dt, dm, f, sy, q, rad)
    fs = gurson_fstar(this, f)
    dq = (qs - q)/(3.0_wp*this%g)
    if (rad > 0.0_wp) then
      r = dv*2.0_wp*q/sy - dq*3.0_wp*this%q1*this%q2*fs*sinh(xarg(this, x, sy))
    else
      sa = apex(this, fs, sy, x)
      r = -dq*3.0_wp*this%q1*this%q2*fs*sinh(xarg(this, sa, sy)) - (x - sa)/this%k
    end if
  end subroutine normality
end module strength_gurson
