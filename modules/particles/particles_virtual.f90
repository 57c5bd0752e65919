!> The virtual fluid at an Euler step (PARTICLES.md §1.1, Eq. 2): the fluid
!> a cell holds under a solid takes the state of the real fluid around the
!> solid before the remap.
!>
!> The grid's cells hold fluid over their whole volume: real where no solid
!> is, virtual under the particles (whose m'_p = rho_c V_p the nodes do not
!> count twice). Eq. 2 reads the fluid's density as one field through the
!> solid, but the Lagrangian phase carries whatever state the virtual fluid
!> had (a solid seeded in near-vacuum keeps near-vacuum inside it), and the
!> remap of a cell the solid's surface cuts spreads its one (real and
!> virtual) state over the new cells on both sides of the surface. Where
!> the two states differ the remap so moves real fluid into the solid (where
!> m'_p then hides it) and virtual fluid out of it: on a free elastic slab
!> driven by gas into near-vacuum (tests/decks/particles_ballistic200.nml,
!> linear support, global Euler steps every 20 steps) 0.7 % of the gas's mass vanished into
!> the slab by t = 1.2 and the slab ran 0.3 to 1.5 % slow.
!>
!> `particles_virtual_fill` gives the covered cells (those whose particles'
!> volumes add up to covered_fraction of theirs, holding one material)
!> within `layers` cells of the solid's surface the state of the fluid
!> around the solid, layer by layer inwards: a layer's cells take the mean
!> density and specific internal energy of their face neighbours filled
!> before it (the real cells and the cells the surface cuts first) that
!> hold the cell's material, where those lie on one side in each direction
!> (a solid one cell thick between two fluids would otherwise pass one
!> side's state to the other). A virtual fluid never changes material (a
!> structure's air does not turn into the products that reach it: the
!> materials' masses would). Their m'_p scale with their density, so the
!> mass the nodes move with changes only where the particles' volumes do not
!> tile their cells; the driver books the energy this changes. A cell the
!> surface cuts keeps its state: it holds real fluid. Deeper cells keep
!> theirs too: their virtual fluid meets no real fluid in one remap, and
!> the particles' quadrature of its pressure and mass is inexact (a light
!> solid whose whole virtual fluid took a dense gas's state rang: the gas /
!> solid Riemann problem's plateau scatter 52 % at 400 cells with GIMP,
!> against 2.4 % with one layer). One layer (the default) against two and
!> three (`tools/particles_euler.py`, GIMP with particle_q 0.4): the slab
!> at 100 / 200 / 400 cells +0.07 / +0.00 / -0.00 % against +0.09 / -0.01 /
!> -0.00 % and +0.08 / +0.01 / -0.00 %, the Riemann plateau alike.
module particles_virtual
  use base_kinds, only: wp
  use mesh_grid, only: grid_t
  use mesh_halo, only: halo_t
  use hydro_state, only: hydro_t
  use particles_state, only: particles_t
  use base_errors, only: error_t, error_set, error_no_memory
  implicit none
  private
  public :: particles_virtual_fill

  !> A cell is covered when its particles' volumes add up to this share of
  !> its volume (a cell the solid's surface cuts holds real fluid)
  real(wp), parameter :: covered_fraction = 0.95_wp

contains

  !> The fill (module notes) on g's block: h's covered cells (owned and
  !> ghost, the ghosts as their owners fill them: halo) take the state of
  !> the fluid around the solid; their corner and nodal masses scale with
  !> their density and the m'_p of p's particles in them follow. filled(ncell):
  !> the stored cells so filled (their EOS is the caller's); nfill the whole
  !> grid's count, nlayer the layers.
  subroutine particles_virtual_fill(g, h, p, halo, layers, filled, nfill, nlayer, err)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    type(particles_t), intent(inout) :: p
    class(halo_t), intent(inout) :: halo
    integer, intent(in) :: layers
    logical, allocatable, intent(out) :: filled(:)
    integer, intent(out) :: nfill, nlayer
    type(error_t), allocatable, intent(inout) :: err
    ! vsolid: the particles' volume in each cell; level: 0 real or cut by the
    ! surface (a source), -1 covered and not yet filled, L > 0 filled in
    ! layer L
    real(wp), allocatable :: vsolid(:), level(:), rho(:), e(:), rho1(:), e1(:), mn(:, :)
    real(wp) :: srho, se, fac
    integer :: c, k, i, j, l, a, n0, nb, stat, cand(6), pick(6), m, new(1)
    logical :: side(6)

    nfill = 0
    nlayer = 0
    allocate(vsolid(g%ncell), level(g%ncell), rho(g%ncell), e(g%ncell), rho1(g%ncell), e1(g%ncell), filled(g%ncell), &
             mn(1, g%nnode), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'particles_virtual_fill', error_no_memory('the fill''s work arrays'))
      return
    end if
    vsolid = 0.0_wp
    do k = 1, p%np
      vsolid(p%cell(k)) = vsolid(p%cell(k)) + p%vol(k)
    end do
    level = 0.0_wp
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          c = g%cell(i, j, k)
          if (vsolid(c) >= covered_fraction*h%vol(c) .and. h%mat(c) > 0) level(c) = -1.0_wp
        end do
      end do
    end do
    call halo%cells(level)
    rho = h%rho
    e = h%e
    do while (nlayer < layers)
      new = 0
      do k = g%clo(3), g%chi(3)
        do j = g%clo(2), g%chi(2)
          do i = g%clo(1), g%chi(1)
            c = g%cell(i, j, k)
            if (level(c) > -0.5_wp) cycle
            ! the face neighbours filled before this layer that hold the
            ! cell's material alone; a cell with such neighbours on both sides
            ! in a direction (a solid one cell thick between two fluids) keeps
            ! its state
            call neighbours(i, j, k, cand)
            m = 0
            side = .false.
            do a = 1, 6
              nb = cand(a)
              if (nb == 0) cycle
              if (level(nb) > -0.5_wp .and. level(nb) < real(nlayer, wp) + 0.5_wp .and. h%mat(nb) == h%mat(c)) then
                m = m + 1
                pick(m) = nb
                side(a) = .true.
              end if
            end do
            if (m == 0) cycle
            if (any(side(1:5:2) .and. side(2:6:2))) cycle
            ! (the mean as the first plus the mean difference: the same
            ! value where they all agree, a uniform state exactly uniform)
            srho = 0.0_wp
            se = 0.0_wp
            do a = 1, m
              srho = srho + (rho(pick(a)) - rho(pick(1)))
              se = se + (e(pick(a)) - e(pick(1)))
            end do
            ! (marked now, set below: this layer reads the layers before it)
            level(c) = real(nlayer + 1, wp)
            rho1(c) = rho(pick(1)) + srho/real(m, wp)
            e1(c) = e(pick(1)) + se/real(m, wp)
            new(1) = new(1) + 1
          end do
        end do
      end do
      call halo%sum_ints(new)
      if (new(1) == 0) exit
      nlayer = nlayer + 1
      nfill = nfill + new(1)
      do c = 1, g%ncell
        if (abs(level(c) - real(nlayer, wp)) < 0.5_wp) then
          rho(c) = rho1(c)
          e(c) = e1(c)
        end if
      end do
      call halo%cells(level)
      call halo%cells(rho)
      call halo%cells(e)
    end do
    ! the cells whose state changed: their masses, corners and nodes with
    ! the new densities
    do c = 1, g%ncell
      filled(c) = level(c) > 0.5_wp .and. (abs(rho(c) - h%rho(c)) > 0.0_wp .or. abs(e(c) - h%e(c)) > 0.0_wp)
      rho1(c) = rho(c)/h%rho(c)
    end do
    mn = 0.0_wp
    do c = 1, g%ncell
      if (.not. filled(c)) cycle
      fac = rho1(c)
      n0 = g%node0(c)
      do a = 1, 8
        l = n0 + g%corner_offset(a)
        mn(1, l) = mn(1, l) + (fac - 1.0_wp)*h%mcorner(a, c)
      end do
      h%mcorner(:, c) = fac*h%mcorner(:, c)
      h%rho(c) = rho(c)
      h%e(c) = e(c)
      h%mass(c) = rho(c)*h%vol(c)
    end do
    ! (a ghost node on the stored box's face lacks the cells beyond it: its
    ! owner's sum)
    do l = 1, g%nnode
      mn(1, l) = h%mnode(l) + mn(1, l)
    end do
    call halo%nodes(mn)
    h%mnode = mn(1, :)
    do k = 1, p%np
      if (filled(p%cell(k))) p%mvf(k) = rho1(p%cell(k))*p%mvf(k)
    end do

  contains

    !> The face neighbours of stored cell (i,j,k) towards -x, +x, -y, +y,
    !> -z, +z; 0 outside the whole grid.
    subroutine neighbours(i, j, k, nbr)
      integer, intent(in) :: i, j, k
      integer, intent(out) :: nbr(6)
      integer :: ijk(3), dd, s
      nbr = 0
      do dd = 1, 3
        do s = -1, 1, 2
          ijk = [i, j, k]
          ijk(dd) = ijk(dd) + s
          if (ijk(dd) + g%off(dd) < 1 .or. ijk(dd) + g%off(dd) > g%gn(dd)) cycle
          nbr(2*dd - 1 + (s + 1)/2) = g%cell(ijk(1), ijk(2), ijk(3))
        end do
      end do
    end subroutine neighbours
  end subroutine particles_virtual_fill
end module particles_virtual
