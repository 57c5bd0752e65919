!> The MPM particles of a scene (PARTICLES.md §1.2): structure of arrays,
!> allocated only when the deck seeds particles (ARCHITECTURE.md §3: a scene without
!> solids pays nothing). A failed particle is flagged, never deleted; np
!> shrinks only when particles leave the grid through an open face at an
!> Euler step (`particles_select`). Ids are the seeding numbers and stay
!> with the particles (unique, in 1..the number seeded).
!>
!> Order and binning. The arrays are sorted by solid material (`mat`), so
!> that material s is the contiguous range mat_start(s) .. mat_start(s+1)-1
!> (a strength model is dispatched once per material, then loops over its
!> range), within a material by host cell, and within a cell by id: the
!> order depends on the keys alone, never on the order the arrays came in,
!> so the blocks of a decomposed run, whatever particles they receive from
!> their neighbours, each hold theirs in the order one process gives them
!> (the cells of a block are numbered in the whole grid's order).
!> `cell_start`/`perm` bin the particles by host cell (CSR): the particles
!> of cell c are perm(cell_start(c) .. cell_start(c+1)-1), in array order.
!> Both are built by counting sorts (and, for the few particles of one
!> cell, an insertion sort by id), so the result depends only on the keys,
!> never on thread count or timing (deterministic).
!> The binning is rebuilt whenever host cells change (after an Euler step,
!> Remark 2 of Sect. 5.2: hook `particles_bin`); it is not restart state.
!>
!> Host and natural coordinates (§1.3-1.4). `cell` is the host cell's index
!> and `xi` the natural coordinates in [0,1]^3 of the particle in it, with
!> shape functions N_a(xi) = prod_d (bit_d(a-1) ? xi_d : 1 - xi_d) over the
!> cell's corners a = 1 + i + 2j + 4k (`particles_shape`). Through a
!> Lagrangian phase cell and xi stay fixed and x = sum_a N_a(xi) x_a follows
!> the grid exactly (Eq. 25 with constant parametric coordinates).
!>
!> Supports (pieces). The particle-to-grid kernels see each particle as
!> pieces: a piece lies in one cell, at natural coordinates pxi there, and
!> carries the share pw of its particle's mass and volume, so that its
!> weights are the cell's shape functions at pxi times pw. With the
!> default linear transfer a particle is one piece (its host, its xi,
!> weight 1: the standard MPM shape functions, §1.3); with &hydro
!> particle_support = 'gimp' (`particles_spread`) a particle is the
!> overlaps of its domain with its host and neighbour cells (the
!> generalized interpolation material point method), so that its weights
!> change continuously as it crosses a face. pc_start/pc_perm bin the
!> pieces by cell as cell_start/perm bin the particles: the scatter
!> kernels loop over the cells' pieces in the cell colours.
!>
!> Stress is the full Cauchy stress in Voigt order xx, yy, zz, yz, xz, xy
!> (sign: tension positive); `hist` holds nhist history variables per
!> particle (plastic strain, damage, porosity...: nhist = 0 until a strength
!> model needs them; allocated (0, np) then).
!>
!> The Lagrangian phase (Eqs. 16-17, 23-25, 29-32, §1.10) is in
!> `particles_lagrange`; it writes x, v, vol, rho, stress and hist. At Euler
!> steps (Remark 2, `particles_euler` and `driver_particles`) cell, xi, x and
!> mvf are rewritten and the particles re-sorted (`particles_order`); after a
!> restart read they are binned again (`particles_index`).
module particles_state
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_strings, only: itoa
  use base_registry, only: registry_t, LOC_PARTICLE, LOWER_POSITIVE, LOWER_NONNEGATIVE
  implicit none
  private
  public :: particles_t, particles_allocate, particles_order, particles_key_order, particles_select, particles_index, &
            particles_bin, particles_solid_order, particles_take_fields, particles_cell_counts, particles_places, &
            particles_register_restart, particles_check, particles_pieces_by_cell, &
            particles_move

  !> The particles. Units: x length, v length/time, m mass, vol length^3,
  !> rho mass/length^3, stress mass/(length time^2).
  type :: particles_t
    integer :: np = 0                        !< number of particles (0: none, nothing allocated)
    integer :: nsolid = 0                    !< number of solid materials
    integer :: nhist = 0                     !< history variables per particle
    integer, allocatable :: id(:)            !< seeding number 1..np (follows the particle through sorts)
    integer, allocatable :: mat(:)           !< solid material 1..nsolid
    integer, allocatable :: body(:)          !< body id (>= 1)
    integer, allocatable :: cell(:)          !< host cell
    real(wp), allocatable :: xi(:, :)        !< (3, np) natural coordinates in the host, in [0,1]^3
    real(wp), allocatable :: x(:, :)         !< (3, np) position
    real(wp), allocatable :: v(:, :)         !< (3, np) velocity
    real(wp), allocatable :: m(:)            !< mass (constant)
    real(wp), allocatable :: vol(:)          !< volume
    real(wp), allocatable :: rho(:)          !< density m/vol
    real(wp), allocatable :: stress(:, :)    !< (6, np) Cauchy stress, Voigt xx, yy, zz, yz, xz, xy
    real(wp), allocatable :: hist(:, :)      !< (nhist, np) history variables
    !> (np) specific internal energy, from the constitutive (virtual) strain
    !> work (PARTICLES.md §1.12): m_p e_p is the particle's internal energy
    real(wp), allocatable :: e(:)
    !> (np) virtual-fluid mass m'_p = host density x V_p, frozen for a
    !> Lagrangian phase (PARTICLES.md §1.7); allocated only when the particles
    !> are coupled to the grid (&hydro particles = 'coupled')
    real(wp), allocatable :: mvf(:)
    integer, allocatable :: mat_start(:)     !< (nsolid+1) material s: mat_start(s) .. mat_start(s+1)-1
    integer, allocatable :: cell_start(:)    !< (ncell+1) CSR of the particles by host cell
    integer, allocatable :: perm(:)          !< (np) particle indices, cell by cell
    !> The particles' supports as pieces in cells (module notes): with
    !> `spread` off one piece per particle (its host, its xi, weight 1);
    !> with it on, `particles_spread` rebuilds them as the overlaps of each
    !> particle's domain with its host and the neighbours (GIMP).
    logical :: spread = .false.              !< spread the supports over neighbour cells (&hydro particle_support)
    logical :: spread_ready = .false.        !< the pieces are spread for the current hosts
    !> (np) half-width of each particle's domain in its host's natural
    !> coordinates, set where the hosts are (`particles_support_widths`),
    !> restart state with `spread` (0: not spread)
    real(wp), allocatable :: lsup(:)
    integer :: npc = 0                       !< number of pieces
    integer, allocatable :: pfirst(:)        !< (np+1) pieces of particle k: pfirst(k) .. pfirst(k+1)-1
    integer, allocatable :: pcell(:)         !< (npc) the piece's cell
    integer, allocatable :: ppart(:)         !< (npc) the piece's particle
    real(wp), allocatable :: pxi(:, :)       !< (3, npc) natural coordinates of the piece's centre in its cell
    real(wp), allocatable :: pw(:)           !< (npc) the piece's share of its particle (sum 1 per particle)
    integer, allocatable :: pc_start(:)      !< (ncell+1) CSR of the pieces by cell
    integer, allocatable :: pc_perm(:)       !< (npc) piece indices, cell by cell
    !> (npc) the pieces' particle, weight and centre in the order of
    !> pc_perm (`particles_pieces_by_cell`): what the cell-by-cell loops
    !> read, in the order they read it (through pc_perm the reads scatter,
    !> and waiting on them was a fifth of a particle run's time)
    integer, allocatable :: cpart(:)
    real(wp), allocatable :: cw(:), cxi(:, :)
  end type particles_t

contains

  !> Allocates np particles of nsolid materials with nhist history variables
  !> each (fields zero, ids 1..np).
  subroutine particles_allocate(p, np, nsolid, nhist, err)
    type(particles_t), intent(inout) :: p
    integer, intent(in) :: np, nsolid, nhist
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat, k
    character(len=200) :: msg
    p = particles_t()
    if (np < 0 .or. nsolid < 0 .or. nhist < 0) then
      call error_set(err, 'particles_allocate', 'negative size')
      return
    end if
    allocate(p%id(np), p%mat(np), p%body(np), p%cell(np), p%xi(3, np), p%x(3, np), p%v(3, np), p%m(np), &
             p%vol(np), p%rho(np), p%e(np), p%stress(6, np), p%hist(nhist, np), p%mat_start(nsolid + 1), p%perm(np), &
             p%lsup(np), stat=stat, errmsg=msg)
    if (stat /= 0) then
      p = particles_t()
      call error_set(err, 'particles_allocate', error_no_memory(itoa(np)//' particles'))
      return
    end if
    p%np = np
    p%nsolid = nsolid
    p%nhist = nhist
    p%id = [(k, k = 1, np)]
    p%mat = 1; p%body = 1; p%cell = 1
    p%xi = 0.0_wp; p%x = 0.0_wp; p%v = 0.0_wp; p%m = 0.0_wp; p%vol = 0.0_wp; p%rho = 0.0_wp; p%e = 0.0_wp
    p%lsup = 0.0_wp
    p%stress = 0.0_wp; p%hist = 0.0_wp
    p%mat_start = 1
    p%perm = 0
  end subroutine particles_allocate

  !> Sorts the particles by material, then by host cell, then by id
  !> (`particles_key_order`), and builds mat_start and the cell binning. mat
  !> must be in 1..nsolid and cell in 1..ncell.
  subroutine particles_order(p, ncell, err)
    type(particles_t), intent(inout) :: p
    integer, intent(in) :: ncell
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: order(:)
    ! (none: an empty binning, as a block of a decomposed run may hold)
    if (p%np == 0) then
      call particles_index(p, ncell, err)
      return
    end if
    if (any(p%cell < 1) .or. any(p%cell > ncell) .or. any(p%mat < 1) .or. any(p%mat > p%nsolid)) then
      call error_set(err, 'particles_order', 'a host cell or material index is out of range')
      return
    end if
    call particles_key_order(p%mat(:p%np), p%nsolid, p%cell(:p%np), ncell, p%id(:p%np), order, err)
    if (allocated(err)) return
    call particles_select(p, order)
    call particles_index(p, ncell, err)
  end subroutine particles_order

  !> The permutation order that sorts the keys (mat in 1..nmat, cell in
  !> 1..ncell, id unique) by mat, then cell, then id: two stable counting
  !> sorts, least significant key first, then an insertion sort by id within
  !> each run of one material and cell (a few particles).
  subroutine particles_key_order(mat, nmat, cell, ncell, id, order, err)
    integer, intent(in) :: mat(:), nmat, cell(:), ncell, id(:)
    integer, allocatable, intent(out) :: order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: by_cell(:)
    integer :: n, s, k, i, j, q, stat
    character(len=200) :: msg
    n = size(mat)
    allocate(order(n), by_cell(n), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'particles_key_order', error_no_memory('work arrays'))
      return
    end if
    call counting_sort(cell, ncell, [(s, s = 1, n)], by_cell)
    call counting_sort(mat, nmat, by_cell, order)
    s = 1
    do k = 2, n + 1
      if (k <= n) then
        if (mat(order(k)) == mat(order(s)) .and. cell(order(k)) == cell(order(s))) cycle
      end if
      ! (the run s .. k-1 of one material and cell)
      do i = s + 1, k - 1
        q = order(i)
        j = i
        do while (j > s)
          if (id(order(j - 1)) < id(q)) exit
          order(j) = order(j - 1)
          j = j - 1
        end do
        order(j) = q
      end do
      s = k
    end do
  end subroutine particles_key_order

  !> The particles pick(:) of p, in that order (a permutation, or a subset:
  !> np becomes size(pick)); the binning is then stale (`particles_index`).
  subroutine particles_select(p, pick)
    type(particles_t), intent(inout) :: p
    integer, intent(in) :: pick(:)
    p%np = size(pick)
    p%id = p%id(pick)
    p%mat = p%mat(pick)
    p%body = p%body(pick)
    p%cell = p%cell(pick)
    p%xi = p%xi(:, pick)
    p%x = p%x(:, pick)
    p%v = p%v(:, pick)
    p%m = p%m(pick)
    p%vol = p%vol(pick)
    p%rho = p%rho(pick)
    p%e = p%e(pick)
    p%stress = p%stress(:, pick)
    p%hist = p%hist(:, pick)
    p%lsup = p%lsup(pick)
    if (allocated(p%mvf)) p%mvf = p%mvf(pick)
    if (allocated(p%perm)) deallocate(p%perm)
  end subroutine particles_select

  !> q: the particles pick of p (in that order) with the fields a restart
  !> holds (`particles_register_restart`, each copied through the two
  !> registries; a frame writes some of them), not their pieces and bins.
  subroutine particles_take_fields(p, pick, q, err)
    type(particles_t), intent(inout), target :: p
    integer, intent(in) :: pick(:)
    type(particles_t), intent(inout), target :: q
    type(error_t), allocatable, intent(inout) :: err
    type(registry_t) :: rp, rq
    integer :: e, m, k, stat
    call particles_allocate(q, size(pick), p%nsolid, p%nhist, err)
    if (allocated(err)) return
    q%spread = p%spread
    if (allocated(p%mvf)) then
      allocate(q%mvf(size(pick)), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'particles_take_fields', error_no_memory(itoa(size(pick))//' particles'))
        return
      end if
    end if
    call particles_register_restart(p, rp)
    call particles_register_restart(q, rq)
    do e = 1, rp%n
      associate (a => rp%e(e), b => rq%e(e))
        m = product(a%dims(1:size(a%dims) - 1))
        do k = 1, size(pick)
          if (associated(a%r)) then
            b%r(m*(k - 1) + 1:m*k) = a%r(m*(pick(k) - 1) + 1:m*pick(k))
          else
            b%i(m*(k - 1) + 1:m*k) = a%i(m*(pick(k) - 1) + 1:m*pick(k))
          end if
        end do
      end associate
    end do
  end subroutine particles_take_fields

  !> cnt(s, c): the particles of solid s hosted by cell c (cnt(nsolid, ncell)).
  subroutine particles_cell_counts(p, cnt)
    type(particles_t), intent(in) :: p
    integer, intent(out) :: cnt(:, :)
    integer :: k
    cnt = 0
    do k = 1, p%np
      cnt(p%mat(k), p%cell(k)) = cnt(p%mat(k), p%cell(k)) + 1
    end do
  end subroutine particles_cell_counts

  !> The 0-based places pos(np) of p's particles in an order by solid, then
  !> host cell, then id, given where each solid's start (first(s)) and, at
  !> each host cell, how many of the solid's particles come before its
  !> cell (before(s, c)): p in that order (`particles_order`), the j-th of
  !> a solid's particles in a cell at before + j - 1. ordered: whether the
  !> places increase (false if p is not in that order).
  subroutine particles_places(p, first, before, pos, ordered)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: first(:), before(:, :)
    integer, intent(out) :: pos(:)
    logical, intent(out) :: ordered
    integer :: k, j
    ordered = .true.
    j = 0
    do k = 1, p%np
      j = j + 1
      if (k > 1) j = merge(j, 1, p%mat(k) == p%mat(max(k - 1, 1)) .and. p%cell(k) == p%cell(max(k - 1, 1)))
      pos(k) = first(p%mat(k)) + before(p%mat(k), p%cell(k)) + j - 1
    end do
    if (p%np > 1) ordered = all(pos(2:p%np) > pos(1:p%np - 1))
  end subroutine particles_places

  !> The particles of solid s in seeding-id order (p%id, 1..p%np): their
  !> indices in p.
  subroutine particles_solid_order(p, s, order, err)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: s
    integer, allocatable, intent(out) :: order(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: at(:)
    integer :: k, i, stat
    allocate(order(p%mat_start(s + 1) - p%mat_start(s)), at(p%np), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'particles_solid_order', error_no_memory('work arrays'))
      return
    end if
    at = 0
    do k = p%mat_start(s), p%mat_start(s + 1) - 1
      at(p%id(k)) = k
    end do
    i = 0
    do k = 1, p%np
      if (at(k) > 0) then
        i = i + 1
        order(i) = at(k)
      end if
    end do
  end subroutine particles_solid_order

  !> The material ranges (mat_start) and the cell binning of particles
  !> already sorted by material (as after a restart read: the stored order
  !> is kept, so a continued run sees the arrays of the straight run).
  subroutine particles_index(p, ncell, err)
    type(particles_t), intent(inout) :: p
    integer, intent(in) :: ncell
    type(error_t), allocatable, intent(inout) :: err
    integer :: s
    if (.not. allocated(p%id)) return   ! (a block may hold none of them)
    if (any(p%mat(2:) < p%mat(:p%np - 1))) then
      call error_set(err, 'particles_index', 'the particles are not sorted by material')
      return
    end if
    p%mat_start(1) = 1
    do s = 1, p%nsolid
      p%mat_start(s + 1) = p%mat_start(s) + count(p%mat == s)
    end do
    call particles_bin(p, ncell, err)
  end subroutine particles_index

  !> The binning of the particles by host cell (cell_start, perm), by a
  !> counting sort of the current array order (within a cell: array order).
  subroutine particles_bin(p, ncell, err)
    type(particles_t), intent(inout) :: p
    integer, intent(in) :: ncell
    type(error_t), allocatable, intent(inout) :: err
    integer :: k, c, stat, cap
    character(len=200) :: msg
    if (.not. allocated(p%id)) return   ! (a block may hold none of them)
    if (allocated(p%cell_start)) deallocate(p%cell_start)
    allocate(p%cell_start(ncell + 1), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'particles_bin', error_no_memory('the cell index'))
      return
    end if
    if (.not. allocated(p%perm)) then
      allocate(p%perm(p%np), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'particles_bin', error_no_memory('the cell index'))
        return
      end if
    end if
    ! counts, then exclusive prefix sums, then placement in array order
    p%cell_start = 0
    do k = 1, p%np
      c = p%cell(k)
      p%cell_start(c + 1) = p%cell_start(c + 1) + 1
    end do
    p%cell_start(1) = 1
    do c = 1, ncell
      p%cell_start(c + 1) = p%cell_start(c + 1) + p%cell_start(c)
    end do
    call counting_sort(p%cell, ncell, [(k, k = 1, p%np)], p%perm)
    ! one piece per particle, its host (room for eight when they are to be
    ! spread, `particles_spread`)
    cap = merge(8, 1, p%spread)*p%np
    if (allocated(p%pfirst)) deallocate(p%pfirst, p%pcell, p%ppart, p%pxi, p%pw, p%pc_start, p%pc_perm, p%cpart, &
                                        p%cw, p%cxi)
    allocate(p%pfirst(p%np + 1), p%pcell(cap), p%ppart(cap), p%pxi(3, cap), p%pw(cap), p%pc_start(ncell + 1), &
             p%pc_perm(cap), p%cpart(cap), p%cw(cap), p%cxi(3, cap), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'particles_bin', error_no_memory('the particles'' pieces'))
      return
    end if
    p%npc = p%np
    p%pfirst = [(k, k = 1, p%np + 1)]
    p%pcell(:p%np) = p%cell
    p%ppart(:p%np) = [(k, k = 1, p%np)]
    p%pxi(:, :p%np) = p%xi
    p%pw(:p%np) = 1.0_wp
    p%pc_start = p%cell_start
    p%pc_perm(:p%np) = p%perm
    call particles_pieces_by_cell(p)
    p%spread_ready = .not. p%spread
  end subroutine particles_bin

  !> to takes from's particles: every allocatable component moved (no copy,
  !> so no allocation that could fail; an intrinsic assignment copies each
  !> array and stops the run where memory is short), from left empty. A
  !> component added to particles_t must be moved here too.
  subroutine particles_move(from, to)
    type(particles_t), intent(inout) :: from
    type(particles_t), intent(inout) :: to
    to%np = from%np
    to%nsolid = from%nsolid
    to%nhist = from%nhist
    to%spread = from%spread
    to%spread_ready = from%spread_ready
    to%npc = from%npc
    call move_alloc(from%id, to%id)
    call move_alloc(from%mat, to%mat)
    call move_alloc(from%body, to%body)
    call move_alloc(from%cell, to%cell)
    call move_alloc(from%xi, to%xi)
    call move_alloc(from%x, to%x)
    call move_alloc(from%v, to%v)
    call move_alloc(from%m, to%m)
    call move_alloc(from%vol, to%vol)
    call move_alloc(from%rho, to%rho)
    call move_alloc(from%stress, to%stress)
    call move_alloc(from%hist, to%hist)
    call move_alloc(from%e, to%e)
    call move_alloc(from%mvf, to%mvf)
    call move_alloc(from%mat_start, to%mat_start)
    call move_alloc(from%cell_start, to%cell_start)
    call move_alloc(from%perm, to%perm)
    call move_alloc(from%lsup, to%lsup)
    call move_alloc(from%pfirst, to%pfirst)
    call move_alloc(from%pcell, to%pcell)
    call move_alloc(from%ppart, to%ppart)
    call move_alloc(from%pxi, to%pxi)
    call move_alloc(from%pw, to%pw)
    call move_alloc(from%pc_start, to%pc_start)
    call move_alloc(from%pc_perm, to%pc_perm)
    call move_alloc(from%cpart, to%cpart)
    call move_alloc(from%cw, to%cw)
    call move_alloc(from%cxi, to%cxi)
    from = particles_t()
  end subroutine particles_move

  !> The pieces' particle, weight and centre copied in pc_perm's order
  !> (cpart, cw, cxi), after pc_perm is made.
  subroutine particles_pieces_by_cell(p)
    type(particles_t), intent(inout) :: p
    integer :: q, j
    do q = 1, p%npc
      j = p%pc_perm(q)
      p%cpart(q) = p%ppart(j)
      p%cw(q) = p%pw(j)
      p%cxi(:, q) = p%pxi(:, j)
    end do
  end subroutine particles_pieces_by_cell

  !> out = items stably sorted by key(items) in 1..nkey (key(i) the key of
  !> particle i; items a list of particle indices).
  pure subroutine counting_sort(key, nkey, items, out)
    integer, intent(in) :: key(:), nkey, items(:)
    integer, intent(out) :: out(:)
    integer :: next(nkey + 1), k, j
    next = 0
    do k = 1, size(items)
      j = key(items(k))
      next(j + 1) = next(j + 1) + 1
    end do
    next(1) = 1
    do j = 1, nkey
      next(j + 1) = next(j + 1) + next(j)
    end do
    do k = 1, size(items)
      j = key(items(k))
      out(next(j)) = items(k)
      next(j) = next(j) + 1
    end do
  end subroutine counting_sort

  !> Registers the particles' restart fields (nothing without particles):
  !> everything that is state; the binning and mat_start are rebuilt from it
  !> (`particles_check`, then `particles_index`).
  subroutine particles_register_restart(p, reg)
    type(particles_t), intent(inout), target :: p
    type(registry_t), intent(inout) :: reg
    if (.not. allocated(p%id)) return   ! (a block may hold none of them)
    call reg%add('particle_id', '1', LOC_PARTICLE, p%id)
    call reg%add('particle_material', '1', LOC_PARTICLE, p%mat)
    call reg%add('particle_body', '1', LOC_PARTICLE, p%body)
    call reg%add('particle_cell', '1', LOC_PARTICLE, p%cell)
    call reg%add('particle_xi', '1', LOC_PARTICLE, p%xi)
    call reg%add('particle_x', 'length', LOC_PARTICLE, p%x)
    call reg%add('particle_velocity', 'length/time', LOC_PARTICLE, p%v)
    call reg%add('particle_mass', 'mass', LOC_PARTICLE, p%m, lower=LOWER_POSITIVE)
    call reg%add('particle_volume', 'length^3', LOC_PARTICLE, p%vol, lower=LOWER_POSITIVE)
    call reg%add('particle_density', 'mass/length^3', LOC_PARTICLE, p%rho, lower=LOWER_POSITIVE)
    call reg%add('particle_stress', 'mass/(length*time^2)', LOC_PARTICLE, p%stress)
    call reg%add('particle_energy', 'energy/mass', LOC_PARTICLE, p%e)
    if (p%nhist > 0) call reg%add('particle_history', '1', LOC_PARTICLE, p%hist)
    if (allocated(p%mvf)) call reg%add('particle_virtual_fluid_mass', 'mass', LOC_PARTICLE, p%mvf, &
                                       lower=LOWER_NONNEGATIVE)
    ! (optional: a dump written with particle_support = 'linear' has none,
    ! and a restart may change &hydro; the caller sets the widths then)
    if (p%spread) call reg%add('particle_support_width', '1', LOC_PARTICLE, p%lsup, mandatory=.false., &
                               lower=LOWER_NONNEGATIVE)
  end subroutine particles_register_restart

  !> The particles' indices after a restart read: host cells in 1..ncell,
  !> materials in 1..nsolid, ids unique in 1..idmax (the number seeded),
  !> natural coordinates in [0,1]; the message names the first particle
  !> that is not. With place (a block's share of the file: particle k at
  !> place(k) among the file's, which names it) the ids are not checked
  !> for repeats (`parallel_particles_ids` does).
  subroutine particles_check(p, ncell, idmax, err, place)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: ncell, idmax
    type(error_t), allocatable, intent(inout) :: err
    integer, intent(in), optional :: place(:)
    logical, allocatable :: seen(:)
    integer :: k, stat
    character(len=200) :: msg
    if (p%np == 0) return
    allocate(seen(merge(0, idmax, present(place))), source=.false., stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'particles_check', error_no_memory('work arrays'))
      return
    end if
    do k = 1, p%np
      if (p%cell(k) < 1 .or. p%cell(k) > ncell) then
        call bad('particle_cell', p%cell(k), 'the grid has cells 1..'//itoa(ncell))
      else if (p%mat(k) < 1 .or. p%mat(k) > p%nsolid) then
        call bad('particle_material', p%mat(k), 'this deck has solids 1..'//itoa(p%nsolid))
      else if (p%id(k) < 1 .or. p%id(k) > idmax) then
        call bad('particle_id', p%id(k), 'the deck seeds ids 1..'//itoa(idmax))
      else if (.not. all(p%xi(:, k) >= 0.0_wp .and. p%xi(:, k) <= 1.0_wp)) then
        call error_set(err, 'particles_check', 'state/particle_xi of particle '//itoa(at(k))// &
                       ' is outside [0,1]^3')
      else if (.not. present(place)) then
        if (seen(p%id(k))) call bad('particle_id', p%id(k), 'the id is repeated')
        seen(p%id(k)) = .true.
      end if
      if (allocated(err)) return
    end do
  contains
    subroutine bad(name, value, rule)
      character(len=*), intent(in) :: name, rule
      integer, intent(in) :: value
      call error_set(err, 'particles_check', 'state/'//name//' = '//itoa(value)//' at particle '// &
                     itoa(at(k))//' ('//rule//')')
    end subroutine bad
    integer function at(k)
      integer, intent(in) :: k
      at = k
      if (present(place)) at = place(k)
    end function at
  end subroutine particles_check
end module particles_state
