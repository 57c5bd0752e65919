!> A surface file in the STL format (`&particles shape = 'stl'`): binary
!> (an 80-byte header, a 32-bit little-endian triangle count, then per
!> triangle a normal and three vertices as 32-bit little-endian reals and a
!> 16-bit attribute) or ASCII (`solid ... facet normal ... outer loop,
!> vertex x y z three times, endloop, endfacet ... endsolid`; only the
!> `vertex` lines are read). A file is binary when its size is exactly
!> 84 + 50 x its count, else ASCII. Coordinates are in the deck's length
!> unit (STL has none); the normals are not used.
module io_stl
  use, intrinsic :: iso_fortran_env, only: int32, int16, real32, int64
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use base_kinds, only: wp
  use base_strings, only: itoa, lower
  use base_errors, only: error_no_memory, error_t, error_set
  implicit none
  private
  public :: stl_read

contains

  !> The triangles tri(3 coordinates, 3 vertices, n) of the STL file path;
  !> at least one, every coordinate finite and of magnitude below 1e30.
  subroutine stl_read(path, tri, err)
    character(len=*), intent(in) :: path
    real(wp), allocatable, intent(out) :: tri(:, :, :)
    type(error_t), allocatable, intent(inout) :: err
    integer(int64) :: size_
    integer(int32) :: count
    integer :: u, ios
    logical :: there
    character(len=256) :: msg
    character(len=80) :: header

    inquire(file=path, exist=there, size=size_)
    if (.not. there) then
      call error_set(err, 'stl_read', 'surface file '''//path//''' does not exist')
      return
    end if
    open(newunit=u, file=path, access='stream', form='unformatted', status='old', action='read', iostat=ios, &
         iomsg=msg)
    if (ios /= 0) then
      call error_set(err, 'stl_read', 'cannot open '''//path//''': '//trim(msg))
      return
    end if
    count = -1
    if (size_ >= 84) read(u, iostat=ios) header, count
    if (size_ >= 84 .and. .not. little_endian()) count = transfer(swap32(transfer(count, 1.0_real32)), count)
    if (size_ >= 84 .and. count >= 0 .and. size_ == 84_int64 + 50_int64*int(count, int64)) then
      call read_binary(u, int(count), tri, err)
      close(u)
    else
      close(u)
      call read_ascii(path, tri, err)
    end if
    if (allocated(err)) return
    if (size(tri, 3) == 0) then
      call error_set(err, 'stl_read', 'surface file '''//path//''' holds no triangle')
    else if (.not. (all(ieee_is_finite(tri)) .and. all(abs(tri) < 1.0e30_wp))) then
      call error_set(err, 'stl_read', 'surface file '''//path//''': a coordinate is not finite or of magnitude '// &
                     '1e30 or more')
    end if

  contains

    subroutine read_binary(unit, n, t, e)
      integer, intent(in) :: unit, n
      real(wp), allocatable, intent(out) :: t(:, :, :)
      type(error_t), allocatable, intent(inout) :: e
      real(real32) :: r(12)
      integer(int16) :: attr
      integer :: k, stat
      allocate(t(3, 3, n), stat=stat)
      if (stat /= 0) then
        call error_set(e, 'stl_read', error_no_memory(itoa(n)//' triangles'))
        return
      end if
      do k = 1, n
        read(unit, iostat=ios, iomsg=msg) r, attr
        if (ios /= 0) then
          call error_set(e, 'stl_read', 'surface file '''//path//''', triangle '//itoa(k)//': '//trim(msg))
          return
        end if
        if (.not. little_endian()) r = swap32(r)
        t(:, :, k) = reshape(real(r(4:12), wp), [3, 3])
      end do
    end subroutine read_binary
  end subroutine stl_read

  !> The `vertex x y z` lines of an ASCII STL file, three per triangle.
  subroutine read_ascii(path, tri, err)
    character(len=*), intent(in) :: path
    real(wp), allocatable, intent(out) :: tri(:, :, :)
    type(error_t), allocatable, intent(inout) :: err
    character(len=1024) :: line
    character(len=256) :: msg
    integer :: u, ios, pass, nv, nline, i, stat
    real(wp) :: x(3)
    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call error_set(err, 'stl_read', 'cannot open '''//path//''': '//trim(msg))
      return
    end if
    ! pass 1 counts the vertices, pass 2 stores them
    do pass = 1, 2
      rewind(u)
      nv = 0
      nline = 0
      do
        read(u, '(a)', iostat=ios) line
        if (ios < 0) exit
        nline = nline + 1
        line = adjustl(line)
        if (lower(line(1:7)) /= 'vertex ') cycle
        read(line(8:), *, iostat=ios) x
        if (ios /= 0) then
          call error_set(err, 'stl_read', 'surface file '''//path//''', line '//itoa(nline)// &
                         ': a vertex needs three numbers')
          close(u)
          return
        end if
        nv = nv + 1
        if (pass == 2) then
          i = nv - 1
          tri(:, mod(i, 3) + 1, i/3 + 1) = x
        end if
      end do
      if (pass == 1) then
        if (mod(nv, 3) /= 0) then
          call error_set(err, 'stl_read', 'surface file '''//path//''' is neither binary STL nor ASCII STL '// &
                         'with three vertices per facet ('//itoa(nv)//' vertex lines)')
          close(u)
          return
        end if
        allocate(tri(3, 3, nv/3), stat=stat)
        if (stat /= 0) then
          call error_set(err, 'stl_read', error_no_memory(itoa(nv/3)//' triangles'))
          close(u)
          return
        end if
      end if
    end do
    close(u)
  end subroutine read_ascii

  !> Whether this machine stores integers little-endian (as STL does).
  logical function little_endian()
    little_endian = ichar(transfer(1_int32, 'a')) == 1
  end function little_endian

  !> The bytes of each 32-bit value reversed.
  elemental function swap32(r) result(s)
    real(real32), intent(in) :: r
    real(real32) :: s
    character(len=4) :: b
    b = transfer(r, b)
    s = transfer(b(4:4)//b(3:3)//b(2:2)//b(1:1), s)
  end function swap32
end module io_stl
