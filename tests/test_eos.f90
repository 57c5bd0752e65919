!> Unit tests of the EOS: ideal-gas pressure and sound speed, thermodynamic
!> consistency of c^2 with the isentropic derivative, the inverse e(rho, p),
!> and the factory's errors.
program test_eos
  use base_kinds, only: wp
  use base_errors, only: error_t
  use eos_base, only: eos_t
  use eos_factory, only: eos_params_t, eos_create
  use test_assert, only: check, check_summary
  implicit none
  class(eos_t), allocatable :: eos
  type(error_t), allocatable :: err
  type(eos_params_t) :: par
  real(wp) :: rho(3), e(3), p(3), cs(3), pp(3), cp(3), pm(3), cm(3), h, dpdrho_s
  integer :: i

  par%gamma = 5.0_wp/3.0_wp
  call eos_create('ideal_gas', par, eos, err)
  call check(.not. allocated(err), 'ideal_gas with gamma 5/3 is accepted')
  rho = [0.125_wp, 1.0_wp, 7.5_wp]
  e = [2.0_wp, 2.5_wp, 1.0e-3_wp]
  call eos%eval(rho, e, p, cs)
  call check(all(abs(p - (2.0_wp/3.0_wp)*rho*e) <= 1e-15_wp*p), 'p = (gamma-1) rho e')
  call check(all(abs(cs**2 - (5.0_wp/3.0_wp)*p/rho) <= 1e-14_wp*cs**2), 'c^2 = gamma p / rho')
  ! isentropic derivative by central differences along de = p/rho^2 drho
  do i = 1, 3
    h = 1e-6_wp*rho(i)
    call eos%eval([rho(i) + h], [e(i) + p(i)/rho(i)**2*h], pp(1:1), cp(1:1))
    call eos%eval([rho(i) - h], [e(i) - p(i)/rho(i)**2*h], pm(1:1), cm(1:1))
    dpdrho_s = (pp(1) - pm(1))/(2.0_wp*h)
    call check(abs(dpdrho_s - cs(i)**2) <= 1e-7_wp*cs(i)**2, 'c^2 equals dp/drho at constant entropy')
    call check(abs(eos%energy(rho(i), p(i)) - e(i)) <= 1e-15_wp*e(i), 'e(rho, p(rho, e)) = e')
  end do

  par%gamma = 1.0_wp
  call eos_create('ideal_gas', par, eos, err)
  call check(allocated(err), 'gamma = 1 is refused')
  if (allocated(err)) call check(index(err%msg, 'gamma') > 0, 'the message names gamma')
  deallocate(err)
  call eos_create('ideal_gaz', par, eos, err)
  call check(allocated(err), 'an unknown EOS name is refused')
  if (allocated(err)) call check(index(err%msg, 'ideal_gas') > 0, 'the message lists the valid names')

  call check_summary('test_eos')

end program test_eos
