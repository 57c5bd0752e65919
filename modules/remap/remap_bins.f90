!> Uniform bins over the bounding boxes of the cells of a structured block:
!> which cells of the old grid can overlap a given box, and how far away in
!> index space the farthest of them lies.
!>
!> The remap (`remap_euler`) intersects a new cell with the old cells of an
!> index window around it and widens the window until the fragments add up
!> to the cell. That test cannot end for a new cell that is partly or wholly
!> outside the old grid: the gap between an open face and a Lagrangian
!> boundary that moved away from it. For those cells the window is taken
!> from the bins instead: it holds every old cell whose bounding box meets
!> the new cell's, so whatever the window then leaves uncovered lies outside
!> the old grid. Building costs one pass over the cells; a query, the cells
!> registered in the bins its box meets.
module remap_bins
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use mesh_grid, only: grid_index_t, grid_index, block_gather
  use base_sort, only: sort_order
  implicit none
  private
  public :: remap_bins_t, remap_bins_build, remap_bins_reach, remap_bins_cells, remap_boxes_reach, remap_box_meets

  !> The bins: a uniform lattice of nb(1) x nb(2) x nb(3) boxes of size h
  !> from lo, each listing the cells whose bounding boxes meet it (CSR:
  !> bin b holds item(start(b) : start(b+1)-1)).
  type :: remap_bins_t
    type(grid_index_t) :: ix                !< the block's index arithmetic
    integer :: nb(3) = 0
    real(wp) :: lo(3) = 0.0_wp, h(3) = 1.0_wp
    !> the binned cells' bounding boxes (3, ncell; the others' are not set)
    real(wp), allocatable :: blo(:, :), bhi(:, :)
    integer, allocatable :: start(:), item(:)
  end type remap_bins_t

