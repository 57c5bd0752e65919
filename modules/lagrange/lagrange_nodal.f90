!> What a Lagrangian step takes from outside the grid: a nodal contributor.
!>
!> `lagrange_step` sequences the grid's corner forces and the boundary's
!> pressure forces itself; what else pushes on the nodes (the coupled
!> particles, a prescribed force; later contact and blast loading) is a
!> `nodal_part_t`, which the step calls at fixed points of its two stages:
!>  - `start`, once the step's start state is saved;
!>  - `visc_scale`, the factor on each cell's artificial viscosity it asks
!>    for in both stages (none by default);
!>  - `forces`, after the corner forces of each stage (1 predictor, 2
!>    corrector), to set its nodal forces f (3, nnode) and masses m
!>    (nnode) of the stage, which `arrays` then points at and the node
!>    update adds to the corner forces and the nodal masses:
!>    u = u^n + dt (sum_c F_c + f)/(m_n + m);
!>  - `cells`, after each stage's cell update: work of its own on the cells
!>    (the particles' virtual fluid's energy), whose exact sum it adds to
!>    `acc`.
!> The step returns the work of f on the nodes, dt sum_n f_n . u_n^{n+1/2},
!> and the sum given in `cells`, both the corrector's. `bad` names a problem
!> the contributor found (0: none), for the caller to report.
!> The type itself is a prescribed force: its components f and m as the
!> caller set them, the same in both stages, and the hooks doing nothing.
module lagrange_nodal
  use base_kinds, only: wp
  use base_xsum, only: xsum_t
  use mesh_grid, only: grid_t
  use mesh_halo, only: halo_t
  use mesh_boundary, only: bc_t
  use hydro_state, only: hydro_t, hydro_params_t
  implicit none
  private
  public :: nodal_part_t

  type :: nodal_part_t
    integer :: bad = 0            !< a problem found in the step (0: none)
    real(wp), allocatable :: f(:, :)   !< (3, nnode) the stage's nodal forces (force)
    real(wp), allocatable :: m(:)      !< (nnode) the nodal masses added (mass)
  contains
    procedure :: start => part_start
    procedure :: visc_scale => part_visc_scale
    procedure :: forces => part_forces
    procedure :: cells => part_cells
    procedure :: arrays => part_arrays
  end type nodal_part_t

contains

  ! A prescribed force's hooks do nothing: each body's one statement, under
  ! `self%bad < -huge(1)` (never true), only keeps the compiler's check of
  ! unused arguments quiet.

  subroutine part_start(self, g, h, par)
    class(nodal_part_t), intent(inout) :: self
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(hydro_params_t), intent(in) :: par
    if (self%bad < -huge(1)) self%bad = g%ncell + size(h%vol) + merge(1, 0, par%cfl > 0.0_wp)
  end subroutine part_start

  !> scaled: whether the viscosity is scaled, by scale(c) in cell c.
  subroutine part_visc_scale(self, par, scaled, scale)
    class(nodal_part_t), intent(in), target :: self
    type(hydro_params_t), intent(in) :: par
    logical, intent(out) :: scaled
    real(wp), pointer, intent(out) :: scale(:)
    scaled = .false.
    scale => null()
    if (self%bad < -huge(1)) scaled = par%cfl > 0.0_wp
  end subroutine part_visc_scale

  !> The stage's nodal forces f (3, nnode) and masses m (nnode).
  subroutine part_arrays(self, f, m)
    class(nodal_part_t), intent(in), target :: self
    real(wp), pointer, contiguous, intent(out) :: f(:, :), m(:)
    f => self%f
    m => self%m
  end subroutine part_arrays

  subroutine part_forces(self, stage, g, h, bc, par, dt, halo)
    class(nodal_part_t), intent(inout) :: self
    integer, intent(in) :: stage
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(bc_t), intent(in) :: bc
    type(hydro_params_t), intent(in) :: par
    real(wp), intent(in) :: dt
    class(halo_t), intent(inout), optional :: halo
    if (self%bad < -huge(1)) self%bad = stage + g%ncell + size(h%vol) + size(bc%kind) + &
                                        merge(1, 0, par%cfl > dt .or. present(halo))
  end subroutine part_forces

  subroutine part_cells(self, stage, g, h, dt, acc)
    class(nodal_part_t), intent(inout) :: self
    integer, intent(in) :: stage
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(inout) :: h
    real(wp), intent(in) :: dt
    type(xsum_t), intent(inout) :: acc
    if (self%bad < -huge(1)) self%bad = stage + g%ncell + size(h%vol) + merge(1, 0, dt > 0.0_wp .or. acc%limb(0) > 0)
  end subroutine part_cells
end module lagrange_nodal
