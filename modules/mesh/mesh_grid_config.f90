!> The &grid group: the structured block (cells per direction and its box,
!> or node coordinates from a file).
module mesh_grid_config
  use base_kinds, only: wp, i8
  use base_strings, only: itoa
  use base_config, only: max_line, no_echo, problem_add, problem_bad, problem_badi, problem_nml, problem_long, &
                         diff_i, diff_r, diff_s
  implicit none
  private
  public :: grid_config_t, grid_config_read, grid_config_changes, resolve_path, grid_axis_nodes

  !> Curved region boundaries in cut cells are resolved to 1/subsamples of
  !> the cell (`geometry_shapes`): 64 is a split 6 levels deep.
  integer, parameter :: max_subsamples = 64

  !> The narrowest cell (length): its volume, min_edge**3, stays a normal
  !> number with room for the products of the Lagrangian step (the
  !> reciprocal of the deck's magnitude rule, 1e30).
  real(wp), parameter, public :: min_edge = 1.0e-30_wp

  !> The most (coordinate, width) pairs of a graded axis (`spacing_x`..).
  integer, parameter, public :: max_spacing = 32

  !> An unset entry of `spacing_x`..: the namelist leaves it as it is (the
  !> echo shows it as 1.797E+308, as it shows other absent values).
  real(wp), parameter :: unset = huge(1.0_wp)

  !> The resolved &grid group; the initial values are the defaults.
  type :: grid_config_t
    integer :: ni = 0, nj = 0, nk = 0              !< cells along x, y, z (required, >= 1)
    real(wp) :: xmin(3) = 0.0_wp                   !< low corner of the box (length)
    real(wp) :: xmax(3) = 1.0_wp                   !< high corner of the box (length)
    integer :: subsamples = 16                     !< curved region boundaries resolved to 1/subsamples of a cut cell
    character(len=256) :: file = ''                !< HDF5 file of node coordinates ('': the box)
    character(len=:), allocatable :: file_path     !< `file` resolved against the deck's directory (resolved)
    !> a graded box: per axis, pairs (coordinate, cell width) in order of
    !> the coordinate, the rest `unset` (`grid_axis_nodes`)
    real(wp) :: spacing(2*max_spacing, 3) = unset
  contains
    procedure :: graded => grid_config_graded
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
    real(wp) :: spacing_x(2*max_spacing), spacing_y(2*max_spacing), spacing_z(2*max_spacing)
    character(len=256) :: file
    character(len=max_line) :: msg
    type(grid_config_t) :: default
    namelist /grid/ ni, nj, nk, xmin, xmax, subsamples, file, spacing_x, spacing_y, spacing_z

    ni = this%ni; nj = this%nj; nk = this%nk; xmin = this%xmin; xmax = this%xmax
    subsamples = this%subsamples; file = this%file
    spacing_x = this%spacing(:, 1); spacing_y = this%spacing(:, 2); spacing_z = this%spacing(:, 3)
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
    this%spacing(:, 1) = spacing_x
    this%spacing(:, 2) = spacing_y
    this%spacing(:, 3) = spacing_z
    if (len_trim(file) > 0 .and. this%graded()) &
      call problem_add(problems, '&grid: spacing_x, spacing_y and spacing_z do not apply with file = '''// &
                       trim(file)//''' (the file gives the nodes); leave them out')
    do d = 1, 3
      if (xmax(d) > xmin(d)) call spacing_check(this, d, problems)
    end do
    this%file_path = resolve_path(file, path)
    if (echo /= no_echo) write(echo, nml=grid)
  end subroutine grid_config_read

  !> True if some axis is graded (`spacing_x`, `spacing_y` or `spacing_z`
  !> given).
  pure logical function grid_config_graded(this) result(graded)
    class(grid_config_t), intent(in) :: this
    graded = any(given(this%spacing(1, :)))
  end function grid_config_graded

  !> An entry of `spacing_x`.. the deck gave (not `unset`).
  elemental logical function given(v)
    real(wp), intent(in) :: v
    given = v < 0.5_wp*unset
  end function given

  !> The problems of axis d's (coordinate, width) pairs: whole pairs, the
  !> coordinates increasing within [xmin, xmax], the widths positive, no
  !> value after the first unset one, and cells of at least min_edge.
  subroutine spacing_check(this, d, problems)
    type(grid_config_t), intent(in) :: this
    integer, intent(in) :: d
    character(len=max_line), allocatable, intent(inout) :: problems(:)
    character(len=*), parameter :: names(3) = ['spacing_x', 'spacing_y', 'spacing_z']
    real(wp), allocatable :: x(:)
    integer :: n, k, n0
    n0 = 0
    if (allocated(problems)) n0 = size(problems)
    associate (sp => this%spacing(:, d), lo => this%xmin(d), hi => this%xmax(d))
      n = count(given(sp))
      if (n == 0) return
      if (any(.not. given(sp(1:n))) .or. mod(n, 2) /= 0) then
        call problem_add(problems, '&grid: '//names(d)//' must be pairs (coordinate, cell width), one after '// &
                         'the other from its first entry; it has '//itoa(n)//' values')
        return
      end if
      do k = 1, n, 2
        if (.not. (sp(k) >= lo .and. sp(k) <= hi)) then
          call problem_bad(problems, 'grid', names(d)//'('//itoa(k)//')', sp(k), &
                           'is a coordinate outside the box [xmin, xmax] along that axis')
        else if (k > 1) then
          if (.not. sp(k) > sp(k - 2)) call problem_bad(problems, 'grid', names(d)//'('//itoa(k)//')', sp(k), &
                                                         'must be greater than the coordinate before it')
        end if
        if (.not. (sp(k + 1) > 0.0_wp .and. sp(k + 1) < huge(1.0_wp))) &
          call problem_bad(problems, 'grid', names(d)//'('//itoa(k + 1)//')', sp(k + 1), 'must be a width > 0')
      end do
      if (allocated(problems)) then
        if (size(problems) > n0) return
      end if
      x = grid_axis_nodes(this, d)
      if (.not. minval(x(2:) - x(:size(x) - 1)) >= min_edge) &
        call problem_add(problems, '&grid: '//names(d)//' gives cells narrower than 1e-30')
    end associate
  end subroutine spacing_check

  !> The node coordinates along axis d, x(1:n+1) for its nodes 0..n (n
  !> cells): uniform from xmin to xmax (the far node exactly at xmax, as
  !> `grid_init_box` places it), or graded by the axis' (coordinate, width)
  !> pairs: the cell width varies linearly in the coordinate between the
  !> pairs (and stays the first pair's below it, the last one's above it),
  !> and the nodes are placed at equal steps of the integral of 1/width, so
  !> every width is scaled by the one factor that makes the axis hold n
  !> cells (the pairs give the widths' shape; n their size). (Small arrays,
  !> n + 1 and the pairs: allocated on assignment.)
  pure function grid_axis_nodes(this, d) result(x)
    class(grid_config_t), intent(in) :: this
    integer, intent(in) :: d
    real(wp), allocatable :: x(:)
    real(wp), allocatable :: xc(:), wc(:), f(:)
    real(wp) :: h, target, s, loc
    integer :: cells(3), n, m, i, k, np
    cells = [this%ni, this%nj, this%nk]
    n = cells(d)
    associate (lo => this%xmin(d), hi => this%xmax(d), sp => this%spacing(:, d))
      np = count(given(sp))/2
      if (np == 0) then
        h = (hi - lo)/real(n, wp)
        x = [(merge(hi, lo + i*h, i == n), i = 0, n)]
        return
      end if
      ! the pairs, extended to both ends of the box
      xc = [lo, sp(1:2*np - 1:2), hi]
      wc = [sp(2), sp(2:2*np:2), sp(2*np)]
      ! f(k): the integral of 1/width from lo to xc(k)
      m = size(xc)
      f = [(0.0_wp, k = 1, m)]
      do k = 2, m
        f(k) = f(k - 1) + segment_integral(xc(k) - xc(k - 1), wc(k - 1), wc(k))
      end do
      x = [(lo, i = 0, n)]
      x(n + 1) = hi
      k = 2
      do i = 1, n - 1
        target = f(m)*real(i, wp)/real(n, wp)
        do while (f(k) < target .and. k < m)
          k = k + 1
        end do
        ! in the stretch xc(k - 1)..xc(k)
        loc = target - f(k - 1)
        associate (a => xc(k - 1), len => xc(k) - xc(k - 1), w1 => wc(k - 1), w2 => wc(k))
          if (abs(w2 - w1) <= 1.0e-12_wp*max(w1, w2)) then
            x(i + 1) = a + loc*w1
          else
            s = (w2 - w1)/len
            x(i + 1) = a + w1*(exp(s*loc) - 1.0_wp)/s
          end if
          x(i + 1) = min(max(x(i + 1), a), xc(k))
        end associate
      end do
    end associate
  end function grid_axis_nodes

  !> The integral of 1/width over a segment of length len whose width goes
  !> linearly from w1 to w2.
  pure real(wp) function segment_integral(len, w1, w2) result(f)
    real(wp), intent(in) :: len, w1, w2
    if (abs(w2 - w1) <= 1.0e-12_wp*max(w1, w2)) then
      f = len/w1
    else
      f = len*log(w2/w1)/(w2 - w1)
    end if
  end function segment_integral

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
    call diff_r(changes, '&grid spacing_x', old%spacing(:, 1), new%spacing(:, 1))
    call diff_r(changes, '&grid spacing_y', old%spacing(:, 2), new%spacing(:, 2))
    call diff_r(changes, '&grid spacing_z', old%spacing(:, 3), new%spacing(:, 3))
  end subroutine grid_config_changes

  !> A 64-bit integer as text.
  pure function i8toa(i) result(s)
    integer(i8), intent(in) :: i
    character(len=24) :: s
    write(s, '(i0)') i
  end function i8toa
end module mesh_grid_config
