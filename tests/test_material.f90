!> Unit tests of the mixed-cell closure (Tipton): volume and energy are
!> shared exactly, pressures equalise, a cell in equilibrium stays so, the
!> exchange is bounded, the acoustic resistance gives the acoustic
!> Riemann problem's exchange without tension in an expanding gas, and a
!> cavitated material (at its pressure floor) takes the change at its floor.
program test_material
  use base_kinds, only: wp
  use base_errors, only: error_t
  use test_assert, only: check, check_summary
  use material_mixed, only: mixed_t, mixed_allocate, mixed_save_step_start, mixed_split, mixed_cell_state
  implicit none
  type(mixed_t) :: mx
  type(error_t), allocatable :: err
  real(wp) :: mass(1), vol(1), en(1), e(1), p(1), cs(1), gam(2), v0, etot, pf(2)
  integer :: s

  gam = [2.0_wp, 1.4_wp]
  call mixed_allocate(mx, 1, 2, err)
  call check(.not. allocated(err), 'allocation')
  mx%cell = 1
  mx%start = [1, 3]
  mx%mat = [1, 2]

  ! 1. a cell whose two gases are at different pressures, volume unchanged
  v0 = 2.0_wp
  call setup([0.5_wp, 0.5_wp], [1.0_wp, 0.125_wp], [2.0_wp, 0.1_wp])
  vol = v0
  e = en
  call mixed_split(mx, mass, vol, vol, en, e, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp)
  call check(abs(sum(mx%vf) - 1.0_wp) < 1e-14_wp, 'volume fractions sum to one')
  call check(abs(dot_product(mx%mass, mx%e) - mass(1)*e(1)) < 1e-14_wp*mass(1)*e(1), &
             'material energies sum to the cell energy')
  call eos_ideal()
  ! one linearised step on a 20:1 pressure ratio removes about half of the
  ! difference (measured 46 %: the light gas stiffens as it is squeezed,
  ! which the linearisation at the start state does not see)
  call check(abs(mx%p(1) - mx%p(2)) < 0.6_wp*abs(2.0_wp - 0.1_wp), 'pressures move together')
  call check(mx%vf(1) > 0.5_wp, 'the high-pressure gas expands')
  do s = 1, 20
    call mixed_save_step_start(mx, vol)
    call mixed_split(mx, mass, vol, vol, en, e, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp)
    call eos_ideal()
  end do
  call check(abs(mx%p(1) - mx%p(2)) < 1e-8_wp*mx%p(1), 'repeated steps equalise the pressures')
  call check(abs(dot_product(mx%mass, mx%e) - mass(1)*e(1)) < 1e-13_wp*mass(1)*e(1), &
             'energy stays exactly shared after many steps')

  ! 2. equal pressures and a compression: the materials share dV in
  !    proportion to V_m / (rho_m c_m^2), and heat by -p dV
  call setup([0.3_wp, 0.7_wp], [1.0_wp, 0.2_wp], [1.0_wp, 1.0_wp])
  vol = 0.99_wp*v0
  etot = mass(1)*en(1) + 1.0_wp*0.01_wp*v0
  e = etot/mass(1)
  call mixed_split(mx, mass, vol, vol, en, e, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp)
  call check(abs(mx%vf(1)*vol(1) - 0.3_wp*v0 - (-0.01_wp*v0)*(0.3_wp/2.0_wp)/(0.3_wp/2.0_wp + 0.7_wp/1.4_wp)) &
             < 1e-14_wp, 'volume change shared by compressibility')
  call eos_ideal()
  call check(abs(mx%p(1) - mx%p(2)) < 2e-4_wp, 'pressures stay equal to second order')
  call mixed_cell_state(mx, p, cs)
  call check(abs(p(1) - dot_product(mx%vf, mx%p)) < 1e-15_wp, 'cell pressure is the volume-weighted mean')
  call check(abs(cs(1) - maxval(mx%cs)) < 1e-15_wp, 'cell sound speed is the largest')

  ! 3. the exchange bounded: on the 20:1 pressure ratio of case 1 with
  !    dv_cap = 0.1 the light gas gives at most 10 % of its volume
  call setup([0.5_wp, 0.5_wp], [1.0_wp, 0.125_wp], [2.0_wp, 0.1_wp])
  e = en
  call mixed_split(mx, mass, vol, vol, en, e, 1.0_wp, 0.0_wp, 0.0_wp, 0.1_wp)
  call check(abs(mx%vf(2)*vol(1) - 0.9_wp*0.5_wp*v0) < 1e-14_wp, 'the exchange takes dv_cap of the volume, no more')
  call check(abs(dot_product(mx%mass, mx%e) - mass(1)*e(1)) < 1e-14_wp*mass(1)*e(1), &
             'bounded exchange: material energies sum to the cell energy')

  ! 4. the acoustic resistance over a short step (c dt much less than the
  !    layers' thickness f V/A): the acoustic Riemann problem between the
  !    layers, the high-pressure gas growing by A dt (p1 - p2)/(Z1 + Z2)
  !    (to the order of c dt / (f V/A), 3e-3 here)
  call setup([0.5_wp, 0.5_wp], [1.0_wp, 0.125_wp], [2.0_wp, 0.1_wp])
  e = en
  call mixed_split(mx, mass, vol, [4.0_wp], en, e, 1.0_wp, 1.0_wp, 1.0e-4_wp, 0.1_wp)
  associate (z1 => sqrt(gam(1)*2.0_wp*1.0_wp), z2 => sqrt(gam(2)*0.1_wp*0.125_wp))
    call check(abs((mx%vf(1) - 0.5_wp)*v0/(4.0_wp*1.0e-4_wp*1.9_wp/(z1 + z2)) - 1.0_wp) < 3e-3_wp, &
               'acoustic exchange: the interface moves at (p1 - p2)/(Z1 + Z2)')
  end associate

  ! 5. an expanding cell with the acoustic resistance: the light gas, of
  !    far the larger weight, takes growth only until its linearised
  !    pressure reaches zero (relative growth 1/gamma); the rest goes to
  !    the dense gas
  call setup([0.5_wp, 0.5_wp], [1.0_wp, 0.125_wp], [2.0_wp, 1.0e-3_wp])
  vol = 1.5_wp*v0
  e = en
  call mixed_split(mx, mass, vol, [4.0_wp], en, e, 1.0_wp, 1.0_wp, 1.0e-4_wp, 0.1_wp)
  call check(abs(mx%vf(2)*vol(1) - 0.5_wp*v0*(1.0_wp + 1.0_wp/gam(2))) < 1e-13_wp, &
             'no tension: the light gas grows by 1/gamma of its volume')
  call check(abs(sum(mx%vf) - 1.0_wp) < 1e-14_wp, 'no tension: the dense gas takes the rest')

  ! 6. a cavitated material (at its pressure floor): B = 0 where it grows.
  !    (a) an expanding cell: the gas relaxes to the floor's pressure in one
  !    step, linearised, and the cavitated material takes the rest, exactly
  call setup([0.5_wp, 0.5_wp], [1.0_wp, 0.125_wp], [0.05_wp, 0.1_wp])
  pf = [mx%p(1), -huge(1.0_wp)]
  vol = 1.2_wp*v0
  e = en
  call mixed_split(mx, mass, vol, vol, en, e, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, pf)
  call check(abs(mx%vf(2)*vol(1) - 0.5_wp*v0*(1.0_wp + (0.1_wp - 0.05_wp)/(gam(2)*0.1_wp))) < 1e-14_wp, &
             'floor, expanding: the gas relaxes to the cavitated pressure')
  call check(abs(mx%vf(1)*vol(1) - (1.2_wp*v0 - mx%vf(2)*vol(1))) < 1e-14_wp, &
             'floor, expanding: the cavitated material takes the rest of the growth')
  call check(abs(dot_product(mx%mass, mx%e) - mass(1)*e(1)) < 1e-14_wp*mass(1)*e(1), &
             'floor: material energies sum to the cell energy')
  ! (b) a floor in tension (-0.05) and a cell growing by 80 %: the gas grows
  !     only until its linearised pressure reaches zero (1/gamma), the
  !     cavitated material takes the rest
  call setup([0.5_wp, 0.5_wp], [1.0_wp, 0.125_wp], [0.05_wp, 0.1_wp])
  mx%pn(1) = -0.05_wp
  pf = [-0.05_wp, -huge(1.0_wp)]
  vol = 1.8_wp*v0
  e = en
  call mixed_split(mx, mass, vol, vol, en, e, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, pf)
  call check(abs(mx%vf(2)*vol(1) - 0.5_wp*v0*(1.0_wp + 1.0_wp/gam(2))) < 1e-14_wp, &
             'floor in tension: the gas grows by 1/gamma, no more')
  call check(abs(sum(mx%vf) - 1.0_wp) < 1e-14_wp, 'floor in tension: fractions sum to one')
  ! (c) where the cavitated material would be compressed (the cell's growth
  !     short of the gas's relaxation, or every material at its floor, or
  !     the floors not reached) the closure is the stiff one, bit for bit
  call stiff_same([0.5_wp, 0.5_wp], [0.05_wp, 0.1_wp], 1.1_wp, [0.05_wp, -huge(1.0_wp)], &
                  'floor, the gas relaxing by more than the growth: stiff closure')
  call stiff_same([0.3_wp, 0.7_wp], [0.05_wp, 0.1_wp], 1.1_wp, [0.05_wp, 0.1_wp], &
                  'all at their floors: stiff closure')
  call stiff_same([0.5_wp, 0.5_wp], [2.0_wp, 0.1_wp], 1.0_wp, [0.0_wp, 0.0_wp], 'floors not reached: unchanged')

  call check_summary('test_material')

contains

  !> Two ideal gases (gamma 2 and 1.4) with volume fractions vf, densities
  !> rho and pressures pr in a cell of volume v0.
  subroutine setup(vf, rho, pr)
    real(wp), intent(in) :: vf(2), rho(2), pr(2)
    mx%vf = vf
    mx%rho = rho
    mx%mass = rho*vf*v0
    mx%e = pr/((gam - 1.0_wp)*rho)
    mass = sum(mx%mass)
    en = dot_product(mx%mass, mx%e)/mass(1)
    call eos_ideal()
    vol = v0
    call mixed_save_step_start(mx, vol)
  end subroutine setup

  !> The closure with floors pf gives the same bits as without them.
  subroutine stiff_same(vf, pr, grow, pf, what)
    real(wp), intent(in) :: vf(2), pr(2), grow, pf(2)
    character(*), intent(in) :: what
    real(wp) :: vf_ref(2), e_ref(2)
    call setup(vf, [1.0_wp, 0.125_wp], pr)
    vol = grow*v0
    e = en
    call mixed_split(mx, mass, vol, vol, en, e, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp)
    vf_ref = mx%vf
    e_ref = mx%e
    call setup(vf, [1.0_wp, 0.125_wp], pr)
    vol = grow*v0
    e = en
    call mixed_split(mx, mass, vol, vol, en, e, 1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, pf)
    call check(all(.not. abs(mx%vf - vf_ref) > 0.0_wp) .and. all(.not. abs(mx%e - e_ref) > 0.0_wp), what)
  end subroutine stiff_same

  subroutine eos_ideal()
    mx%p = (gam - 1.0_wp)*mx%rho*mx%e
    mx%cs = sqrt(gam*mx%p/mx%rho)
  end subroutine eos_ideal
end program test_material
