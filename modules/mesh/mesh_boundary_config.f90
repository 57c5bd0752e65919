!> The &boundary group: one condition per face of the block, and the state
!> that enters through inflow faces.
module mesh_boundary_config
  use base_kinds, only: wp
  use base_strings, only: itoa
  use base_config, only: max_line, no_echo, problem_long, problem_add, problem_bad, problem_nml, diff_i, diff_r, name_index
  use mesh_boundary, only: bc_kind_from_name, bc_kind_names, BC_SYMMETRY, BC_INFLOW, bc_max_fixed
  implicit none
  private
  public :: boundary_config_t, boundary_config_read, boundary_config_changes, face_names

  character(len=*), parameter :: face_names(6) = ['xlo', 'xhi', 'ylo', 'yhi', 'zlo', 'zhi']

  !> The resolved &boundary group, per face 1 xlo, 2 xhi, 3 ylo, 4 yhi, 5 zlo,
  !> 6 zhi; the initial values are the defaults.
  type :: boundary_config_t
    integer :: kind(6) = BC_SYMMETRY                !< `mesh_boundary` kind of each face
    real(wp) :: velocity(3, 6) = 0.0_wp             !< velocity of a velocity or inflow face
    real(wp) :: pressure(6) = 0.0_wp                !< pressure on a pressure face
    integer :: inflow_mat(6) = 0                    !< material entering an inflow face (index)
    real(wp) :: inflow_density(6) = 0.0_wp          !< its density
    real(wp) :: inflow_pressure(6) = 0.0_wp         !< its pressure
    integer :: nfixed = 0                           !< fixed boxes given (the first nfixed)
    real(wp) :: fixed_box(6, bc_max_fixed) = 0.0_wp !< each one's lo(3), hi(3)
  end type boundary_config_t

