!> Mesh smoothing kernels of the combined smoothing step (Sect. 5.3): the
!> modified GETMe (Eqs. 49-50), the weighted average (Eq. 52), the original
!> GETMe of Vartziotis et al. (Eqs. 47-48, for comparison), their combination
!> iterated to a quality target (Sect. 5.3.2, Q of Eq. 46) and transfinite
!> interpolation of a cuboid index box (Eq. 53, the fallback).
!>
!> Which nodes move is said in two steps. A mobility (`smooth_mobility_t`)
!> gives every node of an ni x nj x nk block a kind: fixed, free, or sliding
!> in a plane (unit normal `dir`) or along a line (unit direction `dir`).
!> `smooth_mobility_box` builds the rules of the paper (Sect. 5.3.2) for a
!> block whose boundary is the domain's: face nodes slide in their face,
!> edge nodes along their edge, corners stay; nodes of `frozen` cells (cells
!> holding solid particles, Fig. 4f) never move. A region
!> (`smooth_region_t`, from `smooth_region_init`) then takes a mask of the
!> active cells (the subdomains, or the whole block): a node moves only if
!> its mobility allows it and every cell of the block around it is active,
!> so the nodes on the border of the active cells stay where they are and
!> cells outside are never touched. The region holds the lists of active
!> cells and movable nodes and the work arrays, allocated once; the passes
!> then allocate nothing.
!>
!> Every pass takes x(3, (ni+1)(nj+1)(nk+1)), the positions of all nodes of
!> the block (length, numbered as in `mesh_grid`), and updates it in place.
!> It is Jacobi-style: first a loop over the active cells computes,
!> from the old positions, what each cell proposes for its nodes; then a
!> loop over the movable nodes replaces each node by the average of the
!> proposals of its cells and applies its constraint. No node reads another
!> node's new position, so the result does not depend on the thread count.
!> Constraints act on the displacement (d - n (n.d) in a plane, t (t.d) along
!> a line), so for axis-aligned planes and lines the fixed coordinates are
!> kept bit for bit.
!>
!> Boundary nodes (Sect. 5.3.2): the paper moves face nodes by the 2D
!> versions of the smoothers (Eqs. 51-52) and edge nodes to the arithmetic
!> mean of their neighbours along the edge. Here a face or edge node takes
!> the same 3D proposal as an inner node (the mean over its 4 or 2 cells),
!> projected onto its face or edge: only the tangential part is used, which
!> plays the part of the 2D (1D) smoother, the face (edge) coordinates are
!> kept exactly, and the uniform grid stays a fixed point.
!>
!> Use: smooth_mobility_box once per block (and again when frozen cells
!> change), smooth_region_init per set of subdomains (active = the
!> smoothing cells, e.g. rezone_subdomains' cell_smooth), smooth_combined,
!> then smooth_tfi on the merged cuboids if Q_min is still below target.
module rezone_smooth
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use mesh_geometry, only: hex_corner, hex_faces, hex_edges, hex_volume, hex_tets, tet_det, cross
  use rezone_quality, only: hex_quality, hex_quality_box_parts, hex_box_sides, hex_edge_means
  use mesh_grid, only: grid_index_t, grid_index, nodes_within
  use mesh_halo, only: halo_t
  implicit none
  private
  public :: node_fixed, node_free, node_plane, node_line
  public :: smooth_mobility_t, smooth_region_t, tfi_shell_t, smooth_tfi_shell, tfi_shell_put, smooth_tfi_parameters, &
            smooth_tfi_node
  public :: smooth_mobility_box, smooth_mobility_block, smooth_region_init
  public :: smooth_modified_getme, smooth_weighted_average, smooth_getme_original
  public :: smooth_combined, smooth_q_min, smooth_tfi, smooth_keep_small_moves, smooth_revert_tangled, &
            smooth_region_tangled
  public :: hex_centroid, hex_cube_target, hex_box_target, hex_getme_target, getme_b_default
  public :: hex_min_tet_volume, hex_min_corner_jacobian, hex_tangled, hex_health, smooth_untangle

  !> Node kinds of a mobility: never moves, moves freely, slides in the
  !> plane through it with unit normal `dir`, slides along the line through
  !> it with unit direction `dir`.
  integer, parameter :: node_fixed = 0, node_free = 1, node_plane = 2, node_line = 3

  !> Scaling factor b of Eq. (48) that maps a cube onto itself before the
  !> size correction: (2/3) 3^(1/4).
  real(wp), parameter :: getme_b_default = (2.0_wp/3.0_wp)*3.0_wp**0.25_wp

  !> How each node of an ni x nj x nk block may move.
  type :: smooth_mobility_t
    integer :: ni = 0, nj = 0, nk = 0
    integer, allocatable :: kind(:)        !< (nnode) node_fixed, node_free, node_plane or node_line
    real(wp), allocatable :: dir(:, :)     !< (3, nnode) unit plane normal or line direction
  end type smooth_mobility_t

  !> Active cells, movable nodes and work arrays of one smoothing region.
  type :: smooth_region_t
    integer :: ni = 0, nj = 0, nk = 0
    integer :: ncell = 0                   !< number of active cells
    integer :: nmove = 0                   !< number of movable nodes
    integer :: corner_offset(8) = 0        !< node index offsets of the local corners
    integer, allocatable :: cell(:)        !< (ncell) active cells
    integer, allocatable :: node0(:)       !< (ncell) their first (local a = 1) node
    integer, allocatable :: node(:)        !< (nmove) movable nodes
    integer, allocatable :: kind(:)        !< (nmove) their kind (free, plane or line)
    real(wp), allocatable :: dir(:, :)     !< (3, nmove) their plane normal or line direction
    !> (8, nmove) slot in cell(:) of the cell in which the node is local
    !> corner a, 0 where the block has no such cell
    integer, allocatable :: node_cell(:, :)
    real(wp), allocatable :: xt(:, :, :)   !< (3, 8, ncell) work: proposed node positions
    real(wp), allocatable :: xcell(:, :)   !< (3, ncell) work: cell centres
    real(wp), allocatable :: wcell(:)      !< (ncell) work: cell weights
    !> The box reading (`smooth_region_init` with aspect_max): cells are
    !> smoothed towards boxes of their own proportions (`hex_box_target`),
    !> the weighted average keeps the node spacing (weights 1/(a1 a2 a3)) and
    !> the quality is Eq. (46) against the cell's own box. Else the paper's
    !> cubes, volume weights and Eq. (46).
    logical :: box = .false.
    real(wp) :: aspect_max = 1.0_wp        !< largest aspect ratio of a target box (box reading)
    !> the smallest share of its volume at the smoothing's start a pass may
    !> leave an active cell (`guard_undo` takes it as tangled below); 0: off
    real(wp) :: squeeze = 0.0_wp
    !> cells whose health (`hex_health`) is below this are untangled
    !> (`smooth_untangle`) before the smoothing passes; 0: off
    real(wp) :: health_min = 0.0_wp
    integer :: n_untangled = 0             !< node moves of the untangling (last smoothing)
    integer :: origin(3) = 0               !< the whole grid's index of the block's first node (0-based)
    !> (nmove) the node's colour class for `smooth_untangle` (0..7: the
    !> parities of its whole-grid indices), and work: whether it moves there
    integer, allocatable :: colour(:)
    logical, allocatable :: pick(:)
    real(wp), allocatable :: vstart(:)     !< (ncell) work: volumes at the smoothing's start
    integer :: n_guarded = 0               !< node moves the untangling guard halved or undid (last smoothing)
    real(wp), allocatable :: xsave(:, :)   !< (3, nmove) work: positions before a pass
    integer, allocatable :: nhalve(:)      !< (nmove) work: times a node's move was halved
    integer, allocatable :: node_slot(:)   !< (nnode of the block) work: slot in node(:), 0 if the node does not move
    integer, allocatable :: cell_slot(:)   !< (ncell of the block) slot in cell(:), 0 if the cell is not active
    !> the nodes a ghost refresh may change (those the block does not
    !> count: its ghosts, and its faces' nodes a neighbour counts), and
    !> (3, size(ghost)) work: where they were before a refresh
    integer, allocatable :: ghost(:)
    real(wp), allocatable :: xpre(:, :)
    !> ghost layers of the blocks (`smooth_region_init`'s ghost_width), and
    !> whether an active cell of this block lies within reach of them: its
    !> nodes may be a neighbour's ghosts, or its ghosts the neighbour's
    !> moves (`region_shares_ghosts`); exchange: whether that holds on any
    !> block, so the smoothing refreshes ghosts (`smooth_combined`)
    integer :: ghost_width = 0
    logical :: shares = .false., exchange = .false.
    !> the box of the active cells' nodes, whole-grid node indices (lo > hi:
    !> none): every node a pass writes, or marks, lies in it
    integer :: node_lo(3) = 0, node_hi(3) = -1
    !> (nmove) whether the node counts in the counts of a decomposed grid
    !> (each node on one block: `smooth_region_init`'s counts)
    logical, allocatable :: own(:)
    !> (1, nnode of the block) work: corners of the cells a pass tangled
    !> (0 between rounds), and the nodes so marked (nmarked of them)
    real(wp), allocatable :: mark(:, :)
    integer, allocatable :: marked(:)
    integer :: nmarked = 0
    logical, allocatable :: near(:)        !< (nnode of the block) work: within guard_reach of a marked node
    !> (ncell) work: each active cell not spoiled before a pass (`spoiled`)
    logical, allocatable :: untangled(:)
    !> (ncell) work: the cells the guard finds spoiled (of those not spoiled
    !> before the pass; `smooth_untangle`: those below health_min), and
    !> those whose nodes the guard changed in a round
    logical, allocatable :: tangled(:), recheck(:)
    !> whether `untangled` holds for the present positions (what the
    !> guard's last round found)
    logical :: known = .false.
  end type smooth_region_t

  !> The shell of a node index box lo..hi for the TFI (`smooth_tfi`): the
  !> nodes on its faces, fi(:, j, k, s) on the low (s = 1) and high (s = 2)
  !> face in i, fj(:, i, k, s) and fk(:, i, j, s) likewise, and the edge
  !> parameters (`smooth_tfi_parameters`). A block of a decomposed grid
  !> holds the shell of a merged cuboid, not its nodes.
  type :: tfi_shell_t
    integer :: lo(3) = 0, hi(3) = 0
    real(wp), allocatable :: fi(:, :, :, :), fj(:, :, :, :), fk(:, :, :, :)
    real(wp), allocatable :: ua(:, :), va(:, :), wa(:, :)
  end type tfi_shell_t

contains

  !> Mobility of the nodes of an ni x nj x nk block whose boundary is the
  !> domain's boundary (Sect. 5.3.2). The block's faces are taken as the
  !> planes x_d = const of an axis-aligned box in the logical directions
  !> (as `grid_init_box` builds), so the plane normals and line directions
  !> are unit axis vectors. `boundary`:
  !>   'slide' (default) face nodes slide in their face, edge nodes along
  !>           their edge, corners are fixed (issue 6, the paper's rules);
  !>   'fixed' every boundary node is fixed;
  !>   'free'  no node is constrained (e.g. a single cell on its own).
  !> Nodes of the cells with frozen(c) true (cells holding solid particles,
  !> Fig. 4f) are fixed whatever `boundary` says; the caller may fix more
  !> nodes by setting mob%kind(n) = node_fixed.
  subroutine smooth_mobility_box(ni, nj, nk, mob, err, boundary, frozen)
    integer, intent(in) :: ni, nj, nk
    type(smooth_mobility_t), intent(out) :: mob
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), intent(in), optional :: boundary
    logical, intent(in), optional :: frozen(:)
    character(len=:), allocatable :: rule
    character(len=200) :: msg
    integer :: i, j, k, n, d, nb, stat, ci, cj, ck, a, n0, m
    logical :: on(3)
    type(grid_index_t) :: ix

    if (ni < 1 .or. nj < 1 .or. nk < 1) then
      call error_set(err, 'smooth_mobility_box', 'the block needs at least one cell in each direction')
      return
    end if
    rule = 'slide'
    if (present(boundary)) rule = trim(boundary)
    if (rule /= 'slide' .and. rule /= 'fixed' .and. rule /= 'free') then
      call error_set(err, 'smooth_mobility_box', "boundary = '"//rule//"' is not known; valid: slide, fixed, free")
      return
    end if
    if (present(frozen)) then
      if (size(frozen) /= ni*nj*nk) then
        call error_set(err, 'smooth_mobility_box', 'frozen(:) must have one entry per cell')
        return
      end if
    end if
    mob%ni = ni; mob%nj = nj; mob%nk = nk
    ix = grid_index(ni, nj, nk)
    allocate(mob%kind(ix%nnode), mob%dir(3, ix%nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'smooth_mobility_box', error_no_memory('the mobility'))
      return
    end if

    do k = ix%nlo(3), ix%nhi(3)
      do j = ix%nlo(2), ix%nhi(2)
        do i = ix%nlo(1), ix%nhi(1)
          n = ix%node(i, j, k)
          ! on(d): the node lies on the low or high face of direction d
          m = ix%node_faces(i, j, k)
          on = [(ibits(m, 2*(d - 1), 2) /= 0, d = 1, 3)]
          nb = count(on)
          mob%dir(:, n) = 0.0_wp
          if (nb == 0 .or. rule == 'free') then
            mob%kind(n) = node_free
          else if (rule == 'fixed' .or. nb == 3) then
            mob%kind(n) = node_fixed
          else if (nb == 1) then
            ! a face node: the face's normal is the logical direction it closes
            mob%kind(n) = node_plane
            do d = 1, 3
              if (on(d)) mob%dir(d, n) = 1.0_wp
            end do
          else
            ! an edge node: the edge runs along the one open direction
            mob%kind(n) = node_line
            do d = 1, 3
              if (.not. on(d)) mob%dir(d, n) = 1.0_wp
            end do
          end if
        end do
      end do
    end do

    if (present(frozen)) then
      do ck = ix%clo(3), ix%chi(3)
        do cj = ix%clo(2), ix%chi(2)
          do ci = ix%clo(1), ix%chi(1)
            if (.not. frozen(ix%cell(ci, cj, ck))) cycle
            n0 = ix%cell_node0(ci, cj, ck)
            do a = 1, 8
              mob%kind(n0 + ix%corner_offset(a)) = node_fixed
            end do
          end do
        end do
      end do
    end if
  end subroutine smooth_mobility_box

  !> Mobility of the stored nodes (owned and ghost) of block ix of a
  !> decomposed grid, numbered as ix numbers them: the rules of
  !> `smooth_mobility_box` ('slide') on the whole grid's faces. A node on a
  !> face of the stored box that is not the whole grid's is fixed here: it
  !> is a ghost, whose place comes from its owner. Without ghosts, the
  !> mobility of smooth_mobility_box. frozen(ncell): as there, stored cells.
  !> fixed_faces(6) (xlo, xhi, ylo, yhi, zlo, zhi): the whole grid's faces
  !> whose nodes are fixed, edges and corners included (faces that move
  !> with the material, a piston or a free surface: the smoothing's planes
  !> are the logical box's, which such a face leaves, and a node slid
  !> along one would leave the material's boundary). fixed_nodes: stored
  !> nodes that are fixed too (a clamp's, &boundary fixed_lo, fixed_hi).
  subroutine smooth_mobility_block(ix, mob, err, frozen, fixed_faces, fixed_nodes)
    type(grid_index_t), intent(in) :: ix
    type(smooth_mobility_t), intent(out) :: mob
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: frozen(:)
    logical, intent(in), optional :: fixed_faces(6)
    integer, intent(in), optional :: fixed_nodes(:)
    integer :: i, j, k, d, f, ijk(3), m
    logical :: fixed(6)
    call smooth_mobility_box(ix%shi(1) - ix%slo(1) + 1, ix%shi(2) - ix%slo(2) + 1, ix%shi(3) - ix%slo(3) + 1, &
                             mob, err, frozen=frozen)
    if (allocated(err)) return
    fixed = .false.
    if (present(fixed_faces)) fixed = fixed_faces
    do k = ix%slo(3) - 1, ix%shi(3)
      do j = ix%slo(2) - 1, ix%shi(2)
        do i = ix%slo(1) - 1, ix%shi(1)
          ijk = [i, j, k]
          m = ix%node_faces(i, j, k)
          do d = 1, 3
            ! on the stored box's low (high) face in d, not the grid's
            if ((ijk(d) == ix%slo(d) - 1 .and. .not. btest(m, 2*(d - 1))) .or. &
                (ijk(d) == ix%shi(d) .and. .not. btest(m, 2*d - 1))) mob%kind(ix%node(i, j, k)) = node_fixed
          end do
          ! (bit f - 1 of node_faces: the node lies on the grid's face f)
          do f = 1, 6
            if (fixed(f) .and. btest(m, f - 1)) mob%kind(ix%node(i, j, k)) = node_fixed
          end do
        end do
      end do
    end do
    if (present(fixed_nodes)) mob%kind(fixed_nodes) = node_fixed
  end subroutine smooth_mobility_block

  !> Builds the region of the cells with active(c) true on the block of
  !> `mob`: the active cells, the nodes that may move (mobility not fixed
  !> and every cell of the block around the node active) and the work
  !> arrays of the passes. With aspect_max (>= 1), the box reading (see
  !> `smooth_region_t`).
  subroutine smooth_region_init(mob, active, reg, err, aspect_max, counts, squeeze, health_min, origin, ghost_width)
    type(smooth_mobility_t), intent(in) :: mob
    logical, intent(in) :: active(:)
    type(smooth_region_t), intent(out) :: reg
    type(error_t), allocatable, intent(inout) :: err
    real(wp), intent(in), optional :: aspect_max
    !> (reg%squeeze) the smallest share of its starting volume a pass may leave a cell; default 0 (off)
    real(wp), intent(in), optional :: squeeze
    !> (nnode) the nodes this block counts (a decomposed grid's; default all)
    logical, intent(in), optional :: counts(:)
    !> (reg%health_min) cells below this health are untangled first; default 0 (off)
    real(wp), intent(in), optional :: health_min
    !> (reg%origin) the whole grid's index of the block's first node; default 0
    integer, intent(in), optional :: origin(3)
    !> (reg%ghost_width) the ghost layers of a decomposed grid's blocks; default 0
    integer, intent(in), optional :: ghost_width
    integer :: ni, nj, nk, ncell_all, c, s, i, j, k, n, m, a, ci, cj, ck, stat
    logical, allocatable :: within(:)
    character(len=200) :: msg
    type(grid_index_t) :: ix

    ni = mob%ni; nj = mob%nj; nk = mob%nk
    ncell_all = ni*nj*nk
    if (.not. allocated(mob%kind) .or. ncell_all < 1) then
      call error_set(err, 'smooth_region_init', 'the mobility has not been built')
      return
    end if
    if (size(active) /= ncell_all) then
      call error_set(err, 'smooth_region_init', 'active(:) must have one entry per cell')
      return
    end if
    if (present(aspect_max)) then
      if (.not. aspect_max >= 1.0_wp) then
        call error_set(err, 'smooth_region_init', 'aspect_max must be >= 1')
        return
      end if
      reg%box = .true.
      reg%aspect_max = aspect_max
    end if
    if (present(squeeze)) then
      if (.not. (squeeze >= 0.0_wp .and. squeeze < 1.0_wp)) then
        call error_set(err, 'smooth_region_init', 'squeeze must be in [0, 1)')
        return
      end if
      reg%squeeze = squeeze
    end if
    if (present(health_min)) then
      if (.not. (health_min >= 0.0_wp .and. health_min < 1.0_wp)) then
        call error_set(err, 'smooth_region_init', 'health_min must be in [0, 1)')
        return
      end if
      reg%health_min = health_min
    end if
    if (present(origin)) reg%origin = origin
    ix = grid_index(ni, nj, nk)
    reg%ni = ni; reg%nj = nj; reg%nk = nk
    reg%corner_offset = ix%corner_offset
    reg%ncell = count(active)

    allocate(reg%cell_slot(ncell_all), reg%cell(reg%ncell), reg%node0(reg%ncell), reg%xt(3, 8, reg%ncell), &
             reg%xcell(3, reg%ncell), reg%wcell(reg%ncell), reg%node_slot(ix%nnode), reg%untangled(reg%ncell), &
             reg%vstart(reg%ncell), &
             reg%tangled(reg%ncell), reg%recheck(reg%ncell), reg%mark(1, ix%nnode), reg%near(ix%nnode), &
             within(ix%nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'smooth_region_init', error_no_memory('the region'))
      return
    end if
    reg%mark = 0.0_wp
    reg%near = .false.
    if (present(counts)) then
      reg%ghost = pack([(n, n = 1, ix%nnode)], .not. counts)
    else
      allocate(reg%ghost(0), stat=stat)
    end if
    allocate(reg%xpre(3, size(reg%ghost)), reg%marked(ix%nnode + size(reg%ghost)), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'smooth_region_init', error_no_memory('the region'))
      return
    end if

    ! the active cells
    reg%cell_slot = 0
    s = 0
    do ck = ix%clo(3), ix%chi(3)
      do cj = ix%clo(2), ix%chi(2)
        do ci = ix%clo(1), ix%chi(1)
          c = ix%cell(ci, cj, ck)
          if (.not. active(c)) cycle
          s = s + 1
          reg%cell_slot(c) = s
          reg%cell(s) = c
          reg%node0(s) = ix%cell_node0(ci, cj, ck)
        end do
      end do
    end do
    call nodes_within(ix, active, within, err)
    if (allocated(err)) return

    ! movable nodes: mobility allows it and all cells around are active
    reg%nmove = 0
    do k = ix%nlo(3), ix%nhi(3)
      do j = ix%nlo(2), ix%nhi(2)
        do i = ix%nlo(1), ix%nhi(1)
          if (node_moves(i, j, k)) reg%nmove = reg%nmove + 1
        end do
      end do
    end do
    allocate(reg%node(reg%nmove), reg%kind(reg%nmove), reg%dir(3, reg%nmove), reg%node_cell(8, reg%nmove), &
             reg%xsave(3, reg%nmove), reg%nhalve(reg%nmove), reg%own(reg%nmove), reg%colour(reg%nmove), &
             reg%pick(reg%nmove), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'smooth_region_init', error_no_memory('the region'))
      return
    end if

    m = 0
    do k = ix%nlo(3), ix%nhi(3)
      do j = ix%nlo(2), ix%nhi(2)
        do i = ix%nlo(1), ix%nhi(1)
          if (.not. node_moves(i, j, k)) cycle
          m = m + 1
          n = ix%node(i, j, k)
          reg%node(m) = n
          ! (the parities of the whole grid's node indices)
          reg%colour(m) = mod(i + reg%origin(1), 2) + 2*mod(j + reg%origin(2), 2) + 4*mod(k + reg%origin(3), 2)
          reg%own(m) = .true.
          if (present(counts)) reg%own(m) = counts(n)
          reg%kind(m) = mob%kind(n)
          reg%dir(:, m) = mob%dir(:, n)
          ! the node is corner a of the cell whose lowest corner is node - corner a
          do a = 1, 8
            ci = i - hex_corner(1, a) + 1
            cj = j - hex_corner(2, a) + 1
            ck = k - hex_corner(3, a) + 1
            reg%node_cell(a, m) = 0
            if (all([ci, cj, ck] >= ix%clo) .and. all([ci, cj, ck] <= ix%chi)) &
              reg%node_cell(a, m) = reg%cell_slot(ix%cell(ci, cj, ck))
          end do
        end do
      end do
    end do
    if (present(ghost_width)) reg%ghost_width = ghost_width
    reg%shares = region_shares_ghosts(reg, ix)
    if (reg%ncell > 0) then
      reg%node_lo = huge(1)
      reg%node_hi = -huge(1)
      do s = 1, reg%ncell
        call ix%node_ijk(reg%node0(s), i, j, k)
        reg%node_lo = min(reg%node_lo, [i, j, k] + reg%origin)
        reg%node_hi = max(reg%node_hi, [i, j, k] + 1 + reg%origin)
      end do
    end if

  contains

    !> Whether node (i,j,k) may move in this region: its mobility allows it
    !> and every cell of the block around it is active.
    logical function node_moves(i, j, k)
      integer, intent(in) :: i, j, k
      integer :: n
      n = ix%node(i, j, k)
      node_moves = within(n) .and. mob%kind(n) /= node_fixed
    end function node_moves
  end subroutine smooth_region_init

  !> Whether the smoothing of region reg on block ix may write a node that
  !> another block stores, or read one that another block writes: some
  !> non-counted node (reg%ghost) lies within ghost_width + 1 index steps of
  !> the box around the active cells' nodes. The smoothing writes the
  !> corners of active cells only, and a neighbour stores this block's
  !> nodes up to ghost_width layers from their shared face, within
  !> ghost_width + 1 steps of this block's non-counted nodes; the guard's
  !> marks are corners of active cells too. So where no block shares, no
  !> ghost refresh changes anything, and `smooth_combined` skips them.
  logical function region_shares_ghosts(reg, ix) result(shares)
    type(smooth_region_t), intent(in) :: reg
    type(grid_index_t), intent(in) :: ix
    integer :: s, g, p(3), lo(3), hi(3)
    shares = .false.
    if (reg%ncell == 0 .or. size(reg%ghost) == 0) return
    lo = huge(1)
    hi = -huge(1)
    do s = 1, reg%ncell
      call ix%node_ijk(reg%node0(s), p(1), p(2), p(3))
      lo = min(lo, p)
      hi = max(hi, p + 1)
    end do
    do g = 1, size(reg%ghost)
      call ix%node_ijk(reg%ghost(g), p(1), p(2), p(3))
      if (maxval(max(lo - p, p - hi, 0)) <= reg%ghost_width + 1) then
        shares = .true.
        return
      end if
    end do
  end function region_shares_ghosts

  !> Centroid of a hexahedron xn(3,8) by Eq. (49): the volume-weighted mean
  !> of the centroids of its 24 tetrahedra (Fig. 7: each face split into four
  !> triangles through the face centre, each joined to the cell centre).
  !> For a tangled cell whose signed volume is less than half the sum of the
  !> tetrahedra's absolute volumes the quotient is ill-conditioned (it
  !> diverges as the volume goes to zero), and the node mean (Eq. 47) is
  !> returned instead; a cell inverted as a whole keeps Eq. (49).
  pure function hex_centroid(xn) result(xc)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: xc(3)
    real(wp) :: r(3, 8), rc(3), rf(3), e1(3), vt, v, vabs, mom(3)
    integer :: m, d, f, a, b

    do d = 1, 3
      xc(d) = 0.125_wp*sum(xn(d, :))
    end do
    do m = 1, 8
      r(:, m) = xn(:, m) - xc
    end do
    ! the tetrahedra of hex_tets(r), written out (the numbers of `hex_tets`
    ! and `tet_det`, without the array of 24 tetrahedra)
    do d = 1, 3
      rc(d) = 0.125_wp*sum(r(d, :))
    end do
    v = 0.0_wp
    vabs = 0.0_wp
    mom = 0.0_wp
    do f = 1, 6
      rf = 0.25_wp*((r(:, hex_faces(1, f)) + r(:, hex_faces(3, f))) + &
                    (r(:, hex_faces(2, f)) + r(:, hex_faces(4, f))))
      e1 = rf - rc
      do m = 1, 4
        a = hex_faces(m, f)
        b = hex_faces(mod(m, 4) + 1, f)
        vt = triple(e1, r(:, a) - rc, r(:, b) - rc)/6.0_wp
        v = v + vt
        vabs = vabs + abs(vt)
        mom = mom + vt*0.25_wp*(rc + rf + r(:, a) + r(:, b))
      end do
    end do
    if (abs(v) > 0.5_wp*vabs) xc = xc + mom/v
  end function hex_centroid

  !> Smallest signed volume (length^3) of the 24 tetrahedra of the split of
  !> Fig. 7 (centre, face centre, two neighbouring nodes of the face), the
  !> split the remap intersects: a cell with a non-positive one is tangled
  !> even when its total volume is positive.
  pure function hex_min_tet_volume(xn) result(vmin)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: vmin
    real(wp) :: tets(3, 4, 24)
    integer :: t
    call hex_tets(xn, tets)
    vmin = huge(1.0_wp)
    do t = 1, 24
      vmin = min(vmin, tet_det(tets(:, :, t))/6.0_wp)
    end do
  end function hex_min_tet_volume

  !> Smallest Jacobian determinant of the trilinear map of a hexahedron at
  !> its eight corners (length^3): det of the three edges leaving the corner,
  !> oriented along +i, +j, +k. All eight are positive for a valid (untangled)
  !> cell; a cell with a non-positive one is illegal even if its volume is
  !> positive.
  pure function hex_min_corner_jacobian(xn) result(jmin)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: jmin
    real(wp) :: e(3, 3)
    integer :: a, d, b
    jmin = huge(1.0_wp)
    do a = 1, 8
      do d = 1, 3
        ! the neighbour across direction d flips bit d-1 of a-1
        b = 1 + ieor(a - 1, 2**(d - 1))
        e(:, d) = xn(:, b) - xn(:, a)
        if (hex_corner(d, a) == 1) e(:, d) = -e(:, d)
      end do
      jmin = min(jmin, dot_product(e(:, 1), cross(e(:, 2), e(:, 3))))
    end do
  end function hex_min_corner_jacobian

  !> A hexahedron's health: the smaller of its smallest corner Jacobian
  !> (`hex_min_corner_jacobian`) and 24 times its smallest tetrahedron of the
  !> 24-tet split (`hex_min_tet_volume`), over scale**3: 1 for a cube of edge
  !> scale, about its aspect ratio's inverse for a box, <= 0 when tangled.
  pure real(wp) function hex_health(xn, scale)
    real(wp), intent(in) :: xn(3, 8), scale
    hex_health = min(hex_min_corner_jacobian(xn), 24.0_wp*hex_min_tet_volume(xn))/scale**3
  end function hex_health

  !> Whether a hexahedron is tangled: a corner Jacobian or a tetrahedron of
  !> the 24-tet split non-positive (the test of `smooth_revert_tangled`).
  !> The same numbers as those two functions, written out and stopping at
  !> the first non-positive one (the smoothing's guard tests every cell of
  !> a region after every pass).
  pure logical function hex_tangled(xn)
    real(wp), intent(in) :: xn(3, 8)
    !> corner a's edge along direction d: its number among the four along d
    !> (`hex_corner_tangled`), and the four edges' lower nodes
    integer, parameter :: edge_of(3, 8) = reshape([1, 1, 1, 1, 2, 2, 2, 1, 3, 2, 2, 4, 3, 3, 1, 3, 4, 2, &
                                                   4, 3, 3, 4, 4, 4], [3, 8])
    integer, parameter :: lower(4, 3) = reshape([1, 3, 5, 7, 1, 2, 5, 6, 1, 2, 3, 4], [4, 3])
    integer, parameter :: step(3) = [1, 2, 4]
    real(wp) :: e1(3), xc(3), xf(3), r(3, 8), ed(3, 4, 3)
    integer :: a, f, m, d, q
    hex_tangled = .true.
    ! the twelve edges, each from its lower node to its upper one: corner
    ! a's edges along +i, +j, +k (`hex_min_corner_jacobian`; the value
    ! either end's difference gives, up to the sign of a zero)
    do d = 1, 3
      do q = 1, 4
        ed(:, q, d) = xn(:, lower(q, d) + step(d)) - xn(:, lower(q, d))
      end do
    end do
    do a = 1, 8
      if (.not. triple(ed(:, edge_of(1, a), 1), ed(:, edge_of(2, a), 2), ed(:, edge_of(3, a), 3)) > 0.0_wp) return
    end do
    ! the 24 tetrahedra (centre, face centre, a, b) of `hex_tets`, as
    ! `tet_det` takes them: the edges from the centre
    do m = 1, 3
      xc(m) = 0.125_wp*sum(xn(m, :))
    end do
    do a = 1, 8
      r(:, a) = xn(:, a) - xc
    end do
    do f = 1, 6
      xf = 0.25_wp*((xn(:, hex_faces(1, f)) + xn(:, hex_faces(3, f))) + &
                    (xn(:, hex_faces(2, f)) + xn(:, hex_faces(4, f))))
      e1 = xf - xc
      do m = 1, 4
        if (.not. triple(e1, r(:, hex_faces(m, f)), r(:, hex_faces(mod(m, 4) + 1, f)))/6.0_wp > 0.0_wp) return
      end do
    end do
    hex_tangled = .false.
  end function hex_tangled

  !> a.(b x c), in the order of `tet_det` (and of dot_product with `cross`).
  pure real(wp) function triple(a, b, c)
    real(wp), intent(in) :: a(3), b(3), c(3)
    triple = a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) + a(3)*(b(1)*c(2) - b(2)*c(1))
  end function triple

  !> Mean of the 12 edge lengths of a hexahedron (length).
  pure function mean_edge(xn) result(abar)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: abar
    integer :: d, e
    abar = 0.0_wp
    do d = 1, 3
      do e = 1, 4
        abar = abar + norm2(xn(:, hex_edges(2, e, d)) - xn(:, hex_edges(1, e, d)))
      end do
    end do
    abar = abar/12.0_wp
  end function mean_edge

  !> Modified GETMe transformation of one hexahedron (Eqs. 49-50): the
  !> axis-aligned cube whose side is the mean edge length and whose centre
  !> is the centroid of Eq. (49). Eq. (50)'s columns follow the paper's
  !> counter-clockwise node numbering; in ours (a = 1 + i + 2j + 4k) the
  !> column of node a is A(:,a) = 2 (i,j,k) - 1, so local node a goes to
  !> xc + abar/2 (2 hex_corner(:,a) - 1) whatever the cell looked like,
  !> inverted or not.
  pure subroutine hex_cube_target(xn, xt)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: xt(3, 8)
    real(wp) :: xc(3), h
    integer :: a
    xc = hex_centroid(xn)
    h = 0.5_wp*mean_edge(xn)
    do a = 1, 8
      xt(:, a) = xc + h*real(2*hex_corner(:, a) - 1, wp)
    end do
  end subroutine hex_cube_target

  !> The modified GETMe transformation towards the cell's own box (the box
  !> reading of Eq. 50): the axis-aligned box centred on the centroid of
  !> Eq. (49) whose sides keep the proportions of the cell's mean edge
  !> lengths along its logical directions (aspect ratio capped at
  !> aspect_max, `hex_box_sides`), scaled to the cell's volume (the volume
  !> option of the GETMe scaling, after Eq. 48) when the cell is untangled,
  !> so that a cell compressed along a grid line stays compressed; Eq. (50)
  !> itself is this with the cube of the mean edge (aspect_max = 1, no
  !> scaling). A box of aspect ratio at most aspect_max maps onto itself.
  pure subroutine hex_box_target(xn, aspect_max, xt)
    real(wp), intent(in) :: xn(3, 8), aspect_max
    real(wp), intent(out) :: xt(3, 8)
    call box_target_of(xn, hex_box_sides(xn, aspect_max), hex_volume(xn), xt)
  end subroutine hex_box_target

  !> `hex_box_target` from the cell's own box b (`hex_box_sides`) and its
  !> volume v (`hex_volume`).
  pure subroutine box_target_of(xn, b, v, xt)
    real(wp), intent(in) :: xn(3, 8), b(3), v
    real(wp), intent(out) :: xt(3, 8)
    real(wp) :: xc(3), bs(3)
    integer :: a
    xc = hex_centroid(xn)
    bs = b
    if (v > 0.0_wp .and. all(bs > 0.0_wp)) bs = bs*(v/product(bs))**(1.0_wp/3.0_wp)
    do a = 1, 8
      xt(:, a) = xc + 0.5_wp*bs*real(2*hex_corner(:, a) - 1, wp)
    end do
  end subroutine box_target_of

  !> Original GETMe transformation of one hexahedron (Vartziotis and Wipper's
  !> dual-element transformation, Eqs. 47-48): the centres of the six faces
  !> span the dual octahedron; the octahedron face of corner a (the triangle
  !> of the centres of the three faces through a) has centroid o_a and
  !> outward normal n_a (twice its area), and corner a goes to
  !> o_a + b n_a / sqrt|n_a| (Eq. 48). The new element is then scaled about
  !> its centre so that its sum of edge lengths is the old one (the
  !> paper's second option; unlike the volume it stays positive for tangled
  !> cells) and moved so that its centre (Eq. 47) is the old one. b defaults
  !> to getme_b_default, which maps a cube onto itself.
  pure subroutine hex_getme_target(xn, xt, b)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: xt(3, 8)
    real(wp), intent(in), optional :: b
    real(wp) :: xc(3), xf(3, 6), o(3), nrm(3), nn, bb, c2(3), l0, l1
    integer :: a, d, f, p, q, s

    bb = getme_b_default
    if (present(b)) bb = b
    do d = 1, 3
      xc(d) = 0.125_wp*sum(xn(d, :))
    end do
    do f = 1, 6
      xf(:, f) = 0.25_wp*(xn(:, hex_faces(1, f)) + xn(:, hex_faces(2, f)) + xn(:, hex_faces(3, f)) + &
                          xn(:, hex_faces(4, f)))
    end do
    do a = 1, 8
      ! faces through corner (i,j,k): xi-/xi+ = 1+i, eta-/eta+ = 3+j, zeta-/zeta+ = 5+k
      p = 1 + hex_corner(1, a)
      q = 3 + hex_corner(2, a)
      s = 5 + hex_corner(3, a)
      o = (xf(:, p) + xf(:, q) + xf(:, s))/3.0_wp
      nrm = cross(xf(:, q) - xf(:, p), xf(:, s) - xf(:, p))
      ! (p, q, s) turns the other way round the corners of even parity
      if (mod(sum(hex_corner(:, a)), 2) == 0) nrm = -nrm
      nn = norm2(nrm)
      xt(:, a) = o
      if (nn > 0.0_wp) xt(:, a) = o + (bb/sqrt(nn))*nrm
    end do
    do d = 1, 3
      c2(d) = 0.125_wp*sum(xt(d, :))
    end do
    l0 = mean_edge(xn)
    l1 = mean_edge(xt)
    do a = 1, 8
      xt(:, a) = xc + (l0/l1)*(xt(:, a) - c2)
    end do
  end subroutine hex_getme_target

  !> The 8 node positions of the active cell in slot s.
  pure subroutine region_gather(reg, s, x, xn)
    type(smooth_region_t), intent(in) :: reg
    integer, intent(in) :: s
    real(wp), intent(in) :: x(:, :)
    real(wp), intent(out) :: xn(3, 8)
    integer :: a
    do a = 1, 8
      xn(:, a) = x(:, reg%node0(s) + reg%corner_offset(a))
    end do
  end subroutine region_gather

  !> Moves x from its old position towards xnew as its kind allows: the
  !> displacement is projected onto the plane or the line (exact for axis
  !> directions: the fixed coordinates do not change at all).
  pure subroutine constrain_move(kind, dir, x, xnew)
    integer, intent(in) :: kind
    real(wp), intent(in) :: dir(3), xnew(3)
    real(wp), intent(inout) :: x(3)
    real(wp) :: d(3)
    d = xnew - x
    select case (kind)
    case (node_plane)
      d = d - dir*dot_product(dir, d)
    case (node_line)
      d = dir*dot_product(dir, d)
    case (node_fixed)
      d = 0.0_wp
    end select
    x = x + d
  end subroutine constrain_move

  !> Every movable node to the mean of the positions its cells propose in
  !> reg%xt (the node averaging of GETMe), then constrained.
  subroutine move_to_mean_target(reg, x)
    type(smooth_region_t), intent(in) :: reg
    real(wp), intent(inout) :: x(:, :)
    integer :: m, a, s, cnt
    real(wp) :: xs(3)

    !$omp parallel do default(none) shared(reg, x) private(m, a, s, cnt, xs) schedule(static)
    do m = 1, reg%nmove
      xs = 0.0_wp
      cnt = 0
      do a = 1, 8
        s = reg%node_cell(a, m)
        if (s == 0) cycle
        xs = xs + reg%xt(:, a, s)
        cnt = cnt + 1
      end do
      call constrain_move(reg%kind(m), reg%dir(:, m), x(:, reg%node(m)), xs/real(cnt, wp))
    end do
    !$omp end parallel do
  end subroutine move_to_mean_target

  !> One pass of the modified GETMe (Eqs. 49-51): each active cell proposes
  !> the axis-aligned cube of `hex_cube_target` for its nodes; each movable
  !> node goes to the mean of its cells' proposals, constrained by its
  !> mobility. x(3, nnode): node positions (length), updated in place.
  subroutine smooth_modified_getme(reg, x, sides)
    type(smooth_region_t), intent(inout) :: reg
    real(wp), intent(inout) :: x(:, :)
    !> the box reading: each active cell's own box and volume at these nodes
    !> (`smooth_q_min`'s sides), not measured again
    real(wp), intent(in), optional :: sides(:, :)
    integer :: s
    real(wp) :: xn(3, 8)

    !$omp parallel do default(none) shared(reg, x, sides) private(s, xn) schedule(static)
    do s = 1, reg%ncell
      call region_gather(reg, s, x, xn)
      if (reg%box .and. present(sides)) then
        call box_target_of(xn, sides(1:3, s), sides(4, s), reg%xt(:, :, s))
      else if (reg%box) then
        call hex_box_target(xn, reg%aspect_max, reg%xt(:, :, s))
      else
        call hex_cube_target(xn, reg%xt(:, :, s))
      end if
    end do
    !$omp end parallel do
    call move_to_mean_target(reg, x)
  end subroutine smooth_modified_getme

  !> One pass of the original GETMe (Eqs. 47-48, `hex_getme_target` with
  !> factor b, default getme_b_default) with the same node averaging and
  !> constraints as `smooth_modified_getme`. x(3, nnode) in length units.
  subroutine smooth_getme_original(reg, x, b)
    type(smooth_region_t), intent(inout) :: reg
    real(wp), intent(inout) :: x(:, :)
    real(wp), intent(in), optional :: b
    integer :: s
    real(wp) :: xn(3, 8), bb

    bb = getme_b_default
    if (present(b)) bb = b
    !$omp parallel do default(none) shared(reg, x, bb) private(s, xn) schedule(static)
    do s = 1, reg%ncell
      call region_gather(reg, s, x, xn)
      call hex_getme_target(xn, reg%xt(:, :, s), bb)
    end do
    !$omp end parallel do
    call move_to_mean_target(reg, x)
  end subroutine smooth_getme_original

  !> One pass of the weighted average (Eq. 52): each movable node goes to
  !> sum_k S_k x_ck / sum_k S_k over its cells, x_ck the cell centre of
  !> Eq. (47) (the mean of its nodes) and S_k the cell volume (the paper's
  !> weight for 3D; the area in 2D), then is constrained by its mobility.
  !> Inverted cells (volume <= 0) get weight 0; a node whose cells all are
  !> inverted goes to the plain mean of their centres. x(3, nnode): node
  !> positions (length), updated in place.
  subroutine smooth_weighted_average(reg, x)
    type(smooth_region_t), intent(inout) :: reg
    real(wp), intent(inout) :: x(:, :)
    integer :: s, m, a, d, cnt
    real(wp) :: xn(3, 8), xs(3), xm(3), ws, w

    !$omp parallel do default(none) shared(reg, x) private(s, d, xn) schedule(static)
    do s = 1, reg%ncell
      call region_gather(reg, s, x, xn)
      do d = 1, 3
        reg%xcell(d, s) = 0.125_wp*sum(xn(d, :))
      end do
      if (reg%box) then
        ! 1/(a1 a2 a3): every tensor-product (graded) grid is a fixed point
        reg%wcell(s) = 1.0_wp/max(product(hex_edge_means(xn)), tiny(1.0_wp))
      else
        reg%wcell(s) = max(hex_volume(xn), 0.0_wp)
      end if
    end do
    !$omp end parallel do

    !$omp parallel do default(none) shared(reg, x) private(m, a, s, cnt, xs, xm, ws, w) schedule(static)
    do m = 1, reg%nmove
      xs = 0.0_wp
      xm = 0.0_wp
      ws = 0.0_wp
      cnt = 0
      do a = 1, 8
        s = reg%node_cell(a, m)
        if (s == 0) cycle
        w = reg%wcell(s)
        xs = xs + w*reg%xcell(:, s)
        ws = ws + w
        xm = xm + reg%xcell(:, s)
        cnt = cnt + 1
      end do
      if (ws > 0.0_wp) then
        xs = xs/ws
      else
        xs = xm/real(cnt, wp)
      end if
      call constrain_move(reg%kind(m), reg%dir(:, m), x(:, reg%node(m)), xs)
    end do
    !$omp end parallel do
  end subroutine smooth_weighted_average

  !> Worst cell quality Q_min (Eq. 46, rezone_quality's hex_quality) over
  !> the active cells of the region; huge(1.0_wp) if there are none.
  function smooth_q_min(reg, x, sides) result(q_min)
    type(smooth_region_t), intent(in) :: reg
    real(wp), intent(in) :: x(:, :)
    !> the box reading: each active cell's own box and volume
    !> (`hex_quality_box_parts`), for a GETMe pass at these nodes
    real(wp), intent(out), optional :: sides(:, :)
    real(wp) :: q_min
    integer :: s
    real(wp) :: xn(3, 8), q, bv(4)

    q_min = huge(1.0_wp)
    !$omp parallel do default(none) shared(reg, x, sides) private(s, xn, q, bv) reduction(min: q_min) &
    !$omp schedule(static)
    do s = 1, reg%ncell
      call region_gather(reg, s, x, xn)
      if (reg%box) then
        call hex_quality_box_parts(xn, reg%aspect_max, q, bv(1:3), bv(4))
        q_min = min(q_min, q)
        if (present(sides)) sides(:, s) = bv
      else
        q_min = min(q_min, hex_quality(xn))
      end if
    end do
    !$omp end parallel do
  end function smooth_q_min

  !> The combined smoothing of Sect. 5.3.2 (step 1): while Q_min over the
  !> active cells is below q_target and fewer than n_max iterations were
  !> done, one modified GETMe pass then one weighted-average pass. After
  !> each pass the untangling guard (`guard_undo`) takes back the moves
  !> that tangled a cell (or, with reg%squeeze, squeezed it below that share
  !> of its volume before the first pass). First, with reg%health_min, the
  !> cells below that health are untangled (`smooth_untangle`: the guard
  !> only keeps cells from getting worse). Returns the iterations done (0 if the grid already
  !> met the target) and the final Q_min. The TFI fallback (step 2) is the
  !> caller's: it needs the merged cuboid subdomains (`smooth_tfi`).
  !> x(3, nnode) in length units. With halo (a block of a decomposed grid,
  !> its ghost nodes current on entry): the ghost nodes are refreshed after
  !> every pass and every round of the guard, and Q_min, the guard's tests
  !> and reg%n_guarded are the whole grid's, so every block ends with the
  !> nodes of one process. q_start: Q_min before the first iteration.
  subroutine smooth_combined(reg, x, q_target, n_max, iterations, q_min, halo, q_start)
    type(smooth_region_t), intent(inout) :: reg
    real(wp), intent(inout) :: x(:, :)
    real(wp), intent(in) :: q_target
    integer, intent(in) :: n_max
    integer, intent(out) :: iterations
    real(wp), intent(out) :: q_min
    class(halo_t), intent(inout), optional :: halo
    real(wp), intent(out), optional :: q_start
    !> (the box reading: the active cells' own boxes and volumes where Q_min
    !> was last taken, for the next GETMe pass; without room for them it
    !> measures the cells itself)
    real(wp), allocatable :: sides(:, :)
    integer :: m, guarded(1), flag, stat

    ! (ghost refreshes only where some block's region reaches its ghosts:
    ! elsewhere they change nothing, `region_shares_ghosts`)
    reg%exchange = .false.
    if (present(halo)) then
      if (halo%nblocks > 1) then
        flag = merge(1, 0, reg%shares)
        call halo%max_int(flag)
        reg%exchange = flag > 0
      end if
    end if
    ! (the refreshes then only of the ghosts in the box of every block's
    ! active cells' nodes: no other node changes)
    if (reg%exchange) call limit_refreshes()
    reg%node_slot = 0
    do m = 1, reg%nmove
      reg%node_slot(reg%node(m)) = m
    end do
    iterations = 0
    reg%n_guarded = 0
    reg%known = .false.
    reg%n_untangled = 0
    if (reg%health_min > 0.0_wp) call smooth_untangle(reg, x, halo)
    if (reg%squeeze > 0.0_wp) call keep_volumes()
    if (reg%box) allocate(sides(4, reg%ncell), stat=stat)
    q_min = global_q_min()
    if (present(q_start)) q_start = q_min
    do while (q_min < q_target .and. iterations < n_max)
      call guard_start(reg, x)
      if (allocated(sides)) then
        call smooth_modified_getme(reg, x, sides)
      else
        call smooth_modified_getme(reg, x)
      end if
      if (reg%exchange) call halo%nodes(x)
      call smooth_weighted_average(reg, x)
      if (reg%exchange) call halo%nodes(x)
      call guard_undo(reg, x, halo)
      iterations = iterations + 1
      q_min = global_q_min()
    end do
    if (present(halo)) then
      halo%limited = .false.
      guarded = reg%n_guarded
      call halo%sum_ints(guarded)
      reg%n_guarded = guarded(1)
    end if

  contains

    subroutine limit_refreshes()
      real(wp), allocatable :: boxes(:)
      integer :: b
      call halo%concat(real([reg%node_lo, reg%node_hi], wp), boxes)
      halo%node_box(:, 1) = huge(1)
      halo%node_box(:, 2) = -huge(1)
      do b = 0, size(boxes)/6 - 1
        if (any(boxes(6*b + 1:6*b + 3) > boxes(6*b + 4:6*b + 6))) cycle
        halo%node_box(:, 1) = min(halo%node_box(:, 1), nint(boxes(6*b + 1:6*b + 3)))
        halo%node_box(:, 2) = max(halo%node_box(:, 2), nint(boxes(6*b + 4:6*b + 6)))
      end do
      halo%limited = .true.
      ! (and the guard's look at the ghosts a refresh changed, to those in
      ! the box: a round costs what the tangled cells do, not the block's
      ! faces)
      reg%ghost = pack(reg%ghost, [(in_box(reg%ghost(b)), b = 1, size(reg%ghost))])
    end subroutine limit_refreshes

    !> Whether the block's node n lies in halo%node_box.
    logical function in_box(n)
      integer, intent(in) :: n
      integer :: p(3), sx
      sx = reg%ni + 1
      p = [mod(n - 1, sx), mod((n - 1)/sx, reg%nj + 1), (n - 1)/(sx*(reg%nj + 1))] + reg%origin
      in_box = all(p >= halo%node_box(:, 1) .and. p <= halo%node_box(:, 2))
    end function in_box

    real(wp) function global_q_min()
      real(wp) :: none(0)
      if (allocated(sides)) then
        global_q_min = smooth_q_min(reg, x, sides)
      else
        global_q_min = smooth_q_min(reg, x)
      end if
      if (present(halo)) call halo%choose(global_q_min, none)
    end function global_q_min

    subroutine keep_volumes()
      integer :: s
      real(wp) :: xn(3, 8)
      !$omp parallel do default(none) shared(reg, x) private(s, xn) schedule(static)
      do s = 1, reg%ncell
        call region_gather(reg, s, x, xn)
        reg%vstart(s) = hex_volume(xn)
      end do
      !$omp end parallel do
    end subroutine keep_volumes
  end subroutine smooth_combined

  !> Whether the active cell in slot s (nodes xn) is spoiled for the
  !> untangling guard: tangled (`hex_tangled`), or with reg%squeeze > 0
  !> squeezed below that share of its volume at the smoothing's start.
  pure logical function spoiled(reg, s, xn)
    type(smooth_region_t), intent(in) :: reg
    integer, intent(in) :: s
    real(wp), intent(in) :: xn(3, 8)
    spoiled = hex_tangled(xn)
    if (.not. spoiled .and. reg%squeeze > 0.0_wp) spoiled = hex_volume(xn) < reg%squeeze*reg%vstart(s)
  end function spoiled

  !> Untangling, before the smoothing passes (whose guard keeps cells from
  !> getting worse but cannot mend a cell the Lagrangian phase left nearly
  !> flat or inverted: every move around it tangles a neighbour, so the guard
  !> undoes them all and the cell stays as it is). The movable nodes of the
  !> active cells whose health (`hex_health`, against the cell's mean edge)
  !> is below reg%health_min are moved one at a time to raise the smallest
  !> health of the cells around them: a pattern search along the directions
  !> their mobility allows (free: the three axes; in a plane: two tangents;
  !> on a line: the line), both ways, from a fifth of the shortest mean edge
  !> of those cells, taking the best direction that gains and halving the
  !> step when none does, down to a thousandth of it. A node moves only if
  !> that smallest health rises, so no cell ends below the worst around
  !> the node before. The nodes go in eight colour classes (the parities of
  !> their indices), untangle_sweeps times over: two nodes of one class
  !> share no cell, so a class moves at once, in parallel, and the result
  !> depends on neither the thread count nor the blocks (halo: the ghosts
  !> are refreshed after every class, and the moves counted in
  !> reg%n_untangled are the whole grid's).
  subroutine smooth_untangle(reg, x, halo)
    type(smooth_region_t), intent(inout) :: reg
    real(wp), intent(inout) :: x(:, :)
    class(halo_t), intent(inout), optional :: halo
    integer, parameter :: untangle_sweeps = 3, max_tries = 60
    integer :: s, a, m, n, sweep, col, nbad(1), moves(1)
    real(wp) :: xn(3, 8), xp(3)

    ! the cells' scales (their mean edges, kept through the sweeps), those
    ! below health_min (reg%tangled as work), and their movable nodes
    !$omp parallel do default(none) shared(reg, x) private(s, xn) schedule(static)
    do s = 1, reg%ncell
      call region_gather(reg, s, x, xn)
      reg%wcell(s) = mean_edge(xn)
      reg%tangled(s) = hex_health(xn, reg%wcell(s)) < reg%health_min
    end do
    !$omp end parallel do
    do m = 1, reg%nmove
      reg%pick(m) = .false.
      do a = 1, 8
        s = reg%node_cell(a, m)
        if (s > 0) reg%pick(m) = reg%pick(m) .or. reg%tangled(s)
      end do
    end do
    nbad = count(reg%pick)
    if (present(halo)) call halo%max_int(nbad(1))
    if (nbad(1) == 0) return
    moves = 0
    do sweep = 1, untangle_sweeps
      do col = 0, 7
        !$omp parallel do default(none) shared(reg, x, col) private(m, n, xp) &
        !$omp reduction(+: moves) schedule(dynamic)
        do m = 1, reg%nmove
          if (.not. reg%pick(m) .or. reg%colour(m) /= col) cycle
          n = reg%node(m)
          xp = x(:, n)
          if (.not. improve(m, xp)) cycle
          x(:, n) = xp
          if (reg%own(m)) moves(1) = moves(1) + 1
        end do
        !$omp end parallel do
        if (reg%exchange) call halo%nodes(x)
      end do
    end do
    if (present(halo)) call halo%sum_ints(moves)
    reg%n_untangled = moves(1)

  contains

    !> Moves node slot m (position p) by the pattern search; true if it moved.
    logical function improve(m, p)
      integer, intent(in) :: m
      real(wp), intent(inout) :: p(3)
      real(wp) :: dirs(3, 6), q(3), y(3), best(3), h, hmin, f0, fbest, ft, t1(3), t2(3)
      integer :: nd, d, try, s, b
      logical :: gained
      select case (reg%kind(m))
      case (node_free)
        nd = 6
        dirs = 0.0_wp
        do d = 1, 3
          dirs(d, 2*d - 1) = 1.0_wp
          dirs(d, 2*d) = -1.0_wp
        end do
      case (node_plane)
        nd = 4
        t1 = 0.0_wp
        t1(minloc(abs(reg%dir(:, m)), 1)) = 1.0_wp
        t1 = t1 - reg%dir(:, m)*dot_product(reg%dir(:, m), t1)
        t1 = t1/norm2(t1)
        t2 = cross(reg%dir(:, m), t1)
        dirs(:, 1) = t1; dirs(:, 2) = -t1; dirs(:, 3) = t2; dirs(:, 4) = -t2
      case default
        nd = 2
        dirs(:, 1) = reg%dir(:, m); dirs(:, 2) = -reg%dir(:, m)
      end select
      h = huge(1.0_wp)
      do b = 1, 8
        s = reg%node_cell(b, m)
        if (s > 0) h = min(h, reg%wcell(s))
      end do
      h = 0.2_wp*h
      hmin = 1.0e-3_wp*h
      f0 = health_around(m, p)
      fbest = f0
      do try = 1, max_tries
        best = p
        gained = .false.
        do d = 1, nd
          y = p
          q = p + h*dirs(:, d)
          call constrain_move(reg%kind(m), reg%dir(:, m), y, q)
          ft = health_around(m, y)
          if (ft > fbest) then
            fbest = ft
            best = y
            gained = .true.
          end if
        end do
        if (.not. gained) then
          h = 0.5_wp*h
          if (h < hmin) exit
        else
          p = best
        end if
      end do
      improve = fbest > f0
    end function improve

    !> The smallest health of the active cells around node slot m with the
    !> node at y.
    real(wp) function health_around(m, y)
      integer, intent(in) :: m
      real(wp), intent(in) :: y(3)
      real(wp) :: xc(3, 8)
      integer :: b, s
      health_around = huge(1.0_wp)
      do b = 1, 8
        s = reg%node_cell(b, m)
        if (s == 0) cycle
        call region_gather(reg, s, x, xc)
        xc(:, b) = y
        health_around = min(health_around, hex_health(xc, reg%wcell(s)))
      end do
    end function health_around
  end subroutine smooth_untangle

  !> Whether each active cell of the region is tangled in x (`hex_tangled`),
  !> as tangled(c) over the block's cells c (false outside the region): as
  !> the untangling guard's last round left it known (`smooth_combined`
  !> with iterations, x as it left it), else tested.
  subroutine smooth_region_tangled(reg, x, tangled)
    type(smooth_region_t), intent(in) :: reg
    real(wp), intent(in) :: x(:, :)
    logical, intent(out) :: tangled(:)
    integer :: s
    real(wp) :: xn(3, 8)
    tangled = .false.
    ! (with reg%squeeze the guard's state also holds squeezed cells)
    if (reg%known .and. .not. reg%squeeze > 0.0_wp) then
      do s = 1, reg%ncell
        tangled(reg%cell(s)) = .not. reg%untangled(s)
      end do
      return
    end if
    !$omp parallel do default(none) shared(reg, x, tangled) private(s, xn) schedule(static)
    do s = 1, reg%ncell
      call region_gather(reg, s, x, xn)
      tangled(reg%cell(s)) = hex_tangled(xn)
    end do
    !$omp end parallel do
  end subroutine smooth_region_tangled

  !> Before a smoothing pass: keeps the movable nodes' positions and
  !> whether each active cell is untangled (`hex_tangled`: a corner Jacobian
  !> or a tetrahedron of the 24-tet split, what the remap intersects,
  !> non-positive), unless the guard's last round left that known
  !> (reg%known).
  subroutine guard_start(reg, x)
    type(smooth_region_t), intent(inout) :: reg
    real(wp), intent(in) :: x(:, :)
    integer :: s, m
    real(wp) :: xn(3, 8)
    do m = 1, reg%nmove
      reg%xsave(:, m) = x(:, reg%node(m))
    end do
    if (reg%known) return
    !$omp parallel do default(none) shared(reg, x) private(s, xn) schedule(static)
    do s = 1, reg%ncell
      call region_gather(reg, s, x, xn)
      reg%untangled(s) = .not. spoiled(reg, s, xn)
    end do
    !$omp end parallel do
  end subroutine guard_start

  !> After a smoothing pass: around every cell the pass spoiled (a cell
  !> not `spoiled` before it and spoiled after it: tangled, `hex_tangled`,
  !> or with reg%squeeze squeezed below that share of its volume) the moves of
  !> the movable nodes within guard_reach nodes of the cell (in index space:
  !> of one of its corners) are halved, round after round; a node halved
  !> guard_rounds times goes back where it was. Halving a neighbourhood, not
  !> just the cell's own nodes, keeps the motion smooth (undoing single
  !> nodes leaves their neighbours half moved and tangles the next cells).
  !> Every round halves or undoes at least one node and an undone node stays
  !> put, so this ends; no cell untangled before the pass is tangled after
  !> it. Cells tangled before the pass are the smoother's to mend and are
  !> not held to it. A round tests again only the cells whose nodes the
  !> last round changed (the others are as they were), and the last round
  !> leaves every cell's state known for the next pass's `guard_start`.
  !> With halo (`smooth_combined`): the tangled cells' corners and the nodes
  !> are refreshed on the ghosts (guard_reach is within the ghost width), a
  !> round is the whole grid's, and the cells of the ghost nodes the refresh
  !> changed are tested again too.
  subroutine guard_undo(reg, x, halo)
    type(smooth_region_t), intent(inout) :: reg
    real(wp), intent(inout) :: x(:, :)
    class(halo_t), intent(inout), optional :: halo
    integer, parameter :: guard_reach = 2, guard_rounds = 5
    integer :: s, m, a, nbad, n0, i0, j0, k0, i, j, k, sx, sxy, flag, n, g
    real(wp) :: xn(3, 8)
    logical :: changed, ghosts
    ghosts = .false.
    if (present(halo)) ghosts = halo%nblocks > 1 .and. reg%exchange
    sx = reg%ni + 1
    sxy = sx*(reg%nj + 1)
    reg%nhalve = 0
    reg%tangled = .false.
    reg%recheck = reg%untangled
    do
      !$omp parallel do default(none) shared(reg, x) private(s, xn) schedule(static)
      do s = 1, reg%ncell
        if (.not. reg%recheck(s)) cycle
        call region_gather(reg, s, x, xn)
        reg%tangled(s) = spoiled(reg, s, xn)
      end do
      !$omp end parallel do
      nbad = count(reg%tangled)
      if (present(halo)) call halo%max_int(nbad)
      if (nbad == 0) exit
      ! (the marks and their neighbourhood, only where they are: a round
      ! costs what the tangled cells and the ghosts do, not the block)
      reg%nmarked = 0
      do s = 1, reg%ncell
        if (.not. reg%tangled(s)) cycle
        do a = 1, 8
          n = reg%node0(s) + reg%corner_offset(a)
          if (reg%mark(1, n) > 0.0_wp) cycle
          reg%mark(1, n) = 1.0_wp
          reg%nmarked = reg%nmarked + 1
          reg%marked(reg%nmarked) = n
        end do
      end do
      if (ghosts) then
        call halo%nodes(reg%mark)
        do g = 1, size(reg%ghost)
          if (.not. reg%mark(1, reg%ghost(g)) > 0.0_wp) cycle
          reg%nmarked = reg%nmarked + 1
          reg%marked(reg%nmarked) = reg%ghost(g)
        end do
      end if
      ! the nodes within guard_reach of a marked one (in index space)
      call mark_near(.true.)
      changed = .false.
      reg%recheck = .false.
      do m = 1, reg%nmove
        if (.not. reg%near(reg%node(m))) cycle
        if (.not. any(abs(x(:, reg%node(m)) - reg%xsave(:, m)) > 0.0_wp)) cycle
        changed = .true.
        reg%nhalve(m) = reg%nhalve(m) + 1
        if (reg%own(m)) reg%n_guarded = reg%n_guarded + 1
        if (reg%nhalve(m) >= guard_rounds) then
          x(:, reg%node(m)) = reg%xsave(:, m)
        else
          x(:, reg%node(m)) = 0.5_wp*(x(:, reg%node(m)) + reg%xsave(:, m))
        end if
        do a = 1, 8
          s = reg%node_cell(a, m)
          if (s > 0) reg%recheck(s) = reg%untangled(s)
        end do
      end do
      call mark_near(.false.)
      do g = 1, reg%nmarked
        reg%mark(1, reg%marked(g)) = 0.0_wp
      end do
      if (present(halo)) then
        flag = merge(1, 0, changed)
        call halo%max_int(flag)
        changed = flag > 0
        if (ghosts) then
          do g = 1, size(reg%ghost)
            reg%xpre(:, g) = x(:, reg%ghost(g))
          end do
          call halo%nodes(x)
          ! the ghost nodes their owners changed: their cells are tested again
          call recheck_refreshed(reg, x)
        end if
      end if
      ! (a tangled cell with none of its neighbourhood left to undo cannot be
      ! the pass's doing: all its nodes are where they were)
      if (.not. changed) exit
    end do
    ! the state for the next pass: the cells untangled before it are as the
    ! last round found them; those tangled before it are tested now
    reg%known = .true.
    !$omp parallel do default(none) shared(reg, x) private(s, xn) schedule(static)
    do s = 1, reg%ncell
      if (reg%untangled(s)) then
        reg%untangled(s) = .not. reg%tangled(s)
      else
        call region_gather(reg, s, x, xn)
        reg%untangled(s) = .not. spoiled(reg, s, xn)
      end if
    end do
    !$omp end parallel do

  contains

    !> near = value at the nodes within guard_reach (in index space) of the
    !> marked nodes (those listed with a mark).
    subroutine mark_near(value)
      logical, intent(in) :: value
      integer :: q
      do q = 1, reg%nmarked
        n = reg%marked(q)
        if (.not. reg%mark(1, n) > 0.0_wp) cycle
        n0 = n - 1
        i0 = mod(n0, sx)
        j0 = mod(n0/sx, reg%nj + 1)
        k0 = n0/sxy
        do k = max(k0 - guard_reach, 0), min(k0 + guard_reach, reg%nk)
          do j = max(j0 - guard_reach, 0), min(j0 + guard_reach, reg%nj)
            i = 1 + sx*j + sxy*k
            reg%near(i + max(i0 - guard_reach, 0):i + min(i0 + guard_reach, reg%ni)) = value
          end do
        end do
      end do
    end subroutine mark_near
  end subroutine guard_undo

  !> After a ghost refresh in `guard_undo`: the active cells around every
  !> node that the refresh moved (x against reg%xpre: of the nodes of
  !> reg%ghost, the only ones it can move) are tested again in the next
  !> round (if they were untangled before the pass).
  subroutine recheck_refreshed(reg, x)
    type(smooth_region_t), intent(inout) :: reg
    real(wp), intent(in) :: x(:, :)
    integer :: g, n, n0, i0, j0, k0, ci, cj, ck, s, sx, sxy
    sx = reg%ni + 1
    sxy = sx*(reg%nj + 1)
    do g = 1, size(reg%ghost)
      n = reg%ghost(g)
      if (.not. any(abs(x(:, n) - reg%xpre(:, g)) > 0.0_wp)) cycle
      n0 = n - 1
      i0 = mod(n0, sx)
      j0 = mod(n0/sx, reg%nj + 1)
      k0 = n0/sxy
      do ck = max(k0, 1), min(k0 + 1, reg%nk)
        do cj = max(j0, 1), min(j0 + 1, reg%nj)
          do ci = max(i0, 1), min(i0 + 1, reg%ni)
            s = reg%cell_slot(ci + reg%ni*(cj - 1 + reg%nj*(ck - 1)))
            if (s > 0) reg%recheck(s) = reg%untangled(s)
          end do
        end do
      end do
    end do
  end subroutine recheck_refreshed

  !> Transfinite interpolation (Eq. 53) of the nodes strictly inside the
  !> node index box lo(d) <= i_d <= hi(d) (0-based node indices of an
  !> ni x nj x nk block; the cells clo(d)..chi(d) of a merged cuboid
  !> subdomain, 1-based, are lo = clo - 1, hi = chi) from the nodes on its
  !> six faces: the boolean sum of
  !> the three linear projectors (faces - edges + corners, each node a
  !> weighted sum K_IJ x_J of boundary nodes J). The parameter of a node in
  !> direction d is the normalised arc length along the box's four edges in
  !> that direction (the index fraction on a uniformly spaced edge), blended
  !> bilinearly over the node's place between them, so the interior follows
  !> the spacing of the box's edges. Reproduced exactly: any trilinear (in
  !> particular affine) image of a uniform grid, and any grid that is a sum
  !> of functions of one index each (graded along an axis, say). Boundary
  !> nodes of the box do not move; with `mob`, neither do nodes whose kind
  !> is node_fixed (frozen cells inside the box).
  !> x(3, nnode): node positions (length), updated in place.
  subroutine smooth_tfi(ni, nj, nk, lo, hi, x, err, mob)
    integer, intent(in) :: ni, nj, nk, lo(3), hi(3)
    real(wp), intent(inout) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    type(smooth_mobility_t), intent(in), optional :: mob
    type(tfi_shell_t) :: sh
    type(grid_index_t) :: ix
    integer :: i, j, k, n
    logical :: use_kind

    if (any(lo < 0) .or. hi(1) > ni .or. hi(2) > nj .or. hi(3) > nk .or. any(hi < lo)) then
      call error_set(err, 'smooth_tfi', 'the index box is not inside the block')
      return
    end if
    if (size(x, 2) /= (ni + 1)*(nj + 1)*(nk + 1)) then
      call error_set(err, 'smooth_tfi', 'x(:,:) must hold every node of the block')
      return
    end if
    if (any(hi - lo < 2)) return   ! no interior node
    use_kind = present(mob)
    if (use_kind) then
      if (.not. allocated(mob%kind)) then
        call error_set(err, 'smooth_tfi', 'the mobility has not been built')
        return
      end if
      if (mob%ni /= ni .or. mob%nj /= nj .or. mob%nk /= nk) then
        call error_set(err, 'smooth_tfi', 'the mobility is for another block')
        return
      end if
    end if
    ! (node strides do not depend on nk)
    ix = grid_index(ni, nj, 1)
    call smooth_tfi_shell(lo, hi, sh, err)
    if (allocated(err)) return
    do k = lo(3), hi(3)
      do j = lo(2), hi(2)
        do i = lo(1), hi(1)
          if (tfi_on_shell(sh, i, j, k)) call tfi_shell_put(sh, i, j, k, x(:, ix%node(i, j, k)))
        end do
      end do
    end do
    call smooth_tfi_parameters(sh)
    !$omp parallel do default(none) shared(x, sh, mob, use_kind, ix, lo, hi) private(i, j, k, n) schedule(static)
    do k = lo(3) + 1, hi(3) - 1
      do j = lo(2) + 1, hi(2) - 1
        do i = lo(1) + 1, hi(1) - 1
          n = ix%node(i, j, k)
          if (use_kind) then
            if (mob%kind(n) == node_fixed) cycle
          end if
          x(:, n) = smooth_tfi_node(sh, i, j, k)
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine smooth_tfi

  !> sh: the shell of the node index box lo..hi (its six faces' nodes, to
  !> be put in with `tfi_shell_put`), allocated.
  subroutine smooth_tfi_shell(lo, hi, sh, err)
    integer, intent(in) :: lo(3), hi(3)
    type(tfi_shell_t), intent(out) :: sh
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    sh%lo = lo
    sh%hi = hi
    allocate(sh%fi(3, lo(2):hi(2), lo(3):hi(3), 2), sh%fj(3, lo(1):hi(1), lo(3):hi(3), 2), &
             sh%fk(3, lo(1):hi(1), lo(2):hi(2), 2), sh%ua(lo(1):hi(1), 4), sh%va(lo(2):hi(2), 4), &
             sh%wa(lo(3):hi(3), 4), stat=stat)
    if (stat /= 0) call error_set(err, 'smooth_tfi', error_no_memory('the box''s faces'))
  end subroutine smooth_tfi_shell

  !> Whether node (i, j, k) lies on the shell of sh's box.
  pure logical function tfi_on_shell(sh, i, j, k)
    type(tfi_shell_t), intent(in) :: sh
    integer, intent(in) :: i, j, k
    tfi_on_shell = any([i, j, k] == sh%lo) .or. any([i, j, k] == sh%hi)
  end function tfi_on_shell

  !> Puts node (i, j, k) of the shell, at xn, on every face of sh it lies on
  !> (a node off the shell is ignored).
  pure subroutine tfi_shell_put(sh, i, j, k, xn)
    type(tfi_shell_t), intent(inout) :: sh
    integer, intent(in) :: i, j, k
    real(wp), intent(in) :: xn(3)
    integer :: s
    do s = 1, 2
      if (i == merge(sh%lo(1), sh%hi(1), s == 1)) sh%fi(:, j, k, s) = xn
      if (j == merge(sh%lo(2), sh%hi(2), s == 1)) sh%fj(:, i, k, s) = xn
      if (k == merge(sh%lo(3), sh%hi(3), s == 1)) sh%fk(:, i, j, s) = xn
    end do
  end subroutine tfi_shell_put

  !> The arc-length parameters on the four edges of each direction of sh's
  !> box, ordered (low, low), (high, low), (low, high), (high, high) in the
  !> other two, from its faces.
  pure subroutine smooth_tfi_parameters(sh)
    type(tfi_shell_t), intent(inout) :: sh
    integer :: i0, i1, j0, j1, k0, k1
    i0 = sh%lo(1); i1 = sh%hi(1); j0 = sh%lo(2); j1 = sh%hi(2); k0 = sh%lo(3); k1 = sh%hi(3)
    call edge_parameter(i0, i1, sh%fj(:, :, k0, 1), sh%ua(:, 1))
    call edge_parameter(i0, i1, sh%fj(:, :, k0, 2), sh%ua(:, 2))
    call edge_parameter(i0, i1, sh%fj(:, :, k1, 1), sh%ua(:, 3))
    call edge_parameter(i0, i1, sh%fj(:, :, k1, 2), sh%ua(:, 4))
    call edge_parameter(j0, j1, sh%fi(:, :, k0, 1), sh%va(:, 1))
    call edge_parameter(j0, j1, sh%fi(:, :, k0, 2), sh%va(:, 2))
    call edge_parameter(j0, j1, sh%fi(:, :, k1, 1), sh%va(:, 3))
    call edge_parameter(j0, j1, sh%fi(:, :, k1, 2), sh%va(:, 4))
    call edge_parameter(k0, k1, sh%fi(:, j0, :, 1), sh%wa(:, 1))
    call edge_parameter(k0, k1, sh%fi(:, j0, :, 2), sh%wa(:, 2))
    call edge_parameter(k0, k1, sh%fi(:, j1, :, 1), sh%wa(:, 3))
    call edge_parameter(k0, k1, sh%fi(:, j1, :, 2), sh%wa(:, 4))
  contains
    !> Normalised arc length t(m0:m1) along the node line xl(3, m0:m1);
    !> index fractions if the line has no length.
    pure subroutine edge_parameter(m0, m1, xl, t)
      integer, intent(in) :: m0, m1
      real(wp), intent(in) :: xl(:, m0:)
      real(wp), intent(out) :: t(m0:)
      integer :: m
      t(m0) = 0.0_wp
      do m = m0 + 1, m1
        t(m) = t(m - 1) + norm2(xl(:, m) - xl(:, m - 1))
      end do
      if (t(m1) > 0.0_wp) then
        t(m0 + 1:m1) = t(m0 + 1:m1)/t(m1)
      else
        t = [(real(m - m0, wp)/real(m1 - m0, wp), m = m0, m1)]
      end if
      t(m1) = 1.0_wp
    end subroutine edge_parameter
  end subroutine smooth_tfi_parameters

  !> The TFI of node (i, j, k) strictly inside sh's box (`smooth_tfi`),
  !> from its faces and edge parameters (`smooth_tfi_parameters`).
  pure function smooth_tfi_node(sh, i, j, k) result(xn)
    type(tfi_shell_t), intent(in) :: sh
    integer, intent(in) :: i, j, k
    real(wp) :: xn(3)
    integer :: i0, i1, j0, j1, k0, k1
    real(wp) :: u, v, w, fi, fj, fk, p(3), e(3), c(3)
    i0 = sh%lo(1); i1 = sh%hi(1); j0 = sh%lo(2); j1 = sh%hi(2); k0 = sh%lo(3); k1 = sh%hi(3)
    associate (ua => sh%ua, va => sh%va, wa => sh%wa, xi => sh%fi, xj => sh%fj, xk => sh%fk)
      ! index fractions place the node between the edges of a direction
      fi = real(i - i0, wp)/real(i1 - i0, wp)
      fj = real(j - j0, wp)/real(j1 - j0, wp)
      fk = real(k - k0, wp)/real(k1 - k0, wp)
      u = (1.0_wp - fj)*(1.0_wp - fk)*ua(i, 1) + fj*(1.0_wp - fk)*ua(i, 2) + &
          (1.0_wp - fj)*fk*ua(i, 3) + fj*fk*ua(i, 4)
      v = (1.0_wp - fi)*(1.0_wp - fk)*va(j, 1) + fi*(1.0_wp - fk)*va(j, 2) + &
          (1.0_wp - fi)*fk*va(j, 3) + fi*fk*va(j, 4)
      w = (1.0_wp - fi)*(1.0_wp - fj)*wa(k, 1) + fi*(1.0_wp - fj)*wa(k, 2) + &
          (1.0_wp - fi)*fj*wa(k, 3) + fi*fj*wa(k, 4)
      ! faces
      p = (1.0_wp - u)*xi(:, j, k, 1) + u*xi(:, j, k, 2) &
          + (1.0_wp - v)*xj(:, i, k, 1) + v*xj(:, i, k, 2) &
          + (1.0_wp - w)*xk(:, i, j, 1) + w*xk(:, i, j, 2)
      ! edges
      e = (1.0_wp - u)*((1.0_wp - v)*xi(:, j0, k, 1) + v*xi(:, j1, k, 1)) &
          + u*((1.0_wp - v)*xi(:, j0, k, 2) + v*xi(:, j1, k, 2)) &
          + (1.0_wp - u)*((1.0_wp - w)*xi(:, j, k0, 1) + w*xi(:, j, k1, 1)) &
          + u*((1.0_wp - w)*xi(:, j, k0, 2) + w*xi(:, j, k1, 2)) &
          + (1.0_wp - v)*((1.0_wp - w)*xj(:, i, k0, 1) + w*xj(:, i, k1, 1)) &
          + v*((1.0_wp - w)*xj(:, i, k0, 2) + w*xj(:, i, k1, 2))
      ! corners
      c = (1.0_wp - u)*((1.0_wp - v)*((1.0_wp - w)*xi(:, j0, k0, 1) + w*xi(:, j0, k1, 1)) &
                        + v*((1.0_wp - w)*xi(:, j1, k0, 1) + w*xi(:, j1, k1, 1))) &
          + u*((1.0_wp - v)*((1.0_wp - w)*xi(:, j0, k0, 2) + w*xi(:, j0, k1, 2)) &
               + v*((1.0_wp - w)*xi(:, j1, k0, 2) + w*xi(:, j1, k1, 2)))
    end associate
    xn = p - e + c
  end function smooth_tfi_node


  !> The last safeguard of a rezone: every cell of an ni x nj x nk block that
  !> the rezone changed (a node of x differs from xold) and that is tangled in
  !> x (a corner Jacobian or a tetrahedron of the 24-tet split non-positive)
  !> has its nodes put back where they were, round after round (putting
  !> nodes back can tangle a neighbour, whose nodes then go back too; every
  !> round puts back at least one node and no node moves twice, so this
  !> ends). A round finds all such cells first, then puts their nodes back
  !> (so the result does not depend on the order of the cells, nor on a
  !> decomposition). The new grid's cells are then untangled or unchanged,
  !> which is what the remap needs (a changed tangled cell has no exact
  !> intersection with the old grid). nrevert is the number of nodes put
  !> back. With halo (a block of a decomposed grid, stored nodes numbered as
  !> a block of ni x nj x nk cells, ghosts current on entry): the ghosts are
  !> refreshed after every round, the rounds are the whole grid's and
  !> nrevert counts the nodes of counts(nnode) summed over the blocks. With
  !> xto the nodes of such cells go to xto instead (the same rounds: every
  !> cell of xto untangled).
  subroutine smooth_revert_tangled(ni, nj, nk, xold, x, nrevert, err, halo, counts, xto)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in), target :: xold(:, :)
    real(wp), intent(inout) :: x(:, :)
    integer, intent(out) :: nrevert
    type(error_t), allocatable, intent(inout) :: err
    class(halo_t), intent(inout), optional :: halo
    logical, intent(in), optional :: counts(:)
    real(wp), intent(in), optional, target :: xto(:, :)
    integer :: ci, cj, ck, a, n0, n, nround(1)
    real(wp) :: xn(3, 8)
    real(wp), pointer :: xt(:, :)
    logical, allocatable :: back(:)
    logical :: changed
    type(grid_index_t) :: ix

    xt => xold
    if (present(xto)) xt => xto
    ix = grid_index(ni, nj, nk)
    nrevert = 0
    allocate(back(ix%nnode), stat=n)
    if (n /= 0) then
      call error_set(err, 'smooth_revert_tangled', error_no_memory('the work array'))
      return
    end if
    do
      back = .false.
      !$omp parallel do default(none) shared(ix, x, xold, xt, back) private(ci, cj, ck, a, n0, n, xn, changed) &
      !$omp collapse(2) schedule(static)
      do ck = ix%clo(3), ix%chi(3)
        do cj = ix%clo(2), ix%chi(2)
          do ci = ix%clo(1), ix%chi(1)
            n0 = ix%cell_node0(ci, cj, ck)
            changed = .false.
            do a = 1, 8
              n = n0 + ix%corner_offset(a)
              xn(:, a) = x(:, n)
              changed = changed .or. any(abs(x(:, n) - xold(:, n)) > 0.0_wp)
            end do
            if (.not. changed) cycle
            if (.not. hex_tangled(xn)) cycle
            do a = 1, 8
              n = n0 + ix%corner_offset(a)
              ! (the same value from any thread)
              if (any(abs(x(:, n) - xt(:, n)) > 0.0_wp)) back(n) = .true.
            end do
          end do
        end do
      end do
      !$omp end parallel do
      if (present(counts)) then
        nround = count(back .and. counts)
      else
        nround = count(back)
      end if
      where (spread(back, 1, 3)) x = xt
      if (present(halo)) then
        call halo%sum_ints(nround)
        call halo%nodes(x)
      end if
      nrevert = nrevert + nround(1)
      if (nround(1) == 0) exit
    end do
  end subroutine smooth_revert_tangled

  !> Puts back where they were (x = xold) the nodes of an ni x nj x nk block
  !> that the rezone moved by less than move_min times the shortest grid
  !> edge at the node in xold. A move that small hardly changes a cell's
  !> quality, but every cell with a moved node must be remapped, at the full
  !> cost of the intersection and with its numerical diffusion: the cells
  !> whose nodes all stay are copied instead. nreset is the number of nodes
  !> put back. A reset moves a node by less than move_min of its shortest
  !> edge, so with move_min well below 1 it cannot tangle a valid grid.
  subroutine smooth_keep_small_moves(ni, nj, nk, xold, x, move_min, nreset, counts)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: xold(:, :), move_min
    real(wp), intent(inout) :: x(:, :)
    integer, intent(out) :: nreset
    !> (nnode) the nodes nreset counts (a block's of a decomposed grid; default all)
    logical, intent(in), optional :: counts(:)
    integer :: i, j, k, n, d, stride(3), idx(3)
    real(wp) :: lmin
    type(grid_index_t) :: ix

    ix = grid_index(ni, nj, nk)
    stride = [1, ix%sx, ix%sxy]
    nreset = 0
    !$omp parallel do default(none) shared(ix, xold, x, move_min, stride, counts) &
    !$omp private(i, j, k, n, d, idx, lmin) reduction(+: nreset) collapse(2) schedule(static)
    do k = ix%nlo(3), ix%nhi(3)
      do j = ix%nlo(2), ix%nhi(2)
        do i = ix%nlo(1), ix%nhi(1)
          n = ix%node(i, j, k)
          if (.not. any(abs(x(:, n) - xold(:, n)) > 0.0_wp)) cycle
          idx = [i, j, k]
          lmin = huge(1.0_wp)
          do d = 1, 3
            if (idx(d) > ix%nlo(d)) lmin = min(lmin, norm2(xold(:, n) - xold(:, n - stride(d))))
            if (idx(d) < ix%nhi(d)) lmin = min(lmin, norm2(xold(:, n + stride(d)) - xold(:, n)))
          end do
          if (norm2(x(:, n) - xold(:, n)) < move_min*lmin) then
            x(:, n) = xold(:, n)
            if (present(counts)) then
              if (.not. counts(n)) cycle
            end if
            nreset = nreset + 1
          end if
        end do
      end do
    end do
    !$omp end parallel do
  end subroutine smooth_keep_small_moves
end module rezone_smooth
