!> Volumes and centroids of the scene's shapes in a hexahedral cell: the
!> initial volume fractions and material centroids of the cells a region
!> boundary cuts (the mixed cells' MoF references, Sect. 5.4), by the same
!> polyhedron clipping as the remap.
!>
!> Shapes (deck: &region shape): all, box [lo, hi], sphere (center, radius),
!> half_space n.(x - center) >= 0, cylinder (radius about the axis through
!> center, between lo and hi along it). Regions are applied in order, a
!> later one taking what it covers from the earlier ones ("last wins").
!>
!> Method. Each shape has a level function phi, <= 0 inside, that changes by
!> at most the distance moved (1-Lipschitz): a ball of radius rho about x0
!> lies inside the shape if phi(x0) < -rho and outside if phi(x0) > rho,
!> whatever the shape does in between. The cell is split recursively in its
!> natural coordinates (octants of [-1,1]^3; a piece is the trilinear image
!> of its sub-cube, inside the ball about its centre through its farthest
!> corner). A piece that the last region covering it holds whole, with no
!> later region crossing it, goes to that region whole: its volume and first
!> moment by 2-point Gauss quadrature, exact for the trilinear map (det J is
!> quadratic and x det J cubic in each natural coordinate). A piece crossed
!> by region boundaries is cut exactly (`poly_clip`, regions taken from the
!> last: each one's part is the piece clipped by all its bounding planes,
!> the rest passes on as the convex pieces outside one of them) when those
!> boundaries are planes (box faces, half-spaces, a cylinder's ends) and the
!> piece is a parallelepiped (every piece of a cell of a box grid, at any
!> depth: there the result is exact to round-off without refinement);
!> otherwise it is split further, down to `depth` levels, where a curved
!> boundary (sphere, cylinder side) is taken as its tangent plane at the
!> point nearest the piece's centre and the piece as its six tetrahedra. A
!> curved shape is taken to miss a piece whose bounding box it does not
!> reach (`misses_box`): the tangent plane, which holds the shape, would
!> otherwise give a piece the shape only touches a spurious sliver.
!>
!> Accuracy on curved boundaries: the tangent plane of a sphere of radius R
!> misses a sliver s^2/(2R) thick at a distance s from its foot, so over a
!> leaf of size hl = h 2^-depth the volume error is ~hl^4/(12 R) and over the
!> leaves along the surface of one cell ~(hl/h)^2 h^3 h/(12 R): a volume
!> fraction error of 2^-(2 depth) h/(12 R), 8e-5 h/R at depth 5, always
!> on the side of the sphere (the tangent half-space holds the ball).
!> Centroids are first moments over the same pieces, as accurate.
module geometry_shapes
  use base_kinds, only: wp
  use mesh_geometry, only: hex_trilinear, hex_jacobian
  use mesh_shapes, only: shape_t, shape_inside, shape_level, SHAPE_ALL, SHAPE_BOX, SHAPE_SPHERE, SHAPE_HALF_SPACE, &
                         SHAPE_CYLINDER
  use geometry_polyhedron, only: poly_t, poly_from_hex, poly_from_tet, poly_clip, poly_first_moments
  implicit none
  private
  public :: shape_t, shape_inside, shape_level, shapes_cell_moments, shapes_max_depth
  public :: SHAPE_ALL, SHAPE_BOX, SHAPE_SPHERE, SHAPE_HALF_SPACE, SHAPE_CYLINDER

  !> Deepest split (a leaf 2^-8 of the cell) `shapes_cell_moments` accepts.
  integer, parameter :: shapes_max_depth = 8
  !> Most convex pieces one leaf is cut into while regions are taken from it.
  integer, parameter :: max_pieces = 48
  !> Most bounding planes of one region within a leaf (a box's six).
  integer, parameter :: max_planes = 6
  !> A curved shape whose nearest point to a piece is within this of its
  !> radius (squared, relative) only touches it (`misses_box`): an overlap
  !> 1e-12 R deep has no volume worth keeping.
  real(wp), parameter :: touch_tol = 1.0e-12_wp

  !> The nodes of the six tetrahedra of a hexahedron around its diagonal
  !> from node 1 to node 8 (node a = 1 + i + 2j + 4k).
  integer, parameter :: kuhn(4, 6) = reshape([1, 2, 4, 8,  1, 4, 3, 8,  1, 3, 7, 8,  1, 7, 5, 8, &
                                              1, 5, 6, 8,  1, 6, 2, 8], [4, 6])

  !> A sub-cube of the natural coordinates waiting to be looked at.
  type :: box_t
    real(wp) :: lo(3) = -1.0_wp
    integer :: level = 0
  end type box_t

contains

  !> Volume vol(r) (length^3) and first moment mom(:,r) about the mean of the
  !> nodes (length^4) of the part of the cell xn(3,8) that region r holds
  !> (the last of shapes(1:n) that contains a point holds it), r = 1..n;
  !> vol(0), mom(:,0): the part no region holds. Curved boundaries are
  !> resolved on leaves of 2^-depth of the cell (module header; depth is
  !> clipped to 0..shapes_max_depth). The volumes add up to the volume of the
  !> trilinear cell (the 24-tetrahedron volume of a cell with planar faces).
  pure subroutine shapes_cell_moments(xn, shapes, depth, vol, mom)
    real(wp), intent(in) :: xn(3, 8)
    type(shape_t), intent(in) :: shapes(:)
    integer, intent(in) :: depth
    real(wp), intent(out) :: vol(0:), mom(:, 0:)
    type(box_t) :: stack(8*shapes_max_depth + 1), b
    real(wp) :: xc(3), xr(3, 8), ys(3, 8), y0(3), rho, w, phi, xi(3)
    real(wp) :: blo(3), bhi(3)
    integer :: ns, top, r, rstar, ncut, cuts(size(shapes)), a, dmax, i
    logical :: exact, affine, ok

    ns = size(shapes)
    vol(0:ns) = 0.0_wp
    mom(:, 0:ns) = 0.0_wp
    dmax = max(0, min(depth, shapes_max_depth))
    do i = 1, 3
      xc(i) = 0.125_wp*sum(xn(i, :))
    end do
    do a = 1, 8
      xr(:, a) = xn(:, a) - xc
    end do
    top = 1
    stack(1) = box_t(lo=[-1.0_wp, -1.0_wp, -1.0_wp], level=0)
    do while (top > 0)
      b = stack(top)
      top = top - 1
      w = 2.0_wp**(1 - b%level)
      ! the piece's corners and centre (relative to xc), and a ball holding it
      do a = 1, 8
        xi = b%lo + w*real([mod(a - 1, 2), mod((a - 1)/2, 2), (a - 1)/4], wp)
        ys(:, a) = hex_trilinear(xr, xi)
      end do
      y0 = hex_trilinear(xr, b%lo + 0.5_wp*w)
      rho = 0.0_wp
      do a = 1, 8
        rho = max(rho, norm2(ys(:, a) - y0))
      end do
      rho = rho*(1.0_wp + 1.0e-12_wp) + 1.0e-14_wp*maxval(abs(xr))
      ! the last region holding the whole piece, and the later ones crossing it
      rstar = 0
      ncut = 0
      exact = .true.
      do i = 1, 3
        blo(i) = minval(ys(i, :)) + xc(i)
        bhi(i) = maxval(ys(i, :)) + xc(i)
      end do
      do r = ns, 1, -1
        phi = shape_level(shapes(r), y0 + xc)
        if (phi < -rho) then
          rstar = r
          exit
        else if (.not. phi > rho .and. .not. misses_box(shapes(r), blo, bhi)) then
          ncut = ncut + 1
          cuts(ncut) = r
          if (.not. planar_here(shapes(r), y0 + xc, rho)) exact = .false.
        end if
      end do
      if (ncut == 0) then
        call add_whole(xr, b%lo, w, vol(rstar), mom(:, rstar))
        cycle
      end if
      affine = is_affine(ys)
      if (b%level < dmax .and. .not. (exact .and. affine)) then
        do a = 1, 8
          top = top + 1
          stack(top) = box_t(lo=b%lo + 0.5_wp*w*real([mod(a - 1, 2), mod((a - 1)/2, 2), (a - 1)/4], wp), &
                             level=b%level + 1)
        end do
        cycle
      end if
      call cut_leaf(shapes, xc, ys, y0, rho, affine, cuts(ncut:1:-1), rstar, vol, mom, ok)
      ! (not with realistic shapes: too many pieces) the leaf goes whole
      ! to the region at its centre
      if (.not. ok) then
        r = region_of(shapes, y0 + xc, cuts(ncut:1:-1), rstar)
        call add_whole(xr, b%lo, w, vol(r), mom(:, r))
      end if
    end do
  end subroutine shapes_cell_moments

  !> Adds the volume and first moment of the piece [lo, lo + w]^3 (natural
  !> coordinates) of the cell xr(3,8) to vol and mom: 2-point Gauss
  !> quadrature in each direction, exact for the trilinear map.
  pure subroutine add_whole(xr, lo, w, vol, mom)
    real(wp), intent(in) :: xr(3, 8), lo(3), w
    real(wp), intent(inout) :: vol, mom(3)
    real(wp) :: g(3), jw
    integer :: q
    do q = 1, 8
      g = lo + w*(0.5_wp + (real([mod(q - 1, 2), mod((q - 1)/2, 2), (q - 1)/4], wp) - 0.5_wp)/sqrt(3.0_wp))
      jw = hex_jacobian(xr, g)*(0.5_wp*w)**3
      vol = vol + jw
      mom = mom + jw*hex_trilinear(xr, g)
    end do
  end subroutine add_whole

  !> The leaf with corners ys(3,8) (relative to xc; centre y0, inside the
  !> ball of radius rho about it) shared among the regions crossing it (cut,
  !> in deck order; later ones take their part first), the rest to base
  !> (0: none): volumes and first moments added to vol(0:), mom(:,0:).
  !> Nothing is added and done is false if the pieces overflow.
  pure subroutine cut_leaf(shapes, xc, ys, y0, rho, affine, cut, base, vol, mom, done)
    type(shape_t), intent(in) :: shapes(:)
    real(wp), intent(in) :: xc(3), ys(3, 8), y0(3), rho
    logical, intent(in) :: affine
    integer, intent(in) :: cut(:), base
    real(wp), intent(inout) :: vol(0:), mom(:, 0:)
    logical, intent(out) :: done
    type(poly_t) :: p(max_pieces), q(max_pieces), t
    real(wp) :: pn(3, max_planes), pd(max_planes), v, m(3), tet(3, 4), lv(0:size(shapes)), lm(3, 0:size(shapes))
    integer :: np, nq, i, j, k, npl, kk, ns
    logical :: ok

    done = .false.
    np = 0
    if (affine) then
      np = 1
      p(1) = poly_from_hex(ys)
    else
      do k = 1, 6
        do j = 1, 4
          tet(:, j) = ys(:, kuhn(j, k))
        end do
        np = np + 1
        p(np) = poly_from_tet(tet)
      end do
    end if
    lv = 0.0_wp
    lm = 0.0_wp
    do i = size(cut), 1, -1
      call region_planes(shapes(cut(i)), y0 + xc, rho, xc, pn, pd, npl)
      nq = 0
      do k = 1, np
        ! inside: clipped by every plane
        t = p(k)
        do j = 1, npl
          call poly_clip(t, pn(:, j), pd(j), ok)
          if (.not. ok) return
          if (t%nv == 0) exit
        end do
        call poly_first_moments(t, v, m)
        lv(cut(i)) = lv(cut(i)) + v
        lm(:, cut(i)) = lm(:, cut(i)) + m
        ! outside: beyond plane j and inside planes 1..j-1
        do j = 1, npl
          t = p(k)
          do kk = 1, j - 1
            call poly_clip(t, pn(:, kk), pd(kk), ok)
            if (.not. ok) return
            if (t%nv == 0) exit
          end do
          if (t%nv == 0) exit
          call poly_clip(t, -pn(:, j), -pd(j), ok)
          if (.not. ok) return
          if (t%nv == 0) cycle
          if (nq == max_pieces) return
          nq = nq + 1
          q(nq) = t
        end do
      end do
      np = nq
      p(1:np) = q(1:np)
    end do
    do k = 1, np
      call poly_first_moments(p(k), v, m)
      lv(base) = lv(base) + v
      lm(:, base) = lm(:, base) + m
    end do
    ns = size(shapes)
    vol(0:ns) = vol(0:ns) + lv
    mom(:, 0:ns) = mom(:, 0:ns) + lm
    done = .true.
  end subroutine cut_leaf

  !> The last of the regions cand (indices into shapes) that contains x,
  !> else base.
  pure integer function region_of(shapes, x, cand, base) result(r)
    type(shape_t), intent(in) :: shapes(:)
    real(wp), intent(in) :: x(3)
    integer, intent(in) :: cand(:), base
    integer :: i
    r = base
    do i = size(cand), 1, -1
      if (shape_inside(shapes(cand(i)), x)) then
        r = cand(i)
        return
      end if
    end do
  end function region_of

  !> True if the curved shape sh (sphere, cylinder) has no volume in the box
  !> [blo, bhi] (which holds a piece): the box's nearest point to the centre
  !> (axis) is at least the radius away (less touch_tol of it: what round-off
  !> of the coordinates can do to a shape through a node). Exact for the axis-aligned pieces
  !> of a box grid; it keeps the tangent plane, which holds the shape, from
  !> giving a piece the shape only touches (a sphere through a node) a
  !> spurious sliver. False for other shapes (their planes are exact).
  pure logical function misses_box(sh, blo, bhi)
    type(shape_t), intent(in) :: sh
    real(wp), intent(in) :: blo(3), bhi(3)
    real(wp) :: d(3)
    select case (sh%kind)
    case (SHAPE_SPHERE)
      d = max(blo - sh%center, 0.0_wp, sh%center - bhi)
      misses_box = sum(d**2) >= sh%radius**2*(1.0_wp - touch_tol)
    case (SHAPE_CYLINDER)
      d = max(blo - sh%center, 0.0_wp, sh%center - bhi)
      d(sh%axis) = 0.0_wp
      misses_box = sum(d**2) >= sh%radius**2*(1.0_wp - touch_tol) .or. blo(sh%axis) >= sh%hi(sh%axis) .or. &
                   bhi(sh%axis) <= sh%lo(sh%axis)
    case default
      misses_box = .false.
    end select
  end function misses_box

  !> True if the boundary of sh within the ball (x0, rho) is made of planes
  !> only (so that clipping is exact at any size of the piece).
  pure logical function planar_here(sh, x0, rho)
    type(shape_t), intent(in) :: sh
    real(wp), intent(in) :: x0(3), rho
    real(wp) :: d(3)
    select case (sh%kind)
    case (SHAPE_SPHERE)
      planar_here = .false.
    case (SHAPE_CYLINDER)
      d = x0 - sh%center
      d(sh%axis) = 0.0_wp
      planar_here = abs(sqrt(sum(d**2)) - sh%radius) > rho
    case default
      planar_here = .true.
    end select
  end function planar_here

  !> The planes n.y <= d (y relative to xc) whose intersection is the shape
  !> sh within the ball (x0, rho) (x0 absolute): exact for box faces,
  !> half-spaces and a cylinder's ends, the tangent plane at the point
  !> nearest x0 for a sphere or a cylinder's side; planes the ball lies
  !> wholly inside of are left out.
  pure subroutine region_planes(sh, x0, rho, xc, pn, pd, npl)
    type(shape_t), intent(in) :: sh
    real(wp), intent(in) :: x0(3), rho, xc(3)
    real(wp), intent(out) :: pn(:, :), pd(:)
    integer, intent(out) :: npl
    real(wp) :: u(3), d(3), r
    integer :: i, a

    npl = 0
    select case (sh%kind)
    case (SHAPE_BOX)
      do i = 1, 3
        u = 0.0_wp
        u(i) = 1.0_wp
        if (x0(i) + rho > sh%hi(i)) call push_plane(pn, pd, npl, u, sh%hi(i) - xc(i))
        if (x0(i) - rho < sh%lo(i)) call push_plane(pn, pd, npl, -u, -(sh%lo(i) - xc(i)))
      end do
    case (SHAPE_HALF_SPACE)
      u = sh%normal/norm2(sh%normal)
      call push_plane(pn, pd, npl, -u, dot_product(u, xc - sh%center))
    case (SHAPE_SPHERE)
      d = x0 - sh%center
      r = sqrt(sum(d**2))
      if (r > 0.0_wp) then
        u = d/r
        call push_plane(pn, pd, npl, u, sh%radius + dot_product(u, sh%center - xc))
      end if
    case (SHAPE_CYLINDER)
      a = sh%axis
      d = x0 - sh%center
      d(a) = 0.0_wp
      r = sqrt(sum(d**2))
      if (r > 0.0_wp .and. abs(r - sh%radius) <= rho) then
        u = d/r
        call push_plane(pn, pd, npl, u, sh%radius + dot_product(u, sh%center - xc))
      end if
      u = 0.0_wp
      u(a) = 1.0_wp
      if (x0(a) + rho > sh%hi(a)) call push_plane(pn, pd, npl, u, sh%hi(a) - xc(a))
      if (x0(a) - rho < sh%lo(a)) call push_plane(pn, pd, npl, -u, -(sh%lo(a) - xc(a)))
    end select
  end subroutine region_planes

  !> Appends the plane n.y <= dd to pn(:,1:npl), pd(1:npl) (if there is room).
  pure subroutine push_plane(pn, pd, npl, n, dd)
    real(wp), intent(inout) :: pn(:, :), pd(:)
    integer, intent(inout) :: npl
    real(wp), intent(in) :: n(3), dd
    if (npl == size(pd)) return
    npl = npl + 1
    pn(:, npl) = n
    pd(npl) = dd
  end subroutine push_plane

  !> True if the hexahedron ys(3,8) is a parallelepiped to round-off (its
  !> trilinear map is affine: opposite edges are equal vectors).
  pure logical function is_affine(ys)
    real(wp), intent(in) :: ys(3, 8)
    real(wp) :: e(3), scale
    scale = maxval(abs(ys(:, 8) - ys(:, 1))) + maxval(abs(ys(:, 7) - ys(:, 2)))
    e = abs(ys(:, 1) + ys(:, 4) - ys(:, 2) - ys(:, 3)) + abs(ys(:, 5) + ys(:, 8) - ys(:, 6) - ys(:, 7)) + &
        abs(ys(:, 1) + ys(:, 6) - ys(:, 2) - ys(:, 5)) + abs(ys(:, 1) + ys(:, 7) - ys(:, 3) - ys(:, 5))
    is_affine = maxval(e) <= 1.0e-13_wp*scale
  end function is_affine
end module geometry_shapes
