!> Interfaces of the LAPACK routines the project calls (the library is
!> Fortran 77: explicit interfaces let the compiler check the calls).
module base_lapack
  use base_kinds, only: wp
  implicit none
  private
  public :: dgelss

  interface
    !> Minimum-norm least-squares solution of a(m, n) x = b(m, nrhs) by SVD;
    !> singular values below rcond times the largest are taken as zero.
    subroutine dgelss(m, n, nrhs, a, lda, b, ldb, s, rcond, rank, work, lwork, info)
      import :: wp
      integer, intent(in) :: m, n, nrhs, lda, ldb, lwork
      real(wp), intent(inout) :: a(lda, *), b(ldb, *)
      real(wp), intent(out) :: s(*)
      real(wp), intent(in) :: rcond
      integer, intent(out) :: rank, info
      real(wp), intent(inout) :: work(*)
    end subroutine dgelss
  end interface
end module base_lapack
