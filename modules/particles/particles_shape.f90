!> Shape functions of a particle in its host hex, in natural coordinates
!> xi in [0,1]^3 (PARTICLES.md §1.3), and the inverse map: the host cell
!> and natural coordinates of a physical point (§1.5, general fallback).
!>
!> Corners are numbered a = 1 + i + 2j + 4k as in `mesh_geometry`, so bit d
!> of (a-1) picks the factor of direction d:
!>   N_a(xi) = prod_d ( bit_d(a-1) ? xi_d : 1 - xi_d ),
!>   dN_a/dxi_d = (bit_d(a-1) ? +1 : -1) prod_{e /= d} ( ... ).
!> x(xi) = sum_a N_a(xi) x_a is the trilinear map of the cell; it is the
!> map of `mesh_geometry::hex_trilinear` with xi_mesh = 2 xi - 1. [0,1]^3
!> is used here (not [-1,1]^3) because then a sub-box of a box grid, or the
!> fractional part of (x - xmin)/h (the pre-positioning of Remark 2), is a
!> natural coordinate without rescaling.
!>
!> Inverse map (`particles_natural`): Newton on r(xi) = x(xi) - x_p from the
!> cell centre, J_ij = sum_a x_a,i dN_a/dxi_j solved by Cramer's rule, the
!> step halved (at most 10 times) while |r| does not decrease, stopped when
!> |r| is round-off of the cell's size (8 eps) or the step is below 1e-15;
!> exact in one step for a parallelepiped. `particles_locate` walks from a
!> guessed cell to the neighbour on the side where xi leaves [0,1], and
!> searches every cell if the walk fails (a tangled or strongly curved
!> grid; setup only).
module particles_shape
  use base_kinds, only: wp
  use mesh_geometry, only: cross
  use mesh_grid, only: grid_t
  implicit none
  private
  public :: particles_shape_values, particles_shape_gradients, particles_map, particles_natural, &
            particles_locate, particles_lowest_host, inside_tol, particles_grid_hull

  !> How far outside [0,1] a natural coordinate may be and still count as
  !> inside the cell (then clamped): round-off of the inverse map.
  real(wp), parameter :: inside_tol = 1.0e-10_wp

