!> Restart files: the writer and reader that walk the restart registry
!> (`base_registry`).
!>
!> Packages register each restart quantity once (name, units, location, the
!> array or scalar itself, mandatory or not); `restart_write` and
!> `restart_read` loop over the registry, so a quantity that is registered
!> cannot be forgotten by either. Storage
!> whose size changes during a run (the mixed cells after a remap) is handled
!> by clearing the registry and registering again; before a full read, the
!> sizes stored in a file are read with `restart_read_int_scalar` or
!> `restart_read_dims`, so the caller can allocate to them first. Besides the
!> registry a restart file holds its format version, the resolved deck, and
!> the output bookkeeping (frame names and times), which change in length
!> during a run. The file is written under a temporary name, closed (flushed)
!> and renamed, so a run killed during a dump leaves the previous file intact;
!> a dump that fails (a full disk) removes its temporary file.
!>
!> Damage is refused, never used: the file is written with checksums
!> (`io_hdf5`: Fletcher-32 on every dataset that holds data, the newest HDF5
!> format's checksums on all metadata), so a changed bit makes a read fail
!> with the dataset's name. Values that are well-formed but impossible are
!> caught by checks: every array's shape against what this run registered,
!> sizes against the file's own dataset shapes before anything is allocated
!> (`restart_check_counts`, the frame list against its times), and every
!> real value finite, except quantities registered in units 'bits' (a random
!> generator's state stored in a real). Physical ranges of particular
!> quantities are the caller's to check.
module io_restart
  use, intrinsic :: iso_fortran_env, only: int64
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Allreduce, MPI_LOGICAL, MPI_LOR
  use mesh_grid, only: grid_index_t
  use io_hdf5, only: h5_file_t, h5_create, h5_open_read, h5_close, h5_write_real, h5_write_int, &
                     h5_write_part_real, h5_write_part_int, &
                     h5_write_scalar_real, h5_write_scalar_int, h5_write_string, h5_read_dims, &
                     h5_read_real, h5_read_int, h5_read_scalar_real, h5_read_scalar_int, &
                     h5_read_string, h5_exists
  use io_xdmf, only: io_rename
  use base_strings, only: itoa, rtoa
  use base_sort, only: sorted_runs
  use base_registry, only: registry_t, registry_entry_t, location_name, LOWER_POSITIVE, LOWER_NONNEGATIVE, &
                           LOC_GLOBAL, LOC_NODE, LOC_CELL, LOC_PARTICLE, K_REAL, K_INT, K_REAL_SCALAR, K_INT_SCALAR
  implicit none
  private
  public :: restart_write, restart_read, restart_read_parts, restart_read_int_runs, restart_cell_runs, restart_read_deck, &
            restart_read_int_scalar, restart_read_dims, restart_check_counts, restart_version, finite_bits, &
            nonfinite_name

  !> A decomposed run's share of the arrays at one location (particles,
  !> mixed cells, mixed slots) that the file holds for the whole run: this
  !> rank's values are written at (read from) the runs of their last
  !> dimension, runs(:, r) = (0-based start, length), increasing, among
  !> total entries. An array at the location with one entry more than the
  !> runs hold (the mixed cells' starts, total + 1 in the file) is written
  !> at the runs `plus` (its first values; the rank that holds the last
  !> entry writes it too) and is left to the caller on a read.
  type, public :: restart_part_t
    integer :: location = LOC_GLOBAL
    integer :: total = 0
    integer, allocatable :: runs(:, :), plus(:, :)
  end type restart_part_t

  !> Format version written to every file; a reader refuses any other.
  !> 2: the mixed-cell arrays are always present (possibly empty) and their
  !> sizes are stored as the scalars mixed_n and mixed_nslot.
  !> 3: checksums (HDF5 1.10 format, Fletcher-32 on every dataset with data);
  !> scalars are stored as one-element arrays.
  !> 4: the subcell (corner) masses, corner_mass (8, ncell).
  !> 5: the mixed cells' interface planes, mixed_plane (4, nslot).
  integer, parameter :: restart_version = 5

  !> Values of this magnitude or more are refused (the deck's rule), but for
  !> the largest real, which marks "never".
  real(wp), parameter :: too_big = 1.0e30_wp

contains

  !> Writes every registered quantity, the deck and the frame list (with
  !> each frame's particle count, if given) to `path` (atomically:
  !> `path`.tmp, then rename).
  !>
  !> With `comm` and `ix` (a block of a decomposed run, every rank of comm
  !> calling this) the ranks write the file together: each its owned nodes
  !> and cells of the node and cell quantities (the block's index ix) into
  !> the whole grid's datasets, rank 0 everything else (which must then be
  !> the whole run's: the caller's concern), except at the locations of
  !> `parts`: their quantities hold this rank's share, which it writes at
  !> the part's runs (`restart_part_t`; the particles as `output_frame`
  !> lays them out). The file is the one a single process writes of the
  !> same state.
  subroutine restart_write(path, reg, deck, frames, times, err, nparts, comm, ix, parts)
    character(len=*), intent(in) :: path
    type(registry_t), intent(in) :: reg
    character(len=*), intent(in) :: deck
    character(len=*), intent(in) :: frames(:)
    real(wp), intent(in) :: times(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: nparts(:)
    type(MPI_Comm), intent(in), optional :: comm
    type(grid_index_t), intent(in), optional :: ix
    type(restart_part_t), intent(in), optional :: parts(:)
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f
    integer, allocatable :: ibuf(:)
    real(wp), allocatable :: rbuf(:)
    integer :: k, rank, stat, q
    logical :: blocks, short
    character(len=:), allocatable :: list

    blocks = present(comm) .and. present(ix)
    rank = 0
    if (blocks) then
      call MPI_Comm_rank(comm, rank)
      ! the buffers of this block's parts, allocated before the collective
      ! writes and agreed on (a rank short of memory in the middle of them
      ! would leave the others waiting)
      allocate(rbuf(buffer_size(K_REAL)), ibuf(buffer_size(K_INT)), stat=stat)
      call MPI_Allreduce(stat /= 0, short, 1, MPI_LOGICAL, MPI_LOR, comm)
      if (short) then
        call error_set(err, 'restart_write', 'out of memory for the parts of '//path//' (on some rank)')
        return
      end if
      call h5_create(f, path//'.tmp', err, checksums=.true., comm=comm, need=file_bytes())
    else
      call h5_create(f, path//'.tmp', err, checksums=.true.)
    end if
    if (allocated(err)) return
    call h5_write_scalar_int(f, 'restart_version', restart_version, err)
    do k = 1, reg%n
      if (allocated(err)) exit
      associate (e => reg%e(k))
        if (blocks .and. (e%location == LOC_NODE .or. e%location == LOC_CELL)) then
          call write_owned(e)
          cycle
        end if
        q = part_of(parts, e%location)
        if (blocks .and. q > 0) then
          call write_runs(e, parts(q))
          cycle
        end if
        select case (e%kind)
        case (K_REAL); call h5_write_real(f, 'state/'//trim(e%name), e%r, e%dims, err)
        case (K_INT); call h5_write_int(f, 'state/'//trim(e%name), e%i, e%dims, err)
        case (K_REAL_SCALAR); call h5_write_scalar_real(f, 'scalars/'//trim(e%name), e%rs, err)
        case (K_INT_SCALAR); call h5_write_scalar_int(f, 'scalars/'//trim(e%name), e%is, err)
        end select
      end associate
    end do
    list = ''
    do k = 1, size(frames)
      list = list//trim(frames(k))//new_line('a')
    end do
    if (.not. allocated(err)) call h5_write_string(f, 'deck', deck, err)
    if (.not. allocated(err)) call h5_write_string(f, 'output/frames', list, err)
    if (.not. allocated(err)) call h5_write_real(f, 'output/times', times, [size(times)], err)
    if (present(nparts) .and. .not. allocated(err)) &
      call h5_write_int(f, 'output/particle_counts', nparts, [size(nparts)], err)
    if (allocated(err)) then
      call h5_close(f, err2)
      if (rank == 0) call remove_file(path//'.tmp')
      return
    end if
    call h5_close(f, err)
    if (allocated(err)) then
      if (rank == 0) call remove_file(path//'.tmp')
      return
    end if
    if (rank == 0) call io_rename(path//'.tmp', path, err)
  contains
    !> The file's size, about: its data (the node and cell quantities the
    !> whole grid's), the deck and the frame list, and 4 KiB per dataset.
    integer(int64) function file_bytes() result(n)
      integer :: q, m
      n = 65536_int64 + len(deck) + 256_int64*size(frames)
      do q = 1, reg%n
        associate (e => reg%e(q))
          m = 1
          if (e%location /= LOC_GLOBAL) m = product(e%dims(1:size(e%dims) - 1))
          select case (e%kind)
          case (K_REAL, K_INT)
            if (part_of(parts, e%location) > 0) then
              n = n + 8_int64*m*(parts(part_of(parts, e%location))%total + 1)
            else if (e%location == LOC_NODE) then
              n = n + 8_int64*m*product(int(ix%gn + 1, int64))
            else if (e%location == LOC_CELL) then
              n = n + 8_int64*m*product(int(ix%gn, int64))
            else if (e%kind == K_REAL) then
              n = n + 8_int64*size(e%r, kind=int64)
            else
              n = n + 4_int64*size(e%i, kind=int64)
            end if
          end select
          n = n + 4096
        end associate
      end do
    end function file_bytes

    !> The largest part of a node or cell quantity of this kind this block
    !> writes (values).
    integer function buffer_size(kind) result(n)
      integer, intent(in) :: kind
      integer :: q
      n = 0
      do q = 1, reg%n
        associate (e => reg%e(q))
          if (e%kind /= kind) cycle
          if (e%location == LOC_NODE) then
            n = max(n, product(e%dims(1:size(e%dims) - 1))*product(ix%nhi - ix%ulo + 1))
          else if (e%location == LOC_CELL) then
            n = max(n, product(e%dims(1:size(e%dims) - 1))*product(ix%chi - ix%clo + 1))
          end if
        end associate
      end do
    end function buffer_size

    !> A node or cell quantity: this block's owned nodes (those it counts,
    !> every node once) or cells, in the whole grid's dataset.
    subroutine write_owned(e)
      type(registry_entry_t), intent(in) :: e
      integer :: lead(size(e%dims) - 1)
      integer :: lo(3), hi(3), grid(3), m, p, i, j, l, q
      logical :: nodes
      nodes = e%location == LOC_NODE
      if (nodes) then
        lo = ix%ulo; hi = ix%nhi; grid = ix%gn + 1
      else
        lo = ix%clo; hi = ix%chi; grid = ix%gn
      end if
      lead = e%dims(1:size(e%dims) - 1)
      m = product(lead)
      p = 0
      do l = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            q = m*(merge(ix%node(i, j, l), ix%cell(i, j, l), nodes) - 1)
            if (e%kind == K_REAL) then
              rbuf(p + 1:p + m) = e%r(q + 1:q + m)
            else
              ibuf(p + 1:p + m) = e%i(q + 1:q + m)
            end if
            p = p + m
          end do
        end do
      end do
      ! the box in the whole grid, 0-based (nodes are numbered from 0, cells from 1)
      hi = hi - lo + 1
      lo = lo + ix%off - merge(0, 1, nodes)
      if (e%kind == K_REAL) then
        call h5_write_part_real(f, 'state/'//trim(e%name), rbuf, [lead, product(grid)], [0*lead, lo], [lead, hi], &
                                err, grid)
      else
        call h5_write_part_int(f, 'state/'//trim(e%name), ibuf, [lead, product(grid)], [0*lead, lo], [lead, hi], &
                               err, grid)
      end if
    end subroutine write_owned

    !> A quantity of part p: this rank's values at their places among the
    !> part's total (`h5_write_part_real`'s runs), or one more (`plus`).
    subroutine write_runs(e, p)
      type(registry_entry_t), intent(in) :: e
      type(restart_part_t), intent(in) :: p
      integer :: lead(size(e%dims) - 1), total
      logical :: plus
      lead = e%dims(1:size(e%dims) - 1)
      plus = e%dims(size(e%dims)) /= sum(p%runs(2, :))
      total = p%total + merge(1, 0, plus)
      if (e%kind == K_REAL .and. plus) then
        call h5_write_part_real(f, 'state/'//trim(e%name), e%r, [lead, total], [0*lead, 0], [lead, sum(p%plus(2, :))], &
                                err, runs=p%plus)
      else if (e%kind == K_REAL) then
        call h5_write_part_real(f, 'state/'//trim(e%name), e%r, [lead, total], [0*lead, 0], e%dims, err, runs=p%runs)
      else if (plus) then
        call h5_write_part_int(f, 'state/'//trim(e%name), e%i, [lead, total], [0*lead, 0], [lead, sum(p%plus(2, :))], &
                               err, runs=p%plus)
      else
        call h5_write_part_int(f, 'state/'//trim(e%name), e%i, [lead, total], [0*lead, 0], e%dims, err, runs=p%runs)
      end if
    end subroutine write_runs
  end subroutine restart_write

  !> Deletes `path` if it exists (a temporary file of a failed dump: it frees
  !> the space on a full disk). Failure to delete is no error.
  subroutine remove_file(path)
    character(len=*), intent(in) :: path
    integer :: u, ios
    open(newunit=u, file=path, status='old', iostat=ios)
    if (ios == 0) close(u, status='delete', iostat=ios)
  end subroutine remove_file

  !> The resolved deck stored in a restart file (and a check of its version).
  subroutine restart_read_deck(path, deck, err)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: deck
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f

    call open_checked(path, f, err)
    if (allocated(err)) return
    call h5_read_string(f, 'deck', deck, err)
    call h5_close(f, err2)
  end subroutine restart_read_deck

  !> One integer scalar registered as `name` (stored as scalars/`name`), read
  !> from restart file `path` (whose version is checked) before a full read:
  !> a size to allocate to before registering.
  subroutine restart_read_int_scalar(path, name, value, err)
    character(len=*), intent(in) :: path, name
    integer, intent(out) :: value
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f

    value = 0
    call open_checked(path, f, err)
    if (allocated(err)) return
    call h5_read_scalar_int(f, 'scalars/'//trim(name), value, err)
    call h5_close(f, err2)
  end subroutine restart_read_int_scalar

  !> The shape of the array registered as `name` (stored as state/`name`) in
  !> restart file `path` (whose version is checked), before a full read.
  subroutine restart_read_dims(path, name, dims, err)
    character(len=*), intent(in) :: path, name
    integer, allocatable, intent(out) :: dims(:)
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f

    call open_checked(path, f, err)
    if (allocated(err)) return
    call h5_read_dims(f, 'state/'//trim(name), dims, err)
    call h5_close(f, err2)
  end subroutine restart_read_dims

  !> Checks, before storage is allocated to a size read from the file, that
  !> the file's arrays agree with it: every array of `reg` that lives at
  !> `location` and has `count_now` entries along its last dimension (plus a
  !> fixed offset, as the n+1 starts of n mixed cells) must be stored with
  !> `count_file` instead. `count_name` names the stored size in messages.
  subroutine restart_check_counts(path, reg, location, count_now, count_file, count_name, err)
    character(len=*), intent(in) :: path
    type(registry_t), intent(in) :: reg
    integer, intent(in) :: location, count_now, count_file
    character(len=*), intent(in) :: count_name
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f
    integer, allocatable :: dims(:)
    integer(int64), allocatable :: want(:)
    integer :: k, r
    character(len=128) :: name

    call open_checked(path, f, err)
    if (allocated(err)) return
    do k = 1, reg%n
      associate (e => reg%e(k))
        if (e%location /= location .or. .not. (e%kind == K_REAL .or. e%kind == K_INT)) cycle
        name = 'state/'//trim(e%name)
        if (.not. h5_exists(f, trim(name))) cycle   ! restart_read names a missing one
        call h5_read_dims(f, trim(name), dims, err)
        if (allocated(err)) exit
        r = size(e%dims)
        want = int(e%dims, int64)
        want(r) = want(r) - count_now + count_file
        if (size(dims) /= r) then
          call error_set(err, 'restart_read', trim(path)//': '//trim(name)//' has the wrong rank')
        else if (any(int(dims, int64) /= want)) then
          call error_set(err, 'restart_read', trim(path)//' is damaged: '//trim(name)//' has shape '// &
                         shape_str(int(dims, int64))//', but '//count_name//' = '//itoa(count_file)//' needs '// &
                         shape_str(want))
        end if
      end associate
      if (allocated(err)) exit
    end do
    call h5_close(f, err2)
  end subroutine restart_check_counts

  !> Reads every registered quantity from `path`, checking each one's shape,
  !> and the frame list (with the frames' particle counts in nparts when
  !> the file has them; unallocated otherwise). Nothing is left half-read
  !> silently: on error the caller must not use the state. With `ix` (a
  !> block of a decomposed run) the node and cell quantities are the block's
  !> box (its owned and ghost nodes and cells) of the whole grid's datasets;
  !> everything else is read whole.
  subroutine restart_read(path, reg, frames, times, err, nparts, ix, later)
    character(len=*), intent(in) :: path
    type(registry_t), intent(inout) :: reg
    character(len=256), allocatable, intent(out) :: frames(:)
    real(wp), allocatable, intent(out) :: times(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable, intent(out), optional :: nparts(:)
    type(grid_index_t), intent(in), optional :: ix
    !> the locations whose arrays are left to the caller (`restart_read_parts`)
    integer, intent(in), optional :: later(:)
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f
    integer :: k, n, p, bad, lo(3), cnt(3), grid(3)
    logical :: box
    integer, allocatable :: dims(:), want(:), ibuf(:)
    real(wp), allocatable :: rbuf(:)
    character(len=:), allocatable :: list
    character(len=128) :: name

    call open_checked(path, f, err)
    if (allocated(err)) return
    do k = 1, reg%n
      associate (e => reg%e(k))
        if (e%kind == K_REAL .or. e%kind == K_INT) then
          name = 'state/'//trim(e%name)
        else
          name = 'scalars/'//trim(e%name)
        end if
        if (present(later) .and. (e%kind == K_REAL .or. e%kind == K_INT)) then
          if (any(later == e%location)) cycle
        end if
        if (.not. h5_exists(f, trim(name))) then
          ! an optional quantity keeps the value the deck gave it
          if (e%mandatory) call error_set(err, 'restart_read', trim(path)//' has no '//trim(name)// &
                                          ' ('//location_name(e%location)//' quantity this run needs)')
          if (allocated(err)) exit
          cycle
        end if
        select case (e%kind)
        case (K_REAL, K_INT)
          call h5_read_dims(f, trim(name), dims, err)
          if (allocated(err)) exit
          ! a block's nodes or cells: its stored box of the whole grid's
          box = present(ix) .and. (e%location == LOC_NODE .or. e%location == LOC_CELL)
          want = e%dims
          if (box) then
            if (e%location == LOC_NODE) then
              grid = ix%gn + 1; lo = ix%slo - 1 + ix%off; cnt = ix%shi - ix%slo + 2
            else
              grid = ix%gn; lo = ix%slo - 1 + ix%off; cnt = ix%shi - ix%slo + 1
            end if
            want(size(want)) = product(grid)
          end if
          if (size(dims) /= size(want)) then
            call error_set(err, 'restart_read', trim(path)//': '//trim(name)//' has the wrong rank')
            exit
          else if (any(dims /= want)) then
            call error_set(err, 'restart_read', trim(path)//': '//trim(name)//' has shape '// &
                           shape_str(int(dims, int64))//', this run expects '//shape_str(int(want, int64))// &
                           where_str(e%location))
            exit
          end if
          if (box) then
            if (e%kind == K_REAL) then
              call h5_read_real(f, trim(name), rbuf, err, grid, [0*want(:size(want) - 1), lo], &
                                [want(:size(want) - 1), cnt])
            else
              call h5_read_int(f, trim(name), ibuf, err, grid, [0*want(:size(want) - 1), lo], &
                               [want(:size(want) - 1), cnt])
            end if
          else if (e%kind == K_REAL) then
            call h5_read_real(f, trim(name), rbuf, err)
          else
            call h5_read_int(f, trim(name), ibuf, err)
          end if
          if (e%kind == K_REAL) then
            if (.not. allocated(err) .and. e%units /= 'bits') call check_values(e, rbuf)
            if (.not. allocated(err)) e%r = rbuf
          else if (.not. allocated(err)) then
            e%i = ibuf
          end if
        case (K_REAL_SCALAR)
          call h5_read_scalar_real(f, trim(name), e%rs, err)
          if (.not. allocated(err) .and. e%units /= 'bits') then
            if (.not. finite_bits(e%rs)) call error_set(err, 'restart_read', trim(path)//' is damaged: '// &
              trim(name)//' is '//nonfinite_name(e%rs))
          end if
        case (K_INT_SCALAR)
          call h5_read_scalar_int(f, trim(name), e%is, err)
        end select
      end associate
      if (allocated(err)) exit
    end do
    ! the frame list: its times only once their count matches the names
    if (.not. allocated(err)) call h5_read_string(f, 'output/frames', list, err)
    if (.not. allocated(err)) call h5_read_dims(f, 'output/times', dims, err)
    if (.not. allocated(err)) then
      n = count_lines(list)
      if (size(dims) /= 1) then
        call error_set(err, 'restart_read', trim(path)//' is damaged: output/times is not a list')
      else if (dims(1) /= n) then
        call error_set(err, 'restart_read', trim(path)//' is damaged: output/times has '//itoa(dims(1))// &
                       ' entries, output/frames names '//itoa(n)//' frames')
      end if
    end if
    if (.not. allocated(err)) call h5_read_real(f, 'output/times', times, err)
    if (.not. allocated(err)) then
      bad = findloc(finite_bits(times), .false., 1)
      if (bad > 0) call error_set(err, 'restart_read', trim(path)//' is damaged: output/times has '// &
                                  nonfinite_name(times(bad))//' at entry '//itoa(bad))
    end if
    if (present(nparts) .and. .not. allocated(err)) then
      if (h5_exists(f, 'output/particle_counts')) then
        call h5_read_int(f, 'output/particle_counts', nparts, err)
        if (.not. allocated(err)) then
          if (size(nparts) /= size(times) .or. any(nparts < 0)) call error_set(err, 'restart_read', trim(path)// &
            ' is damaged: output/particle_counts does not match the frame list')
        end if
      end if
    end if
    call h5_close(f, err2)
    if (allocated(err)) return
    n = size(times)
    allocate(frames(n), stat=p, errmsg=name)
    if (p /= 0) then
      call error_set(err, 'restart_read', error_no_memory('the frame list'))
      return
    end if
    do k = 1, n
      p = index(list, new_line('a'))
      if (p == 0) then
        call error_set(err, 'restart_read', trim(path)//': the frame list is damaged')
        return
      end if
      frames(k) = list(1:p - 1)
      list = list(p + 1:)
    end do
  contains

    !> Values finite, held to the deck's magnitude rule (below 1e30, or the
    !> largest real, which marks "never"), and in the range the quantity's
    !> owner registered (`lower`); the message names the first entry that is
    !> not by its place in the whole grid's dataset.
    subroutine check_values(e, v)
      type(registry_entry_t), intent(in) :: e
      real(wp), intent(in) :: v(:)
      integer :: bad
      character(len=:), allocatable :: what, rule
      call values_bad(e, v, bad, what, rule)
      if (bad > 0) call error_set(err, 'restart_read', trim(path)//' is damaged: '//trim(name)//what// &
                                  ' at '//where(bad, e)//rule)
    end subroutine check_values

    !> "entry k (node n)" of the value at v(j): in a block's box, its place
    !> in the whole grid's dataset.
    function where(j, e) result(text)
      integer, intent(in) :: j
      type(registry_entry_t), intent(in) :: e
      character(len=:), allocatable :: text
      integer :: inner, m, q, ijk(3)
      if (.not. box) then
        text = entry_str(j, e%dims, e%location)
        return
      end if
      inner = max(1, product(want(1:size(want) - 1)))
      m = mod(j - 1, inner)
      q = (j - 1)/inner
      ijk = lo + [mod(q, cnt(1)), mod(q/cnt(1), cnt(2)), q/(cnt(1)*cnt(2))]
      text = entry_str(m + 1 + inner*(ijk(1) + grid(1)*(ijk(2) + grid(2)*ijk(3))), want, e%location)
    end function where

  end subroutine restart_read

  !> The first of values v of entry e that is not finite, not below the
  !> deck's magnitude rule (1e30, but for the largest real, which marks
  !> "never") or out of the range its owner registered (`lower`): bad its
  !> place (0: none), what and rule its description before and after the
  !> caller's "at ...".
  subroutine values_bad(e, v, bad, what, rule)
    type(registry_entry_t), intent(in) :: e
    real(wp), intent(in) :: v(:)
    integer, intent(out) :: bad
    character(len=:), allocatable, intent(out) :: what, rule
    character(len=*), parameter :: rules(2) = [character(len=15) :: ' (must be > 0)', ' (must be >= 0)']
    rule = ''
    bad = findloc(finite_bits(v), .false., 1)
    if (bad > 0) then
      what = ' has '//nonfinite_name(v(bad))
      return
    end if
    bad = findloc(abs(v) < too_big .or. abs(v) >= huge(1.0_wp), .false., 1)
    if (bad > 0) then
      rule = ' (magnitudes of 1e30 or more are refused)'
    else
      if (e%lower == LOWER_POSITIVE) bad = findloc(v > 0.0_wp, .false., 1)
      if (e%lower == LOWER_NONNEGATIVE) bad = findloc(v >= 0.0_wp, .false., 1)
      if (bad > 0) rule = trim(rules(e%lower))
    end if
    what = ''
    if (bad > 0) what = ' = '//rtoa(v(bad))
  end subroutine values_bad

  !> The arrays `restart_read` left for later at the locations of parts
  !> (a block's mixed cells and slots): each read at the runs of its part
  !> (`restart_part_t`) of a dataset of the part's total entries into its
  !> registered storage, which holds the runs' values; an array with one
  !> entry more (the mixed cells' starts) is the caller's
  !> (`restart_read_int_runs`). Shapes and values are checked as
  !> `restart_read` checks them; a message names an entry by its place in
  !> the file.
  subroutine restart_read_parts(path, reg, parts, err)
    character(len=*), intent(in) :: path
    type(registry_t), intent(inout) :: reg
    type(restart_part_t), intent(in) :: parts(:)
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f
    integer, allocatable :: dims(:), want(:), ibuf(:)
    real(wp), allocatable :: rbuf(:)
    character(len=:), allocatable :: what, rule
    character(len=128) :: name
    integer :: k, q, bad

    call open_checked(path, f, err)
    if (allocated(err)) return
    do k = 1, reg%n
      associate (e => reg%e(k))
        q = part_of(parts, e%location)
        if (q == 0 .or. .not. (e%kind == K_REAL .or. e%kind == K_INT)) cycle
        if (e%dims(size(e%dims)) /= sum(parts(q)%runs(2, :))) cycle
        name = 'state/'//trim(e%name)
        if (.not. h5_exists(f, trim(name))) then
          if (e%mandatory) call error_set(err, 'restart_read', trim(path)//' has no '//trim(name)// &
                                          ' ('//location_name(e%location)//' quantity this run needs)')
          if (allocated(err)) exit
          cycle
        end if
        call h5_read_dims(f, trim(name), dims, err)
        if (allocated(err)) exit
        want = e%dims
        want(size(want)) = parts(q)%total
        if (size(dims) /= size(want)) then
          call error_set(err, 'restart_read', trim(path)//': '//trim(name)//' has the wrong rank')
        else if (any(dims /= want)) then
          call error_set(err, 'restart_read', trim(path)//': '//trim(name)//' has shape '// &
                         shape_str(int(dims, int64))//', this run expects '//shape_str(int(want, int64))// &
                         where_str(e%location))
        end if
        if (allocated(err)) exit
        if (e%kind == K_REAL) then
          call h5_read_real(f, trim(name), rbuf, err, runs=parts(q)%runs)
          if (.not. allocated(err) .and. e%units /= 'bits') then
            call values_bad(e, rbuf, bad, what, rule)
            if (bad > 0) call error_set(err, 'restart_read', trim(path)//' is damaged: '//trim(name)//what// &
                                        ' at '//entry_str(in_file(bad, product(want(:size(want) - 1)), &
                                        parts(q)%runs), want, e%location)//rule)
          end if
          if (.not. allocated(err)) e%r = rbuf
        else
          call h5_read_int(f, trim(name), ibuf, err, runs=parts(q)%runs)
          if (.not. allocated(err)) e%i = ibuf
        end if
      end associate
      if (allocated(err)) exit
    end do
    call h5_close(f, err2)
  end subroutine restart_read_parts

  !> runs: the runs (`restart_part_t`) of the entries of the integer list
  !> state/`name` of restart file `path` (cells of a whole grid of gn
  !> cells: the particles' hosts) whose cell lies in the box of cells
  !> lo..hi, read in pieces of at most `piece` entries (no whole list is
  !> held); own: how many lie in the box own_lo..own_hi within it. A cell
  !> outside the grid is damage (the message names the first).
  subroutine restart_cell_runs(path, name, gn, lo, hi, own_lo, own_hi, runs, own, err)
    character(len=*), intent(in) :: path, name
    integer, intent(in) :: gn(3), lo(3), hi(3), own_lo(3), own_hi(3)
    integer, allocatable, intent(out) :: runs(:, :)
    integer, intent(out) :: own
    type(error_t), allocatable, intent(inout) :: err
    integer, parameter :: piece = 2**20
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f
    integer, allocatable :: dims(:), buf(:), at(:)
    integer :: n, s, k, c, m, ijk(3), stat
    own = 0
    call open_checked(path, f, err)
    if (allocated(err)) return
    call h5_read_dims(f, 'state/'//name, dims, err)
    if (.not. allocated(err)) then
      if (size(dims) /= 1) call error_set(err, 'restart_read', trim(path)//': state/'//name//' has the wrong rank')
    end if
    m = 0
    allocate(at(0), stat=stat)
    s = 0
    do while (.not. allocated(err))
      if (s >= dims(1)) exit
      n = min(piece, dims(1) - s)
      call h5_read_int(f, 'state/'//name, buf, err, start=[s], count=[n])
      if (allocated(err)) exit
      do k = 1, n
        c = buf(k)
        if (c < 1 .or. c > product(gn)) then
          call error_set(err, 'restart_read', trim(path)//' is damaged: state/'//name//' = '//itoa(c)// &
                         ' at particle '//itoa(s + k)//' (the grid has cells 1..'//itoa(product(gn))//')')
          exit
        end if
        ijk = [mod(c - 1, gn(1)) + 1, mod((c - 1)/gn(1), gn(2)) + 1, (c - 1)/(gn(1)*gn(2)) + 1]
        if (any(ijk < lo .or. ijk > hi)) cycle
        if (all(ijk >= own_lo .and. ijk <= own_hi)) own = own + 1
        if (m == size(at)) at = [at, spread(0, 1, max(m, 64))]
        m = m + 1
        at(m) = s + k - 1
      end do
      s = s + n
    end do
    call h5_close(f, err2)
    if (allocated(err)) return
    call sorted_runs(at(:m), runs, stat)
    if (stat /= 0) call error_set(err, 'restart_read', error_no_memory('the particles'' places in '//trim(path)))
  end subroutine restart_cell_runs

  !> values: the integer array `name` (one-dimensional, total entries in
  !> the file) at the runs given (`restart_part_t`), from restart file
  !> `path` (whose version is checked).
  subroutine restart_read_int_runs(path, name, total, runs, values, err)
    character(len=*), intent(in) :: path, name
    integer, intent(in) :: total, runs(:, :)
    integer, allocatable, intent(out) :: values(:)
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: err2
    type(h5_file_t) :: f
    integer, allocatable :: dims(:)
    call open_checked(path, f, err)
    if (allocated(err)) return
    call h5_read_dims(f, 'state/'//name, dims, err)
    if (.not. allocated(err)) then
      if (size(dims) /= 1) then
        call error_set(err, 'restart_read', trim(path)//': state/'//name//' has the wrong rank')
      else if (dims(1) /= total) then
        call error_set(err, 'restart_read', trim(path)//': state/'//name//' has '//itoa(dims(1))// &
                       ' entries, this run expects '//itoa(total))
      end if
    end if
    if (.not. allocated(err)) call h5_read_int(f, 'state/'//name, values, err, runs=runs)
    call h5_close(f, err2)
  end subroutine restart_read_int_runs

  !> The place in the file (1-based, flattened) of the j-th of the values
  !> read at runs, inner values to an entry.
  pure integer function in_file(j, inner, runs) result(at)
    integer, intent(in) :: j, inner, runs(:, :)
    integer :: q, r
    q = (j - 1)/inner
    do r = 1, size(runs, 2)
      if (q < runs(2, r)) exit
      q = q - runs(2, r)
    end do
    at = inner*(runs(1, r) + q) + mod(j - 1, inner) + 1
  end function in_file

  !> The part of parts (absent: none) at location loc, 0 for none.
  pure integer function part_of(parts, loc) result(q)
    type(restart_part_t), intent(in), optional :: parts(:)
    integer, intent(in) :: loc
    q = 0
    if (present(parts)) q = findloc(parts%location, loc, 1)
  end function part_of

  !> Opens a restart file and checks that it is one, of this version.
  subroutine open_checked(path, f, err)
    character(len=*), intent(in) :: path
    type(h5_file_t), intent(inout) :: f
    type(error_t), allocatable, intent(inout) :: err
    type(error_t), allocatable :: err2
    integer :: version
    character(len=16) :: buf, want

    call h5_open_read(f, path, err)
    if (allocated(err)) then
      err%msg = 'cannot read restart file: '//err%msg
      return
    end if
    if (.not. h5_exists(f, 'restart_version')) then
      call error_set(err, 'restart', trim(path)//' is not a restart file (no restart_version)')
    else
      call h5_read_scalar_int(f, 'restart_version', version, err)
      if (.not. allocated(err) .and. version /= restart_version) then
        write(buf, '(i0)') version
        write(want, '(i0)') restart_version
        call error_set(err, 'restart', trim(path)//' has restart format version '//trim(buf)// &
                       '; this program reads version '//trim(want))
      end if
    end if
    if (allocated(err)) call h5_close(f, err2)
  end subroutine open_checked

  !> Number of newline-terminated lines in `text`.
  pure integer function count_lines(text) result(n)
    character(len=*), intent(in) :: text
    integer :: k
    n = 0
    do k = 1, len(text)
      if (text(k:k) == new_line('a')) n = n + 1
    end do
  end function count_lines

  !> True unless `x` is a NaN or an infinity, decided on its bits, so that a
  !> signalling NaN read from a damaged file cannot trap (Debug build's FPE
  !> traps).
  elemental logical function finite_bits(x)
    real(wp), intent(in) :: x
    integer(int64), parameter :: expo = int(z'7FF', int64)
    finite_bits = iand(shiftr(transfer(x, 0_int64), 52), expo) /= expo
  end function finite_bits

  !> 'NaN', '+Infinity' or '-Infinity' for a value that is not finite (from
  !> its bits, no floating-point operation).
  function nonfinite_name(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    integer(int64) :: b
    b = transfer(x, 0_int64)
    if (iand(b, 2_int64**52 - 1) /= 0) then
      s = 'NaN'
    else if (b < 0) then
      s = '-Infinity'
    else
      s = '+Infinity'
    end if
  end function nonfinite_name

  !> "entry k" of a flattened array, with the grid entity it belongs to.
  function entry_str(k, dims, loc) result(s)
    integer, intent(in) :: k, dims(:), loc
    character(len=:), allocatable :: s
    integer :: inner
    s = 'entry '//itoa(k)
    if (loc == LOC_GLOBAL .or. size(dims) < 1) return
    inner = max(1, product(dims(1:size(dims) - 1)))
    s = s//' ('//location_name(loc)//' '//itoa((k - 1)/inner + 1)//')'
  end function entry_str

  !> " (one per <location>)" for an array that lives on grid entities.
  function where_str(loc) result(s)
    integer, intent(in) :: loc
    character(len=:), allocatable :: s
    s = ''
    if (loc /= LOC_GLOBAL) s = ' (last dimension: one per '//location_name(loc)//')'
  end function where_str

  !> "(n1,n2,...)" for a shape (64-bit, as the counts a file may claim).
  function shape_str(d) result(s)
    integer(int64), intent(in) :: d(:)
    character(len=:), allocatable :: s
    character(len=24) :: buf
    integer :: k
    s = '('
    do k = 1, size(d)
      write(buf, '(i0)') d(k)
      s = s//trim(buf)
      if (k < size(d)) s = s//','
    end do
    s = s//')'
  end function shape_str
end module io_restart
