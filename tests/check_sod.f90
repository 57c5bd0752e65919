!> Checks shock-tube runs on [0,1] against the exact Riemann solution:
!> Sod (gamma 1.4, (1,0,1) | (0.125,0,0.1) at x0 = 0.5) and, in the modes
!> that say so, the two-material Sod (gamma 2 (1,0,2) | gamma 1.4
!> (0.125,0,0.1)) with its interface at X0.
!>
!>   check_sod l1 FRAME AXIS BOUND
!>       L1 density error sum_i |rho_i - <rho>_i| dx_i against the cell-averaged
!>       exact solution must be below BOUND.
!>   check_sod l1_two FRAME X0 BOUND
!>       the same for the two-material Sod along x.
!>   check_sod ratio_two FRAME_A X0_A FRAME_B X0_B MAX
!>       L1(B) / L1(A) <= MAX (two-material Sod; B with a mixed cell, A without).
!>   check_sod contact_two FRAME X0 TOL
!>       no ringing at the material interface: in the 5 cells each side of
!>       the contact the pressure stays within TOL (relative) of the exact p*.
!>   check_sod converge FRAME_N FRAME_2N AXIS
!>       the error must decrease from N to 2N; prints the observed order.
!>   check_sod same FRAME_A AXIS_A FRAME_B AXIS_B TOL
!>       the density profiles along the two axes agree within TOL (max norm).
program check_sod
  use base_kinds, only: wp
  use exact_riemann, only: riemann_t, riemann_solve, riemann_cell_average, riemann_sample
  use check_support, only: frame_t, frame_read, check_fail, arg_real, arg_int, arg_str
  implicit none
  character(len=:), allocatable :: mode
  type(frame_t) :: a, b
  real(wp) :: la, lb, tol, dmax
  real(wp), allocatable :: ra(:), rb(:)

  mode = arg_str(1)
  select case (mode)
  case ('l1')
    call frame_read(arg_str(2), a)
    la = l1_error(a, arg_int(3), sod(), 0.5_wp)
    write(*, '(a,i0,a,es12.5,a,es10.3)') 'Sod N = ', size(a%density), ': L1 density error ', la, &
      ', bound ', arg_real(4)
    if (.not. (la < arg_real(4))) call check_fail('L1 error above the bound')
  case ('converge')
    call frame_read(arg_str(2), a)
    call frame_read(arg_str(3), b)
    la = l1_error(a, arg_int(4), sod(), 0.5_wp)
    lb = l1_error(b, arg_int(4), sod(), 0.5_wp)
    write(*, '(a,i0,a,es12.5,a,i0,a,es12.5,a,f6.3)') 'Sod L1: N = ', size(a%density), ' ', la, &
      '  N = ', size(b%density), ' ', lb, '  order ', log(la/lb)/log(real(size(b%density), wp)/size(a%density))
    if (.not. (lb < la)) call check_fail('error does not decrease with resolution')
  case ('same')
    call frame_read(arg_str(2), a)
    call frame_read(arg_str(4), b)
    ra = profile(a, arg_int(3))
    rb = profile(b, arg_int(5))
    tol = arg_real(6)
    if (size(ra) /= size(rb)) call check_fail('profiles have different lengths')
    dmax = maxval(abs(ra - rb))
    write(*, '(a,es10.3,a,es10.3)') 'max density difference between axes ', dmax, ', tolerance ', tol
    if (.not. (dmax <= tol)) call check_fail('profiles differ between axes')
  case ('l1_two')
    call frame_read(arg_str(2), a)
    la = l1_error(a, 1, two_gamma(), arg_real(3))
    write(*, '(a,i0,a,es12.5,a,es10.3)') 'two-material Sod N = ', size(a%density), &
      ': L1 density error ', la, ', bound ', arg_real(4)
    if (.not. (la < arg_real(4))) call check_fail('L1 error above the bound')
  case ('ratio_two')
    call frame_read(arg_str(2), a)
    call frame_read(arg_str(4), b)
    la = l1_error(a, 1, two_gamma(), arg_real(3))
    lb = l1_error(b, 1, two_gamma(), arg_real(5))
    write(*, '(a,es12.5,a,es12.5,a,f6.3,a,f6.3)') 'two-material Sod L1: without mixed cell ', la, &
      ', with ', lb, ', ratio ', lb/la, ', allowed ', arg_real(6)
    if (.not. (lb <= arg_real(6)*la)) call check_fail('the mixed cell costs too much accuracy')
  case ('contact_two')
    call frame_read(arg_str(2), a)
    call contact_pressure(a, arg_real(3), arg_real(4))
  case default
    call check_fail('unknown mode '//mode)
  end select
  write(*, '(a)') 'PASS check_sod '//mode

contains

  !> Density along the axis (the frame is one cell thick in the other two).
  function profile(fr, axis) result(r)
    type(frame_t), intent(in) :: fr
    integer, intent(in) :: axis
    real(wp), allocatable :: r(:)
    r = fr%density
    if (axis < 1 .or. axis > 3) call check_fail('axis must be 1, 2 or 3')
  end function profile

  !> Node coordinate along `axis` of the i-th node line.
  real(wp) function xnode(fr, axis, i)
    type(frame_t), intent(in) :: fr
    integer, intent(in) :: axis, i
    integer :: stride
    select case (axis)
    case (1); stride = 1
    case (2); stride = fr%ni + 1
    case default; stride = (fr%ni + 1)*(fr%nj + 1)
    end select
    xnode = fr%x(3*(i*stride) + axis)
  end function xnode

  type(riemann_t) function sod()
    logical :: ok
    call riemann_solve(sod, 1.0_wp, 0.0_wp, 1.0_wp, 1.4_wp, 0.125_wp, 0.0_wp, 0.1_wp, 1.4_wp, ok)
    if (.not. ok) call check_fail('exact Riemann solver failed')
  end function sod

  type(riemann_t) function two_gamma()
    logical :: ok
    call riemann_solve(two_gamma, 1.0_wp, 0.0_wp, 2.0_wp, 2.0_wp, 0.125_wp, 0.0_wp, 0.1_wp, 1.4_wp, ok)
    if (.not. ok) call check_fail('exact Riemann solver failed')
  end function two_gamma

  !> Pressure within tol of p* in the 10 cells each side of the contact.
  subroutine contact_pressure(fr, x0, tol)
    type(frame_t), intent(in) :: fr
    real(wp), intent(in) :: x0, tol
    type(riemann_t) :: rs
    integer :: i, n, ic
    real(wp) :: xc, dmax
    rs = two_gamma()
    n = size(fr%density)
    ic = 1
    do i = 1, n
      xc = 0.5_wp*(xnode(fr, 1, i - 1) + xnode(fr, 1, i))
      if (xc < x0 + rs%u_star*fr%time) ic = i
    end do
    dmax = 0.0_wp
    do i = max(3, ic - 5), min(n - 2, ic + 5)
      ! only cells well inside the star region (two cells from the
      ! rarefaction tail and the shock, whose smearing is not ringing)
      if (.not. (in_star(rs, x0, fr%time, xnode(fr, 1, i - 3)) .and. &
                 in_star(rs, x0, fr%time, xnode(fr, 1, i + 2)))) cycle
      dmax = max(dmax, abs(fr%pressure(i) - rs%p_star)/rs%p_star)
    end do
    write(*, '(a,i0,a,es10.3,a,es10.3)') 'contact in cell ', ic, ': largest relative pressure deviation ', &
      dmax, ', tolerance ', tol
    if (.not. (dmax <= tol)) call check_fail('pressure rings at the contact')
  end subroutine contact_pressure

  !> True if point x at time t is in the star region of rs (pressure p*).
  logical function in_star(rs, x0, t, x)
    type(riemann_t), intent(in) :: rs
    real(wp), intent(in) :: x0, t, x
    real(wp) :: r, u, p
    call riemann_sample(rs, (x - x0)/t, r, u, p)
    in_star = abs(p - rs%p_star) <= 1.0e-12_wp*rs%p_star
  end function in_star

  real(wp) function l1_error(fr, axis, rs, x0)
    type(frame_t), intent(in) :: fr
    integer, intent(in) :: axis
    type(riemann_t), intent(in) :: rs
    real(wp), intent(in) :: x0
    integer :: i, n
    real(wp) :: xa, xb, rho, u, p, e

    n = size(fr%density)
    l1_error = 0.0_wp
    do i = 1, n
      xa = xnode(fr, axis, i - 1)
      xb = xnode(fr, axis, i)
      call riemann_cell_average(rs, x0, fr%time, xa, xb, 200, rho, u, p, e)
      l1_error = l1_error + abs(fr%density(i) - rho)*(xb - xa)
    end do
  end function l1_error
end program check_sod
