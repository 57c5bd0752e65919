!> A closed triangulated surface (an STL file's, `io_stl`) as a point
!> predicate: `surface_inside` says whether a point lies inside it, by the
!> parity of the crossings of the ray from the point along +x with the
!> triangles. The triangles are binned over the surface's box in y and z,
!> so a point tests only the triangles whose (y, z) boxes hold its (y, z).
!>
!> Robustness. A ray through a shared edge or vertex in the (y, z)
!> projection must cross exactly one of the triangles there, whatever the
!> round-off. Each projected edge's orientation test is evaluated from its
!> endpoints in one canonical order (lexicographic), so the two triangles
!> sharing the edge compute the same number, of opposite sign; a point
!> exactly on a projected edge is moved symbolically by (eps, eps^2) in
!> (y, z) (simulation of simplicity), which decides the zero case from the
!> edge's direction alone, the same way for both triangles. A triangle
!> seen edge-on (zero projected area) is never crossed. A point on the
!> surface itself may count as inside or outside (on a face crossed at its
!> own x it counts the crossing). The surface must be closed (watertight)
!> for the parity to mean inside; the orientation of its triangles does not
!> matter.
module mesh_surface
  use base_kinds, only: wp
  implicit none
  private
  public :: surface_t, surface_build, surface_inside, surface_box_level

  !> The triangles tri(3 coordinates, 3 vertices, n) (length), their box
  !> lo..hi, and the bins: nb(1) x nb(2) over the box's (y, z), bin b's
  !> triangles list(start(b):start(b+1)-1).
  type :: surface_t
    real(wp), allocatable :: tri(:, :, :)
    real(wp) :: lo(3) = 0.0_wp, hi(3) = 0.0_wp
    integer :: nb(2) = 1
    integer, allocatable :: start(:), list(:)
  end type surface_t

contains

  !> The surface of the triangles tri(3, 3, n), n >= 1, binned (about two
  !> triangles' (y, z) extents per bin side: a few triangles per bin on a
  !> fairly even mesh). stat: the allocations'.
  subroutine surface_build(tri, s, stat)
    real(wp), intent(in) :: tri(:, :, :)
    type(surface_t), intent(out) :: s
    integer, intent(out) :: stat
    integer, allocatable :: fill(:)
    integer :: n, t, d, b0(2), b1(2), i, j, b, pass
    real(wp) :: span(2)
    n = size(tri, 3)
    allocate(s%tri, source=tri, stat=stat)
    if (stat /= 0) return
    do d = 1, 3
      s%lo(d) = minval(tri(d, :, :))
      s%hi(d) = maxval(tri(d, :, :))
    end do
    span = s%hi(2:3) - s%lo(2:3)
    ! about sqrt(n) bins a side, fewer along a direction the surface is thin in
    do d = 1, 2
      s%nb(d) = max(1, min(1024, nint(sqrt(real(n, wp)))))
      if (.not. span(d) > 0.0_wp) s%nb(d) = 1
    end do
    allocate(s%start(s%nb(1)*s%nb(2) + 1), fill(s%nb(1)*s%nb(2)), stat=stat)
    if (stat /= 0) return
    ! pass 1 counts each bin's triangles, pass 2 lists them
    do pass = 1, 2
      fill = 0
      do t = 1, n
        b0 = bin_of(s, [minval(tri(2, :, t)), minval(tri(3, :, t))])
        b1 = bin_of(s, [maxval(tri(2, :, t)), maxval(tri(3, :, t))])
        do j = b0(2), b1(2)
          do i = b0(1), b1(1)
            b = i + s%nb(1)*(j - 1)
            fill(b) = fill(b) + 1
            if (pass == 2) s%list(s%start(b) + fill(b) - 1) = t
          end do
        end do
      end do
      if (pass == 1) then
        s%start(1) = 1
        do b = 1, size(fill)
          s%start(b + 1) = s%start(b) + fill(b)
        end do
        allocate(s%list(s%start(size(fill) + 1) - 1), stat=stat)
        if (stat /= 0) return
      end if
    end do
  end subroutine surface_build

  !> The bin (i, j) of the point whose (y, z) is q, clamped to the bins.
  pure function bin_of(s, q) result(ij)
    type(surface_t), intent(in) :: s
    real(wp), intent(in) :: q(2)
    integer :: ij(2), d
    do d = 1, 2
      ij(d) = 1
      if (s%nb(d) > 1) ij(d) = min(s%nb(d), max(1, 1 + int(real(s%nb(d), wp)*(q(d) - s%lo(d + 1))/ &
                                                         (s%hi(d + 1) - s%lo(d + 1)))))
    end do
  end function bin_of

  !> Whether the point p (length) lies inside the surface s (module notes).
  pure logical function surface_inside(s, p) result(inside)
    type(surface_t), intent(in) :: s
    real(wp), intent(in) :: p(3)
    integer :: ij(2), b, k, t, e, sgn, ncross
    real(wp) :: w(3), det, xc
    inside = .false.
    if (any(p < s%lo) .or. any(p > s%hi)) return
    ij = bin_of(s, p(2:3))
    b = ij(1) + s%nb(1)*(ij(2) - 1)
    ncross = 0
    do k = s%start(b), s%start(b + 1) - 1
      t = s%list(k)
      associate (v => s%tri(:, :, t))
        ! the projected triangle's orientation (exactly 0: seen edge-on)
        det = (v(2, 2) - v(2, 1))*(v(3, 3) - v(3, 1)) - (v(3, 2) - v(3, 1))*(v(2, 3) - v(2, 1))
        if (.not. abs(det) > 0.0_wp) cycle
        sgn = merge(1, -1, det > 0.0_wp)
        ! p inside the projection: on the triangle's side of each edge
        do e = 1, 3
          w(e) = edge_side(v(2:3, e), v(2:3, mod(e, 3) + 1), p(2:3))
          if (sgn*w(e) < 0.0_wp) exit
        end do
        if (e <= 3) cycle
        ! the crossing's x (barycentric weights w/det: w(e) is opposite the
        ! vertex after the edge's end)
        xc = (w(2)*v(1, 1) + w(3)*v(1, 2) + w(1)*v(1, 3))/(w(1) + w(2) + w(3))
        if (xc >= p(1)) ncross = ncross + 1
      end associate
    end do
    inside = mod(ncross, 2) == 1
  end function surface_inside

  !> Twice the signed area of (a, b, q) in the (y, z) plane, from the edge's
  !> endpoints in lexicographic order (negated if a, b come the other way),
  !> never exactly 0: on the line, q moved by (eps, eps^2) decides (module
  !> notes). So the two triangles of an edge get opposite signs exactly.
  pure real(wp) function edge_side(a, b, q) result(w)
    real(wp), intent(in) :: a(2), b(2), q(2)
    real(wp) :: u(2), v(2), f
    f = 1.0_wp
    u = a
    v = b
    if (b(1) < a(1) .or. (.not. b(1) > a(1) .and. b(2) < a(2))) then
      u = b
      v = a
      f = -1.0_wp
    end if
    w = (v(1) - u(1))*(q(2) - u(2)) - (v(2) - u(2))*(q(1) - u(1))
    if (.not. abs(w) > 0.0_wp) then
      ! d/d eps of the area with q + (eps, eps^2): -(v2 - u2), then v1 - u1
      w = -(v(2) - u(2))
      if (.not. abs(w) > 0.0_wp) w = v(1) - u(1)
      w = sign(tiny(1.0_wp), w)
    end if
    w = f*w
  end function edge_side

  !> A lower bound of the distance from p to the surface where p lies
  !> outside its box (the distance to the box), -huge inside the box: a
  !> 1-Lipschitz level function that is > 0 only outside the surface.
  pure real(wp) function surface_box_level(s, p) result(phi)
    type(surface_t), intent(in) :: s
    real(wp), intent(in) :: p(3)
    real(wp) :: d(3)
    d = max(s%lo - p, p - s%hi, 0.0_wp)
    phi = norm2(d)
    if (.not. phi > 0.0_wp) phi = -huge(1.0_wp)
  end function surface_box_level
end module mesh_surface
