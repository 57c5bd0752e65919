!> The run log: every line goes to standard output (errors to standard error)
!> and to the log file, if one is open. The log is an object the driver
!> holds and passes; no module keeps it. `log_identity` writes the run's
!> identity (code version, build type, compiler, HDF5 library, date, host,
!> OpenMP threads), with which every log starts.
module io_log
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, compiler_version
  use base_strings, only: itoa
  !$ use omp_lib, only: omp_get_max_threads
  implicit none
  private
  public :: log_t, log_open, log_close, log_line, log_error, log_identity, host_name

  !> An open (or not yet open) log file.
  type :: log_t
    integer :: unit = -1
    logical :: quiet = .false.   !< write nothing (an MPI rank other than 0)
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
    if (log%quiet) return
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
    if (log%quiet) return
    write(error_unit, '(a)') text
    flush(error_unit)
    if (log%unit /= -1) then
      write(log%unit, '(a)') text
      flush(log%unit)
    end if
  end subroutine log_error

  !> Writes the run's identity: code version and build type (both from
  !> base_build, passed in), compiler, HDF5 library version (passed in), the date and time
  !> the run started (with the UTC offset), the host name and the OpenMP
  !> thread count (1 in a build without OpenMP).
  subroutine log_identity(log, code_version, build_type, hdf5_text)
    type(log_t), intent(in) :: log
    character(len=*), intent(in) :: code_version, build_type, hdf5_text
    character(len=8) :: date
    character(len=10) :: time
    character(len=5) :: zone
    integer :: nthreads

    nthreads = 1
    !$ nthreads = omp_get_max_threads()
    call date_and_time(date, time, zone)
    call log_line(log, 'run: lsalepm '//code_version//' ('//build_type//' build), compiler '// &
                  compiler_version()//', HDF5 '//trim(hdf5_text))
    call log_line(log, 'run: started '//date(1:4)//'-'//date(5:6)//'-'//date(7:8)//' '//time(1:2)//':'// &
                  time(3:4)//':'//time(5:6)//' '//zone//' on host '//host_name()//', '// &
                  itoa(nthreads)//' OpenMP thread(s)')
  end subroutine log_identity

  !> The machine's host name: /proc/sys/kernel/hostname, else the HOSTNAME
  !> environment variable, else 'unknown' (no shell is run).
  function host_name() result(name)
    character(len=:), allocatable :: name
    character(len=256) :: buf
    integer :: u, ios, n
    buf = ''
    open(newunit=u, file='/proc/sys/kernel/hostname', status='old', action='read', iostat=ios)
    if (ios == 0) then
      read(u, '(a)', iostat=ios) buf
      close(u)
      if (ios /= 0) buf = ''
    end if
    if (len_trim(buf) == 0) then
      call get_environment_variable('HOSTNAME', buf, length=n, status=ios)
      if (ios /= 0) buf = ''
    end if
    name = trim(adjustl(buf))
    if (len(name) == 0) name = 'unknown'
  end function host_name
end module io_log
