!> Unit tests of the Johnson-Cook strength model (modules/strength/
!> strength_johnson_cook.f90), through the kernel (the model's update and
!> its return `jc_return`) and through the particle path (one cell, eight
!> particles at the quarter points, node velocities prescribed, the
!> kernels called as the step calls them, as tests/test_particles_lagrange).
!> Units MPa and seconds. Tables: PARTICLES.md §2.3 [computed], printed to
!> 0.1 MPa and 1e-4 in the rate factor, so the tolerance against them is
!> half the last printed digit (0.05 MPa, 5e-5); against the formula the
!> tolerance is the solver's (|g| <= 1e-12 q*: 1e-11 relative allows for
!> the round-off of evaluating q and sigma_y separately).
!>  1. 1045 steel (A 507, B 320, n 0.28, C 0.064, eps0 1/s; E 210 GPa, nu
!>     0.3) in uniaxial stress (lateral strain found by a secant so that
!>     sigma_yy = sigma_zz = 0) at the constant strain rate 1e-3/s (below
!>     eps0: the static curve): after every plastic step q = sigma_y(eps_p,
!>     dp/dt, T) to 1e-11; q at eps_p 0.05, 0.1, 0.2, 0.43 (linear
!>     interpolation between steps of 1e-4 in strain: error < 2e-5 MPa) =
!>     645.3, 674.9, 710.9, 759.7; the first plastic step's q - B eps_p^n
!>     = A = 507.0. The same at 1e3/s: q = sigma_y(eps_p, dp/dt) to 1e-11.
!>  2. The rate factor by one exactly constructed step (the trial
!>     q* = sigma_y(eps_p + dp*, dp*/dt) + 3G dp* of a deviatoric strain,
!>     whose return must give dp*): dp* recovered to 1e-10 relative, and
!>     q/(A + B eps_p^n) = 1.4421 at eps_dot* = 1e3, 1.5895 at 1e4.
!>  3. OFHC copper (A 90, B 292, n 0.31, C 0.025, m 1.09, T_m 1356 K,
!>     T_room 298 K; G 46 GPa, K 140 GPa) at T = 600 K (no heating),
!>     uniaxial stress at 1e-3/s: q at eps_p 0.1, 0.5, 1, 2 = 173.6, 242.5,
!>     284.6, 336.7 (steps of 1e-3: interpolation error < 4e-4 MPa); at
!>     298 K and eps_dot* = 1e4 (constructed steps): 286.7, 400.5, 470.0,
!>     556.1.
!>  4. Plastic heating, perfectly plastic (B = 0, no softening): T -
!>     T_room = chi A eps_p/(rho c_p) exactly (1e-12 relative: a sum of
!>     identical positive terms), through the kernel in uniaxial stress and
!>     through the particle path in isochoric plane strain (rho constant).
!>     Without c_p T stays T_room exactly.
!>  5. The Newton at eps_p = 0 with n < 1 (n = 0.5, 0.1 and 0.01, C = 0.064
!>     at dt = 1e-9): trials just above A (by 1e-13 and 1e-6 relative), at
!>     1.5 A and 10 A: dp finite, in [0, q*/(3G)], converged in at most 100
!>     evaluations, |g(dp)| <= 1e-12 q* (the debug build traps invalid, zero
!>     and overflow: a NaN or an infinity would stop the test), except where
!>     the root is below the 1e-30 floor of dp (n = 0.1 and 0.01, 1e-6 above
!>     A: (r/B)^(1/n) ~ 1e-58 and 1e-580, the second not representable):
!>     those two must end at the floor with dp = 0.
!>  6. The rate guard: at plastic rates below eps0 (1e-3/s, eps0 1/s) q
!>     equals the static curve A + B eps_p^n to 1e-11 (without the guard the
!>     factor would be 1 + C ln 1e-3 = 0.558).
!>  7. The particle path: the eight particles in uniaxial stress (node
!>     velocities u = (r x, s y, s z), s by the secant), 1045 steel at
!>     1e-3/s: q = sigma_y(eps_p, dp/dt) to 1e-11 for every particle and
!>     step, all particles alike, q at eps_p 0.05 and 0.1 = 645.3, 674.9;
!>     the output fields 'plastic_strain' and 'temperature' are hist(1),
!>     hist(2).
!>  8. With eos = 'mie_gruneisen' (the model's k = 0, the EOS sets the
!>     pressure): copper (rho0 8.93 g/cm^3, c0 3.94 km/s, s1 1.49, gamma0
!>     2.0; JC as in 3, heating with c_p 383 J/(kg K)) in uniaxial strain
!>     compression to 5 % at 1e3/s through the particle path: plastic, q =
!>     sigma_y(eps_p, dp/dt, T) to 1e-11 after every plastic step with T of
!>     the step's start, the pressure = the EOS's p(rho, e) to 1e-12, T
!>     above T_room.
program test_strength_jc
  use base_kinds, only: wp
  use base_errors, only: error_t
  use mesh_grid, only: grid_t, grid_init_box
  use particles_state, only: particles_t, particles_allocate, particles_order
  use particles_lagrange, only: particles_velocity_gradients, particles_stress_update, strength_slot_t
  use strength_models, only: strength_t, strength_params_t, strength_point_t, strength_mises
  use strength_factory, only: strength_create
  use strength_jc_flow, only: jc_flow_t, jc_flow
  use strength_johnson_cook, only: strength_johnson_cook_t, jc_return
  use eos_mie_gruneisen, only: mie_gruneisen_t, mie_gruneisen_state
  use test_assert, only: check, check_close, check_summary
  use test_one_cell, only: one_cell
  implicit none
  real(wp), parameter :: st_e = 210000.0_wp, st_nu = 0.3_wp
  real(wp), parameter :: st_k = st_e/(3.0_wp*(1.0_wp - 2.0_wp*st_nu)), st_g = st_e/(2.0_wp*(1.0_wp + st_nu))
  real(wp), parameter :: cu_k = 140000.0_wp, cu_g = 46000.0_wp
  real(wp), parameter :: solver_tol = 1.0e-11_wp, table_tol = 0.05_wp

  call test_flow_curve_1045()
  call test_rate_factor()
  call test_copper()
  call test_heating()
  call test_newton_at_zero()
  call test_rate_guard()
  call test_particle_path()
  call test_mie_gruneisen()
  call check_summary('test_strength_jc')

