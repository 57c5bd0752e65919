!> The &solid and &particles groups: the solid materials of a scene and how
!> its MPM particles are seeded (read / validate / echo / compare for a
!> restart; ARCHITECTURE.md §4). Both may be given several times; a deck without
!> &particles has no particles and allocates nothing for them.
!>
!> &solid: a name, a reference density, the pressure law (an `eos_factory`
!> EOS with its parameters, or 'none': pressure from the bulk modulus), the
!> elastic moduli (bulk and shear, or Young's modulus and Poisson's ratio)
!> and a strength model: 'elastic', 'bilinear' (linear hardening from
!> yield_stress with tangent_modulus, optionally failing at failure_strain;
!> PARTICLES.md §2.1-2.2), 'johnson_cook' (jc_a, jc_b, jc_n, jc_c, jc_eps0,
!> jc_m, t_room, t_melt, specific_heat, taylor_quinney; §2.3), 'gurson'
!> (the jc_* matrix, gtn_*, failure_strain, void_*; §2.4) or 'hjc'
!> (Holmquist-Johnson-Cook concrete from the hjc_* variables, §2.5: its own
!> pressure, so eos = 'none' and no bulk_modulus), a name of the strength
!> factory's list (`strength_factory::strength_names`). Coupled
!> particles use K, G and the model (`strength_create`), or with eos =
!> 'mie_gruneisen' (the only EOS a solid takes) the EOS's pressure p(rho,
!> e), G and the model's deviator. With an EOS the deck gives no
!> bulk_modulus (its pressure would contradict the EOS): the resolved K is
!> E/(3(1 - 2 nu)) if youngs_modulus and poisson_ratio are given, else the
!> EOS's rho0 c0^2, and serves only Young's modulus of the bilinear
!> hardening modulus; rho0 = 0 (not given) means the solid's density.
!>
!> &solid library = 'name' takes the variables the group does not give from
!> the entry `name` of the material library (`material_library`, converted
!> to the deck's &run units): its density, eos and strength; its EOS
!> parameters if the solid's eos is the entry's; its elastic moduli only if
!> the group gives none of bulk_modulus, shear_modulus, youngs_modulus,
!> poisson_ratio (a pair of the group's replaces the entry's pair); and each
!> model's parameters only to a solid of that model (jc_a, jc_b, jc_n, jc_c,
!> jc_eps0 to johnson_cook and gurson; jc_m, t_room, t_melt, specific_heat,
!> taylor_quinney to johnson_cook; yield_stress, tangent_modulus to
!> bilinear; failure_strain to bilinear and gurson; gtn_* to gurson; hjc_*
!> to hjc), so that a deck may take an entry's Johnson-Cook steel as the
!> matrix of a gurson solid.
!>
!> &particles: a shape (box, sphere, cylinder, all, or file: a text file of
!> points), particles per cell per direction, the solid, density (default
!> the solid's), initial velocity (uniform, or a rigid rotation about the x,
!> y or z axis through center) and stress, and a body id.
module particles_config
  use base_kinds, only: wp
  use mesh_shapes, only: shape_inner_radius_problem
  use base_strings, only: itoa, rtoa
  use mesh_grid_config, only: resolve_path
  use base_errors, only: error_t
  use base_config, only: max_line, no_echo, problem_long, problem_add, problem_bad, problem_badi, problem_nml, &
                         diff_i, diff_r, diff_s, name_index
  use eos_base, only: eos_t
  use eos_factory, only: eos_params_t, eos_create
  use strength_factory, only: strength_names, strength_create
  use strength_models, only: strength_t, strength_params_t
  use strength_random_field, only: random_field_covariances, void_fraction_distributions
  use material_library, only: units_known, units_list, library_names, library_has, library_value, library_text
  implicit none
  private
  public :: solid_config_t, particles_config_t, solid_config_read, particles_config_read, particles_config_changes, &
            particles_file_place, strength_names, max_per_cell

  !> Most particles per cell per direction (per_cell^3 per cell).
  integer, parameter :: max_per_cell = 16
  !> poisson_ratio's "not given" (outside its valid range (-1, 0.5)).
  real(wp), parameter :: nu_unset = -1.0_wp

  !> One resolved &solid group; the initial values are the defaults.
  type :: solid_config_t
    character(len=64) :: name = ''                 !< '' becomes 'solid<N>'
    character(len=300) :: where = ''               !< 'deck:line: ' of the group, for later refusals
    real(wp) :: density = 0.0_wp                   !< reference density (required, > 0)
    character(len=64) :: eos = 'none'              !< 'none' (pressure K (rho/rho0 - 1)) or an eos_factory name
    character(len=64) :: library = ''              !< a `material_library` entry ('' none)
    type(eos_params_t) :: par                      !< EOS parameters
    real(wp) :: bulk_modulus = 0.0_wp              !< K (pressure); resolved from E, nu or the EOS (module notes)
    real(wp) :: shear_modulus = 0.0_wp             !< G (pressure); resolved from E, nu if those are given
    !   (the echo shows the deck's own values; K and G here are resolved)
    real(wp) :: youngs_modulus = 0.0_wp            !< E (pressure), with poisson_ratio instead of K, G
    real(wp) :: poisson_ratio = nu_unset           !< nu in (-1, 0.5)
    character(len=16) :: strength = 'elastic'      !< a name of strength_names
    real(wp) :: yield_stress = 0.0_wp              !< bilinear: initial yield stress (pressure)
    real(wp) :: tangent_modulus = 0.0_wp           !< bilinear: slope of stress against strain after yield
    ! johnson_cook (PARTICLES.md §2.3; A, B, n, C, eps_dot0 also gurson's matrix): A, B (pressure), n, C,
    ! eps_dot0 (1/time), m (0: no softening), T_room, T_melt, c_p (energy/(mass temperature), 0: no heating),
    ! Taylor-Quinney chi
    real(wp) :: jc_a = 0.0_wp, jc_b = 0.0_wp, jc_n = 1.0_wp, jc_c = 0.0_wp, jc_eps0 = 1.0_wp, jc_m = 0.0_wp
    real(wp) :: t_room = 293.15_wp, t_melt = 0.0_wp, specific_heat = 0.0_wp, taylor_quinney = 0.9_wp
    ! gurson (GTN + TEPLA-F, PARTICLES.md 2.4)
    real(wp) :: gtn_q1 = 1.5_wp, gtn_q2 = 1.0_wp                    !< yield function q1, q2 (q3 = q1^2)
    real(wp) :: gtn_fn = 0.0_wp, gtn_epsn = 0.3_wp, gtn_sn = 0.1_wp   !< nucleation f_N, eps_N, s_N
    real(wp) :: gtn_fc = 0.15_wp, gtn_ff = 0.25_wp                  !< coalescence f_c (TEPLA-F's), final f_F
    real(wp) :: failure_strain = 0.0_wp                             !< equivalent plastic strain at failure
    real(wp) :: tensile_strength = 0.0_wp        !< bilinear: largest principal stress at failure (0: none)
    real(wp) :: void_mean = 0.0_wp, void_std = 0.0_wp               !< initial porosity f0: mean, standard deviation
    real(wp) :: void_length = 0.0_wp                                !< f0 field's correlation length (0: uncorrelated)
    integer :: void_seed = 1                                        !< f0 field's seed
    character(len=16) :: void_covariance = 'gaussian'               !< f0 field's covariance (random_field_covariances)
    character(len=16) :: void_distribution = 'normal'               !< f0's distribution (void_fraction_distributions)
    type(strength_params_t) :: hjc                 !< strength = 'hjc': its hjc_* values (other fields unused)
  end type solid_config_t

  !> One resolved &particles group; the initial values are the defaults.
  type :: particles_config_t
    character(len=16) :: shape = ''                   !< box, sphere, cylinder, all, file, line, stl (required)
    real(wp) :: lo(3) = -huge(1.0_wp), hi(3) = huge(1.0_wp)   !< box corners; cylinder's extent along its axis
    real(wp) :: center(3) = 0.0_wp, radius = 0.0_wp   !< sphere, cylinder; centre of a rotation
    real(wp) :: inner_radius = 0.0_wp                 !< sphere, cylinder: hollow inside it
    integer :: axis = 3                               !< cylinder and rotation axis: 1 x, 2 y, 3 z
    character(len=256) :: file = ''                   !< shape = 'file': the points (text); 'stl': the surface
    !> shape = 'line': the segment's ends (a bar: reinforcement) and its
    !> cross-section's area (length^2)
    real(wp) :: point(3) = huge(1.0_wp), point2(3) = huge(1.0_wp), area = 0.0_wp
    !> shape = 'file' or 'stl': the file's coordinates x become scale x +
    !> offset (a CAD surface in other units or another frame)
    real(wp) :: scale = 1.0_wp, offset(3) = 0.0_wp
    character(len=:), allocatable :: file_path        !< `file` resolved against the deck's folder
    integer :: per_cell = 2                           !< particles per cell per direction
    character(len=64) :: solid = ''                   !< a &solid name
    integer :: isolid = 0                             !< its index (resolved)
    real(wp) :: density = 0.0_wp                      !< 0: the solid's density
    real(wp) :: velocity(3) = 0.0_wp                  !< uniform velocity (added to the rotation)
    character(len=16) :: velocity_field = 'uniform'   !< uniform, rotation
    real(wp) :: angular_velocity = 0.0_wp             !< rotation: radians per time about axis through center
    real(wp) :: stress(6) = 0.0_wp                    !< initial Cauchy stress xx, yy, zz, yz, xz, xy
    integer :: body = 0                               !< body id; 0: the group's number
  end type particles_config_t

contains

  !> Reads, validates and echoes the s-th &solid group (`text`); `earlier`
  !> are the names of the groups before it (names must be unique); `units`
  !> the deck's &run units, to which a `library` entry's values convert
  !> (module notes: which of the entry's variables a solid takes).
  subroutine solid_config_read(this, s, text, path, earlier, units, echo, problems)
    type(solid_config_t), intent(out) :: this
    integer, intent(in) :: s, echo
    character(len=*), intent(in) :: text(:), path, earlier(:), units
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=64) :: name, eos, library
    character(len=16) :: strength
    real(wp) :: density, gamma, a, b, r1, r2, omega, rho0, c0, s1, gamma0, bulk_modulus, shear_modulus, &
                youngs_modulus, poisson_ratio, yield_stress, tangent_modulus, e_mod, k_mod, g_mod
    real(wp) :: jc_a, jc_b, jc_n, jc_c, jc_eps0, jc_m, t_room, t_melt, specific_heat, taylor_quinney
    real(wp) :: gtn_q1, gtn_q2, gtn_fn, gtn_epsn, gtn_sn, gtn_fc, gtn_ff, failure_strain, void_mean, void_std, void_length
    real(wp) :: tensile_strength
    integer :: void_seed
    character(len=16) :: void_covariance, void_distribution
    integer :: ios
    character(len=max_line) :: msg
    character(len=:), allocatable :: tag
    class(eos_t), allocatable :: trial
    type(error_t), allocatable :: err
    logical :: by_e
    real(wp) :: hjc_a, hjc_b, hjc_n, hjc_c, hjc_fc, hjc_smax, hjc_t, hjc_d1, hjc_d2, hjc_efmin, &
                hjc_pcrush, hjc_mucrush, hjc_plock, hjc_mulock, hjc_k1, hjc_k2, hjc_k3, hjc_eps0, hjc_length
    type(strength_params_t) :: hp
    logical :: moduli_given
    real(wp), parameter :: unset = -huge(1.0_wp)
    namelist /solid/ name, library, density, eos, gamma, a, b, r1, r2, omega, rho0, c0, s1, gamma0, bulk_modulus, &
                     shear_modulus, youngs_modulus, poisson_ratio, strength, yield_stress, tangent_modulus, &
                     jc_a, jc_b, jc_n, jc_c, jc_eps0, jc_m, t_room, t_melt, specific_heat, taylor_quinney, &
                     gtn_q1, gtn_q2, gtn_fn, gtn_epsn, gtn_sn, gtn_fc, gtn_ff, &
                     failure_strain, tensile_strength, void_mean, void_std, void_length, void_seed, void_covariance, &
                     void_distribution, hjc_a, hjc_b, hjc_n, hjc_c, hjc_fc, hjc_smax, hjc_t, hjc_d1, hjc_d2, hjc_efmin, &
                     hjc_pcrush, hjc_mucrush, hjc_plock, hjc_mulock, hjc_k1, hjc_k2, hjc_k3, hjc_eps0, hjc_length

    ! (the variables a library entry can give unset, so that a variable the
    ! group gives is known: they get the entry's value or the default after
    ! the read)
    name = this%name; library = this%library; density = unset; eos = ''
    associate (d => this%par)
      gamma = d%gamma; a = d%a; b = d%b; r1 = d%r1; r2 = d%r2; omega = d%omega
    end associate
    rho0 = unset; c0 = unset; s1 = unset; gamma0 = unset
    bulk_modulus = unset; shear_modulus = unset; youngs_modulus = unset; poisson_ratio = unset
    strength = ''; yield_stress = unset; tangent_modulus = unset
    jc_a = unset; jc_b = unset; jc_n = unset; jc_c = unset; jc_eps0 = unset; jc_m = unset
    t_room = unset; t_melt = unset; specific_heat = unset; taylor_quinney = unset
    gtn_q1 = unset; gtn_q2 = unset; gtn_fn = unset; gtn_epsn = unset; gtn_sn = unset
    gtn_fc = unset; gtn_ff = unset; failure_strain = unset; tensile_strength = unset
    void_mean = this%void_mean; void_std = this%void_std; void_length = this%void_length; void_seed = this%void_seed
    void_covariance = this%void_covariance; void_distribution = this%void_distribution
    hjc_a = unset; hjc_b = unset; hjc_n = unset; hjc_c = unset; hjc_fc = unset; hjc_smax = unset
    hjc_t = unset; hjc_d1 = unset; hjc_d2 = unset; hjc_efmin = unset; hjc_pcrush = unset
    hjc_mucrush = unset; hjc_plock = unset; hjc_mulock = unset; hjc_k1 = unset
    hjc_k2 = unset; hjc_k3 = unset; hjc_eps0 = unset; hjc_length = unset
    read(text, nml=solid, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_nml(problems, path, 'solid', ios, msg)
      return
    end if
    call problem_long(problems, 'solid', 'name', name)
    call problem_long(problems, 'solid', 'eos', eos)
    call problem_long(problems, 'solid', 'strength', strength)
    call problem_long(problems, 'solid', 'library', library)
    if (len_trim(name) == 0) name = 'solid'//itoa(s)
    if (any(earlier == name)) call problem_add(problems, &
      '&solid: name = '''//trim(name)//''' is used twice; names must be unique')
    tag = 'solid '''//trim(name)//''''
    call library_fill()
    if (.not. (density > 0.0_wp)) call problem_bad(problems, tag, 'density', density, 'must be > 0')
    ! the moduli: (E, nu) or (K, G), not both
    ! (the resolved moduli in k_mod, g_mod: the echo keeps what the deck gave,
    ! so that it reads back the same)
    k_mod = bulk_modulus
    g_mod = shear_modulus
    by_e = abs(youngs_modulus) > 0.0_wp .or. abs(poisson_ratio - nu_unset) > 0.0_wp
    if (by_e) then
      if (.not. (youngs_modulus > 0.0_wp)) call problem_bad(problems, tag, 'youngs_modulus', youngs_modulus, &
        'must be > 0 (give youngs_modulus and poisson_ratio together)')
      if (.not. (poisson_ratio > -1.0_wp .and. poisson_ratio < 0.5_wp)) call problem_bad(problems, tag, &
        'poisson_ratio', poisson_ratio, 'must be in (-1, 0.5) (give youngs_modulus and poisson_ratio together)')
      if (abs(bulk_modulus) > 0.0_wp .or. abs(shear_modulus) > 0.0_wp) call problem_add(problems, '&'//tag// &
        ': give either bulk_modulus and shear_modulus or youngs_modulus and poisson_ratio, not both')
      if (youngs_modulus > 0.0_wp .and. poisson_ratio > -1.0_wp .and. poisson_ratio < 0.5_wp) then
        ! K = E/(3(1 - 2 nu)), G = E/(2(1 + nu))
        k_mod = youngs_modulus/(3.0_wp*(1.0_wp - 2.0_wp*poisson_ratio))
        g_mod = youngs_modulus/(2.0_wp*(1.0_wp + poisson_ratio))
      end if
    else
      if (.not. (shear_modulus > 0.0_wp)) then
        if (len_trim(library) > 0) then
          call problem_bad(problems, tag, 'shear_modulus', shear_modulus, 'must be > 0 (or give youngs_modulus '// &
            'and poisson_ratio): the library''s '''//trim(library)//''' gives no elastic moduli')
        else
          call problem_bad(problems, tag, 'shear_modulus', shear_modulus, &
            'must be > 0 (or give youngs_modulus and poisson_ratio)')
        end if
      end if
      if (trim(eos) == 'none' .and. trim(strength) /= 'hjc' .and. .not. (bulk_modulus > 0.0_wp)) &
        call problem_bad(problems, tag, 'bulk_modulus', bulk_modulus, &
        'must be > 0 with eos = ''none'' (or give youngs_modulus and poisson_ratio)')
      if (.not. (bulk_modulus >= 0.0_wp)) call problem_bad(problems, tag, 'bulk_modulus', bulk_modulus, 'must be >= 0')
    end if
    select case (trim(eos))
    case ('none')
    case ('mie_gruneisen')
      if (abs(bulk_modulus) > 0.0_wp) call problem_bad(problems, tag, 'bulk_modulus', bulk_modulus, &
        'applies only to eos = ''none'' (with eos = '''//trim(eos)//''' the pressure comes from the EOS)')
      ! rho0 not given: the solid's density
      if (.not. abs(rho0) > 0.0_wp) rho0 = density
      this%par = eos_params_t(gamma=gamma, a=a, b=b, r1=r1, r2=r2, omega=omega, rho0=rho0, c0=c0, s1=s1, gamma0=gamma0)
      ! the factory validates the parameters
      call eos_create(eos, this%par, trial, err)
      if (allocated(err)) then
        call problem_add(problems, '&'//tag//': '//err%msg//' (or eos = ''none'': pressure from bulk_modulus)')
      else if (.not. by_e) then
        ! K only for Young's modulus of the hardening (module notes): rho0 c0^2
        k_mod = rho0*c0**2
      end if
    case default
      call problem_add(problems, '&'//tag//': eos = '''//trim(eos)//''' is not known for a solid; valid: none, '// &
                       'mie_gruneisen')
    end select
    ! the strength model and its parameters
    hp = strength_params_t(hjc_a=hjc_a, hjc_b=hjc_b, hjc_n=hjc_n, hjc_c=hjc_c, hjc_fc=hjc_fc, hjc_smax=hjc_smax, &
      hjc_t=hjc_t, hjc_d1=hjc_d1, hjc_d2=hjc_d2, hjc_efmin=hjc_efmin, hjc_pcrush=hjc_pcrush, hjc_mucrush=hjc_mucrush, &
      hjc_plock=hjc_plock, hjc_mulock=hjc_mulock, hjc_k1=hjc_k1, hjc_k2=hjc_k2, hjc_k3=hjc_k3, hjc_eps0=hjc_eps0, &
      hjc_length=hjc_length)
    if (.not. (failure_strain >= 0.0_wp)) call problem_bad(problems, tag, 'failure_strain', failure_strain, &
      'must be >= 0 (0: never fails)')
    if (trim(strength) /= 'hjc') call hjc_not_here(problems, tag, strength, hp)
    if (.not. (tensile_strength >= 0.0_wp)) call problem_bad(problems, tag, 'tensile_strength', tensile_strength, &
      'must be >= 0 (0: never fails in tension)')
    if (trim(strength) /= 'bilinear' .and. abs(tensile_strength) > 0.0_wp) call problem_bad(problems, tag, &
      'tensile_strength', tensile_strength, 'applies only to strength = ''bilinear'' (this solid''s is '''// &
      trim(strength)//''')')
    if (trim(strength) /= 'bilinear' .and. trim(strength) /= 'gurson' .and. abs(failure_strain) > 0.0_wp) &
      call problem_bad(problems, tag, 'failure_strain', failure_strain, 'applies only to strength = ''bilinear'' '// &
      'or ''gurson'' (this solid''s is '''//trim(strength)//''')')
    select case (trim(strength))
    case ('elastic')
      if (abs(yield_stress) > 0.0_wp) call problem_bad(problems, tag, 'yield_stress', yield_stress, &
        'applies only to strength = ''bilinear'' (this solid''s is ''elastic'')')
      if (abs(tangent_modulus) > 0.0_wp) call problem_bad(problems, tag, 'tangent_modulus', tangent_modulus, &
        'applies only to strength = ''bilinear'' (this solid''s is ''elastic'')')
    case ('bilinear')
      if (.not. (yield_stress > 0.0_wp)) call problem_bad(problems, tag, 'yield_stress', yield_stress, &
        'must be > 0 for strength = ''bilinear''')
      if (.not. (tangent_modulus >= 0.0_wp)) call problem_bad(problems, tag, 'tangent_modulus', tangent_modulus, &
        'must be >= 0 for strength = ''bilinear''')
      if (k_mod > 0.0_wp .and. g_mod > 0.0_wp .and. tangent_modulus >= 0.0_wp) then
        ! Young's modulus E = 9KG/(3K + G): hardening steeper than elasticity is no hardening
        e_mod = 9.0_wp*k_mod*g_mod/(3.0_wp*k_mod + g_mod)
        if (.not. (tangent_modulus < e_mod)) call problem_bad(problems, tag, 'tangent_modulus', tangent_modulus, &
          'must be below Young''s modulus '//rtoa(e_mod))
      end if
    case ('johnson_cook')
      call johnson_cook_check()
    case ('gurson')
      call gurson_problems(problems, tag, jc_a, jc_b, jc_n, jc_c, jc_eps0, gtn_q1, gtn_q2, gtn_fn, gtn_epsn, gtn_sn, &
                           gtn_fc, gtn_ff, failure_strain, void_mean, void_std, void_length, void_seed, &
                           void_covariance, void_distribution)
      ! (the gurson model has no temperature)
      if (abs(jc_m) > 0.0_wp) call problem_bad(problems, tag, 'jc_m', jc_m, 'applies only to strength = '// &
        '''johnson_cook'' (gurson has no thermal softening)')
      if (abs(specific_heat) > 0.0_wp) call problem_bad(problems, tag, 'specific_heat', specific_heat, &
        'applies only to strength = ''johnson_cook'' (gurson has no plastic heating)')
    case ('hjc')
      if (abs(yield_stress) > 0.0_wp) call problem_bad(problems, tag, 'yield_stress', yield_stress, &
        'applies only to strength = ''bilinear'' (this solid''s is ''hjc'')')
      if (abs(tangent_modulus) > 0.0_wp) call problem_bad(problems, tag, 'tangent_modulus', tangent_modulus, &
        'applies only to strength = ''bilinear'' (this solid''s is ''hjc'')')
      call hjc_check(problems, tag, eos, bulk_modulus, hp, g_mod, density)
    case default
      call problem_add(problems, '&'//tag//': strength = '''//trim(strength)//''' is not known; valid: '// &
                       name_list(strength_names))
    end select
    if (trim(strength) == 'elastic' .or. trim(strength) == 'bilinear') call johnson_cook_unused()
    ! the gurson parameters belong to strength = 'gurson'
    if (trim(strength) /= 'gurson') then
      associate (d => solid_config_t())
        if (any(abs([gtn_q1, gtn_q2, gtn_fn, gtn_epsn, gtn_sn, gtn_fc, gtn_ff, void_mean, void_std, void_length] - &
                     [d%gtn_q1, d%gtn_q2, d%gtn_fn, d%gtn_epsn, d%gtn_sn, d%gtn_fc, d%gtn_ff, d%void_mean, &
                      d%void_std, d%void_length]) > 0.0_wp) .or. void_seed /= d%void_seed .or. &
            void_covariance /= d%void_covariance .or. void_distribution /= d%void_distribution) &
          call problem_add(problems, '&'//tag//': gtn_q1, gtn_q2, gtn_fn, gtn_epsn, gtn_sn, gtn_fc, gtn_ff, '// &
          'void_mean, void_std, void_length, void_seed, void_covariance, void_distribution apply only to '// &
          'strength = ''gurson'' (this solid''s is '''//trim(strength)//''')')
      end associate
    end if
    this = solid_config_t(name=name, library=library, density=density, eos=eos, par=this%par, bulk_modulus=k_mod, &
      shear_modulus=g_mod, youngs_modulus=youngs_modulus, poisson_ratio=poisson_ratio, strength=strength, &
      yield_stress=yield_stress, tangent_modulus=tangent_modulus, jc_a=jc_a, jc_b=jc_b, jc_n=jc_n, jc_c=jc_c, &
      jc_eps0=jc_eps0, gtn_q1=gtn_q1, gtn_q2=gtn_q2, gtn_fn=gtn_fn, gtn_epsn=gtn_epsn, gtn_sn=gtn_sn, gtn_fc=gtn_fc, &
      gtn_ff=gtn_ff, failure_strain=failure_strain, tensile_strength=tensile_strength, void_mean=void_mean, &
      void_std=void_std, void_length=void_length, &
      void_seed=void_seed, void_covariance=void_covariance, void_distribution=void_distribution, jc_m=jc_m, &
      t_room=t_room, t_melt=t_melt, specific_heat=specific_heat, taylor_quinney=taylor_quinney, hjc=hp)
    if (echo /= no_echo) write(echo, nml=solid)
  contains
    !> The library entry (if any), then every variable the group did not
    !> give: the entry's where it applies (module notes), else the default.
    subroutine library_fill()
      logical :: eos_lib, jc, bilinear, gurson, hjc
      if (len_trim(library) > 0) then
        if (.not. library_has(trim(library))) then
          call problem_add(problems, '&'//tag//': library = '''//trim(library)// &
                           ''' is not in the material library (input/materials.txt): '//library_names())
          library = ''
        else if (.not. units_known(units)) then
          call problem_add(problems, '&'//tag//': library = '''//trim(library)// &
                           ''' needs the deck''s unit system, &run units, one of: '//units_list())
          library = ''
        end if
      end if
      if (len_trim(eos) == 0) eos = lib_text('eos', this%eos)
      if (len_trim(strength) == 0) strength = lib_text('strength', this%strength)
      eos_lib = trim(eos) == lib_text('eos', '')
      jc = trim(strength) == 'johnson_cook'
      bilinear = trim(strength) == 'bilinear'
      gurson = trim(strength) == 'gurson'
      hjc = trim(strength) == 'hjc'
      call fill(density, 'density', this%density, .true.)
      call fill(rho0, 'rho0', this%par%rho0, eos_lib)
      call fill(c0, 'c0', this%par%c0, eos_lib)
      call fill(s1, 's1', this%par%s1, eos_lib)
      call fill(gamma0, 'gamma0', this%par%gamma0, eos_lib)
      ! (the moduli as a set: the group's pair, else the entry's)
      moduli_given = any([bulk_modulus, shear_modulus, youngs_modulus, poisson_ratio] > unset)
      call fill(bulk_modulus, 'bulk_modulus', this%bulk_modulus, .not. moduli_given)
      call fill(shear_modulus, 'shear_modulus', this%shear_modulus, .not. moduli_given)
      call fill(youngs_modulus, 'youngs_modulus', this%youngs_modulus, .not. moduli_given)
      call fill(poisson_ratio, 'poisson_ratio', this%poisson_ratio, .not. moduli_given)
      call fill(yield_stress, 'yield_stress', this%yield_stress, bilinear)
      call fill(tangent_modulus, 'tangent_modulus', this%tangent_modulus, bilinear)
      call fill(jc_a, 'jc_a', this%jc_a, jc .or. gurson)
      call fill(jc_b, 'jc_b', this%jc_b, jc .or. gurson)
      call fill(jc_n, 'jc_n', this%jc_n, jc .or. gurson)
      call fill(jc_c, 'jc_c', this%jc_c, jc .or. gurson)
      call fill(jc_eps0, 'jc_eps0', this%jc_eps0, jc .or. gurson)
      call fill(jc_m, 'jc_m', this%jc_m, jc)
      call fill(t_room, 't_room', this%t_room, jc)
      call fill(t_melt, 't_melt', this%t_melt, jc)
      call fill(specific_heat, 'specific_heat', this%specific_heat, jc)
      call fill(taylor_quinney, 'taylor_quinney', this%taylor_quinney, jc)
      call fill(failure_strain, 'failure_strain', this%failure_strain, bilinear .or. gurson)
      call fill(tensile_strength, 'tensile_strength', this%tensile_strength, bilinear)
      call fill(gtn_q1, 'gtn_q1', this%gtn_q1, gurson)
      call fill(gtn_q2, 'gtn_q2', this%gtn_q2, gurson)
      call fill(gtn_fn, 'gtn_fn', this%gtn_fn, gurson)
      call fill(gtn_epsn, 'gtn_epsn', this%gtn_epsn, gurson)
      call fill(gtn_sn, 'gtn_sn', this%gtn_sn, gurson)
      call fill(gtn_fc, 'gtn_fc', this%gtn_fc, gurson)
      call fill(gtn_ff, 'gtn_ff', this%gtn_ff, gurson)
      associate (h => this%hjc)
        call fill(hjc_a, 'hjc_a', h%hjc_a, hjc)
        call fill(hjc_b, 'hjc_b', h%hjc_b, hjc)
        call fill(hjc_n, 'hjc_n', h%hjc_n, hjc)
        call fill(hjc_c, 'hjc_c', h%hjc_c, hjc)
        call fill(hjc_fc, 'hjc_fc', h%hjc_fc, hjc)
        call fill(hjc_smax, 'hjc_smax', h%hjc_smax, hjc)
        call fill(hjc_t, 'hjc_t', h%hjc_t, hjc)
        call fill(hjc_d1, 'hjc_d1', h%hjc_d1, hjc)
        call fill(hjc_d2, 'hjc_d2', h%hjc_d2, hjc)
        call fill(hjc_efmin, 'hjc_efmin', h%hjc_efmin, hjc)
        call fill(hjc_pcrush, 'hjc_pcrush', h%hjc_pcrush, hjc)
        call fill(hjc_mucrush, 'hjc_mucrush', h%hjc_mucrush, hjc)
        call fill(hjc_plock, 'hjc_plock', h%hjc_plock, hjc)
        call fill(hjc_mulock, 'hjc_mulock', h%hjc_mulock, hjc)
        call fill(hjc_k1, 'hjc_k1', h%hjc_k1, hjc)
        call fill(hjc_k2, 'hjc_k2', h%hjc_k2, hjc)
        call fill(hjc_k3, 'hjc_k3', h%hjc_k3, hjc)
        call fill(hjc_eps0, 'hjc_eps0', h%hjc_eps0, hjc)
        ! (the particle size of the damage constants: the deck's, not a library entry's)
        if (.not. hjc_length > unset) hjc_length = h%hjc_length
      end associate
    end subroutine library_fill

    !> The entry's text for `key`, else `def`.
    function lib_text(key, def) result(text)
      character(len=*), intent(in) :: key, def
      character(len=:), allocatable :: text
      text = ''
      if (len_trim(library) > 0) text = library_text(trim(library), key)
      if (len(text) == 0) text = def
      text = trim(text)
    end function lib_text

    !> A variable the group did not give: the entry's (in the deck's units)
    !> if `applies`, else the default `def`.
    subroutine fill(v, key, def, applies)
      real(wp), intent(inout) :: v
      character(len=*), intent(in) :: key
      real(wp), intent(in) :: def
      logical, intent(in) :: applies
      logical :: found
      real(wp) :: lv
      if (v > unset) return
      v = def
      if (.not. applies .or. len_trim(library) == 0) return
      call library_value(trim(library), key, units, lv, found)
      if (found) v = lv
    end subroutine fill

    !> strength = 'johnson_cook': its parameters (PARTICLES.md §2.3).
    subroutine johnson_cook_check()
      character(len=*), parameter :: for = ' for strength = ''johnson_cook'''
      if (.not. (jc_a > 0.0_wp)) call problem_bad(problems, tag, 'jc_a', jc_a, 'must be > 0'//for)
      if (.not. (jc_b >= 0.0_wp)) call problem_bad(problems, tag, 'jc_b', jc_b, 'must be >= 0'//for)
      if (.not. (jc_n > 0.0_wp)) call problem_bad(problems, tag, 'jc_n', jc_n, 'must be > 0'//for)
      if (.not. (jc_c >= 0.0_wp)) call problem_bad(problems, tag, 'jc_c', jc_c, 'must be >= 0'//for)
      if (.not. (jc_eps0 > 0.0_wp)) call problem_bad(problems, tag, 'jc_eps0', jc_eps0, &
        'must be > 0'//for//' (the reference strain rate, 1/time)')
      if (.not. (jc_m >= 0.0_wp)) call problem_bad(problems, tag, 'jc_m', jc_m, 'must be >= 0'//for// &
        ' (0: no thermal softening)')
      if (.not. (abs(t_room) < huge(1.0_wp))) call problem_bad(problems, tag, 't_room', t_room, 'must be finite')
      if (jc_m > 0.0_wp .and. .not. (t_melt > t_room)) call problem_bad(problems, tag, 't_melt', t_melt, &
        'must be above t_room = '//rtoa(t_room)//' with thermal softening (jc_m > 0)')
      if (.not. (specific_heat >= 0.0_wp)) call problem_bad(problems, tag, 'specific_heat', specific_heat, &
        'must be >= 0'//for//' (0: no plastic heating)')
      if (.not. (taylor_quinney >= 0.0_wp .and. taylor_quinney <= 1.0_wp)) call problem_bad(problems, tag, &
        'taylor_quinney', taylor_quinney, 'must be in [0, 1]')
    end subroutine johnson_cook_check

    !> The Johnson-Cook parameters given to a model that has none.
    subroutine johnson_cook_unused()
      character(len=:), allocatable :: why
      why = 'applies only to strength = ''johnson_cook'' (this solid''s is '''//trim(strength)//''')'
      if (abs(jc_a) > 0.0_wp) call problem_bad(problems, tag, 'jc_a', jc_a, why)
      if (abs(jc_b) > 0.0_wp) call problem_bad(problems, tag, 'jc_b', jc_b, why)
      if (abs(jc_c) > 0.0_wp) call problem_bad(problems, tag, 'jc_c', jc_c, why)
      if (abs(jc_m) > 0.0_wp) call problem_bad(problems, tag, 'jc_m', jc_m, why)
      if (abs(specific_heat) > 0.0_wp) call problem_bad(problems, tag, 'specific_heat', specific_heat, why)
    end subroutine johnson_cook_unused
  end subroutine solid_config_read

  !> The problems of a gurson solid's parameters (PARTICLES.md 2.4; Table 5's
  !> f_F = 0.0021 < f0 is refused here: input/README.md).
  subroutine gurson_problems(problems, tag, jc_a, jc_b, jc_n, jc_c, jc_eps0, q1, q2, fn, epsn, sn, fc, ff, &
                             failure_strain, void_mean, void_std, void_length, void_seed, void_covariance, &
                             void_distribution)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), intent(in) :: tag, void_covariance, void_distribution
    real(wp), intent(in) :: jc_a, jc_b, jc_n, jc_c, jc_eps0, q1, q2, fn, epsn, sn, fc, ff, failure_strain, &
                            void_mean, void_std, void_length
    integer, intent(in) :: void_seed
    if (.not. (jc_a > 0.0_wp)) call problem_bad(problems, tag, 'jc_a', jc_a, 'must be > 0 for strength = ''gurson''')
    if (.not. (jc_b >= 0.0_wp)) call problem_bad(problems, tag, 'jc_b', jc_b, 'must be >= 0')
    if (.not. (jc_n > 0.0_wp)) call problem_bad(problems, tag, 'jc_n', jc_n, 'must be > 0')
    if (.not. (jc_c >= 0.0_wp)) call problem_bad(problems, tag, 'jc_c', jc_c, 'must be >= 0')
    if (.not. (jc_eps0 > 0.0_wp)) call problem_bad(problems, tag, 'jc_eps0', jc_eps0, 'must be > 0')
    if (.not. (q1 > 0.0_wp)) call problem_bad(problems, tag, 'gtn_q1', q1, 'must be > 0')
    if (.not. (q2 > 0.0_wp)) call problem_bad(problems, tag, 'gtn_q2', q2, 'must be > 0')
    if (.not. (fn >= 0.0_wp .and. fn < 1.0_wp)) call problem_bad(problems, tag, 'gtn_fn', fn, 'must be in [0, 1)')
    if (.not. (epsn >= 0.0_wp)) call problem_bad(problems, tag, 'gtn_epsn', epsn, 'must be >= 0')
    if (.not. (sn > 0.0_wp)) call problem_bad(problems, tag, 'gtn_sn', sn, 'must be > 0')
    if (.not. (fc > 0.0_wp .and. fc < 1.0_wp)) call problem_bad(problems, tag, 'gtn_fc', fc, 'must be in (0, 1)')
    if (.not. (ff > fc .and. ff <= 1.0_wp)) call problem_bad(problems, tag, 'gtn_ff', ff, &
      'must be in (gtn_fc, 1] (gtn_fc = '//rtoa(fc)//'; Table 5''s 0.0021 is a misprint: input/README.md)')
    if (.not. (failure_strain >= 0.0_wp)) call problem_bad(problems, tag, 'failure_strain', failure_strain, &
      'must be >= 0 (0: no strain term in TEPLA-F)')
    if (.not. (void_mean >= 0.0_wp .and. void_mean < fc)) call problem_bad(problems, tag, 'void_mean', void_mean, &
      'must be in [0, gtn_fc) (gtn_fc = '//rtoa(fc)//': at f0 >= f_c TEPLA-F fails every particle at once)')
    if (.not. (void_std >= 0.0_wp)) call problem_bad(problems, tag, 'void_std', void_std, 'must be >= 0')
    if (void_std > 0.0_wp .and. .not. void_mean > 0.0_wp) call problem_bad(problems, tag, 'void_std', void_std, &
      'needs void_mean > 0 (a random f0 about its mean)')
    if (.not. (void_length >= 0.0_wp)) call problem_bad(problems, tag, 'void_length', void_length, &
      'must be >= 0 (0: uncorrelated f0)')
    if (void_seed < 0) call problem_badi(problems, tag, 'void_seed', void_seed, 'must be >= 0')
    if (.not. any(random_field_covariances == void_covariance)) call problem_add(problems, '&'//tag// &
      ': void_covariance = '''//trim(void_covariance)//''' is not known; valid: '//name_list(random_field_covariances))
    if (.not. any(void_fraction_distributions == void_distribution)) call problem_add(problems, '&'//tag// &
      ': void_distribution = '''//trim(void_distribution)//''' is not known; valid: '// &
      name_list(void_fraction_distributions))
  end subroutine gurson_problems

  !> strength = 'hjc' (strength_hjc): its own pressure (eos = 'none', no
  !> bulk_modulus), each hjc_* in its range, then what the model checks
  !> when it is built (the region III polynomial reaching hjc_plock, the
  !> crushing slope); g and rho0 the solid's.
  subroutine hjc_check(problems, tag, eos, bulk_modulus, hp, g, rho0)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), intent(in) :: tag, eos
    real(wp), intent(in) :: bulk_modulus, g, rho0
    type(strength_params_t), intent(in) :: hp
    class(strength_t), allocatable :: trial
    type(error_t), allocatable :: err
    type(strength_params_t) :: par
    integer :: i, nbad
    real(wp) :: v(18)
    character(len=11), parameter :: names(18) = [character(len=11) :: 'hjc_fc', 'hjc_t', 'hjc_pcrush', &
      'hjc_mucrush', 'hjc_plock', 'hjc_k1', 'hjc_n', 'hjc_smax', 'hjc_efmin', 'hjc_d2', 'hjc_eps0', &
      'hjc_a', 'hjc_b', 'hjc_c', 'hjc_d1', 'hjc_mulock', 'hjc_k3', 'hjc_length']
    if (trim(eos) /= 'none') call problem_add(problems, '&'//tag//': eos = '''//trim(eos)//''' cannot be used '// &
      'with strength = ''hjc'' (the HJC model has its own equation of state): eos = ''none''')
    if (abs(bulk_modulus) > 0.0_wp) call problem_bad(problems, tag, 'bulk_modulus', bulk_modulus, &
      'does not apply to strength = ''hjc'' (its pressure comes from its own equation of state, hjc_*)')
    v = [hp%hjc_fc, hp%hjc_t, hp%hjc_pcrush, hp%hjc_mucrush, hp%hjc_plock, hp%hjc_k1, hp%hjc_n, hp%hjc_smax, &
         hp%hjc_efmin, hp%hjc_d2, hp%hjc_eps0, hp%hjc_a, hp%hjc_b, hp%hjc_c, hp%hjc_d1, hp%hjc_mulock, hp%hjc_k3, &
         hp%hjc_length]
    nbad = 0
    do i = 1, 11
      if (.not. (v(i) > 0.0_wp)) then
        call problem_bad(problems, tag, trim(names(i)), v(i), 'must be > 0 for strength = ''hjc''')
        nbad = nbad + 1
      end if
    end do
    do i = 12, 18
      if (.not. (v(i) >= 0.0_wp)) then
        call problem_bad(problems, tag, trim(names(i)), v(i), 'must be >= 0 for strength = ''hjc''')
        nbad = nbad + 1
      end if
    end do
    if (.not. (hp%hjc_plock > hp%hjc_pcrush)) then
      call problem_bad(problems, tag, 'hjc_plock', hp%hjc_plock, 'must be > hjc_pcrush')
      nbad = nbad + 1
    end if
    if (nbad > 0 .or. .not. (g > 0.0_wp .and. rho0 > 0.0_wp)) return
    par = hp
    par%g = g
    par%hjc_rho0 = rho0
    call strength_create('hjc', par, trial, err)
    if (allocated(err)) call problem_add(problems, '&'//tag//': '//err%msg)
  end subroutine hjc_check

  !> The hjc_* variables given to a solid whose strength is not 'hjc'.
  subroutine hjc_not_here(problems, tag, strength, hp)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), intent(in) :: tag, strength
    type(strength_params_t), intent(in) :: hp
    type(strength_params_t) :: d
    if (any(abs(hjc_values(hp) - hjc_values(d)) > 0.0_wp)) &
      call problem_add(problems, '&'//tag//': the hjc_* variables apply only to strength = ''hjc'' (this solid''s '// &
                       'is '''//trim(strength)//''')')
  end subroutine hjc_not_here

  !> Reads, validates and echoes the k-th &particles group (`text`);
  !> `solids` are the &solid names, `xmin`, `xmax` the grid's box (a shape
  !> must reach into it); the point file is resolved against the deck's
  !> folder (`file_path`).
  subroutine particles_config_read(this, k, text, path, solids, xmin, xmax, echo, problems)
    type(particles_config_t), intent(out) :: this
    integer, intent(in) :: k, echo
    character(len=*), intent(in) :: text(:), path, solids(:)
    real(wp), intent(in) :: xmin(3), xmax(3)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=16) :: shape, velocity_field
    character(len=64) :: solid
    character(len=256) :: file
    character(len=1) :: axis
    real(wp) :: lo(3), hi(3), center(3), radius, density, velocity(3), angular_velocity, stress(6), blo(3), bhi(3), &
                inner_radius, point(3), point2(3), area, scale, offset(3)
    integer :: per_cell, body, ios, m, ax
    character(len=max_line) :: msg
    character(len=:), allocatable :: tag
    namelist /particles/ shape, lo, hi, center, radius, axis, file, per_cell, solid, density, velocity, &
                         velocity_field, angular_velocity, stress, body, inner_radius, point, point2, area, &
                         scale, offset

    shape = this%shape; lo = this%lo; hi = this%hi; center = this%center; radius = this%radius
    axis = 'xyz'(this%axis:this%axis); file = this%file; per_cell = this%per_cell; solid = this%solid
    density = this%density; velocity = this%velocity; velocity_field = this%velocity_field
    angular_velocity = this%angular_velocity; stress = this%stress; body = this%body
    inner_radius = this%inner_radius; point = this%point; point2 = this%point2; area = this%area
    scale = this%scale; offset = this%offset
    read(text, nml=particles, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_nml(problems, path, 'particles', ios, msg)
      return
    end if
    tag = 'particles('//itoa(k)//')'
    call problem_long(problems, tag, 'shape', shape)
    call problem_long(problems, tag, 'solid', solid)
    call problem_long(problems, tag, 'file', file)
    call problem_long(problems, tag, 'velocity_field', velocity_field)
    ax = max(1, index('xyz', axis))
    if (index('xyz', axis) == 0 .or. len_trim(axis) == 0) call problem_add(problems, &
      '&'//tag//': axis = '''//trim(axis)//''' is not known; valid: x, y, z')
    ! the shape, its parameters, and that it reaches into the grid's box
    blo = xmin
    bhi = xmax
    select case (trim(shape))
    case ('all')
    case ('box')
      if (.not. (all(abs(lo) < huge(1.0_wp)) .and. all(abs(hi) < huge(1.0_wp)))) then
        call problem_add(problems, '&'//tag//': shape = ''box'' needs lo and hi (all three components)')
      else if (.not. all(hi > lo)) then
        call problem_add(problems, '&'//tag//': shape = ''box'' needs hi > lo in every component')
      else
        blo = lo
        bhi = hi
      end if
    case ('sphere', 'cylinder')
      if (.not. (radius > 0.0_wp)) then
        call problem_bad(problems, tag, 'radius', radius, 'must be > 0 for shape = '''//trim(shape)//'''')
      else
        blo = center - radius
        bhi = center + radius
      end if
      if (trim(shape) == 'cylinder') then
        if (.not. (abs(lo(ax)) < huge(1.0_wp) .and. abs(hi(ax)) < huge(1.0_wp) .and. hi(ax) > lo(ax))) then
          call problem_add(problems, '&'//tag//': shape = ''cylinder'' needs lo < hi along its axis '''// &
                           axis//''' (its ends)')
        else
          blo(ax) = lo(ax)
          bhi(ax) = hi(ax)
        end if
      end if
    case ('file')
      if (len_trim(file) == 0) call problem_add(problems, '&'//tag//': shape = ''file'' needs a file of points')
    case ('stl')
      if (len_trim(file) == 0) call problem_add(problems, '&'//tag//': shape = ''stl'' needs a surface file')
    case ('line')
      if (.not. (all(abs(point) < huge(1.0_wp)) .and. all(abs(point2) < huge(1.0_wp)))) then
        call problem_add(problems, '&'//tag//': shape = ''line'' needs point and point2 (its ends, all three '// &
                         'components)')
      else if (.not. norm2(point2 - point) > 0.0_wp) then
        call problem_add(problems, '&'//tag//': shape = ''line'' needs point2 /= point (a segment of some length)')
      else if (any(min(point, point2) < xmin) .or. any(max(point, point2) > xmax)) then
        call problem_add(problems, '&'//tag//': the line''s ends must lie in the grid box xmin..xmax')
      else
        blo = min(point, point2)
        bhi = max(point, point2)
      end if
      if (.not. area > 0.0_wp) call problem_bad(problems, tag, 'area', area, &
        'must be > 0 for shape = ''line'' (the cross-section of the bar, length^2)')
    case ('')
      call problem_add(problems, '&'//tag//': shape is required; valid: box, sphere, cylinder, all, file, line, stl')
    case default
      call problem_add(problems, '&'//tag//': shape = '''//trim(shape)// &
                       ''' is not known; valid: box, sphere, cylinder, all, file, line, stl')
    end select
    if (trim(shape) /= 'line' .and. (any(abs(point) < huge(1.0_wp)) .or. any(abs(point2) < huge(1.0_wp)) .or. &
        abs(area) > 0.0_wp)) call problem_add(problems, '&'//tag//': point, point2 and area apply only to '// &
        'shape = ''line'' (this group''s is '''//trim(shape)//''')')
    if (.not. (scale > 0.0_wp .and. scale < huge(1.0_wp))) call problem_bad(problems, tag, 'scale', scale, &
      'must be > 0')
    if ((abs(scale - 1.0_wp) > 0.0_wp .or. any(abs(offset) > 0.0_wp)) .and. trim(shape) /= 'file' .and. &
        trim(shape) /= 'stl') call problem_add(problems, '&'//tag//': scale and offset apply only to shape = '// &
        '''file'' or ''stl'' (this group''s is '''//trim(shape)//''')')
    msg = shape_inner_radius_problem(shape, radius, inner_radius)
    if (len_trim(msg) > 0) call problem_bad(problems, tag, 'inner_radius', inner_radius, trim(msg))
    if (len_trim(file) > 0 .and. trim(shape) /= 'file' .and. trim(shape) /= 'stl') call problem_add(problems, &
      '&'//tag//': file applies only to shape = ''file'' or ''stl'' (this group''s is '''//trim(shape)//''')')
    if (any(bhi < xmin) .or. any(blo > xmax)) call problem_add(problems, '&'//tag//': the '//trim(shape)// &
      ' lies outside the grid box xmin..xmax: it would seed no particle')
    if (per_cell < 1 .or. per_cell > max_per_cell) call problem_badi(problems, tag, 'per_cell', per_cell, &
      'must be in 1..'//itoa(max_per_cell))
    if (.not. (density >= 0.0_wp)) call problem_bad(problems, tag, 'density', density, &
      'must be >= 0 (0: the solid''s density)')
    if (body < 0) call problem_badi(problems, tag, 'body', body, 'must be >= 0 (0: the group''s number)')
    select case (trim(velocity_field))
    case ('uniform')
      if (abs(angular_velocity) > 0.0_wp) call problem_bad(problems, tag, 'angular_velocity', angular_velocity, &
        'applies only to velocity_field = ''rotation'' (this group''s is ''uniform'')')
    case ('rotation')
      if (.not. abs(angular_velocity) > 0.0_wp) call problem_add(problems, '&'//tag// &
        ': velocity_field = ''rotation'' needs an angular_velocity (not 0; radians per unit time)')
    case default
      call problem_add(problems, '&'//tag//': velocity_field = '''//trim(velocity_field)// &
                       ''' is not known; valid: uniform, rotation')
    end select
    m = name_index(solids, solid)
    if (m == 0 .and. len_trim(solid) == 0 .and. size(solids) == 1) m = 1
    if (size(solids) == 0) then
      call problem_add(problems, '&'//tag//': there is no &solid group (particles need a solid material)')
    else if (m == 0) then
      call problem_add(problems, '&'//tag//': solid = '''//trim(solid)//''' is not a &solid name; valid: '// &
                       name_list(solids))
    end if
    this = particles_config_t(shape=shape, lo=lo, hi=hi, center=center, radius=radius, inner_radius=inner_radius, &
      axis=ax, file=file, point=point, point2=point2, area=area, scale=scale, offset=offset, &
      per_cell=per_cell, solid=solid, isolid=m, density=density, velocity=velocity, velocity_field=velocity_field, &
      angular_velocity=angular_velocity, stress=stress, body=merge(body, k, body > 0))
    this%file_path = resolve_path(file, path)
    if (echo /= no_echo) write(echo, nml=particles)
  end subroutine particles_config_read

  !> Points x(3, n) read from a group's file (shape = 'file' or 'stl') in
  !> the deck's frame: scale x + offset.
  pure subroutine particles_file_place(pc, x)
    type(particles_config_t), intent(in) :: pc
    real(wp), intent(inout) :: x(:, :)
    integer :: i
    do i = 1, size(x, 2)
      x(:, i) = pc%scale*x(:, i) + pc%offset
    end do
  end subroutine particles_file_place

  !> The hjc_* values of p, in the namelist's order.
  pure function hjc_values(p) result(v)
    type(strength_params_t), intent(in) :: p
    real(wp) :: v(19)
    v = [p%hjc_a, p%hjc_b, p%hjc_n, p%hjc_c, p%hjc_fc, p%hjc_smax, p%hjc_t, p%hjc_d1, p%hjc_d2, p%hjc_efmin, &
         p%hjc_pcrush, p%hjc_mucrush, p%hjc_plock, p%hjc_mulock, p%hjc_k1, p%hjc_k2, p%hjc_k3, p%hjc_eps0, p%hjc_length]
  end function hjc_values

  !> What a restart may not change in the solids and particles: one line per
  !> changed variable.
  subroutine particles_config_changes(old_solids, new_solids, old_groups, new_groups, changes)
    type(solid_config_t), intent(in) :: old_solids(:), new_solids(:)
    type(particles_config_t), intent(in) :: old_groups(:), new_groups(:)
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    character(len=24) :: w
    integer :: k
    call diff_i(changes, 'number of &solid groups', size(old_solids), size(new_solids))
    do k = 1, min(size(old_solids), size(new_solids))
      associate (a => old_solids(k), b => new_solids(k))
        w = '&solid('//itoa(k)//')'
        call diff_s(changes, trim(w)//' name', a%name, b%name)
        call diff_r(changes, trim(w)//' density', [a%density], [b%density])
        call diff_s(changes, trim(w)//' eos', a%eos, b%eos)
        call diff_s(changes, trim(w)//' library', a%library, b%library)
        call diff_r(changes, trim(w)//' eos parameters', [a%par%gamma, a%par%a, a%par%b, a%par%r1, a%par%r2, &
                    a%par%omega, a%par%rho0, a%par%c0, a%par%s1, a%par%gamma0], [b%par%gamma, b%par%a, b%par%b, &
                    b%par%r1, b%par%r2, b%par%omega, b%par%rho0, b%par%c0, b%par%s1, b%par%gamma0])
        call diff_r(changes, trim(w)//' bulk_modulus, shear_modulus', [a%bulk_modulus, a%shear_modulus], &
                    [b%bulk_modulus, b%shear_modulus])
        call diff_s(changes, trim(w)//' strength', a%strength, b%strength)
        call diff_r(changes, trim(w)//' yield_stress, tangent_modulus', [a%yield_stress, a%tangent_modulus], &
                    [b%yield_stress, b%tangent_modulus])
        call diff_r(changes, trim(w)//' jc_a, jc_b, jc_n, jc_c, jc_eps0, jc_m', [a%jc_a, a%jc_b, a%jc_n, a%jc_c, &
                    a%jc_eps0, a%jc_m], [b%jc_a, b%jc_b, b%jc_n, b%jc_c, b%jc_eps0, b%jc_m])
        call diff_r(changes, trim(w)//' t_room, t_melt, specific_heat, taylor_quinney', [a%t_room, a%t_melt, &
                    a%specific_heat, a%taylor_quinney], [b%t_room, b%t_melt, b%specific_heat, b%taylor_quinney])
        call diff_r(changes, trim(w)//' gurson parameters', [a%gtn_q1, a%gtn_q2, a%gtn_fn, a%gtn_epsn, a%gtn_sn, &
                    a%gtn_fc, a%gtn_ff, a%failure_strain, a%void_mean, a%void_std], [b%gtn_q1, b%gtn_q2, b%gtn_fn, &
                    b%gtn_epsn, b%gtn_sn, b%gtn_fc, b%gtn_ff, b%failure_strain, b%void_mean, b%void_std])
        call diff_r(changes, trim(w)//' void_length', [a%void_length], [b%void_length])
        call diff_r(changes, trim(w)//' tensile_strength', [a%tensile_strength], [b%tensile_strength])
        call diff_i(changes, trim(w)//' void_seed', a%void_seed, b%void_seed)
        call diff_s(changes, trim(w)//' void_covariance', a%void_covariance, b%void_covariance)
        call diff_s(changes, trim(w)//' void_distribution', a%void_distribution, b%void_distribution)
        call diff_r(changes, trim(w)//' hjc_*', hjc_values(a%hjc), hjc_values(b%hjc))
      end associate
    end do
    call diff_i(changes, 'number of &particles groups', size(old_groups), size(new_groups))
    do k = 1, min(size(old_groups), size(new_groups))
      associate (a => old_groups(k), b => new_groups(k))
        w = '&particles('//itoa(k)//')'
        call diff_s(changes, trim(w)//' shape', a%shape, b%shape)
        call diff_r(changes, trim(w)//' lo', a%lo, b%lo)
        call diff_r(changes, trim(w)//' hi', a%hi, b%hi)
        call diff_r(changes, trim(w)//' center', a%center, b%center)
        call diff_r(changes, trim(w)//' radius', [a%radius], [b%radius])
        call diff_r(changes, trim(w)//' inner_radius', [a%inner_radius], [b%inner_radius])
        call diff_i(changes, trim(w)//' axis', a%axis, b%axis)
        call diff_s(changes, trim(w)//' file', a%file, b%file)
        call diff_r(changes, trim(w)//' point, point2, area', [a%point, a%point2, a%area], [b%point, b%point2, b%area])
        call diff_r(changes, trim(w)//' scale, offset', [a%scale, a%offset], [b%scale, b%offset])
        call diff_i(changes, trim(w)//' per_cell', a%per_cell, b%per_cell)
        call diff_s(changes, trim(w)//' solid', a%solid, b%solid)
        call diff_r(changes, trim(w)//' density', [a%density], [b%density])
        call diff_r(changes, trim(w)//' velocity', a%velocity, b%velocity)
        call diff_s(changes, trim(w)//' velocity_field', a%velocity_field, b%velocity_field)
        call diff_r(changes, trim(w)//' angular_velocity', [a%angular_velocity], [b%angular_velocity])
        call diff_r(changes, trim(w)//' stress', a%stress, b%stress)
        call diff_i(changes, trim(w)//' body', a%body, b%body)
      end associate
    end do
  end subroutine particles_config_changes

  !> "a, b, c" of a list of names.
  pure function name_list(names) result(s)
    character(len=*), intent(in) :: names(:)
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, size(names)
      if (k > 1) s = s//', '
      s = s//trim(names(k))
    end do
    if (size(names) == 0) s = '(none)'
  end function name_list
end module particles_config
