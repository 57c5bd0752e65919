!> Unit tests of geometry_polyhedron: clipping the unit cube against closed forms
!> (and an exact piecewise quadrature for a general plane), degenerate planes,
!> the two sides of a plane adding up, the closed-form clip of a tetrahedron
!> by one plane against the general one, the 24-tet split of Fig. 7 against
!> hex_volume, and tet-hex intersections: inside, outside, partial, the
!> partition identities behind Eq. (54)-(57), and symmetry. Ends with timings
!> (printed, not asserted).
program test_remap_geometry
  use base_kinds, only: wp, i8
  use base_random, only: rng_t, rng_seed, rng_uniform
  use mesh_geometry, only: hex_corner, hex_volume, hex_tets, cross
  use geometry_polyhedron, only: poly_t, poly_max_verts, poly_from_tet, poly_from_hex, poly_clip, &
                              poly_moments, poly_first_moments, tet_intersect_tet, &
                              tet_intersect_hex, poly_set_tet, tet_clip_moments
  use test_assert, only: check, check_summary
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  implicit none
  type(rng_t) :: rng
  real(wp) :: cube(3, 8)

  cube = real(hex_corner, wp)
  call rng_seed(rng, 2024)

  call test_axis_planes()
  call test_diagonal_planes()
  call test_general_planes()
  call test_degenerate()
  call test_two_sides()
  call test_capacity()
  call test_hex_tets()
  call test_tet_hex()
  call test_partitions()
  call test_tet_clip()
  call timings()

  call check_summary('test_remap_geometry')

