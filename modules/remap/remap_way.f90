!> One Euler step's remap from the Lagrangian grid to the rezoned one
!> (Sect. 5.4): in one remap, or by the ways that keep it on the swept-face
!> path (`remap_euler`) where only the distance the nodes move, or a few
!> cells, keep it off: in parts of the way (&rezone swept_parts, the plan
!> `remap_parts`) or in two remaps (&rezone swept_hybrid: the cells that can
!> by swept faces first, then the rest by intersection). Each remap
!> conserves, so the step does. The driver decides the rezoned grid and
!> whether it is a lattice, and takes the material states afterwards
!> (`remap_after_state`) on the cells this lists.
module remap_way
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_sort, only: sort_order
  use base_share, only: share_t
  use mesh_grid, only: grid_t
  use mesh_boundary, only: bc_t
  use hydro_state, only: hydro_t
  use material_table, only: material_t
  use material_mixed, only: mixed_t
  use lagrange_centroids, only: centroid_stats_t, centroids_refresh, centroids_remember, plane_memory_t
  use remap_euler, only: remap_params_t, remap_stats_t, remap_euler_step, remap_swept_blockers, remap_stats_add, &
                         remap_hybrid_target, remap_part_target, remap_part_folded, remap_part_uniform, remap_work_t
  use remap_lattice, only: lattice_nodes
  use remap_after, only: remap_after_planes
  use remap_parts, only: remap_parts_t
  implicit none
  private
  public :: remap_way_t, parts_state_t, remap_way_step

  !> The deck's ways (&rezone) and what the step may take.
  type :: remap_way_t
    integer :: swept_parts = 1         !< the most parts of the way (&rezone swept_parts)
    logical :: swept_hybrid = .true.   !< two remaps where some cells cannot sweep (&rezone swept_hybrid)
    !> a global rezone: a part's grid is tested as a lattice (only such a
    !> rezone returns to a box grid)
    logical :: global = .false.
  end type remap_way_t

  !> Where an Euler step remapped in parts of the way stands: on when it
  !> does; the cells that kept the step off one remap by swept faces, the
  !> parts' plan (`remap_parts_t`: taken, left, split, the first part's
  !> fraction of the swept-face bound) and what the parts taken did. A
  !> decomposed run that remaps the parts on its windows hands the whole
  !> grid this when a part needs more than the windows hold, and the whole
  !> grid goes on from there as one process would.
  type :: parts_state_t
    logical :: on = .false.
    integer :: nblock = 0
    type(remap_parts_t) :: plan
    type(remap_stats_t) :: rs
  end type parts_state_t

