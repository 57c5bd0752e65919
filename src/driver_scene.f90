!> Builds the scene of a deck: grid, materials and their EOS, the initial
!> state from the regions (volume fractions and mixed cells where regions
!> cut cells), energy sources, nodal masses (Eq. 16), boundaries and the
!> MPM particles (`driver_particles`).
module driver_scene
  use base_kinds, only: wp, i8
  use base_strings, only: itoa, rtoa
  use base_errors, only: error_no_memory, error_t, error_set, ERR_INPUT
  use base_random, only: rng_t, rng_seed, rng_uniform, rng_jump_t, rng_jump, rng_apply
  use eos_factory, only: eos_create
  use mesh_grid, only: grid_t, grid_index_t, grid_init_box, grid_init_nodes
  use mesh_grid_config, only: grid_axis_nodes
  use mesh_halo, only: halo_t
  use mesh_geometry, only: hex_volume, hex_natural, cross
  use io_grid_file, only: grid_file_read
  use io_gauges, only: gauge_locate
  use mesh_boundary, only: bc_init, bc_constrain, bc_max_fixed
  use material_table, only: material_index_cells, material_eval_eos, material_burn_start
  use material_mixed, only: mixed_allocate, mixed_cell_state
  use geometry_shapes, only: shape_t, shape_inside, shapes_cell_moments
  use mesh_shapes, only: shape_kind
  use hydro_state, only: hydro_allocate, hydro_subcell_masses
  use lagrange_centroids, only: centroid_stats_t, centroids_fit_planes
  use io_log, only: log_t, log_line
  use driver_scene_config, only: region_config_t
  use driver_config, only: config_t
  use driver_state, only: state_t, state_totals, centroid_text
  use driver_particles, only: build_particles
  use driver_burn, only: burn_state, deck_problem
  use driver_prerun, only: prerun_t, prerun_run, prerun_plan, prerun_scale, prerun_cell, prerun_nodes, prerun_totals
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use material_burn, only: burn_initiator, burn_around, burn_width_across, INIT_POINT, INIT_LINE, INIT_PLANE
  implicit none
  private
  public :: build_scene

