!> Programmed burn of a high explosive: where and when the detonation front
!> lights each cell, and the Chapman-Jouguet (CJ) state it runs at.
!>
!> A cell of the explosive is lit at t_L = t_0 + d/D: d the distance from the
!> initiator (a point, a line segment or a plane, lit at t_0) and D the
!> detonation velocity. `straight`: d is the straight-line distance. `around`:
!> d is the shortest path through the explosive (Huygens: the front goes
!> round an inert obstacle), found by `burn_around`. Behind the front the
!> products' JWL pressure is released over a burn time tau = w h/D (h the
!> cell's width across the front, w = &material burn_width cells):
!>   F1 = min(1, max(0, (t - t_L)/tau)),
!> and a compressed cell also burns, F2 = min(1, max(0, (1 - V)/(1 - V_CJ)))
!> with V = rho0/rho, as in the programmed-burn models of the production
!> codes; the pressure is F p_JWL(rho, e) with F = max(F1, F2). The energy of
!> the explosive is its detonation energy from the start (the products'
!> e_0), so total energy is conserved whatever F does.
!>
!> The CJ state of a JWL from the unreacted state (rho0, e_0): the products'
!> Hugoniot through it, with the JWL written per initial volume (E = rho0 e,
!> V = rho0/rho, f(V) the cold terms),
!>   p_H(V) = (f(V) + omega E_0/V)/(1 - omega (1 - V)/(2 V)),
!> meets the Rayleigh line p = rho0 D^2 (1 - V); the CJ point is where D is
!> least (the tangent). For TNT (A = 371.2 GPa, B = 3.231 GPa, R1 = 4.15,
!> R2 = 0.95, omega = 0.30, rho0 = 1.63 g/cm^3, E_0 = 7 GPa) it gives
!> D = 6.93 km/s, p_CJ = 21.0 GPa, V_CJ = 0.732 (Dobratz's 6.93 and 21).
module material_burn
  use base_kinds, only: wp
  use eos_jwl, only: jwl_t, jwl_cold_pressure
  implicit none
  private
  public :: burn_cj, burn_initiator, burn_around, burn_width_across, &
            INIT_POINT, INIT_LINE, INIT_PLANE

  integer, parameter :: INIT_POINT = 1, INIT_LINE = 2, INIT_PLANE = 3

contains

  !> |v|: the square root of a sum of squares, exact under scaling by powers
  !> of two (gfortran's NORM2 is not: the dimensional-rescaling test).
  pure real(wp) function length(v)
    real(wp), intent(in) :: v(:)
    length = sqrt(dot_product(v, v))
  end function length

  !> The CJ state of `eos` detonating from density rho0 [density] and
  !> specific energy e0 [pressure/density]: detonation velocity d_cj
  !> [velocity], pressure p_cj [pressure] and relative volume v_cj = rho0/rho.
  !> d_cj = 0 when no V in (omega/(2 + omega), 1) gives a positive Hugoniot
!> pressure.
  pure subroutine burn_cj(eos, rho0, e0, d_cj, p_cj, v_cj)
    type(jwl_t), intent(in) :: eos
    real(wp), intent(in) :: rho0, e0
    real(wp), intent(out) :: d_cj, p_cj, v_cj
    integer, parameter :: n = 2000
    real(wp), parameter :: vhi = 0.9999_wp, phi = 0.6180339887498949_wp
    real(wp) :: v, d2, best, a, b, c1, c2, f1, f2, vlo
    integer :: i, ib
    ! (the Hugoniot's asymptote of greatest compression: V = omega/(2 + omega))
    vlo = eos%omega/(2.0_wp + eos%omega) + 1.0e-3_wp
    ! a scan for the least D^2, then a golden-section search in its bracket
    best = huge(1.0_wp)
    ib = 0
    do i = 0, n
      v = vlo + (vhi - vlo)*real(i, wp)/real(n, wp)
      d2 = rayleigh_d2(v)
      if (d2 < best) then
        best = d2
        ib = i
      end if
    end do
    d_cj = 0.0_wp; p_cj = 0.0_wp; v_cj = 1.0_wp
    if (.not. best < huge(1.0_wp)) return
    a = vlo + (vhi - vlo)*real(max(ib - 1, 0), wp)/real(n, wp)
    b = vlo + (vhi - vlo)*real(min(ib + 1, n), wp)/real(n, wp)
    c1 = b - phi*(b - a); c2 = a + phi*(b - a)
    f1 = rayleigh_d2(c1); f2 = rayleigh_d2(c2)
    do i = 1, 80
      if (f1 < f2) then
        b = c2; c2 = c1; f2 = f1
        c1 = b - phi*(b - a); f1 = rayleigh_d2(c1)
      else
        a = c1; c1 = c2; f1 = f2
        c2 = a + phi*(b - a); f2 = rayleigh_d2(c2)
      end if
    end do
    v_cj = 0.5_wp*(a + b)
    d_cj = sqrt(rayleigh_d2(v_cj))
    p_cj = rho0*d_cj**2*(1.0_wp - v_cj)

  contains

    !> D^2 of the Rayleigh line through the Hugoniot point at V (huge where
    !> the Hugoniot pressure is not positive).
    pure real(wp) function rayleigh_d2(vv) result(r)
      real(wp), intent(in) :: vv
      real(wp) :: ph
      r = huge(1.0_wp)
      ph = (jwl_cold_pressure(eos, rho0/vv) + eos%omega*rho0*e0/vv)/(1.0_wp - eos%omega*(1.0_wp - vv)/(2.0_wp*vv))
      if (ph > 0.0_wp) r = ph/(rho0*(1.0_wp - vv))
    end function rayleigh_d2
  end subroutine burn_cj

  !> The straight-line distance d [length] from the initiator of `kind`
  !> (INIT_POINT at p; INIT_LINE the segment p..p2; INIT_PLANE through p
  !> with normal nrm) to x, and the front's direction there (unit vector
  !> from the nearest initiator point to x; nrm's side of a plane).
  pure subroutine burn_initiator(kind, p, p2, nrm, x, d, dir)
    integer, intent(in) :: kind
    real(wp), intent(in) :: p(3), p2(3), nrm(3), x(3)
    real(wp), intent(out) :: d, dir(3)
    real(wp) :: q(3), s, l2, n(3)
    select case (kind)
    case (INIT_LINE)
      l2 = sum((p2 - p)**2)
      s = 0.0_wp
      if (l2 > 0.0_wp) s = max(0.0_wp, min(1.0_wp, dot_product(x - p, p2 - p)/l2))
      q = p + s*(p2 - p)
    case (INIT_PLANE)
      n = nrm/length(nrm)
      q = x - dot_product(x - p, n)*n
    case default
      q = p
    end select
    d = length(x - q)
    if (d > 0.0_wp) then
      dir = (x - q)/d
    else if (kind == INIT_PLANE) then
      dir = nrm/length(nrm)
    else
      dir = [1.0_wp, 0.0_wp, 0.0_wp]
    end if
  end subroutine burn_initiator

  !> The width of a hex cell (nodes xn(3, 8), corner order of `mesh_grid`:
  !> node a at offsets ((a-1) mod 2, (a-1)/2 mod 2, (a-1)/4)) across a front
  !> moving along the unit vector dir: sum over its three logical directions
  !> of |dir . mean edge| (the box's extent along dir).
  pure real(wp) function burn_width_across(xn, dir) result(w)
    real(wp), intent(in) :: xn(3, 8), dir(3)
    real(wp) :: e(3, 3)
    e(:, 1) = 0.25_wp*(xn(:, 2) - xn(:, 1) + xn(:, 4) - xn(:, 3) + xn(:, 6) - xn(:, 5) + xn(:, 8) - xn(:, 7))
    e(:, 2) = 0.25_wp*(xn(:, 3) - xn(:, 1) + xn(:, 4) - xn(:, 2) + xn(:, 7) - xn(:, 5) + xn(:, 8) - xn(:, 6))
    e(:, 3) = 0.25_wp*(xn(:, 5) - xn(:, 1) + xn(:, 6) - xn(:, 2) + xn(:, 7) - xn(:, 3) + xn(:, 8) - xn(:, 4))
    w = abs(dot_product(dir, e(:, 1))) + abs(dot_product(dir, e(:, 2))) + abs(dot_product(dir, e(:, 3)))
  end function burn_width_across

  !> Shortest paths through the explosive on a rectilinear grid of
  !> ni x nj x nk cells (node coordinates ax(0:ni), ay(0:nj), az(0:nk)), the
  !> explosive's cells `mask`, from point sources ps(3, ns) lit at distances
  !> d0(ns) (a source's lighting time times D): on return d(c) is the least
  !> d0 + path length to the centre of cell c (huge where no path reaches)
  !> and dir(:, c) the direction the front arrives from.
  !>
  !> Dijkstra over the cells' 26 neighbours, each cell keeping the point
  !> its front comes straight from (its "source": an initiator, or the last
  !> corner the path turned round). A neighbour n of a settled cell c is
  !> offered d(source of c) + |x_n - source| when the segment from that
  !> source to x_n stays in explosive cells (sampled every quarter of the
  !> smallest cell width), else d(c) + |x_n - x_c| with c as its source. In
  !> a convex explosive every cell sees its initiator and d is the straight
  !> distance exactly; round an obstacle the path bends at cell centres next
  !> to its corners (within about a cell of the true geodesic).
  subroutine burn_around(ni, nj, nk, ax, ay, az, mask, ps, d0, d, dir, ok)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: ax(0:ni), ay(0:nj), az(0:nk)
    logical, intent(in) :: mask(ni, nj, nk)
    real(wp), intent(in) :: ps(:, :), d0(:)
    real(wp), intent(out) :: d(ni*nj*nk), dir(3, ni*nj*nk)
    logical, intent(out) :: ok                 !< false: out of memory
    real(wp), allocatable :: src(:, :), dsrc(:)
    integer, allocatable :: heap(:), pos(:)
    logical, allocatable :: done(:)
    integer :: nc, c, i, j, k, s, di, dj, dk, n, nh, ii, jj, kk, stat
    real(wp) :: xc(3), xn(3), cand, hmin, dd

    nc = ni*nj*nk
    allocate(src(3, nc), dsrc(nc), heap(nc), pos(nc), done(nc), stat=stat)
    ok = stat == 0
    if (.not. ok) return
    d = huge(1.0_wp)
    dir = 0.0_wp
    dsrc = huge(1.0_wp)
    done = .false.
    pos = 0
    nh = 0
    hmin = min(minval(ax(1:ni) - ax(0:ni - 1)), minval(ay(1:nj) - ay(0:nj - 1)), minval(az(1:nk) - az(0:nk - 1)))
    ! seeds: every explosive cell that sees a source directly
    do k = 1, nk
      do j = 1, nj
        do i = 1, ni
          if (.not. mask(i, j, k)) cycle
          c = i + ni*((j - 1) + nj*(k - 1))
          xc = centre(i, j, k)
          do s = 1, size(d0)
            if (.not. visible(ps(:, s), xc)) cycle
            cand = d0(s) + length(xc - ps(:, s))
            if (cand < d(c)) then
              d(c) = cand
              src(:, c) = ps(:, s)
              dsrc(c) = d0(s)
            end if
          end do
          if (d(c) < huge(1.0_wp)) call heap_push(c, d(c))
        end do
      end do
    end do
    do while (nh > 0)
      c = heap_pop()
      done(c) = .true.
      k = (c - 1)/(ni*nj) + 1
      j = mod((c - 1)/ni, nj) + 1
      i = mod(c - 1, ni) + 1
      xc = centre(i, j, k)
      do dk = -1, 1
        do dj = -1, 1
          do di = -1, 1
            ii = i + di; jj = j + dj; kk = k + dk
            if (ii < 1 .or. ii > ni .or. jj < 1 .or. jj > nj .or. kk < 1 .or. kk > nk) cycle
            if (.not. mask(ii, jj, kk)) cycle
            n = ii + ni*((jj - 1) + nj*(kk - 1))
            if (done(n)) cycle
            xn = centre(ii, jj, kk)
            if (visible(src(:, c), xn)) then
              cand = dsrc(c) + length(xn - src(:, c))
              if (cand < d(n)) then
                d(n) = cand
                src(:, n) = src(:, c)
                dsrc(n) = dsrc(c)
                call heap_push(n, cand)
              end if
            else
              cand = d(c) + length(xn - xc)
              if (cand < d(n)) then
                d(n) = cand
                src(:, n) = xc
                dsrc(n) = d(c)
                call heap_push(n, cand)
              end if
            end if
          end do
        end do
      end do
    end do
    do c = 1, nc
      if (.not. d(c) < huge(1.0_wp)) cycle
      k = (c - 1)/(ni*nj) + 1
      j = mod((c - 1)/ni, nj) + 1
      i = mod(c - 1, ni) + 1
      xc = centre(i, j, k)
      dd = length(xc - src(:, c))
      dir(:, c) = [1.0_wp, 0.0_wp, 0.0_wp]
      if (dd > 0.0_wp) dir(:, c) = (xc - src(:, c))/dd
    end do

  contains

    pure function centre(i1, j1, k1) result(x)
      integer, intent(in) :: i1, j1, k1
      real(wp) :: x(3)
      x = 0.5_wp*[ax(i1 - 1) + ax(i1), ay(j1 - 1) + ay(j1), az(k1 - 1) + az(k1)]
    end function centre

    !> The cell (1-based indices) holding x, clamped to the grid.
    pure function cell_of(x) result(ijk)
      real(wp), intent(in) :: x(3)
      integer :: ijk(3)
      ijk(1) = locate(ax, ni, x(1))
      ijk(2) = locate(ay, nj, x(2))
      ijk(3) = locate(az, nk, x(3))
    end function cell_of

    pure integer function locate(a, m, v) result(l)
      integer, intent(in) :: m
      real(wp), intent(in) :: a(0:m), v
      integer :: lo, hi, mid
      lo = 0; hi = m
      do while (hi - lo > 1)
        mid = (lo + hi)/2
        if (a(mid) <= v) then
          lo = mid
        else
          hi = mid
        end if
      end do
      l = lo + 1
    end function locate

    !> The segment from a to b lies in explosive cells (its points every
    !> quarter of the smallest width, the end points excluded: a source
    !> on the explosive's surface sees in).
    pure logical function visible(a, b)
      real(wp), intent(in) :: a(3), b(3)
      integer :: m, q, ijk(3)
      m = max(1, ceiling(4.0_wp*length(b - a)/hmin))
      visible = .true.
      do q = 1, m - 1
        ijk = cell_of(a + (b - a)*(real(q, wp)/real(m, wp)))
        if (.not. mask(ijk(1), ijk(2), ijk(3))) then
          visible = .false.
          return
        end if
      end do
    end function visible

    !> Puts `item` in the heap by its key d(item), or moves it up if there
    !> (its key only falls).
    subroutine heap_push(item, key)
      integer, intent(in) :: item
      real(wp), intent(in) :: key
      integer :: q, parent
      q = pos(item)
      if (q == 0) then
        nh = nh + 1
        q = nh
      end if
      do while (q > 1)
        parent = q/2
        if (d(heap(parent)) <= key) exit
        heap(q) = heap(parent)
        pos(heap(q)) = q
        q = parent
      end do
      heap(q) = item
      pos(item) = q
    end subroutine heap_push

    !> The item of least key, taken out of the heap.
    integer function heap_pop() result(item)
      integer :: q, child, last
      item = heap(1)
      pos(item) = 0
      last = heap(nh)
      nh = nh - 1
      if (nh == 0) return
      q = 1
      do
        child = 2*q
        if (child > nh) exit
        if (child < nh) then
          if (d(heap(child + 1)) < d(heap(child))) child = child + 1
        end if
        if (d(last) <= d(heap(child))) exit
        heap(q) = heap(child)
        pos(heap(q)) = q
        q = child
      end do
      heap(q) = last
      pos(last) = q
    end function heap_pop
  end subroutine burn_around
end module material_burn
