!> The particles' supports spread over the cells they overlap (&hydro
!> particle_support = 'gimp'): the generalized interpolation material point
!> method (Bardenhagen and Kober 2004) in the natural coordinates of the
!> grid, so that a particle crossing a face at an Euler step (Remark 2 of
!> Sect. 5.2) changes its weights continuously instead of jumping from one
!> cell's shape functions to the next one's (the cell-crossing error of
!> linear MPM, which the paper's conclusion names).
!>
!> A particle's domain is the box xi_d -/+ l in its host's natural
!> coordinates ([0,1]^3, `particles_shape`), l = (V_p/V_c)^(1/3)/2 (V_c the
!> host's volume; half the particle spacing of a seeding with the same
!> number of particles per cell in each direction), at most 1/2, so that
!> it overlaps at most one neighbour in each direction. l is set where the
!> hosts are set (the seeding, the re-location of an Euler step) and kept
!> with the natural coordinates through the Lagrangian phase (the domain
!> deforms with the grid), so the pieces are the same after a restart. Where it reaches
!> past a face the overlap continues in the neighbour with the same
!> natural length (exact on a uniform grid). Per direction the domain is
!> one or two segments, each with its share (its length over 2l) and its
!> centre; a piece is a product of one segment per direction: the cell,
!> the centre's natural coordinates there and the product of the shares.
!> The GIMP weight of node I, the mean of N_I over the domain, is then
!> sum over pieces of share x N_I(centre) exactly (N is linear in each
!> natural coordinate within a cell), and its gradient the same sum of
!> grad N_I(centre) (exact on a box grid). The shares add up to 1, so mass
!> and momentum transfers stay conservative and a uniform field is kept.
!>
!> A domain that reaches past the grid's boundary (no neighbour there), or
!> into a neighbour that hosts no particle (past the body's surface, the
!> far side of the cells the fluid holds), is not spread in that
!> direction: the particle keeps its point weights across it (nothing
!> crosses a boundary; the body's stress puts no force on the nodes of a
!> fluid cell that only its domains reach, whose mass is the fluid's and
!> their small share: risk R1 of docs/PARTICLES.md, which emptied the
!> wake of a plate one cell thick). A neighbour beyond a block's stored
!> cells hosts none, as does one whose particles the block does not hold
!> (only far ghost particles reach either; the ghost layers are deep
!> enough that no owned node needs their pieces).
module particles_spread
  use base_kinds, only: wp
  use mesh_grid, only: grid_t
  use mesh_geometry, only: hex_volume
  use particles_state, only: particles_t, particles_pieces_by_cell
  implicit none
  private
  public :: particles_spread_pieces, particles_support_widths

contains

  !> The half-widths p%lsup of the particles' domains (module notes) in
  !> their hosts in the grid g, from their volumes and their hosts'
  !> (where the hosts are set: the seeding, an Euler step's re-location;
  !> kept through the Lagrangian phase and its restarts).
  subroutine particles_support_widths(g, p)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout) :: p
    real(wp) :: xn(3, 8)
    integer :: k, a, n0
    do k = 1, p%np
      n0 = g%node0(p%cell(k))
      do a = 1, 8
        xn(:, a) = g%x(:, n0 + g%corner_offset(a))
      end do
      p%lsup(k) = 0.5_wp*min(1.0_wp, (p%vol(k)/hex_volume(xn))**(1.0_wp/3.0_wp))
    end do
  end subroutine particles_support_widths

  !> Spreads the pieces of p (binned for the current hosts by
  !> `particles_bin`, which leaves room for eight per particle when p%spread)
  !> over the cells the particles' domains (half-widths p%lsup) overlap in
  !> the grid g, if p%spread and not already done, and bins them by cell
  !> again.
  subroutine particles_spread_pieces(g, p)
    type(grid_t), intent(in) :: g
    type(particles_t), intent(inout) :: p
    real(wp) :: cen(2, 3), sh(2, 3)
    integer :: nseg(3), off(2, 3), ijk(3), nb(3), k, n, q, a, b, d, c
    logical :: lo_ok

    if (p%spread_ready .or. p%np == 0) return
    n = 0
    do k = 1, p%np
      call g%cell_ijk(p%cell(k), ijk(1), ijk(2), ijk(3))
      do d = 1, 3
        nb = ijk
        nb(d) = ijk(d) - 1
        lo_ok = hosts(nb)
        nb(d) = ijk(d) + 1
        call segments(p%xi(d, k), p%lsup(k), lo_ok, hosts(nb), nseg(d), off(:, d), cen(:, d), sh(:, d))
      end do
      p%pfirst(k) = n + 1
      do c = 1, nseg(3)
        do b = 1, nseg(2)
          do a = 1, nseg(1)
            nb = ijk + [off(a, 1), off(b, 2), off(c, 3)]
            n = n + 1
            p%pcell(n) = g%cell(nb(1), nb(2), nb(3))
            p%ppart(n) = k
            p%pxi(:, n) = [cen(a, 1), cen(b, 2), cen(c, 3)]
            p%pw(n) = sh(a, 1)*sh(b, 2)*sh(c, 3)
          end do
        end do
      end do
    end do
    p%pfirst(p%np + 1) = n + 1
    p%npc = n
    ! the pieces by cell, in piece order within a cell (a counting sort:
    ! counts, prefix sums, placement, and the starts shifted back)
    p%pc_start = 0
    do q = 1, n
      p%pc_start(p%pcell(q) + 1) = p%pc_start(p%pcell(q) + 1) + 1
    end do
    p%pc_start(1) = 1
    do c = 1, size(p%pc_start) - 1
      p%pc_start(c + 1) = p%pc_start(c + 1) + p%pc_start(c)
    end do
    do q = 1, n
      p%pc_perm(p%pc_start(p%pcell(q))) = q
      p%pc_start(p%pcell(q)) = p%pc_start(p%pcell(q)) + 1
    end do
    do c = size(p%pc_start), 2, -1
      p%pc_start(c) = p%pc_start(c - 1)
    end do
    p%pc_start(1) = 1
    call particles_pieces_by_cell(p)
    p%spread_ready = .true.

  contains

    !> Whether the stored cell nb hosts a particle (a domain spreads into
    !> it: module notes).
    logical function hosts(nb)
      integer, intent(in) :: nb(3)
      integer :: cn
      hosts = all(nb >= g%slo .and. nb <= g%shi)
      if (.not. hosts) return
      cn = g%cell(nb(1), nb(2), nb(3))
      hosts = p%cell_start(cn + 1) > p%cell_start(cn)
    end function hosts
  end subroutine particles_spread_pieces

  !> The segments of the domain x -/+ l (natural coordinates of a cell):
  !> ns (1 or 2) segments, each with the offset of its cell (-1, 0, +1), its
  !> centre in that cell's natural coordinate and its share of the domain;
  !> spread into the neighbour below (lo_ok) or above (hi_ok) only where
  !> that neighbour may take a piece (module notes), else the point weights
  !> in this direction.
  pure subroutine segments(x, l, lo_ok, hi_ok, ns, off, cen, sh)
    real(wp), intent(in) :: x, l
    logical, intent(in) :: lo_ok, hi_ok
    integer, intent(out) :: ns, off(2)
    real(wp), intent(out) :: cen(2), sh(2)
    real(wp) :: lo, hi
    lo = x - l
    hi = x + l
    ns = 1
    off = 0
    cen = x
    sh = [1.0_wp, 0.0_wp]
    if (.not. l > 0.0_wp) return
    if (lo < 0.0_wp .and. lo_ok) then
      ns = 2
      cen(1) = 0.5_wp*hi
      sh(1) = hi/(2.0_wp*l)
      off(2) = -1
      cen(2) = 1.0_wp + 0.5_wp*lo
      sh(2) = 1.0_wp - sh(1)
    else if (hi > 1.0_wp .and. hi_ok) then
      ns = 2
      cen(1) = 0.5_wp*(1.0_wp + lo)
      sh(1) = (1.0_wp - lo)/(2.0_wp*l)
      off(2) = 1
      cen(2) = 0.5_wp*(hi - 1.0_wp)
      sh(2) = 1.0_wp - sh(1)
    end if
  end subroutine segments
end module particles_spread
