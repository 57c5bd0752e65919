!> Unit tests of the EOS (ideal gas, JWL, Mie-Gruneisen): pressure and sound
!> speed against hand formulas and published data, thermodynamic consistency
!> of c^2 with the isentropic derivative, the inverse e(rho, p), and the
!> factory's errors.
program test_eos
  use base_kinds, only: wp
  use base_errors, only: error_t
  use eos_base, only: eos_t
  use eos_factory, only: eos_params_t, eos_create
  use test_assert, only: check, check_summary
  implicit none
  class(eos_t), allocatable :: eos
  type(error_t), allocatable :: err
  type(eos_params_t) :: par
  real(wp) :: rho(3), e(3), p(3), cs(3), pp(3), cp(3), pm(3), cm(3), h, dpdrho_s
  integer :: i

  par%gamma = 5.0_wp/3.0_wp
  call eos_create('ideal_gas', par, eos, err)
  call check(.not. allocated(err), 'ideal_gas with gamma 5/3 is accepted')
  rho = [0.125_wp, 1.0_wp, 7.5_wp]
  e = [2.0_wp, 2.5_wp, 1.0e-3_wp]
  call eos%eval(rho, e, p, cs)
  call check(all(abs(p - (2.0_wp/3.0_wp)*rho*e) <= 1e-15_wp*p), 'p = (gamma-1) rho e')
  call check(all(abs(cs**2 - (5.0_wp/3.0_wp)*p/rho) <= 1e-14_wp*cs**2), 'c^2 = gamma p / rho')
  ! isentropic derivative by central differences along de = p/rho^2 drho
  do i = 1, 3
    h = 1e-6_wp*rho(i)
    call eos%eval([rho(i) + h], [e(i) + p(i)/rho(i)**2*h], pp(1:1), cp(1:1))
    call eos%eval([rho(i) - h], [e(i) - p(i)/rho(i)**2*h], pm(1:1), cm(1:1))
    dpdrho_s = (pp(1) - pm(1))/(2.0_wp*h)
    call check(abs(dpdrho_s - cs(i)**2) <= 1e-7_wp*cs(i)**2, 'c^2 equals dp/drho at constant entropy')
    call check(abs(eos%energy(rho(i), p(i)) - e(i)) <= 1e-15_wp*e(i), 'e(rho, p(rho, e)) = e')
  end do

  par%gamma = 1.0_wp
  call eos_create('ideal_gas', par, eos, err)
  call check(allocated(err), 'gamma = 1 is refused')
  if (allocated(err)) call check(index(err%msg, 'gamma') > 0, 'the message names gamma')
  deallocate(err)
  call eos_create('ideal_gaz', par, eos, err)
  call check(allocated(err), 'an unknown EOS name is refused')
  if (allocated(err)) call check(index(err%msg, 'ideal_gas') > 0, 'the message lists the valid names')
  if (allocated(err)) call check(index(err%msg, 'jwl') > 0 .and. index(err%msg, 'mie_gruneisen') > 0, &
                                 'the valid names include jwl and mie_gruneisen')
  if (allocated(err)) deallocate(err)

  call test_jwl()
  call test_mie_gruneisen()

  call check_summary('test_eos')

