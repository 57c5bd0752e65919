!> What every package's configuration shares: the list of problems a deck
!> has (one line each, naming the group, the variable, the value and what is
!> allowed), the wording of those lines, and the exact comparison of two
!> configurations for a restart.
!>
!> Each package has a config type for its namelist group, with the defaults
!> stated once (the type's initial values), and a read / validate / echo /
!> compare-with-restart life cycle built from these helpers. The deck reader
!> (`io_deck`) only finds the groups and hands each its text.
module base_config
  use base_kinds, only: wp, i8
  use base_strings, only: itoa
  implicit none
  private
  public :: max_line, no_echo, problem_add, problem_bad, problem_badi, problem_nml, problem_long, diff_i, diff_r, diff_s, name_index

  !> Length of one problem line (and of one deck line).
  integer, parameter :: max_line = 1024

  !> The echo unit of a reader that should not echo (NEWUNIT never returns
  !> -1, F2008 9.5.6.12).
  integer, parameter :: no_echo = -1

contains

  !> Appends a line (assigned first: gfortran 12 overruns a typed array
  !> constructor given a longer string).
  subroutine problem_add(list, line)
    character(len=max_line), allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: line
    character(len=max_line) :: l
    if (.not. allocated(list)) list = [character(len=max_line) ::]
    l = line
    list = [list, l]
  end subroutine problem_add

  !> "&group: var = value rule" for a real value.
  subroutine problem_bad(list, group, var, value, rule)
    character(len=max_line), allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: group, var, rule
    real(wp), intent(in) :: value
    character(len=32) :: buf
    write(buf, '(g0)') value
    call problem_add(list, '&'//group//': '//var//' = '//trim(buf)//' '//rule)
  end subroutine problem_bad

  !> "&group: var = value rule" for an integer value.
  subroutine problem_badi(list, group, var, value, rule)
    character(len=max_line), allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: group, var, rule
    integer, intent(in) :: value
    call problem_add(list, '&'//group//': '//var//' = '//itoa(value)//' '//rule)
  end subroutine problem_badi

  !> The problem of a failed namelist read. gfortran reports a bad value just
  !> before `/` or a missing `/` as end-of-file; the group is known to be
  !> present here, so end-of-file is an error too.
  subroutine problem_nml(list, path, group, ios, msg)
    character(len=max_line), allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: path, group, msg
    integer, intent(in) :: ios
    if (ios < 0) then
      call problem_add(list, trim(path)//': &'//group//': end of file while reading the group '// &
                       '(missing ''/'' or a bad value before it)')
    else
      call problem_add(list, trim(path)//': &'//group//': '//trim(msg))
    end if
  end subroutine problem_nml

  !> The index of `name` in `names` (the last one if repeated), 0 if absent.
  pure integer function name_index(names, name) result(m)
    character(len=*), intent(in) :: names(:), name
    do m = size(names), 1, -1
      if (names(m) == name) return
    end do
    m = 0
  end function name_index

  !> A string that fills its variable was most likely cut short by the
  !> read: refused, saying how long it may be.
  subroutine problem_long(list, group, var, value)
    character(len=max_line), allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: group, var, value
    if (len_trim(value) < len(value)) return
    call problem_add(list, '&'//group//': '//var//' is too long (at most '//itoa(len(value) - 1)//' characters)')
  end subroutine problem_long

  !> A restart-compatibility line if two integers differ.
  subroutine diff_i(changes, what, a, b)
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    character(len=*), intent(in) :: what
    integer, intent(in) :: a, b
    if (a /= b) call problem_add(changes, what//' changed from '//itoa(a)//' to '//itoa(b))
  end subroutine diff_i

  !> Exact comparison (of the bits): the deck echo stored in a restart file
  !> prints 17 digits, so it reads back as the very values first read.
  subroutine diff_r(changes, what, a, b)
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: a(:), b(:)
    character(len=64) :: buf
    if (all(transfer(a, 1_i8, size(a)) == transfer(b, 1_i8, size(b)))) return
    write(buf, '(g0)') b(1)
    call problem_add(changes, what//' changed (new first value '//trim(buf)//')')
  end subroutine diff_r

  !> A restart-compatibility line if two strings differ.
  subroutine diff_s(changes, what, a, b)
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    character(len=*), intent(in) :: what, a, b
    if (a /= b) call problem_add(changes, what//' changed')
  end subroutine diff_s
end module base_config
