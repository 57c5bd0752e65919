!> One Lagrangian step: predictor-corrector (Eqs. 20-22) with the compatible
!> energy update (Eq. 19).
!>
!> Predictor: corner forces F^n from (x^n, u^n, p^n); u* = u^n + dt F^n/m;
!> u*^{1/2} = (u^n + u*)/2; x^{1/2} = x^n + dt/2 u*^{1/2};
!> e^{1/2} = e^n - dt/(2 m_c) sum_a F^n_a . u*^{1/2}_a; p^{1/2} from the EOS.
!> Corrector: F^{1/2} from (x^{1/2}, u*^{1/2}, p^{1/2});
!> u^{n+1} = u^n + dt F^{1/2}/m (Eq. 20), u^{n+1/2} = (u^n + u^{n+1})/2 (Eq. 21),
!> x^{n+1} = x^n + dt u^{n+1/2} (Eq. 22), e^{n+1} = e^n - dt/m_c sum_a F^{1/2}_a . u^{n+1/2}_a.
!> Because the same corner forces move the nodes and heat the cells, kinetic
!> plus internal energy is conserved to round-off (less the boundary work).
module lagrange_integrator
  use, intrinsic :: iso_fortran_env, only: int8
  use base_kinds, only: wp
  use mesh_grid, only: grid_t, nodes_moved
  use mesh_halo, only: halo_t
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use mesh_geometry, only: hex_volume, hex_volume_gradient, hex_median_areas
  use mesh_boundary, only: bc_t, bc_pressure_forces, bc_apply
  use material_table, only: material_t, material_eval_eos, material_burn_at
  use material_mixed, only: mixed_t, mixed_save_step_start, mixed_split, mixed_cell_state, mixed_volume_gain
  use hydro_state, only: hydro_t, hydro_params_t
  use lagrange_forces, only: lagrange_strain_rates, lagrange_corner_forces, lagrange_cell_rates, lagrange_area_sizes, &
                             lagrange_node_flags, lagrange_cell_flags
  use lagrange_nodal, only: nodal_part_t
  implicit none
  private
  public :: lagrange_step, lagrange_stable_dt, lagrange_update_cells

