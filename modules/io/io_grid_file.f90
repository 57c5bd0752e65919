!> A grid read from an HDF5 file of node coordinates (`&grid file`).
!>
!> The file holds a double dataset `x` of the node positions, a Fortran
!> array x(3, 0:ni, 0:nj, 0:nk): exactly the `x` of the code's own frames
!> (`io_output`), so a frame can serve as a grid file; h5py shows it with
!> the shape (nk+1, nj+1, ni+1, 3). tools/make_grid.py writes such files.
!>
!> What is read is checked before the grid is used: the dataset's shape
!> against the deck's ni, nj, nk (before anything is allocated from it),
!> every coordinate finite and of magnitude below 1e30 (as the deck reader
!> refuses such numbers: they would overflow the volumes), and every cell
!> valid: each of its 24 tetrahedra (`mesh_geometry` `hex_tets`) positive,
!> so that no node has been pushed through a face of its cells, and its
!> volume at least min_edge**3 (`mesh_grid_config`).
!> Each failure is an input error (ERR_INPUT) whose message names the file
!> and the node or cell.
module io_grid_file
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set, ERR_INPUT
  use base_strings, only: itoa, rtoa
  use io_hdf5, only: h5_file_t, h5_open_read, h5_close, h5_exists, h5_read_dims, h5_read_real
  use mesh_grid, only: grid_index_t, grid_index
  use mesh_geometry, only: hex_volume, hex_tets, tet_det
  use mesh_grid_config, only: min_edge
  implicit none
  private
  public :: grid_file_read, grid_file_scan

  !> The bad cells found so far: how many, the first's indices and what is
  !> wrong with it.
  type :: cells_bad_t
    integer :: n = 0
    integer :: first(3) = 0
    character(len=200) :: msg = ''
  end type cells_bad_t

  !> Coordinates of this magnitude or more are refused (as deck values are).
  real(wp), parameter :: huge_coordinate = 1.0e30_wp

