!> Checks Sod runs (gamma 1.4, (1,0,1) | (0.125,0,0.1) at x0 = 0.5 of [0,1]).
!>
!>   check_sod l1 FRAME AXIS BOUND
!>       L1 density error sum_i |rho_i - <rho>_i| dx_i against the cell-averaged
!>       exact solution must be below BOUND.
!>   check_sod converge FRAME_N FRAME_2N AXIS
!>       the error must decrease from N to 2N; prints the observed order.
!>   check_sod same FRAME_A AXIS_A FRAME_B AXIS_B TOL
!>       the density profiles along the two axes agree within TOL (max norm).
program check_sod
  use base_kinds, only: wp
  use exact_riemann, only: riemann_t, riemann_solve, riemann_cell_average
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
    la = l1_error(a, arg_int(3))
    write(*, '(a,i0,a,es12.5,a,es10.3)') 'Sod N = ', size(a%density), ': L1 density error ', la, &
      ', bound ', arg_real(4)
    if (.not. (la < arg_real(4))) call check_fail('L1 error above the bound')
  case ('converge')
    call frame_read(arg_str(2), a)
    call frame_read(arg_str(3), b)
    la = l1_error(a, arg_int(4))
    lb = l1_error(b, arg_int(4))
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

  real(wp) function l1_error(fr, axis)
    type(frame_t), intent(in) :: fr
    integer, intent(in) :: axis
    type(riemann_t) :: rs
    logical :: ok
    integer :: i, n
    real(wp) :: xa, xb, rho, u, p, e

    call riemann_solve(rs, 1.0_wp, 0.0_wp, 1.0_wp, 1.4_wp, 0.125_wp, 0.0_wp, 0.1_wp, 1.4_wp, ok)
    if (.not. ok) call check_fail('exact Riemann solver failed')
    n = size(fr%density)
    l1_error = 0.0_wp
    do i = 1, n
      xa = xnode(fr, axis, i - 1)
      xb = xnode(fr, axis, i)
      call riemann_cell_average(rs, 0.5_wp, fr%time, xa, xb, 200, rho, u, p, e)
      l1_error = l1_error + abs(fr%density(i) - rho)*(xb - xa)
    end do
  end function l1_error
end program check_sod
