!> The structured hexahedral grid: index arithmetic and node positions.
!>
!> `grid_index_t` owns all index arithmetic of a block of ni x nj x nk owned
!> cells. Owned cells are (i,j,k), i = 1..ni, owned nodes i = 0..ni. A block
!> of an MPI decomposition (`grid_index_block`) also stores ghost cells, glo(d)
!> layers below and ghi(d) above in direction d (only towards another block;
!> a physical face has none), and the nodes of those cells: stored cells
!> i = slo(1)..shi(1), stored nodes i = slo(1)-1..shi(1). Both are stored with
!> i fastest, then j, then k, and the nodes of cell c are node0(c) +
!> corner_offset(a), a = 1..8, in the local order of `mesh_geometry`
!> (a = 1 + i + 2j + 4k). Kernels loop over the ranges `clo..chi` (owned
!> cells), `nlo..nhi` (owned nodes) or `cells_around` (owned cells widened
!> into the ghosts) and ask the type for indices (in hot loops once per
!> row: consecutive i are consecutive indices). A single block (`grid_index`,
!> ng = 0) stores exactly its owned cells, in the order c = i + ni*((j-1) +
!> nj*(k-1)), n = 1 + i + (ni+1)*(j + (nj+1)*k). off(d) is the block's place
!> in the whole grid (global cell i + off(1)), gn(d) the whole grid's cells.
!> `grid_t` is a grid_index_t with node positions.
module mesh_grid
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use mesh_geometry, only: hex_corner
  use base_registry, only: registry_t, LOC_NODE
  implicit none
  private
  public :: grid_index_t, grid_index, grid_index_block, grid_t, grid_init_box, grid_init_nodes, block_gather, &
            grid_unflagged_move, grid_rows, grid_copy_rows_real, grid_copy_rows_int, &
            grid_register_restart, nodes_moved, nodes_within, &
            FACE_XLO, FACE_XHI, FACE_YLO, FACE_YHI, FACE_ZLO, FACE_ZHI

  !> The six faces of the block; bit f-1 of a face mask is set for face f.
  integer, parameter :: FACE_XLO = 1, FACE_XHI = 2, FACE_YLO = 3, FACE_YHI = 4, FACE_ZLO = 5, FACE_ZHI = 6

  !> Index arithmetic of a block of cells: sizes, ranges and strides.
  type :: grid_index_t
    integer :: ni = 0, nj = 0, nk = 0     !< owned cells per direction
    integer :: ng = 0                     !< largest ghost width (0: no halo)
    integer :: glo(3) = 0, ghi(3) = 0     !< ghost layers below / above in each direction
    integer :: off(3) = 0                 !< global cell index of owned cell i is i + off
    integer :: gn(3) = 0                  !< cells of the whole grid per direction
    integer :: clo(3) = 1, chi(3) = 0     !< owned cells (i,j,k) range
    integer :: nlo(3) = 0, nhi(3) = -1    !< owned nodes (i,j,k) range
    integer :: ulo(3) = 0                 !< first node this block counts in sums (nlo, or nlo+1 after a ghost)
    integer :: slo(3) = 1, shi(3) = 0     !< stored cells (owned and ghost) range
    integer :: nnode = 0, ncell = 0       !< stored nodes and cells
    integer :: sx = 0, sxy = 0            !< node strides in j and k
    integer :: cx = 0, cxy = 0            !< cell strides in j and k (offsets to neighbour cells)
    integer :: cbase = 0, nbase = 0       !< cell(i,j,k) = cbase + i + cx j + cxy k; node likewise
    integer :: corner_offset(8) = 0       !< node index offsets of the local corners
  contains
    procedure :: cell => grid_cell
    procedure :: node => grid_node
    procedure :: node0 => grid_node0
    procedure :: cell_node0 => grid_cell_node0
    procedure :: corner => grid_corner
    procedure :: cell_ijk => grid_cell_ijk
    procedure :: node_ijk => grid_node_ijk
    procedure :: node_faces => grid_node_faces
    procedure :: cell_faces => grid_cell_faces
    procedure :: gather => grid_gather
    procedure :: cells_around => grid_cells_around
    procedure :: owns_cell => grid_owns_cell
    procedure :: counts_node => grid_counts_node
    procedure :: global_cell => grid_global_cell
    procedure :: stored_cell => grid_stored_cell
    procedure :: colour_first => grid_colour_first
  end type grid_index_t

  !> Grid: its index arithmetic and node positions.
  type, extends(grid_index_t) :: grid_t
    real(wp) :: xmin(3) = 0.0_wp, xmax(3) = 1.0_wp   !< initial box (around the initial nodes)
    real(wp), allocatable :: x(:, :)      !< node positions (3, nnode)
    !> Per row of stored nodes (fixed j and k: node n is in row (n - 1)/sx
    !> + 1): false where every node of the row is known to be at the fixed
    !> grid the last Euler step returned to (`driver_euler`), true where one
    !> may have moved since (the Lagrangian step sets it); unallocated: not
    !> tracked. It lets an Euler step find the moved nodes without reading
    !> the whole grid's positions.
    logical, allocatable :: moved_rows(:)
  end type grid_t

