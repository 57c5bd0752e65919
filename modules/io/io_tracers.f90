!> Tracers: massless material points and their histories, as plain text.
!>
!> What a tracer is. A point of the material: in the Lagrangian phase it
!> moves with the grid, so it is stored as the cell that contains it and its
!> natural coordinates xi in that cell, and its position is the trilinear
!> map of the cell's moving nodes at xi (`hex_trilinear`): exact for a
!> Lagrangian run, where every point of a cell moves by the trilinear
!> interpolation of its nodes' displacements (the nodes are material points
!> of the staggered scheme and the velocity is trilinear in a cell), and
!> at a node the tracer is that node (xi = +-1 gives it exactly). At an
!> Euler step the grid moves under the material: the tracer keeps its
!> physical position (placed on the old grid, `tracers_place`) and is
!> relocated on the new one (`tracers_relocate`: its cell found and the
!> trilinear map inverted by Newton, `gauge_locate`, which puts a point on
!> a face in the cell with the lowest indices whatever the search started
!> from). Newton stops at a residual of 1e-14 of the cell's size, so an
!> Euler step moves a tracer by at most that much.
!>
!> Where it is stored. The cell is the whole grid's index (its single-block
!> order), the same on any number of ranks: on a decomposed run the block
!> that owns the cell places the tracer, and every block gets the answer
!> (one gather of all tracers, `share_rows`); at an Euler step the block
!> that owns the lowest cell containing the point answers (a point outside
!> every cell, which the grid's boundary left behind: the block whose
!> nearest cell has the nearest centroid, clamped into that cell). A run's
!> answers are thus those of one process, bit for bit. The cell and xi are
!> what a restart holds (`tracers_register_restart`); the position follows
!> from them.
!>
!> What is written. `<name>_tracers.txt` on the gauge schedule: time, then
!> per tracer its position and the pressure and density of the cell that
!> contains it.
module io_tracers
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_registry, only: registry_t, LOC_GLOBAL
  use base_strings, only: itoa
  use mesh_grid, only: grid_t
  use mesh_geometry, only: hex_trilinear
  use mesh_halo, only: halo_t
  use hydro_state, only: hydro_t
  use io_gauges, only: gauge_locate
  implicit none
  private
  public :: tracers_t, tracers_start, tracers_place, tracers_relocate, tracers_open, tracers_write, tracers_close, &
            tracers_register_restart, tracer_nfield, tracer_field_names

  !> Values a tracer reports per row.
  integer, parameter :: tracer_nfield = 5
  !> Their column names (a tracer's columns end in _<tracer number>).
  character(len=*), parameter :: tracer_field_names(tracer_nfield) = [character(len=8) :: &
    'x', 'y', 'z', 'pressure', 'density']

  !> The tracers (the same on every rank) and their file.
  type :: tracers_t
    integer :: n = 0
    integer :: unit = -1                  !< the history file (-1: none, or not this rank's)
    integer, allocatable :: cell(:)       !< (n) the whole grid's index of the cell that holds each
    real(wp), allocatable :: xi(:, :)     !< (3, n) its natural coordinates in that cell
    real(wp), allocatable :: x(:, :)      !< (3, n) its position at the last placement (length)
  end type tracers_t

contains

  !> The tracers at the points(3, n) (length) on the grid g: each one's cell
  !> and natural coordinates (`tracers_relocate`).
  subroutine tracers_start(tr, g, halo, points, err)
    type(tracers_t), intent(out) :: tr
    type(grid_t), intent(in) :: g
    class(halo_t), intent(in) :: halo
    real(wp), intent(in) :: points(:, :)
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    character(len=200) :: msg
    tr%n = size(points, 2)
    allocate(tr%cell(tr%n), tr%xi(3, tr%n), tr%x(3, tr%n), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'tracers_start', error_no_memory('the tracers'))
      tr%n = 0
      return
    end if
    tr%cell = 0
    tr%xi = 0.0_wp
    tr%x = points
    call tracers_relocate(tr, g, halo, placed=.true.)
  end subroutine tracers_start

  !> Registers the tracers' restart quantities (none without tracers).
  subroutine tracers_register_restart(tr, reg)
    type(tracers_t), intent(inout), target :: tr
    type(registry_t), intent(inout) :: reg
    if (tr%n == 0) return
    call reg%add('tracer_cell', '1', LOC_GLOBAL, tr%cell)
    call reg%add('tracer_xi', 'natural coordinates', LOC_GLOBAL, tr%xi)
  end subroutine tracers_register_restart

  !> The local (stored) index of the whole grid's cell gc on this block if
  !> the block owns it, else 0.
  pure integer function owned_cell(g, gc) result(c)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: gc
    integer :: ijk(3)
    c = 0
    if (gc < 1) return
    ijk(1) = mod(gc - 1, g%gn(1)) + 1
    ijk(2) = mod((gc - 1)/g%gn(1), g%gn(2)) + 1
    ijk(3) = (gc - 1)/(g%gn(1)*g%gn(2)) + 1
    ijk = ijk - g%off
    if (.not. g%owns_cell(ijk(1), ijk(2), ijk(3))) return
    c = g%cell(ijk(1), ijk(2), ijk(3))
  end function owned_cell

  !> Each tracer's position, the trilinear map of its cell's nodes at its
  !> xi, into tr%x (length): on each block for the tracers in the cells it
  !> owns; with `halo` shared with every block (one gather), without (the
  !> driver's step before an Euler phase, which shares them only when the
  !> grid is rezoned) the others keep what they had.
  subroutine tracers_place(tr, g, halo)
    type(tracers_t), intent(inout) :: tr
    type(grid_t), intent(in) :: g
    class(halo_t), intent(in), optional :: halo
    real(wp) :: key(tr%n), xn(3, 8)
    integer :: k, c
    if (tr%n == 0) return
    do k = 1, tr%n
      c = owned_cell(g, tr%cell(k))
      key(k) = merge(0.0_wp, 1.0_wp, c > 0)
      if (c == 0) cycle
      call g%gather(c, g%x, xn)
      tr%x(:, k) = hex_trilinear(xn, tr%xi(:, k))
    end do
    if (present(halo)) call share_rows(halo, key, tr%x)
  end subroutine tracers_place

  !> After the grid has moved under the material (an Euler step): each
  !> tracer, at its position tr%x (placed on the old grid, `tracers_place`
  !> without halo, unless `placed` says they are shared already), found on
  !> the new grid: its cell (the lowest of the whole grid that contains the
  !> point; outside every cell, the nearest by centroid) and its natural
  !> coordinates there, the same on every block.
  subroutine tracers_relocate(tr, g, halo, placed)
    type(tracers_t), intent(inout) :: tr
    type(grid_t), intent(in) :: g
    class(halo_t), intent(in) :: halo
    logical, intent(in), optional :: placed
    real(wp) :: key(tr%n), rows(5, tr%n), xi(3), xn(3, 8), d(3)
    integer :: k, c, c0, ijk(3)
    logical :: inside, shared

    if (tr%n == 0) return
    shared = .false.
    if (present(placed)) shared = placed
    if (.not. shared) then
      ! (the positions from the blocks that placed them)
      do k = 1, tr%n
        key(k) = merge(0.0_wp, 1.0_wp, owned_cell(g, tr%cell(k)) > 0)
      end do
      call share_rows(halo, key, tr%x)
    end if
    do k = 1, tr%n
      ! (searched from the old cell where this block owns it: the cheapest
      ! start; the answer does not depend on it)
      c0 = owned_cell(g, tr%cell(k))
      call gauge_locate(g, tr%x(:, k), c0, c, xi, inside)
      call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
      ! rows: the key among the blocks whose cell contains the point (the
      ! lowest global cell), the key among the others (the squared
      ! distance to the nearest cell's centroid), the cell and xi
      rows(1, k) = huge(1.0_wp)
      rows(2, k) = huge(1.0_wp)
      if (g%owns_cell(ijk(1), ijk(2), ijk(3))) then
        if (inside) rows(1, k) = real(g%global_cell(c), wp)
        call g%gather(c, g%x, xn)
        d = sum(xn, dim=2)/8.0_wp - tr%x(:, k)
        rows(2, k) = dot_product(d, d)
      end if
      rows(3, k) = real(g%global_cell(c), wp)
      rows(4:5, k) = xi(1:2)
      key(k) = xi(3)
    end do
    call choose_located(halo, rows, key)
    do k = 1, tr%n
      tr%cell(k) = nint(rows(3, k))
      tr%xi(1:2, k) = rows(4:5, k)
      tr%xi(3, k) = key(k)
    end do
  end subroutine tracers_relocate

  !> For each tracer k, the block's answer (rows(:, k), with the third
  !> natural coordinate in xi3(k)) that has the smallest rows(1, k) (the
  !> lowest global cell that contains the point) or, when no block's cell
  !> contains it, the smallest rows(2, k); the lowest block on a tie.
  subroutine choose_located(halo, rows, xi3)
    class(halo_t), intent(in) :: halo
    real(wp), intent(inout) :: rows(:, :), xi3(:)
    real(wp), allocatable :: packed(:), w(:)
    integer :: n, m, k, b, nb, at, best, stat
    n = size(rows, 2)
    m = size(rows, 1) + 1
    allocate(packed(m*n), stat=stat)
    if (stat /= 0) return   ! (a few numbers per tracer)
    do k = 1, n
      packed(m*(k - 1) + 1:m*k - 1) = rows(:, k)
      packed(m*k) = xi3(k)
    end do
    call halo%concat(packed, w)
    nb = size(w)/(m*n)
    do k = 1, n
      best = m*(k - 1)
      do b = 2, nb
        at = m*n*(b - 1) + m*(k - 1)
        if (w(at + 1) < w(best + 1)) then
          best = at
        else if (.not. w(best + 1) < huge(1.0_wp) .and. .not. w(at + 1) < huge(1.0_wp) .and. &
                 w(at + 2) < w(best + 2)) then
          best = at
        end if
      end do
      rows(:, k) = w(best + 1:best + m - 1)
      xi3(k) = w(best + m)
    end do
  end subroutine choose_located

  !> For each tracer k, the values vals(:, k) of the block with the smallest
  !> key(k) (0: the block that owns the tracer's cell), the lowest block on
  !> a tie: one gather for all tracers. Nothing to do on one block.
  subroutine share_rows(halo, key, vals)
    class(halo_t), intent(in) :: halo
    real(wp), intent(in) :: key(:)
    real(wp), intent(inout) :: vals(:, :)
    real(wp), allocatable :: packed(:), w(:)
    integer :: n, m, k, b, nb, at, best, stat
    if (halo%nblocks == 1) return
    n = size(vals, 2)
    m = size(vals, 1) + 1
    allocate(packed(m*n), stat=stat)
    if (stat /= 0) return   ! (a few numbers per tracer)
    do k = 1, n
      packed(m*(k - 1) + 1) = key(k)
      packed(m*(k - 1) + 2:m*k) = vals(:, k)
    end do
    call halo%concat(packed, w)
    nb = size(w)/(m*n)
    do k = 1, n
      best = m*(k - 1)
      do b = 2, nb
        at = m*n*(b - 1) + m*(k - 1)
        if (w(at + 1) < w(best + 1)) best = at
      end do
      vals(:, k) = w(best + 2:best + m)
    end do
  end subroutine share_rows

  !> Opens the history file at `path` for the tracers starting at
  !> points(3, n) (length) and writes its header (comment lines starting
  !> with '#', the last naming every column), or (append, on a restart)
  !> adds rows to the existing file (a new one if it is missing).
  subroutine tracers_open(tr, path, points, append, err)
    type(tracers_t), intent(inout) :: tr
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: points(:, :)
    logical, intent(in) :: append
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios, k, f
    character(len=256) :: msg
    character(len=:), allocatable :: names
    logical :: exists, new

    if (tr%n == 0) return
    inquire(file=path, exist=exists)
    new = .not. (append .and. exists)
    if (new) then
      open(newunit=tr%unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
    else
      open(newunit=tr%unit, file=path, status='old', position='append', action='write', iostat=ios, iomsg=msg)
    end if
    if (ios /= 0) then
      call error_set(err, 'tracers_open', 'cannot open '''//path//''': '//trim(msg))
      tr%unit = -1
      return
    end if
    if (.not. new) return
    write(tr%unit, '(a)') '# tracers (lsalepm): massless material points, moving with the grid in the '// &
      'Lagrangian phase (the trilinear map of their cell''s nodes) and keeping their position through Euler '// &
      'steps (io_tracers.f90); a row on the gauge schedule (&output gauge_dt): time, then per tracer k its '// &
      'position and the pressure and density of the cell that holds it; the last header row names the columns'
    do k = 1, tr%n
      write(tr%unit, '(a,i0,a,3es25.16e3)') '# tracer ', k, ' from ', points(:, k)
    end do
    names = '# time'
    do k = 1, tr%n
      do f = 1, tracer_nfield
        names = names//' '//trim(tracer_field_names(f))//'_'//itoa(k)
      end do
    end do
    write(tr%unit, '(a)') names
    flush(tr%unit)
  end subroutine tracers_open

  !> Appends one row at time t (the block with the file writes it): each
  !> tracer placed on the grid (its position is kept in tr%x on every
  !> block) with the pressure and density of its cell.
  subroutine tracers_write(tr, g, h, t, halo)
    type(tracers_t), intent(inout) :: tr
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    real(wp), intent(in) :: t
    class(halo_t), intent(in) :: halo
    real(wp) :: key(tr%n), vals(tracer_nfield, tr%n), xn(3, 8)
    integer :: k, c
    character(len=32) :: fmt
    if (tr%n == 0) return
    vals = 0.0_wp
    do k = 1, tr%n
      c = owned_cell(g, tr%cell(k))
      key(k) = merge(0.0_wp, 1.0_wp, c > 0)
      if (c == 0) cycle
      call g%gather(c, g%x, xn)
      vals(1:3, k) = hex_trilinear(xn, tr%xi(:, k))
      vals(4, k) = h%p(c)
      vals(5, k) = h%rho(c)
    end do
    call share_rows(halo, key, vals)
    tr%x = vals(1:3, :)
    if (tr%unit == -1) return
    write(fmt, '(a,i0,a)') '(', 1 + tracer_nfield*tr%n, 'es25.16e3)'
    write(tr%unit, fmt) t, vals
    flush(tr%unit)
  end subroutine tracers_write

  subroutine tracers_close(tr)
    type(tracers_t), intent(inout) :: tr
    if (tr%unit /= -1) close(tr%unit)
    tr%unit = -1
  end subroutine tracers_close
end module io_tracers
