!> The driver's side of a run on several MPI ranks: the blocks and their
!> halo, and errors agreed by all ranks so that every rank ends together
!> with the message of the rank that failed.
module driver_parallel
  use base_errors, only: error_t, error_set
  use mesh_grid, only: grid_index_t, grid_index
  use mesh_halo, only: halo_t
  use base_kinds, only: wp
  use parallel_comm, only: comm_t, parallel_decompose, parallel_bcast_text, parallel_min, parallel_max, parallel_sum
  use parallel_halo, only: mpi_halo_t, mpi_halo_init
  use driver_config, only: config_t, shape_slabs
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
    real(wp), allocatable :: weights(:)
    integer :: stat
    if (pc%nranks == 1) then
      ix = grid_index(cfg%grid%ni, cfg%grid%nj, cfg%grid%nk)
      allocate(halo_t :: halo, stat=stat)
    else
      call block_weights(cfg, pc, weights, err)
      if (allocated(err)) return
      if (allocated(weights)) then
        call parallel_decompose(pc, [cfg%grid%ni, cfg%grid%nj, cfg%grid%nk], cfg%control%blocks, ghost_layers(cfg), &
                                ix, err, weights)
      else
        call parallel_decompose(pc, [cfg%grid%ni, cfg%grid%nj, cfg%grid%nk], cfg%control%blocks, ghost_layers(cfg), &
                                ix, err)
      end if
      if (allocated(err)) return
      call mpi_halo_init(mh, pc, ix)
      allocate(halo, source=mh, stat=stat)
    end if
    if (stat /= 0) call error_set(err, 'parallel_blocks', 'out of memory')
  end subroutine parallel_blocks

  !> The work of each plane of cells normal to i, then j, then k for the
  !> block cuts (`parallel_decompose`): its cells, and &run
  !> blocks_particle_weight times the particles the deck's shape groups seed
  !> in it (`shape_slabs`, the slabs shared by the ranks), so that a solid's
  !> particles are spread over the blocks; not allocated where there are no
  !> such particles or the weight is 0 (equal cells). Collective.
  subroutine block_weights(cfg, pc, weights, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    real(wp), allocatable, intent(out) :: weights(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: planes(:), seeds(:)
    integer :: gn(3), stat, d
    if (.not. allocated(cfg%particles) .or. .not. cfg%control%blocks_particle_weight > 0.0_wp) return
    if (size(cfg%particles) == 0) return
    gn = [cfg%grid%ni, cfg%grid%nj, cfg%grid%nk]
    allocate(planes(sum(gn)), seeds(size(cfg%particles)), stat=stat)
    if (stat /= 0) call error_set(err, 'parallel_blocks', 'out of memory for the block weights')
    if (stat == 0) then
      planes = 0
      call shape_slabs(cfg, pc%rank, pc%nranks, seeds, err, planes)
    end if
    call agree_error(pc, err)
    if (allocated(err)) return
    call parallel_sum(pc, planes)
    if (all(planes == 0)) return
    allocate(weights(sum(gn)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'parallel_blocks', 'out of memory for the block weights')
      return
    end if
    do d = 1, 3
      ! (a plane normal to d holds the product of the other two sizes' cells)
      weights(sum(gn(1:d - 1)) + 1:sum(gn(1:d))) = real(gn(1), wp)*real(gn(2), wp)*real(gn(3), wp)/real(gn(d), wp) + &
        cfg%control%blocks_particle_weight*real(planes(sum(gn(1:d - 1)) + 1:sum(gn(1:d))), wp)
    end do
  end subroutine block_weights

  !> Makes an error on any rank an error on all: every rank returns with
  !> err allocated, holding the message of the lowest rank that failed,
  !> and that rank in err%rank. A no-op on one rank.
  subroutine agree_error(pc, err)
    type(comm_t), intent(in) :: pc
    type(error_t), allocatable, intent(inout) :: err
    integer :: first(1), category(1)
    character(len=:), allocatable :: where, msg
    if (pc%nranks == 1) return
    first = huge(1)
    if (allocated(err)) first = pc%rank
    call parallel_min(pc, first)
    if (first(1) == huge(1)) return
    where = ''
    msg = ''
    category = -huge(1)
    if (pc%rank == first(1)) then
      where = err%where
      msg = err%msg
      category = err%category
    end if
    call parallel_bcast_text(pc, where, first(1))
    call parallel_bcast_text(pc, msg, first(1))
    ! (the failed rank's category: the others hold the least integer)
    call parallel_max(pc, category)
    call error_set(err, where, msg, category(1))
    err%rank = first(1)
  end subroutine agree_error
end module driver_parallel
