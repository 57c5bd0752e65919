!> Work that the ranks of a run share over data every rank holds (a
!> decomposed run's Euler phase on the whole grid, `driver_whole`): each
!> part computes the items of a list that are its own (every nparts-th,
!> from its part number: round robin, so that items clustered where the
!> grid moved spread over all parts), then every part receives what the
!> others computed. Each item is computed by the same code whichever part
!> computes it, so the result does not depend on the number of parts.
!>
!> `share_t` is one part: it computes every item and exchanges nothing.
!> The MPI extension is `parallel_share`, so that the kernels that share
!> their work never call MPI themselves.
module base_share
  use base_kinds, only: wp, i8
  implicit none
  private
  public :: share_t

  !> How a list's items are shared, and the exchange of the results.
  type :: share_t
    integer :: nparts = 1   !< parts sharing the work
    integer :: part = 0     !< this part (0 .. nparts - 1)
  contains
    procedure :: mine => share_mine
    procedure :: columns => share_columns
    procedure :: sum_i8 => share_sum_i8
  end type share_t

contains

  !> Whether item i (of a list counted from 1) is this part's to compute.
  elemental logical function share_mine(this, i)
    class(share_t), intent(in) :: this
    integer, intent(in) :: i
    share_mine = mod(i - 1, this%nparts) == this%part
  end function share_mine

  !> On entry a(:, k) holds this part's items in list order (item
  !> this%part + 1 + (k - 1)*nparts; a has room for all n items); on exit
  !> a(:, i) holds item i of the list for every i = 1..n, from the part that
  !> computed it. One part: the list is already whole.
  subroutine share_columns(this, n, a)
    class(share_t), intent(in) :: this
    integer, intent(in) :: n
    real(wp), intent(inout) :: a(:, :)
    if (this%nparts < 1) a(:, :n) = 0.0_wp
  end subroutine share_columns

  !> Adds the integers a(:) of all parts (exact, in any order): on exit
  !> every part holds the totals. One part: they are the totals.
  subroutine share_sum_i8(this, a)
    class(share_t), intent(in) :: this
    integer(i8), intent(inout) :: a(:)
    if (this%nparts < 1) a = 0_i8
  end subroutine share_sum_i8
end module base_share
