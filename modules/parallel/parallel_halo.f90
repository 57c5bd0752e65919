!> The halo of an MPI block (`mesh_halo`'s interface): ghost nodes and cells
!> refreshed from the neighbouring blocks, and the global reductions of the
!> step. Ghosts are filled direction by direction (x, then y, then z, each
!> over the whole stored range of the other two), so edge and corner ghosts
!> come through the face neighbours. A shared face node is computed by both
!> blocks from the same numbers and is not exchanged.
module parallel_halo
  use mpi_f08
  use base_kinds, only: wp, i8
  use base_xsum, only: xsum_t, xsum_normalize, XSUM_LIMBS
  use mesh_grid, only: grid_index_t
  use mesh_halo, only: halo_t
  use parallel_comm, only: comm_t, parallel_nomem
  implicit none
  private
  public :: mpi_halo_t, mpi_halo_init

  !> The halo of this rank's block.
  type, extends(halo_t) :: mpi_halo_t
    type(MPI_Comm) :: comm = MPI_COMM_NULL
    integer :: nbr(6) = -1
    type(grid_index_t) :: ix
  contains
    procedure :: nodes => mpi_nodes
    procedure :: cells => mpi_cells
    procedure :: min_step => mpi_min_step
    procedure :: max_int => mpi_max_int
    procedure :: sums => mpi_sums
    procedure :: choose => mpi_choose
    procedure :: sum_ints => mpi_sum_ints
    procedure :: concat => mpi_concat
  end type mpi_halo_t

contains

  !> The halo of block ix of the layout pc.
  subroutine mpi_halo_init(hl, pc, ix)
    type(mpi_halo_t), intent(out) :: hl
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    hl%nblocks = pc%nranks
    hl%comm = pc%cart
    hl%nbr = pc%nbr
    hl%ix = ix
  end subroutine mpi_halo_init

  !> Ghost nodes of a(m, nnode): owned nodes 1..glo(d) go to the block below
  !> (its ghosts above its shared face), ghi(d) nodes below the upper face to
  !> the block above.
  subroutine mpi_nodes(this, a)
    class(mpi_halo_t), intent(inout) :: this
    real(wp), intent(inout) :: a(:, :)
    integer :: d
    real(wp) :: t0
    if (this%nblocks == 1) return
    t0 = MPI_Wtime()
    associate (ix => this%ix)
      do d = 1, 3
        call swap(this, a, size(a, 1), size(a, 2), d, .true., &
                  [ix%nlo(d) + 1, ix%nlo(d) + ix%glo(d)], [ix%nlo(d) - ix%glo(d), ix%nlo(d) - 1], &
                  [ix%nhi(d) - ix%ghi(d), ix%nhi(d) - 1], [ix%nhi(d) + 1, ix%nhi(d) + ix%ghi(d)])
      end do
    end associate
    this%seconds = this%seconds + (MPI_Wtime() - t0)
  end subroutine mpi_nodes

  !> Ghost cells of a(ncell).
  subroutine mpi_cells(this, a)
    class(mpi_halo_t), intent(inout) :: this
    real(wp), intent(inout) :: a(:)
    integer :: d
    real(wp) :: t0
    if (this%nblocks == 1) return
    t0 = MPI_Wtime()
    associate (ix => this%ix)
      do d = 1, 3
        call swap(this, a, 1, size(a), d, .false., &
                  [ix%clo(d), ix%clo(d) + ix%glo(d) - 1], [ix%clo(d) - ix%glo(d), ix%clo(d) - 1], &
                  [ix%chi(d) - ix%ghi(d) + 1, ix%chi(d)], [ix%chi(d) + 1, ix%chi(d) + ix%ghi(d)])
      end do
    end associate
    this%seconds = this%seconds + (MPI_Wtime() - t0)
  end subroutine mpi_cells

  !> One direction d of an exchange: layers send_lo go down and recv_hi
  !> come from above; send_hi go up and recv_lo come from below (index
  !> ranges in d; the other two directions over the whole stored range).
  subroutine swap(this, a, m, n, d, nodes, send_lo, recv_lo, send_hi, recv_hi)
    class(mpi_halo_t), intent(inout) :: this
    integer, intent(in) :: m, n
    real(wp), intent(inout) :: a(m, n)
    integer, intent(in) :: d
    logical, intent(in) :: nodes
    integer, intent(in) :: send_lo(2), recv_lo(2), send_hi(2), recv_hi(2)
    real(wp), allocatable :: sbuf(:), rbuf(:)
    integer :: lo(3), hi(3), stat, e
    ! the stored range of the other directions (within the box, limited: the
    ! neighbours across d store the same range of them)
    lo = this%ix%slo - merge(1, 0, nodes)
    hi = this%ix%shi
    if (nodes .and. this%limited) then
      do e = 1, 3
        if (e == d) cycle
        lo(e) = max(lo(e), this%node_box(e, 1) - this%ix%off(e))
        hi(e) = min(hi(e), this%node_box(e, 2) - this%ix%off(e))
      end do
    end if
    ! down: my lowest owned layers to the block below, its into my upper ghosts
    call pack(send_lo, sbuf)
    call count_send(this%nbr(2*d - 1))
    allocate(rbuf(size(a, 1)*(recv_hi(2) - recv_hi(1) + 1)*plane(d)), stat=stat)
    call parallel_nomem(stat, 'a halo exchange')
    call MPI_Sendrecv(sbuf, size(sbuf), MPI_DOUBLE_PRECISION, this%nbr(2*d - 1), 10 + d, &
                      rbuf, size(rbuf), MPI_DOUBLE_PRECISION, this%nbr(2*d), 10 + d, this%comm, MPI_STATUS_IGNORE)
    call unpack(recv_hi, rbuf)
    deallocate(sbuf, rbuf)
    ! up
    call pack(send_hi, sbuf)
    call count_send(this%nbr(2*d))
    allocate(rbuf(size(a, 1)*(recv_lo(2) - recv_lo(1) + 1)*plane(d)), stat=stat)
    call parallel_nomem(stat, 'a halo exchange')
    call MPI_Sendrecv(sbuf, size(sbuf), MPI_DOUBLE_PRECISION, this%nbr(2*d), 20 + d, &
                      rbuf, size(rbuf), MPI_DOUBLE_PRECISION, this%nbr(2*d - 1), 20 + d, this%comm, MPI_STATUS_IGNORE)
    call unpack(recv_lo, rbuf)
  contains
    subroutine count_send(to)
      integer, intent(in) :: to
      if (to == MPI_PROC_NULL) return
      this%messages = this%messages + 1_i8
      this%bytes = this%bytes + 8_i8*size(sbuf, kind=i8)
    end subroutine count_send

    integer function plane(dd)
      integer, intent(in) :: dd
      integer :: e
      plane = 1
      do e = 1, 3
        if (e /= dd) plane = plane*max(hi(e) - lo(e) + 1, 0)
      end do
    end function plane

    subroutine pack(r, buf)
      integer, intent(in) :: r(2)
      real(wp), allocatable, intent(out) :: buf(:)
      integer :: i, j, k, p, q, l(3), u(3)
      l = lo; u = hi
      l(d) = r(1); u(d) = r(2)
      allocate(buf(size(a, 1)*max(0, u(d) - l(d) + 1)*plane(d)), stat=stat)
      call parallel_nomem(stat, 'a halo exchange')
      p = 0
      do k = l(3), u(3)
        do j = l(2), u(2)
          do i = l(1), u(1)
            q = index_of(i, j, k)
            buf(p + 1:p + size(a, 1)) = a(:, q)
            p = p + size(a, 1)
          end do
        end do
      end do
    end subroutine pack

    subroutine unpack(r, buf)
      integer, intent(in) :: r(2)
      real(wp), intent(in) :: buf(:)
      integer :: i, j, k, p, q, l(3), u(3)
      l = lo; u = hi
      l(d) = r(1); u(d) = r(2)
      p = 0
      do k = l(3), u(3)
        do j = l(2), u(2)
          do i = l(1), u(1)
            q = index_of(i, j, k)
            a(:, q) = buf(p + 1:p + size(a, 1))
            p = p + size(a, 1)
          end do
        end do
      end do
    end subroutine unpack

    integer function index_of(i, j, k)
      integer, intent(in) :: i, j, k
      if (nodes) then
        index_of = this%ix%node(i, j, k)
      else
        index_of = this%ix%cell(i, j, k)
      end if
    end function index_of
  end subroutine swap

  !> Global smallest step; the limiting cell kept on its owner (lowest
  !> global index on a tie, the order a single block uses).
  subroutine mpi_min_step(this, dt, cell)
    class(mpi_halo_t), intent(inout) :: this
    real(wp), intent(inout) :: dt
    integer, intent(inout) :: cell
    real(wp) :: pair(2), best(2), t0
    integer :: gcell
    if (this%nblocks == 1) return
    t0 = MPI_Wtime()
    gcell = huge(1)
    if (cell > 0) gcell = this%ix%global_cell(cell)
    pair = [dt, real(gcell, wp)]
    call MPI_Allreduce(pair, best, 1, MPI_2DOUBLE_PRECISION, MPI_MINLOC, this%comm)
    dt = best(1)
    if (cell > 0 .and. gcell /= nint(best(2))) cell = 0
    this%seconds = this%seconds + (MPI_Wtime() - t0)
    this%messages = this%messages + 1_i8   ! (a reduction)
    this%bytes = this%bytes + 16_i8
  end subroutine mpi_min_step

  !> Global largest integer.
  subroutine mpi_max_int(this, k)
    class(mpi_halo_t), intent(in) :: this
    integer, intent(inout) :: k
    integer :: kk
    if (this%nblocks == 1) return
    kk = k
    call MPI_Allreduce(kk, k, 1, MPI_INTEGER, MPI_MAX, this%comm)
  end subroutine mpi_max_int

  !> Exact global sums: normalised accumulators added limb by limb (an
  !> integer sum, exact in any order), and whether any block's is not
  !> finite (a count in one more limb).
  subroutine mpi_sums(this, acc)
    class(mpi_halo_t), intent(in) :: this
    type(xsum_t), intent(inout) :: acc(:)
    integer(i8), allocatable :: mine(:, :), all(:, :)
    integer :: q, stat
    if (this%nblocks == 1) return
    allocate(mine(0:XSUM_LIMBS, size(acc)), all(0:XSUM_LIMBS, size(acc)), stat=stat)
    call parallel_nomem(stat, 'a global sum')
    do q = 1, size(acc)
      call xsum_normalize(acc(q))
      mine(0:XSUM_LIMBS - 1, q) = acc(q)%limb
      mine(XSUM_LIMBS, q) = merge(0_i8, 1_i8, acc(q)%finite)
    end do
    call MPI_Allreduce(mine, all, size(mine), MPI_INTEGER8, MPI_SUM, this%comm)
    do q = 1, size(acc)
      acc(q)%limb = all(0:XSUM_LIMBS - 1, q)
      acc(q)%terms = 0
      acc(q)%finite = all(XSUM_LIMBS, q) == 0_i8
    end do
  end subroutine mpi_sums

  !> The values of the block with the smallest key (lowest rank on a tie),
  !> on every block.
  subroutine mpi_choose(this, key, vals)
    class(mpi_halo_t), intent(in) :: this
    real(wp), intent(inout) :: key, vals(:)
    real(wp) :: pair(2), best(2)
    integer :: rank
    if (this%nblocks == 1) return
    call MPI_Comm_rank(this%comm, rank)
    pair = [key, real(rank, wp)]
    call MPI_Allreduce(pair, best, 1, MPI_2DOUBLE_PRECISION, MPI_MINLOC, this%comm)
    key = best(1)
    call MPI_Bcast(vals, size(vals), MPI_DOUBLE_PRECISION, nint(best(2)), this%comm)
  end subroutine mpi_choose

  !> Global sums of integers (exact).
  subroutine mpi_sum_ints(this, a)
    class(mpi_halo_t), intent(in) :: this
    integer, intent(inout) :: a(:)
    if (this%nblocks == 1) return
    call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_INTEGER, MPI_SUM, this%comm)
  end subroutine mpi_sum_ints

  !> Concatenation over the blocks, in rank order, on every block.
  subroutine mpi_concat(this, a, w)
    class(mpi_halo_t), intent(in) :: this
    real(wp), intent(in) :: a(:)
    real(wp), allocatable, intent(out) :: w(:)
    integer :: counts(0:this%nblocks - 1), displs(0:this%nblocks - 1), r, stat
    if (this%nblocks == 1) then
      w = a
      return
    end if
    call MPI_Allgather(size(a), 1, MPI_INTEGER, counts, 1, MPI_INTEGER, this%comm)
    displs(0) = 0
    do r = 1, this%nblocks - 1
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    allocate(w(sum(counts)), stat=stat)
    call parallel_nomem(stat, 'a gather')
    call MPI_Allgatherv(a, size(a), MPI_DOUBLE_PRECISION, w, counts, displs, MPI_DOUBLE_PRECISION, this%comm)
  end subroutine mpi_concat
end module parallel_halo
