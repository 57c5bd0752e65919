!> Unit tests of the cell moments of the 24-tetrahedron split: the volume is
!> `hex_volume`'s, a box's centroid is its centre, and an affine map carries
!> the centroids along (the centroid of Eq. 49 is affine-covariant).
program test_remap_cells
  use base_kinds, only: wp
  use base_random, only: rng_t, rng_seed, rng_uniform
  use test_assert, only: check, check_summary
  use mesh_geometry, only: hex_volume
  use mesh_grid, only: block_gather
  use geometry_cells, only: cell_moments
  implicit none
  integer, parameter :: ni = 4, nj = 3, nk = 2, nc = ni*nj*nk, nn = (ni + 1)*(nj + 1)*(nk + 1)
  real(wp), parameter :: amap(3, 3) = reshape([1.1_wp, 0.2_wp, -0.1_wp, 0.3_wp, 0.9_wp, 0.05_wp, &
                                               -0.2_wp, 0.1_wp, 1.3_wp], [3, 3]), shift(3) = [0.5_wp, -2.0_wp, 7.0_wp]
  real(wp) :: x(3, nn), y(3, nn), vol(nc), cen(3, nc), voly(nc), ceny(3, nc), xn(3, 8), err_v, err_c, det
  type(rng_t) :: rng
  integer :: i, j, k, n, c

  ! a box grid: centroids are the box centres
  do k = 0, nk
    do j = 0, nj
      do i = 0, ni
        n = 1 + i + (ni + 1)*(j + (nj + 1)*k)
        x(:, n) = [0.5_wp*i, 0.25_wp*j, 0.4_wp*k]
      end do
    end do
  end do
  call cell_moments(ni, nj, nk, x, vol, cen)
  err_c = 0.0_wp
  do c = 1, nc
    i = mod(c - 1, ni); j = mod((c - 1)/ni, nj); k = (c - 1)/(ni*nj)
    err_c = max(err_c, maxval(abs(cen(:, c) - [0.5_wp*(i + 0.5_wp), 0.25_wp*(j + 0.5_wp), 0.4_wp*(k + 0.5_wp)])))
  end do
  call check(err_c < 1e-15_wp .and. maxval(abs(vol - 0.05_wp)) < 1e-16_wp, 'box cells: volume and centre exact')

  ! a randomly perturbed grid: volumes are hex_volume's; an affine map
  ! carries the centroids along and scales the volumes by its determinant
  call rng_seed(rng, 3)
  do n = 1, nn
    x(:, n) = x(:, n) + 0.08_wp*[2*rng_uniform(rng) - 1, 2*rng_uniform(rng) - 1, 2*rng_uniform(rng) - 1]
    y(:, n) = matmul(amap, x(:, n)) + shift
  end do
  call cell_moments(ni, nj, nk, x, vol, cen)
  call cell_moments(ni, nj, nk, y, voly, ceny)
  det = amap(1, 1)*(amap(2, 2)*amap(3, 3) - amap(3, 2)*amap(2, 3)) - amap(1, 2)*(amap(2, 1)*amap(3, 3) - &
        amap(3, 1)*amap(2, 3)) + amap(1, 3)*(amap(2, 1)*amap(3, 2) - amap(3, 1)*amap(2, 2))
  err_v = 0.0_wp
  err_c = 0.0_wp
  do c = 1, nc
    call block_gather(ni, nj, 1 + mod(c - 1, ni), 1 + mod((c - 1)/ni, nj), 1 + (c - 1)/(ni*nj), x, xn)
    err_v = max(err_v, abs(vol(c) - hex_volume(xn))/vol(c), abs(voly(c) - det*vol(c))/voly(c))
    err_c = max(err_c, maxval(abs(ceny(:, c) - matmul(amap, cen(:, c)) - shift)))
  end do
  write(*, '(a,es10.3,a,es10.3)') 'largest relative volume error ', err_v, ', centroid error ', err_c
  call check(err_v < 1e-13_wp, 'volumes equal hex_volume and scale with the determinant')
  call check(err_c < 1e-13_wp, 'centroids move with an affine map')
  call check_summary('test_remap_cells')
end program test_remap_cells
