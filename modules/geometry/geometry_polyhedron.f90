!> Geometry kernel of the intersection-based remap (Sect. 5.4): a small convex
!> polyhedron, its clipping by a half-space ("clipping and capping", [33] of the
!> paper), its exact volume and first moments, the 24-tetrahedron split of a
!> hexahedral cell (Fig. 7) and the exact intersection of a tetrahedron with a
!> hexahedron built on them, which is what Eq. (54)-(57) sum over.
!>
!> Representation. A polyhedron is stored as vertices with exactly three
!> neighbours each (a simple polyhedron: every vertex of a tetrahedron, of a
!> hexahedron and of anything cut from them by planes has degree three). The
!> neighbours of a vertex are ordered so that one rule walks every face
!> counter-clockwise seen from outside: arriving at vertex c from its neighbour
!> nbr(j,c), the walk leaves towards nbr(j+1,c) (cyclically). Faces are not
!> stored; they are the closed walks of that rule. Clipping changes only the
!> vertex list, never allocates, and decides topology from one in/out flag per
!> vertex, so the result is always a closed, consistently oriented surface,
!> whatever the round-off in the geometry.
!>
!> Signs. `tet_intersect_tet` and `tet_intersect_hex` return the intersection
!> volume times the orientation signs of the tetrahedra involved. For valid
!> (positively oriented) cells this is the plain volume; if a distorted cell has
!> an inverted tetrahedron in its split, the signed sum is still exactly the
!> cell's own (24-tet) volume, so remapped totals are conserved.
module geometry_polyhedron
  use base_kinds, only: wp
  use mesh_geometry, only: hex_faces, cross, hex_tets, tet_det
  implicit none
  private
  public :: poly_t, poly_max_verts, poly_rel_tol
  public :: poly_from_tet, poly_set_tet, poly_from_hex, poly_clip, poly_clip_axis, poly_first_moments, poly_moments, &
            poly_copy
  public :: tet_planes, tet_sign, tet_intersect_tet, tet_intersect_hex, tet_intersect_split, tet_clip_planes, slot_of
  public :: tet_clip_moments

  !> Vertex capacity of a polyhedron. A tetrahedron clipped by the four planes
  !> of another has at most 8 faces, hence (three edges at each vertex,
  !> V = 2F - 4) at most 12 vertices; 64 leaves room for a few more planes
  !> (e.g. material interfaces, 34 faces).
  integer, parameter :: poly_max_verts = 64

  !> Relative tolerance of the in/out test: a vertex whose signed distance
  !> n.x - d is within poly_rel_tol*(max_v sum_k |n_k x_vk| + |d|) of zero is
  !> taken to lie on the plane. That bound is ~45 round-off units of the
  !> evaluation of n.x - d itself, so coplanar faces and vertices that lie on
  !> the plane in exact arithmetic are recognised, while the volume moved by
  !> the snap is at most this relative size times the polyhedron's area.
  real(wp), parameter :: poly_rel_tol = 1.0e-14_wp

  !> A convex polyhedron of nv vertices x(:,1:nv) (length), each joined to
  !> the three vertices nbr(:,v) (see the module header for their order).
  !> nv = 0 is the empty polyhedron. No component has a default value: a
  !> local poly_t would otherwise be copied whole from the type's initial
  !> value (poly_max_verts vertices) at every entry of the routine that
  !> holds it; every poly is filled (`poly_set_tet`, `poly_from_hex`,
  !> `poly_copy`) before it is read.
  type :: poly_t
    integer :: nv
    real(wp) :: x(3, poly_max_verts)
    integer :: nbr(3, poly_max_verts)
  end type poly_t

  !> Neighbours of the vertices of a positively oriented tetrahedron
  !> (det(x2-x1, x3-x1, x4-x1) > 0), faces (1,3,2), (1,2,4), (1,4,3), (2,3,4).
  integer, parameter :: tet_nbr(3, 4) = reshape([2, 3, 4,  1, 4, 3,  1, 2, 4,  1, 3, 2], [3, 4])
  !> Faces of a positively oriented tetrahedron, counter-clockwise from
  !> outside; face i is the one opposite vertex i.
  integer, parameter :: tet_face(3, 4) = reshape([2, 3, 4,  1, 4, 3,  1, 2, 4,  1, 3, 2], [3, 4])
  !> Neighbours of the hexahedron's nodes, derived from `hex_faces` with the
  !> walking rule (node a = 1 + i + 2j + 4k).
  integer, parameter :: hex_nbr(3, 8) = reshape([2, 3, 5,  1, 6, 4,  1, 4, 7,  2, 8, 3, &
                                                 1, 7, 6,  2, 5, 8,  3, 8, 5,  4, 6, 7], [3, 8])

