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
!>
!> Thin zones merge (`sphere_merge`): the air next to a charge's products,
!> shocked hard in the first microseconds, stays hot and thins out as the
!> fireball grows (its zones' width over radius 200 times below the initial
!> zoning's by 6 ms for 1 kg TNT), and as a Lagrangian shell it sets a step
!> a hundred times below that of every other zone. Two neighbouring zones of
!> one material, neither an explosive, become one where the first is
!> thinner (width over radius) than its initial zoning by more than a given
!> ratio and expanding: the zones' masses and internal energies add, the
!> node between them gives its mass and momentum to the merged zone's nodes
!> (each the half of the other zone's mass it now carries) and the kinetic
!> energy that this loses to the merged zone's internal energy, so that
!> mass, momentum and total energy are conserved to round-off.
module spherical_lagrange
  use base_kinds, only: wp
  use material_table, only: material_t, material_eval_eos, material_burn_start, material_burn_at
  use material_mixed, only: mixed_t
  implicit none
  private
  public :: sphere_t, sphere_setup, sphere_dt, sphere_step, sphere_energy, sphere_merge, sphere_refresh

  !> The 1D state (per steradian) and its materials (a copy of the 3D run's,
  !> whose burn arrays are per zone).
  type :: sphere_t
    integer :: nz = 0
    real(wp), allocatable :: r(:), u(:), mn(:)    !< (0:nz) node radius, velocity, mass
    real(wp), allocatable :: m(:), rho(:), e(:), p(:), cs(:), q(:)   !< (nz) zone state
    integer, allocatable :: mat(:)                !< (nz) zone material
    real(wp), allocatable :: a0(:)                !< (nz) initial width over outer radius (`sphere_merge`)
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
    s%a0 = (s%r(1:s%nz) - s%r(0:s%nz - 1))/s%r(1:s%nz)
    call sphere_refresh(s)
  end subroutine sphere_setup

  !> Pressures, sound speeds and viscosity of the zones at s%t (after a
  !> merge: the materials' cell lists rebuilt first).
  subroutine sphere_refresh(s)
    type(sphere_t), intent(inout) :: s
    call eos_at(s, s%rho, s%e, s%p, s%cs, s%t, 0.0_wp)
    call viscosity(s, s%rho, s%cs, s%u, s%q)
  end subroutine sphere_refresh

  !> Merges each zone z (2 <= z <= nz - 2) thinner than its initial width
  !> over radius divided by ratio, and not compressed (its volume growing),
  !> with the next zone (or else the one before) of the same material, where
  !> neither is an explosive (module header); each zone takes part in one
  !> merge per call. keep: a per-zone array of the caller, the merged zone
  !> keeping the inner zone's value. nmerged: the merges made; the caller
  !> rebuilds the materials' cell lists and calls `sphere_refresh` if any.
  !> stat: nonzero where an array could not be allocated (s is then not
  !> to be used).
  subroutine sphere_merge(s, ratio, keep, nmerged, stat)
    type(sphere_t), intent(inout) :: s
    real(wp), intent(in) :: ratio
    real(wp), allocatable, intent(inout) :: keep(:)
    integer, intent(out) :: nmerged, stat
    integer :: z
    nmerged = 0
    stat = 0
    z = 2
    do while (z <= s%nz - 2 .and. stat == 0)
      if (thin(z)) then
        if (pairs(z)) then
          call merge_pair(z)
        else if (pairs(z - 1)) then
          call merge_pair(z - 1)
        end if
      end if
      z = z + 1
    end do

  contains

    logical function thin(z)
      integer, intent(in) :: z
      thin = (s%r(z) - s%r(z - 1))*ratio < s%a0(z)*s%r(z) .and. &
             .not. s%r(z)**2*s%u(z) < s%r(z - 1)**2*s%u(z - 1)
    end function thin

    !> Whether zones z and z + 1 may merge: one material, not an
    !> explosive, the nodes either side of them free (not the centre's,
    !> not the wall's).
    logical function pairs(z)
      integer, intent(in) :: z
      pairs = z >= 2 .and. z <= s%nz - 2
      if (pairs) pairs = s%mat(z) == s%mat(z + 1)
      if (pairs) pairs = .not. allocated(s%mats(s%mat(z))%burn)
    end function pairs

    !> Zones z and z + 1 into zone z; node z removed.
    subroutine merge_pair(z)
      integer, intent(in) :: z
      real(wp) :: ke0, mlo, mhi, ulo, uhi, mz
      integer :: k
      integer, allocatable :: mat(:)
      mz = s%m(z) + s%m(z + 1)
      ke0 = 0.5_wp*(s%mn(z - 1)*s%u(z - 1)**2 + s%mn(z)*s%u(z)**2 + s%mn(z + 1)*s%u(z + 1)**2)
      mlo = s%mn(z - 1) + 0.5_wp*s%m(z + 1)
      mhi = s%mn(z + 1) + 0.5_wp*s%m(z)
      ulo = (s%mn(z - 1)*s%u(z - 1) + 0.5_wp*s%m(z + 1)*s%u(z))/mlo
      uhi = (s%mn(z + 1)*s%u(z + 1) + 0.5_wp*s%m(z)*s%u(z))/mhi
      s%e(z) = (s%m(z)*s%e(z) + s%m(z + 1)*s%e(z + 1) + (ke0 - 0.5_wp*(mlo*ulo**2 + mhi*uhi**2)))/mz
      s%m(z) = mz
      s%rho(z) = 3.0_wp*mz/(s%r(z + 1)**3 - s%r(z - 1)**3)
      s%a0(z) = min(s%a0(z), s%a0(z + 1))
      s%mn(z - 1) = mlo
      s%u(z - 1) = ulo
      s%mn(z + 1) = mhi
      s%u(z + 1) = uhi
      ! node z and zone z + 1 out
      call drop_entry(s%r, z, stat)
      call drop_entry(s%u, z, stat)
      call drop_entry(s%mn, z, stat)
      call drop_entry(s%m, z + 1, stat)
      call drop_entry(s%rho, z + 1, stat)
      call drop_entry(s%e, z + 1, stat)
      call drop_entry(s%p, z + 1, stat)
      call drop_entry(s%cs, z + 1, stat)
      call drop_entry(s%q, z + 1, stat)
      call drop_entry(s%a0, z + 1, stat)
      call drop_entry(keep, z + 1, stat)
      do k = 1, size(s%mats)
        if (.not. allocated(s%mats(k)%burn)) cycle
        call drop_entry(s%mats(k)%burn%light, z + 1, stat)
        call drop_entry(s%mats(k)%burn%tau, z + 1, stat)
        call drop_entry(s%mats(k)%burn%f, z + 1, stat)
      end do
      s%mat(z + 1:s%nz - 1) = s%mat(z + 2:s%nz)
      if (stat == 0) allocate(mat(s%nz - 1), stat=stat)
      if (stat /= 0) return
      mat = s%mat(1:s%nz - 1)
      call move_alloc(mat, s%mat)
      s%nz = s%nz - 1
      nmerged = nmerged + 1
    end subroutine merge_pair
  end subroutine sphere_merge

  !> a(lo:n) without a(k), as a(lo:n-1) (lo: a's lower bound, 0 for the
  !> nodes' arrays); stat: the allocation's (a unchanged where it fails).
  subroutine drop_entry(a, k, stat)
    real(wp), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: k
    integer, intent(inout) :: stat
    real(wp), allocatable :: b(:)
    integer :: lo, n
    if (stat /= 0) return
    lo = lbound(a, 1)
    n = ubound(a, 1)
    allocate(b(lo:n - 1), stat=stat)
    if (stat /= 0) return
    b(lo:k - 1) = a(lo:k - 1)
    b(k:n - 1) = a(k + 1:n)
    call move_alloc(b, a)
  end subroutine drop_entry

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
