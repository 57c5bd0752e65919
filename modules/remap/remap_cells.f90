!> Cell moments of a structured block for the remap: each cell's volume and
!> centroid from its 24-tetrahedron split (Fig. 7), the centroid of Eq. (49),
!> sum_t x_t V_t / V. The remap (`remap_euler`) expands its linear
!> reconstructions about these points, and they are what every overlap of a
!> cell sums to, so the same split must give both.
module remap_cells
  use base_kinds, only: wp
  use mesh_grid, only: block_gather, grid_index_t, grid_index
  use mesh_geometry, only: hex_tets, tet_det
  implicit none
  private
  public :: cell_moments

contains

  !> Volume and centroid of every cell of a grid of ni x nj x nk cells with
  !> node positions x(3, nnode) (structured numbering of `mesh_grid`).
  subroutine cell_moments(ni, nj, nk, x, vol, centroid, mask)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(inout) :: vol(:), centroid(:, :)
    !> only the cells where mask(c) is true (the others are left as they are)
    logical, intent(in), optional :: mask(:)
    integer :: c, ci, cj, ck, t
    real(wp) :: xn(3, 8), tets(3, 4, 24), v, m(3), vt
    type(grid_index_t) :: ix

    ix = grid_index(ni, nj, nk)

    !$omp parallel do default(none) shared(ni, nj, nk, ix, x, vol, centroid, mask) &
    !$omp private(c, ci, cj, ck, t, xn, tets, v, m, vt) collapse(2) schedule(static)
    do ck = ix%clo(3), ix%chi(3)
      do cj = ix%clo(2), ix%chi(2)
        do ci = ix%clo(1), ix%chi(1)
          c = ix%cell(ci, cj, ck)
          if (present(mask)) then
            if (.not. mask(c)) cycle
          end if
          call block_gather(ni, nj, ci, cj, ck, x, xn)
          call hex_tets(xn, tets)
          v = 0.0_wp
          m = 0.0_wp
          do t = 1, 24
            vt = tet_det(tets(:, :, t))/6.0_wp
            v = v + vt
            m = m + vt*0.25_wp*(tets(:, 1, t) + tets(:, 2, t) + tets(:, 3, t) + tets(:, 4, t))
          end do
          vol(c) = v
          centroid(:, c) = m/v
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine cell_moments
end module remap_cells
