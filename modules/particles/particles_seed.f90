!> Seeding particles from a shape at n particles per cell per direction,
!> and the initial velocity field of a seeded body.
!>
!> Each host cell is split into n^3 sub-boxes of its natural cube [0,1]^3,
!> sub-box (i,j,k) spanning [(i-1)/n, i/n] x ...; a particle goes to the
!> centre xi = ((i - 1/2)/n, ...) of each sub-box whose physical centre
!> x = sum_a N_a(xi) x_a lies in the shape (`mesh_shapes::shape_inside`,
!> boundary included), with the volume of the sub-box's image: the
!> 24-tetrahedron volume (`hex_volume`) of its eight mapped corners, which
!> is the exact volume of the trilinear image (Eq. 50's cell volume), so
!> the sub-boxes of a cell add up to the cell's volume to round-off on any
!> grid. A cell whose bounding ball misses the shape (shape_level above
!> its radius) is skipped without evaluating its sub-boxes: a trilinear
!> cell lies in the convex hull of its corners.
!>
!> Accuracy. A shape covering whole cells is seeded exactly (n^3 particles
!> per cell, volume = the cells' volume). Across a curved boundary only
!> sub-boxes whose centres lie inside count, so the seeded volume differs
!> from the shape's by at most the volume of the band of half a sub-box
!> diagonal about the surface, A sqrt(3) h/(2n) (first order); averaged
!> over positions of the shape relative to the grid the error is a lattice
!> count discrepancy of relative size ~(h/(nR))^2 (second order on
!> average; the test measures it).
module particles_seed
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_strings, only: itoa
  use mesh_geometry, only: hex_volume, cross
  use mesh_grid, only: grid_t
  use mesh_shapes, only: shape_t, shape_inside, shape_level
  use mesh_surface, only: surface_t, surface_inside, surface_box_level
  use particles_shape, only: particles_map, particles_natural, particles_locate, particles_lowest_host
  implicit none
  private
  public :: seed_cell, seed_shape, seed_count, seed_surface, seed_line, seed_hosts, seed_union, seed_points, rigid_velocity, &
            seed_bins_t, seed_bins_build

  !> Bins of a block's stored cells for finding the cells that hold given
  !> points (`seed_bins_build`, `seed_hosts`): as many per direction as the
  !> block has cells, over the box of its stored nodes, a cell listed in
  !> every bin its (padded) box meets (a cell lies in the convex hull of its
  !> corners, so the cells that hold a point are among those of its bin).
  type :: seed_bins_t
    real(wp) :: lo(3) = 0.0_wp, hi(3) = 0.0_wp, h(3) = 1.0_wp
    integer :: nb(3) = 0
    integer, allocatable :: start(:), list(:)
  end type seed_bins_t

contains

  !> The n^3 sub-box centres of the hex xn(3,8): natural coordinates
  !> xi(3, n^3), positions x(3, n^3) (length) and volumes vol(n^3)
  !> (length^3), i fastest.
  pure subroutine seed_cell(xn, n, xi, x, vol)
    real(wp), intent(in) :: xn(3, 8)
    integer, intent(in) :: n
    real(wp), intent(out) :: xi(:, :), x(:, :), vol(:)
    real(wp) :: corners(3, 8), lo(3), h
    integer :: i, j, k, s, a
    h = 1.0_wp/real(n, wp)
    s = 0
    do k = 1, n
      do j = 1, n
        do i = 1, n
          s = s + 1
          lo = real([i - 1, j - 1, k - 1], wp)*h
          xi(:, s) = (real([i, j, k], wp) - 0.5_wp)*h
          x(:, s) = particles_map(xn, xi(:, s))
          do a = 1, 8
            corners(:, a) = particles_map(xn, lo + h*real([ibits(a - 1, 0, 1), ibits(a - 1, 1, 1), &
                                                               ibits(a - 1, 2, 1)], wp))
          end do
          vol(s) = hex_volume(corners)
        end do
      end do
    end do
  end subroutine seed_cell

  !> The particles of shape `sh` seeded at n per cell per direction in grid
  !> g (module notes): host cells, natural coordinates, positions (length)
  !> and volumes (length^3), in cell order then sub-box order.
  subroutine seed_shape(g, sh, n, cell, xi, x, vol, err, surf)
    type(grid_t), intent(in) :: g
    type(shape_t), intent(in) :: sh
    integer, intent(in) :: n
    integer, allocatable, intent(out) :: cell(:)
    real(wp), allocatable, intent(out) :: xi(:, :), x(:, :), vol(:)
    type(error_t), allocatable, intent(inout) :: err
    !> a closed surface to seed inside instead of sh (`seed_surface`)
    type(surface_t), intent(in), optional :: surf
    integer :: np, stat
    character(len=200) :: msg
    integer :: cell0(0)
    real(wp) :: xi0(3, 0), x0(3, 0), vol0(0)

    if (n < 1) then
      call error_set(err, 'seed_shape', 'particles per cell per direction must be >= 1')
      return
    end if
    call visit(g, sh, n, .false., np, cell0, xi0, x0, vol0, surf)
    allocate(cell(np), xi(3, np), x(3, np), vol(np), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'seed_shape', error_no_memory('the seeded particles'))
      return
    end if
    call visit(g, sh, n, .true., np, cell, xi, x, vol, surf)
  end subroutine seed_shape

  !> The particles inside the closed surface s (`mesh_surface`), seeded at n
  !> per cell per direction as `seed_shape` seeds a shape.
  subroutine seed_surface(g, s, n, cell, xi, x, vol, err)
    type(grid_t), intent(in) :: g
    type(surface_t), intent(in) :: s
    integer, intent(in) :: n
    integer, allocatable, intent(out) :: cell(:)
    real(wp), allocatable, intent(out) :: xi(:, :), x(:, :), vol(:)
    type(error_t), allocatable, intent(inout) :: err
    call seed_shape(g, shape_t(), n, cell, xi, x, vol, err, s)
  end subroutine seed_surface

  !> How many particles `seed_shape` seeds (nothing stored: for checking a
  !> deck before the run); with planes (gn(1) + gn(2) + gn(3), the whole
  !> grid's planes of cells normal to i, then j, then k), each particle also
  !> added to the planes of its host cell.
  integer function seed_count(g, sh, n, planes) result(np)
    type(grid_t), intent(in) :: g
    type(shape_t), intent(in) :: sh
    integer, intent(in) :: n
    integer, intent(inout), optional :: planes(:)
    integer :: cell(0)
    real(wp) :: xi(3, 0), x(3, 0), vol(0)
    call visit(g, sh, n, .false., np, cell, xi, x, vol, planes=planes)
  end function seed_count

  !> Counts (np) the sub-box centres of g inside sh and, with `fill`, stores
  !> them in cell, xi, x, vol (sized by a counting visit).
  subroutine visit(g, sh, n, fill, np, cell, xi, x, vol, surf, planes)
    type(grid_t), intent(in) :: g
    type(shape_t), intent(in) :: sh
    integer, intent(in) :: n
    logical, intent(in) :: fill
    integer, intent(out) :: np
    integer, intent(inout) :: cell(:)
    real(wp), intent(inout) :: xi(:, :), x(:, :), vol(:)
    type(surface_t), intent(in), optional :: surf
    integer, intent(inout), optional :: planes(:)
    real(wp) :: cxi(3, n**3), cx(3, n**3), cvol(n**3)
    real(wp) :: xn(3, 8), xc(3), rad, level
    logical :: in
    integer :: c, s, a, ijk(3)

    np = 0
    do c = 1, g%ncell
      call g%gather(c, g%x, xn)
      do a = 1, 3
        xc(a) = 0.125_wp*sum(xn(a, :))
      end do
      rad = 0.0_wp
      do a = 1, 8
        rad = max(rad, norm2(xn(:, a) - xc))
      end do
      if (present(surf)) then
        level = surface_box_level(surf, xc)
      else
        level = shape_level(sh, xc)
      end if
      if (level > rad) cycle
      call seed_cell(xn, n, cxi, cx, cvol)
      do s = 1, n**3
        if (present(surf)) then
          in = surface_inside(surf, cx(:, s))
        else
          in = shape_inside(sh, cx(:, s))
        end if
        if (.not. in) cycle
        np = np + 1
        if (present(planes)) then
          call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
          ijk = ijk + g%off
          planes(ijk(1)) = planes(ijk(1)) + 1
          planes(g%gn(1) + ijk(2)) = planes(g%gn(1) + ijk(2)) + 1
          planes(g%gn(1) + g%gn(2) + ijk(3)) = planes(g%gn(1) + g%gn(2) + ijk(3)) + 1
        end if
        if (fill) then
          cell(np) = c
          xi(:, np) = cxi(:, s)
          x(:, np) = cx(:, s)
          vol(np) = cvol(s)
        end if
      end do
    end do
  end subroutine visit

  !> The points of a bar (a reinforcing bar, a rod) along the segment
  !> p0..p1 at n per cell along it: the segment cut into nb = max(1,
  !> nint(n L/h)) equal pieces (L its length, h the size of the cell
  !> holding its midpoint, the caller's), the midpoint of each piece, x(3,
  !> nb); each particle's volume is then area L/nb, so the bar's volume is
  !> exact. stat nonzero if x could not be allocated.
  pure subroutine seed_line(p0, p1, n, h, x, stat)
    real(wp), intent(in) :: p0(3), p1(3), h
    integer, intent(in) :: n
    real(wp), allocatable, intent(out) :: x(:, :)
    integer, intent(out) :: stat
    integer :: nb, i
    nb = max(1, nint(real(n, wp)*norm2(p1 - p0)/h))
    allocate(x(3, nb), stat=stat)
    if (stat /= 0) return
    do i = 1, nb
      x(:, i) = p0 + ((real(i, wp) - 0.5_wp)/real(nb, wp))*(p1 - p0)
    end do
  end subroutine seed_line

  !> The bins of g's stored cells (`seed_bins_t`), built once for the lists
  !> of points a block seeds; stat nonzero if they could not be allocated.
  pure subroutine seed_bins_build(g, bins, stat)
    type(grid_t), intent(in) :: g
    type(seed_bins_t), intent(out) :: bins
    integer, intent(out) :: stat
    integer :: d, c, q, pass, b0(3), b1(3), bi, bj, bk
    stat = 0
    do d = 1, 3
      bins%lo(d) = minval(g%x(d, :))
      bins%hi(d) = maxval(g%x(d, :))
    end do
    ! (bins as wide as the block's cells, a thin block's too, offset by half
    ! a bin: a cell of a box grid, padded, then meets 2 x 2 x 2 bins, not 27)
    bins%h = max(bins%hi - bins%lo, tiny(1.0_wp))/real(max(1, g%shi - g%slo + 1), wp)
    bins%nb = max(1, g%shi - g%slo + 1) + 1
    bins%lo = bins%lo - 0.5_wp*bins%h
    allocate(bins%start(product(bins%nb) + 1), stat=stat)
    if (stat /= 0) return
    ! (CSR: the first pass counts, the second lists)
    bins%start = 0
    do pass = 1, 2
      do c = 1, g%ncell
        call bins_of(c, b0, b1)
        do bk = b0(3), b1(3)
          do bj = b0(2), b1(2)
            do bi = b0(1), b1(1)
              q = 1 + bi + bins%nb(1)*(bj + bins%nb(2)*bk)
              if (pass == 1) then
                bins%start(q + 1) = bins%start(q + 1) + 1
              else
                bins%list(bins%start(q)) = c
                bins%start(q) = bins%start(q) + 1
              end if
            end do
          end do
        end do
      end do
      if (pass == 1) then
        bins%start(1) = 1
        do q = 2, size(bins%start)
          bins%start(q) = bins%start(q) + bins%start(q - 1)
        end do
        allocate(bins%list(bins%start(size(bins%start)) - 1), stat=stat)
        if (stat /= 0) return
      else
        ! (start(q) now the end of bin q: shifted back to its beginning)
        bins%start(2:) = bins%start(1:size(bins%start) - 1)
        bins%start(1) = 1
      end if
    end do
  contains
    !> The range of bins b0 .. b1 (0-based) that cell c's padded box meets.
    pure subroutine bins_of(c, b0, b1)
      integer, intent(in) :: c
      integer, intent(out) :: b0(3), b1(3)
      real(wp) :: xc(3, 8), bl(3), bh(3), pad(3)
      call g%gather(c, g%x, xc)
      bl = minval(xc, dim=2)
      bh = maxval(xc, dim=2)
      ! (a point within the inside tolerance of the cell: a few 1e-10 of it)
      pad = 1.0e-8_wp*(bh - bl)
      b0 = min(bins%nb - 1, max(0, int((bl - pad - bins%lo)/bins%h)))
      b1 = min(bins%nb - 1, max(0, int((bh + pad - bins%lo)/bins%h)))
    end subroutine bins_of
  end subroutine seed_bins_build

  !> The host cell (cell(i), 0 if none) and natural coordinates xi(:, i) of
  !> each point x(:, i) of a list in g, the lowest of the cells that hold
  !> it (`particles_lowest_host`: a point on a face shared by two cells has
  !> the same host however it was found). One process (bins absent): a walk
  !> from the previous point's host (`particles_locate`, every cell searched
  !> where the walk fails). A block of a decomposed run (bins: its
  !> `seed_bins_build`): among its stored cells, through the bins (no walk
  !> that a block's edge stops), and only hosts among its owned cells count.
  pure subroutine seed_hosts(g, x, cell, xi, bins)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :)
    integer, intent(out) :: cell(:)
    real(wp), intent(out) :: xi(:, :)
    type(seed_bins_t), intent(in), optional :: bins
    real(wp) :: xn(3, 8), pad(3)
    integer :: i, guess, ijk(3), b(3), q, c
    logical :: found
    cell = 0
    xi = 0.0_wp
    if (size(x, 2) == 0 .or. g%ncell == 0) return
    if (.not. present(bins)) then
      guess = 1
      do i = 1, size(x, 2)
        call particles_locate(g, x(:, i), guess, cell(i), xi(:, i), found)
        if (.not. found) then
          cell(i) = 0
          cycle
        end if
        call particles_lowest_host(g, x(:, i), cell(i), xi(:, i))
        guess = cell(i)
      end do
      return
    end if
    pad = 1.0e-9_wp*(bins%hi - bins%lo)
    do i = 1, size(x, 2)
      if (any(x(:, i) < bins%lo - pad) .or. any(x(:, i) > bins%hi + pad)) cycle
      b = min(bins%nb - 1, max(0, int((x(:, i) - bins%lo)/bins%h)))
      q = 1 + b(1) + bins%nb(1)*(b(2) + bins%nb(2)*b(3))
      do c = bins%start(q), bins%start(q + 1) - 1
        call g%gather(bins%list(c), g%x, xn)
        call particles_natural(xn, x(:, i), xi(:, i), found)
        if (.not. found) cycle
        cell(i) = bins%list(c)
        exit
      end do
      if (cell(i) == 0) then
        xi(:, i) = 0.0_wp
        cycle
      end if
      call particles_lowest_host(g, x(:, i), cell(i), xi(:, i))
      call g%cell_ijk(cell(i), ijk(1), ijk(2), ijk(3))
      if (.not. g%owns_cell(ijk(1), ijk(2), ijk(3))) cell(i) = 0
    end do
  end subroutine seed_hosts

  !> Where two groups of one body overlap (a frame composed of boxes): keep
  !> false for the particles of group b whose sub-box group a seeded
  !> already, so the body is the union of its shapes and no sub-box holds
  !> two particles. Both groups as `seed_shape` gives them (in cell order,
  !> then sub-box order), na and nb their particles per cell per direction;
  !> clash if they share a host cell with na /= nb (their sub-boxes differ:
  !> no union of the two is exact).
  pure subroutine seed_union(cell_a, xi_a, na, cell_b, xi_b, nb, keep, clash)
    integer, intent(in) :: cell_a(:), cell_b(:), na, nb
    real(wp), intent(in) :: xi_a(:, :), xi_b(:, :)
    logical, intent(out) :: keep(size(cell_b)), clash
    integer :: i, q
    keep = .true.
    clash = .false.
    i = 1
    do q = 1, size(cell_b)
      ! (the first particle of a at or after b's q-th in (cell, sub-box) order)
      do while (i <= size(cell_a))
        if (cell_a(i) > cell_b(q)) exit
        if (cell_a(i) == cell_b(q)) then
          if (na /= nb) then
            clash = .true.
            return
          end if
          if (sub_box(xi_a(:, i), na) >= sub_box(xi_b(:, q), nb)) exit
        end if
        i = i + 1
      end do
      if (i > size(cell_a)) exit
      if (cell_a(i) == cell_b(q)) keep(q) = sub_box(xi_a(:, i), na) /= sub_box(xi_b(:, q), nb)
    end do
  end subroutine seed_union

  !> The index (`seed_cell`'s order, i fastest) of the sub-box of a cell
  !> split n times per direction whose centre has natural coordinates xi.
  pure integer function sub_box(xi, n) result(s)
    real(wp), intent(in) :: xi(3)
    integer, intent(in) :: n
    integer :: d
    s = 0
    do d = 3, 1, -1
      s = n*s + min(n, max(1, int(xi(d)*real(n, wp)) + 1)) - 1
    end do
    s = s + 1
  end function sub_box

  !> The velocity (length/time) at x (length) of a body moving with velocity
  !> v0 and rotating rigidly at angular velocity omega (radians per unit
  !> time, counter-clockwise) about the unit axis `axis` through `center`:
  !> v = v0 + omega axis x (x - center).
  pure function rigid_velocity(v0, omega, axis, center, x) result(v)
    real(wp), intent(in) :: v0(3), omega, axis(3), center(3), x(3)
    real(wp) :: v(3)
    v = v0 + omega*cross(axis, x - center)
  end function rigid_velocity

  !> The volumes of particles at points with host cells cell(:) (0: not
  !> here, left 0): vfile(i), or when vfile is empty the host cell's volume
  !> / per_cell^3.
  pure subroutine seed_points(g, cell, vfile, per_cell, vol)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: cell(:), per_cell
    real(wp), intent(in) :: vfile(:)
    real(wp), intent(out) :: vol(:)
    real(wp) :: xn(3, 8)
    integer :: i
    vol = 0.0_wp
    do i = 1, size(cell)
      if (cell(i) == 0) cycle
      if (size(vfile) > 0) then
        vol(i) = vfile(i)
      else
        call g%gather(cell(i), g%x, xn)
        vol(i) = hex_volume(xn)/real(per_cell, wp)**3
      end if
    end do
  end subroutine seed_points
end module particles_seed
