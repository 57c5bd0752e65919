!> Hypoelastic strength models of the solid particles (PARTICLES.md §2.0-2.2):
!> an abstract `strength_t` with one type-bound update, the elastic and the
!> bilinear (linear hardening, radial return) models; the factory is
!> `strength_factory`, each further model has its own module.
!>
!> Common update of one particle over one step (§2.0), given the strain
!> increment deps = sym(L) dt and the spin increment dw = skew(L) dt from the
!> virtual solid grid (Eqs. 29-32):
!>  1-2. objective rotation (the Jaumann rate of Eq. 9) by Hughes-Winget,
!>     Q = (I - dw/2)^{-1} (I + dw/2), exactly orthogonal for any increment,
!>     and the hypoelastic increment dsig = K tr(deps) I + 2G dev(deps)
!>     (pressure from the bulk modulus: p -= K tr(deps)), split
!>     symmetrically: sigma* = Q (sigma + dsig/2) Q^T + dsig/2;
!>  3. the model's return (elastic: none; bilinear: radial return on the
!>     deviator, exact for linear hardening).
!> A solid whose pressure comes from an equation of state (&solid eos =
!> 'mie_gruneisen', PARTICLES.md §2.0 step 2) has a model with k = 0: the
!> update then leaves the mean stress as it was (the rotation keeps the
!> trace) and the caller sets the pressure from the EOS
!> (`particles_lagrange`); its bulk modulus only enters Young's modulus of
!> the bilinear hardening modulus.
!>
!> The interface every model implements (issue 15 adds models behind it):
!>  - `update(deps, dw, pt, stress, hist)`: pt (`strength_point_t`) carries
!>    the step's dt (rates), the density at the end of the step, the EOS's
!>    predicted pressure when the solid has one, and gives back the energy
!>    per unit volume a failure removed in this step (`eroded`);
!>  - `nhist()` history variables per particle, `hist_init(hist)` their
!>    initial values, and `field(name, hist)` the common output fields
!>    ('plastic_strain', 'damage', 'temperature', 'porosity'; 0 where a
!>    model has none) and `failed(hist)`. A model with history keeps its
!>    equivalent plastic strain in hist(1) (tracked-particle rows read it). A failed particle keeps its mass
!>    and carries no tension or shear (the model's update zeroes its
!>    deviator and tension; the EOS path clips its pressure at 0).
!> Model parameters reach the factory (`strength_factory`) in one
!> `strength_params_t`.
!> Stresses are Voigt (xx, yy, zz, yz, xz, xy), tension positive.
module strength_models
  use base_kinds, only: wp
  use strength_jc_flow, only: jc_flow_t
  use base_sym3, only: sym3_eigen
  implicit none
  private
  public :: strength_t, strength_elastic_t, strength_bilinear_t, &
            strength_params_t, strength_point_t, strength_fields, &
            strength_rotate, strength_trial, strength_mises, voigt_to_tensor, tensor_to_voigt, strength_principal_max

  !> The common per-particle output fields of the history (`field`).
  character(len=*), parameter :: strength_fields(4) = [character(len=14) :: 'plastic_strain', 'damage', &
                                                       'temperature', 'porosity']

  !> Every model's parameters (pressure units for moduli and stresses); a
  !> model reads the ones it uses.
  type :: strength_params_t
    real(wp) :: k = 0.0_wp    !< bulk modulus
    real(wp) :: g = 0.0_wp    !< shear modulus
    real(wp) :: y0 = 0.0_wp   !< bilinear: initial yield stress
    real(wp) :: et = 0.0_wp   !< bilinear: tangent modulus
    type(jc_flow_t) :: jc     !< Johnson-Cook flow stress (johnson_cook; gurson's matrix)
    real(wp) :: gurson_q1 = 1.5_wp, gurson_q2 = 1.0_wp   !< gurson: yield function q1, q2 (q3 = q1^2)
    real(wp) :: gurson_fn = 0.0_wp, gurson_epsn = 0.3_wp, gurson_sn = 0.1_wp   !< gurson: nucleation f_N, eps_N, s_N
    real(wp) :: gurson_fc = 0.15_wp, gurson_ff = 0.25_wp   !< gurson: coalescence f_c (TEPLA-F's too), f_F
    real(wp) :: gurson_f0 = 0.0_wp      !< gurson: initial porosity
    real(wp) :: jc_cp = 0.0_wp, jc_chi = 0.9_wp          !< johnson_cook: c_p (0: no heating), Taylor-Quinney chi
    !> equivalent plastic strain at failure (bilinear: 0 never fails; gurson: TEPLA-F's eps_p^f, 0 no strain term)
    real(wp) :: failure_strain = 0.0_wp
    !> bilinear: the largest principal stress at which the particle fails in tension (0: never)
    real(wp) :: tensile_strength = 0.0_wp
    ! hjc (strength_hjc): the &solid hjc_* variables and the reference density
    real(wp) :: hjc_a = 0.0_wp, hjc_b = 0.0_wp, hjc_n = 0.0_wp, hjc_c = 0.0_wp, hjc_fc = 0.0_wp, hjc_smax = 0.0_wp
    real(wp) :: hjc_t = 0.0_wp, hjc_d1 = 0.0_wp, hjc_d2 = 0.0_wp, hjc_efmin = 0.0_wp
    real(wp) :: hjc_pcrush = 0.0_wp, hjc_mucrush = 0.0_wp, hjc_plock = 0.0_wp, hjc_mulock = 0.0_wp
    real(wp) :: hjc_k1 = 0.0_wp, hjc_k2 = 0.0_wp, hjc_k3 = 0.0_wp, hjc_eps0 = 1.0_wp, hjc_rho0 = 0.0_wp
    !> hjc: the particle size at which the damage constants hold (0: any size)
    real(wp) :: hjc_length = 0.0_wp
  end type strength_params_t

  !> One particle's step context (module notes): in dt, rho (density at the
  !> end of the step), p (the EOS's predicted pressure at the end of the
  !> step, solids with an EOS only), length (the particle's size, the cube
  !> root of its volume at the end of the step, given to a model that
  !> wants_length; 0: not known); out eroded
  !> (energy per unit volume a failure removed in this step, 0 otherwise).
  type :: strength_point_t
    real(wp) :: dt = 0.0_wp
    real(wp) :: rho = 0.0_wp
    real(wp) :: p = 0.0_wp
    real(wp) :: length = 0.0_wp
    real(wp) :: eroded = 0.0_wp
  end type strength_point_t

  !> A hypoelastic solid: bulk modulus k and shear modulus g (pressure).
  type, abstract :: strength_t
    real(wp) :: k = 0.0_wp   !< bulk modulus (pressure)
    real(wp) :: g = 0.0_wp   !< shear modulus (pressure)
    !> the model reads strength_point_t%length (else the caller need not set it)
    logical :: wants_length = .false.
  contains
    procedure(update_i), deferred :: update
    procedure :: wave_modulus => strength_wave_modulus
    procedure :: nhist => strength_no_hist
    procedure :: hist_init => strength_hist_zero
    procedure :: field => strength_no_field
    procedure :: failed => strength_never_fails
  end type strength_t

  abstract interface
    !> Advances the stress(6) (and the history hist(:), if the model has
    !> any) of one particle by the increments deps(3,3), dw(3,3) (module
    !> notes for pt).
    pure subroutine update_i(this, deps, dw, pt, stress, hist)
      import :: strength_t, strength_point_t, wp
      class(strength_t), intent(in) :: this
      real(wp), intent(in) :: deps(3, 3), dw(3, 3)
      type(strength_point_t), intent(inout) :: pt
      real(wp), intent(inout) :: stress(6), hist(:)
    end subroutine update_i
  end interface

  !> Linear elasticity (§2.1).
  type, extends(strength_t) :: strength_elastic_t
  contains
    procedure :: update => elastic_update
  end type strength_elastic_t

  !> Linear isotropic hardening (§2.2): yield stress y0 + h eps_p, with the
  !> plastic modulus h = E Et/(E - Et) from the tangent modulus Et; hist(1) is
  !> the equivalent plastic strain. Optional failure (ef > 0): the particle
  !> fails in the step its eps_p reaches ef, and is failed while hist(1) >=
  !> ef (so the flag needs no history of its own: eps_p no longer grows
  !> once the deviator is gone); a failed particle carries no shear and, with
  !> its own bulk modulus, no tension (p = max(p, 0); with an EOS, k = 0, the
  !> caller clips the pressure). pt%eroded is the elastic energy per unit
  !> volume removed: s:s/(4G) + p^2/(2K) of the tension (K = k; none with
  !> k = 0) of the stress after the return in the failing step, of the
  !> step's trial stress in later steps.
  !> Optional tensile fracture (st > 0, a second history variable hist(2),
  !> 1 once failed): the particle fails in the step the largest principal
  !> stress after the return reaches st (a brittle solid's cut-off, as
  !> concrete's tensile fracture stress), and is then failed as above.
  type, extends(strength_t) :: strength_bilinear_t
    real(wp) :: y0 = 0.0_wp   !< initial yield stress (pressure)
    real(wp) :: h = 0.0_wp    !< plastic modulus (pressure)
    real(wp) :: ef = 0.0_wp   !< equivalent plastic strain at failure (0: never fails)
    real(wp) :: st = 0.0_wp   !< largest principal stress at failure (0: never fails in tension)
  contains
    procedure :: update => bilinear_update
    procedure :: nhist => bilinear_nhist
    procedure :: field => bilinear_field
    procedure :: failed => bilinear_failed
  end type strength_bilinear_t

contains

  !> No history (the default).
  pure integer function strength_no_hist(this) result(n)
    class(strength_t), intent(in) :: this
    n = 0
    if (this%g < 0.0_wp) n = 0   ! (this unused)
  end function strength_no_hist

  !> Bilinear: the equivalent plastic strain, and with a tensile strength
  !> the tensile failure flag.
  pure integer function bilinear_nhist(this) result(n)
    class(strength_bilinear_t), intent(in) :: this
    n = merge(2, 1, this%st > 0.0_wp)
  end function bilinear_nhist

  !> Initial history: zero (the default).
  pure subroutine strength_hist_zero(this, hist)
    class(strength_t), intent(in) :: this
    real(wp), intent(inout) :: hist(:)
    hist = 0.0_wp
    if (this%g < 0.0_wp) hist = 0.0_wp   ! (this unused)
  end subroutine strength_hist_zero

  !> The output field `name` (strength_fields) of a particle: 0 (the
  !> default: the model has none of them).
  pure real(wp) function strength_no_field(this, name, hist) result(v)
    class(strength_t), intent(in) :: this
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: hist(:)
    v = 0.0_wp
    if (this%g < 0.0_wp .and. len(name) + size(hist) < 0) v = 0.0_wp   ! (unused)
  end function strength_no_field

  !> The equivalent plastic strain hist(1) as 'plastic_strain'; with a
  !> tensile strength, the tensile failure flag hist(2) as 'damage'.
  pure real(wp) function bilinear_field(this, name, hist) result(v)
    class(strength_bilinear_t), intent(in) :: this
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: hist(:)
    v = 0.0_wp
    if (name == 'plastic_strain') v = hist(1)
    if (name == 'damage' .and. this%st > 0.0_wp) v = hist(2)
  end function bilinear_field

  !> Never failed (the default).
  pure logical function strength_never_fails(this, hist) result(f)
    class(strength_t), intent(in) :: this
    real(wp), intent(in) :: hist(:)
    f = .false.
    if (this%g < 0.0_wp .and. size(hist) < 0) f = .false.   ! (unused)
  end function strength_never_fails

  !> Bilinear failed: eps_p has reached the failure strain (type notes).
  pure logical function bilinear_failed(this, hist) result(f)
    class(strength_bilinear_t), intent(in) :: this
    real(wp), intent(in) :: hist(:)
    f = this%ef > 0.0_wp .and. hist(1) >= this%ef
    if (this%st > 0.0_wp) f = f .or. hist(2) > 0.0_wp
  end function bilinear_failed

  !> K + 4G/3, the modulus of the elastic longitudinal wave (pressure).
  pure real(wp) function strength_wave_modulus(this) result(m)
    class(strength_t), intent(in) :: this
    m = this%k + 4.0_wp*this%g/3.0_wp
  end function strength_wave_modulus

  !> Voigt (xx, yy, zz, yz, xz, xy) to a symmetric 3x3 tensor.
  pure function voigt_to_tensor(v) result(t)
    real(wp), intent(in) :: v(6)
    real(wp) :: t(3, 3)
    t(1, 1) = v(1); t(2, 2) = v(2); t(3, 3) = v(3)
    t(2, 3) = v(4); t(3, 2) = v(4)
    t(1, 3) = v(5); t(3, 1) = v(5)
    t(1, 2) = v(6); t(2, 1) = v(6)
  end function voigt_to_tensor

  !> The Voigt vector of the symmetric part of t.
  pure function tensor_to_voigt(t) result(v)
    real(wp), intent(in) :: t(3, 3)
    real(wp) :: v(6)
    v = [t(1, 1), t(2, 2), t(3, 3), 0.5_wp*(t(2, 3) + t(3, 2)), 0.5_wp*(t(1, 3) + t(3, 1)), &
         0.5_wp*(t(1, 2) + t(2, 1))]
  end function tensor_to_voigt

  !> Hughes-Winget rotation of stress(6) by the spin increment dw (skew):
  !> Q = (I - dw/2)^{-1} (I + dw/2), stress <- Q stress Q^T (Eq. 9, objective).
  pure subroutine strength_rotate(dw, stress)
    real(wp), intent(in) :: dw(3, 3)
    real(wp), intent(inout) :: stress(6)
    real(wp) :: a(3, 3), b(3, 3), ainv(3, 3), q(3, 3), s(3, 3), det
    integer :: d
    a = -0.5_wp*dw
    b = 0.5_wp*dw
    do d = 1, 3
      a(d, d) = a(d, d) + 1.0_wp
      b(d, d) = b(d, d) + 1.0_wp
    end do
    ! inverse of a by its cofactors (det = 1 + |w|^2/4 > 0 for a skew dw)
    ainv(1, 1) = a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)
    ainv(1, 2) = a(1, 3)*a(3, 2) - a(1, 2)*a(3, 3)
    ainv(1, 3) = a(1, 2)*a(2, 3) - a(1, 3)*a(2, 2)
    ainv(2, 1) = a(2, 3)*a(3, 1) - a(2, 1)*a(3, 3)
    ainv(2, 2) = a(1, 1)*a(3, 3) - a(1, 3)*a(3, 1)
    ainv(2, 3) = a(1, 3)*a(2, 1) - a(1, 1)*a(2, 3)
    ainv(3, 1) = a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1)
    ainv(3, 2) = a(1, 2)*a(3, 1) - a(1, 1)*a(3, 2)
    ainv(3, 3) = a(1, 1)*a(2, 2) - a(1, 2)*a(2, 1)
    det = a(1, 1)*ainv(1, 1) + a(1, 2)*ainv(2, 1) + a(1, 3)*ainv(3, 1)
    q = matmul(ainv, b)/det
    s = voigt_to_tensor(stress)
    stress = tensor_to_voigt(matmul(q, matmul(s, transpose(q))))
  end subroutine strength_rotate

  !> Steps 1-2 of the common update (module notes): the hypoelastic
  !> increment dsig = K tr(deps) I + 2G dev(deps) and the rotation, split
  !> symmetrically, sigma* = Q (sigma + dsig/2) Q^T + dsig/2: the increment
  !> is then taken in the mid-step frame, which makes the update second-order
  !> accurate for the Jaumann rate (rotating first and adding the whole
  !> increment after is only first order: simple shear to gamma = 1 in 1000
  !> steps has a 2.3e-4 G error in sigma_12 that way, 6.4e-8 G this way).
  pure subroutine strength_trial(k, g, deps, dw, stress)
    real(wp), intent(in) :: k, g, deps(3, 3), dw(3, 3)
    real(wp), intent(inout) :: stress(6)
    real(wp) :: tr, de(6)
    tr = deps(1, 1) + deps(2, 2) + deps(3, 3)
    de = tensor_to_voigt(deps)
    de(1:3) = de(1:3) - tr/3.0_wp
    de = 2.0_wp*g*de
    de(1:3) = de(1:3) + k*tr
    stress = stress + 0.5_wp*de
    call strength_rotate(dw, stress)
    stress = stress + 0.5_wp*de
  end subroutine strength_trial

  !> Elastic (§2.1): the trial stress.
  pure subroutine elastic_update(this, deps, dw, pt, stress, hist)
    class(strength_elastic_t), intent(in) :: this
    real(wp), intent(in) :: deps(3, 3), dw(3, 3)
    type(strength_point_t), intent(inout) :: pt
    real(wp), intent(inout) :: stress(6), hist(:)
    call strength_trial(this%k, this%g, deps, dw, stress)
    if (size(hist) < 0) pt%eroded = 0.0_wp   ! (no history, no failure: hist and pt unused)
  end subroutine elastic_update

  !> Bilinear (§2.2): radial return of the trial deviator, exact for linear
  !> hardening: deps_p = (q* - sy)/(3G + H), s = s* (1 - 3G deps_p/q*),
  !> eps_p += deps_p (hist(1)), sy = y0 + H eps_p.
  pure subroutine bilinear_update(this, deps, dw, pt, stress, hist)
    class(strength_bilinear_t), intent(in) :: this
    real(wp), intent(in) :: deps(3, 3), dw(3, 3)
    type(strength_point_t), intent(inout) :: pt
    real(wp), intent(inout) :: stress(6), hist(:)
    real(wp) :: s(6), p, q, sy, dep
    call strength_trial(this%k, this%g, deps, dw, stress)
    p = (stress(1) + stress(2) + stress(3))/3.0_wp
    s = stress
    s(1:3) = s(1:3) - p
    q = strength_mises(s)
    pt%eroded = 0.0_wp
    if (bilinear_failed(this, hist)) then
      call bilinear_remove(this, q, p, pt, stress)
      return
    end if
    sy = this%y0 + this%h*hist(1)
    if (q > sy) then
      dep = (q - sy)/(3.0_wp*this%g + this%h)
      s = s*(1.0_wp - 3.0_wp*this%g*dep/q)
      hist(1) = hist(1) + dep
      stress = s
      stress(1:3) = stress(1:3) + p
      ! fails in this step (type notes)
      if (bilinear_failed(this, hist)) then
        call bilinear_remove(this, q - 3.0_wp*this%g*dep, p, pt, stress)
        return
      end if
      q = q - 3.0_wp*this%g*dep
    end if
    ! fails in tension in this step (type notes); the largest principal
    ! value is at most p + 2q/3 (a deviator's at most sqrt(2/3 s:s), equal
    ! in uniaxial stress; with a margin for its round-off), so most steps
    ! need no eigenvalues
    if (this%st > 0.0_wp .and. p + 2.0_wp*q/3.0_wp + 1.0e-12_wp*(abs(p) + q) >= this%st) then
      if (strength_principal_max(stress) >= this%st) then
        hist(2) = 1.0_wp
        call bilinear_remove(this, q, p, pt, stress)
      end if
    end if
  end subroutine bilinear_update

  !> The largest principal value of the symmetric stress(6) (Voigt), by
  !> Jacobi rotations (`sym3_eigen`: the invariants' closed form loses half
  !> the digits where two principal values meet).
  pure real(wp) function strength_principal_max(stress) result(smax)
    real(wp), intent(in) :: stress(6)
    real(wp) :: lam(3), ev(3, 3)
    call sym3_eigen(voigt_to_tensor(stress), lam, ev)
    smax = maxval(lam)
  end function strength_principal_max

  !> A failed bilinear particle (type notes): stress with von Mises q and
  !> mean stress p (tension positive) loses its deviator and, with k > 0, its
  !> tension; pt%eroded the elastic energy per unit volume removed.
  pure subroutine bilinear_remove(this, q, p, pt, stress)
    class(strength_bilinear_t), intent(in) :: this
    real(wp), intent(in) :: q, p
    type(strength_point_t), intent(inout) :: pt
    real(wp), intent(inout) :: stress(6)
    real(wp) :: pk
    pt%eroded = q**2/(6.0_wp*this%g)
    pk = p
    if (this%k > 0.0_wp .and. p > 0.0_wp) then
      pt%eroded = pt%eroded + p**2/(2.0_wp*this%k)
      pk = 0.0_wp
    end if
    stress(1:3) = pk
    stress(4:6) = 0.0_wp
  end subroutine bilinear_remove

  !> The von Mises stress q = sqrt(3/2 s:s) of the deviator s(6) (Voigt:
  !> the shear components count twice).
  pure real(wp) function strength_mises(s) result(q)
    real(wp), intent(in) :: s(6)
    q = sqrt(1.5_wp*(s(1)**2 + s(2)**2 + s(3)**2 + 2.0_wp*(s(4)**2 + s(5)**2 + s(6)**2)))
  end function strength_mises
end module strength_models
