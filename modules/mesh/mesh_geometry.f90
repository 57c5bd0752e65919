!> Geometry kernels of one hexahedral cell: exact volume, its gradient with
!> respect to the eight node positions, and subcell (corner) volumes.
!>
!> Local node numbering: a = 1 + i + 2*j + 4*k for the corner (i,j,k) in {0,1}^3.
!> The volume is that of the 24-tetrahedron split of Fig. 7 (each face split
!> into four triangles through its face centre, each triangle joined to the cell
!> centre), which is exact for non-planar faces. Summing the tetrahedra gives
!>   V = sum_f (1/24) s_f . (d1_f x d2_f)                      (*)
!> with d1, d2 the face diagonals and s_f the sum of the face's four nodes; (*)
!> is what the kernels evaluate, and its gradient is exact (not a one-point
!> quadrature), so p dV/dt computed from node velocities equals the work of the
!> corner forces of Eq. (18) exactly.
module mesh_geometry
  use base_kinds, only: wp
  implicit none
  private
  public :: hex_corner, hex_faces, hex_edges, hex_volume, hex_volume_gradient, hex_subcell_volumes, &
            hex_median_areas, hex_trilinear, hex_jacobian, hex_natural, hex_natural_unclamped, hex_tets, tet_det, cross

  !> Logical corner (i,j,k) in {0,1}^3 of local node a = 1 + i + 2j + 4k.
  integer, parameter :: hex_corner(3, 8) = reshape([0, 0, 0,  1, 0, 0,  0, 1, 0,  1, 1, 0, &
                                                    0, 0, 1,  1, 0, 1,  0, 1, 1,  1, 1, 1], [3, 8])
  !> Nodes of the six faces, ordered counter-clockwise seen from outside:
  !> xi-, xi+, eta-, eta+, zeta-, zeta+.
  integer, parameter :: hex_faces(4, 6) = reshape([1, 5, 7, 3,  2, 4, 8, 6, &
                                                   1, 2, 6, 5,  3, 7, 8, 4, &
                                                   1, 3, 4, 2,  5, 6, 8, 7], [4, 6])
  !> The four edges along each logical direction d, as (low node, high node)
  !> pairs ordered e00, e11, e01, e10 in the two transverse directions (cyclic
  !> order), so that 1/2 (m11 - m00) x (m01 - m10) of the edge midpoints m is
  !> the median surface area vector pointing along +d.
  integer, parameter :: hex_edges(2, 4, 3) = reshape([1, 2,  7, 8,  5, 6,  3, 4, &
                                                      1, 3,  6, 8,  2, 4,  5, 7, &
                                                      1, 5,  4, 8,  3, 7,  2, 6], [2, 4, 3])