contains

  !> Bins over the cells c of a block of ni x nj x nk cells (nodes x(3,
  !> nnode), length unit of the deck) with use(c) true; one bin per cell
  !> of the block in each direction, over the bounding box of those cells.
  subroutine remap_bins_build(ni, nj, nk, x, use, bins, err)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :)
    logical, intent(in) :: use(:)
    type(remap_bins_t), intent(out) :: bins
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: xn(3, 8), glo(3), ghi(3)
    integer :: c, ci, cj, ck, b0(3), b1(3), i, j, k, b, nbin, stat
    integer, allocatable :: fill(:)
    character(len=200) :: msg

    bins%ix = grid_index(ni, nj, nk)
    bins%nb = [max(ni, 1), max(nj, 1), max(nk, 1)]
    nbin = product(bins%nb)
    allocate(bins%blo(3, bins%ix%ncell), bins%bhi(3, bins%ix%ncell), bins%start(nbin + 1), fill(nbin), &
             stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_bins_build', error_no_memory('the bins'))
      return
    end if
    glo = huge(1.0_wp)
    ghi = -huge(1.0_wp)
    do ck = 1, nk
      do cj = 1, nj
        do ci = 1, ni
          c = bins%ix%cell(ci, cj, ck)
          ! (only the binned cells' boxes are read)
          if (.not. use(c)) cycle
          call block_gather(ni, nj, ci, cj, ck, x, xn)
          bins%blo(:, c) = minval(xn, 2)
          bins%bhi(:, c) = maxval(xn, 2)
          glo = min(glo, bins%blo(:, c))
          ghi = max(ghi, bins%bhi(:, c))
        end do
      end do
    end do
    if (.not. any(use)) then
      ! nothing to find: one empty bin
      bins%nb = 1
      glo = 0.0_wp
      ghi = 1.0_wp
    end if
    bins%lo = glo
    do i = 1, 3
      bins%h(i) = (ghi(i) - glo(i))/real(bins%nb(i), wp)
      if (.not. bins%h(i) > 0.0_wp) bins%h(i) = 1.0_wp
    end do
    nbin = product(bins%nb)

    ! count, then fill
    fill = 0
    do c = 1, bins%ix%ncell
      if (.not. use(c)) cycle
      call bin_range(bins, bins%blo(:, c), bins%bhi(:, c), b0, b1)
      do k = b0(3), b1(3)
        do j = b0(2), b1(2)
          do i = b0(1), b1(1)
            b = bin_index(bins, i, j, k)
            fill(b) = fill(b) + 1
          end do
        end do
      end do
    end do
    bins%start(1) = 1
    do b = 1, nbin
      bins%start(b + 1) = bins%start(b) + fill(b)
    end do
    allocate(bins%item(bins%start(nbin + 1) - 1), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_bins_build', error_no_memory('the bins'' lists'))
      return
    end if
    fill = 0
    do c = 1, bins%ix%ncell
      if (.not. use(c)) cycle
      call bin_range(bins, bins%blo(:, c), bins%bhi(:, c), b0, b1)
      do k = b0(3), b1(3)
        do j = b0(2), b1(2)
          do i = b0(1), b1(1)
            b = bin_index(bins, i, j, k)
            bins%item(bins%start(b) + fill(b)) = c
            fill(b) = fill(b) + 1
          end do
        end do
      end do
    end do
  end subroutine remap_bins_build

  !> The largest index distance max(|oi-ci|, |oj-cj|, |ok-ck|) from cell
  !> (ci,cj,ck) of a binned cell o whose bounding box meets [lo, hi]
  !> (`remap_box_meets`); -1 if there is none.
  pure integer function remap_bins_reach(bins, ci, cj, ck, lo, hi) result(r)
    type(remap_bins_t), intent(in) :: bins
    integer, intent(in) :: ci, cj, ck
    real(wp), intent(in) :: lo(3), hi(3)
    integer, allocatable :: cells(:)
    integer :: n, t, oi, oj, ok
    r = -1
    call remap_bins_cells(bins, lo, hi, cells, n)
    ! (no room for the list: every cell of the block)
    if (n < 0) r = max(bins%ix%ni, bins%ix%nj, bins%ix%nk)
    do t = 1, n
      call bins%ix%cell_ijk(cells(t), oi, oj, ok)
      r = max(r, abs(oi - ci), abs(oj - cj), abs(ok - ck))
    end do
  end function remap_bins_reach

  !> The binned cells whose bounding boxes meet [lo, hi] (widened as in
  !> `remap_box_meets`), each once, in ascending cell order: cells(1:n).
  !> n = -1 if the list could not be allocated.
  pure subroutine remap_bins_cells(bins, lo, hi, cells, n)
    type(remap_bins_t), intent(in) :: bins
    real(wp), intent(in) :: lo(3), hi(3)
    integer, allocatable, intent(inout) :: cells(:)
    integer, intent(out) :: n
    real(wp) :: qlo(3), qhi(3)
    integer :: b0(3), b1(3), i, j, k, b, t, o, m, stat
    integer, allocatable :: found(:), order(:)
    n = 0
    call padded(lo, hi, qlo, qhi)
    if (any(qhi < bins%lo) .or. any(qlo > bins%lo + bins%h*real(bins%nb, wp))) return
    call bin_range(bins, qlo, qhi, b0, b1)
    m = 0
    do k = b0(3), b1(3)
      do j = b0(2), b1(2)
        do i = b0(1), b1(1)
          b = bin_index(bins, i, j, k)
          m = m + bins%start(b + 1) - bins%start(b)
        end do
      end do
    end do
    allocate(found(m), order(m), stat=stat)
    if (stat == 0 .and. allocated(cells)) then
      if (size(cells) < m) deallocate(cells)
    end if
    if (stat == 0 .and. .not. allocated(cells)) allocate(cells(max(m, 1)), stat=stat)
    if (stat /= 0) then
      n = -1
      return
    end if
    m = 0
    do k = b0(3), b1(3)
      do j = b0(2), b1(2)
        do i = b0(1), b1(1)
          b = bin_index(bins, i, j, k)
          do t = bins%start(b), bins%start(b + 1) - 1
            o = bins%item(t)
            if (any(bins%bhi(:, o) < qlo) .or. any(bins%blo(:, o) > qhi)) cycle
            m = m + 1
            found(m) = o
          end do
        end do
      end do
    end do
    ! ascending, each once (a cell is listed in every bin its box meets)
    call sort_order(found(1:m), order(1:m), stat)
    if (stat /= 0) then
      n = -1
      return
    end if
    do t = 1, m
      o = found(order(t))
      if (n > 0) then
        if (cells(n) == o) cycle
      end if
      n = n + 1
      cells(n) = o
    end do
  end subroutine remap_bins_cells

  !> `remap_bins_reach` over a list of cells instead of bins: cell q at
  !> index ijk(:, q) with bounding box box(1:3, q) to box(4:6, q).
  pure integer function remap_boxes_reach(ijk, box, ci, cj, ck, lo, hi) result(r)
    integer, intent(in) :: ijk(:, :), ci, cj, ck
    real(wp), intent(in) :: box(:, :), lo(3), hi(3)
    integer :: q
    r = -1
    do q = 1, size(ijk, 2)
      if (remap_box_meets(box(1:3, q), box(4:6, q), lo, hi)) &
        r = max(r, abs(ijk(1, q) - ci), abs(ijk(2, q) - cj), abs(ijk(3, q) - ck))
    end do
  end function remap_boxes_reach

  !> Whether the box [blo, bhi] meets the query box [lo, hi] (touching
  !> counts; the query is first widened by a relative 1e-9 of its size, so
  !> that round-off of the caller's own box tests cannot leave a cell out).
  pure logical function remap_box_meets(blo, bhi, lo, hi)
    real(wp), intent(in) :: blo(3), bhi(3), lo(3), hi(3)
    real(wp) :: qlo(3), qhi(3)
    call padded(lo, hi, qlo, qhi)
    remap_box_meets = .not. (any(bhi < qlo) .or. any(blo > qhi))
  end function remap_box_meets

  !> The query box [lo, hi] widened by a relative 1e-9 of its size.
  pure subroutine padded(lo, hi, qlo, qhi)
    real(wp), intent(in) :: lo(3), hi(3)
    real(wp), intent(out) :: qlo(3), qhi(3)
    real(wp) :: pad
    pad = 1.0e-9_wp*maxval(hi - lo)
    qlo = lo - pad
    qhi = hi + pad
  end subroutine padded

  !> The bins (clamped to the lattice) that the box [lo, hi] meets.
  pure subroutine bin_range(bins, lo, hi, b0, b1)
    type(remap_bins_t), intent(in) :: bins
    real(wp), intent(in) :: lo(3), hi(3)
    integer, intent(out) :: b0(3), b1(3)
    integer :: d
    real(wp) :: nbd
    do d = 1, 3
      ! clamped before the conversion, so that no far box overflows an integer
      nbd = real(bins%nb(d), wp)
      b0(d) = min(int(min(max((lo(d) - bins%lo(d))/bins%h(d), 0.0_wp), nbd)) + 1, bins%nb(d))
      b1(d) = min(int(min(max((hi(d) - bins%lo(d))/bins%h(d), 0.0_wp), nbd)) + 1, bins%nb(d))
    end do
  end subroutine bin_range

  !> Flattened index of bin (i,j,k).
  pure integer function bin_index(bins, i, j, k) result(b)
    type(remap_bins_t), intent(in) :: bins
    integer, intent(in) :: i, j, k
    b = i + bins%nb(1)*((j - 1) + bins%nb(2)*(k - 1))
  end function bin_index
end module remap_bins
