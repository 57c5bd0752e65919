!> Whole-grid copies of block fields (frames of a decomposed run are written
!> by rank 0 in the single-block layout, so that a frame does not depend on
!> the rank count; the Euler phase and restarts work on a whole-grid copy on
!> every rank). Each rank sends its owned cells, or the owned nodes it
!> counts (`grid_counts_node`: every node once).
module parallel_gather
  use mpi_f08
  use base_kinds, only: wp
  use mesh_grid, only: grid_index_t, grid_index
  use parallel_comm, only: comm_t, parallel_nomem
  implicit none
  private
  public :: gather_cells, gather_nodes, gather_concat

  !> Concatenation over the ranks, in rank order, on every rank.
  interface gather_concat
    module procedure concat_real, concat_int
  end interface gather_concat

contains

  !> w(m, whole-grid cells) from every block's a(m, ncell): on rank 0, or
  !> with `all` on every rank (w(m, 0) elsewhere).
  subroutine gather_cells(pc, ix, a, w, all)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: a(:, :)
    real(wp), allocatable, intent(out) :: w(:, :)
    logical, intent(in), optional :: all
    logical :: every
    every = .false.
    if (present(all)) every = all
    call gather(pc, ix, a, w, .false., every)
  end subroutine gather_cells

  !> w(m, whole-grid nodes) from every block's a(m, nnode), as `gather_cells`.
  subroutine gather_nodes(pc, ix, a, w, all)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: a(:, :)
    real(wp), allocatable, intent(out) :: w(:, :)
    logical, intent(in), optional :: all
    logical :: every
    every = .false.
    if (present(all)) every = all
    call gather(pc, ix, a, w, .true., every)
  end subroutine gather_nodes

  subroutine gather(pc, ix, a, w, nodes, all)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: a(:, :)
    real(wp), allocatable, intent(out) :: w(:, :)
    logical, intent(in) :: nodes, all
    integer :: m, lo(3), hi(3), box(6), r, i, j, k, p, q, stat
    integer :: boxes(6, 0:pc%nranks - 1), counts(0:pc%nranks - 1), displs(0:pc%nranks - 1)
    real(wp), allocatable :: sbuf(:), rbuf(:)
    type(grid_index_t) :: whole
    logical :: mine

    m = size(a, 1)
    if (nodes) then
      lo = ix%ulo; hi = ix%nhi
    else
      lo = ix%clo; hi = ix%chi
    end if
    box = [lo + ix%off, hi + ix%off]
    allocate(sbuf(m*product(max(hi - lo + 1, 0))), stat=stat)
    call parallel_nomem(stat, 'a gather')
    p = 0
    do k = lo(3), hi(3)
      do j = lo(2), hi(2)
        do i = lo(1), hi(1)
          q = merge(ix%node(i, j, k), ix%cell(i, j, k), nodes)
          sbuf(p + 1:p + m) = a(:, q)
          p = p + m
        end do
      end do
    end do
    call MPI_Allgather(box, 6, MPI_INTEGER, boxes, 6, MPI_INTEGER, pc%cart)
    do r = 0, pc%nranks - 1
      counts(r) = m*product(max(boxes(4:6, r) - boxes(1:3, r) + 1, 0))
    end do
    displs(0) = 0
    do r = 1, pc%nranks - 1
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    mine = all .or. pc%rank == 0
    allocate(rbuf(merge(sum(counts), 1, mine)), stat=stat)
    call parallel_nomem(stat, 'a gather')
    if (all) then
      call MPI_Allgatherv(sbuf, size(sbuf), MPI_DOUBLE_PRECISION, rbuf, counts, displs, MPI_DOUBLE_PRECISION, &
                          pc%cart)
    else
      call MPI_Gatherv(sbuf, size(sbuf), MPI_DOUBLE_PRECISION, rbuf, counts, displs, MPI_DOUBLE_PRECISION, 0, &
                       pc%cart)
    end if
    whole = grid_index(ix%gn(1), ix%gn(2), ix%gn(3))
    allocate(w(m, merge(merge(whole%nnode, whole%ncell, nodes), 0, mine)), stat=stat)
    call parallel_nomem(stat, 'a gather')
    if (.not. mine) return
    do r = 0, pc%nranks - 1
      p = displs(r)
      do k = boxes(3, r), boxes(6, r)
        do j = boxes(2, r), boxes(5, r)
          do i = boxes(1, r), boxes(4, r)
            q = merge(whole%node(i, j, k), whole%cell(i, j, k), nodes)
            w(:, q) = rbuf(p + 1:p + m)
            p = p + m
          end do
        end do
      end do
    end do
  end subroutine gather

  !> The counts and offsets of a concatenation of n items per rank.
  subroutine concat_counts(pc, n, counts, displs)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: n
    integer, allocatable, intent(out) :: counts(:), displs(:)
    integer :: r, stat
    allocate(counts(0:pc%nranks - 1), displs(0:pc%nranks - 1), stat=stat)
    call parallel_nomem(stat, 'a gather')
    call MPI_Allgather(n, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, pc%world)
    displs(0) = 0
    do r = 1, pc%nranks - 1
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
  end subroutine concat_counts

  subroutine concat_real(pc, a, w)
    type(comm_t), intent(in) :: pc
    real(wp), intent(in) :: a(:)
    real(wp), allocatable, intent(out) :: w(:)
    integer, allocatable :: counts(:), displs(:)
    integer :: stat
    call concat_counts(pc, size(a), counts, displs)
    allocate(w(sum(counts)), stat=stat)
    call parallel_nomem(stat, 'a gather')
    call MPI_Allgatherv(a, size(a), MPI_DOUBLE_PRECISION, w, counts, displs, MPI_DOUBLE_PRECISION, pc%world)
  end subroutine concat_real

  subroutine concat_int(pc, a, w)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: a(:)
    integer, allocatable, intent(out) :: w(:)
    integer, allocatable :: counts(:), displs(:)
    integer :: stat
    call concat_counts(pc, size(a), counts, displs)
    allocate(w(sum(counts)), stat=stat)
    call parallel_nomem(stat, 'a gather')
    call MPI_Allgatherv(a, size(a), MPI_INTEGER, w, counts, displs, MPI_INTEGER, pc%world)
  end subroutine concat_int
end module parallel_gather
