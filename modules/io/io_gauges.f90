!> Gauge time histories: the flow at fixed points, as plain text columns.
!>
!> Where. A gauge lives in the cell that contains its point, with the
!> natural coordinates xi of the point in it (the inverse of the cell's
!> trilinear map, by Newton). The previous row's cell is tried first; if the
!> point has left it, a walk by nearest centroid from there and a look at the
!> 26 neighbours of where it ends find the new one (`gauge_locate`); a
!> point on a face shared by cells belongs to the one with the lowest
!> indices, wherever the search started (so a restarted run, which starts
!> from cell 1, reads the same cell as the straight run). A point
!> that the boundary has left behind reads the nearest boundary cell at
!> clamped xi.
!>
!> What. Node fields (velocity) are interpolated with the trilinear shape
!> functions of the containing cell at xi: exact for a linear velocity field
!> on any grid and continuous across faces, as the shape functions are.
!> Cell-centred fields (density, pressure, specific internal energy, sound
!> speed) are interpolated trilinearly in logical space between the centres
!> of the 2 x 2 x 2 cells around the point: the point's logical coordinate
!> along d is s_d = i_d + xi_d/2 (cell centres at whole numbers, faces at
!> halves), and the field is the tensor-product linear interpolation of the
!> cell values at floor(s) and floor(s)+1. This is continuous everywhere
!> (two cells sharing a face give the same s on it, because their trilinear
!> maps agree there), costs 8 cell values and no second inversion, and is
!> exact for a linear field on a grid that is an affine image of a uniform
!> box (a uniform or uniformly strained grid); on a distorted grid it is a
!> smooth approximation. In the half cell next to the block's boundary the
!> value is constant along the boundary normal (the boundary cell's value:
!> there is no centre beyond it). The nearest-centroid sample used before
!> jumped whenever the nearest cell changed; this reading does not.
!> Interpolation uses lerps a + w (b - a), so a uniform field reads exactly.
module io_gauges
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use mesh_grid, only: grid_t
  use mesh_geometry, only: hex_trilinear, hex_natural_unclamped
  use hydro_state, only: hydro_t
  use mesh_halo, only: halo_t
  use io_xdmf, only: io_rename
  use base_strings, only: itoa
  implicit none
  private
  public :: gauges_t, gauges_open, gauges_write, gauges_close, gauge_locate, gauge_sample, text_rows_trim, read_line, &
            gauge_nfield, gauge_field_names, gauges_write_given

  !> Number of values a gauge reports per row (after its cell index).
  integer, parameter :: gauge_nfield = 7
  !> Their column names (a gauge's columns end in _<gauge number>).
  character(len=*), parameter :: gauge_field_names(gauge_nfield) = [character(len=11) :: &
    'density', 'pressure', 'energy', 'sound_speed', 'velocity_x', 'velocity_y', 'velocity_z']

  !> Open gauge file and the current cell of each gauge.
  type :: gauges_t
    integer :: n = 0
    integer :: unit = -1
    character(len=:), allocatable :: path
    real(wp), allocatable :: point(:, :)
    integer, allocatable :: cell(:)
  end type gauges_t

contains

  !> Opens the history file at `path` for the gauge points(3, n) (length)
  !> and writes its header (comment lines starting with '#', the last one
  !> naming every column), or (append, on a restart) adds rows to the
  !> existing file. With file = .false. only the points are kept (a rank of a
  !> decomposed run that samples the gauges but does not write them).
  subroutine gauges_open(gs, path, points, append, err, file)
    type(gauges_t), intent(out) :: gs
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: points(:, :)
    logical, intent(in) :: append
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: file
    integer :: ios, i, f
    character(len=256) :: msg
    character(len=:), allocatable :: names

    gs%n = size(points, 2)
    if (gs%n == 0) return
    gs%path = path
    gs%point = points
    allocate(gs%cell(gs%n), source=0, stat=ios, errmsg=msg)
    if (ios /= 0) then
      call error_set(err, 'gauges_open', error_no_memory('the gauges'))
      return
    end if
    if (present(file)) then
      if (.not. file) return   ! (a rank that samples but does not write)
    end if
    if (append) then
      open(newunit=gs%unit, file=path, status='unknown', position='append', action='write', &
           iostat=ios, iomsg=msg)
    else
      open(newunit=gs%unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
    end if
    if (ios /= 0) then
      call error_set(err, 'gauges_open', 'cannot open '''//path//''': '//trim(msg))
      gs%unit = -1
      return
    end if
    if (append) return
    write(gs%unit, '(a)') '# gauge histories: for each gauge g, the cell that contains its point (cell_g), '// &
      'the cell fields interpolated trilinearly between the cell centres around the point, and the velocity '// &
      'interpolated from that cell''s nodes (see io_gauges.f90); the last header row names the columns'
    do i = 1, gs%n
      write(gs%unit, '(a,i0,a,3es25.16e3)') '# gauge ', i, ' at ', gs%point(:, i)
    end do
    names = '# time'
    do i = 1, gs%n
      names = names//' cell_'//itoa(i)
      do f = 1, gauge_nfield
        names = names//' '//trim(gauge_field_names(f))//'_'//itoa(i)
      end do
    end do
    write(gs%unit, '(a)') names
    flush(gs%unit)
  end subroutine gauges_open

  !> Appends one row at time t.
  !> On a decomposed run every block samples each gauge; the block that owns
  !> the cell containing the point answers (the lowest cell of the whole
  !> grid that contains it, as on one block), and only the block with the
  !> file (rank 0) writes. A point in no cell (moved out of the grid) takes
  !> the answer of the block whose nearest cell has the nearest centroid.
  subroutine gauges_write(gs, g, h, t, halo)
    type(gauges_t), intent(inout) :: gs
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    real(wp), intent(in) :: t
    class(halo_t), intent(in) :: halo
    integer :: i, ijk(3)
    real(wp) :: vals(gauge_nfield + 1), key
    logical :: inside, own

    if (gs%n == 0) return
    if (gs%unit /= -1) write(gs%unit, '(es25.16e3)', advance='no') t
    do i = 1, gs%n
      call gauge_sample(g, h, gs%point(:, i), gs%cell(i), vals(:gauge_nfield), inside)
      call g%cell_ijk(gs%cell(i), ijk(1), ijk(2), ijk(3))
      own = g%owns_cell(ijk(1), ijk(2), ijk(3))
      vals(gauge_nfield + 1) = real(g%global_cell(gs%cell(i)), wp)
      key = huge(1.0_wp)
      if (inside .and. own) key = vals(gauge_nfield + 1)
      call halo%choose(key, vals)
      if (.not. key < huge(1.0_wp)) then
        key = huge(1.0_wp)
        if (own) key = centroid_dist2(g, gs%cell(i), gs%point(:, i))
        call halo%choose(key, vals)
      end if
      if (gs%unit /= -1) write(gs%unit, '(1x,i0,7es25.16e3)', advance='no') nint(vals(gauge_nfield + 1)), &
        vals(:gauge_nfield)
    end do
    if (gs%unit == -1) return
    write(gs%unit, '(a)') ''
    flush(gs%unit)
  end subroutine gauges_write

  !> Appends a row at time t of values given for every gauge, vals(7, n) in
  !> the order of gauge_field_names, with cell 0 (a row not sampled from the
  !> grid: a &prerun's 1D run before it was mapped, `driver_prerun`).
  subroutine gauges_write_given(gs, t, vals)
    type(gauges_t), intent(in) :: gs
    real(wp), intent(in) :: t, vals(:, :)
    integer :: i
    if (gs%n == 0 .or. gs%unit == -1) return
    write(gs%unit, '(es25.16e3)', advance='no') t
    do i = 1, gs%n
      write(gs%unit, '(1x,i0,7es25.16e3)', advance='no') 0, vals(:, i)
    end do
    write(gs%unit, '(a)') ''
  end subroutine gauges_write_given

  subroutine gauges_close(gs)
    type(gauges_t), intent(inout) :: gs
    if (gs%unit /= -1) close(gs%unit)
    gs%unit = -1
  end subroutine gauges_close

  !> The gauge values at point p (length): density, pressure, specific
  !> internal energy, sound speed (cell fields interpolated between the cell
  !> centres around p) and velocity (3, from the containing cell's nodes),
  !> in the order of `gauge_field_names`. On entry `c` is a cell to start the
  !> search from (any cell: the previous answer is the cheapest), on exit the
  !> cell that contains p.
  pure subroutine gauge_sample(g, h, p, c, vals, inside)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    real(wp), intent(in) :: p(3)
    integer, intent(inout) :: c
    real(wp), intent(out) :: vals(gauge_nfield)
    logical, intent(out), optional :: inside
    real(wp) :: xi(3), un(3, 8), w(3)
    integer :: ijk(3), lo(3), hi(3), nlog(3), d, cc(2, 2, 2), a, b, e, c0, f

    c0 = c
    call gauge_locate(g, p, c0, c, xi, inside)
    call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
    ! the whole grid's cells (a block's own and ghost cells around its own)
    nlog = g%gn - g%off
    do d = 1, 3
      ! logical coordinate ijk + xi/2: cell centres at whole numbers, faces
      ! at halves; the weight from xi alone (not rounded with the index,
      ! which differs between a block and the whole grid)
      f = floor(0.5_wp*xi(d))
      lo(d) = ijk(d) + f
      w(d) = 0.5_wp*xi(d) - real(f, wp)
      hi(d) = lo(d) + 1
      if (lo(d) < 1 - g%off(d)) lo(d) = 1 - g%off(d)
      if (hi(d) > nlog(d)) hi(d) = nlog(d)
      if (lo(d) > hi(d)) lo(d) = hi(d)
    end do
    do e = 1, 2
      do b = 1, 2
        do a = 1, 2
          cc(a, b, e) = g%cell(merge(lo(1), hi(1), a == 1), merge(lo(2), hi(2), b == 1), merge(lo(3), hi(3), e == 1))
        end do
      end do
    end do
    vals(1) = lerp3(h%rho, cc, w)
    vals(2) = lerp3(h%p, cc, w)
    vals(3) = lerp3(h%e, cc, w)
    vals(4) = lerp3(h%cs, cc, w)
    call g%gather(c, h%u, un)
    vals(5:7) = hex_trilinear(un, xi)
  end subroutine gauge_sample

  !> Tensor-product linear interpolation of the cell field f between the
  !> cells cc(2,2,2) with weights w(3) in [0,1) (as nested lerps, so that
  !> equal values give that value exactly).
  pure real(wp) function lerp3(f, cc, w) result(v)
    real(wp), intent(in) :: f(:)
    integer, intent(in) :: cc(2, 2, 2)
    real(wp), intent(in) :: w(3)
    real(wp) :: fx(2, 2), fy(2)
    integer :: b, e
    do e = 1, 2
      do b = 1, 2
        fx(b, e) = lerp(f(cc(1, b, e)), f(cc(2, b, e)), w(1))
      end do
    end do
    do e = 1, 2
      fy(e) = lerp(fx(1, e), fx(2, e), w(2))
    end do
    v = lerp(fy(1), fy(2), w(3))
  end function lerp3

  pure real(wp) function lerp(a, b, w)
    real(wp), intent(in) :: a, b, w
    lerp = a + w*(b - a)
  end function lerp

  !> The cell c that contains the point p (length), searched from cell c0,
  !> and the natural coordinates xi of p in it, in [-1,1]^3. If c0 contains
  !> p, that is the answer (the usual case: a gauge stays in a cell for many
  !> rows). Otherwise a walk to the face neighbour whose centroid is nearer
  !> to p ends in the cell with the nearest centroid (the distance falls at
  !> every move, so the walk ends), and the containing cell is that one or
  !> one of its 26 neighbours: the one whose natural coordinates of p leave
  !> the cube least. (Newton's inverse is reliable only for points near the
  !> cell, which is why it is not what steers the walk.) A point outside the
  !> grid gets the nearest cell and xi clamped to the cube; `inside` says
  !> whether the point is in the cell found. On a block of a decomposition
  !> the walk goes over the block's own cells (the search of a point in
  !> another block ends outside).
  pure subroutine gauge_locate(g, p, c0, c, xi, inside)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: p(3)
    integer, intent(in) :: c0
    integer, intent(out) :: c
    real(wp), intent(out) :: xi(3)
    logical, intent(out), optional :: inside
    real(wp), parameter :: tol = 1.0e-10_wp
    real(wp) :: xn(3, 8), xit(3), excess, best_excess
    integer :: ijk(3), lo(3), hi(3), i, j, k, cn, cs

    cs = c0
    if (cs < 1 .or. cs > g%ncell) cs = g%cell(g%clo(1), g%clo(2), g%clo(3))
    call g%cell_ijk(cs, ijk(1), ijk(2), ijk(3))
    if (.not. g%owns_cell(ijk(1), ijk(2), ijk(3))) cs = g%cell(g%clo(1), g%clo(2), g%clo(3))
    if (present(inside)) inside = .true.
    call g%gather(cs, g%x, xn)
    xi = hex_natural_unclamped(xn, p)
    if (maxval(abs(xi)) <= 1.0_wp + tol) then
      c = cs
      call lowest_containing(g, p, tol, c, xi)
      ! (clamped as below: the same answer whichever way it was found)
      xi = min(max(xi, -1.0_wp), 1.0_wp)
      return
    end if
    cn = nearest_cell(g, p, cs)
    call g%cell_ijk(cn, ijk(1), ijk(2), ijk(3))
    lo = max(ijk - 1, g%clo)
    hi = min(ijk + 1, g%chi)
    c = cn
    best_excess = huge(1.0_wp)
    ! the nearest cell first, so that it wins a tie (a point outside the grid)
    do k = lo(3) - 1, hi(3)
      do j = lo(2), hi(2)
        do i = lo(1), hi(1)
          if (k == lo(3) - 1) then
            if (i /= lo(1) .or. j /= lo(2)) cycle
            cs = cn
          else
            cs = g%cell(i, j, k)
          end if
          call g%gather(cs, g%x, xn)
          xit = hex_natural_unclamped(xn, p)
          excess = maxval(abs(xit)) - 1.0_wp
          if (excess < best_excess) then
            best_excess = excess
            c = cs
            xi = xit
          end if
          if (best_excess <= tol) exit
        end do
        if (best_excess <= tol) exit
      end do
      if (best_excess <= tol) exit
    end do
    if (best_excess <= tol) call lowest_containing(g, p, tol, c, xi)
    if (present(inside)) inside = best_excess <= tol
    xi = min(max(xi, -1.0_wp), 1.0_wp)
  end subroutine gauge_locate

  !> A point on a face, edge or corner lies in several cells; the answer
  !> must not depend on where the search started (a restarted run starts
  !> from cell 1, the straight run from the previous row's cell), so it is
  !> the one with the lowest logical indices: from a cell c that contains p
  !> (natural coordinates xi), move to the lower neighbour along each d with
  !> xi(d) within tol of -1, if that neighbour contains p too.
  pure subroutine lowest_containing(g, p, tol, c, xi)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: p(3), tol
    integer, intent(inout) :: c
    real(wp), intent(inout) :: xi(3)
    real(wp) :: xn(3, 8), xit(3)
    integer :: d, ijk(3), stride(3), cn
    stride = [1, g%cx, g%cxy]
    do d = 1, 3
      if (.not. xi(d) < -1.0_wp + tol) cycle
      call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
      if (ijk(d) <= g%slo(d)) cycle
      cn = c - stride(d)
      call g%gather(cn, g%x, xn)
      xit = hex_natural_unclamped(xn, p)
      if (maxval(abs(xit)) <= 1.0_wp + tol) then
        c = cn
        xi = xit
      end if
    end do
  end subroutine lowest_containing

  !> Walks from cell c0 to the face neighbour whose centroid (mean of the
  !> nodes) is nearest to p, until no neighbour is nearer.
  pure integer function nearest_cell(g, p, c0) result(c)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: p(3)
    integer, intent(in) :: c0
    integer :: d, s, cn, ijk(3), stride(3), best
    real(wp) :: dbest, dn

    stride = [1, g%cx, g%cxy]
    c = c0
    dbest = centroid_dist2(g, c, p)
    do
      call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
      best = c
      do d = 1, 3
        do s = -1, 1, 2
          if (ijk(d) + s < g%clo(d) .or. ijk(d) + s > g%chi(d)) cycle
          cn = c + s*stride(d)
          dn = centroid_dist2(g, cn, p)
          if (dn < dbest) then
            dbest = dn
            best = cn
          end if
        end do
      end do
      if (best == c) exit
      c = best
    end do
  end function nearest_cell

  pure real(wp) function centroid_dist2(g, c, p)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: c
    real(wp), intent(in) :: p(3)
    real(wp) :: xn(3, 8)
    call g%gather(c, g%x, xn)
    centroid_dist2 = sum((sum(xn, 2)/8.0_wp - p)**2)
  end function centroid_dist2

  !> Keeps, of the text table at `path`, the comment lines ('#') and the
  !> rows whose first number (the time) is at most t_keep (time; with a
  !> relative margin of 1e-13 for the printed rounding), by writing
  !> `path`.tmp and renaming it over `path`: the rows a run wrote after the
  !> dump a restart continues from are dropped, so that a continued run's
  !> file equals the uninterrupted run's. A missing file is left missing.
  subroutine text_rows_trim(path, t_keep, err)
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: t_keep
    type(error_t), allocatable, intent(inout) :: err
    integer :: uin, uout, ios, n
    character(len=256) :: msg
    character(len=:), allocatable :: line
    real(wp) :: t
    logical :: exists

    inquire(file=path, exist=exists)
    if (.not. exists) return
    open(newunit=uin, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call error_set(err, 'text_rows_trim', 'cannot read '''//path//''': '//trim(msg))
      return
    end if
    open(newunit=uout, file=path//'.tmp', status='replace', action='write', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      close(uin)
      call error_set(err, 'text_rows_trim', 'cannot write '''//path//'.tmp'': '//trim(msg))
      return
    end if
    n = 0
    do
      call read_line(uin, line, ios)
      if (ios /= 0) exit
      if (len_trim(line) == 0) cycle
      if (index(adjustl(line), '#') /= 1) then
        read(line, *, iostat=ios) t
        if (ios /= 0) cycle
        if (t > t_keep + 1.0e-13_wp*abs(t_keep)) exit
      end if
      write(uout, '(a)', iostat=ios, iomsg=msg) line
      if (ios /= 0) exit
      n = n + 1
    end do
    close(uin)
    if (ios > 0) then
      close(uout, status='delete')
      call error_set(err, 'text_rows_trim', 'cannot rewrite '''//path//''': '//trim(msg))
      return
    end if
    close(uout)
    call io_rename(path//'.tmp', path, err)
  end subroutine text_rows_trim

  !> One line of any length from unit u; ios as from read (< 0 at the end).
  subroutine read_line(u, line, ios)
    integer, intent(in) :: u
    character(len=:), allocatable, intent(out) :: line
    integer, intent(out) :: ios
    character(len=1024) :: buf
    integer :: got
    line = ''
    do
      read(u, '(a)', advance='no', iostat=ios, size=got) buf
      line = line//buf(1:got)
      if (ios /= 0) exit
    end do
    if (is_iostat_eor(ios)) ios = 0
  end subroutine read_line
end module io_gauges
