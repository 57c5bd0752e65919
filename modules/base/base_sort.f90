!> Sorting: the order of a list of integer keys (a stable merge sort,
!> n log n comparisons, whatever the keys' order on entry).
module base_sort
  implicit none
  private
  public :: sort_order, sorted_runs, sorted_place

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

  !> The runs of consecutive values of the increasing key: runs(:, r) =
  !> (first value, length), in order. stat: nonzero if runs could not be
  !> allocated.
  pure subroutine sorted_runs(key, runs, stat)
    integer, intent(in) :: key(:)
    integer, allocatable, intent(out) :: runs(:, :)
    integer, intent(out) :: stat
    integer :: n, k, r
    n = size(key)
    r = 0
    if (n > 0) r = 1 + count(key(2:) /= key(:n - 1) + 1)
    allocate(runs(2, r), stat=stat)
    if (stat /= 0) return
    if (n == 0) return
    r = 1
    runs(:, 1) = [key(1), 1]
    do k = 2, n
      if (key(k) == key(k - 1) + 1) then
        runs(2, r) = runs(2, r) + 1
      else
        r = r + 1
        runs(:, r) = [key(k), 1]
      end if
    end do
  end subroutine sorted_runs

  !> The first place q of the increasing list with list(q) >= key (by
  !> bisection; size(list) + 1 if there is none).
  pure integer function sorted_place(list, key) result(q)
    integer, intent(in) :: list(:), key
    integer :: hi, mid
    q = 1
    hi = size(list) + 1
    do while (q < hi)
      mid = (q + hi)/2
      if (list(mid) < key) then
        q = mid + 1
      else
        hi = mid
      end if
    end do
  end function sorted_place
end module base_sort
