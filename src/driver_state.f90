!> The state of a run and the driver's shared services: stopping on bad
!> input (`refuse`), stopping on a runtime failure (`fatal`, which first
!> writes the state), frames and the integral quantities.
module driver_state
  use base_kinds, only: wp
  use base_strings, only: itoa
  use base_errors, only: error_t
  use base_timers, only: timer_t
  use base_random, only: rng_t
  use mesh_grid, only: grid_t
  use mesh_boundary, only: bc_t
  use material_table, only: material_t
  use material_mixed, only: mixed_t
  use lagrange_state, only: hydro_t, hydro_totals
  use io_input, only: config_t
  use io_log, only: log_close, log_line, log_error, log_is_open
  use io_output, only: output_t, output_frame, totals_t
  use io_gauges, only: gauges_t
  use io_restart, only: restart_registry_t
  use rezone_smooth, only: smooth_mobility_t
  implicit none
  private
  public :: run_t, run, refuse, refuse_one, totals, energy_drift, report_conservation, frame_out, fatal

  !> Everything a run holds.
  type :: run_t
    type(config_t) :: cfg
    type(grid_t) :: g
    type(hydro_t) :: h
    type(bc_t) :: bc
    type(material_t), allocatable :: mats(:)
    type(mixed_t) :: mx
    type(output_t) :: out
    type(gauges_t) :: gauges
    type(totals_t) :: tot
    real(wp) :: t = 0.0_wp, dt = 0.0_wp
    integer :: step = 0
    integer :: step_start = 0         !< first step of this run (after a restart)
    ! time-loop bookkeeping (restart state)
    real(wp) :: t_next_frame = 0.0_wp, t_next_gauge = 0.0_wp, t_next_dump = 0.0_wp
    integer :: steps_since_frame = 0
    type(rng_t) :: rng
    real(wp) :: rng_bits = 0.0_wp     !< rng state as stored in restarts
    type(restart_registry_t) :: reg
    character(len=256), allocatable :: dumps(:)   !< this segment's dumps, oldest first
    real(wp) :: step_wall = 0.0_wp, dump_wall = 0.0_wp
    logical :: restarting = .false.
    logical :: ready = .false.        !< state is complete enough to be written
    type(timer_t) :: t_setup, t_lagrange, t_euler, t_output, t_total
    ! Euler phase (only with &rezone mode other than 'none')
    real(wp), allocatable :: x0(:, :)       !< initial grid, the global rezone's target
    real(wp), allocatable :: quality(:)     !< work: cell quality for the triggers
    real(wp) :: t_next_euler = 0.0_wp       !< next Euler step by interval_time (restart state)
    integer :: n_euler = 0                  !< Euler steps so far (restart state)
    integer :: euler_cells = 0, euler_mof = 0, euler_mof_iterations = 0   !< this segment's totals
    real(wp) :: euler_ke = 0.0_wp           !< kinetic energy returned to internal energy, this segment
    real(wp) :: t_rezone_total = 0.0_wp     !< of t_euler, the rezone's part (s)
    type(smooth_mobility_t) :: mobility     !< how nodes may move in an LSSM rezone
  end type run_t

  type(run_t), save, target :: run

contains

  !> Ends the run before step 0: one ERROR line per problem, then a summary.
  subroutine refuse(problems, summary)
    character(len=*), intent(in) :: problems(:), summary
    integer :: i
    do i = 1, size(problems)
      call log_error('ERROR: '//trim(problems(i)))
    end do
    call log_error('ERROR: '//summary)
    stop 2
  end subroutine refuse

  !> `refuse` for a single problem (assignment truncates a long message
  !> safely; a typed array constructor does not in gfortran 12).
  subroutine refuse_one(problem, summary)
    character(len=*), intent(in) :: problem, summary
    character(len=1024) :: line(1)
    line(1) = problem
    call refuse(line, summary)
  end subroutine refuse_one

  subroutine totals(tot)
    type(totals_t), intent(inout) :: tot
    call hydro_totals(run%h, tot%mass, tot%momentum, tot%internal, tot%kinetic)
  end subroutine totals

  !> (E - E0 - W)/|E0|: total energy change not explained by boundary work.
  real(wp) function energy_drift()
    real(wp) :: e
    e = run%tot%internal + run%tot%kinetic
    energy_drift = (e - run%tot%energy_initial - run%tot%boundary_work)/ &
                   max(abs(run%tot%energy_initial), tiny(1.0_wp))
  end function energy_drift

  !> Writes a frame with each cell's material (the largest by volume in a
  !> mixed cell) and, with several materials, their volume fractions.
  subroutine frame_out(path, err)
    character(len=:), allocatable, intent(out) :: path
    type(error_t), allocatable, intent(inout) :: err
    integer :: nmat, c, k, s, m
    integer, allocatable :: cellmat(:)
    real(wp), allocatable :: vf(:, :)
    character(len=32), allocatable :: names(:)

    nmat = size(run%mats)
    allocate(cellmat(run%g%ncell))
    cellmat = run%h%mat
    if (nmat > 1) then
      allocate(vf(run%g%ncell, nmat), names(nmat))
      do m = 1, nmat
        names(m) = 'vf_'//run%mats(m)%name
        vf(:, m) = merge(1.0_wp, 0.0_wp, run%h%mat == m)
      end do
      do k = 1, run%mx%n
        c = run%mx%cell(k)
        do s = run%mx%start(k), run%mx%start(k + 1) - 1
          vf(c, run%mx%mat(s)) = run%mx%vf(s)
        end do
        cellmat(c) = maxloc(vf(c, :), 1)
      end do
    else
      allocate(vf(run%g%ncell, 0), names(0))
    end if
    call output_frame(run%out, run%g, run%h, cellmat, names, vf, run%t, run%step, run%tot, &
                      run%cfg%echo, path, err)
  end subroutine frame_out

  !> Ends the run with a message naming the place, the step and the problem.
  !> A run that has a state writes it first (as the last frame) for diagnosis.
  subroutine fatal(where, msg)
    character(len=*), intent(in) :: where, msg
    type(error_t), allocatable :: err
    character(len=:), allocatable :: path
    logical, save :: in_fatal = .false.

    call log_error('FATAL [rank 0, step '//itoa(run%step)//'] '//where//': '//msg)
    if (run%ready .and. .not. in_fatal) then
      in_fatal = .true.
      call totals(run%tot)
      call frame_out(path, err)
      if (.not. allocated(err)) call log_error('state at failure written to '//path)
    end if
    if (log_is_open()) call log_close()
    stop 1
  end subroutine fatal

  subroutine report_conservation(label)
    character(len=*), intent(in) :: label
    character(len=256) :: line
    call totals(run%tot)
    write(line, '("conservation (",a,"): mass ",es22.15,"  momentum ",3es12.4)') &
      label, run%tot%mass, run%tot%momentum
    call log_line(trim(line))
    write(line, '("  energy: internal ",es22.15,"  kinetic ",es22.15,"  total ",es22.15)') &
      run%tot%internal, run%tot%kinetic, run%tot%internal + run%tot%kinetic
    call log_line(trim(line))
    write(line, '("  boundary work ",es22.15,"  relative energy drift ",es10.3)') &
      run%tot%boundary_work, energy_drift()
    call log_line(trim(line))
  end subroutine report_conservation
end module driver_state
