!> The region a triangle sweeps as its vertices move in straight lines: the
!> geometric kernel of the swept-face (flux-form) remap of `remap_euler`
!> (Margolin and Shashkov's swept regions, applied to the triangles that
!> bound the cells' subcells; Loubere and Shashkov's subcell remap).
!>
!> A triangle with vertices p_i moving to q_i = p_i + d_i sweeps
!>   x(xi, t) = p_1 + xi_1 e_1 + xi_2 e_2 + t D(xi),   0 <= t <= 1,
!> e_i = p_{i+1} - p_1 and D(xi) = d_1 + xi_1 g_1 + xi_2 g_2 (g_i = d_{i+1} - d_1)
!> over the reference triangle xi_1, xi_2 >= 0, xi_1 + xi_2 <= 1. Its sides
!> are the ruled (bilinear) surfaces between an old edge and its new
!> position, fixed by the edge's two end points alone, so a side is the same
!> surface for the two triangles that share the edge: the swept volumes of a
!> closed surface of triangles add up to the change of the volume it
!> encloses (with flat triangles as caps, as the 24- and 48-tetrahedron
!> splits of a cell bound their pieces), whatever the motion, and the
!> integral of any field over them to the change of its integral. The
!> Jacobian is
!>   J = (x_xi1 x x_xi2) . x_t = (A + t B + t^2 C) . D(xi),
!>   A = e_1 x e_2, B = e_1 x g_2 + g_1 x e_2, C = g_1 x g_2,
!> so the signed volume is exactly
!>   V = (A + B/2 + C/3) . (d_1 + d_2 + d_3)/6,
!> positive when the triangle moves along its normal A (vertices counter-
!> clockwise seen from the side it moves to). The first moment integrates
!> x J, of degree 2 in xi and 3 in t: the three-point rule on the triangle
!> (exact to degree 2) times two Gauss points in t (exact to degree 3) give
!> it exactly.
module remap_swept
  use base_kinds, only: wp
  use mesh_geometry, only: cross
  implicit none
  private
  public :: swept_triangle

  !> Gauss points of [0, 1] (two: exact to degree 3).
  real(wp), parameter :: tg(2) = [0.5_wp - 0.5_wp/sqrt(3.0_wp), 0.5_wp + 0.5_wp/sqrt(3.0_wp)]
  !> The triangle's interior three-point rule (barycentric xi_1, xi_2).
  real(wp), parameter :: xq(2, 3) = reshape([1.0_wp/6.0_wp, 1.0_wp/6.0_wp, 2.0_wp/3.0_wp, 1.0_wp/6.0_wp, &
                                             1.0_wp/6.0_wp, 2.0_wp/3.0_wp], [2, 3])

contains

  !> Signed volume v and first moment m of the region swept by the triangle
  !> p(:, 1:3) moving to q(:, 1:3) (module header; positive along the
  !> normal (p2 - p1) x (p3 - p1)). Lengths in any unit; v in its cube, m
  !> in its fourth power, about the coordinates' origin.
  pure subroutine swept_triangle(p, q, v, m)
    real(wp), intent(in) :: p(3, 3), q(3, 3)
    real(wp), intent(out) :: v, m(3)
    real(wp) :: e1(3), e2(3), d1(3), g1(3), g2(3), a(3), b(3), c(3), nt(3), dd(3), jw
    integer :: it, iq
    e1 = p(:, 2) - p(:, 1)
    e2 = p(:, 3) - p(:, 1)
    d1 = q(:, 1) - p(:, 1)
    g1 = (q(:, 2) - p(:, 2)) - d1
    g2 = (q(:, 3) - p(:, 3)) - d1
    a = cross(e1, e2)
    b = cross(e1, g2) + cross(g1, e2)
    c = cross(g1, g2)
    v = dot_product(a + 0.5_wp*b + c/3.0_wp, 3.0_wp*d1 + g1 + g2)/6.0_wp
    m = 0.0_wp
    do it = 1, 2
      nt = a + tg(it)*(b + tg(it)*c)
      do iq = 1, 3
        dd = d1 + xq(1, iq)*g1 + xq(2, iq)*g2
        ! weight: 1/2 (Gauss) x 1/6 (a third of the triangle's area 1/2)
        jw = dot_product(nt, dd)/12.0_wp
        m = m + jw*(p(:, 1) + xq(1, iq)*e1 + xq(2, iq)*e2 + tg(it)*dd)
      end do
    end do
  end subroutine swept_triangle
end module remap_swept
