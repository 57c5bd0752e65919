!> Wall-clock timers for the per-phase report.
module base_timers
  use base_kinds, only: wp, i8
  implicit none
  private
  public :: timer_t, wall_seconds

  !> Accumulating timer: `start` and `stop` add the interval to `total` (s).
  type :: timer_t
    real(wp) :: total = 0.0_wp
    real(wp) :: t0 = 0.0_wp
  contains
    procedure :: start => timer_start
    procedure :: stop => timer_stop
  end type timer_t

contains

  !> Seconds since an arbitrary fixed origin.
  function wall_seconds() result(t)
    real(wp) :: t
    integer(i8) :: count, rate
    call system_clock(count, rate)
    t = real(count, wp)/real(rate, wp)
  end function wall_seconds

  subroutine timer_start(this)
    class(timer_t), intent(inout) :: this
    this%t0 = wall_seconds()
  end subroutine timer_start

  subroutine timer_stop(this)
    class(timer_t), intent(inout) :: this
    this%total = this%total + (wall_seconds() - this%t0)
  end subroutine timer_stop
end module base_timers
