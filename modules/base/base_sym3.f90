!> The eigen-decomposition of a symmetric 3x3 matrix (`sym3_eigen`), for
!> the tensor viscosity's principal strain rates (lagrange_forces) and the
!> principal stresses of the strength models (strength_models).
module base_sym3
  use base_kinds, only: wp
  implicit none
  private
  public :: sym3_eigen

contains

  !> Eigenvalues lam and orthonormal eigenvectors ev(:,k) of a symmetric 3x3
  !> matrix by cyclic Jacobi rotations (converges in a few sweeps; exact
  !> orthonormality, no special cases for repeated eigenvalues).
  pure subroutine sym3_eigen(a_in, lam, ev)
    real(wp), intent(in) :: a_in(3, 3)
    real(wp), intent(out) :: lam(3), ev(3, 3)
    real(wp) :: a(3, 3), theta, t, cth, sth, tau, off, scale, apq, app, aqq, g1, g2
    integer :: sweep, p, q, r, i

    a = a_in
    ev = 0.0_wp
    do i = 1, 3
      ev(i, i) = 1.0_wp
    end do
    scale = abs(a(1, 1)) + abs(a(2, 2)) + abs(a(3, 3)) + abs(a(1, 2)) + abs(a(1, 3)) + abs(a(2, 3))
    do sweep = 1, 12
      off = abs(a(1, 2)) + abs(a(1, 3)) + abs(a(2, 3))
      if (off <= 1.0e-12_wp*scale) exit
      do p = 1, 2
        do q = p + 1, 3
          apq = a(p, q)
          if (abs(apq) <= tiny(1.0_wp)) cycle
          app = a(p, p)
          aqq = a(q, q)
          theta = 0.5_wp*(aqq - app)/apq
          ! (a huge theta would overflow theta**2: then t = 1/(2 theta))
          if (abs(theta) > 1.0e150_wp) then
            t = 0.5_wp/theta
          else
            t = sign(1.0_wp, theta)/(abs(theta) + sqrt(theta*theta + 1.0_wp))
          end if
          cth = 1.0_wp/sqrt(t*t + 1.0_wp)
          sth = t*cth
          tau = sth/(1.0_wp + cth)
          a(p, p) = app - t*apq
          a(q, q) = aqq + t*apq
          a(p, q) = 0.0_wp
          a(q, p) = 0.0_wp
          do r = 1, 3
            if (r == p .or. r == q) cycle
            g1 = a(r, p)
            g2 = a(r, q)
            a(r, p) = g1 - sth*(g2 + tau*g1)
            a(p, r) = a(r, p)
            a(r, q) = g2 + sth*(g1 - tau*g2)
            a(q, r) = a(r, q)
          end do
          do r = 1, 3
            g1 = ev(r, p)
            g2 = ev(r, q)
            ev(r, p) = g1 - sth*(g2 + tau*g1)
            ev(r, q) = g2 + sth*(g1 - tau*g2)
          end do
        end do
      end do
    end do
    do i = 1, 3
      lam(i) = a(i, i)
    end do
  end subroutine sym3_eigen
end module base_sym3