contains

  !> Grid, materials, initial state from the regions, energy sources, nodal
  !> masses (first term of Eq. 16) and boundary lists; the particles unless
  !> fluid_only (a decomposed run's window: `driver_whole`); the Lagrangian
  !> step's work arrays unless fluid_only or remap_only (a state that is
  !> only remapped: a window, a decomposed run's whole-grid copy).
  subroutine build_scene(cfg, st, log, err, block, fluid_only, remap_only)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    type(grid_index_t), intent(in), optional :: block
    logical, intent(in), optional :: fluid_only, remap_only
    integer :: m, c, n, r, s, a, ijk(3), stat
    type(centroid_stats_t) :: planes
    real(wp) :: xn(3, 8), h(3), xi(3), key
    logical :: inside, fluid, remap, mapping
    real(wp), allocatable :: xfile(:, :), xa(:)
    character(len=200) :: msg

    ! a single block's halo (no exchange) unless the driver gave a block's
    if (.not. allocated(st%halo)) then
      allocate(halo_t :: st%halo, stat=stat)
      if (stat /= 0) then
        call error_set(err, 'build_scene', 'out of memory')
        return
      end if
    end if
    fluid = .false.
    if (present(fluid_only)) fluid = fluid_only
    remap = fluid
    if (present(remap_only)) remap = remap .or. remap_only
    ! (an error on one rank leaves this block there; every rank then learns
    ! of it before the collective calls after it)
    scene: block
      associate (gc => cfg%grid, g => st%g, hy => st%h, mx => st%mx)
        if (len_trim(gc%file) == 0) then
          call grid_init_box(g, gc%ni, gc%nj, gc%nk, gc%xmin, gc%xmax, err, block, grid_axis_nodes(gc, 1), &
                             grid_axis_nodes(gc, 2), grid_axis_nodes(gc, 3))
        else
          ! (the deck reader checked the file; read again, it is checked again;
          ! a block reads its stored nodes only)
          if (present(block)) then
            call grid_file_read(gc%file_path, gc%ni, gc%nj, gc%nk, xfile, err, block%slo - 1 + block%off, &
                                block%shi + block%off)
          else
            call grid_file_read(gc%file_path, gc%ni, gc%nj, gc%nk, xfile, err)
          end if
          if (allocated(err)) then
            call error_set(err, deck_problem, '&grid: '//err%msg, ERR_INPUT)
            exit scene
          end if
          if (present(block)) then
            call grid_init_nodes(g, gc%ni, gc%nj, gc%nk, xfile, err, block, reshape([gc%xmin, gc%xmax], [3, 2]))
          else
            call grid_init_nodes(g, gc%ni, gc%nj, gc%nk, xfile, err)
          end if
          deallocate(xfile)
          call log_line(log, 'grid: node positions from '//gc%file_path)
        end if
        if (allocated(err)) exit scene
        call hydro_allocate(hy, g%ncell, g%nnode, err, step_work=.not. remap)
        if (allocated(err)) exit scene

        allocate(st%mats(size(cfg%materials)), stat=stat, errmsg=msg)
        if (stat /= 0) then
          call error_set(err, 'build_scene', error_no_memory('the materials'))
          exit scene
        end if
        do m = 1, size(cfg%materials)
          st%mats(m)%name = trim(cfg%materials(m)%name)
          call eos_create(cfg%materials(m)%eos, cfg%materials(m)%par, st%mats(m)%eos, err)
          if (allocated(err)) then
            call error_set(err, deck_problem, '&material '//st%mats(m)%name//': '//err%msg, ERR_INPUT)
            exit scene
          end if
          st%mats(m)%p_min = cfg%materials(m)%p_min
          st%mats(m)%rho_min = cfg%materials(m)%rho_min
        end do

        do c = 1, g%ncell
          call g%gather(c, g%x, xn)
          hy%vol(c) = hex_volume(xn)
        end do
        ! a &prerun: the 1D run (once: a decomposed run's whole grid takes the
        ! blocks'), its overlaps' factors over the grid, and the start time
        ! (t_end <= &prerun time: the 1D run alone, no mapping)
        mapping = .false.
        if (cfg%pre1d%time > 0.0_wp .and. len_trim(cfg%control%restart_from) == 0 .and. .not. fluid) then
          if (.not. allocated(st%pre1d)) then
            allocate(st%pre1d, stat=stat)
            if (stat /= 0) then
              call error_set(err, 'build_scene', error_no_memory('the 1D run'))
              exit scene
            end if
            call prerun_run(cfg, st%mats, log, st%pre1d, err)
            if (allocated(err)) exit scene
            if (cfg%control%t_end > cfg%pre1d%time) call prerun_plan(cfg, log, st%pre1d, err)
            if (allocated(err)) exit scene
          end if
          mapping = cfg%control%t_end > cfg%pre1d%time
        end if
        if (mapping) then
          call prerun_scale(st%pre1d, g, st%halo, err)
          if (allocated(err)) exit scene
          if (allocated(st%pre1d%prad)) deallocate(st%pre1d%prad, st%pre1d%hit)
          allocate(st%pre1d%prad(g%ncell), st%pre1d%hit(g%ncell), stat=stat)
          if (stat /= 0) then
            call error_set(err, 'build_scene', error_no_memory('the mapping'))
            exit scene
          end if
          st%pre1d%prad = 0.0_wp
          st%pre1d%hit = .false.
          st%t = cfg%pre1d%time
        end if
        if (fluid) then
          call fill_plain(cfg, st, err)
        else
          call fill_regions(cfg, st, log, err)
        end if
        if (allocated(err)) exit scene
        ! a node takes the velocity field of the last region that contains it
        do n = 1, g%nnode
          r = region_at(cfg%regions, g%x(:, n))
          if (r > 0) hy%u(:, n) = region_velocity(cfg%regions(r), g%x(:, n))
        end do
        call rng_seed(st%rng, cfg%control%seed)
        if (cfg%control%velocity_noise > 0.0_wp) call velocity_noise(g, cfg%control%velocity_noise, st%rng, hy%u)
        ! energy sources: added to the cell that contains the point (on a box
        ! grid the cell of global index int((p - xmin)/h) + 1, a point on a
        ! face going to the cell above it, on every block that stores it; on a
        ! grid from a file, the cell found by the gauges' search, which must
        ! contain the point)
        h = (gc%xmax - gc%xmin)/real([gc%ni, gc%nj, gc%nk], wp)
        do s = 1, size(cfg%sources)
          if (len_trim(gc%file) == 0 .and. gc%graded()) then
            ! (a graded box: the cell between the node planes about the point)
            do a = 1, 3
              xa = grid_axis_nodes(gc, a)
              ijk(a) = count(xa(2:size(xa) - 1) <= cfg%sources(s)%position(a)) + 1
            end do
          else if (len_trim(gc%file) == 0) then
            ijk = int((cfg%sources(s)%position - gc%xmin)/h) + 1
            ijk = max(1, min([gc%ni, gc%nj, gc%nk], ijk))
          else
            ! the block that owns the cell containing the point says which
            ! (the lowest such cell of the whole grid, `gauge_locate`)
            call gauge_locate(g, cfg%sources(s)%position, 0, c, xi, inside)
            call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
            key = huge(1.0_wp)
            if (inside .and. g%owns_cell(ijk(1), ijk(2), ijk(3))) key = real(g%global_cell(c), wp)
            call st%halo%choose(key, xi)
            if (.not. key < huge(1.0_wp)) then
              call error_set(err, deck_problem, '&source('//itoa(s)//'): position is not inside the grid of '// &
                             'file '''//trim(gc%file)//'''', ERR_INPUT)
              exit scene
            end if
            ijk = [mod(nint(key) - 1, gc%ni) + 1, mod((nint(key) - 1)/gc%ni, gc%nj) + 1, (nint(key) - 1)/(gc%ni*gc%nj) + 1]
          end if
          call log_line(log, 'source '//itoa(s)//': energy '//rtoa(cfg%sources(s)%energy)// &
                        ' deposited in cell '//itoa(ijk(1) + gc%ni*((ijk(2) - 1) + gc%nj*(ijk(3) - 1))))
          ! (every block that stores the cell)
          ijk = ijk - g%off
          if (any(ijk < g%slo .or. ijk > g%shi)) cycle
          c = g%cell(ijk(1), ijk(2), ijk(3))
          hy%e(c) = hy%e(c) + cfg%sources(s)%energy/hy%mass(c)
          if (hy%mat(c) < 0) then
            ! a mixed cell: every material gets the same specific energy
            associate (k => -hy%mat(c))
              mx%e(mx%start(k):mx%start(k + 1) - 1) = &
                mx%e(mx%start(k):mx%start(k + 1) - 1) + cfg%sources(s)%energy/hy%mass(c)
            end associate
          end if
        end do

        call hydro_subcell_masses(g, g%x, hy%rho, hy%mnode, hy%mcorner)
        if (mapping) then
          call prerun_nodes(st%pre1d, g, hy%mass, hy%mnode, hy%mat, mx, hy%u, hy%e, err)
          if (allocated(err)) exit scene
          call log_line(log, 'prerun: mapped into '//itoa(count(st%pre1d%hit))//' stored cells at t = '//rtoa(st%t))
        end if

        call material_index_cells(st%mats, hy%mat, mx, err)
        if (allocated(err)) exit scene
        ! (a mapped 1D run has burnt its charge, checked by `prerun_run`: no
        ! burn on any copy of the state, nor after a restart)
        if (.not. (cfg%pre1d%time > 0.0_wp .and. cfg%control%t_end > cfg%pre1d%time)) call setup_burn(cfg, st, log, err)
        if (allocated(err)) exit scene
        call material_burn_start(st%mats, st%t)
        ! the mixed cells' interface planes, fitted to the exact fractions and
        ! centroids: how far the first remap's reference is from a plane
        call centroids_fit_planes(g, mx, planes, cfg%rezone%mof_max_iter)
        if (mx%n > 0) call log_line(log, 'mixed-cell planes of the scene: '//centroid_text(planes))
        call material_eval_eos(st%mats, hy%rho, hy%e, hy%p, hy%cs, mx)
        call mixed_cell_state(mx, hy%p, hy%cs)
        ! each cell's largest pressure so far (only when the frames write it)
        if (cfg%output%max_pressure) then
          allocate(st%p_max(g%ncell), source=hy%p, stat=stat, errmsg=msg)
          if (stat /= 0) then
            call error_set(err, 'build_scene', error_no_memory('the maximum pressure'))
            exit scene
          end if
        end if

        associate (bc => st%bc, bcc => cfg%boundary)
          bc%kind = bcc%kind
          bc%velocity = bcc%velocity
          bc%pressure = bcc%pressure
          do m = 1, 6
            if (bcc%inflow_mat(m) == 0) cycle
            bc%inflow_mat(m) = bcc%inflow_mat(m)
            bc%inflow_rho(m) = bcc%inflow_density(m)
            bc%inflow_e(m) = st%mats(bcc%inflow_mat(m))%eos%energy(bcc%inflow_density(m), bcc%inflow_pressure(m))
          end do
          bc%nfixed = bcc%nfixed
          bc%fixed_box = bcc%fixed_box
          call bc_init(bc, g, err)
          if (allocated(err)) exit scene
          ! the boundary conditions hold from t = 0
          call bc_constrain(bc, hy%u)
        end associate
      end associate
    end block scene
    if (failed_anywhere(st%halo, err)) return
    if (.not. (fluid .or. remap)) call fixed_boxes_check(st, log, err)
    if (allocated(err)) return
    ! (a block constrains the boundary nodes it owns; its ghost nodes on a
    ! wall get theirs from the block that owns them)
    call st%halo%nodes(st%h%u)
    ! the MPM particles (none without &particles: nothing allocated)
    ! (the blocks of a decomposed run seed theirs after: `whole_build`)
    if (st%halo%nblocks == 1 .and. .not. fluid) call build_particles(cfg, st, log, err)
    if (allocated(err)) return
    call state_totals(st)
    st%tot%energy_initial = st%tot%internal + st%tot%kinetic
    st%ready = .true.
    call log_line(log, 'grid: '//itoa(st%g%ni)//' x '//itoa(st%g%nj)//' x '//itoa(st%g%nk)// &
                  ' cells, '//itoa(st%g%nnode)//' nodes, '//itoa(size(st%mats))//' material(s)')
    ! (a graded box: the widths its pairs came to, scaled to the cells)
    if (len_trim(cfg%grid%file) == 0 .and. cfg%grid%graded()) then
      do a = 1, 3
        xa = grid_axis_nodes(cfg%grid, a)
        n = size(xa) - 1
        call log_line(log, 'grid: along '//achar(119 + a)//' cell widths '//rtoa(minval(xa(2:) - xa(:n)))// &
                      ' to '//rtoa(maxval(xa(2:) - xa(:n))))
      end do
    end if
  end subroutine build_scene

  !> The nodes each &boundary fixed box fixes, the whole grid's, in the log;
  !> a box that holds none is refused (a user error: a box beside the grid
  !> or between its nodes). Collective.
  subroutine fixed_boxes_check(st, log, err)
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    integer :: n(bc_max_fixed), q
    character(len=:), allocatable :: text
    if (st%bc%nfixed == 0) return
    n = st%bc%fixed_count
    call st%halo%sum_ints(n)
    text = 'boundary: fixed nodes'
    do q = 1, st%bc%nfixed
      text = text//merge(': ', ', ', q == 1)//itoa(n(q))//' in box '//itoa(q)
    end do
    call log_line(log, text)
    do q = 1, st%bc%nfixed
      if (n(q) > 0) cycle
      call error_set(err, deck_problem, '&boundary fixed box '//itoa(q)//' (fixed_lo(:,'//itoa(q)// &
        '), fixed_hi(:,'//itoa(q)//')) holds no node of the grid', ERR_INPUT)
      return
    end do
  end subroutine fixed_boxes_check

  !> Whether err is allocated on any block (on one process: here). A block
  !> where nothing failed keeps err unallocated: the driver's agree_error
  !> then gives every rank the failed rank's own message.
  logical function failed_anywhere(halo, err)
    class(halo_t), intent(in) :: halo
    type(error_t), allocatable, intent(in) :: err
    integer :: flag
    flag = merge(1, 0, allocated(err))
    call halo%max_int(flag)
    failed_anywhere = flag > 0
  end function failed_anywhere

  !> The programmed burn of each explosive that a &detonation lights
  !> (`material_burn`): its CJ state from the JWL and the unreacted state of
  !> its first region, checked against a given detonation velocity; each
  !> stored cell's lighting time and burn time (the least over its
  !> initiators). Explosives no &detonation names start as before: all
  !> products at once (constant-volume detonation).
  subroutine setup_burn(cfg, st, log, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    integer :: m, k, c, stat, ni, nj, nk, i, j, kk, q, unlit
    real(wp) :: rho0, v_cj, dv, xn(3, 8), xc(3), d, dir(3), t, w, tmin, tmax
    real(wp), allocatable :: ax(:), ay(:), az(:), dist(:), dirs(:, :)
    logical, allocatable :: mask(:, :, :)
    logical :: ok
    character(len=200) :: msg
    character(len=100) :: who

    do m = 1, size(st%mats)
      if (.not. any(cfg%detonations%imat == m)) cycle
      who = '&material '''//st%mats(m)%name//''''
      if (.not. burn_state(cfg, st%mats(m), m, log, rho0, dv, v_cj, err)) cycle
      if (allocated(err)) return
      allocate(st%mats(m)%burn, stat=stat, errmsg=msg)
      if (stat == 0) allocate(st%mats(m)%burn%light(st%g%ncell), st%mats(m)%burn%tau(st%g%ncell), &
                              st%mats(m)%burn%f(st%g%ncell), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'setup_burn', error_no_memory('the lighting times'))
        return
      end if
      associate (b => st%mats(m)%burn, g => st%g)
        b%rho0 = rho0
        b%v_cj = v_cj
        b%light = huge(1.0_wp)
        b%tau = 1.0_wp
        do k = 1, size(cfg%detonations)
          associate (dk => cfg%detonations(k))
            if (dk%imat /= m) cycle
            if (dk%path == 'around') then
              if (st%halo%nblocks > 1 .or. len_trim(cfg%grid%file) > 0) then
                call error_set(err, deck_problem, '&detonation('//itoa(k)//'): path = ''around'' needs one '// &
                               'process and a box grid (&grid without file) for now; use path = ''straight''', &
                               ERR_INPUT)
                return
              end if
              ni = g%ni; nj = g%nj; nk = g%nk
              allocate(ax(0:ni), ay(0:nj), az(0:nk), mask(ni, nj, nk), dist(ni*nj*nk), dirs(3, ni*nj*nk), &
                       stat=stat, errmsg=msg)
              if (stat /= 0) then
                call error_set(err, 'setup_burn', error_no_memory('the shortest paths'))
                return
              end if
              if (cfg%grid%graded()) then
                ax = grid_axis_nodes(cfg%grid, 1)
                ay = grid_axis_nodes(cfg%grid, 2)
                az = grid_axis_nodes(cfg%grid, 3)
              else
                ax = cfg%grid%xmin(1) + (cfg%grid%xmax(1) - cfg%grid%xmin(1))*[(real(i, wp), i = 0, ni)]/real(ni, wp)
                ay = cfg%grid%xmin(2) + (cfg%grid%xmax(2) - cfg%grid%xmin(2))*[(real(i, wp), i = 0, nj)]/real(nj, wp)
                az = cfg%grid%xmin(3) + (cfg%grid%xmax(3) - cfg%grid%xmin(3))*[(real(i, wp), i = 0, nk)]/real(nk, wp)
              end if
              do kk = 1, nk
                do j = 1, nj
                  do i = 1, ni
                    mask(i, j, kk) = holds(g%cell(i, j, kk))
                  end do
                end do
              end do
              call burn_around(ni, nj, nk, ax, ay, az, mask, reshape(dk%point, [3, 1]), [dk%time*dv], dist, dirs, ok)
              if (.not. ok) then
                call error_set(err, 'setup_burn', error_no_memory('the shortest paths'))
                return
              end if
              do kk = 1, nk
                do j = 1, nj
                  do i = 1, ni
                    q = i + ni*((j - 1) + nj*(kk - 1))
                    c = g%cell(i, j, kk)
                    if (.not. dist(q) < huge(1.0_wp)) cycle
                    t = dist(q)/dv
                    if (t < b%light(c)) then
                      call g%gather(c, g%x, xn)
                      b%light(c) = t
                      b%tau(c) = cfg%materials(m)%burn_width*burn_width_across(xn, dirs(:, q))/dv
                    end if
                  end do
                end do
              end do
              deallocate(ax, ay, az, mask, dist, dirs)
            else
              do c = 1, g%ncell
                call g%gather(c, g%x, xn)
                xc = sum(xn, dim=2)/8.0_wp
                call burn_initiator(initiator_kind(dk%shape), dk%point, dk%point2, dk%normal, xc, d, dir)
                t = dk%time + d/dv
                if (t < b%light(c)) then
                  w = burn_width_across(xn, dir)
                  b%light(c) = t
                  b%tau(c) = cfg%materials(m)%burn_width*w/dv
                end if
              end do
            end if
          end associate
        end do
        ! the earliest and latest lighting of its owned cells over all blocks
        unlit = 0
        tmin = huge(1.0_wp)
        tmax = -huge(1.0_wp)
        do kk = g%clo(3), g%chi(3)
          do j = g%clo(2), g%chi(2)
            do i = g%clo(1), g%chi(1)
              c = g%cell(i, j, kk)
              if (.not. holds(c)) cycle
              if (b%light(c) < huge(1.0_wp)) then
                tmin = min(tmin, b%light(c))
                tmax = max(tmax, b%light(c))
              else
                unlit = unlit + 1
              end if
            end do
          end do
        end do
        q = 0
        call st%halo%min_step(tmin, q)
        tmax = -tmax
        call st%halo%min_step(tmax, q)
        call st%halo%max_int(unlit)   ! (a flag: some block has unlit cells)
        call log_line(log, 'detonation: '//trim(who)//' lit from t = '//rtoa(tmin)//' to '//rtoa(-tmax)// &
                      ' (cell centres)')
        if (unlit > 0) call log_line(log, 'detonation: '//trim(who)//': some of its cells no path reaches '// &
                                     '(they burn only if compressed)')
      end associate
    end do

  contains

    !> Cell c holds material m (pure or in a mixed cell).
    logical function holds(cc)
      integer, intent(in) :: cc
      integer :: s
      holds = st%h%mat(cc) == m
      if (st%h%mat(cc) < 0) then
        do s = st%mx%start(-st%h%mat(cc)), st%mx%start(-st%h%mat(cc) + 1) - 1
          if (st%mx%mat(s) == m) holds = .true.
        end do
      end if
    end function holds
  end subroutine setup_burn

  pure integer function initiator_kind(shape) result(kind)
    character(len=*), intent(in) :: shape
    select case (shape)
    case ('line')
      kind = INIT_LINE
    case ('plane')
      kind = INIT_PLANE
    case default
      kind = INIT_POINT
    end select
  end function initiator_kind


  !> A window's fill (`build_scene` with fluid_only): the first region's
  !> material and state in every cell, no mixed cell. A window takes its
  !> state from the blocks at every Euler step (`driver_whole`'s
  !> copy_gather) before it is read, so the regions' exact moments
  !> (`fill_regions`, a cell-cycle per cell) are not paid for again; this
  !> state only has to be one the EOS evaluates.
  subroutine fill_plain(cfg, st, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: e1
    associate (r1 => cfg%regions(1), hy => st%h)
      e1 = r1%energy
      if (e1 < 0.0_wp) e1 = st%mats(r1%imat)%eos%energy(r1%density, r1%pressure)
      hy%mat = r1%imat
      hy%rho = r1%density
      hy%e = e1
      hy%mass = hy%rho*hy%vol
    end associate
    call mixed_allocate(st%mx, 0, 0, err)
  end subroutine fill_plain

  !> Fills the cells from the regions (applied in deck order, a later one
  !> overriding an earlier one). Each cell's volume and first moment held by
  !> every region come from `shapes_cell_moments` (exact for planar region
  !> boundaries, curved ones resolved to 1/subsamples of the cell: module
  !> geometry_shapes), which make the volume fractions, masses, energies and
  !> centroids of its materials. A cell with one material is pure (with the
  !> state of its region if one region holds it all, else the mass-averaged
  !> state of its regions); a cell with several is a mixed cell. A region's
  !> share below 1e-12 of a cell is round-off of the clipping (a boundary
  !> on a cell face) and is left out.
  subroutine fill_regions(cfg, st, log, err)
    type(config_t), intent(in) :: cfg
    type(state_t), intent(inout) :: st
    type(log_t), intent(in) :: log
    type(error_t), allocatable, intent(inout) :: err
    integer :: nmat, nreg, c, m, k, nmix, nslot, s, nm, r_only, depth
    real(wp), allocatable :: vfm(:), massm(:), enm(:), xim(:, :), e_reg(:)
    real(wp), allocatable :: keep(:, :), grown(:, :)
    type(shape_t), allocatable :: shapes(:)
    logical :: covered, hit
    logical, allocatable :: used(:)
    character(len=200) :: msg
    real(wp) :: took(5), ref(3)
    type(xsum_t) :: acc(5)
    integer :: ijk(3)
    logical :: mapped

    mapped = .false.
    if (allocated(st%pre1d)) mapped = allocated(st%pre1d%prad)
    associate (g => st%g, hy => st%h, mx => st%mx)
      nmat = size(cfg%materials)
      nreg = size(cfg%regions)
      allocate(vfm(nmat), massm(nmat), enm(nmat), xim(3, nmat), e_reg(nreg), used(nreg), shapes(nreg), &
               keep(6*nmat, 64), stat=k, errmsg=msg)
      if (k /= 0) then
        call error_set(err, 'fill_regions', error_no_memory('work arrays'))
        return
      end if
      used = .false.
      do k = 1, nreg
        shapes(k) = region_shape(cfg%regions(k))
        associate (rg => cfg%regions(k))
          if (rg%energy >= 0.0_wp) then
            e_reg(k) = rg%energy
          else
            e_reg(k) = st%mats(rg%imat)%eos%energy(rg%density, rg%pressure)
          end if
        end associate
      end do
      ! the split depth that resolves curved boundaries to 1/subsamples of a cell
      depth = 0
      do while (2**depth < cfg%grid%subsamples)
        depth = depth + 1
      end do
      ! pass 1: pure cells get their state, mixed cells are counted and
      ! their materials kept (6 numbers per material: fraction, mass,
      ! energy, centroid)
      nmix = 0
      nslot = 0
      do c = 1, g%ncell
        if (mapped) then
          call cell_materials(cfg, g, hy%vol(c), c, shapes, depth, e_reg, vfm, massm, enm, xim, covered, r_only, used, &
                              st%pre1d, took, hit)
          st%pre1d%prad(c) = took(3)
          st%pre1d%hit(c) = hit
          call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
          if (g%owns_cell(ijk(1), ijk(2), ijk(3))) then
            do k = 1, 5
              call xsum_add(acc(k), took(k))
            end do
          end if
          if (.not. covered .and. hit) then
            call error_set(err, deck_problem, '&prerun: cell '//itoa(c)//' lies inside the mapped sphere and '// &
              'holds a region the 1D run did not take (only shape ''all'' and spheres about its centre); '// &
              'map earlier or move the region', ERR_INPUT)
            return
          end if
        else
          call cell_materials(cfg, g, hy%vol(c), c, shapes, depth, e_reg, vfm, massm, enm, xim, covered, r_only, used)
        end if
        if (.not. covered) then
          call error_set(err, deck_problem, 'cell '//itoa(c)// &
            ' is not covered by any &region; add a region with shape = ''all'' first', ERR_INPUT)
          return
        end if
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
          if (nmix > size(keep, 2)) then
            allocate(grown(size(keep, 1), 2*size(keep, 2)), stat=k, errmsg=msg)
            if (k /= 0) then
              call error_set(err, 'fill_regions', error_no_memory('work arrays'))
              return
            end if
            grown(:, 1:size(keep, 2)) = keep
            call move_alloc(grown, keep)
          end if
          keep(:, nmix) = [vfm, massm, enm, reshape(xim, [3*nmat])]
        end if
      end do
      if (mapped) then
        ! (exact sums over the blocks' owned cells)
        call st%halo%sums(acc)
        ref = prerun_totals(st%pre1d)
        call log_line(log, 'prerun: mapped mass '//trim(full(xsum_value(acc(1))))//', total energy '// &
                      trim(full(xsum_value(acc(2))))//', radial momentum '//trim(full(xsum_value(acc(3))))// &
                      ' (the 1D run''s within the mapped radius: '//trim(full(ref(1)))//', '//trim(full(ref(2)))// &
                      ', '//trim(full(ref(3)))//'); the regions'' part: mass '//trim(full(xsum_value(acc(4))))// &
                      ', energy '//trim(full(xsum_value(acc(5)))))
      end if
      ! a region that gives no cell any material is most likely a mistake
      ! (outside the box, or hidden by later regions): say so
      do k = 1, nreg
        if (.not. used(k)) call log_line(log, 'WARNING: &region('//itoa(k)//') ('//trim(cfg%regions(k)%shape)// &
          ') fills no part of any cell: it lies outside the grid or later '// &
          'regions cover it')
      end do
      ! pass 2: the mixed cells' slots
      call mixed_allocate(mx, nmix, nslot, err)
      if (allocated(err)) return
      k = 0
      s = 0
      do c = 1, g%ncell
        if (hy%mat(c) > 0) cycle
        k = k + 1
        vfm = keep(1:nmat, k)
        massm = keep(nmat + 1:2*nmat, k)
        enm = keep(2*nmat + 1:3*nmat, k)
        xim = reshape(keep(3*nmat + 1:6*nmat, k), [3, nmat])
        mx%cell(k) = c
        do m = 1, nmat
          if (.not. (vfm(m) > 0.0_wp)) cycle
          s = s + 1
          mx%mat(s) = m
          mx%vf(s) = vfm(m)
          mx%mass(s) = massm(m)
          mx%e(s) = enm(m)/massm(m)
          mx%rho(s) = massm(m)/(vfm(m)*hy%vol(c))
          mx%xi(:, s) = xim(:, m)
        end do
        mx%start(k + 1) = s + 1
        hy%mass(c) = sum(massm)
        hy%rho(c) = hy%mass(c)/hy%vol(c)
        hy%e(c) = sum(enm)/hy%mass(c)
      end do
      if (nmix > 0) call log_line(log, 'mixed cells: '//itoa(nmix)//' ('//itoa(nslot)//' material slots)')
    end associate

  contains

    !> x with all its digits (the log's record of a conservation check).
    function full(x) result(text)
      real(wp), intent(in) :: x
      character(len=24) :: text
      write(text, '(es24.16e3)') x
      text = adjustl(text)
    end function full
  end subroutine fill_regions

  !> Volume fraction, mass, internal energy and centroid (natural
  !> coordinates) of each material in cell c (volume vol) from the regions'
  !> shapes (`shapes_cell_moments` at the given depth); r_only is the
  !> region that holds the whole cell, if one does (else 0); covered is false
  !> if more than round-off of the cell is in no region.
  subroutine cell_materials(cfg, g, vol, c, shapes, depth, e_reg, vfm, massm, enm, xim, covered, r_only, used, &
                            pr, took, hit)
    type(config_t), intent(in) :: cfg
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: vol
    integer, intent(in) :: c, depth
    type(shape_t), intent(in) :: shapes(:)
    real(wp), intent(in) :: e_reg(:)
    real(wp), intent(out) :: vfm(:), massm(:), enm(:), xim(:, :)
    logical, intent(out) :: covered
    integer, intent(out) :: r_only
    logical, intent(inout) :: used(:)
    type(prerun_t), intent(inout), optional :: pr
    !> with pr: what the cell took of the 1D run (mass, total energy, radial
    !> momentum) and of the regions (mass, internal energy)
    real(wp), intent(out), optional :: took(5)
    logical, intent(out), optional :: hit
    real(wp) :: xn(3, 8), vreg(0:size(shapes)), mreg(3, 0:size(shapes)), vtot, f, xc(3), mm(3, size(vfm))
    real(wp) :: vmp(size(vfm)), mmp(size(vfm)), emp(size(vfm)), xmp(3, size(vfm)), vin, fout, sfac, prad
    integer :: r, m, nkept

    call g%gather(c, g%x, xn)
    call shapes_cell_moments(xn, shapes, depth, vreg, mreg)
    vtot = sum(vreg)
    covered = vreg(0) <= 1.0e-12_wp*vtot
    vfm = 0.0_wp; massm = 0.0_wp; enm = 0.0_wp; xim = 0.0_wp; mm = 0.0_wp
    r_only = 0
    if (present(took)) took = 0.0_wp
    if (present(hit)) hit = .false.
    if (.not. covered) return
    ! round-off slivers out, the others renormalised
    nkept = 0
    do r = 1, size(shapes)
      if (vreg(r) > 1.0e-12_wp*vtot) then
        nkept = nkept + 1
        r_only = r
      else
        vreg(r) = 0.0_wp
      end if
    end do
    if (nkept /= 1) r_only = 0
    vtot = sum(vreg(1:size(shapes)))
    do r = 1, size(shapes)
      if (.not. vreg(r) > 0.0_wp) cycle
      used(r) = .true.
      m = cfg%regions(r)%imat
      f = vreg(r)/vtot
      vfm(m) = vfm(m) + f
      massm(m) = massm(m) + f*cfg%regions(r)%density*vol
      enm(m) = enm(m) + f*cfg%regions(r)%density*e_reg(r)*vol
      mm(:, m) = mm(:, m) + mreg(:, r)
    end do
    ! a &prerun's 1D run inside its mapped radius replaces what the regions
    ! put there (only the regions it took may lie wholly inside)
    if (present(pr)) then
      call prerun_cell(pr, xn, vmp, mmp, emp, xmp, vin, prad)
      hit = vin > 0.0_wp
      took = [0.0_wp, 0.0_wp, 0.0_wp, sum(massm), sum(enm)]
      if (hit) then
        do r = 1, size(shapes)
          if (vreg(r) > 0.0_wp .and. .not. pr%in1d(r) .and. vin >= (1.0_wp - 1.0e-9_wp)*vol) then
            covered = .false.   ! (the caller's refusal names the cell)
            return
          end if
        end do
        ! the regions keep the part outside the mapped radius; the 1D run's
        ! materials share the rest by their (scaled) volumes
        fout = 1.0_wp - vin/vol
        if (fout < 1.0e-12_wp) fout = 0.0_wp   ! (round-off of a cell wholly inside)
        sfac = (1.0_wp - fout)*vol/sum(vmp)
        vfm = fout*vfm + vmp*sfac/vol
        took = [sum(mmp), sum(emp), prad, fout*sum(massm), fout*sum(enm)]
        massm = fout*massm + mmp
        enm = fout*enm + emp
        mm = fout*mm + xmp*sfac
        vtot = vol
        r_only = 0
      end if
    end if
    ! centroids: the first moments are about the mean of the nodes
    xc = 0.125_wp*sum(xn, 2)
    do m = 1, size(vfm)
      if (vfm(m) > 0.0_wp) xim(:, m) = hex_natural(xn, xc + mm(:, m)/(vfm(m)*vtot))
    end do
  end subroutine cell_materials

  !> The shape of a region, for `geometry_shapes`.
  pure function region_shape(rg) result(sh)
    type(region_config_t), intent(in) :: rg
    type(shape_t) :: sh
    sh = shape_t(kind=shape_kind(rg%shape), lo=rg%lo, hi=rg%hi, center=rg%center, radius=rg%radius, &
                 inner_radius=rg%inner_radius, normal=rg%normal, axis=rg%axis)
  end function region_shape

  !> The last region (in deck order) that contains point p, or 0.
  pure integer function region_at(regions, p)
    type(region_config_t), intent(in) :: regions(:)
    real(wp), intent(in) :: p(3)
    integer :: r
    region_at = 0
    do r = size(regions), 1, -1
      if (inside(regions(r), p)) then
        region_at = r
        return
      end if
    end do
  end function region_at

  !> The initial velocity a region gives a node at p (length/time):
  !> 'uniform' its velocity; 'radial' velocity + speed (p - center)/|p - center|
  !> (just velocity at the centre itself; speed < 0 points inward, as in
  !> Noh's problem); 'rotation' velocity + angular_velocity a x (p - center),
  !> a rigid rotation about the region's axis a through center.
  pure function region_velocity(rg, p) result(u)
    type(region_config_t), intent(in) :: rg
    real(wp), intent(in) :: p(3)
    real(wp) :: u(3), d(3), r, a(3)
    u = rg%velocity
    d = p - rg%center
    select case (trim(rg%velocity_field))
    case ('radial')
      ! (sqrt of a sum of squares, not norm2: exact under scaling by powers of two)
      r = sqrt(dot_product(d, d))
      if (r > 0.0_wp) u = u + rg%speed*(d/r)
    case ('rotation')
      a = 0.0_wp
      a(rg%axis) = 1.0_wp
      u = u + rg%angular_velocity*cross(a, d)
    end select
  end function region_velocity

  !> True if point p lies in the region's shape.
  pure logical function inside(rg, p)
    type(region_config_t), intent(in) :: rg
    real(wp), intent(in) :: p(3)
    inside = shape_inside(region_shape(rg), p)
  end function inside
  !> A uniform random velocity in [-amp, amp) added to each component of
  !> the stored nodes' velocities u of g, drawn from r in the whole grid's
  !> node order (k, j, i, then the components), so that a block's nodes get
  !> the numbers they get on one block: each row of the block's nodes from
  !> its first node's place in the sequence (`rng_jump`), not every node of
  !> the whole grid drawn on every rank. r ends past every node's draws, as
  !> one block leaves it.
  subroutine velocity_noise(g, amp, r, u)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: amp
    type(rng_t), intent(inout) :: r
    real(wp), intent(inout) :: u(:, :)
    type(rng_jump_t) :: to_row, to_plane, to_first
    type(rng_t) :: plane, row, q
    integer(i8) :: nx, ny
    integer :: lo(3), hi(3), i, j, k, a, n
    nx = g%gn(1) + 1
    ny = g%gn(2) + 1
    lo = g%slo - 1 + g%off
    hi = g%shi + g%off
    to_row = rng_jump(3*nx)
    to_plane = rng_jump(3*nx*ny)
    to_first = rng_jump(3*(lo(1) + nx*lo(2)))
    plane = r
    call rng_apply(rng_jump(3*nx*ny*lo(3)), plane)
    do k = lo(3), hi(3)
      row = plane
      call rng_apply(to_first, row)
      do j = lo(2), hi(2)
        q = row
        do i = lo(1), hi(1)
          n = g%node(i - g%off(1), j - g%off(2), k - g%off(3))
          do a = 1, 3
            u(a, n) = u(a, n) + amp*(2.0_wp*rng_uniform(q) - 1.0_wp)
          end do
        end do
        call rng_apply(to_row, row)
      end do
      call rng_apply(to_plane, plane)
    end do
    call rng_apply(rng_jump(3*nx*ny*(g%gn(3) + 1)), r)
  end subroutine velocity_noise
end module driver_scene
