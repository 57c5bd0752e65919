!> Moment-of-fluid (MoF) interface reconstruction in a hexahedral cell, the
!> first step of the remap of Sect. 5.4: the old mixed cells are cut into
!> single-material polyhedra by planar interfaces (Fig. 12) that the new
!> cells' tetrahedra are then clipped against (Eq. (54)-(57)). MoF is the
!> method the paper adopts ([22,74], after Dyadechko & Shashkov and Ahn &
!> Shashkov 2007): in a cell holding the volume fraction f and the centroid
!> c_ref of a material, the interface is the plane n.x = d that
!>   (i)  cuts exactly f times the cell's volume off on the side n.x <= d
!>        (d is a 1D root for each n), and
!>   (ii) of all such planes, makes the centroid c(n) of the cut closest to
!>        c_ref: n minimises |c(n) - c_ref| over unit vectors.
!> More than two materials are handled by nested dissection: material 1 is
!> cut from the cell, material 2 from what remains, and so on.
!>
!> Geometry. The cell (any hexahedron, faces need not be planar nor the cell
!> convex) is its 24-tetrahedron split (`hex_tets`, Fig. 7), exactly the
!> volume `hex_volume` sees; each tetrahedron is a `poly_t` clipped by the
!> plane (`poly_clip`), and a piece of an inverted tetrahedron of a tangled
!> cell counts with a minus sign, as in `tet_intersect_hex`. "What remains"
!> after a cut is again at most 24 convex pieces (`mof_pieces_t`), so nested
!> cuts reuse the same code. A box with edges along the axes (the cells of
!> an Eulerian grid) is one convex piece instead, the same region: a cut of
!> it is one clip, not one per tetrahedron the plane crosses. Pieces are
!> stored relative to the mean of the cell's nodes (`origin`): round-off
!> then scales with the cell, not with its distance from the coordinate
!> origin.
!>
!> Volume root (i). On a unit n the cut volume V(d) is a piecewise cubic of
!> d whose pieces join at the projections n.x of the pieces' vertices. The
!> root is found by Newton's method on V^(1/k), k the exponent of the power
!> law V ~ (d - d_min)^k through the current point (exact in one step at a
!> corner, where V is cubic; the derivative is the cut's area, which every
!> evaluation yields), from a guess or from the cone estimate (V/V_region)^(1/3)
!> of the range of d, falling back to bisection over the sorted projections
!> until one cubic piece brackets the root, the exact cubic through four
!> values on that piece, and Illinois regula falsi as a safeguard. The
!> smaller side is the one solved for, to 1e-13 of its own volume (or until
!> a step or the bracket is round-off wide: a thin slab's volume is not
!> known better than eps of the cell's); 1e-12 of the cell's volume is
!> guaranteed (`ok`).
!>
!> Centroid fit (ii). Let F be the interface polygon, A its area, x_F its
!> centroid and J = int_F (x - x_F)(x - x_F)^T dA its second moment. Tilting
!> n by dn (dn.n = 0) at fixed volume moves the plane by dd = dn.x_F and the
!> cut's centroid by dc = -J dn / V (the analytic derivative of [74]), so
!> with n(a, b) = exp-map rotation of n by a t1 + b t2 (two angles in the
!> plane tangent to the sphere of normals) the Jacobian of the residual
!> r = c - c_ref is [-J t1, -J t2]/V, and Gauss-Newton with a step cap and a
!> halving line search converges quadratically when the interface is a plane
!> (zero residual). The start is the direction from c_ref to the cell's
!> centroid, measured in the cell's logical frame (so a long or sheared cell
!> starts as well as a cube), or a normal the caller gives (the plane the
!> interface had: from it a search whose centroid that plane still matches
!> needs no iteration); if the search ends far from its target (a local
!> minimum) it is repeated from the plain Euclidean direction (after a
!> given start: from the logical one) with the iterations left, and the
!> better plane kept. The smaller side is the
!> one fitted (an equivalent objective, free of cancellation for nearly
!> full cells). Iterations are capped (default 50, both starts together);
!> the routine always returns the best plane found, which cuts the exact
!> volume whatever happened.
module geometry_mof
  use base_kinds, only: wp, huge_wp
  use mesh_geometry, only: cross, hex_tets, tet_det
  use geometry_polyhedron, only: poly_t, poly_max_verts, poly_rel_tol, poly_set_tet, poly_from_hex, poly_clip, &
                              poly_first_moments, slot_of, poly_copy, tet_clip_moments
  implicit none
  private
  public :: mof_pieces_t, mof_max_pieces, mof_max_iter_default, mof_angle_tol
  public :: mof_cell_pieces, mof_pieces_moments, mof_material_pieces
  public :: mof_cut_volume, mof_plane_for_volume, mof_reconstruct, mof_reconstruct_nested, mof_nested_cut

  !> Most pieces a region of a cell is made of: the 24 tetrahedra of the
  !> split, each of which stays one convex piece under any number of cuts.
  integer, parameter :: mof_max_pieces = 24
  !> Default cap on the Gauss-Newton iterations of one material.
  integer, parameter :: mof_max_iter_default = 50
  !> Gauss-Newton stops when an accepted step turns n by less than this
  !> (radians); the error left is then ~ its square for a planar interface.
  real(wp), parameter :: mof_angle_tol = 1.0e-8_wp
  !> Largest rotation of n in one Gauss-Newton step (radians).
  real(wp), parameter :: max_turn = 0.5_wp
  !> A search that ends with the smaller side's centroid error above this
  !> times that side's size (cube root of its volume) is tried again from
  !> a second start.
  real(wp), parameter :: restart_tol = 1.0e-3_wp
  !> The same after a search that started from a given plane (`mof_region`'s
  !> guess).
  real(wp), parameter :: restart_tol_guess = 3.0e-2_wp
  !> A centroid error below this times the cell size is round-off of the
  !> centroid itself (~64 units): no plane can do measurably better.
  real(wp), parameter :: err_roundoff = 64.0_wp*epsilon(1.0_wp)
  !> Most vertices of a cut polygon `add_cap_polygon` takes: a tetrahedron's
  !> cut by one plane (`tet_clip_moments`) is a triangle or a quadrilateral.
  integer, parameter :: max_cap = 4

  !> A region of a cell: the convex polyhedra p(1:np), vertices relative to
  !> `origin` (length), each counted with the orientation sign sgn (+1, or
  !> -1 for a piece of an inverted tetrahedron of a tangled cell); vol and
  !> mom are each piece's unsigned volume (length^3) and first moment about
  !> origin (length^4). The region's volume is sum(sgn*vol). No default
  !> values (as `poly_t`: a local would be copied whole, 24 pieces, at every
  !> entry); `mof_cell_pieces` fills a region before it is read.
  type :: mof_pieces_t
    integer :: np
    real(wp) :: origin(3)
    type(poly_t) :: p(mof_max_pieces)
    real(wp) :: sgn(mof_max_pieces)
    real(wp) :: vol(mof_max_pieces)
    real(wp) :: mom(3, mof_max_pieces)
  end type mof_pieces_t

  !> A region cut by n.x <= dl (local coordinates, unit n): the cut's signed
  !> volume and first moment, those of the side that was solved for (the
  !> smaller; computed directly, not as a difference), and the interface
  !> polygon's area, first and second moments (all about the region's origin).
  type :: cut_t
    real(wp) :: dl = 0.0_wp
    real(wp) :: vol = 0.0_wp
    real(wp) :: mom(3) = 0.0_wp
    real(wp) :: svol = 0.0_wp
    real(wp) :: smom(3) = 0.0_wp
    real(wp) :: area = 0.0_wp
    real(wp) :: f1(3) = 0.0_wp
    real(wp) :: f2(3, 3) = 0.0_wp
  end type cut_t

