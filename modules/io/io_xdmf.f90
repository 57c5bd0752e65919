!> XDMF 3 index files describing a time series of structured-grid HDF5 frames
!> and, a second series, the frames' particles,
!> and an atomic rename helper shared by the output writers.
module io_xdmf
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use base_kinds, only: wp
  use base_strings, only: itoa
  use base_errors, only: error_t, error_set
  implicit none
  private
  public :: xdmf_write_series, xdmf_write_particles, io_rename

  interface
    !> libc rename(2): 0 on success.
    function c_rename(old, new) bind(c, name='rename') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*)
      character(kind=c_char), intent(in) :: new(*)
      integer(c_int) :: rc
    end function c_rename
  end interface

contains

  !> Renames file `old` to `new` (replacing `new` atomically on POSIX).
  subroutine io_rename(old, new, err)
    character(len=*), intent(in) :: old
    character(len=*), intent(in) :: new
    type(error_t), allocatable, intent(inout) :: err
    integer(c_int) :: rc
    rc = c_rename(trim(old)//c_null_char, trim(new)//c_null_char)
    if (rc /= 0_c_int) then
      call error_set(err, 'io_rename', 'cannot rename '//q(trim(old))//' to '//q(trim(new)))
    end if
  end subroutine io_rename

  !> Writes the XDMF 3 temporal collection `path` for the HDF5 frames `frames`
  !> (paths relative to the XDMF file) at `times`, on an ni x nj x nk cell grid.
  !> Each frame holds /x (node coordinates, Fortran shape [3,ni+1,nj+1,nk+1]),
  !> node vectors /name for `node_fields` and cell scalars /name (shape
  !> [ni,nj,nk]) for `cell_fields` (doubles) and `int_cell_fields` (default
  !> integers, e.g. the material index). Each frame's time is also field data
  !> `time` (ParaView shows Grid-centred attributes as field data), and so is
  !> each (`field_names`(k), `field_values`(k)) pair, the same in every frame
  !> (e.g. the material legend "material 1: air" = 1). `info_names` and
  !> `info_values` become <Information> elements of the domain (title, code
  !> version, unit system). Written to path//'.tmp', then renamed.
  !>
  !> The field data of a frame sit in its <Information Name="field_data">
  !> and reach the grid through an XInclude (`field_block`): the XDMF
  !> library (ParaView, VisIt) resolves it and sees Grid-centred attributes,
  !> while readers that know only Node and Cell attributes and skip
  !> Information and XInclude elements (meshio's TimeSeriesReader) still
  !> read the series. Particles are a series of their own
  !> (`xdmf_write_particles`).
  !> `real_bytes`: the size of the frames' reals, 8 (default, doubles) or 4
  !> (float32), the DataItems' Precision.
  subroutine xdmf_write_series(path, frames, times, ni, nj, nk, node_fields, cell_fields, err, &
                               int_cell_fields, field_names, field_values, info_names, info_values, real_bytes)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: frames(:)
    real(wp), intent(in) :: times(:)
    integer, intent(in) :: ni, nj, nk
    character(len=*), intent(in) :: node_fields(:)
    character(len=*), intent(in) :: cell_fields(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: int_cell_fields(:)
    character(len=*), intent(in), optional :: field_names(:)
    real(wp), intent(in), optional :: field_values(:)
    character(len=*), intent(in), optional :: info_names(:)
    character(len=*), intent(in), optional :: info_values(:)
    integer, intent(in), optional :: real_bytes
    character(len=*), parameter :: here = 'xdmf_write_series'
    character(len=:), allocatable :: tmp, node_dims, vec_dims, cell_dims, item, int_item
    character(len=32) :: tbuf
    character(len=256) :: msg
    integer :: unit, ios, f, k

    if (size(frames) /= size(times)) then
      call error_set(err, here, 'frames and times differ in size for '//q(path))
      return
    end if
    if (ni < 1 .or. nj < 1 .or. nk < 1) then
      call error_set(err, here, 'grid size must be positive for '//q(path))
      return
    end if
    if (present(field_names) .neqv. present(field_values)) then
      call error_set(err, here, 'field_names and field_values go together for '//q(path))
      return
    end if
    if (present(field_names) .and. present(field_values)) then
      if (size(field_names) /= size(field_values)) then
        call error_set(err, here, 'field_names and field_values differ in size for '//q(path))
        return
      end if
    end if
    call check_info(here, path, err, info_names, info_values)
    if (allocated(err)) return

    node_dims = itoa(nk + 1)//' '//itoa(nj + 1)//' '//itoa(ni + 1)
    vec_dims = node_dims//' 3'
    cell_dims = itoa(nk)//' '//itoa(nj)//' '//itoa(ni)
    item = ' NumberType="Float" Precision="'//itoa(real_size(real_bytes))//'" Format="HDF">'
    int_item = ' NumberType="Int" Precision="'//itoa(storage_size(0)/8)//'" Format="HDF">'
    tmp = path//'.tmp'
    call open_series(tmp, 'series', unit, ios, msg, info_names, info_values)
    if (ios /= 0) then
      call error_set(err, here, 'cannot open '//q(tmp)//': '//trim(msg))
      return
    end if
    do f = 1, size(frames)
      if (ios /= 0) exit
      call frame_start(unit, f - 1, times(f), tbuf, ios, msg)
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
           '        <Topology TopologyType="3DSMesh" Dimensions="'//node_dims//'"/>'
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        <Geometry GeometryType="XYZ">'
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
           '          <DataItem Dimensions="'//vec_dims//'"'//item//xml(trim(frames(f)))//':/x</DataItem>'
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        </Geometry>'
      do k = 1, size(node_fields)
        if (ios /= 0) exit
        call write_attribute(unit, trim(node_fields(k)), 'Vector', 'Node', vec_dims, &
                             item//xml(trim(frames(f)))//':/', ios, msg)
      end do
      do k = 1, size(cell_fields)
        if (ios /= 0) exit
        call write_attribute(unit, trim(cell_fields(k)), 'Scalar', 'Cell', cell_dims, &
                             item//xml(trim(frames(f)))//':/', ios, msg)
      end do
      if (present(int_cell_fields)) then
        do k = 1, size(int_cell_fields)
          if (ios /= 0) exit
          call write_attribute(unit, trim(int_cell_fields(k)), 'Scalar', 'Cell', cell_dims, &
                               int_item//xml(trim(frames(f)))//':/', ios, msg)
        end do
      end if
      if (ios == 0) then
        if (present(field_names) .and. present(field_values)) then
          call field_block(unit, f - 1, tbuf, ios, msg, field_names, field_values)
        else
          call field_block(unit, f - 1, tbuf, ios, msg)
        end if
      end if
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '      </Grid>'
    end do
    call close_series(here, tmp, path, unit, ios, msg, err)
  end subroutine xdmf_write_series

  !> Writes the XDMF 3 temporal collection `path` of the particles of the
  !> HDF5 frames `frames` (paths relative to the XDMF file) at `times`, a
  !> series of its own beside the grid's (`xdmf_write_series`), so that a
  !> reader opens the two as two datasets. Frame f is a Polyvertex grid of
  !> its `nparts`(f) points at /particles/x (3, npart) (the count falls as
  !> particles leave the grid), one vertex cell per particle (without cells
  !> ParaView draws nothing; connectivity /particles/vertex, 0..npart-1),
  !> with node-centred attributes /particles/<name>: `vectors` (3, npart),
  !> `scalars` (npart, doubles), `ints` (npart, default integers) and
  !> `tensors` (6, npart, XDMF Tensor6 order xx, xy, xz, yy, yz, zz). A frame
  !> without particles is a grid with its time and no points. The frame's
  !> time is field data `time` as in the grid's series; `info_names` and
  !> `info_values` become <Information> elements of the domain. Written to
  !> path//'.tmp', then renamed. `real_bytes` as for `xdmf_write_series`.
  subroutine xdmf_write_particles(path, frames, times, nparts, err, vectors, scalars, ints, tensors, &
                                  info_names, info_values, real_bytes)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: frames(:)
    real(wp), intent(in) :: times(:)
    integer, intent(in) :: nparts(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: vectors(:), scalars(:), ints(:), tensors(:)
    character(len=*), intent(in), optional :: info_names(:)
    character(len=*), intent(in), optional :: info_values(:)
    integer, intent(in), optional :: real_bytes
    character(len=*), parameter :: here = 'xdmf_write_particles'
    character(len=:), allocatable :: tmp
    character(len=32) :: tbuf
    character(len=256) :: msg
    integer :: unit, ios, f

    if (size(frames) /= size(times)) then
      call error_set(err, here, 'frames and times differ in size for '//q(path))
      return
    end if
    if (size(nparts) /= size(frames)) then
      call error_set(err, here, 'frames and particle counts differ in size for '//q(path))
      return
    end if
    if (any(nparts < 0)) then
      call error_set(err, here, 'a negative particle count for '//q(path))
      return
    end if
    call check_info(here, path, err, info_names, info_values)
    if (allocated(err)) return
    tmp = path//'.tmp'
    call open_series(tmp, 'particles', unit, ios, msg, info_names, info_values)
    if (ios /= 0) then
      call error_set(err, here, 'cannot open '//q(tmp)//': '//trim(msg))
      return
    end if
    do f = 1, size(frames)
      if (ios /= 0) exit
      call frame_start(unit, f - 1, times(f), tbuf, ios, msg)
      ! a frame without particles has no topology at all: an empty DataItem
      ! stops ParaView's reader
      if (ios == 0 .and. nparts(f) > 0) call write_points(unit, trim(frames(f)), nparts(f), &
                                                        real_size(real_bytes), vectors, scalars, ints, tensors, ios, msg)
      if (ios == 0) call field_block(unit, f - 1, tbuf, ios, msg)
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '      </Grid>'
    end do
    call close_series(here, tmp, path, unit, ios, msg, err)
  end subroutine xdmf_write_particles

  !> info_names and info_values go together and agree in size.
  subroutine check_info(here, path, err, info_names, info_values)
    character(len=*), intent(in) :: here, path
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: info_names(:), info_values(:)
    if (present(info_names) .neqv. present(info_values)) then
      call error_set(err, here, 'info_names and info_values go together for '//q(path))
      return
    end if
    if (present(info_names) .and. present(info_values)) then
      if (size(info_names) /= size(info_values)) then
        call error_set(err, here, 'info_names and info_values differ in size for '//q(path))
      end if
    end if
  end subroutine check_info

  !> Opens `tmp` and writes the head of a series: the domain, its
  !> Information elements and the temporal collection `name`.
  subroutine open_series(tmp, name, unit, ios, msg, info_names, info_values)
    character(len=*), intent(in) :: tmp, name
    integer, intent(out) :: unit, ios
    character(len=*), intent(inout) :: msg
    character(len=*), intent(in), optional :: info_names(:), info_values(:)
    integer :: k
    open(newunit=unit, file=tmp, status='replace', action='write', form='formatted', &
         iostat=ios, iomsg=msg)
    if (ios /= 0) return
    write(unit, '(a)', iostat=ios, iomsg=msg) '<?xml version="1.0" encoding="utf-8"?>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
         '<Xdmf xmlns:xi="http://www.w3.org/2001/XInclude" Version="3.0">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '  <Domain>'
    if (present(info_names) .and. present(info_values)) then
      do k = 1, size(info_names)
        if (ios /= 0) exit
        write(unit, '(a)', iostat=ios, iomsg=msg) '    <Information Name="'//xml(trim(info_names(k)))// &
             '" Value="'//xml(trim(info_values(k)))//'"/>'
      end do
    end if
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
         '    <Grid Name="'//name//'" GridType="Collection" CollectionType="Temporal">'
    if (ios /= 0) close(unit, status='delete', iostat=k)
  end subroutine open_series

  !> Ends the series open on `unit` (`ios` /= 0: a write failed, `msg`
  !> says why), checks that it reached the disk whole and renames `tmp` to
  !> `path`.
  subroutine close_series(here, tmp, path, unit, ios, msg, err)
    character(len=*), intent(in) :: here, tmp, path
    integer, intent(in) :: unit
    integer, intent(inout) :: ios
    character(len=*), intent(inout) :: msg
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, u
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '    </Grid>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '  </Domain>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '</Xdmf>'
    if (ios /= 0) then
      close(unit, status='delete', iostat=k)
      call error_set(err, here, 'cannot write '//q(tmp)//': '//trim(msg))
      return
    end if
    close(unit, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call error_set(err, here, 'cannot close '//q(tmp)//': '//trim(msg))
      return
    end if
    ! gfortran reports no error when a formatted write or close runs out of
    ! space: read the last line back before the file takes its final name
    if (.not. last_line_is(tmp, '</Xdmf>')) then
      open(newunit=u, file=tmp, status='old', iostat=ios)
      if (ios == 0) close(u, status='delete', iostat=ios)
      call error_set(err, here, 'cannot write '//q(tmp)//': it was cut short (disk full?)')
      return
    end if
    call io_rename(tmp, path, err)
  end subroutine close_series

  !> True if the last line of the text file `path` is `text`.
  logical function last_line_is(path, text)
    character(len=*), intent(in) :: path, text
    character(len=256) :: line, last
    integer :: unit, ios
    last_line_is = .false.
    open(newunit=unit, file=path, status='old', action='read', iostat=ios)
    if (ios /= 0) return
    last = ''
    do
      read(unit, '(a)', iostat=ios) line
      if (ios /= 0) exit
      last = line
    end do
    close(unit)
    last_line_is = trim(last) == text
  end function last_line_is

  !> Opens frame k's grid at `time` (`tbuf`: the time as written).
  subroutine frame_start(unit, k, time, tbuf, ios, msg)
    integer, intent(in) :: unit, k
    real(wp), intent(in) :: time
    character(len=*), intent(out) :: tbuf
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    write(tbuf, '(es24.16e3)') time
    write(unit, '(a)', iostat=ios, iomsg=msg) '      <Grid Name="frame_'//itoa(k)//'" GridType="Uniform">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        <Time Value="'//trim(adjustl(tbuf))//'"/>'
  end subroutine frame_start

  !> The frames' real size in bytes: `real_bytes` if given, else 8.
  pure integer function real_size(real_bytes) result(n)
    integer, intent(in), optional :: real_bytes
    n = 8
    if (present(real_bytes)) n = real_bytes
  end function real_size

  !> The Polyvertex topology, geometry and attributes of the `np` particles
  !> of frame file `frame` (see `xdmf_write_particles`).
  subroutine write_points(unit, frame, np, rbytes, vectors, scalars, ints, tensors, ios, msg)
    integer, intent(in) :: unit, np, rbytes
    character(len=*), intent(in) :: frame
    character(len=*), intent(in), optional :: vectors(:), scalars(:), ints(:), tensors(:)
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    character(len=:), allocatable :: fitem, iitem
    integer :: k
    fitem = ' NumberType="Float" Precision="'//itoa(rbytes)//'" Format="HDF">'//xml(frame)//':/particles/'
    iitem = ' NumberType="Int" Precision="'//itoa(storage_size(0)/8)//'" Format="HDF">'//xml(frame)//':/particles/'
    write(unit, '(a)', iostat=ios, iomsg=msg) '        <Topology TopologyType="Polyvertex" '// &
         'NumberOfElements="'//itoa(np)//'" NodesPerElement="1">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          <DataItem Dimensions="'//itoa(np)//'"'// &
         iitem//'vertex</DataItem>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        </Topology>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        <Geometry GeometryType="XYZ">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          <DataItem Dimensions="'//itoa(np)//' 3"'// &
         fitem//'x</DataItem>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        </Geometry>'
    if (present(vectors)) then
      do k = 1, size(vectors)
        if (ios == 0) call write_attribute(unit, trim(vectors(k)), 'Vector', 'Node', itoa(np)//' 3', fitem, ios, msg)
      end do
    end if
    if (present(scalars)) then
      do k = 1, size(scalars)
        if (ios == 0) call write_attribute(unit, trim(scalars(k)), 'Scalar', 'Node', itoa(np), fitem, ios, msg)
      end do
    end if
    if (present(ints)) then
      do k = 1, size(ints)
        if (ios == 0) call write_attribute(unit, trim(ints(k)), 'Scalar', 'Node', itoa(np), iitem, ios, msg)
      end do
    end if
    if (present(tensors)) then
      do k = 1, size(tensors)
        if (ios == 0) call write_attribute(unit, trim(tensors(k)), 'Tensor6', 'Node', itoa(np)//' 6', fitem, ios, msg)
      end do
    end if
  end subroutine write_points

  !> One attribute `name` of a frame's grid whose data is the HDF5 dataset
  !> of that name: `item` holds the DataItem's type attributes and the
  !> dataset's path up to the name.
  subroutine write_attribute(unit, name, kind, centre, dims, item, ios, msg)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: name, kind, centre, dims, item
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    write(unit, '(a)', iostat=ios, iomsg=msg) '        <Attribute Name="'//xml(name)//'" AttributeType="'// &
         kind//'" Center="'//centre//'">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          <DataItem Dimensions="'//dims//'"'// &
         item//xml(name)//'</DataItem>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        </Attribute>'
  end subroutine write_attribute

  !> The field data of frame `f` (0-based): Grid-centred scalar attributes
  !> with their values inline (a scalar HDF5 dataset is no hyperslab for the
  !> XDMF reader), `time` = `tbuf` and the (`names`, `values`) pairs. They
  !> sit in an <Information Name="field_data"> (whose children no reader
  !> takes for the grid's) and an XInclude of its children brings them into
  !> the grid: the XDMF library (libxml2) resolves it, readers that know only
  !> Node and Cell attributes skip it.
  subroutine field_block(unit, f, tbuf, ios, msg, names, values)
    integer, intent(in) :: unit, f
    character(len=*), intent(in) :: tbuf
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    character(len=*), intent(in), optional :: names(:)
    real(wp), intent(in), optional :: values(:)
    character(len=32) :: vbuf
    integer :: k
    write(unit, '(a)', iostat=ios, iomsg=msg) &
         '        <Information Name="field_data" Value="field data, included below">'
    if (ios == 0) call write_field(unit, 'time', tbuf, ios, msg)
    if (present(names) .and. present(values)) then
      do k = 1, size(names)
        if (ios /= 0) exit
        write(vbuf, '(es24.16e3)') values(k)
        call write_field(unit, trim(names(k)), vbuf, ios, msg)
      end do
    end if
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        </Information>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
         '        <xi:include xpointer="xpointer(/Xdmf/Domain/Grid/Grid[@Name=''frame_'//itoa(f)// &
         ''']/Information[@Name=''field_data'']/*)"/>'
  end subroutine field_block

  !> One Grid-centred (field data) scalar attribute with its value inline.
  subroutine write_field(unit, name, value, ios, msg)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: value
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    write(unit, '(a)', iostat=ios, iomsg=msg) '          <Attribute Name="'//xml(name)// &
         '" AttributeType="Scalar" Center="Grid">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
         '            <DataItem Dimensions="1" NumberType="Float" Precision="8" Format="XML">'// &
         trim(adjustl(value))//'</DataItem>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          </Attribute>'
  end subroutine write_field

  !> Escapes the XML special characters of `s`.
  pure function xml(s) result(r)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: r
    integer :: i
    r = ''
    do i = 1, len(s)
      select case (s(i:i))
      case ('&')
        r = r//'&amp;'
      case ('<')
        r = r//'&lt;'
      case ('>')
        r = r//'&gt;'
      case ('"')
        r = r//'&quot;'
      case default
        r = r//s(i:i)
      end select
    end do
  end function xml

  !> Quotes a string for messages.
  pure function q(s) result(r)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: r
    r = "'"//s//"'"
  end function q

end module io_xdmf
