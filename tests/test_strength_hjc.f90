!> Unit tests of the Holmquist-Johnson-Cook concrete model
!> (modules/strength/strength_hjc) and of the bilinear model's failure
!> strain (PARTICLES.md §2.5, §2.6): the kernel called on one point, and the
!> particle path (one cell, eight particles, node velocities prescribed, as
!> tests/test_particles_lagrange.f90). Table 7 constants in MPa (G = 14.86
!> GPa, rho0 = 2.44e-3 g/mm^3: any positive values serve here), eps_dot0 = 1.
!> Expected values are closed forms written out here; the printed ones of
!> PARTICLES.md §2.5-2.6 are checked within half a unit of their last digit.
!>  1. Loading curve p(mu) at the eight mu of §2.5: the closed form to
!>     round-off (1e-12 relative) and the printed table within its rounding.
!>  2. Unloading slopes (unload by 1e-4 in mu from mu_max): K_e (I),
!>     (1 - F) K_e + F K1 (II), K1 (III), to 1e-9 relative (the difference
!>     quotient of a straight line: round-off of p_max/dmu ~ 1e-12); reloading
!>     to mu_max gives p_max back.
!>  3. Uniaxial compression (lateral stresses held at 0 by bisection on the
!>     lateral strain), damage off (EFMIN 1e30): the axial stress settles on
!>     the fixed point sigma* = A + B (sigma*/3)^N (Newton here): 2.0634 and
!>     86.7 MPa printed; with D = 1 from the start, sigma* = (B/3^N)^(1/(1-N))
!>     = 0.5986, 25.1 MPa. Tolerance 1e-9 relative (bisection to 1e-15 of the
!>     strain step).
!>  4. Rate factor: an isochoric path at p = 0, damage off: q/(A f'_c) =
!>     1 + C ln 100 = 1.0322 at 100/s and 1 at 0.5/s (guarded), 1e-12.
!>  5. Uniaxial tension: sigma_t = f'_c A/(1 + f'_c A/(3T)) = 8.97 MPa
!>     (damage off, 1e-9); hydrostatic tension: p = -T = -4.1 MPa exactly,
!>     no damage (no plastic strain, no compaction).
!>  6. Damage against its closed form on isochoric paths (constant p, so
!>     Delta mu_p = 0): D = eps_p/max(EFMIN, D1 (P* + T*)^D2) at p = 0 and at
!>     p = 6 MPa (region I), to 1e-12; at p = 0 the particle fails in the
!>     step D reaches 1, its stress is then zero and the eroded energy is
!>     q^2/(6G) of the stress after the return, q = A (1 - D^n) f'_c.
!>  7. Particle path: hydrostatic compression into region II, p = the
!>     loading curve at the particles' density, then unloading on the line
!>     of slope (1 - F) K_e + F K1, to 1e-10 relative; deviator zero; the
!>     stable-step modulus is K1 + 4G/3.
!>  8. Bilinear failure (particle path, uniaxial strain tension, K 5, G 3,
!>     y0 0.06, Et 0.5): eps_p = (2G e n - y0)/(3G + H) after step n; the
!>     particle fails in the step it crosses failure_strain (not before);
!>     the eroded energy of that step is 8 V [q^2/(6G) + p^2/(2K)], q = y0
!>     + H eps_p, p = K n e (tension), and of the next tension step
!>     8 V [(2G e)^2/(6G) + (K e)^2/(2K)], to 1e-12; after it no shear and
!>     no tension, and compression gives p = K n e with no deviator (the
!>     step's trial deviator, q = 2G e, is what is eroded then).
!>  9. The particle's size (hjc_length L_ref = 20 mm): on the isochoric
!>     path at p = 0 of test 6 a particle of size l books eps_p l/L_ref
!>     towards its damage, D = eps_p (l/L_ref)/(D1 T*^D2) to 1e-12 for l =
!>     10, 20 and 40 mm, and fails when eps_p l/L_ref crosses eps_f: at
!>     twice the strain at l = 10 mm, half of it at 40 mm (the crack opens by
!>     eps_f L_ref whatever l); a size not known (l = 0) and L_ref = 0 leave
!>     test 6's damage. Compaction is booked unscaled: hydrostatic loading
!>     into region II at l = L_ref/4 gives D = mu_p/eps_f as at l = L_ref
!>     (the same steps, 1e-12).
program test_strength_hjc
  use base_kinds, only: wp
  use base_errors, only: error_t
  use mesh_grid, only: grid_t, grid_init_box
  use particles_state, only: particles_t, particles_allocate, particles_order
  use particles_lagrange, only: particles_velocity_gradients, particles_stress_update, strength_slot_t
  use strength_models, only: strength_params_t, strength_point_t, strength_mises, strength_principal_max, &
                             strength_t, voigt_to_tensor, tensor_to_voigt
  use strength_factory, only: strength_create
  use strength_hjc, only: strength_hjc_t, hjc_new, hjc_load, hjc_unload_modulus, hjc_nhist
  use test_assert, only: check, check_close, check_summary
  use test_one_cell, only: one_cell
  implicit none
  real(wp), parameter :: eps = epsilon(1.0_wp)
  ! Table 7 (MPa), G and rho0 (module notes)
  real(wp), parameter :: ta = 0.79_wp, tb = 1.60_wp, tn = 0.61_wp, tc = 0.007_wp, fc = 42.0_wp, smax = 7.0_wp, &
                         tt = 4.1_wp, d1 = 0.04_wp, d2 = 1.0_wp, efmin = 0.001_wp, pcrush = 12.0_wp, &
                         mucrush = 0.001_wp, plock = 800.0_wp, mulock = 0.10_wp, k1 = 85000.0_wp, &
                         k2 = -171000.0_wp, k3 = 208000.0_wp, gmod = 14860.0_wp, rho0 = 2.44e-3_wp

  call test_loading()
  call test_unloading()
  call test_uniaxial_compression()
  call test_rate()
  call test_tension()
  call test_damage()
  call test_damage_length()
  call test_particles_hydrostatic()
  call test_bilinear_failure()
  call test_principal_max()
  call test_bilinear_tension()
  call check_summary('test_strength_hjc')

contains

  !> Table 7's parameters (efmin_ replaces EFMIN: 1e30 switches damage off).
  type(strength_params_t) function table7(efmin_) result(par)
    real(wp), intent(in) :: efmin_
    par = strength_params_t(g=gmod, hjc_a=ta, hjc_b=tb, hjc_n=tn, hjc_c=tc, hjc_fc=fc, hjc_smax=smax, hjc_t=tt, &
      hjc_d1=d1, hjc_d2=d2, hjc_efmin=efmin_, hjc_pcrush=pcrush, hjc_mucrush=mucrush, hjc_plock=plock, &
      hjc_mulock=mulock, hjc_k1=k1, hjc_k2=k2, hjc_k3=k3, hjc_eps0=1.0_wp, hjc_rho0=rho0)
  end function table7

  type(strength_hjc_t) function model_of(efmin_) result(m)
    real(wp), intent(in) :: efmin_
    character(len=:), allocatable :: msg
    call hjc_new(table7(efmin_), m, msg)
    call check(len(msg) == 0, 'hjc model built: '//msg)
  end function model_of

  !> mu_plock of Table 7 by Newton on the cubic (written out here).
  real(wp) function mu_plock() result(mu)
    real(wp) :: mb
    integer :: it
    mb = plock/k1
    do it = 1, 50
      mb = mb - (mb*(k1 + mb*(k2 + mb*k3)) - plock)/(k1 + mb*(2.0_wp*k2 + 3.0_wp*mb*k3))
    end do
    mu = mulock + mb*(1.0_wp + mulock)
  end function mu_plock

  !> The loading curve (PARTICLES.md §2.5, written out).
  real(wp) function p_curve(mu) result(p)
    real(wp), intent(in) :: mu
    real(wp) :: mb
    if (mu <= mucrush) then
      p = pcrush/mucrush*mu
    else if (mu <= mu_plock()) then
      p = pcrush + (plock - pcrush)*(mu - mucrush)/(mu_plock() - mucrush)
    else
      mb = (mu - mulock)/(1.0_wp + mulock)
      p = k1*mb + k2*mb**2 + k3*mb**3
    end if
  end function p_curve

  !> One kernel step of model m: strain increment deps at the density rho
  !> (dw = 0) and step dt, of a particle of size length (absent: not
  !> known); returns the pressure.
  real(wp) function step(m, deps, rho, dt, stress, hist, eroded, length) result(p)
    type(strength_hjc_t), intent(in) :: m
    real(wp), intent(in) :: deps(3, 3), rho, dt
    real(wp), intent(inout) :: stress(6), hist(:)
    real(wp), intent(out), optional :: eroded
    real(wp), intent(in), optional :: length
    type(strength_point_t) :: pt
    pt = strength_point_t(dt=dt, rho=rho)
    if (present(length)) pt%length = length
    call m%update(deps, spread([0.0_wp, 0.0_wp, 0.0_wp], 2, 3), pt, stress, hist)
    p = -(stress(1) + stress(2) + stress(3))/3.0_wp
    if (present(eroded)) eroded = pt%eroded
  end function step

  pure function diag(a, b, c) result(t)
    real(wp), intent(in) :: a, b, c
    real(wp) :: t(3, 3)
    t = 0.0_wp
    t(1, 1) = a; t(2, 2) = b; t(3, 3) = c
  end function diag

  subroutine test_loading()
    type(strength_hjc_t) :: m
    real(wp) :: stress(6), hist(hjc_nhist), p
    real(wp), parameter :: mus(8) = [0.0005_wp, 0.001_wp, 0.01_wp, 0.05_wp, 0.10_wp, 0.11055_wp, 0.12_wp, 0.15_wp]
    real(wp), parameter :: table(8) = [6.00_wp, 12.00_wp, 76.74_wp, 364.45_wp, 724.09_wp, 800.0_wp, 1490.2_wp, &
                                       3529.9_wp]
    real(wp), parameter :: half_unit(8) = [0.005_wp, 0.005_wp, 0.005_wp, 0.005_wp, 0.005_wp, 0.05_wp, 0.05_wp, &
                                           0.05_wp]
    character(len=16) :: lab
    integer :: i
    m = model_of(efmin)
    call check(hjc_nhist == 6 .and. m%nhist() == 6, 'hjc: six history variables')
    call check_close('hjc: mu_plock (Newton here, bisection in the model)', m%muplock, mu_plock(), 1.0e-14_wp)
    do i = 1, 8
      stress = 0.0_wp
      hist = 0.0_wp
      p = step(m, diag(0.0_wp, 0.0_wp, 0.0_wp), rho0*(1.0_wp + mus(i)), 1.0_wp, stress, hist)
      write(lab, '(f8.5)') mus(i)
      call check_close('hjc loading: p/p_curve - 1 at mu ='//lab, p/p_curve(mus(i)) - 1.0_wp, 0.0_wp, 1.0e-12_wp)
      call check_close('hjc loading: p against the printed table at mu ='//lab, p, table(i), half_unit(i))
      call check_close('hjc loading: no deviator', maxval(abs(stress(1:3) + p)) + maxval(abs(stress(4:6))), &
                       0.0_wp, 4*eps*p)
    end do
  end subroutine test_loading

  subroutine test_unloading()
    type(strength_hjc_t) :: m
    real(wp) :: stress(6), hist(hjc_nhist), p1, p2, p3, ku, f
    real(wp), parameter :: mus(3) = [0.0005_wp, 0.05_wp, 0.12_wp], dmu = 1.0e-4_wp
    character(len=*), parameter :: what(3) = [character(len=40) :: 'region I: K_e', &
                                               'region II: (1 - F) K_e + F K1', 'region III: K1']
    integer :: i
    m = model_of(efmin)
    do i = 1, 3
      select case (i)
      case (1)
        ku = pcrush/mucrush
      case (2)
        f = (mus(i) - mucrush)/(mu_plock() - mucrush)
        ku = (1.0_wp - f)*pcrush/mucrush + f*k1
      case default
        ku = k1
      end select
      stress = 0.0_wp
      hist = 0.0_wp
      p1 = step(m, diag(0.0_wp, 0.0_wp, 0.0_wp), rho0*(1.0_wp + mus(i)), 1.0_wp, stress, hist)
      p2 = step(m, diag(0.0_wp, 0.0_wp, 0.0_wp), rho0*(1.0_wp + mus(i) - dmu), 1.0_wp, stress, hist)
      call check_close('hjc unloading slope/expected - 1, '//trim(what(i)), ((p1 - p2)/dmu)/ku - 1.0_wp, 0.0_wp, &
                       1.0e-9_wp)
      call check_close('hjc unloading modulus of the model, '//trim(what(i)), &
                       hjc_unload_modulus(m, hist(3))/ku - 1.0_wp, 0.0_wp, 1.0e-14_wp)
      p3 = step(m, diag(0.0_wp, 0.0_wp, 0.0_wp), rho0*(1.0_wp + mus(i)), 1.0_wp, stress, hist)
      call check_close('hjc reloading to mu_max: p/p_max - 1, '//trim(what(i)), p3/p1 - 1.0_wp, 0.0_wp, 1.0e-12_wp)
    end do
    call check_close('hjc: stable-step modulus K1 + 4G/3 (K1 > K_e)', m%wave_modulus(), k1 + 4.0_wp*gmod/3.0_wp, &
                     0.0_wp)
  end subroutine test_unloading

  !> Uniaxial stress (lateral stresses 0) by axial increments dex, nsteps
  !> of dt: returns the final axial stress (tension positive); hist starts
  !> as given.
  real(wp) function uniaxial(m, hist, dex, nsteps, dt) result(sxx)
    type(strength_hjc_t), intent(in) :: m
    real(wp), intent(inout) :: hist(:)
    real(wp), intent(in) :: dex, dt
    integer, intent(in) :: nsteps
    real(wp) :: stress(6), rho, lo, hi, mid, s_try(6), h_try(size(hist)), p, rho_try
    integer :: n, it
    stress = 0.0_wp
    rho = rho0
    do n = 1, nsteps
      lo = -0.1_wp
      hi = 0.1_wp
      do it = 1, 200
        mid = 0.5_wp*(lo + hi)
        s_try = stress
        h_try = hist
        rho_try = rho/((1.0_wp + dex)*(1.0_wp + mid)**2)
        p = step(m, diag(dex, mid, mid), rho_try, dt, s_try, h_try)
        if (s_try(2) < 0.0_wp) then
          lo = mid
        else
          hi = mid
        end if
        if (.not. hi - lo > 1.0e-15_wp*abs(dex)) exit
      end do
      rho = rho/((1.0_wp + dex)*(1.0_wp + hi)**2)
      p = step(m, diag(dex, hi, hi), rho, dt, stress, hist)
    end do
    sxx = stress(1)
  end function uniaxial

  subroutine test_uniaxial_compression()
    type(strength_hjc_t) :: m
    real(wp) :: hist(hjc_nhist), s, sigma, sd
    integer :: it
    m = model_of(1.0e30_wp)
    ! sigma* = A + B (sigma*/3)^N by Newton
    s = 2.0_wp
    do it = 1, 50
      s = s - (s - ta - tb*(s/3.0_wp)**tn)/(1.0_wp - tb*tn/3.0_wp*(s/3.0_wp)**(tn - 1.0_wp))
    end do
    hist = 0.0_wp
    sigma = -uniaxial(m, hist, -2.0e-5_wp, 300, 1.0_wp)
    call check_close('hjc uniaxial compression, intact: sigma/(f''c sigma*) - 1', sigma/(fc*s) - 1.0_wp, 0.0_wp, &
                     1.0e-9_wp)
    call check_close('hjc uniaxial compression, intact: sigma* (printed 2.0634)', sigma/fc, 2.0634_wp, 5.0e-5_wp)
    call check_close('hjc uniaxial compression, intact: sigma (MPa, printed 86.7)', sigma, 86.7_wp, 0.05_wp)
    call check_close('hjc uniaxial compression, intact: damage stays 0', hist(2), 0.0_wp, 1.0e-20_wp)
    ! fully damaged: sigma* = (B/3^N)^(1/(1-N))
    sd = (tb/3.0_wp**tn)**(1.0_wp/(1.0_wp - tn))
    hist = 0.0_wp
    hist(2) = 1.0_wp
    sigma = -uniaxial(m, hist, -2.0e-5_wp, 300, 1.0_wp)
    call check_close('hjc uniaxial compression, D = 1: sigma/(f''c sigma*) - 1', sigma/(fc*sd) - 1.0_wp, 0.0_wp, &
                     1.0e-9_wp)
    call check_close('hjc uniaxial compression, D = 1: sigma* (printed 0.5986)', sigma/fc, 0.5986_wp, 5.0e-5_wp)
    call check_close('hjc uniaxial compression, D = 1: sigma (MPa, printed 25.1)', sigma, 25.1_wp, 0.05_wp)
    call check(hist(6) < 0.5_wp, 'hjc: fully damaged under pressure is not failed')
  end subroutine test_uniaxial_compression

  !> Isochoric stretching at equivalent rate `rate` (p = 0), damage off:
  !> q/(A f'_c) at the end.
  real(wp) function rate_ratio(rate) result(r)
    real(wp), intent(in) :: rate
    type(strength_hjc_t) :: m
    real(wp) :: stress(6), hist(hjc_nhist), p, dt
    integer :: n
    m = model_of(1.0e30_wp)
    stress = 0.0_wp
    hist = 0.0_wp
    dt = 1.0e-4_wp/rate
    do n = 1, 100
      p = step(m, rate*dt*diag(1.0_wp, -0.5_wp, -0.5_wp), rho0, dt, stress, hist)
    end do
    r = strength_mises([stress(1:3) + p, stress(4:6)])/(ta*fc)
    call check_close('hjc rate path: p', p, 0.0_wp, 0.0_wp)
  end function rate_ratio

  subroutine test_rate()
    call check_close('hjc rate factor at 100/s: q/(A f''c) - (1 + C ln 100)', rate_ratio(100.0_wp), &
                     1.0_wp + tc*log(100.0_wp), 1.0e-12_wp)
    call check_close('hjc rate factor at 100/s (printed 1.0322)', rate_ratio(100.0_wp), 1.0322_wp, 5.0e-5_wp)
    call check_close('hjc rate factor at 0.5/s (below eps_dot0: 1)', rate_ratio(0.5_wp), 1.0_wp, 1.0e-12_wp)
  end subroutine test_rate

  subroutine test_tension()
    type(strength_hjc_t) :: m
    real(wp) :: hist(hjc_nhist), sigma, stress(6), p, rho
    integer :: n
    m = model_of(1.0e30_wp)
    hist = 0.0_wp
    sigma = uniaxial(m, hist, 2.0e-6_wp, 300, 1.0_wp)
    call check_close('hjc uniaxial tension: sigma/(f''c A/(1 + f''c A/(3T))) - 1', &
                     sigma/(fc*ta/(1.0_wp + fc*ta/(3.0_wp*tt))) - 1.0_wp, 0.0_wp, 1.0e-9_wp)
    call check_close('hjc uniaxial tension (MPa, printed 8.97)', sigma, 8.97_wp, 0.005_wp)
    ! hydrostatic tension, the real damage constants
    m = model_of(efmin)
    stress = 0.0_wp
    hist = 0.0_wp
    rho = rho0
    do n = 1, 20
      rho = rho/(1.0_wp + 1.0e-4_wp)**3
      p = step(m, diag(1.0e-4_wp, 1.0e-4_wp, 1.0e-4_wp), rho, 1.0_wp, stress, hist)
    end do
    call check_close('hjc hydrostatic tension: p (MPa, -T = -4.1)', p, -tt, 0.0_wp)
    call check_close('hjc hydrostatic tension: damage', hist(2), 0.0_wp, 0.0_wp)
  end subroutine test_tension

  !> Isochoric stretching at density rho (pressure constant) until the
  !> damage reaches 1 or nmax steps: the largest misfit of D against
  !> eps_p/eps_f, the step of failure (0: none), and the misfit of the
  !> eroded energy in that step.
  subroutine damage_path(rho, pstar, nmax, misfit, nfail, ero_misfit)
    real(wp), intent(in) :: rho, pstar
    integer, intent(in) :: nmax
    real(wp), intent(out) :: misfit, ero_misfit
    integer, intent(out) :: nfail
    type(strength_hjc_t) :: m
    real(wp) :: stress(6), hist(hjc_nhist), p, ef, d_old, ero, q, epsp_old
    integer :: n
    m = model_of(efmin)
    ef = max(efmin, d1*(pstar + tt/fc)**d2)
    stress = 0.0_wp
    hist = 0.0_wp
    misfit = 0.0_wp
    ero_misfit = 0.0_wp
    nfail = 0
    do n = 1, nmax
      d_old = hist(2)
      epsp_old = hist(1)
      p = step(m, 1.0e-5_wp*diag(1.0_wp, -0.5_wp, -0.5_wp), rho, 1.0_wp, stress, hist, ero)
      if (hist(6) > 0.5_wp) then
        nfail = n
        ! the stress after the return: q = A (1 - D^n) f'c (rate below eps_dot0)
        q = ta*(1.0_wp - d_old)*fc
        ero_misfit = ero/(q**2/(6.0_wp*gmod)) - 1.0_wp
        call check(hist(1) >= ef .and. epsp_old < ef, 'hjc: fails in the step eps_p crosses eps_f')
        call check_close('hjc failed: stress', maxval(abs(stress)), 0.0_wp, 0.0_wp)
        exit
      end if
      misfit = max(misfit, abs(hist(2) - min(hist(1)/ef, 1.0_wp)))
      if (ero > 0.0_wp) misfit = huge(1.0_wp)
    end do
  end subroutine damage_path

  subroutine test_damage()
    real(wp) :: misfit, ero_misfit
    integer :: nfail
    call damage_path(rho0, 0.0_wp, 2000, misfit, nfail, ero_misfit)
    call check_close('hjc damage at p = 0: |D - eps_p/(D1 T*^D2)|', misfit, 0.0_wp, 1.0e-12_wp)
    call check(nfail > 0, 'hjc: fully damaged at p = 0 fails')
    call check_close('hjc failure at p = 0: eroded/(q^2/(6G)) - 1', ero_misfit, 0.0_wp, 1.0e-12_wp)
    ! region I, mu = 0.0005: p = 6 MPa
    call damage_path(rho0*1.0005_wp, 6.0_wp/fc, 2000, misfit, nfail, ero_misfit)
    call check_close('hjc damage at p = 6: |D - eps_p/(D1 (P* + T*)^D2)|', misfit, 0.0_wp, 1.0e-12_wp)
    call check(nfail == 0, 'hjc: fully damaged under pressure does not fail')
  end subroutine test_damage


  !> Test 9 (header).
  subroutine test_damage_length()
    real(wp), parameter :: lref = 20.0_wp
    character(len=3), parameter :: ratio(3) = ['0.5', '1  ', '2  ']
    real(wp) :: ef, misfit, epsf(3), dc(2)
    integer :: i
    ef = max(efmin, d1*(tt/fc)**d2)
    do i = 1, 3
      call length_path(lref, lref*0.5_wp*2.0_wp**(i - 1), misfit, epsf(i))
      call check_close('hjc damage at p = 0, l/L_ref = '//trim(ratio(i))// &
                       ': |D - eps_p (l/L_ref)/eps_f|', misfit, 0.0_wp, 1.0e-12_wp)
    end do
    ! (within two of the path's strain steps of 1e-5: the step that crosses,
    ! or the next if round-off leaves the summed damage a hair below 1)
    call check_close('hjc: strain to fracture at l = L_ref/2, /(2 eps_f) - 1', epsf(1)/(2.0_wp*ef) - 1.0_wp, 0.0_wp, &
                     2.0e-5_wp/(2.0_wp*ef))
    call check_close('hjc: strain to fracture at l = L_ref, /eps_f - 1', epsf(2)/ef - 1.0_wp, 0.0_wp, 2.0e-5_wp/ef)
    call check_close('hjc: strain to fracture at l = 2 L_ref, /(eps_f/2) - 1', epsf(3)/(0.5_wp*ef) - 1.0_wp, 0.0_wp, &
                     2.0e-5_wp/(0.5_wp*ef))
    call length_path(lref, 0.0_wp, misfit, epsf(1))
    call check_close('hjc damage, size not known: |D - eps_p/eps_f|', misfit, 0.0_wp, 1.0e-12_wp)
    call length_path(0.0_wp, 10.0_wp, misfit, epsf(1))
    call check_close('hjc damage, hjc_length = 0: |D - eps_p/eps_f|', misfit, 0.0_wp, 1.0e-12_wp)
    dc(1) = compaction_damage(lref, lref)
    dc(2) = compaction_damage(lref, 0.25_wp*lref)
    call check(dc(1) > 0.0_wp, 'hjc: hydrostatic loading into region II damages')
    call check_close('hjc: compaction damage at l = L_ref/4 against l = L_ref', dc(2)/dc(1) - 1.0_wp, 0.0_wp, 1.0e-12_wp)
  end subroutine test_damage_length

  !> Table 7's model with hjc_length lref.
  type(strength_hjc_t) function model_with_length(lref) result(m)
    real(wp), intent(in) :: lref
    type(strength_params_t) :: par
    character(len=:), allocatable :: msg
    par = table7(efmin)
    par%hjc_length = lref
    call hjc_new(par, m, msg)
    call check(len(msg) == 0, 'hjc model with hjc_length built: '//msg)
    call check(m%wants_length .eqv. lref > 0.0_wp, 'hjc: reads the particle size exactly when hjc_length > 0')
  end function model_with_length

  !> The isochoric path of `damage_path` at p = 0 for a model with
  !> hjc_length lref and a particle of size l: the largest misfit of D
  !> against eps_p s/eps_f before failure (s = l/lref, or 1 when either is
  !> 0), and the plastic strain at failure (huge: none in 20000 steps).
  subroutine length_path(lref, l, misfit, epsf)
    real(wp), intent(in) :: lref, l
    real(wp), intent(out) :: misfit, epsf
    type(strength_hjc_t) :: m
    real(wp) :: stress(6), hist(hjc_nhist), p, ef, s
    integer :: n
    m = model_with_length(lref)
    ef = max(efmin, d1*(tt/fc)**d2)
    s = 1.0_wp
    if (lref > 0.0_wp .and. l > 0.0_wp) s = l/lref
    stress = 0.0_wp
    hist = 0.0_wp
    misfit = 0.0_wp
    epsf = huge(1.0_wp)
    do n = 1, 20000
      p = step(m, 1.0e-5_wp*diag(1.0_wp, -0.5_wp, -0.5_wp), rho0, 1.0_wp, stress, hist, length=l)
      if (hist(6) > 0.5_wp) then
        epsf = hist(1)
        exit
      end if
      misfit = max(misfit, abs(hist(2) - min(hist(1)*s/ef, 1.0_wp)))
    end do
    if (p > 0.0_wp) misfit = huge(1.0_wp)
  end subroutine length_path

  !> The damage after hydrostatic loading of a model with hjc_length lref,
  !> particle size l, to mu = 0.01 (region II) in 100 steps.
  real(wp) function compaction_damage(lref, l) result(d)
    real(wp), intent(in) :: lref, l
    type(strength_hjc_t) :: m
    real(wp) :: stress(6), hist(hjc_nhist), p, rho, e
    integer :: n
    m = model_with_length(lref)
    stress = 0.0_wp
    hist = 0.0_wp
    e = -1.0e-4_wp/3.0_wp
    rho = rho0
    do n = 1, 100
      rho = rho0*(1.0_wp + 1.0e-4_wp*n)
      p = step(m, diag(e, e, e), rho, 1.0_wp, stress, hist, length=l)
    end do
    d = hist(2)
    call check(p > pcrush .and. abs(hist(1)) < tiny(1.0_wp), 'hjc hydrostatic compaction: region II, no plastic strain')
  end function compaction_damage

  subroutine test_particles_hydrostatic()
    type(grid_t) :: g
    type(particles_t) :: p
    type(strength_slot_t), allocatable :: models(:)
    type(error_t), allocatable :: err
    real(wp) :: u(3, 8), lgrad(3, 3, 8), dt, mu, misfit, dev, mu_max, p_max, f, ku
    integer :: n, bad, k, stp
    call one_cell(g, p, hjc_nhist, rho0)
    allocate(models(1))
    call strength_create('hjc', table7(efmin), models(1)%m, err)
    call check(.not. allocated(err), 'hjc from the factory')
    do k = 1, 8
      call models(1)%m%hist_init(p%hist(:, k))
    end do
    misfit = 0.0_wp
    dev = 0.0_wp
    dt = 1.0e-3_wp
    do n = 1, 8
      u(:, n) = -1.0_wp*g%x(:, n)   ! L = -I: 0.1 % volume per step
    end do
    do stp = 1, 30
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad)
      do k = 1, 8
        mu = p%rho(k)/rho0 - 1.0_wp
        misfit = max(misfit, abs(-p%stress(1, k)/p_curve(mu) - 1.0_wp))
        dev = max(dev, maxval(abs(p%stress(1:3, k) - p%stress(1, k))), maxval(abs(p%stress(4:6, k))))
      end do
    end do
    call check(bad == 0, 'hjc particles: volumes stay positive')
    call check_close('hjc particles, hydrostatic loading: p/p_curve(rho/rho0 - 1) - 1', misfit, 0.0_wp, 1.0e-10_wp)
    mu_max = p%rho(1)/rho0 - 1.0_wp
    call check(mu_max > mucrush, 'hjc particles: loaded into region II')
    p_max = p_curve(mu_max)
    f = (mu_max - mucrush)/(mu_plock() - mucrush)
    ku = (1.0_wp - f)*pcrush/mucrush + f*k1
    misfit = 0.0_wp
    u = -u
    dt = 1.0e-4_wp   ! 0.03 % of volume a step: 5 steps stay above the tension cut
    do stp = 1, 5
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad)
      do k = 1, 8
        mu = p%rho(k)/rho0 - 1.0_wp
        misfit = max(misfit, abs(-p%stress(1, k)/(p_max + ku*(mu - mu_max)) - 1.0_wp))
        dev = max(dev, maxval(abs(p%stress(1:3, k) - p%stress(1, k))), maxval(abs(p%stress(4:6, k))))
      end do
    end do
    call check_close('hjc particles, unloading: p/(p_max + K_u (mu - mu_max)) - 1', misfit, 0.0_wp, 1.0e-10_wp)
    call check_close('hjc particles: deviator of a hydrostatic path', dev, 0.0_wp, 64*eps*p_max)
  end subroutine test_particles_hydrostatic

  subroutine test_bilinear_failure()
    type(grid_t) :: g
    type(particles_t) :: p
    type(strength_slot_t), allocatable :: models(:)
    type(error_t), allocatable :: err
    real(wp), parameter :: kmod = 5.0_wp, y0 = 0.06_wp, et = 0.5_wp, g3 = 3.0_wp
    real(wp) :: u(3, 8), lgrad(3, 3, 8), dt, e, e_mod, h, ef, eroded, epsp, q, pm, vol, jstep, expect, ek(8)
    integer :: n, bad, stp, nfail
    call one_cell(g, p, 1)
    e_mod = 9.0_wp*kmod*g3/(3.0_wp*kmod + g3)
    h = e_mod*et/(e_mod - et)
    dt = y0/(2.0_wp*g3)/10.5_wp
    e = dt
    ! fails in step 30: between eps_p after 29 and 30 steps
    ef = 0.5_wp*((2.0_wp*g3*e*29 - y0) + (2.0_wp*g3*e*30 - y0))/(3.0_wp*g3 + h)
    allocate(models(1))
    call strength_create('bilinear', strength_params_t(k=kmod, g=g3, y0=y0, et=et, failure_strain=ef), &
                         models(1)%m, err)
    call check(.not. allocated(err), 'bilinear with failure_strain')
    do n = 1, 8
      u(:, n) = [g%x(1, n), 0.0_wp, 0.0_wp]   ! L_xx = 1: uniaxial strain tension
    end do
    jstep = (1.0_wp + 0.5_wp*e)/(1.0_wp - 0.5_wp*e)
    nfail = 0
    do stp = 1, 31
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad, ek)
      eroded = sum(ek)
      if (nfail == 0 .and. models(1)%m%failed(p%hist(:, 1))) then
        nfail = stp
        epsp = (2.0_wp*g3*e*stp - y0)/(3.0_wp*g3 + h)
        call check_close('bilinear failure: eps_p/((2G e n - y0)/(3G + H)) - 1', p%hist(1, 1)/epsp - 1.0_wp, &
                         0.0_wp, 1.0e-12_wp)
        q = y0 + h*epsp
        pm = kmod*e*stp
        vol = 0.125_wp*jstep**stp
        expect = 8.0_wp*vol*(q**2/(6.0_wp*g3) + pm**2/(2.0_wp*kmod))
        call check_close('bilinear failure step: eroded/(8 V (q^2/(6G) + p^2/(2K))) - 1', eroded/expect - 1.0_wp, &
                         0.0_wp, 1.0e-12_wp)
      else if (nfail == 0) then
        call check(.not. abs(eroded) > 0.0_wp, 'bilinear: nothing eroded before failure')
      end if
      if (stp == 31) then
        vol = 0.125_wp*jstep**stp
        expect = 8.0_wp*vol*((2.0_wp*g3*e)**2/(6.0_wp*g3) + (kmod*e)**2/(2.0_wp*kmod))
        call check_close('bilinear, failed, tension step: eroded/expected - 1', eroded/expect - 1.0_wp, 0.0_wp, &
                         1.0e-12_wp)
      end if
    end do
    call check(nfail == 30, 'bilinear: fails in the step eps_p crosses failure_strain (30)')
    call check_close('bilinear failed, after tension: stress', maxval(abs(p%stress)), 0.0_wp, 0.0_wp)
    u = -u
    do stp = 1, 5
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad, ek)
      eroded = sum(ek)
    end do
    call check_close('bilinear failed, compressed: sigma_ii/(-5 K e) - 1', &
                     maxval(abs(p%stress(1:3, :)/(-5.0_wp*kmod*e) - 1.0_wp)), 0.0_wp, 64*eps)
    call check_close('bilinear failed, compressed: shear', maxval(abs(p%stress(4:6, :))), 0.0_wp, 0.0_wp)
    ! the trial deviator of the step, 2G dev(deps) with q = 2G e, is removed
    vol = 0.125_wp*jstep**26
    expect = 8.0_wp*vol*(2.0_wp*g3*e)**2/(6.0_wp*g3)
    call check_close('bilinear failed, compressed: eroded/(8 V (2G e)^2/(6G)) - 1', eroded/expect - 1.0_wp, &
                     0.0_wp, 1.0e-12_wp)
  end subroutine test_bilinear_failure

  !> The largest principal stress of R diag(a) R^T, R a rotation about an
  !> oblique axis, is max(a), for distinct, repeated and equal values (to
  !> 1e-12 of the stress: the Jacobi sweeps stop at an off-diagonal part of
  !> 1e-12 of the matrix's size).
  subroutine test_principal_max()
    real(wp) :: r(3, 3), n(3), th, a(3, 4), st(3, 3)
    integer :: k
    n = [1.0_wp, 2.0_wp, 2.0_wp]/3.0_wp
    th = 0.7_wp
    r = cos(th)*reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3]) + (1.0_wp - cos(th))*spread(n, 2, 3)*spread(n, 1, 3) + &
        sin(th)*reshape([0.0_wp, n(3), -n(2), -n(3), 0.0_wp, n(1), n(2), -n(1), 0.0_wp], [3, 3])
    a = reshape([3.0_wp, -1.0_wp, 0.5_wp, -2.0_wp, -2.0_wp, 1.0_wp, 4.0_wp, 4.0_wp, -3.0_wp, 2.0_wp, 2.0_wp, &
                 2.0_wp], [3, 4])
    do k = 1, 4
      st = matmul(r, matmul(voigt_to_tensor([a(:, k), 0.0_wp, 0.0_wp, 0.0_wp]), transpose(r)))
      call check_close('principal max of a rotated diagonal stress - max(a)', &
                       strength_principal_max(tensor_to_voigt(st)) - maxval(a(:, k)), 0.0_wp, 1.0e-12_wp*maxval(abs(a)))
    end do
  end subroutine test_principal_max

  !> Bilinear with tensile_strength: an elastic particle (yield far away)
  !> in uniaxial strain tension, sigma_xx = (K + 4G/3) e n after n steps,
  !> fails in the step sigma_xx crosses the strength and loses its stress,
  !> the eroded energy q^2/(6G) + p^2/(2K) of that step's stress; one in
  !> pure shear (sigma_1 = the shear stress 2G e n) likewise.
  subroutine test_bilinear_tension()
    class(strength_t), allocatable :: m
    type(error_t), allocatable :: err
    type(strength_point_t) :: pt
    real(wp), parameter :: kmod = 5.0_wp, g3 = 3.0_wp, e = 1.0e-3_wp
    real(wp) :: stress(6), hist(2), deps(3, 3), q, pm, sxx, tau
    integer :: stp, nfail, k
    do k = 1, 2
      deps = 0.0_wp
      if (k == 1) then
        deps(1, 1) = e
        sxx = (kmod + 4.0_wp*g3/3.0_wp)*e
      else
        deps(1, 2) = e
        deps(2, 1) = e
        sxx = 2.0_wp*g3*e
      end if
      ! (between the stresses after 6 and 7 steps)
      call strength_create('bilinear', strength_params_t(k=kmod, g=g3, y0=1.0e3_wp, et=0.5_wp, &
                           tensile_strength=6.5_wp*sxx), m, err)
      call check(.not. allocated(err), 'bilinear with tensile_strength')
      call check(m%nhist() == 2, 'bilinear with tensile_strength: two history variables')
      stress = 0.0_wp
      hist = 0.0_wp
      nfail = 0
      do stp = 1, 9
        call m%update(deps, 0.0_wp*deps, pt, stress, hist)
        if (nfail == 0 .and. m%failed(hist)) then
          nfail = stp
          if (k == 1) then
            q = 2.0_wp*g3*e*stp
            pm = kmod*e*stp
          else
            tau = 2.0_wp*g3*e*stp
            q = sqrt(3.0_wp)*tau
            pm = 0.0_wp
          end if
          call check_close('bilinear tensile failure: eroded/(q^2/(6G) + p^2/(2K)) - 1', &
                           pt%eroded/(q**2/(6.0_wp*g3) + pm**2/(2.0_wp*kmod)) - 1.0_wp, 0.0_wp, 1.0e-12_wp)
          call check_close('bilinear tensile failure: stress removed', maxval(abs(stress)), 0.0_wp, 0.0_wp)
          call check_close('bilinear tensile failure: damage field', m%field('damage', hist), 1.0_wp, 0.0_wp)
        else if (nfail == 0) then
          call check_close('bilinear before tensile failure: damage field', m%field('damage', hist), 0.0_wp, 0.0_wp)
        end if
      end do
      call check(nfail == 7, 'bilinear: fails in the step sigma_1 crosses tensile_strength (7)')
    end do
  end subroutine test_bilinear_tension
end program test_strength_hjc
