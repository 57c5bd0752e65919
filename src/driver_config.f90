!> The resolved configuration of a run: the &run group (time control,
!> restarts, progress), which configures the driver itself, and the
!> configuration of every package, each read, validated and echoed by the
!> package's own config module from the text of its group (`io_deck` finds
!> the groups). Read-only once the deck has been read.
module driver_config
  use base_kinds, only: wp
  use base_strings, only: itoa, lower
  use base_config, only: max_line, no_echo, problem_add, problem_bad, problem_badi, problem_nml, problem_long, diff_i, diff_r
  use base_errors, only: error_no_memory, error_t
  use mesh_grid_config, only: grid_config_t, grid_config_read, grid_config_changes, grid_axis_nodes
  use io_grid_file, only: grid_file_read, grid_file_scan
  use mesh_boundary_config, only: boundary_config_t, boundary_config_read, boundary_config_changes
  use mesh_boundary, only: BC_VELOCITY, BC_PRESSURE
  use material_config, only: material_config_t, material_config_read, material_config_changes
  use material_library, only: units_known, units_list, library_value
  use hydro_state, only: hydro_params_t
  use lagrange_config, only: hydro_config_read
  use rezone_config, only: rezone_config_t, rezone_config_read
  use io_deck, only: deck_t, deck_read, deck_from_lines, text_lines, deck_count, deck_text, deck_where, echo_open, &
                     echo_text
  use io_output_config, only: output_config_t, output_config_read
  use io_points_file, only: points_file_read
  use mesh_grid, only: grid_t, grid_index_t, grid_init_box, grid_init_nodes, grid_index_block
  use mesh_shapes, only: shape_t, shape_kind
  use particles_seed, only: seed_count
  use io_stl, only: stl_read
  use particles_config, only: solid_config_t, particles_config_t, solid_config_read, particles_config_read, &
                              particles_config_changes, particles_file_place
  use driver_scene_config, only: region_config_t, source_config_t, region_config_read, source_config_read, &
                                 scene_config_changes, detonation_config_t, detonation_config_read, &
                                 prerun_config_t, prerun_config_read
  implicit none
  private
  public :: run_config_t, config_t, config_read, config_state_changes, config_defaults_text, group_shape, shape_slabs

  !> The deck's groups, in the order they are read and echoed.
  character(len=*), parameter :: known_groups(13) = [character(len=10) :: &
    'run', 'grid', 'hydro', 'material', 'region', 'source', 'detonation', 'prerun', 'solid', 'particles', 'boundary', &
    'rezone', 'output']
  !> The groups a deck may give more than once.
  character(len=*), parameter :: repeatable_groups(6) = [character(len=10) :: 'material', 'region', 'source', &
                                                         'detonation', 'solid', 'particles']

  !> The resolved &run group; the initial values are the defaults (cfl,
  !> dt_growth and dt_max are stored in `config_t%hydro`, where the
  !> Lagrangian step reads them).
  type :: run_config_t
    character(len=200) :: title = 'untitled'
    character(len=64) :: units = ''            !< the deck's unit system, a label stored with the outputs
    real(wp) :: t_end = 0.0_wp                 !< end time (required, > 0)
    integer :: max_steps = 100000000           !< stop after this many steps
    real(wp) :: dt_init = 0.0_wp               !< cap on the first step (0: the stable step)
    real(wp) :: dt_min = 0.0_wp                !< the run fails below this step (0: 1e-12 t_end, resolved)
    integer :: progress_steps = 0              !< a progress line every this many steps (0: by time only)
    real(wp) :: progress_seconds = 10.0_wp     !< a progress line at least this often (wall seconds)
    real(wp) :: velocity_noise = 0.0_wp        !< amplitude of a random velocity added to the nodes
    integer :: seed = 1                        !< seed of the random numbers
    character(len=256) :: restart_from = ''    !< continue from this restart file
    !> the deck's restart_from when the command line's `--restart` replaced it
    character(len=256) :: restart_overridden = ''
    real(wp) :: wall_time_limit = 0.0_wp       !< wall seconds; a restart and exit 3 before it (0: none)
    integer :: dump_steps = 0                  !< a restart every this many steps (0: off)
    real(wp) :: dump_dt = 0.0_wp               !< a restart every this much time (0: off)
    integer :: dump_keep = 2                   !< keep the newest this many restarts
    integer :: blocks(3) = 0                   !< MPI ranks per direction (0: chosen)
    !> the weight of a shape's particle against a cell's in placing the
    !> block cuts of a decomposed run (0: cells alone)
    real(wp) :: blocks_particle_weight = 3.0_wp
  end type run_config_t

  !> The resolved deck.
  type :: config_t
    character(len=:), allocatable :: deck_path
    character(len=:), allocatable :: echo            !< resolved deck as namelist text
    type(run_config_t) :: control                 !< &run: time control, restarts, progress
    type(grid_config_t) :: grid
    type(hydro_params_t) :: hydro                    !< &hydro, and &run's cfl, dt_growth, dt_max
    type(material_config_t), allocatable :: materials(:)
    type(region_config_t), allocatable :: regions(:)
    type(source_config_t), allocatable :: sources(:)
    type(detonation_config_t), allocatable :: detonations(:)     !< &detonation: initiators of explosives
    type(prerun_config_t) :: pre1d                               !< &prerun: a 1D run mapped in (time 0: none)
    type(solid_config_t), allocatable :: solids(:)              !< &solid: solid materials of the particles
    type(particles_config_t), allocatable :: particles(:)       !< &particles: seeding (none: no particles)
    type(boundary_config_t) :: boundary
    type(rezone_config_t) :: rezone
    type(output_config_t) :: output
  end type config_t

