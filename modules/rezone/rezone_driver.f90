!> The rezone package's driver: what the rezone keeps from one Euler step
!> to the next (the initial grid, the cells' standard side ratios, the last
!> look at the grid's shape, the triggers' bounds, the smoothers' node
!> mobility, the rezoned grid's array), when an Euler step is due (the
!> paper's triggers of Sect. 5.1, or an interval: `rezone_due`) and the
!> rezone of a grid at an Euler step, back to the
!> initial grid (`rezone_global`, moving faces followed) or by smoothing
!> the distorted subdomains or the whole grid (`rezone_lssm`, Sect. 5 of
!> the paper). It prints nothing: what it did comes back to the caller
!> (the time loop's Euler phase, `driver_euler`), which logs it.
module rezone_driver
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_share, only: share_t
  use mesh_grid, only: grid_t
  use mesh_halo, only: halo_t
  use mesh_boundary, only: bc_t
  use rezone_config, only: rezone_config_t
  use rezone_quality, only: grid_shape_worst, grid_standard_ratios
  use rezone_global, only: global_target, global_face_rule, GLOBAL_FACE_MOVE, global_surface_t
  use rezone_lssm, only: lssm_report_t, lssm_rezone, LSSM_SKIPPED
  use rezone_smooth, only: smooth_mobility_t
  implicit none
  private
  public :: rezone_state_t, rezone_state_init, rezone_standard_ratios, rezone_axis, rezone_shape, rezone_grid, &
            rezone_shape_known, &
            rezone_due, rezone_interval_due, rezone_rearm, rezone_worst_cells

  !> What the rezone keeps (allocated only with &rezone mode other than 'none').
  type :: rezone_state_t
    real(wp), allocatable :: x0(:, :)        !< initial grid, the global rezone's target
    !> each of the block's cells' side ratio on the initial grid
    !> (`standard_side_ratio`), against which the triggers measure its side
    !> ratio; not allocated when every cell there has equal sides
    real(wp), allocatable :: ratio0(:)
    !> whether x0 is a lattice (`lattice_nodes`): -1 not yet known
    integer :: x0_lattice = -1
    !> the rezoned grid's array, kept from one Euler step to the next (a
    !> fresh whole-grid array at every step costs its pages' first touch),
    !> and whether it holds x0 already (a global rezone without moving
    !> faces: the copy is then skipped)
    real(wp), allocatable :: xkeep(:, :)
    logical :: xkeep_x0 = .false.
    !> a decomposed run's global rezone with a moving face (`window_global_
    !> target`): the grid's faces (their initial nodes and line parameters,
    !> set at the first such Euler step) and the line parameters at the
    !> block's nodes (allocated then)
    type(global_surface_t) :: surface
    real(wp), allocatable :: xline(:, :)
    real(wp), allocatable :: quality(:)      !< work: cell quality for the triggers
    logical, allocatable :: fail(:)          !< work: cells failing the triggers' tests (LSSM, box reading)
    !> the last look at the grid's shape (`rezone_shape`) on this block: its
    !> largest side ratio and smallest cosine, and the whole grid's number
    !> of its first owned cell with each (for the log's note, `rezone_worst_cells`)
    real(wp) :: shape_mine(2) = 0.0_wp, shape_first(2) = 0.0_wp
    !> with LSSM's box reading, that look's side-ratio and angle tests of
    !> each owned cell against the deck's bounds, and the step and the
    !> stored cells (whole-grid numbers, first and last) of the grid they
    !> were taken on: the rezone of that step on that grid takes them
    !> rather than again (`lssm_rezone`)
    logical, allocatable :: shape_fail(:)
    integer :: shape_step = -1, shape_box(3, 2) = 0
    !> the last look's measures of each owned cell, (side ratio, cosine)
    !> in shape_keep(2, ncell), and the block's node positions then
    !> (shape_x): a cell none of whose nodes moved since is not measured
    !> again (the same numbers, so the same answers), so a look costs what
    !> the moving cells do (a blast's still air is most of the grid until
    !> its shock arrives)
    real(wp), allocatable :: shape_keep(:, :), shape_x(:, :)
    !> the smoothers' mobility of the nodes (`lssm_rezone`), kept for the
    !> grid whose stored cells (whole-grid numbers, first and last) are mob_box
    type(smooth_mobility_t) :: mob
    integer :: mob_box(3, 2) = 0
    !> the triggers (restart state): the next Euler step by interval_time;
    !> the bounds in force, the deck's side_ratio and cos_angle or, while
    !> cells an Euler step left beyond them are there, those cells' values
    !> moved on by &rezone hysteresis (`rezone_due`), and bound_n the Euler
    !> step they were set after
    real(wp) :: t_next = 0.0_wp
    real(wp) :: ratio_bound = 0.0_wp, cos_bound = 0.0_wp
    integer :: bound_n = 0
  end type rezone_state_t

contains

  !> Keeps the initial grid (the global rezone's target, the smoothers'
  !> standard grid) of the grid g the rezone works on, and its work arrays.
  subroutine rezone_state_init(g, rs, err)
    type(grid_t), intent(in) :: g
    type(rezone_state_t), intent(inout) :: rs
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    character(len=200) :: msg
    allocate(rs%x0, source=g%x, stat=stat, errmsg=msg)
    if (stat == 0) allocate(rs%quality(g%ncell), rs%fail(g%ncell), stat=stat, errmsg=msg)
    if (stat /= 0) call error_set(err, 'rezone_state_init', error_no_memory('the Euler phase''s arrays'))
  end subroutine rezone_state_init

  !> Whether an Euler step is due (due) after step `step`, at time t, with n
  !> Euler steps taken: an interval has passed (&rezone interval_steps,
  !> interval_time: rs%t_next), or the grid's largest side ratio or smallest
  !> cosine of the inclined angle has reached its bound (then by_shape;
  !> `rezone_shape` on g's owned cells, or with shape, a decomposed run's
  !> measures of all blocks, g not read).
  subroutine rezone_due(rz, rs, g, step, t, n, due, by_shape, shape)
    type(rezone_config_t), intent(in) :: rz
    type(rezone_state_t), intent(inout) :: rs
    type(grid_t), intent(in) :: g
    integer, intent(in) :: step, n
    real(wp), intent(in) :: t
    logical, intent(out) :: due, by_shape
    real(wp), intent(in), optional :: shape(2)
    real(wp) :: ratio_max, cos_min
    by_shape = .false.
    due = rezone_interval_due(rz, rs, step, t)
    if (due .or. (rz%side_ratio <= 0.0_wp .and. rz%cos_angle <= 0.0_wp)) return
    if (present(shape)) then
      ratio_max = shape(1)
      cos_min = shape(2)
    else
      call rezone_shape(rz, g, step, rs)
      ratio_max = rs%shape_mine(1)
      cos_min = rs%shape_mine(2)
    end if
    call trigger_bounds(rz, rs, n, ratio_max, cos_min)
    due = (rz%side_ratio > 0.0_wp .and. ratio_max >= rs%ratio_bound) .or. &
          (rz%cos_angle > 0.0_wp .and. cos_min <= rs%cos_bound)
    by_shape = due
  end subroutine rezone_due

  !> Whether an interval has made an Euler step due after step `step`, at
  !> time t (&rezone interval_steps, interval_time: rs%t_next). Then
  !> `rezone_due` takes no look at the grid's shape, and a decomposed run
  !> must not either: the look keeps the cells' shape tests for the
  !> smoothing (`rezone_shape`), which would then take them from before the
  !> snaps where one process takes them after.
  pure logical function rezone_interval_due(rz, rs, step, t) result(due)
    type(rezone_config_t), intent(in) :: rz
    type(rezone_state_t), intent(in) :: rs
    integer, intent(in) :: step
    real(wp), intent(in) :: t
    due = .false.
    if (rz%interval_steps > 0) due = mod(step, rz%interval_steps) == 0
    if (rz%interval_time > 0.0_wp) due = due .or. t >= rs%t_next*(1.0_wp - 1.0e-12_wp)
  end function rezone_interval_due

  !> The triggers' bounds after the step just taken (n Euler steps so far),
  !> whose grid's largest side ratio and smallest cosine are ratio_max and
  !> cos_min. At the first look after an Euler step, a measure the step left
  !> beyond the deck's bound (cells a smoothing could not bring to the
  !> target) becomes the bound, moved on by &rezone hysteresis (a relative
  !> margin): those cells alone do not make the next step due at once, as
  !> they did step after step (the paper's Sedov with LSSM took 113 Euler
  !> steps at 20^3, runs of consecutive ones, against 16 with whole-grid
  !> smoothing); the grid getting worse by the margin does, and the cells
  !> remain distorted cells for the smoothing of the next step. The bounds
  !> never move beyond three margins from the deck's (else a run whose every
  !> Euler step left its cells a little worse would ratchet them away: the
  !> paper's Sedov reached a cosine of 0.33). Once the grid is back within a
  !> deck's bound, that bound is in force again.
  subroutine trigger_bounds(rz, rs, n, ratio_max, cos_min)
    type(rezone_config_t), intent(in) :: rz
    type(rezone_state_t), intent(inout) :: rs
    integer, intent(in) :: n
    real(wp), intent(in) :: ratio_max, cos_min
    if (rs%bound_n /= n) then
      rs%bound_n = n
      rs%ratio_bound = rz%side_ratio
      rs%cos_bound = rz%cos_angle
      if (ratio_max >= rz%side_ratio) &
        rs%ratio_bound = min(ratio_max*(1.0_wp + rz%hysteresis), rz%side_ratio*(1.0_wp + 3.0_wp*rz%hysteresis))
      if (cos_min <= rz%cos_angle) &
        rs%cos_bound = max(cos_min*(1.0_wp - rz%hysteresis), rz%cos_angle*(1.0_wp - 3.0_wp*rz%hysteresis))
    end if
    if (ratio_max < rz%side_ratio) rs%ratio_bound = rz%side_ratio
    if (cos_min > rz%cos_angle) rs%cos_bound = rz%cos_angle
  end subroutine trigger_bounds

  !> The next Euler step by interval_time after an Euler step at time t:
  !> past it by whole intervals.
  subroutine rezone_rearm(rz, rs, t)
    type(rezone_config_t), intent(in) :: rz
    type(rezone_state_t), intent(inout) :: rs
    real(wp), intent(in) :: t
    if (.not. rz%interval_time > 0.0_wp) return
    do while (rs%t_next <= t*(1.0_wp + 1.0e-12_wp))
      rs%t_next = rs%t_next + rz%interval_time
    end do
  end subroutine rezone_rearm

  !> Where the grid is worst, for the log's note of a step due by its
  !> shape: the cell (whole-grid indices) of the largest side ratio and of
  !> the smallest cosine, ijk(:, 1) and ijk(:, 2), with the whole grid's
  !> worst values shape: the first in the whole grid's cell order (each
  !> block finds its first owned cell with the worst value in the look that
  !> made the step due, `rezone_shape`; the least cell number of all blocks,
  !> by halo, is the one of one process).
  function rezone_worst_cells(g, halo, rs, shape) result(ijk)
    type(grid_t), intent(in) :: g
    class(halo_t), intent(in) :: halo
    type(rezone_state_t), intent(in) :: rs
    real(wp), intent(in) :: shape(2)
    integer :: ijk(3, 2)
    real(wp) :: first(2), none(0)
    integer :: m, gc
    first = huge(1.0_wp)
    if (rs%shape_mine(1) >= shape(1)) first(1) = rs%shape_first(1)
    if (rs%shape_mine(2) <= shape(2)) first(2) = rs%shape_first(2)
    do m = 1, 2
      call halo%choose(first(m), none)
      gc = nint(min(first(m), 1.0e9_wp)) - 1
      ijk(:, m) = [mod(gc, g%gn(1)), mod(gc/g%gn(1), g%gn(2)), gc/(g%gn(1)*g%gn(2))] + 1
    end do
  end function rezone_worst_cells

  !> rs%ratio0 from the block g's nodes as the deck set them (called before
  !> a restart is read, so a restarted run measures against the same grid).
  subroutine rezone_standard_ratios(g, rs, err)
    type(grid_t), intent(in) :: g
    type(rezone_state_t), intent(inout) :: rs
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    allocate(rs%ratio0(g%ncell), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'rezone_standard_ratios', error_no_memory('the standard side ratios'))
      return
    end if
    call grid_standard_ratios(g, rs%ratio0)
    ! (standard_side_ratio gives exactly 1 for a cell of equal sides)
    if (.not. any(rs%ratio0 > 1.0_wp)) deallocate(rs%ratio0)
  end subroutine rezone_standard_ratios

  !> Whether the triggers measure the inclined angle against the axes (LSSM's
  !> box reading).
  logical function rezone_axis(rz)
    type(rezone_config_t), intent(in) :: rz
    rezone_axis = trim(rz%mode) == 'lssm' .and. trim(rz%smooth_target) == 'box'
  end function rezone_axis

  !> The largest side ratio and smallest inclined-angle cosine over the
  !> cells a block owns in rs%shape_mine, and the whole grid's number of the
  !> first owned cell with each in rs%shape_first (`grid_shape_worst`; the
  !> log's note of where the grid is worst: `rezone_worst_cells`).
  subroutine rezone_shape(rz, g, step, rs)
    type(rezone_config_t), intent(in) :: rz
    type(grid_t), intent(in) :: g
    integer, intent(in) :: step
    type(rezone_state_t), intent(inout) :: rs
    logical, allocatable :: moved(:)
    integer :: stat, n
    rs%shape_step = -1
    ! the nodes moved since the last look (all at the first, or on a grid
    ! of another size), and their places now
    stat = 0
    if (allocated(rs%shape_x)) then
      if (size(rs%shape_x, 2) /= g%nnode .or. size(rs%shape_keep, 2) /= g%ncell) deallocate(rs%shape_x, rs%shape_keep)
    end if
    allocate(moved(g%nnode), stat=stat)
    if (stat == 0 .and. .not. allocated(rs%shape_x)) then
      allocate(rs%shape_x(3, g%nnode), rs%shape_keep(2, g%ncell), stat=stat)
      if (stat == 0) rs%shape_x = huge(1.0_wp)
    end if
    if (stat /= 0) then
      ! (no memory for the last look: every cell is measured)
      if (allocated(rs%shape_x)) deallocate(rs%shape_x, rs%shape_keep)
      if (.not. allocated(moved)) allocate(moved(0), stat=stat)
    else
      !$omp parallel do default(none) shared(g, rs, moved) private(n) schedule(static)
      do n = 1, g%nnode
        moved(n) = any(.not. abs(g%x(:, n) - rs%shape_x(:, n)) <= 0.0_wp)
        if (moved(n)) rs%shape_x(:, n) = g%x(:, n)
      end do
      !$omp end parallel do
    end if
    if (rezone_axis(rz)) then
      if (allocated(rs%shape_fail)) then
        if (size(rs%shape_fail) /= g%ncell) deallocate(rs%shape_fail)
      end if
      stat = 0
      if (.not. allocated(rs%shape_fail)) allocate(rs%shape_fail(g%ncell), stat=stat)
      if (stat == 0) then
        call look([rz%side_ratio, rz%cos_angle])
        rs%shape_step = step
        rs%shape_box = reshape([g%off + g%slo, g%off + g%shi], [3, 2])
        return
      end if
    end if
    call look()

  contains

    !> grid_shape_worst with what is set of ratio0, the kept look and (with
    !> bounds) the fail flags (an array not allocated is an argument not
    !> present).
    subroutine look(bounds)
      real(wp), intent(in), optional :: bounds(2)
      call grid_shape_worst(g, rezone_axis(rz), rs%shape_mine, rs%shape_first, bounds, rs%shape_fail, rs%ratio0, &
                            rs%shape_keep, moved)
    end subroutine look
  end subroutine rezone_shape

  !> Whether rs%shape_fail holds the shape tests of grid g at step.
  logical function rezone_shape_known(g, step, rs)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: step
    type(rezone_state_t), intent(in) :: rs
    rezone_shape_known = rs%shape_step == step .and. all(rs%shape_box(:, 1) == g%off + g%slo) .and. &
                  all(rs%shape_box(:, 2) == g%off + g%shi)
    if (rezone_shape_known) rezone_shape_known = size(rs%shape_fail) == g%ncell
  end function rezone_shape_known

  !> The rezone of an Euler step at step: the new node positions xnew of
  !> the grid g (one process's, a block with its halo (the smoothing only:
  !> its ghosts and global reductions), or the whole grid's node positions
  !> on every rank (share: the ranks that share its quality measures)).
  !> occupied: g's cells that particles occupy in the standard grid. With
  !> &rezone mode 'lssm' or 'smooth' rep says what the smoothing did
  !> (`lssm_rezone`) and done is false if no cell needed it; with 'global'
  !> nmove counts the nodes of moving faces kept where they are. done is
  !> false on an error too. With a face that moves with the material (a
  !> piston, a free surface) the smoothing's standard places (`lssm_rezone`'s
  !> standard, where its snaps go) are the global rezone's target, the
  !> initial grid carried with the moving faces (`global_target`): its nodes
  !> on those faces are where they are, and the initial places of the
  !> others may lie beyond them. On a block of a decomposed run the caller
  !> gives it (standard: the block's stored nodes, `global_block_target`);
  !> on the whole grid it is made here.
  subroutine rezone_grid(rz, g, bc, share, halo, step, rs, xnew, rep, nmove, done, err, occupied, standard)
    type(rezone_config_t), intent(in) :: rz
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    class(share_t), intent(in), optional :: share
    class(halo_t), intent(inout) :: halo
    integer, intent(in) :: step
    type(rezone_state_t), intent(inout) :: rs
    real(wp), allocatable, intent(out) :: xnew(:, :)
    type(lssm_report_t), intent(out) :: rep
    integer, intent(out) :: nmove
    logical, intent(out) :: done
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: occupied(:)
    real(wp), intent(in), optional :: standard(:, :)
    real(wp), allocatable :: xt(:, :)
    integer :: f, stat, rules(6), nkept
    character(len=200) :: msg

    done = .true.
    nmove = 0
    if (allocated(rs%xkeep)) then
      if (all(shape(rs%xkeep) == shape(g%x))) call move_alloc(rs%xkeep, xnew)
    end if
    rules = [(global_face_rule(bc%kind(f)), f = 1, 6)]
    if (trim(rz%mode) == 'lssm' .or. trim(rz%mode) == 'smooth') then
      rs%xkeep_x0 = .false.
      xnew = g%x
      if (any(rs%mob_box /= reshape([g%off + g%slo, g%off + g%shi], [3, 2]))) then
        rs%mob = smooth_mobility_t()
        rs%mob_box = reshape([g%off + g%slo, g%off + g%shi], [3, 2])
      end if
      if (all(rules /= GLOBAL_FACE_MOVE)) then
        call smooth_from()
      else if (present(standard)) then
        call smooth_from(standard)
      else if (all(g%slo == 1) .and. all(g%shi == g%gn)) then
        allocate(xt, mold=rs%x0, stat=stat, errmsg=msg)
        if (stat /= 0) then
          call error_set(err, 'rezone_grid', error_no_memory('the standard grid'))
        else
          call global_target(g%ni, g%nj, g%nk, rules, rs%x0, g%x, xt, nkept, err)
        end if
        if (.not. allocated(err)) call smooth_from(xt)
      else
        call error_set(err, 'rezone_grid', 'a block''s smoothing with moving faces needs its standard grid')
      end if
      done = rep%outcome /= LSSM_SKIPPED
    else
      ! back to the initial grid, except where a face moves with the
      ! material (a piston, a free surface): there the grid follows it
      stat = 0
      if (.not. allocated(xnew)) then
        rs%xkeep_x0 = .false.
        allocate(xnew, mold=rs%x0, stat=stat, errmsg=msg)
      end if
      if (stat /= 0) then
        call error_set(err, 'rezone_grid', error_no_memory('the rezoned grid'))
      else if (.not. (rs%xkeep_x0 .and. all(rules /= GLOBAL_FACE_MOVE))) then
        call global_target(g%ni, g%nj, g%nk, rules, rs%x0, g%x, xnew, nmove, err)
        rs%xkeep_x0 = all(rules /= GLOBAL_FACE_MOVE)
      end if
    end if
    if (allocated(err)) done = .false.

  contains

    !> `lssm_rezone` of xnew, its snaps towards standard (else x0).
    subroutine smooth_from(standard)
      real(wp), intent(in), optional :: standard(:, :)
      if (rezone_shape_known(g, step, rs)) then
        call lssm_rezone(rz, g, bc, share, halo, rs%x0, rs%quality, rs%fail, xnew, rep, err, occupied, rs%shape_fail, &
                         rs%mob, standard)
        ! (once: the grid moves on)
        rs%shape_step = -1
      else
        call lssm_rezone(rz, g, bc, share, halo, rs%x0, rs%quality, rs%fail, xnew, rep, err, occupied, mob_keep=rs%mob, &
                         standard=standard)
      end if
    end subroutine smooth_from
  end subroutine rezone_grid
end module rezone_driver
