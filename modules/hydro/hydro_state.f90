!> Hydrodynamic state of the staggered scheme and its integral quantities.
!>
!> Node-centred: velocity u and nodal mass (first term of Eq. 16, the sum of
!> the subcell masses around the node, constant in the Lagrangian phase).
!> The subcell (corner) masses are kept too: set by Eq. (16) (rho_c V_ca)
!> when the grid is built and after every remap, constant in the Lagrangian
!> phase like the cell masses, so that a cell's corners always add up to its
!> mass and a node's to its nodal mass (what the remap's momentum transfer
!> needs to conserve momentum and keep a uniform flow uniform).
!> Cell-centred: mass, volume, density, specific internal energy, pressure,
!> sound speed and artificial viscosity. Work arrays used inside a step are
!> allocated once here.
module hydro_state
  use, intrinsic :: iso_fortran_env, only: int8
  use base_kinds, only: wp, i8
  use base_strings, only: itoa
  use base_errors, only: error_no_memory, error_t, error_set
  use mesh_grid, only: grid_t
  use mesh_halo, only: halo_t
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use mesh_geometry, only: hex_subcell_volumes
  use base_registry, only: registry_t, LOC_NODE, LOC_CELL, LOWER_POSITIVE, LOWER_NONNEGATIVE
  implicit none
  private
  public :: hydro_t, hydro_params_t, hydro_allocate, hydro_totals, nodal_sums, cell_sums, hydro_subcell_masses, &
            hydro_register_restart, &
            VISC_EDGE, VISC_TENSOR

  !> Artificial viscosity forms (deck: &hydro viscosity = 'edge' | 'tensor').
  integer, parameter :: VISC_EDGE = 1, VISC_TENSOR = 2

  !> Numerical parameters of the Lagrangian phase (deck group &hydro, &run).
  type :: hydro_params_t
    integer :: viscosity = VISC_TENSOR  !< VISC_EDGE or VISC_TENSOR
    real(wp) :: q_linear = 0.5_wp     !< linear viscosity coefficient
    real(wp) :: q_quad = 1.5_wp       !< quadratic viscosity coefficient
    real(wp) :: hourglass = 0.1_wp    !< Flanagan-Belytschko viscous hourglass coefficient
    !> a node whose new velocity is below this fraction of the grid's
    !> fastest at the step's start, in every component, is at rest
    !> (`lagrange_step`); 0: none
    real(wp) :: velocity_cutoff = 1.0e-14_wp
    real(wp) :: cfl = 0.5_wp          !< Courant number
    real(wp) :: dv_max = 0.1_wp       !< largest relative volume change per step (of a cell, and of a material in a mixed cell)
    !> below this volume fraction a material's volume change is measured
    !> against this fraction of its cell for the dv_max limit (`mixed_volume_gain`)
    real(wp) :: dv_vf_min = 0.01_wp
    real(wp) :: dt_growth = 1.1_wp    !< largest ratio of consecutive steps
    real(wp) :: dt_max = huge(1.0_wp) !< largest step
    real(wp) :: relax = 1.0_wp        !< mixed-cell pressure relaxation per step, (0, 1]
    !> mixed cells: each material's acoustic resistance to the relaxation,
    !> rho c L / dt with L = relax_length times the cell's size (Tipton's
    !> closure); 0: none (equal pressures in one step when relax = 1)
    real(wp) :: relax_length = 0.0_wp
    !> particles coupled to the grid (Eqs. 16-17, 23-25, 29-32), or inert
    !> (seeded and written only: they neither move nor act on the gas)
    logical :: particles_coupled = .true.
    !> strain increments of the particles from the virtual solid grid (Eqs.
    !> 29-32, 'decoupled') or from the mixed nodal velocities (Eqs. 26-27)
    logical :: stress_decoupled = .true.
    !> artificial viscosity of cells hosting coupled particles scaled by
    !> 1 - theta_c, theta_c their particles' volume fraction ('scaled', PARTICLES.md
    !> §1.7), or the cells' own ('full')
    logical :: particle_visc_scaled = .true.
    !> each particle's weights the mean of the shape functions over its
    !> domain, spread over the cells it overlaps ('gimp', `particles_spread`:
    !> weights that change smoothly when an Euler step moves a particle
    !> across a face; the default), or the shape functions at its centre
    !> ('linear', standard MPM)
    logical :: particle_gimp = .true.
    !> linear artificial viscosity of the particles, q_p = -particle_q rho_p c_p
    !> l_p tr(D_p) (`particles_viscosity`); 0: none
    real(wp) :: particle_q = 0.2_wp
  end type hydro_params_t

  !> The state, plus per-step work arrays.
  type :: hydro_t
    real(wp), allocatable :: u(:, :)      !< node velocity (3, nnode)
    real(wp), allocatable :: mnode(:)     !< node mass
    real(wp), allocatable :: mcorner(:, :) !< subcell (corner) masses (8, ncell); sum over a node's corners: mnode
    real(wp), allocatable :: mass(:)      !< cell mass
    real(wp), allocatable :: vol(:)       !< cell volume
    real(wp), allocatable :: rho(:)       !< cell density
    real(wp), allocatable :: e(:)         !< cell specific internal energy
    real(wp), allocatable :: p(:)         !< cell pressure
    real(wp), allocatable :: cs(:)        !< cell sound speed
    real(wp), allocatable :: q(:)         !< artificial viscosity (sum over directions)
    integer, allocatable :: mat(:)        !< material of each cell
    !> mixed cells: the largest ratio of a material's relative volume change
    !> to the cell's (`mixed_volume_gain`), set at the start of each step for
    !> the time step; not read for pure cells
    real(wp), allocatable :: gain(:)
    ! work arrays of one step
    real(wp), allocatable :: xn(:, :), un(:, :), uh(:, :), en(:)
    real(wp), allocatable :: fc(:, :, :)  !< corner forces (3, 8, ncell)
    real(wp), allocatable :: grad(:, :)   !< directional strain rates (3, ncell)
    ! geometry of the cells at the positions of the current force evaluation,
    ! computed once per stage (by `lagrange_strain_rates`, or by
    ! `lagrange_update_cells` for the positions it has just made) and read by
    ! `lagrange_corner_forces` (the median-surface area vectors, cheap, are
    ! recomputed where the viscosity needs them)
    real(wp), allocatable :: dvdx(:, :, :)  !< volume gradient dV/dx_a (3, 8, ncell), length^2
    !> the largest and the sum of the three median-surface areas (2, ncell), length^2
    real(wp), allocatable :: amed(:, :)
    !> (ncell) the cell was at rest in the last step's first stage: its
    !> nodes at their places of that step's start, every velocity zero
    !> (`lagrange_update_cells`); its geometry, rates and sizes are then
    !> those of these places at rest
    logical, allocatable :: still(:)
    !> (nnode) work of a kernel's cell loop: bits of what each node's values
    !> tell (`lagrange_node_flags`), so that a cell's test of its eight nodes
    !> (at rest, not moved) reads eight bytes, not 24 or 48 reals
    integer(int8), allocatable :: nflag(:)
  end type hydro_t

