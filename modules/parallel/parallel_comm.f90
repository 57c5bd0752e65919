!> The MPI side of a run: start and stop, the ranks' Cartesian layout and
!> each rank's block of the grid (a block decomposition of the structured
!> grid, hybrid with OpenMP inside each rank). Without mpirun the program is
!> one rank (an MPI singleton) and everything here reduces to the whole grid.
module parallel_comm
  use, intrinsic :: iso_fortran_env, only: error_unit
  use mpi_f08
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set, ERR_INPUT
  use base_strings, only: itoa
  use mesh_grid, only: grid_index_t, grid_index_block
  implicit none
  private
  public :: parallel_cuts, parallel_block, parallel_balance, comm_t, parallel_start, parallel_stop, parallel_abort, &
            parallel_rank, parallel_dims, parallel_decompose, parallel_barrier, parallel_bcast_text, parallel_nomem, &
            parallel_sum, parallel_max, parallel_min, parallel_send, parallel_recv

  !> Every rank's values combined in place, element by element (the
  !> driver's reductions of counts and totals; a no-op on one rank).
  interface parallel_sum
    module procedure sum_ints, sum_reals
  end interface parallel_sum
  interface parallel_max
    module procedure max_ints, max_reals
  end interface parallel_max
  interface parallel_min
    module procedure min_ints, min_reals
  end interface parallel_min

  !> The ranks and their Cartesian layout.
  type :: comm_t
    type(MPI_Comm) :: world = MPI_COMM_NULL   !< all ranks
    type(MPI_Comm) :: cart = MPI_COMM_NULL    !< the Cartesian communicator (after `parallel_decompose`)
    integer :: rank = 0, nranks = 1
    integer :: dims(3) = 1, coords(3) = 0     !< ranks per direction and this rank's place
    integer :: nbr(6) = -1                    !< rank across each face (MPI_PROC_NULL if none)
    !> the block cuts, direction by direction: dims(d) + 1 cell-plane
    !> indices 0 .. gn(d) each (`parallel_decompose`)
    integer, allocatable :: cuts(:)
    !> the cuts balance the work of given weights, not the cells alone
    logical :: weighted = .false.
  end type comm_t

