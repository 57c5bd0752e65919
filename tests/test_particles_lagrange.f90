!> Unit tests of the particles in the Lagrangian phase and of the strength
!> models (modules/particles/particles_lagrange, modules/strength): one cell,
!> eight particles at the quarter points, the kernels called as the step
!> calls them, node velocities prescribed (PARTICLES.md §2.6).
!>  1. Nodal force (Eq. 17) of particles with stress -p I filling a sheared
!>     parallelepiped cell = the cell's pressure corner forces p dV/dx_a
!>     (the quarter-point rule integrates grad N exactly there): round-off.
!>  2. Elastic uniaxial strain (node velocities u_x = r x, original scheme,
!>     Eqs. 26-27): sigma_xx = (K + 4G/3) eps, sigma_yy = sigma_zz =
!>     (K - 2G/3) eps to round-off; volume V0 J^n, J = (1 + r dt/2)/(1 - r dt/2).
!>  3. The virtual solid grid (Eqs. 29-30) of one cell with a linear particle
!>     velocity field: a corner node gets the particles' mass-weighted mean,
!>     the field at 3/8 of the cell from the node side, so the velocity
!>     gradient it gives is exactly L/4 (the smoothing of a one-cell MUSL
!>     re-projection; interior nodes of a larger body get the field exactly).
!>  4. Simple shear with the Jaumann rate (Hughes-Winget): sigma_12 =
!>     G sin(gamma), sigma_11 = -sigma_22 = G (1 - cos(gamma)) at gamma = 1;
!>     error second order in the step (checked at 500 and 1000 steps).
!>  5. Rigid rotation by 90 degrees of a uniaxially stressed block: the
!>     stress turns from xx to yy, invariants unchanged to round-off.
!>  6. Bilinear uniaxial strain: no plastic strain below eps_y = y0/(2G),
!>     then the tangent d sigma_xx/d eps = K + 4GH/(3(3G + H)).
!>  7. Mie-Gruneisen solid (copper: rho0 8.93 g/cm^3, c0 0.394 cm/us, s1
!>     1.49, gamma0 2.0, G 0.477 Mbar), hydrostatic compression to rho =
!>     1.2 rho0: p = p_H(mu)(1 - gamma0 mu/(2(1+mu))) + gamma0 rho0 e (the
!>     Hugoniot-referenced formula, written out here) to round-off, m e =
!>     the compression work -sum 1/2 (p^n + p^{n+1}) Delta V to round-off,
!>     and p within 2e-5 of the exact isentrope (RK4 of de/dV = -p/m,
!>     20000 steps; measured 1.27e-5), the error second order (50 against
!>     100 steps: ratio 4.00).
!>  8. The same solid in uniaxial compression (elastic deviator): s_xx =
!>     -(4/3) G eps exactly, m e = the trapezoid of the deviatoric and the
!>     pressure work, and p from the formula, to round-off; the stable step
!>     of a particle at rest uses c^2 = c0^2 + 4G/(3 rho0).
!>  9. The viscosity scale 1 - theta_c of a cell (`particles_cell_fraction`):
!>     0 for a cell filled by its particles, 1 - 1/8 with one of eight
!>     particles' volume, 1 for an empty cell; the tensor viscosity of a
!>     compressed cell is scaled by it (q and the forces' viscous part).
program test_particles_lagrange
  use base_kinds, only: wp
  use base_errors, only: error_t
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_volume_gradient
  use particles_state, only: particles_t, particles_allocate, particles_order
  use particles_lagrange, only: particles_work_t, particles_work_init, particles_nodal_force, &
                                particles_velocity_gradients, particles_virtual_grid, particles_stress_update, &
                                strength_slot_t
  use strength_models, only: strength_params_t
  use strength_factory, only: strength_create
  use eos_mie_gruneisen, only: mie_gruneisen_t
  use particles_lagrange, only: particles_stable_dt, particles_cell_fraction
  use hydro_state, only: hydro_t, hydro_params_t, hydro_allocate
  use lagrange_forces, only: lagrange_strain_rates, lagrange_corner_forces
  use test_assert, only: check, check_close, check_summary
  use test_one_cell, only: one_cell
  implicit none
  real(wp), parameter :: kmod = 5.0_wp, gmod = 3.0_wp
  real(wp), parameter :: eps = epsilon(1.0_wp)
  real(wp), parameter :: cu_rho0 = 8.93_wp, cu_c0 = 0.394_wp, cu_s1 = 1.49_wp, cu_gamma0 = 2.0_wp, cu_g = 0.477_wp

  call test_force_cancels()
  call test_uniaxial_strain()
  call test_virtual_grid()
  call test_simple_shear()
  call test_rotation()
  call test_bilinear()
  call test_mg_hydrostatic()
  call test_mg_uniaxial()
  call test_visc_scale()
  call check_summary('test_particles_lagrange')

contains


  !> The models: elastic, or bilinear with yield y0 and tangent modulus et.
  subroutine models_of(name, y0, et, models)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: y0, et
    type(strength_slot_t), allocatable, intent(out) :: models(:)
    type(error_t), allocatable :: err
    allocate(models(1))
    call strength_create(name, strength_params_t(k=kmod, g=gmod, y0=y0, et=et), models(1)%m, err)
    call check(.not. allocated(err), 'strength model '//name)
  end subroutine models_of

  subroutine test_force_cancels()
    type(grid_t) :: g
    type(particles_t) :: p
    real(wp) :: f(3, 8), fvf(3, 8), xn(3, 8), vol, dvdx(3, 8), pc(1), err_max
    integer :: bad, a
    call one_cell(g, p, 1)
    ! a sheared, stretched parallelepiped
    do a = 1, 8
      g%x(:, a) = [2.0_wp*g%x(1, a) + 0.3_wp*g%x(2, a), 1.5_wp*g%x(2, a) + 0.2_wp*g%x(3, a), g%x(3, a)]
      xn(:, a) = g%x(:, a)
    end do
    p%vol = 0.125_wp*3.0_wp
    p%stress = 0.0_wp
    p%stress(1:3, :) = -2.5_wp
    pc = 0.0_wp
    call particles_nodal_force(g, g%x, p, pc, f, fvf, bad)
    call hex_volume_gradient(xn, vol, dvdx)
    err_max = maxval(abs(f - 2.5_wp*dvdx))
    call check(bad == 0, 'no inverted host')
    call check_close('particle force - p dV/dx (parallelepiped, 8 particles)', err_max, 0.0_wp, 64*eps*2.5_wp*3.0_wp)
    ! with the host pressure equal to the particles' -stress the force is zero
    pc = 2.5_wp
    call particles_nodal_force(g, g%x, p, pc, f, fvf, bad)
    call check_close('particle force with sigma = -P_host I', maxval(abs(f)), 0.0_wp, 0.0_wp)
    ! its virtual-fluid part is -V_p P_c grad N: -P_c dV/dx
    err_max = maxval(abs(fvf + 2.5_wp*dvdx))
    call check_close('virtual-fluid part of the particle force', err_max, 0.0_wp, 64*eps*2.5_wp*3.0_wp)
  end subroutine test_force_cancels

  subroutine test_uniaxial_strain()
    type(grid_t) :: g
    type(particles_t) :: p
    type(strength_slot_t), allocatable :: models(:)
    real(wp) :: u(3, 8), lgrad(3, 3, 8), dt, r, e, v0
    integer :: n, bad, step
    call one_cell(g, p, 1)
    call models_of('elastic', 0.0_wp, 0.0_wp, models)
    r = -0.01_wp
    dt = 0.1_wp
    do n = 1, 8
      u(:, n) = [r*g%x(1, n), 0.0_wp, 0.0_wp]
    end do
    v0 = p%vol(1)
    do step = 1, 50
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad)
    end do
    e = 50*r*dt
    call check(bad == 0, 'volumes stay positive')
    call check_close('uniaxial strain: sigma_xx/((K + 4G/3) eps) - 1', maxval(abs(p%stress(1, :)))/ &
                     abs((kmod + 4.0_wp*gmod/3.0_wp)*e) - 1.0_wp, 0.0_wp, 100*eps)
    call check_close('uniaxial strain: sigma_yy/((K - 2G/3) eps) - 1', maxval(abs(p%stress(2, :)))/ &
                     abs((kmod - 2.0_wp*gmod/3.0_wp)*e) - 1.0_wp, 0.0_wp, 100*eps)
    call check_close('uniaxial strain: sigma_zz - sigma_yy', maxval(abs(p%stress(3, :) - p%stress(2, :))), 0.0_wp, &
                     0.0_wp)
    call check_close('uniaxial strain: shear stresses', maxval(abs(p%stress(4:6, :))), 0.0_wp, &
                     64*eps*abs(kmod*e))
    call check_close('uniaxial strain: V/(V0 J^50) - 1, J = (1 + r dt/2)/(1 - r dt/2)', p%vol(1)/(v0* &
                     ((1.0_wp + 0.5_wp*r*dt)/(1.0_wp - 0.5_wp*r*dt))**50) - 1.0_wp, 0.0_wp, 100*eps)
  end subroutine test_uniaxial_strain

  subroutine test_virtual_grid()
    type(grid_t) :: g
    type(particles_t) :: p
    type(particles_work_t) :: w
    type(error_t), allocatable :: err
    real(wp) :: lin(3, 3), lgrad(3, 3, 8)
    integer :: k
    call one_cell(g, p, 1)
    call particles_work_init(w, g%nnode, g%ncell, p%np, p%nhist, err)
    lin = reshape([0.1_wp, -0.3_wp, 0.2_wp, 0.5_wp, 0.05_wp, -0.4_wp, 0.7_wp, 0.0_wp, -0.2_wp], [3, 3])
    do k = 1, p%np
      w%vh(:, k) = [1.0_wp, 2.0_wp, 3.0_wp] + matmul(lin, p%x(:, k))
    end do
    call particles_virtual_grid(g, p, w%vh, w%ms, w%vs)
    call check_close('virtual grid mass = particle mass', sum(w%ms), sum(p%m), 8*eps)
    call particles_velocity_gradients(g, p, g%x, w%vs, lgrad)
    call check_close('virtual grid, one cell: max |L - L_exact/4|', maxval(abs(lgrad - &
                     spread(0.25_wp*lin, 3, 8))), 0.0_wp, 32*eps)
  end subroutine test_virtual_grid

  !> Simple shear to gamma = 1 in nsteps; returns the errors of sigma_12 and
  !> sigma_11 against the Jaumann solution (per G).
  subroutine shear_errors(nsteps, e12, e11, e22)
    integer, intent(in) :: nsteps
    real(wp), intent(out) :: e12, e11, e22
    type(grid_t) :: g
    type(particles_t) :: p
    type(strength_slot_t), allocatable :: models(:)
    real(wp) :: u(3, 8), lgrad(3, 3, 8), dt
    integer :: n, bad, step
    call one_cell(g, p, 1)
    call models_of('elastic', 0.0_wp, 0.0_wp, models)
    dt = 1.0_wp/nsteps
    do n = 1, 8
      u(:, n) = [g%x(2, n), 0.0_wp, 0.0_wp]     ! gamma_dot = 1
    end do
    do step = 1, nsteps
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad)
    end do
    e12 = maxval(abs(p%stress(6, :)/gmod - sin(1.0_wp)))
    e11 = maxval(abs(p%stress(1, :)/gmod - (1.0_wp - cos(1.0_wp))))
    e22 = maxval(abs(p%stress(2, :)/gmod + (1.0_wp - cos(1.0_wp))))
  end subroutine shear_errors

  subroutine test_simple_shear()
    real(wp) :: a12, a11, a22, b12, b11, b22
    call shear_errors(500, a12, a11, a22)
    call shear_errors(1000, b12, b11, b22)
    write(*, '(a,3es11.3,a,3es11.3)') '  simple shear errors/G at 500 steps:', a12, a11, a22, '; at 1000:', b12, b11, b22
    ! measured at 1000 steps: 6.4e-8, 4.6e-8, 4.6e-8 (G); bound 2e-7 (a
    ! first-order rotate-then-add update gives 2.3e-4 and fails)
    call check_close('simple shear: |sigma_12/G - sin(1)|, 1000 steps', b12, 0.0_wp, 2.0e-7_wp)
    call check_close('simple shear: |sigma_11/G - (1 - cos(1))|, 1000 steps', b11, 0.0_wp, 2.0e-7_wp)
    call check_close('simple shear: |sigma_22/G + (1 - cos(1))|, 1000 steps', b22, 0.0_wp, 2.0e-7_wp)
    ! second order: halving the step quarters the error (3.5 .. 4.5)
    call check(b12 < a12/3.5_wp .and. b12 > a12/4.5_wp, 'simple shear: sigma_12 error falls at second order')
  end subroutine test_simple_shear

  subroutine test_rotation()
    type(grid_t) :: g
    type(particles_t) :: p
    type(strength_slot_t), allocatable :: models(:)
    real(wp) :: u(3, 8), lgrad(3, 3, 8), dt, w, s0(6), i1, j2, j2_0
    integer :: n, bad, step, nsteps
    call one_cell(g, p, 1)
    call models_of('elastic', 0.0_wp, 0.0_wp, models)
    s0 = [3.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
    p%stress = spread(s0, 2, 8)
    nsteps = 100
    w = 2.0_wp
    dt = acos(-1.0_wp)/2.0_wp/w/nsteps
    do n = 1, 8
      u(:, n) = w*[-g%x(2, n), g%x(1, n), 0.0_wp]   ! rigid rotation about z
    end do
    j2_0 = j2_of(s0)
    do step = 1, nsteps
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad)
    end do
    i1 = maxval(abs(sum(p%stress(1:3, :), 1) - 3.0_wp))
    j2 = 0.0_wp
    do n = 1, 8
      j2 = max(j2, abs(j2_of(p%stress(:, n)) - j2_0))
    end do
    call check_close('rigid rotation: |I1 - I1_0|', i1, 0.0_wp, 64*eps*3.0_wp)
    call check_close('rigid rotation: |J2 - J2_0|', j2, 0.0_wp, 64*eps*9.0_wp)
    call check_close('rigid rotation: volume change', maxval(abs(p%vol - 0.125_wp)), 0.0_wp, 64*eps)
    ! Hughes-Winget rotates by 2 atan(w dt/2) per step, not w dt: 90 degrees
    ! up to that (second-order) angle error
    call check_close('rigid rotation by 90 degrees: sigma_yy', p%stress(2, 1), 3.0_wp, 1.0e-3_wp)
    call check_close('rigid rotation by 90 degrees: sigma_xx', p%stress(1, 1), 0.0_wp, 1.0e-3_wp)
  end subroutine test_rotation

  pure real(wp) function j2_of(s) result(j2)
    real(wp), intent(in) :: s(6)
    real(wp) :: d(3)
    d = s(1:3) - sum(s(1:3))/3.0_wp
    j2 = 0.5_wp*sum(d**2) + sum(s(4:6)**2)
  end function j2_of

  subroutine test_bilinear()
    type(grid_t) :: g
    type(particles_t) :: p
    type(strength_slot_t), allocatable :: models(:)
    real(wp) :: u(3, 8), lgrad(3, 3, 8), dt, r, y0, et, e_mod, h, eps_y, s_a, s_b, tangent, e
    integer :: n, bad, step, first_plastic
    call one_cell(g, p, 1)
    y0 = 0.06_wp
    et = 0.5_wp
    call models_of('bilinear', y0, et, models)
    e_mod = 9.0_wp*kmod*gmod/(3.0_wp*kmod + gmod)
    h = e_mod*et/(e_mod - et)
    eps_y = y0/(2.0_wp*gmod)        ! uniaxial strain: q = 2G |eps|
    r = 1.0_wp
    dt = eps_y/10.5_wp               ! yield inside step 11
    do n = 1, 8
      u(:, n) = [r*g%x(1, n), 0.0_wp, 0.0_wp]
    end do
    first_plastic = 0
    s_a = 0.0_wp
    s_b = 0.0_wp
    do step = 1, 40
      call particles_velocity_gradients(g, p, g%x, u, lgrad)
      call particles_stress_update(p, models, lgrad, dt, bad)
      if (first_plastic == 0 .and. p%hist(1, 1) > 0.0_wp) first_plastic = step
      if (step == 30) s_a = p%stress(1, 1)
      if (step == 40) s_b = p%stress(1, 1)
    end do
    e = r*dt
    call check(first_plastic == 11, 'bilinear: first plastic strain in the step that crosses eps_y = y0/(2G)')
    tangent = (s_b - s_a)/(10*e)
    call check_close('bilinear uniaxial strain: tangent/(K + 4GH/(3(3G + H))) - 1', &
                     tangent/(kmod + 4.0_wp*gmod*h/(3.0_wp*(3.0_wp*gmod + h))) - 1.0_wp, 0.0_wp, 1.0e-10_wp)
  end subroutine test_bilinear

  !> Copper constants (g/cm^3, cm/us, Mbar; Steinberg's table, gamma0 2.0).
  subroutine copper(models, y0)
    type(strength_slot_t), allocatable, intent(out) :: models(:)
    real(wp), intent(in) :: y0
    type(error_t), allocatable :: err
    allocate(models(1))
    ! K = rho0 c0^2 serves only the hardening modulus (y0 large: elastic here)
    call strength_create('bilinear', strength_params_t(k=cu_rho0*cu_c0**2, g=cu_g, y0=y0), models(1)%m, err, &
                         eos_pressure=.true.)
    call check(.not. allocated(err), 'copper strength model')
    models(1)%eos = mie_gruneisen_t(rho0=cu_rho0, c0=cu_c0, s1=cu_s1, gamma0=cu_gamma0)
  end subroutine copper

  !> The Mie-Gruneisen pressure from its Hugoniot (written out, not the
  !> module's): p = p_H (1 - gamma0 mu/(2(1+mu))) + gamma0 rho0 e, p_H =
  !> rho0 c0^2 mu (1+mu)/(1 - (s1-1) mu)^2, for compression.
  pure real(wp) function mg_pressure(rho, e) result(pr)
    real(wp), intent(in) :: rho, e
    real(wp) :: mu, ph
    mu = rho/cu_rho0 - 1.0_wp
    ph = cu_rho0*cu_c0**2*mu*(1.0_wp + mu)/(1.0_wp - (cu_s1 - 1.0_wp)*mu)**2
    pr = ph*(1.0_wp - cu_gamma0*mu/(2.0_wp*(1.0_wp + mu))) + cu_gamma0*cu_rho0*e
  end function mg_pressure

  !> One copper particle of volume v0 compressed hydrostatically (L = -r I)
  !> to volume v0/1.2 in nsteps: its final pressure, energy, and the
  !> largest misfits of p against the formula and of m e against the
  !> compression work along the way.
  subroutine mg_compress(nsteps, pfin, efin, eform, ework)
    integer, intent(in) :: nsteps
    real(wp), intent(out) :: pfin, efin, eform, ework
    type(particles_t) :: p
    type(grid_t) :: g
    type(strength_slot_t), allocatable :: models(:)
    real(wp) :: lgrad(3, 3, 8), a, pold, vold, work, pnow
    integer :: step, bad, d
    call one_cell(g, p, 1)
    p%rho = cu_rho0
    p%m = cu_rho0*p%vol
    call copper(models, 1.0_wp)
    ! (1 - a)^3/(1 + a)^3 per step: J^nsteps = 1/1.2
    a = (1.0_wp - (1.0_wp/1.2_wp)**(1.0_wp/(3*nsteps)))/(1.0_wp + (1.0_wp/1.2_wp)**(1.0_wp/(3*nsteps)))
    lgrad = 0.0_wp
    do d = 1, 3
      lgrad(d, d, :) = -2.0_wp*a   ! dt = 1
    end do
    work = 0.0_wp
    eform = 0.0_wp
    ework = 0.0_wp
    do step = 1, nsteps
      pold = -sum(p%stress(1:3, 1))/3.0_wp
      vold = p%vol(1)
      call particles_stress_update(p, models, lgrad, 1.0_wp, bad)
      call check(bad == 0, 'MG compression: volume positive')
      pnow = -sum(p%stress(1:3, 1))/3.0_wp
      work = work - 0.5_wp*(pold + pnow)*(p%vol(1) - vold)
      eform = max(eform, abs(pnow - mg_pressure(p%rho(1), p%e(1)))/abs(pnow))
      ework = max(ework, abs(p%m(1)*p%e(1) - work)/abs(work))
    end do
    pfin = -sum(p%stress(1:3, 1))/3.0_wp
    efin = p%e(1)
  end subroutine mg_compress

  !> The exact isentrope from (rho0, e = 0) to rho0 1.2: RK4 of de/dv =
  !> -p(1/v, e) in the specific volume v, n steps; returns p at the end.
  real(wp) function isentrope_pressure(n) result(pr)
    integer, intent(in) :: n
    real(wp) :: v, dv, e, k1, k2, k3, k4
    integer :: i
    v = 1.0_wp/cu_rho0
    dv = (1.0_wp/(1.2_wp*cu_rho0) - v)/n
    e = 0.0_wp
    do i = 1, n
      k1 = -mg_pressure(1.0_wp/v, e)
      k2 = -mg_pressure(1.0_wp/(v + 0.5_wp*dv), e + 0.5_wp*dv*k1)
      k3 = -mg_pressure(1.0_wp/(v + 0.5_wp*dv), e + 0.5_wp*dv*k2)
      k4 = -mg_pressure(1.0_wp/(v + dv), e + dv*k3)
      e = e + dv*(k1 + 2.0_wp*k2 + 2.0_wp*k3 + k4)/6.0_wp
      v = v + dv
    end do
    pr = mg_pressure(1.0_wp/v, e)
  end function isentrope_pressure

  subroutine test_mg_hydrostatic()
    real(wp) :: p50, e50, f50, w50, p100, e100, f100, w100, pex, r50, r100
    call mg_compress(50, p50, e50, f50, w50)
    call mg_compress(100, p100, e100, f100, w100)
    pex = isentrope_pressure(20000)
    r50 = p50/pex - 1.0_wp
    r100 = p100/pex - 1.0_wp
    write(*, '(a,es22.14,a,es22.14,a,es22.14)') 'MG isentrope to rho = 1.2 rho0: p ', pex, ', trapezoid 50 steps ', p50, &
      ', 100 steps ', p100
    ! (round-off: a few hundred operations on O(1) numbers)
    call check_close('MG hydrostatic: max |p/p_formula(rho, e) - 1|', f50, 0.0_wp, 1.0e-13_wp)
    call check_close('MG hydrostatic: max |m e/compression work - 1|', w50, 0.0_wp, 1.0e-12_wp)
    ! (the trapezoid is second order in Delta V, Delta V/V = 3.6e-3 per step:
    ! measured 1.27e-5 at 50 steps, 3.2e-6 at 100; the bound is 1.5x that, the
    ! ratio below checks the order)
    call check_close('MG hydrostatic: p/p_isentrope - 1 (50 steps)', r50, 0.0_wp, 2.0e-5_wp)
    call check_close('MG hydrostatic: error ratio 50/100 steps (second order: 4)', r50/r100, 4.0_wp, 0.2_wp)
    call check(e100 > 0.0_wp .and. p100 > cu_rho0*cu_c0**2*0.2_wp, 'MG hydrostatic: e > 0, p above rho0 c0^2 mu')
  end subroutine test_mg_hydrostatic

  subroutine test_mg_uniaxial()
    type(particles_t) :: p
    type(grid_t) :: g
    type(strength_slot_t), allocatable :: models(:)
    real(wp) :: lgrad(3, 3, 8), r, s0(6), v0, work, pm, sdev, dt, kw(8), mnode(8), mp(8)
    integer :: step, bad, kmin
    call one_cell(g, p, 1)
    p%rho = cu_rho0
    p%m = cu_rho0*p%vol
    call copper(models, 1.0_wp)
    ! the stable step at rest: cfl L/c, L = 1 (unit cube), nodes heavy (no guard)
    mnode = 1.0e30_wp
    mp = 0.0_wp
    call particles_stable_dt(g, g%x, p, spread(.true., 1, p%np), models, 0.5_wp, mnode, mp, kw, dt, kmin)
    call check_close('MG stable step / (cfl/sqrt(c0^2 + 4G/(3 rho0))) - 1', &
                     dt/(0.5_wp/sqrt(cu_c0**2 + 4.0_wp*cu_g/(3.0_wp*cu_rho0))) - 1.0_wp, 0.0_wp, 10*eps)
    r = 1.0e-3_wp
    lgrad = 0.0_wp
    lgrad(1, 1, :) = -r
    work = 0.0_wp
    do step = 1, 40
      s0 = p%stress(:, 1)
      v0 = p%vol(1)
      call particles_stress_update(p, models, lgrad, 1.0_wp, bad)
      ! the trapezoid: sigma = s - p I, deviatoric part with Vbar, pressure with Delta V
      pm = (s0(1) + p%stress(1, 1) + s0(2) + p%stress(2, 1) + s0(3) + p%stress(3, 1))/6.0_wp
      sdev = 0.5_wp*(s0(1) + p%stress(1, 1)) - pm
      work = work + sdev*(-r)*0.5_wp*(v0 + p%vol(1)) + pm*(p%vol(1) - v0)
    end do
    pm = -sum(p%stress(1:3, 1))/3.0_wp
    call check(bad == 0, 'MG uniaxial: volume positive')
    call check_close('MG uniaxial: s_xx/(-(4/3) G eps) - 1', (p%stress(1, 1) + pm)/(-4.0_wp/3.0_wp*cu_g*40*r) &
                     - 1.0_wp, 0.0_wp, 100*eps)
    call check_close('MG uniaxial: p/p_formula(rho, e) - 1', pm/mg_pressure(p%rho(1), p%e(1)) - 1.0_wp, 0.0_wp, &
                     1.0e-13_wp)
    call check_close('MG uniaxial: m e/trapezoid work - 1', p%m(1)*p%e(1)/work - 1.0_wp, 0.0_wp, 1.0e-12_wp)
  end subroutine test_mg_uniaxial

  !> Two cells along x; eight particles of volume 1/8 in the first: scale
  !> 0 there, 1 in the second; with one particle's volume, 7/8.
  subroutine test_visc_scale()
    type(grid_t) :: g
    type(particles_t) :: p
    type(hydro_t) :: h
    type(hydro_params_t) :: par
    type(error_t), allocatable :: err
    real(wp) :: vscale(2), vcell(2), vol(8), dts, q_full, f_full(3, 8)
    integer :: n, a
    call grid_init_box(g, 2, 1, 1, [0.0_wp, 0.0_wp, 0.0_wp], [2.0_wp, 1.0_wp, 1.0_wp], err)
    call particles_allocate(p, 8, 1, 1, err)
    call check(.not. allocated(err), 'two cells, eight particles')
    do a = 1, 8
      p%xi(:, a) = 0.25_wp + 0.5_wp*real([ibits(a - 1, 0, 1), ibits(a - 1, 1, 1), ibits(a - 1, 2, 1)], wp)
    end do
    p%cell = 1
    call particles_order(p, g%ncell, err)
    vcell = 1.0_wp
    vol = 0.125_wp
    call particles_cell_fraction(g, p, vol, vcell, vscale)
    call check_close('viscosity scale of a filled cell', vscale(1), 0.0_wp, 0.0_wp)
    call check_close('viscosity scale of an empty cell', vscale(2), 1.0_wp, 0.0_wp)
    vol = 0.0_wp
    vol(3) = 0.125_wp
    call particles_cell_fraction(g, p, vol, vcell, vscale)
    call check_close('viscosity scale of a cell an eighth covered', vscale(1), 0.875_wp, 0.0_wp)
    ! a cell compressed along x (u_x = -x on the first cell's nodes): q scales
    call hydro_allocate(h, g%ncell, g%nnode, err)
    call check(.not. allocated(err), 'hydro arrays')
    h%vol = 1.0_wp
    h%rho = 1.0_wp
    h%cs = 1.0_wp
    h%p = 0.0_wp
    h%u = 0.0_wp
    do n = 1, g%nnode
      h%u(1, n) = -min(g%x(1, n), 1.0_wp)
    end do
    par%hourglass = 0.0_wp
    call lagrange_strain_rates(g, g%x, h%u, h, par, dts)
    call lagrange_corner_forces(g, g%x, h%u, h, par)
    q_full = h%q(1)
    f_full = h%fc(:, :, 1)
    call lagrange_corner_forces(g, g%x, h%u, h, par, vscale)
    call check(q_full > 0.0_wp, 'a compressed cell has viscosity')
    call check_close('scaled viscosity q/q_full', h%q(1)/q_full, 0.875_wp, 4*eps)
    call check_close('scaled viscous forces |f - 7/8 f_full|', maxval(abs(h%fc(:, :, 1) - 0.875_wp*f_full)), 0.0_wp, &
                     8*eps*maxval(abs(f_full)))
  end subroutine test_visc_scale
end program test_particles_lagrange
