!> A file of particle positions (`&particles shape = 'file'`): plain text,
!> one point per line, "x y z" or "x y z volume" (lengths and length^3 in the
!> deck's units, any Fortran list-directed real format), every line with the
!> same number of values; blank lines and lines starting with '#' are
!> skipped, and a UTF-8 byte-order mark at the start. A value must be a
!> finite number of magnitude below 1e30 (the deck's rule, checked on the
!> text: a number too large for a real must not be read), a line at most
!> 1024 characters. Without a volume column each particle gets the volume of its
!> host cell divided by per_cell^3 (the scene decides).
module io_points_file
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use base_kinds, only: wp
  use base_strings, only: itoa, lower, number_ok
  use base_errors, only: error_no_memory, error_t, error_set
  implicit none
  private
  public :: points_file_read

  !> Longest line read, and one more (a line that fills it is too long).
  integer, parameter :: max_len = 1025
  character(len=*), parameter :: bom = char(239)//char(187)//char(191)

contains

  !> Reads the points x(3, n) and, when the file gives them, their volumes
  !> vol(n) (else vol is allocated with size 0). Every value must be finite,
  !> every volume > 0, and there must be at least one point.
  subroutine points_file_read(path, x, vol, err)
    character(len=*), intent(in) :: path
    real(wp), allocatable, intent(out) :: x(:, :), vol(:)
    type(error_t), allocatable, intent(inout) :: err
    character(len=max_len) :: line
    character(len=256) :: msg
    real(wp) :: v(4)
    integer :: u, ios, pass, n, ncol, nline, nc
    logical :: there

    inquire(file=path, exist=there)
    if (.not. there) then
      call error_set(err, 'points_file_read', 'file of points '''//path//''' does not exist')
      return
    end if
    open(newunit=u, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call error_set(err, 'points_file_read', 'cannot open '''//path//''': '//trim(msg))
      return
    end if
    ncol = 0
    ! pass 1 counts and checks, pass 2 stores
    do pass = 1, 2
      rewind(u)
      n = 0
      nline = 0
      do
        read(u, '(a)', iostat=ios, iomsg=msg) line
        if (ios < 0) exit
        nline = nline + 1
        if (ios /= 0) then
          call fail(trim(msg))
          return
        end if
        if (nline == 1 .and. line(1:3) == bom) line = line(4:)
        if (len_trim(line) == max_len) then
          call fail('longer than '//itoa(max_len - 1)//' characters')
          return
        end if
        line = adjustl(line)
        if (len_trim(line) == 0 .or. line(1:1) == '#') cycle
        nc = columns(line)
        if (nc /= 3 .and. nc /= 4) then
          call fail('expected 3 values (x y z) or 4 (x y z volume), found '//itoa(nc))
          return
        end if
        if (ncol == 0) ncol = nc
        if (nc /= ncol) then
          call fail('this line has '//itoa(nc)//' values, the first point''s has '//itoa(ncol))
          return
        end if
        if (.not. numbers_ok(line)) then
          call fail('a value is not finite or of magnitude 1e30 or more')
          return
        end if
        read(line, *, iostat=ios) v(1:nc)
        if (ios /= 0) then
          call fail('cannot read '//itoa(nc)//' numbers from '''//trim(line)//'''')
          return
        end if
        if (.not. all(ieee_is_finite(v(1:nc)))) then
          call fail('a value is not finite')
          return
        end if
        if (nc == 4) then
          if (.not. v(4) > 0.0_wp) then
            call fail('the volume must be > 0')
            return
          end if
        end if
        n = n + 1
        if (pass == 2) then
          x(:, n) = v(1:3)
          if (ncol == 4) vol(n) = v(4)
        end if
      end do
      if (pass == 1) then
        if (n == 0) then
          close(u)
          call error_set(err, 'points_file_read', 'file of points '''//path//''' has no point')
          return
        end if
        allocate(x(3, n), vol(merge(n, 0, ncol == 4)), stat=ios, errmsg=msg)
        if (ios /= 0) then
          close(u)
          call error_set(err, 'points_file_read', error_no_memory(itoa(n)//' points'))
          return
        end if
      end if
    end do
    close(u)

  contains

    subroutine fail(what)
      character(len=*), intent(in) :: what
      close(u)
      call error_set(err, 'points_file_read', 'file of points '''//path//''', line '//itoa(nline)//': '//what)
    end subroutine fail
  end subroutine points_file_read

  !> Every blank- or comma-separated field of the line passes the deck's
  !> number rule (`number_ok`).
  pure logical function numbers_ok(line)
    character(len=*), intent(in) :: line
    integer :: i, j
    numbers_ok = .true.
    i = 1
    do while (i <= len_trim(line))
      if (index(' ,'//achar(9), line(i:i)) > 0) then
        i = i + 1
        cycle
      end if
      j = i
      do while (j < len_trim(line))
        if (index(' ,'//achar(9), line(j + 1:j + 1)) > 0) exit
        j = j + 1
      end do
      numbers_ok = numbers_ok .and. number_ok(lower(line(i:j)))
      i = j + 1
    end do
  end function numbers_ok

  !> The number of blank- or comma-separated fields of a line.
  pure integer function columns(line) result(n)
    character(len=*), intent(in) :: line
    integer :: i
    logical :: in_field, sep
    n = 0
    in_field = .false.
    do i = 1, len_trim(line)
      sep = line(i:i) == ' ' .or. line(i:i) == ',' .or. line(i:i) == achar(9)
      if (.not. sep .and. .not. in_field) n = n + 1
      in_field = .not. sep
    end do
  end function columns
end module io_points_file
