!> The strength factory: the names of the models a deck may choose
!> (`strength_names`), each model built from its name and the parameters
!> (`strength_create`), and the history size of a model by name
!> (`strength_nhist`). A new model: its own module extending
!> `strength_models::strength_t`, its parameters in `strength_params_t`, a
!> case here and its name in `strength_names`.
module strength_factory
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set, ERR_INPUT
  use strength_models, only: strength_t, strength_elastic_t, strength_bilinear_t, strength_params_t
  use strength_jc_flow, only: jc_flow_t
  use strength_johnson_cook, only: strength_johnson_cook_t
  use strength_gurson, only: strength_gurson_t
  use strength_hjc, only: strength_hjc_t, hjc_new, hjc_nhist
  implicit none
  private
  public :: strength_create, strength_names, strength_nhist

  !> The names the factory knows.
  character(len=*), parameter :: strength_names(5) = [character(len=12) :: 'elastic', 'bilinear', 'johnson_cook', &
                                                                      'gurson', 'hjc']

contains

  !> The model `name` with the parameters par (module notes).
  !> eos_pressure (default false): the pressure comes from an EOS, the
  !> model's own k is 0 and par%k serves only Young's modulus
  !> E = 9kg/(3k + g) of the hardening modulus (module notes).
  subroutine strength_create(name, par, model, err, eos_pressure)
    character(len=*), intent(in) :: name
    type(strength_params_t), intent(in) :: par
    class(strength_t), allocatable, intent(out) :: model
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: eos_pressure
    real(wp) :: e
    type(strength_hjc_t) :: hjc
    character(len=:), allocatable :: msg
    select case (trim(name))
    case ('elastic')
      model = strength_elastic_t(k=par%k, g=par%g)
    case ('bilinear')
      e = 9.0_wp*par%k*par%g/(3.0_wp*par%k + par%g)
      model = strength_bilinear_t(k=par%k, g=par%g, y0=par%y0, h=e*par%et/(e - par%et), ef=par%failure_strain, &
                                  st=par%tensile_strength)
    case ('johnson_cook')
      model = strength_johnson_cook_t(k=par%k, g=par%g, chi=par%jc_chi, cp=par%jc_cp, jc=par%jc)
    case ('gurson')
      model = strength_gurson_t(k=par%k, g=par%g, jc=par%jc, q1=par%gurson_q1, q2=par%gurson_q2, fn=par%gurson_fn, &
                                epsn=par%gurson_epsn, sn=par%gurson_sn, fc=par%gurson_fc, ff=par%gurson_ff, &
                                eps_f=par%failure_strain, f0=par%gurson_f0, kv=par%k)
    case ('hjc')
      ! the model owns its pressure (strength_hjc): no EOS
      if (present(eos_pressure)) then
        if (eos_pressure) then
          call error_set(err, 'strength_create', 'strength = ''hjc'' has its own equation of state: eos = ''none''', &
                         ERR_INPUT)
          return
        end if
      end if
      call hjc_new(par, hjc, msg)
      if (len(msg) > 0) then
        call error_set(err, 'strength_create', msg, ERR_INPUT)
        return
      end if
      model = hjc
    case default
      call error_set(err, 'strength_create', 'strength = '''//trim(name)//''' is not known; valid: '// &
                     'elastic, bilinear, johnson_cook, gurson, hjc', ERR_INPUT)
      return
    end select
    if (present(eos_pressure)) then
      if (eos_pressure) model%k = 0.0_wp
    end if
  end subroutine strength_create

  !> The history variables per particle of the model `name` (0 for a
  !> name the factory does not know), so that particles can be allocated
  !> before the models are built; tensile_strength: the bilinear model's
  !> (default 0).
  integer function strength_nhist(name, tensile_strength) result(n)
    character(len=*), intent(in) :: name
    real(wp), intent(in), optional :: tensile_strength
    class(strength_t), allocatable :: model
    type(error_t), allocatable :: err
    type(strength_params_t) :: par
    n = 0
    if (trim(name) == 'hjc') n = hjc_nhist
    if (n > 0) return
    par = strength_params_t(k=1.0_wp, g=1.0_wp, et=0.5_wp)
    if (present(tensile_strength)) par%tensile_strength = tensile_strength
    call strength_create(name, par, model, err)
    if (allocated(model)) n = model%nhist()
  end function strength_nhist
end module strength_factory