contains

  !> Starts MPI (threads funnelled: only the master thread of a rank calls
  !> MPI) unless already started, when the process was launched by an MPI
  !> launcher (mpirun, mpiexec, srun: it sets one of the variables below).
  !> A process started on its own is one rank without MPI: an MPI singleton
  !> would cost about 0.3 s of start-up per run, which the test suite's
  !> thousands of short runs would feel. Nothing calls MPI on one rank.
  subroutine parallel_start(pc)
    type(comm_t), intent(out) :: pc
    character(len=*), parameter :: launched(5) = [character(len=20) :: 'OMPI_COMM_WORLD_SIZE', 'PMIX_RANK', &
                                                   'PMI_RANK', 'PMI_SIZE', 'SLURM_STEP_ID']
    logical :: ready
    integer :: provided, i, n, status
    call MPI_Initialized(ready)
    if (.not. ready) then
      do i = 1, size(launched)
        call get_environment_variable(trim(launched(i)), length=n, status=status)
        if (status == 0) exit
      end do
      if (i > size(launched)) return   ! (on its own: pc is one rank)
      call MPI_Init_thread(MPI_THREAD_FUNNELED, provided)
    end if
    pc%world = MPI_COMM_WORLD
    call MPI_Comm_rank(pc%world, pc%rank)
    call MPI_Comm_size(pc%world, pc%nranks)
    pc%cart = MPI_COMM_WORLD
  end subroutine parallel_start

  !> This rank's number in MPI_COMM_WORLD (0 before MPI starts).
  integer function parallel_rank() result(r)
    logical :: ready
    r = 0
    call MPI_Initialized(ready)
    if (ready) call MPI_Comm_rank(MPI_COMM_WORLD, r)
  end function parallel_rank

  !> Ends MPI on a planned, collective exit (every rank calls it).
  subroutine parallel_stop()
    logical :: ready, done
    call MPI_Initialized(ready)
    call MPI_Finalized(done)
    if (ready .and. .not. done) call MPI_Finalize()
  end subroutine parallel_stop

  !> Ends every rank at once with exit status `code` (a failure found on
  !> one rank only, where the others cannot be told in step).
  subroutine parallel_abort(code)
    integer, intent(in) :: code
    logical :: ready, done
    call MPI_Initialized(ready)
    call MPI_Finalized(done)
    if (ready .and. .not. done) call MPI_Abort(MPI_COMM_WORLD, code)
  end subroutine parallel_abort

  !> Ends every rank if an allocation of a collective step (a halo buffer,
  !> a gather) failed (stat /= 0): the other ranks are already waiting in
  !> the exchange and cannot be told otherwise.
  subroutine parallel_nomem(stat, what)
    integer, intent(in) :: stat
    character(len=*), intent(in) :: what
    if (stat == 0) return
    write(error_unit, '(a)') 'FATAL [rank '//itoa(parallel_rank())//'] out of memory in '//what
    call parallel_abort(1)
  end subroutine parallel_nomem

  !> Sends buf to the rank `to` of the Cartesian communicator (a neighbour,
  !> pc%nbr; nothing if MPI_PROC_NULL). Paired with `parallel_recv`.
  subroutine parallel_send(pc, to, buf)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: to
    real(wp), intent(in) :: buf(:)
    call MPI_Send(buf, size(buf), MPI_DOUBLE_PRECISION, to, 30, pc%cart)
  end subroutine parallel_send

  !> Receives buf from the rank `from` (`parallel_send`); buf unchanged if
  !> from is MPI_PROC_NULL.
  subroutine parallel_recv(pc, from, buf)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: from
    real(wp), intent(inout) :: buf(:)
    call MPI_Recv(buf, size(buf), MPI_DOUBLE_PRECISION, from, 30, pc%cart, MPI_STATUS_IGNORE)
  end subroutine parallel_recv

  !> Waits for every rank.
  subroutine parallel_barrier(pc)
    type(comm_t), intent(in) :: pc
    call MPI_Barrier(pc%world)
  end subroutine parallel_barrier

  !> Broadcasts a text from rank `root` (allocated on every rank on exit).
  subroutine parallel_bcast_text(pc, text, root)
    type(comm_t), intent(in) :: pc
    character(len=:), allocatable, intent(inout) :: text
    integer, intent(in) :: root
    integer :: n, stat
    n = 0
    if (pc%rank == root) n = len(text)
    call MPI_Bcast(n, 1, MPI_INTEGER, root, pc%world)
    if (pc%rank /= root) then
      if (allocated(text)) deallocate(text)
      allocate(character(len=n) :: text, stat=stat)
      call parallel_nomem(stat, 'parallel_bcast_text')
    end if
    if (n > 0) call MPI_Bcast(text, n, MPI_CHARACTER, root, pc%world)
  end subroutine parallel_bcast_text

  !> Ranks per direction for nranks ranks on a grid of gn cells: `fixed`
  !> where positive (from the deck), else the layout with the least halo
  !> surface sum_d (p_d - 1) A_d (A_d the grid's cross-section normal to d),
  !> among those with at least `min_cells` cells per block in each direction
  !> that is cut; on a tie the
  !> layout cut more in z, then y (whole x rows stay together). Returns 0s if
  !> none fits.
  pure function parallel_dims(nranks, gn, fixed, min_cells) result(dims)
    integer, intent(in) :: nranks, gn(3), fixed(3), min_cells
    integer :: dims(3)
    integer :: p1, p2, p3, p(3)
    real(8) :: area, best
    dims = 0
    best = huge(1.0d0)
    do p3 = nranks, 1, -1
      if (mod(nranks, p3) /= 0) cycle
      do p2 = nranks/p3, 1, -1
        if (mod(nranks/p3, p2) /= 0) cycle
        p1 = nranks/(p3*p2)
        p = [p1, p2, p3]
        if (any(fixed > 0 .and. p /= fixed)) cycle
        if (any(p > 1 .and. gn < p*min_cells)) cycle
        area = (p1 - 1)*real(gn(2), 8)*gn(3) + (p2 - 1)*real(gn(1), 8)*gn(3) + (p3 - 1)*real(gn(1), 8)*gn(2)
        if (area < best) then
          best = area
          dims = p
        end if
      end do
    end do
  end function parallel_dims

  !> Lays the ranks out on the grid of gn cells (`dims_deck` from the deck,
  !> 0 to choose) and returns this rank's block with ng ghost layers towards
  !> each neighbouring block. A layout that leaves some block thinner than
  !> ng cells is refused. The cuts in each direction give the blocks equal
  !> numbers of cells (within one), or with weights (gn(1) + gn(2) + gn(3):
  !> the work of each plane of cells normal to i, then j, then k, the same
  !> on every rank) equal work (`parallel_cuts`).
  subroutine parallel_decompose(pc, gn, dims_deck, ng, ix, err, weights)
    type(comm_t), intent(inout) :: pc
    integer, intent(in) :: gn(3), dims_deck(3), ng
    type(grid_index_t), intent(out) :: ix
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: weights(:)
    integer :: d, base, extra, w0, b
    logical, parameter :: periodic(3) = .false.

    pc%dims = parallel_dims(pc%nranks, gn, dims_deck, max(ng, 1))
    if (any(pc%dims == 0)) then
      if (any(dims_deck > 0)) then
        call error_set(err, 'the deck has 1 problem(s); nothing was run', '&run blocks = '//itoa(dims_deck(1))// &
          ', '//itoa(dims_deck(2))//', '//itoa(dims_deck(3))//' does not fit '//itoa(pc%nranks)//' ranks on a grid of '// &
          itoa(gn(1))//' x '//itoa(gn(2))//' x '//itoa(gn(3))//' cells (the product of the non-zero entries must '// &
          'divide the rank count, and every block cut must keep at least '//itoa(max(ng, 1))//' cells)', ERR_INPUT)
      else
        call error_set(err, 'the deck has 1 problem(s); nothing was run', 'no layout of '//itoa(pc%nranks)// &
          ' ranks gives every block at least '//itoa(max(ng, 1))//' cells in each direction it is cut on a grid of '// &
          itoa(gn(1))//' x '//itoa(gn(2))//' x '//itoa(gn(3))//' cells; run on fewer ranks', ERR_INPUT)
      end if
      return
    end if
    pc%cuts = [integer ::]
    pc%weighted = present(weights)
    call MPI_Cart_create(pc%world, 3, pc%dims, periodic, .false., pc%cart)
    call MPI_Comm_rank(pc%cart, pc%rank)
    call MPI_Cart_coords(pc%cart, pc%rank, 3, pc%coords)
    do d = 1, 3
      call MPI_Cart_shift(pc%cart, d - 1, 1, pc%nbr(2*d - 1), pc%nbr(2*d))
      if (present(weights)) then
        w0 = sum(gn(1:d - 1))
        pc%cuts = [pc%cuts, parallel_cuts(weights(w0 + 1:w0 + gn(d)), pc%dims(d), max(ng, 1))]
      else
        ! gn(d) cells over dims(d) blocks, the first mod(gn, dims) one larger
        base = gn(d)/pc%dims(d)
        extra = mod(gn(d), pc%dims(d))
        pc%cuts = [pc%cuts, [(b*base + min(b, extra), b = 0, pc%dims(d))]]
      end if
    end do
    ix = parallel_block(pc, gn, ng, pc%cuts)
  end subroutine parallel_decompose

  !> This rank's block with ng ghost layers towards each neighbouring block
  !> for the cuts (as pc%cuts: direction by direction, dims(d) + 1 cell-plane
  !> indices 0 .. gn(d) each) on pc's layout of the ranks.
  function parallel_block(pc, gn, ng, cuts) result(ix)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: gn(3), ng, cuts(:)
    type(grid_index_t) :: ix
    integer :: d, w0, n(3), off(3), glo(3), ghi(3)
    w0 = 0
    do d = 1, 3
      ! (this direction's cuts c(0:dims) from cuts(w0 + 1))
      off(d) = cuts(w0 + 1 + pc%coords(d))
      n(d) = cuts(w0 + 2 + pc%coords(d)) - off(d)
      glo(d) = merge(ng, 0, pc%coords(d) > 0)
      ghi(d) = merge(ng, 0, pc%coords(d) < pc%dims(d) - 1)
      w0 = w0 + pc%dims(d) + 1
    end do
    ix = grid_index_block(n, glo, ghi, off, gn)
  end function parallel_block

  !> The cuts (as pc%cuts) of pc's layout that balance the work w of the
  !> planes of cells normal to i, then j, then k (gn(1) + gn(2) + gn(3),
  !> the same on every rank; blocks at least m planes thick), or held (the
  !> cuts in use, if allocated) while in each direction their most loaded
  !> slab has at most 1 + tolerance times the work of the new cuts'.
  function parallel_balance(pc, gn, m, w, held, tolerance) result(cuts)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: gn(3), m
    real(wp), intent(in) :: w(:), tolerance
    integer, allocatable, intent(in) :: held(:)
    integer :: cuts(size(pc%cuts))
    integer :: d, w0, c0
    logical :: keep
    keep = allocated(held)
    w0 = 0
    c0 = 0
    do d = 1, 3
      cuts(c0 + 1:c0 + pc%dims(d) + 1) = parallel_cuts(w(w0 + 1:w0 + gn(d)), pc%dims(d), m)
      if (keep) keep = slab_max(held(c0 + 1:c0 + pc%dims(d) + 1)) <= &
                       (1.0_wp + tolerance)*slab_max(cuts(c0 + 1:c0 + pc%dims(d) + 1))
      w0 = w0 + gn(d)
      c0 = c0 + pc%dims(d) + 1
    end do
    if (keep) cuts = held
  contains
    !> The largest work of the slabs between the cuts c(0:) of direction d.
    real(wp) function slab_max(c)
      integer, intent(in) :: c(0:)
      integer :: b
      slab_max = 0.0_wp
      do b = 1, ubound(c, 1)
        slab_max = max(slab_max, sum(w(w0 + c(b - 1) + 1:w0 + c(b))))
      end do
    end function slab_max
  end function parallel_balance

  !> The cuts c(0:p) (c(0) = 0, c(p) = n) of n planes of work w(n) into p
  !> blocks c(b) + 1 .. c(b + 1) of nearly equal work: each cut at the plane
  !> boundary whose prefix of work is nearest to b/p of the whole, each block
  !> at least m planes thick (n >= p m: `parallel_dims`).
  pure function parallel_cuts(w, p, m) result(c)
    real(wp), intent(in) :: w(:)
    integer, intent(in) :: p, m
    integer :: c(0:p)
    real(wp) :: prefix(0:size(w)), target
    integer :: b, e, n
    n = size(w)
    prefix(0) = 0.0_wp
    do e = 1, n
      prefix(e) = prefix(e - 1) + w(e)
    end do
    c(0) = 0
    c(p) = n
    e = 0
    do b = 1, p - 1
      target = prefix(n)*real(b, wp)/real(p, wp)
      do while (e < n)
        if (prefix(e + 1) > target) exit
        e = e + 1
      end do
      ! (e: the last boundary at or below the target; e + 1 if nearer)
      c(b) = e
      if (e < n) then
        if (prefix(e + 1) - target < target - prefix(e)) c(b) = e + 1
      end if
      c(b) = min(max(c(b), c(b - 1) + m), n - (p - b)*m)
    end do
  end function parallel_cuts
  subroutine sum_ints(pc, a)
    type(comm_t), intent(in) :: pc
    integer, contiguous, intent(inout) :: a(:)
    call reduce_ints(pc, a, MPI_SUM)
  end subroutine sum_ints

  subroutine max_ints(pc, a)
    type(comm_t), intent(in) :: pc
    integer, contiguous, intent(inout) :: a(:)
    call reduce_ints(pc, a, MPI_MAX)
  end subroutine max_ints

  subroutine min_ints(pc, a)
    type(comm_t), intent(in) :: pc
    integer, contiguous, intent(inout) :: a(:)
    call reduce_ints(pc, a, MPI_MIN)
  end subroutine min_ints

  subroutine sum_reals(pc, a)
    type(comm_t), intent(in) :: pc
    real(wp), contiguous, intent(inout) :: a(:)
    call reduce_reals(pc, a, MPI_SUM)
  end subroutine sum_reals

  subroutine max_reals(pc, a)
    type(comm_t), intent(in) :: pc
    real(wp), contiguous, intent(inout) :: a(:)
    call reduce_reals(pc, a, MPI_MAX)
  end subroutine max_reals

  subroutine min_reals(pc, a)
    type(comm_t), intent(in) :: pc
    real(wp), contiguous, intent(inout) :: a(:)
    call reduce_reals(pc, a, MPI_MIN)
  end subroutine min_reals

  subroutine reduce_ints(pc, a, op)
    type(comm_t), intent(in) :: pc
    integer, contiguous, intent(inout) :: a(:)
    type(MPI_Op), intent(in) :: op
    if (pc%nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_INTEGER, op, pc%world)
  end subroutine reduce_ints

  subroutine reduce_reals(pc, a, op)
    type(comm_t), intent(in) :: pc
    real(wp), contiguous, intent(inout) :: a(:)
    type(MPI_Op), intent(in) :: op
    if (pc%nranks > 1) call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_DOUBLE_PRECISION, op, pc%world)
  end subroutine reduce_reals
end module parallel_comm
