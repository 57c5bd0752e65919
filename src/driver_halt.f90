!> The one place that ends a run. Every stop goes through `halt` with a
!> documented exit status (0 done, 1 runtime failure, 2 bad input, 3
!> wall-time limit reached after a restart dump, 4 I/O failure), so that
!> with several ranks it can become one collective end; any other end of a
!> run (a Fortran runtime error: a bug) exits with 5 (`base_exit`).
module driver_halt
  use base_errors, only: error_exit_status, ERR_INPUT
  use io_log, only: log_t, log_error, log_close
  use base_exit, only: exit_planned
  use parallel_comm, only: parallel_stop, parallel_rank
  implicit none
  private
  public :: halt, refuse, EXIT_WALL_TIME

  integer, parameter :: EXIT_WALL_TIME = 3

contains

  !> Closes the log and ends the program with exit status `status`.
  subroutine halt(log, status)
    type(log_t), intent(inout) :: log
    integer, intent(in) :: status
    logical :: root
    call log_close(log)
    call exit_planned()
    ! (every rank halts together: after a refusal every rank found the same
    ! problems, and failures are agreed first, `driver_parallel`)
    root = parallel_rank() == 0
    call parallel_stop()
    ! Rank 0 alone carries the status: mpirun ends the job on the first
    ! non-zero exit, and an other rank's could cut off rank 0's messages
    ! still on their way (seen: a refusal printed by no rank).
    if (.not. root) stop
    ! F2008 wants a constant stop code
    select case (status)
    case (0); stop
    case (1); stop 1
    case (2); stop 2
    case (3); stop 3
    case (4); stop 4
    case default; stop 1
    end select
  end subroutine halt

  !> Ends the run before step 0: one ERROR line per problem, then a summary
  !> (exit status of bad input).
  subroutine refuse(log, problems, summary)
    type(log_t), intent(inout) :: log
    character(len=*), intent(in) :: problems(:), summary
    integer :: i
    do i = 1, size(problems)
      call log_error(log, 'ERROR: '//trim(problems(i)))
    end do
    call log_error(log, 'ERROR: '//summary)
    call halt(log, error_exit_status(ERR_INPUT))
  end subroutine refuse
end module driver_halt
