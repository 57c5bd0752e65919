!> Work shared by the MPI ranks over data every rank holds (`base_share`):
!> rank r computes the items r + 1, r + 1 + P, ... of a list (P ranks);
!> their results are gathered on every rank.
module parallel_share
  use mpi_f08, only: MPI_Comm, MPI_COMM_NULL, MPI_Allgatherv, MPI_Allreduce, MPI_DOUBLE_PRECISION, &
                     MPI_INTEGER8, MPI_SUM, MPI_IN_PLACE
  use base_kinds, only: wp, i8
  use base_share, only: share_t
  use parallel_comm, only: comm_t, parallel_nomem
  implicit none
  private
  public :: mpi_share_t, mpi_share_init

  !> The ranks of a communicator sharing work.
  type, extends(share_t) :: mpi_share_t
    type(MPI_Comm) :: comm = MPI_COMM_NULL
  contains
    procedure :: columns => mpi_columns
    procedure :: sum_i8 => mpi_sum_i8
  end type mpi_share_t

contains

  !> All ranks of pc sharing work.
  subroutine mpi_share_init(sh, pc)
    type(mpi_share_t), intent(out) :: sh
    type(comm_t), intent(in) :: pc
    sh%comm = pc%world
    sh%nparts = pc%nranks
    sh%part = pc%rank
  end subroutine mpi_share_init

  !> Every rank's items gathered (`share_columns`).
  subroutine mpi_columns(this, n, a)
    class(mpi_share_t), intent(in) :: this
    integer, intent(in) :: n
    real(wp), intent(inout) :: a(:, :)
    real(wp), allocatable :: all(:, :)
    integer :: counts(0:this%nparts - 1), displs(0:this%nparts - 1), r, k, m, stat
    if (this%nparts == 1 .or. n == 0) return
    m = size(a, 1)
    do r = 0, this%nparts - 1
      counts(r) = m*((n - r + this%nparts - 1)/this%nparts)
    end do
    displs(0) = 0
    do r = 1, this%nparts - 1
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    allocate(all(m, n), stat=stat)
    call parallel_nomem(stat, 'the shared work''s results')
    call MPI_Allgatherv(a, counts(this%part), MPI_DOUBLE_PRECISION, all, counts, displs, MPI_DOUBLE_PRECISION, &
                        this%comm)
    do r = 0, this%nparts - 1
      do k = 1, counts(r)/m
        a(:, r + 1 + (k - 1)*this%nparts) = all(:, displs(r)/m + k)
      end do
    end do
  end subroutine mpi_columns

  !> Integer totals of all ranks.
  subroutine mpi_sum_i8(this, a)
    class(mpi_share_t), intent(in) :: this
    integer(i8), intent(inout) :: a(:)
    if (this%nparts == 1) return
    call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_INTEGER8, MPI_SUM, this%comm)
  end subroutine mpi_sum_i8
end module parallel_share
