!> Distorted subdomain determination (Section 5.2, Fig. 4) and the cell and
!> node sets that the localized smoothing (Section 5.3) and the localized
!> remap (Section 5.4) work on, for one structured block of ni x nj x nk cells
!> (cells and nodes numbered by `grid_index_t` of `mesh_grid`).
!>
!> How the paper's words are read here:
!>
!> - Distance is measured in index space, not in physical length: the paper
!>   sets a subdomain's centre to the cell's indices "(l_x, l_y, l_z)" and its
!>   "maximum range ... with the center (l_x, l_y, l_z) and the maximum side
!>   length d_max", and the subdomain itself is the index box
!>   [l_xmin, l_xmax] x [l_ymin, l_ymax] x [l_zmin, l_zmax]. So d_max is a
!>   number of cells (real, need not be an integer) and the maximum range of a
!>   subdomain is the index cube of side d_max centred on its centre: a cell l
!>   is within range of a subdomain with centre c when
!>   |l_d - c_d| <= d_max/2 in each of the three directions d. (Issue 6 words
!>   it "within d_max of a subdomain centre"; a caller who wants that looser
!>   reading passes 2 d_max.)
!> - Default d_max: "1/10 of the minimum side length in the 2D/3D grid", read
!>   as a tenth of the smallest number of cells along a direction of the block,
!>   ignoring directions one cell thick (a 2D problem on a one-layer 3D grid),
!>   see `rezone_subdomains_default_dmax`.
!> - Cell loop in increasing cell index c (i fastest, then j, then k), so the
!>   result is deterministic. Each distorted cell (Q < q, Eq. 46; a NaN
!>   quality also counts as distorted; or marked by the caller, e.g. a cell
!>   that fails the Euler-step triggers' tests) that is not frozen:
!>   the "subdomain loop" enlarges EVERY existing subdomain whose range holds
!>   the cell, so its box becomes the bounding index box of the old box and the
!>   cell's 3x3x3 neighbourhood (clipped to the block); "the center of subdomain
!>   B_k remains unchanged" (the centre stays the seeding cell's indices).
!>   If no range holds the cell, a new subdomain is its 3x3x3 neighbourhood
!>   (clipped to the block) with centre the cell's indices.
!> - "Expand all subdomains in each direction to get a smoother boundary
!>   without distorted cells": once, by one layer of cells on both sides in
!>   each of the three directions, clipped to the block.
!> - Overlapping subdomains "need no special treatment as they compose a
!>   step-like subdomain": the smoothing region is the union of the boxes.
!> - Frozen cells (cells holding solid particles, Remark 2 and Fig. 4(f):
!>   "the cells occupied by the particles remain unchanged and are seen as the
!>   fixed inner boundary of the grid") never seed or enlarge a subdomain (they
!>   are counted in `n_frozen_distorted` when distorted), may lie inside a box,
!>   but are taken out of the smoothing cell set, so all their nodes are fixed
!>   (a node moves only when every cell around it is in the smoothing set).
!>   The remap set is built from the smoothing set, so a frozen cell is
!>   remapped only when it touches a smoothing cell (where nodal control
!>   volumes change); remapping it then returns its own state, it is unchanged.
module rezone_subdomains
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_strings, only: itoa
  use mesh_grid, only: grid_index_t, grid_index, nodes_within
  implicit none
  private
  public :: rezone_subdomains_t, rezone_subdomains_find, rezone_subdomains_from_boxes, &
            rezone_subdomains_merge, rezone_subdomains_default_dmax, rezone_subdomains_seed

  !> The subdomains of one block and the sets derived from them.
  !> Boxes are inclusive cell-index ranges: box b covers cells
  !> lo(1,b):hi(1,b) x lo(2,b):hi(2,b) x lo(3,b):hi(3,b) (i, j, k).
  type :: rezone_subdomains_t
    integer :: ni = 0, nj = 0, nk = 0
    !> Number of subdomains (boxes).
    integer :: nbox = 0
    !> Lower and upper cell indices (3, nbox) of each box (Sect. 5.2, after
    !> the final one-layer expansion).
    integer, allocatable :: lo(:, :), hi(:, :)
    !> Seeding cell (i, j, k) of each box, its fixed centre (Sect. 5.2 2(a)ii);
    !> 0 for boxes given to `rezone_subdomains_from_boxes`.
    integer, allocatable :: centre(:, :)
    !> Distorted cells (Q < q) that seeded or enlarged a subdomain.
    integer :: n_distorted = 0
    !> Distorted cells skipped because they are frozen.
    integer :: n_frozen_distorted = 0
    !> Smoothing region (ncell): the union of the boxes less the frozen
    !> cells; the cells the smoother transforms (Sect. 5.3).
    logical, allocatable :: cell_smooth(:)
    !> Movable nodes (nnode): every cell around the node (within the block) is
    !> in the smoothing region. Nodes on the region's outer boundary stay
    !> fixed; nodes on the block boundary inside the region are marked
    !> movable and the smoother applies its own face/edge/corner rules.
    logical, allocatable :: node_move(:)
    !> Remap region (ncell): the smoothing region grown by one layer of cells
    !> (26 neighbours, clipped to the block), Sect. 5.4; its outermost nodes
    !> keep their control volumes and so their momentum.
    logical, allocatable :: cell_remap(:)
    !> The same three sets as increasing lists of cell or node indices.
    integer, allocatable :: smooth_cells(:), move_nodes(:), geometry_cells(:)
  end type rezone_subdomains_t

contains

  !> The paper's default maximum side length of a subdomain, in cells
  !> (Sect. 5.2: "1/10 of the minimum side length in the 2D/3D grid"): a tenth
  !> of the smallest of ni, nj, nk over the directions more than one cell
  !> thick (0.1 if the block is a single cell).
  pure function rezone_subdomains_default_dmax(ni, nj, nk) result(d_max)
    integer, intent(in) :: ni, nj, nk
    real(wp) :: d_max
    integer :: n(3), nmin, d
    n = [ni, nj, nk]
    nmin = huge(1)
    do d = 1, 3
      if (n(d) > 1) nmin = min(nmin, n(d))
    end do
    if (nmin == huge(1)) nmin = 1
    d_max = 0.1_wp*real(nmin, wp)
  end function rezone_subdomains_default_dmax

  !> Section 5.2: finds the subdomains of the distorted cells of an
  !> ni x nj x nk block and the smoothing, movable-node and remap sets.
  !> quality(ncell) is Eq. (46) per cell (dimensionless), q the distortion
  !> threshold (cells with quality < q are distorted), d_max the maximum side
  !> length of a subdomain's range in cells (see the module notes), frozen
  !> (optional, ncell) marks cells that must not move (solid particles),
  !> distorted (optional, ncell) cells that are distorted whatever their Q.
  subroutine rezone_subdomains_find(ni, nj, nk, quality, q, d_max, sub, err, frozen, distorted)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: quality(:), q, d_max
    type(rezone_subdomains_t), intent(out) :: sub
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: frozen(:), distorted(:)
    character(len=*), parameter :: where = 'rezone_subdomains_find'
    integer, allocatable :: lo(:, :), hi(:, :), centre(:, :), ijk(:, :)
    integer :: c, ci, cj, ck, nd, stat
    character(len=200) :: msg

    call check_block(ni, nj, nk, where, err, frozen)
    if (allocated(err)) return
    if (size(quality) /= ni*nj*nk) then
      call error_set(err, where, 'quality has '//itoa(size(quality))//' entries, the block has ' &
                     //itoa(ni*nj*nk)//' cells')
      return
    end if
    if (present(distorted)) then
      if (size(distorted) /= ni*nj*nk) then
        call error_set(err, where, 'distorted has '//itoa(size(distorted))//' entries, the block has ' &
                       //itoa(ni*nj*nk)//' cells')
        return
      end if
    end if
    if (ieee_is_nan(d_max) .or. ieee_is_nan(q)) then
      call error_set(err, where, 'd_max and q must be numbers')
      return
    end if
    if (d_max < 0.0_wp) then
      call error_set(err, where, 'd_max must be >= 0 (cells)')
      return
    end if

    ! Step 1: distorted when Q < q (Eq. 46); an undefined Q is distorted too
    ! (counted, then listed in cell order)
    nd = 0
    do c = 1, ni*nj*nk
      if (seeds(c)) nd = nd + 1
      if (is_distorted(c) .and. .not. seeds(c)) sub%n_frozen_distorted = sub%n_frozen_distorted + 1
    end do
    allocate(ijk(3, nd), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('the distorted cells'))
      return
    end if
    nd = 0
    c = 0
    do ck = 1, nk
      do cj = 1, nj
        do ci = 1, ni
          c = c + 1
          if (.not. seeds(c)) cycle
          nd = nd + 1
          ijk(:, nd) = [ci, cj, ck]
        end do
      end do
    end do
    sub%n_distorted = nd
    call rezone_subdomains_seed([ni, nj, nk], ijk(:, 1:nd), d_max, lo, hi, centre, err)
    if (allocated(err)) return
    call set_boxes(sub, ni, nj, nk, lo, hi, centre, where, err)
    if (allocated(err)) return
    call build_sets(sub, where, err, frozen)

  contains

    !> Whether cell c is distorted (Q < q, an undefined Q, or marked).
    logical function is_distorted(c)
      integer, intent(in) :: c
      if (.not. ieee_is_nan(quality(c))) then
        is_distorted = quality(c) < q
      else
        is_distorted = .true.
      end if
      if (present(distorted)) is_distorted = is_distorted .or. distorted(c)
    end function is_distorted

    !> Whether cell c seeds or enlarges a subdomain (distorted, not frozen).
    logical function seeds(c)
      integer, intent(in) :: c
      seeds = is_distorted(c)
      if (present(frozen)) seeds = seeds .and. .not. frozen(c)
    end function seeds
  end subroutine rezone_subdomains_find

  !> Steps 2 and 3 of Sect. 5.2 (module notes) for the distorted cells
  !> ijk(3, nd) of a grid of n(3) cells, taken in the order given (the
  !> cell order, i fastest): the subdomain boxes lo, hi (3, nbox; after the
  !> final one-layer expansion, within 1..n) and their centres. A
  !> decomposed grid's blocks give it all distorted cells in the whole
  !> grid's order, and so find the boxes of one process.
  subroutine rezone_subdomains_seed(n, ijk, d_max, lo, hi, centre, err)
    integer, intent(in) :: n(3), ijk(:, :)
    real(wp), intent(in) :: d_max
    integer, allocatable, intent(out) :: lo(:, :), hi(:, :), centre(:, :)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: where = 'rezone_subdomains_seed'
    integer :: l(3), nlo(3), nhi(3), b, d, nbox, m
    real(wp) :: half
    logical :: found

    half = 0.5_wp*d_max
    nbox = 0
    call grow_boxes(lo, hi, centre, 16, where, err)
    if (allocated(err)) return
    do m = 1, size(ijk, 2)
      l = ijk(:, m)
      nlo = max(l - 1, 1)
      nhi = min(l + 1, n)
      ! Step 2(b)i: enlarge every subdomain whose range holds the cell
      found = .false.
      do b = 1, nbox
        if (all(real(abs(l - centre(:, b)), wp) <= half)) then
          lo(:, b) = min(lo(:, b), nlo)
          hi(:, b) = max(hi(:, b), nhi)
          found = .true.
        end if
      end do
      ! Steps 2(a) and 2(b)ii: a new subdomain of the 27 surrounding cells
      if (.not. found) then
        if (nbox == size(lo, 2)) then
          call grow_boxes(lo, hi, centre, 2*nbox, where, err)
          if (allocated(err)) return
        end if
        nbox = nbox + 1
        lo(:, nbox) = nlo
        hi(:, nbox) = nhi
        centre(:, nbox) = l
      end if
    end do

    ! Step 3: expand all subdomains once, one layer in each direction
    do b = 1, nbox
      do d = 1, 3
        lo(d, b) = max(lo(d, b) - 1, 1)
        hi(d, b) = min(hi(d, b) + 1, n(d))
      end do
    end do
    lo = lo(:, 1:nbox)
    hi = hi(:, 1:nbox)
    centre = centre(:, 1:nbox)
  end subroutine rezone_subdomains_seed

  !> Builds the smoothing, movable-node and remap sets of given boxes
  !> lo(3,nbox), hi(3,nbox) (inclusive cell indices) on an ni x nj x nk block,
  !> e.g. the merged cuboids of `rezone_subdomains_merge` for the TFI fallback
  !> (Eq. 53), whose remap region is then that of the cuboids. Centres are 0.
  subroutine rezone_subdomains_from_boxes(ni, nj, nk, lo, hi, sub, err, frozen)
    integer, intent(in) :: ni, nj, nk
    integer, intent(in) :: lo(:, :), hi(:, :)
    type(rezone_subdomains_t), intent(out) :: sub
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: frozen(:)
    character(len=*), parameter :: where = 'rezone_subdomains_from_boxes'
    integer, allocatable :: centre(:, :)
    integer :: n(3), b, stat
    character(len=200) :: msg

    call check_block(ni, nj, nk, where, err, frozen)
    if (allocated(err)) return
    call check_boxes(lo, hi, where, err)
    if (allocated(err)) return
    n = [ni, nj, nk]
    do b = 1, size(lo, 2)
      if (any(lo(:, b) < 1) .or. any(hi(:, b) > n) .or. any(lo(:, b) > hi(:, b))) then
        call error_set(err, where, 'box '//itoa(b)//' is empty or outside the block')
        return
      end if
    end do
    allocate(centre(3, size(lo, 2)), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('box centres'))
      return
    end if
    centre = 0
    call set_boxes(sub, ni, nj, nk, lo, hi, centre, where, err)
    if (allocated(err)) return
    call build_sets(sub, where, err, frozen)
  end subroutine rezone_subdomains_from_boxes

  !> Merges boxes for the TFI fallback (Sect. 5.3.2 step 2, Fig. 9(c): "merge the
  !> overlapped subdomains into larger cuboid subdomains", then TFI "in
  !> non-overlapping subdomains"). Two boxes are connected when they share a
  !> cell or a face (touching along an edge or at a corner only does not
  !> count: the shared nodes stay fixed in both); connected boxes are
  !> replaced by their bounding box, repeatedly, until no two boxes are
  !> connected. Where a group's union is itself a cuboid the result is exactly
  !> that union; otherwise it is the group's bounding box, which also covers
  !> cells outside the union. The result covers the input, its boxes share no
  !> cell, and is ordered by each group's first box in the input.
  subroutine rezone_subdomains_merge(lo, hi, mlo, mhi, err)
    integer, intent(in) :: lo(:, :), hi(:, :)
    integer, allocatable, intent(out) :: mlo(:, :), mhi(:, :)
    type(error_t), allocatable, intent(inout) :: err
    character(len=*), parameter :: where = 'rezone_subdomains_merge'
    integer, allocatable :: tlo(:, :), thi(:, :)
    integer :: m, a, b, stat
    character(len=200) :: msg
    logical :: merged

    call check_boxes(lo, hi, where, err)
    if (allocated(err)) return
    m = size(lo, 2)
    allocate(tlo(3, m), thi(3, m), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('boxes'))
      return
    end if
    tlo = lo
    thi = hi
    ! Box a absorbs every box connected to it, rechecking all others after
    ! each absorption (it has grown). A box a has finished with is connected
    ! to none; only the box being processed grows afterwards, and its own
    ! final check covers the finished ones.
    a = 1
    do while (a <= m)
      merged = .true.
      do while (merged)
        merged = .false.
        do b = 1, m
          if (b == a) cycle
          if (connected(tlo(:, a), thi(:, a), tlo(:, b), thi(:, b))) then
            tlo(:, a) = min(tlo(:, a), tlo(:, b))
            thi(:, a) = max(thi(:, a), thi(:, b))
            tlo(:, b:m - 1) = tlo(:, b + 1:m)
            thi(:, b:m - 1) = thi(:, b + 1:m)
            m = m - 1
            if (b < a) a = a - 1
            merged = .true.
            exit
          end if
        end do
      end do
      a = a + 1
    end do
    allocate(mlo(3, m), mhi(3, m), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('merged boxes'))
      return
    end if
    mlo = tlo(:, 1:m)
    mhi = thi(:, 1:m)
  end subroutine rezone_subdomains_merge

  ! ---- private helpers ----

  !> True when two boxes share a cell or a face: in every direction their
  !> ranges overlap or abut, and they abut in at most one.
  pure logical function connected(alo, ahi, blo, bhi)
    integer, intent(in) :: alo(3), ahi(3), blo(3), bhi(3)
    integer :: gap(3)
    ! gap <= 0: ranges overlap; 1: adjacent; > 1: apart
    gap = max(alo, blo) - min(ahi, bhi)
    connected = all(gap <= 1) .and. count(gap == 1) <= 1
  end function connected

  !> Validates the block sizes and the frozen mask.
  subroutine check_block(ni, nj, nk, where, err, frozen)
    integer, intent(in) :: ni, nj, nk
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: frozen(:)
    if (ni < 1 .or. nj < 1 .or. nk < 1) then
      call error_set(err, where, 'block of '//itoa(ni)//' x '//itoa(nj)//' x '//itoa(nk) &
                     //' cells: each must be >= 1')
      return
    end if
    if (present(frozen)) then
      if (size(frozen) /= ni*nj*nk) then
        call error_set(err, where, 'frozen has '//itoa(size(frozen))//' entries, the block has ' &
                       //itoa(ni*nj*nk)//' cells')
        return
      end if
    end if
  end subroutine check_block

  !> Validates the shapes of box arrays lo(3,n), hi(3,n).
  subroutine check_boxes(lo, hi, where, err)
    integer, intent(in) :: lo(:, :), hi(:, :)
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    if (size(lo, 1) /= 3 .or. size(hi, 1) /= 3 .or. size(lo, 2) /= size(hi, 2)) then
      call error_set(err, where, 'boxes must be lo(3, n) and hi(3, n)')
    end if
  end subroutine check_boxes

  !> Grows (or first allocates) the box work arrays to hold cap boxes.
  subroutine grow_boxes(lo, hi, centre, cap, where, err)
    integer, allocatable, intent(inout) :: lo(:, :), hi(:, :), centre(:, :)
    integer, intent(in) :: cap
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: tlo(:, :), thi(:, :), tce(:, :)
    integer :: nold, stat
    character(len=200) :: msg

    nold = 0
    if (allocated(lo)) nold = size(lo, 2)
    allocate(tlo(3, cap), thi(3, cap), tce(3, cap), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('subdomain boxes'))
      return
    end if
    tlo = 0
    thi = 0
    tce = 0
    if (nold > 0) then
      tlo(:, 1:nold) = lo
      thi(:, 1:nold) = hi
      tce(:, 1:nold) = centre
    end if
    call move_alloc(tlo, lo)
    call move_alloc(thi, hi)
    call move_alloc(tce, centre)
  end subroutine grow_boxes

  !> Copies the block sizes and the boxes into sub.
  subroutine set_boxes(sub, ni, nj, nk, lo, hi, centre, where, err)
    type(rezone_subdomains_t), intent(inout) :: sub
    integer, intent(in) :: ni, nj, nk
    integer, intent(in) :: lo(:, :), hi(:, :), centre(:, :)
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    character(len=200) :: msg

    sub%ni = ni
    sub%nj = nj
    sub%nk = nk
    sub%nbox = size(lo, 2)
    allocate(sub%lo(3, sub%nbox), sub%hi(3, sub%nbox), sub%centre(3, sub%nbox), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('subdomain boxes'))
      return
    end if
    sub%lo = lo
    sub%hi = hi
    sub%centre = centre
  end subroutine set_boxes

  !> Smoothing set (union of the boxes less frozen cells), movable nodes
  !> (every surrounding cell in the smoothing set) and remap set (smoothing
  !> set grown by one layer, Sect. 5.4), as masks and as index lists.
  subroutine build_sets(sub, where, err, frozen)
    type(rezone_subdomains_t), intent(inout) :: sub
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: frozen(:)
    integer :: ni, nj, nk, ncell, nnode, b, i, j, k, ci, cj, ck, stat
    character(len=200) :: msg
    type(grid_index_t) :: ix

    ni = sub%ni
    nj = sub%nj
    nk = sub%nk
    ix = grid_index(ni, nj, nk)
    ncell = ni*nj*nk
    nnode = (ni + 1)*(nj + 1)*(nk + 1)
    allocate(sub%cell_smooth(ncell), sub%cell_remap(ncell), sub%node_move(nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('subdomain masks'))
      return
    end if
    sub%cell_smooth = .false.
    sub%cell_remap = .false.
    sub%node_move = .false.

    ! the step-like union of the (possibly overlapping) boxes, Fig. 4(e)
    do b = 1, sub%nbox
      do ck = sub%lo(3, b), sub%hi(3, b)
        do cj = sub%lo(2, b), sub%hi(2, b)
          do ci = sub%lo(1, b), sub%hi(1, b)
            sub%cell_smooth(ix%cell(ci, cj, ck)) = .true.
          end do
        end do
      end do
    end do
    ! cells holding solid particles are a fixed inner boundary, Fig. 4(f)
    if (present(frozen)) sub%cell_smooth = sub%cell_smooth .and. .not. frozen

    ! remap region: one more layer of cells, Sect. 5.4
    do ck = ix%clo(3), ix%chi(3)
      do cj = ix%clo(2), ix%chi(2)
        do ci = ix%clo(1), ix%chi(1)
          if (.not. sub%cell_smooth(ix%cell(ci, cj, ck))) cycle
          do k = max(ck - 1, ix%clo(3)), min(ck + 1, ix%chi(3))
            do j = max(cj - 1, ix%clo(2)), min(cj + 1, ix%chi(2))
              do i = max(ci - 1, ix%clo(1)), min(ci + 1, ix%chi(1))
                sub%cell_remap(ix%cell(i, j, k)) = .true.
              end do
            end do
          end do
        end do
      end do
    end do

    ! a node moves when all of its (up to 8) cells are in the smoothing set
    call nodes_within(ix, sub%cell_smooth, sub%node_move, err)
    if (allocated(err)) return

    call mask_list(sub%cell_smooth, sub%smooth_cells, where, err)
    if (allocated(err)) return
    call mask_list(sub%node_move, sub%move_nodes, where, err)
    if (allocated(err)) return
    call mask_list(sub%cell_remap, sub%geometry_cells, where, err)
  end subroutine build_sets

  !> The indices where mask is true, in increasing order.
  subroutine mask_list(mask, list, where, err)
    logical, intent(in) :: mask(:)
    integer, allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: where
    type(error_t), allocatable, intent(inout) :: err
    integer :: i, m, stat
    character(len=200) :: msg

    if (allocated(list)) deallocate(list)
    allocate(list(count(mask)), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, where, error_no_memory('an index list'))
      return
    end if
    m = 0
    do i = 1, size(mask)
      if (mask(i)) then
        m = m + 1
        list(m) = i
      end if
    end do
  end subroutine mask_list
end module rezone_subdomains
