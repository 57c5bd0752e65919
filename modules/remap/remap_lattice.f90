!> The new grid of an Euler step as a rectilinear lattice: the geometric
!> kernel of the old-cell side of the box intersection (`remap_euler`).
!>
!> When every new node lies on the planes x = X(i), y = Y(j), z = Z(k) (the
!> initial box grid an Eulerian or global rezone returns to), the new cells'
!> subcells are the half-cells of the lattice: the slabs between the planes
!> X(i) and the mid-planes (X(i) + X(i+1))/2 in each direction. An old half
!> tetrahedron then lands in the half-cells its bounding box reaches, and
!> its part in each is the tetrahedron clipped by that half-cell's six
!> planes (only those that cut it). Each old half is clipped once per
!> Euler step, however many new cells it meets, where the new-cell side
!> (`remap_new_cell`) clips every half that reaches a new cell's box once
!> per new cell: about 300 halves per new cell, most of them to nothing.
!>
!> Every part is clipped from the whole tetrahedron by its own half-cell's
!> planes, in the order x, y, z (never from what a neighbouring part left),
!> so a part depends only on the tetrahedron and its six planes: the same
!> numbers on a window of the lattice as on the whole grid (rank
!> invariance).
module remap_lattice
  use base_kinds, only: wp, i8
  use mesh_grid, only: grid_index_t
  use geometry_polyhedron, only: poly_t, poly_set_tet, poly_clip, poly_clip_axis, poly_first_moments, poly_copy
  implicit none
  private
  public :: lattice_t, lattice_nodes, lattice_build, lattice_tet

  !> The half-cell planes of a lattice: plane(2m, d) the m-th node plane in
  !> direction d (m = 0 at the first stored node), plane(2m+1, d) the
  !> mid-plane after it; nq(d) half-cells, the half-cell q between plane(q)
  !> and plane(q+1) (cell q/2 from the first, its high half if q is odd).
  type :: lattice_t
    logical :: on = .false.
    integer :: nq(3) = 0
    real(wp), allocatable :: plane(:, :)
  end type lattice_t

