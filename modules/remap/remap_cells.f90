!> Cell remap by exact intersection: the overlaps of new cells with old
!> cells and the conservative transfer of cell quantities (Eqs. 54-55).
!>
!> Both grids share the index space of the structured block, so a new cell
!> can only overlap the old cells within `reach` index steps of itself
!> (reach 1 when no node moved by more than about a cell). Each new cell is
!> split into its 24 tetrahedra (Fig. 7) and each tetrahedron is intersected
!> exactly with every candidate old cell whose bounding box it touches
!> (`remap_polyhedron`), which gives the volume and first moment of every
!> (new cell, old cell) overlap. A density field given per old cell as a mean
!> value and, optionally, a gradient (linear reconstruction about the old
!> cell's centroid) is then integrated exactly over the overlaps: constant
!> fields are remapped exactly, linear ones too when their gradients are
!> exact, and the totals are conserved to round-off because the overlaps of
!> every old cell add up to it when the two grids cover the same domain.
!> This first version handles pure cells; material polyhedra (MoF) and the
!> nodal (momentum) remap come next.
module remap_cells
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set
  use mesh_grid, only: block_gather
  use remap_polyhedron, only: hex_tets, tet_intersect_split
  implicit none
  private
  public :: overlap_t, remap_overlaps, remap_density, cell_moments

  !> Overlaps of every new cell with the old cells: entries 1..count(c) of
  !> column c hold the old cell, the overlap volume and its first moment.
  type :: overlap_t
    integer :: maxent = 0
    integer, allocatable :: count(:)        !< (ncell)
    integer, allocatable :: old(:, :)       !< (maxent, ncell)
    real(wp), allocatable :: vol(:, :)      !< (maxent, ncell)
    real(wp), allocatable :: mom(:, :, :)   !< (3, maxent, ncell)
  end type overlap_t

contains

  !> Volume and centroid of every cell of a grid of ni x nj x nk cells with
  !> node positions x(3, nnode) (structured numbering of `mesh_grid`).
  subroutine cell_moments(ni, nj, nk, x, vol, centroid)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: vol(:), centroid(:, :)
    integer :: c, ci, cj, ck, t
    real(wp) :: xn(3, 8), tets(3, 4, 24), v, m(3), vt

    !$omp parallel do default(none) shared(ni, nj, nk, x, vol, centroid) &
    !$omp private(c, ci, cj, ck, t, xn, tets, v, m, vt) collapse(2) schedule(static)
    do ck = 1, nk
      do cj = 1, nj
        do ci = 1, ni
          c = ci + ni*((cj - 1) + nj*(ck - 1))
          call block_gather(ni, nj, ci, cj, ck, x, xn)
          call hex_tets(xn, tets)
          v = 0.0_wp
          m = 0.0_wp
          do t = 1, 24
            vt = det3(tets(:, 2, t) - tets(:, 1, t), tets(:, 3, t) - tets(:, 1, t), &
                      tets(:, 4, t) - tets(:, 1, t))/6.0_wp
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

  !> Overlaps of the new grid xnew with the old grid xold (same block of
  !> ni x nj x nk cells), searching `reach` index steps around each cell.
  subroutine remap_overlaps(ni, nj, nk, xold, xnew, reach, ov, err)
    integer, intent(in) :: ni, nj, nk, reach
    real(wp), intent(in) :: xold(:, :), xnew(:, :)
    type(overlap_t), intent(out) :: ov
    type(error_t), allocatable, intent(inout) :: err
    integer :: c, ci, cj, ck, oi, oj, ok_, co, t, stat, n
    real(wp) :: xn(3, 8), xo(3, 8), tets(3, 4, 24), otets(3, 4, 24), lo(3), hi(3), tlo(3), thi(3), v, m(3), &
                vsum, msum(3)
    character(len=200) :: msg

    ov%maxent = (2*reach + 1)**3
    allocate(ov%count(ni*nj*nk), ov%old(ov%maxent, ni*nj*nk), ov%vol(ov%maxent, ni*nj*nk), &
             ov%mom(3, ov%maxent, ni*nj*nk), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_overlaps', 'cannot allocate the overlaps: '//trim(msg))
      return
    end if
    !$omp parallel do default(none) shared(ni, nj, nk, xold, xnew, reach, ov) &
    !$omp private(c, ci, cj, ck, oi, oj, ok_, co, t, n, xn, xo, tets, otets, lo, hi, tlo, thi, v, m, vsum, msum) &
    !$omp collapse(2) schedule(dynamic, 1)
    do ck = 1, nk
      do cj = 1, nj
        do ci = 1, ni
          c = ci + ni*((cj - 1) + nj*(ck - 1))
          call block_gather(ni, nj, ci, cj, ck, xnew, xn)
          call hex_tets(xn, tets)
          n = 0
          do ok_ = max(1, ck - reach), min(nk, ck + reach)
            do oj = max(1, cj - reach), min(nj, cj + reach)
              do oi = max(1, ci - reach), min(ni, ci + reach)
                co = oi + ni*((oj - 1) + nj*(ok_ - 1))
                call block_gather(ni, nj, oi, oj, ok_, xold, xo)
                lo = minval(xo, 2)
                hi = maxval(xo, 2)
                if (any(maxval(xn, 2) < lo) .or. any(minval(xn, 2) > hi)) cycle
                ! the old cell's split once, for all 24 new tetrahedra
                call hex_tets(xo, otets)
                vsum = 0.0_wp
                msum = 0.0_wp
                do t = 1, 24
                  tlo = minval(tets(:, :, t), 2)
                  thi = maxval(tets(:, :, t), 2)
                  if (any(thi < lo) .or. any(tlo > hi)) cycle
                  call tet_intersect_split(tets(:, :, t), otets, v, m)
                  vsum = vsum + v
                  msum = msum + m
                end do
                if (.not. (abs(vsum) > 0.0_wp)) cycle
                n = n + 1
                ov%old(n, c) = co
                ov%vol(n, c) = vsum
                ov%mom(:, n, c) = msum
              end do
            end do
          end do
          ov%count(c) = n
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine remap_overlaps

  !> Integral over every new cell of a density field given on the old cells
  !> by its mean rho_old and gradient grad_old (3, ncell; zero for a
  !> piecewise-constant remap) about the old centroids xc_old: the remapped
  !> extensive quantity q_new (e.g. mass for the density). Eq. (54)-(55).
  subroutine remap_density(ov, rho_old, grad_old, xc_old, q_new)
    type(overlap_t), intent(in) :: ov
    real(wp), intent(in) :: rho_old(:), grad_old(:, :), xc_old(:, :)
    real(wp), intent(out) :: q_new(:)
    integer :: c, k, co

    !$omp parallel do default(none) shared(ov, rho_old, grad_old, xc_old, q_new) private(c, k, co) &
    !$omp schedule(static)
    do c = 1, size(q_new)
      q_new(c) = 0.0_wp
      do k = 1, ov%count(c)
        co = ov%old(k, c)
        q_new(c) = q_new(c) + rho_old(co)*ov%vol(k, c) + &
                   dot_product(grad_old(:, co), ov%mom(:, k, c) - xc_old(:, co)*ov%vol(k, c))
      end do
    end do
    !$omp end parallel do
  end subroutine remap_density


  pure real(wp) function det3(a, b, c)
    real(wp), intent(in) :: a(3), b(3), c(3)
    det3 = a(1)*(b(2)*c(3) - b(3)*c(2)) - a(2)*(b(1)*c(3) - b(3)*c(1)) + a(3)*(b(1)*c(2) - b(2)*c(1))
  end function det3
end module remap_cells
