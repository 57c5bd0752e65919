!> Unit tests of the gauges (`io_gauges`): the walk finds the cell that
!> contains the point, a linear field reads exactly (cell fields between the
!> cell centres of an affine grid, the velocity from the nodes on any grid),
!> a uniform field reads bit for bit, the reading is continuous across cell
!> faces of a distorted grid (both cells sharing a face give the same values
!> on it), and `text_rows_trim` keeps the header and the rows up to a time.
program test_io_gauges
  use base_kinds, only: wp, i8
  use base_errors, only: error_t
  use base_random, only: rng_t, rng_seed, rng_uniform
  use test_assert, only: check, check_close, check_summary
  use mesh_grid, only: grid_t, grid_init_box
  use mesh_geometry, only: hex_trilinear
  use hydro_state, only: hydro_t, hydro_allocate
  use io_gauges, only: gauge_locate, gauge_sample, gauge_nfield, text_rows_trim
  implicit none

  integer, parameter :: ni = 7, nj = 5, nk = 4
  !> an affine map x = a xl + b of the logical box [0,ni]x[0,nj]x[0,nk] (unit cells)
  real(wp), parameter :: amap(3, 3) = reshape([0.30_wp, 0.05_wp, -0.02_wp, &
                                                0.10_wp, 0.45_wp, 0.04_wp, &
                                                -0.03_wp, 0.07_wp, 0.60_wp], [3, 3])
  real(wp), parameter :: bmap(3) = [10.0_wp, -2.0_wp, 3.5_wp]
  !> the linear cell field rho = r0 + rg . x and node velocity u = ug x + u0
  real(wp), parameter :: r0 = 1.5_wp, rg(3) = [0.7_wp, -0.4_wp, 0.25_wp]
  real(wp), parameter :: ug(3, 3) = reshape([1.0_wp, -0.5_wp, 0.2_wp, 0.3_wp, 2.0_wp, -0.1_wp, &
                                             -0.7_wp, 0.4_wp, 0.9_wp], [3, 3])
  real(wp), parameter :: u0(3) = [0.1_wp, -0.2_wp, 0.3_wp]
  type(grid_t) :: g
  type(hydro_t) :: h
  type(rng_t) :: rng

  call rng_seed(rng, 13)
  call linear_fields_exact()
  call uniform_field_exact()
  call continuous_across_faces()
  call trim_rows()
  call check_summary('test_io_gauges')