contains

  !> Allocates the state for ncell cells and nnode nodes (whatever h held
  !> before is freed first). Memory: 70 reals, an integer and a logical per cell, 13
  !> reals and a byte per node (about 680 bytes per cell of a large grid, most of it
  !> the corner forces and volume gradients, 192 bytes each). With
  !> step_work false, the state without the work arrays of a Lagrangian
  !> step (xn ... amed): 16 reals and an integer per cell, 4 per node, for a
  !> state that is only remapped (a decomposed run's window).
  subroutine hydro_allocate(h, ncell, nnode, err, step_work)
    type(hydro_t), intent(out) :: h
    integer, intent(in) :: ncell, nnode
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: step_work
    integer :: stat, nw, mw
    integer(i8) :: bytes
    character(len=200) :: msg

    nw = nnode
    mw = ncell
    if (present(step_work)) then
      if (.not. step_work) then
        nw = 0
        mw = 0
      end if
    end if
    allocate(h%u(3, nnode), h%mnode(nnode), h%mcorner(8, ncell), h%mass(ncell), h%vol(ncell), h%rho(ncell), &
             h%e(ncell), h%p(ncell), h%cs(ncell), h%q(ncell), h%mat(ncell), h%gain(ncell), &
             h%xn(3, nw), h%un(3, nw), h%uh(3, nw), h%en(mw), &
             h%fc(3, 8, mw), h%grad(3, mw), h%dvdx(3, 8, mw), h%amed(2, mw), h%still(mw), h%nflag(nw), &
             stat=stat, errmsg=msg)
    if (stat /= 0) then
      bytes = (70_i8*ncell + 13_i8*nnode)*storage_size(1.0_wp)/8 + 2_i8*ncell*storage_size(1)/8 + nnode
      call error_set(err, 'hydro_allocate', error_no_memory('the hydro state ('//itoa(ncell)//' cells, '// &
                     itoa(nnode)//' nodes: '//itoa(bytes/1048576_i8)//' MiB)'))
      return
    end if
    h%u = 0.0_wp; h%mnode = 0.0_wp; h%mcorner = 0.0_wp; h%q = 0.0_wp; h%mat = 0; h%gain = 1.0_wp
    h%xn = 0.0_wp; h%uh = 0.0_wp; h%un = 0.0_wp; h%fc = 0.0_wp; h%grad = 0.0_wp
    h%dvdx = 0.0_wp; h%amed = 0.0_wp; h%still = .false.; h%nflag = 0_int8
  end subroutine hydro_allocate

  !> Eq. (16), first term: the nodal masses mnode (mass) of the grid with
  !> node positions x and cell densities rho, sums of the subcell masses
  !> rho_c V_ca of the cells' corners; those are returned in msub(8, ncell)
  !> if present.
  subroutine hydro_subcell_masses(g, x, rho, mnode, msub)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), rho(:)
    real(wp), intent(out) :: mnode(:)
    real(wp), intent(out), optional :: msub(:, :)
    real(wp) :: xn(3, 8), vsub(8)
    integer :: c, a, n

    mnode = 0.0_wp
    do c = 1, g%ncell
      call g%gather(c, x, xn)
      call hex_subcell_volumes(xn, vsub)
      vsub = rho(c)*vsub
      do a = 1, 8
        n = g%node0(c) + g%corner_offset(a)
        mnode(n) = mnode(n) + vsub(a)
      end do
      if (present(msub)) msub(:, c) = vsub
    end do
  end subroutine hydro_subcell_masses

  !> Total mass, momentum, internal and kinetic energy of the whole grid:
  !> each term added exactly (`base_xsum`) over the owned cells and the
  !> nodes the block counts, and the blocks' sums added by `halo`, so the
  !> totals are the same numbers on any number of ranks and threads;
  !> pscale: the momentum's scale (`nodal_sums`).
  subroutine hydro_totals(g, h, halo, mass, momentum, internal, kinetic, pscale)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    class(halo_t), intent(in) :: halo
    real(wp), intent(out) :: mass, momentum(3), internal, kinetic
    real(wp), intent(out), optional :: pscale
    call cell_sums(g, h, halo, mass, internal)
    call nodal_sums(g, halo, h%mnode, h%u, kinetic, momentum, pscale)
  end subroutine hydro_totals

  !> The mass and internal energy of the cells g's block owns, exact sums
  !> over all blocks.
  subroutine cell_sums(g, h, halo, mass, internal)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    class(halo_t), intent(in) :: halo
    real(wp), intent(out) :: mass, internal
    type(xsum_t) :: acc(2)
    integer :: i, j, k, c
    do k = g%clo(3), g%chi(3)
      do j = g%clo(2), g%chi(2)
        do i = g%clo(1), g%chi(1)
          c = g%cell(i, j, k)
          call xsum_add(acc(1), h%mass(c))
          call xsum_add(acc(2), h%mass(c)*h%e(c))
        end do
      end do
    end do
    call halo%sums(acc)
    mass = xsum_value(acc(1))
    internal = xsum_value(acc(2))
  end subroutine cell_sums

  !> Kinetic energy ke and momentum p of the nodes' velocities u with masses
  !> m, and with scale the sum of m |u| (the momentum's scale), exact sums
  !> over the nodes g's block counts, over all blocks.
  subroutine nodal_sums(g, halo, m, u, ke, p, scale)
    type(grid_t), intent(in) :: g
    class(halo_t), intent(in) :: halo
    real(wp), intent(in) :: m(:), u(:, :)
    real(wp), intent(out) :: ke, p(3)
    real(wp), intent(out), optional :: scale
    type(xsum_t) :: acc(5)
    integer :: i, j, k, n, d, na
    na = merge(5, 4, present(scale))
    do k = g%ulo(3), g%nhi(3)
      do j = g%ulo(2), g%nhi(2)
        do i = g%ulo(1), g%nhi(1)
          n = g%node(i, j, k)
          do d = 1, 3
            call xsum_add(acc(d), m(n)*u(d, n))
          end do
          call xsum_add(acc(4), 0.5_wp*m(n)*dot_product(u(:, n), u(:, n)))
          if (na == 5) call xsum_add(acc(5), m(n)*norm2(u(:, n)))
        end do
      end do
    end do
    call halo%sums(acc(1:na))
    p = [(xsum_value(acc(d)), d = 1, 3)]
    ke = xsum_value(acc(4))
    if (present(scale)) scale = xsum_value(acc(5))
  end subroutine nodal_sums

  !> Registers the hydro state's restart fields (not the work arrays).
  subroutine hydro_register_restart(h, reg)
    type(hydro_t), intent(inout), target :: h
    type(registry_t), intent(inout) :: reg
    call reg%add('velocity', 'length/time', LOC_NODE, h%u)
    call reg%add('node_mass', 'mass', LOC_NODE, h%mnode, lower=LOWER_POSITIVE)
    call reg%add('corner_mass', 'mass', LOC_CELL, h%mcorner, lower=LOWER_NONNEGATIVE)
    call reg%add('mass', 'mass', LOC_CELL, h%mass, lower=LOWER_POSITIVE)
    call reg%add('volume', 'length^3', LOC_CELL, h%vol, lower=LOWER_POSITIVE)
    call reg%add('density', 'mass/length^3', LOC_CELL, h%rho, lower=LOWER_POSITIVE)
    call reg%add('energy', 'energy/mass', LOC_CELL, h%e)
    call reg%add('pressure', 'pressure', LOC_CELL, h%p)
    call reg%add('sound_speed', 'length/time', LOC_CELL, h%cs, lower=LOWER_NONNEGATIVE)
    call reg%add('viscosity', 'pressure', LOC_CELL, h%q)
    call reg%add('material', '1', LOC_CELL, h%mat)
  end subroutine hydro_register_restart
end module hydro_state
