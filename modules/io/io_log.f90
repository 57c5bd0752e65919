!> The run log: every line goes to standard output (errors to standard error)
!> and to the log file, if one is open. The log is an object the driver
!> holds and passes; no module keeps it.
module io_log
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
  implicit none
  private
  public :: log_t, log_open, log_close, log_line, log_error

  !> An open (or not yet open) log file.
  type :: log_t
    integer :: unit = -1
  end type log_t

contains

  !> Opens the log file at path, replacing it or (append) adding to it;
  !> returns a message on failure.
  subroutine log_open(log, path, append, ok, msg)
    type(log_t), intent(inout) :: log
    character(len=*), intent(in) :: path
    logical, intent(in) :: append
    logical, intent(out) :: ok
    character(len=*), intent(inout) :: msg
    integer :: ios
    if (append) then
      open(newunit=log%unit, file=path, status='unknown', position='append', action='write', &
           iostat=ios, iomsg=msg)
    else
      open(newunit=log%unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
    end if
    ok = (ios == 0)
    if (.not. ok) log%unit = -1
  end subroutine log_open

  subroutine log_close(log)
    type(log_t), intent(inout) :: log
    if (log%unit /= -1) close(log%unit)
    log%unit = -1
  end subroutine log_close

  !> Writes one line to standard output and the log.
  subroutine log_line(log, text)
    type(log_t), intent(in) :: log
    character(len=*), intent(in) :: text
    write(output_unit, '(a)') text
    flush(output_unit)
    if (log%unit /= -1) then
      write(log%unit, '(a)') text
      flush(log%unit)
    end if
  end subroutine log_line

  !> Writes one line to standard error and the log.
  subroutine log_error(log, text)
    type(log_t), intent(in) :: log
    character(len=*), intent(in) :: text
    write(error_unit, '(a)') text
    flush(error_unit)
    if (log%unit /= -1) then
      write(log%unit, '(a)') text
      flush(log%unit)
    end if
  end subroutine log_error
end module io_log
