!> The &grid group: the structured block (cells per direction and its box,
!> or node coordinates from a file).
module mesh_grid_config
  use base_kinds, only: wp, i8
  use base_strings, only: itoa
  use base_config, only: max_line, no_echo, problem_add, problem_bad, problem_badi, problem_nml, problem_long, &
                         diff_i, diff_r, diff_s
  implicit none
  private
  public :: grid_config_t, grid_config_read, grid_config_changes, resolve_path

  !> Curved region boundaries in cut cells are resolved to 1/subsamples of
  !> the cell (`geometry_shapes`): 64 is a split 6 levels deep.
  integer, parameter :: max_subsamples = 64

  !> The narrowest cell (length): its volume, min_edge**3, stays a normal
  !> number with room for the products of the Lagrangian step (the
  !> reciprocal of the deck's magnitude rule, 1e30).
  real(wp), parameter, public :: min_edge = 1.0e-30_wp

  !> The resolved &grid group; the initial values are the defaults.
  type :: grid_config_t
    integer :: ni = 0, nj = 0, nk = 0              !< cells along x, y, z (required, >= 1)
    real(wp) :: xmin(3) = 0.0_wp                   !< low corner of the box (length)
    real(wp) :: xmax(3) = 1.0_wp                   !< high corner of the box (length)
    integer :: subsamples = 16                     !< curved region boundaries resolved to 1/subsamples of a cut cell
    character(len=256) :: file = ''                !< HDF5 file of node coordinates ('': the box)
    character(len=:), allocatable :: file_path     !< `file` resolved against the deck's directory (resolved)
  end type grid_config_t

contains

  !> Reads, validates and echoes the &grid group (`text`: its lines, empty
  !> if the deck has none, which is a problem: the sizes are required). A
  !> relative `file` is taken relative to the directory of the deck `path`;
  !> the file itself is read by the driver (`io_grid_file`), which then sets
  !> xmin and xmax to the box around its nodes (`grid_file_scan`).
  subroutine grid_config_read(this, text, path, echo, problems)
    type(grid_config_t), intent(out) :: this
    character(len=*), intent(in) :: text(:), path
    integer, intent(in) :: echo
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    integer :: ni, nj, nk, subsamples, ios, d, cells(3)
    real(wp) :: xmin(3), xmax(3)
    character(len=256) :: file
    character(len=max_line) :: msg
    type(grid_config_t) :: default
    namelist /grid/ ni, nj, nk, xmin, xmax, subsamples, file

    ni = this%ni; nj = this%nj; nk = this%nk; xmin = this%xmin; xmax = this%xmax
    subsamples = this%subsamples; file = this%file
    if (size(text) == 0) then
      call problem_add(problems, trim(path)//': group &grid is missing (ni, nj, nk are required)')
      return
    end if
    read(text, nml=grid, iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call problem_nml(problems, path, 'grid', ios, msg)
      return
    end if
    if (ni < 1) call problem_badi(problems, 'grid', 'ni', ni, 'must be >= 1')
    if (nj < 1) call problem_badi(problems, 'grid', 'nj', nj, 'must be >= 1')
    if (nk < 1) call problem_badi(problems, 'grid', 'nk', nk, 'must be >= 1')
    if (subsamples < 1 .or. subsamples > max_subsamples) call problem_badi(problems, 'grid', 'subsamples', &
      subsamples, 'must be in 1..'//itoa(max_subsamples))
    ! the cell and node counts are default integers
    if (int(max(ni, 1), i8)*max(nj, 1)*max(nk, 1) > huge(1) .or. &
        (int(max(ni, 1), i8) + 1)*(int(max(nj, 1), i8) + 1)*(int(max(nk, 1), i8) + 1) > huge(1)) &
      call problem_add(problems, &
      '&grid: ni*nj*nk = '//trim(i8toa(int(ni, i8)*nj*nk))//' cells is more than one run can index ('// &
      itoa(huge(1))//' cells and nodes)')
    ! cells of at least min_edge: their volumes stay normal numbers (the
    ! reciprocal of the deck's magnitude rule, 1e30)
    cells = [ni, nj, nk]
    do d = 1, 3
      if (.not. (xmax(d) > xmin(d))) then
        call problem_bad(problems, 'grid', 'xmax('//achar(48 + d)//')', xmax(d), &
                         'must be > xmin('//achar(48 + d)//')')
      else if ((xmax(d) - xmin(d)) < min_edge*max(cells(d), 1)) then
        call problem_bad(problems, 'grid', 'xmax('//achar(48 + d)//')', xmax(d), &
                         'gives cells narrower than 1e-30 in direction '//achar(48 + d))
      end if
    end do
    call problem_long(problems, 'grid', 'file', file)
    ! the file gives the nodes, the box with them: a box given too is a
    ! contradiction (most likely a deck edited half way)
    if (len_trim(file) > 0 .and. (any(abs(xmin - default%xmin) > 0.0_wp) .or. &
                                 any(abs(xmax - default%xmax) > 0.0_wp))) &
      call problem_add(problems, '&grid: xmin and xmax do not apply with file = '''//trim(file)// &
                       ''' (the file gives the nodes); leave them out')
    this = grid_config_t(ni=ni, nj=nj, nk=nk, xmin=xmin, xmax=xmax, subsamples=subsamples, file=file)
    this%file_path = resolve_path(file, path)
    if (echo /= no_echo) write(echo, nml=grid)
  end subroutine grid_config_read

  !> `file` relative to the directory of `deck` unless it is absolute or
  !> empty (the deck in the current directory: `file` as it is).
  pure function resolve_path(file, deck) result(full)
    character(len=*), intent(in) :: file, deck
    character(len=:), allocatable :: full
    integer :: k
    full = trim(file)
    if (len(full) == 0) return
    if (full(1:1) == '/') return
    k = index(deck, '/', back=.true.)
    if (k > 0) full = deck(1:k)//full
  end function resolve_path

  !> What a restart may not change in &grid: one line per changed variable.
  subroutine grid_config_changes(old, new, changes)
    type(grid_config_t), intent(in) :: old, new
    character(len=max_line), allocatable, intent(inout) :: changes(:)
    call diff_i(changes, '&grid ni', old%ni, new%ni)
    call diff_i(changes, '&grid nj', old%nj, new%nj)
    call diff_i(changes, '&grid nk', old%nk, new%nk)
    call diff_r(changes, '&grid xmin', old%xmin, new%xmin)
    call diff_r(changes, '&grid xmax', old%xmax, new%xmax)
    call diff_s(changes, '&grid file', old%file, new%file)
  end subroutine grid_config_changes

  !> A 64-bit integer as text.
  pure function i8toa(i) result(s)
    integer(i8), intent(in) :: i
    character(len=24) :: s
    write(s, '(i0)') i
  end function i8toa
end module mesh_grid_config
