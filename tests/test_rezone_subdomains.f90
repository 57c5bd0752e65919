!> Unit tests of the distorted subdomain determination (Section 5.2) and of
!> the smoothing, movable-node and remap sets (Sections 5.3, 5.4) on
!> hand-made quality patterns of a 20 x 20 x 20 block. Every expected box and
!> count below is worked out by hand in the comments; the masks are also
!> checked against brute-force definitions written here independently.
program test_rezone_subdomains
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use base_kinds, only: wp
  use base_errors, only: error_t
  use test_assert, only: check, check_summary
  use rezone_subdomains, only: rezone_subdomains_t, rezone_subdomains_find, rezone_subdomains_from_boxes, &
                               rezone_subdomains_merge, rezone_subdomains_default_dmax
  implicit none
  integer, parameter :: m = 20, ncell = m**3
  real(wp), parameter :: qd = 0.5_wp, q = 0.9_wp
  real(wp) :: quality(ncell)
  logical :: frozen(ncell)
  type(rezone_subdomains_t) :: s, t
  type(error_t), allocatable :: err
  integer, allocatable :: mlo(:, :), mhi(:, :)
  integer :: lo(3, 4), hi(3, 4)

  ! ---- default d_max: a tenth of the smallest dimension (Sect. 5.2) ----
  call check(abs(rezone_subdomains_default_dmax(20, 20, 20) - 2.0_wp) < 1e-15_wp, 'default d_max of 20^3 is 2 cells')
  call check(abs(rezone_subdomains_default_dmax(40, 50, 30) - 3.0_wp) < 1e-15_wp, 'default d_max of 40x50x30 is 3')
  call check(abs(rezone_subdomains_default_dmax(200, 100, 1) - 10.0_wp) < 1e-15_wp, &
             'default d_max ignores a one-cell direction (2D grid)')

  ! ---- no distorted cell: nothing ----
  quality = 1.0_wp
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(.not. allocated(err), 'find on a perfect grid succeeds')
  call check(s%nbox == 0 .and. s%n_distorted == 0, 'no distorted cell: no subdomain')
  call check(.not. any(s%cell_smooth) .and. .not. any(s%node_move) .and. .not. any(s%cell_remap), &
             'no distorted cell: empty masks')
  call check(size(s%smooth_cells) == 0 .and. size(s%move_nodes) == 0 .and. size(s%geometry_cells) == 0, &
             'no distorted cell: empty lists')

  ! ---- one distorted cell in the middle ----
  ! 3x3x3 box 9..11, expanded once: 8..12 (125 cells); movable nodes are the
  ! 4^3 interior nodes 8..11; remap 7..13 (343 cells)
  quality = 1.0_wp
  quality(cell(10, 10, 10)) = qd
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(s%nbox == 1 .and. s%n_distorted == 1, 'one distorted cell: one subdomain')
  call check_box(s, 1, [8, 8, 8], [12, 12, 12], 'one cell: box 8..12 after the expansion')
  call check(all(s%centre(:, 1) == [10, 10, 10]), 'one cell: centre is the cell')
  call check(count(s%cell_smooth) == 125, 'one cell: 125 smoothing cells')
  call check(count(s%node_move) == 64, 'one cell: 64 movable nodes')
  call check(count(s%cell_remap) == 343, 'one cell: 343 remap cells')
  call check_sets(s, 'one cell')

  ! ---- a cell marked distorted by the caller (it fails the triggers'
  ! tests) seeds the same subdomain whatever its Q; q = -huge: Q plays no part
  quality = 1.0_wp
  quality(cell(3, 3, 3)) = qd
  frozen = .false.
  frozen(cell(10, 10, 10)) = .true.
  call rezone_subdomains_find(m, m, m, quality, -huge(1.0_wp), 4.0_wp, t, err, distorted=frozen)
  call check(.not. allocated(err) .and. t%nbox == 1 .and. t%n_distorted == 1, &
             'a marked cell is distorted, a low Q alone is not when q = -huge')
  call check_box(t, 1, [8, 8, 8], [12, 12, 12], 'marked cell: box 8..12 after the expansion')
  frozen = .false.

  ! ---- two distorted cells within range: one subdomain ----
  ! cell (11,12,9) comes first in the cell loop (k = 9 < 10): it seeds the
  ! subdomain with centre (11,12,9), box 10..12 x 11..13 x 8..10; (10,10,10)
  ! is (1,2,1) away, within d_max/2 = 2, so the box grows to 9..12 x 9..13 x
  ! 8..11 and the centre stays; expanded: 8..13 x 8..14 x 7..12 = 6*7*6 = 252
  quality = 1.0_wp
  quality(cell(10, 10, 10)) = qd
  quality(cell(11, 12, 9)) = qd
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(s%nbox == 1 .and. s%n_distorted == 2, 'two close cells: one subdomain')
  call check_box(s, 1, [8, 8, 7], [13, 14, 12], 'two close cells: box')
  call check(all(s%centre(:, 1) == [11, 12, 9]), 'two close cells: centre is the first cell in the loop, unchanged')
  call check(count(s%cell_smooth) == 252, 'two close cells: 252 smoothing cells')
  call check(count(s%node_move) == 5*6*5, 'two close cells: interior nodes of the box')
  call check(count(s%cell_remap) == 8*9*8, 'two close cells: remap box one layer larger')
  call check_sets(s, 'two close cells')

  ! ---- the range is the cube of side d_max about the centre ----
  ! (10,10,10) and (13,10,10) are 3 apart: outside d_max/2 = 2 with d_max = 4
  ! (two subdomains), inside d_max/2 = 3 with d_max = 6 (one)
  quality = 1.0_wp
  quality(cell(10, 10, 10)) = qd
  quality(cell(13, 10, 10)) = qd
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(s%nbox == 2, 'three cells apart, d_max 4: two subdomains')
  call check_box(s, 1, [8, 8, 8], [12, 12, 12], 'three apart, d_max 4: first box')
  call check_box(s, 2, [11, 8, 8], [15, 12, 12], 'three apart, d_max 4: second box')
  ! union 8..15 x 8..12 x 8..12 = 8*5*5 = 200 cells, 7*4*4 = 112 movable nodes
  call check(count(s%cell_smooth) == 200 .and. count(s%node_move) == 112, 'three apart, d_max 4: union')
  call check_sets(s, 'three apart, d_max 4')
  call rezone_subdomains_find(m, m, m, quality, q, 6.0_wp, s, err)
  call check(s%nbox == 1, 'three cells apart, d_max 6: one subdomain')
  call check_box(s, 1, [8, 8, 8], [15, 12, 12], 'three apart, d_max 6: box')

  ! ---- two distorted cells far apart: two subdomains ----
  quality = 1.0_wp
  quality(cell(5, 5, 5)) = qd
  quality(cell(15, 15, 15)) = qd
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(s%nbox == 2, 'two far cells: two subdomains')
  call check_box(s, 1, [3, 3, 3], [7, 7, 7], 'two far cells: first box')
  call check_box(s, 2, [13, 13, 13], [17, 17, 17], 'two far cells: second box')
  call check(all(s%centre(:, 2) == [15, 15, 15]), 'two far cells: second centre')
  call check(count(s%cell_smooth) == 250 .and. count(s%node_move) == 128 .and. count(s%cell_remap) == 686, &
             'two far cells: 250 smoothing cells, 128 nodes, 686 remap cells')
  call check_sets(s, 'two far cells')

  ! ---- a distorted cell at a corner of the block: the box is clipped ----
  ! 3x3x3 box clipped to 1..2, expanded to 1..3 (27 cells); nodes 0..2 move
  ! (27: those on the block faces are inside, the smoother constrains them);
  ! remap 1..4 (64)
  quality = 1.0_wp
  quality(cell(1, 1, 1)) = qd
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(s%nbox == 1, 'corner cell: one subdomain')
  call check_box(s, 1, [1, 1, 1], [3, 3, 3], 'corner cell: box clipped to the block')
  call check(count(s%cell_smooth) == 27 .and. count(s%node_move) == 27 .and. count(s%cell_remap) == 64, &
             'corner cell: 27 cells, 27 nodes, 64 remap cells')
  call check(s%node_move(node(0, 0, 0)) .and. .not. s%node_move(node(3, 0, 0)), &
             'corner cell: block corner inside, region boundary fixed')
  call check_sets(s, 'corner cell')
  quality = 1.0_wp
  quality(cell(m, m, 1)) = qd
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check_box(s, 1, [m - 2, m - 2, 1], [m, m, 3], 'far corner cell: box clipped to the block')
  call check(count(s%node_move) == 27 .and. s%node_move(node(m, m, 0)), 'far corner cell: 27 movable nodes')

  ! ---- overlapping subdomains: a step-like region ----
  ! d_max = 2 (d_max/2 = 1): (5,5,5) and (8,7,5) are 3 apart, two subdomains
  ! A = 3..7 x 3..7 x 3..7 and B = 6..10 x 5..9 x 3..7, overlapping in
  ! 6..7 x 5..7 x 3..7 (30 cells): union 125 + 125 - 30 = 220 cells, not a
  ! cuboid. Movable nodes: per z node level 3..6 (4 levels) the 2D interior
  ! nodes of the L-shaped union, 16 + 16 - 2 = 30: 120. Remap: A and B grown
  ! by one, 343 + 343 - 4*5*7 = 546.
  quality = 1.0_wp
  quality(cell(5, 5, 5)) = qd
  quality(cell(8, 7, 5)) = qd
  call rezone_subdomains_find(m, m, m, quality, q, 2.0_wp, s, err)
  call check(s%nbox == 2, 'overlap: two subdomains')
  call check_box(s, 1, [3, 3, 3], [7, 7, 7], 'overlap: box A')
  call check_box(s, 2, [6, 5, 3], [10, 9, 7], 'overlap: box B')
  call check(count(s%cell_smooth) == 220, 'overlap: union of 220 cells')
  call check(count(s%node_move) == 120, 'overlap: 120 movable nodes')
  call check(count(s%cell_remap) == 546, 'overlap: 546 remap cells')
  call check(s%cell_smooth(cell(7, 9, 5)) .and. .not. s%cell_smooth(cell(3, 9, 5)) &
             .and. .not. s%cell_smooth(cell(10, 3, 5)), 'overlap: step-like, not the bounding box')
  ! the re-entrant corner node (7,4) of the L has a cell outside: fixed
  call check(.not. s%node_move(node(7, 4, 5)) .and. s%node_move(node(6, 7, 5)), 'overlap: seam nodes')
  call check_sets(s, 'overlap')
  ! TFI fallback: A and B overlap, merged into their bounding box
  call rezone_subdomains_merge(s%lo, s%hi, mlo, mhi, err)
  call check(.not. allocated(err) .and. size(mlo, 2) == 1, 'overlap: merged into one cuboid')
  call check(all(mlo(:, 1) == [3, 3, 3]) .and. all(mhi(:, 1) == [10, 9, 7]), 'overlap: merged bounding box')
  call rezone_subdomains_from_boxes(m, m, m, mlo, mhi, t, err)
  call check(.not. allocated(err) .and. count(t%cell_smooth) == 8*7*5 .and. count(t%node_move) == 7*6*4 &
             .and. count(t%cell_remap) == 10*9*7 .and. all(t%centre == 0), 'overlap: sets of the merged cuboid')
  call check_sets(t, 'merged cuboid')

  ! ---- a cell in the range of two subdomains enlarges both ----
  ! d_max = 4: (5,5,5) seeds A; (8,5,5) is 3 away and seeds B; (7,5,5) is
  ! within 2 of both centres, so A grows to 4..8 and B already covers 6..8
  quality = 1.0_wp
  quality(cell(5, 5, 5)) = qd
  quality(cell(8, 5, 5)) = qd
  quality(cell(7, 5, 6)) = qd
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(s%nbox == 2 .and. s%n_distorted == 3, 'shared cell: two subdomains')
  call check_box(s, 1, [3, 3, 3], [9, 7, 8], 'shared cell: A grown (4..8 x 4..6 x 4..7, expanded)')
  call check_box(s, 2, [5, 3, 3], [10, 7, 8], 'shared cell: B grown (6..9 x 4..6 x 4..7, expanded)')

  ! ---- a 2D block (nk = 1): boxes keep k = 1..1; the nodes on both k faces
  ! are inside (block boundary), so 4*4*2 = 32 move ----
  quality = 1.0_wp
  quality(10 + m*9) = qd
  call rezone_subdomains_find(m, m, 1, quality(1:m*m), q, 2.0_wp, s, err)
  call check(.not. allocated(err) .and. s%nbox == 1, '2D block: one subdomain')
  call check_box(s, 1, [8, 8, 1], [12, 12, 1], '2D block: box')
  call check(count(s%node_move) == 32 .and. count(s%cell_remap) == 49, '2D block: 32 nodes, 49 remap cells')

  ! ---- frozen cells (solid particles, Fig. 4(f)) ----
  ! a frozen distorted cell seeds nothing
  quality = 1.0_wp
  frozen = .false.
  quality(cell(10, 10, 10)) = qd
  frozen(cell(10, 10, 10)) = .true.
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err, frozen)
  call check(s%nbox == 0 .and. s%n_distorted == 0 .and. s%n_frozen_distorted == 1, 'frozen distorted cell is skipped')
  ! a frozen cell inside a subdomain leaves the smoothing set and fixes its 8
  ! nodes (all interior here): 125 - 1 cells, 64 - 8 nodes; the remap set is
  ! unchanged (the frozen cell touches smoothing cells)
  frozen = .false.
  frozen(cell(11, 10, 10)) = .true.
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err, frozen)
  call check(s%nbox == 1 .and. s%n_frozen_distorted == 0, 'frozen neighbour: one subdomain')
  call check_box(s, 1, [8, 8, 8], [12, 12, 12], 'frozen neighbour: box unchanged')
  call check(.not. s%cell_smooth(cell(11, 10, 10)), 'frozen neighbour: not smoothed')
  call check(count(s%cell_smooth) == 124 .and. count(s%node_move) == 56 .and. count(s%cell_remap) == 343, &
             'frozen neighbour: 124 cells, 56 nodes, 343 remap cells')
  call check(.not. s%node_move(node(10, 9, 9)) .and. .not. s%node_move(node(11, 10, 10)), &
             'frozen neighbour: its nodes are fixed')
  call check_sets(s, 'frozen neighbour', frozen)

  ! ---- an undefined quality counts as distorted ----
  quality = 1.0_wp
  quality(cell(10, 10, 10)) = ieee_value(1.0_wp, ieee_quiet_nan)
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(s%nbox == 1 .and. s%n_distorted == 1, 'NaN quality is distorted')
  ! inverted cells (Q < 0) are distorted; Q = q exactly is not
  quality = 1.0_wp
  quality(cell(10, 10, 10)) = -0.3_wp
  quality(cell(2, 2, 2)) = q
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err)
  call check(s%nbox == 1 .and. s%n_distorted == 1, 'Q < 0 distorted, Q = q not')

  ! ---- merging for the TFI fallback ----
  ! face-touching boxes whose union is a cuboid merge into it exactly
  lo(:, 1) = [1, 1, 1]; hi(:, 1) = [3, 3, 3]
  lo(:, 2) = [4, 1, 1]; hi(:, 2) = [6, 3, 3]
  call rezone_subdomains_merge(lo(:, 1:2), hi(:, 1:2), mlo, mhi, err)
  call check(size(mlo, 2) == 1, 'merge: face-touching boxes merge')
  call check(all(mlo(:, 1) == [1, 1, 1]) .and. all(mhi(:, 1) == [6, 3, 3]), 'merge: union cuboid')
  ! touching along an edge only: kept apart
  lo(:, 2) = [4, 4, 1]; hi(:, 2) = [6, 6, 3]
  call rezone_subdomains_merge(lo(:, 1:2), hi(:, 1:2), mlo, mhi, err)
  call check(size(mlo, 2) == 2, 'merge: edge contact is not merged')
  ! a chain: 1 and 2 overlap; their bounding box 1..6 x 1..5 x 1..3 then
  ! overlaps 3 (which touched neither); 4 stays apart; order follows the input
  lo(:, 1) = [1, 1, 1]; hi(:, 1) = [3, 3, 3]
  lo(:, 2) = [3, 3, 1]; hi(:, 2) = [6, 5, 3]
  lo(:, 3) = [12, 12, 12]; hi(:, 3) = [14, 14, 14]
  lo(:, 4) = [1, 5, 3]; hi(:, 4) = [1, 8, 3]
  call rezone_subdomains_merge(lo, hi, mlo, mhi, err)
  call check(.not. allocated(err) .and. size(mlo, 2) == 2, 'merge: chain gives two cuboids')
  call check(all(mlo(:, 1) == [1, 1, 1]) .and. all(mhi(:, 1) == [6, 8, 3]), 'merge: chained bounding box')
  call check(all(mlo(:, 2) == [12, 12, 12]) .and. all(mhi(:, 2) == [14, 14, 14]), 'merge: far box kept')

  ! ---- errors are returned, not stopped on ----
  call rezone_subdomains_find(m, m, m, quality(1:10), q, 4.0_wp, s, err)
  call check(allocated(err), 'wrong quality size is an error')
  if (allocated(err)) deallocate(err)
  call rezone_subdomains_find(m, m, m, quality, q, -1.0_wp, s, err)
  call check(allocated(err), 'negative d_max is an error')
  if (allocated(err)) deallocate(err)
  call rezone_subdomains_find(m, m, m, quality, q, 4.0_wp, s, err, frozen(1:5))
  call check(allocated(err), 'wrong frozen size is an error')
  if (allocated(err)) deallocate(err)
  lo(:, 1) = [0, 1, 1]; hi(:, 1) = [3, 3, 3]
  call rezone_subdomains_from_boxes(m, m, m, lo(:, 1:1), hi(:, 1:1), t, err)
  call check(allocated(err), 'a box outside the block is an error')
  if (allocated(err)) deallocate(err)

  call check_summary('test_rezone_subdomains')