contains

  !> Cross product of two 3-vectors.
  pure function cross(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)
    real(wp) :: c(3)
    c(1) = a(2)*b(3) - a(3)*b(2)
    c(2) = a(3)*b(1) - a(1)*b(3)
    c(3) = a(1)*b(2) - a(2)*b(1)
  end function cross

  !> Node positions relative to the cell centre (the mean of the eight nodes),
  !> which keeps round-off small in the volume sums.
  pure function centred(xn) result(r)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: r(3, 8)
    real(wp) :: xc(3)
    integer :: a
    do a = 1, 3
      xc(a) = 0.125_wp*sum(xn(a, :))
    end do
    do a = 1, 8
      r(:, a) = xn(:, a) - xc
    end do
  end function centred

  !> Exact volume of a hexahedron with node positions xn(3,8) (length^3):
  !> the sum (*) alone, without the gradient.
  pure function hex_volume(xn) result(vol)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: vol
    real(wp) :: r(3, 8)
    integer :: f, n1, n2, n3, n4

    r = centred(xn)
    vol = 0.0_wp
    ! (unrolled whole: the faces' nodes by constant indices, not read from
    ! the table at every call; the remap's hot paths call this per cell)
    !GCC$ unroll 6
    do f = 1, 6
      n1 = hex_faces(1, f); n2 = hex_faces(2, f); n3 = hex_faces(3, f); n4 = hex_faces(4, f)
      vol = vol + dot_product(r(:, n1) + r(:, n2) + r(:, n3) + r(:, n4), &
                              cross(r(:, n3) - r(:, n1), r(:, n4) - r(:, n2)))
    end do
    vol = vol/24.0_wp
  end function hex_volume

  !> Exact volume `vol` and its gradient b(:,a) = dV/dx_a (length^2).
  !> Positions are taken relative to the cell centre to limit round-off; the
  !> sum (*) does not depend on the origin, so neither does its gradient.
  pure subroutine hex_volume_gradient(xn, vol, b)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: vol
    real(wp), intent(out) :: b(3, 8)
    real(wp) :: r(3, 8), d1(3), d2(3), s(3), c(3), sd1(3), sd2(3)
    integer :: f, n1, n2, n3, n4

    r = centred(xn)
    b = 0.0_wp
    vol = 0.0_wp
    do f = 1, 6
      n1 = hex_faces(1, f); n2 = hex_faces(2, f); n3 = hex_faces(3, f); n4 = hex_faces(4, f)
      d1 = r(:, n3) - r(:, n1)
      d2 = r(:, n4) - r(:, n2)
      s = r(:, n1) + r(:, n2) + r(:, n3) + r(:, n4)
      c = cross(d1, d2)
      sd1 = cross(s, d1)
      sd2 = cross(s, d2)
      vol = vol + dot_product(s, c)
      b(:, n1) = b(:, n1) + c + sd2
      b(:, n2) = b(:, n2) + c - sd1
      b(:, n3) = b(:, n3) + c - sd2
      b(:, n4) = b(:, n4) + c + sd1
    end do
    vol = vol/24.0_wp
    b = b/24.0_wp
  end subroutine hex_volume_gradient

  !> Subcell volumes vsub(a) of the eight corners (length^3): corner a owns,
  !> of every face triangle (face centre, a, neighbour), the half-tetrahedron on
  !> its side of the edge midpoint. They sum exactly to the cell volume.
  pure subroutine hex_subcell_volumes(xn, vsub)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: vsub(8)
    real(wp) :: r(3, 8), xf(3), t
    integer :: f, m, na, nb

    r = centred(xn)
    vsub = 0.0_wp
    ! (unrolled whole, as `hex_volume`'s: constant indices)
    !GCC$ unroll 6
    do f = 1, 6
      xf = 0.25_wp*(r(:, hex_faces(1, f)) + r(:, hex_faces(2, f)) + &
                    r(:, hex_faces(3, f)) + r(:, hex_faces(4, f)))
      do m = 1, 4
        na = hex_faces(m, f)
        nb = hex_faces(mod(m, 4) + 1, f)
        ! tetrahedron (centre, a, b, face centre), outward orientation
        t = dot_product(xf, cross(r(:, na), r(:, nb)))/12.0_wp
        vsub(na) = vsub(na) + t
        vsub(nb) = vsub(nb) + t
      end do
    end do
  end subroutine hex_subcell_volumes

  !> Median-surface area vectors s(:,d) of the three logical directions
  !> (length^2): the area of the surface through the midpoints of the four
  !> d-edges, oriented along +d; for a parallelepiped it equals the face area.
  pure subroutine hex_median_areas(xn, s)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: s(3, 3)
    real(wp) :: m(3, 4)
    integer :: d, e

    do d = 1, 3
      do e = 1, 4
        m(:, e) = xn(:, hex_edges(1, e, d)) + xn(:, hex_edges(2, e, d))
      end do
      ! midpoints are m/2, so the area 1/2 (m11-m00)/2 x (m01-m10)/2 is 1/8 of this
      s(:, d) = 0.125_wp*cross(m(:, 2) - m(:, 1), m(:, 3) - m(:, 4))
    end do
  end subroutine hex_median_areas
  !> Position (length) at natural coordinates xi in [-1,1]^3 of the hex with
  !> nodes xn: the trilinear map x = sum_a N_a(xi) x_a.
  pure function hex_trilinear(xn, xi) result(x)
    real(wp), intent(in) :: xn(3, 8), xi(3)
    real(wp) :: x(3)
    integer :: a
    real(wp) :: s(3)
    x = 0.0_wp
    do a = 1, 8
      s = 2.0_wp*real(hex_corner(:, a), wp) - 1.0_wp
      x = x + 0.125_wp*(1.0_wp + s(1)*xi(1))*(1.0_wp + s(2)*xi(2))*(1.0_wp + s(3)*xi(3))*xn(:, a)
    end do
  end function hex_trilinear

  !> Jacobian determinant det(dx/dxi) of `hex_trilinear` at xi (length^3 per
  !> unit natural volume: the cell's volume is its integral over [-1,1]^3;
  !> constant, V/8, for a parallelepiped).
  pure real(wp) function hex_jacobian(xn, xi) result(det)
    real(wp), intent(in) :: xn(3, 8), xi(3)
    real(wp) :: jac(3, 3), s(3), f(3)
    integer :: a
    jac = 0.0_wp
    do a = 1, 8
      s = 2.0_wp*real(hex_corner(:, a), wp) - 1.0_wp
      f = 1.0_wp + s*xi
      jac(:, 1) = jac(:, 1) + 0.125_wp*s(1)*f(2)*f(3)*xn(:, a)
      jac(:, 2) = jac(:, 2) + 0.125_wp*s(2)*f(1)*f(3)*xn(:, a)
      jac(:, 3) = jac(:, 3) + 0.125_wp*s(3)*f(1)*f(2)*xn(:, a)
    end do
    det = dot_product(jac(:, 1), cross(jac(:, 2), jac(:, 3)))
  end function hex_jacobian

  !> Natural coordinates of x in the hex xn: the inverse of
  !> `hex_trilinear` by Newton's method from the centre (exact in one step
  !> for a parallelepiped). A point outside the cell, or a cell whose map is
  !> singular, gives the last iterate clamped to [-1,1]^3, so the result is
  !> always a point of the cell's natural cube.
  pure function hex_natural(xn, x) result(xi)
    real(wp), intent(in) :: xn(3, 8), x(3)
    real(wp) :: xi(3)
    real(wp) :: dxi(3)
    logical :: done
    integer :: it

    xi = 0.0_wp
    do it = 1, 20
      call natural_step(xn, x, xi, dxi, done)
      if (done) exit
      xi = min(max(xi + dxi, -1.0_wp), 1.0_wp)
    end do
  end function hex_natural

  !> `hex_natural` not clamped, so that a point outside the cell says on
  !> which side it lies (iterates leaving [-4,4]^3 stop: the side is then
  !> clear; a singular map stops at the last iterate).
  pure function hex_natural_unclamped(xn, x) result(xi)
    real(wp), intent(in) :: xn(3, 8), x(3)
    real(wp) :: xi(3)
    real(wp) :: dxi(3)
    logical :: done
    integer :: it

    xi = 0.0_wp
    do it = 1, 30
      call natural_step(xn, x, xi, dxi, done)
      if (done) exit
      xi = xi + dxi
      if (maxval(abs(xi)) > 4.0_wp .or. maxval(abs(dxi)) <= 1.0e-14_wp) exit
    end do
  end function hex_natural_unclamped

  !> One Newton step of the inverse trilinear map at xi: the correction dxi
  !> (Cramer's rule on the Jacobian of `hex_trilinear`); `done` when the
  !> residual is below 1e-14 of the cell's size or the map is singular.
  pure subroutine natural_step(xn, x, xi, dxi, done)
    real(wp), intent(in) :: xn(3, 8), x(3), xi(3)
    real(wp), intent(out) :: dxi(3)
    logical, intent(out) :: done
    real(wp) :: r(3), jac(3, 3), s(3), nfun, det, c(3, 3), scale
    integer :: a, d

    dxi = 0.0_wp
    done = .true.
    scale = maxval(abs(xn(:, 8) - xn(:, 1))) + maxval(abs(xn(:, 7) - xn(:, 2)))
    r = x - hex_trilinear(xn, xi)
    if (norm2(r) <= 1.0e-14_wp*scale) return
    jac = 0.0_wp
    do a = 1, 8
      s = 2.0_wp*real(hex_corner(:, a), wp) - 1.0_wp
      do d = 1, 3
        nfun = 0.125_wp*s(d)
        if (d /= 1) nfun = nfun*(1.0_wp + s(1)*xi(1))
        if (d /= 2) nfun = nfun*(1.0_wp + s(2)*xi(2))
        if (d /= 3) nfun = nfun*(1.0_wp + s(3)*xi(3))
        jac(:, d) = jac(:, d) + nfun*xn(:, a)
      end do
    end do
    c(:, 1) = cross(jac(:, 2), jac(:, 3))
    c(:, 2) = cross(jac(:, 3), jac(:, 1))
    c(:, 3) = cross(jac(:, 1), jac(:, 2))
    det = dot_product(jac(:, 1), c(:, 1))
    if (.not. abs(det) > tiny(1.0_wp)) return
    do d = 1, 3
      dxi(d) = dot_product(c(:, d), r)/det
    end do
    done = .false.
  end subroutine natural_step

  !> Six times the signed volume of the tetrahedron t(3,4) (length^3).
  pure function tet_det(t) result(det)
    real(wp), intent(in) :: t(3, 4)
    real(wp) :: det
    real(wp) :: a(3), b(3), c(3)
    ! (written out: the remap calls it tens of times per cell)
    a = t(:, 2) - t(:, 1)
    b = t(:, 3) - t(:, 1)
    c = t(:, 4) - t(:, 1)
    det = a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) + a(3)*(b(1)*c(2) - b(2)*c(1))
  end function tet_det

  !> The 24-tetrahedron split of the hexahedron xn(3,8) (Fig. 7; length):
  !> tetrahedron 4(f-1)+m is (cell centre, centre of face f, node a, node b)
  !> with (a, b) the m-th edge of `hex_faces`(:,f), counter-clockwise seen
  !> from outside, so every tetrahedron of a valid cell is positive.
  !> The face centre is the mean of its four nodes and the cell centre the
  !> mean of the eight, as in `hex_volume`, so the split's volumes sum to it
  !> and two cells sharing a face share its four triangles (the split of a
  !> grid is a partition, which makes Eq. (54)-(57) conservative). The side
  !> centres of Fig. 7 lie on the edges and add no tetrahedra. The cell
  !> centroid of Eq. (49) is not the apex: it is what the split yields,
  !> sum_k x_tk V_tk / V.
  pure subroutine hex_tets(xn, tets)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: tets(3, 4, 24)
    real(wp) :: xc(3), xf(3)
    integer :: f, m, k, i

    do i = 1, 3
      xc(i) = 0.125_wp*sum(xn(i, :))
    end do
    do f = 1, 6
      ! diagonal pairs first: the neighbour lists the face in another cyclic
      ! order and direction, which keeps the pairs, so both cells get the
      ! same bits and their triangles match exactly
      xf = 0.25_wp*((xn(:, hex_faces(1, f)) + xn(:, hex_faces(3, f))) + &
                    (xn(:, hex_faces(2, f)) + xn(:, hex_faces(4, f))))
      do m = 1, 4
        k = 4*(f - 1) + m
        tets(:, 1, k) = xc
        tets(:, 2, k) = xf
        tets(:, 3, k) = xn(:, hex_faces(m, f))
        tets(:, 4, k) = xn(:, hex_faces(mod(m, 4) + 1, f))
      end do
    end do
  end subroutine hex_tets
end module mesh_geometry
