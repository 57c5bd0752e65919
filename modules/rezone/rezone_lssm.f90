!> Smoothing rezone of a block (LSSM, Sect. 5.2-5.3 of the paper, and the
!> whole-grid smoothing it is compared with): the nodes put back on the
!> standard grid first, the distorted cells and their subdomains (the whole
!> grid's, the same on any decomposition), the guarded combined smoothing,
!> the TFI fallback and the last safeguards. What it did comes back as a
!> report (`lssm_report_t`) for the caller's log.
module rezone_lssm
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use base_kinds, only: wp
  use base_sort, only: sort_order
  use base_errors, only: error_no_memory, error_t, error_set
  use base_share, only: share_t
  use mesh_grid, only: grid_t, grid_index_t, grid_index
  use mesh_halo, only: halo_t
  use mesh_boundary, only: bc_t, BC_INFLOW, BC_OUTFLOW, bc_fixed_nodes
  use rezone_config, only: rezone_config_t
  use rezone_global, only: global_face_rule, GLOBAL_FACE_MOVE
  use rezone_quality, only: grid_quality, grid_trigger_cells, hex_fails_triggers
  use rezone_subdomains, only: rezone_subdomains_t, rezone_subdomains_seed, rezone_subdomains_merge, &
                               rezone_subdomains_default_dmax, rezone_subdomains_from_boxes
  use rezone_smooth, only: smooth_mobility_t, smooth_mobility_block, smooth_region_t, smooth_region_init, &
                           smooth_combined, smooth_tfi, smooth_q_min, smooth_keep_small_moves, smooth_revert_tangled, &
                           smooth_region_tangled, node_fixed, tfi_shell_t, smooth_tfi_shell, tfi_shell_put, &
                           smooth_tfi_parameters, smooth_tfi_node
  implicit none
  private
  public :: lssm_report_t, lssm_rezone, LSSM_SKIPPED, LSSM_SNAPPED, LSSM_SMOOTHED

  !> What `lssm_rezone` did: nothing (no cell to smooth, no node to put
  !> back), only put nodes back on the standard grid, or smoothed.
  integer, parameter :: LSSM_SKIPPED = 0, LSSM_SNAPPED = 1, LSSM_SMOOTHED = 2

  !> Its counts, the whole grid's: nodes put back on the standard grid
  !> (snapped; ngrown of them beside a cell a snap inverted), distorted
  !> cells (0 with mode 'smooth'), subdomains, cells smoothed, nodes whose
  !> move under &rezone move_min was kept out (kept), the smoothing's Q_min
  !> before and after and its iterations, whether TFI followed, and the
  !> untangling guard's moves halved (guarded), nodes put back (reverted)
  !> and node moves untangling first (untangled); box: the triggers' tests
  !> chose the distorted cells (smooth_target 'box'), not Q.
  type :: lssm_report_t
    integer :: outcome = LSSM_SKIPPED
    integer :: snapped = 0, ngrown = 0, distorted = 0, subdomains = 0, smoothed = 0, kept = 0, iterations = 0
    integer :: guarded = 0, reverted = 0, untangled = 0
    real(wp) :: q_min0 = 0.0_wp, q_min = 0.0_wp
    logical :: tfi = .false., box = .false.
  end type lssm_report_t

contains

  !> Smoothing rezone. 'lssm' (Sect. 5.2-5.3): the distorted subdomains of
  !> the grid; 'smooth': the whole grid (the global MMALE the paper compares
  !> LSSM with, always read as printed: Eq. 46 against a cube, cube targets).
  !> The cells are smoothed by the combined method until their Q_min reaches
  !> quality_target or smooth_iterations are done. x is the grid on entry and
  !> the rezoned grid on return, x0 the standard (initial) grid; quality and
  !> fail: work arrays of g's cells; rep: what was done (the step is
  !> skipped when rep%outcome is LSSM_SKIPPED).
  !>
  !> 'lssm' with smooth_target = 'cube' is the paper as printed: distorted
  !> cells have Eq. (46) Q < quality, nodes of the subdomains move towards
  !> cubes, TFI of the merged cuboids if the target is not reached. With
  !> 'box' (default): a cell is distorted when it fails the Euler-step
  !> triggers' own tests (side ratio, inclined angle against the axes,
  !> tangled: the cells that made the step due); their subdomains (Sect. 5.2) are smoothed
  !> towards boxes of each cell's own proportions (aspect ratio at most
  !> sqrt(side_ratio)) with a spacing-keeping weighted average, so the
  !> Lagrangian compression of a shock stays; TFI (which interpolates the
  !> merged cuboids from their faces, ignoring the spacing inside them) only
  !> for the merged cuboids in which a cell is still tangled after the
  !> smoothing. In both, a smoothing pass never tangles a cell, and a changed
  !> cell left tangled goes back; before the passes the cells below &rezone
  !> untangle's health are untangled (`smooth_untangle`), and with 'box' a
  !> pass may not squeeze a cell below &rezone squeeze of its volume.
  !>
  !> Nodes put back at their standard places (x0, or standard) first (`snap_nodes`):
  !> those of the cells coupled particles occupy (`occupied`, Remark 2),
  !> those of inflow and outflow faces that drifted more than &rezone
  !> drift_open of their standard spacing (an open face is the domain's
  !> fixed edge: left to the Lagrangian motion it drifts with the
  !> through-flow and the domain goes with it), and with drift_max > 0 every
  !> other node that drifted more than drift_max of it. The other cells
  !> around the nodes so moved are distorted if, so moved, they fail the
  !> test of the reading (box: the triggers' tests, on the snapped nodes;
  !> cube: Q < quality): the occupied cells are the smoothing's fixed inner
  !> boundary (Remark 2), and a slab of particles whose nodes moved a
  !> micrometre does not make every cell around it a subdomain's seed.
  !>
  !> shape_fail: the triggers' side-ratio and angle tests of g's owned
  !> cells on these nodes x, taken by the step's look at the grid
  !> (`grid_shape_worst`'s fail with the deck's bounds): with 'box' only
  !> the tangle test is then left to take there.
  !>
  !> mob_keep: the mobility of g's nodes (`smooth_mobility_block`) kept
  !> from one call to the next on the same block, built at the first; not
  !> used with occupied (the frozen nodes change).
  !>
  !> standard: the standard places where they are not x0, with faces that
  !> move with the material (the global rezone's target, `rezone_grid`):
  !> the snaps go there, the trigger tests still measure against x0's
  !> shapes. The nodes of such faces are fixed for the smoothing
  !> (`moving_faces`).
  subroutine lssm_rezone(rz, g, bc, share, halo, x0, quality, fail, x, rep, err, occupied, shape_fail, mob_keep, &
                         standard)
    type(rezone_config_t), intent(in) :: rz
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    class(share_t), intent(in), optional :: share
    class(halo_t), intent(inout) :: halo
    real(wp), intent(in) :: x0(:, :)
    real(wp), intent(inout) :: quality(:)
    logical, intent(inout) :: fail(:)
    real(wp), intent(inout) :: x(:, :)
    type(lssm_report_t), intent(out) :: rep
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: occupied(:)
    logical, intent(in), optional :: shape_fail(:)
    type(smooth_mobility_t), intent(inout), optional :: mob_keep
    real(wp), intent(in), optional :: standard(:, :)
    logical, allocatable :: moved(:), touched(:), counts(:), tangled(:)
    type(rezone_subdomains_t) :: sub
    type(smooth_mobility_t) :: mob
    type(smooth_region_t) :: reg
    integer, allocatable :: blo(:, :), bhi(:, :), mlo(:, :), mhi(:, :), tlo(:, :), thi(:, :)
    real(wp) :: q_min, q_min0, d_max, aspect_max, none(0), xn(3, 8), xn0(3, 8)
    integer :: iterations, b, n(3), c, i, j, k, stat, nd, nrevert, ngrown, sums(3), ntangled
    logical :: tfi, box

    box = trim(rz%mode) == 'lssm' .and. trim(rz%smooth_target) == 'box'
    ! the smoothers' block: the stored cells (owned and ghost)
    n = g%shi - g%slo + 1
    allocate(moved(g%nnode), touched(g%ncell), counts(g%nnode), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'lssm_rezone', error_no_memory('the rezone''s work arrays'))
      return
    end if
    do k = g%slo(3) - 1, g%shi(3)
      do j = g%slo(2) - 1, g%shi(2)
        do i = g%slo(1) - 1, g%shi(1)
          counts(g%node(i, j, k)) = g%counts_node(i, j, k)
        end do
      end do
    end do
    if (present(standard)) then
      call snap_nodes(rz, g, bc, halo, counts, standard, x, moved, ngrown, err, occupied)
    else
      call snap_nodes(rz, g, bc, halo, counts, x0, x, moved, ngrown, err, occupied)
    end if
    if (allocated(err)) return
    call cells_touched(g, moved, touched, occupied)
    aspect_max = huge(1.0_wp)
    if (box) then
      ! Eq. (46) against each cell's own box, aspect ratio up to the
      ! geometric middle of the paper's cube (1) and the trigger's bound
      ! (the distorted cells are the triggers': no cell's Q is needed, and
      ! the log's Q_min before is the smoothed cells', `smooth_combined`)
      if (rz%side_ratio > 1.0_wp) aspect_max = sqrt(rz%side_ratio)
      ! (the snapped nodes' cells join the distorted cells below whatever
      ! their tests: shape tests taken before the snap serve)
      call grid_trigger_cells(n(1), n(2), n(3), x, rz%side_ratio, rz%cos_angle, fail, share, shape_fail, &
                              g%clo - g%slo + 1, g%chi - g%slo + 1, x0)
    else if (trim(rz%mode) /= 'smooth') then
      ! (mode 'smooth' smooths every cell: its Q_min before is the region's)
      call grid_quality(n(1), n(2), n(3), x, quality, q_min0, share=share)
      call halo%choose(q_min0, none)
    end if
    if (trim(rz%mode) == 'smooth') then
      ! the whole grid as one subdomain
      blo = reshape([1, 1, 1], [3, 1])
      bhi = reshape(g%gn, [3, 1])
      nd = 0
    else
      d_max = rz%d_max
      if (.not. d_max > 0.0_wp) d_max = rezone_subdomains_default_dmax(g%gn(1), g%gn(2), g%gn(3))
      ! distorted: with 'box' the cells failing the triggers' tests (q plays
      ! no part), else Q < quality (Eq. 46) or undefined; the cells around
      ! the snapped nodes only where, so moved, they fail them
      if (box) then
        ! (the shape tests taken before the snap: again on the snapped
        ! nodes where they moved)
        do c = 1, g%ncell
          if (fail(c) .or. .not. touched(c)) cycle
          call g%gather(c, x, xn)
          call g%gather(c, x0, xn0)
          fail(c) = hex_fails_triggers(xn, rz%side_ratio, rz%cos_angle, xn0)
        end do
      else
        do c = 1, g%ncell
          fail(c) = ieee_is_nan(quality(c)) .or. quality(c) < rz%quality
        end do
      end if
      call subdomain_boxes(g, halo, fail, d_max, blo, bhi, nd, err, occupied)
    end if
    if (.not. allocated(err)) call block_subdomains(g, blo, bhi, sub, err, occupied)
    if (allocated(err)) return
    ! (counts of this block's owned cells and nodes, then the whole grid's:
    ! snapped, smoothed, kept)
    sums = 0
    sums(1) = count(moved .and. counts)
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          if (sub%cell_smooth(g%cell(i, j, k))) sums(2) = sums(2) + 1
        end do
      end do
    end do
    rep%box = box
    if (size(blo, 2) == 0) then
      call halo%sum_ints(sums)
      ! only the snapped nodes move (every cell around them is occupied, or
      ! so moved passes the tests)
      rep%snapped = sums(1)
      rep%ngrown = ngrown
      if (sums(1) > 0) rep%outcome = LSSM_SNAPPED
      return
    end if
    if (present(mob_keep) .and. .not. present(occupied)) then
      if (.not. allocated(mob_keep%kind)) &
        call smooth_mobility_block(g%grid_index_t, mob_keep, err, fixed_faces=moving_faces(bc), &
                                   fixed_nodes=bc_fixed_nodes(bc))
      if (allocated(err)) return
      mob = mob_keep
    else
      call smooth_mobility_block(g%grid_index_t, mob, err, frozen=occupied, fixed_faces=moving_faces(bc), &
                                 fixed_nodes=bc_fixed_nodes(bc))
    end if
    if (allocated(err)) return
    ! (the squeeze guard with the box reading only: the cube target does not
    ! keep volumes, and with 'smooth' the whole grid moves)
    if (box) then
      call smooth_region_init(mob, sub%cell_smooth, reg, err, aspect_max=aspect_max, counts=counts, &
                              squeeze=rz%squeeze, health_min=rz%untangle, origin=g%off + g%slo - 1, ghost_width=g%ng)
    else
      call smooth_region_init(mob, sub%cell_smooth, reg, err, counts=counts, health_min=rz%untangle, &
                              origin=g%off + g%slo - 1, ghost_width=g%ng)
    end if
    if (allocated(err)) return
    if (box .or. trim(rz%mode) == 'smooth') then
      call smooth_combined(reg, x, rz%quality_target, rz%smooth_iterations, iterations, q_min, halo, q_min0)
    else
      call smooth_combined(reg, x, rz%quality_target, rz%smooth_iterations, iterations, q_min, halo)
    end if
    ! the smoothed cells left tangled (ntangled: the whole grid's)
    allocate(tangled(g%ncell), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'lssm_rezone', error_no_memory('the tangled cells'))
      return
    end if
    call smooth_region_tangled(reg, x, tangled)
    ntangled = 0
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          if (tangled(g%cell(i, j, k))) ntangled = ntangled + 1
        end do
      end do
    end do
    call halo%max_int(ntangled)
    ! the fallback: transfinite interpolation of each merged cuboid
    ! subdomain from its boundary (node index box = cell box widened by
    ! one); with 'box' only of merged boxes around the cells the smoothing
    ! left tangled (the Lagrangian phase can hand over cells whose corners
    ! are inverted, which the guarded smoothing cannot undo: left so, they
    ! only get worse until the old grid cannot be remapped), not of whole
    ! merged subdomains, whose TFI can take back a shock's compression
    ! over hundreds of thousands of cells and cost more remap than the rest
    ! of the run
    tfi = q_min < rz%quality_target .and. .not. box
    if (box) then
      tfi = ntangled > 0
      if (tfi) call tangled_boxes(tlo, thi)
      if (allocated(err)) return
    else if (tfi) then
      tlo = blo
      thi = bhi
    end if
    if (tfi) then
      call rezone_subdomains_merge(tlo, thi, mlo, mhi, err)
      if (allocated(err)) return
      do b = 1, size(mlo, 2)
        call block_tfi(g, halo, mob, mlo(:, b), mhi(:, b), x, err)
        if (allocated(err)) return
      end do
      call halo%nodes(x)
    end if
    if (rz%move_min > 0.0_wp) then
      ! negligible moves kept out of the remap
      call smooth_keep_small_moves(n(1), n(2), n(3), g%x, x, rz%move_min, sums(3), counts)
      call halo%nodes(x)
    end if
    ! a changed cell left tangled (by TFI, say) goes back as it was (none
    ! is where only the smoothing moved nodes, those of its cells alone, and
    ! left none of them tangled: the snaps' cells are among them)
    nrevert = 0
    if (tfi .or. ntangled > 0 .or. rz%move_min > 0.0_wp .or. present(occupied)) &
      call smooth_revert_tangled(n(1), n(2), n(3), g%x, x, nrevert, err, halo, counts)
    if (allocated(err)) return
    q_min = smooth_q_min(reg, x)
    call halo%choose(q_min, none)
    call halo%sum_ints(sums)
    rep%outcome = LSSM_SMOOTHED
    rep%snapped = sums(1)
    rep%smoothed = sums(2)
    rep%kept = sums(3)
    rep%ngrown = ngrown
    rep%distorted = nd
    rep%subdomains = size(blo, 2)
    rep%q_min0 = q_min0
    rep%q_min = q_min
    rep%iterations = iterations
    rep%tfi = tfi
    rep%guarded = reg%n_guarded
    rep%reverted = nrevert
    rep%untangled = reg%n_untangled

  contains

    !> The boxes (the whole grid's cell indices) around the smoothed cells
    !> still tangled after the smoothing (tangled): the subdomains they seed
    !> (`subdomain_boxes` with d_max = 1: a tangled cell's box reaches two
    !> cells from it) widened by tfi_widen layers. Measured on the matrix's
    !> sedov_40_lssm (Euler phase, Euler steps, L1): 0 layers 68 s, 283,
    !> 0.0783; 2 layers 61 s, 252, 0.0761; 4 layers 116 s, 317, 0.0759; the
    !> merged subdomains (before) 253 s, 326, 0.0761.
    subroutine tangled_boxes(lo, hi)
      integer, allocatable, intent(out) :: lo(:, :), hi(:, :)
      integer, parameter :: tfi_widen = 2
      integer :: nt
      call subdomain_boxes(g, halo, tangled, 1.0_wp, lo, hi, nt, err, occupied)
      if (allocated(err)) return
      do nt = 1, size(lo, 2)
        lo(:, nt) = max(lo(:, nt) - tfi_widen, 1)
        hi(:, nt) = min(hi(:, nt) + tfi_widen, g%gn)
      end do
    end subroutine tangled_boxes
  end subroutine lssm_rezone
  !> The nodes `lssm_rezone` puts back on the standard grid x0 before
  !> smoothing (its notes), of the stored nodes of g: x(:, n) = x0(:, n) for
  !> each; moved(n) tells whether node n's place changed so. A snapped node
  !> can invert a cell beside it (an open face's node put back behind an
  !> inner node that drifted further out): such a cell's other nodes are put
  !> back too, round after round, until every changed cell is untangled (the
  !> rounds of `smooth_revert_tangled`, towards x0, whose cells are
  !> untangled; the whole grid's, so a decomposition gives the same). The
  !> guarded smoothing cannot undo an inverted cell and the last safeguard
  !> would put the snap back, leaving the drift to grow at every step.
  !> ngrown: the nodes so added, the whole grid's (counts: the block's own).
  subroutine snap_nodes(rz, g, bc, halo, counts, x0, x, moved, ngrown, err, occupied)
    type(rezone_config_t), intent(in) :: rz
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    class(halo_t), intent(inout) :: halo
    logical, intent(in) :: counts(:)
    real(wp), intent(in) :: x0(:, :)
    real(wp), intent(inout) :: x(:, :)
    logical, intent(out) :: moved(:)
    integer, intent(out) :: ngrown
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: occupied(:)
    real(wp), allocatable :: xin(:, :)
    integer :: n, c, a, i, j, k, d, f, ijk(3), stride(3), stat, nsnap
    real(wp) :: h0, limit
    logical :: snap, open(6)
    ngrown = 0
    allocate(xin, source=x, stat=stat)
    if (stat /= 0) then
      call error_set(err, 'lssm_rezone', error_no_memory('the snapped nodes'))
      return
    end if
    open = [(bc%kind(f) == BC_INFLOW .or. bc%kind(f) == BC_OUTFLOW, f = 1, 6)]
    stride = [1, g%sx, g%sxy]
    do n = 1, g%nnode
      call g%node_ijk(n, i, j, k)
      ijk = [i, j, k]
      ! the drift allowed: drift_open on open faces, drift_max inside
      ! (0: none on open faces, any inside)
      limit = rz%drift_max
      if (.not. limit > 0.0_wp) limit = huge(1.0_wp)
      do f = 1, 6
        if (open(f) .and. btest(g%node_faces(i, j, k), f - 1)) limit = rz%drift_open
      end do
      snap = .false.
      if (limit < huge(1.0_wp)) then
        ! the standard spacing: the shortest edge of x0 at the node (a ghost
        ! on the stored box's face may lack a neighbour's, and takes its
        ! owner's place from the halo)
        h0 = huge(1.0_wp)
        do d = 1, 3
          if (ijk(d) > g%slo(d) - 1) h0 = min(h0, norm2(x0(:, n) - x0(:, n - stride(d))))
          if (ijk(d) < g%shi(d)) h0 = min(h0, norm2(x0(:, n) - x0(:, n + stride(d))))
        end do
        snap = norm2(x(:, n) - x0(:, n)) > limit*h0
      end if
      if (snap) x(:, n) = x0(:, n)
    end do
    if (present(occupied)) then
      do c = 1, g%ncell
        if (.not. occupied(c)) cycle
        do a = 1, 8
          n = g%node0(c) + g%corner_offset(a)
          x(:, n) = x0(:, n)
        end do
      end do
    end if
    call halo%nodes(x)
    do n = 1, g%nnode
      moved(n) = any(abs(x(:, n) - xin(:, n)) > 0.0_wp)
    end do
    nsnap = count(moved)
    call halo%max_int(nsnap)
    if (nsnap == 0) return
    ! (the cells the snaps inverted, as the last safeguard finds them, go to
    ! x0 whole)
    call smooth_revert_tangled(g%shi(1) - g%slo(1) + 1, g%shi(2) - g%slo(2) + 1, g%shi(3) - g%slo(3) + 1, xin, x, &
                               ngrown, err, halo, counts, x0)
    if (allocated(err)) return
    do n = 1, g%nnode
      moved(n) = any(abs(x(:, n) - xin(:, n)) > 0.0_wp)
    end do
  end subroutine snap_nodes

  !> The faces (xlo .. zhi) that move with the material (velocity and
  !> pressure faces, `global_face_rule`): the smoothing does not move their
  !> nodes (their places in the standard grid are where they are:
  !> `rezone_grid`).
  pure function moving_faces(bc) result(moving)
    type(bc_t), intent(in) :: bc
    logical :: moving(6)
    integer :: f
    moving = [(global_face_rule(bc%kind(f)) == GLOBAL_FACE_MOVE, f = 1, 6)]
  end function moving_faces

  !> The cells (not occupied by particles) with a node that moved.
  subroutine cells_touched(g, moved, touched, occupied)
    type(grid_t), intent(in) :: g
    logical, intent(in) :: moved(:)
    logical, intent(out) :: touched(:)
    logical, intent(in), optional :: occupied(:)
    integer :: c, a, n0
    touched = .false.
    if (.not. any(moved)) return
    do c = 1, g%ncell
      if (present(occupied)) then
        if (occupied(c)) cycle
      end if
      n0 = g%node0(c)
      do a = 1, 8
        touched(c) = touched(c) .or. moved(n0 + g%corner_offset(a))
      end do
    end do
  end subroutine cells_touched

  !> The subdomain boxes (Sect. 5.2) of the whole grid, lo, hi (3, nbox,
  !> the whole grid's cell indices), from the cells of g with distorted(c)
  !> true that no particle occupies: each block lists those it owns, and
  !> every block seeds the boxes from all of them in the whole grid's cell
  !> order (`rezone_subdomains_seed`), as one process does. nd: their
  !> number.
  subroutine subdomain_boxes(g, halo, distorted, d_max, lo, hi, nd, err, occupied)
    type(grid_t), intent(in) :: g
    class(halo_t), intent(inout) :: halo
    logical, intent(in) :: distorted(:)
    real(wp), intent(in) :: d_max
    integer, allocatable, intent(out) :: lo(:, :), hi(:, :)
    integer, intent(out) :: nd
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: occupied(:)
    real(wp), allocatable :: mine(:), every(:)
    integer, allocatable :: key(:), order(:), ijk(:, :), centre(:, :)
    integer :: i, j, k, c, m, gc, stat
    allocate(mine(count(distorted)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'lssm_rezone', error_no_memory('the distorted cells'))
      return
    end if
    m = 0
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          c = g%cell(i, j, k)
          if (.not. distorted(c)) cycle
          if (present(occupied)) then
            if (occupied(c)) cycle
          end if
          m = m + 1
          ! (whole-grid cell numbers, exact as reals)
          mine(m) = real(g%global_cell(c), wp)
        end do
      end do
    end do
    call halo%concat(mine(1:m), every)
    nd = size(every)
    key = nint(every)
    allocate(order(nd), ijk(3, nd), stat=stat)
    if (stat == 0) call sort_order(key, order, stat)
    if (stat /= 0) then
      call error_set(err, 'lssm_rezone', error_no_memory('the distorted cells'))
      return
    end if
    do m = 1, nd
      gc = key(order(m)) - 1
      ijk(:, m) = [mod(gc, g%gn(1)), mod(gc/g%gn(1), g%gn(2)), gc/(g%gn(1)*g%gn(2))] + 1
    end do
    call rezone_subdomains_seed(g%gn, ijk, d_max, lo, hi, centre, err)
  end subroutine subdomain_boxes

  !> The smoothing set of g's stored cells (the smoothers' block, stored
  !> cell slo its cell 1) from the whole grid's subdomain boxes lo, hi:
  !> each box clipped to the stored cells (`rezone_subdomains_from_boxes`).
  subroutine block_subdomains(g, lo, hi, sub, err, occupied)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: lo(:, :), hi(:, :)
    type(rezone_subdomains_t), intent(out) :: sub
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: occupied(:)
    integer :: l(3, size(lo, 2)), u(3, size(lo, 2)), b, m, n(3)
    n = g%shi - g%slo + 1
    m = 0
    do b = 1, size(lo, 2)
      if (any(max(lo(:, b) - g%off, g%slo) > min(hi(:, b) - g%off, g%shi))) cycle
      m = m + 1
      l(:, m) = max(lo(:, b) - g%off, g%slo) - g%slo + 1
      u(:, m) = min(hi(:, b) - g%off, g%shi) - g%slo + 1
    end do
    call rezone_subdomains_from_boxes(n(1), n(2), n(3), l(:, 1:m), u(:, 1:m), sub, err, occupied)
  end subroutine block_subdomains

  !> TFI (`smooth_tfi`) of the merged cuboid of cells lo..hi (the whole
  !> grid's indices) on g's nodes x, the nodes of mob's kind node_fixed
  !> kept: in place on one block that holds the whole grid; on a
  !> decomposed grid every block gathers the nodes on the cuboid's faces
  !> (each from the block that counts it) and interpolates its owned nodes
  !> inside from them (`tfi_shell_t`: no block holds the cuboid's nodes;
  !> the ghosts are the caller's).
  subroutine block_tfi(g, halo, mob, lo, hi, x, err)
    type(grid_t), intent(in) :: g
    class(halo_t), intent(inout) :: halo
    type(smooth_mobility_t), intent(in) :: mob
    integer, intent(in) :: lo(3), hi(3)
    real(wp), intent(inout) :: x(:, :)
    type(error_t), allocatable, intent(inout) :: err
    type(grid_index_t) :: cb
    type(tfi_shell_t) :: sh
    real(wp), allocatable :: mine(:), every(:)
    integer :: i, j, k, m, p, q, n(3), b(3), stat, ijk(3), il(3), iu(3)
    logical :: inside
    n = g%shi - g%slo + 1
    if (halo%nblocks == 1) then
      call smooth_tfi(n(1), n(2), n(3), lo - 1 - g%off - g%slo + 1, hi - g%off - g%slo + 1, x, err, mob)
      return
    end if
    ! the cuboid's nodes as a block: node (i, j, k) of the whole grid is
    ! its node (i, j, k) - b
    cb = grid_index(hi(1) - lo(1) + 1, hi(2) - lo(2) + 1, hi(3) - lo(3) + 1)
    b = lo - 1
    allocate(mine(4*product(g%nhi - g%nlo + 1)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'lssm_rezone', error_no_memory('the TFI''s faces'))
      return
    end if
    m = 0
    inside = .false.
    do k = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        do i = g%nlo(1), g%nhi(1)
          ijk = [i, j, k] + g%off - b
          if (any(ijk < 0) .or. any(ijk > [cb%ni, cb%nj, cb%nk])) cycle
          if (all(ijk > 0) .and. all(ijk < [cb%ni, cb%nj, cb%nk])) then
            inside = .true.
            cycle
          end if
          if (.not. g%counts_node(i, j, k)) cycle
          mine(m + 1:m + 4) = [real(cb%node(ijk(1), ijk(2), ijk(3)), wp), x(:, g%node(i, j, k))]
          m = m + 4
        end do
      end do
    end do
    call halo%concat(mine(1:m), every)
    if (.not. inside) return
    ! (the cuboid's shell from the faces gathered, not its nodes)
    call smooth_tfi_shell([0, 0, 0], [cb%ni, cb%nj, cb%nk], sh, err)
    if (allocated(err)) return
    do p = 1, size(every), 4
      call cb%node_ijk(nint(every(p)), ijk(1), ijk(2), ijk(3))
      call tfi_shell_put(sh, ijk(1), ijk(2), ijk(3), every(p + 1:p + 3))
    end do
    call smooth_tfi_parameters(sh)
    ! this block's owned nodes inside, but those that do not move
    il = max(g%nlo, lo - g%off)
    iu = min(g%nhi, hi - 1 - g%off)
    do k = il(3), iu(3)
      do j = il(2), iu(2)
        do i = il(1), iu(1)
          q = g%node(i, j, k)
          if (mob%kind(q) == node_fixed) cycle
          x(:, q) = smooth_tfi_node(sh, i + g%off(1) - b(1), j + g%off(2) - b(2), k + g%off(3) - b(3))
        end do
      end do
    end do
  end subroutine block_tfi
end module rezone_lssm
