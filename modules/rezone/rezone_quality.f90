!> Grid quality: the cell quality Q of Eq. (46) and the Euler-step
!> triggers of the paper (the largest ratio of side lengths and the cosine of
!> the largest inclined angle).
!>
!> Q = 1728 V / L^3 for a hexahedron (V its exact volume, L the sum of its 12
!> edge lengths) and Q = 16 S / L^2 for a quadrilateral (S its area, L its
!> perimeter); both are 1 for a cube or a square and fall as a cell is
!> stretched, sheared or tangled (Q <= 0 for an inverted cell).
!>
!> Eq. (46) against the cell's own box (`hex_quality_box`): Q divided by the
!> Q of the box whose sides are the cell's mean edge lengths along its three
!> logical directions (their aspect ratio capped at aspect_max). 1 for any
!> such box, so it does not count a cell merely compressed or stretched
!> along the grid lines, which is how a Lagrangian grid resolves a shock: a
!> box compressed by 10 % has Eq. (46) Q = 0.996, already "distorted" for
!> the paper's q = 0.999 (Sect. 7.3; the Sedov shock compresses 6:1), while
!> the shear and the tangling Eq. (46) is meant to catch count as before
!> (for a sheared cube the two are the same, Q = sin of the shear angle).
!>
!> The inclined angle at a corner is how far the angle between two of its
!> edges departs from a right angle: cos(inclined) = sin(angle between the
!> edges) = |e1 x e2| / (|e1| |e2|), 1 for a cube. LSSM's box reading
!> measures it instead as an edge's angle to the axis of its logical
!> direction (the paper calls a regular cell "still inclined" when its
!> sides are not parallel to the axes, Sect. 5.3.1 and Fig. 8, and its
!> modified GETMe turns cells back to the axes): cos = |e . a_d| / |e|, 1
!> for an axis-aligned box. A cell compressed 4:1 along a face diagonal has
!> sin 0.47 between its edges but each edge turns only 31 degrees (cos
!> 0.857): the first reading fires at every diagonal of a compressed shock
!> shell. A run triggers an Euler step when the smallest cosine over all
!> cells falls to the deck's bound (0.7 in the paper's Sedov test) or the
!> largest side ratio reaches its bound (4).
module rezone_quality
  use base_kinds, only: wp
  use mesh_geometry, only: hex_volume, hex_edges, cross
  use mesh_grid, only: block_gather, grid_index_t, grid_index, grid_t
  use base_share, only: share_t
  implicit none
  private
  public :: hex_quality, quad_quality, hex_shape, grid_quality, grid_trigger_cells, grid_shape_worst, &
            standard_side_ratio, grid_standard_ratios, hex_fails_triggers, &
            hex_box_sides, hex_edge_means, hex_quality_box, hex_quality_box_parts

  !> The edge of each corner along each logical direction d: its index k
  !> in `mesh_geometry`'s hex_edges(:, k, d) (the edge from corner a to
  !> the corner that differs from it in the d-th logical index).
  integer, parameter :: corner_edge(3, 8) = reshape([1, 1, 1,  1, 3, 4,  4, 1, 3,  4, 3, 2, &
                                                     3, 4, 1,  3, 2, 4,  2, 4, 3,  2, 2, 2], [3, 8])
  !> The 12 edges of a hexahedron as (node, node) in the local numbering.
  integer, parameter :: hex_edge_list(2, 12) = reshape([1, 2, 3, 4, 5, 6, 7, 8, &
                                                        1, 3, 2, 4, 5, 7, 6, 8, &
                                                        1, 5, 2, 6, 3, 7, 4, 8], [2, 12])
  !> The slot in `hex_edge_list` of edge e along direction d of
  !> `mesh_geometry`'s hex_edges (the same (low, high) node pairs).
  integer, parameter :: edge_slot(4, 3) = reshape([1, 4, 3, 2,  5, 8, 6, 7,  9, 12, 11, 10], [4, 3])

