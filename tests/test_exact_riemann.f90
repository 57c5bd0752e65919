!> Checks the exact Riemann solver against published star states (Toro,
!> "Riemann Solvers and Numerical Methods for Fluid Dynamics", Table 4.3),
!> a two-gamma problem checked by its own jump relations, sampled profiles
!> and cell averages. Prints "FAIL: ..." and stops with code 1 on a failure.
program test_exact_riemann
  use base_kinds, only: wp
  use exact_riemann, only: riemann_t, riemann_solve, riemann_sample, &
                           riemann_cell_average
  implicit none

  type(riemann_t) :: rs
  logical :: ok

  ! --- Sod (Toro test 1), gamma 1.4 -----------------------------------------
  call riemann_solve(rs, 1.0_wp, 0.0_wp, 1.0_wp, 1.4_wp, &
                     0.125_wp, 0.0_wp, 0.1_wp, 1.4_wp, ok)
  call check(ok, 'Sod: solver did not converge')
  call show('Sod', rs)
  call check_rel('Sod p*', rs%p_star, 0.30313_wp, 5.0e-5_wp)
  call check_rel('Sod u*', rs%u_star, 0.92745_wp, 5.0e-5_wp)
  call check_rel('Sod rho*L', rs%rho_star_left, 0.42632_wp, 5.0e-5_wp)
  call check_rel('Sod rho*R', rs%rho_star_right, 0.26557_wp, 5.0e-5_wp)
  call sod_profile(rs)
  call sod_cell_averages(rs)

  ! --- Toro test 2 (123 problem) ---------------------------------------------
  call riemann_solve(rs, 1.0_wp, -2.0_wp, 0.4_wp, 1.4_wp, &
                     1.0_wp, 2.0_wp, 0.4_wp, 1.4_wp, ok)
  call check(ok, 'Toro 2: solver did not converge')
  call show('Toro 2 (123)', rs)
  call check_abs('Toro 2 p*', rs%p_star, 0.00189_wp, 1.0e-4_wp)
  call check_abs('Toro 2 u*', rs%u_star, 0.0_wp, 1.0e-10_wp)

  ! --- Toro test 3 -------------------------------------------------------------
  call riemann_solve(rs, 1.0_wp, 0.0_wp, 1000.0_wp, 1.4_wp, &
                     1.0_wp, 0.0_wp, 0.01_wp, 1.4_wp, ok)
  call check(ok, 'Toro 3: solver did not converge')
  call show('Toro 3', rs)
  call check_rel('Toro 3 p*', rs%p_star, 460.894_wp, 1.0e-5_wp)
  call check_rel('Toro 3 u*', rs%u_star, 19.5975_wp, 1.0e-5_wp)

  ! --- Toro test 5 -------------------------------------------------------------
  call riemann_solve(rs, 5.99924_wp, 19.5975_wp, 460.894_wp, 1.4_wp, &
                     5.99242_wp, -6.19633_wp, 46.0950_wp, 1.4_wp, ok)
  call check(ok, 'Toro 5: solver did not converge')
  call show('Toro 5', rs)
  call check_rel('Toro 5 p*', rs%p_star, 1691.64_wp, 1.0e-5_wp)
  call check_rel('Toro 5 u*', rs%u_star, 8.68975_wp, 1.0e-5_wp)

  ! --- Vacuum generation must be reported, not solved --------------------------
  call riemann_solve(rs, 1.0_wp, -20.0_wp, 0.4_wp, 1.4_wp, &
                     1.0_wp, 20.0_wp, 0.4_wp, 1.4_wp, ok)
  call check(.not. ok, 'vacuum: ok should be .false.')
  call check(.not. rs%solved, 'vacuum: rs%solved should be .false.')

  ! --- Sonic point inside a left rarefaction (Toro ch. 6 test 1 data) ----------
  call riemann_solve(rs, 1.0_wp, 0.75_wp, 1.0_wp, 1.4_wp, &
                     0.125_wp, 0.0_wp, 0.1_wp, 1.4_wp, ok)
  call check(ok, 'sonic: solver did not converge')
  call sonic_point(rs)

  ! --- Two-gamma Sod -------------------------------------------------------------
  call riemann_solve(rs, 1.0_wp, 0.0_wp, 2.0_wp, 2.0_wp, &
                     0.125_wp, 0.0_wp, 0.1_wp, 1.4_wp, ok)
  call check(ok, 'two-gamma Sod: solver did not converge')
  call show('two-gamma Sod', rs)
  call two_gamma_checks(rs)

  print '(a)', 'PASS test_exact_riemann'

