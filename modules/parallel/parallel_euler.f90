!> The Euler phase of a decomposed run balanced over the ranks where its
!> work concentrates: near a corner charge most of the cells a smoothing
!> rezone moves, and so most of the remap, lie in one rank's block while
!> the others wait. Two parts: LSSM's smoothing on blocks cut for its work
!> (`rezone_balanced`), and the remap's work per plane of cells
!> (`remap_work`), from which the driver builds the windows around blocks
!> cut for it (`window_balance` in `driver_whole`). Neither changes an
!> answer: the smoothing and the remap compute each cell as one process
!> does, whatever the blocks.
!>
!> LSSM (&rezone mode 'lssm', the box reading) smooths only the distorted
!> subdomains (Sect. 5.2). When the last Euler step smoothed many cells (at
!> least balance_planes times a cut plane's cells: a thinner region split
!> by a cut costs its ghost layers twice, and the gather more than the
!> split saves), the block's node positions are gathered onto blocks of the
!> same layout of the ranks whose cuts balance an estimate of the rezone's
!> work, `rezone_grid` runs there, and each block takes its rezoned nodes
!> back. The smoothing's answer depends on no decomposition (`lssm_rezone`:
!> the subdomains are the whole grid's, the ghosts refreshed after every
!> pass).
!>
!> The estimate, per plane of cells normal to each direction the layout
!> cuts: one per cell (the rezone's sweeps of the block: snaps, trigger
!> tests, subdomain sets) and, for each cell the step's look at the grid
!> found failing the triggers' tests (`rezone_shape`), rezone_weight for
!> each cell of the box its subdomain spans (half side d_max/2,
!> `rezone_subdomains`; overlapping boxes counted each) in each plane the
!> box reaches. Without that look (an Euler step an interval made due, the
!> cube reading) there is no estimate, and the rezone runs on the blocks.
module parallel_euler
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set, error_no_memory
  use mesh_grid, only: grid_t, grid_index_t
  use mesh_boundary, only: bc_t, bc_init
  use mesh_halo, only: halo_t
  use rezone_config, only: rezone_config_t
  use rezone_driver, only: rezone_state_t, rezone_grid, rezone_shape_known
  use rezone_lssm, only: lssm_report_t
  use rezone_subdomains, only: rezone_subdomains_default_dmax
  use parallel_comm, only: comm_t, parallel_balance, parallel_block, parallel_sum, parallel_max, parallel_nomem
  use parallel_gather, only: gather_box, gather_concat
  use parallel_halo, only: mpi_halo_t, mpi_halo_init
  implicit none
  private
  public :: rezone_balance_t, rezone_balanced, remap_work, cut_plane_cells, balance_planes, active_window

  !> The rezone's cost of a cell of a distorted cell's box against a cell of
  !> the block. Measured on one process (Sedov 40^3 LSSM, 17 Euler steps):
  !> 7 ms a step for the sweeps of 64,000 cells (0.11 us a cell) plus 22 us
  !> for each smoothed cell, whose region a distorted cell seeds with about
  !> 15 of them (its box: 125 cells), so about 24 a box cell; the Comp B
  !> cylinder at 40 x 40 x 48 on 2 ranks smooths as fast with 10, 36 or 100.
  real(wp), parameter :: rezone_weight = 36.0_wp
  !> The smoothed cells of the last Euler step, in cut planes' cells, from
  !> which its blocks are cut for the work (and the cells whose nodes a
  !> rezone moved, from which the windows are: `window_balance`): measured
  !> on 2 ranks, Sedov 40^3 (at most 1,610 smoothed cells, one cut plane
  !> 1,600) smooths 40 % slower on such blocks, the Comp B cylinder at 40 x
  !> 40 x 48 (10,000 to 17,000 of 77,000 cells) 20 % faster.
  real(wp), parameter :: balance_planes = 4.0_wp

  !> A block cut for the rezone's work, kept from one Euler step to the next
  !> while its cuts serve: its grid (the standard grid's nodes after
  !> `bc_init`, then the step's), boundary lists, and rezone state (the
  !> standard grid, work arrays, the smoothers' mobility).
  type :: rezone_balance_t
    integer, allocatable :: cuts(:)   !< as comm_t%cuts; unallocated: none built
    type(grid_t) :: g
    type(bc_t) :: bc
    type(rezone_state_t) :: rs
    logical :: taken = .false.        !< the last rezone ran on them
    integer :: smoothed = 0           !< cells the last rezone smoothed (the whole grid's)
  end type rezone_balance_t

contains

  !> `rezone_grid` of a decomposed run's block g (its halo, rezone state rs,
  !> occupied cells and standard places as `rezone_grid` takes them), on
  !> blocks cut for the smoothing's work when their cuts are not g's
  !> (collective): xnew, rep, nmove and done as `rezone_grid` gives them on
  !> g. bal keeps the balanced blocks between calls.
  subroutine rezone_balanced(pc, rz, g, bc, halo, step, rs, bal, xnew, rep, nmove, done, err, occupied, standard)
    type(comm_t), intent(in) :: pc
    type(rezone_config_t), intent(in) :: rz
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    class(halo_t), intent(inout) :: halo
    integer, intent(in) :: step
    type(rezone_state_t), intent(inout) :: rs
    type(rezone_balance_t), intent(inout) :: bal
    real(wp), allocatable, intent(out) :: xnew(:, :)
    type(lssm_report_t), intent(out) :: rep
    integer, intent(out) :: nmove
    logical, intent(out) :: done
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: occupied(:)
    real(wp), intent(in), optional :: standard(:, :)
    type(mpi_halo_t) :: mh
    real(wp), allocatable :: xr(:, :), cells(:, :), got(:, :), xs(:, :)
    logical, allocatable :: occ(:)
    integer, allocatable :: cuts(:)
    integer :: lo(3), hi(3), flag(1), stat

    call balanced_cuts(pc, rz, g, step, rs, bal, cuts)
    bal%taken = .false.
    if (all(cuts == pc%cuts)) then
      call rezone_grid(rz, g, bc, halo=halo, step=step, rs=rs, xnew=xnew, rep=rep, nmove=nmove, done=done, err=err, &
                       occupied=occupied, standard=standard)
      bal%smoothed = rep%smoothed
      return
    end if
    ! (the look's tests are taken here: `rezone_grid` takes them once)
    rs%shape_step = -1
    if (.not. allocated(bal%cuts)) then
      call balance_build(pc, g, bc, rs, cuts, bal, err)
    else if (any(cuts /= bal%cuts)) then
      call balance_build(pc, g, bc, rs, cuts, bal, err)
    end if
    flag(1) = merge(1, 0, allocated(err))
    call parallel_max(pc, flag)
    done = .false.
    nmove = 0
    if (flag(1) > 0) return
    bal%taken = .true.
    associate (b => bal%g)
      lo = b%off + b%slo
      hi = b%off + b%shi
      ! the block's nodes now, the cells particles occupy, the standard
      ! places, and the look's tests of the triggers (which the rezone would
      ! take again: every cell's side ratio and angles, as costly as the
      ! smoothing); an array left unallocated is an argument not present
      call gather_box(pc, g%grid_index_t, g%x, lo, hi, xr, .true.)
      call move_alloc(xr, b%x)
      allocate(cells(1, g%ncell), stat=stat)
      call parallel_nomem(stat, 'the balanced rezone''s gathers')
      if (present(occupied)) then
        cells(1, :) = merge(1.0_wp, 0.0_wp, occupied)
        call gather_box(pc, g%grid_index_t, cells, lo, hi, got, .false.)
        occ = got(1, :) > 0.5_wp
      end if
      if (present(standard)) call gather_box(pc, g%grid_index_t, standard, lo, hi, xs, .true.)
      cells(1, :) = merge(1.0_wp, 0.0_wp, rs%shape_fail)
      call gather_box(pc, g%grid_index_t, cells, lo, hi, got, .false.)
      bal%rs%shape_fail = got(1, :) > 0.5_wp
      bal%rs%shape_step = step
      bal%rs%shape_box = reshape([lo, hi], [3, 2])
      call mpi_halo_init(mh, pc, b%grid_index_t)
      call rezone_grid(rz, b, bal%bc, halo=mh, step=step, rs=bal%rs, xnew=xr, rep=rep, nmove=nmove, done=done, &
                       err=err, occupied=occ, standard=xs)
      flag(1) = merge(1, 0, allocated(err) .or. .not. done)
      call parallel_max(pc, flag)
      done = flag(1) == 0
      if (.not. done) return
      bal%smoothed = rep%smoothed
      ! (each block's stored nodes from the balanced blocks that own them)
      call gather_box(pc, b%grid_index_t, xr, g%off + g%slo, g%off + g%shi, xnew, .true.)
    end associate
  end subroutine rezone_balanced

  !> The cells of the largest plane of a grid of gn cells normal to a
  !> direction pc's layout cuts.
  pure real(wp) function cut_plane_cells(pc, gn) result(plane)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: gn(3)
    integer :: d
    plane = 0.0_wp
    do d = 1, 3
      if (pc%dims(d) > 1) plane = max(plane, product(real(gn, wp))/real(gn(d), wp))
    end do
  end function cut_plane_cells

  !> The remap's work of each plane of g's cells normal to i, then j, then
  !> k (w(gn(1) + gn(2) + gn(3)), summed over the ranks), its rezone having
  !> moved the block's nodes to xb: one per cell (the windows' copies) and
  !> moved_weight more per cell with a moved node (its remap and the MoF
  !> fits of its interfaces); moved: those cells, the whole grid's; box:
  !> the block's.
  subroutine remap_work(pc, g, xb, moved_weight, w, moved, box)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: xb(:, :), moved_weight
    real(wp), allocatable, intent(out) :: w(:)
    integer, intent(out) :: moved
    !> the box of the block's owned cells with a moved node (whole-grid
    !> indices, lo then hi; lo > hi: none)
    integer, intent(out) :: box(3, 2)
    logical, allocatable :: mv(:)
    integer :: i, j, k, d, w0, n0, a, ig(3), stat, nm(1)
    logical :: changed
    allocate(mv(g%nnode), w(sum(g%gn)), stat=stat)
    call parallel_nomem(stat, 'the remap''s work estimate')
    mv = any(abs(xb - g%x) > 0.0_wp, dim=1)
    w = 0.0_wp
    nm = 0
    box(:, 1) = huge(1)
    box(:, 2) = -huge(1)
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          n0 = g%cell_node0(i, j, k)
          changed = .false.
          do a = 1, 8
            changed = changed .or. mv(n0 + g%corner_offset(a))
          end do
          ig = [i, j, k] + g%off
          if (changed) then
            nm = nm + 1
            box(:, 1) = min(box(:, 1), ig)
            box(:, 2) = max(box(:, 2), ig)
          end if
          w0 = 0
          do d = 1, 3
            w(w0 + ig(d)) = w(w0 + ig(d)) + 1.0_wp + merge(moved_weight, 0.0_wp, changed)
            w0 = w0 + g%gn(d)
          end do
        end do
      end do
    end do
    call parallel_sum(pc, nm)
    call parallel_sum(pc, w)
    moved = nm(1)
  end subroutine remap_work

  !> The cuts of pc's layout that balance the rezone's estimated work (the
  !> module's notes; the same on every rank), or pc%cuts without an
  !> estimate or after a step that smoothed few cells. The cuts bal holds
  !> serve while their most loaded slab of each direction has at most 5 %
  !> more work than the new cuts'.
  subroutine balanced_cuts(pc, rz, g, step, rs, bal, cuts)
    type(comm_t), intent(in) :: pc
    type(rezone_config_t), intent(in) :: rz
    type(grid_t), intent(in) :: g
    integer, intent(in) :: step
    type(rezone_state_t), intent(in) :: rs
    type(rezone_balance_t), intent(in) :: bal
    integer, allocatable, intent(out) :: cuts(:)
    real(wp), allocatable :: w(:)
    real(wp) :: d_max, span
    integer :: d, i, j, k, c, ig(3), w0, half, p, stat, known(1)

    cuts = pc%cuts
    if (real(bal%smoothed, wp) < balance_planes*cut_plane_cells(pc, g%gn)) return
    known(1) = 0
    if (trim(rz%mode) == 'lssm' .and. trim(rz%smooth_target) == 'box' .and. rezone_shape_known(g, step, rs)) known = 1
    call parallel_sum(pc, known)
    if (known(1) < pc%nranks) return
    allocate(w(sum(g%gn)), stat=stat)
    call parallel_nomem(stat, 'the rezone''s work estimate')
    w = 0.0_wp
    d_max = rz%d_max
    if (.not. d_max > 0.0_wp) d_max = rezone_subdomains_default_dmax(g%gn(1), g%gn(2), g%gn(3))
    half = int(0.5_wp*d_max)
    span = real(2*half + 1, wp)**2
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          c = g%cell(i, j, k)
          ig = [i, j, k] + g%off
          w0 = 0
          do d = 1, 3
            w(w0 + ig(d)) = w(w0 + ig(d)) + 1.0_wp
            if (rs%shape_fail(c)) then
              do p = max(ig(d) - half, 1), min(ig(d) + half, g%gn(d))
                w(w0 + p) = w(w0 + p) + rezone_weight*span
              end do
            end if
            w0 = w0 + g%gn(d)
          end do
        end do
      end do
    end do
    call parallel_sum(pc, w)
    cuts = parallel_balance(pc, g%gn, max(g%ng, 1), w, bal%cuts, 0.05_wp)
  end subroutine balanced_cuts

  !> bal's block for the cuts (collective): its index (g's ghost layers),
  !> its standard grid gathered from the blocks' (rs%x0), its boundary lists
  !> from that grid (as the deck's grid made g's, `bc_init`), its rezone
  !> state's work arrays.
  subroutine balance_build(pc, g, bc, rs, cuts, bal, err)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    type(rezone_state_t), intent(in) :: rs
    integer, intent(in) :: cuts(:)
    type(rezone_balance_t), intent(inout) :: bal
    type(error_t), allocatable, intent(inout) :: err
    type(grid_index_t) :: ix
    integer :: stat, smoothed

    smoothed = bal%smoothed
    bal = rezone_balance_t()
    bal%smoothed = smoothed
    ix = parallel_block(pc, g%gn, g%ng, cuts)
    bal%g%grid_index_t = ix
    bal%g%xmin = g%xmin
    bal%g%xmax = g%xmax
    call gather_box(pc, g%grid_index_t, rs%x0, ix%off + ix%slo, ix%off + ix%shi, bal%rs%x0, .true.)
    bal%g%x = bal%rs%x0
    ! (the deck's settings of the faces; the lists are the block's)
    bal%bc%kind = bc%kind
    bal%bc%velocity = bc%velocity
    bal%bc%pressure = bc%pressure
    bal%bc%inflow_mat = bc%inflow_mat
    bal%bc%inflow_rho = bc%inflow_rho
    bal%bc%inflow_e = bc%inflow_e
    bal%bc%nfixed = bc%nfixed
    bal%bc%fixed_box = bc%fixed_box
    call bc_init(bal%bc, bal%g, err)
    if (allocated(err)) return
    allocate(bal%rs%quality(ix%ncell), bal%rs%fail(ix%ncell), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'rezone_balanced', error_no_memory('the balanced blocks'' rezone arrays'))
      return
    end if
    bal%cuts = cuts
  end subroutine balance_build
  !> The part of a window around the block b (cells lo to hi, whole-grid
  !> indices, within full: the window the block's cells need) that an
  !> Euler step's remap needs when it changes few cells (collective), and
  !> back, the block's stored cells it takes back from it. moved: each
  !> block's box of owned cells with a moved node (`remap_work`; gathered
  !> here); mixed: the block's mixed cells (its cells). The remap changes
  !> only the cells with a moved node and the cells within rings cells of
  !> them that give to their kinetic energy deficits (`remap_euler`'s
  !> deficit_rings); back holds those of the block's stored cells, and its
  !> mixed cells (whose interface planes every remap fits again:
  !> `remap_after_planes`), so the block's cells outside it keep their
  !> values; lo to hi holds back widened by margin, the cells a remap reads
  !> to compute them. Where the
  !> step changes none of the block's cells, back is its first owned cell
  !> (at a corner: the window about it is the smallest).
  subroutine active_window(pc, b, moved, mixed, rings, margin, full, lo, hi, back)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: b
    integer, intent(in) :: moved(3, 2), mixed(:), rings, margin, full(3, 2)
    integer, intent(out) :: lo(3), hi(3), back(3, 2)
    integer, allocatable :: every(:)
    integer :: stored(3, 2), r, k, ijk(3), q(3, 2)
    stored(:, 1) = b%slo + b%off
    stored(:, 2) = b%shi + b%off
    back(:, 1) = huge(1)
    back(:, 2) = -huge(1)
    call gather_concat(pc, reshape(moved, [6]), every)
    do r = 0, size(every)/6 - 1
      q = reshape(every(6*r + 1:6*r + 6), [3, 2])
      if (any(q(:, 1) > q(:, 2))) cycle
      q(:, 1) = max(q(:, 1) - rings, stored(:, 1))
      q(:, 2) = min(q(:, 2) + rings, stored(:, 2))
      if (any(q(:, 1) > q(:, 2))) cycle
      back(:, 1) = min(back(:, 1), q(:, 1))
      back(:, 2) = max(back(:, 2), q(:, 2))
    end do
    do k = 1, size(mixed)
      call b%cell_ijk(mixed(k), ijk(1), ijk(2), ijk(3))
      back(:, 1) = min(back(:, 1), ijk + b%off)
      back(:, 2) = max(back(:, 2), ijk + b%off)
    end do
    if (any(back(:, 1) > back(:, 2))) then
      back(:, 1) = b%clo + b%off
      back(:, 2) = back(:, 1)
    end if
    lo = max(back(:, 1) - margin, full(:, 1))
    hi = min(back(:, 2) + margin, full(:, 2))
  end subroutine active_window
end module parallel_euler
