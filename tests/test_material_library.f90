!> Unit tests of the material library's solids (input/materials.txt through
!> `material_library` and `solid_config_read`): every solid entry loads into
!> a valid &solid in its own unit system and in others, its strength keys
!> convert with their dimensions (pressure, rate, specific heat) and its
!> temperatures and dimensionless keys do not, the group's own variables
!> override the entry's, and a solid takes only the parameters of its own
!> strength model.
program test_material_library
  use base_kinds, only: wp
  use base_config, only: max_line, no_echo
  use material_library, only: library_value, library_has
  use particles_config, only: solid_config_t, solid_config_read
  use test_assert, only: check, check_close, check_summary
  implicit none
  character(len=*), parameter :: mm_ms = 'mm-ms-g/mm^3-MPa', mm_us = 'mm-us-g/cm^3-GPa'
  !> round-off of a conversion: the entry's value times a product of three
  !> powers of unit ratios, each rounded (a few ulp); a wrong exponent is off
  !> by a factor 1e3 or more
  real(wp), parameter :: rel = 1.0e-14_wp
  character(len=12), parameter :: solids(6) = [character(len=12) :: 'steel1045', 'steel4340', 'steel1006', &
                                               'al6061', 'copper', 'concrete48']
  character(len=16), parameter :: systems(3) = [character(len=16) :: 'SI', mm_us, mm_ms]
  type(solid_config_t) :: sc
  character(len=max_line), allocatable :: problems(:)
  real(wp) :: v
  logical :: found
  integer :: i, j, k

  ! every solid entry is a valid solid in three unit systems (steel4340 has
  ! no elastic moduli: the group gives them, in each system's pressure unit)
  do i = 1, size(solids)
    call check(library_has(trim(solids(i))), 'library: '//trim(solids(i))//' is there')
    do k = 1, size(systems)
      if (solids(i) == 'steel4340') then
        call read_solid('library = ''steel4340'', shear_modulus = 1.0', systems(k))
      else
        call read_solid('library = '''//trim(solids(i))//'''', systems(k))
      end if
      call check(size(problems) == 0, 'library: '//trim(solids(i))//' is a valid &solid in '//trim(systems(k)))
      if (size(problems) > 0) print '(a)', (trim(problems(j)), j = 1, size(problems))
    end do
  end do

  ! conversions: pressure (M L^-1 T^-2), rate (T^-1), specific heat
  ! (L^2 T^-2 per kelvin), density; temperatures and dimensionless keys as they are
  call library_value('steel4340', 'jc_a', 'SI', v, found)
  call check(found .and. abs(v - 792.0e6_wp) <= 0.0_wp, 'library: steel4340 jc_a in SI (its own) is 792e6 exactly')
  call library_value('steel4340', 'jc_a', mm_ms, v, found)
  call check_close('library: steel4340 jc_a in MPa = SI x 1e-6', v, 792.0_wp, rel*792.0_wp)
  call library_value('steel4340', 'jc_b', mm_us, v, found)
  call check_close('library: steel4340 jc_b in GPa', v, 0.51_wp, rel*0.51_wp)
  call library_value('steel4340', 'jc_eps0', mm_ms, v, found)
  call check_close('library: steel4340 jc_eps0 1/s in 1/ms', v, 1.0e-3_wp, rel*1.0e-3_wp)
  call library_value('steel4340', 'jc_eps0', mm_us, v, found)
  call check_close('library: steel4340 jc_eps0 1/s in 1/us', v, 1.0e-6_wp, rel*1.0e-6_wp)
  call library_value('steel4340', 'specific_heat', mm_us, v, found)
  call check_close('library: steel4340 specific_heat J/(kg K) in (mm/us)^2/K', v, 477.0e-6_wp, rel*477.0e-6_wp)
  call library_value('steel4340', 'specific_heat', mm_ms, v, found)
  call check_close('library: steel4340 specific_heat in (mm/ms)^2/K = (m/s)^2/K', v, 477.0_wp, rel*477.0_wp)
  call library_value('steel4340', 'density', mm_ms, v, found)
  call check_close('library: steel4340 density in g/mm^3', v, 7.83e-3_wp, rel*7.83e-3_wp)
  call library_value('steel4340', 't_melt', mm_us, v, found)
  call check(found .and. abs(v - 1793.0_wp) <= 0.0_wp, 'library: a temperature (t_melt, kelvin) is not converted')
  call library_value('steel4340', 'jc_n', mm_ms, v, found)
  call check(found .and. abs(v - 0.26_wp) <= 0.0_wp, 'library: a dimensionless key (jc_n) converts to itself exactly')
  call library_value('copper', 'shear_modulus', 'cm-us-g-Mbar', v, found)
  call check_close('library: copper G in Mbar', v, 0.477_wp, rel*0.477_wp)
  call library_value('al6061', 'c0', mm_us, v, found)
  call check_close('library: al6061 c0 in km/s', v, 5.24_wp, rel*5.24_wp)
  call library_value('concrete48', 'hjc_fc', mm_ms, v, found)
  call check_close('library: concrete48 hjc_fc in MPa', v, 48.0_wp, rel*48.0_wp)
  call library_value('concrete48', 'hjc_k2', mm_ms, v, found)
  call check_close('library: concrete48 hjc_k2 in MPa (negative)', v, -171000.0_wp, rel*171000.0_wp)
  call library_value('concrete48', 'hjc_eps0', mm_ms, v, found)
  call check_close('library: concrete48 hjc_eps0 1/s in 1/ms', v, 1.0e-3_wp, rel*1.0e-3_wp)
  call library_value('concrete48', 'hjc_mucrush', mm_us, v, found)
  call check(found .and. abs(v - 0.001_wp) <= 0.0_wp, 'library: hjc_mucrush (dimensionless) as it is')
  call library_value('steel1045', 'jc_a', mm_ms, v, found)
  call check(found .and. abs(v - 507.0_wp) <= 0.0_wp, 'library: steel1045 jc_a in its own units is 507 exactly')
  call library_value('steel1045', 'youngs_modulus', 'SI', v, found)
  call check_close('library: steel1045 E in Pa', v, 2.1e11_wp, rel*2.1e11_wp)
  call library_value('steel1045', 'jc_eps0', 'SI', v, found)
  call check_close('library: steel1045 jc_eps0 1/ms in 1/s', v, 1.0_wp, rel)
  call library_value('steel1045', 'jc_m', 'SI', v, found)
  call check(.not. found, 'library: steel1045 has no jc_m (the paper''s JC has no temperature)')

  ! a solid of an entry: the entry's values in the deck's units
  call read_solid('library = ''copper''', mm_ms)
  call check(size(problems) == 0, 'solid copper in mm-ms-g/mm^3-MPa: no problem')
  call check_close('solid copper: density in g/mm^3', sc%density, 8.93e-3_wp, rel*8.93e-3_wp)
  call check_close('solid copper: jc_a in MPa', sc%jc_a, 90.0_wp, rel*90.0_wp)
  call check_close('solid copper: G in MPa', sc%shear_modulus, 47700.0_wp, rel*47700.0_wp)
  call check_close('solid copper: EOS c0 in mm/ms', sc%par%c0, 3940.0_wp, rel*3940.0_wp)
  call check_close('solid copper: EOS rho0 = its density', sc%par%rho0, sc%density, 0.0_wp)
  call check(sc%strength == 'johnson_cook' .and. sc%eos == 'mie_gruneisen', 'solid copper: johnson_cook, mie_gruneisen')
  call check(abs(sc%t_melt - 1356.0_wp) <= 0.0_wp .and. abs(sc%jc_m - 1.09_wp) <= 0.0_wp, &
             'solid copper: t_melt 1356 K and jc_m 1.09 as they are')
  call check_close('solid copper: specific_heat in (mm/ms)^2/K', sc%specific_heat, 383.0_wp, rel*383.0_wp)
  call check(abs(sc%t_room - 293.15_wp) <= 0.0_wp .and. abs(sc%taylor_quinney - 0.9_wp) <= 0.0_wp, &
             'solid copper: t_room and taylor_quinney the &solid defaults (the entry has none)')
  ! the group's own variables override the entry's
  call read_solid('library = ''copper'', jc_a = 120, density = 8.96e-3', mm_ms)
  call check(abs(sc%jc_a - 120.0_wp) <= 0.0_wp .and. abs(sc%density - 8.96e-3_wp) <= 0.0_wp, &
             'solid copper: the group''s jc_a and density override the entry''s')
  call check_close('solid copper: ... and the other values stay the entry''s', sc%jc_b, 292.0_wp, rel*292.0_wp)
  call read_solid('library = ''copper'', youngs_modulus = 120000, poisson_ratio = 0.34', mm_ms)
  call check(size(problems) == 0, 'solid copper with its own E and nu: no problem (the entry''s G is not taken)')
  call check_close('solid copper: G from the group''s E and nu', sc%shear_modulus, 120000.0_wp/2.68_wp, &
                   rel*120000.0_wp)
  ! a model takes only its own parameters: steel1045 as a gurson matrix
  call read_solid('library = ''steel1045'', strength = ''gurson'', gtn_fc = 0.2109, void_mean = 0.005', mm_ms)
  call check(size(problems) == 0, 'solid steel1045 as gurson: no problem')
  call check(abs(sc%jc_a - 507.0_wp) <= 0.0_wp .and. abs(sc%jc_c - 0.064_wp) <= 0.0_wp, &
             'solid steel1045 as gurson: its matrix jc_a, jc_c from the entry')
  call read_solid('library = ''copper'', strength = ''gurson'', gtn_fc = 0.2, void_mean = 0.005', mm_ms)
  call check(size(problems) == 0 .and. abs(sc%jc_m) <= 0.0_wp .and. abs(sc%specific_heat) <= 0.0_wp, &
             'solid copper as gurson: no jc_m, specific_heat (gurson has no temperature)')
  call read_solid('library = ''copper'', strength = ''elastic''', mm_ms)
  call check(size(problems) == 0 .and. abs(sc%jc_a) <= 0.0_wp, 'solid copper as elastic: no Johnson-Cook parameter')
  call read_solid('library = ''concrete48''', mm_ms)
  call check_close('solid concrete48: hjc_plock in MPa', sc%hjc%hjc_plock, 800.0_wp, rel*800.0_wp)
  call check(sc%eos == 'none', 'solid concrete48: eos none (HJC has its own)')
  ! refusals
  call read_solid('library = ''steel4340''', 'SI')
  call check(size(problems) > 0, 'solid steel4340 without moduli: refused (shear_modulus required)')
  call read_solid('library = ''unobtainium''', 'SI')
  call check(size(problems) > 0, 'solid of an unknown entry: refused')
  if (size(problems) > 0) call check(index(problems(1), 'is not in the material library') > 0, &
                                     'solid of an unknown entry: the message says so')
  call read_solid('library = ''copper''', '')
  call check(size(problems) > 0, 'solid of a library entry without &run units: refused')
  call check_summary('test_material_library')

contains

  !> `sc` and `problems` of the &solid group with variables `vars` in `units`.
  subroutine read_solid(vars, units)
    character(len=*), intent(in) :: vars, units
    character(len=max_line) :: text(1)
    text(1) = '&solid name = ''s'', '//vars//' /'
    problems = [character(len=max_line) ::]
    call solid_config_read(sc, 1, text, 'test.nml', [character(len=64) ::], units, no_echo, problems)
  end subroutine read_solid
end program test_material_library
