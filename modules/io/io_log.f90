!> The run log: every line goes to standard output and to the log file.
module io_log
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  implicit none
  private
  public :: log_open, log_close, log_line, log_error, log_is_open

  integer, save :: log_unit = -1

contains

  !> Opens the log file at path, replacing it or (append) adding to it;
  !> returns a message on failure.
  subroutine log_open(path, append, ok, msg)
    character(len=*), intent(in) :: path
    logical, intent(in) :: append
    logical, intent(out) :: ok
    character(len=*), intent(inout) :: msg
    integer :: ios
    if (append) then
      open(newunit=log_unit, file=path, status='unknown', position='append', action='write', &
           iostat=ios, iomsg=msg)
    else
      open(newunit=log_unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
    end if
    ok = (ios == 0)
    if (.not. ok) log_unit = -1
  end subroutine log_open

  !> True once the log file is open.
  logical function log_is_open()
    log_is_open = (log_unit /= -1)
  end function log_is_open

  subroutine log_close()
    if (log_unit /= -1) close(log_unit)
    log_unit = -1
  end subroutine log_close

  !> Writes one line to standard output and the log.
  subroutine log_line(text)
    character(len=*), intent(in) :: text
    write(output_unit, '(a)') text
    flush(output_unit)
    if (log_unit /= -1) then
      write(log_unit, '(a)') text
      flush(log_unit)
    end if
  end subroutine log_line

  !> Writes one line to standard error and the log.
  subroutine log_error(text)
    character(len=*), intent(in) :: text
    write(error_unit, '(a)') text
    flush(error_unit)
    if (log_unit /= -1) then
      write(log_unit, '(a)') text
      flush(log_unit)
    end if
  end subroutine log_error
end module io_log
