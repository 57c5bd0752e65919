!> Work shared by MPI ranks (`base_share`, `parallel_share`): on any rank
!> count (run with 1, 3 and 4 ranks), every item of a list is computed by
!> exactly one rank, every rank ends with every item's result, also when
!> some ranks have no item (fewer items than ranks, an empty list), and the
!> integer sums are exact. The single part (`share_t`) computes everything.
program test_share
  use base_kinds, only: wp, i8
  use base_share, only: share_t
  use parallel_comm, only: comm_t, parallel_start, parallel_stop
  use parallel_share, only: mpi_share_t, mpi_share_init
  use test_assert, only: check, check_summary
  implicit none
  type(comm_t) :: pc
  type(mpi_share_t) :: sh
  type(share_t) :: one
  integer :: sizes(6) = [0, 1, 2, 3, 7, 64], q

  call parallel_start(pc)
  call mpi_share_init(sh, pc)
  call check(sh%nparts == pc%nranks .and. sh%part == pc%rank, 'one part per rank')
  call check(all(one%mine([1, 2, 3, 4, 5])), 'a single part computes every item')
  do q = 1, size(sizes)
    call columns_case(sizes(q))
  end do
  call sums_case()
  ! (every rank checks; each prints its own failures)
  call parallel_stop()
  call check_summary('test_share')

contains

  !> Items i = 1..n, item i's result (i, 2i, -i/3): each rank fills only
  !> its own, in list order; after the exchange all are there.
  subroutine columns_case(n)
    integer, intent(in) :: n
    real(wp) :: a(3, max(n, 1))
    integer :: i, k, mine_count, total
    a = -huge(1.0_wp)
    k = 0
    do i = 1, n
      if (.not. sh%mine(i)) cycle
      k = k + 1
      a(:, k) = item(i)
    end do
    mine_count = k
    call sh%columns(n, a)
    do i = 1, n
      call check(.not. any(abs(a(:, i) - item(i)) > 0.0_wp), 'item '//trim(str(i))//' of '//trim(str(n))//' on every rank')
    end do
    ! each item is some rank's: the counts add up to n
    total = mine_count
    call sum_int(total)
    call check(total == n, 'the ranks'' items add up to the list ('//trim(str(n))//')')
  end subroutine columns_case

  pure function item(i) result(v)
    integer, intent(in) :: i
    real(wp) :: v(3)
    v = [real(i, wp), 2.0_wp*i, -real(i, wp)/3.0_wp]
  end function item

  !> Integer totals: rank r adds (r + 1) 2^40 + i to entry i.
  subroutine sums_case()
    integer(i8) :: a(5), expected(5)
    integer :: i
    do i = 1, 5
      a(i) = int(pc%rank + 1, i8)*2_i8**40 + i
      expected(i) = int(pc%nranks*(pc%nranks + 1)/2, i8)*2_i8**40 + int(pc%nranks*i, i8)
    end do
    call sh%sum_i8(a)
    call check(all(a == expected), 'exact integer sums over the ranks')
  end subroutine sums_case

  !> Sum of an integer over the ranks, through sum_i8.
  subroutine sum_int(k)
    integer, intent(inout) :: k
    integer(i8) :: a(1)
    a(1) = k
    call sh%sum_i8(a)
    k = int(a(1))
  end subroutine sum_int

  pure function str(i) result(s)
    integer, intent(in) :: i
    character(len=12) :: s
    write(s, '(i0)') i
  end function str
end program test_share
