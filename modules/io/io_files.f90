!> Files and directories without a shell: the output directory (and its
!> parents) is created with POSIX mkdir through C interoperability, so no
!> character of a name is ever interpreted (`$(...)`, quotes, `--help`).
module io_files
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use base_errors, only: error_t, error_set, ERR_IO
  implicit none
  private
  public :: io_make_dirs, io_is_dir

  interface
    !> int mkdir(const char *path, mode_t mode); mode_t is a 32-bit
    !> unsigned integer on Linux.
    function c_mkdir(path, mode) bind(c, name='mkdir') result(status)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value, intent(in) :: mode
      integer(c_int) :: status
    end function c_mkdir
  end interface

contains

  !> True if `path` names an existing directory.
  logical function io_is_dir(path)
    character(len=*), intent(in) :: path
    inquire(file=trim(path)//'/.', exist=io_is_dir)
  end function io_is_dir

  !> Creates directory `path` and any missing parents (mode 0777 less the
  !> umask), like `mkdir -p`; an error if a part exists and is not a
  !> directory or cannot be created.
  subroutine io_make_dirs(path, err)
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer :: i, status
    logical :: exists
    character(len=:), allocatable :: part

    if (len_trim(path) == 0) then
      call error_set(err, 'io_make_dirs', 'the output directory name is empty', ERR_IO)
      return
    end if
    do i = 1, len_trim(path)
      if (path(i:i) /= '/' .and. i < len_trim(path)) cycle
      part = path(1:i)
      if (part == '/') cycle
      if (io_is_dir(part)) cycle
      ! judged by what exists afterwards (another process may have made it)
      status = c_mkdir(part//c_null_char, int(o'777', c_int))
      exists = io_is_dir(part)
      if (.not. exists) then
        call error_set(err, 'io_make_dirs', 'cannot create the output directory '''//trim(path)// &
                       ''' ('''//part//''' cannot be made a directory)', ERR_IO)
        return
      end if
    end do
  end subroutine io_make_dirs
end module io_files