contains

  !> q = p, copying only p's vertices (a poly_t holds poly_max_verts: an
  !> assignment copies them all, most of them unused).
  pure subroutine poly_copy(p, q)
    type(poly_t), intent(in) :: p
    type(poly_t), intent(inout) :: q
    q%nv = p%nv
    q%x(:, 1:p%nv) = p%x(:, 1:p%nv)
    q%nbr(:, 1:p%nv) = p%nbr(:, 1:p%nv)
  end subroutine poly_copy

  !> The tetrahedron with vertices x(3,4) (length) as a polyhedron; either
  !> orientation of the input gives the same (convex hull) polyhedron.
  pure function poly_from_tet(x) result(p)
    real(wp), intent(in) :: x(3, 4)
    type(poly_t) :: p
    call set_tet(p, x)
  end function poly_from_tet

  !> Fills p with the tetrahedron x(3,4) (length; either orientation), in
  !> place (no copy of a poly_t, unlike `poly_from_tet`).
  pure subroutine poly_set_tet(p, x)
    type(poly_t), intent(inout) :: p
    real(wp), intent(in) :: x(3, 4)
    call set_tet(p, x)
  end subroutine poly_set_tet

  !> Fills p with the tetrahedron x, its vertices reordered to positive.
  pure subroutine set_tet(p, x)
    type(poly_t), intent(inout) :: p
    real(wp), intent(in) :: x(3, 4)
    p%nv = 4
    p%x(:, 1:4) = x
    if (tet_det(x) < 0.0_wp) then
      p%x(:, 3) = x(:, 4)
      p%x(:, 4) = x(:, 3)
    end if
    p%nbr(:, 1:4) = tet_nbr
  end subroutine set_tet

  !> The hexahedron with nodes xn(3,8) (length, local order a = 1 + i + 2j + 4k)
  !> as a polyhedron. Meant for valid convex hexahedra with planar faces
  !> (boxes, parallelepipeds); a general cell is handled through `hex_tets`.
  pure function poly_from_hex(xn) result(p)
    real(wp), intent(in) :: xn(3, 8)
    type(poly_t) :: p
    p%nv = 8
    p%x(:, 1:8) = xn
    p%nbr(:, 1:8) = hex_nbr
  end function poly_from_hex

  !> The slot j of vertex c's neighbour list that holds vertex u.
  pure function slot_of(p, c, u) result(j)
    type(poly_t), intent(in) :: p
    integer, intent(in) :: c, u
    integer :: j
    if (p%nbr(1, c) == u) then
      j = 1
    else if (p%nbr(2, c) == u) then
      j = 2
    else
      j = 3
    end if
  end function slot_of

  !> Clips p to the half-space n.x <= d (n need not be normalised, d is in
  !> length times |n|; n = 0 keeps all of p if d >= 0, nothing otherwise)
  !> and caps the cut, so p stays a closed convex polyhedron. A plane that misses p keeps all of it or empties it; a plane
  !> through vertices, along edges or containing a face is handled by the
  !> tolerance `poly_rel_tol`. If the result would exceed `poly_max_verts`,
  !> p is left unchanged and ok (if present) is false.
  pure subroutine poly_clip(p, n, d, ok)
    type(poly_t), intent(inout) :: p
    real(wp), intent(in) :: n(3)
    real(wp), intent(in) :: d
    logical, intent(out), optional :: ok
    real(wp) :: s(poly_max_verts), xmax
    integer :: v

    if (present(ok)) ok = .true.
    if (p%nv == 0) return
    ! signed distances (times |n|) and the scale of their round-off
    xmax = 0.0_wp
    do v = 1, p%nv
      s(v) = n(1)*p%x(1, v) + n(2)*p%x(2, v) + n(3)*p%x(3, v) - d
      xmax = max(xmax, abs(n(1)*p%x(1, v)) + abs(n(2)*p%x(2, v)) + abs(n(3)*p%x(3, v)))
    end do
    call clip_at(p, s, poly_rel_tol*(xmax + abs(d)), ok)
  end subroutine poly_clip

  !> `poly_clip` by the plane sgn x_k = d (sgn = 1 or -1: the half-space
  !> sgn x_k <= d), the same numbers as poly_clip(p, sgn e_k, d) without
  !> the products by the normal's zeros (the lattice's and the octants'
  !> planes).
  pure subroutine poly_clip_axis(p, k, sgn, d, ok)
    type(poly_t), intent(inout) :: p
    integer, intent(in) :: k
    real(wp), intent(in) :: sgn, d
    logical, intent(out), optional :: ok
    real(wp) :: s(poly_max_verts), xmax
    integer :: v

    if (present(ok)) ok = .true.
    if (p%nv == 0) return
    xmax = 0.0_wp
    do v = 1, p%nv
      s(v) = sgn*p%x(k, v) - d
      xmax = max(xmax, abs(p%x(k, v)))
    end do
    call clip_at(p, s, poly_rel_tol*(xmax + abs(d)), ok)
  end subroutine poly_clip_axis

  !> The clip of `poly_clip` from the vertices' signed distances s (outside
  !> where positive) and the tolerance tol within which a vertex is on the
  !> plane.
  pure subroutine clip_at(p, s, tol, ok)
    type(poly_t), intent(inout) :: p
    real(wp), intent(inout) :: s(:)
    real(wp), intent(in) :: tol
    logical, intent(out), optional :: ok
    real(wp) :: t
    integer :: idx(poly_max_verts)
    integer :: nv, ntot, nin, nout, ncut, v, k, u, w, prev, cur, nxt, it, m

    nv = p%nv
    nin = 0
    nout = 0
    do v = 1, nv
      if (s(v) > tol) then
        nout = nout + 1
      else if (s(v) < -tol) then
        nin = nin + 1
      else
        s(v) = 0.0_wp
      end if
    end do
    ! nothing strictly outside: all kept; nothing strictly inside: what is
    ! kept is at most a face on the plane, of no volume
    if (nout == 0) return
    if (nin == 0) then
      p%nv = 0
      return
    end if

    ! room for the new vertices (one per cut edge; there are 3 nv / 2 edges,
    ! so only a large polyhedron needs them counted)
    if (5*nv > 2*poly_max_verts) then
      ncut = 0
      do v = 1, nv
        if (s(v) > 0.0_wp) cycle
        do k = 1, 3
          if (s(p%nbr(k, v)) > 0.0_wp) ncut = ncut + 1
        end do
      end do
      if (nv + ncut > poly_max_verts) then
        if (present(ok)) ok = .false.
        return
      end if
    end if

    ! a new vertex on every edge from a kept vertex v (s <= 0) to a removed
    ! one u (s > 0), so s(u) - s(v) >= s(u) > 0: no division by zero, and a
    ! kept vertex on the plane gives t = 0, the vertex itself
    ntot = nv
    do v = 1, nv
      if (s(v) > 0.0_wp) cycle
      do k = 1, 3
        u = p%nbr(k, v)
        if (s(u) <= 0.0_wp) cycle
        ntot = ntot + 1
        t = -s(v)/(s(u) - s(v))
        p%x(:, ntot) = p%x(:, v) + t*(p%x(:, u) - p%x(:, v))
        p%nbr(1, ntot) = v
        p%nbr(2, ntot) = ntot
        p%nbr(3, ntot) = ntot
        p%nbr(k, v) = ntot
      end do
    end do

    ! cap: from new vertex w, walk its old face w -> v -> ... along kept
    ! vertices to the next new vertex w2; the cap edge w -> w2 closes that
    ! face, so w2 is w's third neighbour and w is w2's second
    do w = nv + 1, ntot
      prev = w
      cur = p%nbr(1, w)
      do it = 1, ntot
        nxt = p%nbr(mod(slot_of(p, cur, prev), 3) + 1, cur)
        prev = cur
        cur = nxt
        if (cur > nv) exit
      end do
      p%nbr(3, w) = cur
      p%nbr(2, cur) = w
    end do

    ! drop the removed vertices and renumber
    m = 0
    do v = 1, ntot
      if (v <= nv) then
        if (s(v) > 0.0_wp) then
          idx(v) = 0
          cycle
        end if
      end if
      m = m + 1
      idx(v) = m
    end do
    do v = 1, ntot
      if (idx(v) == 0) cycle
      p%x(:, idx(v)) = p%x(:, v)
      p%nbr(1, idx(v)) = idx(p%nbr(1, v))
      p%nbr(2, idx(v)) = idx(p%nbr(2, v))
      p%nbr(3, idx(v)) = idx(p%nbr(3, v))
    end do
    p%nv = m
  end subroutine clip_at

  !> Volume vol (length^3) and first moment mom = integral of x dV
  !> (length^4) of p: every face is fanned from its first vertex and each
  !> triangle joined to the mean of the vertices, so the sum of the signed
  !> tetrahedra is exact for the closed surface; relative to that interior
  !> point every tetrahedron of a convex p is positive, so vol >= 0 up to
  !> round-off. The empty polyhedron has vol = 0, mom = 0.
  pure subroutine poly_first_moments(p, vol, mom)
    type(poly_t), intent(in) :: p
    real(wp), intent(out) :: vol
    real(wp), intent(out) :: mom(3)
    logical :: used(3, poly_max_verts)
    real(wp) :: r(3), a(3), b(3), c(3), t, v6, m24(3)
    integer :: nv, v, k, j, prev, cur, nxt, it

    vol = 0.0_wp
    mom = 0.0_wp
    nv = p%nv
    if (nv < 4) return
    if (nv == 4) then
      ! a tetrahedron (the most common piece: a half that lies in one new
      ! subcell): its neighbours' order at any vertex is positive (the
      ! walking rule), so 6 V = (x_a - x_1).((x_b - x_1) x (x_c - x_1))
      ! with (a, b, c) = nbr(:, 1), and the centroid is the mean vertex
      a = p%x(:, p%nbr(1, 1)) - p%x(:, 1)
      b = p%x(:, p%nbr(2, 1)) - p%x(:, 1)
      c = p%x(:, p%nbr(3, 1)) - p%x(:, 1)
      vol = (a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) + a(3)*(b(1)*c(2) - b(2)*c(1)))/6.0_wp
      mom = 0.25_wp*vol*(p%x(:, 1) + p%x(:, 2) + p%x(:, 3) + p%x(:, 4))
      return
    end if
    do k = 1, 3
      r(k) = sum(p%x(k, 1:nv))/real(nv, wp)
    end do
    used(:, 1:nv) = .false.
    v6 = 0.0_wp
    m24 = 0.0_wp
    do v = 1, nv
      do k = 1, 3
        if (used(k, v)) cycle
        ! the face to the left of the directed edge v -> nbr(k,v)
        used(k, v) = .true.
        a = p%x(:, v) - r
        prev = v
        cur = p%nbr(k, v)
        b = p%x(:, cur) - r
        do it = 1, nv
          j = mod(slot_of(p, cur, prev), 3) + 1
          used(j, cur) = .true.
          nxt = p%nbr(j, cur)
          if (nxt == v) exit
          c = p%x(:, nxt) - r
          ! tetrahedron (r, a, b, c): 6 V_t = a.(b x c), centroid r + (a+b+c)/4
          t = a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) + a(3)*(b(1)*c(2) - b(2)*c(1))
          v6 = v6 + t
          m24 = m24 + t*(a + b + c)
          b = c
          prev = cur
          cur = nxt
        end do
      end do
    end do
    vol = v6/6.0_wp
    mom = m24/24.0_wp + vol*r
  end subroutine poly_first_moments

  !> Volume vol (length^3) and first moment mom (length^4) of the part
  !> n.x <= d of the tetrahedron t(3,4) (either orientation; n need not be
  !> unit): what `poly_set_tet`, `poly_clip` and `poly_first_moments` give,
  !> from the same in/out decision per vertex (`poly_clip`'s distances and
  !> tolerance) and the same cut points, in closed form rather than through
  !> the general polyhedron. One kept vertex keeps a tetrahedron; two or
  !> three keep a triangular prism (ends: the kept vertices' and the cut
  !> points' triangles), summed as its three tetrahedra (ABCD, BCDE, CDEF
  !> for ends ABC, DEF joined A-D, B-E, C-F: the diagonals of the three
  !> quadrilateral sides agree), each part computed directly, so a sliver
  !> is exact to round-off of its own size. The remap clips by one plane
  !> millions of times (a mixed cell's swept prisms, its MoF volume roots).
  pure subroutine tet_clip_moments(t, n, d, vol, mom, cap, ncap)
    real(wp), intent(in) :: t(3, 4), n(3), d
    real(wp), intent(out) :: vol, mom(3)
    !> (optional) the cut's polygon on the plane, its ncap (3 or 4) points
    !> in order round it (either way round); ncap = 0 where the plane
    !> leaves the whole tetrahedron or nothing
    real(wp), intent(out), optional :: cap(3, 4)
    integer, intent(out), optional :: ncap
    real(wp) :: s(4), xmax, tol, w(3, 6), d1, d2, d3, sd
    integer :: v, nin, nk, nr, kept(4), gone(4)

    xmax = 0.0_wp
    do v = 1, 4
      s(v) = n(1)*t(1, v) + n(2)*t(2, v) + n(3)*t(3, v) - d
      xmax = max(xmax, abs(n(1)*t(1, v)) + abs(n(2)*t(2, v)) + abs(n(3)*t(3, v)))
    end do
    tol = poly_rel_tol*(xmax + abs(d))
    nin = 0
    nk = 0
    nr = 0
    do v = 1, 4
      if (s(v) > tol) then
        nr = nr + 1
        gone(nr) = v
      else
        if (s(v) < -tol) then
          nin = nin + 1
        else
          s(v) = 0.0_wp
        end if
        nk = nk + 1
        kept(nk) = v
      end if
    end do
    vol = 0.0_wp
    mom = 0.0_wp
    if (present(ncap)) ncap = 0
    if (nin == 0) return
    select case (nk)
    case (4)
      vol = abs(tet_det(t))/6.0_wp
      mom = 0.25_wp*vol*((t(:, 1) + t(:, 2)) + (t(:, 3) + t(:, 4)))
      return
    case (1)
      w(:, 1) = t(:, kept(1))
      do v = 1, 3
        w(:, 1 + v) = cut_point(kept(1), gone(v))
      end do
      vol = abs(tet_det(w(:, 1:4)))/6.0_wp
      mom = 0.25_wp*vol*((w(:, 1) + w(:, 2)) + (w(:, 3) + w(:, 4)))
      if (present(cap)) cap(:, 1:3) = w(:, 2:4)
      if (present(ncap)) ncap = 3
      return
    case (2)
      ! ends (a, cut a-c, cut a-d) and (b, cut b-c, cut b-d)
      w(:, 1) = t(:, kept(1))
      w(:, 2) = cut_point(kept(1), gone(1))
      w(:, 3) = cut_point(kept(1), gone(2))
      w(:, 4) = t(:, kept(2))
      w(:, 5) = cut_point(kept(2), gone(1))
      w(:, 6) = cut_point(kept(2), gone(2))
      ! (round the cut: on faces acd, abc, bcd, abd in turn)
      if (present(cap)) cap = w(:, [3, 2, 5, 6])
      if (present(ncap)) ncap = 4
    case default
      ! ends (a, b, c) and (cut a-r, cut b-r, cut c-r)
      w(:, 1:3) = t(:, kept(1:3))
      do v = 1, 3
        w(:, 3 + v) = cut_point(kept(v), gone(1))
      end do
      if (present(cap)) cap(:, 1:3) = w(:, 4:6)
      if (present(ncap)) ncap = 3
    end select
    ! the prism's three tetrahedra, one orientation (their signed sum's)
    d1 = tet_det(w(:, 1:4))
    d2 = tet_det(w(:, 2:5))
    d3 = tet_det(w(:, 3:6))
    sd = sign(1.0_wp, d1 + d2 + d3)
    vol = abs(d1 + d2 + d3)/6.0_wp
    mom = (sd/24.0_wp)*(d1*((w(:, 1) + w(:, 2)) + (w(:, 3) + w(:, 4))) + &
                        d2*((w(:, 2) + w(:, 3)) + (w(:, 4) + w(:, 5))) + &
                        d3*((w(:, 3) + w(:, 4)) + (w(:, 5) + w(:, 6))))

  contains

    !> The point where the edge from kept vertex a to removed vertex b
    !> crosses the plane (`clip_at`'s: from the kept end, s(b) > 0 >= s(a)).
    pure function cut_point(a, b) result(x)
      integer, intent(in) :: a, b
      real(wp) :: x(3)
      x = t(:, a) + (-s(a)/(s(b) - s(a)))*(t(:, b) - t(:, a))
    end function cut_point
  end subroutine tet_clip_moments

  !> Volume vol (length^3) and centroid (length) of p. For a polyhedron of
  !> no volume the centroid is the mean of its vertices (the origin if empty).
  pure subroutine poly_moments(p, vol, centroid)
    type(poly_t), intent(in) :: p
    real(wp), intent(out) :: vol
    real(wp), intent(out) :: centroid(3)
    real(wp) :: mom(3), scale
    integer :: k

    call poly_first_moments(p, vol, mom)
    centroid = 0.0_wp
    if (p%nv == 0) return
    ! a volume below round-off of the vertex extents has no meaningful centroid
    scale = 0.0_wp
    do k = 1, 3
      scale = max(scale, maxval(p%x(k, 1:p%nv)) - minval(p%x(k, 1:p%nv)))
    end do
    if (vol > epsilon(1.0_wp)*scale**3 .and. vol > 0.0_wp) then
      centroid = mom/vol
    else
      do k = 1, 3
        centroid(k) = sum(p%x(k, 1:p%nv))/real(p%nv, wp)
      end do
    end if
  end subroutine poly_moments

  !> The orientation sign of the tetrahedron t: +1, -1, or 0 for one flat
  !> to round-off (`tet_planes`' sgn, without its planes).
  pure integer function tet_sign(t) result(sgn)
    real(wp), intent(in) :: t(3, 4)
    real(wp) :: det, scale
    integer :: i
    det = tet_det(t)
    scale = 0.0_wp
    do i = 2, 4
      scale = max(scale, maxval(abs(t(:, i) - t(:, 1))))
    end do
    sgn = 0
    if (abs(det) <= epsilon(1.0_wp)*scale**3) return
    sgn = 1
    if (det < 0.0_wp) sgn = -1
  end function tet_sign

  !> Outward face planes n(:,i).x <= d(i) of the tetrahedron t and its
  !> orientation sign sgn (`tet_sign`; the planes zero where it is 0).
  pure subroutine tet_planes(t, n, d, sgn)
    real(wp), intent(in) :: t(3, 4)
    real(wp), intent(out) :: n(3, 4), d(4)
    integer, intent(out) :: sgn
    real(wp) :: x(3, 4)
    integer :: i, a, b, c

    sgn = tet_sign(t)
    n = 0.0_wp
    d = 0.0_wp
    if (sgn == 0) return
    x = t
    if (sgn < 0) then
      x(:, 3) = t(:, 4)
      x(:, 4) = t(:, 3)
    end if
    do i = 1, 4
      a = tet_face(1, i); b = tet_face(2, i); c = tet_face(3, i)
      n(:, i) = cross(x(:, b) - x(:, a), x(:, c) - x(:, a))
      d(i) = dot_product(n(:, i), x(:, a) + x(:, b) + x(:, c))/3.0_wp
    end do
  end subroutine tet_planes

  !> Adds sgn times the moments of (tetrahedron q) cut by the planes (n, d)
  !> of another tetrahedron with bounding box [lo, hi] to vol and mom.
  pure subroutine add_clipped_tet(q, n, d, lo, hi, sgn, vol, mom)
    real(wp), intent(in) :: q(3, 4), n(3, 4), d(4), lo(3), hi(3), sgn
    real(wp), intent(inout) :: vol, mom(3)
    real(wp) :: v, m(3)
    integer :: i

    do i = 1, 3
      if (minval(q(i, :)) > hi(i) .or. maxval(q(i, :)) < lo(i)) return
    end do
    call tet_clip_planes(q, n, d, v, m)
    vol = vol + sgn*v
    mom = mom + sgn*m
  end subroutine add_clipped_tet

  !> The part of the tetrahedron q(3,4) (length; either orientation) inside
  !> the convex region n(:,i).x <= d(i), i = 1..size(d) (n need not be
  !> normalised): its volume vol >= 0 (length^3) and first moment mom
  !> (length^4). The four vertices are tested against every plane first: a
  !> plane with all of them strictly outside leaves nothing (as poly_clip
  !> would), and with none outside any plane the piece is the whole
  !> tetrahedron, so only planes that really cut it are clipped. At most
  !> poly_max_verts planes.
  pure subroutine tet_clip_planes(q, n, d, vol, mom)
    real(wp), intent(in) :: q(3, 4), n(:, :), d(:)
    real(wp), intent(out) :: vol, mom(3)
    type(poly_t) :: p
    real(wp) :: s
    integer :: i, k, nout, ncut, cut(poly_max_verts)

    vol = 0.0_wp
    mom = 0.0_wp
    ncut = 0
    do i = 1, size(d)
      nout = 0
      do k = 1, 4
        s = n(1, i)*q(1, k) + n(2, i)*q(2, k) + n(3, i)*q(3, k) - d(i)
        if (s > 0.0_wp) nout = nout + 1
      end do
      if (nout == 4) return
      if (nout > 0) then
        ncut = ncut + 1
        cut(ncut) = i
      end if
    end do
    if (ncut == 0) then
      vol = abs(tet_det(q))/6.0_wp
      mom = 0.25_wp*vol*(q(:, 1) + q(:, 2) + q(:, 3) + q(:, 4))
    else
      call set_tet(p, q)
      do k = 1, ncut
        call poly_clip(p, n(:, cut(k)), d(cut(k)))
        if (p%nv == 0) return
      end do
      call poly_first_moments(p, vol, mom)
    end if
  end subroutine tet_clip_planes

  !> Intersection of the tetrahedra t1 and t2 (3,4; length): volume vol
  !> (length^3) and first moment mom (length^4), times the product of their
  !> orientation signs (zero if either is flat).
  pure subroutine tet_intersect_tet(t1, t2, vol, mom)
    real(wp), intent(in) :: t1(3, 4), t2(3, 4)
    real(wp), intent(out) :: vol, mom(3)
    real(wp) :: a(3, 4), b(3, 4), n(3, 4), d(4), det2, lo(3), hi(3), o(3)
    integer :: i, s1

    vol = 0.0_wp
    mom = 0.0_wp
    ! local coordinates (see tet_intersect_hex)
    o = t1(:, 1)
    do i = 1, 4
      a(:, i) = t1(:, i) - o
      b(:, i) = t2(:, i) - o
    end do
    call tet_planes(a, n, d, s1)
    det2 = tet_det(b)
    if (s1 == 0 .or. .not. abs(det2) > 0.0_wp) return
    do i = 1, 3
      lo(i) = minval(a(i, :))
      hi(i) = maxval(a(i, :))
    end do
    call add_clipped_tet(b, n, d, lo, hi, real(s1, wp)*sign(1.0_wp, det2), vol, mom)
    mom = mom + vol*o
  end subroutine tet_intersect_tet

  !> Intersection of the tetrahedron tet(3,4) with the hexahedron xn(3,8)
  !> (length; any valid cell, faces need not be planar nor the cell convex):
  !> volume vol (length^3) and first moment mom = integral of x dV
  !> (length^4), signed by tet's orientation. It is the sum over the cell's
  !> 24 tetrahedra (`hex_tets`) of tet-tet intersections, each by clipping
  !> with four planes, which is exact because they partition the cell.
  pure subroutine tet_intersect_hex(tet, xn, vol, mom)
    real(wp), intent(in) :: tet(3, 4), xn(3, 8)
    real(wp), intent(out) :: vol, mom(3)
    real(wp) :: tets(3, 4, 24)
    integer :: i

    vol = 0.0_wp
    mom = 0.0_wp
    do i = 1, 3
      if (minval(xn(i, :)) > maxval(tet(i, :)) .or. maxval(xn(i, :)) < minval(tet(i, :))) return
    end do
    call hex_tets(xn, tets)
    call tet_intersect_split(tet, tets, vol, mom)
  end subroutine tet_intersect_hex

  !> Intersection of the tetrahedron tet(3,4) with a cell given by its
  !> split into tetrahedra tets(3,4,:) (e.g. the 24 of `hex_tets`, computed
  !> once per cell by the caller): volume and first moment, signed by tet's
  !> orientation, summed over the pieces as in `tet_intersect_hex`.
  pure subroutine tet_intersect_split(tet, tets, vol, mom)
    real(wp), intent(in) :: tet(3, 4), tets(:, :, :)
    real(wp), intent(out) :: vol, mom(3)
    real(wp) :: t(3, 4), x(3, 4), n(3, 4), d(4), lo(3), hi(3), det, o(3)
    integer :: i, k, sgn

    vol = 0.0_wp
    mom = 0.0_wp
    ! local coordinates about a vertex of tet: the round-off of the clipping
    ! then scales with the cell size, not with the distance to the origin
    o = tet(:, 1)
    do i = 1, 4
      t(:, i) = tet(:, i) - o
    end do
    call tet_planes(t, n, d, sgn)
    if (sgn == 0) return
    do i = 1, 3
      lo(i) = minval(t(i, :))
      hi(i) = maxval(t(i, :))
    end do
    do k = 1, size(tets, 3)
      do i = 1, 4
        x(:, i) = tets(:, i, k) - o
      end do
      det = tet_det(x)
      if (.not. abs(det) > 0.0_wp) cycle
      call add_clipped_tet(x, n, d, lo, hi, sign(1.0_wp, det), vol, mom)
    end do
    vol = real(sgn, wp)*vol
    mom = real(sgn, wp)*mom + vol*o
  end subroutine tet_intersect_split
end module geometry_polyhedron
