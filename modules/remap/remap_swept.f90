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
  public :: swept_triangle, swept_triangles, swept_edges

contains

  !> Signed volume v and first moment m of the region swept by the triangle
  !> p1, p2, p3 moving to q1, q2, q3 (module header; positive along the
  !> normal (p2 - p1) x (p3 - p1)). Lengths in any unit; v in its cube, m
  !> in its fourth power, about the coordinates' origin. (`swept_triangles`
  !> on one triangle: the same numbers.)
  pure subroutine swept_triangle(p1, p2, p3, q1, q2, q3, v, m)
    real(wp), intent(in) :: p1(3), p2(3), p3(3), q1(3), q2(3), q3(3)
    real(wp), intent(out) :: v, m(3)
    real(wp) :: p(3, 3), q(3, 3), vs(1), ms(1, 3)
    p(:, 1) = p1
    p(:, 2) = p2
    p(:, 3) = p3
    q(:, 1) = q1
    q(:, 2) = q2
    q(:, 3) = q3
    call swept_triangles(p, q, reshape([1, 2, 3], [3, 1]), vs, ms)
    v = vs(1)
    m = ms(1, :)
  end subroutine swept_triangle

  !> `swept_triangle` for the triangles tri(:, k) (three columns of p each,
  !> moving to the same columns of q): v(k) and m(k, :). The triangles'
  !> edges are gathered first, so that the arithmetic runs over them in
  !> the vector unit's lanes (`swept_edges`). At most 72 triangles among
  !> 27 points.
  pure subroutine swept_triangles(p, q, tri, v, m)
    real(wp), intent(in), contiguous :: p(:, :), q(:, :)
    integer, intent(in), contiguous :: tri(:, :)
    real(wp), intent(out), contiguous :: v(:), m(:, :)
    ! (the points' moves and the triangles' edges, on the stack)
    integer, parameter :: max_tri = 72, max_pts = 27
    real(wp) :: dq(3, max_pts), x1(max_tri, 3), e1(max_tri, 3), e2(max_tri, 3), d1(max_tri, 3), g1(max_tri, 3), &
                g2(max_tri, 3), vk(max_tri), mk(max_tri, 3)
    integer :: k, j, i1, i2, i3, n
    do k = 1, size(p, 2)
      dq(:, k) = q(:, k) - p(:, k)
    end do
    ! (d1 = q1 - p1, g_i = (q_(i+1) - p_(i+1)) - d1)
    n = size(tri, 2)
    do k = 1, n
      i1 = tri(1, k)
      i2 = tri(2, k)
      i3 = tri(3, k)
      do j = 1, 3
        x1(k, j) = p(j, i1)
        e1(k, j) = p(j, i2) - x1(k, j)
        e2(k, j) = p(j, i3) - x1(k, j)
        d1(k, j) = dq(j, i1)
        g1(k, j) = dq(j, i2) - d1(k, j)
        g2(k, j) = dq(j, i3) - d1(k, j)
      end do
    end do
    call swept_edges(n, max_tri, x1, e1, e2, d1, g1, g2, vk, mk)
    v(1:n) = vk(1:n)
    m(1:n, :) = mk(1:n, :)
  end subroutine swept_triangles

  !> The arithmetic of `swept_triangles` on triangles given by their
  !> edges, rows 1..n of arrays with ld rows: the first vertex x1 and its
  !> move d1, the edges e_i = p_(i+1) - p_1 and their moves g_i =
  !> d_(i+1) - d_1 (a caller that knows how its triangles share vertices
  !> builds these itself, without `swept_triangles`' general gather). The
  !> triangles run over the vector unit's lanes.
  pure subroutine swept_edges(n, ld, x1, e1, e2, d1, g1, g2, v, m)
    integer, intent(in) :: n, ld
    real(wp), intent(in) :: x1(ld, 3), e1(ld, 3), e2(ld, 3), d1(ld, 3), g1(ld, 3), g2(ld, 3)
    real(wp), intent(out) :: v(ld), m(ld, 3)
    ! (the weights as products: a division is several times a product's cost)
    real(wp), parameter :: r3 = 1.0_wp/3.0_wp, r6 = 1.0_wp/6.0_wp, r12 = 1.0_wp/12.0_wp, r24 = 1.0_wp/24.0_wp
    real(wp) :: a1, a2, a3, b1, b2, b3, c1, c2, c3, n01, n02, n03, n11, n12, n13, s0, s1, s2, r0, r1, r2, &
                w0, w1, w2, u1, u2
    integer :: k, j
    do k = 1, n
      ! a = e1 x e2, b = e1 x g2 + g1 x e2, c = g1 x g2
      a1 = e1(k, 2)*e2(k, 3) - e1(k, 3)*e2(k, 2)
      a2 = e1(k, 3)*e2(k, 1) - e1(k, 1)*e2(k, 3)
      a3 = e1(k, 1)*e2(k, 2) - e1(k, 2)*e2(k, 1)
      b1 = (e1(k, 2)*g2(k, 3) - e1(k, 3)*g2(k, 2)) + (g1(k, 2)*e2(k, 3) - g1(k, 3)*e2(k, 2))
      b2 = (e1(k, 3)*g2(k, 1) - e1(k, 1)*g2(k, 3)) + (g1(k, 3)*e2(k, 1) - g1(k, 1)*e2(k, 3))
      b3 = (e1(k, 1)*g2(k, 2) - e1(k, 2)*g2(k, 1)) + (g1(k, 1)*e2(k, 2) - g1(k, 2)*e2(k, 1))
      c1 = g1(k, 2)*g2(k, 3) - g1(k, 3)*g2(k, 2)
      c2 = g1(k, 3)*g2(k, 1) - g1(k, 1)*g2(k, 3)
      c3 = g1(k, 1)*g2(k, 2) - g1(k, 2)*g2(k, 1)
      ! the normal's integrals over t: n0 = int N dt, n1 = int t N dt
      n01 = a1 + 0.5_wp*b1 + r3*c1
      n02 = a2 + 0.5_wp*b2 + r3*c2
      n03 = a3 + 0.5_wp*b3 + r3*c3
      n11 = 0.5_wp*a1 + r3*b1 + 0.25_wp*c1
      n12 = 0.5_wp*a2 + r3*b2 + 0.25_wp*c2
      n13 = 0.5_wp*a3 + r3*b3 + 0.25_wp*c3
      s0 = n01*d1(k, 1) + n02*d1(k, 2) + n03*d1(k, 3)
      s1 = n01*g1(k, 1) + n02*g1(k, 2) + n03*g1(k, 3)
      s2 = n01*g2(k, 1) + n02*g2(k, 2) + n03*g2(k, 3)
      r0 = n11*d1(k, 1) + n12*d1(k, 2) + n13*d1(k, 3)
      r1 = n11*g1(k, 1) + n12*g1(k, 2) + n13*g1(k, 3)
      r2 = n11*g2(k, 1) + n12*g2(k, 2) + n13*g2(k, 3)
      ! over the triangle: int 1 = 1/2, int xi_i = 1/6, int xi_i^2 = 1/12,
      ! int xi_1 xi_2 = 1/24
      v(k) = 0.5_wp*s0 + r6*(s1 + s2)
      w1 = r6*s0 + r12*s1 + r24*s2
      w2 = r6*s0 + r24*s1 + r12*s2
      w0 = 0.5_wp*r0 + r6*(r1 + r2)
      u1 = r6*r0 + r12*r1 + r24*r2
      u2 = r6*r0 + r24*r1 + r12*r2
      do j = 1, 3
        m(k, j) = v(k)*x1(k, j) + w1*e1(k, j) + w2*e2(k, j) + w0*d1(k, j) + u1*g1(k, j) + u2*g2(k, j)
      end do
    end do
  end subroutine swept_edges
end module remap_swept
