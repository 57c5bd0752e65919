!> Grid quality: the cell quality Q of Eq. (46) and the Euler-step
!> triggers of the paper (the largest ratio of side lengths and the cosine of
!> the largest inclined angle).
!>
!> Q = 1728 V / L^3 for a hexahedron (V its exact volume, L the sum of its 12
!> edge lengths) and Q = 16 S / L^2 for a quadrilateral (S its area, L its
!> perimeter); both are 1 for a cube or a square and fall as a cell is
!> stretched, sheared or tangled (Q <= 0 for an inverted cell). The inclined
!> angle at a corner is how far the angle between two of its edges departs
!> from a right angle: cos(inclined) = sin(angle between the edges) =
!> |e1 x e2| / (|e1| |e2|), 1 for a cube; a run triggers an Euler step when
!> the smallest of these over all cells falls to the deck's bound (0.7 in the
!> paper's Sedov test) or the largest side ratio reaches its bound (4).
module rezone_quality
  use base_kinds, only: wp
  use mesh_geometry, only: hex_volume, cross
  use mesh_grid, only: block_gather, grid_index_t, grid_index
  implicit none
  private
  public :: hex_quality, quad_quality, hex_shape, grid_quality, grid_worst_cells

  !> The 12 edges of a hexahedron as (node, node) in the local numbering.
  integer, parameter :: hex_edge_list(2, 12) = reshape([1, 2, 3, 4, 5, 6, 7, 8, &
                                                        1, 3, 2, 4, 5, 7, 6, 8, &
                                                        1, 5, 2, 6, 3, 7, 4, 8], [2, 12])
  !> The three neighbours of each corner along the three logical directions.
  integer, parameter :: corner_nbr(3, 8) = reshape([2, 3, 5,  1, 4, 6,  4, 1, 7,  3, 2, 8, &
                                                    6, 7, 1,  5, 8, 2,  8, 5, 3,  7, 6, 4], [3, 8])

contains

  !> Eq. (46) for a hexahedron with nodes xn(3,8): 1728 V / L^3.
  pure function hex_quality(xn) result(q)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: q
    real(wp) :: l
    integer :: e
    l = 0.0_wp
    do e = 1, 12
      l = l + norm2(xn(:, hex_edge_list(2, e)) - xn(:, hex_edge_list(1, e)))
    end do
    q = 1728.0_wp*hex_volume(xn)/l**3
  end function hex_quality

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

  !> Largest ratio of edge lengths and cosine of the largest inclined angle
  !> (the smallest |sin| of the angle between two edges at a corner).
  pure subroutine hex_shape(xn, side_ratio, cos_incl)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: side_ratio, cos_incl
    real(wp) :: lmin, lmax, le, e(3, 3), ne(3)
    integer :: k, a, i, j

    lmin = huge(1.0_wp)
    lmax = 0.0_wp
    do k = 1, 12
      le = norm2(xn(:, hex_edge_list(2, k)) - xn(:, hex_edge_list(1, k)))
      lmin = min(lmin, le)
      lmax = max(lmax, le)
    end do
    side_ratio = huge(1.0_wp)
    if (lmin > 0.0_wp) side_ratio = lmax/lmin
    cos_incl = 1.0_wp
    do a = 1, 8
      do i = 1, 3
        e(:, i) = xn(:, corner_nbr(i, a)) - xn(:, a)
        ne(i) = norm2(e(:, i))
      end do
      do i = 1, 2
        do j = i + 1, 3
          if (ne(i) > 0.0_wp .and. ne(j) > 0.0_wp) then
            cos_incl = min(cos_incl, norm2(cross(e(:, i), e(:, j)))/(ne(i)*ne(j)))
          else
            cos_incl = 0.0_wp
          end if
        end do
      end do
    end do
  end subroutine hex_shape

  !> Quality of every cell of an ni x nj x nk grid with nodes x(3, nnode)
  !> (structured numbering of `mesh_grid`), with the grid-wide minimum of Q
  !> and of the inclined-angle cosine and the maximum side ratio.
  subroutine grid_quality(ni, nj, nk, x, q, q_min, ratio_max, cos_min)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: q(:), q_min, ratio_max, cos_min
    integer :: c, ci, cj, ck
    real(wp) :: xn(3, 8), r, cs
    type(grid_index_t) :: ix

    ix = grid_index(ni, nj, nk)
    q_min = huge(1.0_wp)
    ratio_max = 0.0_wp
    cos_min = 1.0_wp
    !$omp parallel do default(none) shared(ni, nj, nk, ix, x, q) private(c, ci, cj, ck, xn, r, cs) &
    !$omp reduction(min: q_min, cos_min) reduction(max: ratio_max) collapse(2) schedule(static)
    do ck = ix%clo(3), ix%chi(3)
      do cj = ix%clo(2), ix%chi(2)
        do ci = ix%clo(1), ix%chi(1)
          c = ix%cell(ci, cj, ck)
          call block_gather(ni, nj, ci, cj, ck, x, xn)
          q(c) = hex_quality(xn)
          call hex_shape(xn, r, cs)
          q_min = min(q_min, q(c))
          ratio_max = max(ratio_max, r)
          cos_min = min(cos_min, cs)
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine grid_quality

  !> Cell indices (i, j, k) of the cell with the largest side ratio and of
  !> the cell with the smallest inclined-angle cosine (the first such cell
  !> in storage order): where a trigger fired.
  subroutine grid_worst_cells(ni, nj, nk, x, ijk_ratio, ijk_cos)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :)
    integer, intent(out) :: ijk_ratio(3), ijk_cos(3)
    integer :: ci, cj, ck
    real(wp) :: xn(3, 8), r, cs, r_max, cs_min

    r_max = -1.0_wp
    cs_min = huge(1.0_wp)
    ijk_ratio = 1
    ijk_cos = 1
    do ck = 1, nk
      do cj = 1, nj
        do ci = 1, ni
          call block_gather(ni, nj, ci, cj, ck, x, xn)
          call hex_shape(xn, r, cs)
          if (r > r_max) then
            r_max = r
            ijk_ratio = [ci, cj, ck]
          end if
          if (cs < cs_min) then
            cs_min = cs
            ijk_cos = [ci, cj, ck]
          end if
        end do
      end do
    end do
  end subroutine grid_worst_cells
end module rezone_quality
