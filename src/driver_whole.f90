!> The whole grid on every rank of a decomposed run, for the parts of a run
!> that do not yet work block by block: the Euler phase (rezone and remap of
!> the whole grid, computed alike on every rank, each rank then taking its
!> block back) and the particles (seeded on the whole grid, moved on it at
!> Euler steps; without Euler steps the whole grid is let go once they are
!> seeded); a run that holds it for these reads a restart into it too.
!> Restart dumps need no whole grid: the ranks write their blocks into one
!> file together (`whole_dump`), the file of one process, so a dump written
!> on P ranks continues on any Q; a run without Euler steps or particles
!> reads its blocks from it (`read_restart`) and never holds the whole
!> grid.
!>
!> What is copied is what a restart holds (the quantities the packages
!> register, `base_registry`), then what a restart read rebuilds from them
!> (`state_after_read`, the materials' cell lists): a state made this way
!> continues exactly as the one it was copied from, which the restart tests
!> check for every registered quantity. Node and cell arrays go through the
!> blocks' owned ranges (`parallel_gather`); the mixed cells through their
!> owned cells, renumbered and put back in cell order (the order one
!> process keeps them in).
!>
!> This costs the whole grid's memory on every rank and a gather of the
!> whole state per Euler step: it makes a decomposed run with Euler steps
!> give the single process's answer (the costly parts of the Euler step are
!> shared over the ranks, `base_share`).
module driver_whole
  use mpi_f08, only: MPI_Allreduce, MPI_DOUBLE_PRECISION, MPI_INTEGER, MPI_IN_PLACE, MPI_MAX, MPI_MIN, MPI_SUM
  use base_sort, only: sort_order
  use lagrange_centroids, only: centroid_stats_t, centroids_refresh
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set
  use base_registry, only: registry_t, registry_entry_t, LOC_GLOBAL, LOC_NODE, LOC_CELL, K_REAL, K_INT, &
                           K_REAL_SCALAR, K_INT_SCALAR
  use material_mixed, only: mixed_t, mixed_allocate, mixed_subset
  use material_table, only: material_index_cells
  use io_log, only: log_t, log_line
  use base_strings, only: itoa
  use particles_state, only: particles_t, particles_index
  use driver_particles, only: particles_gathered, particles_take
  use parallel_comm, only: comm_t
  use parallel_share, only: mpi_share_t, mpi_share_init
  use parallel_gather, only: gather_cells, gather_nodes, gather_concat
  use driver_config, only: config_t
  use driver_state, only: state_t, state_register_restart, state_after_read
  use driver_scene, only: build_scene
  use driver_euler, only: euler_state_t, euler_due, euler_due_where, euler_shape, euler_step
  use driver_output, only: schedule_t, report_conservation
  use driver_parallel, only: agree_error
  use driver_restart, only: write_restart, read_restart, mixed_of_block, mixed_numbers
  implicit none
  private
  public :: whole_build, whole_euler, whole_dump, whole_restart, whole_gather, whole_scatter

