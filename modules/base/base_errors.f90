!> Error values returned by library routines.
!>
!> A library routine reports failure through an allocatable `error_t` argument:
!> unallocated means success. Library code never stops the program; errors
!> travel up to the driver, which alone ends the run (`driver_halt`), with the
!> exit status of the error's category.
module base_errors
  implicit none
  private
  public :: error_t, error_set, error_no_memory, error_is_no_memory, ERR_RUNTIME, ERR_INPUT, ERR_IO, error_exit_status

  !> Categories: a failure of the computation (tangled cell, NaN, dt
  !> collapse, allocation), a mistake in the user's input (deck, restart file
  !> that does not fit the deck), a failure to read or write a file.
  integer, parameter :: ERR_RUNTIME = 1, ERR_INPUT = 2, ERR_IO = 3

  !> One error: where it happened and what went wrong, in one line.
  type :: error_t
    character(len=:), allocatable :: where
    character(len=:), allocatable :: msg
    integer :: category = ERR_RUNTIME
    integer :: rank = 0                  !< the MPI rank where it happened
  end type error_t

contains

  !> Allocates `err` with the given place, message and (default runtime)
  !> category.
  subroutine error_set(err, where, msg, category)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in) :: where, msg
    integer, intent(in), optional :: category
    if (allocated(err)) deallocate(err)
    err = error_t(where=where, msg=msg)
    if (present(category)) err%category = category
  end subroutine error_set

  !> The message of a failed ALLOCATE of `what` (e.g. 'the hydro state
  !> (3375000 cells, 2.1 GiB)'): 'out of memory: cannot allocate '//what.
  !> The ALLOCATE's own errmsg is not shown: gfortran (12 at least) gives
  !> every failed allocation the text "Attempt to allocate an allocated
  !> object", which would call an out-of-memory failure a bug (the stat,
  !> 5014, is the same for both). This code allocates only unallocated
  !> arrays, so a failed allocation is memory (or address space, `ulimit
  !> -v`) running out.
  pure function error_no_memory(what) result(msg)
    character(len=*), intent(in) :: what
    character(len=:), allocatable :: msg
    msg = 'out of memory: cannot allocate '//what
  end function error_no_memory

  !> Whether err is memory running out (`error_no_memory`'s message, on
  !> this rank or, agreed, on another).
  pure logical function error_is_no_memory(err)
    type(error_t), intent(in) :: err
    error_is_no_memory = .false.
    if (allocated(err%msg)) error_is_no_memory = index(err%msg, 'out of memory') == 1
  end function error_is_no_memory

  !> The documented exit status of a category: 1 runtime failure, 2 bad
  !> input, 4 I/O failure (3 is the wall-time stop, not an error).
  pure integer function error_exit_status(category) result(status)
    integer, intent(in) :: category
    select case (category)
    case (ERR_INPUT); status = 2
    case (ERR_IO); status = 4
    case default; status = 1
    end select
  end function error_exit_status
end module base_errors