contains

  !> Reads, validates and echoes the &boundary group (`text` empty: all
  !> defaults); `materials` are the &material names inflow faces refer to.
  subroutine boundary_config_read(this, text, path, materials, echo, problems)
    type(boundary_config_t), intent(out) :: this
    character(len=*), intent(in) :: text(:), path, materials(:)
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=16) :: xlo, xhi, ylo, yhi, zlo, zhi, kinds(6)
    real(wp) :: xlo_velocity(3), xhi_velocity(3), ylo_velocity(3), yhi_velocity(3), &
                zlo_velocity(3), zhi_velocity(3)
    real(wp) :: xlo_pressure, xhi_pressure, ylo_pressure, yhi_pressure, zlo_pressure, zhi_pressure
    character(len=64) :: inflow_material(6)
    real(wp) :: inflow_density(6), inflow_pressure(6)
    real(wp) :: fixed_lo(3, bc_max_fixed), fixed_hi(3, bc_max_fixed)
    real(wp), parameter :: unset = huge(1.0_wp)
    logical :: given(bc_max_fixed)
    integer :: ios, f, m, q
    character(len=max_line) :: msg
    namelist /boundary/ xlo, xhi, ylo, yhi, zlo, zhi, xlo_velocity, xhi_velocity, ylo_velocity, &
      yhi_velocity, zlo_velocity, zhi_velocity, xlo_pressure, xhi_pressure, ylo_pressure, &
      yhi_pressure, zlo_pressure, zhi_pressure, inflow_material, inflow_density, inflow_pressure, fixed_lo, fixed_hi

    kinds = 'symmetry'
    xlo = kinds(1); xhi = kinds(2); ylo = kinds(3); yhi = kinds(4); zlo = kinds(5); zhi = kinds(6)
    xlo_velocity = this%velocity(:, 1); xhi_velocity = this%velocity(:, 2)
    ylo_velocity = this%velocity(:, 3); yhi_velocity = this%velocity(:, 4)
    zlo_velocity = this%velocity(:, 5); zhi_velocity = this%velocity(:, 6)
    xlo_pressure = this%pressure(1); xhi_pressure = this%pressure(2); ylo_pressure = this%pressure(3)
    yhi_pressure = this%pressure(4); zlo_pressure = this%pressure(5); zhi_pressure = this%pressure(6)
    inflow_material = ''; inflow_density = this%inflow_density; inflow_pressure = this%inflow_pressure
    fixed_lo = unset; fixed_hi = unset
    if (size(text) > 0) then
      read(text, nml=boundary, iostat=ios, iomsg=msg)
      if (ios /= 0) call problem_nml(problems, path, 'boundary', ios, msg)
    end if
    kinds = [xlo, xhi, ylo, yhi, zlo, zhi]
    do f = 1, 6
      call problem_long(problems, 'boundary', face_names(f), kinds(f))
      call problem_long(problems, 'boundary', 'inflow_material('//itoa(f)//')', inflow_material(f))
    end do
    do f = 1, 6
      this%kind(f) = bc_kind_from_name(kinds(f))
      if (this%kind(f) == 0) call problem_add(problems, '&boundary: '//face_names(f)//' = '''// &
        trim(kinds(f))//''' is not known; valid: '//bc_kind_names)
    end do
    this%velocity = reshape([xlo_velocity, xhi_velocity, ylo_velocity, yhi_velocity, &
                             zlo_velocity, zhi_velocity], [3, 6])
    this%pressure = [xlo_pressure, xhi_pressure, ylo_pressure, yhi_pressure, zlo_pressure, zhi_pressure]
    do f = 1, 6
      if (this%pressure(f) < 0.0_wp) call problem_bad(problems, 'boundary', face_names(f)//'_pressure', &
                                                      this%pressure(f), 'must be >= 0')
    end do
    this%inflow_density = inflow_density
    this%inflow_pressure = inflow_pressure
    do f = 1, 6
      if (this%kind(f) /= BC_INFLOW) cycle
      m = name_index(materials, inflow_material(f))
      this%inflow_mat(f) = m
      if (m == 0) call problem_add(problems, '&boundary: inflow_material('//itoa(f)//') = '''// &
        trim(inflow_material(f))//''' is not a &material name (face '//face_names(f)//' is an inflow)')
      if (.not. (inflow_density(f) > 0.0_wp)) call problem_bad(problems, 'boundary', 'inflow_density('// &
        itoa(f)//')', inflow_density(f), 'must be > 0 on an inflow face')
      if (.not. (inflow_pressure(f) >= 0.0_wp)) call problem_bad(problems, 'boundary', 'inflow_pressure('// &
        itoa(f)//')', inflow_pressure(f), 'must be >= 0')
    end do
    ! the fixed boxes: the first ones given, each with both corners
    do q = 1, bc_max_fixed
      given(q) = any(fixed_lo(:, q) < 0.5_wp*unset) .or. any(fixed_hi(:, q) < 0.5_wp*unset)
      if (.not. given(q)) cycle
      if (any(fixed_lo(:, q) > 0.5_wp*unset) .or. any(fixed_hi(:, q) > 0.5_wp*unset)) then
        call problem_add(problems, '&boundary: fixed box '//itoa(q)//' needs all three of fixed_lo(:,'//itoa(q)// &
          ') and of fixed_hi(:,'//itoa(q)//')')
      else if (any(fixed_lo(:, q) > fixed_hi(:, q))) then
        call problem_add(problems, '&boundary: fixed_lo(:,'//itoa(q)//') must be <= fixed_hi(:,'//itoa(q)// &
          ') in each direction')
      end if
    end do
    this%nfixed = count(given)
    if (any(given(this%nfixed + 1:))) call problem_add(problems, '&boundary: the fixed boxes must be the first '// &
      'ones, fixed_lo(:,1), fixed_hi(:,1) on, with none left out')
    do q = 1, this%nfixed
      this%fixed_box(:, q) = [fixed_lo(:, q), fixed_hi(:, q)]
    end do
    if (echo /= no_echo) write(echo, nml=boundary)
  end subroutine boundary_config_read

  !> What a restart may not change in &boundary: one line per changed variable.
  subroutine boundary_config_changes(old, new, changes)
    type(boundary_config_t), intent(in) :: old, new
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    integer :: f
    do f = 1, 6
      call diff_i(changes, '&boundary '//face_names(f), old%kind(f), new%kind(f))
      call diff_r(changes, '&boundary '//face_names(f)//'_velocity', old%velocity(:, f), new%velocity(:, f))
      call diff_r(changes, '&boundary '//face_names(f)//'_pressure', [old%pressure(f)], [new%pressure(f)])
      call diff_r(changes, '&boundary inflow_density('//itoa(f)//')', [old%inflow_density(f)], &
                  [new%inflow_density(f)])
      call diff_r(changes, '&boundary inflow_pressure('//itoa(f)//')', [old%inflow_pressure(f)], &
                  [new%inflow_pressure(f)])
      call diff_i(changes, '&boundary inflow_material('//itoa(f)//')', old%inflow_mat(f), new%inflow_mat(f))
    end do
    call diff_i(changes, '&boundary fixed boxes', old%nfixed, new%nfixed)
    do f = 1, bc_max_fixed
      call diff_r(changes, '&boundary fixed_lo(:,'//itoa(f)//')', old%fixed_box(1:3, f), new%fixed_box(1:3, f))
      call diff_r(changes, '&boundary fixed_hi(:,'//itoa(f)//')', old%fixed_box(4:6, f), new%fixed_box(4:6, f))
    end do
  end subroutine boundary_config_changes
end module mesh_boundary_config