contains

  !> Per material: its library entry's density, energy_per_volume and
  !> pressure in the deck's `units` (-1 where it has none, or no entry).
  function library_states(materials, units) result(lib)
    type(material_config_t), intent(in) :: materials(:)
    character(len=*), intent(in) :: units
    real(wp) :: lib(3, size(materials))
    character(len=*), parameter :: keys(3) = [character(len=17) :: 'density', 'energy_per_volume', 'pressure']
    integer :: m, k
    logical :: found
    lib = -1.0_wp
    do m = 1, size(materials)
      if (len_trim(materials(m)%library) == 0) cycle
      do k = 1, 3
        call library_value(trim(materials(m)%library), trim(keys(k)), trim(units), lib(k, m), found)
        if (.not. found) lib(k, m) = -1.0_wp
      end do
    end do
  end function library_states

  !> Reads and validates the deck at `path`, or (`text` present) the deck
  !> text `text` that `path` names. On return `problems` holds one line per
  !> problem found (empty when the deck is usable). `restart` (the command
  !> line's `--restart FILE`) replaces &run restart_from, before it is
  !> validated and echoed.
  subroutine config_read(path, cfg, problems, text, restart)
    character(len=*), intent(in) :: path
    type(config_t), intent(out) :: cfg
    character(len=max_line), allocatable, intent(out) :: problems(:)
    character(len=*), intent(in), optional :: text, restart
    type(deck_t) :: deck
    integer :: echo
    character(len=max_line), allocatable :: lines(:)
    integer, allocatable :: origin(:)
    integer :: stat

    problems = [character(len=max_line) ::]
    cfg%deck_path = path
    if (present(text)) then
      lines = text_lines(text, origin, stat)
      if (stat /= 0) call problem_add(problems, error_no_memory('the stored deck''s lines'))
      call deck_from_lines(lines, path, known_groups, repeatable_groups, deck, problems, origin)
    else
      call deck_read(path, known_groups, repeatable_groups, deck, problems)
    end if
    if (size(problems) > 0 .and. size(deck%groups) == 0) return   ! no readable deck
    if (deck%unsafe) return                                          ! values that would trap
    call echo_open(echo, problems)
    if (echo == no_echo) return
    call read_groups(deck, cfg, echo, problems, restart)
    ! (the files included and the parameters, as comments, then every group
    ! with every value as used)
    cfg%echo = deck%notes//echo_text(echo)
  end subroutine config_read

  !> Every group of `deck`, in order, each by its package; each problem a
  !> group has is prefixed with the deck's name and the group's line.
  subroutine read_groups(deck, cfg, echo, problems, restart)
    type(deck_t), intent(in) :: deck
    type(config_t), intent(inout) :: cfg
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), intent(in), optional :: restart
    character(len=64), allocatable :: names(:)
    integer :: k, n, n0, j

    associate (path => deck%path)
      n0 = size(problems)
      call run_config_read(cfg%control, cfg%hydro, deck_text(deck, 'run'), path, echo, problems, restart)
      call at_line(problems, n0, deck, 'run')
      call grid_config_read(cfg%grid, deck_text(deck, 'grid'), path, echo, problems)
      if (size(problems) == n0 .and. len_trim(cfg%grid%file) > 0) call grid_file_check(cfg%grid, problems)
      call at_line(problems, n0, deck, 'grid')
      call hydro_config_read(cfg%hydro, deck_text(deck, 'hydro'), path, echo, problems)
      call at_line(problems, n0, deck, 'hydro')
      n = deck_count(deck, 'material')
      cfg%materials = [(material_config_t(), k = 1, n)]
      names = [(cfg%materials(k)%name, k = 1, n)]
      if (n == 0) call problem_add(problems, trim(path)//': no &material group (at least one is required)')
      do k = 1, n
        n0 = size(problems)
        call material_config_read(cfg%materials(k), k, deck_text(deck, 'material', k), path, names(1:k - 1), &
                                  cfg%control%units, echo, problems)
        call at_line(problems, n0, deck, 'material', k)
        names(k) = cfg%materials(k)%name
      end do
      n = deck_count(deck, 'region')
      cfg%regions = [(region_config_t(), k = 1, n)]
      if (n == 0) call problem_add(problems, trim(path)//': no &region group (at least one is required)')
      do k = 1, n
        n0 = size(problems)
        call region_config_read(cfg%regions(k), k, deck_text(deck, 'region', k), path, names, echo, problems, &
                                lib=library_states(cfg%materials, cfg%control%units), units=cfg%control%units)
        call at_line(problems, n0, deck, 'region', k)
      end do
      n = deck_count(deck, 'source')
      cfg%sources = [(source_config_t(), k = 1, n)]
      do k = 1, n
        n0 = size(problems)
        call source_config_read(cfg%sources(k), k, deck_text(deck, 'source', k), path, cfg%grid%xmin, &
                                cfg%grid%xmax, echo, problems)
        call at_line(problems, n0, deck, 'source', k)
      end do
      n = deck_count(deck, 'detonation')
      cfg%detonations = [(detonation_config_t(), k = 1, n)]
      do k = 1, n
        n0 = size(problems)
        call detonation_config_read(cfg%detonations(k), k, deck_text(deck, 'detonation', k), path, names, &
                                    [(cfg%materials(j)%eos, j = 1, size(cfg%materials))], echo, problems)
        call at_line(problems, n0, deck, 'detonation', k)
      end do
      if (deck_count(deck, 'prerun') > 0) then
        n0 = size(problems)
        call prerun_config_read(cfg%pre1d, deck_text(deck, 'prerun'), path, echo, problems)
        call at_line(problems, n0, deck, 'prerun')
      end if
      call read_particle_groups(deck, cfg, echo, problems)
      n0 = size(problems)
      call boundary_config_read(cfg%boundary, deck_text(deck, 'boundary'), path, names, echo, problems)
      call at_line(problems, n0, deck, 'boundary')
      call rezone_config_read(cfg%rezone, deck_text(deck, 'rezone'), path, echo, problems, &
                              particles=size(cfg%particles) > 0)
      call at_line(problems, n0, deck, 'rezone')
      call output_config_read(cfg%output, deck_text(deck, 'output'), path, cfg%grid%xmin, cfg%grid%xmax, echo, &
                              problems)
      call at_line(problems, n0, deck, 'output')
      call track_points_check(cfg, problems)
      call fixed_boxes_mode_check(cfg, problems)
      call check_counts(cfg, problems)
    end associate
  end subroutine read_groups

  !> The &solid and &particles groups, each by the particles package; a
  !> file of points is read and checked now (a missing or unusable file, or a
  !> point outside the grid's box, is a deck problem found by --check).
  subroutine read_particle_groups(deck, cfg, echo, problems)
    type(deck_t), intent(in) :: deck
    type(config_t), intent(inout) :: cfg
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=64), allocatable :: names(:)
    integer :: k, n, n0, stat
    n = deck_count(deck, 'solid')
    cfg%solids = [(solid_config_t(), k = 1, n)]
    names = [(cfg%solids(k)%name, k = 1, n)]
    do k = 1, n
      n0 = size(problems)
      call solid_config_read(cfg%solids(k), k, deck_text(deck, 'solid', k), deck%path, names(1:k - 1), &
                             cfg%control%units, echo, problems)
      call at_line(problems, n0, deck, 'solid', k)
      cfg%solids(k)%where = deck_where(deck, 'solid', k)//': '
      names(k) = cfg%solids(k)%name
    end do
    n = deck_count(deck, 'particles')
    if (allocated(cfg%particles)) deallocate(cfg%particles)
    allocate(cfg%particles(n), stat=stat)
    if (stat /= 0) then
      call problem_add(problems, error_no_memory('the configuration of '//itoa(n)//' &particles groups'))
      return
    end if
    do k = 1, n
      n0 = size(problems)
      call particles_config_read(cfg%particles(k), k, deck_text(deck, 'particles', k), deck%path, names, &
                                 cfg%grid%xmin, cfg%grid%xmax, echo, problems)
      if (size(problems) == n0 .and. cfg%particles(k)%shape == 'file') &
        call points_file_check(cfg%particles(k), k, cfg%grid%xmin, cfg%grid%xmax, problems)
      if (size(problems) == n0 .and. cfg%particles(k)%shape == 'stl') &
        call stl_file_check(cfg%particles(k), k, cfg%grid%xmin, cfg%grid%xmax, problems)
      call at_line(problems, n0, deck, 'particles', k)
    end do
    if (n > 0 .and. size(problems) == 0) call empty_shapes_check(deck, cfg, problems)
  end subroutine read_particle_groups

  !> Fixed boxes (&boundary fixed_lo, fixed_hi) with a face that moves with
  !> the material (velocity, pressure) in &rezone mode 'global' are refused:
  !> that rezone carries the face's displacement into every node it does
  !> not keep, the fixed ones too, and would move the clamp.
  subroutine fixed_boxes_mode_check(cfg, problems)
    type(config_t), intent(in) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    if (cfg%boundary%nfixed == 0 .or. trim(cfg%rezone%mode) /= 'global') return
    if (any(cfg%boundary%kind == BC_VELOCITY .or. cfg%boundary%kind == BC_PRESSURE)) call problem_add(problems, &
      '&boundary: fixed boxes (fixed_lo, fixed_hi) cannot go with a velocity or pressure face in &rezone mode = '// &
      '''global'', which would carry the face''s motion into the fixed nodes; use mode = ''lssm'' or ''smooth''')
  end subroutine fixed_boxes_mode_check

  !> Track points (&output track) name particles: a deck without any is
  !> refused before step 0.
  subroutine track_points_check(cfg, problems)
    type(config_t), intent(in) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer :: n
    if (cfg%output%ntrack == 0) return
    n = 0
    if (allocated(cfg%particles)) n = size(cfg%particles)
    if (n == 0) call problem_add(problems, '&output: track = '//itoa(cfg%output%ntrack)//' point(s) but the deck '// &
      'has no &particles group: track points name particles; add a &particles group or remove track')
  end subroutine track_points_check

  !> A shape that seeds no particle (smaller than the spacing of the
  !> sub-cell centres, or between them) is a deck mistake, found now by
  !> counting on the deck's grid (`shape_slabs`; the scene seeds again).
  subroutine empty_shapes_check(deck, cfg, problems)
    type(deck_t), intent(in) :: deck
    type(config_t), intent(in) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    type(error_t), allocatable :: err
    integer :: k, n0, seeds(size(cfg%particles))
    call shape_slabs(cfg, 0, 1, seeds, err)
    if (allocated(err)) return     ! the grid's own problem is reported by &grid
    do k = 1, size(cfg%particles)
      if (seeds(k) /= 0) cycle
      n0 = size(problems)
      call problem_add(problems, '&particles('//itoa(k)//'): the '//trim(cfg%particles(k)%shape)// &
        ' seeds no particle at per_cell = '//itoa(cfg%particles(k)%per_cell)// &
        ' (no sub-cell centre lies in it): make it larger or raise per_cell')
      call at_line(problems, n0, deck, 'particles', k)
    end do
  end subroutine empty_shapes_check

  !> The particles the deck's shape groups seed, counted on the deck's grid
  !> a slab of planes at a time (`grid_init_box`'s blocks: the same nodes,
  !> so the same centres; a grid file the same slabs of it), so that no
  !> rank holds the whole grid's nodes for it: seeds(k) of group k (-1 for
  !> a file's, a line's or an STL surface's group, not counted; without
  !> planes, a group found to seed some is not counted further). With
  !> planes (gn(1) + gn(2) + gn(3)): every shape group's particles added to
  !> the planes of cells normal to i, j and k of their host cells
  !> (`seed_count`). Only slabs part, part + nparts, ... (0-based): the
  !> ranks of a decomposed run share the work.
  subroutine shape_slabs(cfg, part, nparts, seeds, err, planes)
    type(config_t), intent(in) :: cfg
    integer, intent(in) :: part, nparts
    integer, intent(out) :: seeds(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(inout), optional :: planes(:)
    !> nodes per slab, about (the planes of a slab hold at most this many)
    integer, parameter :: slab_nodes = 2**20
    type(grid_t) :: g
    type(grid_index_t) :: ix
    real(wp), allocatable :: x(:, :)
    integer :: k, k0, nks, gn(3), s
    gn = [cfg%grid%ni, cfg%grid%nj, cfg%grid%nk]
    seeds = [(merge(-1, 0, any(cfg%particles(k)%shape == [character(len=8) :: 'file', 'line', 'stl'])), &
              k = 1, size(cfg%particles))]
    nks = max(1, min(gn(3), slab_nodes/((gn(1) + 1)*(gn(2) + 1))))
    s = -1
    do k0 = 0, gn(3) - 1, nks
      s = s + 1
      if (mod(s, nparts) /= part) cycle
      ix = grid_index_block([gn(1), gn(2), min(nks, gn(3) - k0)], [0, 0, 0], [0, 0, 0], [0, 0, k0], gn)
      if (len_trim(cfg%grid%file) == 0) then
        call grid_init_box(g, gn(1), gn(2), gn(3), cfg%grid%xmin, cfg%grid%xmax, err, ix, grid_axis_nodes(cfg%grid, 1), &
                           grid_axis_nodes(cfg%grid, 2), grid_axis_nodes(cfg%grid, 3))
      else
        call grid_file_read(cfg%grid%file_path, gn(1), gn(2), gn(3), x, err, [0, 0, k0], &
                            [gn(1), gn(2), k0 + ix%nk])
        if (.not. allocated(err)) call grid_init_nodes(g, gn(1), gn(2), gn(3), x, err, ix, &
                                                       reshape([cfg%grid%xmin, cfg%grid%xmax], [3, 2]))
      end if
      if (allocated(err)) return
      do k = 1, size(cfg%particles)
        if (seeds(k) < 0 .or. (seeds(k) > 0 .and. .not. present(planes))) cycle
        seeds(k) = seeds(k) + seed_count(g, group_shape(cfg%particles(k)), cfg%particles(k)%per_cell, planes)
      end do
    end do
  end subroutine shape_slabs

  !> The shape of a &particles group (not 'file', 'line' or 'stl'), for the seeding.
  pure function group_shape(pc) result(sh)
    type(particles_config_t), intent(in) :: pc
    type(shape_t) :: sh
    ! ('half_space' is not a particle shape: the group's validation refuses it)
    sh = shape_t(kind=shape_kind(pc%shape), lo=pc%lo, hi=pc%hi, center=pc%center, radius=pc%radius, &
                 inner_radius=pc%inner_radius, axis=pc%axis)
  end function group_shape

  !> The points of a &particles shape = 'file' group: a readable file
  !> (`io_points_file`) whose points lie in the grid's box. The scene reads
  !> the file again when it seeds the particles.
  subroutine points_file_check(pc, k, xmin, xmax, problems)
    type(particles_config_t), intent(in) :: pc
    integer, intent(in) :: k
    real(wp), intent(in) :: xmin(3), xmax(3)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    type(error_t), allocatable :: err
    real(wp), allocatable :: x(:, :), vol(:)
    integer :: i
    call points_file_read(pc%file_path, x, vol, err)
    if (allocated(err)) then
      call problem_add(problems, '&particles('//itoa(k)//'): '//err%msg)
      return
    end if
    call particles_file_place(pc, x)
    do i = 1, size(x, 2)
      if (any(x(:, i) < xmin) .or. any(x(:, i) > xmax)) then
        call problem_add(problems, '&particles('//itoa(k)//'): point '//itoa(i)//' of file '''//trim(pc%file)// &
                         ''' is outside the grid box xmin..xmax')
        return
      end if
    end do
  end subroutine points_file_check

  !> The surface of a &particles shape = 'stl' group: a readable STL file
  !> (`io_stl`) whose box meets the grid's. The scene reads the file again
  !> when it seeds the particles.
  subroutine stl_file_check(pc, k, xmin, xmax, problems)
    type(particles_config_t), intent(in) :: pc
    integer, intent(in) :: k
    real(wp), intent(in) :: xmin(3), xmax(3)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    type(error_t), allocatable :: err
    real(wp), allocatable :: tri(:, :, :)
    integer :: d
    call stl_read(pc%file_path, tri, err)
    if (allocated(err)) then
      call problem_add(problems, '&particles('//itoa(k)//'): '//err%msg)
      return
    end if
    do d = 1, 3
      call particles_file_place(pc, tri(:, d, :))
    end do
    do d = 1, 3
      if (maxval(tri(d, :, :)) < xmin(d) .or. minval(tri(d, :, :)) > xmax(d)) then
        call problem_add(problems, '&particles('//itoa(k)//'): the surface of '''//trim(pc%file)// &
                         ''' lies outside the grid box xmin..xmax: it would seed no particle')
        return
      end if
    end do
  end subroutine stl_file_check

  !> A grid from a file (`&grid file`): the file is read and checked now, so
  !> that a missing or unusable file is a deck problem like any other (found
  !> by `lsalepm --check`, before anything runs), and the grid's box becomes
  !> the box around its nodes (sources and gauges must lie in it). The scene
  !> reads the file again when it builds the grid.
  subroutine grid_file_check(grid, problems)
    type(grid_config_t), intent(inout) :: grid
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    type(error_t), allocatable :: err
    real(wp) :: xmin(3), xmax(3)
    call grid_file_scan(grid%file_path, grid%ni, grid%nj, grid%nk, xmin, xmax, err)
    if (allocated(err)) then
      call problem_add(problems, '&grid: '//err%msg)
    else
      grid%xmin = xmin
      grid%xmax = xmax
    end if
  end subroutine grid_file_check

  !> Intervals so short for t_end that the run would write more than
  !> max_outputs frames, gauge or history rows, dumps or Euler steps by
  !> interval (1e-300 would loop for ever) are deck mistakes.
  subroutine check_counts(cfg, problems)
    type(config_t), intent(in) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    real(wp), parameter :: max_outputs = 1.0e7_wp
    if (.not. (cfg%control%t_end > 0.0_wp)) return
    call one('output', 'frame_dt', cfg%output%frame_dt)
    call one('output', 'gauge_dt', cfg%output%gauge_dt)
    call one('output', 'history_dt', cfg%output%history_dt)
    call one('run', 'dump_dt', cfg%control%dump_dt)
    call one('rezone', 'interval_time', cfg%rezone%interval_time)
  contains
    subroutine one(group, var, dt)
      character(len=*), intent(in) :: group, var
      real(wp), intent(in) :: dt
      if (.not. (dt > 0.0_wp)) return
      if (cfg%control%t_end/dt > max_outputs) call problem_bad(problems, group, var, dt, &
        'is too short for t_end: more than 1e7 outputs; give a longer interval or 0 (off)')
    end subroutine one
  end subroutine check_counts

  !> Prefixes problems n0+1.. (those of one group) with "file:line: ", where
  !> the group starts (the deck or the file it includes; nothing for an
  !> absent group); n0 is then moved past them.
  subroutine at_line(problems, n0, deck, name, k)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer, intent(inout) :: n0
    type(deck_t), intent(in) :: deck
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: k
    character(len=:), allocatable :: head, place
    integer :: i
    place = deck_where(deck, name, k)
    if (len(place) > 0) then
      head = trim(deck%path)//': '
      do i = n0 + 1, size(problems)
        if (problems(i)(1:len(head)) == head) then
          problems(i) = place//': '//problems(i)(len(head) + 1:)
        else
          problems(i) = place//': '//problems(i)
        end if
      end do
    end if
    n0 = size(problems)
  end subroutine at_line

  !> Reads, validates and echoes the &run group; its time-step controls go
  !> to the Lagrangian parameters `hydro`. `restart` (the command line's
  !> `--restart`) replaces restart_from.
  subroutine run_config_read(this, hydro, text, path, echo, problems, restart)
    type(run_config_t), intent(out) :: this
    type(hydro_params_t), intent(inout) :: hydro
    character(len=*), intent(in) :: text(:), path
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), intent(in), optional :: restart
    character(len=256) :: overridden
    type(hydro_params_t) :: hd
    character(len=200) :: title
    character(len=64) :: units
    real(wp) :: t_end, cfl, dt_init, dt_max, dt_min, dt_growth, progress_seconds
    real(wp) :: velocity_noise, wall_time_limit, dump_dt, blocks_particle_weight
    integer :: max_steps, progress_steps, seed, dump_steps, dump_keep, ios, blocks(3)
    character(len=256) :: restart_from
    character(len=max_line) :: msg
    namelist /run/ title, units, t_end, max_steps, cfl, dt_init, dt_max, dt_min, dt_growth, &
                   progress_steps, progress_seconds, velocity_noise, seed, &
                   restart_from, wall_time_limit, dump_steps, dump_dt, dump_keep, blocks, &
                   blocks_particle_weight

    title = this%title; units = this%units; t_end = this%t_end; max_steps = this%max_steps
    cfl = hd%cfl; dt_init = this%dt_init; dt_max = 0.0_wp; dt_min = this%dt_min; dt_growth = hd%dt_growth
    progress_steps = this%progress_steps; progress_seconds = this%progress_seconds
    velocity_noise = this%velocity_noise; seed = this%seed
    restart_from = this%restart_from; wall_time_limit = this%wall_time_limit; dump_steps = this%dump_steps
    dump_dt = this%dump_dt; dump_keep = this%dump_keep; blocks = this%blocks
    blocks_particle_weight = this%blocks_particle_weight
    if (size(text) == 0) then
      call problem_add(problems, trim(path)//': group &run is missing (t_end is required)')
    else
      read(text, nml=run, iostat=ios, iomsg=msg)
      if (ios /= 0) call problem_nml(problems, path, 'run', ios, msg)
    end if
    overridden = ''
    if (present(restart)) then
      if (len_trim(restart_from) > 0 .and. trim(restart_from) /= restart) overridden = restart_from
      restart_from = restart
      if (len(restart) >= len(restart_from)) call problem_add(problems, '--restart '''//restart//''': the name is '// &
        'longer than '//itoa(len(restart_from) - 1)//' characters')
    end if
    if (.not. (t_end > 0.0_wp)) call problem_bad(problems, 'run', 't_end', t_end, 'must be > 0')
    if (.not. (cfl > 0.0_wp .and. cfl <= 1.0_wp)) call problem_bad(problems, 'run', 'cfl', cfl, 'must be in (0, 1]')
    if (.not. (dt_growth >= 1.0_wp)) call problem_bad(problems, 'run', 'dt_growth', dt_growth, 'must be >= 1')
    if (dt_init < 0.0_wp) call problem_bad(problems, 'run', 'dt_init', dt_init, 'must be >= 0 (0: automatic)')
    if (dt_max < 0.0_wp) call problem_bad(problems, 'run', 'dt_max', dt_max, 'must be >= 0 (0: no limit)')
    if (dt_min < 0.0_wp) call problem_bad(problems, 'run', 'dt_min', dt_min, 'must be >= 0 (0: 1e-12 t_end)')
    if (max_steps < 0) call problem_badi(problems, 'run', 'max_steps', max_steps, 'must be >= 0')
    if (velocity_noise < 0.0_wp) call problem_bad(problems, 'run', 'velocity_noise', velocity_noise, 'must be >= 0')
    if (wall_time_limit < 0.0_wp) call problem_bad(problems, 'run', 'wall_time_limit', wall_time_limit, &
                                                   'must be >= 0 (0: none)')
    if (dump_dt < 0.0_wp) call problem_bad(problems, 'run', 'dump_dt', dump_dt, 'must be >= 0 (0: off)')
    if (dump_steps < 0) call problem_badi(problems, 'run', 'dump_steps', dump_steps, 'must be >= 0 (0: off)')
    if (dump_keep < 1) call problem_badi(problems, 'run', 'dump_keep', dump_keep, 'must be >= 1')
    if (any(blocks < 0)) call problem_badi(problems, 'run', 'blocks', minval(blocks), 'must be >= 0 (0: chosen)')
    if (.not. (blocks_particle_weight >= 0.0_wp .and. blocks_particle_weight <= 1.0e6_wp)) &
      call problem_bad(problems, 'run', 'blocks_particle_weight', blocks_particle_weight, 'must be in [0, 1e6]')
    call problem_long(problems, 'run', 'title', title)
    call problem_long(problems, 'run', 'units', units)
    if (len_trim(units) > 0 .and. .not. units_known(trim(units))) call problem_add(problems, '&run: units = '''// &
      trim(units)//''' is not a unit system the code knows: '//units_list()//' (or leave it out)')
    call problem_long(problems, 'run', 'restart_from', restart_from)
    this = run_config_t(title=title, units=units, t_end=t_end, max_steps=max_steps, dt_init=dt_init, &
      dt_min=merge(dt_min, 1.0e-12_wp*t_end, dt_min > 0.0_wp), progress_steps=progress_steps, &
      progress_seconds=progress_seconds, velocity_noise=velocity_noise, seed=seed, restart_from=restart_from, &
      wall_time_limit=wall_time_limit, dump_steps=dump_steps, dump_dt=dump_dt, dump_keep=dump_keep, blocks=blocks, &
      restart_overridden=overridden, blocks_particle_weight=blocks_particle_weight)
    hydro%cfl = cfl
    hydro%dt_growth = dt_growth
    hydro%dt_max = merge(dt_max, huge(1.0_wp), dt_max > 0.0_wp)
    if (echo /= no_echo) write(echo, nml=run)
  end subroutine run_config_read

  !> What a restart may not change: every variable the state depends on
  !> (grid, materials, regions, sources, boundaries, the initial noise), each
  !> package comparing its own group. One line per changed variable; empty
  !> if the decks agree. Time, output, dump and numerical settings (&hydro,
  !> &rezone, cfl, dt limits) may change: none of them is part of the state.
  subroutine config_state_changes(old, new, changes)
    type(config_t), intent(in) :: old, new
    character(len=max_line), allocatable, intent(out) :: changes(:)
    integer :: k

    changes = [character(len=max_line) ::]
    call grid_config_changes(old%grid, new%grid, changes)
    call diff_r(changes, '&run velocity_noise', [old%control%velocity_noise], [new%control%velocity_noise])
    call diff_i(changes, '&run seed', old%control%seed, new%control%seed)
    call diff_i(changes, 'number of &material groups', size(old%materials), size(new%materials))
    do k = 1, min(size(old%materials), size(new%materials))
      call material_config_changes(k, old%materials(k), new%materials(k), changes)
    end do
    call scene_config_changes(old%regions, new%regions, old%sources, new%sources, old%detonations, new%detonations, &
                              changes)
    call particles_config_changes(old%solids, new%solids, old%particles, new%particles, changes)
    call boundary_config_changes(old%boundary, new%boundary, changes)
  end subroutine config_state_changes

  !> Every group with every variable at its default, as namelist text (the
  !> documentation check compares it with input/README.md). Groups whose
  !> required variables have no default are echoed with those unset.
  function config_defaults_text() result(text)
    character(len=:), allocatable :: text
    type(config_t) :: cfg
    character(len=max_line), allocatable :: problems(:)
    character(len=64) :: names(1)
    integer :: echo, stat

    call echo_open(echo, problems)
    names(1) = 'material1'
    call run_config_read(cfg%control, cfg%hydro, empty('run'), 'deck.nml', echo, problems)
    call grid_config_read(cfg%grid, empty('grid'), 'deck.nml', echo, problems)
    call hydro_config_read(cfg%hydro, empty('hydro'), 'deck.nml', echo, problems)
    cfg%materials = [material_config_t()]
    cfg%regions = [region_config_t()]
    cfg%sources = [source_config_t()]
    call material_config_read(cfg%materials(1), 1, empty('material'), 'deck.nml', [character(len=64) ::], '', echo, &
                              problems)
    call region_config_read(cfg%regions(1), 1, empty('region'), 'deck.nml', names, echo, problems)
    call source_config_read(cfg%sources(1), 1, empty('source'), 'deck.nml', cfg%grid%xmin, cfg%grid%xmax, echo, &
                            problems)
    cfg%detonations = [detonation_config_t()]
    call detonation_config_read(cfg%detonations(1), 1, empty('detonation'), 'deck.nml', names, ['jwl'], echo, problems)
    call prerun_config_read(cfg%pre1d, empty('prerun'), 'deck.nml', echo, problems)
    cfg%solids = [solid_config_t()]
    ! (default-initialized; a constructor would copy an unset file_path)
    allocate(cfg%particles(1), stat=stat)
    if (stat /= 0) then
      text = ''   ! (what the documentation check would then report)
      return
    end if
    call solid_config_read(cfg%solids(1), 1, empty('solid'), 'deck.nml', [character(len=64) ::], '', echo, problems)
    call particles_config_read(cfg%particles(1), 1, empty('particles'), 'deck.nml', [cfg%solids(1)%name], &
                               cfg%grid%xmin, cfg%grid%xmax, echo, problems)
    call boundary_config_read(cfg%boundary, empty('boundary'), 'deck.nml', names, echo, problems)
    call rezone_config_read(cfg%rezone, empty('rezone'), 'deck.nml', echo, problems)
    call output_config_read(cfg%output, empty('output'), 'deck.nml', cfg%grid%xmin, cfg%grid%xmax, echo, problems)
    text = mark_required(echo_text(echo), problems)

  contains

    !> The text of a group that gives no variable.
    function empty(group) result(lines)
      character(len=*), intent(in) :: group
      character(len=max_line) :: lines(1)
      lines(1) = '&'//group//' /'
    end function empty
  end function config_defaults_text

  !> The defaults' text with `! required` after each variable that an empty
  !> group is refused for ("&group...: var = ... must be ..." or "&group...:
  !> var is required"): what a deck must give, found by the packages' own
  !> validation, not by a list kept apart from it. A rule with a way out
  !> ("(or give youngs_modulus and poisson_ratio)") keeps it.
  function mark_required(text, problems) result(out)
    character(len=*), intent(in) :: text
    character(len=max_line), intent(in) :: problems(:)
    character(len=:), allocatable :: out, line, group, var, mark
    integer :: i, j, k, m
    out = ''
    group = ''
    var = ''
    i = 1
    do while (i <= len(text))
      j = index(text(i:), new_line('a'))
      if (j == 0) j = len(text) - i + 2
      line = text(i:i + j - 2)
      i = i + j
      if (len(line) > 1 .and. line(1:1) == '&') group = lower(trim(line(2:)))
      k = index(line, '=')
      mark = ''
      if (line(1:1) == ' ' .and. k > 2) then
        var = lower(trim(adjustl(line(1:k - 1))))
        do m = 1, size(problems)
          if (problem_group(problems(m)) /= group) cycle
          if (.not. problem_names(problems(m), var)) cycle
          mark = '  ! required'
          if (index(problems(m), '(or ') > 0) mark = mark//' '//trim(problems(m)(index(problems(m), '(or '):))
          exit
        end do
      end if
      out = out//line//mark//new_line('a')
    end do
  end function mark_required

  !> The group a problem line names ("&region(1): ..." is region).
  pure function problem_group(problem) result(group)
    character(len=*), intent(in) :: problem
    character(len=:), allocatable :: group
    integer :: k
    group = ''
    if (problem(1:1) /= '&') return
    k = scan(problem(2:), ':( ''')
    if (k > 1) group = lower(problem(2:k))
  end function problem_group

  !> True if a problem line is about variable `var`: "...: var = ..." or
  !> "...: var is required".
  pure logical function problem_names(problem, var) result(yes)
    character(len=*), intent(in) :: problem, var
    integer :: k
    yes = .false.
    k = index(problem, ': ')
    if (k == 0) return
    associate (rest => problem(k + 2:))
      yes = index(rest, var//' = ') == 1 .or. index(rest, var//' is required') == 1
    end associate
  end function problem_names
end module driver_config
