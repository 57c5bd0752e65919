!> The one place that knows the EOS names a deck may use.
module eos_factory
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set
  use eos_base, only: eos_t
  use eos_ideal_gas, only: ideal_gas_t
  use eos_jwl, only: jwl_t
  use eos_mie_gruneisen, only: mie_gruneisen_t
  implicit none
  private
  public :: eos_params_t, eos_create, eos_names

  !> Every EOS parameter a deck can give; each model reads the ones it needs.
  !> Units are the deck's. The JWL and Mie-Gruneisen parameters default to 0,
  !> meaning "not given": the model that needs one refuses 0, so a deck must
  !> state every one of them (there is no unit-free default for rho0, A, c0...).
  !> Paper values: TNT (Section 7.7) a = 371.2 GPa, b = 3.23 GPa, r1 = 4.15,
  !> r2 = 0.95, omega = 0.3, rho0 = 1.63 g/cm^3; 1045 steel (Section 7.6)
  !> c0 = 3570 mm/ms, s1 = 1.92, gamma0 = 1.8, rho0 = 7.8 g/cm^3.
  type :: eos_params_t
    real(wp) :: gamma = 1.4_wp     !< ideal_gas: ratio of specific heats [-]
    real(wp) :: a = 0.0_wp         !< jwl: A, first exponential [pressure]
    real(wp) :: b = 0.0_wp         !< jwl: B, second exponential [pressure]
    real(wp) :: r1 = 0.0_wp        !< jwl: R1 [-]
    real(wp) :: r2 = 0.0_wp        !< jwl: R2 [-]
    real(wp) :: omega = 0.0_wp     !< jwl: omega, Gruneisen coefficient of the products [-]
    real(wp) :: rho0 = 0.0_wp      !< jwl, mie_gruneisen: reference density [density]
    real(wp) :: c0 = 0.0_wp        !< mie_gruneisen: bulk sound speed, Us = c0 + s1 up [velocity]
    real(wp) :: s1 = 0.0_wp        !< mie_gruneisen: slope s1 of Us(up) [-]
    real(wp) :: gamma0 = 0.0_wp    !< mie_gruneisen: Gruneisen coefficient at rho0 [-]
  end type eos_params_t

  !> Valid names, for error messages and documentation.
  character(len=*), parameter :: eos_names = 'ideal_gas, jwl, mie_gruneisen'

contains

  !> Creates the EOS called `name` with parameters `par`; validates them.
  !> Every invalid parameter is reported, one clause each, joined by '; '.
  subroutine eos_create(name, par, eos, err)
    character(len=*), intent(in) :: name
    type(eos_params_t), intent(in) :: par
    class(eos_t), allocatable, intent(out) :: eos
    type(error_t), allocatable, intent(inout) :: err
    character(len=64) :: buf
    character(len=:), allocatable :: problems

    problems = ''
    select case (trim(name))
    case ('ideal_gas')
      if (.not. (par%gamma > 1.0_wp)) then
        write(buf, '(es12.5)') par%gamma
        call error_set(err, 'eos_create', 'gamma = '//trim(adjustl(buf))// &
                       ' must be > 1 for eos = ''ideal_gas''')
        return
      end if
      eos = ideal_gas_t(gamma=par%gamma)
    case ('jwl')
      call require_positive(problems, 'a', par%a, 'jwl')
      call require_positive(problems, 'b', par%b, 'jwl')
      call require_positive(problems, 'r1', par%r1, 'jwl')
      call require_positive(problems, 'r2', par%r2, 'jwl')
      ! omega > 0 also makes e(rho, p) = (p - p_cold)/(omega rho) defined
      call require_positive(problems, 'omega', par%omega, 'jwl')
      call require_positive(problems, 'rho0', par%rho0, 'jwl')
      if (len(problems) > 0) then
        call error_set(err, 'eos_create', problems)
        return
      end if
      eos = jwl_t(a=par%a, b=par%b, r1=par%r1, r2=par%r2, omega=par%omega, rho0=par%rho0)
    case ('mie_gruneisen')
      call require_positive(problems, 'rho0', par%rho0, 'mie_gruneisen')
      call require_positive(problems, 'c0', par%c0, 'mie_gruneisen')
      call require_positive(problems, 's1', par%s1, 'mie_gruneisen')
      ! gamma0 > 0 also makes e(rho, p) = (p - K)/(gamma0 rho0) defined
      call require_positive(problems, 'gamma0', par%gamma0, 'mie_gruneisen')
      if (len(problems) > 0) then
        call error_set(err, 'eos_create', problems)
        return
      end if
      eos = mie_gruneisen_t(rho0=par%rho0, c0=par%c0, s1=par%s1, gamma0=par%gamma0)
    case default
      call error_set(err, 'eos_create', 'eos = '''//trim(name)//''' is not known; valid: '//eos_names)
    end select
  end subroutine eos_create

  !> Appends "<what> = <value> must be > 0 for eos = '<model>'" to `problems`
  !> unless value > 0 (NaN fails too).
  subroutine require_positive(problems, what, value, model)
    character(len=:), allocatable, intent(inout) :: problems
    character(len=*), intent(in) :: what, model
    real(wp), intent(in) :: value
    character(len=64) :: buf
    if (value > 0.0_wp) return
    write(buf, '(es12.5)') value
    if (len(problems) > 0) problems = problems//'; '
    problems = problems//what//' = '//trim(adjustl(buf))//' must be > 0 for eos = '''//model//''''
  end subroutine require_positive
end module eos_factory
