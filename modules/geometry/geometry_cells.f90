!> Cell moments of a structured block for the remap: each cell's volume and
!> centroid from its 24-tetrahedron split (Fig. 7), the centroid of Eq. (49),
!> sum_t x_t V_t / V. The remap (`remap_euler`) expands its linear
!> reconstructions about these points, and they are what every overlap of a
!> cell sums to, so the same split must give both.
module geometry_cells
  use base_kinds, only: wp
  use mesh_grid, only: block_gather, grid_index_t, grid_index
  use mesh_geometry, only: hex_faces
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
  !> x (any) cells with node positions x: the sums over its 24 tetrahedra
  !> (centre, face centre, the face's edge), as `hex_tets` and `tet_det`
  !> give them, without building them (the centre's offsets once per face).
  subroutine one_cell(ni, nj, ci, cj, ck, x, v, cen)
    integer, intent(in) :: ni, nj, ci, cj, ck
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: v, cen(3)
    real(wp) :: xn(3, 8), xc(3), xf(3), a(3), b(3), c(3), m(3), vt
    integer :: f, k, i
    call block_gather(ni, nj, ci, cj, ck, x, xn)
    do i = 1, 3
      xc(i) = 0.125_wp*sum(xn(i, :))
    end do
    v = 0.0_wp
    m = 0.0_wp
    ! (unrolled whole: the faces' nodes by constant indices)
    !GCC$ unroll 6
    do f = 1, 6
      xf = 0.25_wp*((xn(:, hex_faces(1, f)) + xn(:, hex_faces(3, f))) + &
                    (xn(:, hex_faces(2, f)) + xn(:, hex_faces(4, f))))
      a = xf - xc
      do k = 1, 4
        associate (p => xn(:, hex_faces(k, f)), q => xn(:, hex_faces(mod(k, 4) + 1, f)))
          b = p - xc
          c = q - xc
          vt = (a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) + a(3)*(b(1)*c(2) - b(2)*c(1)))/6.0_wp
          v = v + vt
          m = m + vt*0.25_wp*(xc + xf + p + q)
        end associate
      end do
    end do
    cen = m/v
  end subroutine one_cell
end module geometry_cells
