!> Unit tests of the programmed burn (`material_burn`): the CJ state of the
!> TNT JWL against a brute-force scan of its Hugoniot and Dobratz's values,
!> initiator distances, and the shortest paths through an explosive with an
!> inert wall against the exact geodesic round the wall's end; the material
!> library's explosives against their published CJ states, and its units.
program test_burn
  use base_kinds, only: wp
  use eos_jwl, only: jwl_t, jwl_cold_pressure
  use material_burn, only: burn_cj, burn_initiator, burn_around, burn_width_across, INIT_POINT, INIT_LINE, &
                           INIT_PLANE
  use material_library, only: library_value, library_has, units_known
  use test_assert, only: check, check_close, check_summary
  implicit none
  type(jwl_t) :: tnt
  real(wp) :: d_cj, p_cj, v_cj, best, v, ph, d, dir(3), xn(3, 8), ax(0:40), ay(0:40), az(0:1), geo, a(3), b(3)
  real(wp), allocatable :: dist(:), dirs(:, :)
  logical :: mask(40, 40, 1), ok
  integer :: i, j, k, ib, e
  character(len=8), parameter :: explosives(6) = [character(len=8) :: 'tnt', 'c4', 'compb', 'petn', 'compa3', 'rht901']
  real(wp) :: lv(10), d_doc, p_doc
  logical :: found(10)

  ! TNT (Dobratz): mm-us-g/cm^3-GPa, E0 = 7 GPa per volume
  tnt = jwl_t(a=371.2_wp, b=3.231_wp, r1=4.15_wp, r2=0.95_wp, omega=0.30_wp, rho0=1.63_wp)
  call burn_cj(tnt, 1.63_wp, 7.0_wp/1.63_wp, d_cj, p_cj, v_cj)
  ! brute force: the least Rayleigh-line D^2 over 10^6 points of the Hugoniot
  best = huge(1.0_wp)
  ib = 0
  do i = 1, 1000000
    v = 0.2_wp + 0.8_wp*real(i, wp)/1.0e6_wp
    if (v >= 1.0_wp) exit
    ph = (jwl_cold_pressure(tnt, 1.63_wp/v) + 0.3_wp*7.0_wp/v)/(1.0_wp - 0.3_wp*(1.0_wp - v)/(2.0_wp*v))
    if (ph > 0.0_wp .and. ph/(1.63_wp*(1.0_wp - v)) < best) then
      best = ph/(1.63_wp*(1.0_wp - v))
      ib = i
    end if
  end do
  call check_close('CJ velocity against a 1e6-point scan of the Hugoniot', d_cj, sqrt(best), 1.0e-9_wp*sqrt(best))
  call check_close('CJ relative volume against the scan (its spacing 8e-7)', v_cj, 0.2_wp + 0.8_wp*real(ib, wp)/1.0e6_wp, &
                   2.0e-5_wp)
  call check_close('CJ velocity of TNT against Dobratz''s 6.93 km/s (0.2 %)', d_cj, 6.93_wp, 0.014_wp)
  call check_close('CJ pressure of TNT against Dobratz''s 21 GPa (1 %)', p_cj, 21.0_wp, 0.21_wp)
  call check_close('CJ pressure = rho0 D^2 (1 - V_CJ)', p_cj, 1.63_wp*d_cj**2*(1.0_wp - v_cj), 1.0e-12_wp*p_cj)

  ! initiators
  call burn_initiator(INIT_POINT, [1.0_wp, 2.0_wp, 3.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 0.0_wp, 0.0_wp], &
                      [4.0_wp, 6.0_wp, 3.0_wp], d, dir)
  call check_close('point: distance 5', d, 5.0_wp, 1.0e-15_wp)
  call check(all(abs(dir - [0.6_wp, 0.8_wp, 0.0_wp]) <= 1.0e-15_wp), 'point: direction (0.6, 0.8, 0)')
  call burn_initiator(INIT_LINE, [0.0_wp, 0.0_wp, 0.0_wp], [10.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 0.0_wp, 0.0_wp], &
                      [4.0_wp, 3.0_wp, 4.0_wp], d, dir)
  call check_close('line: distance to the segment 5', d, 5.0_wp, 1.0e-15_wp)
  call burn_initiator(INIT_LINE, [0.0_wp, 0.0_wp, 0.0_wp], [10.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 0.0_wp, 0.0_wp], &
                      [13.0_wp, 4.0_wp, 0.0_wp], d, dir)
  call check_close('line: beyond its end, distance to the end 5', d, 5.0_wp, 1.0e-15_wp)
  call burn_initiator(INIT_PLANE, [1.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], [2.0_wp, 0.0_wp, 0.0_wp], &
                      [-3.0_wp, 7.0_wp, 1.0_wp], d, dir)
  call check_close('plane: distance 4 on the back side', d, 4.0_wp, 1.0e-15_wp)
  call check(all(abs(dir - [-1.0_wp, 0.0_wp, 0.0_wp]) <= 1.0e-15_wp), 'plane: direction -n on the back side')
  ! a 1 x 2 x 3 box: width 1 along x, 2 along y, |(1,2,3).(1,1,1)/sqrt 3| for the diagonal
  do k = 0, 1
    do j = 0, 1
      do i = 0, 1
        xn(:, 1 + i + 2*j + 4*k) = [real(i, wp), 2.0_wp*j, 3.0_wp*k]
      end do
    end do
  end do
  call check_close('box width along x', burn_width_across(xn, [1.0_wp, 0.0_wp, 0.0_wp]), 1.0_wp, 1.0e-15_wp)
  call check_close('box width along y', burn_width_across(xn, [0.0_wp, 1.0_wp, 0.0_wp]), 2.0_wp, 1.0e-15_wp)
  call check_close('box width along the diagonal', burn_width_across(xn, [1.0_wp, 1.0_wp, 1.0_wp]/sqrt(3.0_wp)), &
                   6.0_wp/sqrt(3.0_wp), 1.0e-14_wp)

  ! shortest paths on a 40 x 40 x 1 grid of unit cells
  ax = [(real(i, wp), i = 0, 40)]
  ay = ax
  az = [0.0_wp, 1.0_wp]
  allocate(dist(1600), dirs(3, 1600))
  mask = .true.
  call burn_around(40, 40, 1, ax, ay, az, mask, reshape([10.5_wp, 10.5_wp, 0.5_wp], [3, 1]), [2.0_wp], dist, dirs, ok)
  call check(ok, 'around: memory')
  call check(all(abs(dist - [((2.0_wp + norm2([i - 0.5_wp, j - 0.5_wp] - 10.5_wp), i = 1, 40), j = 1, 40)]) &
                 <= 1.0e-12_wp), 'around, no obstacle: every cell at d0 + its straight distance')
  ! an inert wall x in [19, 20], y in [0, 30]: round its end at y = 30
  mask(20, 1:30, 1) = .false.
  call burn_around(40, 40, 1, ax, ay, az, mask, reshape([10.5_wp, 10.5_wp, 0.5_wp], [3, 1]), [0.0_wp], dist, dirs, ok)
  a = [19.0_wp, 30.0_wp, 0.5_wp]
  b = [20.0_wp, 30.0_wp, 0.5_wp]
  geo = norm2(a - [10.5_wp, 10.5_wp, 0.5_wp]) + 1.0_wp + norm2([30.5_wp, 10.5_wp, 0.5_wp] - b)
  call check_close('around the wall: cell (31, 11) within one cell of the geodesic round its end', &
                   dist(31 + 40*10), geo, 1.0_wp)
  call check(dist(31 + 40*10) >= geo - 1.0e-12_wp, 'around the wall: never shorter than the geodesic')
  call check(all(.not. dist(20 + 40*[(j, j = 0, 29)]) < huge(1.0_wp)), 'around: the wall cells are not lit')
  ! (the segment to the centre (20.5, 39.5) passes x = 19..20 at y > 35)
  geo = norm2([20.5_wp, 39.5_wp, 0.5_wp] - [10.5_wp, 10.5_wp, 0.5_wp])
  call check_close('around: a cell that sees the source past the wall end: straight distance', &
                   dist(21 + 40*39), geo, 1.0e-12_wp)
  ! the library's explosives: the CJ state of each JWL from its unreacted
  ! state against the published CJ velocity and pressure of the entry (0.1 %
  ! and 0.5 %: the fits reproduce them; a mistyped parameter would not)
  do e = 1, size(explosives)
    call check(library_has(trim(explosives(e))), 'library: '//trim(explosives(e))//' is there')
    call library_value(trim(explosives(e)), 'cj_velocity', 'mm-us-g/cm^3-GPa', d_doc, found(9))
    if (.not. found(9)) cycle   ! (the paper's RHT-901 gives no CJ state)
    call library_value(trim(explosives(e)), 'cj_pressure', 'mm-us-g/cm^3-GPa', p_doc, found(10))
    call library_value(trim(explosives(e)), 'a', 'mm-us-g/cm^3-GPa', lv(1), found(1))
    call library_value(trim(explosives(e)), 'b', 'mm-us-g/cm^3-GPa', lv(2), found(2))
    call library_value(trim(explosives(e)), 'r1', 'mm-us-g/cm^3-GPa', lv(3), found(3))
    call library_value(trim(explosives(e)), 'r2', 'mm-us-g/cm^3-GPa', lv(4), found(4))
    call library_value(trim(explosives(e)), 'omega', 'mm-us-g/cm^3-GPa', lv(5), found(5))
    call library_value(trim(explosives(e)), 'rho0', 'mm-us-g/cm^3-GPa', lv(6), found(6))
    call library_value(trim(explosives(e)), 'energy_per_volume', 'mm-us-g/cm^3-GPa', lv(7), found(7))
    call check(all(found(1:7)) .and. found(10), 'library: '//trim(explosives(e))//' has a JWL, E0 and a CJ state')
    tnt = jwl_t(a=lv(1), b=lv(2), r1=lv(3), r2=lv(4), omega=lv(5), rho0=lv(6))
    call burn_cj(tnt, lv(6), lv(7)/lv(6), d_cj, p_cj, v_cj)
    call check_close('library '//trim(explosives(e))//': CJ velocity of its JWL against the published', d_cj, d_doc, &
                     1.0e-3_wp*d_doc)
    call check_close('library '//trim(explosives(e))//': CJ pressure of its JWL against the published', p_cj, p_doc, &
                     5.0e-3_wp*p_doc)
  end do
  ! units: the entry's own system read exactly; another one converted
  call library_value('tnt', 'a', 'mm-us-g/cm^3-GPa', lv(1), found(1))
  call check(found(1) .and. abs(lv(1) - 371.2_wp) <= 0.0_wp, 'library: tnt a in its own units is 371.2 exactly')
  call library_value('tnt', 'a', 'SI', lv(1), found(1))
  call check_close('library: tnt a in SI (Pa)', lv(1), 3.712e11_wp, 1.0e-15_wp*3.712e11_wp)
  call library_value('tnt', 'rho0', 'SI', lv(1), found(1))
  call check_close('library: tnt rho0 in SI (kg/m^3)', lv(1), 1630.0_wp, 1.0e-12_wp)
  call library_value('tnt', 'energy_per_volume', 'mm-ms-g/mm^3-MPa', lv(1), found(1))
  call check_close('library: tnt E0 in MPa', lv(1), 7000.0_wp, 1.0e-9_wp)
  call library_value('air', 'pressure', 'mm-us-g/cm^3-GPa', lv(1), found(1))
  call check_close('library: air pressure in GPa', lv(1), 1.01325e-4_wp, 1.0e-19_wp)
  call library_value('air', 'density', 'cm-us-g-Mbar', lv(1), found(1))
  call check_close('library: air density in g/cm^3', lv(1), 1.225e-3_wp, 1.0e-18_wp)
  call library_value('water', 'c0', 'SI', lv(1), found(1))
  call check_close('library: water c0 in m/s', lv(1), 1480.0_wp, 1.0e-12_wp)
  call library_value('air', 'gamma', 'mm-us-g/cm^3-GPa', lv(1), found(1))
  call check(found(1) .and. abs(lv(1) - 1.4_wp) <= 0.0_wp, 'library: a dimensionless value converts to itself exactly')
  call library_value('tnt', 'no_such_key', 'SI', lv(1), found(1))
  call check(.not. found(1), 'library: a key the entry lacks is not found')
  call check(.not. library_has('dynamite'), 'library: no entry dynamite')
  call check(units_known('SI') .and. .not. units_known('furlong-fortnight'), 'units: SI known, furlong-fortnight not')
  call check_summary('test_burn')
end program test_burn
