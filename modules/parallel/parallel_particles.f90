!> The particles of a decomposed run between the whole run's arrays and a
!> block's: a block takes the particles its cells host from the whole
!> run's (`parallel_particles_take`), and the blocks' owned particles are
!> gathered back into the whole run's order on every rank
!> (`parallel_particles_gather`). The order is the keys' (material, host
!> cell, id: `particles_order`), the same on a block as on one process.
!> Between Euler steps' relocations on the blocks, `parallel_particles_move`
!> sends each block's owned particles to every block whose cells or ghost
!> layers host them: no rank holds more than its block's. A walk to a
!> particle's host that steps past a block's cut is taken on by the blocks
!> beyond it (`parallel_walks`).
module parallel_particles
  use, intrinsic :: iso_fortran_env, only: int64
  use base_kinds, only: wp
  use base_sort, only: sort_order
  use base_errors, only: error_no_memory, error_t, error_set
  use base_registry, only: registry_t, K_REAL
  use mesh_grid, only: grid_t, grid_index_t
  use particles_state, only: particles_t, particles_allocate, particles_select, particles_index, &
                             particles_register_restart, particles_key_order, particles_order, particles_move
  use particles_shape, only: particles_locate
  use parallel_comm, only: comm_t, parallel_nomem, parallel_sum
  use parallel_gather, only: gather_concat, exchange_lists
  implicit none
  private
  public :: parallel_particles_take, parallel_particles_gather, parallel_particles_move, parallel_mark_cells, &
            parallel_particles_ids, parallel_walks