contains

  !> Remaps g (its nodes at the Lagrangian positions g%x), with its state
  !> h, mx of the materials mats, to the rezoned nodes xnew: rs what the
  !> remaps did, written the cells whose states they wrote (each once).
  !> par: the remap's settings, its lattice flag for xnew set (a part's
  !> own is tested here). rows: only the node rows g%moved_rows flags can
  !> have moved (the others are at xnew). single: one remap, neither in
  !> parts nor hybrid (a decomposed run's second remap of a hybrid step,
  !> when it needs the whole grid); resume: a step in parts whose first
  !> parts the windows of a decomposed run took (the blocks hold their
  !> state), to go on from there; before: with single, what the windows
  !> remapped first, added to rs.
  subroutine remap_way_step(way, g, h, mx, mats, bc, share, xnew, par, work, centroids, rs, written, err, &
                            rows, single, resume, before)
    type(remap_way_t), intent(in) :: way
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    type(mixed_t), intent(inout) :: mx
    type(material_t), intent(inout) :: mats(:)
    type(bc_t), intent(in) :: bc
    !> the ranks that share the remap's work (`base_share`; absent: none)
    class(share_t), intent(in), optional :: share
    real(wp), intent(in) :: xnew(:, :)
    type(remap_params_t), intent(inout) :: par
    type(remap_work_t), intent(inout) :: work
    type(centroid_stats_t), intent(inout) :: centroids
    type(remap_stats_t), intent(out) :: rs
    integer, allocatable, intent(out) :: written(:)
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in) :: rows, single
    type(parts_state_t), intent(in), optional :: resume
    type(remap_stats_t), intent(in), optional :: before
    real(wp), allocatable :: xk(:, :), xpart(:, :), xh(:, :)
    type(remap_stats_t) :: rk
    type(plane_memory_t) :: memory
    integer, allocatable :: moved(:), cells(:), wrote(:), blockers(:), broke(:)
    type(remap_parts_t) :: pp
    integer :: nblock, nparts, nfar, stat
    real(wp) :: r
    logical :: split, arrived, hybrid, lattice, one, started, again

    if (rows) then
      nblock = remap_swept_blockers(g, h, bc, xnew, par%swept_max, par%swept_mixed, work=work, &
                                    parts=nparts, moved=moved, blockers=blockers, rows=g%moved_rows)
    else
      nblock = remap_swept_blockers(g, h, bc, xnew, par%swept_max, par%swept_mixed, work=work, &
                                    parts=nparts, moved=moved, blockers=blockers)
    end if
    par%swept = nblock == 0
    ! the way from the Lagrangian grid to the rezoned one in parts
    ! (&rezone swept_parts), each remapped in full (conservative), by swept
    ! faces where it can: where only the distance the nodes move keeps the
    ! step off them. The first part takes every node as far as the swept
    ! faces allow it in one go (`remap_part_target`), so most nodes arrive
    ! in it; the rest of the way goes in the equal parts that keep every
    ! cell still moving within swept_max, and those remap only the cells
    ! around the nodes that still have far to go. A part whose swept faces
    ! would break a material's bounds, or that they cannot take (a cell it
    ! tangles on the way), is taken again at half the distance (while the
    ! parts stay within swept_parts), and the last part the deck allows
    ! goes the rest of the way.
    one = single
    split = way%swept_parts > 1 .and. nblock > 0 .and. nparts >= 2 .and. &
            nparts <= way%swept_parts .and. .not. one
    if (present(resume)) then
      split = resume%on
      if (split) nblock = resume%nblock
    end if
    if (split) cells = moved
    ! a hybrid step (&rezone swept_hybrid): first the cells that can, by
    ! swept faces (every node but the blockers'), then the blockers and the
    ! cells around them by intersection (`remap_hybrid_target`); each remap
    ! conserves, so the step does
    hybrid = way%swept_hybrid .and. .not. (split .or. one) .and. nblock > 0 .and. nblock < size(moved)
    lattice = par%lattice
    if (hybrid) then
      call remap_hybrid_target(g, xnew, blockers, xk)
      nfar = remap_swept_blockers(g, h, bc, xk, par%swept_max, par%swept_mixed, work=work, moved=cells)
      hybrid = nfar == 0 .and. size(cells) > 0
    end if
    ! (the remaps taken, and a step in parts' plan: `remap_parts`)
    pp = remap_parts_t(nmax=way%swept_parts, hybrid=way%swept_hybrid)
    written = [integer ::]
    arrived = .true.
    started = .false.
    if (present(before)) then
      rs = before
      started = .true.
    end if
    ! (set when a rescue begins; allocated empty here, which also keeps GCC
    ! from taking their bounds for uninitialized)
    allocate(xpart(3, 0), xh(3, 0), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_way_step', error_no_memory('the parts'' grids'))
      return
    end if
    if (split .and. present(resume)) then
      ! (the windows' plan, without a rescue under way)
      pp = resume%plan
      pp%rescue = 0
      if (pp%ntaken > 0) rs = resume%rs
      started = pp%ntaken > 0
    end if
    do
      if (pp%rescue > 0) then
        ! a part some of whose cells cannot take it by swept faces (too
        ! far, or a broken bound) and no split left: first every node but
        ! those around these cells by swept faces, then those by
        ! intersection, as a hybrid step does (a first stage that cannot
        ! sweep, or breaks a bound again: the whole part by intersection)
        xk = xpart
        if (pp%rescue == 1) xk = xh
        if (way%global) par%lattice = lattice_nodes(g, xk)
        par%swept = remap_swept_blockers(g, h, bc, xk, par%swept_max, par%swept_mixed, work=work, &
                                         moved=moved) == 0
        if (pp%rescue_next(par%swept, size(moved))) cycle
        par%swept_only = pp%rescue == 1
      else if (hybrid) then
        if (pp%ntaken == 0) then
          par%swept = .true.
          par%lattice = .false.
          moved = cells
          arrived = .false.
        else
          xk = xnew
          par%lattice = lattice
          par%swept = remap_swept_blockers(g, h, bc, xk, par%swept_max, par%swept_mixed, work=work, &
                                           moved=moved) == 0
          arrived = .true.
        end if
      else if (split) then
        if (pp%first()) then
          call remap_part_target(g, xnew, pp%fac*par%swept_max, cells, xk, arrived, r, err)
          if (allocated(err)) return
          if (.not. arrived) then
            if (remap_part_folded(g, cells, xk)) call remap_part_uniform(g, xnew, cells, r, xk)
          end if
        else
          if (pp%nleft == 0) call parts_left()
          xk = xnew
          if (pp%nleft > 1) xk = g%x + (xnew - g%x)/real(pp%nleft, wp)
          arrived = pp%nleft == 1
        end if
        if (pp%last(arrived)) then
          xk = xnew
          arrived = .true.
        end if
        if (way%global) par%lattice = lattice_nodes(g, xk)
        par%swept = remap_swept_blockers(g, h, bc, xk, par%swept_max, par%swept_mixed, work=work, &
                                         moved=moved, blockers=broke) == 0
        ! (with no split left a part that breaks a bound is remapped around
        ! the cells that broke it, `rescue`)
        par%swept_only = pp%swept_only(par%swept)
        if (pp%wants_rescue(par%swept, arrived, size(broke), size(moved))) then
          ! a part some cells cannot sweep (their nodes go further than
          ! swept_max: the last part goes the rest of the way) and no split
          ! left: by swept faces but around those cells (`rescue`)
          xpart = xk
          call remap_hybrid_target(g, xk, broke, xh)
          pp%rescue = 1
          cycle
        end if
        if (pp%wants_split(par%swept, arrived)) then
          ! a part the swept faces cannot take though its nodes stay within
          ! swept_max (a cell it tangles on the way): shorter parts, the
          ! first one's nodes the same fraction of their way
          if (pp%nleft == 0) call parts_left()
          call pp%split()
          cycle
        end if
      end if
      ! the reference centroids the remap's MoF gets: those of the planes that
      ! cut the fractions the Lagrangian steps left (but for the cells the
      ! remap changes: it cuts their planes itself and replaces their
      ! centroids, `mof_cell`)
      call centroids_refresh(g, mx, centroids, skip=moved)
      ! (the planes the fits after the remap start from)
      call centroids_remember(mx, memory)
      if (split .or. hybrid) then
        call remap_euler_step(g, h, mx, size(mats), bc, xk, par, rk, err, share, moved=moved, &
                              written=wrote, work=work, broke=broke)
      else
        call remap_euler_step(g, h, mx, size(mats), bc, xnew, par, rk, err, share, moved=moved, &
                              written=wrote, work=work)
      end if
      ! (the cells whose states the parts wrote, for their EOS below)
      if (allocated(wrote)) written = [written, wrote]
      if (.not. allocated(err) .and. par%swept_only .and. rk%swept_unbounded > 0) then
        ! (nothing remapped: the first part again half as far, or the rest
        ! of the way in twice the parts; with no split left, the part around
        ! the cells that broke a bound, `rescue`)
        if (pp%unbounded()) then
          xpart = xk
          call remap_hybrid_target(g, xk, broke, xh)
        end if
        cycle
      end if
      if (.not. started) rs = rk
      if (started) call remap_stats_add(rs, rk)
      started = .true.
      again = pp%taken()
      rs%swept_blockers = nblock
      rs%swept_splits = pp%nsplit
      rs%swept_rescued = pp%nrescue
      rs%hybrid = hybrid
      ! the new mixed cells' centroids are the remapped material's: their
      ! interface planes, fitted to them, carry them to the next remap
      ! (wrote not allocated: not present, every cell listed again)
      if (.not. allocated(err)) call remap_after_planes(g, mats, h%mat, mx, par%mof_max_iter, memory, &
                                                        centroids, err, written=wrote)
      if (allocated(err)) return
      ! (a rescue's second stage)
      if (again) cycle
      if (.not. (split .or. hybrid) .or. arrived) exit
    end do
    ! (a cell two parts wrote is evaluated once: a material's work arrays
    ! hold its cells once)
    if (pp%ntaken > 1) call unique_cells(written, err)

  contains

    !> pp%nleft, the equal parts of the rest of the way to xnew that keep
    !> every moving cell within swept_max (at least 1).
    subroutine parts_left()
      nfar = remap_swept_blockers(g, h, bc, xnew, par%swept_max, par%swept_mixed, work=work, parts=pp%nleft)
      pp%nleft = max(pp%nleft, 1)
    end subroutine parts_left
  end subroutine remap_way_step

  !> (remap_way_step) The cells of list in increasing order, each once.
  subroutine unique_cells(list, err)
    integer, allocatable, intent(inout) :: list(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: order(:)
    integer :: i, n, stat
    allocate(order(size(list)), stat=stat)
    if (stat == 0) call sort_order(list, order, stat)
    if (stat /= 0) then
      call error_set(err, 'remap_way_step', error_no_memory('a cell list'))
      return
    end if
    list = list(order)
    n = min(size(list), 1)
    do i = 2, size(list)
      if (list(i) == list(n)) cycle
      n = n + 1
      list(n) = list(i)
    end do
    list = list(1:n)
  end subroutine unique_cells
end module remap_way
