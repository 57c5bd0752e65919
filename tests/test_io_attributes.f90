!> HDF5 attributes (io_hdf5 h5_write_attribute, h5_read_attribute_string) and
!> the XDMF series' integer fields, field data and Information (io_xdmf).
!> Usage: test_io_attributes [--keep]   (files in the working directory)
program test_io_attributes
  use base_kinds, only: wp
  use base_errors, only: error_t
  use io_hdf5, only: h5_file_t, h5_create, h5_open_read, h5_close, h5_write_real, h5_write_int, &
       h5_write_scalar_real, h5_write_attribute, h5_write_attribute_string, h5_read_attribute_string
  use io_xdmf, only: xdmf_write_series, xdmf_write_particles
  use test_assert, only: check, check_summary
  implicit none

  character(len=*), parameter :: h5name = 'test_io_attributes.h5'
  character(len=*), parameter :: xdmfname = 'test_io_attributes.xdmf'
  character(len=*), parameter :: pxdmfname = 'test_io_attributes_particles.xdmf'
  type(error_t), allocatable :: err
  type(h5_file_t) :: file
  real(wp) :: rho(2, 3, 1), x(3, 3, 4, 2)
  integer :: mat(2, 3, 1)
  character(len=:), allocatable :: long, back
  character(len=8) :: arg
  integer :: unit, ios

  call get_command_argument(1, arg)
  rho = 1.5_wp
  x = 0.0_wp
  mat = 2
  long = 'title with "quotes", <tags> & a newline'//new_line('a')//repeat('x', 300)

  ! ---- writing
  call h5_create(file, h5name, err)
  call ok_now('create')
  call h5_write_real(file, 'density', rho, shape(rho), err)
  call h5_write_int(file, 'material', mat, shape(mat), err)
  call h5_write_scalar_real(file, 'totals/mass', 3.0_wp, err)
  call ok_now('datasets')
  call h5_write_attribute(file, '', 'title', long, err)
  call ok_now('string attribute on the file')
  call h5_write_attribute(file, '/', 'unit_system', '', err)
  call ok_now('empty string attribute on the file (root as /)')
  call h5_write_attribute(file, 'density', 'units', 'mass/length^3', err)
  call ok_now('string attribute on a dataset')
  call h5_write_attribute(file, 'totals/mass', 'units', 'mass', err)
  call ok_now('string attribute on a dataset in a group')
  call h5_write_attribute(file, 'density', 'scale', 2.5_wp, err)
  call ok_now('real attribute')
  call h5_write_attribute(file, 'material', 'values', [1, 2, 3], err)
  call ok_now('integer attribute')
  ! refusals, each with a message naming the attribute
  call h5_write_attribute(file, 'density', 'units', 'again', err)
  call refused('a second attribute of the same name', 'units')
  call h5_write_attribute(file, 'no_such', 'units', 'mass', err)
  call refused('an attribute of a missing dataset', 'no_such')
  call h5_write_attribute(file, 'material', 'values', [integer ::], err)
  call refused('an integer attribute without values', 'values')
  call h5_write_attribute_string(file, 'density', '', 'x', err)
  call refused('an attribute without a name', 'empty')
  call h5_close(file, err)
  call ok_now('close')
  call h5_write_attribute(file, '', 'late', 'x', err)
  call refused('an attribute on a closed file', 'not open')

  ! ---- reading back
  call h5_open_read(file, h5name, err)
  call ok_now('open')
  call h5_read_attribute_string(file, '', 'title', back, err)
  call ok_now('read title')
  call check(back == long, 'the title comes back unchanged (quotes, tags, newline, 300 characters)')
  call h5_read_attribute_string(file, '', 'unit_system', back, err)
  call ok_now('read empty string')
  call check(back == '', 'the empty string comes back empty, got '''//back//'''')
  call h5_read_attribute_string(file, 'totals/mass', 'units', back, err)
  call ok_now('read units in a group')
  call check(back == 'mass', 'totals/mass units, got '''//back//'''')
  call h5_read_attribute_string(file, 'density', 'missing', back, err)
  call refused('reading a missing attribute', 'missing')
  call h5_read_attribute_string(file, 'density', 'scale', back, err)
  call refused('reading a real attribute as a string', 'not a string')
  call h5_close(file, err)
  call ok_now('close after reading')

  ! ---- XDMF: integer cell field, field data, Information
  call xdmf_write_series(xdmfname, [character(len=24) :: h5name], [0.5_wp], 2, 3, 1, &
       [character(len=8) :: 'velocity'], [character(len=8) :: 'density'], err, &
       int_cell_fields=[character(len=8) :: 'material'], &
       field_names=[character(len=20) :: 'material 1: air'], field_values=[1.0_wp], &
       info_names=[character(len=8) :: 'title'], info_values=[character(len=64) :: 'a "quoted" & <title>'])
  call ok_now('xdmf_write_series with the optional lists')
  call contains_line(xdmfname, 'NumberType="Int" Precision="4" Format="HDF">'//h5name//':/material<')
  call contains_line(xdmfname, '<Attribute Name="material 1: air" AttributeType="Scalar" Center="Grid">')
  call contains_line(xdmfname, '<Attribute Name="time" AttributeType="Scalar" Center="Grid">')
  call contains_line(xdmfname, 'Format="XML">5.0000000000000000E-001</DataItem>')
  call contains_line(xdmfname, '<Information Name="title" Value="a &quot;quoted&quot; &amp; &lt;title&gt;"/>')
  ! the field data reach the grid through an XInclude of its Information
  call contains_line(xdmfname, '<Information Name="field_data" Value="field data, included below">')
  call contains_line(xdmfname, '<xi:include xpointer="xpointer(/Xdmf/Domain/Grid/Grid[@Name=''frame_0'']/'// &
                     'Information[@Name=''field_data'']/*)"/>')
  ! ---- the particles' series: a frame with 5 particles, one without
  call xdmf_write_particles(pxdmfname, [character(len=24) :: h5name, h5name], [0.5_wp, 1.0_wp], [5, 0], err, &
       vectors=[character(len=8) :: 'velocity'], scalars=[character(len=8) :: 'mass'], &
       ints=[character(len=8) :: 'body'], tensors=[character(len=8) :: 'stress'], &
       info_names=[character(len=8) :: 'title'], info_values=[character(len=8) :: 'parts'])
  call ok_now('xdmf_write_particles')
  call contains_line(pxdmfname, '<Grid Name="particles" GridType="Collection" CollectionType="Temporal">')
  call contains_line(pxdmfname, '<Topology TopologyType="Polyvertex" NumberOfElements="5" NodesPerElement="1">')
  call contains_line(pxdmfname, '<DataItem Dimensions="5 6" NumberType="Float" Precision="8" Format="HDF">'// &
                     h5name//':/particles/stress<')
  call contains_line(pxdmfname, '<Attribute Name="stress" AttributeType="Tensor6" Center="Node">')
  call contains_line(pxdmfname, 'Format="HDF">'//h5name//':/particles/body<')
  call contains_line(pxdmfname, 'Format="XML">1.0000000000000000E+000</DataItem>')
  call contains_line(pxdmfname, '<Information Name="title" Value="parts"/>')
  call xdmf_write_particles(pxdmfname, [character(len=24) :: h5name], [0.5_wp], [5, 0], err)
  call refused('particle counts for another number of frames', 'differ in size')
  call xdmf_write_particles(pxdmfname, [character(len=24) :: h5name], [0.5_wp], [-1], err)
  call refused('a negative particle count', 'negative')
  call xdmf_write_series(xdmfname, [character(len=24) :: h5name], [0.5_wp], 2, 3, 1, &
       [character(len=8) :: 'velocity'], [character(len=8) :: 'density'], err, &
       field_names=[character(len=20) :: 'a', 'b'], field_values=[1.0_wp])
  call refused('field names and values of different sizes', 'differ in size')
  call xdmf_write_series(xdmfname, [character(len=24) :: h5name], [0.5_wp], 2, 3, 1, &
       [character(len=8) :: 'velocity'], [character(len=8) :: 'density'], err, &
       info_names=[character(len=8) :: 'title'])
  call refused('info names without values', 'go together')

  if (arg /= '--keep') then
    open(newunit=unit, file=h5name, status='old', iostat=ios)
    if (ios == 0) close(unit, status='delete', iostat=ios)
    open(newunit=unit, file=xdmfname, status='old', iostat=ios)
    if (ios == 0) close(unit, status='delete', iostat=ios)
    open(newunit=unit, file=pxdmfname, status='old', iostat=ios)
    if (ios == 0) close(unit, status='delete', iostat=ios)
  end if
  call check_summary('test_io_attributes')

contains

  !> The last call succeeded.
  subroutine ok_now(what)
    character(len=*), intent(in) :: what
    if (allocated(err)) then
      call check(.false., what//': '//err%msg)
      deallocate(err)
    else
      write(*, '(a)') 'ok    '//what
    end if
  end subroutine ok_now

  !> The last call failed with a message containing `word`.
  subroutine refused(what, word)
    character(len=*), intent(in) :: what, word
    if (.not. allocated(err)) then
      call check(.false., what//' was accepted')
      return
    end if
    call check(index(err%msg, word) > 0, what//': message without '''//word//''': '//err%msg)
    write(*, '(a)') 'ok    '//what//' refused: '//err%msg
    deallocate(err)
  end subroutine refused

  !> The text file `path` has a line containing `s`.
  subroutine contains_line(path, s)
    character(len=*), intent(in) :: path, s
    character(len=1000) :: line
    integer :: u, ios2
    logical :: found
    found = .false.
    open(newunit=u, file=path, status='old', action='read', iostat=ios2)
    if (ios2 /= 0) then
      call check(.false., 'cannot open '//path)
      return
    end if
    do
      read(u, '(a)', iostat=ios2) line
      if (ios2 /= 0) exit
      if (index(line, s) > 0) found = .true.
    end do
    close(u)
    call check(found, path//' has a line with '//s)
    if (found) write(*, '(a)') 'ok    '//path//' has '//s
  end subroutine contains_line
end program test_io_attributes
