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
  public :: gather_cells, gather_nodes, gather_box, gather_box_into, gather_box_fields, gather_concat, gather_field_t, &
            exchange_lists, cell_prefix, gather_to, scatter_from

  !> One field of `gather_box_fields`: the block's a(m, nnode or ncell)
  !> and the box's w(m, nodes or cells of the box).
  type :: gather_field_t
    real(wp), pointer, contiguous :: a(:, :) => null(), w(:, :) => null()
  end type gather_field_t

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

  !> w(m, nodes or cells of a box) on every rank from every block's a(m,
  !> nnode or ncell): the box of cells lo..hi (whole-grid indices; its nodes
  !> lo-1..hi), stored as a single block of that size (`grid_index`). Each
  !> rank asks for its own box; the blocks send what they own of each
  !> (their owned cells, or the owned nodes they count), so that a rank
  !> receives only the part of the whole grid it asked for.
  subroutine gather_box(pc, ix, a, lo, hi, w, nodes)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    ! (contiguous, as `gather_box_into` takes it: no copy on the way)
    real(wp), intent(in), contiguous :: a(:, :)
    integer, intent(in) :: lo(3), hi(3)
    real(wp), allocatable, intent(out) :: w(:, :)
    logical, intent(in) :: nodes
    type(grid_index_t) :: box
    integer :: stat
    box = grid_index(hi(1) - lo(1) + 1, hi(2) - lo(2) + 1, hi(3) - lo(3) + 1)
    allocate(w(size(a, 1), merge(box%nnode, box%ncell, nodes)), stat=stat)
    call parallel_nomem(stat, 'a gather')
    call gather_box_into(pc, ix, a, lo, hi, w, nodes, [1, 1, 1], [0, 0, 0])
  end subroutine gather_box

  !> `gather_box` into w as it is, but for the nodes or cells (whole-grid
  !> indices) hlo..hhi of the box, which keep their values (a hole: what the
  !> asking rank holds already; none if hlo > hhi in some direction).
  subroutine gather_box_into(pc, ix, a, lo, hi, w, nodes, hlo, hhi)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in), target, contiguous :: a(:, :)
    integer, intent(in) :: lo(3), hi(3), hlo(3), hhi(3)
    real(wp), intent(inout), target, contiguous :: w(:, :)
    logical, intent(in) :: nodes
    type(gather_field_t) :: f(1)
    f(1)%a => a
    f(1)%w => w
    call gather_box_fields(pc, ix, f, lo, hi, nodes, hlo, hhi)
  end subroutine gather_box_into

  !> `gather_box_into` for several fields at once, all node fields or all
  !> cell fields (f(:): each its block's a and its box's w): one exchange of
  !> the boxes, then one message per pair of ranks for each batch of fields
  !> (consecutive fields of at most max(8, the largest field's) values per
  !> entry together: the buffers stay as small as one field's).
  subroutine gather_box_fields(pc, ix, f, lo, hi, nodes, hlo, hhi)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    type(gather_field_t), intent(in) :: f(:)
    integer, intent(in) :: lo(3), hi(3), hlo(3), hhi(3)
    logical, intent(in) :: nodes
    integer :: boxes(18, 0:pc%nranks - 1), mine(18)
    integer :: l0, l1, cap, msum
    if (size(f) == 0) return
    ! (owned range, asked box, its hole, in whole-grid node or cell indices)
    if (nodes) then
      mine = [ix%ulo + ix%off, ix%nhi + ix%off, lo - 1, hi, hlo, hhi]
    else
      mine = [ix%clo + ix%off, ix%chi + ix%off, lo, hi, hlo, hhi]
    end if
    call MPI_Allgather(mine, 18, MPI_INTEGER, boxes, 18, MPI_INTEGER, pc%cart)
    cap = 8
    do l0 = 1, size(f)
      cap = max(cap, size(f(l0)%a, 1))
    end do
    l0 = 1
    do while (l0 <= size(f))
      l1 = l0
      msum = size(f(l0)%a, 1)
      do while (l1 < size(f))
        if (msum + size(f(l1 + 1)%a, 1) > cap) exit
        l1 = l1 + 1
        msum = msum + size(f(l1)%a, 1)
      end do
      call gather_batch(pc, ix, f(l0:l1), lo, hi, nodes, mine, boxes)
      l0 = l1 + 1
    end do
  end subroutine gather_box_fields

  !> One batch of `gather_box_fields`, the ranks' boxes known (mine: this
  !> rank's owned range, box and hole; boxes: every rank's).
  subroutine gather_batch(pc, ix, f, lo, hi, nodes, mine, boxes)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    type(gather_field_t), intent(in) :: f(:)
    integer, intent(in) :: lo(3), hi(3), mine(18), boxes(18, 0:pc%nranks - 1)
    logical, intent(in) :: nodes
    integer :: scounts(0:pc%nranks - 1), rcounts(0:pc%nranks - 1), sdispls(0:pc%nranks - 1), &
               rdispls(0:pc%nranks - 1)
    integer :: m, r, j, k, p, q, stat, blo(3), bhi(3), olo(3), ohi(3), b(3), run(2, 2), e, nrun, l
    real(wp), allocatable :: sbuf(:), rbuf(:)
    type(grid_index_t) :: box

    ! (the values per entry, over the fields)
    m = 0
    do l = 1, size(f)
      m = m + size(f(l)%a, 1)
    end do
    do r = 0, pc%nranks - 1
      ! what this rank sends to r, and receives from r (less the holes)
      blo = max(mine(1:3), boxes(7:9, r))
      bhi = min(mine(4:6), boxes(10:12, r))
      scounts(r) = m*(count_box(blo, bhi) - count_box(max(blo, boxes(13:15, r)), min(bhi, boxes(16:18, r))))
      olo = max(boxes(1:3, r), mine(7:9))
      ohi = min(boxes(4:6, r), mine(10:12))
      rcounts(r) = m*(count_box(olo, ohi) - count_box(max(olo, mine(13:15)), min(ohi, mine(16:18))))
    end do
    ! (what this rank holds of its own box is copied, not sent to itself)
    scounts(pc%rank) = 0
    rcounts(pc%rank) = 0
    sdispls(0) = 0
    rdispls(0) = 0
    do r = 1, pc%nranks - 1
      sdispls(r) = sdispls(r - 1) + scounts(r - 1)
      rdispls(r) = rdispls(r - 1) + rcounts(r - 1)
    end do
    allocate(sbuf(max(sum(scounts), 1)), rbuf(max(sum(rcounts), 1)), stat=stat)
    call parallel_nomem(stat, 'a gather')
    box = grid_index(hi(1) - lo(1) + 1, hi(2) - lo(2) + 1, hi(3) - lo(3) + 1)
    ! (box index = whole-grid index - b)
    b = lo - 1
    ! (a row's entries are consecutive in i, in the block and in the box;
    ! a row through the hole in two runs)
    blo = max(mine(1:3), mine(7:9))
    bhi = min(mine(4:6), mine(10:12))
    do k = blo(3), bhi(3)
      do j = blo(2), bhi(2)
        call row_runs(blo(1), bhi(1), j, k, mine(13:18), run, nrun)
        q = row_start(ix, 0, j - ix%off(2), k - ix%off(3), nodes) - ix%off(1)
        p = row_start(box, 0, j - b(2), k - b(3), nodes) - b(1)
        do e = 1, nrun
          do l = 1, size(f)
            f(l)%w(:, p + run(1, e):p + run(2, e)) = f(l)%a(:, q + run(1, e):q + run(2, e))
          end do
        end do
      end do
    end do
    ! (a run's values field by field, in both buffers)
    do r = 0, pc%nranks - 1
      if (r == pc%rank) cycle
      blo = max(mine(1:3), boxes(7:9, r))
      bhi = min(mine(4:6), boxes(10:12, r))
      p = sdispls(r)
      do k = blo(3), bhi(3)
        do j = blo(2), bhi(2)
          call row_runs(blo(1), bhi(1), j, k, boxes(13:18, r), run, nrun)
          q = row_start(ix, 0, j - ix%off(2), k - ix%off(3), nodes) - ix%off(1)
          do e = 1, nrun
            do l = 1, size(f)
              call pack_run(f(l)%a, q + run(1, e), q + run(2, e), sbuf, p)
            end do
          end do
        end do
      end do
    end do
    call MPI_Alltoallv(sbuf, scounts, sdispls, MPI_DOUBLE_PRECISION, rbuf, rcounts, rdispls, MPI_DOUBLE_PRECISION, &
                       pc%cart)
    do r = 0, pc%nranks - 1
      if (r == pc%rank) cycle
      olo = max(boxes(1:3, r), mine(7:9))
      ohi = min(boxes(4:6, r), mine(10:12))
      p = rdispls(r)
      do k = olo(3), ohi(3)
        do j = olo(2), ohi(2)
          call row_runs(olo(1), ohi(1), j, k, mine(13:18), run, nrun)
          q = row_start(box, 0, j - b(2), k - b(3), nodes) - b(1)
          do e = 1, nrun
            do l = 1, size(f)
              call unpack_run(rbuf, p, f(l)%w, q + run(1, e), q + run(2, e))
            end do
          end do
        end do
      end do
    end do
  end subroutine gather_batch

  !> The number of entries of the index box lo..hi (0 if empty).
  pure integer function count_box(lo, hi)
    integer, intent(in) :: lo(3), hi(3)
    count_box = product(max(hi - lo + 1, 0))
  end function count_box

  !> The runs of i in ilo..ihi of row (j, k) outside the box hole (lo(3),
  !> hi(3)): at most two.
  pure subroutine row_runs(ilo, ihi, j, k, hole, run, nrun)
    integer, intent(in) :: ilo, ihi, j, k, hole(6)
    integer, intent(out) :: run(2, 2), nrun
    nrun = 0
    if (ihi < ilo) return
    if (j < hole(2) .or. j > hole(5) .or. k < hole(3) .or. k > hole(6) .or. hole(4) < hole(1)) then
      nrun = 1
      run(:, 1) = [ilo, ihi]
      return
    end if
    if (ilo < hole(1)) then
      nrun = 1
      run(:, 1) = [ilo, min(ihi, hole(1) - 1)]
    end if
    if (ihi > hole(4)) then
      nrun = nrun + 1
      run(:, nrun) = [max(ilo, hole(4) + 1), ihi]
    end if
  end subroutine row_runs

  !> a(:, q0..q1) appended to buf after p.
  pure subroutine pack_run(a, q0, q1, buf, p)
    real(wp), intent(in) :: a(:, :)
    integer, intent(in) :: q0, q1
    real(wp), intent(inout) :: buf(:)
    integer, intent(inout) :: p
    integer :: q
    do q = q0, q1
      buf(p + 1:p + size(a, 1)) = a(:, q)
      p = p + size(a, 1)
    end do
  end subroutine pack_run

  !> w(:, q0..q1) from buf after p.
  pure subroutine unpack_run(buf, p, w, q0, q1)
    real(wp), intent(in) :: buf(:)
    integer, intent(inout) :: p
    real(wp), intent(inout) :: w(:, :)
    integer, intent(in) :: q0, q1
    integer :: q
    do q = q0, q1
      w(:, q) = buf(p + 1:p + size(w, 1))
      p = p + size(w, 1)
    end do
  end subroutine unpack_run

  !> The index of node (or cell) (i, j, k) of ix, where its row starts (the
  !> next in i follow it).
  pure integer function row_start(ix, i, j, k, nodes)
    type(grid_index_t), intent(in) :: ix
    integer, intent(in) :: i, j, k
    logical, intent(in) :: nodes
    if (nodes) then
      row_start = ix%node(i, j, k)
    else
      row_start = ix%cell(i, j, k)
    end if
  end function row_start

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

  !> Every rank's a concatenated in rank order on rank root alone (w empty
  !> on the others): what one rank computes for all, `scatter_from` then
  !> handing back each rank's share.
  subroutine gather_to(pc, root, a, w)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: root
    real(wp), intent(in) :: a(:)
    real(wp), allocatable, intent(out) :: w(:)
    integer, allocatable :: counts(:), displs(:)
    integer :: stat
    call root_counts(pc, root, size(a), counts, displs)
    allocate(w(merge(sum(counts), 0, pc%rank == root)), stat=stat)
    call parallel_nomem(stat, 'a gather')
    call MPI_Gatherv(a, size(a), MPI_DOUBLE_PRECISION, w, counts, displs, MPI_DOUBLE_PRECISION, root, pc%world)
  end subroutine gather_to

  !> Each rank's a, as many values as it holds, from rank root's w: the
  !> shares in rank order (`gather_to`'s layout).
  subroutine scatter_from(pc, root, w, a)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: root
    real(wp), intent(in) :: w(:)
    real(wp), intent(inout) :: a(:)
    integer, allocatable :: counts(:), displs(:)
    call root_counts(pc, root, size(a), counts, displs)
    call MPI_Scatterv(w, counts, displs, MPI_DOUBLE_PRECISION, a, size(a), MPI_DOUBLE_PRECISION, root, pc%world)
  end subroutine scatter_from

  !> Every rank's n and their offsets in rank order, on rank root (zeros
  !> elsewhere).
  subroutine root_counts(pc, root, n, counts, displs)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: root, n
    integer, allocatable, intent(out) :: counts(:), displs(:)
    integer :: r, stat
    allocate(counts(0:pc%nranks - 1), displs(0:pc%nranks - 1), stat=stat)
    call parallel_nomem(stat, 'a gather')
    counts = 0
    call MPI_Gather(n, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, root, pc%world)
    displs(0) = 0
    do r = 1, pc%nranks - 1
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
  end subroutine root_counts

  !> Each rank's lists for the others exchanged: sbuf holds the values for
  !> rank 0, 1, ... in turn (scounts(r) for rank r), rbuf receives those
  !> from rank 0, 1, ... in turn (one all-to-all of the counts, one of the
  !> values).
  subroutine exchange_lists(pc, sbuf, scounts, rbuf)
    type(comm_t), intent(in) :: pc
    real(wp), intent(in) :: sbuf(:)
    integer, intent(in) :: scounts(0:)
    real(wp), allocatable, intent(out) :: rbuf(:)
    integer :: rcounts(0:pc%nranks - 1), sdispls(0:pc%nranks - 1), rdispls(0:pc%nranks - 1), r, stat
    call MPI_Alltoall(scounts, 1, MPI_INTEGER, rcounts, 1, MPI_INTEGER, pc%world)
    sdispls(0) = 0
    rdispls(0) = 0
    do r = 1, pc%nranks - 1
      sdispls(r) = sdispls(r - 1) + scounts(r - 1)
      rdispls(r) = rdispls(r - 1) + rcounts(r - 1)
    end do
    allocate(rbuf(sum(rcounts)), stat=stat)
    call parallel_nomem(stat, 'an exchange')
    call MPI_Alltoallv(sbuf, scounts, sdispls, MPI_DOUBLE_PRECISION, rbuf, rcounts, rdispls, MPI_DOUBLE_PRECISION, &
                       pc%world)
  end subroutine exchange_lists

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
  !> The exclusive prefix sums of m counts per cell in the whole grid's
  !> cell order: counts(m, ncell) of the block's owned cells (its ghost
  !> cells' ignored) give before(m, ncell), at each owned cell the sums over
  !> every cell before it in the whole grid (0 at ghost cells), and total(m)
  !> the whole grid's sums. Each block's rows (one j, k of its owned cells)
  !> are summed and the row sums gathered on every rank (m + 2 integers per
  !> row of each block: the size of a face of the whole grid times the
  !> blocks along x, not of the grid). Collective.
  subroutine cell_prefix(pc, ix, counts, before, total)
    type(comm_t), intent(in) :: pc
    type(grid_index_t), intent(in) :: ix
    integer, intent(in) :: counts(:, :)
    integer, allocatable, intent(out) :: before(:, :)
    integer, intent(out) :: total(:)
    integer, allocatable :: mine(:), rows(:), order(:), base(:)
    integer :: m, nrow, q, r, j, k, i, c, at, stat, run(size(total))
    m = size(counts, 1)
    nrow = (ix%chi(2) - ix%clo(2) + 1)*(ix%chi(3) - ix%clo(3) + 1)
    allocate(mine((m + 2)*nrow), before(m, ix%ncell), stat=stat)
    call parallel_nomem(stat, 'the cells'' prefix sums')
    ! (each row: its global row number, its first global i, its m sums)
    q = 0
    do k = ix%clo(3), ix%chi(3)
      do j = ix%clo(2), ix%chi(2)
        mine(q + 1) = (j + ix%off(2)) + ix%gn(2)*(k + ix%off(3) - 1)
        mine(q + 2) = ix%clo(1) + ix%off(1)
        mine(q + 3:q + 2 + m) = 0
        do i = ix%clo(1), ix%chi(1)
          mine(q + 3:q + 2 + m) = mine(q + 3:q + 2 + m) + counts(:, ix%cell(i, j, k))
        end do
        q = q + m + 2
      end do
    end do
    call gather_concat(pc, mine, rows)
    ! (the rows of all blocks in the whole grid's order: by row, then i)
    nrow = size(rows)/(m + 2)
    allocate(order(nrow), base(m*nrow), stat=stat)
    call parallel_nomem(stat, 'the cells'' prefix sums')
    order = [(r, r = 1, nrow)]
    call sort_rows()
    run = 0
    do r = 1, nrow
      at = (m + 2)*(order(r) - 1)
      base(m*(order(r) - 1) + 1:m*order(r)) = run
      run = run + rows(at + 3:at + 2 + m)
    end do
    total = run
    before = 0
    ! (this rank's rows are its own entries of the gathered list: find the
    ! first by its key)
    q = first_mine()
    do k = ix%clo(3), ix%chi(3)
      do j = ix%clo(2), ix%chi(2)
        q = q + 1
        run = base(m*(q - 1) + 1:m*q)
        do i = ix%clo(1), ix%chi(1)
          c = ix%cell(i, j, k)
          before(:, c) = run
          run = run + counts(:, c)
        end do
      end do
    end do

  contains

    !> order sorted by (row, first i) of the gathered rows (a merge sort).
    subroutine sort_rows()
      integer, allocatable :: tmp(:)
      integer :: width, lo, mid, hi, a, b, t
      allocate(tmp(nrow), stat=stat)
      call parallel_nomem(stat, 'the cells'' prefix sums')
      width = 1
      do while (width < nrow)
        do lo = 1, nrow, 2*width
          mid = min(lo + width - 1, nrow)
          hi = min(lo + 2*width - 1, nrow)
          a = lo
          b = mid + 1
          do t = lo, hi
            if (b > hi) then
              tmp(t) = order(a); a = a + 1
            else if (a > mid) then
              tmp(t) = order(b); b = b + 1
            else if (.not. row_less(order(b), order(a))) then
              tmp(t) = order(a); a = a + 1
            else
              tmp(t) = order(b); b = b + 1
            end if
          end do
        end do
        order = tmp
        width = 2*width
      end do
    end subroutine sort_rows

    logical function row_less(x, y)
      integer, intent(in) :: x, y
      integer :: ax, ay
      ax = (m + 2)*(x - 1)
      ay = (m + 2)*(y - 1)
      row_less = rows(ax + 1) < rows(ay + 1) .or. (rows(ax + 1) == rows(ay + 1) .and. rows(ax + 2) < rows(ay + 2))
    end function row_less

    !> The index before this rank's first row in the gathered list.
    integer function first_mine() result(f)
      integer :: counts_r(pc%nranks)
      call concat_counts_rows(counts_r)
      f = sum(counts_r(:pc%rank))
    end function first_mine

    subroutine concat_counts_rows(n)
      integer, intent(out) :: n(:)
      integer :: one(1)
      integer, allocatable :: all(:)
      one(1) = (ix%chi(2) - ix%clo(2) + 1)*(ix%chi(3) - ix%clo(3) + 1)
      call gather_concat(pc, one, all)
      n = all
    end subroutine concat_counts_rows
  end subroutine cell_prefix
end module parallel_gather
