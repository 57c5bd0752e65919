!> The particles of a decomposed run between the whole run's arrays and a
!> block's: a block takes the particles its cells host from the whole
!> run's (`parallel_particles_take`), and the blocks' owned particles are
!> gathered back into the whole run's order on every rank
!> (`parallel_particles_gather`). Both keep the whole run's order, so a
!> block's particles are sorted as one process sorts them.
module parallel_particles
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_registry, only: registry_t, K_REAL
  use mesh_grid, only: grid_t, grid_index_t
  use particles_state, only: particles_t, particles_allocate, particles_select, particles_index, &
                             particles_register_restart
  use parallel_comm, only: comm_t
  use parallel_gather, only: gather_concat
  implicit none
  private
  public :: parallel_particles_take, parallel_particles_gather, parallel_particles_gather_mvf

contains

  !> The particles of w (host cells numbered on the whole grid's index wix)
  !> whose host is one of g's owned cells or lies in the `layers` ghost
  !> layers around them, into pt in w's order with their host cells
  !> numbered in g and indexed; pick: their indices in w; owned: which of
  !> them g owns.
  subroutine parallel_particles_take(w, wix, g, layers, pt, pick, owned, err)
    type(particles_t), intent(in) :: w
    type(grid_index_t), intent(in) :: wix
    type(grid_t), intent(in) :: g
    integer, intent(in) :: layers
    type(particles_t), intent(out) :: pt
    integer, allocatable, intent(out) :: pick(:)
    logical, allocatable, intent(out) :: owned(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: all(:)
    integer :: k, n, q, lo(3), hi(3), ijk(3), stat
    call g%cells_around(layers, lo, hi)
    allocate(all(w%np), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'parallel_particles_take', error_no_memory('work arrays'))
      return
    end if
    n = 0
    do k = 1, w%np
      call wix%cell_ijk(w%cell(k), ijk(1), ijk(2), ijk(3))
      ijk = ijk - g%off
      if (any(ijk < lo .or. ijk > hi)) cycle
      n = n + 1
      all(n) = k
    end do
    pick = all(:n)
    pt = w
    call particles_select(pt, pick)
    do q = 1, n
      call wix%cell_ijk(pt%cell(q), ijk(1), ijk(2), ijk(3))
      ijk = ijk - g%off
      pt%cell(q) = g%cell(ijk(1), ijk(2), ijk(3))
    end do
    call particles_index(pt, g%ncell, err)
    if (allocated(err)) return
    allocate(owned(n), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'parallel_particles_take', error_no_memory('work arrays'))
      return
    end if
    do q = 1, n
      call g%cell_ijk(pt%cell(q), ijk(1), ijk(2), ijk(3))
      owned(q) = g%owns_cell(ijk(1), ijk(2), ijk(3))
    end do
  end subroutine parallel_particles_take

  !> The particles of a decomposed run in the whole run's order (ptw, host
  !> cells numbered in the whole grid): each block gives the ones of pt it
  !> owns (owned) with their whole index (whole), host cells numbered on
  !> g. On every rank (collective).
  subroutine parallel_particles_gather(pc, g, pt, owned, whole, ptw, err)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout), target :: pt
    logical, intent(in) :: owned(:)
    integer, intent(in) :: whole(:)
    type(particles_t), intent(inout), target :: ptw
    type(error_t), allocatable, intent(inout) :: err
    type(registry_t) :: rb, rw
    integer, allocatable :: own(:), at(:), iw(:), cells(:)
    real(wp), allocatable :: rw_(:)
    integer :: k, e, m, q, j, stat

    own = pack([(k, k = 1, pt%np)], owned)
    call gather_concat(pc, whole(own), at)
    call particles_allocate(ptw, size(at), pt%nsolid, pt%nhist, err)
    if (allocated(err)) return
    ptw%spread = pt%spread
    if (allocated(pt%mvf)) then
      allocate(ptw%mvf(size(at)), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'parallel_particles_gather', error_no_memory('the gathered particles'))
        return
      end if
    end if
    ! (host cells in the whole grid's numbering while they are sent)
    cells = pt%cell
    do k = 1, pt%np
      pt%cell(k) = g%global_cell(cells(k))
    end do
    call particles_register_restart(pt, rb)
    call particles_register_restart(ptw, rw)
    do e = 1, rb%n
      associate (b => rb%e(e), v => rw%e(e))
        m = product(b%dims(1:size(b%dims) - 1))
        if (b%kind == K_REAL) then
          call gather_concat(pc, [((b%r(m*(own(q) - 1) + j), j = 1, m), q = 1, size(own))], rw_)
          do q = 1, size(at)
            v%r(m*(at(q) - 1) + 1:m*at(q)) = rw_(m*(q - 1) + 1:m*q)
          end do
        else
          call gather_concat(pc, [((b%i(m*(own(q) - 1) + j), j = 1, m), q = 1, size(own))], iw)
          do q = 1, size(at)
            v%i(m*(at(q) - 1) + 1:m*at(q)) = iw(m*(q - 1) + 1:m*q)
          end do
        end if
      end associate
    end do
    pt%cell = cells
  end subroutine parallel_particles_gather

  !> The virtual-fluid masses of ptw (`parallel_particles_gather`) taken
  !> again from the blocks' owned particles of pt. On every rank
  !> (collective).
  subroutine parallel_particles_gather_mvf(pc, pt, owned, whole, ptw)
    type(comm_t), intent(in) :: pc
    type(particles_t), intent(in) :: pt
    logical, intent(in) :: owned(:)
    integer, intent(in) :: whole(:)
    type(particles_t), intent(inout) :: ptw
    integer, allocatable :: own(:), at(:)
    real(wp), allocatable :: mvf(:)
    integer :: k
    own = pack([(k, k = 1, pt%np)], owned)
    call gather_concat(pc, whole(own), at)
    call gather_concat(pc, pt%mvf(own), mvf)
    ptw%mvf(at) = mvf
  end subroutine parallel_particles_gather_mvf
end module parallel_particles
