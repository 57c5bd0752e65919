!> Checks a frame against conservation laws and the Sedov-Taylor solution.
!>
!>   check_scene energy FRAME TOL
!>       |E - E0 - W| / |E0| <= TOL, E total energy, W boundary work.
!>   check_scene sedov FRAME E_TOTAL RHO0 GAMMA ALPHA TOL
!>       shock radius within the relative tolerance TOL of the exact
!>       R = (E/(alpha rho0))^(1/5) t^(2/5) (spherical; the frame holds one
!>       octant, so E_TOTAL is eight times the energy deposited in it, and
!>       alpha is the Sedov energy integral for GAMMA: 0.851072 for 1.4,
!>       Kamm and Timmes 2007).
!>
!>   check_scene piston FRAME UP RHO0 P0 GAMMA TOL
!>       a piston (the xlo face) moving at UP into gas at rest along x: the
!>       mean density between the piston and the shock equals the exact
!>       ideal-gas shock value rho2 = rho0 D/(D - UP), D = a + sqrt(a^2 + c0^2),
!>       a = (gamma+1) UP/4, within the relative tolerance TOL. Cells within a
!>       quarter of the shocked layer of the piston (wall heating) and the
!>       last tenth before the shock (its smeared front) are left out.
!>   check_scene still FRAME TOL
!>       every node speed is at most TOL (an equilibrium must stay at rest).
!>   check_scene uniform FRAME RHO TOL
!>       every cell density is within TOL of RHO (a uniform state must stay so).
!>   check_scene uniform_pressure FRAME P TOL
!>       every cell pressure p has |p - P| <= TOL P.
!>
!>   check_scene radial FRAME CX CY CZ SPEED TOL
!>       every node velocity is SPEED (x - c)/|x - c| (0 at c itself) within
!>       TOL in each component (&region velocity_field = 'radial').
!>   check_scene rotation FRAME CX CY CZ AXIS OMEGA TOL
!>       every node velocity is OMEGA a x (x - c), a the unit vector of AXIS
!>       (x, y or z), within TOL in each component, and the kinetic energy of
!>       the frame is 1/2 I OMEGA^2 within the relative tolerance TOL, I the
!>       moment of inertia sum_n m_n |a x (x_n - c)|^2 of the nodal masses
!>       (each cell's density times its subcell volumes, Eq. 16), summed here
!>       independently of the code (&region velocity_field = 'rotation').
!>
!>   check_scene positive FRAME
!>       every cell pressure is positive.
!>   check_scene converged COARSE FINE TOL
!>       a quasi-1D run along x against a finer run of the same problem (the
!>       fine cell count a multiple r of the coarse one): the coarse densities
!>       against the fine ones averaged over the same mass (r cells) differ by
!>       at most TOL in the relative L1 norm sum |d| dx / sum rho dx.
!>
!>   check_scene volume FRAME FIELD EXACT TOL
!>       the volume sum_c FIELD_c V_c (FIELD a volume fraction) is within the
!>       relative tolerance TOL of EXACT.
!>
!> The numerical shock radius comes from the shocked mass. Behind the shock
!> the entropy p/rho^gamma is far above ambient and grows inward, so a cell
!> counts as shocked when its entropy exceeds half the exact post-shock
!> entropy s2 = p2/rho2^gamma (p2 = 2 rho0 D^2/(gamma+1), rho2 = rho0
!> (gamma+1)/(gamma-1), D = 2R/(5t)). The shocked mass m is then the ambient
!> mass of an octant of radius R_num: R_num = (6 m/(pi rho0))^(1/3). Half the
!> jump marks the middle of the smeared shock, as a half-maximum would.
program check_scene
  use base_kinds, only: wp, pi
  use check_support, only: frame_t, frame_read, check_fail, arg_real, arg_str
  implicit none
  character(len=:), allocatable :: mode
  type(frame_t) :: fr, fine
  real(wp) :: drift, tol, e_total, rho0, gamma, alpha, r_exact, d, p2, rho2, s2, m, r_num
  real(wp) :: up, p0, xa, xb, xc
  integer :: c, n

  mode = arg_str(1)
  call frame_read(arg_str(2), fr)
  select case (mode)
  case ('energy')
    tol = arg_real(3)
    drift = abs(fr%internal + fr%kinetic - fr%initial - fr%work)/abs(fr%initial)
    write(*, '(a,es10.3,a,es10.3,a,es10.3)') 'relative energy drift ', drift, ' (boundary work ', &
      fr%work, '), tolerance ', tol
    if (.not. (drift <= tol)) call check_fail('total energy not conserved')
  case ('sedov')
    e_total = arg_real(3); rho0 = arg_real(4); gamma = arg_real(5); alpha = arg_real(6)
    tol = arg_real(7)
    r_exact = (e_total/(alpha*rho0))**0.2_wp*fr%time**0.4_wp
    d = 0.4_wp*r_exact/fr%time
    p2 = 2.0_wp*rho0*d*d/(gamma + 1.0_wp)
    rho2 = rho0*(gamma + 1.0_wp)/(gamma - 1.0_wp)
    s2 = p2/rho2**gamma
    m = 0.0_wp
    do c = 1, size(fr%density)
      if (fr%pressure(c)/fr%density(c)**gamma > 0.5_wp*s2) m = m + fr%density(c)*fr%volume(c)
    end do
    r_num = (6.0_wp*m/(pi*rho0))**(1.0_wp/3.0_wp)
    write(*, '(a,f8.5,a,f8.5,a,f7.4,a,f8.4,a,f8.4)') 'Sedov t = ', fr%time, ': shock radius ', r_num, &
      ' exact ', r_exact, ' relative error ', (r_num - r_exact)/r_exact, '; peak density ', &
      maxval(fr%density)
    if (.not. (abs(r_num - r_exact) <= tol*r_exact)) call check_fail('shock radius outside tolerance')
  case ('piston')
    up = arg_real(3); rho0 = arg_real(4); p0 = arg_real(5); gamma = arg_real(6); tol = arg_real(7)
    d = 0.25_wp*(gamma + 1.0_wp)*up
    d = d + sqrt(d*d + gamma*p0/rho0)
    rho2 = rho0*d/(d - up)
    xa = up*fr%time + 0.25_wp*(d - up)*fr%time
    xb = d*fr%time - 0.1_wp*(d - up)*fr%time
    m = 0.0_wp
    n = 0
    do c = 1, size(fr%density)
      xc = 0.5_wp*(fr%x(3*(c - 1) + 1) + fr%x(3*c + 1))
      if (xc < xa .or. xc > xb) cycle
      m = m + fr%density(c)
      n = n + 1
    end do
    if (n == 0) call check_fail('no cells in the shocked layer')
    m = m/n
    write(*, '(a,f9.5,a,f9.5,a,i0,a,es10.3)') 'piston: mean shocked density ', m, ' exact ', rho2, &
      ' over ', n, ' cells; relative error ', (m - rho2)/rho2
    if (.not. (abs(m - rho2) <= tol*rho2)) call check_fail('shocked density outside tolerance')
  case ('still')
    tol = arg_real(3)
    d = maxval(abs(fr%velocity))
    write(*, '(a,es10.3,a,es10.3)') 'largest velocity component ', d, ', tolerance ', tol
    if (.not. (d <= tol)) call check_fail('the equilibrium moved')
  case ('uniform')
    tol = arg_real(4)
    d = maxval(abs(fr%density - arg_real(3)))
    write(*, '(a,es10.3,a,es10.3)') 'largest density deviation ', d, ', tolerance ', tol
    if (.not. (d <= tol)) call check_fail('the uniform state changed')
  case ('uniform_pressure')
    tol = arg_real(4)
    d = maxval(abs(fr%pressure - arg_real(3)))/arg_real(3)
    write(*, '(a,es10.3,a,es10.3)') 'largest relative pressure deviation ', d, ', tolerance ', tol
    if (.not. (d <= tol)) call check_fail('the uniform pressure changed')
  case ('radial')
    block
      real(wp) :: centre(3), dx(3), speed, u(3), r, worst
      centre = [arg_real(3), arg_real(4), arg_real(5)]
      speed = arg_real(6)
      tol = arg_real(7)
      worst = 0.0_wp
      do n = 1, size(fr%x)/3
        dx = fr%x(3*n - 2:3*n) - centre
        r = sqrt(dot_product(dx, dx))
        u = 0.0_wp
        if (r > 0.0_wp) u = speed*dx/r
        worst = max(worst, maxval(abs(fr%velocity(3*n - 2:3*n) - u)))
      end do
      write(*, '(a,i0,a,es10.3,a,es10.3)') 'radial field: ', size(fr%x)/3, ' nodes, largest difference ', &
        worst, ', tolerance ', tol
      if (.not. (worst <= tol)) call check_fail('node velocities are not speed (x - c)/|x - c|')
    end block
  case ('rotation')
    block
      use mesh_grid, only: grid_index_t, grid_index
      use mesh_geometry, only: hex_subcell_volumes, cross
      type(grid_index_t) :: ix
      real(wp) :: centre(3), axis(3), omega, worst, xn(3, 8), vsub(8), inertia, ke
      real(wp), allocatable :: xs(:, :), mnode(:)
      character(len=:), allocatable :: ax
      integer :: a
      centre = [arg_real(3), arg_real(4), arg_real(5)]
      ax = arg_str(6)
      axis = 0.0_wp
      if (index('xyz', ax) < 1 .or. len(ax) /= 1) call check_fail('AXIS must be x, y or z')
      axis(index('xyz', ax)) = 1.0_wp
      omega = arg_real(7)
      tol = arg_real(8)
      ix = grid_index(fr%ni, fr%nj, fr%nk)
      xs = reshape(fr%x, [3, ix%nnode])
      allocate(mnode(ix%nnode), stat=n)
      if (n /= 0) call check_fail('cannot allocate the nodal masses')
      mnode = 0.0_wp
      do c = 1, ix%ncell
        call ix%gather(c, xs, xn)
        call hex_subcell_volumes(xn, vsub)
        do a = 1, 8
          n = ix%node0(c) + ix%corner_offset(a)
          mnode(n) = mnode(n) + fr%density(c)*vsub(a)
        end do
      end do
      worst = 0.0_wp
      inertia = 0.0_wp
      do n = 1, ix%nnode
        xn(:, 1) = cross(axis, xs(:, n) - centre)
        worst = max(worst, maxval(abs(fr%velocity(3*n - 2:3*n) - omega*xn(:, 1))))
        inertia = inertia + mnode(n)*dot_product(xn(:, 1), xn(:, 1))
      end do
      ke = 0.5_wp*inertia*omega**2
      write(*, '(a,i0,a,es10.3,a,es10.3)') 'rotation about '//ax//': ', ix%nnode, &
        ' nodes, largest velocity difference ', worst, ', tolerance ', tol
      write(*, '(a,es22.15,a,es22.15,a,es10.3)') 'kinetic energy ', fr%kinetic, ', 1/2 I omega^2 ', ke, &
        ', relative difference ', abs(fr%kinetic - ke)/ke
      if (.not. (worst <= tol)) call check_fail('node velocities are not omega a x (x - c)')
      if (.not. (abs(fr%kinetic - ke) <= tol*ke)) call check_fail('kinetic energy is not 1/2 I omega^2')
    end block
  case ('volume')
    block
      use check_support, only: frame_field
      real(wp), allocatable :: vf(:)
      real(wp) :: exact, v
      call frame_field(arg_str(2), arg_str(3), vf)
      exact = arg_real(4)
      tol = arg_real(5)
      v = sum(vf*fr%volume)
      write(*, '(a,es16.8,a,es16.8,a,es10.3,a,es10.3)') 'volume of '//arg_str(3)//' ', v, ', exact ', exact, &
        ', relative error ', (v - exact)/exact, ', tolerance ', tol
      if (.not. (abs(v - exact) <= tol*exact)) call check_fail('volume outside tolerance')
    end block
  case ('positive')
    write(*, '(a,es12.4)') 'smallest pressure ', minval(fr%pressure)
    if (.not. (minval(fr%pressure) > 0.0_wp)) call check_fail('a pressure is not positive')
  case ('converged')
    call frame_read(arg_str(3), fine)
    tol = arg_real(4)
    drift = converged_difference(fr, fine)
    write(*, '(a,i0,a,i0,a,es10.3,a,es10.3)') 'density, ', size(fr%density), ' cells against ', &
      size(fine%density), ': relative L1 difference ', drift, ', tolerance ', tol
    if (.not. (drift <= tol)) call check_fail('the coarse run is not close to the fine one')
  case default
    call check_fail('unknown mode '//mode)
  end select
  write(*, '(a)') 'PASS check_scene '//mode

contains

  !> Relative L1 difference of the densities of a coarse quasi-1D frame and
  !> a fine one averaged over the same Lagrangian mass (groups of r cells).
  real(wp) function converged_difference(coarse, fine) result(diff)
    type(frame_t), intent(in) :: coarse, fine
    integer :: nc, nf, r, i, j
    real(wp) :: dxc, mass, dxf, num, den
    nc = size(coarse%density)
    nf = size(fine%density)
    r = nf/nc
    if (r*nc /= nf) call check_fail('the fine cell count is not a multiple of the coarse one')
    num = 0.0_wp
    den = 0.0_wp
    do i = 1, nc
      dxc = coarse%x(3*i + 1) - coarse%x(3*(i - 1) + 1)
      mass = 0.0_wp
      dxf = 0.0_wp
      do j = r*(i - 1) + 1, r*i
        mass = mass + fine%density(j)*(fine%x(3*j + 1) - fine%x(3*(j - 1) + 1))
        dxf = dxf + fine%x(3*j + 1) - fine%x(3*(j - 1) + 1)
      end do
      num = num + abs(coarse%density(i) - mass/dxf)*dxc
      den = den + coarse%density(i)*dxc
    end do
    diff = num/den
  end function converged_difference
end program check_scene
