!> The driver: reads the deck, builds the scene, runs the time loop, and owns
!> all input, output and the decision to stop.
module driver
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use base_kinds, only: wp, i8
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t
  use base_timers, only: timer_t, wall_seconds
  use base_random, only: rng_t, rng_seed, rng_uniform
  use eos_factory, only: eos_create
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_volume, hex_subcell_volumes
  use mesh_boundary, only: bc_t, bc_init, bc_constrain
  use material_table, only: material_t, material_index_cells, material_eval_eos
  use material_mixed, only: mixed_t, mixed_allocate, mixed_cell_state
  use lagrange_state, only: hydro_t, hydro_allocate, hydro_totals
  use lagrange_integrator, only: lagrange_step
  use io_input, only: config_t, input_read, input_state_changes
  use io_log, only: log_open, log_close, log_line, log_error, log_is_open
  use io_output, only: output_t, output_frame, totals_t
  use io_gauges, only: gauges_t, gauges_open, gauges_write, gauges_close
  use io_hdf5, only: hdf5_start, hdf5_stop
  use io_restart, only: restart_registry_t, restart_write, restart_read, restart_read_deck
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
    run%restarting = len_trim(run%cfg%restart_from) > 0
    if (run%restarting) call check_restart_deck()
    call open_outputs()
    call build_scene()
    call register_restart()
    if (run%restarting) then
      call read_restart()
    else
      run%t_next_frame = huge(1.0_wp)
      if (run%cfg%frame_dt > 0.0_wp) run%t_next_frame = run%cfg%frame_dt
      run%t_next_dump = huge(1.0_wp)
      if (run%cfg%dump_dt > 0.0_wp) run%t_next_dump = run%cfg%dump_dt
      call report_conservation('initial')
      call write_frame()
      call gauge_output()
    end if
    call run%t_setup%stop()
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

    call input_read(path, run%cfg, problems)
    if (size(problems) > 0) call refuse(problems, 'the deck has '//itoa(size(problems))// &
                                        ' problem(s); nothing was run')
  end subroutine read_deck

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

  !> A restart may change time, output, dump and numerical settings, but not
  !> what the state depends on: compare the deck stored in the restart file
  !> with this one and refuse, naming each changed variable.
  subroutine check_restart_deck()
    type(error_t), allocatable :: err
    character(len=:), allocatable :: text, tmp
    character(len=1024), allocatable :: problems(:)
    type(config_t) :: old
    integer :: u, ios

    call hdf5_start(err)
    if (.not. allocated(err)) call restart_read_deck(trim(run%cfg%restart_from), text, err)
    if (allocated(err)) call refuse_one('&run restart_from: '//err%msg, 'cannot restart')
    ! the stored deck is namelist text: read it back through the same reader
    tmp = trim(run%cfg%restart_from)//'.deck.tmp'
    open(newunit=u, file=tmp, status='replace', action='write', iostat=ios)
    if (ios /= 0) call refuse_one('cannot write '//tmp, 'cannot restart')
    write(u, '(a)') text
    close(u)
    call input_read(tmp, old, problems)
    open(newunit=u, file=tmp, status='old', iostat=ios)
    if (ios == 0) close(u, status='delete')
    if (size(problems) > 0) call refuse(problems, 'the deck stored in '// &
      trim(run%cfg%restart_from)//' cannot be read back')
    call input_state_changes(old, run%cfg, problems)
    if (size(problems) > 0) call refuse(problems, 'a restart cannot change what the state '// &
      'depends on; undo these changes or start a new run')
  end subroutine check_restart_deck

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
    call log_open(dir//'/'//base//'.log', run%restarting, ok, msg)
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
                     run%cfg%gauges(:, 1:run%cfg%ngauge), run%restarting, err)
    if (allocated(err)) call fatal(err%where, err%msg)
  end subroutine open_outputs

  !> Grid, materials, initial state from the regions, energy sources, nodal
  !> masses (first term of Eq. 16) and boundary lists.
  subroutine build_scene()
    type(error_t), allocatable :: err
    integer :: m, c, n, a, n0, r, s, ijk(3)
    real(wp) :: xn(3, 8), vsub(8), h(3), rv

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
        run%mats(m)%p_min = cfg%materials(m)%p_min
        run%mats(m)%rho_min = cfg%materials(m)%rho_min
      end do

      do c = 1, g%ncell
        call g%gather(c, g%x, xn)
        hy%vol(c) = hex_volume(xn)
      end do
      call fill_regions()
      do n = 1, g%nnode
        do r = 1, size(cfg%regions)
          if (inside(cfg%regions(r), g%x(:, n))) hy%u(:, n) = cfg%regions(r)%velocity
        end do
      end do
      call rng_seed(run%rng, cfg%seed)
      if (cfg%velocity_noise > 0.0_wp) then
        do n = 1, g%nnode
          do a = 1, 3
            rv = rng_uniform(run%rng)
            hy%u(a, n) = hy%u(a, n) + cfg%velocity_noise*(2.0_wp*rv - 1.0_wp)
          end do
        end do
      end if
      ! energy sources: added to the cell that contains the point
      h = (cfg%xmax - cfg%xmin)/real([cfg%ni, cfg%nj, cfg%nk], wp)
      do s = 1, size(cfg%sources)
        ijk = int((cfg%sources(s)%position - cfg%xmin)/h) + 1
        ijk = max(1, min([cfg%ni, cfg%nj, cfg%nk], ijk))
        c = ijk(1) + cfg%ni*((ijk(2) - 1) + cfg%nj*(ijk(3) - 1))
        hy%e(c) = hy%e(c) + cfg%sources(s)%energy/hy%mass(c)
        if (hy%mat(c) < 0) then
          ! a mixed cell: every material gets the same specific energy
          associate (k => -hy%mat(c))
            run%mx%e(run%mx%start(k):run%mx%start(k + 1) - 1) = &
              run%mx%e(run%mx%start(k):run%mx%start(k + 1) - 1) + cfg%sources(s)%energy/hy%mass(c)
          end associate
        end if
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

      call material_index_cells(run%mats, hy%mat, run%mx, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      call material_eval_eos(run%mats, hy%rho, hy%e, hy%p, hy%cs, run%mx)
      call mixed_cell_state(run%mx, hy%p, hy%cs)

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

  !> Fills the cells from the regions (applied in deck order, a later one
  !> overriding an earlier one). A cell whose corners and centre all lie in
  !> the same region takes that region's state; any other cell is sampled at
  !> subsamples^3 points (midpoints of a uniform split of its natural
  !> coordinates: exact volume weights on the initial box grid) and gets
  !> volume fractions, masses, energies and centroids per material. A cell
  !> with one material is pure (with the mass-averaged state of its regions);
  !> a cell with several is a mixed cell.
  subroutine fill_regions()
    type(error_t), allocatable :: err
    integer :: nmat, c, m, k, nmix, nslot, s, nm, r_only
    real(wp), allocatable :: vfm(:), massm(:), enm(:), xim(:, :), e_reg(:)
    logical :: covered

    associate (cfg => run%cfg, g => run%g, hy => run%h)
      nmat = size(cfg%materials)
      allocate(vfm(nmat), massm(nmat), enm(nmat), xim(3, nmat), e_reg(size(cfg%regions)))
      do k = 1, size(cfg%regions)
        associate (rg => cfg%regions(k))
          if (rg%energy >= 0.0_wp) then
            e_reg(k) = rg%energy
          else
            e_reg(k) = run%mats(rg%imat)%eos%energy(rg%density, rg%pressure)
          end if
        end associate
      end do
      ! pass 1: pure cells get their state, mixed cells are counted
      nmix = 0
      nslot = 0
      do c = 1, g%ncell
        call sample_cell(c, e_reg, vfm, massm, enm, xim, covered, r_only)
        if (.not. covered) call fatal('build_scene', 'cell '//itoa(c)// &
          ' is not covered by any &region; add a region with shape = ''all'' first')
        nm = count(vfm > 0.0_wp)
        if (nm == 1) then
          m = maxloc(vfm, 1)
          hy%mat(c) = m
          if (r_only > 0) then
            ! the whole cell in one region: its state exactly as given
            hy%rho(c) = cfg%regions(r_only)%density
            hy%e(c) = e_reg(r_only)
            hy%mass(c) = hy%rho(c)*hy%vol(c)
          else
            hy%mass(c) = massm(m)
            hy%rho(c) = massm(m)/hy%vol(c)
            hy%e(c) = enm(m)/massm(m)
          end if
        else
          nmix = nmix + 1
          nslot = nslot + nm
          hy%mat(c) = -nmix
        end if
      end do
      ! pass 2: the mixed cells' slots
      call mixed_allocate(run%mx, nmix, nslot, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      k = 0
      s = 0
      do c = 1, g%ncell
        if (hy%mat(c) > 0) cycle
        k = k + 1
        call sample_cell(c, e_reg, vfm, massm, enm, xim, covered, r_only)
        run%mx%cell(k) = c
        do m = 1, nmat
          if (.not. (vfm(m) > 0.0_wp)) cycle
          s = s + 1
          run%mx%mat(s) = m
          run%mx%vf(s) = vfm(m)
          run%mx%mass(s) = massm(m)
          run%mx%e(s) = enm(m)/massm(m)
          run%mx%rho(s) = massm(m)/(vfm(m)*hy%vol(c))
          run%mx%xi(:, s) = xim(:, m)/vfm(m)
        end do
        run%mx%start(k + 1) = s + 1
        hy%mass(c) = sum(massm)
        hy%rho(c) = hy%mass(c)/hy%vol(c)
        hy%e(c) = sum(enm)/hy%mass(c)
      end do
      if (nmix > 0) call log_line('mixed cells: '//itoa(nmix)//' ('//itoa(nslot)//' material slots)')
    end associate
  end subroutine fill_regions

  !> Volume fraction, mass, internal energy and centroid (natural
  !> coordinates, times the volume fraction) of each material in cell c;
  !> r_only is the region that holds the whole cell, if one does (else 0).
  subroutine sample_cell(c, e_reg, vfm, massm, enm, xim, covered, r_only)
    integer, intent(in) :: c
    real(wp), intent(in) :: e_reg(:)
    real(wp), intent(out) :: vfm(:), massm(:), enm(:), xim(:, :)
    logical, intent(out) :: covered
    integer, intent(out) :: r_only
    real(wp) :: xn(3, 8), xi(3), w
    integer :: a, i, j, k, r, r0, ns
    logical :: same

    associate (cfg => run%cfg, g => run%g)
      call g%gather(c, g%x, xn)
      vfm = 0.0_wp; massm = 0.0_wp; enm = 0.0_wp; xim = 0.0_wp
      ! quick test: corners and centre in one region
      r0 = region_at(sum(xn, 2)/8.0_wp)
      same = .true.
      do a = 1, 8
        same = same .and. region_at(xn(:, a)) == r0
      end do
      r_only = 0
      if (same) then
        covered = (r0 > 0)
        if (.not. covered) return
        call add_sample(r0, [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp)
        r_only = r0
        return
      end if
      ns = cfg%subsamples
      w = 1.0_wp/real(ns, wp)**3
      covered = .true.
      do k = 1, ns
        do j = 1, ns
          do i = 1, ns
            xi = -1.0_wp + (2.0_wp*real([i, j, k], wp) - 1.0_wp)/real(ns, wp)
            r = region_at(trilinear(xn, xi))
            if (r == 0) then
              covered = .false.
              return
            end if
            call add_sample(r, xi, w)
          end do
        end do
      end do
    end associate

  contains

    subroutine add_sample(r, xi_pt, wt)
      integer, intent(in) :: r
      real(wp), intent(in) :: xi_pt(3), wt
      integer :: m
      m = run%cfg%regions(r)%imat
      vfm(m) = vfm(m) + wt
      massm(m) = massm(m) + wt*run%cfg%regions(r)%density*run%h%vol(c)
      enm(m) = enm(m) + wt*run%cfg%regions(r)%density*e_reg(r)*run%h%vol(c)
      xim(:, m) = xim(:, m) + wt*xi_pt
    end subroutine add_sample
  end subroutine sample_cell

  !> The last region (in deck order) that contains point p, or 0.
  integer function region_at(p)
    real(wp), intent(in) :: p(3)
    integer :: r
    region_at = 0
    do r = size(run%cfg%regions), 1, -1
      if (inside(run%cfg%regions(r), p)) then
        region_at = r
        return
      end if
    end do
  end function region_at

  !> Position at natural coordinates xi in [-1,1]^3 of the hex with nodes xn.
  pure function trilinear(xn, xi) result(x)
    real(wp), intent(in) :: xn(3, 8), xi(3)
    real(wp) :: x(3)
    integer :: a
    real(wp) :: s(3)
    x = 0.0_wp
    do a = 1, 8
      s = real([mod(a - 1, 2), mod((a - 1)/2, 2), (a - 1)/4], wp)*2.0_wp - 1.0_wp
      x = x + 0.125_wp*(1.0_wp + s(1)*xi(1))*(1.0_wp + s(2)*xi(2))*(1.0_wp + s(3)*xi(3))*xn(:, a)
    end do
  end function trilinear

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
    case ('half_space')
      inside = dot_product(p - rg%center, rg%normal) >= 0.0_wp
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
    real(wp) :: dt_cap, work, wall_last, wall_now, eps_t, w0
    integer :: bad_cell
    logical :: last

    eps_t = 1.0e-12_wp*run%cfg%t_end
    wall_last = wall_seconds()
    do while (run%t < run%cfg%t_end - eps_t .and. run%step < run%cfg%max_steps)
      if (near_wall_time_limit()) call stop_for_wall_time()
      ! the step the controller allows: growth limit, dt_max, end time, frames
      if (run%step == 0) then
        dt_cap = run%cfg%hydro%dt_max
        if (run%cfg%dt_init > 0.0_wp) dt_cap = min(dt_cap, run%cfg%dt_init)
      else
        dt_cap = min(run%cfg%hydro%dt_growth*run%dt, run%cfg%hydro%dt_max)
      end if
      dt_cap = min(dt_cap, run%cfg%t_end - run%t, run%t_next_frame - run%t)

      w0 = wall_seconds()
      call run%t_lagrange%start()
      call lagrange_step(run%g, run%h, run%bc, run%mats, run%mx, run%cfg%hydro, dt_cap, work, bad_cell)
      call run%t_lagrange%stop()
      run%step_wall = wall_seconds() - w0
      if (bad_cell /= 0) call fatal('lagrange_step', 'cell '//itoa(bad_cell)// &
        ' has a non-positive volume (tangled grid) at t = '//rtoa(run%t))
      if (dt_cap < run%cfg%dt_min) call fatal('time_loop', 'time step collapsed to '// &
        rtoa(dt_cap)//' (dt_min = '//rtoa(run%cfg%dt_min)//')')
      run%dt = dt_cap
      run%t = run%t + run%dt
      run%step = run%step + 1
      run%tot%boundary_work = run%tot%boundary_work + work
      last = .not. (run%t < run%cfg%t_end - eps_t .and. run%step < run%cfg%max_steps)

      call gauge_output()
      run%steps_since_frame = run%steps_since_frame + 1
      if (.not. last .and. (run%t >= run%t_next_frame - eps_t .or. &
          (run%cfg%frame_steps > 0 .and. run%steps_since_frame >= run%cfg%frame_steps))) then
        call write_frame()
        run%steps_since_frame = 0
        do while (run%t_next_frame <= run%t + eps_t)
          run%t_next_frame = run%t_next_frame + run%cfg%frame_dt
        end do
      end if
      if ((run%cfg%dump_steps > 0 .and. mod(run%step, max(run%cfg%dump_steps, 1)) == 0) .or. &
          run%t >= run%t_next_dump - eps_t) then
        call write_restart()
        do while (run%t_next_dump <= run%t + eps_t)
          run%t_next_dump = run%t_next_dump + run%cfg%dump_dt
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

  !> True when the next step and a dump might not fit before the wall-time
  !> limit (a margin of two steps, two dumps and half a second).
  logical function near_wall_time_limit()
    real(wp) :: elapsed
    near_wall_time_limit = .false.
    if (run%cfg%wall_time_limit <= 0.0_wp) return
    elapsed = wall_seconds() - run%t_total%t0
    near_wall_time_limit = elapsed + 2.0_wp*(run%step_wall + run%dump_wall) + 0.5_wp >= &
                           run%cfg%wall_time_limit
  end function near_wall_time_limit

  !> Writes a restart (unless the last dump is of this very step) and stops
  !> with exit status 3, saying how to continue.
  subroutine stop_for_wall_time()
    character(len=:), allocatable :: path
    logical :: have
    path = restart_path(run%step)
    have = .false.
    if (allocated(run%dumps)) then
      if (size(run%dumps) > 0) have = (trim(run%dumps(size(run%dumps))) == path)
    end if
    if (.not. have) call write_restart()
    call progress()
    call log_line('wall-time limit of '//rtoa(run%cfg%wall_time_limit)//' s reached at step '// &
                  itoa(run%step)//', t = '//rtoa(run%t))
    call log_line('to continue, run the same deck with  &run restart_from = '''//path//''' /')
    call gauges_close(run%gauges)
    call log_close()
    stop 3
  end subroutine stop_for_wall_time

  subroutine gauge_output()
    if (run%gauges%n == 0) return
    if (run%t < run%t_next_gauge .and. run%t < run%cfg%t_end) return
    call run%t_output%start()
    call gauges_write(run%gauges, run%g, run%h, run%t)
    call run%t_output%stop()
    if (run%cfg%gauge_dt > 0.0_wp) then
      do while (run%t_next_gauge <= run%t)
        run%t_next_gauge = run%t_next_gauge + run%cfg%gauge_dt
      end do
    end if
  end subroutine gauge_output

  ! ------------------------------------------------------------ restarts

  !> Registers everything a restart must hold (once, after allocation).
  subroutine register_restart()
    associate (r => run%reg, h => run%h)
      call r%add('x', 'length', run%g%x)
      call r%add('velocity', 'length/time', h%u)
      call r%add('node_mass', 'mass', h%mnode)
      call r%add('mass', 'mass', h%mass)
      call r%add('volume', 'length^3', h%vol)
      call r%add('density', 'mass/length^3', h%rho)
      call r%add('energy', 'energy/mass', h%e)
      call r%add('pressure', 'pressure', h%p)
      call r%add('sound_speed', 'length/time', h%cs)
      call r%add('viscosity', 'pressure', h%q)
      call r%add('material', '1', h%mat)
      if (run%mx%n > 0) then
        call r%add('mixed_cell', '1', run%mx%cell)
        call r%add('mixed_start', '1', run%mx%start)
        call r%add('mixed_material', '1', run%mx%mat)
        call r%add('mixed_volume_fraction', '1', run%mx%vf)
        call r%add('mixed_mass', 'mass', run%mx%mass)
        call r%add('mixed_energy', 'energy/mass', run%mx%e)
        call r%add('mixed_density', 'mass/length^3', run%mx%rho)
        call r%add('mixed_pressure', 'pressure', run%mx%p)
        call r%add('mixed_sound_speed', 'length/time', run%mx%cs)
        call r%add('mixed_centroid', 'natural coordinates', run%mx%xi)
      end if
      call r%add('time', 'time', run%t)
      call r%add('dt', 'time', run%dt)
      call r%add('step', '1', run%step)
      call r%add('boundary_work', 'energy', run%tot%boundary_work)
      call r%add('initial_energy', 'energy', run%tot%energy_initial)
      call r%add('t_next_frame', 'time', run%t_next_frame)
      call r%add('t_next_gauge', 'time', run%t_next_gauge)
      call r%add('t_next_dump', 'time', run%t_next_dump)
      call r%add('steps_since_frame', '1', run%steps_since_frame)
      call r%add('nframe', '1', run%out%nframe)
      call r%add('rng_state', 'bits', run%rng_bits)
    end associate
  end subroutine register_restart

  function restart_path(step) result(path)
    integer, intent(in) :: step
    character(len=:), allocatable :: path
    character(len=16) :: buf
    write(buf, '(i8.8)') step
    path = run%out%dir//'/'//run%out%name//'_restart_'//trim(buf)//'.h5'
  end function restart_path

  !> Writes a restart dump and keeps only the last dump_keep of this run.
  subroutine write_restart()
    type(error_t), allocatable :: err
    character(len=:), allocatable :: path
    character(len=256) :: entry
    real(wp) :: w0
    integer :: u, ios

    w0 = wall_seconds()
    call run%t_output%start()
    path = restart_path(run%step)
    run%rng_bits = transfer(run%rng%s, 1.0_wp)
    if (.not. allocated(run%out%frames)) allocate(run%out%frames(0), run%out%times(0))
    call restart_write(path, run%reg, run%cfg%echo, run%out%frames, run%out%times, err)
    call run%t_output%stop()
    if (allocated(err)) call fatal(err%where, err%msg)
    run%dump_wall = wall_seconds() - w0
    call log_line('restart '//path//' at step '//itoa(run%step)//', t = '//rtoa(run%t))
    if (.not. allocated(run%dumps)) allocate(run%dumps(0))
    entry = path
    run%dumps = [run%dumps, entry]
    do while (size(run%dumps) > run%cfg%dump_keep)
      open(newunit=u, file=trim(run%dumps(1)), status='old', iostat=ios)
      if (ios == 0) close(u, status='delete')
      run%dumps = run%dumps(2:)
    end do
  end subroutine write_restart

  !> The next output time after a restart: the stored one if the interval is
  !> unchanged, none if the interval is now off, else the next multiple of it.
  real(wp) function next_time(stored, interval)
    real(wp), intent(in) :: stored, interval
    if (interval <= 0.0_wp) then
      next_time = huge(1.0_wp)
    else if (stored < huge(1.0_wp)) then
      next_time = stored
    else
      next_time = (aint(run%t/interval) + 1.0_wp)*interval
    end if
  end function next_time

  !> Replaces the state built from the deck by the one in the restart file.
  subroutine read_restart()
    type(error_t), allocatable :: err
    character(len=256), allocatable :: frames(:)
    real(wp), allocatable :: times(:)
    character(len=:), allocatable :: path

    path = trim(run%cfg%restart_from)
    call restart_read(path, run%reg, frames, times, err)
    if (allocated(err)) call refuse_one('&run restart_from: '//err%msg, 'cannot restart')
    run%rng%s = transfer(run%rng_bits, 1_i8)
    ! the frame list continues the XDMF series where it was
    run%out%frames = frames
    run%out%times = times
    call material_index_cells(run%mats, run%h%mat, run%mx, err)
    if (allocated(err)) call fatal(err%where, err%msg)
    ! settings a restart may change: frame and dump intervals
    run%t_next_frame = next_time(run%t_next_frame, run%cfg%frame_dt)
    run%t_next_dump = next_time(run%t_next_dump, run%cfg%dump_dt)
    run%step_start = run%step
    call log_line('restarted from '//path//' at step '//itoa(run%step)//', t = '//rtoa(run%t))
    call report_conservation('restart')
  end subroutine read_restart

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
      rate = real(run%g%ncell, wp)*real(run%step - run%step_start, wp)/run%t_lagrange%total
    write(line, '("timers [s]: setup ",f9.3,"  lagrange ",f9.3,"  output ",f9.3,"  total ",f9.3)') &
      run%t_setup%total, run%t_lagrange%total, run%t_output%total, run%t_total%total
    call log_line(trim(line))
    write(line, '("throughput: ",es10.3," cell-cycles/s over ",i0," steps")') rate, &
      run%step - run%step_start
    call log_line(trim(line))
    call log_line('outputs: '//run%out%dir//'/'//run%out%name//'.xdmf (ParaView), '// &
                  run%out%dir//'/'//run%out%name//'.log')
    call log_line('done: t = '//rtoa(run%t)//' after '//itoa(run%step)//' steps')
  end subroutine report_end

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

  subroutine write_frame()
    type(error_t), allocatable :: err
    character(len=:), allocatable :: path
    call run%t_output%start()
    call totals(run%tot)
    call frame_out(path, err)
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
      call frame_out(path, err)
      if (.not. allocated(err)) call log_error('state at failure written to '//path)
    end if
    if (log_is_open()) call log_close()
    stop 1
  end subroutine fatal


end module driver