contains

  ! ---------------------------------------------------------------- helpers

  real(wp) function pos(x)
    real(wp), intent(in) :: x
    pos = max(x, 0.0_wp)
  end function pos

  real(wp) function uni(a, b)
    real(wp), intent(in) :: a, b
    uni = a + (b - a)*rng_uniform(rng)
  end function uni

  real(wp) function det6(t)
    real(wp), intent(in) :: t(3, 4)
    det6 = dot_product(t(:, 2) - t(:, 1), cross(t(:, 3) - t(:, 1), t(:, 4) - t(:, 1)))
  end function det6

  !> The unit cube clipped by n.x <= d: volume and centroid.
  subroutine cube_clip(n, d, vol, xc, p)
    real(wp), intent(in) :: n(3), d
    real(wp), intent(out) :: vol, xc(3)
    type(poly_t), intent(out) :: p
    logical :: ok
    p = poly_from_hex(cube)
    call poly_clip(p, n, d, ok)
    call check(ok, 'cube clip within capacity')
    call poly_moments(p, vol, xc)
    call check_topology(p, 'cube clip')
  end subroutine cube_clip

  !> Walks the faces of p with the documented rule, independently of the
  !> module, and checks: neighbour lists symmetric and in range, every
  !> directed edge on exactly one face, faces of >= 3 vertices, Euler's
  !> V - E + F = 2, a closed surface (face area vectors sum to zero) and the
  !> module's volume equal to the divergence-theorem volume about the origin.
  subroutine check_topology(p, what)
    type(poly_t), intent(in) :: p
    character(len=*), intent(in) :: what
    integer :: used(3, poly_max_verts), nf, v, kk, jj, prev, cur, nxt, len, it
    real(wp) :: area(3), vol0, vol, mom(3), scale
    logical :: good

    if (p%nv == 0) return
    good = p%nv >= 4 .and. p%nv <= poly_max_verts
    call check(good, what//': vertex count in range')
    if (.not. good) return
    good = .true.
    do v = 1, p%nv
      do kk = 1, 3
        cur = p%nbr(kk, v)
        if (cur < 1 .or. cur > p%nv .or. cur == v) then
          good = .false.
        else if (count(p%nbr(:, cur) == v) /= 1) then
          good = .false.
        end if
      end do
    end do
    call check(good, what//': neighbour lists symmetric')
    if (.not. good) return
    used = 0
    nf = 0
    area = 0.0_wp
    vol0 = 0.0_wp
    do v = 1, p%nv
      do kk = 1, 3
        if (used(kk, v) > 0) cycle
        nf = nf + 1
        used(kk, v) = used(kk, v) + 1
        prev = v
        cur = p%nbr(kk, v)
        len = 1
        do it = 1, 3*p%nv
          do jj = 1, 3
            if (p%nbr(jj, cur) == prev) exit
          end do
          jj = mod(jj, 3) + 1
          used(jj, cur) = used(jj, cur) + 1
          nxt = p%nbr(jj, cur)
          len = len + 1
          if (nxt == v) exit
          area = area + cross(p%x(:, cur) - p%x(:, v), p%x(:, nxt) - p%x(:, v))
          vol0 = vol0 + dot_product(p%x(:, v), cross(p%x(:, cur), p%x(:, nxt)))
          prev = cur
          cur = nxt
        end do
        call check(len >= 3, what//': faces have at least 3 vertices')
      end do
    end do
    call check(all(used(:, 1:p%nv) == 1), what//': every directed edge on one face')
    call check(p%nv - 3*p%nv/2 + nf == 2, what//': Euler V - E + F = 2')
    scale = maxval(abs(p%x(:, 1:p%nv)))
    call check(maxval(abs(area)) <= 1e-13_wp*max(scale, 1.0_wp)**2, what//': closed surface')
    call poly_first_moments(p, vol, mom)
    call check(abs(vol - vol0/6.0_wp) <= 1e-13_wp*max(scale, 1.0_wp)**3, &
               what//': volume equals the divergence-theorem volume')
    call check(vol >= -1e-15_wp*max(scale, 1.0_wp)**3, what//': volume not negative')
  end subroutine check_topology

  !> A random hexahedron: the unit cube shifted by `shift` with every node
  !> moved by up to `amp` in each direction (faces non-planar).
  subroutine random_hex(amp, shift, xn)
    real(wp), intent(in) :: amp, shift(3)
    real(wp), intent(out) :: xn(3, 8)
    integer :: a, c
    do a = 1, 8
      do c = 1, 3
        xn(c, a) = cube(c, a) + shift(c) + uni(-amp, amp)
      end do
    end do
  end subroutine random_hex

  !> A random positively oriented tetrahedron with vertices in [lo, hi]^3.
  subroutine random_tet(lo, hi, t)
    real(wp), intent(in) :: lo, hi
    real(wp), intent(out) :: t(3, 4)
    real(wp) :: tmp(3)
    integer :: a, c
    do
      do a = 1, 4
        do c = 1, 3
          t(c, a) = uni(lo, hi)
        end do
      end do
      if (abs(det6(t)) > 1e-3_wp*(hi - lo)**3) exit
    end do
    if (det6(t) < 0.0_wp) then
      tmp = t(:, 3)
      t(:, 3) = t(:, 4)
      t(:, 4) = tmp
    end if
  end subroutine random_tet

  !> Exact volume and first moments of {x in [0,1]^3 : n.x <= d} for n with
  !> no zero component, by integrating the closed-form section area
  !>   A(t) = sum_{i,j in {0,1}} (-1)^(i+j) (t - a i - b j)_+^2 / (2 a b)
  !> (area of {(y,z) in [0,1]^2 : a y + b z <= t}) along each axis in turn,
  !> 3-point Gauss on the pieces between A's kinks: x A is piecewise cubic,
  !> so the quadrature is exact.
  subroutine cube_halfspace_quadrature(n, d, vol, mom)
    real(wp), intent(in) :: n(3), d
    real(wp), intent(out) :: vol, mom(3)
    real(wp), parameter :: gx(3) = [-sqrt(0.6_wp), 0.0_wp, sqrt(0.6_wp)]
    real(wp), parameter :: gw(3) = [5.0_wp/9.0_wp, 8.0_wp/9.0_wp, 5.0_wp/9.0_wp]
    real(wp) :: brk(6), a, b, x, w, area, tmp
    integer :: ax, nb, ii, jj, q, m

    do ax = 1, 3
      a = n(mod(ax, 3) + 1)
      b = n(mod(ax + 1, 3) + 1)
      nb = 2
      brk(1) = 0.0_wp
      brk(2) = 1.0_wp
      do ii = 0, 1
        do jj = 0, 1
          x = (d - a*ii - b*jj)/n(ax)
          if (x > 0.0_wp .and. x < 1.0_wp) then
            nb = nb + 1
            brk(nb) = x
          end if
        end do
      end do
      ! sort the break points
      do ii = 2, nb
        tmp = brk(ii)
        jj = ii - 1
        do while (jj >= 1)
          if (brk(jj) <= tmp) exit
          brk(jj + 1) = brk(jj)
          jj = jj - 1
        end do
        brk(jj + 1) = tmp
      end do
      mom(ax) = 0.0_wp
      if (ax == 1) vol = 0.0_wp
      do m = 1, nb - 1
        do q = 1, 3
          x = 0.5_wp*(brk(m) + brk(m + 1)) + 0.5_wp*(brk(m + 1) - brk(m))*gx(q)
          w = 0.5_wp*(brk(m + 1) - brk(m))*gw(q)
          area = 0.0_wp
          do ii = 0, 1
            do jj = 0, 1
              area = area + (-1)**(ii + jj)*pos(d - n(ax)*x - a*ii - b*jj)**2
            end do
          end do
          area = area/(2.0_wp*a*b)
          mom(ax) = mom(ax) + w*x*area
          if (ax == 1) vol = vol + w*area
        end do
      end do
    end do
  end subroutine cube_halfspace_quadrature

  ! ------------------------------------------------------------------ tests

  subroutine test_axis_planes()
    real(wp), parameter :: offs(4) = [0.25_wp, 0.5_wp, 0.9_wp, 1e-3_wp]
    real(wp) :: n(3), vol, xc(3), ex(3)
    type(poly_t) :: p
    integer :: ax, io, sgn
    do ax = 1, 3
      do io = 1, size(offs)
        do sgn = -1, 1, 2
          n = 0.0_wp
          n(ax) = real(sgn, wp)
          ! x_ax <= o (sgn = 1) or x_ax >= o (sgn = -1)
          call cube_clip(n, real(sgn, wp)*offs(io), vol, xc, p)
          ex = 0.5_wp
          if (sgn == 1) then
            ex(ax) = 0.5_wp*offs(io)
            call check(abs(vol - offs(io)) < 1e-13_wp, 'axis plane: volume')
          else
            ex(ax) = 0.5_wp*(1.0_wp + offs(io))
            call check(abs(vol - (1.0_wp - offs(io))) < 1e-13_wp, 'axis plane: volume')
          end if
          call check(maxval(abs(xc - ex)) < 1e-13_wp, 'axis plane: centroid')
        end do
      end do
    end do
  end subroutine test_axis_planes

  subroutine test_diagonal_planes()
    ! x + y + z <= d: inclusion-exclusion over the corners the simplex
    ! {x,y,z >= 0, x+y+z <= d} overshoots gives the piecewise cubic
    !   V = sum_k (-1)^k C(3,k) (d-k)_+^3 / 6,
    !   M_x = sum_k (-1)^k [C(3,k) (d-k)_+^4 / 24 + C(2,k-1) (d-k)_+^3 / 6]
    real(wp), parameter :: ds(7) = [0.3_wp, 0.5_wp, 1.0_wp, 1.2_wp, 1.5_wp, 2.5_wp, 2.7_wp]
    integer, parameter :: c3(0:3) = [1, 3, 3, 1], c2(0:3) = [0, 1, 2, 1]
    real(wp) :: vol, xc(3), ve, mx, d
    type(poly_t) :: p
    integer :: id, kk
    do id = 1, size(ds)
      d = ds(id)
      ve = 0.0_wp
      mx = 0.0_wp
      do kk = 0, 3
        ve = ve + (-1)**kk*c3(kk)*pos(d - kk)**3/6.0_wp
        mx = mx + (-1)**kk*(c3(kk)*pos(d - kk)**4/24.0_wp + c2(kk)*pos(d - kk)**3/6.0_wp)
      end do
      call cube_clip([1.0_wp, 1.0_wp, 1.0_wp], d, vol, xc, p)
      call check(abs(vol - ve) < 1e-13_wp, 'diagonal plane: volume')
      call check(maxval(abs(xc - mx/ve)) < 1e-13_wp, 'diagonal plane: centroid')
      ! the other side, x + y + z >= d
      call cube_clip([-1.0_wp, -1.0_wp, -1.0_wp], -d, vol, xc, p)
      call check(abs(vol - (1.0_wp - ve)) < 1e-13_wp, 'diagonal plane: volume of the other side')
      call check(maxval(abs(xc - (0.5_wp - mx)/(1.0_wp - ve))) < 1e-13_wp, &
                 'diagonal plane: centroid of the other side')
    end do
  end subroutine test_diagonal_planes

  subroutine test_general_planes()
    real(wp) :: ns(3, 3), dd(3), vol, xc(3), vq, mq(3), v3, n(3)
    type(poly_t) :: p
    integer :: ip, iv, vv(3)
    ns = reshape([0.3_wp, -0.7_wp, 0.5_wp,  0.9_wp, 0.4_wp, -0.25_wp,  -0.2_wp, -0.35_wp, -0.6_wp], [3, 3])
    dd = [0.1_wp, 0.55_wp, -0.5_wp]
    do ip = 1, 3
      n = ns(:, ip)
      call cube_clip(n, dd(ip), vol, xc, p)
      call cube_halfspace_quadrature(n, dd(ip), vq, mq)
      ! and the 3D closed form sum_v (-1)^|v| (d - n.v)_+^3 / (6 n1 n2 n3)
      v3 = 0.0_wp
      do iv = 0, 7
        vv = [mod(iv, 2), mod(iv/2, 2), iv/4]
        v3 = v3 + (-1)**sum(vv)*pos(dd(ip) - dot_product(n, real(vv, wp)))**3
      end do
      v3 = v3/(6.0_wp*n(1)*n(2)*n(3))
      call check(abs(vq - v3) < 1e-14_wp, 'general plane: quadrature agrees with the closed form')
      call check(abs(vol - vq) < 1e-13_wp, 'general plane: volume')
      call check(maxval(abs(xc - mq/vq)) < 1e-13_wp, 'general plane: centroid')
    end do
  end subroutine test_general_planes

  subroutine test_degenerate()
    real(wp) :: vol, xc(3), v2, c2(3)
    type(poly_t) :: p, q
    ! plane through a vertex only
    call cube_clip([1.0_wp, 1.0_wp, 1.0_wp], 0.0_wp, vol, xc, p)
    call check(p%nv == 0 .and. abs(vol) < 1e-300_wp, 'plane touching a vertex from outside: empty')
    call cube_clip([1.0_wp, 1.0_wp, 1.0_wp], 3.0_wp, vol, xc, p)
    call check(p%nv == 8 .and. abs(vol - 1.0_wp) < 1e-15_wp, 'plane touching a vertex from inside: all kept')
    ! plane through vertices 1, 6 and 7: x + y <= z, a pyramid of volume
    ! int z^2/2 dz = 1/6 and centroid (1/4, 1/4, 3/4)
    call cube_clip([1.0_wp, 1.0_wp, -1.0_wp], 0.0_wp, vol, xc, p)
    call check(abs(vol - 1.0_wp/6.0_wp) < 1e-14_wp, 'plane through vertex 1: volume')
    call check(maxval(abs(xc - [0.25_wp, 0.25_wp, 0.75_wp])) < 1e-14_wp, 'plane through vertex 1: centroid')
    ! plane through an edge only
    call cube_clip([1.0_wp, 1.0_wp, 0.0_wp], 0.0_wp, vol, xc, p)
    call check(p%nv == 0, 'plane touching an edge from outside: empty')
    ! plane through two opposite edges (diagonal section)
    call cube_clip([1.0_wp, -1.0_wp, 0.0_wp], 0.0_wp, vol, xc, p)
    call check(abs(vol - 0.5_wp) < 1e-15_wp, 'plane through two edges: volume')
    call check(maxval(abs(xc - [1.0_wp/3.0_wp, 2.0_wp/3.0_wp, 0.5_wp])) < 1e-15_wp, &
               'plane through two edges: centroid')
    call cube_clip([1.0_wp, 1.0_wp, 0.0_wp], 1.0_wp, vol, xc, p)
    call check(abs(vol - 0.5_wp) < 1e-15_wp, 'plane x+y=1 through two edges: volume')
    call check(maxval(abs(xc - [1.0_wp/3.0_wp, 1.0_wp/3.0_wp, 0.5_wp])) < 1e-15_wp, &
               'plane x+y=1 through two edges: centroid')
    ! plane containing a face, from either side
    call cube_clip([1.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, vol, xc, p)
    call check(p%nv == 0, 'plane containing a face, cube outside: empty')
    call cube_clip([-1.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, vol, xc, p)
    call check(p%nv == 8 .and. abs(vol - 1.0_wp) < 1e-15_wp, 'plane containing a face, cube inside: all kept')
    call cube_clip([0.0_wp, 0.0_wp, 2.0_wp], 2.0_wp, vol, xc, p)
    call check(p%nv == 8 .and. abs(vol - 1.0_wp) < 1e-15_wp, 'plane containing the top face: all kept')
    ! plane missing the cube, both sides
    call cube_clip([1.0_wp, 0.0_wp, 0.0_wp], -1.0_wp, vol, xc, p)
    call check(p%nv == 0 .and. abs(vol) < 1e-300_wp, 'plane missing the cube: all removed')
    call cube_clip([1.0_wp, 0.0_wp, 0.0_wp], 2.0_wp, vol, xc, p)
    call check(p%nv == 8 .and. abs(vol - 1.0_wp) < 1e-15_wp, 'plane missing the cube: all kept')
    call check(maxval(abs(xc - 0.5_wp)) < 1e-15_wp, 'plane missing the cube: centroid')
    ! a zero normal: 0 <= d is everything or nothing
    call cube_clip([0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp, vol, xc, p)
    call check(p%nv == 8, 'zero normal, d > 0: all kept')
    call cube_clip([0.0_wp, 0.0_wp, 0.0_wp], -1.0_wp, vol, xc, p)
    call check(p%nv == 0, 'zero normal, d < 0: all removed')
    ! slivers: within the tolerance (empty) and just above it (kept, exact)
    call cube_clip([1.0_wp, 0.0_wp, 0.0_wp], 1e-300_wp, vol, xc, p)
    call check(p%nv == 0 .and. abs(vol) < 1e-300_wp, 'sliver below tolerance: empty')
    call cube_clip([1.0_wp, 0.0_wp, 0.0_wp], 1e-12_wp, vol, xc, p)
    call check(abs(vol - 1e-12_wp) < 1e-15_wp*1e-12_wp*100.0_wp, 'sliver of width 1e-12: volume')
    call check(abs(xc(1) - 5e-13_wp) < 1e-25_wp .and. maxval(abs(xc(2:3) - 0.5_wp)) < 1e-14_wp, &
               'sliver of width 1e-12: centroid')
    call poly_clip(p, [0.0_wp, 1.0_wp, 1.0_wp], 1.0_wp)
    call poly_moments(p, vol, xc)
    call check(abs(vol - 0.5e-12_wp) < 1e-26_wp .and. .not. any(ieee_is_nan(xc)), 'sliver clipped again: half, no NaN')
    call check_topology(p, 'sliver clipped again')
    ! clipping again by the same plane changes nothing; by its reverse
    ! leaves only the face, which is empty
    call cube_clip([1.0_wp, 0.0_wp, 0.0_wp], 0.5_wp, vol, xc, p)
    q = p
    call poly_clip(q, [1.0_wp, 0.0_wp, 0.0_wp], 0.5_wp)
    call poly_moments(q, v2, c2)
    call check(q%nv == p%nv .and. abs(v2 - 0.5_wp) < 1e-15_wp, 'same plane twice: unchanged')
    q = p
    call poly_clip(q, [-1.0_wp, 0.0_wp, 0.0_wp], -0.5_wp)
    call check(q%nv == 0, 'reverse of the cap plane: empty')
    ! x <= z/2: a plane through an edge of the cap and an edge of the cube
    q = p
    call poly_clip(q, [1.0_wp, 0.0_wp, -0.5_wp], 0.0_wp)
    call poly_moments(q, v2, c2)
    call check(abs(v2 - 0.25_wp) < 1e-15_wp, 'plane through cap edge and cube edge: volume')
    call check(maxval(abs(c2 - [1.0_wp/6.0_wp, 0.5_wp, 2.0_wp/3.0_wp])) < 1e-15_wp, &
               'plane through cap edge and cube edge: centroid')
    call check_topology(q, 'plane through cap edge and cube edge')
    ! empty polyhedron: moments zero, clipping a no-op
    q%nv = 0
    call poly_clip(q, [1.0_wp, 2.0_wp, 3.0_wp], 0.1_wp)
    call poly_moments(q, v2, c2)
    call check(q%nv == 0 .and. abs(v2) < 1e-300_wp .and. maxval(abs(c2)) < 1e-300_wp, 'empty polyhedron')
  end subroutine test_degenerate

  !> A random convex polyhedron: the unit cube (shifted) cut by nplanes
  !> random planes passing between 0.15 and 0.5 from its centre.
  subroutine random_convex(nplanes, shift, p)
    integer, intent(in) :: nplanes
    real(wp), intent(in) :: shift(3)
    type(poly_t), intent(out) :: p
    real(wp) :: n(3), xs(3, 8)
    integer :: ip, a
    logical :: ok
    do a = 1, 8
      xs(:, a) = cube(:, a) + shift
    end do
    p = poly_from_hex(xs)
    do ip = 1, nplanes
      n = [uni(-1.0_wp, 1.0_wp), uni(-1.0_wp, 1.0_wp), uni(-1.0_wp, 1.0_wp)]
      n = n/norm2(n)
      call poly_clip(p, n, dot_product(n, shift + 0.5_wp) + uni(0.15_wp, 0.5_wp), ok)
      call check(ok, 'random convex polyhedron within capacity')
    end do
  end subroutine random_convex

  subroutine test_two_sides()
    type(poly_t) :: p, a, b
    real(wp) :: n(3), d, v, va, vb, m(3), ma(3), mb(3), x0(3), shift(3), tol
    integer :: trial
    do trial = 1, 200
      ! far from the origin now and then: the tolerance is relative
      shift = 0.0_wp
      if (mod(trial, 4) == 0) shift = [1e3_wp, -2e3_wp, 5e2_wp]
      call random_convex(1 + mod(trial, 6), shift, p)
      call check_topology(p, 'random convex polyhedron')
      call poly_first_moments(p, v, m)
      n = [uni(-1.0_wp, 1.0_wp), uni(-1.0_wp, 1.0_wp), uni(-1.0_wp, 1.0_wp)]
      x0 = shift + [uni(0.2_wp, 0.8_wp), uni(0.2_wp, 0.8_wp), uni(0.2_wp, 0.8_wp)]
      d = dot_product(n, x0)
      a = p
      b = p
      call poly_clip(a, n, d)
      call poly_clip(b, -n, -d)
      call check_topology(a, 'random polyhedron, one side')
      call check_topology(b, 'random polyhedron, other side')
      call poly_first_moments(a, va, ma)
      call poly_first_moments(b, vb, mb)
      ! positions far from the origin carry round-off of eps |x|, not eps L:
      ! the relative error grows like |x|/L (measured 1.3e-13 at |x|/L = 2e3)
      tol = 1e-14_wp + 1e-15_wp*maxval(abs(shift))
      call check(abs(va + vb - v) <= tol*v, 'two sides of a plane: volumes add up')
      call check(maxval(abs(ma + mb - m)) <= tol*v*maxval(abs(m/v)), &
                 'two sides of a plane: first moments add up')
    end do
  end subroutine test_two_sides

  subroutine test_capacity()
    type(poly_t) :: p, q
    real(wp) :: n(3), v, vq, c(3)
    integer :: ip, nclip
    logical :: ok, overflowed
    ! planes tangent to the sphere of radius 0.45 about the cube's centre:
    ! every one adds a face, so the vertex count grows until it would overflow
    p = poly_from_hex(cube)
    overflowed = .false.
    nclip = 0
    do ip = 1, 200
      n = [uni(-1.0_wp, 1.0_wp), uni(-1.0_wp, 1.0_wp), uni(-1.0_wp, 1.0_wp)]
      n = n/norm2(n)
      q = p
      call poly_clip(p, n, dot_product(n, [0.5_wp, 0.5_wp, 0.5_wp]) + 0.45_wp, ok)
      if (.not. ok) then
        overflowed = .true.
        call poly_moments(q, vq, c)
        call poly_moments(p, v, c)
        call check(p%nv == q%nv .and. abs(v - vq) < 1e-300_wp, 'overflow leaves the polyhedron unchanged')
        exit
      end if
      nclip = nclip + 1
    end do
    call check(overflowed, 'tangent planes eventually exceed the capacity')
    call check(nclip >= 20, 'capacity holds at least 20 extra faces')
    call check_topology(p, 'many tangent planes')
    call poly_moments(p, v, c)
    call check(v < 1.0_wp .and. v > 4.0_wp/3.0_wp*3.14159_wp*0.45_wp**3, &
               'many tangent planes: volume between the sphere and the cube')
  end subroutine test_capacity

  subroutine test_hex_tets()
    real(wp) :: xn(3, 8), tets(3, 4, 24), vt, vsum, a(3, 3), mom(3), xc(3), vol
    integer :: trial, kk
    logical :: allpos
    do trial = 1, 100
      call random_hex(0.15_wp, [0.0_wp, 0.0_wp, 0.0_wp], xn)
      call hex_tets(xn, tets)
      vsum = 0.0_wp
      allpos = .true.
      do kk = 1, 24
        vt = det6(tets(:, :, kk))/6.0_wp
        vsum = vsum + vt
        allpos = allpos .and. vt > 0.0_wp
      end do
      call check(abs(vsum - hex_volume(xn)) <= 1e-14_wp*hex_volume(xn), &
                 '24 tets sum to hex_volume')
      call check(allpos, '24 tets of a mildly distorted hex are positive')
      ! the 24 tets of the cell against the cell itself: the tets as
      ! polyhedra give the same volume
      vol = 0.0_wp
      do kk = 1, 24
        call poly_moments(poly_from_tet(tets(:, :, kk)), vt, xc)
        vol = vol + vt
      end do
      call check(abs(vol - vsum) <= 1e-14_wp*vsum, 'tets as polyhedra: same volume')
    end do
    ! Eq. (49) centroid of a parallelepiped is its centre
    a = reshape([1.3_wp, 0.2_wp, -0.1_wp, 0.4_wp, 0.9_wp, 0.3_wp, 0.1_wp, -0.2_wp, 1.1_wp], [3, 3])
    xn = matmul(a, cube)
    call hex_tets(xn, tets)
    vol = 0.0_wp
    mom = 0.0_wp
    do kk = 1, 24
      vt = det6(tets(:, :, kk))/6.0_wp
      vol = vol + vt
      mom = mom + vt*0.25_wp*sum(tets(:, :, kk), 2)
    end do
    call check(maxval(abs(mom/vol - 0.125_wp*sum(xn, 2))) < 1e-15_wp, &
               'Eq. (49) centroid of a parallelepiped is its centre')
  end subroutine test_hex_tets

  subroutine test_tet_hex()
    real(wp) :: t(3, 4), t2(3, 4), xn(3, 8), vol, mom(3), v2, m2(3), ve, a(3, 3), nrm(3), d
    real(wp) :: tets(3, 4, 24)
    type(poly_t) :: p
    integer, parameter :: face(3, 4) = reshape([2, 3, 4,  1, 4, 3,  1, 2, 4,  1, 3, 2], [3, 4])
    integer :: trial, f, kk
    ! fully inside the unit cube (and inside a distorted one)
    t = reshape([0.2_wp, 0.2_wp, 0.2_wp,  0.7_wp, 0.3_wp, 0.25_wp,  0.3_wp, 0.8_wp, 0.3_wp, &
                 0.35_wp, 0.4_wp, 0.75_wp], [3, 4])
    ve = det6(t)/6.0_wp
    call check(ve > 0.0_wp, 'inside tet is positive')
    call tet_intersect_hex(t, cube, vol, mom)
    call check(abs(vol - ve) < 1e-15_wp, 'tet inside the cube: its volume')
    call check(maxval(abs(mom - ve*0.25_wp*sum(t, 2))) < 1e-15_wp, 'tet inside the cube: its moment')
    call random_hex(0.1_wp, [0.0_wp, 0.0_wp, 0.0_wp], xn)
    call tet_intersect_hex(t, xn, vol, mom)
    call check(abs(vol - ve) < 1e-15_wp, 'tet inside a distorted hex: its volume')
    call check(maxval(abs(mom - ve*0.25_wp*sum(t, 2))) < 1e-15_wp, 'tet inside a distorted hex: its moment')
    ! inverted: the same, negated
    t2 = t
    t2(:, 3) = t(:, 4)
    t2(:, 4) = t(:, 3)
    call tet_intersect_hex(t2, xn, v2, m2)
    call check(abs(v2 + vol) < 1e-15_wp .and. maxval(abs(m2 + mom)) < 1e-15_wp, &
               'inverted tet: negated result')
    ! fully outside, far and near
    t2 = t
    t2(1, :) = t2(1, :) + 2.0_wp
    call tet_intersect_hex(t2, cube, vol, mom)
    call check(abs(vol) < 1e-300_wp .and. maxval(abs(mom)) < 1e-300_wp, 'tet far outside: zero')
    ! (x+y >= 2.1 on the tet, <= 2 on the cube, bounding boxes overlap)
    t2 = reshape([1.6_wp, 0.5_wp, 0.2_wp,  0.5_wp, 1.6_wp, 0.2_wp,  1.6_wp, 1.6_wp, 0.2_wp, &
                  1.1_wp, 1.1_wp, 0.8_wp], [3, 4])
    call tet_intersect_hex(t2, cube, vol, mom)
    call check(abs(vol) < 1e-17_wp, 'tet near but outside (boxes overlap): zero')
    ! flat tet: zero, no NaN
    t2 = t
    t2(:, 4) = 0.5_wp*(t(:, 2) + t(:, 3))
    call tet_intersect_hex(t2, cube, vol, mom)
    call check(abs(vol) < 1e-300_wp .and. .not. any(ieee_is_nan(mom)), 'flat tet: zero')
    ! partial: the corner simplex of size 2 clips the cube to x+y+z <= 2
    ! (three of its faces on the cube's), and a shifted one of size 2.6 that
    ! cuts the same region with no coplanar faces: V = 5/6, M_x = 3/8
    t = reshape([0, 0, 0,  2, 0, 0,  0, 2, 0,  0, 0, 2], [3, 4])*1.0_wp
    call tet_intersect_hex(t, cube, vol, mom)
    call check(abs(vol - 5.0_wp/6.0_wp) < 1e-14_wp, 'corner simplex and cube: volume')
    call check(maxval(abs(mom - 0.375_wp)) < 1e-14_wp, 'corner simplex and cube: moment')
    do kk = 1, 4
      t(:, kk) = t(:, kk)*1.3_wp + [-0.1_wp, -0.2_wp, -0.3_wp]
    end do
    call tet_intersect_hex(t, cube, vol, mom)
    call check(abs(vol - 5.0_wp/6.0_wp) < 1e-14_wp, 'shifted simplex and cube: volume')
    call check(maxval(abs(mom - 0.375_wp)) < 1e-14_wp, 'shifted simplex and cube: moment')
    ! partial, against another route: a parallelepiped (a convex hex) as one
    ! polyhedron clipped by the tet's four planes
    do trial = 1, 100
      a = reshape([1.0_wp + uni(-0.2_wp, 0.2_wp), uni(-0.2_wp, 0.2_wp), uni(-0.2_wp, 0.2_wp), &
                   uni(-0.2_wp, 0.2_wp), 1.0_wp + uni(-0.2_wp, 0.2_wp), uni(-0.2_wp, 0.2_wp), &
                   uni(-0.2_wp, 0.2_wp), uni(-0.2_wp, 0.2_wp), 1.0_wp + uni(-0.2_wp, 0.2_wp)], [3, 3])
      xn = matmul(a, cube)
      call random_tet(-0.3_wp, 1.3_wp, t)
      call tet_intersect_hex(t, xn, vol, mom)
      p = poly_from_hex(xn)
      do f = 1, 4
        nrm = cross(t(:, face(2, f)) - t(:, face(1, f)), t(:, face(3, f)) - t(:, face(1, f)))
        d = dot_product(nrm, t(:, face(1, f)))
        call poly_clip(p, nrm, d)
      end do
      call poly_first_moments(p, v2, m2)
      call check(abs(vol - v2) < 1e-14_wp, 'tet and parallelepiped: volume by both routes')
      call check(maxval(abs(mom - m2)) < 1e-14_wp, 'tet and parallelepiped: moment by both routes')
      ! tet-tet is symmetric
      call hex_tets(xn, tets)
      call tet_intersect_tet(t, tets(:, :, 1 + mod(trial, 24)), vol, mom)
      call tet_intersect_tet(tets(:, :, 1 + mod(trial, 24)), t, v2, m2)
      call check(abs(vol - v2) < 1e-15_wp .and. maxval(abs(mom - m2)) < 1e-15_wp, &
                 'tet-tet intersection is symmetric')
    end do
    call tet_intersect_tet(t, t, vol, mom)
    call check(abs(vol - det6(t)/6.0_wp) < 1e-15_wp, 'a tet with itself: its volume')
  end subroutine test_tet_hex

  subroutine test_partitions()
    real(wp) :: xa(3, 8), xb(3, 8), ta(3, 4, 24), tb(3, 4, 24), vol, mom(3), vab, mab(3), vba, mba(3)
    real(wp) :: veq, meq(3), lat(3, 0:2, 0:2, 0:2), xc(3, 8), t(3, 4), shift(3), tol
    integer :: trial, kk, ci, cj, ck, ii, jj, ll
    ! A with itself: the sum over A's tets of (tet and A) is A's volume and
    ! its Eq. (49) moment; half of the cells far from the origin, where the
    ! global face centres of A's tets carry round-off of eps |x| (tolerance
    ! 1e-13 + 1e-15 |x|/L)
    do trial = 1, 20
      shift = 0.0_wp
      if (trial > 10) shift = [1e3_wp, -2e3_wp, 5e2_wp]
      tol = 1e-13_wp + 1e-15_wp*maxval(abs(shift))
      call random_hex(0.15_wp, shift, xa)
      call hex_tets(xa, ta)
      vab = 0.0_wp
      mab = 0.0_wp
      meq = 0.0_wp
      do kk = 1, 24
        call tet_intersect_hex(ta(:, :, kk), xa, vol, mom)
        vab = vab + vol
        mab = mab + mom
        meq = meq + det6(ta(:, :, kk))/24.0_wp*sum(ta(:, :, kk), 2)
      end do
      veq = hex_volume(xa)
      call check(abs(vab - veq) <= tol*veq, 'A with A: sum over its tets is vol(A)')
      call check(maxval(abs(mab - meq)) <= tol*veq*(1.0_wp + maxval(abs(shift))), &
                 'A with A: first moment of Eq. (49)')
    end do
    ! two different hexes sharing a region: the same volume from either side
    do trial = 1, 20
      call random_hex(0.15_wp, [0.0_wp, 0.0_wp, 0.0_wp], xa)
      call random_hex(0.15_wp, [uni(-0.5_wp, 0.5_wp), uni(-0.5_wp, 0.5_wp), uni(-0.5_wp, 0.5_wp)], xb)
      call hex_tets(xa, ta)
      call hex_tets(xb, tb)
      vab = 0.0_wp
      mab = 0.0_wp
      vba = 0.0_wp
      mba = 0.0_wp
      do kk = 1, 24
        call tet_intersect_hex(ta(:, :, kk), xb, vol, mom)
        vab = vab + vol
        mab = mab + mom
        call tet_intersect_hex(tb(:, :, kk), xa, vol, mom)
        vba = vba + vol
        mba = mba + mom
      end do
      call check(vab > 0.0_wp, 'A and B overlap')
      call check(abs(vab - vba) <= 1e-12_wp*vab, 'vol(A and B) is the same from A and from B')
      call check(maxval(abs(mab - mba)) <= 1e-12_wp*vab, 'moment of A and B is the same from A and from B')
    end do
    ! two unit cubes offset by (0.3, 0.2, 0.1): a 0.7 x 0.8 x 0.9 box
    call hex_tets(cube, ta)
    do kk = 1, 8
      xb(:, kk) = cube(:, kk) + [0.3_wp, 0.2_wp, 0.1_wp]
    end do
    vab = 0.0_wp
    mab = 0.0_wp
    do kk = 1, 24
      call tet_intersect_hex(ta(:, :, kk), xb, vol, mom)
      vab = vab + vol
      mab = mab + mom
    end do
    call check(abs(vab - 0.504_wp) < 1e-13_wp, 'offset cubes: volume of the overlap box')
    call check(maxval(abs(mab/vab - [0.65_wp, 0.6_wp, 0.55_wp])) < 1e-13_wp, 'offset cubes: centroid')
    ! a tet inside a block of 2 x 2 x 2 distorted cells: the cells' pieces
    ! add up to the tet (the 24-tet splits of neighbours share face triangles)
    do trial = 1, 20
      do ll = 0, 2
        do jj = 0, 2
          do ii = 0, 2
            lat(:, ii, jj, ll) = real([ii, jj, ll], wp) + [uni(-0.1_wp, 0.1_wp), uni(-0.1_wp, 0.1_wp), &
                                                           uni(-0.1_wp, 0.1_wp)]
          end do
        end do
      end do
      call random_tet(0.5_wp, 1.5_wp, t)
      vab = 0.0_wp
      mab = 0.0_wp
      do ck = 0, 1
        do cj = 0, 1
          do ci = 0, 1
            do ll = 0, 1
              do jj = 0, 1
                do ii = 0, 1
                  xc(:, 1 + ii + 2*jj + 4*ll) = lat(:, ci + ii, cj + jj, ck + ll)
                end do
              end do
            end do
            call tet_intersect_hex(t, xc, vol, mom)
            vab = vab + vol
            mab = mab + mom
          end do
        end do
      end do
      ! round-off of O(1) coordinates: 1e-15 of a cell's volume (a thin tet
      ! of volume 1e-4 is not held to 1e-13 of its own volume)
      veq = det6(t)/6.0_wp
      call check(abs(vab - veq) <= 1e-15_wp, 'tet over a block of cells: pieces add up to the tet')
      call check(maxval(abs(mab - veq*0.25_wp*sum(t, 2))) <= 1e-15_wp, &
                 'tet over a block of cells: moments add up to the tet''s')
    end do
  end subroutine test_partitions

  !> `tet_clip_moments` against `poly_set_tet` + `poly_clip` +
  !> `poly_first_moments` (the same numbers to round-off of the tetrahedron's
  !> size): random tetrahedra cut by random planes, by planes through one,
  !> two and three of their vertices (the tolerance's on-plane cases: the
  !> kept part a tetrahedron, a prism with a degenerate end, the whole or
  !> nothing), and by planes a round-off unit off a vertex; with the other
  !> side, the whole tetrahedron (volume and moment).
  subroutine test_tet_clip()
    type(poly_t) :: p
    real(wp) :: t(3, 4), n(3), d, v1, m1(3), v2, m2(3), vo, mo(3), vt, errv, errm, errs
    integer :: ic, kind, a, b
    errv = 0.0_wp
    errm = 0.0_wp
    errs = 0.0_wp
    do ic = 1, 20000
      call random_tet(-1.0_wp, 2.0_wp, t)
      if (mod(ic, 2) == 0) t(:, [3, 4]) = t(:, [4, 3])   ! either orientation
      n = [uni(-1.0_wp, 1.0_wp), uni(-1.0_wp, 1.0_wp), uni(-1.0_wp, 1.0_wp)]
      kind = mod(ic, 5)
      a = 1 + mod(ic/5, 4)
      b = 1 + mod(a, 4)
      select case (kind)
      case (0)
        d = uni(-3.0_wp, 3.0_wp)
      case (1)
        d = dot_product(n, t(:, a))
      case (2)
        ! through two vertices: n normal to their edge
        n = cross(t(:, b) - t(:, a), n)
        d = dot_product(n, t(:, a))
      case (3)
        ! through three: the face's plane, from either side
        n = cross(t(:, 2) - t(:, 1), t(:, 3) - t(:, 1))
        if (mod(ic/5, 2) == 1) n = -n
        d = dot_product(n, t(:, 1))
      case default
        d = dot_product(n, t(:, a))*(1.0_wp + 3.0_wp*epsilon(1.0_wp)*merge(1.0_wp, -1.0_wp, mod(ic/5, 2) == 0))
      end select
      vt = abs(det6(t))/6.0_wp
      call tet_clip_moments(t, n, d, v1, m1)
      call poly_set_tet(p, t)
      call poly_clip(p, n, d)
      call poly_first_moments(p, v2, m2)
      errv = max(errv, abs(v1 - v2)/vt)
      errm = max(errm, maxval(abs(m1 - m2))/(vt*3.0_wp))
      call tet_clip_moments(t, -n, -d, vo, mo)
      errs = max(errs, abs(v1 + vo - vt)/vt, &
                 maxval(abs(m1 + mo - 0.25_wp*vt*(t(:, 1) + t(:, 2) + t(:, 3) + t(:, 4))))/(vt*3.0_wp))
    end do
    write(*, '(a,3es10.2)') 'tet clip, closed form against the polyhedron: volume, moment, two sides ', &
      errv, errm, errs
    call check(errv <= 1e-13_wp, 'tet clip: volume as poly_clip + poly_first_moments')
    call check(errm <= 1e-13_wp, 'tet clip: first moment as poly_clip + poly_first_moments')
    call check(errs <= 1e-13_wp, 'tet clip: the two sides make the tetrahedron')
  end subroutine test_tet_clip

  subroutine timings()
    integer, parameter :: ncase = 100000
    real(wp), allocatable :: t1(:, :, :), t2(:, :, :), hx(:, :, :)
    real(wp) :: vol, mom(3), acc, s_tt, s_th
    integer(i8) :: c0, c1, rate
    integer :: ic, st
    character(len=200) :: msg

    allocate(t1(3, 4, ncase), t2(3, 4, ncase), hx(3, 8, ncase), stat=st, errmsg=msg)
    call check(st == 0, 'timing arrays: '//trim(msg))
    if (st /= 0) return
    do ic = 1, ncase
      call random_tet(0.0_wp, 1.0_wp, t1(:, :, ic))
      call random_tet(0.0_wp, 1.0_wp, t2(:, :, ic))
      call random_hex(0.15_wp, [0.0_wp, 0.0_wp, 0.0_wp], hx(:, :, ic))
    end do
    acc = 0.0_wp
    call system_clock(c0, rate)
    do ic = 1, ncase
      call tet_intersect_tet(t1(:, :, ic), t2(:, :, ic), vol, mom)
      acc = acc + vol
    end do
    call system_clock(c1)
    s_tt = real(c1 - c0, wp)/real(rate, wp)
    call system_clock(c0)
    do ic = 1, ncase
      call tet_intersect_hex(t1(:, :, ic), hx(:, :, ic), vol, mom)
      acc = acc + vol
    end do
    call system_clock(c1)
    s_th = real(c1 - c0, wp)/real(rate, wp)
    write(*, '(a,i0,a)') 'timing over ', ncase, ' random cases (tets in the unit cube, hexes +-0.15):'
    write(*, '(a,f10.3,a)') '  tet-tet intersection:          ', 1e6_wp*s_tt/ncase, ' us'
    write(*, '(a,f10.3,a)') '  tet-hex intersection (24 tets):', 1e6_wp*s_th/ncase, ' us'
    write(*, '(a,es12.4,a)') '  (checksum of volumes ', acc, ')'
  end subroutine timings
end program test_remap_geometry
