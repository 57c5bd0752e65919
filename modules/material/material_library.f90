!> The material library (`input/materials.txt`, built in as
!> `material_library_data`) and the unit systems a deck may declare
!> (&run units): an entry's values converted to the deck's system.
!>
!> A unit system is a length, time and mass unit (in metres, seconds and
!> kilograms); every other unit follows from them (density M/L^3, pressure
!> M/(L T^2), velocity L/T, specific energy L^2/T^2). A value converts from
!> the entry's system to the deck's by the ratio of the two systems' units
!> raised to the key's dimension; the same system converts nothing (the
!> value is the entry's text, read exactly).
module material_library
  use base_kinds, only: wp
  use material_library_data, only: library_lines
  implicit none
  private
  public :: units_known, units_list, library_names, library_has, library_value, library_text

  !> The unit systems: name, then length, time and mass units in SI.
  integer, parameter :: nsys = 6
  character(len=*), parameter :: sys_names(nsys) = [character(len=20) :: 'SI', 'mm-us-g/cm^3-GPa', &
    'cm-us-g-Mbar', 'mm-ms-g/mm^3-MPa', 'mm-s-t-MPa', 'cm-s-g-dyn']
  real(wp), parameter :: sys_units(3, nsys) = reshape([ &
    1.0_wp, 1.0_wp, 1.0_wp, &          ! m, s, kg
    1.0e-3_wp, 1.0e-6_wp, 1.0e-6_wp, & ! mm, us, mg (g/cm^3 x mm^3): GPa, km/s
    1.0e-2_wp, 1.0e-6_wp, 1.0e-3_wp, & ! cm, us, g: Mbar
    1.0e-3_wp, 1.0e-3_wp, 1.0e-3_wp, & ! mm, ms, g: MPa, g/mm^3, mJ/g (the paper's)
    1.0e-3_wp, 1.0_wp, 1.0e3_wp, &     ! mm, s, tonne: MPa, t/mm^3
    1.0e-2_wp, 1.0_wp, 1.0e-3_wp], &   ! cm, s, g: dyn/cm^2
    [3, nsys])

  !> The library keys with a dimension, by dimension ((L, T, M) exponents in
  !> `key_dimension`): the EOS keys of &material and the &solid keys (its
  !> EOS, elastic moduli and strength models). Temperatures (t_room, t_melt)
  !> are kelvin in every system (a degree is the same size in all six), so
  !> they, like the dimensionless keys, convert to themselves; a specific
  !> heat is energy per mass per kelvin, L^2 T^-2.
  character(len=*), parameter :: pressure_keys(*) = [character(len=20) :: 'a', 'b', 'energy_per_volume', &
    'pressure', 'p_min', 'cj_pressure', 'bulk_modulus', 'shear_modulus', 'youngs_modulus', 'yield_stress', &
    'tangent_modulus', 'tensile_strength', 'jc_a', 'jc_b', 'hjc_fc', 'hjc_t', 'hjc_pcrush', 'hjc_plock', 'hjc_k1', &
    'hjc_k2', 'hjc_k3']
  character(len=*), parameter :: density_keys(*) = [character(len=20) :: 'rho0', 'density']
  character(len=*), parameter :: velocity_keys(*) = [character(len=20) :: 'c0', 'cj_velocity']
  character(len=*), parameter :: rate_keys(*) = [character(len=20) :: 'jc_eps0', 'hjc_eps0']
  !> specific energy; a specific heat (per kelvin) converts the same way
  character(len=*), parameter :: specific_keys(*) = [character(len=20) :: 'energy', 'specific_heat']
  character(len=*), parameter :: plain_keys(*) = [character(len=20) :: 'gamma', 'r1', 'r2', 'omega', 's1', &
    'gamma0', 'poisson_ratio', 'jc_n', 'jc_c', 'jc_m', 't_room', 't_melt', 'taylor_quinney', 'failure_strain', &
    'gtn_q1', 'gtn_q2', 'gtn_fn', 'gtn_epsn', 'gtn_sn', 'gtn_fc', 'gtn_ff', 'hjc_a', 'hjc_b', 'hjc_n', 'hjc_c', &
    'hjc_smax', 'hjc_d1', 'hjc_d2', 'hjc_efmin', 'hjc_mucrush', 'hjc_mulock']

contains

  !> `units` is a unit system the library can convert to.
  pure logical function units_known(units)
    character(len=*), intent(in) :: units
    units_known = any(sys_names == units)
  end function units_known

  !> The known unit systems, for messages.
  pure function units_list() result(text)
    character(len=:), allocatable :: text
    integer :: k
    text = trim(sys_names(1))
    do k = 2, nsys
      text = text//', '//trim(sys_names(k))
    end do
  end function units_list

  !> The entries' names, for messages.
  pure function library_names() result(text)
    character(len=:), allocatable :: text
    integer :: i
    text = ''
    do i = 1, size(library_lines)
      if (entry_name(library_lines(i)) == '') cycle
      if (len(text) > 0) text = text//', '
      text = text//entry_name(library_lines(i))
    end do
  end function library_names

  !> The library has an entry `name`.
  pure logical function library_has(name)
    character(len=*), intent(in) :: name
    library_has = entry_start(name) > 0
  end function library_has

  !> The text of key `key` of entry `name` ('' if it has none).
  pure function library_text(name, key) result(text)
    character(len=*), intent(in) :: name, key
    character(len=:), allocatable :: text
    integer :: i, eq
    character(len=len(library_lines)) :: line
    text = ''
    i = entry_start(name)
    if (i == 0) return
    do i = i + 1, size(library_lines)
      line = uncomment(library_lines(i))
      if (entry_name(line) /= '') return
      eq = index(line, '=')
      if (eq == 0) cycle
      if (trim(adjustl(line(1:eq - 1))) == key) then
        text = trim(adjustl(line(eq + 1:)))
        return
      end if
    end do
  end function library_text

  !> The value of key `key` of entry `name` in the unit system `units`;
  !> found false if the entry has no such key (or `units` is not known).
  pure subroutine library_value(name, key, units, value, found)
    character(len=*), intent(in) :: name, key, units
    real(wp), intent(out) :: value
    logical, intent(out) :: found
    character(len=:), allocatable :: text, from
    integer :: ios, dims(3), s0, s1
    logical :: known
    value = 0.0_wp
    text = library_text(name, key)
    from = library_text(name, 'units')
    found = .false.
    if (len(text) == 0 .or. .not. units_known(units)) return
    read(text, *, iostat=ios) value
    if (ios /= 0) return
    found = .true.
    if (from == units) return
    call key_dimension(key, dims, known)
    s0 = sys_index(from)
    s1 = sys_index(units)
    if (.not. known .or. s0 == 0) then
      found = .false.
      return
    end if
    value = value*product((sys_units(:, s0)/sys_units(:, s1))**dims)
  end subroutine library_value

  !> The index of unit system `name` in `sys_names` (0: none). (A loop:
  !> gfortran 12's findloc on these character arrays missed names it holds.)
  pure integer function sys_index(name) result(k)
    character(len=*), intent(in) :: name
    do k = 1, nsys
      if (sys_names(k) == name) return
    end do
    k = 0
  end function sys_index

  !> The dimension of library key `key`: (L, T, M) exponents; known false
  !> for a key that has none in the lists above (its value cannot convert).
  pure subroutine key_dimension(key, dims, known)
    character(len=*), intent(in) :: key
    integer, intent(out) :: dims(3)
    logical, intent(out) :: known
    known = .true.
    if (any(pressure_keys == key)) then
      dims = [-1, -2, 1]
    else if (any(density_keys == key)) then
      dims = [-3, 0, 1]
    else if (any(velocity_keys == key)) then
      dims = [1, -1, 0]
    else if (any(rate_keys == key)) then
      dims = [0, -1, 0]
    else if (any(specific_keys == key)) then
      dims = [2, -2, 0]
    else
      dims = 0
      known = any(plain_keys == key)
    end if
  end subroutine key_dimension

  !> The line of entry `name`'s header (0: none).
  pure integer function entry_start(name) result(i)
    character(len=*), intent(in) :: name
    do i = 1, size(library_lines)
      if (entry_name(library_lines(i)) == name) return
    end do
    i = 0
  end function entry_start

  !> The name of an entry header line '[name]' ('' for any other line).
  pure function entry_name(line) result(name)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: name
    character(len=:), allocatable :: s
    s = trim(adjustl(uncomment(line)))   ! (allocated by the assignment)
    name = ''
    if (len(s) < 3) return
    if (s(1:1) == '[' .and. s(len(s):len(s)) == ']') name = trim(adjustl(s(2:len(s) - 1)))
  end function entry_name

  !> A line without its comment (from '#').
  pure function uncomment(line) result(s)
    character(len=*), intent(in) :: line
    character(len=len(line)) :: s
    integer :: h
    h = index(line, '#')
    s = line
    if (h > 0) s = line(1:h - 1)
  end function uncomment
end module material_library
