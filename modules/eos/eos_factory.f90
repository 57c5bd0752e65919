!> The one place that knows the EOS names a deck may use.
module eos_factory
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set
  use eos_base, only: eos_t
  use eos_ideal_gas, only: ideal_gas_t
  implicit none
  private
  public :: eos_params_t, eos_create, eos_names

  !> Every EOS parameter a deck can give; each model reads the ones it needs.
  type :: eos_params_t
    real(wp) :: gamma = 1.4_wp     !< ideal gas ratio of specific heats
  end type eos_params_t

  !> Valid names, for error messages and documentation.
  character(len=*), parameter :: eos_names = 'ideal_gas'

contains

  !> Creates the EOS called `name` with parameters `par`; validates them.
  subroutine eos_create(name, par, eos, err)
    character(len=*), intent(in) :: name
    type(eos_params_t), intent(in) :: par
    class(eos_t), allocatable, intent(out) :: eos
    type(error_t), allocatable, intent(inout) :: err
    character(len=64) :: buf

    select case (trim(name))
    case ('ideal_gas')
      if (.not. (par%gamma > 1.0_wp)) then
        write(buf, '(es12.5)') par%gamma
        call error_set(err, 'eos_create', 'gamma = '//trim(adjustl(buf))// &
                       ' must be > 1 for eos = ''ideal_gas''')
        return
      end if
      eos = ideal_gas_t(gamma=par%gamma)
    case default
      call error_set(err, 'eos_create', 'eos = '''//trim(name)//''' is not known; valid: '//eos_names)
    end select
  end subroutine eos_create
end module eos_factory
