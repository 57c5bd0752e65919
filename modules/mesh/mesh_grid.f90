!> The structured hexahedral grid: node positions and index arithmetic.
!>
!> Cells are (i,j,k), i = 1..ni, flattened c = i + ni*((j-1) + nj*(k-1)).
!> Nodes are (i,j,k), i = 0..ni, flattened n = 1 + i + sx*(j + (nj+1)*k),
!> sx = ni+1. The nodes of cell c are node0(c) + corner_offset(a), a = 1..8,
!> in the local order of `mesh_geometry` (a = 1 + i + 2j + 4k).
module mesh_grid
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set
  use mesh_geometry, only: hex_corner
  use base_registry, only: registry_t, LOC_NODE
  implicit none
  private
  public :: grid_t, grid_init_box, block_gather, grid_register_restart

  !> Grid sizes, strides and node positions.
  type :: grid_t
    integer :: ni = 0, nj = 0, nk = 0
    integer :: nnode = 0, ncell = 0
    integer :: sx = 0, sxy = 0            !< node strides in j and k
    integer :: corner_offset(8) = 0
    real(wp) :: xmin(3) = 0.0_wp, xmax(3) = 1.0_wp   !< initial box
    real(wp), allocatable :: x(:, :)      !< node positions (3, nnode)
  contains
    procedure :: node => grid_node
    procedure :: node0 => grid_node0
    procedure :: cell_ijk => grid_cell_ijk
    procedure :: gather => grid_gather
  end type grid_t

contains

  !> Builds a uniform box grid of ni x nj x nk cells between xmin and xmax.
  subroutine grid_init_box(g, ni, nj, nk, xmin, xmax, err)
    type(grid_t), intent(out) :: g
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: xmin(3), xmax(3)
    type(error_t), allocatable, intent(inout) :: err
    integer :: i, j, k, n, stat
    character(len=200) :: msg
    real(wp) :: h(3)

    g%ni = ni; g%nj = nj; g%nk = nk
    g%sx = ni + 1
    g%sxy = (ni + 1)*(nj + 1)
    g%nnode = (ni + 1)*(nj + 1)*(nk + 1)
    g%ncell = ni*nj*nk
    g%xmin = xmin; g%xmax = xmax
    g%corner_offset = [0, 1, g%sx, g%sx + 1, g%sxy, g%sxy + 1, g%sxy + g%sx, g%sxy + g%sx + 1]
    allocate(g%x(3, g%nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'grid_init_box', 'cannot allocate node positions: '//trim(msg))
      return
    end if
    h = (xmax - xmin)/real([ni, nj, nk], wp)
    do k = 0, nk
      do j = 0, nj
        do i = 0, ni
          n = g%node(i, j, k)
          ! the far face is placed exactly at xmax, not at xmin + n*h
          g%x(1, n) = merge(xmax(1), xmin(1) + i*h(1), i == ni)
          g%x(2, n) = merge(xmax(2), xmin(2) + j*h(2), j == nj)
          g%x(3, n) = merge(xmax(3), xmin(3) + k*h(3), k == nk)
        end do
      end do
    end do
  end subroutine grid_init_box

  !> Flattened index of node (i,j,k), 0-based logical indices.
  pure integer function grid_node(this, i, j, k)
    class(grid_t), intent(in) :: this
    integer, intent(in) :: i, j, k
    grid_node = 1 + i + this%sx*j + this%sxy*k
  end function grid_node

  !> Index of the first (local a = 1) node of cell c.
  pure integer function grid_node0(this, c)
    class(grid_t), intent(in) :: this
    integer, intent(in) :: c
    integer :: ci, cj, ck, t
    ci = mod(c - 1, this%ni)
    t = (c - 1)/this%ni
    cj = mod(t, this%nj)
    ck = t/this%nj
    grid_node0 = 1 + ci + this%sx*cj + this%sxy*ck
  end function grid_node0

  !> Logical indices (1-based) of cell c.
  pure subroutine grid_cell_ijk(this, c, i, j, k)
    class(grid_t), intent(in) :: this
    integer, intent(in) :: c
    integer, intent(out) :: i, j, k
    integer :: t
    i = mod(c - 1, this%ni) + 1
    t = (c - 1)/this%ni
    j = mod(t, this%nj) + 1
    k = t/this%nj + 1
  end subroutine grid_cell_ijk

  !> Copies a node field f(3,nnode) at the eight nodes of cell c into fn(3,8).
  pure subroutine grid_gather(this, c, f, fn)
    class(grid_t), intent(in) :: this
    integer, intent(in) :: c
    real(wp), intent(in) :: f(:, :)
    real(wp), intent(out) :: fn(3, 8)
    integer :: a, n0
    n0 = this%node0(c)
    do a = 1, 8
      fn(:, a) = f(:, n0 + this%corner_offset(a))
    end do
  end subroutine grid_gather

  !> Copies the node positions of cell (ci,cj,ck) of a block of ni x nj
  !> cells per layer from x(3, nnode) into xn(3,8) (for code that has the
  !> block sizes but no grid_t, such as a grid being built or an old grid).
  pure subroutine block_gather(ni, nj, ci, cj, ck, x, xn)
    integer, intent(in) :: ni, nj, ci, cj, ck
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: xn(3, 8)
    integer :: a, n0, sx, sxy
    sx = ni + 1
    sxy = (ni + 1)*(nj + 1)
    n0 = ci + sx*(cj - 1) + sxy*(ck - 1)
    do a = 1, 8
      xn(:, a) = x(:, n0 + hex_corner(1, a) + sx*hex_corner(2, a) + sxy*hex_corner(3, a))
    end do
  end subroutine block_gather

  !> Registers the grid's restart fields: the node positions.
  subroutine grid_register_restart(g, reg)
    type(grid_t), intent(inout), target :: g
    type(registry_t), intent(inout) :: reg
    call reg%add('x', 'length', LOC_NODE, g%x)
  end subroutine grid_register_restart
end module mesh_grid