contains

  subroutine check(cond, msg)
    logical, intent(in) :: cond
    character(len=*), intent(in) :: msg
    if (.not. cond) then
      print '(a)', 'FAIL: '//msg
      error stop 1
    end if
  end subroutine check

  subroutine check_rel(name, val, ref, tol)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: val, ref, tol
    character(len=160) :: buf
    if (.not. abs(val - ref) <= tol * abs(ref)) then
      write (buf, '(a,": got ",es24.16," expected ",es24.16," (rel tol ",es9.2,")")') &
        name, val, ref, tol
      call check(.false., trim(buf))
    end if
  end subroutine check_rel

  subroutine check_abs(name, val, ref, tol)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: val, ref, tol
    character(len=160) :: buf
    if (.not. abs(val - ref) <= tol) then
      write (buf, '(a,": got ",es24.16," expected ",es24.16," (abs tol ",es9.2,")")') &
        name, val, ref, tol
      call check(.false., trim(buf))
    end if
  end subroutine check_abs

  subroutine show(name, r)
    character(len=*), intent(in) :: name
    type(riemann_t), intent(in) :: r
    print '(a)', name//':'
    print '(a,es24.16)', '  p*     = ', r%p_star
    print '(a,es24.16)', '  u*     = ', r%u_star
    print '(a,es24.16)', '  rho*L  = ', r%rho_star_left
    print '(a,es24.16)', '  rho*R  = ', r%rho_star_right
  end subroutine show

  ! Sod at t = 0.2 with the diaphragm at x0 = 0.5: wave positions, which
  ! region x = 0.6 lies in, and the rarefaction head at x0 - c_L t.
  subroutine sod_profile(r)
    type(riemann_t), intent(in) :: r
    real(wp), parameter :: t = 0.2_wp, x0 = 0.5_wp
    real(wp) :: cl, cstar_l, x_head, x_tail, x_contact, x_shock, s_shock
    real(wp) :: rho, u, p, sa, sb, sm
    integer :: i

    cl = sqrt(1.4_wp * 1.0_wp / 1.0_wp)
    cstar_l = sqrt(1.4_wp * r%p_star / r%rho_star_left)
    s_shock = r%u_star * r%rho_star_right / (r%rho_star_right - 0.125_wp)  ! mass RH, u_R = 0
    x_head = x0 - cl * t
    x_tail = x0 + (r%u_star - cstar_l) * t
    x_contact = x0 + r%u_star * t
    x_shock = x0 + s_shock * t
    print '(a)', 'Sod profile at t = 0.2, x0 = 0.5:'
    print '(a,f12.8)', '  rarefaction head x = ', x_head
    print '(a,f12.8)', '  rarefaction tail x = ', x_tail
    print '(a,f12.8)', '  contact          x = ', x_contact
    print '(a,f12.8)', '  shock            x = ', x_shock

    ! x = 0.6 lies between the rarefaction tail and the contact (left star).
    call check(0.6_wp > x_tail .and. 0.6_wp < x_contact, 'Sod: x=0.6 not in left star region')
    call riemann_sample(r, (0.6_wp - x0) / t, rho, u, p)
    print '(a,es24.16,a)', '  rho(x=0.60)       = ', rho, '  (left star region: rho*L)'
    call check_rel('Sod rho(0.6) = rho*L', rho, r%rho_star_left, 1.0e-14_wp)
    call check_rel('Sod u(0.6) = u*', u, r%u_star, 1.0e-14_wp)
    call check_rel('Sod p(0.6) = p*', p, r%p_star, 1.0e-14_wp)

    ! x = 0.75 lies between the contact and the shock (right star).
    call check(0.75_wp > x_contact .and. 0.75_wp < x_shock, 'Sod: x=0.75 not in right star region')
    call riemann_sample(r, (0.75_wp - x0) / t, rho, u, p)
    print '(a,es24.16,a)', '  rho(x=0.75)       = ', rho, '  (right star region: rho*R)'
    call check_rel('Sod rho(0.75) = rho*R', rho, r%rho_star_right, 1.0e-14_wp)

    ! Rarefaction head: locate the edge of the undisturbed left state in the
    ! sampled profile by bisection on s.
    sa = -2.0_wp * cl
    sb = 0.0_wp
    do i = 1, 200
      sm = 0.5_wp * (sa + sb)
      call riemann_sample(r, sm, rho, u, p)
      if (rho >= 1.0_wp) then
        sa = sm
      else
        sb = sm
      end if
      if (sb - sa <= 1.0e-15_wp) exit
    end do
    print '(a,f18.14)', '  head from profile x = ', x0 + sa * t
    call check_abs('Sod rarefaction head position', x0 + sa * t, x_head, 1.0e-12_wp)
    call riemann_sample(r, -cl - 1.0e-9_wp, rho, u, p)
    call check_abs('Sod left state ahead of head', rho, 1.0_wp, 0.0_wp)
    call riemann_sample(r, -cl + 1.0e-6_wp, rho, u, p)
    call check(rho < 1.0_wp .and. rho > 1.0_wp - 1.0e-5_wp, 'Sod: density not continuous at head')
  end subroutine sod_profile

  subroutine sod_cell_averages(r)
    type(riemann_t), intent(in) :: r
    real(wp), parameter :: t = 0.2_wp, x0 = 0.5_wp
    real(wp) :: rho, u, p, e, xa, xb, xc, xs, expect, s_shock

    ! Constant left region (head is at x ~ 0.263).
    call riemann_cell_average(r, x0, t, 0.1_wp, 0.2_wp, 50, rho, u, p, e)
    call check_abs('avg const left rho', rho, 1.0_wp, 1.0e-14_wp)
    call check_abs('avg const left u', u, 0.0_wp, 1.0e-14_wp)
    call check_abs('avg const left p', p, 1.0_wp, 1.0e-14_wp)
    call check_abs('avg const left e', e, 1.0_wp / (0.4_wp * 1.0_wp), 1.0e-14_wp)
    ! Constant right-star region.
    call riemann_cell_average(r, x0, t, 0.72_wp, 0.78_wp, 50, rho, u, p, e)
    call check_rel('avg const star rho', rho, r%rho_star_right, 1.0e-14_wp)
    call check_rel('avg const star u', u, r%u_star, 1.0e-14_wp)
    call check_rel('avg const star p', p, r%p_star, 1.0e-14_wp)
    call check_rel('avg const star e', e, r%p_star / (0.4_wp * r%rho_star_right), 1.0e-14_wp)

    ! Cell straddling the contact.
    xa = 0.67_wp
    xb = 0.70_wp
    xc = x0 + r%u_star * t
    expect = (r%rho_star_left * (xc - xa) + r%rho_star_right * (xb - xc)) / (xb - xa)
    call riemann_cell_average(r, x0, t, xa, xb, 1000, rho, u, p, e)
    print '(a,2es24.16)', 'Sod contact cell avg rho (nsub=1000), exact mix: ', rho, expect
    call check_abs('avg contact cell rho', rho, expect, 1.0e-3_wp)
    call check_rel('avg contact cell u', u, r%u_star, 1.0e-13_wp)
    call check_rel('avg contact cell p', p, r%p_star, 1.0e-13_wp)
    call check_rel('avg contact cell e', e, r%p_star / (0.4_wp * rho), 1.0e-13_wp)

    ! Cell straddling the shock with nsub = 50: within |jump| / (2*50).
    s_shock = r%u_star * r%rho_star_right / (r%rho_star_right - 0.125_wp)
    xs = x0 + s_shock * t
    xa = xs - 0.013_wp
    xb = xs + 0.017_wp
    expect = (r%rho_star_right * (xs - xa) + 0.125_wp * (xb - xs)) / (xb - xa)
    call riemann_cell_average(r, x0, t, xa, xb, 50, rho, u, p, e)
    print '(a,2es24.16)', 'Sod shock cell avg rho (nsub=50), exact mix:     ', rho, expect
    call check_abs('avg shock cell rho (nsub=50)', rho, expect, &
                   (r%rho_star_right - 0.125_wp) / 100.0_wp)
  end subroutine sod_cell_averages

  ! In a transonic left fan the state at s = 0 is sonic: u = c.
  subroutine sonic_point(r)
    type(riemann_t), intent(in) :: r
    real(wp) :: rho, u, p, c
    call check(r%p_star < r%pl, 'sonic: left wave is not a rarefaction')
    call check(r%ul - r%cl < 0.0_wp .and. &
               r%u_star - sqrt(1.4_wp * r%p_star / r%rho_star_left) > 0.0_wp, &
               'sonic: fan is not transonic')
    call riemann_sample(r, 0.0_wp, rho, u, p)
    c = sqrt(1.4_wp * p / rho)
    print '(a,2es24.16)', 'sonic point (u, c): ', u, c
    call check_rel('sonic point u = c', u, c, 1.0e-13_wp)
  end subroutine sonic_point

  ! Two-gamma Sod: left rarefaction (gamma 2), right shock (gamma 1.4).
  ! Independent checks of the star state through the wave relations.
  subroutine two_gamma_checks(r)
    type(riemann_t), intent(in) :: r
    real(wp), parameter :: gl = 2.0_wp, gr = 1.4_wp
    real(wp), parameter :: rhol = 1.0_wp, ul = 0.0_wp, pl = 2.0_wp
    real(wp), parameter :: rhor = 0.125_wp, ur = 0.0_wp, pr = 0.1_wp
    real(wp), parameter :: tol = 1.0e-10_wp
    real(wp) :: cl, cr, cstar_l, u_from_left, u_from_right, qr
    real(wp) :: s_mass, s_formula, s_profile, sa, sb, sm
    real(wp) :: rho1, u1, p1, rho2, u2, p2, eps
    real(wp) :: m_flux_l, m_flux_r, mom_l, mom_r, en_l, en_r, er, es
    real(wp) :: xa, xb, xc, rho, u, p, e, expect_rho, expect_e
    integer :: i

    call check(r%p_star < pl .and. r%p_star > pr, 'two-gamma: expected rarefaction + shock')
    cl = sqrt(gl * pl / rhol)
    cr = sqrt(gr * pr / rhor)

    ! Velocity continuity at p*: left-rarefaction Riemann invariant and
    ! right-shock Hugoniot give the same u*.
    u_from_left = ul + 2.0_wp * cl / (gl - 1.0_wp) * &
                  (1.0_wp - (r%p_star / pl)**((gl - 1.0_wp) / (2.0_wp * gl)))
    qr = sqrt((r%p_star + (gr - 1.0_wp) / (gr + 1.0_wp) * pr) * (gr + 1.0_wp) * rhor / 2.0_wp)
    u_from_right = ur + (r%p_star - pr) / qr
    print '(a,2es24.16)', '  u* from left wave, right wave: ', u_from_left, u_from_right
    call check_rel('two-gamma u* (left wave)', u_from_left, r%u_star, tol)
    call check_rel('two-gamma u* (right wave)', u_from_right, r%u_star, tol)

    ! Left rarefaction: isentrope and Riemann invariant.
    call check_rel('two-gamma left isentrope', r%p_star / r%rho_star_left**gl, &
                   pl / rhol**gl, tol)
    cstar_l = sqrt(gl * r%p_star / r%rho_star_left)
    call check_rel('two-gamma left Riemann invariant', &
                   r%u_star + 2.0_wp * cstar_l / (gl - 1.0_wp), &
                   ul + 2.0_wp * cl / (gl - 1.0_wp), tol)

    ! Pressure / velocity continuity across the contact in the sampled profile.
    eps = 1.0e-9_wp
    call riemann_sample(r, r%u_star - eps, rho1, u1, p1)
    call riemann_sample(r, r%u_star + eps, rho2, u2, p2)
    call check_rel('two-gamma contact p continuity', p1, p2, tol)
    call check_rel('two-gamma contact u continuity', u1, u2, tol)
    call check_rel('two-gamma contact p = p*', p1, r%p_star, tol)
    call check_rel('two-gamma contact rho left', rho1, r%rho_star_left, tol)
    call check_rel('two-gamma contact rho right', rho2, r%rho_star_right, tol)

    ! Right shock speed: from mass conservation, from the shock formula, and
    ! located in the sampled profile by bisection.
    s_mass = (r%rho_star_right * r%u_star - rhor * ur) / (r%rho_star_right - rhor)
    s_formula = ur + cr * sqrt((gr + 1.0_wp) / (2.0_wp * gr) * r%p_star / pr &
                               + (gr - 1.0_wp) / (2.0_wp * gr))
    sa = r%u_star + eps
    sb = 10.0_wp * s_formula
    do i = 1, 200
      sm = 0.5_wp * (sa + sb)
      call riemann_sample(r, sm, rho1, u1, p1)
      if (rho1 > 0.5_wp * (r%rho_star_right + rhor)) then
        sa = sm
      else
        sb = sm
      end if
      if (sb - sa <= 1.0e-15_wp * abs(sm)) exit
    end do
    s_profile = 0.5_wp * (sa + sb)
    print '(a,3es24.16)', '  shock speed (mass RH, formula, profile): ', s_mass, s_formula, s_profile
    call check_rel('two-gamma shock speed formula vs mass RH', s_formula, s_mass, tol)
    call check_rel('two-gamma shock speed profile vs mass RH', s_profile, s_mass, tol)

    ! Rankine-Hugoniot in the shock frame: F(W*R) - S U*R = F(WR) - S UR.
    m_flux_l = r%rho_star_right * (r%u_star - s_mass)
    m_flux_r = rhor * (ur - s_mass)
    call check_rel('two-gamma RH mass', m_flux_l, m_flux_r, tol)
    mom_l = r%rho_star_right * r%u_star * (r%u_star - s_mass) + r%p_star
    mom_r = rhor * ur * (ur - s_mass) + pr
    call check_rel('two-gamma RH momentum', mom_l, mom_r, tol)
    es = r%p_star / (gr - 1.0_wp) + 0.5_wp * r%rho_star_right * r%u_star**2
    er = pr / (gr - 1.0_wp) + 0.5_wp * rhor * ur**2
    en_l = (es + r%p_star) * r%u_star - s_mass * es
    en_r = (er + pr) * ur - s_mass * er
    call check_rel('two-gamma RH energy', en_l, en_r, tol)
    print '(a,2es24.16)', '  RH mass flux (star, right):     ', m_flux_l, m_flux_r
    print '(a,2es24.16)', '  RH momentum flux (star, right): ', mom_l, mom_r

    ! Cell straddling the material interface: e uses each side's gamma.
    xa = 0.6_wp
    xb = 0.66_wp
    xc = 0.5_wp + r%u_star * 0.1_wp
    call check(xa > 0.5_wp + (r%u_star - cstar_l) * 0.1_wp .and. xb < 0.5_wp + s_mass * 0.1_wp &
               .and. xa < xc .and. xc < xb, &
               'two-gamma: averaging cell not inside star region or not straddling contact')
    expect_rho = (r%rho_star_left * (xc - xa) + r%rho_star_right * (xb - xc)) / (xb - xa)
    expect_e = (r%p_star / (gl - 1.0_wp) * (xc - xa) + r%p_star / (gr - 1.0_wp) * (xb - xc)) &
               / (r%rho_star_left * (xc - xa) + r%rho_star_right * (xb - xc))
    call riemann_cell_average(r, 0.5_wp, 0.1_wp, xa, xb, 1000, rho, u, p, e)
    print '(a,2es24.16)', '  contact cell avg rho, e (nsub=1000): ', rho, e
    call check_abs('two-gamma contact cell rho', rho, expect_rho, 1.0e-3_wp)
    call check_rel('two-gamma contact cell e', e, expect_e, 1.0e-3_wp)
    call check_rel('two-gamma contact cell p', p, r%p_star, 1.0e-13_wp)
  end subroutine two_gamma_checks

end program test_exact_riemann
