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
  public :: grid_file_read

  !> Coordinates of this magnitude or more are refused (as deck values are).
  real(wp), parameter :: huge_coordinate = 1.0e30_wp

contains

  !> Reads and checks the node positions x(3, nnode) of an ni x nj x nk
  !> block from the HDF5 file `path` (length; nodes in the order of
  !> `mesh_grid`: i fastest, then j, then k).
  subroutine grid_file_read(path, ni, nj, nk, x, err)
    character(len=*), intent(in) :: path
    integer, intent(in) :: ni, nj, nk
    real(wp), allocatable, intent(out) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: here = 'grid_file_read'
    type(h5_file_t) :: f
    type(error_t), allocatable :: err_close
    type(grid_index_t) :: ix
    integer, allocatable :: dims(:)
    real(wp), allocatable :: data(:)
    real(wp) :: xn(3, 8), vol, tets(3, 4, 24)
    integer :: want(4), n, c, i, j, k, nbad, stat, first(3), t
    logical :: same, inverted
    character(len=200) :: msg
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
      call h5_read_real(f, 'x', data, err)
    end block get
    call h5_close(f, err_close)
    if (.not. allocated(err) .and. allocated(err_close)) call move_alloc(err_close, err)
    if (allocated(err)) then
      if (err%where /= here) then
        more = 'grid file '''//path//''': '//err%msg
        call error_set(err, here, more, ERR_INPUT)
      end if
      return
    end if

    ix = grid_index(ni, nj, nk)
    allocate(x(3, ix%nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, here, error_no_memory('the node positions'))
      return
    end if
    x = reshape(data, [3, ix%nnode])
    deallocate(data)
    do n = 1, ix%nnode
      if (all(ieee_is_finite(x(:, n)))) then
        if (all(abs(x(:, n)) < huge_coordinate)) cycle
      end if
      call ix%node_ijk(n, i, j, k)
      call error_set(err, here, 'grid file '''//path//''': node ('//itoa(i)//', '//itoa(j)//', '//itoa(k)// &
        ') has a coordinate that is not finite or of magnitude 1e30 or more', ERR_INPUT)
      return
    end do
    nbad = 0
    do c = 1, ix%ncell
      call ix%gather(c, x, xn)
      vol = hex_volume(xn)
      call hex_tets(xn, tets)
      inverted = .false.
      do t = 1, 24
        inverted = inverted .or. .not. (tet_det(tets(:, :, t)) > 0.0_wp)
      end do
      if (vol >= min_edge**3 .and. .not. inverted) cycle
      nbad = nbad + 1
      if (nbad > 1) cycle
      call ix%cell_ijk(c, first(1), first(2), first(3))
      if (inverted) then
        msg = 'is inverted or self-intersecting (a tetrahedron of its 24 has no positive volume; volume '// &
              rtoa(vol)//')'
      else
        msg = 'has a volume of '//rtoa(vol)//', below 1e-90 (cells must be at least 1e-30 across)'
      end if
    end do
    if (nbad == 0) return
    more = ''
    if (nbad > 1) more = ' (and '//itoa(nbad - 1)//' more cells)'
    call error_set(err, here, 'grid file '''//path//''': cell ('//itoa(first(1))//', '//itoa(first(2))//', '// &
      itoa(first(3))//') '//trim(msg)//more, ERR_INPUT)
  end subroutine grid_file_read

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
