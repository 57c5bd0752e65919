!> The halo of a block: how the Lagrangian step and the drivers refresh the
!> ghost nodes and cells of a block and turn a block's result into the whole
!> grid's. `halo_t` is the single block (the whole grid, no ghosts): nothing
!> to exchange, every result already global. The MPI decomposition extends
!> it (`parallel_halo`), so that the kernels and the integrator never call
!> MPI themselves.
module mesh_halo
  use base_kinds, only: wp, i8
  use base_xsum, only: xsum_t
  implicit none
  private
  public :: halo_t

  !> Ghost refresh and global reductions of one block (here: the only one).
  type :: halo_t
    integer :: nblocks = 1   !< blocks of the decomposition
    !> the cost of the exchanges and of the step's global minimum so far:
    !> wall seconds, messages sent and bytes sent by this block
    real(wp) :: seconds = 0.0_wp
    integer(i8) :: messages = 0_i8, bytes = 0_i8
    !> while limited, node refreshes (`nodes`) take only the ghost nodes in
    !> the box node_box(:, 1)..node_box(:, 2) of whole-grid node indices
    !> (the same box on every block): a smoothing whose writes all lie in it
    !> (`smooth_combined`)
    logical :: limited = .false.
    integer :: node_box(3, 2) = 0
  contains
    procedure :: nodes => halo_nodes
    procedure :: cells => halo_cells
    procedure :: min_step => halo_min_step
    procedure :: max_int => halo_max_int
    procedure :: sums => halo_sums
    procedure :: choose => halo_choose
    procedure :: sum_ints => halo_sum_ints
    procedure :: concat => halo_concat
  end type halo_t

contains

  ! The single block's procedures do nothing: each body's one statement,
  ! under `nblocks < 1` (never true), only keeps the compiler's check of
  ! unused arguments quiet.

  !> Refreshes the ghost nodes of a node field a(m, nnode).
  subroutine halo_nodes(this, a)
    class(halo_t), intent(inout) :: this
    real(wp), intent(inout) :: a(:, :)
    if (this%nblocks < 1) a = 0.0_wp
  end subroutine halo_nodes

  !> Refreshes the ghost cells of a cell field a(ncell).
  subroutine halo_cells(this, a)
    class(halo_t), intent(inout) :: this
    real(wp), intent(inout) :: a(:)
    if (this%nblocks < 1) a = 0.0_wp
  end subroutine halo_cells

  !> The smallest stable step of all blocks, dt (time), and the cell that
  !> sets it: on entry this block's (local index, 0 if none); on exit the
  !> limiting cell's local index on the block that owns it (the lowest
  !> global index on a tie), 0 on the others.
  subroutine halo_min_step(this, dt, cell)
    class(halo_t), intent(inout) :: this
    real(wp), intent(inout) :: dt
    integer, intent(inout) :: cell
    if (this%nblocks < 1) dt = real(cell, wp)
  end subroutine halo_min_step

  !> The largest of an integer over all blocks (a failure flag or a count).
  subroutine halo_max_int(this, k)
    class(halo_t), intent(in) :: this
    integer, intent(inout) :: k
    if (this%nblocks < 1) k = 0
  end subroutine halo_max_int

  !> Adds the exact sums acc(:) of all blocks: on exit every block holds the
  !> totals (`base_xsum`).
  subroutine halo_sums(this, acc)
    class(halo_t), intent(in) :: this
    type(xsum_t), intent(inout) :: acc(:)
    if (this%nblocks < 1) acc(1)%terms = 0
  end subroutine halo_sums

  !> The values of the block with the smallest key (the lowest-numbered
  !> block on a tie): on exit key and vals are that block's, on every block.
  subroutine halo_choose(this, key, vals)
    class(halo_t), intent(in) :: this
    real(wp), intent(inout) :: key, vals(:)
    if (this%nblocks < 1) vals = key
  end subroutine halo_choose

  !> Adds the integers a(:) of all blocks (exact): on exit every block
  !> holds the totals.
  subroutine halo_sum_ints(this, a)
    class(halo_t), intent(in) :: this
    integer, intent(inout) :: a(:)
    if (this%nblocks < 1) a = 0
  end subroutine halo_sum_ints

  !> w: the a(:) of all blocks concatenated in block order, on every block.
  subroutine halo_concat(this, a, w)
    class(halo_t), intent(in) :: this
    real(wp), intent(in) :: a(:)
    real(wp), allocatable, intent(out) :: w(:)
    if (this%nblocks < 1) return
    w = a
  end subroutine halo_concat
end module mesh_halo
