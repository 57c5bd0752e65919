!> Unit test of io_restart: a registry round trip (bit for bit), and storage
!> whose size changed between the writing run and the reading one (mixed
!> cells after a remap): the sizes are read from the file first, the storage
!> is allocated to them, the registry is cleared and filled again, and the
!> full read then restores every value. Zero-size arrays (no mixed cells)
!> must survive the trip too, and a reader must refuse a file whose arrays do
!> not match what it registered.
!> Usage: test_io_restart   (files are written in the working directory)
program test_io_restart
  use, intrinsic :: iso_fortran_env, only: int64
  use base_kinds, only: wp
  use base_errors, only: error_t
  use io_hdf5, only: h5_file_t, hdf5_start, h5_create, h5_write_scalar_int, h5_close
  use base_registry, only: registry_t, LOC_MIXED_CELL, LOC_MIXED_SLOT
  use io_restart, only: restart_write, restart_read, restart_read_int_scalar, &
                        restart_read_dims
  use test_assert, only: check, check_summary
  implicit none

  character(len=*), parameter :: path = 'test_io_restart_a.h5', path0 = 'test_io_restart_zero.h5', &
                                 foreign = 'test_io_restart_foreign.h5'
  character(len=*), parameter :: deck = '&run t_end = 1 /'//new_line('a')
  type(error_t), allocatable :: err

  call hdf5_start(err)
  call check(.not. allocated(err), 'hdf5_start')
  call round_trip(7, 16, path)
  call round_trip(0, 0, path0)
  call refusals()
  call check_summary('test_io_restart')

