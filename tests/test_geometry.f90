!> Unit tests of mesh_geometry: exact hex volume (against an explicit 24-tet
!> decomposition written independently here), its gradient (against finite
!> differences), subcell volumes, and the identities the scheme relies on.
program test_geometry
  use base_kinds, only: wp
  use base_random, only: rng_t, rng_seed, rng_uniform
  use mesh_geometry, only: hex_corner, hex_volume, hex_volume_gradient, hex_subcell_volumes, hex_median_areas
  use test_assert, only: check, check_summary
  implicit none
  real(wp) :: x0(3, 8), xn(3, 8), b(3, 8), vsub(8), vol, v24, s(3, 3), a(3, 3), xp(3, 8), xm(3, 8)
  real(wp) :: h, fd, m(3, 3)
  type(rng_t) :: rng
  integer :: n, trial, d

  ! unit cube, local order a = 1 + i + 2j + 4k
  x0 = real(hex_corner, wp)
  call check(abs(hex_volume(x0) - 1.0_wp) < 1e-15_wp, 'unit cube volume')
  call hex_median_areas(x0, s)
  call check(maxval(abs(s - reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3]))) < 1e-15_wp, &
             'median areas of the unit cube are the unit normals')

  ! affine map: the volume is |det A| exactly
  a = reshape([1.3_wp, 0.2_wp, -0.1_wp, 0.4_wp, 0.9_wp, 0.3_wp, 0.1_wp, -0.2_wp, 1.1_wp], [3, 3])
  xn = matmul(a, x0)
  call check(abs(hex_volume(xn) - det3(a))/det3(a) < 1e-14_wp, 'parallelepiped volume = det A')

  call rng_seed(rng, 7)
  do trial = 1, 50
    ! distorted hex with non-planar faces: every node moved by up to 0.3
    do n = 1, 8
      do d = 1, 3
        xn(d, n) = x0(d, n) + 0.6_wp*(rng_uniform(rng) - 0.5_wp)
      end do
    end do
    call hex_volume_gradient(xn, vol, b)
    v24 = volume_24_tets(xn)
    call check(abs(vol - v24) <= 1e-14_wp*abs(v24), 'volume equals the explicit 24-tet sum')
    call hex_subcell_volumes(xn, vsub)
    call check(abs(sum(vsub) - vol) <= 1e-14_wp*vol, 'subcell volumes sum to the cell volume')
    call check(all(vsub > 0.0_wp), 'subcell volumes positive for a mildly distorted hex')
    ! gradient against central differences (the volume is cubic: h^2 error)
    h = 1e-5_wp
    do n = 1, 8
      do d = 1, 3
        xp = xn; xm = xn
        xp(d, n) = xp(d, n) + h
        xm(d, n) = xm(d, n) - h
        fd = (hex_volume(xp) - hex_volume(xm))/(2.0_wp*h)
        call check(abs(fd - b(d, n)) < 1e-9_wp, 'volume gradient matches finite differences')
      end do
    end do
    ! translation invariance and sum_a x_a (x) b_a = V I (needed by the
    ! hourglass vectors and by momentum conservation)
    do d = 1, 3
      call check(abs(sum(b(d, :))) < 1e-14_wp, 'gradient sums to zero')
    end do
    m = matmul(xn, transpose(b))
    call check(maxval(abs(m - vol*reshape([1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 3]))) < 1e-13_wp, &
               'sum_a x_a b_a^T = V I')
  end do

  call check_summary('test_geometry')

contains


  real(wp) function det3(m3)
    real(wp), intent(in) :: m3(3, 3)
    det3 = m3(1, 1)*(m3(2, 2)*m3(3, 3) - m3(3, 2)*m3(2, 3)) &
         - m3(1, 2)*(m3(2, 1)*m3(3, 3) - m3(3, 1)*m3(2, 3)) &
         + m3(1, 3)*(m3(2, 1)*m3(3, 2) - m3(3, 1)*m3(2, 2))
  end function det3

  !> Fig. 7 split written out: 6 faces x 4 triangles, each joined to the
  !> cell centre; faces listed here independently of mesh_geometry.
  real(wp) function volume_24_tets(x)
    real(wp), intent(in) :: x(3, 8)
    integer, parameter :: face(4, 6) = reshape([1, 3, 7, 5,  2, 6, 8, 4,  1, 5, 6, 2, &
                                                3, 4, 8, 7,  1, 2, 4, 3,  5, 7, 8, 6], [4, 6])
    real(wp) :: xc(3), xf(3), t(3, 3)
    integer :: f, e
    xc = sum(x, 2)/8.0_wp
    volume_24_tets = 0.0_wp
    do f = 1, 6
      xf = sum(x(:, face(:, f)), 2)/4.0_wp
      do e = 1, 4
        ! this list runs clockwise seen from outside, so the tet is (c, f, b, a)
        t(:, 1) = xf - xc
        t(:, 2) = x(:, face(mod(e, 4) + 1, f)) - xc
        t(:, 3) = x(:, face(e, f)) - xc
        volume_24_tets = volume_24_tets + det3(t)/6.0_wp
      end do
    end do
  end function volume_24_tets
end program test_geometry
