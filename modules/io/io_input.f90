!> Reads a namelist deck into a resolved configuration, and validates it.
!>
!> Groups: &run, &grid, &hydro, &material (one or more), &region (one or more,
!> applied in order), &source (zero or more), &boundary, &rezone, &output. Defaults are
!> set before each read and documented in input/README.md. Every problem found
!> is reported, one line each, naming the group, the variable, the value and
!> what is allowed; the driver then stops before step 0.
module io_input
  use base_kinds, only: wp, i8
  use base_strings, only: itoa
  use base_errors, only: error_t
  use eos_base, only: eos_t
  use eos_factory, only: eos_params_t, eos_create
  use lagrange_state, only: hydro_params_t, VISC_EDGE, VISC_TENSOR
  use mesh_boundary, only: bc_kind_from_name, bc_kind_names
  implicit none
  private
  public :: config_t, material_cfg_t, region_cfg_t, source_cfg_t, rezone_cfg_t, input_read, input_state_changes, &
            max_gauges

  integer, parameter :: max_gauges = 64
  integer, parameter :: max_line = 1024

  !> One &material group.
  type :: material_cfg_t
    character(len=64) :: name = ''
    character(len=64) :: eos = 'ideal_gas'
    type(eos_params_t) :: par
    real(wp) :: p_min = -huge(1.0_wp), rho_min = 0.0_wp
  end type material_cfg_t

  !> One &region group: a shape filled with a material state.
  type :: region_cfg_t
    character(len=16) :: shape = 'all'
    character(len=64) :: material = ''
    integer :: imat = 0
    real(wp) :: density = 0.0_wp, energy = -1.0_wp, pressure = -1.0_wp
    real(wp) :: velocity(3) = 0.0_wp
    real(wp) :: lo(3) = 0.0_wp, hi(3) = 0.0_wp
    real(wp) :: center(3) = 0.0_wp, radius = 0.0_wp, normal(3) = [1.0_wp, 0.0_wp, 0.0_wp]
    integer :: axis = 3
  end type region_cfg_t

  !> One &source group: energy deposited in the cell containing a point.
  type :: source_cfg_t
    real(wp) :: position(3) = 0.0_wp
    real(wp) :: energy = 0.0_wp
  end type source_cfg_t

  !> The &rezone group: whether, when and how an Euler step (rezone, then
  !> remap) follows the Lagrangian step. An Euler step runs when any trigger
  !> that is on fires.
  type :: rezone_cfg_t
    !> 'none': pure Lagrangian, no Euler step; 'global': rezone the whole grid
    !> back to the initial one and remap (Eulerian-like global MMALE); 'lssm':
    !> smooth and remap only the distorted subdomains (Sect. 5); 'smooth':
    !> smooth the whole grid and remap (the global MMALE LSSM is measured against)
    character(len=16) :: mode = 'none'
    !> trigger: the largest ratio of side lengths of any cell reaches this
    !> (0: off; else > 1)
    real(wp) :: side_ratio = 4.0_wp
    !> trigger: the smallest cosine of the largest inclined angle over all
    !> cells falls to or below this (0: off; else in (0, 1))
    real(wp) :: cos_angle = 0.7_wp
    integer :: interval_steps = 0          !< trigger: every this many steps (0: off)
    real(wp) :: interval_time = 0.0_wp     !< trigger: every this much simulated time (time; 0: off)
    !> remap reconstruction: 'linear' (limited, second order) or 'constant'
    !> (first order)
    character(len=16) :: reconstruction = 'linear'
    integer :: mof_max_iter = 50           !< cap on MoF Gauss-Newton iterations per material
    !> check mass, momentum and energy conservation to round-off at every
    !> Euler step and stop the run if broken (Debug builds always check)
    logical :: check_conservation = .false.
    ! mode 'lssm' (Sect. 5): only distorted subdomains are smoothed and remapped
    real(wp) :: quality = 0.999_wp         !< a cell with Q (Eq. 46) below this is distorted (the paper's q)
    real(wp) :: quality_target = 0.999_wp  !< smoothing stops when Q_min of the subdomains reaches this
    integer :: smooth_iterations = 20      !< at most this many combined smoothing iterations (N_max)
    !> side of a subdomain's range in cells (0: a tenth of the smallest grid dimension, as the paper)
    real(wp) :: d_max = 0.0_wp
    !> 'lssm', 'smooth': a node the smoothing moves by less than this times its
    !> shortest edge stays where it was (0: every move is kept, as the paper)
    real(wp) :: move_min = 0.0_wp
    !> nodal masses after a remap: 'transported' (the old ones, carried; a uniform
    !> velocity stays exact) or 'consistent' (the reconstructed subcell masses)
    character(len=16) :: nodal_mass = 'transported'
  end type rezone_cfg_t

  !> The resolved deck.
  type :: config_t
    character(len=:), allocatable :: deck_path
    character(len=:), allocatable :: echo            !< resolved deck as namelist text
    ! &run
    character(len=200) :: title = ''
    real(wp) :: t_end = 0.0_wp, dt_init = 0.0_wp, dt_min = 0.0_wp
    integer :: max_steps = 0, progress_steps = 0, seed = 1
    real(wp) :: velocity_noise = 0.0_wp
    ! restarts
    character(len=256) :: restart_from = ''
    real(wp) :: wall_time_limit = 0.0_wp, dump_dt = 0.0_wp
    integer :: dump_steps = 0, dump_keep = 2
    real(wp) :: progress_seconds = 0.0_wp
    ! &grid
    integer :: ni = 0, nj = 0, nk = 0, subsamples = 8
    real(wp) :: xmin(3) = 0.0_wp, xmax(3) = 1.0_wp
    ! &hydro and &run numerical parameters
    type(hydro_params_t) :: hydro
    ! &material, &region, &source
    type(material_cfg_t), allocatable :: materials(:)
    type(region_cfg_t), allocatable :: regions(:)
    type(source_cfg_t), allocatable :: sources(:)
    ! &boundary
    integer :: bc_kind(6) = 1
    real(wp) :: bc_velocity(3, 6) = 0.0_wp, bc_pressure(6) = 0.0_wp
    ! inflow state per face (kind 'inflow'): material index, density, pressure
    integer :: bc_inflow_mat(6) = 0
    real(wp) :: bc_inflow_density(6) = 0.0_wp, bc_inflow_pressure(6) = 0.0_wp
    ! &rezone
    type(rezone_cfg_t) :: rezone
    ! &output
    character(len=256) :: out_dir = 'out', out_name = 'run'
    real(wp) :: frame_dt = 0.0_wp, gauge_dt = 0.0_wp
    integer :: frame_steps = 0, ngauge = 0
    real(wp) :: gauges(3, max_gauges) = 0.0_wp
  end type config_t

  character(len=*), parameter :: known_groups(9) = [character(len=8) :: &
    'run', 'grid', 'hydro', 'material', 'region', 'source', 'boundary', 'rezone', 'output']
  character(len=*), parameter :: face_names(6) = ['xlo', 'xhi', 'ylo', 'yhi', 'zlo', 'zhi']

contains

  !> Reads and validates the deck at `path`. On return `problems` holds one
  !> line per problem found (empty when the deck is usable).
  subroutine input_read(path, cfg, problems)
    character(len=*), intent(in) :: path
    type(config_t), intent(out) :: cfg
    character(len=max_line), allocatable, intent(out) :: problems(:)
    character(len=max_line), allocatable :: lines(:)
    integer :: unit, ios, echo_unit
    character(len=max_line) :: msg
    logical :: exists

    allocate(problems(0))
    cfg%deck_path = path
    inquire(file=path, exist=exists)
    if (.not. exists) then
      call add(problems, 'deck file '''//trim(path)//''' does not exist')
      return
    end if
    open(newunit=unit, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call add(problems, 'cannot open deck '''//trim(path)//''': '//trim(msg))
      return
    end if
    call read_lines(unit, lines, ios, msg)
    if (ios /= 0) then
      call add(problems, 'cannot read deck '''//trim(path)//''': '//trim(msg))
      close(unit)
      return
    end if
    call check_group_names(path, lines, problems)

    open(newunit=echo_unit, status='scratch', action='readwrite', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call add(problems, 'cannot open a scratch file for the deck echo: '//trim(msg))
      close(unit)
      return
    end if
    call read_run(unit, lines, cfg, echo_unit, problems)
    call read_grid(unit, lines, cfg, echo_unit, problems)
    call read_hydro(unit, lines, cfg, echo_unit, problems)
    call read_materials(unit, lines, cfg, echo_unit, problems)
    call read_regions(unit, lines, cfg, echo_unit, problems)
    call read_sources(unit, lines, cfg, echo_unit, problems)
    call read_boundary(unit, lines, cfg, echo_unit, problems)
    call read_rezone(unit, lines, cfg, echo_unit, problems)
    call read_output(unit, lines, cfg, echo_unit, problems)
    close(unit)
    rewind(echo_unit)
    call read_lines(echo_unit, lines, ios, msg)
    close(echo_unit)
    cfg%echo = join(lines)
  end subroutine input_read

  ! ---------------------------------------------------------------- groups

  subroutine read_run(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=200) :: title
    real(wp) :: t_end, cfl, dt_init, dt_max, dt_min, dt_growth, progress_seconds
    real(wp) :: velocity_noise, wall_time_limit, dump_dt
    integer :: max_steps, progress_steps, seed, dump_steps, dump_keep, ios
    character(len=256) :: restart_from
    character(len=max_line) :: msg
    namelist /run/ title, t_end, max_steps, cfl, dt_init, dt_max, dt_min, dt_growth, &
                   progress_steps, progress_seconds, velocity_noise, seed, &
                   restart_from, wall_time_limit, dump_steps, dump_dt, dump_keep

    title = 'untitled'; t_end = 0.0_wp; max_steps = 100000000
    cfl = 0.5_wp; dt_init = 0.0_wp; dt_max = 0.0_wp; dt_min = 0.0_wp; dt_growth = 1.1_wp
    progress_steps = 0; progress_seconds = 10.0_wp; velocity_noise = 0.0_wp; seed = 1
    restart_from = ''; wall_time_limit = 0.0_wp; dump_steps = 0; dump_dt = 0.0_wp; dump_keep = 2
    if (group_count(lines, 'run') == 0) then
      call add(problems, trim(cfg%deck_path)//': group &run is missing (t_end is required)')
    else
      rewind(unit)
      read(unit, nml=run, iostat=ios, iomsg=msg)
      if (ios /= 0) call add(problems, nml_error(cfg%deck_path, 'run', ios, msg))
    end if
    if (.not. (t_end > 0.0_wp)) call add(problems, bad('run', 't_end', t_end, 'must be > 0'))
    if (.not. (cfl > 0.0_wp .and. cfl <= 1.0_wp)) call add(problems, bad('run', 'cfl', cfl, 'must be in (0, 1]'))
    if (.not. (dt_growth >= 1.0_wp)) call add(problems, bad('run', 'dt_growth', dt_growth, 'must be >= 1'))
    if (dt_init < 0.0_wp) call add(problems, bad('run', 'dt_init', dt_init, 'must be >= 0 (0: automatic)'))
    if (dt_max < 0.0_wp) call add(problems, bad('run', 'dt_max', dt_max, 'must be >= 0 (0: no limit)'))
    if (dt_min < 0.0_wp) call add(problems, bad('run', 'dt_min', dt_min, 'must be >= 0 (0: 1e-12 t_end)'))
    if (max_steps < 0) call add(problems, badi('run', 'max_steps', max_steps, 'must be >= 0'))
    if (velocity_noise < 0.0_wp) call add(problems, bad('run', 'velocity_noise', velocity_noise, 'must be >= 0'))
    if (wall_time_limit < 0.0_wp) call add(problems, bad('run', 'wall_time_limit', wall_time_limit, &
      'must be >= 0 (0: none)'))
    if (dump_dt < 0.0_wp) call add(problems, bad('run', 'dump_dt', dump_dt, 'must be >= 0 (0: off)'))
    if (dump_steps < 0) call add(problems, badi('run', 'dump_steps', dump_steps, 'must be >= 0 (0: off)'))
    if (dump_keep < 1) call add(problems, badi('run', 'dump_keep', dump_keep, 'must be >= 1'))
    cfg%title = title; cfg%t_end = t_end; cfg%max_steps = max_steps
    cfg%hydro%cfl = cfl; cfg%dt_init = dt_init; cfg%hydro%dt_growth = dt_growth
    cfg%hydro%dt_max = merge(dt_max, huge(1.0_wp), dt_max > 0.0_wp)
    cfg%dt_min = merge(dt_min, 1.0e-12_wp*t_end, dt_min > 0.0_wp)
    cfg%progress_steps = progress_steps; cfg%progress_seconds = progress_seconds
    cfg%velocity_noise = velocity_noise; cfg%seed = seed
    cfg%restart_from = restart_from; cfg%wall_time_limit = wall_time_limit
    cfg%dump_steps = dump_steps; cfg%dump_dt = dump_dt; cfg%dump_keep = dump_keep
    write(echo, nml=run)
  end subroutine read_run

  subroutine read_grid(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer :: ni, nj, nk, subsamples, ios, d
    real(wp) :: xmin(3), xmax(3)
    character(len=max_line) :: msg
    namelist /grid/ ni, nj, nk, xmin, xmax, subsamples

    ni = 0; nj = 0; nk = 0; xmin = 0.0_wp; xmax = 1.0_wp; subsamples = 8
    if (group_count(lines, 'grid') == 0) then
      call add(problems, trim(cfg%deck_path)//': group &grid is missing (ni, nj, nk are required)')
      return
    end if
    rewind(unit)
    read(unit, nml=grid, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call add(problems, nml_error(cfg%deck_path, 'grid', ios, msg))
      return
    end if
    if (ni < 1) call add(problems, badi('grid', 'ni', ni, 'must be >= 1'))
    if (nj < 1) call add(problems, badi('grid', 'nj', nj, 'must be >= 1'))
    if (nk < 1) call add(problems, badi('grid', 'nk', nk, 'must be >= 1'))
    if (subsamples < 1) call add(problems, badi('grid', 'subsamples', subsamples, 'must be >= 1'))
    do d = 1, 3
      if (.not. (xmax(d) > xmin(d))) call add(problems, &
        bad('grid', 'xmax('//achar(48 + d)//')', xmax(d), 'must be > xmin('//achar(48 + d)//')'))
    end do
    cfg%ni = ni; cfg%nj = nj; cfg%nk = nk; cfg%xmin = xmin; cfg%xmax = xmax
    cfg%subsamples = subsamples
    write(echo, nml=grid)
  end subroutine read_grid

  subroutine read_hydro(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    real(wp) :: q_linear, q_quad, hourglass, dv_max, relax
    character(len=16) :: viscosity
    integer :: ios
    character(len=max_line) :: msg
    namelist /hydro/ viscosity, q_linear, q_quad, hourglass, dv_max, relax

    viscosity = 'tensor'
    q_linear = cfg%hydro%q_linear; q_quad = cfg%hydro%q_quad
    hourglass = cfg%hydro%hourglass; dv_max = cfg%hydro%dv_max; relax = cfg%hydro%relax
    if (group_count(lines, 'hydro') > 0) then
      rewind(unit)
      read(unit, nml=hydro, iostat=ios, iomsg=msg)
      if (ios /= 0) call add(problems, nml_error(cfg%deck_path, 'hydro', ios, msg))
    end if
    select case (trim(viscosity))
    case ('tensor'); cfg%hydro%viscosity = VISC_TENSOR
    case ('edge'); cfg%hydro%viscosity = VISC_EDGE
    case default
      call add(problems, '&hydro: viscosity = '''//trim(viscosity)//''' is not known; valid: tensor, edge')
    end select
    if (q_linear < 0.0_wp) call add(problems, bad('hydro', 'q_linear', q_linear, 'must be >= 0'))
    if (q_quad < 0.0_wp) call add(problems, bad('hydro', 'q_quad', q_quad, 'must be >= 0'))
    if (hourglass < 0.0_wp) call add(problems, bad('hydro', 'hourglass', hourglass, 'must be >= 0'))
    if (.not. (dv_max > 0.0_wp)) call add(problems, bad('hydro', 'dv_max', dv_max, 'must be > 0'))
    if (.not. (relax > 0.0_wp .and. relax <= 1.0_wp)) call add(problems, bad('hydro', 'relax', relax, &
      'must be in (0, 1]'))
    cfg%hydro%q_linear = q_linear; cfg%hydro%q_quad = q_quad
    cfg%hydro%hourglass = hourglass; cfg%hydro%dv_max = dv_max; cfg%hydro%relax = relax
    write(echo, nml=hydro)
  end subroutine read_hydro

  subroutine read_materials(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=64) :: name, eos
    real(wp) :: gamma, a, b, r1, r2, omega, rho0, c0, s1, gamma0, p_min, rho_min
    integer :: n, m, ios, m2
    character(len=max_line) :: msg
    class(eos_t), allocatable :: trial
    type(error_t), allocatable :: err
    type(eos_params_t) :: defaults
    namelist /material/ name, eos, gamma, a, b, r1, r2, omega, rho0, c0, s1, gamma0, p_min, rho_min

    n = group_count(lines, 'material')
    allocate(cfg%materials(n))
    if (n == 0) call add(problems, trim(cfg%deck_path)//': no &material group (at least one is required)')
    rewind(unit)
    do m = 1, n
      name = ''; eos = 'ideal_gas'; p_min = -huge(1.0_wp); rho_min = 0.0_wp
      gamma = defaults%gamma; a = defaults%a; b = defaults%b; r1 = defaults%r1; r2 = defaults%r2
      omega = defaults%omega; rho0 = defaults%rho0; c0 = defaults%c0; s1 = defaults%s1
      gamma0 = defaults%gamma0
      read(unit, nml=material, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call add(problems, nml_error(cfg%deck_path, 'material', ios, msg))
        return
      end if
      if (len_trim(name) == 0) write(name, '(a,i0)') 'material', m
      do m2 = 1, m - 1
        if (cfg%materials(m2)%name == name) call add(problems, &
          '&material: name = '''//trim(name)//''' is used twice; names must be unique')
      end do
      cfg%materials(m)%name = name
      cfg%materials(m)%eos = eos
      cfg%materials(m)%par = eos_params_t(gamma=gamma, a=a, b=b, r1=r1, r2=r2, omega=omega, &
                                          rho0=rho0, c0=c0, s1=s1, gamma0=gamma0)
      cfg%materials(m)%p_min = p_min
      cfg%materials(m)%rho_min = rho_min
      if (rho_min < 0.0_wp) call add(problems, bad('material '''//trim(name)//'''', 'rho_min', rho_min, &
        'must be >= 0'))
      ! the factory validates the model name and its parameters
      call eos_create(eos, cfg%materials(m)%par, trial, err)
      if (allocated(err)) then
        call add(problems, '&material '''//trim(name)//''': '//err%msg)
        deallocate(err)
      end if
      write(echo, nml=material)
    end do
  end subroutine read_materials

  subroutine read_regions(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=16) :: shape
    character(len=64) :: material
    character(len=1) :: axis
    real(wp) :: density, energy, pressure, energy_per_volume, velocity(3), lo(3), hi(3), center(3), radius, &
                normal(3)
    integer :: n, r, ios, m
    character(len=max_line) :: msg
    character(len=16) :: tag
    namelist /region/ shape, material, density, energy, pressure, energy_per_volume, velocity, lo, hi, &
                      center, radius, axis, normal

    n = group_count(lines, 'region')
    allocate(cfg%regions(n))
    if (n == 0) call add(problems, trim(cfg%deck_path)//': no &region group (at least one is required)')
    rewind(unit)
    do r = 1, n
      shape = 'all'; material = ''; density = 0.0_wp; energy = -1.0_wp; pressure = -1.0_wp
      energy_per_volume = -1.0_wp
      velocity = 0.0_wp; lo = -huge(1.0_wp); hi = huge(1.0_wp); center = 0.0_wp; radius = 0.0_wp
      normal = [1.0_wp, 0.0_wp, 0.0_wp]
      axis = 'z'
      read(unit, nml=region, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call add(problems, nml_error(cfg%deck_path, 'region', ios, msg))
        return
      end if
      write(tag, '(a,i0,a)') 'region(', r, ')'
      if (.not. (density > 0.0_wp)) call add(problems, bad(trim(tag), 'density', density, 'must be > 0'))
      if (count([energy >= 0.0_wp, pressure >= 0.0_wp, energy_per_volume >= 0.0_wp]) /= 1) &
        call add(problems, '&'//trim(tag)//': give exactly one of energy (specific internal energy), '// &
                 'pressure and energy_per_volume, >= 0')
      ! an energy per unit volume (as explosive charges are given) is a
      ! specific energy of energy_per_volume / density
      if (energy_per_volume >= 0.0_wp .and. density > 0.0_wp) energy = energy_per_volume/density
      select case (trim(shape))
      case ('all', 'box')
      case ('half_space')
        if (.not. (norm2(normal) > 0.0_wp)) call add(problems, '&'//trim(tag)// &
          ': normal must not be zero for shape = ''half_space''')
      case ('sphere', 'cylinder')
        if (.not. (radius > 0.0_wp)) call add(problems, bad(trim(tag), 'radius', radius, &
          'must be > 0 for shape = '''//trim(shape)//''''))
      case default
        call add(problems, '&'//trim(tag)//': shape = '''//trim(shape)// &
          ''' is not known; valid: all, box, sphere, cylinder, half_space')
      end select
      if (index('xyz', axis) == 0 .or. len_trim(axis) == 0) call add(problems, &
        '&'//trim(tag)//': axis = '''//trim(axis)//''' is not known; valid: x, y, z')
      m = material_index(cfg, material)
      if (m == 0 .and. len_trim(material) == 0 .and. allocated(cfg%materials)) then
        if (size(cfg%materials) == 1) m = 1
      end if
      if (m == 0) call add(problems, '&'//trim(tag)//': material = '''//trim(material)// &
        ''' is not a &material name')
      cfg%regions(r) = region_cfg_t(shape=shape, material=material, imat=m, density=density, &
        energy=energy, pressure=pressure, velocity=velocity, lo=lo, hi=hi, center=center, &
        radius=radius, axis=max(1, index('xyz', axis)), normal=normal)
      write(echo, nml=region)
    end do
  end subroutine read_regions

  subroutine read_sources(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    real(wp) :: position(3), energy
    integer :: n, s, ios
    character(len=max_line) :: msg
    character(len=16) :: tag
    namelist /source/ position, energy

    n = group_count(lines, 'source')
    allocate(cfg%sources(n))
    rewind(unit)
    do s = 1, n
      position = 0.0_wp; energy = 0.0_wp
      read(unit, nml=source, iostat=ios, iomsg=msg)
      if (ios /= 0) then
        call add(problems, nml_error(cfg%deck_path, 'source', ios, msg))
        return
      end if
      write(tag, '(a,i0,a)') 'source(', s, ')'
      if (.not. (energy > 0.0_wp)) call add(problems, bad(trim(tag), 'energy', energy, 'must be > 0'))
      if (any(position < cfg%xmin) .or. any(position > cfg%xmax)) call add(problems, &
        '&'//trim(tag)//': position is outside the grid box xmin..xmax')
      cfg%sources(s) = source_cfg_t(position=position, energy=energy)
      write(echo, nml=source)
    end do
  end subroutine read_sources

  subroutine read_boundary(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=16) :: xlo, xhi, ylo, yhi, zlo, zhi, kinds(6)
    real(wp) :: xlo_velocity(3), xhi_velocity(3), ylo_velocity(3), yhi_velocity(3), &
                zlo_velocity(3), zhi_velocity(3)
    real(wp) :: xlo_pressure, xhi_pressure, ylo_pressure, yhi_pressure, zlo_pressure, zhi_pressure
    character(len=64) :: inflow_material(6)
    real(wp) :: inflow_density(6), inflow_pressure(6)
    integer :: ios, f, m
    character(len=max_line) :: msg
    namelist /boundary/ xlo, xhi, ylo, yhi, zlo, zhi, xlo_velocity, xhi_velocity, ylo_velocity, &
      yhi_velocity, zlo_velocity, zhi_velocity, xlo_pressure, xhi_pressure, ylo_pressure, &
      yhi_pressure, zlo_pressure, zhi_pressure, inflow_material, inflow_density, inflow_pressure

    xlo = 'symmetry'; xhi = 'symmetry'; ylo = 'symmetry'; yhi = 'symmetry'
    zlo = 'symmetry'; zhi = 'symmetry'
    xlo_velocity = 0.0_wp; xhi_velocity = 0.0_wp; ylo_velocity = 0.0_wp
    yhi_velocity = 0.0_wp; zlo_velocity = 0.0_wp; zhi_velocity = 0.0_wp
    xlo_pressure = 0.0_wp; xhi_pressure = 0.0_wp; ylo_pressure = 0.0_wp
    yhi_pressure = 0.0_wp; zlo_pressure = 0.0_wp; zhi_pressure = 0.0_wp
    inflow_material = ''; inflow_density = 0.0_wp; inflow_pressure = 0.0_wp
    if (group_count(lines, 'boundary') > 0) then
      rewind(unit)
      read(unit, nml=boundary, iostat=ios, iomsg=msg)
      if (ios /= 0) call add(problems, nml_error(cfg%deck_path, 'boundary', ios, msg))
    end if
    kinds = [xlo, xhi, ylo, yhi, zlo, zhi]
    do f = 1, 6
      cfg%bc_kind(f) = bc_kind_from_name(kinds(f))
      if (cfg%bc_kind(f) == 0) call add(problems, '&boundary: '//face_names(f)//' = '''// &
        trim(kinds(f))//''' is not known; valid: '//bc_kind_names)
    end do
    cfg%bc_velocity = reshape([xlo_velocity, xhi_velocity, ylo_velocity, yhi_velocity, &
                               zlo_velocity, zhi_velocity], [3, 6])
    cfg%bc_pressure = [xlo_pressure, xhi_pressure, ylo_pressure, yhi_pressure, zlo_pressure, zhi_pressure]
    do f = 1, 6
      if (cfg%bc_pressure(f) < 0.0_wp) call add(problems, &
        bad('boundary', face_names(f)//'_pressure', cfg%bc_pressure(f), 'must be >= 0'))
    end do
    ! the inflow state of each inflow face (arrays indexed by face: 1 xlo,
    ! 2 xhi, 3 ylo, 4 yhi, 5 zlo, 6 zhi)
    cfg%bc_inflow_density = inflow_density
    cfg%bc_inflow_pressure = inflow_pressure
    cfg%bc_inflow_mat = 0
    do f = 1, 6
      if (kinds(f) /= 'inflow') cycle
      m = material_index(cfg, inflow_material(f))
      cfg%bc_inflow_mat(f) = m
      if (m == 0) call add(problems, '&boundary: inflow_material('//itoa(f)//') = '''// &
        trim(inflow_material(f))//''' is not a &material name (face '//face_names(f)//' is an inflow)')
      if (.not. (inflow_density(f) > 0.0_wp)) call add(problems, bad('boundary', 'inflow_density('// &
        itoa(f)//')', inflow_density(f), 'must be > 0 on an inflow face'))
      if (.not. (inflow_pressure(f) >= 0.0_wp)) call add(problems, bad('boundary', 'inflow_pressure('// &
        itoa(f)//')', inflow_pressure(f), 'must be >= 0'))
    end do
    write(echo, nml=boundary)
  end subroutine read_boundary

  !> The index of the &material called name (the last one if repeated), 0
  !> if there is none.
  integer function material_index(cfg, name) result(m)
    type(config_t), intent(in) :: cfg
    character(len=*), intent(in) :: name
    m = 0
    if (.not. allocated(cfg%materials)) return
    do m = size(cfg%materials), 1, -1
      if (cfg%materials(m)%name == name) return
    end do
    m = 0
  end function material_index

  subroutine read_rezone(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=16) :: mode, reconstruction, nodal_mass
    real(wp) :: side_ratio, cos_angle, interval_time, quality, quality_target, d_max, move_min
    integer :: interval_steps, mof_max_iter, smooth_iterations, ios
    logical :: check_conservation
    character(len=max_line) :: msg
    type(rezone_cfg_t) :: defaults
    namelist /rezone/ mode, side_ratio, cos_angle, interval_steps, interval_time, reconstruction, &
                      mof_max_iter, check_conservation, quality, quality_target, smooth_iterations, d_max, &
                      move_min, nodal_mass

    mode = defaults%mode; side_ratio = defaults%side_ratio; cos_angle = defaults%cos_angle
    interval_steps = defaults%interval_steps; interval_time = defaults%interval_time
    reconstruction = defaults%reconstruction; mof_max_iter = defaults%mof_max_iter
    check_conservation = defaults%check_conservation
    quality = defaults%quality; quality_target = defaults%quality_target
    smooth_iterations = defaults%smooth_iterations; d_max = defaults%d_max; move_min = defaults%move_min
    nodal_mass = defaults%nodal_mass
    if (group_count(lines, 'rezone') > 0) then
      rewind(unit)
      read(unit, nml=rezone, iostat=ios, iomsg=msg)
      if (ios /= 0) call add(problems, nml_error(cfg%deck_path, 'rezone', ios, msg))
    end if
    select case (trim(mode))
    case ('none', 'global', 'lssm', 'smooth')
    case default
      call add(problems, '&rezone: mode = '''//trim(mode)//''' is not known; valid: none, global, lssm, smooth')
    end select
    select case (trim(reconstruction))
    case ('linear', 'constant')
    case default
      call add(problems, '&rezone: reconstruction = '''//trim(reconstruction)// &
        ''' is not known; valid: linear, constant')
    end select
    select case (trim(nodal_mass))
    case ('transported', 'consistent')
    case default
      call add(problems, '&rezone: nodal_mass = '''//trim(nodal_mass)// &
        ''' is not known; valid: transported, consistent')
    end select
    if (.not. (side_ratio >= 0.0_wp) .or. (side_ratio > 0.0_wp .and. side_ratio <= 1.0_wp)) &
      call add(problems, bad('rezone', 'side_ratio', side_ratio, 'must be 0 (off) or > 1'))
    if (.not. (cos_angle >= 0.0_wp .and. cos_angle < 1.0_wp)) &
      call add(problems, bad('rezone', 'cos_angle', cos_angle, 'must be in [0, 1) (0: off)'))
    if (interval_steps < 0) call add(problems, badi('rezone', 'interval_steps', interval_steps, &
      'must be >= 0 (0: off)'))
    if (.not. (interval_time >= 0.0_wp)) call add(problems, bad('rezone', 'interval_time', interval_time, &
      'must be >= 0 (0: off)'))
    if (mof_max_iter < 1) call add(problems, badi('rezone', 'mof_max_iter', mof_max_iter, 'must be >= 1'))
    if (.not. (quality > 0.0_wp .and. quality <= 1.0_wp)) &
      call add(problems, bad('rezone', 'quality', quality, 'must be in (0, 1]'))
    if (.not. (quality_target > 0.0_wp .and. quality_target <= 1.0_wp)) &
      call add(problems, bad('rezone', 'quality_target', quality_target, 'must be in (0, 1]'))
    if (smooth_iterations < 1) call add(problems, badi('rezone', 'smooth_iterations', smooth_iterations, &
      'must be >= 1'))
    if (.not. (d_max >= 0.0_wp)) call add(problems, bad('rezone', 'd_max', d_max, &
      'must be >= 0 (0: a tenth of the smallest grid dimension)'))
    if (.not. (move_min >= 0.0_wp .and. move_min < 0.5_wp)) call add(problems, bad('rezone', 'move_min', &
      move_min, 'must be in [0, 0.5) (0: off)'))
    if (trim(mode) /= 'none' .and. .not. (side_ratio > 0.0_wp .or. cos_angle > 0.0_wp .or. &
                                            interval_steps > 0 .or. interval_time > 0.0_wp)) &
      call add(problems, '&rezone: mode = '''//trim(mode)//''' needs a trigger; set side_ratio > 1, '// &
        'cos_angle > 0, interval_steps > 0 or interval_time > 0')
    cfg%rezone = rezone_cfg_t(mode=mode, side_ratio=side_ratio, cos_angle=cos_angle, &
      interval_steps=interval_steps, interval_time=interval_time, reconstruction=reconstruction, &
      mof_max_iter=mof_max_iter, check_conservation=check_conservation, quality=quality, &
      quality_target=quality_target, smooth_iterations=smooth_iterations, d_max=d_max, move_min=move_min, &
      nodal_mass=nodal_mass)
    write(echo, nml=rezone)
  end subroutine read_rezone

  subroutine read_output(unit, lines, cfg, echo, problems)
    integer, intent(in) :: unit, echo
    character(len=*), intent(in) :: lines(:)
    type(config_t), intent(inout) :: cfg
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=256) :: dir, name
    real(wp) :: frame_dt, gauge_dt, gauge(3, max_gauges)
    integer :: frame_steps, ios, i
    character(len=max_line) :: msg
    character(len=16) :: tag
    namelist /output/ dir, name, frame_dt, frame_steps, gauge_dt, gauge

    dir = 'out'; name = ''; frame_dt = 0.0_wp; frame_steps = 0; gauge_dt = 0.0_wp
    gauge = huge(1.0_wp)
    if (group_count(lines, 'output') > 0) then
      rewind(unit)
      read(unit, nml=output, iostat=ios, iomsg=msg)
      if (ios /= 0) call add(problems, nml_error(cfg%deck_path, 'output', ios, msg))
    end if
    if (len_trim(name) == 0) name = deck_stem(cfg%deck_path)
    if (frame_dt < 0.0_wp) call add(problems, bad('output', 'frame_dt', frame_dt, 'must be >= 0 (0: first and last frame only)'))
    if (gauge_dt < 0.0_wp) call add(problems, bad('output', 'gauge_dt', gauge_dt, 'must be >= 0 (0: every step)'))
    if (frame_steps < 0) call add(problems, badi('output', 'frame_steps', frame_steps, 'must be >= 0'))
    cfg%ngauge = 0
    do i = 1, max_gauges
      if (any(gauge(:, i) > 0.5_wp*huge(1.0_wp))) exit
      cfg%ngauge = i
      cfg%gauges(:, i) = gauge(:, i)
      if (any(gauge(:, i) < cfg%xmin) .or. any(gauge(:, i) > cfg%xmax)) then
        write(tag, '(a,i0,a)') 'gauge(:,', i, ')'
        call add(problems, '&output: '//trim(tag)//' is outside the grid box xmin..xmax')
      end if
    end do
    cfg%out_dir = dir; cfg%out_name = name; cfg%frame_dt = frame_dt
    cfg%frame_steps = frame_steps; cfg%gauge_dt = gauge_dt
    write(echo, nml=output)
  end subroutine read_output

  !> What a restart may not change: every variable the state depends on
  !> (grid, materials, regions, sources, boundaries, the initial noise). One
  !> line per changed variable, naming it; empty if the decks agree. Time,
  !> output, dump and numerical settings (&hydro, &rezone, cfl, dt limits)
  !> may change: none of them is part of the stored state.
  subroutine input_state_changes(old, new, changes)
    type(config_t), intent(in) :: old, new
    character(len=max_line), allocatable, intent(out) :: changes(:)
    integer :: k, f

    allocate(changes(0))
    call diff_i(changes, '&grid ni', old%ni, new%ni)
    call diff_i(changes, '&grid nj', old%nj, new%nj)
    call diff_i(changes, '&grid nk', old%nk, new%nk)
    call diff_r(changes, '&grid xmin', old%xmin, new%xmin)
    call diff_r(changes, '&grid xmax', old%xmax, new%xmax)
    call diff_r(changes, '&run velocity_noise', [old%velocity_noise], [new%velocity_noise])
    call diff_i(changes, '&run seed', old%seed, new%seed)
    call diff_i(changes, 'number of &material groups', size(old%materials), size(new%materials))
    do k = 1, min(size(old%materials), size(new%materials))
      associate (a => old%materials(k), b => new%materials(k))
        if (a%name /= b%name) call add(changes, '&material('//itoa(k)//') name changed')
        if (a%eos /= b%eos) call add(changes, '&material '''//trim(a%name)//''' eos changed')
        call diff_r(changes, '&material '''//trim(a%name)//''' gamma', [a%par%gamma], [b%par%gamma])
        call diff_r(changes, '&material '''//trim(a%name)//''' jwl a, b, r1, r2, omega', &
                    [a%par%a, a%par%b, a%par%r1, a%par%r2, a%par%omega], &
                    [b%par%a, b%par%b, b%par%r1, b%par%r2, b%par%omega])
        call diff_r(changes, '&material '''//trim(a%name)//''' rho0, c0, s1, gamma0', &
                    [a%par%rho0, a%par%c0, a%par%s1, a%par%gamma0], &
                    [b%par%rho0, b%par%c0, b%par%s1, b%par%gamma0])
        call diff_r(changes, '&material '''//trim(a%name)//''' p_min, rho_min', [a%p_min, a%rho_min], &
                    [b%p_min, b%rho_min])
      end associate
    end do
    call diff_i(changes, 'number of &region groups', size(old%regions), size(new%regions))
    do k = 1, min(size(old%regions), size(new%regions))
      associate (a => old%regions(k), b => new%regions(k))
        if (a%shape /= b%shape) call add(changes, '&region('//itoa(k)//') shape changed')
        if (a%material /= b%material) call add(changes, '&region('//itoa(k)//') material changed')
        call diff_r(changes, '&region('//itoa(k)//') density', [a%density], [b%density])
        call diff_r(changes, '&region('//itoa(k)//') energy', [a%energy], [b%energy])
        call diff_r(changes, '&region('//itoa(k)//') pressure', [a%pressure], [b%pressure])
        call diff_r(changes, '&region('//itoa(k)//') velocity', a%velocity, b%velocity)
        call diff_r(changes, '&region('//itoa(k)//') lo', a%lo, b%lo)
        call diff_r(changes, '&region('//itoa(k)//') hi', a%hi, b%hi)
        call diff_r(changes, '&region('//itoa(k)//') center', a%center, b%center)
        call diff_r(changes, '&region('//itoa(k)//') radius', [a%radius], [b%radius])
        call diff_i(changes, '&region('//itoa(k)//') axis', a%axis, b%axis)
        call diff_r(changes, '&region('//itoa(k)//') normal', a%normal, b%normal)
      end associate
    end do
    call diff_i(changes, 'number of &source groups', size(old%sources), size(new%sources))
    do k = 1, min(size(old%sources), size(new%sources))
      call diff_r(changes, '&source('//itoa(k)//') position', old%sources(k)%position, new%sources(k)%position)
      call diff_r(changes, '&source('//itoa(k)//') energy', [old%sources(k)%energy], [new%sources(k)%energy])
    end do
    do f = 1, 6
      call diff_i(changes, '&boundary '//face_names(f), old%bc_kind(f), new%bc_kind(f))
      call diff_r(changes, '&boundary '//face_names(f)//'_velocity', old%bc_velocity(:, f), new%bc_velocity(:, f))
      call diff_r(changes, '&boundary '//face_names(f)//'_pressure', [old%bc_pressure(f)], [new%bc_pressure(f)])
      call diff_r(changes, '&boundary inflow_density('//itoa(f)//')', [old%bc_inflow_density(f)], &
                  [new%bc_inflow_density(f)])
      call diff_r(changes, '&boundary inflow_pressure('//itoa(f)//')', [old%bc_inflow_pressure(f)], &
                  [new%bc_inflow_pressure(f)])
      call diff_i(changes, '&boundary inflow_material('//itoa(f)//')', old%bc_inflow_mat(f), new%bc_inflow_mat(f))
    end do
  end subroutine input_state_changes

  subroutine diff_i(changes, what, a, b)
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    character(len=*), intent(in) :: what
    integer, intent(in) :: a, b
    if (a /= b) call add(changes, what//' changed from '//itoa(a)//' to '//itoa(b))
  end subroutine diff_i

  !> Exact comparison (of the bits): the deck echo stored in a restart file
  !> prints 17 digits, so it reads back as the very values first read.
  subroutine diff_r(changes, what, a, b)
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    character(len=*), intent(in) :: what
    real(wp), intent(in) :: a(:), b(:)
    character(len=64) :: buf
    if (all(transfer(a, 1_i8, size(a)) == transfer(b, 1_i8, size(b)))) return
    write(buf, '(g0)') b(1)
    call add(changes, what//' changed (new first value '//trim(buf)//')')
  end subroutine diff_r


  ! ---------------------------------------------------------------- helpers

  !> Reads all records of an open unit.
  subroutine read_lines(unit, lines, ios, msg)
    integer, intent(in) :: unit
    character(len=max_line), allocatable, intent(out) :: lines(:)
    integer, intent(out) :: ios
    character(len=*), intent(inout) :: msg
    character(len=max_line) :: buf
    character(len=max_line), allocatable :: tmp(:)
    integer :: n

    allocate(lines(64))
    n = 0
    rewind(unit)
    do
      read(unit, '(a)', iostat=ios, iomsg=msg) buf
      if (ios /= 0) exit
      n = n + 1
      if (n > size(lines)) then
        allocate(tmp(2*size(lines)))
        tmp(1:n - 1) = lines(1:n - 1)
        call move_alloc(tmp, lines)
      end if
      lines(n) = buf
    end do
    if (ios < 0) ios = 0
    lines = lines(1:n)
  end subroutine read_lines

  !> Number of `&name` group starts in the deck (case-insensitive; text after
  !> `!` is a comment).
  integer function group_count(lines, name)
    character(len=*), intent(in) :: lines(:), name
    integer :: i
    group_count = 0
    do i = 1, size(lines)
      if (group_at(lines(i)) == name) group_count = group_count + 1
    end do
  end function group_count

  !> The group name that line starts, lower case, or '' if none.
  function group_at(line) result(name)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: name
    character(len=:), allocatable :: s
    integer :: i, j
    s = adjustl(line)
    name = ''
    if (len(s) < 2) return
    if (s(1:1) /= '&') return
    j = 1
    do i = 2, len_trim(s)
      if (scan(s(i:i), ' /!,') > 0) exit
      j = i
    end do
    name = lower(s(2:j))
  end function group_at

  !> Reports any `&group` that is not one of the known groups.
  subroutine check_group_names(path, lines, problems)
    character(len=*), intent(in) :: path, lines(:)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=:), allocatable :: g
    integer :: i
    do i = 1, size(lines)
      g = group_at(lines(i))
      if (len(g) == 0) cycle
      if (any(known_groups == g)) cycle
      call add(problems, trim(path)//': group &'//g//' is not known; valid: &run, &grid, &hydro, '// &
        '&material, &region, &source, &boundary, &rezone, &output')
    end do
  end subroutine check_group_names

  !> Message for a failed namelist read. gfortran reports a bad value just
  !> before `/` or a missing `/` as end-of-file; the group is known to be
  !> present here, so end-of-file is an error too.
  function nml_error(path, group, ios, msg) result(line)
    character(len=*), intent(in) :: path, group, msg
    integer, intent(in) :: ios
    character(len=:), allocatable :: line
    if (ios < 0) then
      line = trim(path)//': &'//group//': end of file while reading the group '// &
             '(missing ''/'' or a bad value before it)'
    else
      line = trim(path)//': &'//group//': '//trim(msg)
    end if
  end function nml_error

  function bad(group, var, value, rule) result(line)
    character(len=*), intent(in) :: group, var, rule
    real(wp), intent(in) :: value
    character(len=:), allocatable :: line
    character(len=32) :: buf
    write(buf, '(g0)') value
    line = '&'//group//': '//var//' = '//trim(buf)//' '//rule
  end function bad

  function badi(group, var, value, rule) result(line)
    character(len=*), intent(in) :: group, var, rule
    integer, intent(in) :: value
    character(len=:), allocatable :: line
    character(len=32) :: buf
    write(buf, '(i0)') value
    line = '&'//group//': '//var//' = '//trim(buf)//' '//rule
  end function badi

  !> Appends a line (assigned first: gfortran 12 overruns a typed array
  !> constructor given a longer string).
  subroutine add(list, line)
    character(len=max_line), allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: line
    character(len=max_line) :: l
    l = line
    list = [list, l]
  end subroutine add

  pure function lower(s) result(t)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: t
    integer :: i
    t = s
    do i = 1, len(s)
      if (s(i:i) >= 'A' .and. s(i:i) <= 'Z') t(i:i) = achar(iachar(s(i:i)) + 32)
    end do
  end function lower

  function join(lines) result(text)
    character(len=*), intent(in) :: lines(:)
    character(len=:), allocatable :: text
    integer :: i
    text = ''
    do i = 1, size(lines)
      text = text//squeeze_quoted(trim(lines(i)))//new_line('a')
    end do
  end function join

  !> Drops the blanks that list-directed namelist output pads inside quoted
  !> strings ("out/sedov3d      " becomes "out/sedov3d").
  function squeeze_quoted(line) result(t)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: t
    integer :: i
    logical :: inq
    t = ''
    inq = .false.
    do i = 1, len(line)
      if (line(i:i) == '"') then
        if (inq) t = trim(t)
        inq = .not. inq
      end if
      t = t//line(i:i)
    end do
  end function squeeze_quoted

  !> File name of the deck without directory and extension.
  function deck_stem(path) result(stem)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: stem
    integer :: i, j
    i = index(path, '/', back=.true.)
    stem = path(i + 1:)
    j = index(stem, '.', back=.true.)
    if (j > 1) stem = stem(1:j - 1)
  end function deck_stem
end module io_input