contains

  !> Fills the "mixed cells" of a writer with n cells and nslot slots with
  !> distinct bit patterns, dumps them, then reads them into a reader that
  !> starts with other sizes.
  subroutine round_trip(n, nslot, file)
    integer, intent(in) :: n, nslot
    character(len=*), intent(in) :: file
    ! the writer's storage (targets: the registry points at it)
    integer, target :: wn, wnslot
    integer, allocatable, target :: wcell(:), wmat(:)
    real(wp), allocatable, target :: wvf(:), wxi(:, :)
    real(wp), target :: wt
    ! the reader's storage
    integer, target :: rn, rnslot
    integer, allocatable, target :: rcell(:), rmat(:)
    real(wp), allocatable, target :: rvf(:), rxi(:, :)
    real(wp), target :: rt
    integer, allocatable :: dims(:)
    real(wp), allocatable :: times(:)
    character(len=256), allocatable :: frames(:)
    type(registry_t) :: wreg, rreg
    integer :: k, n_file, nslot_file
    character(len=32) :: tag

    write(tag, '(a,i0,a,i0,a)') ' (n = ', n, ', nslot = ', nslot, ')'
    wn = n
    wnslot = nslot
    allocate(wcell(n), wmat(nslot), wvf(nslot), wxi(3, nslot))
    do k = 1, n
      wcell(k) = 1000 + 37*k
    end do
    do k = 1, nslot
      wmat(k) = mod(k, 3) + 1
      wvf(k) = real(k, wp)/7.0_wp - 1.0e-17_wp
      wxi(:, k) = [sqrt(real(k, wp)), -1.0_wp/real(k, wp), real(k, wp)*1.0e-300_wp]
    end do
    wt = acos(-1.0_wp)/3.0_wp
    call register(wreg, wn, wnslot, wcell, wmat, wvf, wxi, wt)
    call restart_write(file, wreg, deck, [character(len=8) :: 'f_00000', 'f_00001'], [0.0_wp, 0.5_wp], err)
    call check(.not. allocated(err), 'restart_write'//trim(tag))
    if (allocated(err)) then
      write(*, '(a)') err%msg
      deallocate(err)
      return
    end if

    ! the reader was built for other sizes (as from the deck, before a remap)
    rn = 3
    rnslot = 6
    allocate(rcell(rn), rmat(rnslot), rvf(rnslot), rxi(3, rnslot))
    call register(rreg, rn, rnslot, rcell, rmat, rvf, rxi, rt)
    call check(rreg%n == 7, 'registry holds 7 entries'//trim(tag))
    ! the sizes first
    call restart_read_int_scalar(file, 'mixed_n', n_file, err)
    call check(.not. allocated(err), 'restart_read_int_scalar mixed_n'//trim(tag))
    call restart_read_int_scalar(file, 'mixed_nslot', nslot_file, err)
    call check(.not. allocated(err), 'restart_read_int_scalar mixed_nslot'//trim(tag))
    call check(n_file == n .and. nslot_file == nslot, 'sizes read back'//trim(tag))
    call restart_read_dims(file, 'mixed_centroid', dims, err)
    call check(.not. allocated(err), 'restart_read_dims'//trim(tag))
    if (allocated(dims)) call check(size(dims) == 2, 'rank of mixed_centroid'//trim(tag))
    if (allocated(dims)) call check(all(dims == [3, nslot]), 'dims of mixed_centroid'//trim(tag))
    if (allocated(err)) deallocate(err)
    ! reallocate to the stored sizes, then register afresh
    deallocate(rcell, rmat, rvf, rxi)
    allocate(rcell(n_file), rmat(nslot_file), rvf(nslot_file), rxi(3, nslot_file))
    rcell = -1
    rmat = -1
    rvf = -1.0_wp
    rxi = -1.0_wp
    call rreg%clear()
    call check(rreg%n == 0, 'clear empties the registry'//trim(tag))
    call register(rreg, rn, rnslot, rcell, rmat, rvf, rxi, rt)
    call check(rreg%n == 7, 'registry holds 7 entries again'//trim(tag))
    call restart_read(file, rreg, frames, times, err)
    call check(.not. allocated(err), 'restart_read'//trim(tag))
    if (allocated(err)) then
      write(*, '(a)') err%msg
      deallocate(err)
      return
    end if
    call check(rn == n .and. rnslot == nslot, 'registered sizes restored'//trim(tag))
    call check(all(rcell == wcell), 'cells bit for bit'//trim(tag))
    call check(all(rmat == wmat), 'materials bit for bit'//trim(tag))
    call check(same(rvf, wvf), 'volume fractions bit for bit'//trim(tag))
    call check(same(reshape(rxi, [size(rxi)]), reshape(wxi, [size(wxi)])), 'centroids bit for bit'//trim(tag))
    call check(same([rt], [wt]), 'real scalar bit for bit'//trim(tag))
    call check(size(frames) == 2 .and. size(times) == 2, 'frame list'//trim(tag))
    if (size(frames) == 2) call check(frames(2) == 'f_00001', 'frame names'//trim(tag))
  end subroutine round_trip

  !> The registration a package would make: sizes as scalars, then arrays.
  subroutine register(reg, n, nslot, cell, mat, vf, xi, t)
    type(registry_t), intent(inout) :: reg
    integer, intent(inout), target :: n, nslot
    integer, intent(inout), target, contiguous :: cell(:), mat(:)
    real(wp), intent(inout), target, contiguous :: vf(:), xi(:, :)
    real(wp), intent(inout), target :: t
    call reg%add('mixed_n', '1', n)
    call reg%add('mixed_nslot', '1', nslot)
    call reg%add('mixed_cell', '1', LOC_MIXED_CELL, cell)
    call reg%add('mixed_material', '1', LOC_MIXED_SLOT, mat)
    call reg%add('mixed_volume_fraction', '1', LOC_MIXED_SLOT, vf)
    call reg%add('mixed_centroid', 'natural coordinates', LOC_MIXED_SLOT, xi)
    call reg%add('time', 'time', t)
  end subroutine register

  !> A reader whose storage does not match the file is refused (naming the
  !> field and both shapes), and a file that is no restart gives no sizes.
  subroutine refusals()
    type(registry_t) :: reg
    integer, target :: n, nslot
    integer :: value
    integer, allocatable, target :: cell(:), mat(:)
    real(wp), allocatable, target :: vf(:), xi(:, :)
    real(wp), allocatable :: times(:)
    real(wp), target :: t, extra
    character(len=256), allocatable :: frames(:)
    type(h5_file_t) :: f

    n = 2
    nslot = 4
    allocate(cell(n), mat(nslot), vf(nslot), xi(3, nslot))
    call register(reg, n, nslot, cell, mat, vf, xi, t)
    call restart_read(path, reg, frames, times, err)
    call check(allocated(err), 'reading 7 mixed cells into storage for 2 is refused')
    if (allocated(err)) then
      call check(index(err%msg, 'state/mixed_cell has shape (7), this run expects (2)') > 0, &
                 'the refusal names the field and both shapes: '//err%msg)
      deallocate(err)
    end if
    call h5_create(f, foreign, err)
    if (.not. allocated(err)) call h5_write_scalar_int(f, 'scalars/mixed_n', 5, err)
    if (.not. allocated(err)) call h5_close(f, err)
    call check(.not. allocated(err), 'writing a foreign file')
    if (allocated(err)) deallocate(err)
    call restart_read_int_scalar(foreign, 'mixed_n', value, err)
    call check(allocated(err), 'a file without restart_version gives no sizes')
    if (allocated(err)) then
      call check(index(err%msg, 'is not a restart file') > 0, 'the refusal says why: '//err%msg)
      deallocate(err)
    end if
    call restart_read_int_scalar(path, 'no_such_scalar', value, err)
    call check(allocated(err), 'a missing scalar is an error')
    if (allocated(err)) deallocate(err)
    ! a quantity the file lacks: refused if mandatory, kept if optional
    call reg%clear()
    extra = 42.0_wp
    call reg%add('not_in_file', 'time', extra)
    call restart_read(path, reg, frames, times, err)
    call check(allocated(err), 'a mandatory quantity missing from the file is refused')
    if (allocated(err)) then
      call check(index(err%msg, 'has no scalars/not_in_file') > 0, 'the refusal names it: '//err%msg)
      deallocate(err)
    end if
    call reg%clear()
    call reg%add('not_in_file', 'time', extra, mandatory=.false.)
    call restart_read(path, reg, frames, times, err)
    call check(.not. allocated(err), 'an optional quantity missing from the file is no error')
    call check(same([extra], [42.0_wp]), 'an optional quantity missing from the file keeps its value')
    if (allocated(err)) deallocate(err)
  end subroutine refusals

  !> Bitwise equality of two real arrays.
  logical function same(a, b)
    real(wp), intent(in) :: a(:), b(:)
    same = size(a) == size(b)
    if (same) same = all(transfer(a, 0_int64, size(a)) == transfer(b, 0_int64, size(b)))
  end function same
end program test_io_restart
