!> Error values returned by library routines.
!>
!> A library routine reports failure through an allocatable `error_t` argument:
!> unallocated means success. Library code never stops the program; only the
!> driver decides to abort (see `src/driver_fatal`).
module base_errors
  implicit none
  private
  public :: error_t, error_set

  !> One error: where it happened and what went wrong, in one line.
  type :: error_t
    character(len=:), allocatable :: where
    character(len=:), allocatable :: msg
  end type error_t

contains

  !> Allocates `err` with the given place and message.
  subroutine error_set(err, where, msg)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in) :: where, msg
    if (allocated(err)) deallocate(err)
    allocate(err)
    err%where = where
    err%msg = msg
  end subroutine error_set
end module base_errors
