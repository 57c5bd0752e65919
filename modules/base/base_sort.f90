!> Sorting: the order of a list of integer keys (a stable merge sort,
!> n log n comparisons, whatever the keys' order on entry).
module base_sort
  implicit none
  private
  public :: sort_order

contains

  !> order(1:n): the positions of key in ascending key order, equal keys in
  !> the order they come in. stat: nonzero if the work array could not be
  !> allocated (order is then unset).
  pure subroutine sort_order(key, order, stat)
    integer, intent(in) :: key(:)
    integer, intent(out) :: order(size(key))
    integer, intent(out) :: stat
    integer, allocatable :: work(:)
    integer :: n, width, lo, mid, hi, i, j, k
    n = size(key)
    allocate(work(n), stat=stat)
    if (stat /= 0) return
    order = [(i, i = 1, n)]
    width = 1
    do while (width < n)
      ! merge the sorted runs [lo, mid) and [mid, hi) of width `width`
      ! (min(., n) only keeps the index in range: Fortran need not skip the
      ! comparison when the first test already decides)
      do lo = 1, n, 2*width
        mid = min(lo + width, n + 1)
        hi = min(lo + 2*width, n + 1)
        i = lo; j = mid
        do k = lo, hi - 1
          if (i < mid .and. (j >= hi .or. key(order(min(i, n))) <= key(order(min(j, n))))) then
            work(k) = order(i)
            i = i + 1
          else
            work(k) = order(j)
            j = j + 1
          end if
        end do
      end do
      order = work
      width = 2*width
    end do
  end subroutine sort_order
end module base_sort
