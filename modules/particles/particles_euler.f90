!> The particles in the Euler phase ("physical variables correction with
!> solid particles", PARTICLES.md §1.13, Remark 2 of Sect. 5.2): the
!> kernels the driver (`driver_particles`) strings together around the
!> fluid's rezone and remap.
!>
!> 1. The particles keep their own velocities (Eq. 23 accumulates the
!>    grid's increments on them, FLIP): through a Lagrangian phase
!>    sum_p (m_p - m'_p) v_p changes exactly as the particles' share of the
!>    nodal momentum, sum_I (sum_p (m_p - m'_p) N_Ip) v_I, does, and a rigid
!>    motion stays exact on them whatever the grid does. (Replacing v_p by the
!>    grid's velocity at it, PIC, as the design note proposed, loses the
!>    rotation's kinetic energy at the body's edge nodes at every Euler step:
!>    43 % of a rotating projectile's over 149 Euler steps.)
!> 2. `particles_relocate`: each particle's host cell and natural coordinates
!>    in a grid (the standard grid for the pre-positioning of Remark 2, the
!>    rezoned grid after the remap), by its physical position, walking from a
!>    guess. The particles' positions do not change.
!> 3. `particles_occupied`: the cells holding particles (the fixed inner
!>    boundary of the smoothing, Fig. 4f).
!> 4. (the rezone, `rezone_lssm`) the nodes of the occupied cells put at
!>    their places in the standard grid.
!> After the remap `particles_relocate_rezoned` finds each particle's new
!> host, puts it on the new grid's map (`particles_place`) and re-sorts and
!> re-bins the particles; those a rezone left beyond an open face
!> (`particles_out_open_face`; a block of a decomposed run knows them when
!> no block's cell may hold them, `particles_cells_hold`) leave the run
!> (`particles_take_out`: what they take out, `particles_leaving`, for the
!> driver's balance), and `particles_rebuild_nodes` gives them new virtual-fluid
!> masses from their new hosts' densities and rebuilds the nodal velocity
!> from the remapped fluid momentum and the particles' (before the remap
!> `particles_euler_save` took their share of the nodes' kinetic energy and
!> momentum for the balance); then
!> 5. `particles_flip`: the rebuild's change of the node velocities against
!>    the particles' mean (the fluid's share, the kinematic conditions) goes
!>    to the particles, so that they and the nodes agree again
!>    (`particles_share_velocities`: the rebuild and the flip, also the
!>    coupling's start).
module particles_euler
  use base_kinds, only: wp
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use base_errors, only: error_t, error_set, error_no_memory, ERR_RUNTIME
  use base_strings, only: itoa, rtoa
  use base_lapack, only: dgelss
  use mesh_grid, only: grid_t
  use mesh_boundary, only: bc_t, BC_INFLOW, BC_OUTFLOW, bc_constrain
  use mesh_halo, only: halo_t
  use hydro_state, only: hydro_t, nodal_sums
  use particles_state, only: particles_t, particles_select, particles_order
  use strength_gurson, only: strength_gurson_t
  use strength_hjc, only: strength_hjc_t
  use particles_spread, only: particles_support_widths
  use particles_shape, only: particles_locate, particles_shape_values, inside_tol, particles_grid_hull
  use particles_lagrange, only: particles_interpolate, particles_work_t, strength_slot_t, particles_phase_mass, &
                                particles_virtual_grid, particles_blend_velocities, particles_virtual_masses, particles_work_resize
  implicit none
  private
  public :: particles_euler_t, particles_euler_save, particles_cell_density, &
            particles_rebuild_nodes, particles_share_velocities, particles_flip, &
            particles_relocate, particles_occupied, particles_place, particles_leaving, particles_out_open_face, &
            particles_first_lost, particles_owned_hosts, particles_open_far, particles_cells_hold, &
            particles_out_t, particles_take_out, particles_relocate_rezoned

  !> What the particles' Euler-phase hooks pass on (PARTICLES.md §1.13).
  type :: particles_euler_t
    !> (np) where the walk for each particle's new host starts: its host in
    !> the standard grid (pre-positioning) or its old host
    integer, allocatable :: guess(:)
    !> (ncell) cells of the standard grid holding particles (smoothing rezones)
    logical, allocatable :: occupied(:)
    !> guess and occupied are a block's (the driver's pre-positioning on the blocks)
    logical :: on_blocks = .false.
    !> the particles' share of the nodal kinetic energy and momentum before the
    !> remap, and the share of those that left through open faces
    real(wp) :: ke_solid = 0.0_wp, p_solid(3) = 0.0_wp, ke_out = 0.0_wp, p_out(3) = 0.0_wp
  end type particles_euler_t

  !> What the particles that left the grid through open faces took out
  !> (`particles_take_out`), the whole run's: how many left and remain,
  !> their mass, the momentum and kinetic energy of their share of the
  !> nodal mass (m_p - m'_p), and their energy (that kinetic energy and
  !> their internal energy).
  type :: particles_out_t
    integer :: left = 0, remain = 0
    real(wp) :: mass = 0.0_wp, momentum(3) = 0.0_wp, ke = 0.0_wp, energy = 0.0_wp
  end type particles_out_t

contains

  !> Before the remap: the particles' share of the nodal kinetic energy and
  !> momentum (the transfer's balance, in pe), summed exactly over the nodes
  !> the block counts (`nodal_sums`). Coupled particles only.
  subroutine particles_euler_save(g, h, pt, pw, halo, pe)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    type(particles_t), intent(inout) :: pt
    type(particles_work_t), intent(inout) :: pw
    class(halo_t), intent(inout) :: halo
    type(particles_euler_t), intent(inout) :: pe
    call particles_phase_mass(g, pt, pw, h%mnode)
    call nodal_sums(g, halo, pw%mp, h%u, pe%ke_solid, pe%p_solid)
  end subroutine particles_euler_save

  !> After the remap (PARTICLES.md §1.13 item 4, the particles relocated):
  !> their virtual-fluid masses from the new hosts' densities and the nodes
  !> they reach rebuilt (`particles_share_velocities`); ke_f, p_f the nodal
  !> kinetic energy and momentum of the remapped fluid's masses before it,
  !> ke1, p1 those of the fluid's and the particles' share after it, exact
  !> sums over the nodes the blocks count.
  subroutine particles_rebuild_nodes(g, h, bc, pt, pw, halo, ke_f, p_f, ke1, p1)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    type(bc_t), intent(in) :: bc
    type(particles_t), intent(inout) :: pt
    type(particles_work_t), intent(inout) :: pw
    class(halo_t), intent(inout) :: halo
    real(wp), intent(out) :: ke_f, p_f(3), ke1, p1(3)
    call particles_virtual_masses(pt, h%rho)
    call nodal_sums(g, halo, h%mnode, h%u, ke_f, p_f)
    call particles_share_velocities(g, h, bc, pt, pw, halo)
    call nodal_sums(g, halo, h%mnode + pw%mp, h%u, ke1, p1)
  end subroutine particles_rebuild_nodes

  !> The particles' nodal mass term (Eq. 16, from the current m'_p), and at
  !> each node the particles reach the velocity u = (m_f u + m_p,I vbar_I) /
  !> (m_f + m_p,I), vbar_I the particles' mass-weighted mean velocity there
  !> (Eq. 30 with v_p); the kinematic conditions; the change u - vbar given
  !> to the particles (`particles_flip`), so that particles and nodes agree.
  !> A block's ghost nodes are taken as their owners have them: its
  !> particles in ghost cells reach nodes whose sums the block does not
  !> complete.
  subroutine particles_share_velocities(g, h, bc, pt, pw, halo)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    type(bc_t), intent(in) :: bc
    type(particles_t), intent(inout) :: pt
    type(particles_work_t), intent(inout) :: pw
    class(halo_t), intent(inout) :: halo
    pw%mass_ready = .false.
    call particles_phase_mass(g, pt, pw, h%mnode)
    call particles_virtual_grid(g, pt, pt%v, pw%ms, pw%vs)
    call particles_blend_velocities(pw%ms, h%mnode, pw%mp, pw%vs, h%u)
    call bc_constrain(bc, h%u)
    call halo%nodes(h%u)
    call halo%nodes(pw%vs)
    call particles_flip(g, pt, h%u, pw%vs)
  end subroutine particles_share_velocities

  !> v_p += sum_a N_a(xi_p) (u_a - vbar_a) over the host's corners (item 5):
  !> the change the rebuild made to the nodes' velocities, given to the
  !> particles as a Lagrangian step's would be (Eq. 23).
  subroutine particles_flip(g, p, u, vbar)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout) :: p
    real(wp), intent(in) :: u(:, :), vbar(:, :)
    integer :: k
    !$omp parallel do default(none) shared(g, p, u, vbar) private(k) schedule(static)
    do k = 1, p%np
      p%v(:, k) = p%v(:, k) + particles_interpolate(g, p, k, u, vbar)
    end do
    !$omp end parallel do
  end subroutine particles_flip

  !> Host cell(np) and natural coordinates xi(3, np) of every particle's
  !> position in the grid with nodes at x(3, nnode), the walk starting at
  !> guess(np) (item 2). bad: the first particle in no cell (0 if none).
  !> cut: a block's (`particles_locate`: cell -1 where the walk would leave
  !> the block's stored cells).
  subroutine particles_relocate(g, x, p, guess, cell, xi, bad, cut, at_cut)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: guess(:)
    integer, intent(out) :: cell(:)
    real(wp), intent(out) :: xi(:, :)
    integer, intent(out) :: bad
    logical, intent(in), optional :: cut(6)
    !> (np; with cut) where a walk would step past a cut: the stored cell
    !> it would step on from, by its number in the whole grid
    !> (`grid_global_cell`), else 0 (`particles_locate`)
    integer, intent(out), optional :: at_cut(:)
    logical :: found, cuts(6), on_block
    integer :: k, last
    real(wp) :: hull(6)
    on_block = present(cut)
    cuts = .false.
    if (on_block) cuts = cut
    ! (a particle out of the grid, through an open face, found in no cell at
    ! once, not by the search cell by cell)
    hull = particles_grid_hull(g, x)
    bad = huge(1)
    !$omp parallel do default(none) shared(g, x, p, guess, cell, xi, cuts, on_block, at_cut, hull) private(k, found, last) &
    !$omp reduction(min: bad) schedule(dynamic, 256)
    do k = 1, p%np
      if (on_block) then
        call particles_locate(g, p%x(:, k), guess(k), cell(k), xi(:, k), found, x, cuts, last)
        if (present(at_cut)) at_cut(k) = merge(g%global_cell(max(last, 1)), 0, last > 0)
      else
        call particles_locate(g, p%x(:, k), guess(k), cell(k), xi(:, k), found, x, hull=hull)
      end if
      if (.not. found) bad = min(bad, k)
    end do
    !$omp end parallel do
    if (bad == huge(1)) bad = 0
  end subroutine particles_relocate

  !> How many of the block g's owned cells host particles of p (binned).
  integer function particles_owned_hosts(g, p) result(n)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(in) :: p
    integer :: c, i, j, k
    n = 0
    do c = 1, g%ncell
      if (p%cell_start(c + 1) == p%cell_start(c)) cycle
      call g%cell_ijk(c, i, j, k)
      if (g%owns_cell(i, j, k)) n = n + 1
    end do
  end function particles_owned_hosts

  !> The cells that host a particle of cell(np) (item 3).
  pure function particles_occupied(cell, ncell) result(occ)
    integer, intent(in) :: cell(:), ncell
    logical :: occ(ncell)
    integer :: k
    occ = .false.
    do k = 1, size(cell)
      occ(cell(k)) = .true.
    end do
  end function particles_occupied

  !> Each particle's position from its host cell and natural coordinates in
  !> g's nodes (after `particles_relocate` on a rezoned grid: the trilinear
  !> map of the new host).
  subroutine particles_place(g, p)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout) :: p
    real(wp) :: sh(8)
    integer :: k, a, n0
    do k = 1, p%np
      sh = particles_shape_values(p%xi(:, k))
      n0 = g%node0(p%cell(k))
      p%x(:, k) = 0.0_wp
      do a = 1, 8
        p%x(:, k) = p%x(:, k) + sh(a)*g%x(:, n0 + g%corner_offset(a))
      end do
    end do
  end subroutine particles_place

  !> What the particles with no new host (cell(k) = 0) take out of the run
  !> as they leave through an open face, exact sums (the blocks of a
  !> decomposed run add theirs): their mass acc(1), their share
  !> (m_p - m'_p) of the nodal momentum acc(2:4) and kinetic energy acc(5),
  !> and their internal energy acc(6). Inert particles (no m'_p) carry only
  !> their mass.
  subroutine particles_leaving(p, cell, acc)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: cell(:)
    type(xsum_t), intent(inout) :: acc(6)
    real(wp) :: mx
    integer :: k, d
    do k = 1, p%np
      if (cell(k) > 0) cycle
      call xsum_add(acc(1), p%m(k))
      if (.not. allocated(p%mvf)) cycle
      mx = p%m(k) - p%mvf(k)
      do d = 1, 3
        call xsum_add(acc(1 + d), mx*p%v(d, k))
      end do
      call xsum_add(acc(5), 0.5_wp*mx*dot_product(p%v(:, k), p%v(:, k)))
      call xsum_add(acc(6), p%m(k)*p%e(k))
    end do
  end subroutine particles_leaving

  !> The particles of pt with no cell (cell(k) = 0) leave through open
  !> faces: what they take out (`particles_leaving`, summed exactly over the
  !> blocks of halo: every rank the run's) in out, and they are taken out of
  !> pt, cell and xi.
  subroutine particles_take_out(pt, cell, xi, halo, out)
    type(particles_t), intent(inout) :: pt
    integer, allocatable, intent(inout) :: cell(:)
    real(wp), allocatable, intent(inout) :: xi(:, :)
    class(halo_t), intent(in) :: halo
    type(particles_out_t), intent(out) :: out
    type(xsum_t) :: acc(6)
    integer, allocatable :: pick(:)
    integer :: k, n(2)
    call particles_leaving(pt, cell, acc)
    call halo%sums(acc)
    out%mass = xsum_value(acc(1))
    out%momentum = [(xsum_value(acc(1 + k)), k = 1, 3)]
    out%ke = xsum_value(acc(5))
    out%energy = xsum_value(acc(6)) + out%ke
    pick = pack([(k, k = 1, pt%np)], cell > 0)
    n = [pt%np - size(pick), size(pick)]
    call halo%sum_ints(n)
    out%left = n(1)
    out%remain = n(2)
    call particles_select(pt, pick)
    cell = cell(pick)
    xi = xi(:, pick)
  end subroutine particles_take_out

  !> After the remap (PARTICLES.md §1.13 item 3), on a grid g that holds
  !> all of pt's hosts (one process's, or a decomposed run's whole grid):
  !> every particle's host and natural coordinates in the rezoned grid (the
  !> walk from guess, `particles_relocate`), its position put on the new
  !> host's map, the particles re-sorted and re-binned (and their supports'
  !> widths taken again, GIMP). Those the rezone left beyond an open face
  !> leave (`particles_take_out`: what they took out in out, the others'
  !> work arrays pw resized; left: some particle had no cell); any other
  !> particle in no cell is a runtime failure (the grid lost it).
  subroutine particles_relocate_rezoned(g, bc, halo, pt, pw, guess, out, left, err)
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    class(halo_t), intent(in) :: halo
    type(particles_t), intent(inout) :: pt
    type(particles_work_t), intent(inout) :: pw
    integer, intent(in) :: guess(:)
    type(particles_out_t), intent(out) :: out
    logical, intent(out) :: left
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: cell(:)
    real(wp), allocatable :: xi(:, :)
    integer :: bad, k, stat
    character(len=200) :: msg
    left = .false.
    allocate(cell(pt%np), xi(3, pt%np), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'particles_euler_finish', error_no_memory('work arrays'))
      return
    end if
    call particles_relocate(g, g%x, pt, guess, cell, xi, bad)
    if (bad /= 0) then
      k = particles_first_lost(g, bc, g%x, pt, cell)
      if (k > 0) then
        call error_set(err, 'particles_euler_finish', 'particle '//itoa(pt%id(k))//' at ('// &
                       rtoa(pt%x(1, k))//', '//rtoa(pt%x(2, k))//', '//rtoa(pt%x(3, k))// &
                       ') lies in no cell of the rezoned grid', ERR_RUNTIME)
        return
      end if
      left = .true.
      call particles_take_out(pt, cell, xi, halo, out)
      if (allocated(pw%vh)) call particles_work_resize(pw, pt%np, pt%nhist, err)
      if (allocated(err)) return
    end if
    pt%cell = cell
    pt%xi = xi
    call particles_place(g, pt)
    call particles_order(pt, g%ncell, err)
    if (pt%spread) call particles_support_widths(g, pt)
  end subroutine particles_relocate_rezoned

  !> The particles of one solid in one host cell keep only the part of
  !> their specific volume and specific internal energy (mass-weighted),
  !> and for a solid whose pressure is in its stress (no EOS) of their mean
  !> stress (volume-weighted; the deviator kept), that is linear in their
  !> positions over the cell (`linear_part`): sum V, sum m e and sum V p
  !> are kept. An Euler step leaves particles of different histories
  !> sharing a cell (cell crossing: a shocked solid's cells of two and of
  !> three particle layers end with densities 4 % apart, PARTICLES.md 1.9);
  !> the grid sees only the particles' sums over a cell, so a spread among
  !> them that no linear field explains would never even out. A linear
  !> variation is the solid's own: the bending stress across a plate one or
  !> two cells thick (the cell's mean, which this took before, halved the
  !> flexible plate's stiffness at each Euler step: input/flexible_plate.nml
  !> bent twice as far). Not for Gurson (its porosity follows the volume) or
  !> HJC (pressure from its compaction history) solids. Call with the
  !> particles sorted by solid and host (`particles_order`), each cell's
  !> particles all present (a block's owned and ghost cells).
  subroutine particles_cell_density(p, models)
    type(particles_t), intent(inout) :: p
    type(strength_slot_t), intent(in) :: models(:)
    integer :: k, j, q
    real(wp), allocatable :: f(:, :)
    k = 1
    do while (k <= p%np)
      j = k
      do while (j < p%np)
        if (p%mat(j + 1) /= p%mat(k) .or. p%cell(j + 1) /= p%cell(k)) exit
        j = j + 1
      end do
      ! (two particles are their own linear field)
      if (j > k + 1 .and. evened(models(p%mat(k)))) then
        if (.not. allocated(models(p%mat(k))%eos)) then
          f = reshape([(mean_stress(q), q = k, j)], [1, j - k + 1])
          call linear_part(p%x(:, k:j), p%vol(k:j), f)
          do q = k, j
            p%stress(1:3, q) = p%stress(1:3, q) - mean_stress(q) + f(1, q - k + 1)
          end do
        end if
        f = reshape([(p%vol(q)/p%m(q), p%e(q), q = k, j)], [2, j - k + 1])
        call linear_part(p%x(:, k:j), p%m(k:j), f)
        do q = k, j
          p%vol(q) = p%m(q)*f(1, q - k + 1)
          p%rho(q) = 1.0_wp/f(1, q - k + 1)
          p%e(q) = f(2, q - k + 1)
        end do
      end if
      k = j + 1
    end do
  contains
    pure logical function evened(slot)
      type(strength_slot_t), intent(in) :: slot
      select type (m => slot%m)
      type is (strength_gurson_t)
        evened = .false.
      type is (strength_hjc_t)
        evened = .false.
      class default
        evened = .true.
      end select
    end function evened

    pure real(wp) function mean_stress(q)
      integer, intent(in) :: q
      mean_stress = (p%stress(1, q) + p%stress(2, q) + p%stress(3, q))/3.0_wp
    end function mean_stress
  end subroutine particles_cell_density

  !> f(:, q), nf fields at the points x(:, q) with weights w(q) > 0, is
  !> replaced by its weighted least-squares linear fit fbar + g.(x - xbar)
  !> (xbar, fbar the weighted means, so sum w f is kept), the gradient
  !> scaled down where needed to keep the fit within the range of f (no new
  !> extrema; a negative specific volume cannot come of it). Directions the
  !> points do not span take no gradient (SVD, `dgelss`); f is left as it
  !> was if the SVD fails.
  subroutine linear_part(x, w, f)
    real(wp), intent(in) :: x(:, :), w(:)
    real(wp), intent(inout) :: f(:, :)
    !> singular values below this times the largest are round-off of
    !> points on a line or a plane
    real(wp), parameter :: rcond = 1.0e-10_wp
    real(wp) :: xbar(3), fbar(size(f, 1)), a(size(w), 3), b(max(size(w), 3), size(f, 1)), s(3), d(size(w)), theta
    real(wp) :: work(9 + max(6, size(w), size(f, 1)))
    integer :: n, nf, q, i, rank, info
    n = size(w)
    nf = size(f, 1)
    xbar = matmul(x, w)/sum(w)
    fbar = matmul(f, w)/sum(w)
    b = 0.0_wp
    do q = 1, n
      a(q, :) = sqrt(w(q))*(x(:, q) - xbar)
      b(q, :) = sqrt(w(q))*(f(:, q) - fbar)
    end do
    call dgelss(n, 3, nf, a, n, b, size(b, 1), s, rcond, rank, work, size(work), info)
    if (info /= 0) return
    do i = 1, nf
      do q = 1, n
        d(q) = dot_product(b(1:3, i), x(:, q) - xbar)
      end do
      theta = 1.0_wp
      do q = 1, n
        if (d(q) > 0.0_wp) theta = min(theta, (maxval(f(i, :)) - fbar(i))/d(q))
        if (d(q) < 0.0_wp) theta = min(theta, (minval(f(i, :)) - fbar(i))/d(q))
      end do
      f(i, :) = fbar(i) + max(theta, 0.0_wp)*d
    end do
  end subroutine linear_part

  !> The first particle with no cell in the grid x (cell(k) = 0) that did
  !> not go out through an inflow or outflow face (`particles_out_open_face`,
  !> from its host p%cell(k) and position): the grid lost it (0: none).
  integer function particles_first_lost(g, bc, x, p, cell) result(lost)
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: x(:, :)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: cell(:)
    real(wp) :: far(6)
    integer :: k
    lost = 0
    if (all(cell(:p%np) > 0)) return
    far = particles_open_far(g, bc, x)
    do k = 1, p%np
      if (cell(k) > 0) cycle
      if (particles_out_open_face(g, bc, far, p%cell(k), p%x(:, k))) cycle
      lost = k
      return
    end do
  end function particles_first_lost

  !> For each inflow or outflow face f of the whole grid, how far out its
  !> nodes reach: the largest of s x(d) over the face's nodes that grid g
  !> stores (s = -1 on a low face, +1 on a high one; -huge for a closed
  !> face or one g does not touch: a block of a decomposed run takes the
  !> largest over the blocks).
  function particles_open_far(g, bc, x) result(far)
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: x(:, :)
    real(wp) :: far(6), sgn
    integer :: f, d, i, j, k, lo(3), hi(3)
    logical :: low
    far = -huge(1.0_wp)
    do f = 1, 6
      if (.not. (bc%kind(f) == BC_INFLOW .or. bc%kind(f) == BC_OUTFLOW)) cycle
      d = (f + 1)/2
      low = mod(f, 2) == 1
      ! (the face's nodes: the whole grid's node index 0 or n along d)
      lo = g%slo - 1
      hi = g%shi
      if (low) then
        if (g%off(d) + g%slo(d) /= 1) cycle
        hi(d) = lo(d)
      else
        if (g%off(d) + g%shi(d) /= g%gn(d)) cycle
        lo(d) = hi(d)
      end if
      sgn = merge(-1.0_wp, 1.0_wp, low)
      do k = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            far(f) = max(far(f), sgn*x(d, g%node(i, j, k)))
          end do
        end do
      end do
    end do
  end function particles_open_far

  !> Whether a particle at xp, hosted by cell c of grid g (the whole grid or
  !> a block of it), went out through an inflow or outflow face of the whole
  !> grid, whose nodes reach far (`particles_open_far`): its host lies on
  !> such a face, or xp lies beyond the face (past every one of the face's
  !> nodes along its direction).
  pure logical function particles_out_open_face(g, bc, far, c, xp) result(out)
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: far(6), xp(3)
    integer, intent(in) :: c
    integer :: ijk(3), f, d
    logical :: low
    call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
    ijk = ijk + g%off
    out = .false.
    do f = 1, 6
      if (.not. (bc%kind(f) == BC_INFLOW .or. bc%kind(f) == BC_OUTFLOW)) cycle
      d = (f + 1)/2
      low = mod(f, 2) == 1
      if (low) then
        out = out .or. ijk(d) == 1 .or. -xp(d) > far(f)
      else
        out = out .or. ijk(d) == g%gn(d) .or. xp(d) > far(f)
      end if
    end do
  end function particles_out_open_face

  !> held(q): whether some cell that block g owns, with nodes at x, may hold
  !> point xp(:, q): its corners' bounding box, widened by what the walk's
  !> tolerance reaches (`particles_locate`'s inside_tol on the box's size),
  !> holds it. A point no block's cell may hold is in no cell of the whole
  !> grid (a cell lies in the hull of its corners).
  function particles_cells_hold(g, x, xp) result(held)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), xp(:, :)
    logical :: held(size(xp, 2))
    real(wp) :: xn(3, 8), lo(3), hi(3), w, blo(3), bhi(3)
    integer, allocatable :: near(:)
    integer :: i, j, k, q, p
    held = .false.
    if (size(xp, 2) == 0) return
    ! (the union of the owned cells' widened boxes: only the points in it
    ! are tested cell by cell, so that points far from the block, those
    ! that left the grid, cost one test each)
    blo = huge(1.0_wp)
    bhi = -huge(1.0_wp)
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          call cell_box(g%cell(i, j, k))
          blo = min(blo, lo - w)
          bhi = max(bhi, hi + w)
        end do
      end do
    end do
    near = pack([(q, q = 1, size(xp, 2))], [(all(xp(:, q) >= blo .and. xp(:, q) <= bhi), q = 1, size(xp, 2))])
    if (size(near) == 0) return
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          call cell_box(g%cell(i, j, k))
          do p = 1, size(near)
            q = near(p)
            if (all(xp(:, q) >= lo - w .and. xp(:, q) <= hi + w)) held(q) = .true.
          end do
        end do
      end do
    end do
  contains
    !> Cell c's box lo..hi in x and its widening w.
    subroutine cell_box(c)
      integer, intent(in) :: c
      call g%gather(c, x, xn)
      lo = minval(xn, dim=2)
      hi = maxval(xn, dim=2)
      w = 10.0_wp*inside_tol*sum(hi - lo)
    end subroutine cell_box
  end function particles_cells_hold
end module particles_euler