contains

  !> Largest stable step of the current state (no growth limit applied);
  !> `dt_cell` (optional) the cell that limits it (see `lagrange_strain_rates`).
  !> Mixed cells are limited with the material volume gains h%gain of the
  !> last `lagrange_step` (1 before any).
  subroutine lagrange_stable_dt(g, h, par, dt_stable, dt_cell)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(out) :: dt_stable
    integer, intent(out), optional :: dt_cell
    call lagrange_strain_rates(g, g%x, h%u, h, par, dt_stable, dt_cell)
  end subroutine lagrange_stable_dt

  !> Advances the state by one step. On entry `dt` is the largest step the
  !> caller allows (end time, output times, growth limit); on exit it is the
  !> step taken: the smaller of that and the stable step. `work` returns the
  !> work done by the boundaries; `bad_cell` is the first cell whose volume
  !> became non-positive (0 if none; -1 if only another block has one), in
  !> which case the state is not usable.
  !> With `halo` (a block of an MPI decomposition) the ghost nodes are
  !> refreshed after each stage's node update and the outer ghost cells'
  !> energy after its cell update; the stable step, the boundary work and a
  !> tangled cell are agreed over all blocks.
  !> `dt_cell` (optional) returns the cell whose stable step is the smallest
  !> (lowest index on a tie; 0 if none), whether or not that step was taken:
  !> the step was limited by it when `dt` came back smaller than it went in.
  !>
  !> A nodal contributor (`nodal`, `lagrange_nodal`: the coupled particles,
  !> a prescribed force) adds its forces f and masses m of each stage to
  !> the corner forces and the nodal masses, so the nodes move as u = u^n +
  !> dt (sum_c F_c + f) / (m_n + m). Energy accounting: the cells are heated
  !> only by their own corner forces (Eq. 19), so f's work is not internal
  !> energy of the cells; it is returned separately in `work_nodal` = dt
  !> sum_n f_n . u_n^{n+1/2} (the corrector's, the same discrete work as
  !> the boundary pressure forces), and what the contributor does to the
  !> cells itself (`cells`) in `work_cells`. Without cells' work the balance
  !> that holds to round-off is
  !>   Delta [sum_c m_c e_c + sum_n (m_n + m) |u_n|^2 / 2] = work + work_nodal,
  !> the kinetic energy taken with the combined nodal mass (the caller owns
  !> the contributor's share of it and its internal energy). The impulse of
  !> a kinematic boundary on f is boundary work, as for the corner forces.
  !> Without a contributor the step is the grid's alone.
  !>
  !> Mixed cells: the stable step holds each material's volume change to
  !> dv_max of itself (`mixed_volume_gain`), and the closure shares the
  !> volume and energy changes in both stages. Their interface planes
  !> (natural coordinates) follow the grid untouched; the centroids that
  !> follow from them and the new fractions are computed where they are
  !> read (`lagrange_centroids`).
  subroutine lagrange_step(g, h, bc, mats, mx, par, dt, work, bad_cell, dt_cell, nodal, work_nodal, work_cells, halo)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    type(bc_t), intent(inout) :: bc
    type(material_t), intent(inout) :: mats(:)
    type(mixed_t), intent(inout) :: mx
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(inout) :: dt
    real(wp), intent(out) :: work
    integer, intent(out) :: bad_cell
    integer, intent(out), optional :: dt_cell
    class(nodal_part_t), intent(inout), optional, target :: nodal
    real(wp), intent(out), optional :: work_nodal, work_cells
    class(halo_t), intent(inout), optional :: halo
    real(wp) :: dt_stable, w_pred, ucut, none(0)
    integer :: dtc
    ! (wacc: the boundary work; acc: the contributor's nodal work, 1, and
    ! its cells', 2)
    type(xsum_t) :: wacc(1), acc(2)
    real(wp), pointer, contiguous :: fn(:, :), mn(:)
    real(wp), pointer :: vscale(:)
    logical :: scaled

    if (present(work_nodal)) work_nodal = 0.0_wp
    if (present(work_cells)) work_cells = 0.0_wp
    call mixed_volume_gain(mx, par%relax, par%dv_vf_min, h%gain)
    call lagrange_strain_rates(g, g%x, h%u, h, par, dt_stable, dtc)
    if (present(halo)) call halo%min_step(dt_stable, dtc)
    if (present(dt_cell)) dt_cell = dtc
    dt = min(dt, dt_stable)
    call save_step_start(g, h)
    call mixed_save_step_start(mx, h%vol)
    ! the speed below which a node is at rest: par%velocity_cutoff of the
    ! grid's fastest node (a maximum: the same on any rank or thread count)
    ucut = 0.0_wp
    if (par%velocity_cutoff > 0.0_wp) then
      ucut = -par%velocity_cutoff*max_speed(g, h)
      if (present(halo)) call halo%choose(ucut, none)
      ucut = -ucut
    end if
    scaled = .false.
    vscale => null()
    if (present(nodal)) then
      call nodal%start(g, h, par)
      call nodal%visc_scale(par, scaled, vscale)
    end if

    ! predictor
    call stage_forces(1, h%u)
    call advance_nodes(0.5_wp*dt, .false., w_pred)
    call halo_nodes()
    ! the geometry of x^{1/2} (volumes, their gradients, median areas, strain
    ! rates for u*^{1/2}) is computed here once, for the densities and for the
    ! corrector
    call lagrange_update_cells(g, h, 0.5_wp*dt, bad_cell, geometry=.true.)
    call agree_bad()
    if (bad_cell /= 0) return
    if (present(nodal)) call nodal%cells(1, g, h, dt, acc(2))
    if (present(halo)) call halo%cells(h%e)
    call update_materials(h, mats, mx, par, 0.5_wp*dt)

    ! corrector
    call stage_forces(2, h%uh)
    call advance_nodes(dt, .true., work)
    call note_boundary_moves(g, h)
    if (present(nodal)) call node_work(g, fn, h%uh, acc(1))
    call halo_nodes()
    call lagrange_update_cells(g, h, dt, bad_cell)
    call agree_bad()
    if (bad_cell /= 0) return
    if (present(nodal)) call nodal%cells(2, g, h, dt, acc(2))
    if (present(halo)) then
      call halo%cells(h%e)
      call halo%sums(wacc)
      if (present(nodal)) call halo%sums(acc)
    end if
    work = xsum_value(wacc(1))
    if (present(work_nodal)) work_nodal = dt*xsum_value(acc(1))
    if (present(work_cells)) work_cells = xsum_value(acc(2))
    call update_materials(h, mats, mx, par, dt)
  contains
    !> The forces of a stage (1 predictor, 2 corrector) for the velocities
    !> v: the boundary's pressure forces, the corner forces (the viscosity
    !> scaled where the contributor asks), the contributor's.
    subroutine stage_forces(stage, v)
      integer, intent(in) :: stage
      real(wp), intent(in) :: v(:, :)
      call bc_pressure_forces(bc, g, g%x, h%p)
      if (scaled) then
        call lagrange_corner_forces(g, g%x, v, h, par, vscale, dt)
      else
        call lagrange_corner_forces(g, g%x, v, h, par, dt=dt)
      end if
      if (present(nodal)) then
        call nodal%forces(stage, g, h, bc, par, dt, halo)
        call nodal%arrays(fn, mn)
      end if
    end subroutine stage_forces

    !> A stage's node update over dt (positions over dtx; `last`: the
    !> corrector) with the contributor's forces and masses, then the
    !> boundary conditions; w the boundary's work (its exact sum in wacc).
    subroutine advance_nodes(dtx, last, w)
      real(wp), intent(in) :: dtx
      logical, intent(in) :: last
      real(wp), intent(out) :: w
      if (present(nodal)) then
        call update_nodes(g, h, dt, dtx, last, ucut, fn, mn)
        call bc_apply(bc, dt, dtx, h%mnode, h%un, h%xn, h%u, h%uh, g%x, w, mn, wacc(1))
      else
        call update_nodes(g, h, dt, dtx, last, ucut)
        call bc_apply(bc, dt, dtx, h%mnode, h%un, h%xn, h%u, h%uh, g%x, w, work_acc=wacc(1))
      end if
    end subroutine advance_nodes

    !> Ghost nodes from the neighbouring blocks: positions, new and
    !> half-step velocities of the stage just taken.
    subroutine halo_nodes()
      if (.not. present(halo)) return
      call halo%nodes(g%x)
      call halo%nodes(h%u)
      call halo%nodes(h%uh)
    end subroutine halo_nodes

    !> Every block stops where one found a tangled cell: bad_cell = -1 on
    !> the blocks that did not.
    subroutine agree_bad()
      integer :: k
      if (.not. present(halo)) return
      k = merge(1, 0, bad_cell /= 0)
      call halo%max_int(k)
      if (k /= 0 .and. bad_cell == 0) bad_cell = -1
    end subroutine agree_bad
  end subroutine lagrange_step

  !> acc: sum_n f(:,n) . u(:,n) over the nodes this block counts, exact
  !> (force x velocity; `base_xsum`).
  pure subroutine node_work(g, f, u, acc)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: f(:, :), u(:, :)
    type(xsum_t), intent(out) :: acc
    integer :: i, j, k, n
    do k = g%ulo(3), g%nhi(3)
      do j = g%ulo(2), g%nhi(2)
        do i = g%ulo(1), g%nhi(1)
          n = g%node(i, j, k)
          call xsum_add(acc, dot_product(f(:, n), u(:, n)))
        end do
      end do
    end do
  end subroutine node_work

  !> Material states after a stage: mixed cells share their volume and
  !> energy change among their materials (Tipton), every material's EOS is
  !> evaluated (explosives' burn fractions at the stage's time, dt_stage
  !> after the step's start), and mixed cells get their cell pressure and
  !> sound speed.
  subroutine update_materials(h, mats, mx, par, dt_stage)
    type(hydro_t), intent(inout) :: h
    type(material_t), intent(inout) :: mats(:)
    type(mixed_t), intent(inout) :: mx
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(in) :: dt_stage
    real(wp) :: pfloor(size(mats))
    pfloor = mats%p_min
    call mixed_split(mx, h%mass, h%vol, h%amed(1, :), h%en, h%e, par%relax, par%relax_length, dt_stage, par%dv_max, &
                     pfloor)
    call material_burn_at(mats, dt_stage)
    call material_eval_eos(mats, h%rho, h%e, h%p, h%cs, mx)
    call mixed_cell_state(mx, h%p, h%cs)
  end subroutine update_materials

  !> Keeps x^n, u^n, e^n for the two stages of the step.
  subroutine save_step_start(g, h)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    integer :: n, c
    !$omp parallel default(none) shared(g, h) private(n, c)
    !$omp do schedule(static)
    do n = 1, g%nnode
      h%xn(1:3, n) = g%x(1:3, n)
      h%un(1:3, n) = h%u(1:3, n)
    end do
    !$omp end do nowait
    !$omp do schedule(static)
    do c = 1, g%ncell
      h%en(c) = h%e(c)
    end do
    !$omp end do
    !$omp end parallel
  end subroutine save_step_start

  !> Sum of the corner forces fc(3,8,ncell) of the cells around node (i,j,k)
  !> of grid g (force); c0 is cell (i+1, j+1, k+1), used only where all
  !> eight cells are stored. The order of the terms is the same wherever the
  !> node lies in its block, so a node on a face between two blocks gets the
  !> same sum from both.
  pure function node_force(g, fc, i, j, k, c0) result(f)
    type(grid_t), intent(in) :: g
    real(wp), intent(in), contiguous :: fc(:, :, :)
    integer, intent(in) :: i, j, k, c0
    real(wp) :: f(3)
    integer :: ii, jj, kk, ci, cj, ck, sj, sk

    if (i >= g%slo(1) .and. i < g%shi(1) .and. j >= g%slo(2) .and. j < g%shi(2) .and. &
        k >= g%slo(3) .and. k < g%shi(3)) then
      ! interior node: all eight cells exist (same order as below)
      sj = g%cx
      sk = g%cxy
      f = fc(1:3, 1, c0) + fc(1:3, 2, c0 - 1) + fc(1:3, 3, c0 - sj) + fc(1:3, 4, c0 - 1 - sj) &
        + fc(1:3, 5, c0 - sk) + fc(1:3, 6, c0 - 1 - sk) + fc(1:3, 7, c0 - sj - sk) &
        + fc(1:3, 8, c0 - 1 - sj - sk)
    else
      f = 0.0_wp
      ! node (i,j,k) is corner (ii,jj,kk) of cell (i+1-ii, j+1-jj, k+1-kk)
      do kk = 0, 1
        ck = k + 1 - kk
        if (ck < g%slo(3) .or. ck > g%shi(3)) cycle
        do jj = 0, 1
          cj = j + 1 - jj
          if (cj < g%slo(2) .or. cj > g%shi(2)) cycle
          do ii = 0, 1
            ci = i + 1 - ii
            if (ci < g%slo(1) .or. ci > g%shi(1)) cycle
            f = f + fc(1:3, 1 + ii + 2*jj + 4*kk, g%cell(ci, cj, ck))
          end do
        end do
      end do
    end if
  end function node_force

  !> Gathers the corner forces at each node and advances it (Eqs. 20-22):
  !> u = u^n + dt F/m, uh = (u^n + u)/2, x = x^n + dtx uh; with a nodal
  !> contributor's force f_add and mass m_add (both or neither). A node
  !> whose u is below ucut in every component is at rest: u = 0.
  subroutine update_nodes(g, h, dt, dtx, last, ucut, f_add, m_add)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: dt, dtx
    !> the step's last stage (its positions are the step's: `move_nodes`)
    logical, intent(in) :: last
    real(wp), intent(in) :: ucut
    real(wp), intent(in), optional, contiguous :: f_add(:, :), m_add(:)
    real(wp) :: no_f(3, 0), no_m(0)

    ! (absent arguments as zero-size arrays: the node loop's OpenMP region
    ! cannot share an absent optional)
    if (present(f_add) .and. present(m_add)) then
      call move_nodes(g, h, dt, dtx, last, ucut, f_add, m_add, .true.)
    else
      call move_nodes(g, h, dt, dtx, last, ucut, no_f, no_m, .false.)
    end if
  end subroutine update_nodes

  !> The node loop of `update_nodes`: an extra nodal force f_add and mass
  !> m_add (if has_add); the switch is the same for
  !> every node, so the branches cost nothing measurable.
  subroutine move_nodes(g, h, dt, dtx, last, ucut, f_add, m_add, has_add)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: dt, dtx
    logical, intent(in) :: last
    real(wp), intent(in) :: ucut
    real(wp), intent(in), contiguous :: f_add(:, :), m_add(:)
    logical, intent(in) :: has_add
    integer :: n, i, j, k, c0, n0
    real(wp) :: f(3), m, u(3), un(3), uh(3)
    logical :: track

    ! (in the last stage, a row of nodes whose inner nodes leave x^n is
    ! noted in g%moved_rows: one thread takes each row, so each flag has
    ! one writer; the nodes on the block's faces are `note_boundary_moves`',
    ! after their conditions)
    track = last .and. allocated(g%moved_rows)
    !$omp parallel do default(none) shared(g, h, dt, dtx, ucut, f_add, m_add, has_add, track) collapse(2) &
    !$omp private(n, i, j, k, c0, f, m, n0, u, un, uh) schedule(static)
    do k = g%nlo(3), g%nhi(3)
    do j = g%nlo(2), g%nhi(2)
    ! consecutive i are consecutive nodes and cells; c0 = cell (i+1, j+1, k+1)
    n = g%node(g%nlo(1), j, k) - 1
    c0 = g%cell(g%nlo(1) + 1, j + 1, k + 1) - 1
    n0 = n + 1
    do i = g%nlo(1), g%nhi(1)
      n = n + 1
      c0 = c0 + 1
      f = node_force(g, h%fc, i, j, k, c0)
      if (has_add) f = f + f_add(1:3, n)
      m = h%mnode(n)
      if (has_add) m = m + m_add(n)
      ! (the node's values in locals, stored once each)
      un = h%un(1:3, n)
      u = un + dt*f/m
      if (all(abs(u) < ucut)) u = 0.0_wp
      uh = 0.5_wp*(un + u)
      h%u(1:3, n) = u
      h%uh(1:3, n) = uh
      g%x(1:3, n) = h%xn(1:3, n) + dtx*uh
    end do
    ! (the row's inner nodes n0+1 .. n-1, read again while they are in the
    ! cache: a loop of its own runs in the vector lanes)
    if (track .and. j > g%nlo(2) .and. j < g%nhi(2) .and. k > g%nlo(3) .and. k < g%nhi(3)) then
      if (n - n0 > 1) then
        if (nodes_moved(n - n0 - 1, g%x(:, n0 + 1:n - 1), h%xn(:, n0 + 1:n - 1))) &
          g%moved_rows((n - 1)/g%sx + 1) = .true.
      end if
    end if
    end do
    end do
    !$omp end parallel do
  end subroutine move_nodes

  !> The largest velocity component over g's owned nodes (a maximum: the
  !> same in any order).
  real(wp) function max_speed(g, h) result(s)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    integer :: i, j, k, n
    s = 0.0_wp
    !$omp parallel do default(none) shared(g, h) private(i, n) reduction(max: s) collapse(2) schedule(static)
    do k = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        do i = g%nlo(1), g%nhi(1)
          n = g%node(i, j, k)
          s = max(s, abs(h%u(1, n)), abs(h%u(2, n)), abs(h%u(3, n)))
        end do
      end do
    end do
    !$omp end parallel do
  end function max_speed

  !> Notes in g%moved_rows (if tracked) the rows of the nodes on the
  !> block's faces that the step (`move_nodes`, then the face conditions of
  !> `bc_apply`) left away from x^n: with `move_nodes`' notes of the inner
  !> nodes, every row in which a node ends the step elsewhere than it began
  !> it. (A face node's move before its condition, e.g. the round-off
  !> normal velocity a symmetry plane removes, is not a move.)
  subroutine note_boundary_moves(g, h)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(in) :: h
    integer :: j, k, n0, n1
    logical :: moved
    if (.not. allocated(g%moved_rows)) return
    do k = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        n0 = g%node(g%nlo(1), j, k)
        n1 = n0 + g%nhi(1) - g%nlo(1)
        ! (a row on a face whole, else its two end nodes)
        if (j == g%nlo(2) .or. j == g%nhi(2) .or. k == g%nlo(3) .or. k == g%nhi(3)) then
          moved = nodes_moved(n1 - n0 + 1, g%x(:, n0:n1), h%xn(:, n0:n1))
        else
          moved = nodes_moved(1, g%x(:, n0), h%xn(:, n0)) .or. nodes_moved(1, g%x(:, n1), h%xn(:, n1))
        end if
        if (moved) g%moved_rows((n0 - 1)/g%sx + 1) = .true.
      end do
    end do
  end subroutine note_boundary_moves

  !> Compatible energy update (Eq. 19) over dte with the half-step velocity,
  !> then new volume and density of every cell. bad_cell > 0 names the first
  !> owned cell with a non-positive volume. In a block with ghosts the energy
  !> is updated where the corner forces are known (`cells_around(1)`), the
  !> geometry in every stored cell; the outer ghost layer's energy comes
  !> from the halo. With `geometry` (default false), also
  !> leaves the geometry of the new positions and the strain rates of the
  !> half-step velocity h%uh in h (h%dvdx, h%amed, h%grad), as
  !> `lagrange_strain_rates` would for (g%x, h%uh), so that the forces of the
  !> next stage need not compute them again. The volume is then taken from
  !> `hex_volume_gradient`, which evaluates the same sum as `hex_volume` in
  !> the same order (tests/test_lagrange.f90 checks that both agree bit for bit).
  subroutine lagrange_update_cells(g, h, dte, bad_cell, geometry)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: dte
    integer, intent(out) :: bad_cell
    logical, intent(in), optional :: geometry
    integer :: c, a, n0, ci, cj, ck, lo(3), hi(3)
    integer(int8) :: fl
    real(wp) :: de, xn(3, 8), vn(3, 8), s(3, 3), area(3), dumax
    logical :: geom, forced, rest, moving

    geom = .false.
    if (present(geometry)) geom = geometry
    ! (bit 1: a node's half-step velocity; with geom, bit 2: its velocity at
    ! the step's start)
    call lagrange_node_flags(h%nflag, h%uh, 1_int8, .true.)
    if (geom) call lagrange_node_flags(h%nflag, h%un, 2_int8, .false.)
    ! the cells whose corner forces are known (owned and one ghost layer)
    call g%cells_around(1, lo, hi)
    bad_cell = huge(1)
    !$omp parallel do default(none) shared(g, h, dte, geom, lo, hi) &
    !$omp private(c, a, n0, ci, cj, ck, de, xn, vn, s, area, dumax, forced, rest, fl, moving) &
    !$omp reduction(min: bad_cell) collapse(2) schedule(static)
    do ck = g%slo(3), g%shi(3)
    do cj = g%slo(2), g%shi(2)
    ! consecutive i are consecutive cells and nodes
    c = g%cell(g%slo(1), cj, ck) - 1
    n0 = g%cell_node0(g%slo(1), cj, ck) - 1
    do ci = g%slo(1), g%shi(1)
      c = c + 1
      n0 = n0 + 1
      forced = ci >= lo(1) .and. ci <= hi(1) .and. cj >= lo(2) .and. cj <= hi(2) .and. ck >= lo(3) .and. ck <= hi(3)
      rest = .false.
      de = 0.0_wp
      fl = lagrange_cell_flags(g, h%nflag, n0)
      moving = btest(fl, 0)
      ! (the nodes' places and velocities where a branch below reads them)
      if (.not. ((geom .and. fl == 0) .or. (.not. geom .and. h%still(c) .and. .not. moving))) then
        do a = 1, 8
          vn(:, a) = h%uh(1:3, n0 + g%corner_offset(a))
          xn(:, a) = g%x(1:3, n0 + g%corner_offset(a))
        end do
      end if
      ! (nodes at rest do no work: de stays 0, as the products would leave
      ! it, without reading the corner forces)
      if (forced .and. moving) then
        do a = 1, 8
          de = de - dot_product(h%fc(1:3, a, c), vn(:, a))
        end do
      end if
      if (forced) h%e(c) = h%en(c) + dte*de/h%mass(c)
      ! (within a step every node is at x^n + dtx uh, `move_nodes` and
      ! `bc_apply`: with uh = 0 at its eight nodes a cell is where the step
      ! began)
      if (geom) then
        ! (a cell at rest in this stage, with zero velocities at the step's
        ! start too, keeps the geometry, rates and sizes
        ! `lagrange_strain_rates` took at these places: what the calls below
        ! give; with the velocity cut-off most of the gas ahead of a blast)
        rest = fl == 0
        h%still(c) = rest
        if (.not. rest) then
          call hex_volume_gradient(xn, h%vol(c), h%dvdx(1:3, 1:8, c))
          call hex_median_areas(xn, s)
        end if
      else if (h%still(c) .and. .not. moving) then
        ! (the step's last stage: a cell at rest in its first and now, where
        ! the step began, keeps its volume)
        continue
      else
        h%vol(c) = hex_volume(xn)
      end if
      if (h%vol(c) > 0.0_wp) then
        h%rho(c) = h%mass(c)/h%vol(c)
        if (geom .and. .not. rest) then
          call lagrange_cell_rates(vn, s, h%vol(c), area, h%grad(1:3, c), dumax)
          h%amed(1:2, c) = lagrange_area_sizes(area)
        end if
      else if (g%owns_cell(ci, cj, ck)) then
        bad_cell = min(bad_cell, c)
      end if
    end do
    end do
    end do
    !$omp end parallel do
    if (bad_cell == huge(1)) bad_cell = 0
  end subroutine lagrange_update_cells
end module lagrange_integrator