contains

  ! ------------------------------------------------------------ regions

  !> The cell with nodes xn(3,8) (length, order a = 1 + i + 2j + 4k) as the
  !> region of its 24 tetrahedra (Fig. 7); tetrahedra flat to round-off are
  !> left out (they have no volume). pcs is overwritten (intent(inout): an
  !> intent(out) argument would be default-initialised whole, 24 pieces of
  !> poly_max_verts vertices, at every call).
  pure subroutine mof_cell_pieces(xn, pcs)
    real(wp), intent(in) :: xn(3, 8)
    type(mof_pieces_t), intent(inout) :: pcs
    real(wp) :: x(3, 8), tets(3, 4, 24), det, scale
    integer :: i, k

    pcs%np = 0
    do i = 1, 3
      pcs%origin(i) = 0.125_wp*sum(xn(i, :))
    end do
    do i = 1, 8
      x(:, i) = xn(:, i) - pcs%origin
    end do
    if (is_box(xn)) then
      ! (a box, the cells of an Eulerian grid: one convex piece, the same
      ! region as its 24 tetrahedra; every cut of it costs one clip)
      pcs%np = 1
      pcs%p(1) = poly_from_hex(x)
      pcs%sgn(1) = 1.0_wp
      call poly_first_moments(pcs%p(1), pcs%vol(1), pcs%mom(:, 1))
      return
    end if
    scale = maxval(abs(x))
    call hex_tets(x, tets)
    do k = 1, 24
      det = tet_det(tets(:, :, k))
      if (.not. abs(det) > epsilon(1.0_wp)*scale**3) cycle
      pcs%np = pcs%np + 1
      call poly_set_tet(pcs%p(pcs%np), tets(:, :, k))
      pcs%sgn(pcs%np) = sign(1.0_wp, det)
      call poly_first_moments(pcs%p(pcs%np), pcs%vol(pcs%np), pcs%mom(:, pcs%np))
    end do
  end subroutine mof_cell_pieces

  !> Whether the hexahedron xn(3,8) (node a = 1 + i + 2j + 4k) is a box
  !> with edges along the axes and positive extent in each, to the last bit
  !> (each node's x from its i, y from its j, z from its k).
  pure logical function is_box(xn) result(box)
    real(wp), intent(in) :: xn(3, 8)
    integer, parameter :: lo(4, 3) = reshape([1, 3, 5, 7,  1, 2, 5, 6,  1, 2, 3, 4], [4, 3])
    integer, parameter :: hi(4, 3) = reshape([2, 4, 6, 8,  3, 4, 7, 8,  5, 6, 7, 8], [4, 3])
    integer :: d
    box = .true.
    do d = 1, 3
      box = box .and. .not. (any(abs(xn(d, lo(:, d)) - xn(d, lo(1, d))) > 0.0_wp) .or. &
                             any(abs(xn(d, hi(:, d)) - xn(d, hi(1, d))) > 0.0_wp)) .and. xn(d, hi(1, d)) > xn(d, lo(1, d))
    end do
  end function is_box

  !> Signed volume vol (length^3) and centroid (length, global coordinates)
  !> of the region pcs; a region of no volume has its origin as centroid.
  pure subroutine mof_pieces_moments(pcs, vol, centroid)
    type(mof_pieces_t), intent(in) :: pcs
    real(wp), intent(out) :: vol
    real(wp), intent(out) :: centroid(3)
    real(wp) :: mom(3)

    call region_moments(pcs, vol, mom)
    centroid = pcs%origin
    if (abs(vol) > 0.0_wp) centroid = centroid + mom/vol
  end subroutine mof_pieces_moments

  !> Signed volume and first moment about the origin of a region.
  pure subroutine region_moments(pcs, vol, mom)
    type(mof_pieces_t), intent(in) :: pcs
    real(wp), intent(out) :: vol, mom(3)
    integer :: k
    vol = 0.0_wp
    mom = 0.0_wp
    do k = 1, pcs%np
      vol = vol + pcs%sgn(k)*pcs%vol(k)
      mom = mom + pcs%sgn(k)*pcs%mom(:, k)
    end do
  end subroutine region_moments

  !> Clips every piece of pcs to n.x <= dl (local coordinates; n need not be
  !> unit, see `poly_clip`), drops the emptied pieces and updates the
  !> moments. ok becomes false if a piece would exceed `poly_max_verts`.
  pure subroutine region_clip(pcs, n, dl, ok)
    type(mof_pieces_t), intent(inout) :: pcs
    real(wp), intent(in) :: n(3), dl
    logical, intent(inout) :: ok
    integer :: k, m
    logical :: okc

    m = 0
    do k = 1, pcs%np
      call poly_clip(pcs%p(k), n, dl, okc)
      if (.not. okc) ok = .false.
      if (pcs%p(k)%nv == 0) cycle
      m = m + 1
      if (m < k) then
        pcs%p(m) = pcs%p(k)
        pcs%sgn(m) = pcs%sgn(k)
      end if
      call poly_first_moments(pcs%p(m), pcs%vol(m), pcs%mom(:, m))
    end do
    pcs%np = m
  end subroutine region_clip

  !> The region of material k after the nested dissection n(:,j).x <= d(j),
  !> j = 1..k (global coordinates; the output of `mof_reconstruct_nested`):
  !> the cell minus materials 1..k-1, cut by plane k. ok is false if a piece
  !> ran out of vertex capacity (not with realistic numbers of materials).
  pure subroutine mof_material_pieces(xn, n, d, k, pcs, ok)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(in) :: n(:, :)
    real(wp), intent(in) :: d(:)
    integer, intent(in) :: k
    type(mof_pieces_t), intent(inout) :: pcs   !< (overwritten: `mof_cell_pieces`)
    logical, intent(out) :: ok
    integer :: j

    ok = k >= 1 .and. k <= size(d) .and. size(n, 1) == 3 .and. size(n, 2) >= k
    pcs%np = 0
    if (.not. ok) return
    call mof_cell_pieces(xn, pcs)
    do j = 1, k - 1
      call region_clip(pcs, -n(:, j), -(d(j) - dot_product(n(:, j), pcs%origin)), ok)
    end do
    call region_clip(pcs, n(:, k), d(k) - dot_product(n(:, k), pcs%origin), ok)
  end subroutine mof_material_pieces

  ! ------------------------------------------------------ one plane cut

  !> Adds to (area, f1, f2) the area, first and second moments (about the
  !> origin) of the faces of the convex piece p that lie on the plane
  !> n.x = dl (every vertex within tolf), times sgn. Such a face of a piece
  !> kept below the plane faces +n; a face facing -n is skipped.
  pure subroutine add_cap_faces(p, n, dl, tolf, sgn, area, f1, f2)
    type(poly_t), intent(in) :: p
    real(wp), intent(in) :: n(3), dl, tolf, sgn
    real(wp), intent(inout) :: area, f1(3), f2(3, 3)
    logical :: used(3, poly_max_verts)
    integer :: face(poly_max_verts + 1), nv, m, v, k, j, prev, cur, nxt, it, i
    real(wp) :: s(poly_max_verts), a(3), b(3), c(3), tot

    nv = p%nv
    if (nv < 4) return
    do v = 1, nv
      s(v) = abs(n(1)*p%x(1, v) + n(2)*p%x(2, v) + n(3)*p%x(3, v) - dl)
    end do
    used(:, 1:nv) = .false.
    do v = 1, nv
      ! (a face with a vertex off the plane is not a cap: its walk stops
      ! there; a cap's directed edges are its own, so it is still walked
      ! once, from its first vertex)
      if (s(v) > tolf) cycle
      do k = 1, 3
        if (used(k, v)) cycle
        ! the face to the left of the directed edge v -> nbr(k,v), walked
        ! with the rule of geometry_polyhedron's header
        used(k, v) = .true.
        m = 1
        face(1) = v
        prev = v
        cur = p%nbr(k, v)
        do it = 1, nv
          if (s(cur) > tolf) exit
          m = m + 1
          face(m) = cur
          j = mod(slot_of(p, cur, prev), 3) + 1
          used(j, cur) = .true.
          nxt = p%nbr(j, cur)
          if (nxt == v) exit
          prev = cur
          cur = nxt
        end do
        if (m < 3 .or. s(cur) > tolf) cycle
        ! fan from the first vertex; triangle areas signed along n
        a = p%x(:, face(1))
        tot = 0.0_wp
        do i = 2, m - 1
          tot = tot + dot_product(n, cross(p%x(:, face(i)) - a, p%x(:, face(i + 1)) - a))
        end do
        if (.not. tot > 0.0_wp) cycle
        do i = 2, m - 1
          b = p%x(:, face(i))
          c = p%x(:, face(i + 1))
          call add_triangle(a, b, c, 0.5_wp*sgn*dot_product(n, cross(b - a, c - a)), area, f1, f2)
        end do
      end do
    end do
  end subroutine add_cap_faces

  !> Adds to (area, f1, f2) the polygon x(:, 1:m) on the plane with unit
  !> normal n (its points in order round it, either way), its area counted
  !> along +n, times sgn: `add_cap_faces` for a cut whose polygon is known
  !> (`tet_clip_moments`).
  pure subroutine add_cap_polygon(x, m, n, sgn, area, f1, f2)
    integer, intent(in) :: m
    ! (explicit shapes and a fixed-size t: an assumed-shape x made every
    ! edge difference, and t, a heap temporary, three per call)
    real(wp), intent(in) :: x(3, m), n(3), sgn
    real(wp), intent(inout) :: area, f1(3), f2(3, 3)
    real(wp) :: t(max_cap), tot, e1(3), e2(3)
    integer :: i
    if (m < 3) return
    tot = 0.0_wp
    do i = 2, m - 1
      e1 = x(:, i) - x(:, 1)
      e2 = x(:, i + 1) - x(:, 1)
      t(i) = 0.5_wp*dot_product(n, cross(e1, e2))
      tot = tot + t(i)
    end do
    if (tot < 0.0_wp) t(2:m - 1) = -t(2:m - 1)
    do i = 2, m - 1
      call add_triangle(x(:, 1), x(:, i), x(:, i + 1), sgn*t(i), area, f1, f2)
    end do
  end subroutine add_cap_polygon

  !> Adds the triangle (a, b, c) of signed area t to (area, f1, f2): its
  !> area, first moment t (a + b + c)/3 and second moment
  !> int_T x x^T dA = t/12 (a a^T + b b^T + c c^T + s s^T), s = a + b + c.
  pure subroutine add_triangle(a, b, c, t, area, f1, f2)
    real(wp), intent(in) :: a(3), b(3), c(3), t
    real(wp), intent(inout) :: area, f1(3), f2(3, 3)
    real(wp) :: sv(3)
    integer :: ii, jj
    sv = a + b + c
    area = area + t
    f1 = f1 + (t/3.0_wp)*sv
    do jj = 1, 3
      do ii = 1, 3
        f2(ii, jj) = f2(ii, jj) + (t/12.0_wp)*(a(ii)*a(jj) + b(ii)*b(jj) + c(ii)*c(jj) + sv(ii)*sv(jj))
      end do
    end do
  end subroutine add_triangle


  !> The region pcs cut by n.x <= dl (local coordinates, unit n): volume and
  !> first moment and, if want_face, the interface polygon's moments. The
  !> in/out decision per piece is poly_clip's own (same distances, same
  !> tolerance), so a piece counted whole, empty or clipped here is what
  !> poly_clip would give, and the interface is counted once. ok becomes
  !> false if a piece ran out of vertex capacity.
  pure subroutine cut_eval(pcs, n, dl, want_face, c, ok)
    type(mof_pieces_t), intent(in) :: pcs
    real(wp), intent(in) :: n(3), dl
    logical, intent(in) :: want_face
    type(cut_t), intent(out) :: c
    logical, intent(inout) :: ok
    type(poly_t) :: q
    real(wp) :: s, smn, smx, xmax, tol, v, m(3), cap(3, 4)
    integer :: k, iv, ncap
    logical :: okc

    c%dl = dl
    do k = 1, pcs%np
      smn = huge_wp
      smx = -huge_wp
      xmax = 0.0_wp
      associate (x => pcs%p(k)%x)
        do iv = 1, pcs%p(k)%nv
          s = n(1)*x(1, iv) + n(2)*x(2, iv) + n(3)*x(3, iv) - dl
          smn = min(smn, s)
          smx = max(smx, s)
          xmax = max(xmax, abs(n(1)*x(1, iv)) + abs(n(2)*x(2, iv)) + abs(n(3)*x(3, iv)))
        end do
      end associate
      tol = poly_rel_tol*(xmax + abs(dl))
      if (smx <= tol) then
        ! nothing outside: the whole piece (a face may lie on the plane)
        c%vol = c%vol + pcs%sgn(k)*pcs%vol(k)
        c%mom = c%mom + pcs%sgn(k)*pcs%mom(:, k)
        if (want_face .and. smx >= -tol) &
          call add_cap_faces(pcs%p(k), n, dl, 8.0_wp*tol, pcs%sgn(k), c%area, c%f1, c%f2)
      else if (smn >= -tol) then
        ! nothing strictly inside: no volume
        cycle
      else if (pcs%p(k)%nv == 4) then
        ! (a tetrahedron of the cell's split, cut: in closed form, the
        ! same decision per vertex and the same cut points)
        call tet_clip_moments(pcs%p(k)%x(:, 1:4), n, dl, v, m, cap, ncap)
        c%vol = c%vol + pcs%sgn(k)*v
        c%mom = c%mom + pcs%sgn(k)*m
        if (want_face) call add_cap_polygon(cap, ncap, n, pcs%sgn(k), c%area, c%f1, c%f2)
      else
        call poly_copy(pcs%p(k), q)
        call poly_clip(q, n, dl, okc)
        if (.not. okc) ok = .false.
        call poly_first_moments(q, v, m)
        c%vol = c%vol + pcs%sgn(k)*v
        c%mom = c%mom + pcs%sgn(k)*m
        ! the cap's vertices are within a few round-off units of the plane
        if (want_face) call add_cap_faces(q, n, dl, 8.0_wp*tol, pcs%sgn(k), c%area, c%f1, c%f2)
      end if
    end do
  end subroutine cut_eval

  !> Smallest and largest projection n.x of the region's vertices.
  pure subroutine region_range(pcs, n, smin, smax)
    type(mof_pieces_t), intent(in) :: pcs
    real(wp), intent(in) :: n(3)
    real(wp), intent(out) :: smin, smax
    real(wp) :: s
    integer :: k, iv
    smin = huge_wp
    smax = -huge_wp
    do k = 1, pcs%np
      do iv = 1, pcs%p(k)%nv
        s = dot_product(n, pcs%p(k)%x(:, iv))
        smin = min(smin, s)
        smax = max(smax, s)
      end do
    end do
  end subroutine region_range

  !> Root in [0,1] of the cubic through (0,f0), (1/3,f1), (2/3,f2), (1,f3)
  !> with f0 <= 0 <= f3: Newton safeguarded by bisection.
  pure function cubic_root(f0, f1, f2, f3) result(u)
    real(wp), intent(in) :: f0, f1, f2, f3
    real(wp) :: u
    real(wp) :: c1, c2, c3, a1, a2, a3, lo, hi, p, dp, un
    integer :: it

    ! Newton divided differences on the nodes 0, 1/3, 2/3, 1, then the
    ! monomial form (u(u-1/3)(u-2/3) = u^3 - u^2 + 2u/9)
    c1 = 3.0_wp*(f1 - f0)
    c2 = 1.5_wp*(3.0_wp*(f2 - f1) - c1)
    c3 = 1.5_wp*(3.0_wp*(f3 - f2) - 3.0_wp*(f2 - f1)) - c2
    a1 = c1 - c2/3.0_wp + 2.0_wp*c3/9.0_wp
    a2 = c2 - c3
    a3 = c3
    lo = 0.0_wp
    hi = 1.0_wp
    u = 0.5_wp
    if (f3 - f0 > 0.0_wp) u = -f0/(f3 - f0)
    do it = 1, 100
      p = ((a3*u + a2)*u + a1)*u + f0
      if (p < 0.0_wp) then
        lo = u
      else
        hi = u
      end if
      dp = (3.0_wp*a3*u + 2.0_wp*a2)*u + a1
      un = -1.0_wp
      if (dp > 0.0_wp .and. abs(p) < dp*(hi - lo)) un = u - p/dp
      if (.not. (un > lo .and. un < hi)) un = 0.5_wp*(lo + hi)
      if (abs(un - u) <= 4.0_wp*epsilon(1.0_wp)) then
        u = un
        exit
      end if
      u = un
    end do
  end function cubic_root

  !> Sorts s(1:m) ascending (insertion sort: m is a few dozen) and removes
  !> repeated values.
  pure subroutine sort_unique(s, m)
    real(wp), intent(inout) :: s(:)
    integer, intent(inout) :: m
    real(wp) :: t
    integer :: i, j, k

    do i = 2, m
      t = s(i)
      j = i - 1
      do while (j >= 1)
        if (s(j) <= t) exit
        s(j + 1) = s(j)
        j = j - 1
      end do
      s(j + 1) = t
    end do
    k = min(m, 1)
    do i = 2, m
      if (s(i) > s(k)) then
        k = k + 1
        s(k) = s(i)
      end if
    end do
    m = k
  end subroutine sort_unique

  !> The plane n.x = dl (local coordinates, unit n) cutting the volume vt
  !> (length^3) from the region pcs, whose other side has the volume vc
  !> (vt + vc is the region's volume; both are given so that the smaller is
  !> exact to round-off of itself), and the cut c there (with its interface
  !> moments). The smaller side is solved for (by `solve_lower`, with -n for
  !> the far side), so a sliver of either material is matched to round-off
  !> of its own volume, not of the cell's.
  pure subroutine solve_plane(pcs, n, vt, vc, use_guess, dguess, c, ok)
    type(mof_pieces_t), intent(in) :: pcs
    real(wp), intent(in) :: n(3), vt, vc, dguess
    logical, intent(in) :: use_guess
    type(cut_t), intent(out) :: c
    logical, intent(out) :: ok
    real(wp) :: vtot, momtot(3)

    call region_moments(pcs, vtot, momtot)
    if (vt <= vc) then
      call solve_lower(pcs, n, vt, vtot, use_guess, dguess, c, ok)
      c%svol = c%vol
      c%smom = c%mom
    else
      ! the far side n.x >= dl is the cut by -n; the interface polygon and
      ! its moments are the same
      call solve_lower(pcs, -n, vc, vtot, use_guess, -dguess, c, ok)
      c%svol = c%vol
      c%smom = c%mom
      c%dl = -c%dl
      c%vol = vtot - c%vol
      c%mom = momtot - c%mom
    end if
  end subroutine solve_plane

  !> The plane n.x = dl (local coordinates, unit n) cutting the volume vt
  !> (length^3) from the region pcs of volume vtot (the sum over its
  !> pieces), and the cut c there (with its interface moments): Newton (on
  !> V^(1/k)) from dguess if use_guess, else from the cone estimate; where
  !> it leaves the bracket, bisection over the vertex projections, the
  !> exact cubic of the last bracket and Illinois regula falsi (see the
  !> module header). ok is false if |vol - vt| > 1e-12 vtot at the end or a
  !> piece overflowed.
  pure subroutine solve_lower(pcs, n, vt, vtot, use_guess, dguess, c, ok)
    type(mof_pieces_t), intent(in) :: pcs
    real(wp), intent(in) :: n(3), vt, vtot, dguess
    logical, intent(in) :: use_guess
    type(cut_t), intent(out) :: c
    logical, intent(out) :: ok
    real(wp) :: proj(mof_max_pieces*poly_max_verts)
    real(wp) :: smin, smax, tolv, a, b, fa, fb, f, dl, dn, w, g1, g2, s, dfloor, pk, dp
    integer :: it, k, iv, m, lo, hi, mid, side
    logical :: last

    ok = .true.
    call region_range(pcs, n, smin, smax)
    if (pcs%np == 0) then
      ok = .false.
      return
    end if
    if (vt <= 0.0_wp) then
      call cut_eval(pcs, n, smin, .true., c, ok)
      return
    end if
    if (vt >= vtot) then
      call cut_eval(pcs, n, smax, .true., c, ok)
      return
    end if
    tolv = 1.0e-13_wp*vt
    dfloor = 4.0_wp*epsilon(1.0_wp)*max(abs(smin), abs(smax), smax - smin)
    a = smin
    fa = -vt
    b = smax
    fb = vtot - vt

    ! Newton with the cut's area as dV/dd, kept inside the bracket, from
    ! the guess, or else from where a cone from the lowest point would
    ! hold vt (the power law of the steps below with k = 3)
    dl = smin + (smax - smin)*(vt/vtot)**(1.0_wp/3.0_wp)
    if (use_guess) dl = min(max(dguess, a), b)
    last = .false.
    do it = 1, 8
      call cut_eval(pcs, n, dl, .true., c, ok)
      f = c%vol - vt
      ! (or within what one rounding of the plane's offset moves: the
      ! cut's area times eps of the offsets, which a thin slab's tolv can
      ! lie below)
      if (abs(f) <= max(tolv, 0.25_wp*dfloor*c%area) .or. (last .and. abs(f) <= 1.0e-12_wp*abs(vtot))) return
      if (f < 0.0_wp) then
        a = dl
        fa = f
      else
        b = dl
        fb = f
      end if
      if (.not. (c%area > 0.0_wp .and. abs(f) < c%area*(b - a))) exit
      ! (Newton on V^(1/k), not on V: with k = A (dl - smin)/V, the
      ! exponent of the power law V ~ (d - smin)^k through this point (1
      ! where the region starts with a face, 3 at a vertex), the step
      ! smin + (dl - smin) (vt/V)^(1/k) is exact for any such law, and
      ! it is Newton's to second order at the root. On V itself a cut
      ! near a corner, where V is cubic, takes a third off the error per
      ! step: 8 steps from a guess a cell away, then the bisection)
      dn = dl - f/c%area
      if (c%vol > 0.0_wp .and. dl > smin) then
        pk = min(max(c%area*(dl - smin)/c%vol, 0.25_wp), 3.0_wp)
        dp = smin + (dl - smin)*(vt/c%vol)**(1.0_wp/pk)
        if (dp > a .and. dp < b) dn = dp
      end if
      if (.not. (dn > a .and. dn < b)) exit
      ! (a step within round-off of the plane's offset is the last: V is
      ! known no better than this here, as for a sliver, whose tolv lies
      ! below the round-off of the cell's volume; the bisection would end
      ! at the same plane after a dozen more cuts)
      last = abs(dn - dl) <= dfloor
      dl = dn
    end do

    ! bisection over the vertex projections inside (a, b): V is one cubic
    ! between neighbouring projections
    m = 0
    do k = 1, pcs%np
      do iv = 1, pcs%p(k)%nv
        s = dot_product(n, pcs%p(k)%x(:, iv))
        if (s > a .and. s < b) then
          m = m + 1
          proj(m) = s
        end if
      end do
    end do
    call sort_unique(proj, m)
    lo = 0
    hi = m + 1
    do while (hi - lo > 1)
      mid = (lo + hi)/2
      call cut_eval(pcs, n, proj(mid), .false., c, ok)
      f = c%vol - vt
      if (abs(f) <= tolv) then
        call cut_eval(pcs, n, proj(mid), .true., c, ok)
        return
      end if
      if (f < 0.0_wp) then
        lo = mid
        a = proj(mid)
        fa = f
      else
        hi = mid
        b = proj(mid)
        fb = f
      end if
    end do

    ! the cubic through four values on [a, b], then regula falsi (Illinois)
    ! on the true V should round-off spoil the cubic's root
    w = b - a
    call cut_eval(pcs, n, a + w/3.0_wp, .false., c, ok)
    g1 = c%vol - vt
    call cut_eval(pcs, n, a + 2.0_wp*w/3.0_wp, .false., c, ok)
    g2 = c%vol - vt
    dl = a + w*cubic_root(fa, g1, g2, fb)
    side = 0
    last = .false.
    do it = 1, 100
      call cut_eval(pcs, n, dl, .true., c, ok)
      f = c%vol - vt
      if (abs(f) <= max(tolv, 0.25_wp*dfloor*c%area) .or. (last .and. abs(f) <= 1.0e-12_wp*abs(vtot))) exit
      if (f < 0.0_wp) then
        a = dl
        fa = f
        if (side < 0) fb = 0.5_wp*fb
        side = -1
      else
        b = dl
        fb = f
        if (side > 0) fa = 0.5_wp*fa
        side = 1
      end if
      if (b - a <= 4.0_wp*epsilon(1.0_wp)*max(abs(a), abs(b), smax - smin)) exit
      dn = a - fa*((b - a)/(fb - fa))
      if (.not. (dn > a .and. dn < b)) dn = 0.5_wp*(a + b)
      ! (the same round-off floor as Newton's above: the false position
      ! would only stall on the noise of V)
      last = abs(dn - dl) <= dfloor
      dl = dn
    end do
    if (abs(c%vol - vt) > 1.0e-12_wp*abs(vtot)) ok = .false.
  end subroutine solve_lower

  ! ------------------------------------------------------ public kernels

  !> Volume vol (length^3) and centroid (length) of the part of the cell
  !> xn(3,8) with n.x <= d (n need not be unit; d in length times |n|;
  !> n = 0 keeps all if d >= 0, nothing otherwise). Exact for any
  !> hexahedron through its 24-tet split. An empty cut has the mean of the
  !> nodes as centroid.
  pure subroutine mof_cut_volume(xn, n, d, vol, centroid)
    real(wp), intent(in) :: xn(3, 8), n(3), d
    real(wp), intent(out) :: vol, centroid(3)
    type(mof_pieces_t) :: pcs
    logical :: ok

    ok = .true.
    call mof_cell_pieces(xn, pcs)
    call region_clip(pcs, n, d - dot_product(n, pcs%origin), ok)
    call mof_pieces_moments(pcs, vol, centroid)
  end subroutine mof_cut_volume

  !> The d such that the part of the cell xn(3,8) with n.x <= d has vfrac
  !> times the cell's volume (n need not be unit; d in length times |n|).
  !> vfrac <= 0 gives the smallest and vfrac >= 1 the largest projection of
  !> the cell's points. ok is false if n = 0, vfrac is not in [0, 1], the
  !> cell's volume is not positive or the volume could not be matched to
  !> 1e-12 of the cell's volume.
  pure subroutine mof_plane_for_volume(xn, n, vfrac, d, ok)
    real(wp), intent(in) :: xn(3, 8), n(3), vfrac
    real(wp), intent(out) :: d
    logical, intent(out) :: ok
    type(mof_pieces_t) :: pcs
    type(cut_t) :: c
    real(wp) :: nn, nu(3), vtot, mom(3), f

    d = 0.0_wp
    nn = norm2(n)
    ok = nn > 0.0_wp .and. vfrac >= 0.0_wp .and. vfrac <= 1.0_wp
    if (.not. nn > 0.0_wp) return
    f = 0.0_wp
    if (vfrac > 0.0_wp) f = min(vfrac, 1.0_wp)
    nu = n/nn
    call mof_cell_pieces(xn, pcs)
    call region_moments(pcs, vtot, mom)
    if (.not. vtot > 0.0_wp) then
      ok = .false.
      return
    end if
    call solve_plane(pcs, nu, f*vtot, (1.0_wp - f)*vtot, .false., 0.0_wp, c, ok)
    ok = ok .and. vfrac >= 0.0_wp .and. vfrac <= 1.0_wp
    d = nn*(c%dl + dot_product(nu, pcs%origin))
  end subroutine mof_plane_for_volume

  !> Unit vectors t1, t2 with (t1, t2, n) right-handed orthonormal.
  pure subroutine tangent_frame(n, t1, t2)
    real(wp), intent(in) :: n(3)
    real(wp), intent(out) :: t1(3), t2(3)
    real(wp) :: e(3)
    e = 0.0_wp
    e(minloc(abs(n), 1)) = 1.0_wp
    t1 = cross(n, e)
    t1 = t1/norm2(t1)
    t2 = cross(n, t1)
  end subroutine tangent_frame

  !> Distance from the centroid mom/vol of a cut (or of its smaller side) to
  !> cref (local coordinates); huge if it has no volume.
  pure function moment_error(vol, mom, cref) result(err)
    real(wp), intent(in) :: vol, mom(3), cref(3)
    real(wp) :: err
    err = huge_wp
    if (vol > 0.0_wp) err = norm2(mom/vol - cref)
  end function moment_error

  !> MoF in a region: from the unit normal n, Gauss-Newton on the angles of
  !> the tangent frame (module header) for the plane cutting vt from pcs
  !> (vc on the other side) whose cut's centroid is closest to cref (local).
  !> The smaller side is the one fitted, against its centroid implied by
  !> cref and the region's moments: |c1 - c1ref| = (V2/V1)|c2 - c2ref|, the
  !> same minimiser, but the sliver's centroid is computed directly, so a
  !> nearly full cell's search does not wander in the round-off of a
  !> difference of moments. Returns the best n, its cut c, the centroid
  !> error err of the vt side, the iterations used and whether it converged
  !> (turn below mof_angle_tol, error at round-off, no descent left along
  !> the Gauss-Newton direction, or a full step that gained almost nothing)
  !> within max_iter. okv is false if a volume root failed.
  pure subroutine minimise(pcs, vt, vc, cref, scale, max_iter, n, c, err, iterations, converged, okv)
    type(mof_pieces_t), intent(in) :: pcs
    real(wp), intent(in) :: vt, vc, cref(3), scale
    integer, intent(in) :: max_iter
    real(wp), intent(inout) :: n(3)
    type(cut_t), intent(out) :: c
    real(wp), intent(out) :: err
    integer, intent(out) :: iterations
    logical, intent(out) :: converged, okv
    type(cut_t) :: ct
    real(wp) :: t1(3), t2(3), r(3), jm(3, 3), g1(3), g2(3), xf(3), dir(3), ntry(3), cs(3), vtot, momtot(3)
    real(wp) :: h11, h12, h22, b1, b2, tr, det, da, db, stp, lam, th, es, est, gain, side
    integer :: it, ls, i
    logical :: accepted, okt

    converged = .false.
    iterations = 0
    ! the fitted side: n.x <= d (side = 1) or n.x >= d (side = -1)
    call region_moments(pcs, vtot, momtot)
    if (vt <= vc) then
      side = 1.0_wp
      cs = cref
    else
      side = -1.0_wp
      cs = (momtot - vt*cref)/vc
    end if
    call solve_plane(pcs, n, vt, vc, .false., 0.0_wp, c, okv)
    es = moment_error(c%svol, c%smom, cs)
    if (es <= err_roundoff*scale) converged = .true.
    do it = 1, max_iter
      if (converged) exit
      iterations = it
      if (.not. (c%area > 0.0_wp .and. c%svol > 0.0_wp)) exit
      ! Jacobian of r = c(n) - cs in the angles along t1, t2: -J t/V for
      ! the side below the plane, +J t/V for the side above
      call tangent_frame(n, t1, t2)
      xf = c%f1/c%area
      do i = 1, 3
        jm(:, i) = c%f2(:, i) - c%f1*xf(i)
      end do
      g1 = -side*matmul(jm, t1)/c%svol
      g2 = -side*matmul(jm, t2)/c%svol
      r = c%smom/c%svol - cs
      ! normal equations scaled by their trace, a touch of Levenberg damping
      ! for slivers (rotation about a thin interface's long axis)
      h11 = dot_product(g1, g1)
      h12 = dot_product(g1, g2)
      h22 = dot_product(g2, g2)
      tr = h11 + h22
      if (.not. tr > 0.0_wp) exit
      h11 = h11/tr + 1.0e-12_wp
      h12 = h12/tr
      h22 = h22/tr + 1.0e-12_wp
      b1 = -dot_product(g1, r)/tr
      b2 = -dot_product(g2, r)/tr
      det = h11*h22 - h12*h12
      if (.not. det > 0.0_wp) exit
      da = (b1*h22 - h12*b2)/det
      db = (h11*b2 - h12*b1)/det
      stp = hypot(da, db)
      if (.not. stp > 0.0_wp) then
        converged = .true.
        exit
      end if
      dir = (da*t1 + db*t2)/stp
      stp = min(stp, max_turn)
      ! halving line search on the error; the plane through the old
      ! interface centroid is Newton's start (volume error ~ turn^2)
      accepted = .false.
      lam = 1.0_wp
      do ls = 1, 40
        th = lam*stp
        ntry = cos(th)*n + sin(th)*dir
        ntry = ntry/norm2(ntry)
        call solve_plane(pcs, ntry, vt, vc, .true., dot_product(ntry, xf), ct, okt)
        est = moment_error(ct%svol, ct%smom, cs)
        if (est < es) then
          accepted = .true.
          exit
        end if
        lam = 0.5_wp*lam
        if (th < 1.0e-3_wp*mof_angle_tol) exit
      end do
      if (.not. accepted) then
        ! no descent left: a minimum to round-off
        converged = .true.
        exit
      end if
      n = ntry
      c = ct
      gain = es - est
      es = est
      okv = okt
      ! converged: a tiny turn, the error at round-off, or a full step that
      ! gained almost nothing (the error is then within ~1e-6 of its least
      ! value even at slow linear convergence, as for curved interfaces)
      if (th <= mof_angle_tol .or. es <= err_roundoff*scale .or. &
          (lam >= 1.0_wp .and. gain <= 1.0e-8_wp*(es + gain))) converged = .true.
    end do
    err = moment_error(c%vol, c%mom, cref)
  end subroutine minimise

  !> Largest extent of the cell's nodes along the three axes (length).
  pure function cell_scale(xn) result(scale)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: scale
    integer :: i
    scale = 0.0_wp
    do i = 1, 3
      scale = max(scale, maxval(xn(i, :)) - minval(xn(i, :)))
    end do
  end function cell_scale

  !> A start for n when c_ref carries no direction: the cell's first
  !> logical axis (mean of the i = 1 nodes minus mean of the i = 0 nodes).
  pure function default_normal(xn) result(n)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: n(3)
    n = (xn(:, 2) + xn(:, 4) + xn(:, 6) + xn(:, 8)) - (xn(:, 1) + xn(:, 3) + xn(:, 5) + xn(:, 7))
    if (norm2(n) > 0.0_wp) then
      n = n/norm2(n)
    else
      n = [1.0_wp, 0.0_wp, 0.0_wp]
    end if
  end function default_normal

  !> (A A^T)^-1 for the cell's logical axes A = [a_i, a_j, a_k], a_i the mean
  !> of the four i = 1 nodes minus that of the i = 0 nodes (the identity if
  !> A is singular to round-off). A plane through the unit cube with normal
  !> m is, mapped by x = x0 + A xi, the plane with normal A^-T m, so the
  !> centroid-direction start m = A^-1 (c_cell - c_ref) taken in the logical
  !> frame is n = (A A^T)^-1 (c_cell - c_ref) here: for planar data it is as
  !> good in a long, thin or sheared cell as in a cube (a small corner cut of
  !> a 10 x 1 x 0.3 box is found from its corner's diagonal, not from the
  !> long axis).
  pure subroutine logical_metric(xn, minv)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: minv(3, 3)
    real(wp) :: a(3, 3), m(3, 3), det
    integer :: i

    a(:, 1) = 0.25_wp*((xn(:, 2) + xn(:, 4) + xn(:, 6) + xn(:, 8)) - (xn(:, 1) + xn(:, 3) + xn(:, 5) + xn(:, 7)))
    a(:, 2) = 0.25_wp*((xn(:, 3) + xn(:, 4) + xn(:, 7) + xn(:, 8)) - (xn(:, 1) + xn(:, 2) + xn(:, 5) + xn(:, 6)))
    a(:, 3) = 0.25_wp*((xn(:, 5) + xn(:, 6) + xn(:, 7) + xn(:, 8)) - (xn(:, 1) + xn(:, 2) + xn(:, 3) + xn(:, 4)))
    m = matmul(a, transpose(a))
    ! inverse of the symmetric m by cofactors
    minv(:, 1) = cross(m(:, 2), m(:, 3))
    minv(:, 2) = cross(m(:, 3), m(:, 1))
    minv(:, 3) = cross(m(:, 1), m(:, 2))
    det = dot_product(m(:, 1), minv(:, 1))
    if (det > 1.0e-12_wp*(m(1, 1) + m(2, 2) + m(3, 3))**3) then
      minv = minv/det
    else
      minv = 0.0_wp
      do i = 1, 3
        minv(i, i) = 1.0_wp
      end do
    end if
  end subroutine logical_metric

  !> MoF in one region pcs (cell or remainder) of centroid creg (local):
  !> the material of volume vt and reference centroid cref (local) is the
  !> part with n.x <= dl, the other side has the volume vc. The search
  !> starts from (A A^T)^-1 (creg - cref) (minv from `logical_metric`), or
  !> from start if cref is creg. vt <= 0 and vc <= 0 need no search
  !> (iterations = 0).
  pure subroutine mof_region(pcs, vt, vc, creg, cref, start, minv, scale, max_iter, n, dl, err, &
                             iterations, converged, okv, guess)
    type(mof_pieces_t), intent(in) :: pcs
    real(wp), intent(in) :: vt, vc, creg(3), cref(3), start(3), minv(3, 3), scale
    integer, intent(in) :: max_iter
    real(wp), intent(out) :: n(3), dl, err
    integer, intent(out) :: iterations
    logical, intent(out) :: converged, okv
    !> a normal to start from (any length; 0: none): the plane the interface
    !> had, which the search then leaves only as far as the centroid asks
    real(wp), intent(in), optional :: guess(3)
    type(cut_t) :: c, c2
    real(wp) :: g(3), n2(3), err2, es, tol2
    integer :: it2
    logical :: conv2, ok2

    iterations = 0
    converged = .true.
    ! the direction from cref to the region's centroid, taken in the
    ! cell's logical frame (see `logical_metric`)
    n = start
    n2 = start
    g = creg - cref
    if (norm2(g) > 1.0e-12_wp*scale) then
      n2 = g/norm2(g)
      g = matmul(minv, g)
      if (norm2(g) > 0.0_wp) n = g/norm2(g)
    end if
    tol2 = restart_tol
    if (present(guess)) then
      ! the guess first, the logical centroid direction as the second start,
      ! tried only if the first search ends far from its target (a search
      ! from the plane the interface had ends in a local minimum rarely; one
      ! that matches a curved interface to a few percent of a cell is not one)
      if (norm2(guess) > 0.0_wp) then
        n2 = n
        n = guess/norm2(guess)
        tol2 = restart_tol_guess
      end if
    end if
    if (vt <= 0.0_wp .or. vc <= 0.0_wp) then
      call solve_plane(pcs, n, vt, vc, .false., 0.0_wp, c, okv)
      dl = c%dl
      err = 0.0_wp
      if (vt > 0.0_wp) err = moment_error(c%vol, c%mom, cref)
      return
    end if
    call minimise(pcs, vt, vc, cref, scale, max_iter, n, c, err, iterations, converged, okv)
    dl = c%dl
    ! a second start, the plain centroid direction, with the iterations left
    ! when the first ends far from its target (an error above restart_tol of
    ! the smaller side's size: a local minimum, which long or distorted cells
    ! can have; a planar interface is then usually found from here)
    es = moment_error(c%svol, c%smom, merge(cref, (creg*(vt + vc) - vt*cref)/vc, vt <= vc))
    if (es > tol2*min(vt, vc)**(1.0_wp/3.0_wp) .and. iterations < max_iter .and. &
        dot_product(n2, n) < 1.0_wp - 1.0e-6_wp) then
      call minimise(pcs, vt, vc, cref, scale, max_iter - iterations, n2, c2, err2, it2, conv2, ok2)
      iterations = iterations + it2
      if (err2 < err) then
        n = n2
        dl = c2%dl
        err = err2
        converged = conv2
        okv = ok2
      end if
    end if
  end subroutine mof_region

  !> Two-material MoF in the cell xn(3,8) (length, order a = 1 + i + 2j + 4k,
  !> any hexahedron): the material of volume fraction vfrac and centroid
  !> centroid_ref (length) is {x in cell : n.x <= d}, n unit, d (length)
  !> cutting exactly vfrac of the cell's volume, n minimising
  !> err_centroid = |centroid of the cut - centroid_ref| (length).
  !> iterations: Gauss-Newton iterations used, both starts together (0 when
  !> vfrac <= 0 or >= 1, which need no search; at most max_iter, default
  !> mof_max_iter_default). ok is true when the search converged (see
  !> `minimise`) within max_iter and the cut volume matches to 1e-12 of the
  !> cell's; it is false when the cap was hit (n, d are then the best plane
  !> found, still cutting the exact volume), when vfrac is not in [0, 1]
  !> (it is clamped) or the cell's volume is not positive (n = first
  !> logical axis, d = 0, err_centroid = huge). The routine always returns
  !> and never gives NaN for finite input. Cost: ~50 us on one core for a
  !> cube or a skewed hex (release build, mean 3.6 and 4.1 iterations).
  pure subroutine mof_reconstruct(xn, vfrac, centroid_ref, n, d, err_centroid, iterations, ok, max_iter)
    real(wp), intent(in) :: xn(3, 8), vfrac, centroid_ref(3)
    real(wp), intent(out) :: n(3), d, err_centroid
    integer, intent(out) :: iterations
    logical, intent(out) :: ok
    integer, intent(in), optional :: max_iter
    type(mof_pieces_t) :: pcs
    real(wp) :: vtot, mom(3), f, dl, start(3), minv(3, 3)
    integer :: mi
    logical :: converged, okv

    mi = mof_max_iter_default
    if (present(max_iter)) mi = max(max_iter, 0)
    n = default_normal(xn)
    d = 0.0_wp
    err_centroid = huge_wp
    iterations = 0
    ok = .false.
    if (.not. (vfrac >= -huge_wp .and. vfrac <= huge_wp)) return
    call mof_cell_pieces(xn, pcs)
    call region_moments(pcs, vtot, mom)
    if (.not. vtot > 0.0_wp) return
    f = min(max(vfrac, 0.0_wp), 1.0_wp)
    start = n
    call logical_metric(xn, minv)
    call mof_region(pcs, f*vtot, (1.0_wp - f)*vtot, mom/vtot, centroid_ref - pcs%origin, start, minv, &
                    cell_scale(xn), mi, n, dl, err_centroid, iterations, converged, okv)
    d = dl + dot_product(n, pcs%origin)
    ok = converged .and. okv .and. vfrac >= 0.0_wp .and. vfrac <= 1.0_wp
  end subroutine mof_reconstruct

  !> MoF for nmat = size(vfrac) materials in the cell xn(3,8) by nested
  !> dissection in the given order (reorder the inputs to choose another):
  !> material 1 is {x in cell : n(:,1).x <= d(1)}, material k is what
  !> materials 1..k-1 left with n(:,k).x <= d(k), each plane found by the
  !> two-material MoF of `mof_reconstruct` in the remaining region against
  !> vfrac(k) (of the whole cell's volume) and centroid_ref(:,k) (length).
  !> The last material takes the rest: n(:,nmat) = 0, d(nmat) = 1 (in the
  !> convention of `poly_clip`, n = 0 keeps all if d >= 0, nothing if not).
  !> A material with vfrac <= 0 gets n = 0, d = -1 (empty); one that would
  !> take all that is left (to 1e-12 of the cell's volume) gets n = 0, d = 1
  !> and the later ones are empty.
  !> err_centroid(k) = |centroid of material k's region - centroid_ref(:,k)|
  !> (0 for empty materials), iterations(k) its Gauss-Newton iterations.
  !> `mof_material_pieces` gives each material's region. ok is false if an
  !> array is too small (nothing else is then set), a vfrac is not in [0, 1],
  !> their sum differs from 1 by more than 1e-10, the cell's volume is not
  !> positive, or a material's search hit the cap or failed.
  pure subroutine mof_reconstruct_nested(xn, vfrac, centroid_ref, n, d, err_centroid, iterations, ok, &
                                         max_iter, guess)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(in) :: vfrac(:)
    real(wp), intent(in) :: centroid_ref(:, :)
    real(wp), intent(out) :: n(:, :)
    real(wp), intent(out) :: d(:)
    real(wp), intent(out) :: err_centroid(:)
    integer, intent(out) :: iterations(:)
    logical, intent(out) :: ok
    integer, intent(in), optional :: max_iter
    !> (3, nmat) each material's normal to start its search from (any
    !> length; a zero column: the centroid direction, as without it): the
    !> planes the interface had before, which a search then leaves only as
    !> far as the centroids ask (one volume root when they match)
    real(wp), intent(in), optional :: guess(:, :)
    type(mof_pieces_t) :: rest
    real(wp) :: vcell, vrest, mom(3), vt, dl, nk(3), start(3), scale, cr(3), minv(3, 3)
    integer :: nmat, k, mi
    logical :: converged, okv, all_taken

    nmat = size(vfrac)
    ok = size(centroid_ref, 1) == 3 .and. size(centroid_ref, 2) >= nmat .and. size(n, 1) == 3 .and. &
         size(n, 2) >= nmat .and. size(d) >= nmat .and. size(err_centroid) >= nmat .and. &
         size(iterations) >= nmat .and. nmat >= 1
    if (.not. ok) return
    mi = mof_max_iter_default
    if (present(max_iter)) mi = max(max_iter, 0)
    n(:, 1:nmat) = 0.0_wp
    d(1:nmat) = -1.0_wp
    err_centroid(1:nmat) = 0.0_wp
    iterations(1:nmat) = 0
    if (.not. all(vfrac >= 0.0_wp .and. vfrac <= 1.0_wp)) ok = .false.
    if (ok) ok = abs(sum(vfrac) - 1.0_wp) <= 1.0e-10_wp
    call mof_cell_pieces(xn, rest)
    call region_moments(rest, vcell, mom)
    if (.not. vcell > 0.0_wp) then
      ok = .false.
      err_centroid(1:nmat) = huge_wp
      return
    end if
    scale = cell_scale(xn)
    start = default_normal(xn)
    call logical_metric(xn, minv)
    all_taken = .false.
    do k = 1, nmat
      if (all_taken) exit
      call region_moments(rest, vrest, mom)
      cr = centroid_ref(:, k) - rest%origin
      vt = 0.0_wp
      if (vfrac(k) > 0.0_wp) vt = min(vfrac(k), 1.0_wp)*vcell
      if (k == nmat .or. vt >= vrest - 1.0e-12_wp*vcell) then
        ! the rest of the region (also when only round-off would be left)
        d(k) = 1.0_wp
        err_centroid(k) = 0.0_wp
        if (vrest > 0.0_wp) err_centroid(k) = norm2(mom/vrest - cr)
        all_taken = .true.
        cycle
      end if
      if (vt <= 0.0_wp) cycle
      if (present(guess)) then
        call mof_region(rest, vt, vrest - vt, mom/vrest, cr, start, minv, scale, mi, nk, dl, err_centroid(k), &
                        iterations(k), converged, okv, guess(:, k))
      else
        call mof_region(rest, vt, vrest - vt, mom/vrest, cr, start, minv, scale, mi, nk, dl, err_centroid(k), &
                        iterations(k), converged, okv)
      end if
      ok = ok .and. converged .and. okv
      n(:, k) = nk
      d(k) = dl + dot_product(nk, rest%origin)
      call region_clip(rest, -nk, -dl, ok)
    end do
  end subroutine mof_reconstruct_nested

  !> The nested dissection of `mof_reconstruct_nested` with the normals
  !> given instead of fitted: for k = 1..nmat = size(vfrac) in order,
  !> material k is what materials 1..k-1 left of the cell xn(3,8) with
  !> n(:,k).x <= d(k), d(k) (length times |n(:,k)|) cutting vfrac(k) of the
  !> cell's volume. No search: one volume root per material, so a plane keeps
  !> its orientation while its material grows or shrinks. The last material,
  !> one with n(:,k) = 0 and one that would take all that is left (to 1e-12
  !> of the cell's volume) take the rest, and the later ones are empty; one
  !> with vfrac <= 0 is empty. d(k) is then the plane along n(:,k) through
  !> the farthest (rest) or nearest (empty) point of what was left, or, for
  !> n(:,k) = 0, 1 (rest) or -1 (empty) in the convention of `poly_clip`.
  !> vol(k) (length^3) and centroid(:,k) (length) are the volume
  !> and centroid of each material's region, the smaller side of each cut
  !> computed directly (not as a difference), so a sliver's centroid is
  !> exact to round-off of its own size; an empty region has vol = 0 and the
  !> mean of the nodes as centroid. ok is false if an array is too small
  !> (nothing is then set), the cell's volume is not positive, or a volume
  !> root failed. dguess (optional, the units of d) starts each root's
  !> Newton iteration (a plane that moved little: a few cuts instead of the
  !> bisection's dozen); the result does not depend on it beyond round-off.
  !> planes (optional, (4, nmat)): the same dissection in the convention of
  !> `mof_reconstruct_nested`'s n and d (unit normal and offset in length;
  !> n = 0 with d = 1 for the material that takes the rest, with d = -1 for
  !> an empty one), for `mof_material_pieces`.
  pure subroutine mof_nested_cut(xn, vfrac, n, d, vol, centroid, ok, dguess, planes)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(in) :: vfrac(:)
    real(wp), intent(in) :: n(:, :)
    real(wp), intent(out) :: d(:), vol(:), centroid(:, :)
    logical, intent(out) :: ok
    real(wp), intent(in), optional :: dguess(:)
    real(wp), intent(out), optional :: planes(:, :)
    type(mof_pieces_t) :: rest
    type(cut_t) :: c
    real(wp) :: vcell, vrest, mom(3), vt, nu(3), nn, dg, smin, smax
    integer :: nmat, k
    logical :: okv, all_taken, guess

    nmat = size(vfrac)
    ok = size(n, 1) == 3 .and. size(n, 2) >= nmat .and. size(d) >= nmat .and. size(vol) >= nmat .and. &
         size(centroid, 1) == 3 .and. size(centroid, 2) >= nmat .and. nmat >= 1
    guess = present(dguess)
    if (guess) ok = ok .and. size(dguess) >= nmat
    if (present(planes)) ok = ok .and. size(planes, 1) == 4 .and. size(planes, 2) >= nmat
    if (.not. ok) return
    if (present(planes)) then
      planes(1:3, 1:nmat) = 0.0_wp
      planes(4, 1:nmat) = -1.0_wp
    end if
    call mof_cell_pieces(xn, rest)
    call region_moments(rest, vcell, mom)
    d(1:nmat) = -1.0_wp
    vol(1:nmat) = 0.0_wp
    do k = 1, nmat
      centroid(:, k) = rest%origin
    end do
    if (.not. vcell > 0.0_wp) then
      ok = .false.
      return
    end if
    all_taken = .false.
    do k = 1, nmat
      nn = norm2(n(:, k))
      nu = 0.0_wp
      if (nn > 0.0_wp) nu = n(:, k)/nn
      smin = 0.0_wp
      smax = 0.0_wp
      if (nn > 0.0_wp .and. rest%np > 0) call region_range(rest, nu, smin, smax)
      if (all_taken) then
        if (nn > 0.0_wp) d(k) = nn*(smin + dot_product(nu, rest%origin))
        cycle
      end if
      call region_moments(rest, vrest, mom)
      vt = 0.0_wp
      if (vfrac(k) > 0.0_wp) vt = min(vfrac(k), 1.0_wp)*vcell
      if (k == nmat .or. .not. nn > 0.0_wp .or. vt >= vrest - 1.0e-12_wp*vcell) then
        d(k) = 1.0_wp
        if (nn > 0.0_wp) d(k) = nn*(smax + dot_product(nu, rest%origin))
        if (present(planes)) planes(4, k) = 1.0_wp
        vol(k) = vrest
        if (abs(vrest) > 0.0_wp) centroid(:, k) = rest%origin + mom/vrest
        all_taken = .true.
        cycle
      end if
      if (vt <= 0.0_wp) then
        if (nn > 0.0_wp) d(k) = nn*(smin + dot_product(nu, rest%origin))
        cycle
      end if
      dg = 0.0_wp
      if (guess) dg = dguess(k)/nn - dot_product(nu, rest%origin)
      call solve_plane(rest, nu, vt, vrest - vt, guess, dg, c, okv)
      ok = ok .and. okv
      d(k) = nn*(c%dl + dot_product(nu, rest%origin))
      if (present(planes)) planes(:, k) = [nu, c%dl + dot_product(nu, rest%origin)]
      vol(k) = c%vol
      if (abs(c%vol) > 0.0_wp) centroid(:, k) = rest%origin + c%mom/c%vol
      call region_clip(rest, -nu, -c%dl, ok)
    end do
  end subroutine mof_nested_cut
end module geometry_mof
