!> Gauge time histories: cell fields at fixed points, as plain text columns.
!>
!> A gauge reports the cell whose centroid is nearest to its point, found by
!> walking from the previous answer to the neighbour with the nearest centroid
!> (cheap, and exact on the structured grids of a Lagrangian or ALE run as
!> long as cells stay convex-ish around the gauge).
module io_gauges
  use base_kinds, only: wp
  use base_errors, only: error_t, error_set
  use mesh_grid, only: grid_t
  use lagrange_state, only: hydro_t
  implicit none
  private
  public :: gauges_t, gauges_open, gauges_write, gauges_close

  !> Open gauge file and the current cell of each gauge.
  type :: gauges_t
    integer :: n = 0
    integer :: unit = -1
    real(wp), allocatable :: point(:, :)
    integer, allocatable :: cell(:)
  end type gauges_t

contains

  !> Opens the history file and writes its header, or (append, on a
  !> restart) adds rows to the existing file.
  subroutine gauges_open(gs, path, points, append, err)
    type(gauges_t), intent(out) :: gs
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: points(:, :)
    logical, intent(in) :: append
    type(error_t), allocatable, intent(inout) :: err
    integer :: ios, i
    character(len=256) :: msg

    gs%n = size(points, 2)
    if (gs%n == 0) return
    gs%point = points
    allocate(gs%cell(gs%n), source=1, stat=ios, errmsg=msg)
    if (ios /= 0) then
      call error_set(err, 'gauges_open', 'cannot allocate the gauges: '//trim(msg))
      return
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
    write(gs%unit, '(a)') '# gauge histories: time, then for each gauge g: '// &
      'cell_g density_g pressure_g energy_g sound_speed_g velocity_x/y/z_g (cell-mean of its nodes)'
    do i = 1, gs%n
      write(gs%unit, '(a,i0,a,3es15.7)') '# gauge ', i, ' at ', gs%point(:, i)
    end do
  end subroutine gauges_open

  !> Appends one row at time t.
  subroutine gauges_write(gs, g, h, t)
    type(gauges_t), intent(inout) :: gs
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    real(wp), intent(in) :: t
    integer :: i, c
    real(wp) :: v(3), un(3, 8)

    if (gs%unit == -1) return
    write(gs%unit, '(es23.15)', advance='no') t
    do i = 1, gs%n
      gs%cell(i) = nearest_cell(g, gs%point(:, i), gs%cell(i))
      c = gs%cell(i)
      call g%gather(c, h%u, un)
      v = sum(un, 2)/8.0_wp
      write(gs%unit, '(1x,i0,7es23.15)', advance='no') c, h%rho(c), h%p(c), h%e(c), h%cs(c), v
    end do
    write(gs%unit, '(a)') ''
    flush(gs%unit)
  end subroutine gauges_write

  subroutine gauges_close(gs)
    type(gauges_t), intent(inout) :: gs
    if (gs%unit /= -1) close(gs%unit)
    gs%unit = -1
  end subroutine gauges_close

  !> Walks from cell `c0` to the cell whose centroid is nearest to p.
  function nearest_cell(g, p, c0) result(c)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: p(3)
    integer, intent(in) :: c0
    integer :: c
    integer :: i, j, k, d, s, cn, ijk(3), nlog(3), stride(3), best
    real(wp) :: dbest, dn

    nlog = [g%ni, g%nj, g%nk]
    stride = [1, g%ni, g%ni*g%nj]
    c = c0
    dbest = dist2(g, c, p)
    do
      call g%cell_ijk(c, i, j, k)
      ijk = [i, j, k]
      best = c
      do d = 1, 3
        do s = -1, 1, 2
          if (ijk(d) + s < 1 .or. ijk(d) + s > nlog(d)) cycle
          cn = c + s*stride(d)
          dn = dist2(g, cn, p)
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

  real(wp) function dist2(g, c, p)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: c
    real(wp), intent(in) :: p(3)
    real(wp) :: xn(3, 8), xc(3)
    call g%gather(c, g%x, xn)
    xc = sum(xn, 2)/8.0_wp
    dist2 = sum((xc - p)**2)
  end function dist2
end module io_gauges
