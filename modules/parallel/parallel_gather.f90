!> Whole-grid copies of block fields on rank 0 (frames of a decomposed run
!> are written there, in the single-block layout, so a frame does not
!> depend on the rank count). Each rank sends its owned cells, or the owned
!> nodes it counts (`grid_counts_node`: every node once).
module parallel_gather
  use mpi_f08
  use base_kinds, only: wp
  use mesh_grid, only: grid_index_t, grid_index
  use parallel_comm, only: comm_t, parallel_nomem
  implicit none
  private
  public :: gather_cells, gather_nodes

contains

  !> w(m, whole-grid cells) on rank 0 from every block's a(m, ncell).
  subroutine gather_cells(pc, ix, a, w)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: a(:, :)
    real(wp), allocatable, intent(out) :: w(:, :)
    call gather(pc, ix, a, w, .false.)
  end subroutine gather_cells

  !> w(m, whole-grid nodes) on rank 0 from every block's a(m, nnode).
  subroutine gather_nodes(pc, ix, a, w)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: a(:, :)
    real(wp), allocatable, intent(out) :: w(:, :)
    call gather(pc, ix, a, w, .true.)
  end subroutine gather_nodes

  subroutine gather(pc, ix, a, w, nodes)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: a(:, :)
    real(wp), allocatable, intent(out) :: w(:, :)
    logical, intent(in) :: nodes
    integer :: m, lo(3), hi(3), box(6), r, i, j, k, p, q, ntot, stat
    integer, allocatable :: boxes(:, :), counts(:), displs(:)
    real(wp), allocatable :: sbuf(:), rbuf(:)
    type(grid_index_t) :: whole

    m = size(a, 1)
    if (nodes) then
      lo = ix%ulo; hi = ix%nhi
    else
      lo = ix%clo; hi = ix%chi
    end if
    box = [lo + ix%off, hi + ix%off]
    allocate(sbuf(m*product(max(hi - lo + 1, 0))), stat=stat)
    call parallel_nomem(stat, 'a gather to rank 0')
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
    allocate(boxes(6, 0:pc%nranks - 1), counts(0:pc%nranks - 1), displs(0:pc%nranks - 1), stat=stat)
    call parallel_nomem(stat, 'a gather to rank 0')
    call MPI_Gather(box, 6, MPI_INTEGER, boxes, 6, MPI_INTEGER, 0, pc%cart)
    if (pc%rank == 0) then
      do r = 0, pc%nranks - 1
        counts(r) = m*product(max(boxes(4:6, r) - boxes(1:3, r) + 1, 0))
      end do
      displs(0) = 0
      do r = 1, pc%nranks - 1
        displs(r) = displs(r - 1) + counts(r - 1)
      end do
      ntot = sum(counts)
    else
      counts = 0; displs = 0; ntot = 0
    end if
    allocate(rbuf(max(ntot, 1)), stat=stat)
    call parallel_nomem(stat, 'a gather to rank 0')
    call MPI_Gatherv(sbuf, size(sbuf), MPI_DOUBLE_PRECISION, rbuf, counts, displs, MPI_DOUBLE_PRECISION, 0, pc%cart)
    if (pc%rank /= 0) then
      allocate(w(m, 0), stat=stat)
      call parallel_nomem(stat, 'a gather to rank 0')
      return
    end if
    whole = grid_index(ix%gn(1), ix%gn(2), ix%gn(3))
    allocate(w(m, merge(whole%nnode, whole%ncell, nodes)), stat=stat)
    call parallel_nomem(stat, 'a gather to rank 0')
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
end module parallel_gather
