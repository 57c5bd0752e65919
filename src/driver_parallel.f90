!> The driver's side of a run on several MPI ranks: the blocks and their
!> halo, and errors agreed by all ranks so that every rank ends together
!> with the message of the rank that failed.
module driver_parallel
  use mpi_f08, only: MPI_Allreduce, MPI_INTEGER, MPI_MIN, MPI_MAX
  use base_errors, only: error_t, error_set
  use mesh_grid, only: grid_index_t, grid_index
  use mesh_halo, only: halo_t
  use parallel_comm, only: comm_t, parallel_decompose, parallel_bcast_text
  use parallel_halo, only: mpi_halo_t, mpi_halo_init
  use driver_config, only: config_t
  implicit none
  private
  public :: ghost_layers, parallel_blocks, agree_error

  !> Ghost layers: the corner forces of the first ghost layer need the
  !> strain rates of its neighbours (the viscosity limiter).
  integer, parameter :: GHOST_WIDTH = 2

contains

  !> The ghost layers of the deck's blocks: GHOST_WIDTH, one more with
  !> particles spread over their neighbour cells (&hydro particle_support =
  !> 'gimp': a particle in the second ghost layer reaches the owned nodes
  !> through the first, and its own update needs the third).
  pure integer function ghost_layers(cfg)
    type(config_t), intent(in) :: cfg
    ghost_layers = GHOST_WIDTH
    if (.not. cfg%hydro%particle_gimp .or. .not. allocated(cfg%particles)) return
    if (size(cfg%particles) > 0) ghost_layers = GHOST_WIDTH + 1
  end function ghost_layers

  !> This rank's block of the deck's grid and its halo (the whole grid and
  !> the halo of a single block on one rank).
  subroutine parallel_blocks(cfg, pc, ix, halo, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(inout) :: pc
    type(grid_index_t), intent(out) :: ix
    class(halo_t), allocatable, intent(out) :: halo
    type(error_t), allocatable, intent(inout) :: err
    type(mpi_halo_t) :: mh
    integer :: stat
    if (pc%nranks == 1) then
      ix = grid_index(cfg%grid%ni, cfg%grid%nj, cfg%grid%nk)
      allocate(halo_t :: halo, stat=stat)
    else
      call parallel_decompose(pc, [cfg%grid%ni, cfg%grid%nj, cfg%grid%nk], cfg%control%blocks, ghost_layers(cfg), ix, err)
      if (allocated(err)) return
      call mpi_halo_init(mh, pc, ix)
      allocate(halo, source=mh, stat=stat)
    end if
    if (stat /= 0) call error_set(err, 'parallel_blocks', 'out of memory')
  end subroutine parallel_blocks

  !> Makes an error on any rank an error on all: every rank returns with
  !> err allocated, holding the message of the lowest rank that failed,
  !> and that rank in err%rank. A no-op on one rank.
  subroutine agree_error(pc, err)
    type(comm_t), intent(in) :: pc
    type(error_t), allocatable, intent(inout) :: err
    integer :: mine, first, category
    character(len=:), allocatable :: where, msg
    if (pc%nranks == 1) return
    mine = huge(1)
    if (allocated(err)) mine = pc%rank
    call MPI_Allreduce(mine, first, 1, MPI_INTEGER, MPI_MIN, pc%world)
    if (first == huge(1)) return
    where = ''
    msg = ''
    category = 0
    if (pc%rank == first) then
      where = err%where
      msg = err%msg
      category = err%category
    end if
    call parallel_bcast_text(pc, where, first)
    call parallel_bcast_text(pc, msg, first)
    call bcast_int(category)
    call error_set(err, where, msg, category)
    err%rank = first
  contains
    subroutine bcast_int(k)
      integer, intent(inout) :: k
      integer :: kk
      kk = merge(k, -huge(1), pc%rank == first)
      call MPI_Allreduce(kk, k, 1, MPI_INTEGER, MPI_MAX, pc%world)
    end subroutine bcast_int
  end subroutine agree_error
end module driver_parallel
