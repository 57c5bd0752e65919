!> Round-trip test of io_hdf5 and io_xdmf.
!> Usage: test_io_hdf5 [--keep]   (files are written in the working directory;
!> --keep leaves them there for inspection, e.g. with h5dump).
program test_io_hdf5
  use, intrinsic :: iso_fortran_env, only: int64, int32, real32
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf, ieee_negative_inf, ieee_is_nan, &
                                           ieee_quiet_nan
  use base_kinds, only: wp
  use base_errors, only: error_t
  use io_hdf5, only: h5_file_t, hdf5_start, hdf5_stop, h5_create, h5_open_read, h5_close, &
       h5_exists, h5_write_real, h5_write_int, h5_write_scalar_real, h5_write_scalar_int, &
       h5_write_string, h5_read_dims, h5_read_real, h5_read_int, h5_read_scalar_real, &
       h5_read_scalar_int, h5_read_string
  use io_xdmf, only: xdmf_write_series
  implicit none

  character(len=*), parameter :: h5name = 'test_io_hdf5_data.h5'
  character(len=*), parameter :: txtname = 'test_io_hdf5_not_h5.txt'
  character(len=*), parameter :: xdmfname = 'test_io_hdf5_series.xdmf'
  character(len=*), parameter :: smallname = 'test_io_hdf5_single.h5'
  character(len=*), parameter :: frame_names(2) = [character(len=24) :: &
       'test_io_hdf5_frame_0.h5', 'test_io_hdf5_frame_1.h5']
  integer, parameter :: ni = 2, nj = 3, nk = 4

  type(error_t), allocatable :: err
  type(h5_file_t) :: file
  real(wp) :: a4(3, 4, 5, 6), rscal, rback, x(3, ni + 1, nj + 1, nk + 1), rho(ni, nj, nk)
  real(wp) :: zr(3, 0)
  integer :: zi(0)
  integer :: i3(2, 3, 4), iscal, iback, i, j, k, l, unit, f
  integer, allocatable :: dims(:), iflat(:)
  real(wp), allocatable :: rflat(:)
  character(len=:), allocatable :: text, textback
  character(len=8) :: arg
  logical :: keep, exists
  ! float32 storage: FLT_MAX, half its last place (2^103), the smallest
  ! float32 subnormal 2^-149
  real(wp), parameter :: flt_max = real(huge(1.0_real32), wp), half_ulp = 2.0_wp**103, sub = 2.0_wp**(-149)
  real(wp) :: edge(9)
  real(real32) :: want(9)

  call get_command_argument(1, arg)
  keep = arg == '--keep'

  ! ---- data with non-trivial bit patterns
  do l = 1, 6
    do k = 1, 5
      do j = 1, 4
        do i = 1, 3
          a4(i, j, k, l) = real(i + 10 * j + 100 * k + 1000 * l, wp) / 7.0_wp - 0.1_wp
        end do
      end do
    end do
  end do
  do k = 1, 4
    do j = 1, 3
      do i = 1, 2
        i3(i, j, k) = -(i + 10 * j + 100 * k) * 12345
      end do
    end do
  end do
  rscal = acos(-1.0_wp) * 1.0e-300_wp
  iscal = -2147483647
  text = 'line one'//new_line('a')//'  line two with "quotes" & <tags>'//new_line('a')
  do i = 1, 400
    text = text//'deck line '//repeat('x', 40)//new_line('a')
  end do
  text = text//'last line, trailing blanks   '

  ! ---- write
  call hdf5_start(err)
  call check('hdf5_start')
  call hdf5_start(err)
  call check('hdf5_start (second call)')
  call h5_create(file, h5name, err)
  call check('h5_create')
  call h5_write_real(file, 'a4', a4, shape(a4), err)
  call check('h5_write_real')
  call h5_write_int(file, 'grp/sub/i3', i3, shape(i3), err)
  call check('h5_write_int')
  call h5_write_scalar_real(file, 'rscal', rscal, err)
  call check('h5_write_scalar_real')
  call h5_write_scalar_int(file, 'grp/iscal', iscal, err)
  call check('h5_write_scalar_int')
  call h5_write_string(file, 'deck', text, err)
  call check('h5_write_string')
  call h5_write_string(file, 'empty', '', err)
  call check('h5_write_string (empty)')
  ! zero-size arrays (a scene without mixed cells writes them in restarts)
  call h5_write_real(file, 'zero/r', zr, shape(zr), err)
  call check('h5_write_real (zero size)')
  call h5_write_int(file, 'zero/i', zi, shape(zi), err)
  call check('h5_write_int (zero size)')
  call h5_write_real(file, 'a4', a4, shape(a4), err)
  if (.not. allocated(err)) call fail('writing an existing dataset gave no error')
  deallocate(err)
  call h5_close(file, err)
  call check('h5_close')

  ! ---- read back
  call h5_open_read(file, h5name, err)
  call check('h5_open_read')
  if (.not. h5_exists(file, 'grp/sub/i3')) call fail('h5_exists false for grp/sub/i3')
  if (h5_exists(file, 'nope/i3')) call fail('h5_exists true for nope/i3')
  call h5_read_dims(file, 'a4', dims, err)
  call check('h5_read_dims')
  if (size(dims) /= 4) call fail('rank of a4 is not 4')
  if (any(dims /= [3, 4, 5, 6])) call fail('dims of a4 are not [3,4,5,6]')
  call h5_read_real(file, 'a4', rflat, err)
  call check('h5_read_real')
  if (size(rflat) /= size(a4)) call fail('size of a4 read back differs')
  if (any(transfer(rflat, 0_int64, size(rflat)) /= transfer(a4, 0_int64, size(a4)))) &
       call fail('a4 values differ')
  call h5_read_dims(file, 'grp/sub/i3', dims, err)
  call check('h5_read_dims i3')
  if (size(dims) /= 3) call fail('rank of i3 is not 3')
  if (any(dims /= [2, 3, 4])) call fail('dims of i3 are not [2,3,4]')
  call h5_read_int(file, 'grp/sub/i3', iflat, err)
  call check('h5_read_int')
  if (size(iflat) /= size(i3)) call fail('size of i3 read back differs')
  if (any(iflat /= reshape(i3, [size(i3)]))) call fail('i3 values differ')
  call h5_read_scalar_real(file, 'rscal', rback, err)
  call check('h5_read_scalar_real')
  if (transfer(rback, 0_int64) /= transfer(rscal, 0_int64)) call fail('rscal differs')
  call h5_read_scalar_int(file, 'grp/iscal', iback, err)
  call check('h5_read_scalar_int')
  if (iback /= iscal) call fail('iscal differs')
  call h5_read_string(file, 'deck', textback, err)
  call check('h5_read_string')
  if (len(textback) /= len(text)) call fail('string length differs')
  if (textback /= text) call fail('string differs')
  call h5_read_string(file, 'empty', textback, err)
  call check('h5_read_string (empty)')
  if (len(textback) /= 0) call fail('empty string not empty')
  call h5_read_dims(file, 'zero/r', dims, err)
  call check('h5_read_dims (zero size)')
  if (size(dims) /= 2) call fail('rank of zero/r is not 2')
  if (any(dims /= [3, 0])) call fail('dims of zero/r are not [3,0]')
  call h5_read_real(file, 'zero/r', rflat, err)
  call check('h5_read_real (zero size)')
  if (size(rflat) /= 0) call fail('zero/r read back is not empty')
  call h5_read_int(file, 'zero/i', iflat, err)
  call check('h5_read_int (zero size)')
  if (size(iflat) /= 0) call fail('zero/i read back is not empty')

  ! ---- errors
  call h5_read_real(file, 'missing', rflat, err)
  if (.not. allocated(err)) call fail('reading a missing dataset gave no error')
  deallocate(err)
  call h5_read_real(file, 'nogroup/missing', rflat, err)
  if (.not. allocated(err)) call fail('reading a dataset in a missing group gave no error')
  deallocate(err)
  call h5_read_int(file, 'a4', iflat, err)
  if (.not. allocated(err)) call fail('reading reals as integers gave no error')
  deallocate(err)
  call h5_close(file, err)
  call check('h5_close (read)')

  open(newunit=unit, file=txtname, status='replace', action='write')
  write(unit, '(a)') 'this is not an HDF5 file'
  close(unit)
  call h5_open_read(file, txtname, err)
  if (.not. allocated(err)) call fail('opening a text file gave no error')
  deallocate(err)
  call h5_open_read(file, 'test_io_hdf5_does_not_exist.h5', err)
  if (.not. allocated(err)) call fail('opening a missing file gave no error')
  deallocate(err)

  ! ---- float32 storage and compression (frames: &output precision, compress)
  ! edge values: FLT_MAX; just below FLT_MAX + half its last place (rounds
  ! down to it) and exactly that (a tie: to even, infinity); beyond the
  ! float32 range both ways; a subnormal; underflow to 0; a plain value; NaN
  edge = [flt_max, flt_max + 0.999_wp*half_ulp, flt_max + half_ulp, 1.0e300_wp, -1.0e39_wp, 3.0_wp*sub, &
          0.25_wp*sub, 0.1_wp, 0.0_wp]
  edge(9) = ieee_value(edge(9), ieee_quiet_nan)
  want = [huge(1.0_real32), huge(1.0_real32), ieee_value(1.0_real32, ieee_positive_inf), &
          ieee_value(1.0_real32, ieee_positive_inf), ieee_value(1.0_real32, ieee_negative_inf), &
          3.0_real32*2.0_real32**(-149), 0.0_real32, 0.1_real32, 0.0_real32]
  call h5_create(file, smallname, err)
  call check('h5_create (single)')
  call h5_write_real(file, 'a4', a4, shape(a4), err, single=.true., deflate=5)
  call check('h5_write_real (single, deflate)')
  call h5_write_real(file, 'edge', edge, shape(edge), err, single=.true.)
  call check('h5_write_real (single, edge values)')
  call h5_write_int(file, 'i3', i3, shape(i3), err, deflate=9)
  call check('h5_write_int (deflate)')
  call h5_write_real(file, 'zero', zr, shape(zr), err, single=.true., deflate=1)
  call check('h5_write_real (single, deflate, zero size)')
  call h5_close(file, err)
  call check('h5_close (single)')
  call h5_open_read(file, smallname, err)
  call check('h5_open_read (single)')
  call h5_read_real(file, 'a4', rflat, err)
  call check('h5_read_real (single)')
  ! (float32 to double on read is exact)
  if (any(transfer(real(rflat, real32), 0_int32, size(rflat)) /= &
          transfer(real(reshape(a4, [size(a4)]), real32), 0_int32, size(a4)))) &
    call fail('a4 stored as float32 is not real(a4, real32)')
  if (any(transfer(rflat, 0_int64, size(rflat)) == transfer(a4, 0_int64, size(a4)))) &
    call fail('a4 stored as float32 kept double digits')
  call h5_read_real(file, 'edge', rflat, err)
  call check('h5_read_real (edge values)')
  if (.not. ieee_is_nan(rflat(9))) call fail('NaN not stored as NaN in float32')
  if (any(transfer(real(rflat(1:8), real32), 0_int32, 8) /= transfer(want(1:8), 0_int32, 8))) &
    call fail('edge values not rounded to nearest float32 (infinity beyond its range)')
  call h5_read_int(file, 'i3', iflat, err)
  call check('h5_read_int (deflate)')
  if (any(iflat /= reshape(i3, [size(i3)]))) call fail('compressed i3 values differ')
  call h5_read_dims(file, 'zero', dims, err)
  call check('h5_read_dims (single, zero size)')
  if (any(dims /= [3, 0])) call fail('dims of the zero-size float32 array are not [3,0]')
  call h5_close(file, err)
  call check('h5_close (single, read)')

  ! ---- XDMF series of two frames
  do k = 1, nk + 1
    do j = 1, nj + 1
      do i = 1, ni + 1
        x(:, i, j, k) = [real(i - 1, wp), real(j - 1, wp), real(k - 1, wp)] * 0.5_wp
      end do
    end do
  end do
  rho = 1.0_wp
  do f = 1, 2
    call h5_create(file, trim(frame_names(f)), err)
    call check('h5_create frame')
    call h5_write_real(file, 'x', x, shape(x), err)
    call check('h5_write_real x')
    call h5_write_real(file, 'u', x * real(f, wp), shape(x), err)
    call check('h5_write_real u')
    call h5_write_real(file, 'rho', rho * real(f, wp), shape(rho), err)
    call check('h5_write_real rho')
    call h5_close(file, err)
    call check('h5_close frame')
  end do
  call xdmf_write_series(xdmfname, frame_names, [0.0_wp, 0.1_wp], ni, nj, nk, &
       [character(len=1) :: 'u'], [character(len=3) :: 'rho'], err)
  call check('xdmf_write_series')
  inquire(file=xdmfname, exist=exists)
  if (.not. exists) call fail('xdmf file not written')
  inquire(file=xdmfname//'.tmp', exist=exists)
  if (exists) call fail('xdmf temporary file left behind')
  call check_contains(xdmfname, '3DSMesh')
  call check_contains(xdmfname, 'Temporal')

  call hdf5_stop(err)
  call check('hdf5_stop')

  if (.not. keep) then
    call remove(h5name)
    call remove(smallname)
    call remove(txtname)
    call remove(xdmfname)
    call remove(trim(frame_names(1)))
    call remove(trim(frame_names(2)))
  end if
  print '(a)', 'PASS test_io_hdf5'

contains

  !> Fails if `err` is set.
  subroutine check(what)
    character(len=*), intent(in) :: what
    if (allocated(err)) call fail(what//': '//err%where//': '//err%msg)
  end subroutine check

  !> Prints one FAIL line and stops with status 1.
  subroutine fail(msg)
    character(len=*), intent(in) :: msg
    print '(a)', 'FAIL: '//msg
    error stop 1
  end subroutine fail

  !> Fails unless the text file `path` contains `word`.
  subroutine check_contains(path, word)
    character(len=*), intent(in) :: path, word
    character(len=4096) :: buf
    integer :: u, ios
    logical :: found
    found = .false.
    open(newunit=u, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) call fail('cannot open '//path)
    do
      read(u, '(a)', iostat=ios) buf
      if (ios /= 0) exit
      if (index(buf, word) > 0) found = .true.
    end do
    close(u)
    if (.not. found) call fail(path//' does not contain '//word)
  end subroutine check_contains

  !> Deletes `path` if it exists.
  subroutine remove(path)
    character(len=*), intent(in) :: path
    integer :: u, ios
    open(newunit=u, file=path, status='old', iostat=ios)
    if (ios == 0) close(u, status='delete')
  end subroutine remove

end program test_io_hdf5