contains

  !> Reads and checks the node positions x(3, n) of the box of nodes lo ..
  !> hi (0-based node indices (i, j, k), inclusive; absent: the whole grid)
  !> of an ni x nj x nk grid from the HDF5 file `path` (length; nodes in the
  !> order of `mesh_grid`: i fastest, then j, then k): its nodes and the
  !> cells between them (module notes; a block of a decomposed run reads
  !> its stored nodes only).
  subroutine grid_file_read(path, ni, nj, nk, x, err, lo, hi)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ni, nj, nk
    real(wp), allocatable, intent(out) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: lo(3), hi(3)
    type(h5_file_t) :: f
    type(cells_bad_t) :: bad
    integer :: blo(3), bhi(3)
    blo = 0
    bhi = [ni, nj, nk]
    if (present(lo)) blo = lo
    if (present(hi)) bhi = hi
    call file_open(path, ni, nj, nk, f, err)
    if (allocated(err)) return
    call read_box(f, path, ni, nj, nk, blo, bhi, x, err)
    call file_close(f, path, err)
    if (allocated(err)) return
    call cells_check(x, blo, bhi, bad)
    call bad_report(path, bad, err)
  end subroutine grid_file_read

  !> Checks the whole grid of the HDF5 file `path` (as `grid_file_read`)
  !> and gives the box around its nodes, reading it a slab of node planes at
  !> a time (about 2^20 nodes: a deck check holds no whole-grid array).
  subroutine grid_file_scan(path, ni, nj, nk, xmin, xmax, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(out) :: xmin(3), xmax(3)
    type(error_t), allocatable, intent(inout) :: err
    integer, parameter :: slab_nodes = 2**20
    type(h5_file_t) :: f
    type(cells_bad_t) :: bad
    real(wp), allocatable :: x(:, :)
    integer :: nks, k0, d
    xmin = huge(1.0_wp)
    xmax = -huge(1.0_wp)
    call file_open(path, ni, nj, nk, f, err)
    if (allocated(err)) return
    nks = max(1, min(nk, slab_nodes/((ni + 1)*(nj + 1))))
    ! (cells k0+1 .. k0+nks between node planes k0 .. k0+nks: each cell once)
    do k0 = 0, nk - 1, nks
      call read_box(f, path, ni, nj, nk, [0, 0, k0], [ni, nj, min(nk, k0 + nks)], x, err)
      if (allocated(err)) exit
      call cells_check(x, [0, 0, k0], [ni, nj, min(nk, k0 + nks)], bad)
      do d = 1, 3
        xmin(d) = min(xmin(d), minval(x(d, :)))
        xmax(d) = max(xmax(d), maxval(x(d, :)))
      end do
    end do
    call file_close(f, path, err)
    if (.not. allocated(err)) call bad_report(path, bad, err)
  end subroutine grid_file_scan

  !> Opens the grid file and checks its dataset x's shape against ni, nj, nk.
  subroutine file_open(path, ni, nj, nk, f, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ni, nj, nk
    type(h5_file_t), intent(out) :: f
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'grid_file_read'
    integer, allocatable :: dims(:)
    integer :: want(4)
    logical :: same
    character(len=:), allocatable :: more
    call h5_open_read(f, path, err)
    if (allocated(err)) then
      more = 'grid '//err%msg     ! (a copy: error_set deallocates err first)
      call error_set(err, here, more, ERR_INPUT)
      return
    end if
    get: block
      if (.not. h5_exists(f, 'x')) then
        call error_set(err, here, 'grid file '''//path//''' has no dataset ''x'' (the node coordinates)', ERR_INPUT)
        exit get
      end if
      call h5_read_dims(f, 'x', dims, err)
      if (allocated(err)) exit get
      want = [3, ni + 1, nj + 1, nk + 1]
      same = size(dims) == 4
      if (same) same = all(dims == want)
      if (.not. same) then
        call error_set(err, here, 'grid file '''//path//''': dataset x has shape '//shape_text(dims)// &
          ', expected '//shape_text(want)//' (nk+1, nj+1, ni+1, 3 as h5py shows it) for ni = '//itoa(ni)// &
          ', nj = '//itoa(nj)//', nk = '//itoa(nk), ERR_INPUT)
        exit get
      end if
    end block get
    if (allocated(err)) call file_close(f, path, err)
  end subroutine file_open

  !> Closes the grid file; an error (an earlier one kept) is given as the
  !> file's input error.
  subroutine file_close(f, path, err)
    type(h5_file_t), intent(inout) :: f
    character(len=*), intent(in) :: path
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'grid_file_read'
    type(error_t), allocatable :: err_close
    character(len=:), allocatable :: more
    call h5_close(f, err_close)
    if (.not. allocated(err) .and. allocated(err_close)) call move_alloc(err_close, err)
    if (.not. allocated(err)) return
    if (err%where /= here) then
      more = 'grid file '''//path//''': '//err%msg
      call error_set(err, here, more, ERR_INPUT)
    end if
  end subroutine file_close

  !> The nodes lo .. hi of the open grid file's dataset x into x(3, n), each
  !> checked finite and of magnitude below huge_coordinate (the first that
  !> is not named by its node indices).
  subroutine read_box(f, path, ni, nj, nk, lo, hi, x, err)
    type(h5_file_t), intent(in) :: f
    character(len=*), intent(in) :: path
    integer, intent(in) :: ni, nj, nk, lo(3), hi(3)
    real(wp), allocatable, intent(out) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'grid_file_read'
    real(wp), allocatable :: data(:)
    integer :: nb(3), n, i, j, k, stat
    nb = hi - lo + 1
    if (all(lo == 0) .and. all(hi == [ni, nj, nk])) then
      call h5_read_real(f, 'x', data, err)
    else
      call h5_read_real(f, 'x', data, err, start=[0, lo], count=[3, nb])
    end if
    if (allocated(err)) return
    allocate(x(3, product(nb)), stat=stat)
    if (stat /= 0) then
      call error_set(err, here, error_no_memory('the node positions'))
      return
    end if
    x = reshape(data, [3, product(nb)])
    deallocate(data)
    do n = 1, size(x, 2)
      if (all(ieee_is_finite(x(:, n)))) then
        if (all(abs(x(:, n)) < huge_coordinate)) cycle
      end if
      i = lo(1) + mod(n - 1, nb(1))
      j = lo(2) + mod((n - 1)/nb(1), nb(2))
      k = lo(3) + (n - 1)/(nb(1)*nb(2))
      call error_set(err, here, 'grid file '''//path//''': node ('//itoa(i)//', '//itoa(j)//', '//itoa(k)// &
        ') has a coordinate that is not finite or of magnitude 1e30 or more', ERR_INPUT)
      return
    end do
  end subroutine read_box

  !> Adds to bad the cells between the nodes x of the box lo .. hi that are
  !> inverted or too small (the first in the grid's cell order named).
  pure subroutine cells_check(x, lo, hi, bad)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: lo(3), hi(3)
    type(cells_bad_t), intent(inout) :: bad
    type(grid_index_t) :: ix
    real(wp) :: xn(3, 8), vol, tets(3, 4, 24)
    integer :: c, t, ijk(3)
    logical :: inverted
    if (any(hi <= lo)) return
    ix = grid_index(hi(1) - lo(1), hi(2) - lo(2), hi(3) - lo(3))
    do c = 1, ix%ncell
      call ix%gather(c, x, xn)
      vol = hex_volume(xn)
      call hex_tets(xn, tets)
      inverted = .false.
      do t = 1, 24
        inverted = inverted .or. .not. (tet_det(tets(:, :, t)) > 0.0_wp)
      end do
      if (vol >= min_edge**3 .and. .not. inverted) cycle
      bad%n = bad%n + 1
      if (bad%n > 1) cycle
      call ix%cell_ijk(c, ijk(1), ijk(2), ijk(3))
      bad%first = ijk + lo
      if (inverted) then
        bad%msg = 'is inverted or self-intersecting (a tetrahedron of its 24 has no positive volume; volume '// &
                  rtoa(vol)//')'
      else
        bad%msg = 'has a volume of '//rtoa(vol)//', below 1e-90 (cells must be at least 1e-30 across)'
      end if
    end do
  end subroutine cells_check

  !> The input error of the bad cells found (none: nothing).
  subroutine bad_report(path, bad, err)
    character(len=*), intent(in) :: path
    type(cells_bad_t), intent(in) :: bad
    type(error_t), allocatable, intent(inout) :: err
    character(len=:), allocatable :: more
    if (bad%n == 0) return
    more = ''
    if (bad%n > 1) more = ' (and '//itoa(bad%n - 1)//' more cells)'
    call error_set(err, 'grid_file_read', 'grid file '''//path//''': cell ('//itoa(bad%first(1))//', '// &
      itoa(bad%first(2))//', '//itoa(bad%first(3))//') '//trim(bad%msg)//more, ERR_INPUT)
  end subroutine bad_report

  !> A shape given in Fortran order as h5py shows it: "(d_n, ..., d_1)".
  pure function shape_text(dims) result(s)
    integer, intent(in) :: dims(:)
    character(len=:), allocatable :: s
    integer :: k
    s = '('
    do k = size(dims), 1, -1
      s = s//itoa(dims(k))//merge(', ', ') ', k > 1)
    end do
    s = trim(s)
    if (size(dims) == 0) s = '() (a scalar)'
  end function shape_text
end module io_grid_file
