!> The &material group (one per material): its name, its equation of state
!> and the EOS parameters (validated by the EOS factory), and cut-offs.
module material_config
  use base_kinds, only: wp
  use base_errors, only: error_t
  use base_strings, only: itoa
  use base_config, only: max_line, no_echo, problem_long, problem_add, problem_bad, problem_nml, diff_r, diff_s
  use eos_base, only: eos_t
  use eos_factory, only: eos_params_t, eos_create
  use material_library, only: units_known, units_list, library_names, library_has, library_value, library_text
  implicit none
  private
  public :: material_config_t, material_config_read, material_config_changes

  !> One resolved &material group; the initial values are the defaults (the
  !> EOS parameters' are in `eos_params_t`).
  type :: material_config_t
    character(len=64) :: name = ''                 !< '' becomes 'material<N>'
    character(len=64) :: eos = 'ideal_gas'         !< an `eos_factory` name
    character(len=64) :: library = ''              !< a `material_library` entry ('' none)
    type(eos_params_t) :: par                      !< EOS parameters
    real(wp) :: p_min = -huge(1.0_wp)              !< pressure floor (pressure)
    real(wp) :: rho_min = 0.0_wp                   !< void density (density)
    !> jwl lit by &detonation: the detonation velocity (velocity; 0: the CJ
    !> velocity of its JWL from the unreacted state, `material_burn`)
    real(wp) :: detonation_velocity = 0.0_wp
    real(wp) :: burn_width = 1.5_wp                !< burn time in cell widths across the front
  end type material_config_t

contains

  !> Reads, validates and echoes the m-th &material group (`text`); `earlier`
  !> are the names of the groups before it (names must be unique); `units`
  !> the deck's &run units, to which a `library` entry's values convert.
  !> Variables the group does not give come from its library entry, if it
  !> names one, else from the defaults.
  subroutine material_config_read(this, m, text, path, earlier, units, echo, problems)
    type(material_config_t), intent(out) :: this
    integer, intent(in) :: m, echo
    character(len=*), intent(in) :: text(:), path, earlier(:), units
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=64) :: name, eos, library
    real(wp) :: gamma, a, b, r1, r2, omega, rho0, c0, s1, gamma0, p_min, rho_min, detonation_velocity, burn_width
    integer :: ios
    character(len=max_line) :: msg
    class(eos_t), allocatable :: trial
    type(error_t), allocatable :: err
    real(wp), parameter :: unset = -huge(1.0_wp)
    namelist /material/ name, eos, library, gamma, a, b, r1, r2, omega, rho0, c0, s1, gamma0, p_min, rho_min, &
                        detonation_velocity, burn_width

    ! (the EOS and its parameters unset, so that a library entry can fill them)
    name = this%name; eos = ''; library = this%library; p_min = this%p_min; rho_min = this%rho_min
    detonation_velocity = this%detonation_velocity; burn_width = this%burn_width
    gamma = unset; a = unset; b = unset; r1 = unset; r2 = unset
    omega = unset; rho0 = unset; c0 = unset; s1 = unset; gamma0 = unset
    read(text, nml=material, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_nml(problems, path, 'material', ios, msg)
      return
    end if
    call problem_long(problems, 'material', 'name', name)
    call problem_long(problems, 'material', 'eos', eos)
    call problem_long(problems, 'material', 'library', library)
    if (len_trim(name) == 0) name = 'material'//itoa(m)
    if (any(earlier == name)) call problem_add(problems, &
      '&material: name = '''//trim(name)//''' is used twice; names must be unique')
    if (len_trim(library) > 0) then
      if (.not. library_has(trim(library))) then
        call problem_add(problems, '&material '''//trim(name)//''': library = '''//trim(library)// &
                         ''' is not in the material library (input/materials.txt): '//library_names())
        library = ''
      else if (.not. units_known(units)) then
        call problem_add(problems, '&material '''//trim(name)//''': library = '''//trim(library)// &
                         ''' needs the deck''s unit system, &run units, one of: '//units_list())
        library = ''
      else if (len_trim(eos) == 0) then
        eos = library_text(trim(library), 'eos')
      end if
    end if
    if (len_trim(eos) == 0) eos = this%eos
    ! a parameter the group gives must be one of its EOS's (or its default:
    ! the resolved deck that --check prints and the dumps store gives them all)
    call not_of(gamma, 'gamma', 'ideal_gas', this%par%gamma)
    call not_of(a, 'a', 'jwl', this%par%a)
    call not_of(b, 'b', 'jwl', this%par%b)
    call not_of(r1, 'r1', 'jwl', this%par%r1)
    call not_of(r2, 'r2', 'jwl', this%par%r2)
    call not_of(omega, 'omega', 'jwl', this%par%omega)
    call not_of(rho0, 'rho0', 'jwl mie_gruneisen', this%par%rho0)
    call not_of(c0, 'c0', 'mie_gruneisen', this%par%c0)
    call not_of(s1, 's1', 'mie_gruneisen', this%par%s1)
    call not_of(gamma0, 'gamma0', 'mie_gruneisen', this%par%gamma0)
    call fill(gamma, 'gamma', this%par%gamma)
    call fill(a, 'a', this%par%a)
    call fill(b, 'b', this%par%b)
    call fill(r1, 'r1', this%par%r1)
    call fill(r2, 'r2', this%par%r2)
    call fill(omega, 'omega', this%par%omega)
    call fill(rho0, 'rho0', this%par%rho0)
    call fill(c0, 'c0', this%par%c0)
    call fill(s1, 's1', this%par%s1)
    call fill(gamma0, 'gamma0', this%par%gamma0)
    call fill(p_min, 'p_min', this%p_min)
    this%name = name
    this%eos = eos
    this%library = library
    this%par = eos_params_t(gamma=gamma, a=a, b=b, r1=r1, r2=r2, omega=omega, &
                            rho0=rho0, c0=c0, s1=s1, gamma0=gamma0)
    this%p_min = p_min
    this%rho_min = rho_min
    if (rho_min < 0.0_wp) call problem_bad(problems, 'material '''//trim(name)//'''', 'rho_min', rho_min, &
                                           'must be >= 0')
    this%detonation_velocity = detonation_velocity
    this%burn_width = burn_width
    if (.not. detonation_velocity >= 0.0_wp) call problem_bad(problems, 'material '''//trim(name)//'''', &
      'detonation_velocity', detonation_velocity, 'must be >= 0 (0: the CJ velocity of the JWL)')
    if (.not. (burn_width > 0.0_wp .and. burn_width <= 100.0_wp)) call problem_bad(problems, &
      'material '''//trim(name)//'''', 'burn_width', burn_width, 'must be > 0 and <= 100 (cell widths)')
    if (detonation_velocity > 0.0_wp .and. eos /= 'jwl') call problem_add(problems, '&material '''//trim(name)// &
      ''': detonation_velocity is for eos = ''jwl'' (an explosive''s products)')
    ! the factory validates the model name and its parameters
    call eos_create(eos, this%par, trial, err)
    if (allocated(err)) call problem_add(problems, '&material '''//trim(name)//''': '//err%msg)
    if (echo /= no_echo) write(echo, nml=material)

  contains

    !> A problem if the group gives v (key) other than its default def and
    !> eos is none of the (space-separated) models that use it.
    subroutine not_of(v, key, models, def)
      real(wp), intent(in) :: v, def
      character(len=*), intent(in) :: key, models
      if (.not. v > unset .or. .not. abs(v - def) > 0.0_wp) return
      if (index(' '//models//' ', ' '//trim(eos)//' ') > 0) return
      call problem_add(problems, '&material '''//trim(name)//''': '//key//' is a parameter of eos = '''// &
                       replace_spaces(trim(models))//''', not of eos = '''//trim(eos)//'''')
    end subroutine not_of

    !> models with each space written as ''' or ''' (a list of names).
    pure function replace_spaces(models) result(t)
      character(len=*), intent(in) :: models
      character(len=:), allocatable :: t
      integer :: i
      t = ''
      do i = 1, len(models)
        if (models(i:i) == ' ') then
          t = t//''' or '''
        else
          t = t//models(i:i)
        end if
      end do
    end function replace_spaces

    !> A variable the group did not give: the library entry's (in the
    !> deck's units), else the default `def`.
    subroutine fill(v, key, def)
      real(wp), intent(inout) :: v
      character(len=*), intent(in) :: key
      real(wp), intent(in) :: def
      logical :: found
      real(wp) :: lv
      if (v > unset) return
      v = def
      if (len_trim(library) == 0) return
      call library_value(trim(library), key, units, lv, found)
      if (found) v = lv
    end subroutine fill
  end subroutine material_config_read

  !> What a restart may not change in the k-th &material: one line per change.
  subroutine material_config_changes(k, a, b, changes)
    integer, intent(in) :: k
    type(material_config_t), intent(in) :: a, b
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    character(len=:), allocatable :: what
    call diff_s(changes, '&material('//itoa(k)//') name', a%name, b%name)
    what = '&material '''//trim(a%name)//''''
    call diff_s(changes, what//' eos', a%eos, b%eos)
    call diff_s(changes, what//' library', a%library, b%library)
    call diff_r(changes, what//' gamma', [a%par%gamma], [b%par%gamma])
    call diff_r(changes, what//' jwl a, b, r1, r2, omega', [a%par%a, a%par%b, a%par%r1, a%par%r2, a%par%omega], &
                [b%par%a, b%par%b, b%par%r1, b%par%r2, b%par%omega])
    call diff_r(changes, what//' rho0, c0, s1, gamma0', [a%par%rho0, a%par%c0, a%par%s1, a%par%gamma0], &
                [b%par%rho0, b%par%c0, b%par%s1, b%par%gamma0])
    call diff_r(changes, what//' p_min, rho_min', [a%p_min, a%rho_min], [b%p_min, b%rho_min])
    call diff_r(changes, what//' detonation_velocity, burn_width', [a%detonation_velocity, a%burn_width], &
                [b%detonation_velocity, b%burn_width])
  end subroutine material_config_changes
end module material_config