contains

  !> The particles of w (host cells numbered on the whole grid's index wix)
  !> whose host is one of g's owned cells or lies in the `layers` ghost
  !> layers around them, into pt in w's order with their host cells
  !> numbered in g and indexed; owned: which of them g owns.
  subroutine parallel_particles_take(w, wix, g, layers, pt, owned, err)
    type(particles_t), intent(in) :: w
    type(grid_index_t), intent(in) :: wix
    type(grid_t), intent(in) :: g
    integer, intent(in) :: layers
    type(particles_t), intent(out) :: pt
    logical, allocatable, intent(out) :: owned(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: all(:), pick(:)
    integer :: k, n, q, lo(3), hi(3), ijk(3), stat
    call g%cells_around(layers, lo, hi)
    allocate(all(w%np), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'parallel_particles_take', error_no_memory('work arrays'))
      return
    end if
    n = 0
    do k = 1, w%np
      call wix%cell_ijk(w%cell(k), ijk(1), ijk(2), ijk(3))
      ijk = ijk - g%off
      if (any(ijk < lo .or. ijk > hi)) cycle
      n = n + 1
      all(n) = k
    end do
    pick = all(:n)
    pt = w
    call particles_select(pt, pick)
    do q = 1, n
      call wix%cell_ijk(pt%cell(q), ijk(1), ijk(2), ijk(3))
      ijk = ijk - g%off
      pt%cell(q) = g%cell(ijk(1), ijk(2), ijk(3))
    end do
    call particles_index(pt, g%ncell, err)
    if (allocated(err)) return
    allocate(owned(n), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'parallel_particles_take', error_no_memory('work arrays'))
      return
    end if
    do q = 1, n
      call g%cell_ijk(pt%cell(q), ijk(1), ijk(2), ijk(3))
      owned(q) = g%owns_cell(ijk(1), ijk(2), ijk(3))
    end do
  end subroutine parallel_particles_take

  !> The particles of a decomposed run in the whole run's order (ptw, host
  !> cells numbered in the whole grid, sorted by material, host cell and id
  !> as one process sorts them): each block gives the ones of pt it owns
  !> (owned), host cells numbered on g. On every rank (collective).
  subroutine parallel_particles_gather(pc, g, pt, owned, ptw, err)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout), target :: pt
    logical, intent(in) :: owned(:)
    type(particles_t), intent(inout), target :: ptw
    type(error_t), allocatable, intent(inout) :: err
    type(registry_t) :: rb, rw
    integer, allocatable :: own(:), at(:), iw(:), cells(:), mat(:), cell(:), id(:), order(:)
    real(wp), allocatable :: rw_(:)
    integer :: k, e, m, q, j, stat

    own = pack([(k, k = 1, pt%np)], owned)
    ! (host cells in the whole grid's numbering while they are sent)
    cells = pt%cell
    do k = 1, pt%np
      pt%cell(k) = g%global_cell(cells(k))
    end do
    ! each gathered particle's place in the whole order
    call gather_concat(pc, pt%mat(own), mat)
    call gather_concat(pc, pt%cell(own), cell)
    call gather_concat(pc, pt%id(own), id)
    call particles_key_order(mat, pt%nsolid, cell, product(g%gn), id, order, err)
    if (.not. allocated(err)) call particles_allocate(ptw, size(order), pt%nsolid, pt%nhist, err)
    if (allocated(err)) then
      pt%cell = cells
      return
    end if
    allocate(at(size(order)), stat=stat)
    if (stat == 0 .and. allocated(pt%mvf)) allocate(ptw%mvf(size(order)), stat=stat)
    if (stat /= 0) then
      pt%cell = cells
      call error_set(err, 'parallel_particles_gather', error_no_memory('the gathered particles'))
      return
    end if
    at(order) = [(q, q = 1, size(order))]
    ptw%spread = pt%spread
    call particles_register_restart(pt, rb)
    call particles_register_restart(ptw, rw)
    do e = 1, rb%n
      associate (b => rb%e(e), v => rw%e(e))
        m = product(b%dims(1:size(b%dims) - 1))
        if (b%kind == K_REAL) then
          call gather_concat(pc, [((b%r(m*(own(q) - 1) + j), j = 1, m), q = 1, size(own))], rw_)
          do q = 1, size(at)
            v%r(m*(at(q) - 1) + 1:m*at(q)) = rw_(m*(q - 1) + 1:m*q)
          end do
        else
          call gather_concat(pc, [((b%i(m*(own(q) - 1) + j), j = 1, m), q = 1, size(own))], iw)
          do q = 1, size(at)
            v%i(m*(at(q) - 1) + 1:m*at(q)) = iw(m*(q - 1) + 1:m*q)
          end do
        end if
      end associate
    end do
    pt%cell = cells
  end subroutine parallel_particles_gather

  !> The particles of the blocks after their owned ones changed host (an
  !> Euler step's relocation on each block): each rank's owned particles of
  !> pt (owned; host cells numbered on its g, in its cells or ghost layers)
  !> go to every rank whose owned cells or `layers` ghost layers around them
  !> hold their host, itself included; pt becomes what this rank receives,
  !> host cells numbered on g, sorted (`particles_order`, the order one
  !> process gives them) and indexed, and owned which of them g owns. The
  !> others' blocks are each rank's box, gathered (6 integers per rank); a
  !> particle can go only to the ranks whose boxes meet this block's stored
  !> cells (its neighbours: the work and the list of receivers per particle
  !> grow with them, not with the number of ranks). Collective.
  subroutine parallel_particles_move(pc, g, layers, pt, owned, err, route)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    integer, intent(in) :: layers
    type(particles_t), intent(inout), target :: pt
    logical, allocatable, intent(inout) :: owned(:)
    type(error_t), allocatable, intent(inout) :: err
    !> (np; with layers = 0) each particle's host as a cell of the whole
    !> grid, any of them (pt%cell is then not read): it goes to the rank
    !> that owns that cell, a neighbour or not
    integer, intent(in), optional :: route(:)
    type(particles_t), target :: pn
    type(registry_t) :: rb, rn
    integer, allocatable :: boxes(:), to(:, :), count_to(:), at(:), near(:)
    real(wp), allocatable :: sbuf(:), rbuf(:)
    integer :: lo(3), hi(3), ijk(3), k, r, e, m, j, q, n, rec, pos, stat, nr, c
    logical :: skip

    nr = pc%nranks
    call g%cells_around(layers, lo, hi)
    call gather_concat(pc, [lo + g%off, hi + g%off], boxes)
    ! (the ranks whose boxes meet this block's stored cells, in rank order)
    near = pack([(r, r = 0, nr - 1)], [(all(boxes(6*r + 1:6*r + 3) <= g%shi + g%off) .and. &
                                        all(boxes(6*r + 4:6*r + 6) >= g%slo + g%off), r = 0, nr - 1)])
    ! (each owned particle's receivers, in rank order: to(:, k), -1 ends;
    ! routed, the owner of its cell, found among all ranks)
    allocate(to(max(size(near), 1), pt%np), count_to(0:nr - 1), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'parallel_particles_move', error_no_memory('work arrays'))
      return
    end if
    to = -1
    count_to = 0
    do k = 1, pt%np
      if (.not. owned(k)) cycle
      if (present(route)) then
        ijk = global_ijk(g, route(k))
        r = owner_of(ijk)
        if (r < 0) cycle
        to(1, k) = r
        count_to(r) = count_to(r) + 1
        cycle
      end if
      call g%cell_ijk(pt%cell(k), ijk(1), ijk(2), ijk(3))
      ijk = ijk + g%off
      n = 0
      do c = 1, size(near)
        r = near(c)
        if (any(ijk < boxes(6*r + 1:6*r + 3) .or. ijk > boxes(6*r + 4:6*r + 6))) cycle
        n = n + 1
        to(n, k) = r
        count_to(r) = count_to(r) + 1
      end do
    end do
    ! (host cells in the whole grid's numbering while they are sent)
    at = pt%cell
    if (present(route)) then
      pt%cell = route
    else
      do k = 1, pt%np
        pt%cell(k) = g%global_cell(at(k))
      end do
    end if
    call particles_register_restart(pt, rb)
    rec = 0
    do e = 1, rb%n
      rec = rec + product(rb%e(e)%dims(1:size(rb%e(e)%dims) - 1))
    end do
    allocate(sbuf(rec*sum(count_to)), stat=stat)
    call parallel_nomem(stat, 'the particles sent')
    ! (each receiver's records in turn, in this rank's order)
    pos = 0
    if (present(route)) near = [(r, r = 0, nr - 1)]
    do c = 1, size(near)
      r = near(c)
      if (count_to(r) == 0) cycle
      do k = 1, pt%np
        if (.not. any(to(:, k) == r)) cycle
        do e = 1, rb%n
          associate (b => rb%e(e))
            m = product(b%dims(1:size(b%dims) - 1))
            if (b%kind == K_REAL) then
              sbuf(pos + 1:pos + m) = b%r(m*(k - 1) + 1:m*k)
            else
              sbuf(pos + 1:pos + m) = real(b%i(m*(k - 1) + 1:m*k), wp)
            end if
            pos = pos + m
          end associate
        end do
      end do
    end do
    pt%cell = at
    call exchange_lists(pc, sbuf, rec*count_to, rbuf)
    deallocate(sbuf)
    n = size(rbuf)/max(rec, 1)
    call particles_allocate(pn, n, pt%nsolid, pt%nhist, err)
    skip = allocated(err)
    if (.not. skip .and. allocated(pt%mvf)) then
      allocate(pn%mvf(n), stat=stat)
      if (stat /= 0) call error_set(err, 'parallel_particles_move', error_no_memory('the particles received'))
    end if
    if (allocated(err)) return
    pn%spread = pt%spread
    call particles_register_restart(pn, rn)
    pos = 0
    do q = 1, n
      do e = 1, rn%n
        associate (v => rn%e(e))
          m = product(v%dims(1:size(v%dims) - 1))
          if (v%kind == K_REAL) then
            v%r(m*(q - 1) + 1:m*q) = rbuf(pos + 1:pos + m)
          else
            v%i(m*(q - 1) + 1:m*q) = [(nint(rbuf(pos + j)), j = 1, m)]
          end if
          pos = pos + m
        end associate
      end do
    end do
    do q = 1, n
      ijk = global_ijk(g, pn%cell(q)) - g%off
      pn%cell(q) = g%cell(ijk(1), ijk(2), ijk(3))
    end do
    call particles_order(pn, g%ncell, err)
    if (allocated(err)) return
    call particles_move(pn, pt)
    deallocate(owned)
    allocate(owned(pt%np), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'parallel_particles_move', error_no_memory('work arrays'))
      return
    end if
    do q = 1, pt%np
      call g%cell_ijk(pt%cell(q), ijk(1), ijk(2), ijk(3))
      owned(q) = g%owns_cell(ijk(1), ijk(2), ijk(3))
    end do
  contains
    !> The rank whose owned cells (boxes, layers = 0) hold whole-grid
    !> cell ijk (-1: none).
    integer function owner_of(ijk) result(o)
      integer, intent(in) :: ijk(3)
      integer :: rr
      o = -1
      do rr = 0, nr - 1
        if (all(ijk >= boxes(6*rr + 1:6*rr + 3) .and. ijk <= boxes(6*rr + 4:6*rr + 6))) then
          o = rr
          return
        end if
      end do
    end function owner_of
  end subroutine parallel_particles_move

  !> The owned cells of g that any rank names (cells: global cell numbers
  !> of the whole grid): each rank sends each cell to the rank that owns
  !> it, found among the ranks whose owned cells meet its stored cells
  !> (ranks' owned boxes gathered, 6 integers each), else among all;
  !> mark(ncell) true at the owned cells named, false elsewhere (the ghost
  !> cells are the caller's: a halo exchange). Collective.
  subroutine parallel_mark_cells(pc, g, cells, mark)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    integer, intent(in) :: cells(:)
    logical, allocatable, intent(out) :: mark(:)
    integer, allocatable :: boxes(:), to(:), near(:)
    real(wp), allocatable :: sbuf(:), rbuf(:)
    integer :: lo(3), hi(3), ijk(3), q, r, c, stat, count_to(0:pc%nranks - 1), pos(0:pc%nranks - 1)
    call g%cells_around(0, lo, hi)
    call gather_concat(pc, [lo + g%off, hi + g%off], boxes)
    ! (the ranks whose owned cells meet this block's stored cells)
    near = pack([(r, r = 0, pc%nranks - 1)], [(all(boxes(6*r + 1:6*r + 3) <= g%shi + g%off) .and. &
                                                all(boxes(6*r + 4:6*r + 6) >= g%slo + g%off), r = 0, pc%nranks - 1)])
    allocate(to(size(cells)), sbuf(size(cells)), mark(g%ncell), stat=stat)
    call parallel_nomem(stat, 'the cells marked')
    count_to = 0
    do q = 1, size(cells)
      ijk = global_ijk(g, cells(q))
      to(q) = -1
      do c = 1, size(near)
        r = near(c)
        if (all(ijk >= boxes(6*r + 1:6*r + 3) .and. ijk <= boxes(6*r + 4:6*r + 6))) then
          to(q) = r
          exit
        end if
      end do
      ! (a cell beyond the block's stored cells: a walk taken on found it,
      ! `parallel_walks`)
      if (to(q) < 0) then
        do r = 0, pc%nranks - 1
          if (all(ijk >= boxes(6*r + 1:6*r + 3) .and. ijk <= boxes(6*r + 4:6*r + 6))) then
            to(q) = r
            exit
          end if
        end do
      end if
      if (to(q) >= 0) count_to(to(q)) = count_to(to(q)) + 1
    end do
    pos(0) = 0
    do r = 1, pc%nranks - 1
      pos(r) = pos(r - 1) + count_to(r - 1)
    end do
    do q = 1, size(cells)
      if (to(q) < 0) cycle
      pos(to(q)) = pos(to(q)) + 1
      sbuf(pos(to(q))) = real(cells(q), wp)
    end do
    call exchange_lists(pc, sbuf(:sum(count_to)), count_to, rbuf)
    mark = .false.
    do q = 1, size(rbuf)
      ijk = global_ijk(g, nint(rbuf(q))) - g%off
      mark(g%cell(ijk(1), ijk(2), ijk(3))) = .true.
    end do
  end subroutine parallel_mark_cells

  !> The particles a restart read, got(4, n) (id, body, solid and place in
  !> the file of each, every block its owned ones), against those the deck
  !> seeds, seeded(3, m) (id, body, solid, every block its owned ones; ids
  !> 1..nseed), with no rank holding more than its share of the ids: each
  !> record goes to the rank whose range of ids holds its id (rank r the
  !> ids i with (i - 1) nranks / nseed = r), which finds there, in the
  !> file's order, an id read twice or a body or solid other than the
  !> seeded one. bad: the first of those in this rank's range (kind 1
  !> repeated, 2 body, 3 solid; then its id, its place in the file, the
  !> value read and the one seeded); kind 0 for none. got's ids must be
  !> in 1..nseed. Collective.
  subroutine parallel_particles_ids(pc, nseed, seeded, got, bad)
    type(comm_t), intent(in) :: pc
    integer, intent(in) :: nseed, seeded(:, :), got(:, :)
    integer, intent(out) :: bad(5)
    real(wp), allocatable :: sbuf(:), rbuf(:)
    integer, allocatable :: tab(:, :), place(:), order(:)
    integer :: scounts(0:pc%nranks - 1), pos(0:pc%nranks - 1), base, top, q, r, k, i, n, stat
    bad = 0
    scounts = 0
    do q = 1, size(seeded, 2)
      r = owner(seeded(1, q))
      scounts(r) = scounts(r) + 4
    end do
    do q = 1, size(got, 2)
      r = owner(got(1, q))
      scounts(r) = scounts(r) + 4
    end do
    pos(0) = 0
    do r = 1, pc%nranks - 1
      pos(r) = pos(r - 1) + scounts(r - 1)
    end do
    allocate(sbuf(sum(scounts)), stat=stat)
    call parallel_nomem(stat, 'the particles'' ids')
    do q = 1, size(seeded, 2)
      r = owner(seeded(1, q))
      sbuf(pos(r) + 1:pos(r) + 4) = real([seeded(:, q), 0], wp)
      pos(r) = pos(r) + 4
    end do
    do q = 1, size(got, 2)
      r = owner(got(1, q))
      sbuf(pos(r) + 1:pos(r) + 4) = real(got(:, q), wp)
      pos(r) = pos(r) + 4
    end do
    call exchange_lists(pc, sbuf, scounts, rbuf)
    ! (this rank's ids: base + 1 .. top)
    base = int((int(pc%rank, int64)*nseed + pc%nranks - 1)/pc%nranks)
    top = int((int(pc%rank + 1, int64)*nseed + pc%nranks - 1)/pc%nranks)
    n = size(rbuf)/4
    ! (tab(:, i - base): the seeded body and solid of id i, and the place
    ! it was first read at)
    call table(top - base, n, tab, place, order)
    do k = 1, n
      place(k) = nint(rbuf(4*k))
      if (place(k) > 0) cycle
      tab(1:2, nint(rbuf(4*k - 3)) - base) = nint(rbuf(4*k - 2:4*k - 1))
    end do
    call sort_order(place, order, stat)
    call parallel_nomem(stat, 'the particles'' ids')
    do q = 1, n
      k = order(q)
      if (place(k) == 0) cycle
      i = nint(rbuf(4*k - 3))
      if (tab(3, i - base) > 0) then
        bad = [1, i, place(k), i, i]
      else if (nint(rbuf(4*k - 2)) /= tab(1, i - base)) then
        bad = [2, i, place(k), nint(rbuf(4*k - 2)), tab(1, i - base)]
      else if (nint(rbuf(4*k - 1)) /= tab(2, i - base)) then
        bad = [3, i, place(k), nint(rbuf(4*k - 1)), tab(2, i - base)]
      end if
      if (bad(1) /= 0) return
      tab(3, i - base) = place(k)
    end do
  contains
    !> The work arrays (tab zero).
    subroutine table(m, n, tab, place, order)
      integer, intent(in) :: m, n
      integer, allocatable, intent(out) :: tab(:, :), place(:), order(:)
      allocate(tab(3, m), source=0, stat=stat)
      if (stat == 0) allocate(place(n), order(n), stat=stat)
      call parallel_nomem(stat, 'the particles'' ids')
    end subroutine table
    !> The rank whose range holds id.
    integer function owner(id)
      integer, intent(in) :: id
      owner = int((int(id - 1, int64)*pc%nranks)/nseed)
    end function owner
  end subroutine parallel_particles_ids

  !> Walks to the hosts of points that step past a block's cut, taken on
  !> by the blocks beyond it (collective). Each request q of this rank, the
  !> point x(:, q) and the cell start(q) of the whole grid its walk stands
  !> in, goes to the rank that owns that cell, which walks on from there in
  !> the grid with nodes xg (its stored nodes) with its own cuts
  !> (`particles_locate`; each step depends only on the cell it is in and
  !> the point, so this is the whole grid's walk, step for step); a walk
  !> that stops at that block's cut goes on to the block beyond, round
  !> after round, at most one per rank. host(q): the cell of the whole grid
  !> the walk ends in, xi(:, q) the point's natural coordinates there;
  !> host(q) = 0 where it ends in no cell (or the rounds run out).
  subroutine parallel_walks(pc, g, xg, x, start, host, xi)
    type(comm_t), intent(in) :: pc
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: xg(:, :), x(:, :)
    integer, intent(in) :: start(:)
    integer, intent(out) :: host(:)
    real(wp), intent(out) :: xi(:, :)
    !> a request's record: its point, its cell, its rank and its number there;
    !> a reply's: its rank and number, the host, xi
    integer, parameter :: rw = 6
    real(wp), allocatable :: act(:, :), rep(:, :), sbuf(:), rbuf(:), add(:, :)
    integer, allocatable :: boxes(:), dest(:), kind(:)
    integer :: lo(3), hi(3), ijk(3), nr, round, q, n(1), cell, last, stat, cnt(0:pc%nranks - 1)
    real(wp) :: xq(3), xiq(3)
    logical :: found

    nr = pc%nranks
    host = 0
    xi = 0.0_wp
    call g%cells_around(0, lo, hi)
    call gather_concat(pc, [lo + g%off, hi + g%off], boxes)
    ! (add allocated empty here, which also keeps GCC from taking its bounds
    ! for uninitialized)
    allocate(act(rw, size(start)), rep(rw, 0), add(rw, 0), stat=stat)
    call parallel_nomem(stat, 'the walks taken on')
    do q = 1, size(start)
      act(:, q) = [x(:, q), real(start(q), wp), real(pc%rank, wp), real(q, wp)]
    end do
    do round = 0, nr
      n = size(act, 2)
      call parallel_sum(pc, n)
      if (n(1) == 0) exit
      if (round == nr) then
        ! (the rounds ran out: no host)
        add = 0.0_wp*act
        add(1:2, :) = act(5:6, :)
        rep = reshape([rep, add], [rw, size(rep, 2) + size(add, 2)])
        exit
      end if
      ! (each request to the rank that owns its cell)
      dest = [(owner(nint(act(4, q))), q = 1, size(act, 2))]
      call send(act, dest)
      act = reshape(rbuf, [rw, size(rbuf)/rw])
      ! (walked on here: 1 found, 2 stopped at a cut again, 3 in no cell)
      deallocate(add)
      allocate(kind(size(act, 2)), add(rw, size(act, 2)), stat=stat)
      call parallel_nomem(stat, 'the walks taken on')
      do q = 1, size(act, 2)
        ijk = global_ijk(g, nint(act(4, q))) - g%off
        xq = act(1:3, q)
        call particles_locate(g, xq, g%cell(ijk(1), ijk(2), ijk(3)), cell, xiq, found, xg, [g%glo > 0, g%ghi > 0], &
                              at_cut=last)
        add(:, q) = [act(5:6, q), 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        if (found) then
          kind(q) = 1
          add(3:6, q) = [real(g%global_cell(cell), wp), xiq]
        else if (last > 0) then
          kind(q) = 2
          act(4, q) = real(g%global_cell(last), wp)
        else
          kind(q) = 3
        end if
      end do
      add = add(:, pack([(q, q = 1, size(act, 2))], kind /= 2))
      rep = reshape([rep, add], [rw, size(rep, 2) + size(add, 2)])
      act = act(:, pack([(q, q = 1, size(act, 2))], kind == 2))
      deallocate(kind)
    end do
    ! (the replies to the ranks that asked)
    dest = [(nint(rep(1, q)), q = 1, size(rep, 2))]
    call send(rep, dest)
    do q = 1, size(rbuf)/rw
      host(nint(rbuf(rw*(q - 1) + 2))) = nint(rbuf(rw*(q - 1) + 3))
      xi(:, nint(rbuf(rw*(q - 1) + 2))) = rbuf(rw*(q - 1) + 4:rw*q)
    end do
  contains
    !> The rank whose owned cells hold cell c of the whole grid.
    integer function owner(c) result(o)
      integer, intent(in) :: c
      integer :: r, ix(3)
      ix = global_ijk(g, c)
      do o = 0, nr - 1
        r = 6*o
        if (all(ix >= boxes(r + 1:r + 3) .and. ix <= boxes(r + 4:r + 6))) return
      end do
      o = 0   ! (every cell has an owner)
    end function owner

    !> The records rec(rw, :) to the ranks to(:), in rank order: rbuf.
    subroutine send(rec, to)
      real(wp), intent(in) :: rec(:, :)
      integer, intent(in) :: to(:)
      integer :: r, k
      do r = 0, nr - 1
        cnt(r) = rw*count(to == r)
      end do
      sbuf = [(rec(:, pack([(k, k = 1, size(to))], to == r)), r = 0, nr - 1)]
      call exchange_lists(pc, sbuf, cnt, rbuf)
    end subroutine send
  end subroutine parallel_walks

  !> The indices of global cell c of the whole grid (g%gn).
  pure function global_ijk(g, c) result(ix)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: c
    integer :: ix(3)
    ix(1) = mod(c - 1, g%gn(1)) + 1
    ix(2) = mod((c - 1)/g%gn(1), g%gn(2)) + 1
    ix(3) = (c - 1)/(g%gn(1)*g%gn(2)) + 1
  end function global_ijk
end module parallel_particles
