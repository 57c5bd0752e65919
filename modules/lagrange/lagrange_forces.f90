!> Corner forces of the staggered scheme: pressure (Eq. 18), a directional
!> artificial viscosity with a monotonic limiter, and viscous hourglass
!> control. Also the stable time step.
!>
!> Pressure. The corner force on node a is f_a = p dV/dx_a, the exact
!> gradient of the 24-tet volume (`mesh_geometry`); it equals -p times the
!> integral of n over the corner's share of the cell surface (Eq. 18) and
!> makes the compatible energy update (Eq. 19) reproduce p dV exactly.
!>
!> Artificial viscosity (an edge viscosity in the spirit of Caramana,
!> Shashkov and Whalen 1998, with the four parallel edges of a logical
!> direction taken together). In each logical direction d a cell has a median
!> surface S_d (through the midpoints of its four d-edges) and a velocity jump
!> dv_d (mean over the d-edges of v_high - v_low). When the cell is compressed
!> along d (S_d.dv_d < 0) a viscous pressure
!>   q_d = rho (1 - phi_d) (c_quad |dv_d|^2 + c_lin cs |dv_d|)
!> acts along the jump: -q_d A_d dv_d/|dv_d| / 4 on each high node and the
!> opposite on each low node, with A_d = |S_d . dv_d|/|dv_d| the area seen by
!> the jump. The forces sum to zero (momentum), their work q_d A_d |dv_d| only
!> heats, and pure shear (S_d.dv_d = 0) feels nothing. Using the whole jump
!> rather than its normal part keeps a shock running along a grid diagonal
!> from getting a much weaker viscosity than one along a grid line (tried:
!> the normal-part variant let the 3D Sedov shock run 20 % ahead on the axes).
!> phi_d is a Christensen-type limiter on the ratios of the strain rate
!> g_d = S_d.dv_d / V of the two d-neighbours to the cell's own:
!>   phi = max(0, min(1, 2 r_-, 2 r_+, (r_- + r_+)/2)),
!> so uniform compression and smooth flow get no viscosity and shocks full
!> viscosity (Christensen 1990).
!>
!> Hourglass. Flanagan-Belytschko viscous control: with the hourglass base
!> vectors h (xi eta, eta zeta, zeta xi, xi eta zeta at the nodes) made
!> orthogonal to linear fields, gamma_a = h_a - (dV/dx_a . sum_b h_b x_b)/V,
!> f_a = -k rho cs A sum_modes gamma_a (sum_b gamma_b v_b); it sums to
!> zero, is dissipative and vanishes for any linear velocity field. A is the
!> mean of the three median areas (V^(2/3) for a cube).
module lagrange_forces
  use base_kinds, only: wp
  use mesh_grid, only: grid_t
  use mesh_geometry, only: hex_volume_gradient, hex_median_areas, hex_edges
  use lagrange_state, only: hydro_t, hydro_params_t
  implicit none
  private
  public :: lagrange_strain_rates, lagrange_corner_forces

  !> Hourglass base vectors at the eight nodes, (node, mode).
  real(wp), parameter :: hg_base(8, 4) = reshape( &
    [ 1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp,  1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp, &
      1.0_wp,  1.0_wp, -1.0_wp, -1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp,  1.0_wp, &
      1.0_wp, -1.0_wp,  1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp, -1.0_wp,  1.0_wp, &
     -1.0_wp,  1.0_wp,  1.0_wp, -1.0_wp,  1.0_wp, -1.0_wp, -1.0_wp,  1.0_wp], [8, 4])

