!> XDMF 3 index files describing a time series of structured-grid HDF5 frames,
!> and an atomic rename helper shared by the output writers.
module io_xdmf
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use base_kinds, only: wp
  use base_strings, only: itoa
  use base_errors, only: error_t, error_set
  implicit none
  private
  public :: xdmf_write_series, io_rename

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
  !> [ni,nj,nk]) for `cell_fields` (reals, `real_bytes`) and `int_cell_fields` (default
  !> integers, e.g. the material index). Each frame's time is also field data
  !> `time` (ParaView shows Grid-centred attributes as field data), and so is
  !> each (`field_names`(k), `field_values`(k)) pair, the same in every frame
  !> (e.g. the material legend "material 1: air" = 1). `info_names` and
  !> `info_values` become <Information> elements of the domain (title, code
  !> version, unit system). Written to path//'.tmp', then renamed.
  !>
  !> Particles (`nparts`, the count of each frame, some of them > 0): each
  !> frame is then a spatial collection of the grid above and, when
  !> the frame has particles, a Polyvertex grid "particles" of its npart
  !> points at /particles/x (3, npart) (the count falls as particles leave
  !> the grid), with node-centred attributes /particles/<name>:
  !> `part_vectors` (3, npart), `part_scalars` (npart, reals),
  !> `part_ints` (npart, default integers) and `part_tensors` (6, npart,
  !> XDMF Tensor6 order xx, xy, xz, yy, yz, zz), so ParaView shows the
  !> particles with the grid; one vertex cell per particle, its connectivity
  !> /particles/vertex (0..npart-1). Without particles the file is as before.
  !> `real_bytes`: the size of the frames' reals, 8 (default, doubles) or 4
  !> (float32), the DataItems' Precision.
  subroutine xdmf_write_series(path, frames, times, ni, nj, nk, node_fields, cell_fields, err, &
                               int_cell_fields, field_names, field_values, info_names, info_values, &
                               nparts, part_vectors, part_scalars, part_ints, part_tensors, real_bytes)
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
    integer, intent(in), optional :: nparts(:)
    character(len=*), intent(in), optional :: part_vectors(:), part_scalars(:), part_ints(:), part_tensors(:)
    integer, intent(in), optional :: real_bytes
    character(len=*), parameter :: here = 'xdmf_write_series'
    character(len=:), allocatable :: tmp, node_dims, vec_dims, cell_dims, item, int_item, ind
    logical :: with_particles
    character(len=32) :: tbuf
    character(len=256) :: msg
    integer :: unit, ios, f, k, rbytes

    if (size(frames) /= size(times)) then
      call error_set(err, here, 'frames and times differ in size for '//q(path))
      return
    end if
    with_particles = .false.
    if (present(nparts)) then
      if (size(nparts) /= size(frames)) then
        call error_set(err, here, 'frames and particle counts differ in size for '//q(path))
        return
      end if
      with_particles = any(nparts > 0)
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
    if (present(info_names) .neqv. present(info_values)) then
      call error_set(err, here, 'info_names and info_values go together for '//q(path))
      return
    end if
    if (present(info_names) .and. present(info_values)) then
      if (size(info_names) /= size(info_values)) then
        call error_set(err, here, 'info_names and info_values differ in size for '//q(path))
        return
      end if
    end if

    node_dims = itoa(nk + 1)//' '//itoa(nj + 1)//' '//itoa(ni + 1)
    vec_dims = node_dims//' 3'
    cell_dims = itoa(nk)//' '//itoa(nj)//' '//itoa(ni)
    rbytes = 8
    if (present(real_bytes)) rbytes = real_bytes
    item = ' NumberType="Float" Precision="'//itoa(rbytes)//'" Format="HDF">'
    int_item = ' NumberType="Int" Precision="'//itoa(storage_size(0)/8)//'" Format="HDF">'
    tmp = path//'.tmp'
    ! with particles the frame's grid sits one level deeper, in a spatial collection
    ind = repeat(' ', merge(2, 0, with_particles))

    open(newunit=unit, file=tmp, status='replace', action='write', form='formatted', &
         iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call error_set(err, here, 'cannot open '//q(tmp)//': '//trim(msg))
      return
    end if

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
         '    <Grid Name="series" GridType="Collection" CollectionType="Temporal">'
    do f = 1, size(frames)
      if (ios /= 0) exit
      write(tbuf, '(es24.16e3)') times(f)
      if (with_particles) then
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
             '      <Grid Name="frame_'//itoa(f - 1)//'" GridType="Collection" CollectionType="Spatial">'
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
             '        <Time Value="'//trim(adjustl(tbuf))//'"/>'
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
             '        <Grid Name="grid" GridType="Uniform">'
      else
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
             '      <Grid Name="frame_'//itoa(f - 1)//'" GridType="Uniform">'
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
             '        <Time Value="'//trim(adjustl(tbuf))//'"/>'
      end if
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
           ind//'        <Topology TopologyType="3DSMesh" Dimensions="'//node_dims//'"/>'
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        <Geometry GeometryType="XYZ">'
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
           ind//'          <DataItem Dimensions="'//vec_dims//'"'//item//xml(trim(frames(f)))//':/x</DataItem>'
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        </Geometry>'
      do k = 1, size(node_fields)
        if (ios /= 0) exit
        write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        <Attribute Name="'//xml(trim(node_fields(k)))// &
             '" AttributeType="Vector" Center="Node">'
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
             ind//'          <DataItem Dimensions="'//vec_dims//'"'//item//xml(trim(frames(f)))//':/'// &
             xml(trim(node_fields(k)))//'</DataItem>'
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        </Attribute>'
      end do
      do k = 1, size(cell_fields)
        if (ios /= 0) exit
        write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        <Attribute Name="'//xml(trim(cell_fields(k)))// &
             '" AttributeType="Scalar" Center="Cell">'
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
             ind//'          <DataItem Dimensions="'//cell_dims//'"'//item//xml(trim(frames(f)))//':/'// &
             xml(trim(cell_fields(k)))//'</DataItem>'
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        </Attribute>'
      end do
      if (present(int_cell_fields)) then
        do k = 1, size(int_cell_fields)
          if (ios /= 0) exit
          write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        <Attribute Name="'//xml(trim(int_cell_fields(k)))// &
               '" AttributeType="Scalar" Center="Cell">'
          if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
               ind//'          <DataItem Dimensions="'//cell_dims//'"'//int_item//xml(trim(frames(f)))//':/'// &
               xml(trim(int_cell_fields(k)))//'</DataItem>'
          if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        </Attribute>'
        end do
      end if
      ! field data, inline: a scalar HDF5 dataset is no hyperslab for the XDMF reader
      if (ios == 0) call write_field(unit, ind, 'time', tbuf, ios, msg)
      if (present(field_names) .and. present(field_values)) then
        do k = 1, size(field_names)
          if (ios /= 0) exit
          write(tbuf, '(es24.16e3)') field_values(k)
          call write_field(unit, ind, trim(field_names(k)), tbuf, ios, msg)
        end do
      end if
      if (with_particles) then
        if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        </Grid>'
        if (ios == 0 .and. nparts(f) > 0) call write_particles(unit, trim(frames(f)), nparts(f), part_vectors, &
                                                              part_scalars, part_ints, part_tensors, ios, msg, rbytes)
      end if
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '      </Grid>'
    end do
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
      open(newunit=unit, file=tmp, status='old', iostat=ios)
      if (ios == 0) close(unit, status='delete', iostat=ios)
      call error_set(err, here, 'cannot write '//q(tmp)//': it was cut short (disk full?)')
      return
    end if
    call io_rename(tmp, path, err)
  end subroutine xdmf_write_series

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


  !> The Polyvertex grid of the particles of frame file `frame` (see
  !> `xdmf_write_series`).
  subroutine write_particles(unit, frame, np, vectors, scalars, ints, tensors, ios, msg, rbytes)
    integer, intent(in) :: unit, np, rbytes
    character(len=*), intent(in) :: frame
    character(len=*), intent(in), optional :: vectors(:), scalars(:), ints(:), tensors(:)
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    character(len=:), allocatable :: fitem, iitem
    integer :: k
    fitem = ' NumberType="Float" Precision="'//itoa(rbytes)//'" Format="HDF">'//xml(frame)//':/particles/'
    iitem = ' NumberType="Int" Precision="'//itoa(storage_size(0)/8)//'" Format="HDF">'//xml(frame)//':/particles/'
    write(unit, '(a)', iostat=ios, iomsg=msg) '        <Grid Name="particles" GridType="Uniform">'
    ! one vertex cell per particle (without cells ParaView draws nothing):
    ! the connectivity 0..np-1 (the frame's particles/vertex)
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          <Topology TopologyType="Polyvertex" '// &
         'NumberOfElements="'//itoa(np)//'" NodesPerElement="1">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '            <DataItem Dimensions="'//itoa(np)//'"'// &
         iitem//'vertex</DataItem>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          </Topology>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          <Geometry GeometryType="XYZ">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '            <DataItem Dimensions="'//itoa(np)//' 3"'// &
         fitem//'x</DataItem>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          </Geometry>'
    if (present(vectors)) then
      do k = 1, size(vectors)
        if (ios == 0) call one(trim(vectors(k)), 'Vector', itoa(np)//' 3', fitem)
      end do
    end if
    if (present(scalars)) then
      do k = 1, size(scalars)
        if (ios == 0) call one(trim(scalars(k)), 'Scalar', itoa(np), fitem)
      end do
    end if
    if (present(ints)) then
      do k = 1, size(ints)
        if (ios == 0) call one(trim(ints(k)), 'Scalar', itoa(np), iitem)
      end do
    end if
    if (present(tensors)) then
      do k = 1, size(tensors)
        if (ios == 0) call one(trim(tensors(k)), 'Tensor6', itoa(np)//' 6', fitem)
      end do
    end if
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '        </Grid>'
  contains
    subroutine one(name, kind, dims, item)
      character(len=*), intent(in) :: name, kind, dims, item
      write(unit, '(a)', iostat=ios, iomsg=msg) '          <Attribute Name="'//xml(name)//'" AttributeType="'// &
           kind//'" Center="Node">'
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '            <DataItem Dimensions="'//dims//'"'// &
           item//xml(name)//'</DataItem>'
      if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) '          </Attribute>'
    end subroutine one
  end subroutine write_particles

  !> One Grid-centred (field data) scalar attribute with its value inline.
  subroutine write_field(unit, ind, name, value, ios, msg)
    integer, intent(in) :: unit
    character(len=*), intent(in) :: ind, name
    character(len=*), intent(in) :: value
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        <Attribute Name="'//xml(name)// &
         '" AttributeType="Scalar" Center="Grid">'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) &
         ind//'          <DataItem Dimensions="1" NumberType="Float" Precision="8" Format="XML">'// &
         trim(adjustl(value))//'</DataItem>'
    if (ios == 0) write(unit, '(a)', iostat=ios, iomsg=msg) ind//'        </Attribute>'
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
