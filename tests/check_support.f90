!> Helpers shared by the scene checkers: reading a frame and failing a test.
module check_support
  use base_kinds, only: wp
  use base_errors, only: error_t
  use io_hdf5, only: h5_file_t, h5_open_read, h5_close, h5_read_real, h5_read_dims, &
                     h5_read_scalar_real
  implicit none
  private
  public :: frame_t, frame_read, frame_field, check_fail, arg_real, arg_int, arg_str

  !> The parts of a frame the checkers use.
  type :: frame_t
    integer :: ni = 0, nj = 0, nk = 0
    real(wp) :: time = 0.0_wp
    real(wp), allocatable :: x(:), density(:), pressure(:), volume(:), velocity(:)
    real(wp) :: mass = 0.0_wp, internal = 0.0_wp, kinetic = 0.0_wp, initial = 0.0_wp, work = 0.0_wp
  end type frame_t

contains

  subroutine frame_read(path, fr)
    character(len=*), intent(in) :: path
    type(frame_t), intent(out) :: fr
    type(h5_file_t) :: f
    type(error_t), allocatable :: err
    integer, allocatable :: dims(:)

    call h5_open_read(f, path, err)
    if (.not. allocated(err)) call h5_read_dims(f, 'density', dims, err)
    if (.not. allocated(err)) call h5_read_real(f, 'x', fr%x, err)
    if (.not. allocated(err)) call h5_read_real(f, 'velocity', fr%velocity, err)
    if (.not. allocated(err)) call h5_read_real(f, 'density', fr%density, err)
    if (.not. allocated(err)) call h5_read_real(f, 'pressure', fr%pressure, err)
    if (.not. allocated(err)) call h5_read_real(f, 'volume', fr%volume, err)
    if (.not. allocated(err)) call h5_read_scalar_real(f, 'time', fr%time, err)
    if (.not. allocated(err)) call h5_read_scalar_real(f, 'totals/mass', fr%mass, err)
    if (.not. allocated(err)) call h5_read_scalar_real(f, 'totals/internal_energy', fr%internal, err)
    if (.not. allocated(err)) call h5_read_scalar_real(f, 'totals/kinetic_energy', fr%kinetic, err)
    if (.not. allocated(err)) call h5_read_scalar_real(f, 'totals/initial_energy', fr%initial, err)
    if (.not. allocated(err)) call h5_read_scalar_real(f, 'totals/boundary_work', fr%work, err)
    if (allocated(err)) call check_fail('cannot read frame '//path//': '//err%msg)
    call h5_close(f, err)
    fr%ni = dims(1); fr%nj = dims(2); fr%nk = dims(3)
  end subroutine frame_read

  !> One more dataset of a frame, by name.
  subroutine frame_field(path, name, data)
    character(len=*), intent(in) :: path, name
    real(wp), allocatable, intent(out) :: data(:)
    type(h5_file_t) :: f
    type(error_t), allocatable :: err
    call h5_open_read(f, path, err)
    if (.not. allocated(err)) call h5_read_real(f, name, data, err)
    if (allocated(err)) call check_fail('cannot read '//name//' from '//path//': '//err%msg)
    call h5_close(f, err)
  end subroutine frame_field

  subroutine check_fail(msg)
    character(len=*), intent(in) :: msg
    write(*, '(a)') 'FAIL: '//msg
    error stop 1
  end subroutine check_fail

  function arg_str(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    integer :: n
    if (command_argument_count() < i) call check_fail('missing command-line argument')
    call get_command_argument(i, length=n)
    allocate(character(len=n) :: s)
    call get_command_argument(i, s)
  end function arg_str

  real(wp) function arg_real(i)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    integer :: ios
    s = arg_str(i)
    read(s, *, iostat=ios) arg_real
    if (ios /= 0) call check_fail('argument '//s//' is not a number')
  end function arg_real

  integer function arg_int(i)
    integer, intent(in) :: i
    arg_int = nint(arg_real(i))
  end function arg_int
end module check_support
