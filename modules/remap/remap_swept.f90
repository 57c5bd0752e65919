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
!> clockwise seen from the side it moves to). The first moment, the
!> integral of x J with x = p_1 + xi.E + t D, is as exact: with
!> n0 = A + B/2 + C/3 and n1 = A/2 + B/3 + C/4 (the integrals of N and tN
!> over t) it is the triangle's polynomial integrals of
!> (p_1 + xi.E)(n0 . D) and D (n1 . D).
module remap_swept
  use base_kinds, only: wp
  implicit none
  private
  public :: swept_triangle

contains

  !> Signed volume v and first moment m of the region swept by the triangle
  !> p1, p2, p3 moving to q1, q2, q3 (module header; positive along the
  !> normal (p2 - p1) x (p3 - p1)). Lengths in any unit; v in its cube, m
  !> in its fourth power, about the coordinates' origin. (The points one by
  !> one: a caller passes its arrays' columns, no copies.)
  pure subroutine swept_triangle(p1, p2, p3, q1, q2, q3, v, m)
    real(wp), intent(in) :: p1(3), p2(3), p3(3), q1(3), q2(3), q3(3)
    real(wp), intent(out) :: v, m(3)
    ! (the weights as products: a division is several times a product's cost)
    real(wp), parameter :: r3 = 1.0_wp/3.0_wp, r6 = 1.0_wp/6.0_wp, r12 = 1.0_wp/12.0_wp, r24 = 1.0_wp/24.0_wp
    real(wp) :: e1(3), e2(3), d1(3), g1(3), g2(3), a(3), b(3), c(3), n0(3), n1(3), s0, s1, s2, r0, r1, r2
    e1 = p2 - p1
    e2 = p3 - p1
    d1 = q1 - p1
    g1 = (q2 - p2) - d1
    g2 = (q3 - p3) - d1
    ! a = e1 x e2, b = e1 x g2 + g1 x e2, c = g1 x g2, written out: this is
    ! the remap's innermost kernel (72 calls per remapped cell)
    a(1) = e1(2)*e2(3) - e1(3)*e2(2)
    a(2) = e1(3)*e2(1) - e1(1)*e2(3)
    a(3) = e1(1)*e2(2) - e1(2)*e2(1)
    b(1) = (e1(2)*g2(3) - e1(3)*g2(2)) + (g1(2)*e2(3) - g1(3)*e2(2))
    b(2) = (e1(3)*g2(1) - e1(1)*g2(3)) + (g1(3)*e2(1) - g1(1)*e2(3))
    b(3) = (e1(1)*g2(2) - e1(2)*g2(1)) + (g1(1)*e2(2) - g1(2)*e2(1))
    c(1) = g1(2)*g2(3) - g1(3)*g2(2)
    c(2) = g1(3)*g2(1) - g1(1)*g2(3)
    c(3) = g1(1)*g2(2) - g1(2)*g2(1)
    ! the normal's integrals over t: n0 = int N dt, n1 = int t N dt
    n0 = a + 0.5_wp*b + r3*c
    n1 = 0.5_wp*a + r3*b + 0.25_wp*c
    s0 = n0(1)*d1(1) + n0(2)*d1(2) + n0(3)*d1(3)
    s1 = n0(1)*g1(1) + n0(2)*g1(2) + n0(3)*g1(3)
    s2 = n0(1)*g2(1) + n0(2)*g2(2) + n0(3)*g2(3)
    r0 = n1(1)*d1(1) + n1(2)*d1(2) + n1(3)*d1(3)
    r1 = n1(1)*g1(1) + n1(2)*g1(2) + n1(3)*g1(3)
    r2 = n1(1)*g2(1) + n1(2)*g2(2) + n1(3)*g2(3)
    ! over the triangle: int 1 = 1/2, int xi_i = 1/6, int xi_i^2 = 1/12,
    ! int xi_1 xi_2 = 1/24
    v = 0.5_wp*s0 + r6*(s1 + s2)
    m = v*p1 + (r6*s0 + r12*s1 + r24*s2)*e1 + (r6*s0 + r24*s1 + r12*s2)*e2 + &
        (0.5_wp*r0 + r6*(r1 + r2))*d1 + (r6*r0 + r12*r1 + r24*r2)*g1 + &
        (r6*r0 + r24*r1 + r12*r2)*g2
  end subroutine swept_triangle
end module remap_swept