contains

  !> 1045 steel (PARTICLES.md §2.3, B = 320 MPa) with rate sensitivity c.
  type(strength_params_t) function steel(c) result(par)
    real(wp), intent(in) :: c
    par = strength_params_t(k=st_k, g=st_g, jc=jc_flow_t(a=507.0_wp, b=320.0_wp, n=0.28_wp, c=c, eps0=1.0_wp))
  end function steel

  !> OFHC copper (Johnson & Cook 1983, PARTICLES.md §2.3).
  type(strength_params_t) function copper() result(par)
    par = strength_params_t(k=cu_k, g=cu_g, jc=jc_flow_t(a=90.0_wp, b=292.0_wp, n=0.31_wp, c=0.025_wp, eps0=1.0_wp, &
                                                        m=1.09_wp, t_room=298.0_wp, t_melt=1356.0_wp))
  end function copper

  !> The Johnson-Cook model of par.
  subroutine make(par, model)
    type(strength_params_t), intent(in) :: par
    class(strength_t), allocatable, intent(out) :: model
    type(error_t), allocatable :: err
    call strength_create('johnson_cook', par, model, err)
    call check(.not. allocated(err), 'strength_create johnson_cook')
  end subroutine make

  !> The flow parameters of a model made by `make`.
  type(jc_flow_t) function flow_of(model) result(jc)
    class(strength_t), intent(in) :: model
    select type (model)
    type is (strength_johnson_cook_t)
      jc = model%jc
    class default
      call check(.false., 'the model is a strength_johnson_cook_t')
    end select
  end function flow_of

  !> The von Mises stress of stress(6).
  real(wp) function mises_of(stress) result(q)
    real(wp), intent(in) :: stress(6)
    real(wp) :: s(6), p
    p = sum(stress(1:3))/3.0_wp
    s = stress
    s(1:3) = s(1:3) - p
    q = strength_mises(s)
  end function mises_of

  !> One kernel step in uniaxial stress: the axial strain increment d, the
  !> lateral one found by a secant so that sigma_yy = sigma_zz = 0 (to 1e-12
  !> of the axial stress scale sc); stress and hist advanced.
  subroutine uniaxial_step(model, d, dt, rho, stress, hist, sc)
    class(strength_t), intent(in) :: model
    real(wp), intent(in) :: d, dt, rho, sc
    real(wp), intent(inout) :: stress(6), hist(:)
    real(wp) :: x0, x1, f0, f1, x2, s(6), h(size(hist))
    integer :: it
    x0 = -0.5_wp*d
    x1 = -0.3_wp*d
    f0 = uniaxial_try(model, d, x0, dt, rho, stress, hist, s, h)
    f1 = uniaxial_try(model, d, x1, dt, rho, stress, hist, s, h)
    do it = 1, 60
      if (abs(f1) <= 1.0e-12_wp*sc .or. .not. abs(f1 - f0) > 0.0_wp) exit
      x2 = x1 - f1*(x1 - x0)/(f1 - f0)
      x0 = x1
      f0 = f1
      x1 = x2
      f1 = uniaxial_try(model, d, x1, dt, rho, stress, hist, s, h)
    end do
    call check(abs(f1) <= 1.0e-10_wp*sc, 'uniaxial stress: the lateral stress vanishes')
    stress = s
    hist = h
  end subroutine uniaxial_step

  !> sigma_yy after the kernel step diag(d, x, x) from (stress, hist), the
  !> result in (s, h).
  real(wp) function uniaxial_try(model, d, x, dt, rho, stress, hist, s, h) result(f)
    class(strength_t), intent(in) :: model
    real(wp), intent(in) :: d, x, dt, rho, stress(6), hist(:)
    real(wp), intent(out) :: s(6), h(:)
    real(wp) :: deps(3, 3)
    type(strength_point_t) :: pt
    deps = 0.0_wp
    deps(1, 1) = d
    deps(2, 2) = x
    deps(3, 3) = x
    s = stress
    h = hist
    pt = strength_point_t(dt=dt, rho=rho)
    call model%update(deps, 0.0_wp*deps, pt, s, h)
    f = s(2)
  end function uniaxial_try

  !> A uniaxial-stress run at the strain rate rate (steps d = rate dt) until
  !> eps_p reaches ep_end: eps_p and q after each plastic step (np of them),
  !> the largest |q/sigma_y(eps_p, dp/dt, T) - 1| (worst), and q - B eps_p^n
  !> of the first plastic step (q_first).
  subroutine uniaxial_run(model, rate, d, t0, ep_end, ep, qs, np, worst, q_first, rho, t_end)
    class(strength_t), intent(in) :: model
    real(wp), intent(in) :: rate, d, t0, ep_end
    real(wp), allocatable, intent(out) :: ep(:), qs(:)
    integer, intent(out) :: np
    real(wp), intent(out) :: worst, q_first
    real(wp), intent(in), optional :: rho
    real(wp), intent(out), optional :: t_end
    real(wp) :: stress(6), hist(2), dt, q, ep0, r
    type(jc_flow_t) :: jc
    integer :: step
    jc = flow_of(model)
    dt = d/rate
    stress = 0.0_wp
    call model%hist_init(hist)
    hist(2) = t0
    r = 7.8e-9_wp
    if (present(rho)) r = rho
    allocate(ep(nint(3*ep_end/d) + 100), qs(nint(3*ep_end/d) + 100))
    np = 0
    worst = 0.0_wp
    q_first = -1.0_wp
    do step = 1, size(ep)
      ep0 = hist(1)
      call uniaxial_step(model, d, dt, r, stress, hist, jc%a)
      q = mises_of(stress)
      if (hist(1) > ep0) then
        np = np + 1
        ep(np) = hist(1)
        qs(np) = q
        ! sigma_y at the step's start temperature (no heating in these runs unless t_end is asked)
        if (.not. present(t_end)) worst = max(worst, abs(q/jc_flow(jc, hist(1), (hist(1) - ep0)/dt, hist(2)) - 1.0_wp))
        if (q_first < 0.0_wp) q_first = q - jc%b*hist(1)**jc%n
      end if
      if (hist(1) >= ep_end) exit
    end do
    if (present(t_end)) t_end = hist(2)
  end subroutine uniaxial_run

  !> q at eps_p = e by linear interpolation in the run's (ep, qs).
  real(wp) function q_at(ep, qs, np, e) result(q)
    real(wp), intent(in) :: ep(:), qs(:), e
    integer, intent(in) :: np
    integer :: i
    q = -1.0_wp
    do i = 1, np - 1
      if (ep(i) <= e .and. ep(i + 1) >= e) then
        q = qs(i) + (qs(i + 1) - qs(i))*(e - ep(i))/(ep(i + 1) - ep(i))
        return
      end if
    end do
  end function q_at

  subroutine test_flow_curve_1045()
    class(strength_t), allocatable :: model
    real(wp), allocatable :: ep(:), qs(:)
    real(wp) :: worst, q_first
    real(wp), parameter :: e_tab(4) = [0.05_wp, 0.1_wp, 0.2_wp, 0.43_wp], q_tab(4) = [645.3_wp, 674.9_wp, 710.9_wp, &
                                                                                         759.7_wp]
    character(len=8) :: lbl
    integer :: np, i
    call make(steel(0.064_wp), model)
    call uniaxial_run(model, 1.0e-3_wp, 1.0e-4_wp, 293.0_wp, 0.44_wp, ep, qs, np, worst, q_first)
    call check(np > 4000, '1045 uniaxial stress: the run reached eps_p = 0.44')
    call check_close('1045 uniaxial stress 1e-3/s: max |q/sigma_y(eps_p, rate) - 1|', worst, 0.0_wp, solver_tol)
    call check_close('1045: q - B eps_p^n of the first plastic step (A = 507.0)', q_first, 507.0_wp, table_tol)
    do i = 1, 4
      write(lbl, '(f5.2)') e_tab(i)
      call check_close('1045 uniaxial stress 1e-3/s: q at eps_p ='//trim(lbl), q_at(ep, qs, np, e_tab(i)), q_tab(i), &
                       table_tol)
    end do
    call uniaxial_run(model, 1.0e3_wp, 1.0e-4_wp, 293.0_wp, 0.2_wp, ep, qs, np, worst, q_first)
    call check_close('1045 uniaxial stress 1e3/s: max |q/sigma_y(eps_p, dp/dt) - 1|', worst, 0.0_wp, solver_tol)
    call check(q_at(ep, qs, np, 0.1_wp) > 1.4_wp*674.9_wp, '1045 at 1e3/s: q(0.1) above 1.4 x the static 674.9')
  end subroutine test_flow_curve_1045

  !> One step constructed so that its return is dp (module notes, test 2):
  !> from zero stress and eps_p = e - dp, the deviatoric strain increment
  !> diag(a, -a/2, -a/2) with 3G a = sigma_y(e, dp/dt, t) + 3G dp. Returns
  !> q after the step and the plastic increment found.
  subroutine constructed_step(model, e, dp, dt, t, q, dp_found)
    class(strength_t), intent(in) :: model
    real(wp), intent(in) :: e, dp, dt, t
    real(wp), intent(out) :: q, dp_found
    real(wp) :: stress(6), hist(2), deps(3, 3), a
    type(strength_point_t) :: pt
    type(jc_flow_t) :: jc
    jc = flow_of(model)
    a = (jc_flow(jc, e, dp/dt, t) + 3.0_wp*model%g*dp)/(3.0_wp*model%g)
    deps = 0.0_wp
    deps(1, 1) = a
    deps(2, 2) = -0.5_wp*a
    deps(3, 3) = -0.5_wp*a
    stress = 0.0_wp
    hist = [e - dp, t]
    pt = strength_point_t(dt=dt, rho=1.0_wp)
    call model%update(deps, 0.0_wp*deps, pt, stress, hist)
    q = mises_of(stress)
    dp_found = hist(1) - (e - dp)
  end subroutine constructed_step

  subroutine test_rate_factor()
    class(strength_t), allocatable :: model
    real(wp) :: q, dpf, static
    call make(steel(0.064_wp), model)
    static = 507.0_wp + 320.0_wp*0.2_wp**0.28_wp
    call constructed_step(model, 0.2_wp, 1.0e-4_wp, 1.0e-7_wp, 293.0_wp, q, dpf)
    call check_close('1045 constructed step at eps_dot* = 1e3: dp/dp* - 1', dpf/1.0e-4_wp - 1.0_wp, 0.0_wp, 1.0e-10_wp)
    call check_close('1045 rate factor at eps_dot* = 1e3 (q/static at eps_p 0.2)', q/static, 1.4421_wp, 5.0e-5_wp)
    call constructed_step(model, 0.2_wp, 1.0e-4_wp, 1.0e-8_wp, 293.0_wp, q, dpf)
    call check_close('1045 constructed step at eps_dot* = 1e4: dp/dp* - 1', dpf/1.0e-4_wp - 1.0_wp, 0.0_wp, 1.0e-10_wp)
    call check_close('1045 rate factor at eps_dot* = 1e4', q/static, 1.5895_wp, 5.0e-5_wp)
  end subroutine test_rate_factor

  subroutine test_copper()
    class(strength_t), allocatable :: model
    real(wp), allocatable :: ep(:), qs(:)
    real(wp) :: worst, q_first, q, dpf
    real(wp), parameter :: e_tab(4) = [0.1_wp, 0.5_wp, 1.0_wp, 2.0_wp]
    real(wp), parameter :: q600(4) = [173.6_wp, 242.5_wp, 284.6_wp, 336.7_wp], q1e4(4) = [286.7_wp, 400.5_wp, 470.0_wp, &
                                                                                            556.1_wp]
    character(len=8) :: lbl
    integer :: np, i
    call make(copper(), model)
    call uniaxial_run(model, 1.0e-3_wp, 1.0e-3_wp, 600.0_wp, 2.01_wp, ep, qs, np, worst, q_first)
    call check_close('Cu 600 K uniaxial stress: max |q/sigma_y(eps_p, rate, T) - 1|', worst, 0.0_wp, solver_tol)
    do i = 1, 4
      write(lbl, '(f4.1)') e_tab(i)
      call check_close('Cu 600 K, eps_dot* <= 1: q at eps_p ='//trim(lbl), q_at(ep, qs, np, e_tab(i)), q600(i), table_tol)
      call constructed_step(model, e_tab(i), 1.0e-4_wp, 1.0e-8_wp, 298.0_wp, q, dpf)
      call check_close('Cu 298 K, eps_dot* = 1e4 (constructed step): q at eps_p ='//trim(lbl), q, q1e4(i), table_tol)
    end do
  end subroutine test_copper


  subroutine test_heating()
    class(strength_t), allocatable :: model
    type(strength_slot_t), allocatable :: models(:)
    type(strength_params_t) :: par
    type(grid_t) :: g
    type(particles_t) :: p
    real(wp), allocatable :: ep(:), qs(:)
    real(wp), parameter :: rho = 7.8e-9_wp, cp = 4.6e8_wp, chi = 0.9_wp, a = 400.0_wp, t0 = 293.0_wp
    real(wp) :: worst, q_first, t_end, lgrad(3, 3, 8), u(3, 8), dt, r, expect
    integer :: np, n, step, bad
    ! (units MPa, s, mm: rho tonne/mm^3, c_p mm^2/(s^2 K), rho c_p MPa/K)
    par = strength_params_t(k=st_k, g=st_g, jc=jc_flow_t(a=a, n=0.5_wp, t_room=t0), jc_cp=cp, jc_chi=chi)
    call make(par, model)
    call uniaxial_run(model, 1.0e-3_wp, 1.0e-3_wp, t0, 0.3_wp, ep, qs, np, worst, q_first, rho=rho, t_end=t_end)
    call check_close('heating, perfectly plastic, kernel: (T - T_room)/(chi A eps_p/(rho c_p)) - 1', &
                     (t_end - t0)/(chi*a*ep(np)/(rho*cp)) - 1.0_wp, 0.0_wp, 1.0e-12_wp)
    call check_close('heating, perfectly plastic, kernel: q = A', maxval(abs(qs(1:np) - a)), 0.0_wp, solver_tol*a)
    ! the particle path, isochoric plane strain L = diag(r, -r, 0)
    allocate(models(1))
    call make(par, models(1)%m)
    call one_cell(g, p, models(1)%m%nhist(), rho, models(1)%m)
    r = 1.0_wp
    dt = 1.0e-3_wp
    do n = 1, 8
      u(:, n) = [r*g%x(1, n), -r*g%x(2, n), 0.0_wp]
    end do
    do step = 1, 400
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad)
    end do
    call check(bad == 0 .and. p%hist(1, 1) > 0.3_wp, 'heating, particle path: plastic, volumes positive')
    expect = chi*a*p%hist(1, 1)/(p%rho(1)*cp)
    call check_close('heating, particle path, plane strain: (T - T_room)/(chi A eps_p/(rho c_p)) - 1', &
                     maxval(abs(p%hist(2, :) - t0))/expect - 1.0_wp, 0.0_wp, 1.0e-12_wp)
    call check_close('heating, particle path: rho/rho0 - 1 (isochoric)', maxval(abs(p%rho/rho - 1.0_wp)), 0.0_wp, &
                     1.0e-13_wp)
    call check_close('heating, particle path: field temperature = hist(2)', &
                     models(1)%m%field('temperature', p%hist(:, 3)) - p%hist(2, 3), 0.0_wp, 0.0_wp)
    ! without c_p no heating
    par%jc_cp = 0.0_wp
    call make(par, model)
    call uniaxial_run(model, 1.0e-3_wp, 1.0e-3_wp, t0, 0.05_wp, ep, qs, np, worst, q_first, rho=rho, t_end=t_end)
    call check_close('no c_p: T stays T_room', t_end - t0, 0.0_wp, 0.0_wp)
  end subroutine test_heating

  subroutine test_newton_at_zero()
    type(jc_flow_t) :: jc
    real(wp) :: dp, g, q, r, worst
    real(wp), parameter :: ns(3) = [0.5_wp, 0.1_wp, 0.01_wp], over(4) = [1.0e-13_wp, 1.0e-6_wp, 0.5_wp, 9.0_wp]
    integer :: i, j, iters, most, floored
    logical :: ok, all_ok
    g = st_g
    worst = 0.0_wp
    most = 0
    floored = 0
    all_ok = .true.
    do i = 1, 3
      jc = jc_flow_t(a=507.0_wp, b=320.0_wp, n=ns(i), c=0.064_wp, eps0=1.0_wp)
      do j = 1, 4
        q = 507.0_wp*(1.0_wp + over(j))
        call jc_return(jc, g, q, 0.0_wp, 1.0e-9_wp, 293.0_wp, dp, iters, ok)
        all_ok = all_ok .and. ok .and. dp >= 0.0_wp .and. dp <= q/(3.0_wp*g) .and. abs(dp) < huge(1.0_wp)
        r = q - 3.0_wp*g*dp - jc_flow(jc, dp, dp/1.0e-9_wp, 293.0_wp)
        write(*, '(a,f5.2,a,es8.1,a,es10.3,a,es10.3,a,i0)') '  n = ', ns(i), ', q*/A - 1 = ', over(j), ': dp ', dp, &
          ', g/q* ', r/q, ', evaluations ', iters
        if (abs(dp) > 0.0_wp .or. j == 1) then
          worst = max(worst, abs(r)/q)
        else
          floored = floored + 1
        end if
        most = max(most, iters)
      end do
    end do
    call check(all_ok, 'Newton at eps_p = 0, n = 0.5, 0.1, 0.01: converged, dp in [0, q*/(3G)], finite')
    call check_close('Newton at eps_p = 0, n < 1: max |g(dp)|/q*', worst, 0.0_wp, 1.0e-12_wp)
    ! (n = 0.1 and 0.01 a hair above A: the roots (r/B)^(1/n) ~ 1e-58 and
    ! 1e-580 are below the 1e-30 floor (the second not even representable):
    ! the step is elastic, dp = 0, the only two such cases)
    call check(floored == 2, 'Newton at eps_p = 0: only n = 0.1, 0.01 at q*/A - 1 = 1e-6 end at the dp floor (dp = 0)')
    call check(most <= 100, 'Newton at eps_p = 0: at most 100 evaluations')
    ! an elastic trial (q* = A): dp = 0 exactly
    call jc_return(jc, g, 507.0_wp, 0.0_wp, 1.0e-9_wp, 293.0_wp, dp, iters, ok)
    call check(.not. abs(dp) > 0.0_wp .and. ok, 'trial at the yield stress: no plastic increment')
  end subroutine test_newton_at_zero

  subroutine test_rate_guard()
    class(strength_t), allocatable :: model
    real(wp), allocatable :: ep(:), qs(:)
    real(wp) :: worst, q_first, dev
    integer :: np, i
    call make(steel(0.064_wp), model)
    call uniaxial_run(model, 1.0e-3_wp, 1.0e-4_wp, 293.0_wp, 0.05_wp, ep, qs, np, worst, q_first)
    dev = 0.0_wp
    do i = 1, np
      dev = max(dev, abs(qs(i)/(507.0_wp + 320.0_wp*ep(i)**0.28_wp) - 1.0_wp))
    end do
    call check_close('rate guard: plastic rate 1e-3 eps0, max |q/(A + B eps_p^n) - 1|', dev, 0.0_wp, solver_tol)
  end subroutine test_rate_guard

  subroutine test_particle_path()
    type(strength_slot_t), allocatable :: models(:)
    type(grid_t) :: g
    type(particles_t) :: p, pc
    type(jc_flow_t) :: jc
    real(wp) :: dt, r, s0, s1, f0, f1, s2, worst, spread, ep0(8), q
    real(wp), allocatable :: ep(:), qs(:)
    integer :: step, it, bad, k, np
    real(wp), parameter :: rho = 7.8e-9_wp
    allocate(models(1), ep(2000), qs(2000))
    call make(steel(0.064_wp), models(1)%m)
    jc = flow_of(models(1)%m)
    call one_cell(g, p, models(1)%m%nhist(), rho, models(1)%m)
    r = 1.0e-3_wp
    dt = 0.1_wp           ! axial strain 1e-4 per step
    s1 = -0.3_wp*r
    worst = 0.0_wp
    spread = 0.0_wp
    np = 0
    do step = 1, size(ep)
      ep0 = p%hist(1, :)
      ! the secant on the lateral rate s: sigma_yy = 0
      s0 = -0.5_wp*r
      f0 = particle_try(g, p, pc, models, r, s0, dt, bad)
      f1 = particle_try(g, p, pc, models, r, s1, dt, bad)
      do it = 1, 60
        if (abs(f1) <= 1.0e-12_wp*jc%a .or. .not. abs(f1 - f0) > 0.0_wp) exit
        s2 = s1 - f1*(s1 - s0)/(f1 - f0)
        s0 = s1
        f0 = f1
        s1 = s2
        f1 = particle_try(g, p, pc, models, r, s1, dt, bad)
      end do
      p = pc
      call check(bad == 0, 'particle path: volumes positive')
      do k = 1, 8
        spread = max(spread, abs(p%stress(1, k) - p%stress(1, 1)), abs(p%hist(1, k) - p%hist(1, 1)))
        if (p%hist(1, k) > ep0(k)) then
          q = mises_of(p%stress(:, k))
          worst = max(worst, abs(q/jc_flow(jc, p%hist(1, k), (p%hist(1, k) - ep0(k))/dt, p%hist(2, k)) - 1.0_wp))
        end if
      end do
      if (p%hist(1, 1) > ep0(1)) then
        np = np + 1
        ep(np) = p%hist(1, 1)
        qs(np) = mises_of(p%stress(:, 1))
      end if
      if (p%hist(1, 1) > 0.105_wp) exit
    end do
    call check(p%hist(1, 1) > 0.1_wp, 'particle path: the run reached eps_p = 0.1')
    call check_close('particle path, uniaxial stress: max |q/sigma_y(eps_p, dp/dt) - 1|', worst, 0.0_wp, solver_tol)
    call check_close('particle path: the eight particles alike (stress, eps_p)', spread, 0.0_wp, 1.0e-9_wp)
    call check_close('particle path: q at eps_p = 0.05', q_at(ep, qs, np, 0.05_wp), 645.3_wp, table_tol)
    call check_close('particle path: q at eps_p = 0.1', q_at(ep, qs, np, 0.1_wp), 674.9_wp, table_tol)
    call check_close('particle path: field plastic_strain = hist(1)', &
                     models(1)%m%field('plastic_strain', p%hist(:, 5)) - p%hist(1, 5), 0.0_wp, 0.0_wp)
    call check_close('particle path: field temperature = T_room (no c_p)', &
                     models(1)%m%field('temperature', p%hist(:, 5)), jc%t_room, 0.0_wp)
  end subroutine test_particle_path

  subroutine test_mie_gruneisen()
    type(strength_slot_t), allocatable :: models(:)
    type(error_t), allocatable :: err
    type(grid_t) :: g
    type(particles_t) :: p
    type(jc_flow_t) :: jc
    type(strength_params_t) :: par
    real(wp) :: lgrad(3, 3, 8), dt, worst, pw, pe, cs, ep0, t0, q
    integer :: step, bad
    ! (MPa, s, mm: rho tonne/mm^3, c0 mm/s, c_p mm^2/(s^2 K))
    real(wp), parameter :: rho0 = 8.93e-9_wp
    allocate(models(1))
    par = copper()
    par%k = rho0*3.94e6_wp**2
    par%jc_cp = 3.83e8_wp
    call strength_create('johnson_cook', par, models(1)%m, err, eos_pressure=.true.)
    call check(.not. allocated(err) .and. abs(models(1)%m%k) <= 0.0_wp, 'MG: johnson_cook with k = 0')
    models(1)%eos = mie_gruneisen_t(rho0=rho0, c0=3.94e6_wp, s1=1.49_wp, gamma0=2.0_wp)
    jc = flow_of(models(1)%m)
    call one_cell(g, p, models(1)%m%nhist(), rho0, models(1)%m)
    dt = 1.0e-7_wp
    lgrad = 0.0_wp
    lgrad(1, 1, :) = -1.0e3_wp
    worst = 0.0_wp
    pw = 0.0_wp
    do step = 1, 500
      ep0 = p%hist(1, 1)
      t0 = p%hist(2, 1)
      call particles_stress_update(p, models, lgrad, dt, bad)
      if (p%hist(1, 1) > ep0) then
        q = mises_of(p%stress(:, 1))
        worst = max(worst, abs(q/jc_flow(jc, p%hist(1, 1), (p%hist(1, 1) - ep0)/dt, t0) - 1.0_wp))
      end if
      call mie_gruneisen_state(models(1)%eos, p%rho(1), p%e(1), pe, cs)
      pw = max(pw, abs(-sum(p%stress(1:3, 1))/3.0_wp/pe - 1.0_wp))
    end do
    call check(bad == 0 .and. p%hist(1, 1) > 0.01_wp, 'MG uniaxial strain: volumes positive, plastic')
    call check_close('MG uniaxial strain: max |q/sigma_y(eps_p, dp/dt, T) - 1|', worst, 0.0_wp, solver_tol)
    call check_close('MG uniaxial strain: max |p/p_EOS(rho, e) - 1|', pw, 0.0_wp, 1.0e-12_wp)
    call check(p%hist(2, 1) > jc%t_room, 'MG uniaxial strain: plastic heating raised T')
  end subroutine test_mie_gruneisen

  !> sigma_yy of particle 1 after the step of p with node velocities (r x,
  !> s y, s z), on the copy pc.
  real(wp) function particle_try(g, p, pc, models, r, s, dt, bad) result(f)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: p
    type(particles_t), intent(inout) :: pc
    type(strength_slot_t), intent(in) :: models(:)
    real(wp), intent(in) :: r, s, dt
    integer, intent(out) :: bad
    real(wp) :: u(3, 8), lgrad(3, 3, 8)
    integer :: n
    do n = 1, 8
      u(:, n) = [r*g%x(1, n), s*g%x(2, n), s*g%x(3, n)]
    end do
    pc = p
    call particles_velocity_gradients(g, pc, g%x, u, lgrad)
    call particles_stress_update(pc, models, lgrad, dt, bad)
    f = pc%stress(2, 1)
  end function particle_try
end program test_strength_jc