contains

  !> Mean jump of a node field across the cell in logical direction d:
  !> the average over the four d-edges of (high node - low node).
  pure function edge_jump(vn, d) result(dv)
    real(wp), intent(in) :: vn(3, 8)
    integer, intent(in) :: d
    real(wp) :: dv(3)
    integer :: e
    dv = 0.0_wp
    do e = 1, 4
      dv = dv + vn(:, hex_edges(2, e, d)) - vn(:, hex_edges(1, e, d))
    end do
    dv = 0.25_wp*dv
  end function edge_jump

  !> Directional strain rates g(d,c) = S_d.dv_d / V of every cell for the
  !> velocity v, and the largest stable step for that state (CFL on sound
  !> speed plus viscous signal speed, and a bound on the relative volume change).
  subroutine lagrange_strain_rates(g, x, v, h, par, dt_stable)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), v(:, :)
    type(hydro_t), intent(inout) :: h
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(out) :: dt_stable
    integer :: c, d, e, n0, ci, cj, ck
    real(wp) :: xn(3, 8), vn(3, 8), s(3, 3), dv(3), area, amax, du, dumax, div, cq, ceff, dtc

    dt_stable = huge(1.0_wp)
    !$omp parallel do default(none) shared(g, x, v, h, par) collapse(2) &
    !$omp private(c, d, e, n0, ci, cj, ck, xn, vn, s, dv, area, amax, du, dumax, div, cq, ceff, dtc) &
    !$omp reduction(min: dt_stable) schedule(static)
    do ck = 1, g%nk
    do cj = 1, g%nj
    do ci = 1, g%ni
      c = ci + g%ni*((cj - 1) + g%nj*(ck - 1))
      n0 = ci + g%sx*(cj - 1) + g%sxy*(ck - 1)
      do e = 1, 8
        xn(:, e) = x(:, n0 + g%corner_offset(e))
        vn(:, e) = v(:, n0 + g%corner_offset(e))
      end do
      call hex_median_areas(xn, s)
      amax = 0.0_wp
      dumax = 0.0_wp
      div = 0.0_wp
      do d = 1, 3
        dv = edge_jump(vn, d)
        area = norm2(s(:, d))
        amax = max(amax, area)
        h%grad(d, c) = dot_product(s(:, d), dv)/h%vol(c)
        div = div + h%grad(d, c)
        du = dot_product(s(:, d), dv)/max(area, tiny(1.0_wp))
        dumax = max(dumax, -du)
      end do
      ! signal speed with viscosity: cq + sqrt(cq^2 + cs^2) (Wilkins)
      cq = par%q_linear*h%cs(c) + par%q_quad*dumax
      ceff = cq + sqrt(cq*cq + h%cs(c)**2)
      dtc = huge(1.0_wp)
      if (ceff > 0.0_wp) dtc = par%cfl*(h%vol(c)/amax)/ceff
      if (abs(div) > 0.0_wp) dtc = min(dtc, par%dv_max/abs(div))
      dt_stable = min(dt_stable, dtc)
    end do
    end do
    end do
    !$omp end parallel do
  end subroutine lagrange_strain_rates

  !> Corner forces fc(3,8,c) from the positions x, velocities v and the cell
  !> pressures in h; needs h%grad from `lagrange_strain_rates` for the same x, v.
  subroutine lagrange_corner_forces(g, x, v, h, par)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), v(:, :)
    type(hydro_t), intent(inout) :: h
    type(hydro_params_t), intent(in) :: par
    integer :: c, d, e, a, m, n0, ci, cj, ck, cm, cp, stride(3), ilog(3), nlog(3)
    real(wp) :: xn(3, 8), vn(3, 8), b(3, 8), f(3, 8), s(3, 3), dv(3)
    real(wp) :: vol, sdv, area, du, gself, rm, rp, phi, qd, qsum, coef, hx(3), gam(8), gv(3)

    stride = [1, g%ni, g%ni*g%nj]
    nlog = [g%ni, g%nj, g%nk]
    !$omp parallel do default(none) shared(g, x, v, h, par, stride, nlog) collapse(2) &
    !$omp private(c, d, e, a, m, n0, ci, cj, ck, cm, cp, ilog, xn, vn, b, f, s, dv) &
    !$omp private(vol, sdv, area, du, gself, rm, rp, phi, qd, qsum, coef, hx, gam, gv) &
    !$omp schedule(static)
    do ck = 1, g%nk
    do cj = 1, g%nj
    do ci = 1, g%ni
      c = ci + g%ni*((cj - 1) + g%nj*(ck - 1))
      n0 = ci + g%sx*(cj - 1) + g%sxy*(ck - 1)
      do a = 1, 8
        xn(:, a) = x(:, n0 + g%corner_offset(a))
        vn(:, a) = v(:, n0 + g%corner_offset(a))
      end do
      call hex_volume_gradient(xn, vol, b)
      ! Eq. (18): pressure corner forces
      f = h%p(c)*b

      ! directional viscosity with limiter
      call hex_median_areas(xn, s)
      ilog = [ci, cj, ck]
      qsum = 0.0_wp
      do d = 1, 3
        dv = edge_jump(vn, d)
        sdv = dot_product(s(:, d), dv)
        if (.not. (sdv < 0.0_wp)) cycle
        du = norm2(dv)
        area = abs(sdv)/du
        gself = h%grad(d, c)
        cm = c
        cp = c
        if (ilog(d) > 1) cm = c - stride(d)
        if (ilog(d) < nlog(d)) cp = c + stride(d)
        rm = h%grad(d, cm)/gself
        rp = h%grad(d, cp)/gself
        phi = max(0.0_wp, min(1.0_wp, 2.0_wp*rm, 2.0_wp*rp, 0.5_wp*(rm + rp)))
        qd = h%rho(c)*(1.0_wp - phi)*(par%q_quad*du*du + par%q_linear*h%cs(c)*du)
        qsum = qsum + qd
        ! force along -dv on the high side, +dv on the low side
        dv = (0.25_wp*qd*area/du)*dv
        do e = 1, 4
          f(:, hex_edges(2, e, d)) = f(:, hex_edges(2, e, d)) - dv
          f(:, hex_edges(1, e, d)) = f(:, hex_edges(1, e, d)) + dv
        end do
      end do
      h%q(c) = qsum

      ! Flanagan-Belytschko viscous hourglass control
      if (par%hourglass > 0.0_wp) then
        ! length^2 scale: the mean median area (V^(2/3) for a cube, without a pow)
        coef = par%hourglass*h%rho(c)*h%cs(c)*(norm2(s(:, 1)) + norm2(s(:, 2)) + norm2(s(:, 3)))/3.0_wp
        do m = 1, 4
          hx = 0.0_wp
          do a = 1, 8
            hx = hx + hg_base(a, m)*xn(:, a)
          end do
          gv = 0.0_wp
          do a = 1, 8
            gam(a) = hg_base(a, m) - dot_product(b(:, a), hx)/vol
            gv = gv + gam(a)*vn(:, a)
          end do
          do a = 1, 8
            f(:, a) = f(:, a) - coef*gam(a)*gv
          end do
        end do
      end if
      h%fc(:, :, c) = f
    end do
    end do
    end do
    !$omp end parallel do
  end subroutine lagrange_corner_forces
end module lagrange_forces
