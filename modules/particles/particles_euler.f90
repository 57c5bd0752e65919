!> The particles in the Euler phase ("physical variables correction with
!> solid particles", PARTICLES.md §1.13, Remark 2 of Sect. 5.2): the
!> kernels the driver (`driver_particles`) strings together around the
!> fluid's rezone and remap.
!>
!> 1. The particles keep their own velocities (Eq. 23 accumulates the
!>    grid's increments on them, FLIP): through a Lagrangian phase
!>    sum_p (m_p - m'_p) v_p changes exactly as the particles' share of the
!>    nodal momentum, sum_I (sum_p (m_p - m'_p) N_Ip) v_I, does, and a rigid
!>    motion stays exact on them whatever the grid does. (Replacing v_p by the
!>    grid's velocity at it, PIC, as the design note proposed, loses the
!>    rotation's kinetic energy at the body's edge nodes at every Euler step:
!>    43 % of a rotating projectile's over 149 Euler steps.)
!> 2. `particles_relocate`: each particle's host cell and natural coordinates
!>    in a grid (the standard grid for the pre-positioning of Remark 2, the
!>    rezoned grid after the remap), by its physical position, walking from a
!>    guess. The particles' positions do not change.
!> 3. `particles_occupied`: the cells holding particles (the fixed inner
!>    boundary of the smoothing, Fig. 4f).
!> 4. (the driver, `driver_euler::snap_nodes`) the nodes of the occupied
!>    cells put at their places in the standard grid.
!> After the remap the driver re-sorts and re-bins the particles, gives them
!> new virtual-fluid masses from their new hosts' densities and rebuilds the
!> nodal velocity from the remapped fluid momentum and the particles'; then
!> 5. `particles_flip`: the rebuild's change of the node velocities against
!>    the particles' mean (the fluid's share, the kinematic conditions) goes
!>    to the particles, so that they and the nodes agree again.
module particles_euler
  use base_kinds, only: wp
  use mesh_grid, only: grid_t
  use particles_state, only: particles_t
  use particles_shape, only: particles_locate
  use particles_lagrange, only: particles_interpolate
  implicit none
  private
  public :: particles_flip, particles_relocate, particles_occupied

contains

  !> v_p += sum_a N_a(xi_p) (u_a - vbar_a) over the host's corners (item 5):
  !> the change the rebuild made to the nodes' velocities, given to the
  !> particles as a Lagrangian step's would be (Eq. 23).
  subroutine particles_flip(g, p, u, vbar)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout) :: p
    real(wp), intent(in) :: u(:, :), vbar(:, :)
    integer :: k
    !$omp parallel do default(none) shared(g, p, u, vbar) private(k) schedule(static)
    do k = 1, p%np
      p%v(:, k) = p%v(:, k) + particles_interpolate(g, p, k, u, vbar)
    end do
    !$omp end parallel do
  end subroutine particles_flip

  !> Host cell(np) and natural coordinates xi(3, np) of every particle's
  !> position in the grid with nodes at x(3, nnode), the walk starting at
  !> guess(np) (item 2). bad: the first particle in no cell (0 if none).
  subroutine particles_relocate(g, x, p, guess, cell, xi, bad)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: guess(:)
    integer, intent(out) :: cell(:)
    real(wp), intent(out) :: xi(:, :)
    integer, intent(out) :: bad
    integer :: k
    logical :: found
    bad = huge(1)
    !$omp parallel do default(none) shared(g, x, p, guess, cell, xi) private(k, found) reduction(min: bad) &
    !$omp schedule(dynamic, 256)
    do k = 1, p%np
      call particles_locate(g, p%x(:, k), guess(k), cell(k), xi(:, k), found, x)
      if (.not. found) bad = min(bad, k)
    end do
    !$omp end parallel do
    if (bad == huge(1)) bad = 0
  end subroutine particles_relocate

  !> The cells that host a particle of cell(np) (item 3).
  pure function particles_occupied(cell, ncell) result(occ)
    integer, intent(in) :: cell(:), ncell
    logical :: occ(ncell)
    integer :: k
    occ = .false.
    do k = 1, size(cell)
      occ(cell(k)) = .true.
    end do
  end function particles_occupied
end module particles_euler
