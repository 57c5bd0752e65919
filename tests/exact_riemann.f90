!> Exact solution of the Riemann problem for the 1-D Euler equations with two
!> ideal gases (one gamma each side of the material interface).
!>
!> Method (Toro, "Riemann Solvers and Numerical Methods for Fluid Dynamics",
!> ch. 4): the star pressure p* is the root of
!>
!>   f(p) = f_L(p) + f_R(p) + (u_R - u_L),
!>
!> where, for side K with gamma g_K, sound speed c_K,
!>   shock       (p >  p_K): f_K = (p - p_K) sqrt(A_K / (p + B_K)),
!>                           A_K = 2 / ((g_K + 1) rho_K),
!>                           B_K = (g_K - 1) / (g_K + 1) p_K,
!>   rarefaction (p <= p_K): f_K = 2 c_K / (g_K - 1) ((p / p_K)**z_K - 1),
!>                           z_K = (g_K - 1) / (2 g_K).
!> f is increasing and concave in p, and convex in y = ln p (f'p + f''p**2 > 0
!> on both branches). Hence a Newton step in p taken where f < 0 climbs
!> towards the root without passing it, and a Newton step in ln p taken where
!> f > 0, p <- p exp(-f / (p f')), descends towards it without passing it and
!> stays positive. Every iterate therefore stays inside the bracket [pa, pb]
!> with f(pa) < 0 < f(pb) (pa = 0 initially, valid whenever no vacuum is
!> generated) and convergence is quadratic from either side; a bisection step
!> replaces any step that leaves the bracket through rounding.
!> Then u* = (u_L + u_R)/2 + (f_R(p*) - f_L(p*))/2.
!>
!> The solution is self-similar in s = (x - x0) / t; `riemann_sample` returns
!> the state at a given s (left / right shock or rarefaction, including the
!> interior of a fan, where the sonic point s = 0 is just one more fan point),
!> and `riemann_cell_average` integrates it over a cell for comparison with
!> finite-volume results. Nothing here prints or stops.
module exact_riemann
  use base_kinds, only: wp
  implicit none
  private
  public :: riemann_t, riemann_solve, riemann_sample, riemann_cell_average

  !> Relative tolerance on successive p* iterates.
  real(wp), parameter :: p_tol = 1.0e-14_wp
  !> Maximum number of Newton (or bisection) iterations for p*.
  integer, parameter :: max_iter = 100

  !> Initial data of one Riemann problem (left / right constant states, each
  !> with its own ideal-gas gamma) and its solved star region.
  type, public :: riemann_t
    !> Left state: density, velocity, pressure, ratio of specific heats.
    real(wp) :: rhol = 0.0_wp, ul = 0.0_wp, pl = 0.0_wp, gl = 0.0_wp
    !> Right state: density, velocity, pressure, ratio of specific heats.
    real(wp) :: rhor = 0.0_wp, ur = 0.0_wp, pr = 0.0_wp, gr = 0.0_wp
    !> Sound speeds of the left and right states.
    real(wp) :: cl = 0.0_wp, cr = 0.0_wp
    !> Star-region pressure and velocity (continuous across the contact).
    real(wp) :: p_star = 0.0_wp, u_star = 0.0_wp
    !> Star-region densities left and right of the contact.
    real(wp) :: rho_star_left = 0.0_wp, rho_star_right = 0.0_wp
    !> True once `riemann_solve` succeeded; sampling is meaningful only then.
    logical :: solved = .false.
  end type riemann_t

contains

  !> Solves the Riemann problem (rhol, ul, pl; gamma gl) | (rhor, ur, pr;
  !> gamma gr) for the star state. ok = .false. (and rs%solved = .false.) if
  !> the data are not admissible (rho, p > 0, gamma > 1), if the data generate
  !> vacuum (2 c_L/(g_L-1) + 2 c_R/(g_R-1) <= u_R - u_L), or if p* does not
  !> converge to 1e-14 relative in 100 iterations.
  pure subroutine riemann_solve(rs, rhol, ul, pl, gl, rhor, ur, pr, gr, ok)
    type(riemann_t), intent(out) :: rs
    real(wp), intent(in) :: rhol, ul, pl, gl
    real(wp), intent(in) :: rhor, ur, pr, gr
    logical, intent(out) :: ok

    real(wp) :: du, p, pn, pa, pb, f, df, fl, dfl, fr, dfr
    logical :: have_pb, converged
    integer :: iter

    ok = .false.
    rs%rhol = rhol
    rs%ul = ul
    rs%pl = pl
    rs%gl = gl
    rs%rhor = rhor
    rs%ur = ur
    rs%pr = pr
    rs%gr = gr
    rs%solved = .false.

    if (.not. (rhol > 0.0_wp .and. pl > 0.0_wp .and. gl > 1.0_wp .and. &
               rhor > 0.0_wp .and. pr > 0.0_wp .and. gr > 1.0_wp)) return

    rs%cl = sqrt(gl * pl / rhol)
    rs%cr = sqrt(gr * pr / rhor)
    du = ur - ul

    ! Pressure positivity condition: f(0) < 0, else vacuum is generated.
    if (2.0_wp * rs%cl / (gl - 1.0_wp) + 2.0_wp * rs%cr / (gr - 1.0_wp) <= du) return

    p = initial_guess(rs)
    pa = 0.0_wp
    pb = 0.0_wp
    have_pb = .false.
    converged = .false.
    do iter = 1, max_iter
      call pressure_function(p, rhol, pl, rs%cl, gl, fl, dfl)
      call pressure_function(p, rhor, pr, rs%cr, gr, fr, dfr)
      f = fl + fr + du
      df = dfl + dfr
      if (f < 0.0_wp) then
        pa = p
        pn = p - f / df                 ! Newton in p (f concave): pn <= p*
      else if (f > 0.0_wp) then
        pb = p
        have_pb = .true.
        pn = p * exp(-f / (p * df))     ! Newton in ln p (convex): pn >= p*
      else
        converged = .true.
        exit
      end if
      if (abs(pn - p) <= p_tol * p) then
        p = pn
        converged = .true.
        exit
      end if
      ! Safeguard against rounding: stay strictly inside the bracket. pn <= pa
      ! can only follow a step with f > 0, so pb is then defined.
      if (pn <= pa .or. (have_pb .and. pn >= pb)) pn = 0.5_wp * (pa + pb)
      p = pn
      if (have_pb .and. pb - pa <= p_tol * p) then
        converged = .true.
        exit
      end if
    end do
    if (.not. converged) return

    call pressure_function(p, rhol, pl, rs%cl, gl, fl, dfl)
    call pressure_function(p, rhor, pr, rs%cr, gr, fr, dfr)
    rs%p_star = p
    rs%u_star = 0.5_wp * (ul + ur) + 0.5_wp * (fr - fl)
    rs%rho_star_left = star_density(p, rhol, pl, gl)
    rs%rho_star_right = star_density(p, rhor, pr, gr)
    rs%solved = .true.
    ok = .true.
  end subroutine riemann_solve

  !> Exact state (rho, u, p) at similarity coordinate s = (x - x0) / t of a
  !> solved problem. Points with s <= u_star belong to the left material.
  !> Returns zeros if `rs` is not solved.
  elemental subroutine riemann_sample(rs, s, rho, u, p)
    type(riemann_t), intent(in) :: rs
    real(wp), intent(in) :: s
    real(wp), intent(out) :: rho, u, p

    real(wp) :: g

    call sample_state(rs, s, rho, u, p, g)
  end subroutine riemann_sample

  !> Averages of the exact solution at time t (discontinuity initially at x0)
  !> over the cell [xa, xb]: density rho and pressure p are length averages,
  !> velocity u and specific internal energy e = p / ((gamma - 1) rho) (gamma
  !> of the local material) are mass-weighted, so rho*u and rho*e are the
  !> cell's momentum and internal-energy densities.
  !>
  !> Quadrature: composite midpoint rule with nsub (>= 1) equal sub-intervals.
  !> In smooth parts (constant states, rarefaction fans) the error is
  !> O((dx/nsub)**2). A discontinuity inside the cell is resolved only to the
  !> sub-interval containing it, so the error is at most |jump| / (2 nsub) per
  !> discontinuity (O(1/nsub), first order). With nsub >= 50 this is <= 1% of
  !> the jump, well below the O(jump) error that any shock-capturing scheme
  !> makes in a cell containing a discontinuity, so the reference is converged
  !> for comparison purposes; use nsub ~ 1000 for 1e-3-level checks. t <= 0
  !> returns averages of the initial data. Zeros if `rs` is not solved.
  pure subroutine riemann_cell_average(rs, x0, t, xa, xb, nsub, rho, u, p, e)
    type(riemann_t), intent(in) :: rs
    real(wp), intent(in) :: x0, t, xa, xb
    integer, intent(in) :: nsub
    real(wp), intent(out) :: rho, u, p, e

    real(wp) :: h, x, s, ri, ui, pi_, gi, mass, mom, pres, eint
    integer :: i, n

    rho = 0.0_wp
    u = 0.0_wp
    p = 0.0_wp
    e = 0.0_wp
    if (.not. rs%solved) return

    n = max(nsub, 1)
    h = (xb - xa) / real(n, wp)
    mass = 0.0_wp
    mom = 0.0_wp
    pres = 0.0_wp
    eint = 0.0_wp
    do i = 1, n
      x = xa + (real(i, wp) - 0.5_wp) * h
      if (t > 0.0_wp) then
        s = (x - x0) / t
      else if (x < x0) then
        s = -huge(1.0_wp)
      else
        s = huge(1.0_wp)
      end if
      call sample_state(rs, s, ri, ui, pi_, gi)
      mass = mass + ri
      mom = mom + ri * ui
      pres = pres + pi_
      eint = eint + pi_ / (gi - 1.0_wp)
    end do
    rho = mass / real(n, wp)
    u = mom / mass
    p = pres / real(n, wp)
    e = eint / mass
  end subroutine riemann_cell_average

  ! ---------------------------------------------------------------------------
  ! Private helpers.
  ! ---------------------------------------------------------------------------

  ! f_K(p) and f_K'(p) for one side (Toro eqs. 4.6-4.7 and 4.37).
  pure subroutine pressure_function(p, rhok, pk, ck, gk, f, df)
    real(wp), intent(in) :: p, rhok, pk, ck, gk
    real(wp), intent(out) :: f, df

    real(wp) :: ak, bk, q

    if (p > pk) then
      ak = 2.0_wp / ((gk + 1.0_wp) * rhok)
      bk = (gk - 1.0_wp) / (gk + 1.0_wp) * pk
      q = sqrt(ak / (p + bk))
      f = (p - pk) * q
      df = q * (1.0_wp - 0.5_wp * (p - pk) / (p + bk))
    else
      f = 2.0_wp * ck / (gk - 1.0_wp) * ((p / pk)**((gk - 1.0_wp) / (2.0_wp * gk)) - 1.0_wp)
      df = (p / pk)**(-(gk + 1.0_wp) / (2.0_wp * gk)) / (rhok * ck)
    end if
  end subroutine pressure_function

  ! Density behind a shock (Rankine-Hugoniot) or a rarefaction (isentrope)
  ! that connects (rhok, pk) to pressure pstar.
  pure function star_density(pstar, rhok, pk, gk) result(rho)
    real(wp), intent(in) :: pstar, rhok, pk, gk
    real(wp) :: rho

    real(wp) :: mu, ratio

    ratio = pstar / pk
    if (pstar > pk) then
      mu = (gk - 1.0_wp) / (gk + 1.0_wp)
      rho = rhok * (ratio + mu) / (mu * ratio + 1.0_wp)
    else
      rho = rhok * ratio**(1.0_wp / gk)
    end if
  end function star_density

  ! Starting value for p* (Toro sec. 9.5.1, adapted to two gammas):
  ! primitive-variable guess if the data are nearly uniform, else a
  ! two-rarefaction guess (exact for equal gammas; a mean exponent otherwise)
  ! when both waves look like rarefactions, else the two-shock guess. Always
  ! positive.
  pure function initial_guess(rs) result(p0)
    type(riemann_t), intent(in) :: rs
    real(wp) :: p0

    real(wp) :: du, ppv, pmin, pmax, al, ar, z, qa, ql, qr

    du = rs%ur - rs%ul
    pmin = min(rs%pl, rs%pr)
    pmax = max(rs%pl, rs%pr)
    ppv = 0.5_wp * (rs%pl + rs%pr) &
          - 0.125_wp * du * (rs%rhol + rs%rhor) * (rs%cl + rs%cr)
    ppv = max(ppv, 0.0_wp)

    if (pmax <= 2.0_wp * pmin .and. ppv >= pmin .and. ppv <= pmax) then
      p0 = ppv
    else if (ppv < pmin) then
      al = 2.0_wp * rs%cl / (rs%gl - 1.0_wp)
      ar = 2.0_wp * rs%cr / (rs%gr - 1.0_wp)
      z = 0.5_wp * ((rs%gl - 1.0_wp) / (2.0_wp * rs%gl) &
                    + (rs%gr - 1.0_wp) / (2.0_wp * rs%gr))
      ! al + ar - du > 0: checked (no vacuum) before this is called.
      p0 = ((al + ar - du) / (al * rs%pl**(-z) + ar * rs%pr**(-z)))**(1.0_wp / z)
    else
      ql = sqrt(2.0_wp / ((rs%gl + 1.0_wp) * rs%rhol) &
                / (ppv + (rs%gl - 1.0_wp) / (rs%gl + 1.0_wp) * rs%pl))
      qr = sqrt(2.0_wp / ((rs%gr + 1.0_wp) * rs%rhor) &
                / (ppv + (rs%gr - 1.0_wp) / (rs%gr + 1.0_wp) * rs%pr))
      qa = ql + qr
      p0 = (ql * rs%pl + qr * rs%pr - du) / qa
    end if
    p0 = max(p0, 1.0e-12_wp * pmin)
  end function initial_guess

  ! State and local gamma at s (Toro sec. 4.5, fig. 4.14).
  elemental subroutine sample_state(rs, s, rho, u, p, g)
    type(riemann_t), intent(in) :: rs
    real(wp), intent(in) :: s
    real(wp), intent(out) :: rho, u, p, g

    real(wp) :: ratio, sk, shead, stail, cstar, base

    rho = 0.0_wp
    u = 0.0_wp
    p = 0.0_wp
    g = 0.0_wp
    if (.not. rs%solved) return

    if (s <= rs%u_star) then
      g = rs%gl
      ratio = rs%p_star / rs%pl
      if (rs%p_star > rs%pl) then
        ! Left shock.
        sk = rs%ul - rs%cl * sqrt((g + 1.0_wp) / (2.0_wp * g) * ratio &
                                  + (g - 1.0_wp) / (2.0_wp * g))
        if (s <= sk) then
          call set_state(rs%rhol, rs%ul, rs%pl, rho, u, p)
        else
          call set_state(rs%rho_star_left, rs%u_star, rs%p_star, rho, u, p)
        end if
      else
        ! Left rarefaction.
        shead = rs%ul - rs%cl
        cstar = rs%cl * ratio**((g - 1.0_wp) / (2.0_wp * g))
        stail = rs%u_star - cstar
        if (s <= shead) then
          call set_state(rs%rhol, rs%ul, rs%pl, rho, u, p)
        else if (s >= stail) then
          call set_state(rs%rho_star_left, rs%u_star, rs%p_star, rho, u, p)
        else
          base = 2.0_wp / (g + 1.0_wp) &
                 + (g - 1.0_wp) / ((g + 1.0_wp) * rs%cl) * (rs%ul - s)
          rho = rs%rhol * base**(2.0_wp / (g - 1.0_wp))
          u = 2.0_wp / (g + 1.0_wp) * (rs%cl + 0.5_wp * (g - 1.0_wp) * rs%ul + s)
          p = rs%pl * base**(2.0_wp * g / (g - 1.0_wp))
        end if
      end if
    else
      g = rs%gr
      ratio = rs%p_star / rs%pr
      if (rs%p_star > rs%pr) then
        ! Right shock.
        sk = rs%ur + rs%cr * sqrt((g + 1.0_wp) / (2.0_wp * g) * ratio &
                                  + (g - 1.0_wp) / (2.0_wp * g))
        if (s >= sk) then
          call set_state(rs%rhor, rs%ur, rs%pr, rho, u, p)
        else
          call set_state(rs%rho_star_right, rs%u_star, rs%p_star, rho, u, p)
        end if
      else
        ! Right rarefaction.
        shead = rs%ur + rs%cr
        cstar = rs%cr * ratio**((g - 1.0_wp) / (2.0_wp * g))
        stail = rs%u_star + cstar
        if (s >= shead) then
          call set_state(rs%rhor, rs%ur, rs%pr, rho, u, p)
        else if (s <= stail) then
          call set_state(rs%rho_star_right, rs%u_star, rs%p_star, rho, u, p)
        else
          base = 2.0_wp / (g + 1.0_wp) &
                 - (g - 1.0_wp) / ((g + 1.0_wp) * rs%cr) * (rs%ur - s)
          rho = rs%rhor * base**(2.0_wp / (g - 1.0_wp))
          u = 2.0_wp / (g + 1.0_wp) * (-rs%cr + 0.5_wp * (g - 1.0_wp) * rs%ur + s)
          p = rs%pr * base**(2.0_wp * g / (g - 1.0_wp))
        end if
      end if
    end if
  end subroutine sample_state

  pure subroutine set_state(rho_in, u_in, p_in, rho, u, p)
    real(wp), intent(in) :: rho_in, u_in, p_in
    real(wp), intent(out) :: rho, u, p

    rho = rho_in
    u = u_in
    p = p_in
  end subroutine set_state

end module exact_riemann
