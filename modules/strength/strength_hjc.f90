!> The Holmquist-Johnson-Cook concrete model (Holmquist, Johnson & Cook
!> 1993; PARTICLES.md §2.5): a compaction equation of state with unloading,
!> a pressure-, rate- and damage-dependent strength and a damage sum. The
!> model owns its pressure: a solid with strength = 'hjc' has eos = 'none'
!> and no bulk_modulus (the deck refuses both others).
!>
!> Equation of state (mu = rho/rho0 - 1 from the end-of-step density pt%rho
!> and the model's rho0), loading curve:
!>  I   mu <= mu_crush: p = K_e mu, K_e = p_crush/mu_crush;
!>  II  mu_crush < mu <= mu_plock: p = p_crush + (p_lock - p_crush)
!>      (mu - mu_crush)/(mu_plock - mu_crush);
!>  III mu > mu_plock: p = K1 mubar + K2 mubar^2 + K3 mubar^3, mubar =
!>      (mu - mu_lock)/(1 + mu_lock),
!> with mu_plock > mu_lock where region III reaches p_lock (solved once, by
!> bisection, when the model is built), so that the curve is continuous.
!> Unloading and reloading below the largest compression reached (mu_max,
!> p_max, both in the history) follow the straight line p = p_max + K_u
!> (mu - mu_max), K_u = K_e (I), (1 - F) K_e + F K1 with F = (mu_max -
!> mu_crush)/(mu_plock - mu_crush) (II), K1 (III); the slope K1 of region
!> III is taken in mu (dp/dmu = K1, the region-II slope at F = 1, so that
!> the unloading slope is continuous; the 1993 paper writes p = K1 mubar,
!> which would be K1/(1 + mu_lock) in mu). The permanent compaction mu_p =
!> mu_max - p_max/K_u (the strain of the unloading line at p = 0; 0 in
!> region I) grows only while loading; its increments Delta mu_p feed the
!> damage. Tension: p >= -T (1 - D) (the curve is cut there; no tensile
!> plastic strain is booked, so a particle recompressed from beyond the cut
!> keeps the limit until it is back on its line: for D = 1 that is an open
!> crack closing without resistance).
!>
!> Strength (normalised by f'_c; P* = p/f'_c, T* = T/f'_c, eps_dot* the
!> equivalent deviatoric strain rate sqrt(2/3 de:de)/dt over eps_dot0):
!>   sigma* = min([A (1 - D) + B P*^N] R, S_max)     (P* >= 0),
!>   sigma* = A (1 + p/T) (1 - D) R                    (P* < 0),
!> R = 1 + C ln max(eps_dot*, 1) (rates below eps_dot0 do not soften below
!> the static surface), sigma_y = f'_c sigma*, with D at the start of the
!> step. Perfectly-plastic radial return of the trial deviator at the
!> step's pressure: Delta eps_p = (q* - sigma_y)/(3G), s = s* sigma_y/q*.
!> Damage: D += (Delta eps_p + Delta mu_p)/max(EFMIN, D1 (P* + T*)^D2),
!> clamped to [0, 1], with the end-of-step pressure.
!>
!> Size of the particle (hjc_length = L_ref > 0, the deck's; 0: off): the
!> plastic strain a particle of size l (the cube root of its volume)
!> books towards its damage is Delta eps_p l/L_ref, so that the strain to
!> fracture scales as L_ref/l. A crack or shear band localises in one row
!> of particles whatever their size, and the model's damage has no length
!> of its own: without this a finer particle set breaks at a smaller
!> opening (displacement across the band, eps_f l) and dissipates less
!> energy per unit area of the band; with it the band opens by eps_f L_ref
!> at any l (the crack-band idea of Bazant and Oh 1983, applied here to
!> the damage by plastic strain).
!> The compaction Delta mu_p is a volume change that does not localise and
!> is booked as it is. The damage constants then hold at particles of size
!> L_ref (the size at which the deck takes them to be valid).
!>
!> Failure (what `failed` means here): the particle fails when D = 1 while
!> its pressure is not compressive (p <= 0 at the end of a step): a fully
!> damaged particle in tension is a crack. From then on it carries no
!> tension (p = max(p, 0)) and no shear, also when recompressed (a fully
!> damaged particle under pressure that never went into tension keeps the
!> model's residual strength B P*^N). pt%eroded is the elastic energy per
!> unit volume the failure removes: in the failing step s:s/(4G) + p^2/(2
!> K_u) of its tension (the model's own stress after the return); in later
!> steps that of the step's elastic increment it cannot carry (the trial
!> deviator from zero, and the tension of p^n - K_u tr(deps) if negative).
!>
!> Stable step: the model's k (used by `wave_modulus`, K + 4G/3) is the
!> stiffest slope the equation of state shows on unloading or reloading,
!> max(K1, K_e) (the region-II slope lies between the two); the region-III
!> loading tangent (K1 + 2 K2 mubar + 3 K3 mubar^2)/(1 + mu_lock) stays below
!> K1 for Table 7 up to mubar = 0.6 (mu = 0.76), far beyond concrete.
!>
!> History (`hjc_nhist` = 6): 1 eps_p ('plastic_strain'), 2 D ('damage'),
!> 3 mu_max, 4 p_max, 5 mu_p, 6 failed (0 or 1). Units: the deck's
!> (pressures, density, 1/time for eps_dot0).
module strength_hjc
  use base_kinds, only: wp
  use strength_models, only: strength_t, strength_point_t, strength_params_t, strength_trial, strength_mises
  implicit none
  private
  public :: strength_hjc_t, hjc_new, hjc_load, hjc_unload_modulus, hjc_eos, hjc_flow, hjc_nhist

  !> History variables per particle (module notes).
  integer, parameter :: hjc_nhist = 6

  !> The model (parameters as in the deck, module notes), with the derived
  !> K_e (ke) and mu_plock.
  type, extends(strength_t) :: strength_hjc_t
    real(wp) :: a = 0.0_wp, b = 0.0_wp, n = 1.0_wp, c = 0.0_wp   !< A, B, N, C
    real(wp) :: fc = 0.0_wp        !< f'_c (pressure)
    real(wp) :: smax = 0.0_wp      !< S_max (normalised)
    real(wp) :: t = 0.0_wp         !< T, hydrostatic tensile strength (pressure)
    real(wp) :: d1 = 0.0_wp, d2 = 1.0_wp, efmin = 0.0_wp   !< damage constants
    real(wp) :: pcrush = 0.0_wp, mucrush = 0.0_wp   !< end of region I (pressure, -)
    real(wp) :: plock = 0.0_wp, mulock = 0.0_wp     !< locking pressure and strain
    real(wp) :: k1 = 0.0_wp, k2 = 0.0_wp, k3 = 0.0_wp   !< region III (pressure)
    real(wp) :: eps0 = 1.0_wp      !< reference strain rate (1/time)
    real(wp) :: rho0 = 0.0_wp      !< reference density
    real(wp) :: length = 0.0_wp    !< L_ref, the particle size of the damage constants (0: off)
    real(wp) :: ke = 0.0_wp        !< K_e = p_crush/mu_crush
    real(wp) :: muplock = 0.0_wp   !< mu where region III reaches p_lock
  contains
    procedure :: update => hjc_update
    procedure :: nhist => hjc_nhist_of
    procedure :: field => hjc_field
    procedure :: failed => hjc_failed
  end type strength_hjc_t

contains

  !> The model from par (its g, hjc_* and hjc_rho0); msg is '' or the
  !> first thing wrong with the parameters (module notes).
  pure subroutine hjc_new(par, model, msg)
    type(strength_params_t), intent(in) :: par
    type(strength_hjc_t), intent(out) :: model
    character(len=:), allocatable, intent(out) :: msg
    real(wp) :: lo, hi, mid, mc, slope2
    integer :: it
    msg = ''
    model = strength_hjc_t(g=par%g, a=par%hjc_a, b=par%hjc_b, n=par%hjc_n, c=par%hjc_c, fc=par%hjc_fc, &
      smax=par%hjc_smax, t=par%hjc_t, d1=par%hjc_d1, d2=par%hjc_d2, efmin=par%hjc_efmin, pcrush=par%hjc_pcrush, &
      mucrush=par%hjc_mucrush, plock=par%hjc_plock, mulock=par%hjc_mulock, k1=par%hjc_k1, k2=par%hjc_k2, &
      k3=par%hjc_k3, eps0=par%hjc_eps0, rho0=par%hjc_rho0, length=par%hjc_length, wants_length=par%hjc_length > 0.0_wp)
    associate (m => model)
      if (.not. (m%g > 0.0_wp .and. m%rho0 > 0.0_wp)) msg = 'hjc: the shear modulus and the density must be > 0'
      if (.not. (m%a >= 0.0_wp .and. m%b >= 0.0_wp .and. m%c >= 0.0_wp .and. m%d1 >= 0.0_wp)) &
        msg = 'hjc: hjc_a, hjc_b, hjc_c and hjc_d1 must be >= 0'
      if (.not. (m%n > 0.0_wp .and. m%d2 > 0.0_wp .and. m%efmin > 0.0_wp .and. m%smax > 0.0_wp .and. &
                 m%eps0 > 0.0_wp)) msg = 'hjc: hjc_n, hjc_d2, hjc_efmin, hjc_smax and hjc_eps0 must be > 0'
      if (.not. (m%fc > 0.0_wp .and. m%t > 0.0_wp .and. m%pcrush > 0.0_wp .and. m%mucrush > 0.0_wp .and. &
                 m%k1 > 0.0_wp)) msg = 'hjc: hjc_fc, hjc_t, hjc_pcrush, hjc_mucrush and hjc_k1 must be > 0'
      if (.not. (m%plock > m%pcrush)) msg = 'hjc: hjc_plock must be > hjc_pcrush'
      if (.not. (m%mulock >= 0.0_wp)) msg = 'hjc: hjc_mulock must be >= 0'
      if (.not. (m%length >= 0.0_wp)) msg = 'hjc: hjc_length must be >= 0 (0: off)'
      if (len(msg) > 0) return
      m%ke = m%pcrush/m%mucrush
      ! region III reaches p_lock at mubar in (0, hi): hi the first maximum
      ! of the cubic, or (increasing for ever) doubled until past p_lock
      mc = first_max(m%k1, m%k2, m%k3)
      if (mc > 0.0_wp) then
        hi = mc
        if (cubic(m, hi) < m%plock) then
          msg = 'hjc: the region III polynomial hjc_k1, hjc_k2, hjc_k3 never reaches hjc_plock'
          return
        end if
      else
        hi = m%plock/m%k1
        do it = 1, 2000
          if (cubic(m, hi) >= m%plock) exit
          hi = 2.0_wp*hi
        end do
      end if
      lo = 0.0_wp
      do it = 1, 200
        mid = 0.5_wp*(lo + hi)
        if (cubic(m, mid) < m%plock) then
          lo = mid
        else
          hi = mid
        end if
        if (.not. (hi - lo > 0.0_wp)) exit
      end do
      m%muplock = m%mulock + hi*(1.0_wp + m%mulock)
      if (.not. (m%muplock > m%mucrush)) then
        msg = 'hjc: region III reaches hjc_plock below hjc_mucrush (raise hjc_mulock)'
        return
      end if
      ! the crushing slope must stay below the unloading slopes (else the
      ! permanent compaction would be negative)
      slope2 = (m%plock - m%pcrush)/(m%muplock - m%mucrush)
      if (.not. (slope2 < min(m%ke, m%k1))) then
        msg = 'hjc: the crushing slope (hjc_plock - hjc_pcrush)/(mu_plock - hjc_mucrush) must be below '// &
              'hjc_pcrush/hjc_mucrush and hjc_k1'
        return
      end if
      m%k = max(m%k1, m%ke)
    end associate
  end subroutine hjc_new

  !> The first positive maximum of k1 m + k2 m^2 + k3 m^3 (k1 > 0), or 0 if
  !> the cubic increases for all m > 0.
  pure real(wp) function first_max(k1, k2, k3) result(mc)
    real(wp), intent(in) :: k1, k2, k3
    real(wp) :: disc
    mc = 0.0_wp
    if (abs(k3) > 0.0_wp) then
      ! 3 k3 m^2 + 2 k2 m + k1 = 0
      disc = k2**2 - 3.0_wp*k1*k3
      if (disc < 0.0_wp) return
      if (k3 < 0.0_wp) then
        mc = (-k2 - sqrt(disc))/(3.0_wp*k3)
      else if (k2 < 0.0_wp) then
        mc = (-k2 - sqrt(disc))/(3.0_wp*k3)
      end if
    else if (k2 < 0.0_wp) then
      mc = -k1/(2.0_wp*k2)
    end if
  end function first_max

  !> The region III polynomial at mubar.
  pure real(wp) function cubic(this, mb) result(p)
    type(strength_hjc_t), intent(in) :: this
    real(wp), intent(in) :: mb
    p = mb*(this%k1 + mb*(this%k2 + mb*this%k3))
  end function cubic

  !> The loading curve p(mu) (module notes; pressure).
  pure real(wp) function hjc_load(this, mu) result(p)
    type(strength_hjc_t), intent(in) :: this
    real(wp), intent(in) :: mu
    if (mu <= this%mucrush) then
      p = this%ke*mu
    else if (mu <= this%muplock) then
      p = this%pcrush + (this%plock - this%pcrush)*(mu - this%mucrush)/(this%muplock - this%mucrush)
    else
      p = cubic(this, (mu - this%mulock)/(1.0_wp + this%mulock))
    end if
  end function hjc_load

  !> The unloading/reloading slope dp/dmu below mu_max (module notes).
  pure real(wp) function hjc_unload_modulus(this, mu_max) result(ku)
    type(strength_hjc_t), intent(in) :: this
    real(wp), intent(in) :: mu_max
    real(wp) :: f
    if (mu_max <= this%mucrush) then
      ku = this%ke
    else if (mu_max <= this%muplock) then
      f = (mu_max - this%mucrush)/(this%muplock - this%mucrush)
      ku = (1.0_wp - f)*this%ke + f*this%k1
    else
      ku = this%k1
    end if
  end function hjc_unload_modulus

  !> The pressure p at mu (before the tension cut) and the history
  !> mu_max, p_max (module notes: loading above mu_max, else the unloading
  !> line through (mu_max, p_max)).
  pure subroutine hjc_eos(this, mu, mu_max, p_max, p)
    type(strength_hjc_t), intent(in) :: this
    real(wp), intent(in) :: mu
    real(wp), intent(inout) :: mu_max, p_max
    real(wp), intent(out) :: p
    if (mu > mu_max) then
      mu_max = mu
      p_max = hjc_load(this, mu)
      p = p_max
    else
      p = p_max + hjc_unload_modulus(this, mu_max)*(mu - mu_max)
    end if
  end subroutine hjc_eos

  !> The permanent compaction of the unloading line through (mu_max, p_max).
  pure real(wp) function mu_perm(this, mu_max, p_max) result(mup)
    type(strength_hjc_t), intent(in) :: this
    real(wp), intent(in) :: mu_max, p_max
    mup = 0.0_wp
    if (mu_max > this%mucrush) mup = mu_max - p_max/hjc_unload_modulus(this, mu_max)
  end function mu_perm

  !> The flow stress sigma_y = f'_c sigma* (pressure) at pressure p,
  !> damage d and equivalent strain rate rate (1/time) (module notes).
  pure real(wp) function hjc_flow(this, p, d, rate) result(sy)
    class(strength_hjc_t), intent(in) :: this
    real(wp), intent(in) :: p, d, rate
    real(wp) :: r, ss
    r = 1.0_wp + this%c*log(max(rate/this%eps0, 1.0_wp))
    if (p >= 0.0_wp) then
      ss = min((this%a*(1.0_wp - d) + this%b*(p/this%fc)**this%n)*r, this%smax)
    else
      ss = max(this%a*(1.0_wp + p/this%t)*(1.0_wp - d)*r, 0.0_wp)
    end if
    sy = this%fc*ss
  end function hjc_flow

  !> One step of one particle (module notes).
  pure subroutine hjc_update(this, deps, dw, pt, stress, hist)
    class(strength_hjc_t), intent(in) :: this
    real(wp), intent(in) :: deps(3, 3), dw(3, 3)
    type(strength_point_t), intent(inout) :: pt
    real(wp), intent(inout) :: stress(6), hist(:)
    real(wp) :: s(6), p, p_old, pm, mu, mup, dmup, ku, q, sy, dep, tr, de(6), rate, d, pel
    p_old = -(stress(1) + stress(2) + stress(3))/3.0_wp
    ! the deviator's trial (k = 0: the mean stress is the EOS's, below)
    call strength_trial(0.0_wp, this%g, deps, dw, stress)
    pm = (stress(1) + stress(2) + stress(3))/3.0_wp
    s = stress
    s(1:3) = s(1:3) - pm
    ! the equation of state and the permanent compaction
    mu = pt%rho/this%rho0 - 1.0_wp
    call hjc_eos(this, mu, hist(3), hist(4), p)
    mup = mu_perm(this, hist(3), hist(4))
    dmup = max(mup - hist(5), 0.0_wp)
    hist(5) = max(hist(5), mup)
    ku = hjc_unload_modulus(this, hist(3))
    d = hist(2)
    p = max(p, -this%t*(1.0_wp - d))
    pt%eroded = 0.0_wp
    if (hist(6) > 0.5_wp) then
      ! failed: no shear, no tension (module notes for the energy)
      tr = deps(1, 1) + deps(2, 2) + deps(3, 3)
      pel = p_old - ku*tr
      pt%eroded = strength_mises(s)**2/(6.0_wp*this%g)
      if (pel < 0.0_wp) pt%eroded = pt%eroded + pel**2/(2.0_wp*ku)
      p = max(p, 0.0_wp)
      stress = 0.0_wp
      stress(1:3) = -p
      return
    end if
    ! the equivalent deviatoric strain rate
    rate = 0.0_wp
    if (pt%dt > 0.0_wp) then
      tr = deps(1, 1) + deps(2, 2) + deps(3, 3)
      de = [deps(1, 1) - tr/3.0_wp, deps(2, 2) - tr/3.0_wp, deps(3, 3) - tr/3.0_wp, deps(2, 3), deps(1, 3), &
            deps(1, 2)]
      rate = sqrt((2.0_wp/3.0_wp)*(de(1)**2 + de(2)**2 + de(3)**2 + 2.0_wp*(de(4)**2 + de(5)**2 + de(6)**2)))/pt%dt
    end if
    ! perfectly-plastic radial return at fixed p
    sy = hjc_flow(this, p, d, rate)
    q = strength_mises(s)
    dep = 0.0_wp
    if (q > sy) then
      dep = (q - sy)/(3.0_wp*this%g)
      s = s*(sy/q)
      hist(1) = hist(1) + dep
    end if
    ! damage (the plastic strain scaled by the particle's size: module notes)
    if (this%length > 0.0_wp .and. pt%length > 0.0_wp) dep = dep*(pt%length/this%length)
    if (dep + dmup > 0.0_wp) then
      d = d + (dep + dmup)/max(this%efmin, this%d1*max(p/this%fc + this%t/this%fc, 0.0_wp)**this%d2)
      hist(2) = min(d, 1.0_wp)
    end if
    ! failure: fully damaged and not in compression
    if (hist(2) >= 1.0_wp .and. p <= 0.0_wp) then
      hist(6) = 1.0_wp
      pt%eroded = strength_mises(s)**2/(6.0_wp*this%g) + p**2/(2.0_wp*ku)
      s = 0.0_wp
      p = 0.0_wp
    end if
    stress = s
    stress(1:3) = stress(1:3) - p
  end subroutine hjc_update

  !> hjc_nhist history variables.
  pure integer function hjc_nhist_of(this) result(n)
    class(strength_hjc_t), intent(in) :: this
    n = hjc_nhist
    if (this%g < 0.0_wp) n = hjc_nhist   ! (this unused)
  end function hjc_nhist_of

  !> 'plastic_strain' hist(1), 'damage' hist(2); 0 for the other fields.
  pure real(wp) function hjc_field(this, name, hist) result(v)
    class(strength_hjc_t), intent(in) :: this
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: hist(:)
    v = 0.0_wp
    if (name == 'plastic_strain') v = hist(1)
    if (name == 'damage') v = hist(2)
    if (this%g < 0.0_wp) v = 0.0_wp   ! (this unused)
  end function hjc_field

  !> Failed (module notes): the flag hist(6).
  pure logical function hjc_failed(this, hist) result(f)
    class(strength_hjc_t), intent(in) :: this
    real(wp), intent(in) :: hist(:)
    f = hist(6) > 0.5_wp
    if (this%g < 0.0_wp) f = .false.   ! (this unused)
  end function hjc_failed
end module strength_hjc