contains

  !> Eq. (46) for a hexahedron with nodes xn(3,8): 1728 V / L^3.
  pure function hex_quality(xn) result(q)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: q
    q = quality_of(hex_volume(xn), edge_lengths(xn))
  end function hex_quality

  !> The 12 edge lengths of a hexahedron (length), in the order of
  !> `hex_edge_list`.
  pure function edge_lengths(xn) result(len)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: len(12)
    integer :: e
    do e = 1, 12
      len(e) = norm2(xn(:, hex_edge_list(2, e)) - xn(:, hex_edge_list(1, e)))
    end do
  end function edge_lengths

  !> Eq. (46) from the cell's volume v (`hex_volume`) and edge lengths len
  !> (`edge_lengths`).
  pure real(wp) function quality_of(v, len) result(q)
    real(wp), intent(in) :: v, len(12)
    real(wp) :: l
    integer :: e
    l = 0.0_wp
    do e = 1, 12
      l = l + len(e)
    end do
    q = 1728.0_wp*v/l**3
  end function quality_of

  !> Sides (length) of a hexahedron's own box: the mean lengths of its four
  !> edges along each logical direction, their spread shrunk (in log space,
  !> about their geometric mean, which is kept) until the largest over the
  !> smallest is at most aspect_max (>= 1; 1 gives the cube of the same
  !> geometric mean). Returned as they are if an edge mean is zero.
  pure function hex_box_sides(xn, aspect_max) result(b)
    real(wp), intent(in) :: xn(3, 8), aspect_max
    real(wp) :: b(3)
    b = box_shrunk(hex_edge_means(xn), aspect_max)
  end function hex_box_sides

  !> The edge means b of `hex_box_sides`, shrunk to aspect_max.
  pure function box_shrunk(b0, aspect_max) result(b)
    real(wp), intent(in) :: b0(3), aspect_max
    real(wp) :: b(3)
    real(wp) :: t(3), g, spread
    b = b0
    if (any(.not. b > 0.0_wp)) return
    ! logs of the ratios to b(1), so that scaling the cell by a power of two
    ! scales the result bit for bit (dimensional invariance)
    t = log(b/b(1))
    g = sum(t)/3.0_wp
    t = t - g
    spread = maxval(t) - minval(t)
    if (spread > log(aspect_max)) then
      t = t*(log(aspect_max)/spread)
      b = b(1)*exp(g + t)
    end if
  end function box_shrunk

  !> The mean lengths of a hexahedron's four edges along each logical
  !> direction (length): `hex_box_sides` before any shrinking.
  pure function hex_edge_means(xn) result(b)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: b(3)
    b = edge_means_of(edge_lengths(xn))
  end function hex_edge_means

  !> `hex_edge_means` from the edge lengths len (`edge_lengths`), summed in
  !> the order of `hex_edges`.
  pure function edge_means_of(len) result(b)
    real(wp), intent(in) :: len(12)
    real(wp) :: b(3)
    integer :: d, e
    do d = 1, 3
      b(d) = 0.0_wp
      do e = 1, 4
        b(d) = b(d) + len(edge_slot(e, d))
      end do
      b(d) = 0.25_wp*b(d)
    end do
  end function edge_means_of

  !> Eq. (46) against the cell's own box (`hex_box_sides` with aspect_max):
  !> 1728 V / L^3 divided by 27 b1 b2 b3 / (b1 + b2 + b3)^3, the Eq. (46) of
  !> the box. 1 for a box of aspect ratio at most aspect_max whatever its
  !> proportions; below 1 as the cell is sheared, tangled or stretched beyond
  !> aspect_max (a 4:1 box has 0.69 with aspect_max 2). aspect_max = 1 gives
  !> Eq. (46) itself (exactly); so does a cell with a zero mean edge.
  pure function hex_quality_box(xn, aspect_max) result(q)
    real(wp), intent(in) :: xn(3, 8), aspect_max
    real(wp) :: q
    real(wp) :: b(3), v
    call hex_quality_box_parts(xn, aspect_max, q, b, v)
  end function hex_quality_box

  !> `hex_quality_box` q, with what it is made of: the cell's own box b
  !> (`hex_box_sides`, the same numbers) and its volume v (`hex_volume`),
  !> for a smoothing pass at the same nodes (`smooth_combined`).
  pure subroutine hex_quality_box_parts(xn, aspect_max, q, b, v)
    real(wp), intent(in) :: xn(3, 8), aspect_max
    real(wp), intent(out) :: q, b(3), v
    real(wp) :: len(12)
    len = edge_lengths(xn)
    v = hex_volume(xn)
    q = quality_of(v, len)
    b = box_shrunk(edge_means_of(len), aspect_max)
    if (.not. aspect_max > 1.0_wp) return
    if (any(.not. b > 0.0_wp)) return
    q = q*sum(b)**3/(27.0_wp*product(b))
  end subroutine hex_quality_box_parts

  !> Eq. (46) for a plane quadrilateral with corners xq(2,4) in cyclic order:
  !> 16 S / L^2.
  pure function quad_quality(xq) result(q)
    real(wp), intent(in) :: xq(2, 4)
    real(wp) :: q
    real(wp) :: s, l
    integer :: a, b
    s = 0.0_wp
    l = 0.0_wp
    do a = 1, 4
      b = mod(a, 4) + 1
      s = s + 0.5_wp*(xq(1, a)*xq(2, b) - xq(1, b)*xq(2, a))
      l = l + norm2(xq(:, b) - xq(:, a))
    end do
    q = 16.0_wp*s/l**2
  end function quad_quality

  !> Largest ratio of edge lengths and cosine of the largest inclined angle:
  !> the smallest |sin| of the angle between two edges at a corner, or with
  !> axis = .true. the smallest cosine of the angle between an edge and the
  !> axis of its logical direction (0 for an edge of zero length; negative
  !> for an edge turned back against its axis: a cell folded through itself
  !> along an axis keeps every |cos| near 1, and must still trip the
  !> trigger).
  pure subroutine hex_shape(xn, side_ratio, cos_incl, axis)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: side_ratio, cos_incl
    logical, intent(in), optional :: axis
    real(wp) :: l2min, l2max, ed(3, 4, 3), le2(4, 3), c2, cr(3), den, cneg
    integer :: k, a, i, j, d
    logical :: by_axis

    ! squares throughout, one square root at the end of each measure (the
    ! triggers evaluate this for every cell at every step); each edge once,
    ! for the side ratio and for the angles at both its corners (an edge
    ! taken from its other end is the same vector negated, exactly, and the
    ! squares below do not see the sign)
    by_axis = .false.
    if (present(axis)) by_axis = axis
    l2min = huge(1.0_wp)
    l2max = 0.0_wp
    c2 = 1.0_wp
    ! (signed: an edge turned back against its axis, as in a cell folded
    ! through itself, has a negative cosine; cneg: the largest square of
    ! those, -1 if none)
    cneg = -1.0_wp
    do d = 1, 3
      do k = 1, 4
        ed(:, k, d) = xn(:, hex_edges(2, k, d)) - xn(:, hex_edges(1, k, d))
        le2(k, d) = ed(1, k, d)**2 + ed(2, k, d)**2 + ed(3, k, d)**2
        l2min = min(l2min, le2(k, d))
        l2max = max(l2max, le2(k, d))
        if (.not. by_axis) cycle
        if (.not. le2(k, d) > 0.0_wp) then
          c2 = 0.0_wp
        else if (ed(d, k, d) > 0.0_wp) then
          c2 = min(c2, ed(d, k, d)**2/le2(k, d))
        else
          cneg = max(cneg, ed(d, k, d)**2/le2(k, d))
        end if
      end do
    end do
    side_ratio = huge(1.0_wp)
    if (l2min > 0.0_wp) side_ratio = sqrt(l2max/l2min)
    if (by_axis) then
      cos_incl = sqrt(c2)
      if (cneg >= 0.0_wp) cos_incl = -sqrt(cneg)
      return
    end if
    do a = 1, 8
      do i = 1, 2
        do j = i + 1, 3
          den = le2(corner_edge(i, a), i)*le2(corner_edge(j, a), j)
          if (den > 0.0_wp) then
            cr = cross(ed(:, corner_edge(i, a), i), ed(:, corner_edge(j, a), j))
            c2 = min(c2, (cr(1)**2 + cr(2)**2 + cr(3)**2)/den)
          else
            c2 = 0.0_wp
          end if
        end do
      end do
    end do
    cos_incl = sqrt(c2)
  end subroutine hex_shape

  !> Quality of every cell of an ni x nj x nk grid with nodes x(3, nnode)
  !> (structured numbering of `mesh_grid`), with the grid-wide minimum of Q
  !> and, if asked for, of the inclined-angle cosine and the maximum side
  !> ratio (`hex_shape`, with axis). q(c) is Eq. (46), or with aspect_max
  !> (>= 1) Eq. (46) against the cell's own box (`hex_quality_box`). With
  !> share (ranks that all hold the grid) each rank computes its share of
  !> the cells and every rank gets all (`base_share`).
  subroutine grid_quality(ni, nj, nk, x, q, q_min, ratio_max, cos_min, aspect_max, axis, share)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: q(:), q_min
    real(wp), intent(out), optional :: ratio_max, cos_min
    real(wp), intent(in), optional :: aspect_max
    logical, intent(in), optional :: axis
    class(share_t), intent(in), optional :: share
    integer :: c, ci, cj, ck, k, nmine, p0, np, stat
    real(wp) :: amax, rmax, cmin, m(3)
    real(wp), allocatable :: v(:, :)
    logical :: box, by_axis, shape, sharing
    type(grid_index_t) :: ix

    ix = grid_index(ni, nj, nk)
    by_axis = .false.
    if (present(axis)) by_axis = axis
    shape = present(ratio_max) .or. present(cos_min)
    box = present(aspect_max)
    amax = 1.0_wp
    if (box) amax = aspect_max
    q_min = huge(1.0_wp)
    rmax = 0.0_wp
    cmin = 1.0_wp
    sharing = .false.
    if (present(share)) sharing = share%nparts > 1
    ! (no room for the shared results: every cell here)
    if (sharing) allocate(v(3, ix%ncell), stat=stat)
    if (sharing) sharing = stat == 0
    if (.not. sharing) then
      !$omp parallel do default(none) shared(ix, q) private(c, ci, cj, ck, m) &
      !$omp reduction(min: q_min, cmin) reduction(max: rmax) collapse(2) schedule(static)
      do ck = ix%clo(3), ix%chi(3)
        do cj = ix%clo(2), ix%chi(2)
          do ci = ix%clo(1), ix%chi(1)
            c = ix%cell(ci, cj, ck)
            call measure(ci, cj, ck, m)
            q(c) = m(1)
            q_min = min(q_min, m(1))
            rmax = max(rmax, m(2))
            cmin = min(cmin, m(3))
          end do
        end do
      end do
      !$omp end parallel do
    else
      ! this rank's cells (list order), then every rank's gathered
      p0 = share%part
      np = share%nparts
      nmine = (ix%ncell - p0 + np - 1)/np
      !$omp parallel do default(none) shared(ix, v, p0, np, nmine) private(k, ci, cj, ck) schedule(static)
      do k = 1, nmine
        call ix%cell_ijk(p0 + 1 + (k - 1)*np, ci, cj, ck)
        call measure(ci, cj, ck, v(:, k))
      end do
      !$omp end parallel do
      call share%columns(ix%ncell, v)
      do c = 1, ix%ncell
        q(c) = v(1, c)
        q_min = min(q_min, v(1, c))
        rmax = max(rmax, v(2, c))
        cmin = min(cmin, v(3, c))
      end do
    end if
    if (present(ratio_max)) ratio_max = rmax
    if (present(cos_min)) cos_min = cmin

  contains

    !> Cell (i, j, k)'s quality and, if asked for, its side ratio and
    !> cosine (else 0 and 1).
    subroutine measure(i, j, k, m)
      integer, intent(in) :: i, j, k
      real(wp), intent(out) :: m(3)
      real(wp) :: xn(3, 8)
      call block_gather(ni, nj, i, j, k, x, xn)
      if (box) then
        m(1) = hex_quality_box(xn, amax)
      else
        m(1) = hex_quality(xn)
      end if
      m(2:3) = [0.0_wp, 1.0_wp]
      if (shape) call hex_shape(xn, m(2), m(3), by_axis)
    end subroutine measure
  end subroutine grid_quality

  !> The cells of an ni x nj x nk grid that fail the Euler-step triggers' own
  !> tests (Sect. 5.1): fail(c) is true when the cell's side ratio reaches
  !> side_ratio (if > 0) or its inclined-angle cosine falls to cos_angle (if
  !> > 0), `hex_shape`; or when it is tangled (a corner's three edges, along
  !> +i, +j, +k, span a non-positive volume). These are the cells that make
  !> the grid "determined distorted", so an Euler step that does not move
  !> them fires again at the next step. The inclined angle is measured
  !> against the axes (`hex_shape` with axis), as the box reading's trigger.
  !> With x0 (the standard grid, nodes as x) the side ratio is measured
  !> against the cell's there (`standard_side_ratio`), as the triggers do.
  subroutine grid_trigger_cells(ni, nj, nk, x, side_ratio, cos_angle, fail, share, shape_fail, lo, hi, x0)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :), side_ratio, cos_angle
    logical, intent(out) :: fail(:)
    !> ranks that all hold the grid, sharing the cells (`base_share`)
    class(share_t), intent(in), optional :: share
    !> the side-ratio and angle tests already taken on these nodes x for
    !> the cells (lo:hi) of the grid (`grid_shape_worst`'s fail, with the
    !> same bounds): there only the tangle test is left to take (not with
    !> share)
    logical, intent(in), optional :: shape_fail(:)
    integer, intent(in), optional :: lo(3), hi(3)
    real(wp), intent(in), optional :: x0(:, :)
    integer :: c, ci, cj, ck, k, nmine, p0, np, stat, klo(3), khi(3)
    real(wp), allocatable :: v(:, :)
    logical :: sharing
    type(grid_index_t) :: ix

    ix = grid_index(ni, nj, nk)
    sharing = .false.
    if (present(share)) sharing = share%nparts > 1
    if (sharing) allocate(v(1, ix%ncell), stat=stat)
    if (sharing) sharing = stat == 0
    if (.not. sharing) then
      ! (the cells whose shape tests are known: none without shape_fail)
      klo = 1
      khi = 0
      if (present(shape_fail) .and. present(lo) .and. present(hi)) then
        klo = lo
        khi = hi
      end if
      !$omp parallel do default(none) shared(ix, fail, shape_fail, klo, khi, x0) private(c, ci, cj, ck) &
      !$omp collapse(2) schedule(static)
      do ck = ix%clo(3), ix%chi(3)
        do cj = ix%clo(2), ix%chi(2)
          do ci = ix%clo(1), ix%chi(1)
            c = ix%cell(ci, cj, ck)
            if (ci >= klo(1) .and. ci <= khi(1) .and. cj >= klo(2) .and. cj <= khi(2) .and. &
                ck >= klo(3) .and. ck <= khi(3)) then
              fail(c) = shape_fail(c)
              if (.not. fail(c)) fail(c) = gathered_tangled(ci, cj, ck)
            else
              fail(c) = fails(ci, cj, ck)
            end if
          end do
        end do
      end do
      !$omp end parallel do
      return
    end if
    p0 = share%part
    np = share%nparts
    nmine = (ix%ncell - p0 + np - 1)/np
    !$omp parallel do default(none) shared(ix, v, p0, np, nmine, x0) private(k, ci, cj, ck) schedule(static)
    do k = 1, nmine
      call ix%cell_ijk(p0 + 1 + (k - 1)*np, ci, cj, ck)
      v(1, k) = merge(1.0_wp, 0.0_wp, fails(ci, cj, ck))
    end do
    !$omp end parallel do
    call share%columns(ix%ncell, v)
    fail = v(1, :) > 0.5_wp

  contains

    !> Whether cell (i, j, k) fails the tests.
    logical function fails(i, j, kk)
      integer, intent(in) :: i, j, kk
      real(wp) :: xn(3, 8), xn0(3, 8)
      call block_gather(ni, nj, i, j, kk, x, xn)
      if (present(x0)) then
        call block_gather(ni, nj, i, j, kk, x0, xn0)
        fails = hex_fails_triggers(xn, side_ratio, cos_angle, xn0)
      else
        fails = hex_fails_triggers(xn, side_ratio, cos_angle)
      end if
    end function fails

    !> Whether cell (i, j, k) is tangled (`hex_corner_tangled`).
    logical function gathered_tangled(i, j, kk)
      integer, intent(in) :: i, j, kk
      real(wp) :: xn(3, 8)
      call block_gather(ni, nj, i, j, kk, x, xn)
      gathered_tangled = hex_corner_tangled(xn)
    end function gathered_tangled
  end subroutine grid_trigger_cells

  !> Whether a hexahedron with nodes xn is tangled: a corner's three edges,
  !> along +i, +j, +k, span a non-positive volume. (Each edge is taken once,
  !> from its lower node to its upper one: the value the corner at either
  !> end reads, as xn(b) - xn(a) or its negation.)
  pure logical function hex_corner_tangled(xn) result(tangled)
    real(wp), intent(in) :: xn(3, 8)
    !> corner a's edge along direction d: the edge's number in 1..4 among
    !> the four along d (the corner's other two index bits)
    integer, parameter :: edge_of(3, 8) = reshape([1, 1, 1, 1, 2, 2, 2, 1, 3, 2, 2, 4, 3, 3, 1, 3, 4, 2, &
                                                   4, 3, 3, 4, 4, 4], [3, 8])
    !> the four edges along each direction: their lower and upper nodes
    integer, parameter :: lower(4, 3) = reshape([1, 3, 5, 7, 1, 2, 5, 6, 1, 2, 3, 4], [4, 3])
    integer, parameter :: step(3) = [1, 2, 4]
    real(wp) :: ed(3, 4, 3), e(3, 3), jmin
    integer :: a, d, q
    do d = 1, 3
      do q = 1, 4
        ed(:, q, d) = xn(:, lower(q, d) + step(d)) - xn(:, lower(q, d))
      end do
    end do
    jmin = huge(1.0_wp)
    do a = 1, 8
      do d = 1, 3
        e(:, d) = ed(:, edge_of(d, a), d)
      end do
      jmin = min(jmin, e(1, 1)*(e(2, 2)*e(3, 3) - e(3, 2)*e(2, 3)) - e(2, 1)*(e(1, 2)*e(3, 3) - &
                 e(3, 2)*e(1, 3)) + e(3, 1)*(e(1, 2)*e(2, 3) - e(2, 2)*e(1, 3)))
    end do
    tangled = .not. jmin > 0.0_wp
  end function hex_corner_tangled

  !> A cell's side ratio on the standard grid (nodes xn0), against which the
  !> triggers measure its side ratio: `hex_shape`'s, or 1 for a cell
  !> within 1e-9 of equal sides (a grid of cubes is measured as the paper
  !> measures it, bit for bit). A cell the deck made long (a quasi-1D tube,
  !> a graded grid) then triggers when it is side_ratio times as long as
  !> it was made, not at every step: an Euler step cannot bring it below
  !> its standard shape.
  pure real(wp) function standard_side_ratio(xn0) result(r0)
    real(wp), intent(in) :: xn0(3, 8)
    real(wp) :: cs
    call hex_shape(xn0, r0, cs)
    if (.not. r0 > 1.0_wp + 1.0e-9_wp) r0 = 1.0_wp
  end function standard_side_ratio

  !> Each of g's stored cells' `standard_side_ratio` on its nodes as they
  !> are now (the standard grid), in ratio0(ncell).
  subroutine grid_standard_ratios(g, ratio0)
    type(grid_t), intent(in) :: g
    real(wp), intent(out) :: ratio0(:)
    real(wp) :: xn(3, 8)
    integer :: c
    do c = 1, g%ncell
      call g%gather(c, g%x, xn)
      ratio0(c) = standard_side_ratio(xn)
    end do
  end subroutine grid_standard_ratios

  !> Whether the cell of nodes xn fails the Euler-step triggers' own tests
  !> (`grid_trigger_cells`); xn0: its nodes in the standard grid, against
  !> whose side ratio its own is measured.
  pure logical function hex_fails_triggers(xn, side_ratio, cos_angle, xn0) result(fails)
    real(wp), intent(in) :: xn(3, 8), side_ratio, cos_angle
    real(wp), intent(in), optional :: xn0(3, 8)
    real(wp) :: r, cs
    call hex_shape(xn, r, cs, .true.)
    if (present(xn0) .and. side_ratio > 0.0_wp .and. r >= side_ratio) r = r/standard_side_ratio(xn0)
    fails = shape_fails(r, cs, side_ratio, cos_angle)
    if (fails) return
    fails = hex_corner_tangled(xn)
  end function hex_fails_triggers

  !> Whether a cell of side ratio r and inclined-angle cosine cs fails the
  !> Euler-step triggers' bounds (each test on if its bound is > 0).
  pure logical function shape_fails(r, cs, side_ratio, cos_angle)
    real(wp), intent(in) :: r, cs, side_ratio, cos_angle
    shape_fails = (side_ratio > 0.0_wp .and. r >= side_ratio) .or. (cos_angle > 0.0_wp .and. cs <= cos_angle)
  end function shape_fails

  !> The largest side ratio and smallest inclined-angle cosine over the
  !> cells g's block owns (`hex_shape`, axis as there) in worst(1:2), and
  !> the whole grid's number of the first owned cell with each in first(1:2)
  !> (0 and 1, and huge, when the block owns no cell). Each thread keeps
  !> its cells' first worst (its cells come in the whole grid's order); the
  !> threads' are combined by value, then by the lower number, so the result
  !> does not depend on the threads. With ratio0 (each cell's side ratio
  !> on the standard grid, `standard_side_ratio`) a cell's side ratio is
  !> measured against it: r / ratio0(c). With keep (2, ncell) and moved
  !> (nnode): keep holds each owned cell's (r, cs) of an earlier look, and
  !> moved flags the nodes that moved since; a cell with no moved node
  !> takes its kept pair (the same numbers it would measure), the others
  !> are measured and their pair kept.
  subroutine grid_shape_worst(g, axis, worst, first, bounds, fail, ratio0, keep, moved)
    type(grid_t), intent(in) :: g
    logical, intent(in) :: axis
    real(wp), intent(out) :: worst(2), first(2)
    !> with fail: the triggers' side-ratio and cosine bounds, and fail(c)
    !> set for each owned cell c to whether it reaches one
    !> (`shape_fails`: what `grid_trigger_cells` tests before the tangle)
    real(wp), intent(in), optional :: bounds(2)
    logical, intent(inout), optional :: fail(:)
    real(wp), intent(in), optional :: ratio0(:)
    real(wp), intent(inout), optional :: keep(:, :)
    logical, intent(in), optional :: moved(:)
    real(wp) :: xn(3, 8), r, cs, ratio_max, cos_min, fr, fc, rt, ct, frt, fct, bnd(2)
    integer :: i, j, k, c, a, n0
    logical :: flags, relative, kept, stale
    ratio_max = -huge(1.0_wp)
    cos_min = huge(1.0_wp)
    fr = huge(1.0_wp)
    fc = huge(1.0_wp)
    flags = present(bounds) .and. present(fail)
    bnd = 0.0_wp
    if (flags) bnd = bounds
    relative = present(ratio0)
    kept = present(keep) .and. present(moved)
    !$omp parallel default(none) shared(g, axis, ratio_max, cos_min, fr, fc, flags, bnd, fail, relative, ratio0, kept, &
    !$omp keep, moved) private(i, j, k, c, xn, r, cs, rt, ct, frt, fct, a, n0, stale)
    rt = -huge(1.0_wp)
    ct = huge(1.0_wp)
    frt = huge(1.0_wp)
    fct = huge(1.0_wp)
    !$omp do collapse(2) schedule(static)
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          c = g%cell(i, j, k)
          stale = .true.
          if (kept) then
            n0 = g%node0(c)
            stale = .false.
            do a = 1, 8
              stale = stale .or. moved(n0 + g%corner_offset(a))
            end do
          end if
          if (stale) then
            call g%gather(c, g%x, xn)
            call hex_shape(xn, r, cs, axis)
            if (relative) r = r/ratio0(c)
            if (kept) keep(:, c) = [r, cs]
          else
            r = keep(1, c)
            cs = keep(2, c)
          end if
          if (flags) fail(c) = shape_fails(r, cs, bnd(1), bnd(2))
          if (r > rt) then
            rt = r
            frt = real(g%global_cell(c), wp)
          end if
          if (cs < ct) then
            ct = cs
            fct = real(g%global_cell(c), wp)
          end if
        end do
      end do
    end do
    !$omp end do
    !$omp critical (grid_shape_worst_combine)
    if (rt > ratio_max .or. (.not. rt < ratio_max .and. frt < fr)) then
      ratio_max = rt
      fr = frt
    end if
    if (ct < cos_min .or. (.not. ct > cos_min .and. fct < fc)) then
      cos_min = ct
      fc = fct
    end if
    !$omp end critical (grid_shape_worst_combine)
    !$omp end parallel
    ! (as the bounds 0 and 1 of the measures started them before)
    worst = [max(ratio_max, 0.0_wp), min(cos_min, 1.0_wp)]
    first = [fr, fc]
  end subroutine grid_shape_worst
end module rezone_quality