contains

  !> Builds st%whole from the deck when a decomposed run needs it (Euler
  !> steps or particles); nothing otherwise. With particles the blocks are
  !> then taken from it.
  subroutine whole_build(cfg, pc, st, log, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    type(log_t) :: silent
    type(mpi_share_t) :: share
    integer :: stat
    if (pc%nranks == 1) return
    if (trim(cfg%rezone%mode) == 'none' .and. size(cfg%particles) == 0) return
    allocate(st%whole, stat=stat)
    if (stat /= 0) then
      call error_set(err, 'whole_build', 'out of memory for the whole grid''s state')
      return
    end if
    silent%quiet = .true.   ! (the blocks' scene has been logged)
    call build_scene(cfg, st%whole, silent, err)
    if (.not. allocated(err)) then
      ! the ranks share the Euler step's intersections on the whole grid
      call mpi_share_init(share, pc)
      allocate(st%whole%share, source=share, stat=stat)
      if (stat /= 0) call error_set(err, 'whole_build', 'out of memory')
    end if
    if (allocated(err) .or. .not. allocated(st%whole%pt%id)) return
    ! the particles are seeded on the whole grid (the order of one process);
    ! each block takes those of its cells, and the nodes their momentum
    call log_line(log, 'particles: '//itoa(st%whole%pt%np)//' in all, seeded on the whole grid')
    call whole_scatter(st, err)
  end subroutine whole_build

  !> The Euler phase of a decomposed run after a Lagrangian step: whether it
  !> is due (the quality triggers from each block's owned cells, reduced:
  !> a maximum and a minimum, exact in any order), then the Euler step on
  !> the whole grid and each block taken back from it.
  subroutine whole_euler(cfg, pc, st, es, log, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(euler_state_t), intent(inout) :: es
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: mine(2), shape(2)
    logical :: due
    if (.not. es%on) return
    st%whole%t = st%t
    st%whole%dt = st%dt
    st%whole%step = st%step
    shape = [0.0_wp, 1.0_wp]
    if (cfg%rezone%side_ratio > 0.0_wp .or. cfg%rezone%cos_angle > 0.0_wp) then
      call euler_shape(cfg%rezone, st%g, mine)
      call MPI_Allreduce(mine(1), shape(1), 1, MPI_DOUBLE_PRECISION, MPI_MAX, pc%world)
      call MPI_Allreduce(mine(2), shape(2), 1, MPI_DOUBLE_PRECISION, MPI_MIN, pc%world)
    end if
    call euler_due(cfg%rezone, st%whole, es, due, shape)
    if (.not. due) return
    call whole_gather(pc, st, err)
    if (.not. allocated(err)) call euler_due_where(cfg%rezone, st%whole, es, shape)
    if (.not. allocated(err)) call euler_step(cfg%rezone, st%whole, es, log, err)
    if (.not. allocated(err)) call whole_scatter(st, err)
  end subroutine whole_euler

  !> A restart dump of a decomposed run, written by the ranks together
  !> (`write_restart`, `restart_write`): each block its owned nodes and cells
  !> of the node and cell quantities, rank 0 the rest, which must be the
  !> whole run's: the mixed cells (their centroids refreshed in each block,
  !> then gathered in cell order, `mixed_gather`) and the particles (in the
  !> whole run's order) are put in the block's place for the dump, and a
  !> mixed cell's material (minus its number in the block's storage) its
  !> number among the whole grid's. The file is the one a single process
  !> writes; the whole grid's state is not needed.
  subroutine whole_dump(cfg, pc, st, sch, es, err)
    type(config_t), intent(in) :: cfg
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    type(mixed_t) :: mw, mb
    type(particles_t) :: pw, pb
    type(centroid_stats_t) :: cs
    integer, allocatable :: mat(:), keep(:)
    integer :: k, c, lo, hi, mid, gc, n(2), ijk(3)

    call mixed_gather(pc, st, mw, err, cs)
    if (allocated(err)) return
    n = [cs%moved, cs%failed]
    call MPI_Allreduce(MPI_IN_PLACE, n, 2, MPI_INTEGER, MPI_SUM, pc%world)
    es%centroids%moved = es%centroids%moved + n(1)
    es%centroids%failed = es%centroids%failed + n(2)
    ! the owned mixed cells' numbers in the whole grid's list (ascending cells)
    mat = st%h%mat
    do k = 1, st%mx%n
      c = st%mx%cell(k)
      call st%g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
      if (.not. st%g%owns_cell(ijk(1), ijk(2), ijk(3))) cycle
      gc = st%g%global_cell(c)
      lo = 1; hi = mw%n
      do while (lo < hi)
        mid = (lo + hi)/2
        if (mw%cell(mid) < gc) then
          lo = mid + 1
        else
          hi = mid
        end if
      end do
      mat(c) = -lo
    end do
    if (allocated(st%pwhole)) then
      call particles_gathered(pc, st, pw, err)
      if (allocated(err)) return
      pb = st%pt
      st%pt = pw
    end if
    mb = st%mx
    st%mx = mw
    call move_alloc(st%h%mat, keep)
    call move_alloc(mat, st%h%mat)
    call write_restart(cfg, st, sch, es, err)
    ! the block's own again
    call move_alloc(keep, st%h%mat)
    st%mx = mb
    if (allocated(st%pwhole)) st%pt = pb
  end subroutine whole_dump

  !> A decomposed run's restart: with the whole grid held (Euler steps,
  !> particles) every rank reads the file into it and takes its block from
  !> it; otherwise each rank reads its block (`read_restart`).
  subroutine whole_restart(cfg, st, sch, es, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout), target :: st
    type(schedule_t), intent(inout) :: sch
    type(euler_state_t), intent(inout) :: es
    type(error_t), allocatable, intent(inout) :: err
    if (allocated(st%whole)) then
      call read_restart(cfg, st%whole, sch, es, err)
      if (.not. allocated(err)) call whole_scatter(st, err)
    else
      call read_restart(cfg, st, sch, es, err, block=.true.)
      ! (a block's file may be damaged where another's is not)
      call agree_error(sch%pc, err)
      if (.not. allocated(err)) call report_conservation(st, sch%log, 'restart')
    end if
  end subroutine whole_restart

  !> Every rank's st%whole: the whole grid's state assembled from the
  !> blocks' st (st%whole built from the deck on the whole grid first,
  !> `build_scene` without a block).
  subroutine whole_gather(pc, st, err)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(inout), target :: st
    type(error_t), allocatable, intent(inout) :: err
    type(registry_t) :: rb, rw
    real(wp), allocatable :: whole(:, :)
    real(wp), pointer, contiguous :: a(:, :)
    integer :: e, m, n

    call mixed_gather(pc, st, st%whole%mx, err)
    if (allocated(err)) return
    if (allocated(st%pwhole)) then
      call particles_gathered(pc, st, st%whole%pt, err)
      if (.not. allocated(err)) call particles_index(st%whole%pt, st%whole%g%ncell, err)
      if (allocated(err)) return
      st%whole%pw%mass_ready = .false.
    end if
    call state_register_restart(st, rb)
    call state_register_restart(st%whole, rw)
    do e = 1, rb%n
      associate (b => rb%e(e), v => rw%e(e))
        select case (b%location)
        case (LOC_NODE, LOC_CELL)
          m = product(b%dims(1:size(b%dims) - 1))
          n = b%dims(size(b%dims))
          if (b%kind == K_REAL) then
            a(1:m, 1:n) => b%r
            call gather_entry(a)
            v%r = reshape(whole, [size(whole)])
          else
            ! (integers: material indices, exact as reals)
            call gather_entry(reshape(real(b%i, wp), [m, n]))
            v%i = nint(reshape(whole, [size(whole)]))
          end if
        case (LOC_GLOBAL)
          if (.not. mixed_entry(b)) call copy_global(b, v)
        end select
      end associate
    end do
    call mixed_numbers(st%whole)
    call state_after_read(st%whole)
    call material_index_cells(st%whole%mats, st%whole%h%mat, st%whole%mx, err)
  contains
    subroutine gather_entry(x)
      real(wp), intent(in) :: x(:, :)
      if (rb%e(e)%location == LOC_NODE) then
        call gather_nodes(pc, st%g%grid_index_t, x, whole, all=.true.)
      else
        call gather_cells(pc, st%g%grid_index_t, x, whole, all=.true.)
      end if
    end subroutine gather_entry
  end subroutine whole_gather

  !> The counts of the mixed cells (copied with the cells themselves).
  logical function mixed_entry(e)
    type(registry_entry_t), intent(in) :: e
    mixed_entry = e%name(1:6) == 'mixed_'
  end function mixed_entry

  !> This rank's block st (owned and ghost cells and nodes) taken from the
  !> whole grid's state st%whole.
  subroutine whole_scatter(st, err)
    type(state_t), intent(inout), target :: st
    type(error_t), allocatable, intent(inout) :: err
    type(registry_t) :: rb, rw
    integer, allocatable :: pick(:)
    integer :: e, i, j, l, c, n, m, q
    logical :: nodes

    ! the mixed cells the block stores, in the whole grid's (cell) order
    call mixed_of_block(st%g, st%whole%mx, st%mx, err, pick)
    if (allocated(err)) return
    if (allocated(st%whole%pt%id)) then
      call particles_take(st, err)
      if (allocated(err)) return
    end if
    call state_register_restart(st, rb)
    call state_register_restart(st%whole, rw)
    do e = 1, rb%n
      associate (b => rb%e(e), v => rw%e(e), g => st%g, wg => st%whole%g)
        select case (b%location)
        case (LOC_NODE, LOC_CELL)
          nodes = b%location == LOC_NODE
          m = product(b%dims(1:size(b%dims) - 1))
          do l = g%slo(3) - merge(1, 0, nodes), g%shi(3)
            do j = g%slo(2) - merge(1, 0, nodes), g%shi(2)
              do i = g%slo(1) - merge(1, 0, nodes), g%shi(1)
                if (nodes) then
                  n = g%node(i, j, l)
                  c = wg%node(i + g%off(1), j + g%off(2), l + g%off(3))
                else
                  n = g%cell(i, j, l)
                  c = wg%cell(i + g%off(1), j + g%off(2), l + g%off(3))
                end if
                do q = 1, m
                  if (b%kind == K_REAL) then
                    b%r(m*(n - 1) + q) = v%r(m*(c - 1) + q)
                  else
                    b%i(m*(n - 1) + q) = v%i(m*(c - 1) + q)
                  end if
                end do
              end do
            end do
          end do
        case (LOC_GLOBAL)
          if (.not. mixed_entry(b)) call copy_global(v, b)
        end select
      end associate
    end do
    call mixed_numbers(st)
    call state_after_read(st)
    call material_index_cells(st%mats, st%h%mat, st%mx, err)
  end subroutine whole_scatter

  !> A quantity of the whole run (time, step, energy bookkeeping, the random
  !> numbers' state): the same on every rank, copied.
  subroutine copy_global(from, to)
    type(registry_entry_t), intent(in) :: from
    type(registry_entry_t), intent(inout) :: to
    select case (from%kind)
    case (K_REAL); to%r = from%r
    case (K_INT); to%i = from%i
    case (K_REAL_SCALAR); to%rs = from%rs
    case (K_INT_SCALAR); to%is = from%is
    end select
  end subroutine copy_global

  !> The whole grid's mixed cells mw, in cell order, from the cells each
  !> block owns (on every rank). With `refreshed` the centroids of each
  !> block's owned mixed cells are refreshed first (`centroids_refresh`,
  !> counted in it; the block's own storage is left as it is).
  subroutine mixed_gather(pc, st, mw, err, refreshed)
    type(comm_t), intent(in) :: pc
    type(state_t), intent(in) :: st
    type(mixed_t), intent(inout) :: mw
    type(error_t), allocatable, intent(inout) :: err
    type(centroid_stats_t), intent(inout), optional :: refreshed
    type(mixed_t) :: own, cat
    integer, allocatable :: pick(:), cells(:), nslots(:), mats(:)
    real(wp), allocatable :: r(:)
    integer :: k, m, stat, ijk(3)

    allocate(pick(st%mx%n), cells(st%mx%n), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'mixed_gather', 'out of memory')
      return
    end if
    m = 0
    do k = 1, st%mx%n
      call st%g%cell_ijk(st%mx%cell(k), ijk(1), ijk(2), ijk(3))
      if (.not. st%g%owns_cell(ijk(1), ijk(2), ijk(3))) cycle
      m = m + 1
      pick(m) = k
    end do
    call mixed_subset(st%mx, pick(:m), st%mx%cell(pick(:m)), own, err)
    if (allocated(err)) return
    if (present(refreshed)) call centroids_refresh(st%g, own, refreshed)
    do k = 1, own%n
      own%cell(k) = st%g%global_cell(own%cell(k))
    end do
    call gather_concat(pc, own%cell, cells)
    call gather_concat(pc, own%start(2:) - own%start(:own%n), nslots)
    call gather_concat(pc, own%mat, mats)
    call mixed_allocate(cat, size(cells), size(mats), err)
    if (allocated(err)) return
    cat%cell = cells
    do k = 1, cat%n
      cat%start(k + 1) = cat%start(k) + nslots(k)
    end do
    cat%mat = mats
    call gather_concat(pc, own%vf, cat%vf)
    call gather_concat(pc, own%mass, cat%mass)
    call gather_concat(pc, own%e, cat%e)
    call gather_concat(pc, own%rho, cat%rho)
    call gather_concat(pc, own%p, cat%p)
    call gather_concat(pc, own%cs, cat%cs)
    call gather_concat(pc, reshape(own%xi, [3*own%nslot]), r)
    cat%xi = reshape(r, [3, cat%nslot])
    call gather_concat(pc, reshape(own%plane, [4*own%nslot]), r)
    cat%plane = reshape(r, [4, cat%nslot])
    ! in cell order (each cell is owned by one block)
    deallocate(pick)
    allocate(pick(cat%n), stat=stat)
    if (stat == 0) call sort_order(cat%cell, pick, stat)
    if (stat /= 0) then
      call error_set(err, 'mixed_gather', 'out of memory')
      return
    end if
    call mixed_subset(cat, pick, cat%cell(pick), mw, err)
  end subroutine mixed_gather
end module driver_whole
