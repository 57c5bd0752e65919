!> A one-dimensional spherical Lagrangian hydrocode: the pre-run of a
!> charge's free expansion (in air or water) before it is mapped into the 3D
!> grid (`spherical_map`, `driver_prerun`), on the same materials, EOS, cut-offs
!> and programmed burn as the 3D solver (`material_table`).
!>
!> Zones z = 1..nz between nodes z-1 and z at radii r(0) = 0 < r(1) < ...
!> < r(nz); quantities per steradian (a zone's mass m = rho (r_z^3 -
!> r_{z-1}^3)/3, its volume rate r^2 u at each node). A staggered grid as in
!> the 3D solver (Eq. 5-7 of the paper in one dimension): velocities at the
!> nodes, density, energy and pressure in the zones, node masses half each
!> neighbouring zone's. The node at the centre stays at rest, the outer node
!> is a wall (the domain is sized so that nothing reaches it: the driver
!> checks). Artificial viscosity in compression only,
!>   q = rho (c_quad du^2 + c_lin cs |du|),  du = u_z - u_{z-1} < 0,
!> the coefficients of the deck's &hydro.
!>
!> A step is a predictor to the half step (positions, densities, energies
!> and the EOS there) and a corrector with the half-step forces
!>   m_i (u_i^{n+1} - u_i^n) = dt r_i^2 (P_{z=i} - P_{z=i+1}),  P = p + q,
!> moving nodes with the mean velocity ub = (u^n + u^{n+1})/2 and changing
!> each zone's energy by the work of the same forces,
!>   m_z (e^{n+1} - e^n) = -dt P_z (r_z^2 ub_z - r_{z-1}^2 ub_{z-1}),
!> so that the total energy (internal plus nodal kinetic) is conserved to
!> round-off (the compatible discretisation of the 3D solver).
module spherical_lagrange
  use base_kinds, only: wp
  use material_table, only: material_t, material_eval_eos, material_burn_start, material_burn_at
  use material_mixed, only: mixed_t
  implicit none
  private
  public :: sphere_t, sphere_setup, sphere_dt, sphere_step, sphere_energy

  !> The 1D state (per steradian) and its materials (a copy of the 3D run's,
  !> whose burn arrays are per zone).
  type :: sphere_t
    integer :: nz = 0
    real(wp), allocatable :: r(:), u(:), mn(:)    !< (0:nz) node radius, velocity, mass
    real(wp), allocatable :: m(:), rho(:), e(:), p(:), cs(:), q(:)   !< (nz) zone state
    integer, allocatable :: mat(:)                !< (nz) zone material
    type(material_t), allocatable :: mats(:)
    type(mixed_t) :: mx                           !< (no mixed zones: empty)
    real(wp) :: t = 0.0_wp, dt = 0.0_wp
    integer :: steps = 0
    real(wp) :: q_lin = 0.0_wp, q_quad = 0.0_wp, cfl = 0.5_wp
  end type sphere_t

