!> The driver: reads the deck, builds the scene, runs the time loop, and owns
!> all input, output and the decision to stop.
module driver
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_timers, only: timer_t, wall_seconds
  use base_random, only: rng_t, rng_seed, rng_uniform
  use eos_factory, only: eos_create
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_volume, hex_subcell_volumes
  use mesh_boundary, only: bc_t, bc_init, bc_constrain
  use material_table, only: material_t, material_index_cells, material_eval_eos
  use lagrange_state, only: hydro_t, hydro_allocate, hydro_totals
  use lagrange_integrator, only: lagrange_step
  use io_input, only: config_t, input_read
  use io_log, only: log_open, log_close, log_line, log_error, log_is_open
  use io_output, only: output_t, output_frame, totals_t
  use io_gauges, only: gauges_t, gauges_open, gauges_write, gauges_close
  use io_hdf5, only: hdf5_start, hdf5_stop
  implicit none
  private
  public :: driver_run

  !> Everything a run holds.
  type :: run_t
    type(config_t) :: cfg
    type(grid_t) :: g
    type(hydro_t) :: h
    type(bc_t) :: bc
    type(material_t), allocatable :: mats(:)
    type(output_t) :: out
    type(gauges_t) :: gauges
    type(totals_t) :: tot
    real(wp) :: t = 0.0_wp, dt = 0.0_wp
    integer :: step = 0
    logical :: ready = .false.        !< state is complete enough to be written
    type(timer_t) :: t_setup, t_lagrange, t_output, t_total
  end type run_t

  type(run_t), save, target :: run

