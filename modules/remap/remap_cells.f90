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
  subroutine cell_moments(ni, nj, nk, x, vol, centroid, cells)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(inout) :: vol(:), centroid(:, :)
    !> only these cells (the others are left as they are; absent: every cell)
    integer, intent(in), optional :: cells(:)
    integer :: c, ci, cj, ck, i
    type(grid_index_t) :: ix

    ix = grid_index(ni, nj, nk)
    if (present(cells)) then
      !$omp parallel do default(none) shared(ni, nj, ix, x, vol, centroid, cells) private(i, c, ci, cj, ck) &
      !$omp schedule(static)
      do i = 1, size(cells)
        c = cells(i)
        call ix%cell_ijk(c, ci, cj, ck)
        call one_cell(ni, nj, ci, cj, ck, x, vol(c), centroid(:, c))
      end do
      !$omp end parallel do
      return
    end if
    !$omp parallel do default(none) shared(ni, nj, ix, x, vol, centroid) private(c, ci, cj, ck) &
    !$omp collapse(2) schedule(static)
    do ck = ix%clo(3), ix%chi(3)
      do cj = ix%clo(2), ix%chi(2)
        do ci = ix%clo(1), ix%chi(1)
          c = ix%cell(ci, cj, ck)
          call one_cell(ni, nj, ci, cj, ck, x, vol(c), centroid(:, c))
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine cell_moments

  !> Volume v and centroid cen of cell (ci, cj, ck) of a block of ni x nj
  !> x (any) cells with node positions x: the sums over its 24 tetrahedra.
  subroutine one_cell(ni, nj, ci, cj, ck, x, v, cen)
    integer, intent(in) :: ni, nj, ci, cj, ck
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: v, cen(3)
    real(wp) :: xn(3, 8), tets(3, 4, 24), m(3), vt
    integer :: t
    call block_gather(ni, nj, ci, cj, ck, x, xn)
    call hex_tets(xn, tets)
    v = 0.0_wp
    m = 0.0_wp
    do t = 1, 24
      vt = tet_det(tets(:, :, t))/6.0_wp
      v = v + vt
      m = m + vt*0.25_wp*(tets(:, 1, t) + tets(:, 2, t) + tets(:, 3, t) + tets(:, 4, t))
    end do
    cen = m/v
  end subroutine one_cell
end module remap_cells
