!> The &hydro group: the numerical parameters of the Lagrangian phase. Its
!> configuration type is the kernels' own `hydro_params_t` (`hydro_state`),
!> whose initial values are the defaults; &run's time-step controls (cfl,
!> dt_growth, dt_max) are stored in it by the driver's &run reader.
module lagrange_config
  use base_kinds, only: wp
  use base_config, only: max_line, no_echo, problem_long, problem_add, problem_bad, problem_nml
  use hydro_state, only: hydro_params_t, VISC_EDGE, VISC_TENSOR
  implicit none
  private
  public :: hydro_config_read

  !> Deck names of the viscosity forms, by VISC_* value.
  character(len=*), parameter :: visc_names(2) = [character(len=8) :: 'edge', 'tensor']

contains

  !> Reads, validates and echoes the &hydro group into `par` (`text` empty:
  !> all defaults). Only the &hydro components of `par` are set.
  subroutine hydro_config_read(par, text, path, echo, problems)
    type(hydro_params_t), intent(inout) :: par
    character(len=*), intent(in) :: text(:), path
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    type(hydro_params_t) :: defaults
    real(wp) :: q_linear, q_quad, hourglass, dv_max, relax, dv_vf_min, particle_q, relax_length, velocity_cutoff
    character(len=16) :: viscosity, particles, stress_update, particle_viscosity, particle_support
    integer :: ios
    character(len=max_line) :: msg
    namelist /hydro/ viscosity, q_linear, q_quad, hourglass, dv_max, relax, dv_vf_min, particles, stress_update, &
                     particle_viscosity, particle_support, particle_q, relax_length, velocity_cutoff

    viscosity = visc_names(defaults%viscosity)
    q_linear = defaults%q_linear; q_quad = defaults%q_quad
    hourglass = defaults%hourglass; dv_max = defaults%dv_max; relax = defaults%relax
    dv_vf_min = defaults%dv_vf_min
    particles = merge('coupled', 'inert  ', defaults%particles_coupled)
    stress_update = merge('decoupled', 'original ', defaults%stress_decoupled)
    particle_viscosity = merge('scaled', 'full  ', defaults%particle_visc_scaled)
    particle_support = merge('gimp  ', 'linear', defaults%particle_gimp)
    particle_q = defaults%particle_q
    relax_length = defaults%relax_length
    velocity_cutoff = defaults%velocity_cutoff
    if (size(text) > 0) then
      read(text, nml=hydro, iostat=ios, iomsg=msg)
      if (ios /= 0) call problem_nml(problems, path, 'hydro', ios, msg)
    end if
    call problem_long(problems, 'hydro', 'viscosity', viscosity)
    select case (trim(viscosity))
    case ('tensor'); par%viscosity = VISC_TENSOR
    case ('edge'); par%viscosity = VISC_EDGE
    case default
      call problem_add(problems, '&hydro: viscosity = '''//trim(viscosity)//''' is not known; valid: tensor, edge')
    end select
    call problem_long(problems, 'hydro', 'particles', particles)
    call problem_long(problems, 'hydro', 'stress_update', stress_update)
    call problem_long(problems, 'hydro', 'particle_viscosity', particle_viscosity)
    call problem_long(problems, 'hydro', 'particle_support', particle_support)
    select case (trim(particles))
    case ('coupled'); par%particles_coupled = .true.
    case ('inert'); par%particles_coupled = .false.
    case default
      call problem_add(problems, '&hydro: particles = '''//trim(particles)//''' is not known; valid: coupled, inert')
    end select
    select case (trim(stress_update))
    case ('decoupled'); par%stress_decoupled = .true.
    case ('original'); par%stress_decoupled = .false.
    case default
      call problem_add(problems, '&hydro: stress_update = '''//trim(stress_update)// &
                       ''' is not known; valid: decoupled, original')
    end select
    select case (trim(particle_viscosity))
    case ('scaled'); par%particle_visc_scaled = .true.
    case ('full'); par%particle_visc_scaled = .false.
    case default
      call problem_add(problems, '&hydro: particle_viscosity = '''//trim(particle_viscosity)// &
                       ''' is not known; valid: scaled, full')
    end select
    select case (trim(particle_support))
    case ('linear'); par%particle_gimp = .false.
    case ('gimp'); par%particle_gimp = .true.
    case default
      call problem_add(problems, '&hydro: particle_support = '''//trim(particle_support)// &
                       ''' is not known; valid: linear, gimp')
    end select
    if (q_linear < 0.0_wp) call problem_bad(problems, 'hydro', 'q_linear', q_linear, 'must be >= 0')
    if (q_quad < 0.0_wp) call problem_bad(problems, 'hydro', 'q_quad', q_quad, 'must be >= 0')
    if (hourglass < 0.0_wp) call problem_bad(problems, 'hydro', 'hourglass', hourglass, 'must be >= 0')
    if (.not. (particle_q >= 0.0_wp .and. particle_q <= 2.0_wp)) call problem_bad(problems, 'hydro', 'particle_q', &
      particle_q, 'must be in [0, 2]')
    if (.not. (dv_max > 0.0_wp)) call problem_bad(problems, 'hydro', 'dv_max', dv_max, 'must be > 0')
    if (.not. (relax > 0.0_wp .and. relax <= 1.0_wp)) call problem_bad(problems, 'hydro', 'relax', relax, &
      'must be in (0, 1]')
    if (.not. (relax_length >= 0.0_wp .and. relax_length <= 100.0_wp)) call problem_bad(problems, 'hydro', &
      'relax_length', relax_length, 'must be in [0, 100]')
    if (.not. (dv_vf_min > 0.0_wp .and. dv_vf_min <= 1.0_wp)) call problem_bad(problems, 'hydro', 'dv_vf_min', &
      dv_vf_min, 'must be in (0, 1]')
    if (.not. (velocity_cutoff >= 0.0_wp .and. velocity_cutoff <= 1.0e-6_wp)) call problem_bad(problems, 'hydro', &
      'velocity_cutoff', velocity_cutoff, 'must be in [0, 1e-6]')
    par%q_linear = q_linear; par%q_quad = q_quad
    par%hourglass = hourglass; par%dv_max = dv_max; par%relax = relax; par%dv_vf_min = dv_vf_min
    par%particle_q = particle_q
    par%relax_length = relax_length
    par%velocity_cutoff = velocity_cutoff
    if (echo /= no_echo) write(echo, nml=hydro)
  end subroutine hydro_config_read
end module lagrange_config