contains

  !> Runs the deck at `deck_path` to completion, or stops with a message.
  subroutine driver_run(deck_path)
    character(len=*), intent(in) :: deck_path
    type(error_t), allocatable :: err

    call run%t_total%start()
    call run%t_setup%start()
    call read_deck(deck_path)
    call open_outputs()
    call build_scene()
    call run%t_setup%stop()
    call report_conservation('initial')
    call write_frame()
    call time_loop()
    call write_frame()
    call gauges_close(run%gauges)
    call run%t_total%stop()
    call report_end()
    call hdf5_stop(err)
    call log_close()
  end subroutine driver_run

  ! ------------------------------------------------------------ set-up

  subroutine read_deck(path)
    character(len=*), intent(in) :: path
    character(len=1024), allocatable :: problems(:)
    integer :: i

    call input_read(path, run%cfg, problems)
    if (size(problems) > 0) then
      do i = 1, size(problems)
        call log_error('ERROR: '//trim(problems(i)))
      end do
      call log_error('ERROR: the deck has '//itoa(size(problems))// &
                     ' problem(s); nothing was run')
      error stop 2
    end if
  end subroutine read_deck

  subroutine open_outputs()
    character(len=:), allocatable :: dir, base
    character(len=512) :: msg
    integer :: stat
    logical :: ok
    type(error_t), allocatable :: err

    dir = trim(run%cfg%out_dir)
    base = trim(run%cfg%out_name)
    call execute_command_line('mkdir -p "'//dir//'"', exitstat=stat)
    if (stat /= 0) call fatal('open_outputs', 'cannot create the output directory '''//dir//'''')
    msg = ''
    call log_open(dir//'/'//base//'.log', ok, msg)
    if (.not. ok) call fatal('open_outputs', 'cannot open the log: '//trim(msg))
    call log_line('lsalepm: '//trim(run%cfg%title))
    call log_line('deck: '//run%cfg%deck_path)
    call log_line('resolved input:')
    call log_line(run%cfg%echo)
    run%out%dir = dir
    run%out%name = base
    call hdf5_start(err)
    if (allocated(err)) call fatal(err%where, err%msg)
    call gauges_open(run%gauges, dir//'/'//base//'_gauges.txt', &
                     run%cfg%gauges(:, 1:run%cfg%ngauge), err)
    if (allocated(err)) call fatal(err%where, err%msg)
  end subroutine open_outputs

  !> Grid, materials, initial state from the regions, energy sources, nodal
  !> masses (first term of Eq. 16) and boundary lists.
  subroutine build_scene()
    type(error_t), allocatable :: err
    integer :: m, c, n, a, n0, r, s, ijk(3)
    real(wp) :: xn(3, 8), xc(3), vsub(8), h(3), rv
    type(rng_t) :: rng

    associate (cfg => run%cfg, g => run%g, hy => run%h)
      call grid_init_box(g, cfg%ni, cfg%nj, cfg%nk, cfg%xmin, cfg%xmax, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      call hydro_allocate(hy, g%ncell, g%nnode, err)
      if (allocated(err)) call fatal(err%where, err%msg)

      allocate(run%mats(size(cfg%materials)))
      do m = 1, size(cfg%materials)
        run%mats(m)%name = trim(cfg%materials(m)%name)
        call eos_create(cfg%materials(m)%eos, cfg%materials(m)%par, run%mats(m)%eos, err)
        if (allocated(err)) call fatal('&material '//run%mats(m)%name, err%msg)
      end do

      ! regions in deck order; a later region overrides an earlier one
      hy%mat = 0
      do c = 1, g%ncell
        call g%gather(c, g%x, xn)
        hy%vol(c) = hex_volume(xn)
        xc = sum(xn, 2)/8.0_wp
        do r = 1, size(cfg%regions)
          if (.not. inside(cfg%regions(r), xc)) cycle
          associate (rg => cfg%regions(r))
            hy%mat(c) = rg%imat
            hy%rho(c) = rg%density
            if (rg%energy >= 0.0_wp) then
              hy%e(c) = rg%energy
            else
              hy%e(c) = run%mats(rg%imat)%eos%energy(rg%density, rg%pressure)
            end if
          end associate
        end do
        if (hy%mat(c) == 0) call fatal('build_scene', 'cell '//itoa(c)// &
          ' is in no &region; add a region with shape = ''all'' first')
      end do
      do n = 1, g%nnode
        do r = 1, size(cfg%regions)
          if (inside(cfg%regions(r), g%x(:, n))) hy%u(:, n) = cfg%regions(r)%velocity
        end do
      end do
      if (cfg%velocity_noise > 0.0_wp) then
        call rng_seed(rng, cfg%seed)
        do n = 1, g%nnode
          do a = 1, 3
            rv = rng_uniform(rng)
            hy%u(a, n) = hy%u(a, n) + cfg%velocity_noise*(2.0_wp*rv - 1.0_wp)
          end do
        end do
      end if
      hy%mass = hy%rho*hy%vol

      ! energy sources: added to the cell that contains the point
      h = (cfg%xmax - cfg%xmin)/real([cfg%ni, cfg%nj, cfg%nk], wp)
      do s = 1, size(cfg%sources)
        ijk = int((cfg%sources(s)%position - cfg%xmin)/h) + 1
        ijk = max(1, min([cfg%ni, cfg%nj, cfg%nk], ijk))
        c = ijk(1) + cfg%ni*((ijk(2) - 1) + cfg%nj*(ijk(3) - 1))
        hy%e(c) = hy%e(c) + cfg%sources(s)%energy/hy%mass(c)
        call log_line('source '//itoa(s)//': energy '//rtoa(cfg%sources(s)%energy)// &
                      ' deposited in cell '//itoa(c))
      end do

      ! nodal mass from subcell masses, Eq. (16) first term
      hy%mnode = 0.0_wp
      do c = 1, g%ncell
        n0 = g%node0(c)
        call g%gather(c, g%x, xn)
        call hex_subcell_volumes(xn, vsub)
        do a = 1, 8
          n = n0 + g%corner_offset(a)
          hy%mnode(n) = hy%mnode(n) + hy%rho(c)*vsub(a)
        end do
      end do

      call material_index_cells(run%mats, hy%mat, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      call material_eval_eos(run%mats, hy%rho, hy%e, hy%p, hy%cs)

      run%bc%kind = cfg%bc_kind
      run%bc%velocity = cfg%bc_velocity
      run%bc%pressure = cfg%bc_pressure
      call bc_init(run%bc, g, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      ! the boundary conditions hold from t = 0
      call bc_constrain(run%bc, hy%u)
    end associate
    call totals(run%tot)
    run%tot%energy_initial = run%tot%internal + run%tot%kinetic
    run%ready = .true.
    call log_line('grid: '//itoa(run%g%ni)//' x '//itoa(run%g%nj)//' x '//itoa(run%g%nk)// &
                  ' cells, '//itoa(run%g%nnode)//' nodes, '//itoa(size(run%mats))//' material(s)')
  end subroutine build_scene

  !> True if point p lies in the region's shape.
  pure logical function inside(rg, p)
    use io_input, only: region_cfg_t
    type(region_cfg_t), intent(in) :: rg
    real(wp), intent(in) :: p(3)
    real(wp) :: d(3)
    select case (trim(rg%shape))
    case ('all')
      inside = .true.
    case ('box')
      inside = all(p >= rg%lo) .and. all(p <= rg%hi)
    case ('sphere')
      inside = sum((p - rg%center)**2) <= rg%radius**2
    case ('cylinder')
      d = p - rg%center
      d(rg%axis) = 0.0_wp
      inside = sum(d**2) <= rg%radius**2 .and. p(rg%axis) >= rg%lo(rg%axis) .and. &
               p(rg%axis) <= rg%hi(rg%axis)
    case default
      inside = .false.
    end select
  end function inside

  ! ------------------------------------------------------------ time loop

  subroutine time_loop()
    real(wp) :: dt_cap, work, t_next_frame, t_next_gauge, wall_last, wall_now, eps_t
    integer :: bad_cell, steps_since_frame
    logical :: last

    eps_t = 1.0e-12_wp*run%cfg%t_end
    t_next_frame = huge(1.0_wp)
    if (run%cfg%frame_dt > 0.0_wp) t_next_frame = run%cfg%frame_dt
    t_next_gauge = 0.0_wp
    call gauge_output(t_next_gauge)
    wall_last = wall_seconds()
    steps_since_frame = 0
    do while (run%t < run%cfg%t_end - eps_t .and. run%step < run%cfg%max_steps)
      ! the step the controller allows: growth limit, dt_max, end time, frames
      if (run%step == 0) then
        dt_cap = run%cfg%hydro%dt_max
        if (run%cfg%dt_init > 0.0_wp) dt_cap = min(dt_cap, run%cfg%dt_init)
      else
        dt_cap = min(run%cfg%hydro%dt_growth*run%dt, run%cfg%hydro%dt_max)
      end if
      dt_cap = min(dt_cap, run%cfg%t_end - run%t, t_next_frame - run%t)

      call run%t_lagrange%start()
      call lagrange_step(run%g, run%h, run%bc, run%mats, run%cfg%hydro, dt_cap, work, bad_cell)
      call run%t_lagrange%stop()
      if (bad_cell /= 0) call fatal('lagrange_step', 'cell '//itoa(bad_cell)// &
        ' has a non-positive volume (tangled grid) at t = '//rtoa(run%t))
      if (dt_cap < run%cfg%dt_min) call fatal('time_loop', 'time step collapsed to '// &
        rtoa(dt_cap)//' (dt_min = '//rtoa(run%cfg%dt_min)//')')
      run%dt = dt_cap
      run%t = run%t + run%dt
      run%step = run%step + 1
      run%tot%boundary_work = run%tot%boundary_work + work
      last = .not. (run%t < run%cfg%t_end - eps_t .and. run%step < run%cfg%max_steps)

      call gauge_output(t_next_gauge)
      steps_since_frame = steps_since_frame + 1
      if (.not. last .and. (run%t >= t_next_frame - eps_t .or. &
          (run%cfg%frame_steps > 0 .and. steps_since_frame >= run%cfg%frame_steps))) then
        call write_frame()
        steps_since_frame = 0
        do while (t_next_frame <= run%t + eps_t)
          t_next_frame = t_next_frame + run%cfg%frame_dt
        end do
      end if
      wall_now = wall_seconds()
      if ((run%cfg%progress_steps > 0 .and. mod(run%step, max(run%cfg%progress_steps, 1)) == 0) .or. &
          wall_now - wall_last >= run%cfg%progress_seconds .or. last) then
        call progress()
        wall_last = wall_now
      end if
    end do
  end subroutine time_loop

  subroutine gauge_output(t_next)
    real(wp), intent(inout) :: t_next
    if (run%gauges%n == 0) return
    if (run%t < t_next .and. run%t < run%cfg%t_end) return
    call run%t_output%start()
    call gauges_write(run%gauges, run%g, run%h, run%t)
    call run%t_output%stop()
    if (run%cfg%gauge_dt > 0.0_wp) then
      do while (t_next <= run%t)
        t_next = t_next + run%cfg%gauge_dt
      end do
    end if
  end subroutine gauge_output

  !> One progress line: step, time, dt, wall time, estimated time left, and
  !> the energy balance. A NaN anywhere in the state shows up here.
  subroutine progress()
    real(wp) :: wall, left, drift
    character(len=256) :: line

    call totals(run%tot)
    drift = energy_drift()
    if (ieee_is_nan(drift)) call fatal('time_loop', 'the state has a NaN (energy balance is NaN)')
    wall = wall_seconds() - run%t_total%t0
    left = 0.0_wp
    if (run%t > 0.0_wp) left = wall*(run%cfg%t_end - run%t)/run%t
    write(line, '("step ",i8,"  t ",es12.5,"  dt ",es10.3,"  wall ",f9.2," s  left ",f9.2, &
      &" s  energy drift ",es10.2)') run%step, run%t, run%dt, wall, left, drift
    call log_line(trim(line))
  end subroutine progress

  ! ------------------------------------------------------------ reports

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

  subroutine report_end()
    character(len=256) :: line
    real(wp) :: rate

    call report_conservation('final')
    rate = 0.0_wp
    if (run%t_lagrange%total > 0.0_wp) &
      rate = real(run%g%ncell, wp)*real(run%step, wp)/run%t_lagrange%total
    write(line, '("timers [s]: setup ",f9.3,"  lagrange ",f9.3,"  output ",f9.3,"  total ",f9.3)') &
      run%t_setup%total, run%t_lagrange%total, run%t_output%total, run%t_total%total
    call log_line(trim(line))
    write(line, '("throughput: ",es10.3," cell-cycles/s over ",i0," steps")') rate, run%step
    call log_line(trim(line))
    call log_line('outputs: '//run%out%dir//'/'//run%out%name//'.xdmf (ParaView), '// &
                  run%out%dir//'/'//run%out%name//'.log')
    call log_line('done: t = '//rtoa(run%t)//' after '//itoa(run%step)//' steps')
  end subroutine report_end

  subroutine write_frame()
    type(error_t), allocatable :: err
    character(len=:), allocatable :: path
    call run%t_output%start()
    call totals(run%tot)
    call output_frame(run%out, run%g, run%h, run%t, run%step, run%tot, run%cfg%echo, path, err)
    call run%t_output%stop()
    if (allocated(err)) call fatal(err%where, err%msg)
    call log_line('frame '//path//' at t = '//rtoa(run%t))
  end subroutine write_frame

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
      call output_frame(run%out, run%g, run%h, run%t, run%step, run%tot, run%cfg%echo, path, err)
      if (.not. allocated(err)) call log_error('state at failure written to '//path)
    end if
    if (log_is_open()) call log_close()
    error stop 1
  end subroutine fatal

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write(buf, '(i0)') i
    s = trim(buf)
  end function itoa

  function rtoa(x) result(s)
    real(wp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write(buf, '(es14.7)') x
    s = trim(adjustl(buf))
  end function rtoa
end module driver
