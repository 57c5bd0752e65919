!> How much of each zone of a 1D spherical profile an axis-aligned box cell
!> holds: the overlaps that map a pre-run (`spherical_lagrange`) into the 3D
!> grid conservatively (`driver_prerun`).
!>
!> The cell is cut into nsub^3 sub-boxes; a sub-box at distance d from the
!> centre spans radii [d - h, d + h], h = sum_a |n_a| w_a/2 its half extent
!> along the radial direction n (w its widths), and its volume is spread
!> evenly over that span: each zone gets the part of the span it covers. A
!> zone thinner than a sub-box thus still gets its share from every sub-box
!> it crosses. The overlaps are approximate (the sub-boxes' volume does not
!> lie evenly in radius); the driver rescales each zone's overlaps over the
!> whole grid to the zone's exact volume, which makes the mapping conserve
!> mass, momentum and energy exactly.
module spherical_map
  use base_kinds, only: wp
  implicit none
  private
  public :: sphere_box_overlaps

contains

  !> Overlaps ov(k) of zones k = k1..k2 (radii rz(k-1)..rz(k), rz(0) = 0,
  !> zones up to kmap, rz(kmap) the mapped radius) with the box lo..hi, and
  !> their first moments mom(:, k) about the box's centre; vin is the box's
  !> volume inside rz(kmap) (the sum of the overlaps). k2 < k1 if none.
  !> ov and mom hold zones 1..kmap and must be zero on entry: the overlaps
  !> are added to them (the caller zeroes k1..k2 again after use).
  pure subroutine sphere_box_overlaps(lo, hi, centre, rz, kmap, nsub, k1, k2, ov, mom, vin)
    real(wp), intent(in) :: lo(3), hi(3), centre(3), rz(0:)
    integer, intent(in) :: kmap, nsub
    integer, intent(out) :: k1, k2
    real(wp), intent(inout) :: ov(:), mom(:, :)
    real(wp), intent(out) :: vin
    real(wp) :: w(3), dv, xs(3), xc(3), dx(3), d, h, a, b, part, rmap
    integer :: i, j, l, k, ka

    k1 = kmap + 1
    k2 = 0
    vin = 0.0_wp
    rmap = rz(kmap)
    ! the nearest point of the box beyond the mapped radius: nothing to do
    dx = max(lo - centre, 0.0_wp) + max(centre - hi, 0.0_wp)
    if (dot_product(dx, dx) >= rmap**2) return
    w = (hi - lo)/real(nsub, wp)
    dv = w(1)*w(2)*w(3)
    xc = 0.5_wp*(lo + hi)
    do l = 1, nsub
      do j = 1, nsub
        do i = 1, nsub
          xs = lo + w*(real([i, j, l], wp) - 0.5_wp)
          dx = xs - centre
          d = sqrt(dot_product(dx, dx))
          if (d > 0.0_wp) then
            h = 0.5_wp*sum(abs(dx)*w)/d
          else
            h = 0.5_wp*sqrt(dot_product(w, w))
          end if
          a = max(0.0_wp, d - h)
          b = d + h
          if (a >= rmap) cycle
          ! the first zone the span reaches (bisection on the radii)
          ka = first_zone(rz, kmap, a)
          do k = ka, kmap
            if (rz(k - 1) >= b) exit
            part = dv*(min(b, rz(k)) - max(a, rz(k - 1)))/(b - a)
            if (.not. part > 0.0_wp) cycle
            k1 = min(k1, k)
            k2 = max(k2, k)
            ov(k) = ov(k) + part
            mom(:, k) = mom(:, k) + part*(xs - xc)
            vin = vin + part
          end do
        end do
      end do
    end do
  end subroutine sphere_box_overlaps

  !> The zone k (1..kmap) with rz(k-1) <= r < rz(k) (kmap if r >= rz(kmap)).
  pure integer function first_zone(rz, kmap, r) result(k)
    real(wp), intent(in) :: rz(0:), r
    integer, intent(in) :: kmap
    integer :: lo, hi, mid
    lo = 1
    hi = kmap
    do while (lo < hi)
      mid = (lo + hi)/2
      if (rz(mid) <= r) then
        lo = mid + 1
      else
        hi = mid
      end if
    end do
    k = lo
  end function first_zone
end module spherical_map