contains

  !> Whether the stored nodes of the block gi at positions x lie on a
  !> rectilinear lattice with increasing coordinates: each node's x the
  !> same as its row's first node's (likewise y, z), and the planes in
  !> increasing order. Exact comparisons: the lattice path is taken only
  !> where the new cells are boxes to the last bit.
  logical function lattice_nodes(gi, x) result(ok)
    class(grid_index_t), intent(in) :: gi
    real(wp), intent(in) :: x(:, :)
    integer :: i, j, k, i0, j0, k0, n0, m0, nbad
    real(wp) :: y, z
    i0 = gi%slo(1) - 1
    j0 = gi%slo(2) - 1
    k0 = gi%slo(3) - 1
    m0 = gi%node(i0, j0, k0) - i0
    nbad = 0
    ! (a row's nodes are consecutive: node(i, j, k) = n0 + i; counted, not
    ! and-ed, so that the inner loop vectorises)
    !$omp parallel do default(none) shared(gi, x, i0, j0, k0, m0) private(i, j, n0, y, z) reduction(+:nbad) &
    !$omp schedule(static)
    do k = k0, gi%shi(3)
      z = x(3, gi%node(i0, j0, k))
      do j = j0, gi%shi(2)
        y = x(2, gi%node(i0, j, k0))
        n0 = gi%node(i0, j, k) - i0
        do i = i0, gi%shi(1)
          if (abs(x(1, n0 + i) - x(1, m0 + i)) > 0.0_wp .or. abs(x(2, n0 + i) - y) > 0.0_wp &
              .or. abs(x(3, n0 + i) - z) > 0.0_wp) nbad = nbad + 1
        end do
      end do
    end do
    !$omp end parallel do
    ok = nbad == 0
    do i = i0 + 1, gi%shi(1)
      ok = ok .and. x(1, gi%node(i, j0, k0)) > x(1, gi%node(i - 1, j0, k0))
    end do
    do j = j0 + 1, gi%shi(2)
      ok = ok .and. x(2, gi%node(i0, j, k0)) > x(2, gi%node(i0, j - 1, k0))
    end do
    do k = k0 + 1, gi%shi(3)
      ok = ok .and. x(3, gi%node(i0, j0, k)) > x(3, gi%node(i0, j0, k - 1))
    end do
  end function lattice_nodes

  !> The half-cell planes of the lattice of the stored nodes of gi at x
  !> (`lattice_nodes` true); lt%on set.
  subroutine lattice_build(gi, x, lt)
    class(grid_index_t), intent(in) :: gi
    real(wp), intent(in) :: x(:, :)
    type(lattice_t), intent(out) :: lt
    integer :: d, m, n0(3), nn(3), ijk(3)
    n0 = gi%slo - 1
    nn = gi%shi - n0
    lt%nq = 2*nn
    lt%plane = reshape([(0.0_wp, m = 0, 3*(2*maxval(nn) + 1) - 1)], [2*maxval(nn) + 1, 3])
    do d = 1, 3
      do m = 0, nn(d)
        ijk = n0
        ijk(d) = n0(d) + m
        lt%plane(2*m + 1, d) = x(d, gi%node(ijk(1), ijk(2), ijk(3)))
      end do
      do m = 0, nn(d) - 1
        lt%plane(2*m + 2, d) = 0.5_wp*(lt%plane(2*m + 1, d) + lt%plane(2*m + 3, d))
      end do
    end do
    lt%on = .true.
  end subroutine lattice_build

  !> The parts of the tetrahedron t (coordinates about oo), clipped first
  !> by the planes mn(:, i).x <= md(i), in the lattice's half-cells: for
  !> each part with volume, sgn times its volume and first moment (about
  !> oo) added to acc(:, e), the entry after n0 whose code(e) is the
  !> half-cell's qx + nq(1) (qy + nq(2) qz) (64-bit: 8 per cell); entries are appended (n) in
  !> the order the half-cells are first reached, and the arrays grow as
  !> needed. What lies outside the lattice is dropped.
  pure subroutine lattice_tet(lt, oo, hint, t, mn, md, sgn, n0, n, code, acc)
    type(lattice_t), intent(in) :: lt
    real(wp), intent(in) :: oo(3), t(3, 4), mn(:, :), md(:), sgn
    !> a half-cell in each direction near which the parts lie (a start
    !> for the search of their planes)
    integer, intent(in) :: hint(3)
    integer, intent(in) :: n0
    integer, intent(inout) :: n
    integer(i8), allocatable, intent(inout) :: code(:)
    real(wp), allocatable, intent(inout) :: acc(:, :)
    type(poly_t) :: p
    integer :: i

    call poly_set_tet(p, t)
    do i = 1, size(md)
      call poly_clip(p, mn(:, i), md(i))
      if (p%nv == 0) return
    end do
    call lattice_split(lt, oo, hint, sgn, p, 1, 0_i8, n0, n, code, acc)
  end subroutine lattice_tet

  !> The parts of p (`lattice_tet`) in the half-cells of directions d..3,
  !> cq the code of its half-cells in the directions before d.
  recursive pure subroutine lattice_split(lt, oo, hint, sgn, p, d, cq, n0, n, code, acc)
    type(lattice_t), intent(in) :: lt
    real(wp), intent(in) :: oo(3), sgn
    integer, intent(in) :: hint(3)
    type(poly_t), intent(in) :: p
    integer, intent(in) :: d, n0
    integer(i8), intent(in) :: cq
    integer, intent(inout) :: n
    integer(i8), allocatable, intent(inout) :: code(:)
    real(wp), allocatable, intent(inout) :: acc(:, :)
    type(poly_t) :: r
    integer :: qd, q(2)
    integer(i8) :: stride
    real(wp) :: ex(2), a, b, v, m(3)
    if (d > 3) then
      call poly_first_moments(p, v, m)
      if (v > 0.0_wp) call lattice_add(cq, sgn*v, sgn*m, n0, n, code, acc)
      return
    end if
    stride = 1_i8
    if (d > 1) stride = int(lt%nq(1), i8)
    if (d > 2) stride = stride*lt%nq(2)
    call slab_range(lt, d, oo(d), p, hint(d), q, ex)
    do qd = q(1), q(2)
      a = lt%plane(qd + 1, d) - oo(d)
      b = lt%plane(qd + 2, d) - oo(d)
      if (.not. ex(1) < a .and. .not. ex(2) > b) then
        ! all in this half-cell: no copy
        call lattice_split(lt, oo, hint, sgn, p, d + 1, cq + stride*qd, n0, n, code, acc)
        cycle
      end if
      call poly_copy(p, r)
      if (ex(1) < a) call poly_clip_axis(r, d, -1.0_wp, -a)
      if (r%nv > 0 .and. ex(2) > b) call poly_clip_axis(r, d, 1.0_wp, b)
      if (r%nv > 0) call lattice_split(lt, oo, hint, sgn, r, d + 1, cq + stride*qd, n0, n, code, acc)
    end do
  end subroutine lattice_split

  !> Adds the part (volume vq, first moment mq) to the entry after n0 of
  !> code cq, appended if new (`lattice_tet`).
  pure subroutine lattice_add(cq, vq, mq, n0, n, code, acc)
    integer(i8), intent(in) :: cq
    integer, intent(in) :: n0
    real(wp), intent(in) :: vq, mq(3)
    integer, intent(inout) :: n
    integer(i8), allocatable, intent(inout) :: code(:)
    real(wp), allocatable, intent(inout) :: acc(:, :)
    integer :: e
    integer(i8), allocatable :: c2(:)
    real(wp), allocatable :: a2(:, :)
    do e = n0 + 1, n
      if (code(e) == cq) then
        acc(:, e) = acc(:, e) + [vq, mq]
        return
      end if
    end do
    if (n == size(code)) then
      c2 = [code, code]
      a2 = reshape([acc, acc], [4, 2*size(code)])
      call move_alloc(c2, code)
      call move_alloc(a2, acc)
    end if
    n = n + 1
    code(n) = cq
    acc(:, n) = [vq, mq]
  end subroutine lattice_add

  !> The half-cells q(1)..q(2) of direction d that p reaches (coordinates
  !> about o, the d-th of oo), and p's extent ex in that direction; an
  !> empty range (q(2) < q(1)) if p lies outside the lattice.
  pure subroutine slab_range(lt, d, o, p, hint, q, ex)
    type(lattice_t), intent(in) :: lt
    integer, intent(in) :: d, hint
    real(wp), intent(in) :: o
    type(poly_t), intent(in) :: p
    integer, intent(out) :: q(2)
    real(wp), intent(out) :: ex(2)
    ex(1) = minval(p%x(d, 1:p%nv))
    ex(2) = maxval(p%x(d, 1:p%nv))
    q = [0, -1]
    if (ex(2) <= lt%plane(1, d) - o .or. ex(1) >= lt%plane(lt%nq(d) + 1, d) - o) return
    ! the half-cell holding the low end: the last plane at or below it; the
    ! one holding the high end: the last plane strictly below it
    q(1) = last_plane(lt, d, o, ex(1), .false., hint)
    q(2) = last_plane(lt, d, o, ex(2), .true., q(1))
  end subroutine slab_range

  !> The last of the planes 0..nq(d)-1 of direction d (coordinates about o)
  !> below xv (strictly, or at or below it); 0 if none is.
  pure integer function last_plane(lt, d, o, xv, strict, hint) result(k)
    type(lattice_t), intent(in) :: lt
    integer, intent(in) :: d, hint
    real(wp), intent(in) :: o, xv
    logical, intent(in) :: strict
    ! a walk from the hint (the old cell's own half-cell: the parts of its
    ! halves are at most a few half-cells away where the nodes moved less
    ! than a cell)
    k = min(max(hint, 0), lt%nq(d) - 1)
    if (strict) then
      do while (k > 0 .and. .not. lt%plane(k + 1, d) - o < xv)
        k = k - 1
      end do
      do while (k < lt%nq(d) - 1 .and. lt%plane(k + 2, d) - o < xv)
        k = k + 1
      end do
    else
      do while (k > 0 .and. .not. lt%plane(k + 1, d) - o <= xv)
        k = k - 1
      end do
      do while (k < lt%nq(d) - 1 .and. lt%plane(k + 2, d) - o <= xv)
        k = k + 1
      end do
    end if
  end function last_plane

end module remap_lattice