contains

  !> Cell index of (i, j, k) on the m^3 block.
  pure integer function cell(i, j, k)
    integer, intent(in) :: i, j, k
    cell = i + m*((j - 1) + m*(k - 1))
  end function cell

  !> Node index of (i, j, k) on the m^3 block.
  pure integer function node(i, j, k)
    integer, intent(in) :: i, j, k
    node = 1 + i + (m + 1)*(j + (m + 1)*k)
  end function node

  !> Checks box b of s against the expected lower and upper cell indices.
  subroutine check_box(s, b, elo, ehi, what)
    type(rezone_subdomains_t), intent(in) :: s
    integer, intent(in) :: b, elo(3), ehi(3)
    character(len=*), intent(in) :: what
    if (b > s%nbox) then
      call check(.false., what//' (missing)')
      return
    end if
    call check(all(s%lo(:, b) == elo) .and. all(s%hi(:, b) == ehi), what)
    if (.not. (all(s%lo(:, b) == elo) .and. all(s%hi(:, b) == ehi))) &
      write(*, '(a,6i4)') '  got lo, hi:', s%lo(:, b), s%hi(:, b)
  end subroutine check_box

  !> Brute-force movable nodes of s on a block of s%ni x s%nj x s%nk: a node
  !> moves iff no cell within the block around it is outside the smoothing set.
  function brute_nodes(s) result(mv)
    type(rezone_subdomains_t), intent(in) :: s
    logical :: mv((s%ni + 1)*(s%nj + 1)*(s%nk + 1))
    integer :: i, j, k, di, dj, dk, ci, cj, ck, n
    mv = .false.
    n = 0
    do k = 0, s%nk
      do j = 0, s%nj
        do i = 0, s%ni
          n = n + 1
          mv(n) = .true.
          do dk = 0, 1
            do dj = 0, 1
              do di = 0, 1
                ci = i + di
                cj = j + dj
                ck = k + dk
                if (ci < 1 .or. ci > s%ni .or. cj < 1 .or. cj > s%nj .or. ck < 1 .or. ck > s%nk) cycle
                if (.not. s%cell_smooth(ci + s%ni*((cj - 1) + s%nj*(ck - 1)))) mv(n) = .false.
              end do
            end do
          end do
        end do
      end do
    end do
  end function brute_nodes

  !> The sets of s against their definitions: smoothing = union of the boxes
  !> less the frozen cells, remap = cells within one layer (26
  !> neighbours) of a smoothing cell, nodes by brute force, lists = masks.
  subroutine check_sets(s, what, frozen)
    type(rezone_subdomains_t), intent(in) :: s
    character(len=*), intent(in) :: what
    logical, intent(in), optional :: frozen(:)
    logical :: inbox, near, ok_union, ok_remap
    integer :: i, j, k, b, c, i2, j2, k2
    ok_union = .true.
    ok_remap = .true.
    c = 0
    do k = 1, s%nk
      do j = 1, s%nj
        do i = 1, s%ni
          c = c + 1
          inbox = .false.
          do b = 1, s%nbox
            if (all([i, j, k] >= s%lo(:, b)) .and. all([i, j, k] <= s%hi(:, b))) inbox = .true.
          end do
          if (present(frozen)) then
            if (frozen(c)) inbox = .false.
          end if
          if (s%cell_smooth(c) .neqv. inbox) ok_union = .false.
          near = .false.
          do k2 = max(k - 1, 1), min(k + 1, s%nk)
            do j2 = max(j - 1, 1), min(j + 1, s%nj)
              do i2 = max(i - 1, 1), min(i + 1, s%ni)
                if (s%cell_smooth(i2 + s%ni*((j2 - 1) + s%nj*(k2 - 1)))) near = .true.
              end do
            end do
          end do
          if (s%cell_remap(c) .neqv. near) ok_remap = .false.
        end do
      end do
    end do
    call check(ok_union, what//': smoothing set is the union of the boxes less frozen cells')
    call check(ok_remap, what//': remap set is the smoothing set grown by one layer')
    call check(all(s%node_move .eqv. brute_nodes(s)), what//': movable nodes')
    call check(size(s%smooth_cells) == count(s%cell_smooth) .and. size(s%move_nodes) == count(s%node_move) &
               .and. size(s%geometry_cells) == count(s%cell_remap), what//': list sizes')
    if (size(s%smooth_cells) > 0) call check(all(s%cell_smooth(s%smooth_cells)), what//': smoothing list')
    if (size(s%geometry_cells) > 0) call check(all(s%cell_remap(s%geometry_cells)), what//': remap list')
    if (size(s%move_nodes) > 0) call check(all(s%node_move(s%move_nodes)), what//': node list')
  end subroutine check_sets
end program test_rezone_subdomains