contains

  !> c^2 against the isentropic derivative dp/drho along de = p/rho^2 drho by
  !> central differences (h = 1e-6 rho: truncation ~1e-12, round-off
  !> ~1e-10 relative, so 1e-7 as for the ideal gas), and e(rho, p(rho, e)) = e
  !> to 1e-14 of the largest term entering p (|e|, |p|/rho, c^2 all in
  !> energy units): the inverse is exact but for the cancellation of those
  !> terms, a few ulps each (measured <= 1e-16).
  subroutine check_consistency(eos, rho, e, what)
    class(eos_t), intent(in) :: eos
    real(wp), intent(in) :: rho(:), e(:)
    character(len=*), intent(in) :: what
    real(wp) :: p(size(rho)), cs(size(rho)), pp(1), cp(1), pm(1), cm(1), h, dpdrho_s, scale
    integer :: i
    call eos%eval(rho, e, p, cs)
    do i = 1, size(rho)
      h = 1e-6_wp*rho(i)
      call eos%eval([rho(i) + h], [e(i) + p(i)/rho(i)**2*h], pp, cp)
      call eos%eval([rho(i) - h], [e(i) - p(i)/rho(i)**2*h], pm, cm)
      dpdrho_s = (pp(1) - pm(1))/(2.0_wp*h)
      call check(cs(i) > 0.0_wp .and. abs(dpdrho_s - cs(i)**2) <= 1e-7_wp*cs(i)**2, &
                 what//': c^2 equals dp/drho at constant entropy')
      scale = abs(e(i)) + abs(p(i))/rho(i) + cs(i)**2
      call check(abs(eos%energy(rho(i), p(i)) - e(i)) <= 1e-14_wp*scale, what//': e(rho, p(rho, e)) = e')
    end do
  end subroutine check_consistency

  !> JWL for TNT, LLNL Explosives Handbook (Dobratz & Crawford, UCRL-52997,
  !> 1985): A = 371.2 GPa, B = 3.231 GPa, C = 1.045 GPa, R1 = 4.15, R2 = 0.95,
  !> omega = 0.30, rho0 = 1.630 g/cm^3, E0 = 7.0 GPa (per unit volume),
  !> D = 6.93 km/s, P_CJ = 21.0 GPa. Units: GPa, g/cm^3, kJ/g, km/s.
  subroutine test_jwl()
    real(wp), parameter :: a = 371.2_wp, b = 3.231_wp, r1 = 4.15_wp, r2 = 0.95_wp, w = 0.30_wp
    real(wp), parameter :: rho0 = 1.63_wp, e0 = 7.0_wp, d = 6.93_wp, p_cj = 21.0_wp, c_pub = 1.045_wp
    integer, parameter :: nstep = 2000
    real(wp), parameter :: v_check(4) = [1.0_wp, 2.0_wp, 4.0_wp, 7.0_wp]
    type(eos_params_t) :: par
    class(eos_t), allocatable :: eos
    type(error_t), allocatable :: err
    real(wp) :: p(1), cs(1), v_cj, rho_cj, e_cj, u_cj, c, v, dv, ev, k1, k2, k3, k4, p_s
    integer :: i, j, n

    par%a = a; par%b = b; par%r1 = r1; par%r2 = r2; par%omega = w; par%rho0 = rho0
    call eos_create('jwl', par, eos, err)
    call check(.not. allocated(err), 'jwl with the TNT parameters is accepted')
    if (allocated(err)) return

    ! At rho = rho0 Eq. (13) reduces to A (1 - w/R1) e^-R1 + B (1 - w/R2) e^-R2 + w E0
    ! = 8.3837 GPa; only round-off separates the two evaluations.
    call eos%eval([rho0], [e0/rho0], p, cs)
    call check(abs(p(1) - (a*(1.0_wp - w/r1)*exp(-r1) + b*(1.0_wp - w/r2)*exp(-r2) + w*e0)) <= 1e-14_wp*p(1), &
               'jwl: p(rho0, E0/rho0) matches the hand formula')

    ! The CJ state from the published D and P_CJ: Rayleigh line (mass and
    ! momentum) V_CJ = 1 - P_CJ/(rho0 D^2), Hugoniot energy
    ! e_CJ = E0/rho0 + P_CJ (1/rho0 - 1/rho_CJ)/2. The JWL must return P_CJ
    ! there (measured 20.996 GPa), and, the Rayleigh line being tangent to the
    ! isentrope at CJ, c_CJ = D - u_CJ (measured 5.0700 vs 5.0709 km/s).
    ! Tolerance 0.5 %: the published D and P_CJ are rounded to three digits
    ! (up to 0.24 % in P_CJ), and a wrong formula is off by far more.
    v_cj = 1.0_wp - p_cj/(rho0*d**2)
    rho_cj = rho0/v_cj
    e_cj = e0/rho0 + 0.5_wp*p_cj*(1.0_wp/rho0 - 1.0_wp/rho_cj)
    u_cj = p_cj/(rho0*d)
    call eos%eval([rho_cj], [e_cj], p, cs)
    call check(abs(p(1) - p_cj) <= 5e-3_wp*p_cj, 'jwl: TNT CJ pressure is 21.0 GPa')
    call check(abs(cs(1) - (d - u_cj)) <= 5e-3_wp*(d - u_cj), 'jwl: TNT CJ sound speed is D - u_CJ')

    ! Release isentrope through CJ: integrating de/dV = -p/rho0 (V = rho0/rho)
    ! with this EOS (RK4, 2000 steps, error ~1e-12) must follow the closed
    ! form p_s = A e^(-R1 V) + B e^(-R2 V) + C V^-(1+w) of the JWL family,
    ! with C fixed by the CJ point; C must be the handbook's 1.045 GPa (1 %:
    ! C is a small difference of rounded numbers; measured 1.0478).
    c = (p(1) - a*exp(-r1*v_cj) - b*exp(-r2*v_cj))*v_cj**(1.0_wp + w)
    call check(abs(c - c_pub) <= 1e-2_wp*c_pub, 'jwl: TNT isentrope constant C is 1.045 GPa')
    v = v_cj
    ev = e_cj
    do j = 1, size(v_check)
      n = max(1, nint(nstep*(v_check(j) - v)/(v_check(size(v_check)) - v_cj)))
      dv = (v_check(j) - v)/n
      do i = 1, n
        k1 = -isentrope_p(eos, rho0, v, ev)/rho0
        k2 = -isentrope_p(eos, rho0, v + 0.5_wp*dv, ev + 0.5_wp*dv*k1)/rho0
        k3 = -isentrope_p(eos, rho0, v + 0.5_wp*dv, ev + 0.5_wp*dv*k2)/rho0
        k4 = -isentrope_p(eos, rho0, v + dv, ev + dv*k3)/rho0
        ev = ev + dv*(k1 + 2.0_wp*k2 + 2.0_wp*k3 + k4)/6.0_wp
        v = v + dv
      end do
      p_s = a*exp(-r1*v) + b*exp(-r2*v) + c*v**(-(1.0_wp + w))
      call check(abs(isentrope_p(eos, rho0, v, ev) - p_s) <= 1e-8_wp*p_s, 'jwl: the release isentrope follows the closed form')
    end do

    ! compression, CJ, rho0, expansion to V = 16
    call check_consistency(eos, [2.6_wp, rho_cj, rho0, 0.5_wp, 0.1_wp], &
                           [7.0_wp, e_cj, e0/rho0, 2.0_wp, 0.5_wp], 'jwl')

    ! factory: one bad parameter gives one message naming it
    par%omega = -0.3_wp
    call eos_create('jwl', par, eos, err)
    call check(allocated(err), 'jwl: omega < 0 is refused')
    if (allocated(err)) then
      call check(index(err%msg, 'omega = -3.00000E-01 must be > 0') > 0 .and. index(err%msg, ';') == 0, &
                 'jwl: the message names omega, its value and the rule, and nothing else')
      deallocate(err)
    end if
    ! no parameters at all: every missing one is named
    call eos_create('jwl', eos_params_t(), eos, err)
    call check(allocated(err), 'jwl without parameters is refused')
    if (allocated(err)) then
      call check(index(err%msg, 'a = ') > 0 .and. index(err%msg, 'b = ') > 0 .and. &
                 index(err%msg, 'r1 = ') > 0 .and. index(err%msg, 'r2 = ') > 0 .and. &
                 index(err%msg, 'omega = ') > 0 .and. index(err%msg, 'rho0 = ') > 0, &
                 'jwl: the message names every missing parameter')
      deallocate(err)
    end if
  end subroutine test_jwl

  !> Pressure of `eos` at relative volume v = rho0/rho and specific energy ev.
  function isentrope_p(eos, rho0, v, ev) result(p)
    class(eos_t), intent(in) :: eos
    real(wp), intent(in) :: rho0, v, ev
    real(wp) :: p
    real(wp) :: pa(1), ca(1)
    call eos%eval([rho0/v], [ev], pa, ca)
    p = pa(1)
  end function isentrope_p

  !> Mie-Gruneisen for steel: c0 = 3.57 km/s, s1 = 1.92, gamma0 = 1.8,
  !> rho0 = 7.85 g/cm^3 (the paper's Section 7.6 values, c0 = 3570 mm/ms).
  !> Units: GPa, g/cm^3, kJ/g, km/s.
  subroutine test_mie_gruneisen()
    real(wp), parameter :: rho0 = 7.85_wp, c0 = 3.57_wp, s1 = 1.92_wp, g0 = 1.8_wp
    real(wp), parameter :: mus(3) = [0.02_wp, 0.1_wp, 0.3_wp]
    type(eos_params_t) :: par
    class(eos_t), allocatable :: eos
    type(error_t), allocatable :: err
    real(wp) :: p(1), cs(1), pa(1), ca(1), mu, r, p_h, e_h, up, us, dv
    integer :: j

    par%rho0 = rho0; par%c0 = c0; par%s1 = s1; par%gamma0 = g0
    call eos_create('mie_gruneisen', par, eos, err)
    call check(.not. allocated(err), 'mie_gruneisen with the steel parameters is accepted')
    if (allocated(err)) return

    ! ON the Hugoniot: with e = e_H(mu) the pressure is p_H(mu) (at mu = 0.1:
    ! p_H = 13.348 GPa, e_H = 0.077292 kJ/g); the state must also satisfy the
    ! jump conditions it came from, Us = c0 + s1 up with up = sqrt(p dv),
    ! Us = sqrt(p/dv)/rho0, dv = 1/rho0 - 1/rho. Round-off only: 1e-13.
    do j = 1, size(mus)
      mu = mus(j)
      r = rho0*(1.0_wp + mu)
      p_h = rho0*c0**2*mu*(1.0_wp + mu)/(1.0_wp - (s1 - 1.0_wp)*mu)**2
      e_h = p_h*mu/(2.0_wp*rho0*(1.0_wp + mu))
      call eos%eval([r], [e_h], p, cs)
      call check(abs(p(1) - p_h) <= 1e-13_wp*p_h, 'mie_gruneisen: p(rho, e_H) = p_H on the Hugoniot')
      call check(abs(eos%energy(r, p_h) - e_h) <= 1e-13_wp*e_h, 'mie_gruneisen: e(rho, p_H) = e_H')
      dv = 1.0_wp/rho0 - 1.0_wp/r
      up = sqrt(p(1)*dv)
      us = sqrt(p(1)/dv)/rho0
      call check(abs(us - (c0 + s1*up)) <= 1e-13_wp*us, 'mie_gruneisen: the Hugoniot is Us = c0 + s1 up')
    end do

    ! At rho0, e = 0: p = 0 and c = c0 exactly (bulk sound speed).
    call eos%eval([rho0], [0.0_wp], p, cs)
    call check(abs(p(1)) <= 1e-15_wp*rho0*c0**2 .and. abs(cs(1) - c0) <= 1e-14_wp*c0, &
               'mie_gruneisen: p(rho0, 0) = 0 and c = c0')

    ! Continuity through mu = 0 into tension: p changes by ~ rho0 c0^2 * 2e-9
    ! and c by ~1e-9 relative across rho0 (1 +- 1e-9).
    call eos%eval([rho0*(1.0_wp + 1e-9_wp)], [0.1_wp], p, cs)
    call eos%eval([rho0*(1.0_wp - 1e-9_wp)], [0.1_wp], pa, ca)
    call check(abs(p(1) - pa(1)) <= 3e-9_wp*rho0*c0**2 .and. abs(cs(1) - ca(1)) <= 1e-8_wp*cs(1), &
               'mie_gruneisen: p and c are continuous at mu = 0')
    ! tension is the linear extension p = rho0 c0^2 mu + gamma0 rho0 e
    call eos%eval([0.95_wp*rho0], [0.01_wp], p, cs)
    call check(abs(p(1) - (-0.05_wp*rho0*c0**2 + g0*rho0*0.01_wp)) <= 1e-13_wp*rho0*c0**2, &
               'mie_gruneisen: tension p = rho0 c0^2 mu + gamma0 rho0 e')

    ! Past the singularity mu = 1/(s1-1) = 1.087 (rho = 17 is mu = 1.166) the
    ! guard keeps p and c finite and still consistent.
    call eos%eval([17.0_wp], [0.5_wp], p, cs)
    call check(abs(p(1)) < huge(1.0_wp) .and. p(1) > 0.0_wp .and. cs(1) > c0, &
               'mie_gruneisen: finite p and c beyond 1 - (s1-1) mu = 0')

    ! compression (on and off the Hugoniot, past mu_max), tension
    call check_consistency(eos, [rho0*1.02_wp, rho0*1.1_wp, rho0*1.3_wp, rho0*1.5_wp, 17.0_wp, &
                                 rho0*0.95_wp, rho0*0.8_wp], &
                           [0.0_wp, 0.07729203458246812_wp, 1.0_wp, 0.2_wp, 0.5_wp, 0.01_wp, 0.0_wp], &
                           'mie_gruneisen')
    ! and the ideal gas through the same helper
    call check_consistency(ideal_gas(), [0.125_wp, 1.0_wp, 7.5_wp], [2.0_wp, 2.5_wp, 1.0e-3_wp], 'ideal_gas')

    ! factory: one bad parameter gives one message naming it
    par%s1 = 0.0_wp
    call eos_create('mie_gruneisen', par, eos, err)
    call check(allocated(err), 'mie_gruneisen: s1 = 0 is refused')
    if (allocated(err)) then
      call check(index(err%msg, 's1 = 0.00000E+00 must be > 0') > 0 .and. index(err%msg, ';') == 0, &
                 'mie_gruneisen: the message names s1, its value and the rule, and nothing else')
      deallocate(err)
    end if
    par%s1 = s1
    par%gamma0 = -1.0_wp
    call eos_create('mie_gruneisen', par, eos, err)
    call check(allocated(err), 'mie_gruneisen: gamma0 < 0 is refused')
    if (allocated(err)) then
      call check(index(err%msg, 'gamma0') > 0, 'mie_gruneisen: the message names gamma0')
      deallocate(err)
    end if
  end subroutine test_mie_gruneisen

  !> A fresh ideal gas with gamma = 5/3.
  function ideal_gas() result(g)
    class(eos_t), allocatable :: g
    type(error_t), allocatable :: err
    call eos_create('ideal_gas', eos_params_t(gamma=5.0_wp/3.0_wp), g, err)
  end function ideal_gas

end program test_eos