contains

  !> A grid of unit logical cells mapped by (amap, bmap), nodes moved at
  !> random by up to amp of a cell (logical), fields set from their linear
  !> definitions (cells at the mean of their nodes; on an affine grid the
  !> centroid) or (wavy) from a smooth nonlinear cell field.
  subroutine build(amp, wavy)
    real(wp), intent(in) :: amp
    logical, intent(in) :: wavy
    type(error_t), allocatable :: err
    real(wp) :: xn(3, 8), xc(3), xl(3)
    integer :: c, n, d, i, j, k

    call grid_init_box(g, ni, nj, nk, [0.0_wp, 0.0_wp, 0.0_wp], real([ni, nj, nk], wp), err)
    call check(.not. allocated(err), 'grid_init_box')
    do k = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        do i = g%nlo(1), g%nhi(1)
          n = g%node(i, j, k)
          xl = g%x(:, n)
          if (g%node_faces(i, j, k) == 0) then
            do d = 1, 3
              xl(d) = xl(d) + amp*(2.0_wp*rng_uniform(rng) - 1.0_wp)
            end do
          end if
          g%x(:, n) = matmul(amap, xl) + bmap
        end do
      end do
    end do
    if (allocated(h%u)) h = hydro_t()
    call hydro_allocate(h, g%ncell, g%nnode, err)
    call check(.not. allocated(err), 'hydro_allocate')
    do c = 1, g%ncell
      call g%gather(c, g%x, xn)
      xc = sum(xn, 2)/8.0_wp
      if (wavy) then
        h%rho(c) = field_wavy(xc)
      else
        h%rho(c) = r0 + dot_product(rg, xc)
      end if
      h%p(c) = 2.0_wp*h%rho(c)
      h%e(c) = -h%rho(c)
      h%cs(c) = 0.5_wp*h%rho(c) + 1.0_wp
    end do
    do n = 1, g%nnode
      h%u(:, n) = matmul(ug, g%x(:, n)) + u0
    end do
  end subroutine build

  pure real(wp) function field_wavy(x)
    real(wp), intent(in) :: x(3)
    field_wavy = 2.0_wp + sin(3.0_wp*x(1))*cos(2.0_wp*x(2)) + x(3)**2
  end function field_wavy

  !> A point at logical coordinates xl of the affine grid.
  pure function at_logical(xl) result(x)
    real(wp), intent(in) :: xl(3)
    real(wp) :: x(3)
    x = matmul(amap, xl) + bmap
  end function at_logical

  !> On the affine grid, 200 random points with every logical coordinate
  !> between the first and last cell centres read the linear cell field
  !> exactly (1e-12 relative: Newton's xi to ~1e-14, a few roundings), and
  !> 200 points anywhere (boundary half cells too) read the linear velocity
  !> exactly; the walk from cell 1 ends in a cell whose trilinear map gives
  !> the point back at the returned xi. On a distorted grid (nodes moved by
  !> up to 0.3 cells) the velocity is still exact and the cell still found.
  subroutine linear_fields_exact()
    real(wp) :: xl(3), p(3), vals(gauge_nfield), xi(3), xn(3, 8), err_rho, err_u, err_x, scale
    integer :: it, c, d, pass

    do pass = 1, 2
      call build(merge(0.0_wp, 0.3_wp, pass == 1), .false.)
      err_rho = 0.0_wp
      err_u = 0.0_wp
      err_x = 0.0_wp
      c = 1
      do it = 1, 400
        do d = 1, 3
          if (it <= 200) then
            xl(d) = 0.5_wp + rng_uniform(rng)*(real(dims(d), wp) - 1.0_wp)   ! between first and last centres
          else
            xl(d) = rng_uniform(rng)*real(dims(d), wp)                        ! anywhere in the box
          end if
        end do
        p = at_logical(xl)
        call gauge_locate(g, p, 1, c, xi)
        call g%gather(c, g%x, xn)
        err_x = max(err_x, norm2(hex_trilinear(xn, xi) - p))
        call gauge_sample(g, h, p, c, vals)
        if (it <= 200 .and. pass == 1) err_rho = max(err_rho, abs(vals(1) - (r0 + dot_product(rg, p))))
        err_u = max(err_u, maxval(abs(vals(5:7) - (matmul(ug, p) + u0))))
      end do
      scale = maxval(abs(bmap)) + 10.0_wp
      if (pass == 1) then
        call check_close('affine grid: linear cell field at 200 interior points, largest error', err_rho, &
                         0.0_wp, 1.0e-12_wp*scale)
        call check_close('affine grid: linear velocity at 400 points, largest error', err_u, 0.0_wp, &
                         1.0e-12_wp*scale*10.0_wp)
        call check_close('affine grid: |x(cell, xi) - point| after the walk from cell 1', err_x, 0.0_wp, &
                         1.0e-12_wp*scale)
      else
        call check_close('distorted grid: linear velocity at 400 points, largest error', err_u, 0.0_wp, &
                         1.0e-12_wp*scale*10.0_wp)
        call check_close('distorted grid: |x(cell, xi) - point| after the walk from cell 1', err_x, 0.0_wp, &
                         1.0e-12_wp*scale)
      end if
    end do
  end subroutine linear_fields_exact

  pure integer function dims(d)
    integer, intent(in) :: d
    integer, parameter :: n(3) = [ni, nj, nk]
    dims = n(d)
  end function dims

  !> A uniform density reads exactly that number everywhere (the lerps of
  !> equal values are exact), whatever the grid.
  subroutine uniform_field_exact()
    real(wp) :: xl(3), p(3), vals(gauge_nfield)
    integer :: it, c, d
    logical :: same
    call build(0.3_wp, .false.)
    h%rho = 0.1_wp
    same = .true.
    c = 1
    do it = 1, 200
      do d = 1, 3
        xl(d) = rng_uniform(rng)*real(dims(d), wp)
      end do
      p = at_logical(xl)
      call gauge_sample(g, h, p, c, vals)
      same = same .and. transfer(vals(1), 1_i8) == transfer(0.1_wp, 1_i8)
    end do
    call check(same, 'a uniform density 0.1 reads 0.1 exactly at 200 points of a distorted grid')
  end subroutine uniform_field_exact

  !> Continuity: on a distorted grid with a nonlinear cell field, two points
  !> 1e-9 (in natural coordinates) on either side of a face shared by cells A
  !> and B, at the same place on the face, are found in A and in B and read
  !> values within 1e-7 (relative; gradients are O(10) in these units, so
  !> a continuous reading differs by ~1e-8 and a jump between cells by
  !> ~0.1), over 300 random interior faces of the three directions; a point
  !> on the face itself belongs to A (the lower cell) whichever cell the
  !> search starts from; and along a line through the grid the largest
  !> change between neighbouring samples halves when the sample spacing
  !> does (no jump anywhere).
  subroutine continuous_across_faces()
    real(wp), parameter :: off = 1.0e-9_wp
    real(wp) :: xn(3, 8), xi(3), p(3), va(gauge_nfield), vb(gauge_nfield), worst, p0(3), p1(3), jump(2)
    integer :: it, d, ijk(3), ca, cb, cc, nwrong, nface, k, nsamp, pass
    integer :: stride(3)
    real(wp) :: v_prev(gauge_nfield), v(gauge_nfield)

    call build(0.3_wp, .true.)
    stride = [1, g%cx, g%cxy]
    worst = 0.0_wp
    nwrong = 0
    nface = 0
    do it = 1, 300
      d = mod(it, 3) + 1
      ! cell A with a neighbour B on its high side along d
      ijk(1) = 1 + int(rng_uniform(rng)*ni)
      ijk(2) = 1 + int(rng_uniform(rng)*nj)
      ijk(3) = 1 + int(rng_uniform(rng)*nk)
      ijk(d) = 1 + int(rng_uniform(rng)*(dims(d) - 1))
      ca = g%cell(ijk(1), ijk(2), ijk(3))
      cb = ca + stride(d)
      xi = [2.0_wp*rng_uniform(rng) - 1.0_wp, 2.0_wp*rng_uniform(rng) - 1.0_wp, 2.0_wp*rng_uniform(rng) - 1.0_wp]
      xi(d) = 1.0_wp - off
      call g%gather(ca, g%x, xn)
      p = hex_trilinear(xn, xi)
      cc = cb
      call gauge_sample(g, h, p, cc, va)
      if (cc /= ca) nwrong = nwrong + 1
      xi(d) = -1.0_wp + off
      call g%gather(cb, g%x, xn)
      p = hex_trilinear(xn, xi)
      cc = ca
      call gauge_sample(g, h, p, cc, vb)
      if (cc /= cb) nwrong = nwrong + 1
      worst = max(worst, maxval(abs(va - vb)/(abs(va) + 1.0_wp)))
      ! on the face itself: cell A from either side
      xi(d) = -1.0_wp
      p = hex_trilinear(xn, xi)
      cc = cb
      call gauge_sample(g, h, p, cc, vb)
      if (cc /= ca) nface = nface + 1
    end do
    call check(nwrong == 0, 'points 1e-9 inside A or B are found in A or B, starting from the other cell')
    call check(nface == 0, 'a point on the face of A and B is found in A (the lower), starting from B')
    call check_close('300 faces: largest relative difference across the face', worst, 0.0_wp, 1.0e-7_wp)

    ! along the line between two points near opposite corners
    p0 = at_logical([0.3_wp, 0.4_wp, 0.2_wp])
    p1 = at_logical([real(ni, wp) - 0.2_wp, real(nj, wp) - 0.5_wp, real(nk, wp) - 0.3_wp])
    do pass = 1, 2
      nsamp = 2000*pass
      jump(pass) = 0.0_wp
      cc = 1
      do k = 0, nsamp
        p = p0 + (p1 - p0)*(real(k, wp)/real(nsamp, wp))
        call gauge_sample(g, h, p, cc, v)
        if (k > 0) jump(pass) = max(jump(pass), maxval(abs(v(1:4) - v_prev(1:4))))
        v_prev = v
      end do
    end do
    write(*, '(a,2es12.4)') 'largest change between neighbouring samples along a line, 2000 and 4000 samples:', jump
    call check_close('that change with half the spacing, as a ratio (continuous: 0.5)', jump(2)/jump(1), 0.5_wp, &
                     0.05_wp)
  end subroutine continuous_across_faces

  !> text_rows_trim keeps the header and the rows up to t_keep.
  subroutine trim_rows()
    type(error_t), allocatable :: err
    character(len=*), parameter :: path = 'test_io_gauges_trim.txt'
    character(len=80) :: line
    integer :: u, ios, nrow, nhead
    real(wp) :: t, tlast
    open(newunit=u, file=path, status='replace', action='write')
    write(u, '(a)') '# header'
    write(u, '(a)') '# time a b'
    write(u, '(3es24.16)') 0.0_wp, 1.0_wp, 2.0_wp
    write(u, '(3es24.16)') 0.1_wp, 1.0_wp, 2.0_wp
    write(u, '(3es24.16)') 0.2_wp, 1.0_wp, 2.0_wp
    write(u, '(3es24.16)') 0.3_wp, 1.0_wp, 2.0_wp
    close(u)
    call text_rows_trim(path, 0.2_wp, err)
    call check(.not. allocated(err), 'text_rows_trim runs')
    open(newunit=u, file=path, status='old', action='read')
    nrow = 0
    nhead = 0
    tlast = -1.0_wp
    do
      read(u, '(a)', iostat=ios) line
      if (ios /= 0) exit
      if (line(1:1) == '#') then
        nhead = nhead + 1
      else
        read(line, *) t
        tlast = t
        nrow = nrow + 1
      end if
    end do
    close(u, status='delete')
    call check(nhead == 2 .and. nrow == 3, 'trimmed at t = 0.2: the 2 header lines and the rows at 0, 0.1, 0.2 remain')
    call check_close('last row kept', tlast, 0.2_wp, 0.0_wp)
  end subroutine trim_rows
end program test_io_gauges
