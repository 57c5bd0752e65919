!> The Euler phase in the time loop: when to run it (the paper's triggers,
!> or an interval), the rezone (back to the initial grid, or smoothing of the
!> distorted subdomains (LSSM) or of the whole grid), the remap
!> (`remap_euler`), the material state after it, the conservation check and
!> the log.
module driver_euler
  use base_kinds, only: wp
  use base_build, only: build_checks
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_t
  use base_timers, only: wall_seconds
  use rezone_quality, only: grid_quality, grid_worst_cells
  use rezone_subdomains, only: rezone_subdomains_t, rezone_subdomains_find, rezone_subdomains_merge, &
                               rezone_subdomains_default_dmax, rezone_subdomains_from_boxes
  use rezone_smooth, only: smooth_mobility_box, smooth_region_t, smooth_region_init, smooth_combined, &
                           smooth_tfi, smooth_q_min, smooth_keep_small_moves
  use material_table, only: material_index_cells, material_eval_eos
  use material_mixed, only: mixed_cell_state
  use lagrange_state, only: hydro_totals
  use remap_euler, only: remap_params_t, remap_stats_t, remap_euler_step
  use io_log, only: log_line
  use driver_state, only: run, fatal
  implicit none
  private
  public :: euler_init, euler_due, euler_step, euler_report

  !> Relative size of a conservation error that stops a checked run: a
  !> remap adds up ~ncell fragments per quantity, each exact to ~1e-16.
  real(wp), parameter :: conservation_tol = 1.0e-11_wp

  !> What made the Euler step due (for its log line).
  character(len=160) :: trigger_note = ''