contains

  !> Masses, node masses, viscosity and EOS of a 1D state whose r, u, rho,
  !> e, mat and mats are set (mats indexed over the zones, burn arrays too).
  subroutine sphere_setup(s)
    type(sphere_t), intent(inout) :: s
    integer :: z
    do z = 1, s%nz
      s%m(z) = s%rho(z)*(s%r(z)**3 - s%r(z - 1)**3)/3.0_wp
    end do
    s%mn(0) = 0.5_wp*s%m(1)
    s%mn(1:s%nz - 1) = 0.5_wp*(s%m(1:s%nz - 1) + s%m(2:s%nz))
    s%mn(s%nz) = 0.5_wp*s%m(s%nz)
    call eos_at(s, s%rho, s%e, s%p, s%cs, s%t, 0.0_wp)
    call viscosity(s, s%rho, s%cs, s%u, s%q)
  end subroutine sphere_setup

  !> The stable step: cfl times the least zone width over its signal speed
  !> (sound plus twice the quadratic viscosity's compression rate).
  pure real(wp) function sphere_dt(s) result(dt)
    type(sphere_t), intent(in) :: s
    integer :: z
    real(wp) :: du, c
    dt = huge(1.0_wp)
    do z = 1, s%nz
      du = min(0.0_wp, s%u(z) - s%u(z - 1))
      c = s%cs(z) + s%q_lin*s%cs(z) + 2.0_wp*s%q_quad*abs(du)
      dt = min(dt, (s%r(z) - s%r(z - 1))/max(c, tiny(1.0_wp)))
    end do
    dt = s%cfl*dt
  end function sphere_dt

  !> One step of length dt; ok is false (and nothing changed) if a zone
  !> would turn inside out.
  subroutine sphere_step(s, dt, ok)
    type(sphere_t), intent(inout) :: s
    real(wp), intent(in) :: dt
    logical, intent(out) :: ok
    real(wp) :: rh(0:s%nz), un(0:s%nz), ub(0:s%nz), rn(0:s%nz)
    real(wp) :: rhoh(s%nz), eh(s%nz), ph(s%nz), csh(s%nz), qh(s%nz), big(s%nz), en(s%nz), rhon(s%nz)
    integer :: i, z
    ! predictor: the half step
    rh = s%r + 0.5_wp*dt*s%u
    ok = all(rh(1:s%nz) > rh(0:s%nz - 1))
    if (.not. ok) return
    do z = 1, s%nz
      rhoh(z) = 3.0_wp*s%m(z)/(rh(z)**3 - rh(z - 1)**3)
      eh(z) = s%e(z) - 0.5_wp*dt*(s%p(z) + s%q(z))*(s%r(z)**2*s%u(z) - s%r(z - 1)**2*s%u(z - 1))/s%m(z)
    end do
    call eos_at(s, rhoh, eh, ph, csh, s%t, 0.5_wp*dt)
    call viscosity(s, rhoh, csh, s%u, qh)
    big = ph + qh
    ! corrector: half-step forces, the mean velocity moves the nodes
    un(0) = 0.0_wp
    do i = 1, s%nz - 1
      un(i) = s%u(i) + dt*rh(i)**2*(big(i) - big(i + 1))/s%mn(i)
    end do
    un(s%nz) = 0.0_wp
    ub = 0.5_wp*(s%u + un)
    rn = s%r + dt*ub
    ok = all(rn(1:s%nz) > rn(0:s%nz - 1))
    if (.not. ok) return
    do z = 1, s%nz
      en(z) = s%e(z) - dt*big(z)*(rh(z)**2*ub(z) - rh(z - 1)**2*ub(z - 1))/s%m(z)
      rhon(z) = 3.0_wp*s%m(z)/(rn(z)**3 - rn(z - 1)**3)
    end do
    s%r = rn
    s%u = un
    s%e = en
    s%rho = rhon
    call eos_at(s, s%rho, s%e, s%p, s%cs, s%t, dt)
    call viscosity(s, s%rho, s%cs, s%u, s%q)
    s%t = s%t + dt
    s%dt = dt
    s%steps = s%steps + 1
  end subroutine sphere_step

  !> Internal and kinetic energy per steradian.
  pure subroutine sphere_energy(s, internal, kinetic)
    type(sphere_t), intent(in) :: s
    real(wp), intent(out) :: internal, kinetic
    internal = sum(s%m*s%e)
    kinetic = 0.5_wp*sum(s%mn*s%u**2)
  end subroutine sphere_energy

  !> Pressures and sound speeds at time t0 + dt (the burn fractions then).
  subroutine eos_at(s, rho, e, p, cs, t0, dt)
    type(sphere_t), intent(inout) :: s
    real(wp), intent(in) :: rho(:), e(:), t0, dt
    real(wp), intent(out) :: p(:), cs(:)
    call material_burn_start(s%mats, t0)
    if (dt > 0.0_wp) call material_burn_at(s%mats, dt)
    call material_eval_eos(s%mats, rho, e, p, cs, s%mx)
  end subroutine eos_at

  !> The zones' artificial viscosity for node velocities u.
  pure subroutine viscosity(s, rho, cs, u, q)
    type(sphere_t), intent(in) :: s
    real(wp), intent(in) :: rho(:), cs(:), u(0:)
    real(wp), intent(out) :: q(:)
    integer :: z
    real(wp) :: du
    do z = 1, s%nz
      du = min(0.0_wp, u(z) - u(z - 1))
      q(z) = rho(z)*(s%q_quad*du**2 + s%q_lin*cs(z)*abs(du))
    end do
  end subroutine viscosity
end module spherical_lagrange