contains

  !> Builds a box grid of ni x nj x nk cells between xmin and xmax, or the
  !> block `ix` of it (`grid_index_block`, its ghost nodes included):
  !> uniform, or with the node planes at ax(0:ni), ay(0:nj), az(0:nk) (a
  !> graded box, `grid_axis_nodes`; all three or none).
  subroutine grid_init_box(g, ni, nj, nk, xmin, xmax, err, ix, ax, ay, az)
    type(grid_t), intent(out) :: g
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: xmin(3), xmax(3)
    type(error_t), allocatable, intent(inout) :: err
    type(grid_index_t), intent(in), optional :: ix
    real(wp), intent(in), optional :: ax(0:), ay(0:), az(0:)
    integer :: i, j, k, n, stat, ig(3)
    character(len=200) :: msg
    real(wp) :: h(3)

    if (present(ix)) then
      g%grid_index_t = ix
    else
      g%grid_index_t = grid_index(ni, nj, nk)
    end if
    g%xmin = xmin; g%xmax = xmax
    allocate(g%x(3, g%nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'grid_init_box', error_no_memory('node positions'))
      return
    end if
    h = (xmax - xmin)/real([ni, nj, nk], wp)
    do k = g%slo(3) - 1, g%shi(3)
      do j = g%slo(2) - 1, g%shi(2)
        do i = g%slo(1) - 1, g%shi(1)
          n = g%node(i, j, k)
          ig = [i, j, k] + g%off
          if (present(ax)) then
            g%x(:, n) = [ax(ig(1)), ay(ig(2)), az(ig(3))]
            cycle
          end if
          ! the far face is placed exactly at xmax, not at xmin + n*h
          g%x(1, n) = merge(xmax(1), xmin(1) + ig(1)*h(1), ig(1) == ni)
          g%x(2, n) = merge(xmax(2), xmin(2) + ig(2)*h(2), ig(2) == nj)
          g%x(3, n) = merge(xmax(3), xmin(3) + ig(3)*h(3), ig(3) == nk)
        end do
      end do
    end do
  end subroutine grid_init_box

  !> Builds a grid of ni x nj x nk cells on given node positions x(3, nnode)
  !> (length; `grid_index` order of the whole grid), e.g. read from a file
  !> (`io_grid_file`), or the block `ix` of it (its stored nodes taken from
  !> x); xmin and xmax become the box around all of them. With box (the
  !> whole grid's xmin, xmax) x holds only the block's stored nodes, in its
  !> node order (a block that read only those).
  subroutine grid_init_nodes(g, ni, nj, nk, x, err, ix, box)
    type(grid_t), intent(out) :: g
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    type(grid_index_t), intent(in), optional :: ix
    !> the whole grid's xmin, xmax (3, 2) where x is the block's nodes
    real(wp), intent(in), optional :: box(3, 2)
    type(grid_index_t) :: whole
    integer :: stat, i, j, k
    character(len=200) :: msg

    whole = grid_index(ni, nj, nk)
    g%grid_index_t = whole
    if (present(ix)) g%grid_index_t = ix
    if (size(x, 1) /= 3 .or. (size(x, 2) /= whole%nnode .and. .not. (size(x, 2) == g%nnode .and. present(box)))) then
      call error_set(err, 'grid_init_nodes', 'the node positions do not fit the grid')
      return
    end if
    allocate(g%x(3, g%nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'grid_init_nodes', error_no_memory('node positions'))
      return
    end if
    if (present(box)) then
      ! (the block's stored nodes, in its order)
      g%x = x
      g%xmin = box(:, 1)
      g%xmax = box(:, 2)
      return
    end if
    do k = g%slo(3) - 1, g%shi(3)
      do j = g%slo(2) - 1, g%shi(2)
        do i = g%slo(1) - 1, g%shi(1)
          g%x(:, g%node(i, j, k)) = x(:, whole%node(i + g%off(1), j + g%off(2), k + g%off(3)))
        end do
      end do
    end do
    g%xmin = minval(x, dim=2)
    g%xmax = maxval(x, dim=2)
  end subroutine grid_init_nodes

  !> The index arithmetic of a single block of ni x nj x nk cells (no ghosts).
  pure function grid_index(ni, nj, nk) result(ix)
    integer, intent(in) :: ni, nj, nk
    type(grid_index_t) :: ix
    ix = grid_index_block([ni, nj, nk], [0, 0, 0], [0, 0, 0], [0, 0, 0], [ni, nj, nk])
  end function grid_index

  !> The index arithmetic of a block of n(3) owned cells with glo(d) / ghi(d)
  !> ghost layers below / above, at global offset off in a grid of gn cells.
  pure function grid_index_block(n, glo, ghi, off, gn) result(ix)
    integer, intent(in) :: n(3), glo(3), ghi(3), off(3), gn(3)
    type(grid_index_t) :: ix
    integer :: ns(3)
    ix%ni = n(1); ix%nj = n(2); ix%nk = n(3)
    ix%glo = glo
    ix%ghi = ghi
    ix%ng = max(maxval(glo), maxval(ghi))
    ix%off = off
    ix%gn = gn
    ix%clo = 1
    ix%chi = n
    ix%nlo = 0
    ix%nhi = n
    ix%ulo = merge(1, 0, glo > 0)
    ix%slo = 1 - glo
    ix%shi = n + ghi
    ns = ix%shi - ix%slo + 1
    ix%sx = ns(1) + 1
    ix%sxy = (ns(1) + 1)*(ns(2) + 1)
    ix%cx = ns(1)
    ix%cxy = ns(1)*ns(2)
    ix%nnode = (ns(1) + 1)*(ns(2) + 1)*(ns(3) + 1)
    ix%ncell = ns(1)*ns(2)*ns(3)
    ix%cbase = 1 - ix%slo(1) - ix%cx*ix%slo(2) - ix%cxy*ix%slo(3)
    ix%nbase = 1 - (ix%slo(1) - 1) - ix%sx*(ix%slo(2) - 1) - ix%sxy*(ix%slo(3) - 1)
    ix%corner_offset = hex_corner(1, :) + ix%sx*hex_corner(2, :) + ix%sxy*hex_corner(3, :)
  end function grid_index_block

  !> Flattened index of cell (i,j,k), 1-based logical indices.
  pure integer function grid_cell(this, i, j, k)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: i, j, k
    grid_cell = this%cbase + i + this%cx*j + this%cxy*k
  end function grid_cell

  !> Flattened index of node (i,j,k), 0-based logical indices.
  pure integer function grid_node(this, i, j, k)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: i, j, k
    grid_node = this%nbase + i + this%sx*j + this%sxy*k
  end function grid_node

  !> The owned cells widened by up to w ghost layers on each side that has
  !> them: the cells a stage computes so that its owned nodes see every
  !> cell around them (w = 1) or the neighbours of those (w = 2).
  pure subroutine grid_cells_around(this, w, lo, hi)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: w
    integer, intent(out) :: lo(3), hi(3)
    lo = this%clo - min(w, this%glo)
    hi = this%chi + min(w, this%ghi)
  end subroutine grid_cells_around

  !> The first cell at or after lo (i,j,k) of colour col (0..7): bit d-1 of
  !> col is the parity of the whole grid's index in direction d. Cells of one
  !> colour share no node, so a nodal sum taken colour by colour adds a
  !> node's cells in the same order in any block and on any thread count.
  pure function grid_colour_first(this, lo, col) result(first)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: lo(3), col
    integer :: first(3), d
    do d = 1, 3
      first(d) = lo(d) + modulo(ibits(col, d - 1, 1) - (lo(d) + this%off(d) - 1), 2)
    end do
  end function grid_colour_first

  !> True if cell (i,j,k) is owned (not a ghost).
  pure logical function grid_owns_cell(this, i, j, k)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: i, j, k
    grid_owns_cell = all([i, j, k] >= this%clo) .and. all([i, j, k] <= this%chi)
  end function grid_owns_cell

  !> True if this block counts owned node (i,j,k) in global sums: a node on
  !> the face shared with the block below is counted there.
  pure logical function grid_counts_node(this, i, j, k)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: i, j, k
    grid_counts_node = all([i, j, k] >= this%ulo) .and. all([i, j, k] <= this%nhi)
  end function grid_counts_node

  !> The whole grid's index of stored cell c (its single-block order: what
  !> a decomposed run reports, the same on any rank count).
  pure integer function grid_global_cell(this, c) result(gc)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: c
    integer :: i, j, k
    call this%cell_ijk(c, i, j, k)
    associate (o => this%off, n => this%gn)
      gc = (i + o(1)) + n(1)*((j + o(2) - 1) + n(2)*(k + o(3) - 1))
    end associate
  end function grid_global_cell

  !> The stored cell (owned or ghost) that is cell gc of the whole grid
  !> (`grid_global_cell`'s numbering), 0 where the block does not store it.
  pure integer function grid_stored_cell(this, gc) result(c)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: gc
    integer :: ijk(3)
    associate (n => this%gn)
      ijk = [mod(gc - 1, n(1)) + 1, mod((gc - 1)/n(1), n(2)) + 1, (gc - 1)/(n(1)*n(2)) + 1] - this%off
    end associate
    c = 0
    if (all(ijk >= this%slo .and. ijk <= this%shi)) c = this%cell(ijk(1), ijk(2), ijk(3))
  end function grid_stored_cell

  !> Index of the first (local a = 1) node of cell (i,j,k): node (i-1,j-1,k-1).
  pure integer function grid_cell_node0(this, i, j, k)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: i, j, k
    grid_cell_node0 = this%nbase + (i - 1) + this%sx*(j - 1) + this%sxy*(k - 1)
  end function grid_cell_node0

  !> Index of the first (local a = 1) node of cell c.
  pure integer function grid_node0(this, c)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: c
    integer :: ci, cj, ck
    call this%cell_ijk(c, ci, cj, ck)
    grid_node0 = this%cell_node0(ci, cj, ck)
  end function grid_node0

  !> Index of local corner a (1..8, order of `mesh_geometry`) of cell c.
  pure integer function grid_corner(this, c, a)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: c, a
    grid_corner = this%node0(c) + this%corner_offset(a)
  end function grid_corner

  !> Logical indices (1-based) of cell c.
  pure subroutine grid_cell_ijk(this, c, i, j, k)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: c
    integer, intent(out) :: i, j, k
    integer :: t, ny
    ny = this%shi(2) - this%slo(2) + 1
    i = mod(c - 1, this%cx) + this%slo(1)
    t = (c - 1)/this%cx
    j = mod(t, ny) + this%slo(2)
    k = t/ny + this%slo(3)
  end subroutine grid_cell_ijk

  !> Logical indices (0-based) of node n.
  pure subroutine grid_node_ijk(this, n, i, j, k)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: n
    integer, intent(out) :: i, j, k
    integer :: t, ny
    ny = this%shi(2) - this%slo(2) + 2
    i = mod(n - 1, this%sx) + this%slo(1) - 1
    t = (n - 1)/this%sx
    j = mod(t, ny) + this%slo(2) - 1
    k = t/ny + this%slo(3) - 1
  end subroutine grid_node_ijk

  !> Physical faces of the grid that node (i,j,k) lies on: bit f-1 set for
  !> face f (FACE_XLO .. FACE_ZHI); 0 for an interior node. A block's face
  !> towards another block is no face.
  pure integer function grid_node_faces(this, i, j, k) result(m)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: i, j, k
    m = face_mask([i, j, k] + this%off, [0, 0, 0], this%gn)
  end function grid_node_faces

  !> Physical faces of the grid that cell (i,j,k) touches: bit f-1 set for face f.
  pure integer function grid_cell_faces(this, i, j, k) result(m)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: i, j, k
    m = face_mask([i, j, k] + this%off, [1, 1, 1], this%gn)
  end function grid_cell_faces

  !> Bit 2(d-1) set where ijk(d) = lo(d), bit 2d-1 where ijk(d) = hi(d).
  pure integer function face_mask(ijk, lo, hi) result(m)
    integer, intent(in) :: ijk(3), lo(3), hi(3)
    integer :: d
    m = 0
    do d = 1, 3
      if (ijk(d) == lo(d)) m = ibset(m, 2*(d - 1))
      if (ijk(d) == hi(d)) m = ibset(m, 2*d - 1)
    end do
  end function face_mask

  !> Copies a node field f(3,nnode) at the eight nodes of cell c into fn(3,8).
  pure subroutine grid_gather(this, c, f, fn)
    class(grid_index_t), intent(in) :: this
    integer, intent(in) :: c
    real(wp), intent(in) :: f(:, :)
    real(wp), intent(out) :: fn(3, 8)
    integer :: a, n0
    n0 = this%node0(c)
    do a = 1, 8
      fn(:, a) = f(:, n0 + this%corner_offset(a))
    end do
  end subroutine grid_gather
  !> The rows of block g's stored nodes (nodes true; else its stored cells)
  !> in a grid wg that stores them too (g's indices plus g%off - wg%off are
  !> wg's), for values of m per entry: row r starts after to(r) values in
  !> g's arrays and after from(r) in wg's, and holds len values (a row's
  !> entries are consecutive in both). `grid_copy_rows_real` and `_int`
  !> (to, from, len, a, b) copy wg's values a into g's b by them.
  subroutine grid_rows(g, wg, nodes, m, to, from, len, stat, box)
    class(grid_index_t), intent(in) :: g, wg
    logical, intent(in) :: nodes
    integer, intent(in) :: m
    integer, allocatable, intent(out) :: to(:), from(:)
    integer, intent(out) :: len, stat
    !> the cells of g (its indices, lo then hi) whose rows are copied, and
    !> their nodes (default: g's stored cells)
    integer, intent(in), optional :: box(3, 2)
    integer :: i, j, k, o(3), e, r, lo(3), hi(3)
    e = merge(1, 0, nodes)
    o = g%off - wg%off
    lo = g%slo
    hi = g%shi
    if (present(box)) then
      lo = box(:, 1)
      hi = box(:, 2)
    end if
    i = lo(1) - e
    len = m*(hi(1) - i + 1)
    r = (hi(2) - lo(2) + 1 + e)*(hi(3) - lo(3) + 1 + e)
    allocate(to(r), from(r), stat=stat)
    if (stat /= 0) return
    r = 0
    do k = lo(3) - e, hi(3)
      do j = lo(2) - e, hi(2)
        r = r + 1
        if (nodes) then
          to(r) = m*(g%node(i, j, k) - 1)
          from(r) = m*(wg%node(i + o(1), j + o(2), k + o(3)) - 1)
        else
          to(r) = m*(g%cell(i, j, k) - 1)
          from(r) = m*(wg%cell(i + o(1), j + o(2), k + o(3)) - 1)
        end if
      end do
    end do
  end subroutine grid_rows

  subroutine grid_copy_rows_real(to, from, len, a, b)
    integer, intent(in) :: to(:), from(:), len
    real(wp), intent(in) :: a(*)
    real(wp), intent(inout) :: b(*)
    integer :: r
    do r = 1, size(to)
      b(to(r) + 1:to(r) + len) = a(from(r) + 1:from(r) + len)
    end do
  end subroutine grid_copy_rows_real

  subroutine grid_copy_rows_int(to, from, len, a, b)
    integer, intent(in) :: to(:), from(:), len
    integer, intent(in) :: a(*)
    integer, intent(inout) :: b(*)
    integer :: r
    do r = 1, size(to)
      b(to(r) + 1:to(r) + len) = a(from(r) + 1:from(r) + len)
    end do
  end subroutine grid_copy_rows_int

  !> The first node of g whose row g%moved_rows does not flag but whose
  !> place in x differs from g%x (0 if none; -1 if the flags do not match
  !> the grid): the check that the Lagrangian steps noted every node they
  !> moved.
  integer function grid_unflagged_move(g, x) result(bad)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :)
    integer :: n
    bad = -1
    if (size(g%moved_rows)*g%sx /= g%nnode) return
    bad = 0
    do n = 1, g%nnode
      if (g%moved_rows((n - 1)/g%sx + 1)) cycle
      if (any(abs(x(:, n) - g%x(:, n)) > 0.0_wp)) then
        bad = n
        return
      end if
    end do
  end function grid_unflagged_move


  !> Whether any of m nodes' coordinates differ between a and b (the
  !> largest difference: no early exit, so that the compiler takes several
  !> at a time).
  pure logical function nodes_moved(m, a, b) result(moved)
    integer, intent(in) :: m
    real(wp), intent(in) :: a(3*m), b(3*m)
    real(wp) :: d
    integer :: i
    d = 0.0_wp
    do i = 1, 3*m
      d = max(d, abs(a(i) - b(i)))
    end do
    moved = d > 0.0_wp
  end function nodes_moved

  !> Copies the node positions of cell (ci,cj,ck) of a block of ni x nj
  !> cells per layer from x(3, nnode) into xn(3,8) (for code that has the
  !> block sizes but no grid_t, such as a grid being built or an old grid).
  pure subroutine block_gather(ni, nj, ci, cj, ck, x, xn)
    integer, intent(in) :: ni, nj, ci, cj, ck
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: xn(3, 8)
    integer :: n0, sx, sxy
    ! (the numbering of `grid_index(ni, nj, nk)`, without building it: this
    ! is called once per cell by every whole-grid loop)
    sx = ni + 1
    sxy = (ni + 1)*(nj + 1)
    n0 = 1 + (ci - 1) + sx*(cj - 1) + sxy*(ck - 1)
    ! (the corners in `hex_corner`'s order, a = 1 + i + 2j + 4k, written
    ! out: the table read and its products at every call cost twice the
    ! copy, and this runs several times per remapped cell)
    xn(:, 1) = x(:, n0)
    xn(:, 2) = x(:, n0 + 1)
    xn(:, 3) = x(:, n0 + sx)
    xn(:, 4) = x(:, n0 + sx + 1)
    xn(:, 5) = x(:, n0 + sxy)
    xn(:, 6) = x(:, n0 + sxy + 1)
    xn(:, 7) = x(:, n0 + sxy + sx)
    xn(:, 8) = x(:, n0 + sxy + sx + 1)
  end subroutine block_gather

  !> For each node of block ix: whether every cell of the block around it
  !> (up to 8) has cell(c) true; false for a node none of whose cells has.
  !> The cells with cell(c) true are counted per node, so the cost is one
  !> pass over the cells and one over the nodes, with no neighbour search.
  subroutine nodes_within(ix, cell, within, err)
    type(grid_index_t), intent(in) :: ix
    logical, intent(in) :: cell(:)
    logical, intent(out) :: within(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: nin(:)
    integer :: i, j, k, a, n, stat
    allocate(nin(ix%nnode), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'nodes_within', error_no_memory('the cells per node'))
      return
    end if
    nin = 0
    do k = ix%clo(3), ix%chi(3)
      do j = ix%clo(2), ix%chi(2)
        do i = ix%clo(1), ix%chi(1)
          if (.not. cell(ix%cell(i, j, k))) cycle
          n = ix%cell_node0(i, j, k)
          do a = 1, 8
            nin(n + ix%corner_offset(a)) = nin(n + ix%corner_offset(a)) + 1
          end do
        end do
      end do
    end do
    do k = ix%nlo(3), ix%nhi(3)
      do j = ix%nlo(2), ix%nhi(2)
        do i = ix%nlo(1), ix%nhi(1)
          n = ix%node(i, j, k)
          within(n) = nin(n) > 0 .and. nin(n) == (min(i + 1, ix%chi(1)) - max(i, ix%clo(1)) + 1)* &
                                                 (min(j + 1, ix%chi(2)) - max(j, ix%clo(2)) + 1)* &
                                                 (min(k + 1, ix%chi(3)) - max(k, ix%clo(3)) + 1)
        end do
      end do
    end do
  end subroutine nodes_within

  !> Registers the grid's restart fields: the node positions.
  subroutine grid_register_restart(g, reg)
    type(grid_t), intent(inout), target :: g
    type(registry_t), intent(inout) :: reg
    call reg%add('x', 'length', LOC_NODE, g%x)
  end subroutine grid_register_restart
end module mesh_grid