contains

  !> The eight shape functions at xi (natural coordinates in [0,1]^3):
  !> N_a = f_1 f_2 f_3 with f_d = xi_d where bit d-1 of a-1 is set, else
  !> 1 - xi_d (written out: a table indexed by the bits was a tenth of a
  !> particle run's time).
  pure function particles_shape_values(xi) result(n)
    real(wp), intent(in) :: xi(3)
    real(wp) :: n(8)
    real(wp) :: x0, x1, y0, y1, z0, z1
    x1 = xi(1)
    y1 = xi(2)
    z1 = xi(3)
    x0 = 1.0_wp - x1
    y0 = 1.0_wp - y1
    z0 = 1.0_wp - z1
    n(1) = x0*y0*z0
    n(2) = x1*y0*z0
    n(3) = x0*y1*z0
    n(4) = x1*y1*z0
    n(5) = x0*y0*z1
    n(6) = x1*y0*z1
    n(7) = x0*y1*z1
    n(8) = x1*y1*z1
  end function particles_shape_values

  !> dN_a/dxi_d (8, 3) at xi (per unit natural coordinate): the factor of
  !> direction d replaced by -1 or +1 (`particles_shape_values`).
  pure function particles_shape_gradients(xi) result(dn)
    real(wp), intent(in) :: xi(3)
    real(wp) :: dn(8, 3)
    real(wp) :: x0, x1, y0, y1, z0, z1
    x1 = xi(1)
    y1 = xi(2)
    z1 = xi(3)
    x0 = 1.0_wp - x1
    y0 = 1.0_wp - y1
    z0 = 1.0_wp - z1
    dn(:, 1) = [-y0*z0, y0*z0, -y1*z0, y1*z0, -y0*z1, y0*z1, -y1*z1, y1*z1]
    dn(:, 2) = [-x0*z0, -x1*z0, x0*z0, x1*z0, -x0*z1, -x1*z1, x0*z1, x1*z1]
    dn(:, 3) = [-x0*y0, -x1*y0, -x0*y1, -x1*y1, x0*y0, x1*y0, x0*y1, x1*y1]
  end function particles_shape_gradients

  !> The position (length) at natural coordinates xi of the hex xn(3,8):
  !> x = sum_a N_a(xi) x_a (Eq. 25 with constant xi: the particle follows
  !> the grid).
  pure function particles_map(xn, xi) result(x)
    real(wp), intent(in) :: xn(3, 8), xi(3)
    real(wp) :: x(3)
    real(wp) :: n(8)
    integer :: a
    n = particles_shape_values(xi)
    x = 0.0_wp
    do a = 1, 8
      x = x + n(a)*xn(:, a)
    end do
  end function particles_map

  !> Natural coordinates xi (unclamped) of the point x (length) in the hex
  !> xn(3,8) by damped Newton (module notes); `inside` if every xi_d is in
  !> [-inside_tol, 1 + inside_tol] and Newton converged (xi is then clamped
  !> into [0,1]^3).
  pure subroutine particles_natural(xn, x, xi, inside)
    real(wp), intent(in) :: xn(3, 8), x(3)
    real(wp), intent(out) :: xi(3)
    logical, intent(out) :: inside
    real(wp) :: r(3), rt(3), jac(3, 3), c(3, 3), det, dxi(3), scale, s, rn, rtn, trial(3)
    real(wp) :: dn(8, 3)
    integer :: it, a, d, half
    logical :: converged

    scale = maxval(abs(xn(:, 8) - xn(:, 1))) + maxval(abs(xn(:, 7) - xn(:, 2)))
    xi = 0.5_wp
    r = particles_map(xn, xi) - x
    rn = norm2(r)
    converged = .false.
    do it = 1, 40
      if (rn <= 8.0_wp*epsilon(1.0_wp)*scale) then
        converged = .true.
        exit
      end if
      dn = particles_shape_gradients(xi)
      jac = 0.0_wp
      do d = 1, 3
        do a = 1, 8
          jac(:, d) = jac(:, d) + dn(a, d)*xn(:, a)
        end do
      end do
      c(:, 1) = cross(jac(:, 2), jac(:, 3))
      c(:, 2) = cross(jac(:, 3), jac(:, 1))
      c(:, 3) = cross(jac(:, 1), jac(:, 2))
      det = dot_product(jac(:, 1), c(:, 1))
      if (.not. abs(det) > tiny(1.0_wp)) exit
      do d = 1, 3
        dxi(d) = -dot_product(c(:, d), r)/det
      end do
      ! backtracking: halve the step while the residual does not decrease
      s = 1.0_wp
      do half = 0, 10
        trial = xi + s*dxi
        rt = particles_map(xn, trial) - x
        rtn = norm2(rt)
        if (rtn < rn) exit
        s = 0.5_wp*s
      end do
      if (.not. rtn < rn) then
        ! no decrease at all: the residual is round-off (or the map folds)
        converged = maxval(abs(dxi)) <= 1.0e-12_wp
        exit
      end if
      xi = trial
      r = rt
      rn = rtn
      if (maxval(abs(s*dxi)) <= 1.0e-15_wp) then
        converged = .true.
        exit
      end if
      if (maxval(abs(xi)) > 8.0_wp) exit   ! far outside: the side is clear
    end do
    inside = converged .and. all(xi >= -inside_tol) .and. all(xi <= 1.0_wp + inside_tol)
    if (inside) xi = min(max(xi, 0.0_wp), 1.0_wp)
  end subroutine particles_natural

  !> The host cell of point x (length) and its natural coordinates xi in
  !> [0,1]^3: a walk from cell `guess` (module notes), then, if the walk
  !> does not end in a cell containing x, every cell in index order whose
  !> corners' box (widened by the tolerance's reach) holds x; none if x
  !> lies outside hull (a particle gone through an open face: one test, not
  !> one per cell). found = .false. (cell = 0) if no cell contains x. The grid's nodes are
  !> at g%x, or at xg(3, nnode) if given (the standard grid of Remark 2).
  !> cut (a block of a decomposed run: cut(d) / cut(3 + d), its stored cells
  !> end at a neighbour block's below / above in direction d): the walk
  !> that would step past a cut, or ends without a cell, gives cell = -1
  !> (found = .false.), where the whole grid's walk may go on: so a cell
  !> found is the one the whole grid's walk finds; at_cut (with cut) is then
  !> the stored cell the walk would have stepped on from (0 where it
  !> ended without a cell for another reason): the whole grid's walk from
  !> that cell, which the block that owns it stores with the cells around
  !> it, goes on as this one would have (each step depends only on the
  !> cell it is in and x).
  pure subroutine particles_locate(g, x, guess, cell, xi, found, xg, cut, at_cut, hull)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(3)
    integer, intent(in) :: guess
    integer, intent(out) :: cell
    real(wp), intent(out) :: xi(3)
    logical, intent(out) :: found
    real(wp), intent(in), optional :: xg(:, :)
    logical, intent(in), optional :: cut(6)
    integer, intent(out), optional :: at_cut
    !> (lo(3), hi(3)) a box that holds every cell's reach
    !> (`particles_grid_hull`): a point outside it is in no cell, without
    !> the search cell by cell
    real(wp), intent(in), optional :: hull(6)
    real(wp) :: xn(3, 8)
    integer :: ijk(3), nmin(3), nmax(3), step, d, c
    logical :: moved, lo_cut(3), hi_cut(3)

    ! (the stored cells: a block's with its ghost layers)
    nmin = g%slo
    nmax = g%shi
    lo_cut = .false.
    hi_cut = .false.
    if (present(cut)) then
      lo_cut = cut(1:3)
      hi_cut = cut(4:6)
    end if
    if (present(at_cut)) at_cut = 0
    c = max(1, min(g%ncell, guess))
    call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
    do step = 1, sum(nmax - nmin) + 6
      c = g%cell(ijk(1), ijk(2), ijk(3))
      call corners(c, xn)
      call particles_natural(xn, x, xi, found)
      if (found) then
        cell = c
        return
      end if
      moved = .false.
      do d = 1, 3
        if ((xi(d) < -inside_tol .and. ijk(d) == nmin(d) .and. lo_cut(d)) .or. &
            (xi(d) > 1.0_wp + inside_tol .and. ijk(d) == nmax(d) .and. hi_cut(d))) then
          if (present(at_cut)) at_cut = c
          moved = .false.
          exit
        else if (xi(d) < -inside_tol .and. ijk(d) > nmin(d)) then
          ijk(d) = ijk(d) - 1
          moved = .true.
        else if (xi(d) > 1.0_wp + inside_tol .and. ijk(d) < nmax(d)) then
          ijk(d) = ijk(d) + 1
          moved = .true.
        end if
      end do
      if (.not. moved) exit
    end do
    if (present(cut)) then
      cell = -1
      xi = 0.0_wp
      found = .false.
      return
    end if
    cell = 0
    xi = 0.0_wp
    found = .false.
    if (present(hull)) then
      if (any(x < hull(1:3) .or. x > hull(4:6))) return
    end if
    ! (a cell's corners' box, widened by what the tolerance reaches, holds
    ! every point the cell may hold: `particles_cells_hold`)
    do c = 1, g%ncell
      call corners(c, xn)
      if (.not. cell_reaches(xn, x)) cycle
      call particles_natural(xn, x, xi, found)
      if (found) then
        cell = c
        return
      end if
    end do
    cell = 0
    xi = 0.0_wp
    found = .false.
  contains
    !> The corners of cell c in the grid searched.
    pure subroutine corners(c, xc)
      integer, intent(in) :: c
      real(wp), intent(out) :: xc(3, 8)
      if (present(xg)) then
        call g%gather(c, xg, xc)
      else
        call g%gather(c, g%x, xc)
      end if
    end subroutine corners
  end subroutine particles_locate

  !> Whether the cell with corners xn may hold x: its corners' box widened
  !> by what the walk's tolerance reaches (inside_tol on the box's size).
  pure logical function cell_reaches(xn, x)
    real(wp), intent(in) :: xn(3, 8), x(3)
    real(wp) :: lo(3), hi(3), w
    lo = minval(xn, dim=2)
    hi = maxval(xn, dim=2)
    w = 10.0_wp*inside_tol*sum(hi - lo)
    cell_reaches = all(x >= lo - w .and. x <= hi + w)
  end function cell_reaches

  !> A box (lo(3), hi(3)) that holds what every stored cell of g with nodes
  !> at x may hold (`particles_locate`'s hull): the nodes' box widened as
  !> `cell_reaches` widens a cell's, by the grid's size.
  pure function particles_grid_hull(g, x) result(hull)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :)
    real(wp) :: hull(6)
    real(wp) :: w
    hull(1:3) = minval(x(:, :g%nnode), dim=2)
    hull(4:6) = maxval(x(:, :g%nnode), dim=2)
    w = 10.0_wp*inside_tol*sum(hull(4:6) - hull(1:3))
    hull = hull + [-w, -w, -w, w, w, w]
  end function particles_grid_hull

  !> From a cell that holds x (natural coordinates xi within inside_tol of
  !> [0,1]^3), the holding cell of lowest index in each direction: a point
  !> on a face, an edge or a corner that several cells share goes to the
  !> lowest of them, whichever a walk found first, so that its host does not
  !> depend on where the walk started (a block of a decomposed run finds
  !> the host one process finds). Only the stored cells are looked at (an
  !> owned cell's lower neighbours are stored: a block's ghost layers).
  pure subroutine particles_lowest_host(g, x, cell, xi)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(3)
    integer, intent(inout) :: cell
    real(wp), intent(inout) :: xi(3)
    real(wp) :: xn(3, 8), xt(3)
    integer :: ijk(3), d, c
    logical :: moved, found
    call g%cell_ijk(cell, ijk(1), ijk(2), ijk(3))
    moved = .true.
    do while (moved)
      moved = .false.
      do d = 1, 3
        ! (a lower neighbour holds x only if x is on the low side of this cell)
        if (ijk(d) <= g%slo(d) .or. xi(d) >= 0.5_wp) cycle
        ijk(d) = ijk(d) - 1
        c = g%cell(ijk(1), ijk(2), ijk(3))
        call g%gather(c, g%x, xn)
        call particles_natural(xn, x, xt, found)
        if (found) then
          cell = c
          xi = xt
          moved = .true.
        else
          ijk(d) = ijk(d) + 1
        end if
      end do
    end do
  end subroutine particles_lowest_host
end module particles_shape