contains

  !> Keeps the initial grid (the global rezone's target), the node mobility
  !> of the smoothers and the first interval time. Call after the scene is
  !> built, before a restart is read.
  subroutine euler_init()
    type(error_t), allocatable :: err
    if (trim(run%cfg%rezone%mode) == 'none') return
    run%x0 = run%g%x
    allocate(run%quality(run%g%ncell))
    if (trim(run%cfg%rezone%mode) == 'lssm' .or. trim(run%cfg%rezone%mode) == 'smooth') then
      ! face nodes slide in their face, edge nodes along their edge, corners stay
      call smooth_mobility_box(run%g%ni, run%g%nj, run%g%nk, run%mobility, err)
      if (allocated(err)) call fatal(err%where, err%msg)
    end if
    run%t_next_euler = huge(1.0_wp)
    if (run%cfg%rezone%interval_time > 0.0_wp) run%t_next_euler = run%cfg%rezone%interval_time
  end subroutine euler_init

  !> True when an Euler step is due after the step just taken: an interval
  !> has passed, or the grid's largest side ratio or smallest cosine of the
  !> inclined angle has reached its bound.
  logical function euler_due()
    real(wp) :: q_min, ratio_max, cos_min
    integer :: ijk_ratio(3), ijk_cos(3)
    euler_due = .false.
    associate (rz => run%cfg%rezone)
      if (trim(rz%mode) == 'none') return
      if (rz%interval_steps > 0) euler_due = mod(run%step, rz%interval_steps) == 0
      if (rz%interval_time > 0.0_wp) euler_due = euler_due .or. run%t >= run%t_next_euler*(1.0_wp - 1.0e-12_wp)
      trigger_note = 'interval'
      if (euler_due .or. (rz%side_ratio <= 0.0_wp .and. rz%cos_angle <= 0.0_wp)) return
      call grid_quality(run%g%ni, run%g%nj, run%g%nk, run%g%x, run%quality, q_min, ratio_max, cos_min)
      euler_due = (rz%side_ratio > 0.0_wp .and. ratio_max >= rz%side_ratio) .or. &
                  (rz%cos_angle > 0.0_wp .and. cos_min <= rz%cos_angle)
      if (.not. euler_due) return
      ! where: the worst cell of each measure
      call grid_worst_cells(run%g%ni, run%g%nj, run%g%nk, run%g%x, ijk_ratio, ijk_cos)
      write(trigger_note, '("side ratio ",f0.2," in cell (",i0,",",i0,",",i0,"), cosine ",f0.3," in cell (", &
        &i0,",",i0,",",i0,")")') ratio_max, ijk_ratio, cos_min, ijk_cos
    end associate
  end function euler_due

  !> One Euler step: rezone, remap, new material states; checks
  !> conservation (Debug builds, or &rezone check_conservation) and logs.
  subroutine euler_step()
    type(remap_params_t) :: par
    type(remap_stats_t) :: st
    type(error_t), allocatable :: err
    real(wp) :: m0, p0(3), ie0, ke0, m1, p1(3), ie1, ke1, pscale, dp(3), t_rezone
    real(wp), allocatable :: xnew(:, :)
    integer :: n
    character(len=400) :: line

    call log_line('euler '//itoa(run%n_euler + 1)//' due at step '//itoa(run%step)//': '//trim(trigger_note))
    call run%t_euler%start()
    par%linear = trim(run%cfg%rezone%reconstruction) == 'linear'
    par%mof_max_iter = run%cfg%rezone%mof_max_iter
    par%consistent_nodal_mass = trim(run%cfg%rezone%nodal_mass) == 'consistent'
    call hydro_totals(run%h, m0, p0, ie0, ke0)
    pscale = 0.0_wp
    do n = 1, run%g%nnode
      pscale = pscale + run%h%mnode(n)*norm2(run%h%u(:, n))
    end do

    ! rezone: back to the initial grid, or smoothing (localized or global)
    t_rezone = wall_seconds()
    if (trim(run%cfg%rezone%mode) == 'lssm' .or. trim(run%cfg%rezone%mode) == 'smooth') then
      xnew = run%g%x
      if (.not. smooth_rezone(xnew)) then
        call run%t_euler%stop()
        return
      end if
    else
      xnew = run%x0
    end if
    t_rezone = wall_seconds() - t_rezone
    run%t_rezone_total = run%t_rezone_total + t_rezone
    call remap_euler_step(run%g, run%h, run%mx, size(run%mats), run%bc, xnew, par, st, err)
    if (allocated(err)) call fatal(err%where, err%msg)
    call material_index_cells(run%mats, run%h%mat, run%mx, err)
    if (allocated(err)) call fatal(err%where, err%msg)
    call material_eval_eos(run%mats, run%h%rho, run%h%e, run%h%p, run%h%cs, run%mx)
    call mixed_cell_state(run%mx, run%h%p, run%h%cs)
    run%n_euler = run%n_euler + 1
    if (run%cfg%rezone%interval_time > 0.0_wp) then
      do while (run%t_next_euler <= run%t*(1.0_wp + 1.0e-12_wp))
        run%t_next_euler = run%t_next_euler + run%cfg%rezone%interval_time
      end do
    end if
    call run%t_euler%stop()

    ! what came in and went out through open faces is external work
    run%tot%boundary_work = run%tot%boundary_work + st%energy_in - st%energy_out
    call hydro_totals(run%h, m1, p1, ie1, ke1)
    m1 = m1 - st%mass_in + st%mass_out
    ie1 = ie1 - st%energy_in + st%energy_out
    dp = p1 - p0 + st%momentum_constrained - st%momentum_in + st%momentum_out
    write(line, '("euler ",i0," at step ",i0,", t = ",es12.5,": ",i0," cells remapped, ",i0," copied, reach ",i0, &
      &", volume defect ",es8.1,", old-cell defect ",es8.1," (",i0," rescaled), ",i0," slivers merged", &
      &"; MoF ",i0," cells, ",f5.2," iterations, ",i0," capped, centroid error/size ",es8.1, &
      &"; KE to internal ",es10.3,"; rezone ",f8.3," s, remap ",f8.3," s (prepare ",f7.3,", intersect ",f7.3, &
      &", assemble ",f7.3,")")') &
      run%n_euler, run%step, run%t, st%cells_remapped, st%cells_copied, st%reach, st%volume_defect, &
      st%given_defect, st%regions_rescaled, st%slivers_merged, st%mof_cells, &
      real(st%mof_iterations, wp)/real(max(st%mof_cells, 1), wp), st%mof_not_converged, st%mof_err_max, &
      st%ke_to_internal, t_rezone, st%t_prepare + st%t_intersect + st%t_assemble, st%t_prepare, st%t_intersect, &
      st%t_assemble
    call log_line(trim(line))
    write(line, '("  conservation: relative change of mass ",es9.2,", momentum ",es9.2,", total energy ",es9.2, &
      &"; momentum taken by velocity conditions ",3es10.2)') abs(m1 - m0)/m0, &
      norm2(dp)/max(pscale, tiny(1.0_wp)), abs(ie1 + ke1 - ie0 - ke0)/max(abs(ie0 + ke0), tiny(1.0_wp)), &
      st%momentum_constrained
    call log_line(trim(line))
    if (st%mass_in > 0.0_wp .or. abs(st%mass_out) > 0.0_wp) then
      write(line, '("  open faces: mass in ",es12.5," out ",es12.5,"; energy in ",es12.5," out ",es12.5)') &
        st%mass_in, st%mass_out, st%energy_in, st%energy_out
      call log_line(trim(line))
    end if
    run%euler_cells = run%euler_cells + st%cells_remapped
    run%euler_mof = run%euler_mof + st%mof_cells
    run%euler_mof_iterations = run%euler_mof_iterations + st%mof_iterations
    run%euler_ke = run%euler_ke + st%ke_to_internal
    if (build_checks .or. run%cfg%rezone%check_conservation) then
      if (abs(m1 - m0) > conservation_tol*m0) call fatal('euler_step', 'mass not conserved: '//rtoa(m0)// &
        ' -> '//rtoa(m1))
      if (abs(ie1 + ke1 - ie0 - ke0) > conservation_tol*abs(ie0 + ke0)) call fatal('euler_step', &
        'total energy not conserved: '//rtoa(ie0 + ke0)//' -> '//rtoa(ie1 + ke1))
      if (norm2(dp) > conservation_tol*pscale) call fatal('euler_step', 'momentum not conserved: change '// &
        rtoa(norm2(dp))//' of '//rtoa(pscale))
    end if
  end subroutine euler_step

  !> Smoothing rezone. 'lssm' (Sect. 5.2-5.3): the distorted subdomains of
  !> the grid (Q < quality); 'smooth': the whole grid (the global MMALE the
  !> paper compares LSSM with). The cells are smoothed by the combined method
  !> until their Q_min reaches quality_target or smooth_iterations are done,
  !> then TFI on the merged cuboid subdomains (or the whole block) if the
  !> target was not reached. x is the grid on entry and the rezoned grid on
  !> return; false if no cell is distorted (nothing to do).
  logical function smooth_rezone(x) result(done)
    real(wp), intent(inout) :: x(:, :)
    type(rezone_subdomains_t) :: sub
    type(smooth_region_t) :: reg
    type(error_t), allocatable :: err
    integer, allocatable :: mlo(:, :), mhi(:, :)
    real(wp) :: q_min, q_min0, d_max, ratio_max, cos_min
    integer :: iterations, b, nreset
    logical :: tfi
    character(len=300) :: line
    character(len=60) :: kept

    associate (g => run%g, rz => run%cfg%rezone)
      call grid_quality(g%ni, g%nj, g%nk, x, run%quality, q_min0, ratio_max, cos_min)
      if (trim(rz%mode) == 'smooth') then
        ! the whole block as one subdomain
        call rezone_subdomains_from_boxes(g%ni, g%nj, g%nk, reshape([1, 1, 1], [3, 1]), &
                                          reshape([g%ni, g%nj, g%nk], [3, 1]), sub, err)
      else
        d_max = rz%d_max
        if (.not. d_max > 0.0_wp) d_max = rezone_subdomains_default_dmax(g%ni, g%nj, g%nk)
        call rezone_subdomains_find(g%ni, g%nj, g%nk, run%quality, rz%quality, d_max, sub, err)
      end if
      if (allocated(err)) call fatal(err%where, err%msg)
      done = sub%nbox > 0
      if (.not. done) then
        call log_line('euler step skipped at step '//itoa(run%step)//': no cell has Q < '//rtoa(rz%quality))
        return
      end if
      call smooth_region_init(run%mobility, sub%cell_smooth, reg, err)
      if (allocated(err)) call fatal(err%where, err%msg)
      call smooth_combined(reg, x, rz%quality_target, rz%smooth_iterations, iterations, q_min)
      tfi = q_min < rz%quality_target
      if (tfi) then
        ! the fallback: transfinite interpolation of each merged cuboid
        ! subdomain from its boundary (node index box = cell box widened by one)
        call rezone_subdomains_merge(sub%lo(:, 1:sub%nbox), sub%hi(:, 1:sub%nbox), mlo, mhi, err)
        if (allocated(err)) call fatal(err%where, err%msg)
        do b = 1, size(mlo, 2)
          call smooth_tfi(g%ni, g%nj, g%nk, mlo(:, b) - 1, mhi(:, b), x, err, run%mobility)
          if (allocated(err)) call fatal(err%where, err%msg)
        end do
        q_min = smooth_q_min(reg, x)
      end if
      kept = ''
      if (rz%move_min > 0.0_wp) then
        ! negligible moves kept out of the remap
        call smooth_keep_small_moves(g%ni, g%nj, g%nk, g%x, x, rz%move_min, nreset)
        q_min = smooth_q_min(reg, x)
        write(kept, '("; ",i0," nodes moved < move_min kept")') nreset
      end if
      write(line, '(a," at step ",i0,": ",i0," subdomains, ",i0," cells smoothed (Q_min ",f7.4," -> ",f7.4, &
        &" after ",i0," iterations",a,")",a)') trim(rz%mode), run%step, sub%nbox, count(sub%cell_smooth), q_min0, &
        q_min, iterations, trim(merge(', then TFI', '          ', tfi)), trim(kept)
      call log_line(trim(line))
    end associate
  end function smooth_rezone

  !> Summary line of the run's Euler steps.
  subroutine euler_report()
    character(len=300) :: line
    if (trim(run%cfg%rezone%mode) == 'none') return
    write(line, '("euler steps: ",i0,", cells remapped ",i0," (",es10.3," per second of remap), MoF ",i0, &
      &" cells (",f5.2," iterations), KE returned to internal energy ",es10.3,"; rezone ",f9.3," s")') &
      run%n_euler, run%euler_cells, &
      real(run%euler_cells, wp)/max(run%t_euler%total - run%t_rezone_total, tiny(1.0_wp)), run%euler_mof, &
      real(run%euler_mof_iterations, wp)/real(max(run%euler_mof, 1), wp), run%euler_ke, run%t_rezone_total
    call log_line(trim(line))
  end subroutine euler_report
end module driver_euler
