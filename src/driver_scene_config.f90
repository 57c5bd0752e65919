!> The &region, &source, &detonation and &prerun groups: the initial state
!> of a scene (shapes filled with a material state, energy deposited at
!> points, the initiators of explosives, and a 1D pre-run mapped in), read by
!> `driver_scene`.
module driver_scene_config
  use base_kinds, only: wp
  use mesh_shapes, only: shape_inner_radius_problem
  use base_strings, only: itoa, rtoa
  use base_config, only: max_line, no_echo, problem_long, problem_add, problem_bad, problem_nml, diff_i, diff_r, diff_s, name_index
  implicit none
  private
  public :: region_config_t, source_config_t, region_config_read, source_config_read, scene_config_changes, &
            detonation_config_t, detonation_config_read, prerun_config_t, prerun_config_read

  !> One &region group: a shape filled with a material state; the initial
  !> values are the defaults (negative energies: not given).
  type :: region_config_t
    character(len=16) :: shape = 'all'                !< all, box, sphere, cylinder, half_space
    character(len=64) :: material = ''                !< a &material name
    integer :: imat = 0                               !< its index (resolved)
    real(wp) :: density = 0.0_wp                      !< density (required, > 0)
    real(wp) :: energy = -1.0_wp                      !< specific internal energy
    real(wp) :: pressure = -1.0_wp                    !< pressure (energy from the EOS)
    real(wp) :: energy_per_volume = -1.0_wp           !< internal energy per volume (becomes energy)
    real(wp) :: velocity(3) = 0.0_wp                  !< node velocity (length/time)
    character(len=16) :: velocity_field = 'uniform'   !< uniform, radial, rotation (about center)
    real(wp) :: speed = 0.0_wp                        !< radial: speed along (x - center)/|x - center|
    real(wp) :: angular_velocity = 0.0_wp             !< rotation: radians per time about axis
    real(wp) :: lo(3) = -huge(1.0_wp), hi(3) = huge(1.0_wp)   !< box corners, cylinder length
    real(wp) :: center(3) = 0.0_wp, radius = 0.0_wp   !< sphere / cylinder
    real(wp) :: inner_radius = 0.0_wp                 !< sphere / cylinder: hollow inside it
    real(wp) :: normal(3) = [1.0_wp, 0.0_wp, 0.0_wp]  !< half space normal
    integer :: axis = 3                               !< cylinder and rotation axis: 1 x, 2 y, 3 z
  end type region_config_t

  !> One &source group: energy deposited in the cell containing a point.
  type :: source_config_t
    real(wp) :: position(3) = 0.0_wp    !< the point (length)
    real(wp) :: energy = 0.0_wp         !< total energy deposited (required, > 0)
  end type source_config_t

  !> One &detonation group: an initiator lighting an explosive (programmed
  !> burn, `material_burn`) at `time`.
  type :: detonation_config_t
    character(len=64) :: material = ''                !< the explosive's &material name (eos jwl)
    integer :: imat = 0                               !< its index (resolved)
    character(len=16) :: shape = 'point'              !< point, line (point..point2), plane (point, normal)
    real(wp) :: point(3) = 0.0_wp                     !< the point, a line's start, a point of the plane (length)
    real(wp) :: point2(3) = 0.0_wp                    !< a line's end (length)
    real(wp) :: normal(3) = [1.0_wp, 0.0_wp, 0.0_wp]  !< a plane's normal
    real(wp) :: time = 0.0_wp                         !< lighting time of the initiator (time)
    character(len=16) :: path = 'straight'            !< straight, or around (shortest path through the explosive)
  end type detonation_config_t

  !> The &prerun group: the charge's free expansion run first in one
  !> dimension (spherical, `spherical_lagrange`) and mapped into the grid at
  !> `time` (`driver_prerun`); absent (time = 0): no pre-run.
  type :: prerun_config_t
    real(wp) :: time = 0.0_wp                       !< when the 1D run is mapped (time, required, > 0)
    real(wp) :: center(3) = huge(1.0_wp)            !< the centre (length; default: the sphere regions')
    real(wp) :: radius = 0.0_wp                     !< the 1D domain's radius (0: the grid box's farthest corner)
    real(wp) :: zone_width = 0.0_wp                 !< 1D zone width (0: the smallest sphere radius / 100)
    real(wp) :: far_zone_width = 0.0_wp             !< widest 1D zone beyond the outermost sphere (0: 10 zone_width)
    real(wp) :: map_radius = 0.0_wp                 !< mapped within (0: the shock's radius + 2 cells)
    integer :: subsamples = 8                       !< sub-boxes per cell edge for the overlaps
    real(wp) :: cfl = 0.5_wp                        !< the 1D run's Courant number
    real(wp) :: q_linear = 0.1_wp                   !< the 1D run's linear viscosity coefficient
    real(wp) :: q_quad = 1.5_wp                     !< the 1D run's quadratic viscosity coefficient
    real(wp) :: merge_ratio = 20.0_wp               !< thin zones merge (`sphere_merge`; 0: never)
  end type prerun_config_t

contains

  !> Reads, validates and echoes the r-th &region group (`text`);
  !> `materials` are the &material names.
  subroutine region_config_read(this, r, text, path, materials, echo, problems, lib, units)
    type(region_config_t), intent(out) :: this
    integer, intent(in) :: r, echo
    character(len=*), intent(in) :: text(:), path, materials(:)
    !> per material: its library entry's density, energy_per_volume and
    !> pressure in the deck's units (< 0: none), and those units
    real(wp), intent(in), optional :: lib(:, :)
    character(len=*), intent(in), optional :: units
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=16) :: shape, velocity_field
    character(len=64) :: material
    character(len=1) :: axis
    real(wp) :: density, energy, pressure, energy_per_volume, e_given, velocity(3), lo(3), hi(3), center(3), radius, &
              normal(3), speed, angular_velocity, inner_radius
    integer :: ios, m
    character(len=max_line) :: msg
    character(len=16) :: tag
    namelist /region/ shape, material, density, energy, pressure, energy_per_volume, velocity, velocity_field, &
                      speed, angular_velocity, lo, hi, center, radius, axis, normal, inner_radius

    shape = this%shape; material = this%material; density = this%density; energy = this%energy
    pressure = this%pressure; energy_per_volume = this%energy_per_volume
    velocity = this%velocity; lo = this%lo; hi = this%hi; center = this%center; radius = this%radius
    normal = this%normal; velocity_field = this%velocity_field; speed = this%speed
    angular_velocity = this%angular_velocity; inner_radius = this%inner_radius
    axis = 'xyz'(this%axis:this%axis)
    read(text, nml=region, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_nml(problems, path, 'region', ios, msg)
      return
    end if
    write(tag, '(a,i0,a)') 'region(', r, ')'
    call problem_long(problems, trim(tag), 'shape', shape)
    call problem_long(problems, trim(tag), 'material', material)
    m = name_index(materials, material)
    if (m == 0 .and. len_trim(material) == 0 .and. size(materials) == 1) m = 1
    ! a library material: its entry's density and energy where the region
    ! gives none, and a density far from the entry's refused (a deck in
    ! another unit system than its &run units says)
    if (present(lib) .and. m > 0) then
      if (lib(1, m) > 0.0_wp) then
        ! (not given: the default 0 exactly; a negative or NaN density given
        ! is refused below, not replaced)
        if (density >= 0.0_wp .and. density <= 0.0_wp) then
          density = lib(1, m)
        else if (density > 0.0_wp .and. (density > 10.0_wp*lib(1, m) .or. density < 0.1_wp*lib(1, m))) then
          call problem_add(problems, '&'//trim(tag)//': density = '//rtoa(density)//' is '// &
            rtoa(density/lib(1, m))//' times the library''s '//rtoa(lib(1, m))//' for '''//trim(material)// &
            ''' in &run units '''//trim(units)//''': are the deck''s values in another unit system?')
        end if
      end if
      if (count([energy >= 0.0_wp, pressure >= 0.0_wp, energy_per_volume >= 0.0_wp]) == 0) then
        if (lib(2, m) >= 0.0_wp) then
          energy_per_volume = lib(2, m)
        else if (lib(3, m) >= 0.0_wp) then
          pressure = lib(3, m)
        end if
      end if
    end if
    if (.not. (density > 0.0_wp)) call problem_bad(problems, trim(tag), 'density', density, 'must be > 0')
    if (count([energy >= 0.0_wp, pressure >= 0.0_wp, energy_per_volume >= 0.0_wp]) /= 1) &
      call problem_add(problems, '&'//trim(tag)//': give exactly one of energy (specific internal energy), '// &
               'pressure and energy_per_volume, >= 0')
    ! an energy per unit volume (as explosive charges are given) is a
    ! specific energy of energy_per_volume / density
    ! (kept out of the echo, which must read back as given: a restart reads it)
    e_given = energy
    if (energy_per_volume >= 0.0_wp .and. density > 0.0_wp) e_given = energy_per_volume/density
    if (.not. (radius >= 0.0_wp)) call problem_bad(problems, trim(tag), 'radius', radius, 'must be >= 0')
    msg = shape_inner_radius_problem(shape, radius, inner_radius)
    if (len_trim(msg) > 0) call problem_bad(problems, trim(tag), 'inner_radius', inner_radius, trim(msg))
    select case (trim(shape))
    case ('all', 'box')
    case ('half_space')
      if (.not. (norm2(normal) > 0.0_wp)) call problem_add(problems, '&'//trim(tag)// &
        ': normal must not be zero for shape = ''half_space''')
    case ('sphere', 'cylinder')
      if (radius >= 0.0_wp .and. .not. (radius > 0.0_wp)) call problem_bad(problems, trim(tag), 'radius', &
        radius, 'must be > 0 for shape = '''//trim(shape)//'''')
    case default
      call problem_add(problems, '&'//trim(tag)//': shape = '''//trim(shape)// &
        ''' is not known; valid: all, box, sphere, cylinder, half_space')
    end select
    if (index('xyz', axis) == 0 .or. len_trim(axis) == 0) call problem_add(problems, &
      '&'//trim(tag)//': axis = '''//trim(axis)//''' is not known; valid: x, y, z')
    call velocity_field_problems(trim(tag), velocity_field, speed, angular_velocity, problems)
    if (m == 0) call problem_add(problems, '&'//trim(tag)//': material = '''//trim(material)// &
      ''' is not a &material name')
    this = region_config_t(shape=shape, material=material, imat=m, density=density, &
      energy=e_given, pressure=pressure, energy_per_volume=energy_per_volume, velocity=velocity, &
      velocity_field=velocity_field, speed=speed, angular_velocity=angular_velocity, lo=lo, hi=hi, center=center, &
      radius=radius, inner_radius=inner_radius, axis=max(1, index('xyz', axis)), normal=normal)
    if (echo /= no_echo) write(echo, nml=region)
  end subroutine region_config_read

  !> The problems of a region's initial velocity field: an unknown field, a
  !> speed or angular velocity given to a field that does not use it (most
  !> likely the field was forgotten: the value would be ignored), or a field
  !> without the value it needs (it would be a uniform one).
  subroutine velocity_field_problems(tag, field, speed, angular_velocity, problems)
    character(len=*), intent(in) :: tag, field
    real(wp), intent(in) :: speed, angular_velocity
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    call problem_long(problems, tag, 'velocity_field', field)
    select case (trim(field))
    case ('uniform', 'radial', 'rotation')
    case default
      call problem_add(problems, '&'//tag//': velocity_field = '''//trim(field)// &
        ''' is not known; valid: uniform, radial, rotation')
      return
    end select
    if (abs(speed) > 0.0_wp .and. field /= 'radial') call problem_bad(problems, tag, 'speed', speed, &
      'applies only to velocity_field = ''radial'' (this region''s is '''//trim(field)//''')')
    if (abs(angular_velocity) > 0.0_wp .and. field /= 'rotation') call problem_bad(problems, tag, 'angular_velocity', &
      angular_velocity, 'applies only to velocity_field = ''rotation'' (this region''s is '''//trim(field)//''')')
    if (field == 'radial' .and. .not. abs(speed) > 0.0_wp) call problem_add(problems, '&'//tag// &
      ': velocity_field = ''radial'' needs a speed (not 0; < 0 is inward)')
    if (field == 'rotation' .and. .not. abs(angular_velocity) > 0.0_wp) call problem_add(problems, '&'//tag// &
      ': velocity_field = ''rotation'' needs an angular_velocity (not 0; radians per unit time)')
  end subroutine velocity_field_problems

  !> Reads, validates and echoes the s-th &source group (`text`); the point
  !> must lie in the grid box xmin..xmax.
  subroutine source_config_read(this, s, text, path, xmin, xmax, echo, problems)
    type(source_config_t), intent(out) :: this
    integer, intent(in) :: s, echo
    character(len=*), intent(in) :: text(:), path
    real(wp), intent(in) :: xmin(3), xmax(3)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    real(wp) :: position(3), energy
    integer :: ios
    character(len=max_line) :: msg
    character(len=16) :: tag
    namelist /source/ position, energy

    position = this%position; energy = this%energy
    read(text, nml=source, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_nml(problems, path, 'source', ios, msg)
      return
    end if
    write(tag, '(a,i0,a)') 'source(', s, ')'
    if (.not. (energy > 0.0_wp)) call problem_bad(problems, trim(tag), 'energy', energy, 'must be > 0')
    if (any(position < xmin) .or. any(position > xmax)) call problem_add(problems, &
      '&'//trim(tag)//': position is outside the grid box xmin..xmax')
    this = source_config_t(position=position, energy=energy)
    if (echo /= no_echo) write(echo, nml=source)
  end subroutine source_config_read

  !> Reads, validates and echoes the d-th &detonation group (`text`);
  !> `materials` and `eos` are the &material names and their EOS names.
  subroutine detonation_config_read(this, d, text, deck_file, materials, eos, echo, problems)
    type(detonation_config_t), intent(out) :: this
    integer, intent(in) :: d, echo
    character(len=*), intent(in) :: text(:), deck_file, materials(:), eos(:)
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=16) :: shape, path
    character(len=64) :: material
    real(wp) :: point(3), point2(3), normal(3), time
    integer :: ios
    character(len=max_line) :: msg
    character(len=24) :: tag
    namelist /detonation/ material, shape, point, point2, normal, time, path

    material = this%material; shape = this%shape; point = this%point; point2 = this%point2
    normal = this%normal; time = this%time; path = this%path
    read(text, nml=detonation, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_nml(problems, deck_file, 'detonation', ios, msg)
      return
    end if
    write(tag, '(a,i0,a)') 'detonation(', d, ')'
    call problem_long(problems, trim(tag), 'material', material)
    call problem_long(problems, trim(tag), 'shape', shape)
    call problem_long(problems, trim(tag), 'path', path)
    this%imat = name_index(materials, material)
    if (this%imat == 0) then
      call problem_add(problems, '&'//trim(tag)//': material = '''//trim(material)//''' is not a &material name')
    else if (eos(this%imat) /= 'jwl') then
      call problem_add(problems, '&'//trim(tag)//': material '''//trim(material)//''' has eos = '''// &
                       trim(eos(this%imat))//'''; a detonation lights an explosive (eos = ''jwl'')')
    end if
    select case (shape)
    case ('point')
    case ('line')
      if (.not. norm2(point2 - point) > 0.0_wp) call problem_add(problems, '&'//trim(tag)//': a line needs point2 /= point')
    case ('plane')
      if (.not. norm2(normal) > 0.0_wp) call problem_add(problems, '&'//trim(tag)//': a plane needs a normal /= 0')
    case default
      call problem_add(problems, '&'//trim(tag)//': shape = '''//trim(shape)//''' is not one of point, line, plane')
    end select
    select case (path)
    case ('straight')
    case ('around')
      if (shape /= 'point') call problem_add(problems, '&'//trim(tag)//': path = ''around'' is for '// &
                                             'shape = ''point'' (lines and planes light in straight lines)')
    case default
      call problem_add(problems, '&'//trim(tag)//': path = '''//trim(path)// &
                       ''' is not one of straight, around')
    end select
    if (.not. abs(time) < 0.5_wp*huge(1.0_wp)) call problem_bad(problems, trim(tag), 'time', time, 'must be finite')
    this%material = material; this%shape = shape; this%point = point; this%point2 = point2
    this%normal = normal; this%time = time; this%path = path
    if (echo /= no_echo) write(echo, nml=detonation)
  end subroutine detonation_config_read

  !> Reads, validates and echoes the &prerun group (`text`; none: this%time
  !> stays 0).
  subroutine prerun_config_read(this, text, deck_file, echo, problems)
    type(prerun_config_t), intent(out) :: this
    character(len=*), intent(in) :: text(:), deck_file
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    real(wp) :: time, center(3), radius, zone_width, far_zone_width, map_radius, cfl, q_linear, q_quad, merge_ratio
    integer :: subsamples, ios
    character(len=max_line) :: msg
    namelist /prerun/ time, center, radius, zone_width, far_zone_width, map_radius, subsamples, cfl, q_linear, q_quad, &
                      merge_ratio

    time = this%time; center = this%center; radius = this%radius; zone_width = this%zone_width
    far_zone_width = this%far_zone_width
    map_radius = this%map_radius; subsamples = this%subsamples; cfl = this%cfl
    q_linear = this%q_linear; q_quad = this%q_quad; merge_ratio = this%merge_ratio
    read(text, nml=prerun, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_nml(problems, deck_file, 'prerun', ios, msg)
      return
    end if
    if (.not. (time > 0.0_wp .and. time < 0.5_wp*huge(1.0_wp))) &
      call problem_bad(problems, 'prerun', 'time', time, 'must be > 0 (when the 1D run is mapped into the grid)')
    if (radius < 0.0_wp) call problem_bad(problems, 'prerun', 'radius', radius, 'must be >= 0')
    if (zone_width < 0.0_wp) call problem_bad(problems, 'prerun', 'zone_width', zone_width, 'must be >= 0')
    if (.not. far_zone_width >= 0.0_wp) &
      call problem_bad(problems, 'prerun', 'far_zone_width', far_zone_width, 'must be >= 0')
    if (map_radius < 0.0_wp) call problem_bad(problems, 'prerun', 'map_radius', map_radius, 'must be >= 0')
    if (subsamples < 1 .or. subsamples > 64) call problem_add(problems, '&prerun: subsamples = '//itoa(subsamples)// &
                                                              ' must be 1..64')
    if (.not. (cfl > 0.0_wp .and. cfl <= 1.0_wp)) call problem_bad(problems, 'prerun', 'cfl', cfl, 'must be in (0, 1]')
    if (.not. (q_linear >= 0.0_wp .and. q_linear <= 10.0_wp)) &
      call problem_bad(problems, 'prerun', 'q_linear', q_linear, 'must be in [0, 10]')
    if (.not. (q_quad > 0.0_wp .and. q_quad <= 10.0_wp)) &
      call problem_bad(problems, 'prerun', 'q_quad', q_quad, 'must be in (0, 10]')
    if (.not. (merge_ratio >= 10.0_wp .or. (merge_ratio >= 0.0_wp .and. merge_ratio <= 0.0_wp))) &
      call problem_bad(problems, 'prerun', 'merge_ratio', merge_ratio, 'must be 0 (no merges) or >= 10')
    this = prerun_config_t(time=time, center=center, radius=radius, zone_width=zone_width, &
                           far_zone_width=far_zone_width, map_radius=map_radius, &
                           subsamples=subsamples, cfl=cfl, q_linear=q_linear, q_quad=q_quad, merge_ratio=merge_ratio)
    if (echo /= no_echo) write(echo, nml=prerun)
  end subroutine prerun_config_read

  !> What a restart may not change in the regions and sources: one line per
  !> changed variable.
  subroutine scene_config_changes(old_regions, new_regions, old_sources, new_sources, old_det, new_det, changes)
    type(region_config_t), intent(in) :: old_regions(:), new_regions(:)
    type(source_config_t), intent(in) :: old_sources(:), new_sources(:)
    type(detonation_config_t), intent(in) :: old_det(:), new_det(:)
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    integer :: k
    call diff_i(changes, 'number of &region groups', size(old_regions), size(new_regions))
    do k = 1, min(size(old_regions), size(new_regions))
      associate (a => old_regions(k), b => new_regions(k))
        call diff_s(changes, '&region('//itoa(k)//') shape', a%shape, b%shape)
        call diff_s(changes, '&region('//itoa(k)//') material', a%material, b%material)
        call diff_r(changes, '&region('//itoa(k)//') density', [a%density], [b%density])
        call diff_r(changes, '&region('//itoa(k)//') energy', [a%energy], [b%energy])
        call diff_r(changes, '&region('//itoa(k)//') pressure', [a%pressure], [b%pressure])
        call diff_r(changes, '&region('//itoa(k)//') velocity', a%velocity, b%velocity)
        call diff_s(changes, '&region('//itoa(k)//') velocity_field', a%velocity_field, b%velocity_field)
        call diff_r(changes, '&region('//itoa(k)//') speed', [a%speed], [b%speed])
        call diff_r(changes, '&region('//itoa(k)//') angular_velocity', [a%angular_velocity], [b%angular_velocity])
        call diff_r(changes, '&region('//itoa(k)//') lo', a%lo, b%lo)
        call diff_r(changes, '&region('//itoa(k)//') hi', a%hi, b%hi)
        call diff_r(changes, '&region('//itoa(k)//') center', a%center, b%center)
        call diff_r(changes, '&region('//itoa(k)//') radius', [a%radius], [b%radius])
        call diff_r(changes, '&region('//itoa(k)//') inner_radius', [a%inner_radius], [b%inner_radius])
        call diff_i(changes, '&region('//itoa(k)//') axis', a%axis, b%axis)
        call diff_r(changes, '&region('//itoa(k)//') normal', a%normal, b%normal)
      end associate
    end do
    call diff_i(changes, 'number of &source groups', size(old_sources), size(new_sources))
    do k = 1, min(size(old_sources), size(new_sources))
      call diff_r(changes, '&source('//itoa(k)//') position', old_sources(k)%position, new_sources(k)%position)
      call diff_r(changes, '&source('//itoa(k)//') energy', [old_sources(k)%energy], [new_sources(k)%energy])
    end do
    call diff_i(changes, 'number of &detonation groups', size(old_det), size(new_det))
    do k = 1, min(size(old_det), size(new_det))
      associate (a => old_det(k), b => new_det(k))
        call diff_s(changes, '&detonation('//itoa(k)//') material, shape, path', &
                    trim(a%material)//' '//trim(a%shape)//' '//trim(a%path), trim(b%material)//' '//trim(b%shape)//' '// &
                    trim(b%path))
        call diff_r(changes, '&detonation('//itoa(k)//') point, point2, normal, time', &
                    [a%point, a%point2, a%normal, a%time], [b%point, b%point2, b%normal, b%time])
      end associate
    end do
  end subroutine scene_config_changes
end module driver_scene_config
