!> The remap of the Euler phase (Sect. 5.4): the state on the Lagrangian
!> (old) grid is transferred to the rezoned (new) grid by exact polyhedron
!> intersection, conservatively, with MoF interfaces in mixed cells.
!>
!> Pieces. Every cell is split into its 24 tetrahedra (cell centre, face
!> centre, edge; Fig. 7) and each of those into two halves at the edge
!> midpoint: the six halves at a node are the cell's corner (subcell) of that
!> node, the subcells whose volumes make the nodal mass (Eq. 16). The old
!> cell's 48 halves are its pieces whatever its shape (each half convex, a
!> half of an inverted tetrahedron counted negative); in a mixed old cell
!> the materials' planes come from MoF (`mof_reconstruct_nested`, deck
!> order) and material k's region is the cell on the inner side of its own
!> plane and the outer side of the planes before it (Fig. 12), so a piece of
!> a material region is a half clipped by at most nmat planes.
!>
!> Intersection. A new cell's corners are intersected with the old pieces
!> within its index window: in general its 48 halves are each clipped by an
!> old piece's planes (`tet_clip_planes`, with the plane tests done once on
!> the 27 points of the split); into an axis-aligned box (the initial grid
!> of a global rezone) each old piece is clipped by the box faces that cut
!> it and split among the eight octants (the box's subcells) by the
!> mid-planes it straddles. Each fragment has its volume and first moment;
!> summed per material they give the new cells' material volumes,
!> centroids, masses and energies (Eqs. 54-55), summed per corner and then
!> over the cells around a node, the nodal control-volume quantities
!> (Fig. 11, Eqs. 56-57).
!>
!> Mass and energy: linear in each old region about its exact centroid x_k
!> (the limited least-squares gradients of `remap_gradient`, or constant):
!>   mass of a fragment (volume v, first moment m):   rho_k v + grad rho_k . (m - x_k v)
!>   its internal energy:  mass_f e_k + rho_k grad e_k . (m - x_k v)
!> Over a whole region sum (m - x_k v) = 0, so each region gives away exactly
!> its mass and energy: conservation to round-off whatever the gradients,
!> and the limiter keeps the new values within the old neighbours' bounds.
!>
!> Momentum and nodal masses. Every cell's corners carry subcell masses
!> m_ca (Eq. 16: rho_c V_ca when set, constant in the Lagrangian phase like
!> the cell mass, so sum_a m_ca = m_c and a node's mass is the sum of its
!> corners'). Velocity moves with the mass: a fragment cut from subcell a of
!> an old cell carries, with its own mass m_f, the corner velocity u_a (plus
!> a shift per old cell that makes the fragments hand out exactly the old
!> cell's momentum sum_a m_ca u_a and kinetic energy: `subcell_shifts`). A
!> new cell's mass M is shared among its corners by subcell volume (Eq. 16
!> on the new grid), its momentum P the same way plus the deviations of the
!> momentum that landed in each corner from what the landed mass carries at
!> the cell's mean velocity P/M; the deviations are scaled down where a
!> corner received more than its share of mass, so every corner velocity
!> lies between the cell's mean and the velocity that landed in it
!> (`assemble`). Hence, whatever the densities of the materials in a mixed
!> cell:
!>   - momentum is conserved (each old cell hands out its momentum exactly
!>     once, each new cell's corners share exactly what it received);
!>   - a uniform velocity stays uniform (every fragment carries u);
!>   - no new extrema of velocity: every fragment carries an old corner's
!>     velocity (shifted by the mismatch of corner and reconstructed masses),
!>     every corner a mean of those;
!>   - as the grid stops moving each corner gets back its own velocity (the
!>     fragments of its own subcell land in it);
!>   - nodal masses always match the cells (Eq. 16 after each remap): a
!>     node next to a mixed cell gets its share of the cell's mean density,
!>     the density its pressure acts on. A node's mass from the material
!>     reconstruction instead (the air side of a cell holding explosive)
!>     left the air nodes of a TNT charge a hundredth of the mass the mixed
!>     cell's pressure pushes, and the grid tangled in the next step; nodal
!>     masses transported from the old ones drifted from the cells' through
!>     the Lagrangian phases and crushed the core of a Sedov blast.
!>
!> A tangled old cell, or one the new grid does not cover, hands out its
!> mean velocity instead. At each new node the difference between
!> the remapped kinetic energy and 1/2 m u^2 of the new nodal momentum
!> (what averaging velocities loses: never negative but for the shifts, by
!> convexity) is returned to the internal energy of the cells around the
!> node in proportion to their corner masses. Mass, momentum and total
!> energy are therefore conserved to round-off (velocity boundary
!> conditions applied after the remap, and open faces, aside: both are
!> reported).
!>
!> Unchanged cells. A new cell identical to its old cell is copied (its
!> material data too), and since the new cells tile the domain no other new
!> cell overlaps it; its corners pass on the old subcell masses and momenta,
!> and a node whose eight cells are all unchanged keeps its mass and velocity
!> bit for bit. Only the changed cells are intersected, which is what makes a
!> localized remap (LSSM) cheap.
!>
!> Open faces (inflow, outflow). The Lagrangian boundary at an open face may
!> have moved any number of cells from the face the new grid puts back. A
!> new cell that reaches past the old face's innermost point may lie partly
!> in the gap between them: if its fragments fall short it is intersected
!> again with a window that holds every old cell whose bounding box meets
!> its own (`remap_bins`), and what is then still missing is gap, filled
!> with the inflow state or, at an outflow face, with the state of the old
!> cell at the face on the same grid line. An old cell that reaches past the
!> new face's innermost point may give less than its volume: the rest has
!> left the domain. Everywhere else a new cell not covered, or an old cell
!> wholly outside the new grid, is still an error.
module remap_euler
  use base_kinds, only: wp, i8
  use base_errors, only: error_no_memory, error_t, error_set
  use base_strings, only: itoa, rtoa
  use base_timers, only: wall_seconds
  use mesh_grid, only: grid_t, grid_index_t, grid_index, block_gather, nodes_moved
  use mesh_geometry, only: hex_corner, hex_subcell_volumes, hex_edges, hex_volume, hex_trilinear, hex_natural, &
                           tet_det, cross
  use mesh_boundary, only: bc_t, bc_constrain_nodes, BC_INFLOW, BC_OUTFLOW
  use material_mixed, only: mixed_t, mixed_allocate
  use hydro_state, only: hydro_t
  use lagrange_centroids, only: plane_normals, planes_known, carried_cut
  use geometry_polyhedron, only: tet_planes, tet_sign, poly_t, poly_set_tet, poly_clip, poly_clip_axis, &
                              poly_first_moments, poly_copy, tet_clip_moments
  use geometry_mof, only: mof_reconstruct_nested, mof_material_pieces, mof_pieces_t, mof_pieces_moments
  use remap_gradient, only: remap_limited_gradients
  use geometry_cells, only: cell_moments
  use remap_bins, only: remap_bins_t, remap_bins_build, remap_bins_reach, remap_bins_cells, remap_boxes_reach, &
                        remap_box_meets
  use remap_swept, only: swept_edges
  use remap_lattice, only: lattice_t, lattice_build, lattice_tet
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use base_share, only: share_t
  use base_build, only: build_checks
  use base_sort, only: sort_order, sorted_place
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
  implicit none
  private
  public :: remap_params_t, remap_stats_t, remap_zone_t, remap_work_t, remap_work_ready, remap_euler_step, remap_zone_open, &
            deficit_patch_t, &
            remap_zone_block, remap_zone_beyond, remap_zone_reach_box, remap_zone_wants, remap_zone_far, &
            remap_stats_flows, remap_swept_blockers, remap_stats_add, remap_part_target, remap_part_folded, &
            remap_part_uniform, remap_hybrid_target, remap_change_rings

  !> Most materials in one cell the remap handles.
  integer, parameter :: max_mat = 16
  !> The index step to the cell across each face of `hex_faces`.
  integer, parameter :: face_step(3, 6) = reshape([-1, 0, 0, 1, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, -1, 0, 0, 1], [3, 6])
  !> An old region whose fragments fall short of its volume by more than
  !> this times its cell's volume (round-off of the sums is ~1e-15) is not
  !> covered by the new grid; a new cell whose fragments miss its volume by
  !> more than this times it has an overlap beyond its window, which is
  !> widened (a looser bound, 1e-9, once let an old cell two cells away
  !> keep 4e-10 of a new cell's volume: the old region was then rescaled
  !> and the Euler step missed momentum and energy by 3e-12 and 5e-12).
  real(wp), parameter :: uncovered_tol = 1.0e-12_wp
  !> the intersection's window (index steps) from which a new cell's old
  !> cells are taken from bins (`remap_bins_cells`) rather than visited
  !> all: 7^3 cells, most of which a new cell that reaches so far misses
  integer, parameter :: bins_reach_min = 3
  !> new cells per chunk of the lattice path (`lattice_release`)
  integer, parameter :: lattice_chunk = 2048
  !> the rings of cells around a cell with a residual kinetic energy
  !> deficit that pay it (`deficits_repair`)
  integer, parameter :: deficit_rings = 4
  !> How far (in cells) from the cells with a moved node a remap may change
  !> a cell: a node of theirs whose kinetic energy deficit the cells around
  !> it (one ring further) cannot pay moves it up to deficit_rings further
  !> (`deficits_repair`). Every other cell keeps its values.
  integer, parameter :: remap_change_rings = deficit_rings + 1

  !> Settings of the remap (deck group &rezone).
  type :: remap_params_t
    logical :: linear = .true.        !< limited linear reconstruction (else piecewise constant)
    integer :: mof_max_iter = 50      !< cap on MoF Gauss-Newton iterations per material
    real(wp) :: vf_min = 1.0e-9_wp    !< a material below this volume fraction is merged into the cell's largest
    !> the same for the cells the swept-face path remaps (`sliver_fraction`)
    real(wp) :: swept_vf_min = 1.0e-5_wp
    !> the swept-face path (`remap_new_cell`) can take a changed cell whose
    !> nodes moved at most this times its shortest old edge
    !> (`remap_swept_blockers`); 0: every changed cell is intersected
    real(wp) :: swept_max = 0.25_wp
    !> the swept-face path also through mixed cells (their MoF planes share
    !> what is swept from them; `remap_swept_blockers`)
    logical :: swept_mixed = .true.
    !> this step takes the swept-face path: every changed cell can
    !> (`remap_swept_blockers` is zero over the whole grid; the caller's to
    !> decide, as the count runs over every rank's cells)
    logical :: swept = .false.
    !> with swept: a step whose swept faces break a material's bounds is
    !> not remapped by intersection instead; the remap returns with
    !> stats%swept_unbounded > 0 and the state as it was (the caller may
    !> take the way in smaller parts)
    logical :: swept_only = .false.
    !> the new grid is a rectilinear lattice over the whole grid
    !> (`lattice_nodes`, the caller's to decide, as a decomposed run's
    !> windows must agree): a box cell's intersection fragments come from the
    !> old cells' parts on the lattice, each old half clipped once
    !> (`remap_lattice`), not once per new cell that it reaches
    logical :: lattice = .false.
  end type remap_params_t

  !> What one remap did.
  type :: remap_stats_t
    integer :: cells_remapped = 0     !< changed new cells, intersected with the old grid
    integer :: cells_swept = 0        !< of them, those remapped by their faces' swept regions
    !> cells whose swept-face results broke a material's bounds (positive
    !> mass and volume, density and specific energy within those of its old
    !> neighbours): the step was remapped by intersection instead (a
    !> window's remap leaves that to its caller)
    integer :: swept_unbounded = 0
    !> changed cells that kept the step off the swept-face path (set by the
    !> caller: `remap_swept_blockers` over the whole grid)
    integer :: swept_blockers = 0
    integer :: cells_copied = 0       !< unchanged cells, copied
    integer :: swept_parts = 1        !< the parts of the way the step was remapped in (`remap_stats_add`)
    integer :: swept_splits = 0       !< of them, parts split in two because their swept faces broke a bound (the caller's)
    !> of them, parts with no split left that some cells could not take by
    !> swept faces (too far, or a broken bound): remapped by swept faces but
    !> around those cells, then there by intersection (the caller's)
    integer :: swept_rescued = 0
    !> the step was hybrid: by swept faces where the cells could, then by
    !> intersection around those that could not (the caller's)
    logical :: hybrid = .false.
    integer :: reach = 0              !< widest index window that was needed
    integer :: mof_cells = 0          !< MoF reconstructions (old mixed cells that moved)
    !> of them, cut by the planes the Lagrangian steps carried (`mof_cell`:
    !> no search, no iterations, no centroid error counted)
    integer :: mof_carried = 0
    integer :: mof_iterations = 0     !< their Gauss-Newton iterations, all materials
    integer :: mof_not_converged = 0  !< reconstructions that hit the cap or failed
    real(wp) :: mof_err_max = 0.0_wp  !< largest material centroid error / cell size
    integer :: slivers_merged = 0     !< materials below vf_min merged into another
    real(wp) :: volume_defect = 0.0_wp    !< largest |sum of fragments - V|/V of a new cell
    !> largest |volume given away - V_region|/V_cell of an old region:
    !> part of an old cell not covered by the new grid
    real(wp) :: given_defect = 0.0_wp
    integer :: regions_rescaled = 0   !< old regions not covered entirely, remapped scaled
    real(wp) :: ke_to_internal = 0.0_wp   !< kinetic energy returned to internal energy
    !> cells whose nodes' kinetic energy deficits the cells around them could
    !> not pay, the deficit moved to the nearest cells with energy to give,
    !> and what was left of it, taken by mass (internal energy units)
    integer :: cells_deficit = 0
    real(wp) :: deficit_moved = 0.0_wp, deficit_by_mass = 0.0_wp
    real(wp) :: momentum_constrained(3) = 0.0_wp  !< momentum the velocity conditions removed
    ! through open faces (inflow, outflow): what came in and went out
    real(wp) :: mass_in = 0.0_wp, mass_out = 0.0_wp
    real(wp) :: momentum_in(3) = 0.0_wp, momentum_out(3) = 0.0_wp
    real(wp) :: energy_in = 0.0_wp, energy_out = 0.0_wp
    !> the same, exact (`base_xsum`; mass, momentum, energy in, then out):
    !> a window's callers add them over the ranks (`remap_stats_flows`)
    type(xsum_t) :: flow(10)
    !> what the remap changed in the totals of mass, momentum, internal and
    !> kinetic energy (`hydro_totals`' sums), exact (`base_xsum`): the cells
    !> and nodes it wrote, summed before and after (change_known; a window's
    !> remap, over its block's owned cells and counted nodes: its caller adds
    !> them over the blocks). So the conservation check costs what the
    !> remap touched, not the grid.
    type(xsum_t) :: change(6)
    logical :: change_known = .false.
    !> with change_known: the scales of the conservation check, what the
    !> remap wrote, before it (over its cells and nodes: the mass, the total
    !> energy (its magnitude), the sum of |m u|): a check relative to what
    !> was remapped, at a cost that follows it, not the grid
    real(wp) :: scale(3) = 0.0_wp
    real(wp) :: t_prepare = 0.0_wp, t_intersect = 0.0_wp, t_assemble = 0.0_wp  !< wall seconds
    integer :: parts = 1   !< ranks that shared the intersections and MoF (`base_share`)
    !> with a zone: computed new cells the old cells within reach_max did
    !> not cover (the remap then stops), and owned old regions the computed
    !> new cells did not cover (neither is an error there: the caller remaps
    !> the whole grid instead)
    integer :: cells_short = 0, regions_uncovered = 0
  end type remap_stats_t

  !> A remap of a window of the grid: one rank's block widened by the
  !> cells around it (a box of the whole grid; `driver_whole`), of which
  !> only some cells come out right. The new cells `compute` are
  !> intersected (the others are copied as if unchanged); `own` (cells) and
  !> `own_node` (nodes) are those the stats count and the checks look at,
  !> each cell and node of the whole grid in one rank's zone only. A new
  !> cell is searched within reach_max index steps at most. What the whole
  !> grid's remap does beyond the window is not done but counted
  !> (remap_stats_t's cells_short, regions_uncovered and cells_deficit:
  !> the kinetic energy deficits taken from cells further away, in cell
  !> order over the whole grid): the caller checks that none occurred in
  !> any zone, else the results of this remap are not those of the whole
  !> grid's. With compute = own widened by max(w + 1, reach_max) layers and
  !> the window = compute widened by reach_max + 2 (the old cells within
  !> reach of a computed cell, and their gradients' stencils), the results
  !> in own and the w layers around it are bit for bit those of the whole
  !> grid's remap (a node needs every cell around it computed, a cell its
  !> nodes; an owned old region every new cell within reach).
  !>
  !> With open faces (`remap_zone_open`) the zone also holds what the gap
  !> search needs beyond the window: each open face's innermost points (old
  !> and new grids, reduced over the blocks by the caller), bins over the
  !> window's moved old cells, and far: the moved old cells outside the
  !> window that reach past an open face of the new grid (`open_face_cells`'
  !> beyond) and whose boxes meet the computed cells' (`remap_zone_far`).
  !> A computed gap cell whose old cells lie beyond reach_max, or whose
  !> outflow face lies beyond the window, counts as cells_short. Any other
  !> old cell outside the window that meets a computed cell lies further
  !> than reach_max from it, and its own block's remap finds it: it gives
  !> less than its volume (regions_uncovered) or, if the cell is computed
  !> there, it is in that window's bins (cells_short).
  !> Cells of a kinetic energy deficits' repair (`deficits_repair`) by
  !> their whole-grid numbers (id, increasing), each with its residual
  !> deficit and its energies before the repair: v(1:4, q) = rdef, ie, iav,
  !> avail (`assemble`).
  type :: deficit_patch_t
    integer, allocatable :: id(:)
    real(wp), allocatable :: v(:, :)
  end type deficit_patch_t

  type :: remap_zone_t
    logical, allocatable :: compute(:), own(:), own_node(:)
    integer :: reach_max = 2
    logical :: open = .false.               !< set by `remap_zone_open`
    real(wp) :: bold(6) = 0.0_wp, bnew(6) = 0.0_wp
    type(remap_bins_t) :: bins
    !> the far cells: whole-grid indices (3, n) and boxes (lo, hi: 6, n)
    integer, allocatable :: far_ijk(:, :)
    real(wp), allocatable :: far_box(:, :)
    !> kinetic energy deficits repaired over the windows, in three remaps
    !> of the same step (`assemble`): the first finds the cells with a
    !> residual deficit, each window its own cells' (deficit_mine, their
    !> whole-grid numbers); given them all (deficit_cells, every window's,
    !> increasing), the second gives the energies before the repair of its
    !> own cells within the repair's rings of them (donors); given them all
    !> (patch, increasing), the third repairs every deficit as the whole
    !> grid does, over the patch, and takes its cells' results
    integer, allocatable :: deficit_mine(:), deficit_cells(:)
    type(deficit_patch_t) :: donors, patch
  end type remap_zone_t

  !> The old grid's cells as the remap needs them.
  type :: old_t
    logical, allocatable :: changed(:)          !< cell moved (ncell)
    !> cells the remap reads: the moved ones, their neighbours, the cells
    !> open-face gaps take their state from (ncell)
    logical, allocatable :: near(:)
    !> work: all false but while a procedure marks nodes in it (nnode)
    logical, allocatable :: node(:)
    !> the changed cells, the near cells and the changed cells' nodes as
    !> lists in increasing order: the loops run over these, so that an Euler
    !> step that moves few cells costs little whatever the grid (entries of
    !> the per-cell and per-node arrays elsewhere are not set, and not read;
    !> a debug build fills them with NaN)
    integer, allocatable :: lchanged(:), lnear(:), lnode(:)
    !> the changed cells are remapped through the regions their subcells'
    !> faces sweep, not by intersection (`remap_params_t`)
    logical :: swept = .false.
    logical :: open(6) = .false.   !< the grid's faces that are inflow or outflow faces
    !> the cell's mean velocity v_c (3, ncell), carried with the mass
    real(wp), allocatable :: ucell(:, :)
    !> per moved cell: the velocity ushift(3, ncell) added to its corners'
    !> and the kinetic energy per unit mass kshift(ncell) added to theirs, so
    !> that fragments carrying them with their mass hand out exactly the
    !> cell's momentum and kinetic energy (`subcell_shifts`)
    real(wp), allocatable :: ushift(:, :), kshift(:)
    !> the velocity's linear part about each node (the second order of the
    !> velocity remap, `velocity_gradients`): its limited gradient
    !> gu(3, 3, nnode) (gu(:, i, n) that of component i) about the point
    !> xdual(3, nnode); and per corner of a moved cell its subcell's volume
    !> and first moment weighted by the regions' smallest densities,
    !> wv(8, :) and ws(3, 8, :), whose sums over a node's corners make xdual
    !> (entry ic: the changed cell lchanged(ic), the arrays sized for the
    !> changed cells, not the grid: `changed_arrays`)
    real(wp), allocatable :: gu(:, :, :), xdual(:, :), wv(:, :), ws(:, :, :)
    !> per corner of a moved pure cell that is not tangled: its subcell's
    !> volume and first moment about the cell's centre, sub(4, 8, :), entry
    !> ic as wv's (`subcell_shifts`; what the swept-face path keeps of the
    !> old cell)
    real(wp), allocatable :: sub(:, :, :)
    !> cells whose subcells cannot carry their own velocity (tangled, or not
    !> covered by the new grid): their fragments carry only the mean velocity,
    !> and kinetic energy kcell per unit mass about it
    logical, allocatable :: uniform(:)
    real(wp), allocatable :: kcell(:)
    !> Kinetic energies are counted about a local velocity, never as the
    !> difference of two totals in the lab frame: such a difference carries
    !> round-off of eps |u|^2 per unit mass, which a material whose internal
    !> energy is far below its kinetic energy (a body 1e6 denser than the
    !> gas around it at the same pressure, in a flow: e/|u|^2 ~ 1e-6) takes
    !> as a relative error of eps |u|^2/e per Euler step. Counted about a
    !> local velocity, a uniform flow's differences vanish to eps^2 and a
    !> fluid at rest's exactly. uref(3, ncell): per new cell, the mean of the
    !> old velocities at its nodes, about which its fragments' kinetic
    !> energy is summed (pcell(4)); the old cell's shifts and kcell are about
    !> its mean velocity, a node's returned energy about its new velocity.
    real(wp), allocatable :: uref(:, :)
    ! one region per pure cell (index c) or per mixed slot (index ncell + s)
    real(wp), allocatable :: rho(:), e(:)       !< mean density (mass / region volume), energy
    real(wp), allocatable :: xr(:, :)           !< region centroid (3, ncell + nslot)
    real(wp), allocatable :: grho(:, :), ge(:, :)   !< gradients (3, ncell + nslot)
    real(wp), allocatable :: wreg(:)            !< smallest density of the region's reconstruction (`region_floor`)
    real(wp), allocatable :: pn(:, :), pd(:)    !< MoF plane of each slot (n.x <= d)
    real(wp), allocatable :: vreg(:)            !< region volume (ncell + nslot)
    !> volume given away (ncell + nslot), in units of 2^-50 of the region's
    !> cell volume (gunit): integer sums are exact, so the result does not
    !> depend on the order the threads add in
    integer(i8), allocatable :: given(:)
    real(wp), allocatable :: gunit(:)
    real(wp), allocatable :: scale(:)           !< factor on what a region gives (1, or > 1 if not covered)
    !> the swept path's budgets of the mixed cells (`swept_budgets`), per
    !> slot (nslot): the factor on what the region gives through the cell's
    !> faces (1, or < 1), the share it takes of the volume held back
    !> and the shift of its parts' centroids (3, nslot) that makes a region
    !> given away whole give its first moment too
    real(wp), allocatable :: sfac(:), sroom(:), sshift(:, :)
    !> and what `swept_budgets` finds on the way, so that each mixed cell's
    !> regions are clipped once per Euler step, not once by each cell that
    !> books them: per slot the volume and first moment its region keeps in
    !> each old subcell, skv(8, nslot) and skm(3, 8, nslot), and its parts
    !> (`swept_split`) of the regions the cell's 48 face triangles sweep out
    !> of it, sov(48, nslot) and som(3, 48, nslot) (negative: outgoing),
    !> all about the new cell's centre so(3, nslot); sout(nslot): bit i - 1
    !> set where triangle i sweeps out (the same for the cell's slots)
    real(wp), allocatable :: skv(:, :), skm(:, :, :), sov(:, :), som(:, :, :), so(:, :)
    integer(i8), allocatable :: sout(:)
    !> face triangle i of a cell is triangle twin(i) of the cell across its
    !> face (`twin_triangles`; 0: not yet set)
    integer :: twin(48) = 0
    !> `material_gradients`' work: per cell a material's density and energy,
    !> the point they are at, whether it holds the material, whether its
    !> gradient is needed, and the gradients
    real(wp), allocatable :: gq(:, :), gpos(:, :), ggrad(:, :, :)
    logical, allocatable :: ghas(:), gneed(:)
    !> the swept path's shared faces (`swept_low_faces`): per changed cell
    !> c, entry fslot(c) (valid where fstamp(c) == fgen, this remap's), the
    !> regions its 24 triangles on its three low faces (xi-, eta-, zeta-;
    !> faces 1, 3, 5, eight triangles each in order) sweep, fv(24, e) and
    !> fm(24, 3, e), about its new centre fo(:, e): each face's triangles
    !> swept once, for the cell and for its neighbour across the face
    integer, allocatable :: fslot(:), fstamp(:)
    integer :: fgen = 0
    real(wp), allocatable :: fv(:, :), fm(:, :, :), fo(:, :)
  end type old_t

  !> The remap's work arrays, kept from one call to the next by its caller
  !> (an Euler phase): the old grid's arrays (sized on first use, again for
  !> a grid of another size, and the regions' when the mixed cells change)
  !> and its marks of cells and nodes, all false between calls (the sets a
  !> remap works on start empty without a pass over the grid, and are
  !> emptied through their lists). So an Euler step that changes few cells
  !> of a large grid costs what they do: no pass over the grid, and no
  !> fresh pages of whole-grid arrays to fault in. The new cells' sums
  !> (`remap_euler_step`'s avol ... gaps, written before they are read for
  !> the cells a remap computes) are kept likewise.
  type :: remap_work_t
    type(old_t) :: old
    real(wp), allocatable :: avol(:, :), amom(:, :, :), amass(:, :), aie(:, :), cmass(:, :), cmom(:, :, :), &
                             cke(:, :), cland(:, :), cdef(:, :), pcell(:, :), vcell(:)
    integer, allocatable :: reach(:), gaps(:)
    logical, allocatable :: redo(:)
  end type remap_work_t

  !> The parts of one old cell on the lattice (`remap_lattice`): entry e
  !> is k(1, e) the new cell it lands in, k(2, e) - 1 = octant - 1 +
  !> 8 (corner - 1) + 64 (s - s0) (the new cell's corner; the old cell's
  !> corner whose subcell it comes from; its region, slot s of s0..s1 or
  !> 0 for a pure cell: `region_slots`), r(:, e) its signed volume and
  !> first moment about oo, the old cell's centre.
  type :: lattice_cell_t
    integer, allocatable :: k(:, :)
    real(wp), allocatable :: r(:, :)
    real(wp) :: oo(3) = 0.0_wp
  end type lattice_cell_t

  !> The lattice path of one remap: the lattice, and the changed old cells'
  !> parts on it (cells(pos(c)) for old cell c), computed where first needed
  !> (`lattice_prepare`).
  type :: lattice_old_t
    type(lattice_t) :: lt
    integer, allocatable :: pos(:), state(:)
    type(lattice_cell_t), allocatable :: cells(:)
    integer :: released = 0   !< the parts of cells(1:released) are dropped (`lattice_release`)
  end type lattice_old_t

  !> The 48 halves of `half_tets` among the 27 points of the split: half
  !> 2t-1 of tetrahedron t = 4(f-1)+m (face f, its m-th edge from node
  !> a = hex_faces(m, f) to b = hex_faces(m mod 4 + 1, f), edge number e of
  !> `hex_edges`' order) is (centre 1, face centre 1+f, node 7+a, midpoint
  !> 15+e) at corner a, half 2t is (1, 1+f, 15+e, 7+b) at corner b
  !> (constants of the split, written out rather than rebuilt at each call;
  !> every remap test of volumes, moments and subcell masses rests on them)
  integer, parameter :: half_hv(4, 48) = reshape([ &
       1,  2,  8, 24,  1,  2, 24, 12,  1,  2, 12, 23,  1,  2, 23, 14, &
       1,  2, 14, 26,  1,  2, 26, 10,  1,  2, 10, 20,  1,  2, 20,  8, &
       1,  3,  9, 22,  1,  3, 22, 11,  1,  3, 11, 25,  1,  3, 25, 15, &
       1,  3, 15, 21,  1,  3, 21, 13,  1,  3, 13, 27,  1,  3, 27,  9, &
       1,  4,  8, 16,  1,  4, 16,  9,  1,  4,  9, 27,  1,  4, 27, 13, &
       1,  4, 13, 18,  1,  4, 18, 12,  1,  4, 12, 24,  1,  4, 24,  8, &
       1,  5, 10, 26,  1,  5, 26, 14,  1,  5, 14, 17,  1,  5, 17, 15, &
       1,  5, 15, 25,  1,  5, 25, 11,  1,  5, 11, 19,  1,  5, 19, 10, &
       1,  6,  8, 20,  1,  6, 20, 10,  1,  6, 10, 19,  1,  6, 19, 11, &
       1,  6, 11, 22,  1,  6, 22,  9,  1,  6,  9, 16,  1,  6, 16,  8, &
       1,  7, 12, 18,  1,  7, 18, 13,  1,  7, 13, 21,  1,  7, 21, 15, &
       1,  7, 15, 17,  1,  7, 17, 14,  1,  7, 14, 23,  1,  7, 23, 12], [4, 48])
  !> The corner of each half (`half_hv`).
  integer, parameter :: half_corner(48) = [ &
       1,  5,  5,  7,  7,  3,  3,  1,  2,  4,  4,  8,  8,  6,  6,  2, &
       1,  2,  2,  6,  6,  5,  5,  1,  3,  7,  7,  8,  8,  4,  4,  3, &
       1,  3,  3,  4,  4,  2,  2,  1,  5,  6,  6,  8,  8,  7,  7,  5]
  !> The 72 triangles the swept-face path sweeps per cell (`swept_fluxes`),
  !> as columns of the 27 points of the split: the 48 on the cell's faces,
  !> (face centre, node, midpoint) or (face centre, midpoint, node) of half
  !> i, then for each tetrahedron t the one between its two corners,
  !> (half_hv(4, 2t-1), 1, half_hv(2, 2t-1)) = (midpoint, centre, face
  !> centre), its normal from corner a to b
  integer, parameter :: swept_tri(3, 72) = reshape([half_hv(2:4, :), &
    24,  1,  2, 23,  1,  2, 26,  1,  2, 20,  1,  2, 22,  1,  3, 25,  1,  3, &
    21,  1,  3, 27,  1,  3, 16,  1,  4, 27,  1,  4, 18,  1,  4, 24,  1,  4, &
    26,  1,  5, 17,  1,  5, 25,  1,  5, 19,  1,  5, 20,  1,  6, 19,  1,  6, &
    22,  1,  6, 16,  1,  6, 18,  1,  7, 21,  1,  7, 17,  1,  7, 23,  1,  7], [3, 72])
  !> For each tetrahedron t of the 24-split, the slot of `swept_fluxes`'
  !> sums that the region its inner triangle sweeps from corner a =
  !> half_corner(2t-1) to its neighbour b = half_corner(2t) comes from: 1 +
  !> the direction of the edge ab (`edge_dir`; written out, as the halves'
  !> constants are)
  integer, parameter :: tet_slot(24) = [4, 3, 4, 3, 3, 4, 3, 4, 2, 4, 2, 4, &
                                         4, 2, 4, 2, 3, 2, 3, 2, 2, 3, 2, 3]

contains

  !> Remaps the state from the grid g%x to the grid xnew (same block) and
  !> moves the grid there. h and mx are replaced by the remapped state
  !> (mass, volume, density, specific internal energy, material of each
  !> cell, mixed cells, nodal mass and velocity); pressures and sound speeds
  !> are left for the caller to evaluate. bc's kinematic conditions are
  !> applied to the new velocities. nmat is the number of materials.
  subroutine remap_euler_step(g, h, mx, nmat, bc, xnew, par, stats, err, share, zone, moved, written, work, broke)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    type(mixed_t), intent(inout) :: mx
    integer, intent(in) :: nmat
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: xnew(:, :)
    type(remap_params_t), intent(in) :: par
    type(remap_stats_t), intent(out) :: stats
    type(error_t), allocatable, intent(inout) :: err
    !> the ranks sharing the intersections and MoF of the changed cells, when every
    !> rank holds the whole grid (`base_share`; absent: this process does all)
    class(share_t), intent(in), optional :: share
    !> a window's remap (the module's `remap_zone_t`; absent: the whole
    !> grid); its deficit_mine and donors set here
    type(remap_zone_t), intent(inout), optional :: zone
    !> the cells that move from g%x to xnew, in increasing order, if the
    !> caller has them (`remap_swept_blockers`' moved; absent: found here)
    integer, intent(in), optional :: moved(:)
    !> a whole grid's remap: the cells whose state it may have written, in
    !> increasing order (the rest are as they were)
    integer, allocatable, intent(out), optional :: written(:)
    !> the caller's work arrays (absent: this call's, its marks set over
    !> the grid)
    type(remap_work_t), intent(inout), optional, target :: work
    !> with par%swept_only, when the swept faces broke a material's bounds
    !> (nothing remapped): the new cells that broke them, in increasing
    !> order (else empty)
    integer, allocatable, intent(out), optional :: broke(:)
    type(old_t), target :: own_old
    type(old_t), pointer :: old
    type(lattice_old_t) :: lat
    ! the changed old cells binned, once a window reaches bins_reach_min
    ! (`intersect_list`)
    type(remap_bins_t) :: wide
    real(wp), allocatable :: avol(:, :), amom(:, :, :), amass(:, :), aie(:, :), &
                             cmass(:, :), cmom(:, :, :), cke(:, :), cland(:, :), cdef(:, :), &
                             pcell(:, :), vcell(:)
    integer, allocatable :: todo(:), reach(:), gap_face(:), gap_cell(:), gaps(:), done(:)
    logical, allocatable :: redo(:)
    integer(i8), allocatable :: before(:)
    real(wp), allocatable :: buf(:, :)
    logical :: sharing
    real(wp) :: w0, vnew, defect, xn(3, 8), given, bold(6), bnew(6)
    integer :: ncell, c, co, r, rmax, i, nbad, ngap, stat, ci, cj, ck, ir
    integer, allocatable :: dmine(:)
    type(deficit_patch_t) :: dpatch
    logical :: any_open, windowed
    logical, allocatable :: own(:), own_node(:)
    integer, allocatable :: wcells(:), wnodes(:)
    character(len=200) :: msg

    old => own_old
    if (present(broke)) broke = [integer ::]
    if (present(work)) then
      call marks_ready(work%old, g%ncell, g%nnode, stat)
      if (stat /= 0) then
        call error_set(err, 'remap_euler_step', error_no_memory('the cell marks'))
        return
      end if
      old => work%old
    end if
    ! (every way out of the step goes through the end of this block, where
    ! the marks are emptied)
    main: block
      ncell = g%ncell
      windowed = present(zone)
      if (windowed) then
        ! (this remap's, none before `assemble` sets them)
        if (allocated(zone%deficit_mine)) deallocate(zone%deficit_mine)
        if (allocated(zone%donors%id)) deallocate(zone%donors%id, zone%donors%v)
      end if
      if (nmat > max_mat) then
        call error_set(err, 'remap_euler_step', 'at most '//itoa(max_mat)//' materials')
        exit main
      end if
      w0 = wall_seconds()
      stat = 0
      if (present(work)) call take_sums()
      if (.not. allocated(avol)) allocate(avol(nmat, ncell), amom(3, nmat, ncell), amass(nmat, ncell), &
               aie(nmat, ncell), cmass(8, ncell), cmom(3, 8, ncell), cke(8, ncell), cland(8, ncell), cdef(8, ncell), &
               pcell(4, ncell), vcell(ncell), reach(ncell), &
               redo(ncell), gaps(ncell), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'remap_euler_step', error_no_memory('work arrays'))
        exit main
      end if
      if (build_checks) then
        ! (set only where read: the changed cells and those around them)
        cmass = ieee_value(1.0_wp, ieee_quiet_nan)
        cmom = cmass(1, 1)
        cke = cmass(1, 1)
        pcell = cmass(1, 1)
      end if
      any_open = any(bc%kind == BC_INFLOW .or. bc%kind == BC_OUTFLOW)
      ! (the gaps at open faces: none without them, and nothing to mark)
      allocate(gap_face(merge(ncell, 0, any_open)), gap_cell(merge(ncell, 0, any_open)), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'remap_euler_step', error_no_memory('the open faces'' gaps'))
        exit main
      end if
      if (windowed) then
        if (any_open .and. .not. zone%open) then
          call error_set(err, 'remap_euler_step', 'a window''s remap with open faces needs remap_zone_open')
          exit main
        end if
        own = zone%own
        own_node = zone%own_node
        bold = zone%bold
        bnew = zone%bnew
      else if (any_open) then
        ! (a whole grid's remap owns every cell: the masks only for open_faces)
        allocate(own(ncell), own_node(g%nnode), stat=stat)
        if (stat /= 0) then
          call error_set(err, 'remap_euler_step', error_no_memory('the cell masks'))
          exit main
        end if
        own = .true.
        own_node = .true.
        call open_face_bounds(g, bc, g%x, xnew, bold, bnew)
      end if
      ! (only a changed cell can have a gap)
      if (any_open .and. present(moved)) then
        call open_face_cells(g, bc, xnew, bold, gap_face, gap_cell, moved)
      else if (any_open) then
        call open_face_cells(g, bc, xnew, bold, gap_face, gap_cell)
      end if
      if (windowed) then
        call prepare_old(g, h, mx, nmat, xnew, par, gap_face, gap_cell, old, stats, err, share, own)
      else
        call prepare_old(g, h, mx, nmat, xnew, par, gap_face, gap_cell, old, stats, err, share, moved=moved)
      end if
      if (allocated(err)) exit main
      ! (less the totals of what the remap may write; added back after it;
      ! a window's, of its block's owned cells and counted nodes: its caller
      ! adds them over the blocks)
      if (windowed) then
        wcells = pack(old%lnear, zone%own(old%lnear))
        wnodes = pack(old%lnode, zone%own_node(old%lnode))
      else
        wcells = old%lnear
        wnodes = old%lnode
      end if
      call totals_of(h, wcells, wnodes, -1.0_wp, stats%change)
      stats%scale = magnitudes(h, wcells, wnodes)
      sharing = .false.
      if (present(share)) sharing = share%nparts > 1
      if (sharing) stats%parts = share%nparts
      if (sharing) then
        ! a changed cell's results, gathered from the rank that computed them
        allocate(before(size(old%given)), buf(6*nmat + 44, count(old%changed)), stat=stat, errmsg=msg)
        if (stat /= 0) then
          call error_set(err, 'remap_euler_step', error_no_memory('the shared work''s buffers'))
          exit main
        end if
      end if
      stats%t_prepare = wall_seconds() - w0

      ! intersect every changed new cell, widening the window where the
      ! fragments do not add up to the cell (a node moved further than a cell)
      w0 = wall_seconds()
      todo = old%lchanged
      stats%cells_remapped = size(old%lchanged)
      if (windowed) stats%cells_remapped = count(old%changed .and. own)
      old%swept = par%swept
      old%open = bc%kind == BC_INFLOW .or. bc%kind == BC_OUTFLOW
      if (old%swept .and. mx%n > 0) call swept_budgets(g, h, mx, old, xnew)
      if (old%swept) call swept_low_faces(g, old, xnew)
      if (old%swept) stats%cells_swept = stats%cells_remapped
      stats%cells_copied = ncell - stats%cells_remapped
      if (windowed) stats%cells_copied = count(own) - stats%cells_remapped
      ! the whole block: no overlap can lie further
      rmax = max(g%chi(1) - g%clo(1), g%chi(2) - g%clo(2), g%chi(3) - g%clo(3), 1)
      if (windowed) then
        todo = pack([(c, c = 1, ncell)], old%changed .and. zone%compute)
        rmax = min(rmax, zone%reach_max)
      end if
      done = todo
      ! (a second pass, by intersection, where the swept faces broke a bound)
      passes: do
      ! (the lattice's parts serve the intersections only)
      if (par%lattice .and. .not. old%swept .and. .not. lat%lt%on) then
        call lattice_start(g, old, xnew, lat, err)
        if (allocated(err)) exit main
      end if
      todo = done
      reach(old%lchanged) = 0
      r = 1
      ngap = 0
      stats%volume_defect = 0.0_wp
      do while (size(todo) > 0)
        call intersect_cells(todo, r, 1.0_wp)
        nbad = 0
        do i = 1, size(todo)
          c = todo(i)
          call g%gather(c, xnew, xn)
          vnew = hex_volume(xn)
          ! (the new cell's volume, for `assemble`)
          vcell(c) = vnew
          defect = abs(sum(avol(:, c)) - vnew)/abs(vnew)
          if (gap_of(c) > 0 .and. defect > uncovered_tol .and. old%swept) then
            ! (the swept faces leave the gap itself to `open_faces`)
            reach(c) = r
            if (gap_cell(c) == 0) stats%cells_short = stats%cells_short + 1
          else if (gap_of(c) > 0 .and. defect > uncovered_tol) then
            ! maybe in the gap between an open face and the old grid: no
            ! window makes the fragments add up there; widened below to
            ! every old cell that can meet it
            ngap = ngap + 1
            gaps(ngap) = c
            reach(c) = r
            ! (an outflow face beyond the window: its state is not here)
            if (gap_cell(c) == 0) stats%cells_short = stats%cells_short + 1
          else if (defect > uncovered_tol .and. r < rmax) then
            nbad = nbad + 1
            todo(nbad) = c
          else if (windowed) then
            ! (beyond the window's reach: the caller's to redo; any computed
            ! cell, whose results would be wrong, and whose owner finds it too)
            if (defect > uncovered_tol) stats%cells_short = stats%cells_short + 1
            if (own(c) .and. .not. defect > uncovered_tol) stats%volume_defect = max(stats%volume_defect, defect)
            if (own(c)) reach(c) = r
          else
            stats%volume_defect = max(stats%volume_defect, defect)
            reach(c) = r
          end if
        end do
        todo = todo(1:nbad)
        if (nbad > 0) then
          ! take back what these cells gave, then widen their window (doubling
          ! it: however far the nodes moved, a few passes find the overlaps)
          call intersect_cells(todo, r, -1.0_wp)
          r = min(2*r, rmax)
        end if
      end do
      if (ngap > 0) call widen_gaps(gaps(1:ngap), err)
      if (allocated(err)) exit main
      if (.not. old%swept) exit passes
      stats%swept_unbounded = swept_unbounded(g, h, mx, old, done, avol, amass, aie, sliver_fraction(par, old%swept), &
                                              redo)
      if (stats%swept_unbounded == 0) exit passes
      if (par%swept_only .and. present(broke)) broke = pack(done, redo(done))
      ! (a window's: the caller remaps the whole grid instead, where this
      ! pass decides for every cell alike)
      if (windowed .or. par%swept_only) exit main
      old%swept = .false.
      stats%cells_swept = 0
      old%given = 0_i8
      end do passes
      stats%reach = 0
      do i = 1, size(old%lchanged)
        if (owns(old%lchanged(i))) stats%reach = max(stats%reach, reach(old%lchanged(i)))
      end do
      ! (nothing more to do in a window that cannot hold the step)
      if (stats%cells_short > 0) exit main
      if (stats%volume_defect > 1.0e-9_wp) then
        call error_set(err, 'remap_euler_step', 'the old grid does not cover the new one (volume defect '// &
                       rtoa(stats%volume_defect)//') even searching the whole block: boundary nodes left the '// &
                       'boundary, or the old grid is tangled')
        exit main
      end if

      ! old regions the new grid does not cover entirely (a tangled old cell
      ! poking out of the domain): remapped again, piecewise constant and
      ! scaled, so that all of their mass, energy and momentum still goes
      ! to the new cells they do overlap
      do i = 1, size(old%lnear) + mx%nslot
        c = region_at(i)
        if (old%vreg(c) <= 0.0_wp) cycle
        ! what lies beyond an open face has left the domain
        co = c
        if (c > ncell) co = mx%cell(slot_cell(mx, c - ncell))
        if (.not. owns(co)) cycle
        ! (an old cell that reaches past an open face's innermost point
        ! of the new grid may lose what lies outside)
        if (any_open) then
          call g%gather(co, g%x, xn)
          if (reaches_out(old%open, xn, bnew)) cycle
        end if
        ! relative to the cell: a sliver region's own round-off can be larger
        given = real(old%given(c), wp)*old%gunit(c)
        if (abs(given - old%vreg(c)) <= uncovered_tol*h%vol(co)) then
          stats%given_defect = max(stats%given_defect, abs(given - old%vreg(c))/h%vol(co))
          cycle
        end if
        if (windowed) then
          stats%regions_uncovered = stats%regions_uncovered + 1
          cycle
        end if
        stats%given_defect = max(stats%given_defect, abs(given - old%vreg(c))/h%vol(co))
        if (.not. given > 0.0_wp) then
          call g%cell_ijk(co, ci, cj, ck)
          call error_set(err, 'remap_euler_step', 'old region '//itoa(c)//' (cell ('//itoa(ci)//','//itoa(cj)// &
                         ','//itoa(ck)//'), volume '//rtoa(old%vreg(c))//' of '//rtoa(h%vol(co))// &
                         ') lies outside the new grid')
          exit main
        end if
        stats%regions_rescaled = stats%regions_rescaled + 1
        old%uniform(co) = .true.
        old%scale(c) = old%vreg(c)/given
        old%grho(:, c) = 0.0_wp
        old%ge(:, c) = 0.0_wp
      end do
      if (stats%regions_rescaled > 0) then
        redo = .false.
        do ir = 1, size(old%lnear) + mx%nslot
          c = region_at(ir)
          if (abs(old%scale(c) - 1.0_wp) > 0.0_wp) then
            co = c
            if (c > ncell) co = mx%cell(slot_cell(mx, c - ncell))
            ! its nodes lose the velocity's linear part (it would no longer
            ! add up to zero over them), so every new cell that a fragment
            ! of a cell next to it may have reached is done again
            do i = 1, 8
              old%gu(:, :, g%node0(co) + g%corner_offset(i)) = 0.0_wp
            end do
            call mark_window(co, stats%reach + 1)
          end if
        end do
        ! (each cell again at the reach its first intersection found
        ! complete: a wider window can add pieces of a tangled old cell
        ! whose signed volumes cancel in the new cell, but whose regions
        ! then give more, or less, than the volumes their scales were set
        ! from: mass made or lost, 1.8e-5 of an Euler step of the Saltzman
        ! piston with LSSM)
        todo = pack([(c, c = 1, ncell)], redo .and. old%changed)
        do while (size(todo) > 0)
          r = redo_reach(todo(1))
          call intersect_cells(pack(todo, [(redo_reach(todo(i)) == r, i = 1, size(todo))]), r, 0.0_wp)
          todo = pack(todo, [(redo_reach(todo(i)) /= r, i = 1, size(todo))])
        end do
      end if
      stats%t_intersect = wall_seconds() - w0
      ! (a window's cells not computed are copied: their results are not used)
      if (windowed) then
        old%changed = old%changed .and. zone%compute
        call true_list(old%changed, old%lchanged, err)
        if (allocated(err)) exit main
        call node_list(g, old%lchanged, old%node, old%lnode, err)
        if (allocated(err)) exit main
      end if
      call unchanged_corners(g, h, old, cmass, cmom, cke, pcell)
      if (any_open) call open_faces(g, h, mx, bc, old, xnew, gap_face, gap_cell, own, own_node, avol, amom, amass, &
                                    aie, cdef, cmom, cke, cland, pcell, stats)

      w0 = wall_seconds()
      if (windowed) then
        call assemble(g, h, mx, nmat, bc, old, xnew, par, avol, amom, amass, aie, cmass, cmom, cke, cland, pcell, &
                      vcell, stats, err, own, zone%own_node, deficit_cells=zone%deficit_cells, patch=zone%patch, &
                      deficit_mine=dmine, donors=dpatch)
        call move_alloc(dmine, zone%deficit_mine)
        call move_alloc(dpatch%id, zone%donors%id)
        call move_alloc(dpatch%v, zone%donors%v)
      else
        call assemble(g, h, mx, nmat, bc, old, xnew, par, avol, amom, amass, aie, cmass, cmom, cke, cland, pcell, &
                      vcell, stats, err, written=written)
      end if
      if (.not. allocated(err)) call totals_of(h, wcells, wnodes, 1.0_wp, stats%change)
      stats%change_known = .not. allocated(err)
      stats%t_assemble = wall_seconds() - w0
    end block main
    if (.not. present(work)) return
    if (allocated(avol)) call keep_sums()
    ! (emptied through the lists; where a rescaled region or an error may
    ! have left marks the lists do not hold, over the grid)
    if (allocated(err) .or. stats%regions_rescaled > 0) then
      if (allocated(old%changed)) old%changed = .false.
      if (allocated(old%near)) old%near = .false.
      if (allocated(old%uniform)) old%uniform = .false.
      if (allocated(old%node)) old%node = .false.
    else
      if (allocated(old%lchanged)) old%changed(old%lchanged) = .false.
      if (allocated(old%lnear)) old%near(old%lnear) = .false.
      if (allocated(old%lnear)) old%uniform(old%lnear) = .false.
    end if

  contains

    !> The new cells' sums from the caller's work arrays, where they have
    !> this grid's and these materials' sizes (`remap_work_t`).
    subroutine take_sums()
      if (.not. allocated(work%avol)) return
      if (size(work%avol, 1) /= nmat .or. size(work%avol, 2) /= ncell) return
      call move_alloc(work%avol, avol)
      call move_alloc(work%amom, amom)
      call move_alloc(work%amass, amass)
      call move_alloc(work%aie, aie)
      call move_alloc(work%cmass, cmass)
      call move_alloc(work%cmom, cmom)
      call move_alloc(work%cke, cke)
      call move_alloc(work%cland, cland)
      call move_alloc(work%cdef, cdef)
      call move_alloc(work%pcell, pcell)
      call move_alloc(work%vcell, vcell)
      call move_alloc(work%reach, reach)
      call move_alloc(work%redo, redo)
      call move_alloc(work%gaps, gaps)
    end subroutine take_sums

    !> The new cells' sums back to the caller's work arrays.
    subroutine keep_sums()
      call move_alloc(avol, work%avol)
      call move_alloc(amom, work%amom)
      call move_alloc(amass, work%amass)
      call move_alloc(aie, work%aie)
      call move_alloc(cmass, work%cmass)
      call move_alloc(cmom, work%cmom)
      call move_alloc(cke, work%cke)
      call move_alloc(cland, work%cland)
      call move_alloc(cdef, work%cdef)
      call move_alloc(pcell, work%pcell)
      call move_alloc(vcell, work%vcell)
      call move_alloc(reach, work%reach)
      call move_alloc(redo, work%redo)
      call move_alloc(gaps, work%gaps)
    end subroutine keep_sums

    !> Whether this remap counts cell cc (a window's own cells; every cell
    !> of a whole grid's).
    logical function owns(cc)
      integer, intent(in) :: cc
      owns = .true.
      if (windowed) owns = own(cc)
    end function owns

    !> The open face whose gap new cell cc may lie in (`open_face_cells`; 0:
    !> none).
    integer function gap_of(cc)
      integer, intent(in) :: cc
      gap_of = 0
      if (any_open) gap_of = gap_face(cc)
    end function gap_of

    !> The window a new cell is intersected again with, when old regions
    !> are rescaled: the one its first intersection took (the step's
    !> largest where it took none).
    integer function redo_reach(cc)
      integer, intent(in) :: cc
      redo_reach = reach(cc)
      if (redo_reach == 0) redo_reach = stats%reach
    end function redo_reach

    !> The i-th region the remap reads: the near cells', then every slot's.
    integer function region_at(i) result(r)
      integer, intent(in) :: i
      if (i <= size(old%lnear)) then
        r = old%lnear(i)
      else
        r = ncell + i - size(old%lnear)
      end if
    end function region_at

    !> Intersects the new cells `cells` with the old grid within `rr` index
    !> steps; given_sign (+1, -1 or 0) says how their fragments count in
    !> the volume each old region gave away.
    subroutine intersect_cells(cells, rr, given_sign)
      integer, intent(in) :: cells(:), rr
      real(wp), intent(in) :: given_sign
      integer :: ii, nn, k
      nn = size(cells)
      if (.not. sharing) then
        call intersect_list(cells, rr, given_sign)
        return
      end if
      ! this rank's cells; what they gave away added over the ranks (exact
      ! integers), their results gathered from the ranks that computed them
      before = old%given
      call intersect_list(pack(cells, share%mine([(ii, ii = 1, nn)])), rr, given_sign)
      if (abs(given_sign) > 0.0_wp) then
        before = old%given - before   ! (this rank's part)
        old%given = old%given - before
        call share%sum_i8(before)
        old%given = old%given + before
      end if
      k = 0
      do ii = share%part + 1, nn, share%nparts
        k = k + 1
        associate (c => cells(ii))
          buf(:, k) = [avol(:, c), reshape(amom(:, :, c), [3*nmat]), amass(:, c), aie(:, c), pcell(:, c), &
                       reshape(cmom(:, :, c), [24]), cland(:, c), cdef(:, c)]
        end associate
      end do
      call share%columns(nn, buf(:, :nn))
      do ii = 1, nn
        associate (c => cells(ii), b => buf(:, ii))
          avol(:, c) = b(1:nmat)
          amom(:, :, c) = reshape(b(nmat + 1:4*nmat), [3, nmat])
          amass(:, c) = b(4*nmat + 1:5*nmat)
          aie(:, c) = b(5*nmat + 1:6*nmat)
          pcell(:, c) = b(6*nmat + 1:6*nmat + 4)
          cmom(:, :, c) = reshape(b(6*nmat + 5:6*nmat + 28), [3, 8])
          cland(:, c) = b(6*nmat + 29:6*nmat + 36)
          cdef(:, c) = b(6*nmat + 37:6*nmat + 44)
        end associate
      end do
    end subroutine intersect_cells

    !> `intersect_cells` on this process.
    subroutine intersect_list(cells, rr, given_sign)
      integer, intent(in) :: cells(:), rr
      real(wp), intent(in) :: given_sign
      integer :: ii, nn, i0, i1, chunk
      integer, allocatable :: low(:)
      logical :: parts
      type(error_t), allocatable :: berr
      nn = size(cells)
      ! the lattice path in chunks: the parts of the old cells a chunk
      ! reaches, then dropped once no later cell reaches them (low: the
      ! lowest cell index from each cell on), so that the parts held are
      ! a chunk's and its reach's, not the grid's
      parts = lat%lt%on .and. .not. old%swept
      chunk = max(nn, 1)
      if (parts) then
        chunk = lattice_chunk
        low = cells
        do ii = nn - 1, 1, -1
          low(ii) = min(low(ii), low(ii + 1))
        end do
      end if
      if (rr >= bins_reach_min .and. .not. old%swept .and. .not. allocated(wide%start)) then
        ! (a cell numbering of its own, or no room: every cell of the window visited)
        call remap_bins_build(g%ni, g%nj, g%nk, g%x, old%changed, wide, berr)
        if (allocated(berr) .or. wide%ix%ncell /= g%ncell) then
          if (allocated(wide%item)) deallocate(wide%item)
        end if
      end if
      do i0 = 1, nn, chunk
        i1 = min(nn, i0 + chunk - 1)
        if (parts) call lattice_prepare(g, h, mx, old, lat, cells(i0:i1), rr)
        !$omp parallel do default(none) shared(g, h, mx, old, lat, xnew, i0, i1, cells, rr, given_sign, avol, amom, &
        !$omp amass, aie, cmom, cland, cdef, pcell, wide) private(ii) schedule(dynamic, 4)
        do ii = i0, i1
          call remap_new_cell(g, h, mx, old, lat, old%given, given_sign, xnew, cells(ii), rr, avol(:, cells(ii)), &
                              amom(:, :, cells(ii)), amass(:, cells(ii)), aie(:, cells(ii)), pcell(:, cells(ii)), &
                              cmom(:, :, cells(ii)), cland(:, cells(ii)), cdef(:, cells(ii)), wide)
        end do
        !$omp end parallel do
        if (parts .and. i1 < nn) call lattice_release(old, lat, low(i1 + 1) - rr*(1 + g%cx + g%cxy))
      end do
      if (parts) call lattice_release(old, lat, huge(1))
    end subroutine intersect_list

    !> The new cells `cells`, intersected with the window rr that found
    !> their fragments short, again with a window that holds every old
    !> cell whose bounding box meets theirs (`remap_bins`): what is still
    !> missing then lies outside the old grid, a gap (filled in
    !> `open_faces`). Only an excess of fragments counts as a defect.
    subroutine widen_gaps(cells, err)
      integer, intent(in) :: cells(:)
      type(error_t), allocatable, intent(inout) :: err
      type(remap_bins_t) :: bins
      integer, allocatable :: rw(:)
      logical, allocatable :: wider(:)
      integer :: ii, cc, i0, j0, k0, st
      real(wp) :: xc(3, 8), vc
      character(len=200) :: emsg

      ! (a window's: its own, which its caller built)
      if (.not. windowed) call remap_bins_build(g%ni, g%nj, g%nk, g%x, old%changed, bins, err)
      if (allocated(err)) return
      allocate(rw(size(cells)), wider(size(cells)), stat=st, errmsg=emsg)
      if (st /= 0) then
        call error_set(err, 'remap_euler_step', error_no_memory('the gap windows'))
        return
      end if
      do ii = 1, size(cells)
        cc = cells(ii)
        call g%cell_ijk(cc, i0, j0, k0)
        call g%gather(cc, xnew, xc)
        if (windowed) then
          rw(ii) = max(remap_bins_reach(zone%bins, i0, j0, k0, minval(xc, 2), maxval(xc, 2)), reach(cc), &
                       remap_boxes_reach(zone%far_ijk, zone%far_box, i0 + g%off(1), j0 + g%off(2), k0 + g%off(3), &
                                         minval(xc, 2), maxval(xc, 2)))
          if (rw(ii) > zone%reach_max) then
            stats%cells_short = stats%cells_short + 1
            rw(ii) = zone%reach_max
          end if
        else
          rw(ii) = max(remap_bins_reach(bins, i0, j0, k0, minval(xc, 2), maxval(xc, 2)), reach(cc))
        end if
      end do
      wider = rw > reach(cells)
      if (any(wider)) then
        call intersect_each(pack(cells, wider), pack(reach(cells), wider), -1.0_wp)
        call intersect_each(pack(cells, wider), pack(rw, wider), 1.0_wp)
      end if
      do ii = 1, size(cells)
        cc = cells(ii)
        reach(cc) = rw(ii)
        call g%gather(cc, xnew, xc)
        vc = hex_volume(xc)
        if (owns(cc)) stats%volume_defect = max(stats%volume_defect, (sum(avol(:, cc)) - vc)/abs(vc))
      end do
    end subroutine widen_gaps

    !> `intersect_cells` with a window of its own for each cell (rr(i) for
    !> cells(i)), one pass per window size.
    subroutine intersect_each(cells, rr, given_sign)
      integer, intent(in) :: cells(:), rr(:)
      real(wp), intent(in) :: given_sign
      logical :: pend(size(cells))
      integer :: rc
      pend = .true.
      do while (any(pend))
        rc = minval(rr, mask=pend)
        call intersect_cells(pack(cells, pend .and. rr == rc), rc, given_sign)
        where (rr == rc) pend = .false.
      end do
    end subroutine intersect_each

    !> Marks the new cells within rr index steps of cell co.
    subroutine mark_window(co, rr)
      integer, intent(in) :: co, rr
      integer :: i0, j0, k0, ii, jj, kk
      call g%cell_ijk(co, i0, j0, k0)
      do kk = max(g%clo(3), k0 - rr), min(g%chi(3), k0 + rr)
        do jj = max(g%clo(2), j0 - rr), min(g%chi(2), j0 + rr)
          do ii = max(g%clo(1), i0 - rr), min(g%chi(1), i0 + rr)
            redo(g%cell(ii, jj, kk)) = .true.
          end do
        end do
      end do
    end subroutine mark_window
  end subroutine remap_euler_step

  !> The marks of work for a grid of ncell cells and nnode nodes, set up
  !> before the first Euler step (with the grid: their first touch is a
  !> pass over the grid, which the Euler steps then never make).
  subroutine remap_work_ready(work, ncell, nnode, err)
    type(remap_work_t), intent(inout) :: work
    integer, intent(in) :: ncell, nnode
    type(error_t), allocatable, intent(inout) :: err
    integer :: stat
    call marks_ready(work%old, ncell, nnode, stat)
    ! (and the swept faces' slots and stamps, `swept_low_faces`)
    if (stat == 0 .and. .not. allocated(work%old%fslot)) then
      allocate(work%old%fslot(ncell), work%old%fstamp(ncell), stat=stat)
      if (stat == 0) work%old%fstamp = work%old%fgen - 1
    end if
    if (stat /= 0) call error_set(err, 'remap_work_ready', error_no_memory('the cell marks'))
  end subroutine remap_work_ready

  !> The marks of old (changed, near, uniform, node) sized for a grid of
  !> ncell cells and nnode nodes, all false: kept if they are (stat: the
  !> allocation's).
  subroutine marks_ready(old, ncell, nnode, stat)
    type(old_t), intent(inout) :: old
    integer, intent(in) :: ncell, nnode
    integer, intent(out) :: stat
    stat = 0
    if (allocated(old%changed) .and. allocated(old%node)) then
      if (size(old%changed) == ncell .and. size(old%node) == nnode) return
      deallocate(old%changed, old%near, old%uniform, old%node)
    end if
    allocate(old%changed(ncell), old%near(ncell), old%uniform(ncell), old%node(nnode), stat=stat)
    if (stat /= 0) return
    old%changed = .false.
    old%near = .false.
    old%uniform = .false.
    old%node = .false.
  end subroutine marks_ready

  !> The old grid's arrays of old for ncell cells, nnode nodes, nreg
  !> regions and nslot slots: kept where they have those sizes (a kept
  !> workspace's), else allocated afresh (stat: the allocation's).
  subroutine old_arrays(old, ncell, nnode, nreg, nslot, stat)
    type(old_t), intent(inout) :: old
    integer, intent(in) :: ncell, nnode, nreg, nslot
    integer, intent(out) :: stat
    logical :: keep
    stat = 0
    keep = allocated(old%ucell)
    if (keep) keep = size(old%ucell, 2) == ncell .and. size(old%gu, 3) == nnode
    if (.not. keep) then
      if (allocated(old%ucell)) deallocate(old%ucell, old%kcell, old%uref, old%ushift, old%kshift, old%gu, old%xdual)
      allocate(old%ucell(3, ncell), old%kcell(ncell), old%uref(3, ncell), old%ushift(3, ncell), old%kshift(ncell), &
               old%gu(3, 3, nnode), old%xdual(3, nnode), stat=stat)
      if (stat /= 0) return
    end if
    keep = allocated(old%wreg)
    if (keep) keep = size(old%wreg) == nreg .and. size(old%pd) == nslot
    if (keep) return
    if (allocated(old%wreg)) deallocate(old%wreg, old%rho, old%e, old%xr, old%grho, old%ge, old%pn, old%pd, old%sfac, &
                                        old%sroom, old%sshift, old%vreg, old%given, old%gunit, old%scale, old%skv, &
                                        old%skm, old%sov, old%som, old%so, old%sout)
    allocate(old%wreg(nreg), old%rho(nreg), old%e(nreg), old%xr(3, nreg), old%grho(3, nreg), old%ge(3, nreg), &
             old%pn(3, nslot), old%pd(nslot), old%sfac(nslot), old%sroom(nslot), old%sshift(3, nslot), &
             old%vreg(nreg), old%given(nreg), old%gunit(nreg), old%scale(nreg), old%skv(8, nslot), &
             old%skm(3, 8, nslot), old%sov(48, nslot), old%som(3, 48, nslot), old%so(3, nslot), old%sout(nslot), &
             stat=stat)
  end subroutine old_arrays

  !> The changed cells' arrays of old (wv, ws, sub) for n changed cells of
  !> a grid of ncell: kept where they hold n entries, else allocated for
  !> twice n, at most ncell (so that a region the shock grows does not
  !> reallocate them at every Euler step, and a grid whose every cell
  !> changes holds them once; stat: the allocation's).
  subroutine changed_arrays(old, n, ncell, stat)
    type(old_t), intent(inout) :: old
    integer, intent(in) :: n, ncell
    integer, intent(out) :: stat
    integer :: m
    stat = 0
    if (allocated(old%sub)) then
      if (size(old%sub, 3) >= n) return
      deallocate(old%wv, old%ws, old%sub)
    end if
    m = max(n, min(2*n, ncell))
    allocate(old%wv(8, m), old%ws(3, 8, m), old%sub(4, 8, m), stat=stat)
  end subroutine changed_arrays

  !> The cells of g with a node that moves from g%x to xnew (marked in
  !> changed, all false on entry, and their list in increasing order): each
  !> node is compared once, and only the moved nodes' cells are visited.
  !> rows (optional): g%moved_rows, where xnew is the grid those flags refer
  !> to; then only the flagged rows of nodes are compared, so the cost
  !> follows the moved region, not the grid (where most rows are flagged,
  !> all nodes are compared in blocks, the faster way then).
  subroutine moved_cells(g, xnew, changed, list, err, rows)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: xnew(:, :)
    logical, intent(inout) :: changed(:)
    integer, allocatable, intent(out) :: list(:)
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: rows(:)
    integer, parameter :: block = 32
    integer, allocatable :: fresh(:)
    integer :: n, i, j, k, ci, cj, ck, nf, c, stat, n0, n1, step
    logical, allocatable :: moved(:)
    logical :: by_rows
    allocate(fresh(size(changed)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('a cell list'))
      return
    end if
    nf = 0
    by_rows = .false.
    if (present(rows)) by_rows = 4*count(rows) < size(rows)
    if (by_rows) then
      ! (the rows the Lagrangian steps noted)
      step = g%sx
      moved = rows
    else
      ! (blocks of nodes compared at once first: most nodes of a large grid
      ! do not move)
      step = block
      allocate(moved((g%nnode + block - 1)/block), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'remap_euler', error_no_memory('a node list'))
        return
      end if
      call blocks_moved(g%nnode, xnew, g%x, block, moved)
    end if
    do n0 = 1, g%nnode, step
      n1 = min(n0 + step - 1, g%nnode)
      if (.not. moved((n0 - 1)/step + 1)) cycle
      do n = n0, n1
        if (.not. any(abs(xnew(:, n) - g%x(:, n)) > 0.0_wp)) cycle
        ! (node (i,j,k) is corner 1 of cell (i+1,j+1,k+1))
        call g%node_ijk(n, i, j, k)
        do ck = max(k, g%slo(3)), min(k + 1, g%shi(3))
          do cj = max(j, g%slo(2)), min(j + 1, g%shi(2))
            do ci = max(i, g%slo(1)), min(i + 1, g%shi(1))
              c = g%cell(ci, cj, ck)
              if (changed(c)) cycle
              changed(c) = .true.
              nf = nf + 1
              fresh(nf) = c
            end do
          end do
        end do
      end do
    end do
    call marked_list(changed, fresh(1:nf), list, err)
  end subroutine moved_cells

  !> moved(q): whether a node of the q-th block of `block` nodes differs
  !> between the m nodes' coordinates a and b (the largest difference over
  !> each block's coordinates in storage order: no early exit, and a
  !> maximum is exact in any order, so that the compiler takes several at
  !> a time).
  pure subroutine blocks_moved(m, a, b, block, moved)
    integer, intent(in) :: m, block
    real(wp), intent(in) :: a(3, m), b(3, m)
    logical, intent(out) :: moved(:)
    integer :: q, n0, n1
    do q = 1, size(moved)
      n0 = block*(q - 1) + 1
      n1 = min(block*q, m)
      moved(q) = nodes_moved(n1 - n0 + 1, a(:, n0:n1), b(:, n0:n1))
    end do
  end subroutine blocks_moved

  !> The indices where mask is true, in increasing order: fresh, the same
  !> indices in any order, sorted where they are few, else the mask read
  !> through (either way the same list, at a cost that follows the count
  !> where it is small against the mask's size).
  subroutine marked_list(mask, fresh, list, err)
    logical, intent(in) :: mask(:)
    integer, intent(in) :: fresh(:)
    integer, allocatable, intent(out) :: list(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: order(:)
    integer :: stat
    if (16*size(fresh) > size(mask)) then
      call true_list(mask, list, err)
      return
    end if
    allocate(order(size(fresh)), stat=stat)
    if (stat == 0) call sort_order(fresh, order, stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('a cell list'))
      return
    end if
    list = fresh(order)
  end subroutine marked_list

  !> The indices where mask is true, in increasing order.
  subroutine true_list(mask, list, err)
    logical, intent(in) :: mask(:)
    integer, allocatable, intent(out) :: list(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: i, k, stat
    allocate(list(count(mask)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('a cell list'))
      return
    end if
    k = 0
    do i = 1, size(mask)
      if (.not. mask(i)) cycle
      k = k + 1
      list(k) = i
    end do
  end subroutine true_list

  !> The union of the increasing lists a and b, in increasing order.
  subroutine sorted_union(a, b, list, err)
    integer, intent(in) :: a(:), b(:)
    integer, allocatable, intent(out) :: list(:)
    type(error_t), allocatable, intent(inout) :: err
    integer :: i, j, n, stat
    if (build_checks) then
      if (any(a(2:) <= a(:size(a) - 1)) .or. any(b(2:) <= b(:size(b) - 1))) then
        call error_set(err, 'remap_euler', 'sorted_union: a list is not increasing')
        return
      end if
    end if
    allocate(list(size(a) + size(b)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('a cell list'))
      return
    end if
    i = 1
    j = 1
    n = 0
    do while (i <= size(a) .or. j <= size(b))
      n = n + 1
      if (j > size(b)) then
        list(n) = a(i)
        i = i + 1
      else if (i > size(a)) then
        list(n) = b(j)
        j = j + 1
      else if (a(i) < b(j)) then
        list(n) = a(i)
        i = i + 1
      else
        if (a(i) == b(j)) i = i + 1
        list(n) = b(j)
        j = j + 1
      end if
    end do
    list = list(1:n)
  end subroutine sorted_union

  !> The nodes of the cells `cells`, in increasing order (mark: work, all
  !> false on entry and on return).
  subroutine node_list(g, cells, mark, list, err)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: cells(:)
    logical, intent(inout) :: mark(:)
    integer, allocatable, intent(out) :: list(:)
    type(error_t), allocatable, intent(inout) :: err
    integer, allocatable :: fresh(:)
    integer :: i, a, n, stat, nf
    allocate(fresh(min(8*size(cells), g%nnode)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('a node list'))
      return
    end if
    nf = 0
    do i = 1, size(cells)
      n = g%node0(cells(i))
      do a = 1, 8
        if (mark(n + g%corner_offset(a))) cycle
        mark(n + g%corner_offset(a)) = .true.
        nf = nf + 1
        fresh(nf) = n + g%corner_offset(a)
      end do
    end do
    call marked_list(mark, fresh(1:nf), list, err)
    mark(fresh(1:nf)) = .false.
  end subroutine node_list

  !> The mixed cell that owns slot s.
  pure integer function slot_cell(mx, s) result(k)
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: s
    integer :: lo, hi, mid
    ! binary search in start(1:n+1): start(k) <= s < start(k+1)
    lo = 1
    hi = mx%n
    do while (lo < hi)
      mid = (lo + hi + 1)/2
      if (mx%start(mid) <= s) then
        lo = mid
      else
        hi = mid - 1
      end if
    end do
    k = lo
  end function slot_cell

  ! ------------------------------------------------------------ old side

  !> The old grid's cells: which moved, their mean velocities and their
  !> subcells' momentum deviations and kinetic energies, MoF planes of the
  !> mixed cells that moved, region centroids, and the gradients of the
  !> reconstruction. Only the old cells a remap reads are prepared: those
  !> that moved (only they give fragments), their neighbours (the gradients'
  !> stencils) and the cells open-face gaps take their state from
  !> (gap_face, gap_cell of `open_face_cells`); the other cells' state is NaN
  !> here, so that a read of it could not pass unnoticed. An Euler step that
  !> moves a few cells of a large grid then costs little more than them.
  subroutine prepare_old(g, h, mx, nmat, xnew, par, gap_face, gap_cell, old, stats, err, share, own, moved)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(inout) :: mx
    integer, intent(in) :: nmat
    real(wp), intent(in) :: xnew(:, :)
    type(remap_params_t), intent(in) :: par
    integer, intent(in) :: gap_face(:), gap_cell(:)
    type(old_t), intent(inout) :: old
    type(remap_stats_t), intent(inout) :: stats
    type(error_t), allocatable, intent(inout) :: err
    class(share_t), intent(in), optional :: share
    logical, intent(in), optional :: own(:)   !< the cells the stats count (absent: every cell)
    integer, intent(in), optional :: moved(:)  !< the changed cells (`remap_euler_step`)
    real(wp) :: xn(3, 8), errmax, ua(3, 8)
    integer :: c, ci, cj, ck, n, a_, k, s, nm, ncell, nreg, j, nmof, nits, nfail, nf
    logical :: ok
    logical, allocatable :: mine(:)
    integer, allocatable :: mof(:), fresh(:)
    real(wp), allocatable :: res(:, :)
    real(wp) :: nan, err1
    integer :: stat, oi, oj, ok_, its1
    logical :: sharing
    character(len=200) :: msg

    ncell = g%ncell
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    nreg = ncell + mx%nslot
    ! (a kept workspace's arrays, and marks all false, or this call's)
    call marks_ready(old, ncell, g%nnode, stat)
    if (stat == 0) call old_arrays(old, ncell, g%nnode, nreg, mx%nslot, stat)
    if (stat == 0) allocate(fresh(ncell), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the old grid''s regions'))
      return
    end if
    ! changed cells
    if (present(moved)) then
      old%changed(moved) = .true.
      old%lchanged = moved
    else
      call moved_cells(g, xnew, old%changed, old%lchanged, err)
      if (allocated(err)) return
    end if
    call changed_arrays(old, size(old%lchanged), ncell, stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the changed cells'' subcells'))
      return
    end if
    ! the cells read
    nf = 0
    do j = 1, size(old%lchanged)
      c = old%lchanged(j)
      call g%cell_ijk(c, ci, cj, ck)
      do ok_ = max(g%clo(3), ck - 1), min(g%chi(3), ck + 1)
        do oj = max(g%clo(2), cj - 1), min(g%chi(2), cj + 1)
          do oi = max(g%clo(1), ci - 1), min(g%chi(1), ci + 1)
            call mark(c + (oi - ci) + g%cx*(oj - cj) + g%cxy*(ok_ - ck))
          end do
        end do
      end do
      if (size(gap_face) == 0) cycle
      if (gap_face(c) > 0 .and. gap_cell(c) > 0) call mark(gap_cell(c))
    end do
    call marked_list(old%near, fresh(1:nf), old%lnear, err)
    if (allocated(err)) return
    if (build_checks) then
      old%ucell = nan
      old%kcell = nan
      old%uref = nan
      old%ushift = nan
      old%kshift = nan
      old%wv = nan
      old%ws = nan
      old%sub = nan
      old%rho = nan
      old%e = nan
      old%xr = nan
      old%vreg = nan
      old%gunit = nan
      old%scale = nan
      old%grho = nan
      old%ge = nan
      old%wreg = nan
    end if
    do j = 1, size(old%lnear)
      c = old%lnear(j)
      old%gunit(c) = abs(h%vol(c))*2.0_wp**(-50)
      old%scale(c) = 1.0_wp
      old%vreg(c) = 0.0_wp
      old%grho(:, c) = 0.0_wp
      old%ge(:, c) = 0.0_wp
      old%wreg(c) = 0.0_wp
      old%given(c) = 0_i8
    end do
    old%given(ncell + 1:) = 0_i8
    do k = 1, mx%n
      old%gunit(ncell + mx%start(k):ncell + mx%start(k + 1) - 1) = abs(h%vol(mx%cell(k)))*2.0_wp**(-50)
    end do
    old%scale(ncell + 1:) = 1.0_wp
    old%vreg(ncell + 1:) = 0.0_wp
    old%grho(:, ncell + 1:) = 0.0_wp
    old%ge(:, ncell + 1:) = 0.0_wp
    old%wreg(ncell + 1:) = 0.0_wp
    old%rho(ncell + 1:) = nan
    old%e(ncell + 1:) = nan
    old%xr(:, ncell + 1:) = nan
    old%sfac = 1.0_wp
    old%sroom = 0.0_wp
    old%sshift = 0.0_wp
    old%pn = 0.0_wp
    old%pd = 1.0_wp
    ! mean velocities and kinetic energies per unit mass (subcell masses:
    ! Eq. 16), read only where a cell hands out fragments (the changed
    ! cells: `subcell_shifts` takes them there) or fills a gap at an open
    ! face (`open_faces`: any near cell, so all of them here)
    if (size(gap_face) > 0) then
      !$omp parallel do default(none) shared(g, h, old) private(j, c, n, a_, ua) schedule(static)
      do j = 1, size(old%lnear)
        c = old%lnear(j)
        n = g%node0(c)
        do a_ = 1, 8
          ua(:, a_) = h%u(:, n + g%corner_offset(a_))
        end do
        call mean_velocity(h%mcorner(:, c), ua, old%ucell(:, c), old%uref(:, c), old%kcell(c))
      end do
      !$omp end parallel do
    end if

    ! regions: pure cells whole (the split's volume and centroid); mixed
    ! cells that moved cut by MoF
    call cell_moments(g%ni, g%nj, g%nk, g%x, old%vreg(1:ncell), old%xr(:, 1:ncell), old%lnear)
    !$omp parallel do default(none) shared(g, h, mx, old, ncell) private(j, c, k, s, xn) schedule(static)
    do j = 1, size(old%lnear)
      c = old%lnear(j)
      old%rho(c) = h%mass(c)/old%vreg(c)
      old%e(c) = h%e(c)
      if (h%mat(c) > 0) cycle
      call g%gather(c, g%x, xn)
      k = -h%mat(c)
      do s = mx%start(k), mx%start(k + 1) - 1
        old%rho(ncell + s) = mx%rho(s)
        old%e(ncell + s) = mx%e(s)
        old%xr(:, ncell + s) = hex_trilinear(xn, mx%xi(:, s))
      end do
    end do
    !$omp end parallel do
    ! the mixed cells that moved: MoF (shared by the ranks, as the
    ! intersections: each item's result is the same whoever computes it)
    mof = pack([(k, k = 1, mx%n)], [(old%changed(mx%cell(k)), k = 1, mx%n)])
    nmof = size(mof)
    sharing = .false.
    if (present(share)) sharing = share%nparts > 1
    nm = 0
    do k = 1, mx%n
      nm = max(nm, mx%start(k + 1) - mx%start(k))
    end do
    allocate(res(3 + 12*nm, nmof), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the MoF results'))
      return
    end if
    mine = [(.true., j = 1, nmof)]
    if (sharing) mine = share%mine([(j, j = 1, nmof)])
    !$omp parallel do default(none) shared(g, mx, old, par, mof, nmof, mine, res) private(j, its1, ok, err1) &
    !$omp schedule(dynamic, 4)
    do j = 1, nmof
      if (.not. mine(j)) cycle
      call mof_cell(g, mx, old, par, mof(j), its1, ok, err1)
      ! (its1 < 0: cut by the carried planes)
      res(1:3, j) = [real(its1, wp), merge(0.0_wp, 1.0_wp, ok), err1]
    end do
    !$omp end parallel do
    if (sharing) then
      ! this rank's cells' results, their slots' state with them
      k = 0
      do j = share%part + 1, nmof, share%nparts
        k = k + 1
        res(:, k) = res(:, j)
        call slot_state(mof(j), res(4:, k), .true.)
      end do
      call share%columns(nmof, res)
      do j = 1, nmof
        call slot_state(mof(j), res(4:, j), .false.)
      end do
    end if
    mine = [(.true., j = 1, nmof)]
    if (present(own)) mine = [(own(mx%cell(mof(j))), j = 1, nmof)]
    nits = nint(sum(res(1, :), mask=mine .and. res(1, :) > 0.0_wp))
    stats%mof_carried = count(mine .and. res(1, :) < 0.0_wp)
    nfail = nint(sum(res(2, :), mask=mine))
    errmax = 0.0_wp
    if (nmof > 0) errmax = maxval(res(3, :), mask=mine)
    ! only what the intersection hands out counts as a region: pure cells
    ! and slots with mass, of cells that moved
    do j = 1, size(old%lnear)
      c = old%lnear(j)
      if (.not. old%changed(c) .or. h%mat(c) <= 0) old%vreg(c) = 0.0_wp
    end do
    do k = 1, mx%n
      do s = mx%start(k), mx%start(k + 1) - 1
        if (.not. old%changed(mx%cell(k)) .or. .not. mx%mass(s) > 0.0_wp) old%vreg(ncell + s) = 0.0_wp
      end do
    end do
    stats%mof_cells = count(mine)
    stats%mof_iterations = nits
    stats%mof_not_converged = nfail
    stats%mof_err_max = errmax
    if (par%linear) call material_gradients(g, h, mx, nmat, old, err)
    if (allocated(err)) return
    if (par%swept .and. par%swept_mixed) then
      ! the swept path through mixed cells: their regions give their mean
      ! state (what such a region keeps and what its faces give are not
      ! parts of one region, and a reconstruction taken on their difference
      ! leaves its bounds); set here, so that the subcells' masses and
      ! shifts (`subcell_shifts`) and the floors see the same state
      old%grho(:, ncell + 1:) = 0.0_wp
      old%ge(:, ncell + 1:) = 0.0_wp
    end if
    ! (with the regions' floors: `region_floor`)
    call subcell_shifts(g, h, mx, old, size(gap_face) == 0)
    ! the changed cells' nodes
    call node_list(g, old%lchanged, old%node, old%lnode, err)
    if (allocated(err)) return
    if (build_checks) then
      old%gu = nan
      old%xdual = nan
    end if
    do j = 1, size(old%lnode)
      ! (by `zero_values`)
      call zero_values(9, old%gu(1, 1, old%lnode(j)))
      call zero_values(3, old%xdual(1, old%lnode(j)))
    end do
    if (par%linear) call velocity_gradients(g, old, h%u, err)

  contains

    !> Cell cc is read (near), and listed once (fresh).
    subroutine mark(cc)
      integer, intent(in) :: cc
      if (old%near(cc)) return
      old%near(cc) = .true.
      nf = nf + 1
      fresh(nf) = cc
    end subroutine mark

    !> The state MoF sets in the slots of mixed cell k, packed into b
    !> (to_buffer) or unpacked from it: 12 values per slot.
    subroutine slot_state(k, b, to_buffer)
      integer, intent(in) :: k
      real(wp), intent(inout) :: b(:)
      logical, intent(in) :: to_buffer
      integer :: q, r
      do q = mx%start(k), mx%start(k + 1) - 1
        r = ncell + q
        associate (v => b(12*(q - mx%start(k)) + 1:12*(q - mx%start(k) + 1)))
          if (to_buffer) then
            v = [old%pn(:, q), old%pd(q), old%vreg(r), old%xr(:, r), old%rho(r), old%e(r), mx%e(q), mx%mass(q)]
          else
            old%pn(:, q) = v(1:3)
            old%pd(q) = v(4)
            old%vreg(r) = v(5)
            old%xr(:, r) = v(6:8)
            old%rho(r) = v(9)
            old%e(r) = v(10)
            mx%e(q) = v(11)
            mx%mass(q) = v(12)
          end if
        end associate
      end do
    end subroutine slot_state
  end subroutine prepare_old

  !> MoF in mixed cell k (which moved): each material's plane (nested
  !> dissection), its region's exact volume and centroid, the point its
  !> linear reconstruction is about, and its mean density and energy; its
  !> iterations (its_sum; -1 where the carried planes were cut and no
  !> search was made), whether it converged (ok) and its largest centroid
  !> error relative to the cell's size (err_rel; 0 for carried planes).
  subroutine mof_cell(g, mx, old, par, k, its_sum, ok, err_rel)
    type(grid_t), intent(in) :: g
    type(mixed_t), intent(inout) :: mx
    type(old_t), intent(inout) :: old
    type(remap_params_t), intent(in) :: par
    integer, intent(in) :: k
    integer, intent(out) :: its_sum
    logical, intent(out) :: ok
    real(wp), intent(out) :: err_rel
    real(wp) :: xn(3, 8), v, m(3), vf(max_mat), cref(3, max_mat), pn(3, max_mat), pd(max_mat), &
                errc(max_mat), vreg(max_mat), guess(3, max_mat), det, planes(4, max_mat), cen(3, max_mat)
    integer :: c, s, s0, s1, nm, its(max_mat), j, big, ncell
    type(mof_pieces_t) :: pcs
    logical :: okp, known, carried
    ncell = g%ncell
    c = mx%cell(k)
    call g%gather(c, g%x, xn)
    v = old%vreg(c)
    s0 = mx%start(k)
    s1 = mx%start(k + 1) - 1
    nm = s1 - s0 + 1
    vf(1:nm) = mx%vf(s0:s1)/sum(mx%vf(s0:s1))
    cref(:, 1:nm) = old%xr(:, ncell + s0:ncell + s1)
    ! the planes the Lagrangian phase carried (`lagrange_centroids`): cut to
    ! the fractions as `centroids_refresh` cuts them, they are the planes
    ! whose regions' centroids the reference centroids are, and so MoF's
    ! answer for them (to its convergence: the refresh leaves these cells'
    ! centroids to this cut, the same numbers); where that cut fails, MoF
    ! from them
    carried = .false.
    known = allocated(mx%plane)
    if (known) known = size(mx%plane, 2) == mx%nslot
    if (known) known = planes_known(mx, s0, s1) .and. nm <= max_mat
    if (known) then
      call carried_cut(xn, mx, s0, s1, vreg(1:nm), cen(:, 1:nm), ok, planes(:, 1:nm))
      if (ok) then
        pn(:, 1:nm) = planes(1:3, 1:nm)
        pd(1:nm) = planes(4, 1:nm)
        its(1:nm) = 0
        errc(1:nm) = 0.0_wp
        ! (an empty region's point too, whether or not the refresh saw it:
        ! the regions' below)
        old%xr(:, ncell + s0:ncell + s1) = cen(:, 1:nm)
      end if
      known = ok
      carried = ok
      if (.not. known) then
        call plane_normals(xn, mx%plane(:, s0:s1), guess(:, 1:nm), det)
        known = det > 0.0_wp
        if (known) call mof_reconstruct_nested(xn, vf(1:nm), cref(:, 1:nm), pn(:, 1:nm), pd(1:nm), errc(1:nm), &
                                               its(1:nm), ok, par%mof_max_iter, guess=guess(:, 1:nm))
      end if
    end if
    if (.not. known) then
      call mof_reconstruct_nested(xn, vf(1:nm), cref(:, 1:nm), pn(:, 1:nm), pd(1:nm), errc(1:nm), &
                                  its(1:nm), ok, par%mof_max_iter)
    end if
    its_sum = sum(its(1:nm))
    if (carried) its_sum = -1
    err_rel = maxval(errc(1:nm))/v**(1.0_wp/3.0_wp)
    ! each material's region: its exact volume and centroid, the point
    ! its linear reconstruction is about (the carried planes' cut gave them)
    do j = 1, nm
      s = s0 + j - 1
      old%pn(:, s) = pn(:, j)
      old%pd(s) = pd(j)
      if (carried) then
        m = cen(:, j)
      else
        call mof_material_pieces(xn, pn(:, 1:nm), pd(1:nm), j, pcs, okp)
        call mof_pieces_moments(pcs, vreg(j), m)
      end if
      old%vreg(ncell + s) = vreg(j)
      if (vreg(j) > 0.0_wp) old%xr(:, ncell + s) = m
    end do
    ! a material whose region has no volume (a fraction below round-off)
    ! cannot hand its mass to any fragment: the largest material takes
    ! it, energy with it
    big = s0 - 1 + maxloc(vreg(1:nm), 1)
    do j = 1, nm
      s = s0 + j - 1
      if (s == big .or. vreg(j) > 0.0_wp .or. .not. mx%mass(s) > 0.0_wp) cycle
      mx%e(big) = (mx%mass(big)*mx%e(big) + mx%mass(s)*mx%e(s))/(mx%mass(big) + mx%mass(s))
      mx%mass(big) = mx%mass(big) + mx%mass(s)
      mx%mass(s) = 0.0_wp
    end do
    do j = 1, nm
      s = s0 + j - 1
      old%e(ncell + s) = mx%e(s)
      if (vreg(j) > 0.0_wp) old%rho(ncell + s) = mx%mass(s)/vreg(j)
    end do
  end subroutine mof_cell

  !> Region r's smallest density wreg (its cell's nodes xn): its limited
  !> linear density's smallest value at the cell's nodes (the density is
  !> linear, so it is smallest at a node of the cell, and the region lies
  !> within the cell).
  !> A fragment of volume v whose centroid lies delta from the region's
  !> centroid gets the mass v rho(x_f) and the energy m_f e + rho_r v
  !> ge.delta, so its specific energy is e + (rho_r/rho(x_f)) ge.delta:
  !> where the density falls across the region (a contact, a blast front)
  !> the energy deviation is amplified by rho_r/rho(x_f), and a cold light
  !> gas next to a dense one went negative (LeBlanc's tube). Scaling the
  !> energy gradient by wreg/rho_r keeps the amplified deviation within the
  !> limited one: every fragment's energy stays within the old neighbours'
  !> bounds. The velocity's linear part is weighted the same way
  !> (`deposit`). Conservation is untouched (it holds for any gradient).
  !> Taken for each changed cell's regions in `subcell_shifts`' loop.
  pure subroutine region_floor(old, r, xn)
    type(old_t), intent(inout) :: old
    integer, intent(in) :: r
    real(wp), intent(in) :: xn(3, 8)
    integer :: a_
    real(wp) :: rmin
    rmin = old%rho(r)
    do a_ = 1, 8
      rmin = min(rmin, old%rho(r) + dot_product(old%grho(:, r), xn(:, a_) - old%xr(:, r)))
    end do
    old%wreg(r) = max(rmin, 0.0_wp)
    if (old%rho(r) > 0.0_wp) then
      old%ge(:, r) = old%ge(:, r)*old%wreg(r)/old%rho(r)
    else
      old%ge(:, r) = 0.0_wp
    end if
  end subroutine region_floor

  !> Limited least-squares gradients of each material's density and energy
  !> about the region centroids, over the cells that hold the material.
  subroutine material_gradients(g, h, mx, nmat, old, err)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: nmat
    type(old_t), intent(inout) :: old
    type(error_t), allocatable, intent(inout) :: err
    integer :: ncell, kmat, c, k, s, stat, j
    character(len=200) :: msg

    ncell = g%ncell
    ! (kept with old: a fresh whole-grid array's pages cost their first touch)
    stat = 0
    if (allocated(old%gq)) then
      if (size(old%gq, 2) /= ncell) deallocate(old%gq, old%gpos, old%ghas, old%gneed, old%ggrad)
    end if
    if (.not. allocated(old%gq)) allocate(old%gq(2, ncell), old%gpos(3, ncell), old%ghas(ncell), old%gneed(ncell), &
                                          old%ggrad(3, 2, ncell), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the gradient work arrays'))
      return
    end if
    associate (q => old%gq, pos => old%gpos, has => old%ghas, need => old%gneed, grad => old%ggrad)
    ! (the gradients of the changed cells read the cells around them only:
    ! the near cells; has and need are set there, q and pos where has is)
    do kmat = 1, nmat
      do j = 1, size(old%lnear)
        c = old%lnear(j)
        has(c) = h%mat(c) == kmat
        need(c) = .false.
        q(:, c) = [old%rho(c), old%e(c)]
        ! (pos, by `copy_values`: its array's element, not the name)
        call copy_values(3, old%xr(1, c), old%gpos(1, c))
      end do
      do k = 1, mx%n
        c = mx%cell(k)
        if (.not. old%near(c)) cycle
        do s = mx%start(k), mx%start(k + 1) - 1
          if (mx%mat(s) /= kmat .or. .not. mx%mass(s) > 0.0_wp) cycle
          has(c) = .true.
          q(:, c) = [old%rho(ncell + s), old%e(ncell + s)]
          call copy_values(3, old%xr(1, ncell + s), old%gpos(1, c))
        end do
      end do
      do j = 1, size(old%lchanged)
        c = old%lchanged(j)
        need(c) = has(c)
      end do
      if (.not. any(need(old%lchanged))) cycle
      call remap_limited_gradients(g%ni, g%nj, g%nk, g%x, q, pos, has, need, grad, cells=old%lchanged)
      do j = 1, size(old%lchanged)
        c = old%lchanged(j)
        if (h%mat(c) /= kmat .or. .not. need(c)) cycle
        ! (by `copy_values`, from the work array itself)
        call copy_values(3, old%ggrad(1, 1, c), old%grho(1, c))
        call copy_values(3, old%ggrad(1, 2, c), old%ge(1, c))
      end do
      do k = 1, mx%n
        c = mx%cell(k)
        if (.not. old%changed(c)) cycle
        if (.not. need(c)) cycle
        do s = mx%start(k), mx%start(k + 1) - 1
          if (mx%mat(s) /= kmat) cycle
          old%grho(:, ncell + s) = grad(:, 1, c)
          old%ge(:, ncell + s) = grad(:, 2, c)
        end do
      end do
    end do
    end associate
  end subroutine material_gradients

  !> The velocity a moved old cell's fragments carry. A fragment of subcell
  !> a (the six halves of the 24-split at node a, Fig. 11) carries, with its
  !> own mass m_f from the material reconstruction, the velocity u_a + s_c
  !> and the kinetic energy per unit mass |u_a + s_c|^2/2 + k_c. The cell's
  !> momentum is sum_a m_ca u_a with its corner masses m_ca (Eq. 16), but
  !> the reconstruction puts the mass M_a in subcell a (the density's
  !> gradient, the materials' regions in a mixed cell, the subcells' volume
  !> changes since the corner masses were set); the shifts
  !>   s_c = sum_a (m_ca - M_a) u_a / m_c,
  !>   k_c = (sum_a m_ca |u_a - v_c|^2/2 - sum_a M_a |u_a + s_c - v_c|^2/2) / m_c
  !> (v_c the cell's mean velocity: the kinetic energies about it)
  !> make the fragments hand out exactly the cell's momentum and kinetic
  !> energy (sum_a M_a = m_c). Carrying velocity with the mass that moves
  !> (rather than momentum with volume) keeps every fragment's velocity a
  !> shifted corner velocity, whatever the densities: momentum carried with
  !> the volume of a subcell whose mean density is far above the material
  !> that lies in it (the air side of a mixed cell, the cold side of a
  !> contact) gave that material a velocity far beyond any old one, and the
  !> kinetic energy the nodes then lacked drove the internal energy
  !> negative. A uniform velocity has s_c = 0 and k_c = 0: it stays uniform
  !> exactly. A tangled cell (an inverted half) hands out its mean velocity
  !> and kinetic energy per unit mass only (uniform).
  subroutine subcell_shifts(g, h, mx, old, means)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    type(old_t), intent(inout) :: old
    !> the cells' mean velocities (`mean_velocity`) are taken here (else
    !> the caller took them)
    logical, intent(in) :: means
    real(wp) :: xn(3, 8), pts(3, 27), t(3, 4), msub(8), v, m(3), o(3), pn(3, max_mat), pd(max_mat), &
                ua(3, 8), mc, kc, ksum, det6(48), sub(4, 8)
    integer :: c, j, i, n, s, s0, s1, nm, r, ic

    ! (only moved cells hand out fragments: the others' entries are not read)
    !$omp parallel do default(none) shared(g, h, mx, old, means) &
    !$omp private(ic, c, j, i, n, xn, pts, t, msub, v, m, o, pn, pd, ua, mc, kc, ksum, s, s0, s1, nm, r, det6, &
    !$omp sub) &
    !$omp schedule(dynamic, 16)
    do ic = 1, size(old%lchanged)
      c = old%lchanged(ic)
      old%ushift(:, c) = 0.0_wp
      old%kshift(c) = 0.0_wp
      n = g%node0(c)
      do j = 1, 8
        call copy_values(3, h%u(1, n + g%corner_offset(j)), ua(1, j))
      end do
      if (means) call mean_velocity(h%mcorner(:, c), ua, old%ucell(:, c), old%uref(:, c), old%kcell(c))
      call g%gather(c, g%x, xn)
      ! its regions' floors (`region_floor`), read below
      call region_slots(h, mx, c, s0, s1)
      if (s0 == 0) then
        call region_floor(old, c, xn)
      else
        do s = s0, s1
          call region_floor(old, g%ncell + s, xn)
        end do
      end if
      ! (the halves' volumes as `remap_swept_blockers` found them for
      ! these nodes: the same operations, the same numbers, taken again
      ! rather than stored there and read back, which costs more memory
      ! traffic than the arithmetic)
      o = sum(xn, 2)/8.0_wp
      do j = 1, 8
        xn(:, j) = xn(:, j) - o
      end do
      call half_points(xn, pts)
      call half_dets(pts, det6)
      if (.not. all(det6 > 0.0_wp)) old%uniform(c) = .true.
      ! the reconstruction's mass in each subcell
      msub = 0.0_wp
      ! (set whole below for a pure cell that is not tangled)
      if (s0 /= 0 .or. old%uniform(c)) then
        old%wv(:, ic) = 0.0_wp
        old%ws(:, :, ic) = 0.0_wp
        old%sub(:, :, ic) = 0.0_wp
      end if
      if (s0 == 0 .and. .not. old%uniform(c)) then
        ! (a pure cell's subcells whole: their mass and weights below;
        ! summed here, then stored)
        sub = 0.0_wp
        ! (unrolled whole: the halves' corners and points by constant indices)
        !GCC$ unroll 48
        do i = 1, 48
          v = det6(i)/6.0_wp
          sub(1, half_corner(i)) = sub(1, half_corner(i)) + v
          sub(2:4, half_corner(i)) = sub(2:4, half_corner(i)) + &
            0.25_wp*v*(pts(:, 1) + pts(:, half_hv(2, i)) + pts(:, half_hv(3, i)) + pts(:, half_hv(4, i)))
        end do
        call copy_values(32, sub, old%sub(1, 1, ic))
      end if
      do i = 1, 48
        if (old%uniform(c) .or. s0 == 0) exit
        do j = 1, 4
          t(:, j) = pts(:, half_hv(j, i))
        end do
        do s = s0, s1
          if (.not. mx%mass(s) > 0.0_wp) cycle
          call region_planes(old, s0, s, o, pn, pd, nm)
          call region_piece(t, pn(:, 1:nm), pd(1:nm), v, m)
          if (.not. v > 0.0_wp) cycle
          msub(half_corner(i)) = msub(half_corner(i)) + region_mass(g%ncell + s, v, m, o)
          old%wv(half_corner(i), ic) = old%wv(half_corner(i), ic) + old%wreg(g%ncell + s)*v
          old%ws(:, half_corner(i), ic) = old%ws(:, half_corner(i), ic) + old%wreg(g%ncell + s)*(m + o*v)
        end do
      end do
      if (old%uniform(c)) then
        old%wv(:, ic) = 0.0_wp
        old%ws(:, :, ic) = 0.0_wp
        cycle
      end if
      if (s0 == 0) then
        ! (all linear in a piece's volume and moment: once per subcell)
        do j = 1, 8
          v = sub(1, j)
          m = sub(2:4, j)
          msub(j) = region_mass(c, v, m, o)
          old%wv(j, ic) = old%wreg(c)*v
          old%ws(:, j, ic) = old%wreg(c)*(m + o*v)
        end do
      end if
      mc = sum(h%mcorner(:, c))
      do j = 1, 8
        old%ushift(:, c) = old%ushift(:, c) + (h%mcorner(j, c) - msub(j))*ua(:, j)
      end do
      old%ushift(:, c) = old%ushift(:, c)/mc
      kc = 0.0_wp
      ksum = 0.0_wp
      ! (about the cell's mean velocity: `old_t`)
      do j = 1, 8
        kc = kc + 0.5_wp*h%mcorner(j, c)*sum((ua(:, j) - old%ucell(:, c))**2)
        ksum = ksum + 0.5_wp*msub(j)*sum((ua(:, j) + old%ushift(:, c) - old%ucell(:, c))**2)
      end do
      old%kshift(c) = (kc - ksum)/mc
    end do
    !$omp end parallel do

  contains

    !> The reconstructed mass of region r in a piece of volume v and first
    !> moment m (both about the cell's centre o), as `deposit` computes it.
    !> (o passed: the loop's private copy, not the host's)
    real(wp) function region_mass(r, v, m, o)
      integer, intent(in) :: r
      real(wp), intent(in) :: v, m(3), o(3)
      region_mass = old%rho(r)*v + dot_product(old%grho(:, r), m - (old%xr(:, r) - o)*v)
    end function region_mass
  end subroutine subcell_shifts

  !> A cell's mean velocity ucell (its corner masses mc, Eq. 16, and corner
  !> velocities ua), the mean of its corner velocities uref and its
  !> kinetic energy per unit mass about ucell, kcell (`old_t`).
  pure subroutine mean_velocity(mc, ua, ucell, uref, kcell)
    real(wp), intent(in) :: mc(8), ua(3, 8)
    real(wp), intent(out) :: ucell(3), uref(3), kcell
    integer :: a
    ucell = 0.0_wp
    kcell = 0.0_wp
    uref = 0.0_wp
    do a = 1, 8
      ucell = ucell + mc(a)*ua(:, a)
      uref = uref + ua(:, a)
    end do
    ucell = ucell/sum(mc)
    uref = 0.125_wp*uref
    do a = 1, 8
      kcell = kcell + 0.5_wp*mc(a)*sum((ua(:, a) - ucell)**2)
    end do
    kcell = kcell/sum(mc)
  end subroutine mean_velocity

  !> The second-order part of the velocity remap: about each node n, the
  !> velocity u_n + G_n (x - X_n) over its control volume (the subcells
  !> around it, Fig. 11), G_n the limited least-squares gradient over the
  !> neighbouring nodes (`remap_limited_gradients` on the dual block: its
  !> cells are the nodes, its nodes the cell centres, face centres and edge
  !> midpoints around them; Barth-Jespersen keeps u_n + G_n (x - X_n) at the
  !> dual cell's corners within the neighbours' velocities). A fragment of a
  !> region r of that control volume (volume v, first moment m) adds
  !>   w_r G_n (m - X_n v)
  !> to the momentum it carries (`deposit`), w_r the region's smallest
  !> density (`region_floor`): its velocity is then u + (w_r/rho(x_f))
  !> G_n (x_f - X_n), within the limited range whatever the densities, and
  !> X_n, the centroid of the moved subcells around n weighted by w_r, makes
  !> these terms add up to zero over the node: momentum is conserved exactly
  !> (and the kinetic energy terms u_n . w_r G_n (m - X_n v) with it). A
  !> uniform velocity has G_n = 0. Subcells of unchanged or tangled cells
  !> (copied, or handing out their mean velocity) take no part.
  subroutine velocity_gradients(g, old, u, err)
    type(grid_t), intent(in) :: g
    type(old_t), intent(inout) :: old
    real(wp), intent(in) :: u(:, :)
    type(error_t), allocatable, intent(inout) :: err
    real(wp), allocatable :: wsum(:), xd(:, :)
    logical, allocatable :: has(:)
    type(grid_index_t) :: dual
    integer :: c, a, n, i, j, k, m, m0, stat, ic, doff(8)
    real(wp) :: nan
    character(len=200) :: msg

    allocate(wsum(g%nnode), has(g%nnode), xd(3, (g%ni + 2)*(g%nj + 2)*(g%nk + 2)), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the velocity gradient work arrays'))
      return
    end if
    ! (the changed cells' nodes: xdual is zero there, `prepare_old`)
    do i = 1, size(old%lnode)
      wsum(old%lnode(i)) = 0.0_wp
    end do
    do ic = 1, size(old%lchanged)
      c = old%lchanged(ic)
      n = g%node0(c)
      do a = 1, 8
        wsum(n + g%corner_offset(a)) = wsum(n + g%corner_offset(a)) + old%wv(a, ic)
        ! (dst = dst + src by `add_values`)
        call add_values(3, old%ws(1, a, ic), old%xdual(1, n + g%corner_offset(a)))
      end do
    end do
    ! (a changed node's gradient reads the nodes next to it: the near
    ! cells' nodes, where has is set)
    do ic = 1, size(old%lnear)
      n = g%node0(old%lnear(ic))
      do a = 1, 8
        has(n + g%corner_offset(a)) = .false.
      end do
    end do
    do i = 1, size(old%lnode)
      n = old%lnode(i)
      has(n) = wsum(n) > 0.0_wp
      if (has(n)) old%xdual(:, n) = old%xdual(:, n)/wsum(n)
    end do
    if (.not. any(has(old%lnode))) return
    nan = ieee_value(1.0_wp, ieee_quiet_nan)
    ! the dual block's nodes: the mean of the grid nodes (i, j, k) with
    ! i in {I-1, I} within 0..ni (and so on): cell centres inside, face
    ! centres, edge midpoints and the nodes themselves on the boundary;
    ! only the corners of the dual cells of nodes with a gradient (the
    ! gradients read no other)
    dual = grid_index(g%ni + 1, g%nj + 1, g%nk + 1)
    ! (a dual node is a corner of up to eight dual cells: each is placed
    ! once, marked first by a NaN in every one the gradients read)
    ! (the index `grid_node` gives, written out: no call per node; the
    ! eight corners (i + di, j + dj, k + dk_) by their offsets from the
    ! first, a = 1 + di + 2 dj + 4 dk_, without three loops' overhead per
    ! node)
    do a = 1, 8
      doff(a) = mod(a - 1, 2) + dual%sx*mod((a - 1)/2, 2) + dual%sxy*((a - 1)/4)
    end do
    do ic = 1, size(old%lnode)
      if (.not. has(old%lnode(ic))) cycle
      call g%node_ijk(old%lnode(ic), i, j, k)
      m0 = dual%nbase + i + dual%sx*j + dual%sxy*k
      do a = 1, 8
        xd(1, m0 + doff(a)) = nan
      end do
    end do
    ! (m0, not m: `dual_node` sets m)
    do ic = 1, size(old%lnode)
      if (.not. has(old%lnode(ic))) cycle
      call g%node_ijk(old%lnode(ic), i, j, k)
      m0 = dual%nbase + i + dual%sx*j + dual%sxy*k
      do a = 1, 8
        if (ieee_is_nan(xd(1, m0 + doff(a)))) call dual_node(i + mod(a - 1, 2), j + mod((a - 1)/2, 2), k + (a - 1)/4)
      end do
    end do
    call remap_limited_gradients(g%ni + 1, g%nj + 1, g%nk + 1, xd, u, old%xdual, has, has, old%gu, err, &
                                 cells=old%lnode)

  contains

    !> The position of dual node (id, jd, kd).
    subroutine dual_node(id, jd, kd)
      integer, intent(in) :: id, jd, kd
      integer :: ii, jj, kk, nsum, n0
      real(wp) :: xs(3)
      m = dual%node(id, jd, kd)
      if (id >= 1 .and. id <= g%ni .and. jd >= 1 .and. jd <= g%nj .and. kd >= 1 .and. kd <= g%nk) then
        ! (a cell centre: its eight nodes in the loops' order below, the
        ! same sum)
        n0 = g%nbase + (id - 1) + g%sx*(jd - 1) + g%sxy*(kd - 1)
        xs = 0.0_wp
        xs = xs + g%x(:, n0)
        xs = xs + g%x(:, n0 + 1)
        xs = xs + g%x(:, n0 + g%sx)
        xs = xs + g%x(:, n0 + g%sx + 1)
        xs = xs + g%x(:, n0 + g%sxy)
        xs = xs + g%x(:, n0 + g%sxy + 1)
        xs = xs + g%x(:, n0 + g%sxy + g%sx)
        xs = xs + g%x(:, n0 + g%sxy + g%sx + 1)
        xd(:, m) = xs/8.0_wp
        return
      end if
      xd(:, m) = 0.0_wp
      nsum = 0
      do kk = max(kd - 1, 0), min(kd, g%nk)
        do jj = max(jd - 1, 0), min(jd, g%nj)
          do ii = max(id - 1, 0), min(id, g%ni)
            xd(:, m) = xd(:, m) + g%x(:, g%nbase + ii + g%sx*jj + g%sxy*kk)
            nsum = nsum + 1
          end do
        end do
      end do
      xd(:, m) = xd(:, m)/real(nsum, wp)
    end subroutine dual_node
  end subroutine velocity_gradients

  !> The regions of cell c as a slot range: s0 = s1 = 0 for a pure cell (its
  !> one region is the cell), else its first and last mixed-cell slot.
  pure subroutine region_slots(h, mx, c, s0, s1)
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: c
    integer, intent(out) :: s0, s1
    s0 = 0
    s1 = 0
    if (h%mat(c) > 0) return
    s0 = mx%start(-h%mat(c))
    s1 = mx%start(-h%mat(c) + 1) - 1
  end subroutine region_slots

  !> The planes of the region of slot s of a mixed cell whose slots start at
  !> s0 (nested dissection): its own plane, and the outer side of the planes
  !> of the slots before it, shifted to coordinates about o.
  pure subroutine region_planes(old, s0, s, o, pn, pd, nm)
    type(old_t), intent(in) :: old
    integer, intent(in) :: s0, s
    real(wp), intent(in) :: o(3)
    real(wp), intent(inout) :: pn(:, :), pd(:)
    integer, intent(out) :: nm
    integer :: j
    nm = 0
    do j = s0, s
      nm = nm + 1
      if (j < s) then
        pn(:, nm) = -old%pn(:, j)
        pd(nm) = -(old%pd(j) - dot_product(old%pn(:, j), o))
      else
        pn(:, nm) = old%pn(:, j)
        pd(nm) = old%pd(j) - dot_product(old%pn(:, j), o)
      end if
    end do
  end subroutine region_planes

  ! ------------------------------------------------------------ new side

  !> How many of the new cells `cells` hold a material outside the bounds
  !> the intersection keeps: a material with volume (more than vf_min of
  !> the cell) whose mass is not positive, or whose density or specific
  !> energy lies outside the range of its regions in the old cells within
  !> two index steps (the stencils of the regions the swept faces take
  !> from; 1e-9 relative slack: round-off), and a sliver (merged into
  !> another material) whose mass is negative beyond 1e-9 of the cell's. The
  !> swept faces keep these bounds by construction where the regions they
  !> take from lie next to their faces; a mixed cell's planes extended past
  !> it, or a region swept out of a thin material layer, can break them.
  integer function swept_unbounded(g, h, mx, old, cells, avol, amass, aie, vf_min, bad_cell) result(nbad)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    type(old_t), intent(in) :: old
    integer, intent(in) :: cells(:)
    real(wp), intent(in) :: avol(:, :), amass(:, :), aie(:, :), vf_min
    !> (ncell) set at each of cells: whether it broke a bound
    logical, intent(inout) :: bad_cell(:)
    real(wp), parameter :: slack = 1.0e-9_wp
    real(wp) :: rlo, rhi, elo, ehi, vtot, mtot, rho, e
    integer :: i, c, k, ci, cj, ck, oi, oj, ok_, co, s, r
    logical :: bad, found

    nbad = 0
    !$omp parallel do default(none) shared(g, h, mx, old, cells, avol, amass, aie, vf_min, bad_cell) &
    !$omp private(i, c, k, ci, cj, ck, oi, oj, ok_, co, s, r, bad, found, rlo, rhi, elo, ehi, vtot, mtot, rho, e) &
    !$omp reduction(+:nbad) schedule(static)
    do i = 1, size(cells)
      c = cells(i)
      call g%cell_ijk(c, ci, cj, ck)
      vtot = sum(avol(:, c))
      mtot = sum(amass(:, c))
      bad = .not. mtot > 0.0_wp
      do k = 1, size(avol, 1)
        if (bad) exit
        if (.not. avol(k, c) > vf_min*vtot) then
          bad = amass(k, c) < -slack*mtot
          cycle
        end if
        if (.not. amass(k, c) > 0.0_wp) then
          bad = .true.
          exit
        end if
        ! the cells within one index step first: their bounds lie within
        ! those of the cells within two, and each test below only loosens
        ! as the bounds widen, so a material within the first is within
        ! the second (the 27 cells settle most, not the 125)
        do r = 1, 2
          rlo = huge(1.0_wp)
          rhi = -huge(1.0_wp)
          elo = huge(1.0_wp)
          ehi = -huge(1.0_wp)
          found = .false.
          do ok_ = max(g%clo(3), ck - r), min(g%chi(3), ck + r)
            do oj = max(g%clo(2), cj - r), min(g%chi(2), cj + r)
              do oi = max(g%clo(1), ci - r), min(g%chi(1), ci + r)
                co = c + (oi - ci) + g%cx*(oj - cj) + g%cxy*(ok_ - ck)
                if (.not. old%near(co)) cycle
                if (h%mat(co) == k) then
                  call widen(old%rho(co), old%e(co), found, rlo, rhi, elo, ehi)
                else if (h%mat(co) <= 0) then
                  do s = mx%start(-h%mat(co)), mx%start(-h%mat(co) + 1) - 1
                    if (mx%mat(s) == k .and. mx%mass(s) > 0.0_wp) &
                      call widen(old%rho(g%ncell + s), old%e(g%ncell + s), found, rlo, rhi, elo, ehi)
                  end do
                end if
              end do
            end do
          end do
          rho = amass(k, c)/avol(k, c)
          e = aie(k, c)/amass(k, c)
          ! (no slack below zero: a cold material stays cold, not negative by
          ! a round-off the intersection does not make)
          bad = .not. found .or. rho < rlo - slack*abs(rlo) .or. rho > rhi + slack*abs(rhi) .or. &
                e < elo - slack*max(abs(elo), abs(ehi)) .or. e > ehi + slack*max(abs(elo), abs(ehi)) .or. &
                (elo >= 0.0_wp .and. e < 0.0_wp)
          if (.not. bad) exit
        end do
      end do
      bad_cell(c) = bad
      if (bad) nbad = nbad + 1
    end do
    !$omp end parallel do

  contains

    !> Widens the bounds by a region's density rr and energy er (the
    !> bounds passed: the loop's private copies, which host association
    !> would not see).
    pure subroutine widen(rr, er, found_, rlo_, rhi_, elo_, ehi_)
      real(wp), intent(in) :: rr, er
      logical, intent(inout) :: found_
      real(wp), intent(inout) :: rlo_, rhi_, elo_, ehi_
      found_ = .true.
      rlo_ = min(rlo_, rr)
      rhi_ = max(rhi_, rr)
      elo_ = min(elo_, er)
      ehi_ = max(ehi_, er)
    end subroutine widen
  end function swept_unbounded

  !> Adds sgn times the totals of the cells and nodes given (mass, momentum,
  !> internal and kinetic energy, as `hydro_totals` sums them over the grid)
  !> to acc, exactly: with -1 before the remap and +1 after it, over every
  !> cell and node it may write, acc is what it changed in the whole grid.
  pure subroutine totals_of(h, cells, nodes, sgn, acc)
    type(hydro_t), intent(in) :: h
    integer, intent(in) :: cells(:), nodes(:)
    real(wp), intent(in) :: sgn
    type(xsum_t), intent(inout) :: acc(6)
    integer :: i, c, n, d
    do i = 1, size(cells)
      c = cells(i)
      call xsum_add(acc(1), sgn*h%mass(c))
      call xsum_add(acc(5), sgn*h%mass(c)*h%e(c))
    end do
    do i = 1, size(nodes)
      n = nodes(i)
      do d = 1, 3
        call xsum_add(acc(1 + d), sgn*h%mnode(n)*h%u(d, n))
      end do
      call xsum_add(acc(6), sgn*0.5_wp*h%mnode(n)*dot_product(h%u(:, n), h%u(:, n)))
    end do
  end subroutine totals_of

  !> The scales of the conservation check (remap_stats_t scale) over the
  !> cells and nodes given.
  pure function magnitudes(h, cells, nodes) result(scale)
    type(hydro_t), intent(in) :: h
    integer, intent(in) :: cells(:), nodes(:)
    real(wp) :: scale(3)
    integer :: i, n
    scale = 0.0_wp
    do i = 1, size(cells)
      scale(1) = scale(1) + h%mass(cells(i))
      scale(2) = scale(2) + h%mass(cells(i))*h%e(cells(i))
    end do
    do i = 1, size(nodes)
      n = nodes(i)
      scale(2) = scale(2) + 0.5_wp*h%mnode(n)*dot_product(h%u(:, n), h%u(:, n))
      scale(3) = scale(3) + h%mnode(n)*norm2(h%u(:, n))
    end do
    scale(2) = abs(scale(2))
  end function magnitudes

  !> The statistics of an Euler step remapped in parts (`remap_swept_blockers`'
  !> parts): part's added to total (counts, times, energies and the open
  !> faces' flows summed, defects and reaches the largest; the copied cells
  !> are the last part's).
  pure subroutine remap_stats_add(total, part)
    type(remap_stats_t), intent(inout) :: total
    type(remap_stats_t), intent(in) :: part
    type(remap_stats_t) :: sum_
    integer :: q
    sum_ = part
    do q = 1, size(sum_%flow)
      call xsum_add(sum_%flow(q), xsum_value(total%flow(q)))
    end do
    call remap_stats_flows(sum_)
    do q = 1, size(sum_%change)
      call xsum_add(sum_%change(q), xsum_value(total%change(q)))
    end do
    sum_%change_known = total%change_known .and. part%change_known
    sum_%scale = max(total%scale, part%scale)
    sum_%cells_remapped = total%cells_remapped + part%cells_remapped
    sum_%cells_swept = total%cells_swept + part%cells_swept
    sum_%swept_unbounded = total%swept_unbounded + part%swept_unbounded
    sum_%reach = max(total%reach, part%reach)
    sum_%mof_cells = total%mof_cells + part%mof_cells
    sum_%mof_iterations = total%mof_iterations + part%mof_iterations
    sum_%mof_carried = total%mof_carried + part%mof_carried
    sum_%mof_not_converged = total%mof_not_converged + part%mof_not_converged
    sum_%mof_err_max = max(total%mof_err_max, part%mof_err_max)
    sum_%slivers_merged = total%slivers_merged + part%slivers_merged
    sum_%volume_defect = max(total%volume_defect, part%volume_defect)
    sum_%given_defect = max(total%given_defect, part%given_defect)
    sum_%regions_rescaled = total%regions_rescaled + part%regions_rescaled
    sum_%ke_to_internal = total%ke_to_internal + part%ke_to_internal
    sum_%cells_deficit = total%cells_deficit + part%cells_deficit
    sum_%deficit_moved = total%deficit_moved + part%deficit_moved
    sum_%deficit_by_mass = total%deficit_by_mass + part%deficit_by_mass
    sum_%momentum_constrained = total%momentum_constrained + part%momentum_constrained
    sum_%t_prepare = total%t_prepare + part%t_prepare
    sum_%t_intersect = total%t_intersect + part%t_intersect
    sum_%t_assemble = total%t_assemble + part%t_assemble
    sum_%swept_parts = total%swept_parts + part%swept_parts
    total = sum_
  end subroutine remap_stats_add

  !> The volume fraction below which a material of a new cell is a sliver,
  !> merged into the cell's largest (`assemble`): vf_min, or on the
  !> swept-face path (swept) the larger swept_vf_min. That path shares a
  !> region swept out of a mixed cell among its materials by the cell's
  !> planes extended past it; where the interface curves, a plane that
  !> grazes a swept region leaves a sliver of the other material that an
  !> exact intersection would not, each such sliver is carried on from
  !> cell to cell by its own planes, and its MoF fit is ill-posed. On the
  !> TNT octant at 32^3 (Eulerian, every step by swept faces) a threshold
  !> of 1e-9 left 1,188 cells with a TNT fraction below 1e-4, up to 8 mm
  !> ahead of the 33 mm contact at 7 us, where the intersection leaves 18.
  !> A material's mass is then conserved up to what its slivers give to the
  !> others (the total mass, momentum and energy to round-off): on that
  !> octant 3.5e-7 of the charge's mass over the run at the default 1e-5
  !> (6e-6 at 1e-4, whose merges also spoil a uniform flow's pressure at a
  !> density ratio of 1e6: input/README.md).
  pure real(wp) function sliver_fraction(par, swept) result(vf)
    type(remap_params_t), intent(in) :: par
    logical, intent(in) :: swept
    vf = par%vf_min
    if (swept) vf = max(vf, par%swept_vf_min)
  end function sliver_fraction

  !> How many of the cells `own` would move from the grid g%x to xnew and
  !> cannot take the swept-face path (`remap_new_cell`): a changed cell can
  !> if it is pure amid cells of its own material (or mixed is set), not
  !> tangled, its nodes moved at most smax times its shortest
  !> old edge (the swept regions stay next to the face that sweeps them,
  !> and the cell keeps most of its own content), and its faces on the
  !> grid's boundary sweep no volume unless they are inflow or outflow faces
  !> (nodes that slide along a plane wall: there is no cell beyond to take
  !> it from). The path is all or nothing: what an old cell gives away adds
  !> up to its volume only if every new cell around it takes its share the
  !> same way, so the caller adds the count over the whole grid and sets
  !> `remap_params_t`'s swept where it is 0.
  integer function remap_swept_blockers(g, h, bc, xnew, smax, mixed, own, parts, moved, work, blockers, rows) &
    result(nblock)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: xnew(:, :), smax
    !> mixed cells allowed (else a changed cell must be pure, amid cells of
    !> its own material only)
    logical, intent(in) :: mixed
    logical, intent(in), optional :: own(:)   !< (absent: every cell)
    !> the equal parts of the straight way from g%x to xnew that would each
    !> move every changed cell's nodes by at most smax of its shortest edge
    !> (0: a cell of another material around a changed one blocks in any
    !> part; each part's tangles and boundary faces are its own to test)
    integer, intent(out), optional :: parts
    !> the cells that move (every one, whatever own), in increasing order:
    !> `remap_euler_step`'s moved, for a remap to the same xnew
    integer, allocatable, intent(out), optional :: moved(:)
    !> the caller's work arrays (`remap_euler_step`; absent: this call's)
    type(remap_work_t), intent(inout), optional :: work
    !> the cells counted (those of own that move and cannot), in
    !> increasing order
    integer, allocatable, intent(out), optional :: blockers(:)
    !> g%moved_rows, where xnew is the grid they refer to (`moved_cells`)
    logical, intent(in), optional :: rows(:)
    real(wp) :: xo(3, 8), xn(3, 8), o(3), opts(3, 27), pts(3, 27), det6(48), hmin2, dmax2, vw(48), mw(48, 3), vb, rmax
    logical :: other, wall(6)
    integer :: c, ci, cj, ck, oi, oj, ok_, d, e, a, f, nb(3), i, stat, nt
    logical :: ok
    logical, allocatable :: changed(:), blocks(:)
    integer, allocatable :: list(:)
    type(error_t), allocatable :: err

    nblock = 1
    if (present(parts)) parts = 0
    if (present(blockers)) blockers = [integer ::]
    ! (unchanged cells are copied: only the changed ones are looked at)
    if (present(work)) then
      call marks_ready(work%old, g%ncell, g%nnode, stat)
      if (stat /= 0) return
      call moved_cells(g, xnew, work%old%changed, list, err, rows)
      if (allocated(err)) then
        work%old%changed = .false.
        return
      end if
      work%old%changed(list) = .false.
    else
      allocate(changed(g%ncell), stat=stat)
      if (stat /= 0) return
      changed = .false.
      call moved_cells(g, xnew, changed, list, err, rows)
      if (allocated(err)) return
    end if
    if (present(moved)) moved = list
    if (.not. smax > 0.0_wp) return
    if (present(own)) list = pack(list, own(list))
    nblock = 0
    rmax = 0.0_wp
    other = .false.
    allocate(blocks(size(list)), stat=stat)
    if (stat /= 0) then
      nblock = 1
      return
    end if
    !$omp parallel do default(none) shared(g, h, bc, xnew, smax, mixed, list, blocks) &
    !$omp reduction(+:nblock) reduction(max:rmax) reduction(.or.:other) &
    !$omp private(i, c, ci, cj, ck, oi, oj, ok_, d, e, a, f, nb, ok, xo, xn, o, opts, pts, det6, wall, hmin2, &
    !$omp dmax2, vw, mw, vb, nt) schedule(static)
    do i = 1, size(list)
      c = list(i)
      call g%cell_ijk(c, ci, cj, ck)
      call block_gather(g%ni, g%nj, ci, cj, ck, g%x, xo)
      call block_gather(g%ni, g%nj, ci, cj, ck, xnew, xn)
      ok = mixed .or. h%mat(c) > 0
      if (.not. mixed) then
        do ok_ = max(g%clo(3), ck - 1), min(g%chi(3), ck + 1)
          do oj = max(g%clo(2), cj - 1), min(g%chi(2), cj + 1)
            do oi = max(g%clo(1), ci - 1), min(g%chi(1), ci + 1)
              ok = ok .and. h%mat(c + (oi - ci) + g%cx*(oj - cj) + g%cxy*(ok_ - ck)) == h%mat(c)
            end do
          end do
        end do
      end if
      if (.not. ok) other = .true.
      hmin2 = shortest_edge2(xo)
      dmax2 = 0.0_wp
      do a = 1, 8
        dmax2 = max(dmax2, sum((xn(:, a) - xo(:, a))**2))
      end do
      if (ok) rmax = max(rmax, sqrt(dmax2/hmin2))
      ok = ok .and. dmax2 <= smax**2*hmin2
      ! the faces on the grid's boundary that must sweep nothing
      do f = 1, 6
        nb = [ci, cj, ck] + face_step(:, f)
        wall(f) = .not. (all(nb >= g%clo .and. nb <= g%chi) .or. bc%kind(f) == BC_INFLOW .or. &
                         bc%kind(f) == BC_OUTFLOW)
      end do
      if (ok) then
        ! (about the old cell's centre; the new cell's points only for
        ! such faces)
        o = sum(xo, 2)/8.0_wp
        do a = 1, 8
          xo(:, a) = xo(:, a) - o
        end do
        call half_points(xo, opts)
        if (any(wall)) then
          do a = 1, 8
            xn(:, a) = xn(:, a) - o
          end do
          call half_points(xn, pts)
        end if
        ! not tangled (as `subcell_shifts` finds it)
        call half_dets(opts, det6)
        ok = ok .and. all(det6 > 0.0_wp)
        vb = 0.0_wp
        if (any(wall)) vb = abs(hex_volume(xo))
        ! (the wall faces' triangles in one call: `swept_walls`)
        if (any(wall)) then
          call swept_walls(opts, pts, wall, nt, vw, mw)
          ok = ok .and. all(abs(vw(1:nt)) <= 1.0e-12_wp*vb)
        end if
      end if
      blocks(i) = .not. ok
      if (.not. ok) nblock = nblock + 1
    end do
    !$omp end parallel do
    if (present(blockers)) blockers = pack(list, blocks)
    if (present(parts)) then
      parts = 0
      if (.not. other .and. rmax < real(huge(1), wp)*smax) parts = max(ceiling(rmax/smax), 1)
    end if
  end function remap_swept_blockers

  !> The square of the shortest of the hexahedron xo's twelve edges.
  pure function shortest_edge2(xo) result(h2)
    real(wp), intent(in) :: xo(3, 8)
    real(wp) :: h2
    integer :: d, e
    h2 = huge(1.0_wp)
    do d = 1, 3
      do e = 1, 4
        h2 = min(h2, sum((xo(:, hex_edges(2, e, d)) - xo(:, hex_edges(1, e, d)))**2))
      end do
    end do
  end function shortest_edge2

  !> The first part of the way from g%x to xnew, as far as the swept-face
  !> path can take it at once (`remap_swept_blockers`' distance test): every
  !> node of the cells `cells` (those that move from g%x to xnew, as
  !> `remap_swept_blockers`' moved gives them) goes straight towards xnew,
  !> by at most smax times the shortest edge of the cells around it (in
  !> g%x); the other nodes are at xnew already. xk: the part's grid;
  !> arrived: every node reached xnew; r: the largest fraction of the way
  !> that keeps every node within its bound (both over the nodes of the
  !> cells of `cells` that are `own`, if given: a window's, the caller
  !> reducing them over the blocks). A node whose cells are long enough
  !> arrives at once, so the rest of the way moves (and remaps) only the
  !> cells around the nodes that still have far to go: where a smoothing
  !> straightens a compressed shell, not the whole of what it moved. Nodes
  !> stopped at different fractions of their way can tangle a cell that
  !> neither grid tangles: the caller then takes the same fraction r of the
  !> way for every node (`remap_part_folded`, `remap_part_uniform`).
  subroutine remap_part_target(g, xnew, smax, cells, xk, arrived, r, err, own)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: xnew(:, :), smax
    integer, intent(in) :: cells(:)
    real(wp), allocatable, intent(inout) :: xk(:, :)
    logical, intent(out) :: arrived
    real(wp), intent(out) :: r
    type(error_t), allocatable, intent(inout) :: err
    logical, intent(in), optional :: own(:)
    real(wp), allocatable :: lim(:)
    real(wp) :: xo(3, 8), hmin2, d(3), d2, a2
    integer :: i, c, ci, cj, ck, a, n, stat
    logical :: counted

    arrived = .true.
    r = 1.0_wp
    xk = xnew
    allocate(lim(g%nnode), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_part_target', error_no_memory('a node array'))
      return
    end if
    do i = 1, size(cells)
      do a = 1, 8
        lim(g%node0(cells(i)) + g%corner_offset(a)) = huge(1.0_wp)
      end do
    end do
    ! the square of the shortest edge of the moving cells around each node
    do i = 1, size(cells)
      c = cells(i)
      call g%cell_ijk(c, ci, cj, ck)
      call block_gather(g%ni, g%nj, ci, cj, ck, g%x, xo)
      hmin2 = shortest_edge2(xo)
      do a = 1, 8
        n = g%node0(c) + g%corner_offset(a)
        lim(n) = min(lim(n), hmin2)
      end do
    end do
    do i = 1, size(cells)
      counted = .true.
      if (present(own)) counted = own(cells(i))
      do a = 1, 8
        n = g%node0(cells(i)) + g%corner_offset(a)
        d = xnew(:, n) - g%x(:, n)
        d2 = sum(d**2)
        ! (a hair inside the bound, so that round-off does not fail its test)
        a2 = (1.0_wp - 1.0e-9_wp)**2*smax**2*lim(n)
        if (d2 <= a2) cycle
        xk(:, n) = g%x(:, n) + sqrt(a2/d2)*d
        if (.not. counted) cycle
        r = min(r, sqrt(a2/d2))
        arrived = .false.
      end do
    end do
  end subroutine remap_part_target

  !> Whether the part's grid xk tangles one of the cells `cells` (those
  !> `own`, if given), as `remap_swept_blockers` tests the next part's old
  !> cells (`remap_part_target`).
  logical function remap_part_folded(g, cells, xk, own) result(folded)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: cells(:)
    real(wp), intent(in) :: xk(:, :)
    logical, intent(in), optional :: own(:)
    real(wp) :: xo(3, 8), xc(3, 8), opts(3, 27), pts(3, 27), det6(48)
    integer :: i, ci, cj, ck, hv(4, 48), hc(48)
    folded = .false.
    do i = 1, size(cells)
      if (present(own)) then
        if (.not. own(cells(i))) cycle
      end if
      call g%cell_ijk(cells(i), ci, cj, ck)
      call block_gather(g%ni, g%nj, ci, cj, ck, xk, xo)
      xc = xo
      call halves_about(sum(xo, 2)/8.0_wp, xo, xc, opts, pts, hv, hc)
      call half_dets(opts, det6)
      folded = .not. all(det6 > 0.0_wp)
      if (folded) return
    end do
  end function remap_part_folded

  !> Every node of the cells `cells` the same fraction r of its way from g%x
  !> to xnew, in xk (`remap_part_target`).
  pure subroutine remap_part_uniform(g, xnew, cells, r, xk)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: xnew(:, :), r
    integer, intent(in) :: cells(:)
    real(wp), intent(inout) :: xk(:, :)
    integer :: i, a, n
    do i = 1, size(cells)
      do a = 1, 8
        n = g%node0(cells(i)) + g%corner_offset(a)
        xk(:, n) = g%x(:, n) + r*(xnew(:, n) - g%x(:, n))
      end do
    end do
  end subroutine remap_part_uniform

  !> The first of the two remaps of a hybrid Euler step (`euler_step`):
  !> every node at xnew but those of the cells `blockers` (the changed cells
  !> `remap_swept_blockers` finds cannot take the swept-face path) and of
  !> the cells around them (3 x 3 x 3), which stay at g%x. So the cells this
  !> first remap changes are those with a node outside that zone: none of
  !> them a blocker, each can take the swept-face path, and no face of a
  !> blocker moves (its nodes stay), so nothing is swept through it. The
  !> second remap, to xnew, moves only the zone's nodes: it changes the zone
  !> and the cells that share a node with it, by intersection. (Without the
  !> layer around the blockers, the cells remapped twice lie next to them:
  !> the TNT octant at 32^3 then turned 24 % more kinetic energy into heat
  !> than by intersection alone and its gauge peaks moved by up to 33 %;
  !> with it, 8 % and 3 %.)
  pure subroutine remap_hybrid_target(g, xnew, blockers, xk)
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: xnew(:, :)
    integer, intent(in) :: blockers(:)
    real(wp), allocatable, intent(inout) :: xk(:, :)
    integer :: i, a, n, ci, cj, ck, oi, oj, ok_, c
    xk = xnew
    do i = 1, size(blockers)
      call g%cell_ijk(blockers(i), ci, cj, ck)
      do ok_ = max(g%clo(3), ck - 1), min(g%chi(3), ck + 1)
        do oj = max(g%clo(2), cj - 1), min(g%chi(2), cj + 1)
          do oi = max(g%clo(1), ci - 1), min(g%chi(1), ci + 1)
            c = g%cell(oi, oj, ok_)
            do a = 1, 8
              n = g%node0(c) + g%corner_offset(a)
              xk(:, n) = g%x(:, n)
            end do
          end do
        end do
      end do
    end do
  end subroutine remap_hybrid_target

  !> Intersects the changed new cell c with the old cells within `reach`
  !> index steps: per material the volume, first moment, mass and internal
  !> energy that land in it, the momentum carried with the mass (pcell), per
  !> corner the momentum deviations and kinetic energy carried with the
  !> volume.
  subroutine remap_new_cell(g, h, mx, old, lat, given, given_sign, xnew, c, reach, avol, amom, amass, aie, pcell, &
                            cmom, cland, cdef, bins)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    type(old_t), intent(in) :: old
    !> the lattice path (`lattice_old_t`; off: every old cell clipped here)
    type(lattice_old_t), intent(in) :: lat
    integer(i8), intent(inout) :: given(:)
    real(wp), intent(in) :: given_sign
    real(wp), intent(in) :: xnew(:, :)
    integer, intent(in) :: c, reach
    real(wp), intent(out) :: avol(:), amom(:, :), amass(:), aie(:), pcell(:), cmom(:, :), cland(:)
    !> per corner: its volume less what the old grid gave it (a gap at an open face)
    real(wp), intent(out) :: cdef(:)
    !> the changed old cells binned (`remap_bins`; or not built): with a
    !> wide window (reach >= bins_reach_min) only the cells whose boxes
    !> meet this one's are visited, not every cell of the window
    type(remap_bins_t), intent(in) :: bins
    integer, allocatable :: near(:)
    integer :: nnear, il, w0(3), we(3)
    real(wp) :: alo(3), ahi(3)
    real(wp) :: xn(3, 8), o(3), det6(48), ht(3, 4, 48), hlo(3, 48), hhi(3, 48), hsg(48), hvol(48), hmom(3, 48), &
                xo(3, 8), lo(3), hi(3), olo(3, 48), ohi(3, 48), pn(3, 4 + max_mat), pd(4 + max_mat), &
                v, pts(3, 27), mid(3), qblo(3, 8), qbhi(3, 8), opts(3, 27), ot(3, 4), osg(48), on(3, 4, 48), &
                od(4, 48), ub(3), kemb, wb
    ! the sources' numbers (`source`, `deposit`), kept for the last few
    ! regions (tags rk: with their cell's) and nodes (tags nk) this cell's
    ! sources came from: entry ir of the region's, in of the node's
    integer, parameter :: nkeep = 8
    real(wp) :: rxo(3, nkeep), rrho(nkeep), rgrho(3, nkeep), rge(3, nkeep), re(nkeep), rsc(nkeep), rscrho(nkeep), &
                rgunit(nkeep), rub(3, nkeep), rke(nkeep), rw(nkeep), nu(3, nkeep), nxo(3, nkeep), ngu(3, 3, nkeep), &
                ndu(3, nkeep), urefc(3)
    integer :: rk(nkeep), nk(nkeep), nrk, nnk, ir, in
    ! the entry of node nb where the caller of `node_entry` knows it (0:
    ! known not held), so that no search is made; -1: not known
    integer :: in_hint
    logical :: runi(nkeep)
    ! whether `deposit` counts each fragment in given (else its caller
    ! sums them by source region in gsum, `swept_fluxes`)
    logical :: tally
    real(wp) :: gsum(nkeep)
    ! what `deposit` adds up, in arrays of this call (not through the
    ! dummies' descriptors at every fragment): avol, amom, amass, aie,
    ! pcell, cmom, cland, cdef while the fragments are booked
    real(wp) :: svol(max_mat), smom(3, max_mat), smass(max_mat), sie(max_mat), spc(4), scmom(3, 8), scland(8), &
                scdef(8)
    real(wp) :: tv(3, 4, 24), tvlo(3, 24), tvhi(3, 24), midn(3, 24), midd(24), tvn(3, 4, 24), tvd(4, 24)
    integer :: tvmask(24), tvsg(24)
    integer :: tmask(48), ci, cj, ck, oi, oj, ok_, co, s, s0, s1, &
               j, nm, kmat, t, i, kreg, ohv(4, 48), ocorner(48), isg, nb, n0c, live(24, 48), nlive(48), need(48)
    logical :: box

    call g%cell_ijk(c, ci, cj, ck)
    n0c = g%cell_node0(ci, cj, ck)
    tally = .true.
    nrk = 0
    nnk = 0
    in_hint = -1
    urefc = old%uref(:, c)
    ! (placed again rather than read back from `swept_low_faces`: the
    ! same operations, the same numbers, and less memory traffic than a
    ! stored copy)
    call block_gather(g%ni, g%nj, ci, cj, ck, xnew, xn)
    alo = minval(xn, 2)
    ahi = maxval(xn, 2)
    ! local coordinates about the new cell's centre: round-off scales with the cell
    o = sum(xn, 2)/8.0_wp
    do j = 1, 8
      xn(:, j) = xn(:, j) - o
    end do
    call half_points(xn, pts)
    ! (the sums start in `deposit`'s arrays, which `sums_out` copies to
    ! the dummies: no zeros written through their descriptors first)
    svol = 0.0_wp
    smom = 0.0_wp
    smass = 0.0_wp
    sie = 0.0_wp
    spc = 0.0_wp
    scmom = 0.0_wp
    scland = 0.0_wp
    scdef = 0.0_wp
    if (old%swept) then
      ! cdef, the gaps' measure, only where there are open faces
      if (any(old%open)) then
        ! (the halves' determinants as `tet_det` gives them, `half_dets`)
        call half_dets(pts, det6)
        do t = 1, 48
          scdef(half_corner(t)) = scdef(half_corner(t)) + det6(t)/6.0_wp
        end do
      end if
      call swept_fluxes()
      call sums_out()
      do kmat = 1, size(avol)
        amom(:, kmat) = amom(:, kmat) + avol(kmat)*o
      end do
      return
    end if
    do t = 1, 48
      tmask(t) = 0
      do j = 1, 4
        ht(:, j, t) = pts(:, half_hv(j, t))
        tmask(t) = ibset(tmask(t), half_hv(j, t) - 1)
      end do
      hlo(:, t) = minval(ht(:, :, t), 2)
      hhi(:, t) = maxval(ht(:, :, t), 2)
      v = tet_det(ht(:, :, t))
      hsg(t) = sign(1.0_wp, v)
      hvol(t) = abs(v)/6.0_wp
      hmom(:, t) = 0.25_wp*hvol(t)*(ht(:, 1, t) + ht(:, 2, t) + ht(:, 3, t) + ht(:, 4, t))
    end do
    ! the 24 tetrahedra (two halves each), their masks and the mid-plane
    ! (centre, face centre, edge midpoint) that splits them, oriented with
    ! the first half's corner on the inner side
    do t = 1, 24
      tv(:, 1:3, t) = ht(:, 1:3, 2*t - 1)
      tv(:, 4, t) = ht(:, 4, 2*t)
      tvmask(t) = ior(tmask(2*t - 1), tmask(2*t))
      tvmask(t) = ibclr(tvmask(t), half_hv(4, 2*t - 1) - 1)
      tvlo(:, t) = min(hlo(:, 2*t - 1), hlo(:, 2*t))
      tvhi(:, t) = max(hhi(:, 2*t - 1), hhi(:, 2*t))
      midn(:, t) = cross(ht(:, 2, 2*t - 1) - ht(:, 1, 2*t - 1), ht(:, 4, 2*t - 1) - ht(:, 1, 2*t - 1))
      midd(t) = dot_product(midn(:, t), ht(:, 1, 2*t - 1))
      if (dot_product(midn(:, t), ht(:, 3, 2*t - 1)) > midd(t)) then
        midn(:, t) = -midn(:, t)
        midd(t) = -midd(t)
      end if
      ! its face planes: an old piece wholly outside one of them misses it
      call tet_planes(tv(:, :, t), tvn(:, :, t), tvd(:, t), tvsg(t))
    end do
    lo = minval(xn, 2)
    hi = maxval(xn, 2)
    ! an axis-aligned box (the initial grid of a global rezone): its corners'
    ! subcells are the eight octant boxes, far fewer pieces than 48 halves
    box = is_box(xn)
    if (box) then
      mid = 0.5_wp*(lo + hi)
      do t = 1, 8
        do j = 1, 3
          if (btest(t - 1, j - 1)) then
            qblo(j, t) = mid(j)
            qbhi(j, t) = hi(j)
          else
            qblo(j, t) = lo(j)
            qbhi(j, t) = mid(j)
          end if
        end do
      end do
    end if
    if (box) then
      do t = 1, 8
        scdef(t) = product(qbhi(:, t) - qblo(:, t))
      end do
    else
      do t = 1, 48
        scdef(half_corner(t)) = scdef(half_corner(t)) + hsg(t)*hvol(t)
      end do
    end if
    ! the changed old cells within reach, in index order (an unchanged old
    ! cell is all in the identical new cell); through a wide window, those
    ! the bins list whose boxes meet this cell's (the others fail the box
    ! test below): the same cells in the same order
    nnear = -1
    if (allocated(bins%item) .and. reach >= bins_reach_min .and. .not. (box .and. lat%lt%on)) &
      call remap_bins_cells(bins, alo, ahi, near, nnear)
    if (nnear >= 0) then
      ! (the bins' cells are numbered as the grid's, `remap_bins_build`)
      j = 0
      do il = 1, nnear
        call g%cell_ijk(near(il), oi, oj, ok_)
        if (max(abs(oi - ci), abs(oj - cj), abs(ok_ - ck)) > reach) cycle
        if (any([oi, oj, ok_] < g%clo) .or. any([oi, oj, ok_] > g%chi)) cycle
        j = j + 1
        near(j) = near(il)
      end do
      nnear = j
    end if
    ! else the window's cells one by one (k, then j, then i)
    w0 = max(g%clo, [ci, cj, ck] - reach)
    we = min(g%chi, [ci, cj, ck] + reach) - w0 + 1
    do il = 1, merge(nnear, product(we), nnear >= 0)
      if (nnear >= 0) then
        co = near(il)
        call g%cell_ijk(co, oi, oj, ok_)
      else
        oi = w0(1) + mod(il - 1, we(1))
        oj = w0(2) + mod((il - 1)/we(1), we(2))
        ok_ = w0(3) + (il - 1)/(we(1)*we(2))
        co = g%cell(oi, oj, ok_)
        if (.not. old%changed(co)) cycle
      end if
      if (box .and. lat%lt%on) then
        call lattice_deposits(co)
        cycle
      end if
      call block_gather(g%ni, g%nj, oi, oj, ok_, g%x, xo)
      do j = 1, 8
        xo(:, j) = xo(:, j) - o
      end do
      if (any(maxval(xo, 2) < lo) .or. any(minval(xo, 2) > hi)) cycle
      ! the old cell's 48 halves: its subcells (corner velocities) and
      ! the signed pieces of any cell, convex or not
      call half_tets(xo, opts, ohv, ocorner)
      ! the planes of the halves that reach the new cell's box
      do i = 1, 48
        do j = 1, 4
          ot(:, j) = opts(:, ohv(j, i))
        end do
        olo(:, i) = min(min(ot(:, 1), ot(:, 2)), min(ot(:, 3), ot(:, 4)))
        ohi(:, i) = max(max(ot(:, 1), ot(:, 2)), max(ot(:, 3), ot(:, 4)))
        osg(i) = 0.0_wp
        if (any(ohi(:, i) < lo) .or. any(olo(:, i) > hi)) cycle
        ! (a half flat to round-off has no volume to give: sign 0, skipped)
        osg(i) = real(tet_sign(ot), wp)
        if (box .or. .not. abs(osg(i)) > 0.0_wp) cycle
        ! the new cell's tetrahedra it may meet (whatever the region),
        ! and its planes only where there are some
        call live_tets(olo(:, i), ohi(:, i), ot, live(:, i), nlive(i), need(i))
        if (nlive(i) == 0) then
          osg(i) = 0.0_wp
          cycle
        end if
        call tet_planes(ot, on(:, :, i), od(:, i), isg)
      end do
      call region_slots(h, mx, co, s0, s1)
      ! every material region of the old cell
      do s = s0, s1
        nm = 0
        if (s == 0) then
          kmat = h%mat(co)
          kreg = co
        else
          kmat = mx%mat(s)
          kreg = g%ncell + s
          if (.not. mx%mass(s) > 0.0_wp) cycle
          call region_planes(old, s0, s, o, pn(:, 5:), pd(5:), nm)
        end if
        do i = 1, 48
          if (.not. abs(osg(i)) > 0.0_wp) cycle
          ! the velocity and kinetic energy per unit mass its fragments carry
          ! (and, about the subcell's node, the velocity's linear part)
          call source(co, kreg, kmat, g%node0(co) + g%corner_offset(ocorner(i)))
          if (box) then
            do j = 1, 4
              ot(:, j) = opts(:, ohv(j, i))
            end do
            call clip_into_octants(ot, pn(:, 5:4 + nm), pd(5:4 + nm), osg(i))
          else
            pn(:, 1:4) = on(:, :, i)
            pd(1:4) = od(:, i)
            call clip_halves(pn, pd, 4 + nm, osg(i), live(1:nlive(i), i), need(i))
          end if
        end do
      end do
    end do
    call sums_out()
    ! first moments back to global coordinates
    do kmat = 1, size(avol)
      amom(:, kmat) = amom(:, kmat) + avol(kmat)*o
    end do

  contains

    !> `deposit`'s sums back to the dummies.
    subroutine sums_out()
      integer :: nm_
      nm_ = size(avol)
      avol = svol(1:nm_)
      amom = smom(:, 1:nm_)
      amass = smass(1:nm_)
      aie = sie(1:nm_)
      pcell = spc
      cmom = scmom
      cland = scland
      cdef = scdef
    end subroutine sums_out

    !> The swept-face path (`remap_params_t`'s swept): the new cell
    !> is its old cell plus what the faces of its subcells swept,
    !>   new subcell a = old subcell a + sum of the signed regions swept by
    !>   the 12 triangles that bound it (`remap_swept`),
    !> each region taken from the upwind subcell: a triangle on the cell's
    !> face takes what it sweeps into the cell from the subcell across the
    !> face at the same node (its regions' reconstructions, its node's
    !> velocity) and gives what it sweeps out of the cell from the cell's
    !> own; a triangle between two corners of the cell moves what it sweeps
    !> from one to the other. Old and new triangles bound the same 48
    !> halves as the intersection's pieces, so the fragments add up to the
    !> new cell and each old region gives away exactly its volume (what one
    !> cell takes through a face, the cell across it gives); `deposit`
    !> books them as the intersection's fragments. In a mixed old cell the
    !> subcells are cut by its MoF regions (as `subcell_shifts` cuts them),
    !> and a region swept from it is shared among its materials by the same
    !> planes (`swept_from`).
    subroutine swept_fluxes()
      ! acc: per corner, what pure sources give it, summed before it is
      ! booked (`deposit` is linear for one source): slot 1 the cell's own
      ! subcell at the corner, 1 + d its subcell across direction d, 4 + d
      ! the subcell at the corner of the cell across the face in direction d
      real(wp) :: sv(max_mat, 8), sm(3, max_mat, 8), v, m(3), tp(3, 3), tn(3, 3), acc(4, 7, 8), oc(3), &
                  tv(72), tm(72, 3), vs(max_mat), ms(3, max_mat)
      integer :: i, j, t, f, ia, ib, nbr(6), nx(3), s0c, s1c, s0, s1, s, d, slot, slot_in(6), irc, ink(8), k, irf(6), jc
      logical :: pure, pure_nbr(6), done_k(8), shared, fresh
      real(wp) :: ubk(3, 8), kembk(8), wbk(8)

      call block_gather(g%ni, g%nj, ci, cj, ck, g%x, xo)
      do j = 1, 8
        xo(:, j) = xo(:, j) - o
      end do
      call half_points(xo, opts)
      ! the old subcells stay where they were (region by region)
      call region_slots(h, mx, c, s0c, s1c)
      pure = s0c == 0
      acc = 0.0_wp
      if (.not. pure) then
        sv = 0.0_wp
        sm = 0.0_wp
      end if
      if (pure) then
        ! (their volumes and moments about the old centre oc, `subcell_shifts`)
        ! (the changed cell's entry: its place in lchanged, `swept_low_faces`)
        oc = opts(:, 1)
        jc = old%fslot(c)
        do j = 1, 8
          acc(1, 1, j) = old%sub(1, j, jc)
          acc(2:4, 1, j) = old%sub(2:4, j, jc) + old%sub(1, j, jc)*oc
        end do
      end if
      if (.not. pure) then
        ! (a changed mixed cell's, as `swept_budgets` found them)
        do s = s0c, s1c
          sv(s - s0c + 1, :) = old%skv(:, s)
          sm(:, s - s0c + 1, :) = old%skm(:, :, s)
        end do
        do j = 1, 8
          do s = s0c, s1c
            if (.not. abs(sv(s - s0c + 1, j)) > 0.0_wp) cycle
            call source(c, g%ncell + s, mx%mat(s), n0c + g%corner_offset(j))
            call deposit(sv(s - s0c + 1, j), sm(:, s - s0c + 1, j), j)
          end do
        end do
      end if
      ! the cells across the faces; on the grid's boundary the cell itself
      ! (a wall or symmetry face sweeps nothing; an open face's outflow
      ! leaves the grid, and the gap it opens is `open_faces`' to fill: 0)
      ! (unrolled: the faces' steps by constants)
      !GCC$ unroll 6
      do f = 1, 6
        nx = [ci, cj, ck] + face_step(:, f)
        nbr(f) = c
        if (all(nx >= g%clo .and. nx <= g%chi)) then
          nbr(f) = g%cell(nx(1), nx(2), nx(3))
        else if (old%open(f)) then
          nbr(f) = 0
        end if
      end do
      ! (whether the cell across each face is pure: the face's sources)
      do f = 1, 6
        pure_nbr(f) = .false.
        if (nbr(f) /= c .and. nbr(f) /= 0) pure_nbr(f) = h%mat(nbr(f)) > 0
      end do
      ! a pure cell whose faces take only from pure cells (or from none):
      ! every region goes to its slot of acc, as the general loop below
      ! books it, in the same order (the same sums), without its tests;
      ! slot_in(f), the slot a face's incoming region goes to (0: none)
      do f = 1, 6
        slot_in(f) = -1
        if (nbr(f) == c) slot_in(f) = 1
        if (nbr(f) == 0) slot_in(f) = 0
        if (pure_nbr(f)) slot_in(f) = 4 + (f + 1)/2
      end do
      ! the 72 triangles' swept regions (`swept_tri`): at once
      ! (`swept_cell`), or on that path with its low faces' and those of
      ! the cells across its high faces as `swept_low_faces` swept them
      ! (`shared_faces`)
      shared = .false.
      if (pure .and. all(slot_in >= 0)) call shared_faces(nbr, tv, tm, shared)
      if (.not. shared) call swept_cell(opts, pts, tv, tm)
      if (pure .and. all(slot_in >= 0)) then
        ! (unrolled whole: the halves' corners by constant indices)
        !GCC$ unroll 24
        do t = 1, 24
          f = (t - 1)/4 + 1
          do i = 2*t - 1, 2*t
            v = tv(i)
            slot = 1
            if (v > 0.0_wp) slot = slot_in(f)
            if (.not. abs(v) > 0.0_wp .or. slot == 0) cycle
            acc(1, slot, half_corner(i)) = acc(1, slot, half_corner(i)) + v
            acc(2:4, slot, half_corner(i)) = acc(2:4, slot, half_corner(i)) + tm(i, :)
          end do
          v = tv(48 + t)
          if (.not. abs(v) > 0.0_wp) cycle
          ia = half_corner(2*t - 1)
          ib = half_corner(2*t)
          slot = tet_slot(t)
          if (v > 0.0_wp) then
            acc(1, slot, ia) = acc(1, slot, ia) + v
            acc(2:4, slot, ia) = acc(2:4, slot, ia) + tm(48 + t, :)
            acc(1, 1, ib) = acc(1, 1, ib) - v
            acc(2:4, 1, ib) = acc(2:4, 1, ib) - tm(48 + t, :)
          else
            acc(1, 1, ia) = acc(1, 1, ia) + v
            acc(2:4, 1, ia) = acc(2:4, 1, ia) + tm(48 + t, :)
            acc(1, slot, ib) = acc(1, slot, ib) - v
            acc(2:4, slot, ib) = acc(2:4, slot, ib) - tm(48 + t, :)
          end if
        end do
      end if
      do t = 1, 24
        if (pure .and. all(slot_in >= 0)) exit
        f = (t - 1)/4 + 1
        d = (f + 1)/2
        ia = half_corner(2*t - 1)
        ib = half_corner(2*t)
        ! on the face: (face centre, a, edge midpoint) and (face centre,
        ! edge midpoint, b), counter-clockwise seen from outside
        do i = 2*t - 1, 2*t
          v = tv(i)
          if (.not. abs(v) > 0.0_wp .or. (v > 0.0_wp .and. nbr(f) == 0)) cycle
          m = tm(i, :)
          if (v > 0.0_wp .and. nbr(f) /= c) then
            if (pure_nbr(f)) then
              acc(:, 4 + d, half_corner(i)) = acc(:, 4 + d, half_corner(i)) + [v, m]
            else if (swept_out(nbr(f), old%twin(i))) then
              ! (the region as the cell across the face split it, moved
              ! to this cell's frame)
              call region_slots(h, mx, nbr(f), s0, s1)
              do s = s0, s1
                vs(s - s0 + 1) = -old%sov(old%twin(i), s)
                ms(:, s - s0 + 1) = -old%som(:, old%twin(i), s) + vs(s - s0 + 1)*(old%so(:, s) - o)
              end do
              call book_parts(nbr(f), half_corner(i), s0, s1, vs, ms, half_corner(i), 0)
            else
              tp = opts(:, half_hv(2:4, i))
              tn = pts(:, half_hv(2:4, i))
              call swept_from(nbr(f), half_corner(i), tp, tn, v, m, half_corner(i), 0)
            end if
          else if (pure) then
            acc(:, 1, half_corner(i)) = acc(:, 1, half_corner(i)) + [v, m]
          else if (v < 0.0_wp .and. swept_out(c, i)) then
            ! (its own region swept out, as `swept_budgets` split it)
            vs(1:s1c - s0c + 1) = old%sov(i, s0c:s1c)
            ms(:, 1:s1c - s0c + 1) = old%som(:, i, s0c:s1c)
            call book_parts(c, half_corner(i), s0c, s1c, vs, ms, half_corner(i), 0)
          else
            tp = opts(:, half_hv(2:4, i))
            tn = pts(:, half_hv(2:4, i))
            call swept_from(c, half_corner(i), tp, tn, v, m, half_corner(i), 0)
          end if
        end do
        ! between corners a and b: (edge midpoint, centre, face centre),
        ! its normal pointing from a to b (b is a's neighbour across the
        ! direction of the edge)
        i = 2*t - 1
        v = tv(48 + t)
        if (.not. abs(v) > 0.0_wp) cycle
        m = tm(48 + t, :)
        if (pure) then
          slot = 1 + edge_dir(ia, ib)
          if (v > 0.0_wp) then
            acc(:, slot, ia) = acc(:, slot, ia) + [v, m]
            acc(:, 1, ib) = acc(:, 1, ib) - [v, m]
          else
            acc(:, 1, ia) = acc(:, 1, ia) + [v, m]
            acc(:, slot, ib) = acc(:, slot, ib) - [v, m]
          end if
        else
          tp = opts(:, [half_hv(4, i), 1, half_hv(2, i)])
          tn = pts(:, [half_hv(4, i), 1, half_hv(2, i)])
          call swept_from(c, merge(ib, ia, v > 0.0_wp), tp, tn, v, m, ia, ib)
        end if
      end do
      ! what the pure sources gave, one fragment per source and corner
      if (pure .and. all(slot_in >= 0)) then
        ! (the cell's own region: `source_region` once; its subcell at
        ! corner k, `source_node`, once for the fragments of slots 1-4 it
        ! gives; each neighbour's region once, and each node's entry
        ! (ink, 0: not yet) once: the numbers `source` would take at each.
        ! Only where no source was taken before (no mixed cell across a
        ! face): then at most 7 regions and 8 nodes, and `source` replaces
        ! none of the entries held here)
        call source_region(c, c, h%mat(c))
        irc = ir
        ink = 0
        irf = 0
        ! (no node's entry held yet: then each one taken below is in ink,
        ! and `node_entry` need not search)
        fresh = nnk == 0
        ! (the volume each region gives is counted once, its fragments'
        ! sum (gsum) rounded to `old_t`'s given units at the end, rather
        ! than each fragment rounded and counted on its own: the count
        ! differs by a few units of 2^-50 of the cell's volume, far below
        ! uncovered_tol, and the per-fragment division, rounding and
        ! atomic update are saved)
        tally = .false.
        gsum = 0.0_wp
        done_k = .false.
        do j = 1, 8
          ! (unrolled: each slot's source by constants)
          !GCC$ unroll 7
          do slot = 1, 7
            if (.not. abs(acc(1, slot, j)) > 0.0_wp) cycle
            if (slot <= 4) then
              k = j
              if (slot > 1) k = ieor(j - 1, ishft(1, slot - 2)) + 1
              kreg = c
              kmat = h%mat(c)
              ir = irc
              nb = n0c + g%corner_offset(k)
              if (.not. done_k(k)) then
                ! (node k's entry, if any, is ink(k): every entry taken
                ! here is)
                in_hint = merge(ink(k), -1, fresh)
                call source_node(nb)
                in_hint = -1
                done_k(k) = .true.
                if (.not. runi(ir)) ink(k) = in
                ubk(:, k) = ub
                kembk(k) = kemb
                wbk(k) = wb
              end if
              in = ink(k)
              ub = ubk(:, k)
              kemb = kembk(k)
              wb = wbk(k)
            else
              d = slot - 4
              f = 2*d - 1 + merge(1, 0, btest(j - 1, d - 1))
              if (irf(f) == 0) then
                call source_region(nbr(f), nbr(f), h%mat(nbr(f)))
                irf(f) = ir
              else
                kreg = nbr(f)
                kmat = h%mat(nbr(f))
                ir = irf(f)
              end if
              ! (`source_node` at node j, its entry found once)
              nb = n0c + g%corner_offset(j)
              if (runi(ir)) then
                ub = rub(:, ir)
              else
                if (ink(j) == 0) then
                  in_hint = merge(0, -1, fresh)
                  call node_entry()
                  in_hint = -1
                  ink(j) = in
                end if
                in = ink(j)
                ub = nu(:, in) + rub(:, ir)
              end if
              kemb = 0.5_wp*sum((ub - urefc)**2) + rke(ir)
              wb = rw(ir)
            end if
            call deposit(acc(1, slot, j), acc(2:4, slot, j), j)
            gsum(ir) = gsum(ir) + acc(1, slot, j)
          end do
        end do
        tally = .true.
        if (abs(given_sign) > 0.0_wp) then
          do k = 1, nrk
            if (.not. abs(gsum(k)) > 0.0_wp) cycle
            !$omp atomic
            given(rk(k)) = given(rk(k)) + nint_i8(given_sign*gsum(k)/rgunit(k))
          end do
        end if
        return
      end if
      do j = 1, 8
        do slot = 1, 7
          if (.not. abs(acc(1, slot, j)) > 0.0_wp) cycle
          if (slot == 1) then
            call source(c, c, h%mat(c), n0c + g%corner_offset(j))
          else if (slot <= 4) then
            call source(c, c, h%mat(c), n0c + g%corner_offset(ieor(j - 1, ishft(1, slot - 2)) + 1))
          else
            d = slot - 4
            f = 2*d - 1 + merge(1, 0, btest(j - 1, d - 1))
            call source(nbr(f), nbr(f), h%mat(nbr(f)), n0c + g%corner_offset(j))
          end if
          call deposit(acc(1, slot, j), acc(2:4, slot, j), j)
        end do
      end do
    end subroutine swept_fluxes

    !> tv, tm from `swept_low_faces`' regions where it swept them: this
    !> cell's low faces as they are (the same numbers `swept_cell` gives);
    !> a high face's from the cell across it, the same triangle of its
    !> low face (`twin_triangles`), turned (the region's sign) and its
    !> moment moved to this cell's centre, so that the two cells book the
    !> same region through it (the other way round); the inner triangles
    !> and any face on the grid's boundary swept here. A face shared with
    !> an unchanged cell did not move: it sweeps nothing. False (tv, tm
    !> not set) where this cell has no entry of this remap. (`swept_fluxes`'
    !> cells across the faces, nbr, and its tv, tm passed.)
    subroutine shared_faces(nbr, tv, tm, done)
      integer, intent(in) :: nbr(6)
      real(wp), intent(inout) :: tv(72), tm(72, 3)
      logical, intent(out) :: done
      real(wp) :: vw(48), mw(48, 3), dlo(3), vi(24), mi(24, 3)
      logical :: local(6)
      integer :: e, en, ff, ii, pp, nt, tw
      done = .false.
      if (.not. allocated(old%fslot)) return
      if (size(old%fslot) /= g%ncell) return
      if (old%fstamp(c) /= old%fgen) return
      e = old%fslot(c)
      done = .true.
      local = .false.
      ! (unrolled: the faces' triangles by constant ranges)
      !GCC$ unroll 3
      do ff = 1, 5, 2
        pp = 8*((ff - 1)/2)
        tv(8*ff - 7:8*ff) = old%fv(pp + 1:pp + 8, e)
        tm(8*ff - 7:8*ff, :) = old%fm(pp + 1:pp + 8, :, e)
      end do
      !GCC$ unroll 3
      do ff = 2, 6, 2
        en = nbr(ff)
        if (en == c .or. en == 0) then
          local(ff) = .true.
        else if (.not. old%changed(en)) then
          tv(8*ff - 7:8*ff) = 0.0_wp
          tm(8*ff - 7:8*ff, :) = 0.0_wp
        else if (old%fstamp(en) /= old%fgen) then
          local(ff) = .true.
        else
          en = old%fslot(en)
          dlo = old%fo(:, en) - o
          do ii = 8*ff - 7, 8*ff
            tw = old%twin(ii)
            ! (its place among the neighbour's 24: face ff - 1's eight)
            pp = tw - 8*(ff - 1) + 8 + 8*((ff - 2)/2)
            tv(ii) = -old%fv(pp, en)
            tm(ii, :) = -(old%fm(pp, :, en) + old%fv(pp, en)*dlo)
          end do
        end if
      end do
      ! (into whole arrays: tm's rows 49..72 are no contiguous argument)
      call swept_inner(opts, pts, vi, mi)
      tv(49:72) = vi
      tm(49:72, :) = mi
      if (any(local)) then
        call swept_walls(opts, pts, local, nt, vw, mw)
        nt = 0
        do ff = 2, 6, 2
          if (.not. local(ff)) cycle
          tv(8*ff - 7:8*ff) = vw(nt + 1:nt + 8)
          tm(8*ff - 7:8*ff, :) = mw(nt + 1:nt + 8, :)
          nt = nt + 8
        end do
      end if
    end subroutine shared_faces

    !> The fragments of old cell co in this new cell, from its parts on the
    !> lattice (`lattice_prepare`), in the order they were made.
    subroutine lattice_deposits(co)
      integer, intent(in) :: co
      integer :: e, key, prev, p, s0_, s_
      p = lat%pos(co)
      call region_slots(h, mx, co, s0_, s_)
      prev = -1
      associate (pc => lat%cells(p))
        do e = 1, size(pc%k, 2)
          if (pc%k(1, e) /= c) cycle
          key = pc%k(2, e) - 1
          if (key/8 /= prev) then
            ! a new source: region s_ of the old cell, its subcell at the corner
            prev = key/8
            s_ = s0_ + key/64
            if (s_ == 0) then
              call source(co, co, h%mat(co), g%node0(co) + g%corner_offset(mod(key/8, 8) + 1))
            else
              call source(co, g%ncell + s_, mx%mat(s_), g%node0(co) + g%corner_offset(mod(key/8, 8) + 1))
            end if
          end if
          call deposit(pc%r(1, e), pc%r(2:4, e) + pc%r(1, e)*(pc%oo - o), mod(key, 8) + 1)
        end do
      end associate
    end subroutine lattice_deposits

    !> Deposits the region (volume v, first moment m) the triangle tp swept
    !> to tn, taken from cell co's subcell at corner a of this cell, in
    !> corner into (and, if give > 0, taken out of corner give). From a
    !> mixed cell it is shared among the cell's regions (`swept_split`),
    !> through a face within the cell's budget (`swept_held`).
    subroutine swept_from(co, a, tp, tn, v, m, into, give)
      integer, intent(in) :: co, a, into, give
      real(wp), intent(in) :: tp(3, 3), tn(3, 3), v, m(3)
      real(wp) :: vs(max_mat), ms(3, max_mat)
      integer :: s0, s1, nb_
      nb_ = n0c + g%corner_offset(a)
      if (h%mat(co) > 0) then
        call source(co, co, h%mat(co), nb_)
        call put(v, m, into, give)
        return
      end if
      call region_slots(h, mx, co, s0, s1)
      call swept_split(mx, old, s0, s1, o, tp, tn, v, m, vs, ms)
      call book_parts(co, a, s0, s1, vs, ms, into, give)
    end subroutine swept_from

    !> Books the parts vs, ms of a region swept from mixed cell co (slots
    !> s0..s1, `swept_split`), its subcell at corner a of this cell, as
    !> `swept_from` does.
    subroutine book_parts(co, a, s0, s1, vs, ms, into, give)
      integer, intent(in) :: co, a, s0, s1, into, give
      real(wp), intent(inout) :: vs(:), ms(:, :)
      integer :: s, nb_
      nb_ = n0c + g%corner_offset(a)
      if (give == 0) call swept_held(old, s0, s1, vs, ms)
      do s = s0, s1
        if (.not. abs(vs(s - s0 + 1)) > 0.0_wp) cycle
        call source(co, g%ncell + s, mx%mat(s), nb_)
        call put(vs(s - s0 + 1), ms(:, s - s0 + 1), into, give)
      end do
    end subroutine book_parts

    !> True if `swept_budgets` split the region face triangle i of changed
    !> mixed cell co sweeps out of it.
    logical function swept_out(co, i)
      integer, intent(in) :: co, i
      swept_out = .false.
      if (h%mat(co) > 0 .or. i < 1) return
      if (.not. old%changed(co)) return
      swept_out = btest(old%sout(mx%start(-h%mat(co))), i - 1)
    end function swept_out

    !> A fragment into corner into (and out of corner give, if > 0).
    subroutine put(vf, mf, into, give)
      real(wp), intent(in) :: vf, mf(3)
      integer, intent(in) :: into, give
      call deposit(vf, mf, into)
      if (give > 0) call deposit(-vf, -mf, give)
    end subroutine put

    !> Region kr (material km) of old cell co, and its subcell at node
    !> node, as the source of the next fragments (`deposit`): the velocity
    !> and kinetic energy per unit mass they carry.
    subroutine source(co, kr, km, node)
      integer, intent(in) :: co, kr, km, node
      call source_region(co, kr, km)
      call source_node(node)
    end subroutine source

    !> `source`'s part for the region: kr (material km) of old cell co.
    subroutine source_region(co, kr, km)
      integer, intent(in) :: co, kr, km
      kreg = kr
      kmat = km
      ! (old's numbers taken once per region and node of this cell's
      ! sources, the last entry replaced when all are taken)
      ir = findloc(rk(1:nrk), kr, 1)
      if (ir == 0) then
        nrk = min(nrk + 1, nkeep)
        ir = nrk
        rk(ir) = kr
        rsc(ir) = old%scale(kr)
        call diff_values(3, old%xr(1, kr), o, rxo(1, ir))
        rrho(ir) = old%rho(kr)
        ! (the vectors by `copy_values`)
        call copy_values(3, old%grho(1, kr), rgrho(1, ir))
        call copy_values(3, old%ge(1, kr), rge(1, ir))
        re(ir) = old%e(kr)
        rscrho(ir) = rsc(ir)*rrho(ir)
        rgunit(ir) = old%gunit(kr)
        runi(ir) = old%uniform(co)
        if (runi(ir)) then
          call copy_values(3, old%ucell(1, co), rub(1, ir))
          rke(ir) = old%kcell(co)
          rw(ir) = 0.0_wp
        else
          call copy_values(3, old%ushift(1, co), rub(1, ir))
          rke(ir) = old%kshift(co)
          rw(ir) = old%wreg(kr)
        end if
      end if
    end subroutine source_region

    !> `source`'s part for the node (after `source_region`): the subcell
    !> of the region at node node.
    subroutine source_node(node)
      integer, intent(in) :: node
      nb = node
      if (runi(ir)) then
        ub = rub(:, ir)
      else
        call node_entry()
        ub = nu(:, in) + rub(:, ir)
      end if
      kemb = 0.5_wp*sum((ub - urefc)**2) + rke(ir)
      wb = rw(ir)
    end subroutine source_node

    !> The entry in of node nb among the nodes' numbers (`source`), taken
    !> if it is not there yet.
    subroutine node_entry()
      if (in_hint >= 0) then
        in = in_hint
      else
        in = findloc(nk(1:nnk), nb, 1)
      end if
      if (in == 0) then
        nnk = min(nnk + 1, nkeep)
        in = nnk
        nk(in) = nb
        ! (the node's velocity and its gradient by `copy_values`)
        call copy_values(3, h%u(1, nb), nu(1, in))
        call diff_values(3, old%xdual(1, nb), o, nxo(1, in))
        call copy_values(9, old%gu(1, 1, nb), ngu(1, 1, in))
        ndu(:, in) = nu(:, in) - urefc
      end if
    end subroutine node_entry

    !> The new cell's tetrahedra an old half (bounding box [blo, bhi],
    !> vertices ov) may meet, in increasing order, live(1:nlive), and the
    !> points of the split they use (bits of need): their boxes overlap, and
    !> none of their own face planes has all four vertices of the half
    !> outside (the two are then disjoint).
    subroutine live_tets(blo, bhi, ov, live, nlive, need)
      real(wp), intent(in) :: blo(3), bhi(3), ov(3, 4)
      integer, intent(out) :: live(24), nlive, need
      integer :: t, i
      nlive = 0
      need = 0
      near: do t = 1, 24
        if (any(tvhi(:, t) < blo) .or. any(tvlo(:, t) > bhi)) cycle
        if (tvsg(t) /= 0) then
          do i = 1, 4
            if (all(tvn(1, i, t)*ov(1, :) + tvn(2, i, t)*ov(2, :) + tvn(3, i, t)*ov(3, :) > tvd(i, t))) cycle near
          end do
        end if
        nlive = nlive + 1
        live(nlive) = t
        need = ior(need, tvmask(t))
      end do near
    end subroutine live_tets

    !> Intersects the 48 halves with the convex region pn(:,i).x <= pd(i),
    !> i = 1..np, and deposits the fragments with the sign sgn, of the
    !> tetrahedra live (`live_tets`, the points they use: bits of need).
    !> Which of those points lie outside each plane is found once (as
    !> tet_clip_planes tests them): a half is rejected by a plane with all
    !> four of its points outside, taken whole if no plane has any, else
    !> clipped by just the planes that cut it.
    subroutine clip_halves(pn, pd, np, sgn, live, need)
      real(wp), intent(in) :: pn(:, :), pd(:), sgn
      integer, intent(in) :: np, live(:), need
      integer :: outm(4 + max_mat), i, j, t, ncut, bits, k, left, il
      real(wp) :: cn(3, 4 + max_mat), cd(4 + max_mat), v, m(3), sa, sb, sm
      type(poly_t) :: p, q

      ! which of those points lie outside each plane (the bits the
      ! tetrahedra below read: the others stay clear)
      do i = 1, np
        outm(i) = 0
        left = need
        do while (left /= 0)
          j = trailz(left) + 1
          left = ibclr(left, j - 1)
          if (pn(1, i)*pts(1, j) + pn(2, i)*pts(2, j) + pn(3, i)*pts(3, j) - pd(i) > 0.0_wp) &
            outm(i) = ibset(outm(i), j - 1)
        end do
      end do
      ! whole tetrahedra first: one clip for both halves, then the
      ! mid-plane split where the piece straddles it
      tets: do il = 1, size(live)
        t = live(il)
        ncut = 0
        do i = 1, np
          bits = iand(outm(i), tvmask(t))
          if (bits == tvmask(t)) cycle tets
          if (bits /= 0) then
            ncut = ncut + 1
            cn(:, ncut) = pn(:, i)
            cd(ncut) = pd(i)
          end if
        end do
        if (ncut == 0) then
          call deposit(sgn*hsg(2*t - 1)*hvol(2*t - 1), sgn*hsg(2*t - 1)*hmom(:, 2*t - 1), half_corner(2*t - 1))
          call deposit(sgn*hsg(2*t)*hvol(2*t), sgn*hsg(2*t)*hmom(:, 2*t), half_corner(2*t))
          cycle
        end if
        call poly_set_tet(p, tv(:, :, t))
        do i = 1, ncut
          call poly_clip(p, cn(:, i), cd(i))
          if (p%nv == 0) cycle tets
        end do
        sa = 0.0_wp
        sb = 0.0_wp
        do j = 1, p%nv
          sm = dot_product(midn(:, t), p%x(:, j)) - midd(t)
          sa = min(sa, sm)
          sb = max(sb, sm)
        end do
        if (sb <= 0.0_wp .or. sa >= 0.0_wp) then
          ! all on one side of the mid-plane
          call poly_first_moments(p, v, m)
          k = merge(2*t - 1, 2*t, sb <= 0.0_wp)
          if (v > 0.0_wp) call deposit(sgn*hsg(k)*v, sgn*hsg(k)*m, half_corner(k))
        else
          call poly_copy(p, q)
          call poly_clip(p, midn(:, t), midd(t))
          call poly_first_moments(p, v, m)
          if (v > 0.0_wp) call deposit(sgn*hsg(2*t - 1)*v, sgn*hsg(2*t - 1)*m, half_corner(2*t - 1))
          call poly_clip(q, -midn(:, t), -midd(t))
          call poly_first_moments(q, v, m)
          if (v > 0.0_wp) call deposit(sgn*hsg(2*t)*v, sgn*hsg(2*t)*m, half_corner(2*t))
        end if
      end do tets
    end subroutine clip_halves

    !> The part of the old half tetrahedron t (material planes mn.x <= md)
    !> inside this box cell, split among the cell's eight octants (its
    !> corners' subcells) by its three mid-planes, deposited with the sign
    !> sgn. The half is clipped by the material planes and the box faces
    !> that cut it, then split plane by plane only where it straddles one,
    !> so most pieces take a few clips of a small polyhedron.
    subroutine clip_into_octants(t, mn, md, sgn)
      real(wp), intent(in) :: t(3, 4), mn(:, :), md(:), sgn
      type(poly_t) :: p
      integer :: i, d

      call poly_set_tet(p, t)
      do i = 1, size(md)
        call poly_clip(p, mn(:, i), md(i))
        if (p%nv == 0) return
      end do
      do d = 1, 3
        if (maxval(p%x(d, 1:p%nv)) > hi(d)) call poly_clip_axis(p, d, 1.0_wp, hi(d))
        if (p%nv == 0) return
        if (minval(p%x(d, 1:p%nv)) < lo(d)) call poly_clip_axis(p, d, -1.0_wp, -lo(d))
        if (p%nv == 0) return
      end do
      call split_octants(p, 1, 0, sgn)
    end subroutine clip_into_octants

    !> Splits p by the mid-planes of directions d..3 and deposits each piece
    !> in the octant whose bits (direction d-1 .. 0 set on the high side) it
    !> has reached.
    recursive subroutine split_octants(p, d, bits, sgn)
      type(poly_t), intent(inout) :: p
      integer, intent(in) :: d, bits
      real(wp), intent(in) :: sgn
      type(poly_t) :: q
      real(wp) :: v, m(3), xlo, xhi

      if (d > 3) then
        call poly_first_moments(p, v, m)
        if (v > 0.0_wp) call deposit(sgn*v, sgn*m, bits + 1)
        return
      end if
      xlo = minval(p%x(d, 1:p%nv))
      xhi = maxval(p%x(d, 1:p%nv))
      if (xhi <= mid(d)) then
        call split_octants(p, d + 1, bits, sgn)
      else if (xlo >= mid(d)) then
        call split_octants(p, d + 1, ibset(bits, d - 1), sgn)
      else
        call poly_copy(p, q)
        call poly_clip_axis(p, d, 1.0_wp, mid(d))
        if (p%nv > 0) call split_octants(p, d + 1, bits, sgn)
        call poly_clip_axis(q, d, -1.0_wp, -mid(d))
        if (q%nv > 0) call split_octants(q, d + 1, ibset(bits, d - 1), sgn)
      end if
    end subroutine split_octants

    !> One fragment (signed volume vf, first moment mf about o) of region
    !> kreg (material kmat) of old cell co, landing in corner a.
    subroutine deposit(vf, mf, a)
      real(wp), intent(in) :: vf, mf(3)
      integer, intent(in) :: a
      real(wp) :: dm(3), fm, fie, plin(3), fu(3)
      integer :: j_
      ! (the source's numbers: `source`)
      dm = mf - rxo(:, ir)*vf
      fm = rsc(ir)*(rrho(ir)*vf + dot_product(rgrho(:, ir), dm))
      fie = fm*re(ir) + rscrho(ir)*dot_product(rge(:, ir), dm)
      svol(kmat) = svol(kmat) + vf
      scdef(a) = scdef(a) - vf
      smom(:, kmat) = smom(:, kmat) + mf
      smass(kmat) = smass(kmat) + fm
      sie(kmat) = sie(kmat) + fie
      ! velocity and kinetic energy with the mass (plus the velocity's linear
      ! part about the old node: `velocity_gradients`): the cell's totals,
      ! and the mass and momentum that landed in each of its corners
      fu = fm*ub
      if (wb > 0.0_wp) then
        dm = mf - nxo(:, in)*vf
        do j_ = 1, 3
          plin(j_) = wb*dot_product(ngu(:, j_, in), dm)
        end do
        spc(1:3) = spc(1:3) + fu + plin
        spc(4) = spc(4) + fm*kemb + dot_product(ndu(:, in), plin)
        scmom(:, a) = scmom(:, a) + fu + plin
      else
        ! (plin = 0: what adding it and its product with the velocity did)
        spc(1:3) = spc(1:3) + fu + 0.0_wp
        spc(4) = spc(4) + fm*kemb + 0.0_wp
        scmom(:, a) = scmom(:, a) + fu + 0.0_wp
      end if
      scland(a) = scland(a) + fm
      if (tally .and. abs(given_sign) > 0.0_wp) then
        !$omp atomic
        given(kreg) = given(kreg) + nint_i8(given_sign*vf/rgunit(ir))
      end if
    end subroutine deposit
  end subroutine remap_new_cell

  !> The lattice path's start (`remap_params_t`'s lattice): the new grid
  !> xnew's half-cell planes, no old cell's parts yet.
  subroutine lattice_start(g, old, xnew, lat, err)
    type(grid_t), intent(in) :: g
    type(old_t), intent(in) :: old
    real(wp), intent(in) :: xnew(:, :)
    type(lattice_old_t), intent(out) :: lat
    type(error_t), allocatable, intent(inout) :: err
    integer :: i, stat
    call lattice_build(g%grid_index_t, xnew, lat%lt)
    ! (allocated, then set: an array constructor of the whole grid's size
    ! would be built and copied at every Euler step)
    allocate(lat%pos(g%ncell), lat%state(size(old%lchanged)), lat%cells(size(old%lchanged)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the lattice''s cell list'))
      return
    end if
    lat%pos = 0
    do i = 1, size(old%lchanged)
      lat%pos(old%lchanged(i)) = i
    end do
    lat%state = 0
  end subroutine lattice_start

  !> The parts on the lattice of the changed old cells within rr index
  !> steps of the new cells `cells` that do not have them yet.
  subroutine lattice_prepare(g, h, mx, old, lat, cells, rr)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    type(old_t), intent(in) :: old
    type(lattice_old_t), intent(inout) :: lat
    integer, intent(in) :: cells(:), rr
    integer, allocatable :: need(:)
    integer :: i, ci, cj, ck, oi, oj, ok_, co
    ! (state: 0 not needed yet, 1 needed now, 2 done)
    do i = 1, size(cells)
      call g%cell_ijk(cells(i), ci, cj, ck)
      do ok_ = max(g%clo(3), ck - rr), min(g%chi(3), ck + rr)
        do oj = max(g%clo(2), cj - rr), min(g%chi(2), cj + rr)
          do oi = max(g%clo(1), ci - rr), min(g%chi(1), ci + rr)
            co = g%cell(oi, oj, ok_)
            if (.not. old%changed(co)) cycle
            if (lat%state(lat%pos(co)) == 0) lat%state(lat%pos(co)) = 1
          end do
        end do
      end do
    end do
    need = pack(old%lchanged, lat%state == 1)
    where (lat%state == 1) lat%state = 2
    !$omp parallel do default(none) shared(g, h, mx, old, lat, need) private(i) schedule(dynamic, 4)
    do i = 1, size(need)
      call lattice_cell_parts(g, h, mx, old, lat%lt, need(i), lat%cells(lat%pos(need(i))))
    end do
    !$omp end parallel do
  end subroutine lattice_prepare

  !> Drops the parts of the old cells below index below (all: huge):
  !> they are made again if a later pass needs them.
  subroutine lattice_release(old, lat, below)
    type(old_t), intent(in) :: old
    type(lattice_old_t), intent(inout) :: lat
    integer, intent(in) :: below
    integer :: i
    ! (all of them: from the first, and the next pass starts again there)
    if (below == huge(1)) lat%released = 0
    do i = lat%released + 1, size(old%lchanged)
      if (old%lchanged(i) >= below) exit
      if (below < huge(1)) lat%released = i
      if (lat%state(i) /= 2) cycle
      lat%state(i) = 0
      if (allocated(lat%cells(i)%k)) deallocate(lat%cells(i)%k, lat%cells(i)%r)
    end do
  end subroutine lattice_release

  !> The parts of the changed old cell co on the lattice lt
  !> (`lattice_cell_t`): each region's subcells (the six halves at each
  !> corner, cut by the region's MoF planes) in the lattice's half-cells.
  subroutine lattice_cell_parts(g, h, mx, old, lt, co, pc)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    type(old_t), intent(in) :: old
    type(lattice_t), intent(in) :: lt
    integer, intent(in) :: co
    type(lattice_cell_t), intent(inout) :: pc
    real(wp) :: xo(3, 8), opts(3, 27), ot(3, 4), tn(3, 4), td(4), pn(3, max_mat), pd(max_mat)
    integer :: ohv(4, 48), ocorner(48), isg(48), ci, cj, ck, i, j, s, s0, s1, nm, a, n, e, sub, first(0:8*max_mat)
    integer(i8), allocatable :: code(:)
    real(wp), allocatable :: acc(:, :)

    call g%cell_ijk(co, ci, cj, ck)
    call block_gather(g%ni, g%nj, ci, cj, ck, g%x, xo)
    pc%oo = sum(xo, 2)/8.0_wp
    do j = 1, 8
      xo(:, j) = xo(:, j) - pc%oo
    end do
    call half_tets(xo, opts, ohv, ocorner)
    do i = 1, 48
      ! (a half flat to round-off has no volume to give: sign 0, skipped)
      call tet_planes(opts(:, ohv(:, i)), tn, td, isg(i))
    end do
    call region_slots(h, mx, co, s0, s1)
    code = [(0_i8, i = 1, 64)]
    acc = reshape([(0.0_wp, i = 1, 4*64)], [4, 64])
    ! the subcells one after the other (sub = corner - 1 + 8 (s - s0)),
    ! their entries from first(sub) + 1 to first(sub + 1)
    n = 0
    first(0) = 0
    do s = s0, s1
      do a = 1, 8
        sub = a - 1 + 8*(s - s0)
        first(sub + 1) = n
        if (s > 0) then
          if (.not. mx%mass(s) > 0.0_wp) cycle
        end if
        nm = 0
        if (s > 0) call region_planes(old, s0, s, pc%oo, pn, pd, nm)
        do i = 1, 48
          if (ocorner(i) /= a .or. isg(i) == 0) cycle
          do j = 1, 4
            ot(:, j) = opts(:, ohv(j, i))
          end do
          call lattice_tet(lt, pc%oo, 2*([ci, cj, ck] - g%slo), ot, pn(:, 1:nm), pd(1:nm), real(isg(i), wp), &
                           first(sub), n, code, acc)
        end do
        first(sub + 1) = n
      end do
    end do
    pc%r = acc(:, 1:n)
    ! half-cell -> the new cell and its corner (octant); with the subcell
    pc%k = reshape([((lattice_key(g, lt, code(e), sub), e = first(sub) + 1, first(sub + 1)), &
                     sub = 0, 8*(s1 - s0) + 7)], [2, n])
  end subroutine lattice_cell_parts

  !> An entry of `lattice_cell_t`: the new cell of half-cell code q of the
  !> lattice lt and the key of its corner there from subcell sub.
  pure function lattice_key(g, lt, q, sub) result(k)
    type(grid_t), intent(in) :: g
    type(lattice_t), intent(in) :: lt
    integer(i8), intent(in) :: q
    integer, intent(in) :: sub
    integer :: k(2), qi(3)
    qi(1) = int(mod(q, int(lt%nq(1), i8)))
    qi(2) = int(mod(q/lt%nq(1), int(lt%nq(2), i8)))
    qi(3) = int(q/(int(lt%nq(1), i8)*lt%nq(2)))
    k(1) = g%cell(g%slo(1) + qi(1)/2, g%slo(2) + qi(2)/2, g%slo(3) + qi(3)/2)
    k(2) = 1 + mod(qi(1), 2) + 2*mod(qi(2), 2) + 4*mod(qi(3), 2) + 8*sub
  end function lattice_key

  !> nint(x, i8), rounding half away from zero, without the library call
  !> (lround) it costs at every fragment (`deposit`): below 2^52 the
  !> truncation and the remainder x - trunc(x) are exact, so the result is
  !> nint's bit for bit; beyond (never a fragment's count), nint itself.
  elemental integer(i8) function nint_i8(x) result(k)
    real(wp), intent(in) :: x
    real(wp) :: r
    if (.not. abs(x) < 2.0_wp**52) then
      k = nint(x, i8)
      return
    end if
    k = int(x, i8)
    r = x - real(k, wp)
    if (r >= 0.5_wp) then
      k = k + 1
    else if (r <= -0.5_wp) then
      k = k - 1
    end if
  end function nint_i8

  !> The 48 half tetrahedra of a cell: each tetrahedron (centre, face centre,
  !> a, b) of the 24-split (`hex_tets`) cut at the midpoint of edge ab; the
  !> half at a belongs to corner a (six halves make a subcell, Fig. 11).
  !> They are given by their vertices hv(:,t) among the 27 points pts of the
  !> split: 1 the centre, 1+f the centre of face f, 7+a node a, 15+e the
  !> midpoint of edge e (the order of `hex_edges`), computed as `hex_tets`
  !> does, so a half's volume adds up with its twin to the split's exactly.
  pure subroutine half_tets(xn, pts, hv, corner)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: pts(3, 27)
    integer, intent(out) :: hv(4, 48), corner(48)
    call half_points(xn, pts)
    hv = half_hv
    corner = half_corner
  end subroutine half_tets

  !> dst = src, n values. Callers pass array elements (element sequence
  !> association): the copy is made without an array assignment's
  !> descriptor arithmetic and run-time tests for overlap, which cost
  !> several times the copy itself where a few values are copied per call.
  pure subroutine copy_values(n, src, dst)
    integer, intent(in) :: n
    real(wp), intent(in) :: src(n)
    real(wp), intent(out) :: dst(n)
    dst = src
  end subroutine copy_values

  !> dst = dst + src, n values, passed like `copy_values`'.
  pure subroutine add_values(n, src, dst)
    integer, intent(in) :: n
    real(wp), intent(in) :: src(n)
    real(wp), intent(inout) :: dst(n)
    dst = dst + src
  end subroutine add_values

  !> dst = 0, n values, passed like `copy_values`'.
  pure subroutine zero_values(n, dst)
    integer, intent(in) :: n
    real(wp), intent(out) :: dst(n)
    dst = 0.0_wp
  end subroutine zero_values

  !> dst = a - b, n values, passed like `copy_values`'.
  pure subroutine diff_values(n, a, b, dst)
    integer, intent(in) :: n
    real(wp), intent(in) :: a(n), b(n)
    real(wp), intent(out) :: dst(n)
    dst = a - b
  end subroutine diff_values

  !> The 27 points of `half_tets`' split alone (its halves are the
  !> constants half_hv, half_corner: callers on the hot paths read those
  !> rather than a copy made at each call).
  pure subroutine half_points(xn, pts)
    real(wp), intent(in) :: xn(3, 8)
    real(wp), intent(out) :: pts(3, 27)
    integer :: d

    do d = 1, 3
      pts(d, 1) = 0.125_wp*sum(xn(d, :))
    end do
    ! the face centres (their nodes: `hex_faces`, 1 + f for face f) and the
    ! edge midpoints (`hex_edges`, 15 + e for edge e), their nodes written
    ! out: constant indices, no table to read at every call (one of the
    ! hot paths: three or four calls per remapped cell)
    pts(:, 2) = 0.25_wp*((xn(:, 1) + xn(:, 7)) + (xn(:, 5) + xn(:, 3)))
    pts(:, 3) = 0.25_wp*((xn(:, 2) + xn(:, 8)) + (xn(:, 4) + xn(:, 6)))
    pts(:, 4) = 0.25_wp*((xn(:, 1) + xn(:, 6)) + (xn(:, 2) + xn(:, 5)))
    pts(:, 5) = 0.25_wp*((xn(:, 3) + xn(:, 8)) + (xn(:, 7) + xn(:, 4)))
    pts(:, 6) = 0.25_wp*((xn(:, 1) + xn(:, 4)) + (xn(:, 3) + xn(:, 2)))
    pts(:, 7) = 0.25_wp*((xn(:, 5) + xn(:, 8)) + (xn(:, 6) + xn(:, 7)))
    pts(:, 8:15) = xn
    pts(:, 16) = 0.5_wp*(xn(:, 1) + xn(:, 2))
    pts(:, 17) = 0.5_wp*(xn(:, 7) + xn(:, 8))
    pts(:, 18) = 0.5_wp*(xn(:, 5) + xn(:, 6))
    pts(:, 19) = 0.5_wp*(xn(:, 3) + xn(:, 4))
    pts(:, 20) = 0.5_wp*(xn(:, 1) + xn(:, 3))
    pts(:, 21) = 0.5_wp*(xn(:, 6) + xn(:, 8))
    pts(:, 22) = 0.5_wp*(xn(:, 2) + xn(:, 4))
    pts(:, 23) = 0.5_wp*(xn(:, 5) + xn(:, 7))
    pts(:, 24) = 0.5_wp*(xn(:, 1) + xn(:, 5))
    pts(:, 25) = 0.5_wp*(xn(:, 4) + xn(:, 8))
    pts(:, 26) = 0.5_wp*(xn(:, 3) + xn(:, 7))
    pts(:, 27) = 0.5_wp*(xn(:, 2) + xn(:, 6))
  end subroutine half_points

  !> `swept_triangles` on the 72 triangles `swept_tri` of the split whose
  !> 27 points p move to q (`half_points`): the 48 on the faces as
  !> `swept_walls` takes them, the 24 inner ones as `swept_inner` does
  !> (each triangle's numbers are its own: the same, bit for bit).
  pure subroutine swept_cell(p, q, v, m)
    real(wp), intent(in) :: p(3, 27), q(3, 27)
    real(wp), intent(out) :: v(72), m(72, 3)
    logical, parameter :: every(6) = .true.
    real(wp) :: vw(48), mw(48, 3), vi(24), mi(24, 3)
    integer :: nt
    call swept_walls(p, q, every, nt, vw, mw)
    call swept_inner(p, q, vi, mi)
    v(1:48) = vw
    m(1:48, :) = mw
    v(49:72) = vi
    m(49:72, :) = mi
  end subroutine swept_cell

  !> `swept_triangles` on the triangles `swept_tri` of the faces f with
  !> wall(f) (eight each, in order; nt of them), as `swept_cell` gathers
  !> them (both loops unrolled whole: constant indices).
  pure subroutine swept_walls(p, q, wall, nt, v, m)
    real(wp), intent(in) :: p(3, 27), q(3, 27)
    logical, intent(in) :: wall(6)
    integer, intent(out) :: nt
    real(wp), intent(out) :: v(48), m(48, 3)
    real(wp) :: dq(3, 27), x1(48, 3), e1(48, 3), e2(48, 3), d1(48, 3), g1(48, 3), g2(48, 3)
    integer :: k, j, f
    do k = 1, 27
      dq(:, k) = q(:, k) - p(:, k)
    end do
    nt = 0
    !GCC$ unroll 6
    do f = 1, 6
      if (.not. wall(f)) cycle
      !GCC$ unroll 8
      do k = 8*f - 7, 8*f
        nt = nt + 1
        do j = 1, 3
          x1(nt, j) = p(j, swept_tri(1, k))
          e1(nt, j) = p(j, swept_tri(2, k)) - x1(nt, j)
          e2(nt, j) = p(j, swept_tri(3, k)) - x1(nt, j)
          d1(nt, j) = dq(j, swept_tri(1, k))
          g1(nt, j) = dq(j, swept_tri(2, k)) - d1(nt, j)
          g2(nt, j) = dq(j, swept_tri(3, k)) - d1(nt, j)
        end do
      end do
    end do
    if (nt > 0) call swept_edges(nt, 48, x1, e1, e2, d1, g1, g2, v, m)
  end subroutine swept_walls

  !> `swept_cell`'s 24 inner triangles (49..72 of `swept_tri`) alone, as
  !> it gathers them (unrolled whole: constant indices): the same numbers.
  pure subroutine swept_inner(p, q, v, m)
    real(wp), intent(in) :: p(3, 27), q(3, 27)
    real(wp), intent(out) :: v(24), m(24, 3)
    real(wp) :: dq(3, 27), x1(24, 3), e1(24, 3), e2(24, 3), d1(24, 3), g1(24, 3), g2(24, 3)
    integer :: k, j
    do k = 1, 27
      dq(:, k) = q(:, k) - p(:, k)
    end do
    !GCC$ unroll 24
    do k = 1, 24
      do j = 1, 3
        x1(k, j) = p(j, swept_tri(1, 48 + k))
        e1(k, j) = p(j, swept_tri(2, 48 + k)) - x1(k, j)
        e2(k, j) = p(j, swept_tri(3, 48 + k)) - x1(k, j)
        d1(k, j) = dq(j, swept_tri(1, 48 + k))
        g1(k, j) = dq(j, swept_tri(2, 48 + k)) - d1(k, j)
        g2(k, j) = dq(j, swept_tri(3, 48 + k)) - d1(k, j)
      end do
    end do
    call swept_edges(24, 24, x1, e1, e2, d1, g1, g2, v, m)
  end subroutine swept_inner

  !> The regions the 24 triangles on the three low faces of every changed
  !> cell sweep from g%x to xnew, about the new cell's centre, as
  !> `swept_fluxes` sweeps them (the same points, `swept_walls`: the same
  !> numbers), kept in old (fslot ... fo, under a new fgen) for the cell
  !> and for its neighbours across those faces: each face is swept once
  !> per remap instead of by both its cells (`remap_new_cell`'s
  !> `shared_faces`). Where the store cannot be had, no cell has an entry
  !> and each sweeps its own.
  subroutine swept_low_faces(g, old, xnew)
    type(grid_t), intent(in) :: g
    type(old_t), intent(inout) :: old
    real(wp), intent(in) :: xnew(:, :)
    logical, parameter :: low(6) = [.true., .false., .true., .false., .true., .false.]
    real(wp) :: xo(3, 8), xn(3, 8), o(3), opts(3, 27), pts(3, 27), vw(48), mw(48, 3)
    integer :: ic, c, ci, cj, ck, j, nt, n, m, stat

    if (old%twin(1) == 0) old%twin = twin_triangles()
    old%fgen = old%fgen + 1
    n = size(old%lchanged)
    stat = 0
    ! (the grid's slots and stamps kept while the grid is the same; the
    ! changed cells' entries grown to twice what is needed when too few:
    ! the whole grid's arrays are not set again as the changed cells grow)
    if (allocated(old%fslot)) then
      if (size(old%fslot) /= g%ncell) deallocate(old%fslot, old%fstamp)
    end if
    if (allocated(old%fv)) then
      if (size(old%fv, 2) < n) deallocate(old%fv, old%fm, old%fo)
    end if
    if (.not. allocated(old%fslot)) then
      allocate(old%fslot(g%ncell), old%fstamp(g%ncell), stat=stat)
      if (stat == 0) old%fstamp = old%fgen - 1
    end if
    if (stat == 0 .and. .not. allocated(old%fv)) then
      m = max(2*n, 1)
      allocate(old%fv(24, m), old%fm(24, 3, m), old%fo(3, m), stat=stat)
    end if
    if (stat /= 0) then
      if (allocated(old%fslot)) deallocate(old%fslot)
      if (allocated(old%fstamp)) deallocate(old%fstamp)
      if (allocated(old%fv)) deallocate(old%fv)
      if (allocated(old%fm)) deallocate(old%fm)
      if (allocated(old%fo)) deallocate(old%fo)
      return
    end if
    !$omp parallel do default(none) shared(g, old, xnew, n) private(ic, c, ci, cj, ck, j, nt, xo, xn, o, opts, pts, &
    !$omp vw, mw) schedule(static)
    do ic = 1, n
      c = old%lchanged(ic)
      call g%cell_ijk(c, ci, cj, ck)
      ! (as `remap_new_cell` and `swept_fluxes` place the points)
      call block_gather(g%ni, g%nj, ci, cj, ck, xnew, xn)
      o = sum(xn, 2)/8.0_wp
      do j = 1, 8
        xn(:, j) = xn(:, j) - o
      end do
      call half_points(xn, pts)
      call block_gather(g%ni, g%nj, ci, cj, ck, g%x, xo)
      do j = 1, 8
        xo(:, j) = xo(:, j) - o
      end do
      call half_points(xo, opts)
      call swept_walls(opts, pts, low, nt, vw, mw)
      old%fv(:, ic) = vw(1:24)
      old%fm(:, :, ic) = mw(1:24, :)
      old%fo(:, ic) = o
      old%fslot(c) = ic
      old%fstamp(c) = old%fgen
    end do
    !$omp end parallel do
  end subroutine swept_low_faces

  !> Six times the signed volumes of the 48 halves of the split with the
  !> points pts (`half_tets`), as `tet_det` gives them: every half has the
  !> centre for its first point, so the offsets from it are taken once.
  !> (The loop over the halves unrolled whole, as `swept_cell`'s: their
  !> points by constant indices.)
  pure subroutine half_dets(pts, det6)
    real(wp), intent(in) :: pts(3, 27)
    real(wp), intent(out) :: det6(48)
    real(wp) :: r(3, 27)
    integer :: i, j
    do j = 2, 27
      r(:, j) = pts(:, j) - pts(:, 1)
    end do
    !GCC$ unroll 48
    do i = 1, 48
      associate (a => r(:, half_hv(2, i)), b => r(:, half_hv(3, i)), c => r(:, half_hv(4, i)))
        det6(i) = a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) + a(3)*(b(1)*c(2) - b(2)*c(1))
      end associate
    end do
  end subroutine half_dets

  !> The region (signed volume v, first moment m about o) a triangle sweeps
  !> from tp to tn, taken from the mixed old cell whose regions are the
  !> slots s0..s1, shared among them: vs(k) and ms(:, k) for slot s0 + k - 1,
  !> adding up to v and m. A region that holds the whole prism (the hull of
  !> its six points) takes all of it, one that misses it none; else each
  !> region's part of the prism with its sides split into triangles
  !> (`prism_part`), the parts scaled to add up to the exact v and m (the
  !> ruled sides and the flat ones differ only in how the region is shared,
  !> and a material the flat prism does not reach gets nothing: no sliver
  !> from the difference; nor a part of the opposite sign); no part with
  !> volume (a degenerate prism): all to the last region with mass.
  pure subroutine swept_split(mx, old, s0, s1, o, tp, tn, v, m, vs, ms)
    type(mixed_t), intent(in) :: mx
    type(old_t), intent(in) :: old
    integer, intent(in) :: s0, s1
    real(wp), intent(in) :: o(3), tp(3, 3), tn(3, 3), v, m(3)
    real(wp), intent(out) :: vs(:), ms(:, :)
    real(wp) :: pn(3, max_mat), pd(max_mat), vsum, msum(3), x6(3, 6), vraw, mraw(3), vflat
    integer :: s, k, nm, side, last
    logical :: rest
    vs = 0.0_wp
    ms = 0.0_wp
    last = 0
    x6(:, 1:3) = tp
    x6(:, 4:6) = tn
    ! (every region with mass: the last one's part is the flat prism's less
    ! the others' as clipped, one clip of the prism fewer; vraw, mraw: the
    ! others' parts before a part against the sign is dropped)
    rest = all(mx%mass(s0:s1) > 0.0_wp) .and. s1 > s0
    vraw = 0.0_wp
    mraw = 0.0_wp
    do s = s0, s1
      if (.not. mx%mass(s) > 0.0_wp) cycle
      k = s - s0 + 1
      last = k
      call region_planes(old, s0, s, o, pn, pd, nm)
      side = hull_side(x6, pn(:, 1:nm), pd(1:nm))
      if (side == 1) then
        ! (the regions do not overlap: this one holds the whole prism)
        vs = 0.0_wp
        ms = 0.0_wp
        last = k
        exit
      end if
      if (side == 0) then
        if (rest .and. s == s1) then
          call prism_part(tp, tn, pn(:, 1:0), pd(1:0), vflat, ms(:, k))
          vs(k) = vflat - vraw
          ms(:, k) = ms(:, k) - mraw
          ! (a difference at round-off is no part)
          if (abs(vs(k)) <= 1.0e-12_wp*abs(vflat)) then
            vs(k) = 0.0_wp
            ms(:, k) = 0.0_wp
          end if
        else
          call prism_part(tp, tn, pn(:, 1:nm), pd(1:nm), vs(k), ms(:, k))
        end if
      end if
      vraw = vraw + vs(k)
      mraw = mraw + ms(:, k)
      ! (a part against the region's sign, of a twisted prism, would give
      ! a material that is not there: none)
      if (vs(k)*v < 0.0_wp) then
        vs(k) = 0.0_wp
        ms(:, k) = 0.0_wp
      end if
    end do
    vsum = sum(vs(1:s1 - s0 + 1))
    if (.not. abs(vsum) > 0.0_wp) then
      if (last > 0) then
        vs(last) = v
        ms(:, last) = m
      end if
      return
    end if
    msum = sum(ms(:, 1:s1 - s0 + 1), 2)
    do k = 1, s1 - s0 + 1
      if (.not. abs(vs(k)) > 0.0_wp) cycle
      ms(:, k) = ms(:, k) + (m - msum)*(vs(k)/vsum)
      vs(k) = vs(k)*(v/vsum)
    end do
  end subroutine swept_split

  !> A region swept through a face out of a mixed old cell (its parts vs,
  !> ms in the slots s0..s1, `swept_split`) with the cell's budget applied
  !> (`swept_budgets`): each slot's part times its factor sfac (its
  !> centroid moved by sshift), what that holds back shared among the slots
  !> by sroom. The region's volume and first moment are kept.
  pure subroutine swept_held(old, s0, s1, vs, ms)
    type(old_t), intent(in) :: old
    integer, intent(in) :: s0, s1
    real(wp), intent(inout) :: vs(:), ms(:, :)
    real(wp) :: hv, hm(3), f
    integer :: s, k
    if (all(old%sfac(s0:s1) >= 1.0_wp)) return
    hv = 0.0_wp
    hm = 0.0_wp
    do s = s0, s1
      k = s - s0 + 1
      f = old%sfac(s)
      if (f >= 1.0_wp) cycle
      hv = hv + (1.0_wp - f)*vs(k)
      hm = hm + (1.0_wp - f)*ms(:, k) - f*vs(k)*old%sshift(:, s)
      ms(:, k) = f*(ms(:, k) + vs(k)*old%sshift(:, s))
      vs(k) = f*vs(k)
    end do
    do s = s0, s1
      k = s - s0 + 1
      vs(k) = vs(k) + old%sroom(s)*hv
      ms(:, k) = ms(:, k) + old%sroom(s)*hm
    end do
  end subroutine swept_held

  !> A cell's old and new nodes xo and xn moved to coordinates about o (in
  !> place), and the points of their 48 halves (`half_tets`: opts old, pts
  !> new, the vertices hv and corners hc alike for both).
  pure subroutine halves_about(o, xo, xn, opts, pts, hv, hc)
    real(wp), intent(in) :: o(3)
    real(wp), intent(inout) :: xo(3, 8), xn(3, 8)
    real(wp), intent(out) :: opts(3, 27), pts(3, 27)
    integer, intent(out) :: hv(4, 48), hc(48)
    integer :: a
    do a = 1, 8
      xo(:, a) = xo(:, a) - o
      xn(:, a) = xn(:, a) - o
    end do
    call half_tets(xn, pts, hv, hc)
    call half_tets(xo, opts, hv, hc)
  end subroutine halves_about

  !> For each of the 48 triangles on a cell's faces (`half_tets`: triangle
  !> i = points half_hv(2:4, i), on face half_hv(2, i) - 1), the triangle
  !> of the cell across that face that has the same three points: found on
  !> a unit cube and its neighbour, whose points are exact binary fractions.
  pure function twin_triangles() result(tw)
    integer :: tw(48)
    real(wp) :: xa(3, 8), xb(3, 8), pa(3, 27), pb(3, 27)
    integer :: hv(4, 48), hc(48), i, j, a, q, r, nsame
    do a = 1, 8
      xa(:, a) = real(hex_corner(:, a), wp)
    end do
    call half_tets(xa, pa, hv, hc)
    tw = 0
    do i = 1, 48
      do a = 1, 8
        xb(:, a) = xa(:, a) + real(face_step(:, hv(2, i) - 1), wp)
      end do
      call half_tets(xb, pb, hv, hc)
      do j = 1, 48
        nsame = 0
        do q = 2, 4
          do r = 2, 4
            if (all(abs(pa(:, hv(q, i)) - pb(:, hv(r, j))) < 1.0e-12_wp)) nsame = nsame + 1
          end do
        end do
        if (nsame == 3) tw(i) = j
      end do
    end do
  end function twin_triangles

  !> The budgets of the mixed old cells on the swept path. A region swept
  !> out of a mixed cell is shared among its materials by the cell's planes
  !> extended past it (`swept_split`), so the parts of one material that
  !> its faces sweep out can add up to more than the cell keeps of it (a
  !> thin layer by an outgoing face): the new cell would hold a negative
  !> volume of it. Per mixed cell that moved, what its faces sweep out of it
  !> is added up by material, and so is what its subcells keep (their parts
  !> in the material's region, as `swept_fluxes` books them); a material
  !> whose parts exceed what is kept has them scaled to it (sfac < 1) and
  !> their centroids moved so that they give the kept first moment too
  !> (sshift: the new cell then keeps neither its volume nor its first
  !> moment, so no stray centroid of a vanished material reaches MoF; the
  !> mass and energy go with the volume, the regions of mixed cells giving
  !> their mean state on this path), and the volume held back goes to the
  !> materials with room,
  !> in proportion to the room they keep (sroom). Both cells that book a
  !> region (the one that gives it, the one that takes it) apply the same
  !> factors, so the transfer stays conservative; each cell's budget
  !> depends on that cell alone, whoever computes it.
  subroutine swept_budgets(g, h, mx, old, xnew)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    type(old_t), intent(inout) :: old
    real(wp), intent(in) :: xnew(:, :)
    real(wp) :: xo(3, 8), xn(3, 8), o(3), opts(3, 27), pts(3, 27), tp(3, 3), tn(3, 3), v, m(3), &
                vs(max_mat), ms(3, max_mat), out(max_mat), mout(3, max_mat), kept(max_mat), mkept(3, max_mat), &
                room(max_mat), held, total, pn(3, max_mat), pd(max_mat), f, tv(72), tm(72, 3), vraw, mraw(3)
    integer :: k, c, ci, cj, ck, s0, s1, s, n, i, j, nm, hv(4, 48), hc(48)
    integer(i8) :: bits
    logical :: rest

    if (old%twin(1) == 0) old%twin = twin_triangles()
    !$omp parallel do default(none) shared(g, h, mx, old, xnew) private(k, c, ci, cj, ck, s0, s1, s, n, i, j, nm, &
    !$omp hv, hc, xo, xn, o, opts, pts, tp, tn, v, m, vs, ms, out, mout, kept, mkept, room, held, total, pn, pd, f, &
    !$omp tv, tm, bits, vraw, mraw, rest) schedule(dynamic, 4)
    do k = 1, mx%n
      c = mx%cell(k)
      if (.not. old%changed(c)) cycle
      s0 = mx%start(k)
      s1 = mx%start(k + 1) - 1
      n = s1 - s0 + 1
      old%sfac(s0:s1) = 1.0_wp
      old%sroom(s0:s1) = 0.0_wp
      old%sshift(:, s0:s1) = 0.0_wp
      ! in the frame `remap_new_cell` takes (about the new cell's centre)
      call g%cell_ijk(c, ci, cj, ck)
      call block_gather(g%ni, g%nj, ci, cj, ck, g%x, xo)
      call block_gather(g%ni, g%nj, ci, cj, ck, xnew, xn)
      o = sum(xn, 2)/8.0_wp
      call halves_about(o, xo, xn, opts, pts, hv, hc)
      out(1:n) = 0.0_wp
      mout(:, 1:n) = 0.0_wp
      kept(1:n) = 0.0_wp
      mkept(:, 1:n) = 0.0_wp
      old%skv(:, s0:s1) = 0.0_wp
      old%skm(:, :, s0:s1) = 0.0_wp
      do s = s0, s1
        old%so(:, s) = o
      end do
      bits = 0_i8
      ! (the triangles' swept regions as `swept_fluxes` takes them)
      call swept_cell(opts, pts, tv, tm)
      ! (every region with mass: the last one's part of a half that the
      ! planes cut is the half's less the others', one clip fewer)
      rest = all(mx%mass(s0:s1) > 0.0_wp) .and. n > 1
      do i = 1, 48
        ! what the old subcells keep
        vraw = 0.0_wp
        mraw = 0.0_wp
        do s = s0, s1
          if (.not. mx%mass(s) > 0.0_wp) cycle
          call region_planes(old, s0, s, o, pn, pd, nm)
          if (rest .and. s == s1) then
            call region_rest(opts(:, hv(:, i)), pn(:, 1:nm), pd(1:nm), vraw, mraw, v, m)
          else
            call region_piece(opts(:, hv(:, i)), pn(:, 1:nm), pd(1:nm), v, m)
          end if
          vraw = vraw + v
          mraw = mraw + m
          if (.not. v > 0.0_wp) cycle
          kept(s - s0 + 1) = kept(s - s0 + 1) + v
          mkept(:, s - s0 + 1) = mkept(:, s - s0 + 1) + m
          old%skv(hc(i), s) = old%skv(hc(i), s) + v
          old%skm(:, hc(i), s) = old%skm(:, hc(i), s) + m
        end do
        ! a region swept out through a face (`swept_fluxes`): the cell's
        v = tv(i)
        if (.not. v < 0.0_wp) cycle
        m = tm(i, :)
        tp = opts(:, hv(2:4, i))
        tn = pts(:, hv(2:4, i))
        call swept_split(mx, old, s0, s1, o, tp, tn, v, m, vs, ms)
        bits = ibset(bits, i - 1)
        old%sov(i, s0:s1) = vs(1:n)
        old%som(:, i, s0:s1) = ms(:, 1:n)
        out(1:n) = out(1:n) - vs(1:n)
        mout(:, 1:n) = mout(:, 1:n) - ms(:, 1:n)
      end do
      old%sout(s0:s1) = bits
      held = 0.0_wp
      do i = 1, n
        room(i) = max(kept(i) - out(i), 0.0_wp)
        if (out(i) > kept(i)) then
          f = max(kept(i), 0.0_wp)/out(i)
          old%sfac(s0 + i - 1) = f
          if (kept(i) > 0.0_wp) old%sshift(:, s0 + i - 1) = (mkept(:, i) - f*mout(:, i))/kept(i)
          held = held + out(i) - max(kept(i), 0.0_wp)
        end if
      end do
      if (.not. held > 0.0_wp) cycle
      total = sum(room(1:n))
      if (.not. total >= held) then
        ! (no room for it: the regions give what they sweep, and the step
        ! falls back to intersection if that breaks a bound)
        old%sfac(s0:s1) = 1.0_wp
        old%sshift(:, s0:s1) = 0.0_wp
        cycle
      end if
      old%sroom(s0:s1) = room(1:n)/total
    end do
    !$omp end parallel do
  end subroutine swept_budgets

  !> Volume v and first moment m of the part of the tetrahedron t inside
  !> the region pn(:, i).x <= pd(i) (0 if none; a tetrahedron wholly
  !> outside one plane is not clipped, one wholly inside by no plane).
  pure subroutine region_piece(t, pn, pd, v, m)
    real(wp), intent(in) :: t(3, 4), pn(:, :), pd(:)
    real(wp), intent(out) :: v, m(3)
    type(poly_t) :: p
    integer :: side, k
    v = 0.0_wp
    m = 0.0_wp
    side = hull_side(t, pn, pd)
    if (side == -1) return
    if (side == 0 .and. size(pd) == 1) then
      call tet_clip_moments(t, pn(:, 1), pd(1), v, m)
      return
    end if
    call poly_set_tet(p, t)
    if (side == 0) then
      do k = 1, size(pd)
        call poly_clip(p, pn(:, k), pd(k))
        if (p%nv == 0) return
      end do
    end if
    call poly_first_moments(p, v, m)
  end subroutine region_piece

  !> `region_piece` for the last region of a mixed cell, whose parts of t
  !> in the regions before it are vb and mb: where its planes cut t, what
  !> t holds beyond those (a difference at round-off is none).
  pure subroutine region_rest(t, pn, pd, vb, mb, v, m)
    real(wp), intent(in) :: t(3, 4), pn(:, :), pd(:), vb, mb(3)
    real(wp), intent(out) :: v, m(3)
    real(wp) :: vt
    if (hull_side(t, pn, pd) /= 0) then
      call region_piece(t, pn, pd, v, m)
      return
    end if
    vt = abs(tet_det(t))/6.0_wp
    v = vt - vb
    m = 0.25_wp*vt*((t(:, 1) + t(:, 2)) + (t(:, 3) + t(:, 4))) - mb
    if (.not. v > 1.0e-12_wp*vt) then
      v = 0.0_wp
      m = 0.0_wp
    end if
  end subroutine region_rest

  !> Where the convex hull of the points x(3, :) lies against the region
  !> pn(:, i).x <= pd(i): 1 wholly inside, -1 wholly outside one of the
  !> planes, 0 across.
  pure integer function hull_side(x, pn, pd) result(side)
    real(wp), intent(in) :: x(:, :), pn(:, :), pd(:)
    integer :: i, j, nout
    side = 1
    do i = 1, size(pd)
      nout = 0
      do j = 1, size(x, 2)
        if (dot_product(pn(:, i), x(:, j)) > pd(i)) nout = nout + 1
      end do
      if (nout == size(x, 2)) then
        side = -1
        return
      end if
      if (nout > 0) side = 0
    end do
  end function hull_side

  !> Signed volume v and first moment m of the part on the inner side of
  !> the planes pn(:, i).x <= pd(i) of the prism a triangle sweeps from tp
  !> to tn, its sides split into four triangles about their centres: the
  !> cone from the prism's centre over its 14 boundary triangles, each tet
  !> clipped and counted with its orientation's sign. The split depends on
  !> no vertex order, so the two cells that share the triangle (each
  !> seeing it from its side) share the region among the materials alike.
  pure subroutine prism_part(tp, tn, pn, pd, v, m)
    real(wp), intent(in) :: tp(3, 3), tn(3, 3), pn(:, :), pd(:)
    real(wp), intent(out) :: v, m(3)
    real(wp) :: t(3, 4), d, vv, mm(3), xs(3)
    integer :: k, i, e, e2, side
    type(poly_t) :: p
    v = 0.0_wp
    m = 0.0_wp
    t(:, 1) = (sum(tp, 2) + sum(tn, 2))/6.0_wp
    do k = 1, 14
      if (k == 1) then
        t(:, 2:4) = tp(:, [1, 3, 2])
      else if (k == 2) then
        t(:, 2:4) = tn
      else
        ! side e (edge e -> e2 of the triangle), its k-th quarter
        e = (k - 3)/4 + 1
        e2 = mod(e, 3) + 1
        xs = 0.25_wp*((tp(:, e) + tn(:, e2)) + (tp(:, e2) + tn(:, e)))
        t(:, 2) = xs
        select case (mod(k - 3, 4))
        case (0)
          t(:, 3) = tp(:, e)
          t(:, 4) = tp(:, e2)
        case (1)
          t(:, 3) = tp(:, e2)
          t(:, 4) = tn(:, e2)
        case (2)
          t(:, 3) = tn(:, e2)
          t(:, 4) = tn(:, e)
        case default
          t(:, 3) = tn(:, e)
          t(:, 4) = tp(:, e)
        end select
      end if
      d = tet_det(t)
      if (.not. abs(d) > 0.0_wp) cycle
      ! (a tetrahedron wholly outside a plane gives nothing, one inside
      ! every plane itself; only the planes that cut it are clipped by)
      side = hull_side(t, pn, pd)
      if (side == -1) cycle
      if (side == 1) then
        vv = abs(d)/6.0_wp
        mm = 0.25_wp*vv*((t(:, 1) + t(:, 2)) + (t(:, 3) + t(:, 4)))
      else if (size(pd) == 1) then
        ! (one plane, the common case: in closed form)
        call tet_clip_moments(t, pn(:, 1), pd(1), vv, mm)
      else
        call poly_set_tet(p, t)
        do i = 1, size(pd)
          call poly_clip(p, pn(:, i), pd(i))
          if (p%nv == 0) exit
        end do
        if (p%nv == 0) cycle
        call poly_first_moments(p, vv, mm)
      end if
      v = v + sign(1.0_wp, d)*vv
      m = m + sign(1.0_wp, d)*mm
    end do
  end subroutine prism_part

  !> The direction (1, 2, 3) of the edge between corners a and b of a cell
  !> (local numbering a = 1 + i + 2j + 4k: they differ in one bit).
  pure integer function edge_dir(a, b) result(d)
    integer, intent(in) :: a, b
    d = 1 + trailz(ieor(a - 1, b - 1))
  end function edge_dir

  !> True if the hex xn is an axis-aligned box (its nodes take just two
  !> values in each coordinate, in the corner order of `hex_corner`).
  pure logical function is_box(xn)
    real(wp), intent(in) :: xn(3, 8)
    integer :: a, d
    is_box = .true.
    do a = 2, 8
      do d = 1, 3
        if (btest(a - 1, d - 1)) then
          is_box = is_box .and. .not. abs(xn(d, a) - xn(d, 8)) > 0.0_wp
        else
          is_box = is_box .and. .not. abs(xn(d, a) - xn(d, 1)) > 0.0_wp
        end if
      end do
    end do
    is_box = is_box .and. all(xn(:, 8) > xn(:, 1))
  end function is_box

  ! ------------------------------------------------------------ assembly

  !> The corners of unchanged cells pass on the old subcell mass, momentum
  !> and kinetic energy (cke: in the frame of the nodal velocities, for the
  !> open faces' outflow count; `assemble` then uses cke for what a changed
  !> cell's corners hold beyond their own kinetic energy).
  subroutine unchanged_corners(g, h, old, cmass, cmom, cke, pcell)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(old_t), intent(in) :: old
    real(wp), intent(inout) :: cmass(:, :), cmom(:, :, :), cke(:, :), pcell(:, :)
    integer :: c, n, a, i
    ! (the unchanged cells the assembly and `open_faces` read: those
    ! around a changed node)
    do i = 1, size(old%lnear)
      c = old%lnear(i)
      if (old%changed(c)) cycle
      n = g%node0(c)
      pcell(:, c) = 0.0_wp
      do a = 1, 8
        cmass(a, c) = h%mcorner(a, c)
        cmom(:, a, c) = h%mcorner(a, c)*h%u(:, n + g%corner_offset(a))
        cke(a, c) = 0.5_wp*h%mcorner(a, c)*sum(h%u(:, n + g%corner_offset(a))**2)
      end do
    end do
  end subroutine unchanged_corners

  !> Each open face's innermost point along its axis (the largest or
  !> smallest coordinate of its nodes), on the old grid xold (bold) and the
  !> new grid xnew (bnew), over the face nodes of the grid ix (those with
  !> use true, if given); huge on other faces.
  pure subroutine open_face_bounds(ix, bc, xold, xnew, bold, bnew, use)
    class(grid_index_t), intent(in) :: ix
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: xold(:, :), xnew(:, :)
    real(wp), intent(out) :: bold(6), bnew(6)
    logical, intent(in), optional :: use(:)
    integer :: f, a, i, j, k, n, lo(3), hi(3)
    logical :: high
    do f = 1, 6
      a = (f + 1)/2
      high = mod(f, 2) == 0
      bold(f) = merge(huge(1.0_wp), -huge(1.0_wp), high)
      bnew(f) = bold(f)
      if (bc%kind(f) /= BC_INFLOW .and. bc%kind(f) /= BC_OUTFLOW) cycle
      ! (the face's plane of nodes, if this grid holds it: the nodes whose
      ! `node_faces` has face f)
      lo = ix%nlo
      hi = ix%nhi
      lo(a) = merge(ix%gn(a), 0, high) - ix%off(a)
      hi(a) = lo(a)
      if (lo(a) < ix%nlo(a) .or. lo(a) > ix%nhi(a)) cycle
      do k = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            n = ix%node(i, j, k)
            if (present(use)) then
              if (.not. use(n)) cycle
            end if
            if (high) then
              bold(f) = min(bold(f), xold(a, n))
              bnew(f) = min(bnew(f), xnew(a, n))
            else
              bold(f) = max(bold(f), xold(a, n))
              bnew(f) = max(bnew(f), xnew(a, n))
            end if
          end do
        end do
      end do
    end do
  end subroutine open_face_bounds

  !> Where the open faces (inflow, outflow) of the new grid xnew and of the
  !> old grid g%x part, at any depth, given each open face's innermost
  !> points (`open_face_bounds`: bold on the old grid, bnew on the new). A
  !> new cell may hold part of the gap between an open face f and the old
  !> grid if it reaches past bold(f) along the face's axis; gap_face(c) is
  !> then the nearest such face (fewest cells away, in the whole grid's
  !> indices; the first in face order on a tie), and gap_cell(c) the old
  !> cell at face f on the same index line (the cell itself if it lies at
  !> the face), whose state an outflow face extrapolates into the gap (0 if
  !> that cell is not in g, a window; an inflow face's gap_cell is c). A
  !> necessary condition only; the fragments say how much is actually
  !> missing.
  subroutine open_face_cells(g, bc, xnew, bold, gap_face, gap_cell, cells)
    type(grid_t), intent(in) :: g
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: xnew(:, :), bold(6)
    integer, intent(out) :: gap_face(:), gap_cell(:)
    !> the cells that may have a gap (those the remap changes; absent: all)
    integer, intent(in), optional :: cells(:)
    logical :: isopen(6)
    real(wp) :: xn(3, 8)
    integer :: f, a, c, i, n, ijk(3), q(3), depth, best

    isopen = bc%kind == BC_INFLOW .or. bc%kind == BC_OUTFLOW
    do c = 1, g%ncell
      gap_face(c) = 0
      gap_cell(c) = c
    end do
    n = g%ncell
    if (present(cells)) n = size(cells)
    do i = 1, n
      c = i
      if (present(cells)) c = cells(i)
      call g%cell_ijk(c, ijk(1), ijk(2), ijk(3))
      call g%gather(c, xnew, xn)
      best = huge(1)
      do f = 1, 6
        if (.not. isopen(f)) cycle
        a = (f + 1)/2
        ! (q: the face's cell on the index line, in g's indices)
        q = ijk
        if (mod(f, 2) == 0) then
          if (.not. maxval(xn(a, :)) > bold(f)) cycle
          q(a) = g%gn(a) - g%off(a)
        else
          if (.not. minval(xn(a, :)) < bold(f)) cycle
          q(a) = 1 - g%off(a)
        end if
        depth = abs(q(a) - ijk(a))
        if (depth < best) then
          best = depth
          gap_face(c) = f
          if (bc%kind(f) == BC_INFLOW) then
            gap_cell(c) = c
          else if (q(a) >= g%clo(a) .and. q(a) <= g%chi(a)) then
            gap_cell(c) = g%cell(q(1), q(2), q(3))
          else
            gap_cell(c) = 0
          end if
        end if
      end do
    end do
  end subroutine open_face_cells

  !> Whether an old cell with nodes xo reaches past the innermost point
  !> bnew of an open face (isopen) of the new grid (`open_face_bounds`).
  pure logical function reaches_out(isopen, xo, bnew)
    logical, intent(in) :: isopen(6)
    real(wp), intent(in) :: xo(3, 8), bnew(6)
    integer :: f, a
    reaches_out = .false.
    do f = 1, 6
      if (.not. isopen(f)) cycle
      a = (f + 1)/2
      if (mod(f, 2) == 0) then
        reaches_out = reaches_out .or. maxval(xo(a, :)) > bnew(f)
      else
        reaches_out = reaches_out .or. minval(xo(a, :)) < bnew(f)
      end if
    end do
  end function reaches_out

  !> Makes zone (`remap_zone_t`) the window wg's around the block g (both
  !> on the whole grid's indices through their offsets): own, the block's
  !> owned cells and the nodes it counts; compute, own widened by width
  !> layers; a new cell searched within reach index steps at most.
  subroutine remap_zone_block(zone, g, wg, width, reach, err)
    type(remap_zone_t), intent(out) :: zone
    class(grid_index_t), intent(in) :: g, wg
    integer, intent(in) :: width, reach
    type(error_t), allocatable, intent(inout) :: err
    integer :: i, j, k, stat, ijk(3)
    allocate(zone%compute(wg%ncell), zone%own(wg%ncell), zone%own_node(wg%nnode), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_zone_block', 'out of memory')
      return
    end if
    zone%reach_max = reach
    do k = 1, wg%nk
      do j = 1, wg%nj
        do i = 1, wg%ni
          ! (in the block's indices)
          ijk = [i, j, k] + wg%off - g%off
          zone%own(wg%cell(i, j, k)) = all(ijk >= g%clo .and. ijk <= g%chi)
          zone%compute(wg%cell(i, j, k)) = all(ijk >= g%clo - width .and. ijk <= g%chi + width)
        end do
      end do
    end do
    do k = 0, wg%nk
      do j = 0, wg%nj
        do i = 0, wg%ni
          ijk = [i, j, k] + wg%off - g%off
          zone%own_node(wg%node(i, j, k)) = all(ijk >= g%ulo .and. ijk <= g%nhi)
        end do
      end do
    end do
  end subroutine remap_zone_block

  !> Makes zone (`remap_zone_t`, built by `remap_zone_block`) ready for
  !> the remap of the window ix with open faces, from the window's old and
  !> new node positions xold, xnew: the bins over its moved cells, and each
  !> open face's innermost points over the nodes its block counts (the
  !> caller takes the extremes over the blocks: `open_face_bounds`' bold
  !> and bnew for the whole grid, exact in any order). No far cells yet
  !> (`remap_zone_far`).
  subroutine remap_zone_open(zone, ix, bc, xold, xnew, err)
    type(remap_zone_t), intent(inout) :: zone
    type(grid_index_t), intent(in) :: ix
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: xold(:, :), xnew(:, :)
    type(error_t), allocatable, intent(inout) :: err
    logical, allocatable :: moved(:)
    integer :: stat
    if (allocated(zone%far_ijk)) deallocate(zone%far_ijk, zone%far_box)
    allocate(moved(ix%ncell), zone%far_ijk(3, 0), zone%far_box(6, 0), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_zone_open', 'out of memory for the moved cells')
      return
    end if
    moved = cells_moved(ix, xold, xnew)
    call remap_bins_build(ix%ni, ix%nj, ix%nk, xold, moved, zone%bins, err)
    call open_face_bounds(ix, bc, xold, xnew, zone%bold, zone%bnew, zone%own_node)
    zone%open = .true.
  end subroutine remap_zone_open

  !> Whether each cell of the block ix (no ghosts) has a node that moves
  !> from xold to xnew (as `prepare_old` marks them changed): the nodes
  !> compared in blocks first (`blocks_moved`; most nodes of a window do not
  !> move), each moved node marking its cells.
  pure function cells_moved(ix, xold, xnew) result(moved)
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: xold(:, :), xnew(:, :)
    logical :: moved(ix%ncell)
    integer, parameter :: block = 32
    logical, allocatable :: some(:)
    integer :: n, n0, i, j, k, ci, cj, ck, stat
    moved = .false.
    ! (without room for the blocks' flags every node is compared)
    allocate(some((ix%nnode + block - 1)/block), stat=stat)
    if (stat == 0) call blocks_moved(ix%nnode, xnew, xold, block, some)
    do n0 = 1, ix%nnode, block
      if (allocated(some)) then
        if (.not. some((n0 - 1)/block + 1)) cycle
      end if
      do n = n0, min(n0 + block - 1, ix%nnode)
        if (.not. any(abs(xnew(:, n) - xold(:, n)) > 0.0_wp)) cycle
        ! (node (i,j,k) is corner 1 of cell (i+1,j+1,k+1))
        call ix%node_ijk(n, i, j, k)
        do ck = max(k, ix%slo(3)), min(k + 1, ix%shi(3))
          do cj = max(j, ix%slo(2)), min(j + 1, ix%shi(2))
            do ci = max(i, ix%slo(1)), min(i + 1, ix%shi(1))
              moved(ix%cell(ci, cj, ck)) = .true.
            end do
          end do
        end do
      end do
    end do
  end function cells_moved

  !> The window ix's cells (of its zone, after `remap_zone_open` and the
  !> bounds' reduction) that may be far cells of other windows: those its
  !> block owns that move and reach past an open face of the new grid,
  !> with their whole-grid indices ijk(3, n) and old boxes box(6, n).
  subroutine remap_zone_beyond(zone, ix, bc, xold, xnew, ijk, box, err)
    type(remap_zone_t), intent(in) :: zone
    type(grid_index_t), intent(in) :: ix
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: xold(:, :), xnew(:, :)
    integer, allocatable, intent(out) :: ijk(:, :)
    real(wp), allocatable, intent(out) :: box(:, :)
    type(error_t), allocatable, intent(inout) :: err
    logical, allocatable :: pick(:)
    logical :: isopen(6)
    real(wp) :: xo(3, 8)
    integer :: c, n, stat
    isopen = bc%kind == BC_INFLOW .or. bc%kind == BC_OUTFLOW
    allocate(pick(ix%ncell), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_zone_beyond', 'out of memory')
      return
    end if
    pick = cells_moved(ix, xold, xnew) .and. zone%own
    do c = 1, ix%ncell
      if (.not. pick(c)) cycle
      call ix%gather(c, xold, xo)
      pick(c) = reaches_out(isopen, xo, zone%bnew)
    end do
    allocate(ijk(3, count(pick)), box(6, count(pick)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_zone_beyond', 'out of memory')
      return
    end if
    n = 0
    do c = 1, ix%ncell
      if (.not. pick(c)) cycle
      n = n + 1
      call ix%cell_ijk(c, ijk(1, n), ijk(2, n), ijk(3, n))
      ijk(:, n) = ijk(:, n) + ix%off
      call ix%gather(c, xold, xo)
      box(1:3, n) = minval(xo, 2)
      box(4:6, n) = maxval(xo, 2)
    end do
  end subroutine remap_zone_beyond

  !> What other windows need to know of this one for their far cells: its
  !> cells' whole-grid index range (lo, hi) and the box of its computed
  !> cells on the new grid xnew (lo, hi), as reals (12).
  pure function remap_zone_reach_box(zone, ix, xnew) result(r)
    type(remap_zone_t), intent(in) :: zone
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: xnew(:, :)
    real(wp) :: r(12)
    integer :: c, n0, a
    r(1:3) = real(ix%off + 1, wp)
    r(4:6) = real(ix%off + [ix%ni, ix%nj, ix%nk], wp)
    r(7:9) = huge(1.0_wp)
    r(10:12) = -huge(1.0_wp)
    ! (the extremes over the computed cells' nodes: exact in any order)
    do c = 1, ix%ncell
      if (.not. zone%compute(c)) cycle
      n0 = ix%node0(c)
      do a = 1, 8
        r(7:9) = min(r(7:9), xnew(:, n0 + ix%corner_offset(a)))
        r(10:12) = max(r(10:12), xnew(:, n0 + ix%corner_offset(a)))
      end do
    end do
  end function remap_zone_reach_box

  !> Whether the cell at whole-grid index ijk with box box(6) may be a far
  !> cell of the window described by r (`remap_zone_reach_box`): outside
  !> its index range, its box meeting that of the window's computed cells.
  pure logical function remap_zone_wants(r, ijk, box)
    real(wp), intent(in) :: r(12), box(6)
    integer, intent(in) :: ijk(3)
    remap_zone_wants = .false.
    if (r(7) > r(10)) return
    remap_zone_wants = (any(ijk < nint(r(1:3))) .or. any(ijk > nint(r(4:6)))) .and. &
                       remap_box_meets(box(1:3), box(4:6), r(7:9), r(10:12))
  end function remap_zone_wants

  !> The far cells of zone (`remap_zone_t`) from candidates ijk, box (every
  !> block's `remap_zone_beyond` that some window may want), given this
  !> window's description r (`remap_zone_reach_box`).
  subroutine remap_zone_far(zone, r, ijk, box)
    type(remap_zone_t), intent(inout) :: zone
    real(wp), intent(in) :: r(12)
    integer, intent(in) :: ijk(:, :)
    real(wp), intent(in) :: box(:, :)
    logical :: keep(size(ijk, 2))
    integer :: q
    keep = [(remap_zone_wants(r, ijk(:, q), box(:, q)), q = 1, size(ijk, 2))]
    zone%far_ijk = reshape(pack(ijk, spread(keep, 1, 3)), [3, count(keep)])
    zone%far_box = reshape(pack(box, spread(keep, 1, 6)), [6, count(keep)])
  end subroutine remap_zone_far

  !> The flows through open faces (stats%mass_in ... energy_out) from
  !> their exact sums stats%flow (after adding those of several windows).
  pure subroutine remap_stats_flows(stats)
    type(remap_stats_t), intent(inout) :: stats
    real(wp) :: v(10)
    integer :: q
    v = [(xsum_value(stats%flow(q)), q = 1, 10)]
    stats%mass_in = v(1)
    stats%momentum_in = v(2:4)
    stats%energy_in = v(5)
    stats%mass_out = v(6)
    stats%momentum_out = v(7:9)
    stats%energy_out = v(10)
  end subroutine remap_stats_flows

  !> Open faces. What the old grid had beyond them has left: the outflow is
  !> the old totals less what the new cells received. The gap between an
  !> open face and the Lagrangian boundary that moved in from it, however
  !> many cells deep, is filled, corner by corner, with the face's inflow
  !> state, or at an outflow face with the state of the old cell at the face
  !> on the same index line (gap_cell: its largest material, its velocity):
  !> zero-gradient extrapolation. The gap's centroid is taken as the new
  !> cell's centre (it only steers MoF in mixed boundary cells). The flows
  !> are exact sums over the cells own and nodes own_node (stats%flow).
  subroutine open_faces(g, h, mx, bc, old, xnew, gap_face, gap_cell, own, own_node, avol, amom, amass, aie, cdef, &
                        cmom, cke, cland, pcell, stats)
    type(grid_t), intent(in) :: g
    type(hydro_t), intent(in) :: h
    type(mixed_t), intent(in) :: mx
    type(bc_t), intent(in) :: bc
    !> (its node marks used and left false)
    type(old_t), intent(inout) :: old
    real(wp), intent(in) :: xnew(:, :), cdef(:, :)
    integer, intent(in) :: gap_face(:), gap_cell(:)
    logical, intent(in) :: own(:), own_node(:)
    real(wp), intent(inout) :: avol(:, :), amom(:, :, :), amass(:, :), aie(:, :), cmom(:, :, :), cke(:, :), &
                               cland(:, :), pcell(:, :)
    type(remap_stats_t), intent(inout) :: stats
    real(wp) :: xn(3, 8), vcell, rho, e, u(3), dm
    integer :: c, n, a, f, k, ks, gc, d, i
    ! (flow: mass, momentum, energy in (1:5), then out (6:10))
    integer, parameter :: m_out = 6, p_out = 7, e_out = 10

    ! outflow: the old totals less what was received, over what the remap
    ! can change: the changed cells, their nodes, and the corners of the
    ! unchanged cells at those nodes (everywhere else old and new are the
    ! same cells and nodes; the cells and nodes `remap_euler_step` checks
    ! conservation over). With old%node marking the changed cells' nodes.
    old%node(old%lnode) = .true.
    associate (fl => stats%flow)
      do i = 1, size(old%lchanged)
        c = old%lchanged(i)
        if (.not. own(c)) cycle
        call xsum_add(fl(m_out), h%mass(c))
        call xsum_add(fl(e_out), h%mass(c)*h%e(c))
        do k = 1, size(amass, 1)
          call xsum_add(fl(m_out), -amass(k, c))
          call xsum_add(fl(e_out), -aie(k, c))
        end do
        ! a changed cell's momentum and kinetic energy are its totals (its
        ! corners hold what landed in them, part of those), an unchanged
        ! cell's its corners'
        ! (pcell(4) is about uref: `old_t`)
        call xsum_add(fl(e_out), -(pcell(4, c) + dot_product(old%uref(:, c), pcell(1:3, c)) - &
                                   0.5_wp*sum(amass(:, c))*dot_product(old%uref(:, c), old%uref(:, c))))
        do d = 1, 3
          call xsum_add(fl(p_out + d - 1), -pcell(d, c))
        end do
      end do
      do i = 1, size(old%lnode)
        n = old%lnode(i)
        if (.not. own_node(n)) cycle
        do d = 1, 3
          call xsum_add(fl(p_out + d - 1), h%mnode(n)*h%u(d, n))
        end do
        call xsum_add(fl(e_out), 0.5_wp*h%mnode(n)*sum(h%u(:, n)**2))
      end do
      do i = 1, size(old%lnear)
        c = old%lnear(i)
        if (.not. own(c) .or. old%changed(c)) cycle
        do a = 1, 8
          if (.not. old%node(g%node0(c) + g%corner_offset(a))) cycle
          call xsum_add(fl(e_out), -cke(a, c))
          do d = 1, 3
            call xsum_add(fl(p_out + d - 1), -cmom(d, a, c))
          end do
        end do
      end do
    end associate
    old%node(old%lnode) = .false.

    ! inflow: fill the gaps
    do i = 1, size(old%lchanged)
      c = old%lchanged(i)
      f = gap_face(c)
      if (f == 0) cycle
      call g%gather(c, xnew, xn)
      vcell = hex_volume(xn)
      gc = gap_cell(c)
      if (bc%kind(f) == BC_INFLOW) then
        k = bc%inflow_mat(f)
        rho = bc%inflow_rho(f)
        e = bc%inflow_e(f)
        u = bc%velocity(:, f)
      else if (h%mat(gc) > 0) then
        k = h%mat(gc)
        rho = old%rho(gc)
        e = old%e(gc)
      else
        ks = mx%start(-h%mat(gc)) - 1 + maxloc(mx%vf(mx%start(-h%mat(gc)):mx%start(-h%mat(gc) + 1) - 1), 1)
        k = mx%mat(ks)
        rho = old%rho(g%ncell + ks)
        e = old%e(g%ncell + ks)
      end if
      ! or the old cell's mean velocity
      if (bc%kind(f) /= BC_INFLOW) u = old%ucell(:, gc)
      do a = 1, 8
        ! a gap of round-off size is no gap
        if (.not. cdef(a, c) > 1.0e-12_wp*vcell) cycle
        dm = rho*cdef(a, c)
        avol(k, c) = avol(k, c) + cdef(a, c)
        amom(:, k, c) = amom(:, k, c) + cdef(a, c)*sum(xn, 2)/8.0_wp
        amass(k, c) = amass(k, c) + dm
        aie(k, c) = aie(k, c) + dm*e
        pcell(1:3, c) = pcell(1:3, c) + dm*u
        pcell(4, c) = pcell(4, c) + 0.5_wp*dm*sum((u - old%uref(:, c))**2)
        cmom(:, a, c) = cmom(:, a, c) + dm*u
        cland(a, c) = cland(a, c) + dm
        if (.not. own(c)) cycle
        call xsum_add(stats%flow(1), dm)
        do d = 1, 3
          call xsum_add(stats%flow(1 + d), dm*u(d))
        end do
        call xsum_add(stats%flow(5), dm*(e + 0.5_wp*dot_product(u, u)))
      end do
    end do
    call remap_stats_flows(stats)
  end subroutine open_faces

  !> The new state from the fragments: cells and mixed cells, nodal masses
  !> and velocities, and the kinetic energy returned to internal energy.
  subroutine assemble(g, h, mx, nmat, bc, old, xnew, par, avol, amom, amass, aie, cmass, cmom, cke, cland, pcell, &
                      vcell, stats, err, own, own_node, written, deficit_cells, patch, deficit_mine, donors)
    type(grid_t), intent(inout) :: g
    type(hydro_t), intent(inout) :: h
    type(mixed_t), intent(inout) :: mx
    integer, intent(in) :: nmat
    type(bc_t), intent(in) :: bc
    type(old_t), intent(inout) :: old
    real(wp), intent(in) :: xnew(:, :)
    type(remap_params_t), intent(in) :: par
    real(wp), intent(inout) :: avol(:, :), amom(:, :, :), amass(:, :), aie(:, :), cmass(:, :), cmom(:, :, :), &
                               cke(:, :)
    real(wp), intent(in) :: cland(:, :), pcell(:, :)
    !> the changed new cells' volumes (`hex_volume` of their nodes in xnew,
    !> taken for the volume check)
    real(wp), intent(in) :: vcell(:)
    type(remap_stats_t), intent(inout) :: stats
    type(error_t), allocatable, intent(inout) :: err
    !> a window's (`remap_zone_t`): the cells and nodes the stats count; the
    !> kinetic energy deficits are found there (deficit_mine: the own
    !> cells'), their donors' energies given (donors: deficit_cells given)
    !> or repaired over the patch (`remap_zone_t`)
    logical, intent(in), optional :: own(:), own_node(:)
    !> the cells whose state may have been written (`remap_euler_step`)
    integer, allocatable, intent(out), optional :: written(:)
    integer, intent(in), optional :: deficit_cells(:)
    type(deficit_patch_t), intent(in), optional :: patch
    integer, allocatable, intent(out), optional :: deficit_mine(:)
    type(deficit_patch_t), intent(out), optional :: donors
    type(mixed_t) :: nx
    integer, allocatable :: nmix(:), visit(:), n0(:)
    real(wp), allocatable :: dk(:), ie(:), iav(:), avail(:), navail(:), kdef(:), rdef(:), uc(:, :)
    real(wp) :: xn(3, 8), vtot, mnew, vs(8), take, frac, vmean(3), theta, surplus, kdev, kmean, kland, kscale, short_c
    integer :: c, n, a, k, s, kk, big, nslot, nmixed, ncell, stat, i, phase
    character(len=200) :: msg
    logical :: keep(max_mat), short, wide, limited

    ncell = g%ncell
    wide = .false.
    ! materials of the changed cells: merge slivers into the largest
    allocate(nmix(ncell), ie(ncell), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the assembly work arrays'))
      return
    end if
    ! (read at the near and the mixed cells only: the cells `visit`)
    nmix(old%lnear) = 0
    do k = 1, mx%n
      nmix(mx%cell(k)) = mx%start(k + 1) - mx%start(k)
    end do
    do i = 1, size(old%lchanged)
      c = old%lchanged(i)
      nmix(c) = 0
      vtot = sum(avol(:, c))
      big = maxloc(avol(:, c), 1)
      keep(1:nmat) = avol(:, c) > sliver_fraction(par, old%swept)*vtot .and. amass(:, c) > 0.0_wp
      keep(big) = .true.
      do k = 1, nmat
        if (keep(k) .or. .not. abs(avol(k, c)) > 0.0_wp) cycle
        if (counted(c)) stats%slivers_merged = stats%slivers_merged + 1
        amass(big, c) = amass(big, c) + amass(k, c)
        aie(big, c) = aie(big, c) + aie(k, c)
        avol(big, c) = avol(big, c) + avol(k, c)
        amom(:, big, c) = amom(:, big, c) + amom(:, k, c)
        amass(k, c) = 0.0_wp
        aie(k, c) = 0.0_wp
        avol(k, c) = 0.0_wp
      end do
      if (count(keep(1:nmat)) > 1) nmix(c) = count(keep(1:nmat))
    end do

    ! the cells the assembly sets: the near cells and the mixed ones, in
    ! increasing order (every cell when a deficit repair reached further)
    call sorted_union(old%lnear, mx%cell(1:mx%n), visit, err)
    if (allocated(err)) return
    ! new mixed-cell storage: unchanged cells keep theirs, in the same order
    nmixed = 0
    nslot = 0
    do i = 1, size(visit)
      if (nmix(visit(i)) == 0) cycle
      nmixed = nmixed + 1
      nslot = nslot + nmix(visit(i))
    end do
    call mixed_allocate(nx, nmixed, nslot, err)
    if (allocated(err)) return
    kk = 0
    do i = 1, size(visit)
      c = visit(i)
      if (nmix(c) == 0) cycle
      kk = kk + 1
      nx%cell(kk) = c
      nx%start(kk + 1) = nx%start(kk) + nmix(c)
    end do

    ! nodes: sums over the corners around them; KE difference to cells
    allocate(dk(g%nnode), navail(g%nnode), iav(ncell), avail(ncell), kdef(ncell), rdef(ncell), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the nodal work arrays'))
      return
    end if
    ! (the loops below visit the changed cells, the cells around the changed
    ! nodes (near) and the changed nodes, in increasing order: what the
    ! others would add is zero)
    ! (old%node: emptied again at the end)
    old%node(old%lnode) = .true.
    ! (kdef, ie, iav, rdef, avail are read at the near cells only, unless
    ! the deficit repair reaches further: `wide`, below)
    kdef(old%lnear) = 0.0_wp
    ! a changed cell's corners: its new mass M shared by subcell volume
    ! (Eq. 16 on the new grid), its momentum P shared the same way plus the
    ! landed momenta's deviations from its mean velocity V = P/M:
    !   p_a = w_a P + theta (Q_a - L_a V),
    ! w_a the subcell's volume share, L_a and Q_a the mass and momentum that
    ! landed in the corner. The deviations add up to zero (momentum is
    ! conserved); with theta = 1 a corner whose subcell received the mass
    ! Eq. 16 gives it keeps the velocity that landed (the remap tends to
    ! the identity as the grid stops moving). A corner that received more
    ! than its share of mass (L_a > w_a M: a subcell of the new cell in the
    ! dense part of a contact) would amplify the deviation by L_a/(w_a M);
    ! theta = min(1, min_a w_a M/L_a) keeps every corner's velocity between
    ! V and the landed one, within the old velocities. The corner's kinetic
    ! energy is its own, |p_a|^2/(2 w_a M), plus cke(a), its volume share of
    ! what the cell received beyond their sum (never negative but for the
    ! shifts' round-off: by convexity the corners hold at most the
    ! fragments' kinetic energy), so that a node gets at least its kinetic
    ! energy.
    !$omp parallel do default(none) shared(g, old, xnew, amass, aie, pcell, cmass, cmom, cke, cland, kdef) &
    !$omp private(i, c, xn, vs, mnew, a, vmean, theta, surplus, kdev, kmean, kland, kscale, limited) schedule(static)
    do i = 1, size(old%lchanged)
      c = old%lchanged(i)
      call g%gather(c, xnew, xn)
      call hex_subcell_volumes(xn, vs)
      vs = vs/sum(vs)
      ! (a cell warped so far that a corner's share of its volume is not
      ! positive, as the intersection may meet in a first part of the way:
      ! equal shares, since a corner mass of zero or less has no velocity
      ! and its kinetic energy would escape the sums below)
      if (.not. all(vs > 0.0_wp)) vs = 0.125_wp
      mnew = sum(amass(:, c))
      vmean = pcell(1:3, c)/mnew
      theta = 1.0_wp
      kdev = 0.0_wp
      do a = 1, 8
        if (abs(cland(a, c)) > vs(a)*mnew) theta = min(theta, vs(a)*mnew/abs(cland(a, c)))
        kdev = kdev + 0.5_wp*sum((cmom(:, a, c) - cland(a, c)*vmean)**2)/(vs(a)*mnew)
      end do
      ! The corners' kinetic energy is 1/2 M |V|^2 + theta^2 kdev (the
      ! deviations add up to zero). The velocity's linear part hands out its
      ! kinetic energy to first order only, so the corners may hold more
      ! than the cell received; the cell pays the difference from its own
      ! internal energy (kdef), at most half of it (theta is reduced
      ! further where it would take more: in a cold gas any larger deficit
      ! drove the energy negative), and its nodes get at least their own
      ! kinetic energy, never a deficit to take from the cells around.
      ! kland: the kinetic energy that landed about V (pcell(4) is about
      ! uref). Negative only through the linear part's first-order energy,
      ! or round-off: the difference of two sums of size kscale, exact to
      ! some hundred eps of it (a cold gas with a velocity precursor has
      ! nodes whose velocities differ by orders of magnitude; uref then
      ! lies far from V). A negative value within that is zero, not a
      ! deficit the cell's internal energy (none, in a cold gas) must pay.
      kscale = 0.5_wp*mnew*sum((vmean - old%uref(:, c))**2)
      kland = pcell(4, c) - kscale
      if (kland < 0.0_wp .and. -kland < 1.0e-13_wp*(abs(pcell(4, c)) + kscale)) kland = 0.0_wp
      kmean = kland + 0.5_wp*sum(max(aie(:, c), 0.0_wp))
      ! (kmean < 0, round-off in a cold gas, with kdev = 0: theta stays)
      limited = theta**2*kdev > kmean .and. kdev > 0.0_wp
      if (limited) theta = sqrt(max(kmean, 0.0_wp)/kdev)
      do a = 1, 8
        cmass(a, c) = mnew*vs(a)
        cmom(:, a, c) = vs(a)*pcell(1:3, c) + theta*(cmom(:, a, c) - cland(a, c)*vmean)
      end do
      surplus = kland - theta**2*kdev
      ! (theta set so that the corners hold kmean: the cell then pays half
      ! its positive internal energy at most, not that plus the round-off of
      ! theta**2 kdev against kmean, which in a nearly cold gas is larger
      ! than the energy and would leave it below zero)
      if (limited .and. kmean > 0.0_wp) surplus = max(surplus, -0.5_wp*sum(max(aie(:, c), 0.0_wp)))
      kdef(c) = min(surplus, 0.0_wp)
      cke(:, c) = vs*max(surplus, 0.0_wp)
    end do
    !$omp end parallel do
    h%mnode(old%lnode) = 0.0_wp
    h%u(:, old%lnode) = 0.0_wp
    ! (the near cells' first nodes, for the loops over their corners below;
    ! allocated here, which keeps GCC from taking its bounds for
    ! uninitialized)
    allocate(n0(size(old%lnear)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the nodal work arrays'))
      return
    end if
    do i = 1, size(old%lnear)
      n0(i) = g%node0(old%lnear(i))
    end do
    do i = 1, size(old%lnear)
      c = old%lnear(i)
      n = n0(i)
      do a = 1, 8
        if (.not. old%node(n + g%corner_offset(a))) cycle
        h%mnode(n + g%corner_offset(a)) = h%mnode(n + g%corner_offset(a)) + cmass(a, c)
        ! (by `add_values`)
        call add_values(3, cmom(:, a, c), h%u(1, n + g%corner_offset(a)))
      end do
    end do
    do i = 1, size(old%lnode)
      n = old%lnode(i)
      if (.not. h%mnode(n) > 0.0_wp) then
        call error_set(err, 'remap_euler_step', 'node '//itoa(n)//' received no mass')
        return
      end if
      h%u(:, n) = h%u(:, n)/h%mnode(n)
    end do
    ! what the node's corners hold beyond its kinetic energy, about its
    ! velocity (`old_t`): sum_a |p_a - m_a u_n|^2/(2 m_a) (never negative)
    ! plus what the changed cells' corners received beyond their own
    dk(old%lnode) = 0.0_wp
    do i = 1, size(old%lnear)
      c = old%lnear(i)
      n = n0(i)
      do a = 1, 8
        k = n + g%corner_offset(a)
        if (.not. old%node(k)) cycle
        if (cmass(a, c) > 0.0_wp) dk(k) = dk(k) + 0.5_wp*sum((cmom(:, a, c) - cmass(a, c)*h%u(:, k))**2)/cmass(a, c)
        if (old%changed(c)) dk(k) = dk(k) + cke(a, c)
      end do
    end do
    ! the velocity conditions: the momentum and kinetic energy they take
    ! (the other nodes' velocities met them before: unchanged)
    allocate(uc(3, size(old%lnode)), stat=stat)
    if (stat /= 0) then
      call error_set(err, 'remap_euler', error_no_memory('the nodal work arrays'))
      return
    end if
    uc = h%u(:, old%lnode)
    call bc_constrain_nodes(bc, g, old%lnode, h%u)
    stats%momentum_constrained = 0.0_wp
    do i = 1, size(old%lnode)
      n = old%lnode(i)
      if (node_counted(n)) stats%momentum_constrained = stats%momentum_constrained + h%mnode(n)*(uc(:, i) - h%u(:, n))
      dk(n) = dk(n) + 0.5_wp*h%mnode(n)*dot_product(uc(:, i) - h%u(:, n), uc(:, i) + h%u(:, n))
    end do
    stats%ke_to_internal = 0.0_wp
    do i = 1, size(old%lnode)
      if (node_counted(old%lnode(i))) stats%ke_to_internal = stats%ke_to_internal + dk(old%lnode(i))
    end do

    ! The kinetic energy averaging returns (dk > 0) goes to the cells around
    ! the node by corner mass. Where the node's new kinetic energy exceeds
    ! what it received (dk < 0: only where a velocity condition raised the
    ! node's kinetic energy, a piston), the difference is taken from the
    ! internal energy the cells around it have above zero, each cell offering
    ! an eighth of its own to each of its nodes, so that no cell (and, below,
    ! no material) is driven negative by it. A deficit larger than all of
    ! that (cold gas: nothing above zero around the node) is taken from the
    ! nearest cells that still have energy to give (`repair_deficits`), and
    ! only what none of those has is taken by mass.
    do i = 1, size(old%lnear)
      avail(old%lnear(i)) = cell_avail(old%lnear(i))
    end do
    navail(old%lnode) = 0.0_wp
    do i = 1, size(old%lnear)
      c = old%lnear(i)
      n = n0(i)
      do a = 1, 8
        if (.not. old%node(n + g%corner_offset(a))) cycle
        navail(n + g%corner_offset(a)) = navail(n + g%corner_offset(a)) + 0.125_wp*(avail(c) + kdef(c))
      end do
    end do
    ! what the cell pays for its corners' kinetic energy, by positive energy
    ie(old%lnear) = 0.0_wp
    iav(old%lnear) = kdef(old%lnear)
    rdef(old%lnear) = 0.0_wp
    do i = 1, size(old%lnear)
      c = old%lnear(i)
      n = n0(i)
      do a = 1, 8
        if (.not. old%node(n + g%corner_offset(a))) cycle
        take = dk(n + g%corner_offset(a))
        ! (a deficit beyond what the cells around offer leaves a residual)
        short = take < 0.0_wp .and. .not. -take < navail(n + g%corner_offset(a))
        if (take < 0.0_wp .and. navail(n + g%corner_offset(a)) > 0.0_wp) then
          frac = min(1.0_wp, -take/navail(n + g%corner_offset(a)))
          iav(c) = iav(c) - frac*0.125_wp*(avail(c) + kdef(c))
          take = take + frac*navail(n + g%corner_offset(a))
        end if
        ie(c) = ie(c) + take*cmass(a, c)/h%mnode(n + g%corner_offset(a))
        if (short) rdef(c) = rdef(c) + take*cmass(a, c)/h%mnode(n + g%corner_offset(a))
      end do
    end do
    ! A cell that would end below zero (its corners' kinetic energy, kdef,
    ! costs more than it has and its nodes return: where the velocity's
    ! linear part handed out less than the mean velocity holds, in a cold
    ! gas with a velocity precursor) pays all it has; the rest is a deficit
    ! for the cells nearest to it (`repair_deficits`), not a negative
    ! energy of its own
    do i = 1, size(old%lnear)
      c = old%lnear(i)
      short_c = avail(c) + ie(c) + iav(c)
      if (.not. short_c < 0.0_wp) cycle
      iav(c) = -avail(c)
      ie(c) = short_c
      rdef(c) = short_c
    end do
    phase = 0
    if (present(deficit_cells)) phase = 1
    if (present(patch)) then
      if (allocated(patch%id)) phase = 2
    end if
    if (present(own) .and. phase < 2) then
      ! (a window: the repair reaches cells further away, in the whole
      ! grid's order; its own cells' deficits, or with every window's its
      ! donors' energies, `remap_zone_t`)
      stats%cells_deficit = count(rdef(old%lnear) < 0.0_wp .and. own(old%lnear))
      if (phase == 0 .and. present(deficit_mine)) then
        deficit_mine = pack(old%lnear, rdef(old%lnear) < 0.0_wp .and. own(old%lnear))
        deficit_mine = [(g%global_cell(deficit_mine(i)), i = 1, size(deficit_mine))]
      end if
      ! (the state is written as before: the caller takes none of it)
      if (phase == 1 .and. present(donors)) call give_donors()
    else if (present(own)) then
      ! (a window given the patch: the repair as the whole grid's over it;
      ! the window's cells in it join the cells set)
      call repair_patch()
      if (allocated(err)) return
    else if (any(rdef(old%lnear) < 0.0_wp)) then
      ! (it reaches cells beyond the near ones: every cell's energy is offered)
      wide = .true.
      visit = [(c, c = 1, ncell)]
      call offer_far()
      call deficits_repair(g%gn, rdef, ie, iav, avail, stats)
    end if

    ! cells (what moved: the changed cells' nodes; a window's other nodes
    ! may move too)
    if (present(own)) then
      g%x = xnew
    else
      g%x(:, old%lnode) = xnew(:, old%lnode)
    end if
    kk = 0
    do i = 1, size(visit)
      c = visit(i)
      if (.not. old%changed(c)) then
        ! copied: mass, volume, density as they were; energy plus its share of the KE returned
        if (nmix(c) > 0) then
          kk = kk + 1
          k = -h%mat(c)
          nx%mat(nx%start(kk):nx%start(kk + 1) - 1) = mx%mat(mx%start(k):mx%start(k + 1) - 1)
          nx%vf(nx%start(kk):nx%start(kk + 1) - 1) = mx%vf(mx%start(k):mx%start(k + 1) - 1)
          nx%mass(nx%start(kk):nx%start(kk + 1) - 1) = mx%mass(mx%start(k):mx%start(k + 1) - 1)
          do s = 0, nmix(c) - 1
            if (old%near(c) .or. wide) then
              nx%e(nx%start(kk) + s) = mx%e(mx%start(k) + s) + ie(c)/h%mass(c) + &
                iav(c)*share(mx%mass(mx%start(k) + s)*mx%e(mx%start(k) + s), avail(c))/mx%mass(mx%start(k) + s)
            else
              nx%e(nx%start(kk) + s) = mx%e(mx%start(k) + s)
            end if
          end do
          nx%rho(nx%start(kk):nx%start(kk + 1) - 1) = mx%rho(mx%start(k):mx%start(k + 1) - 1)
          nx%xi(:, nx%start(kk):nx%start(kk + 1) - 1) = mx%xi(:, mx%start(k):mx%start(k + 1) - 1)
          h%mat(c) = -kk
        end if
        if (old%near(c) .or. wide) h%e(c) = h%e(c) + (ie(c) + iav(c))/h%mass(c)
        cycle
      end if
      mnew = sum(amass(:, c))
      h%mass(c) = mnew
      h%mcorner(:, c) = cmass(:, c)
      h%vol(c) = vcell(c)
      h%rho(c) = mnew/h%vol(c)
      h%e(c) = (sum(aie(:, c)) + ie(c) + iav(c))/mnew
      if (nmix(c) == 0) then
        h%mat(c) = maxloc(avol(:, c), 1)
        cycle
      end if
      kk = kk + 1
      h%mat(c) = -kk
      call g%gather(c, g%x, xn)
      vtot = sum(avol(:, c))
      s = nx%start(kk)
      do k = 1, nmat
        if (.not. avol(k, c) > 0.0_wp) cycle
        nx%mat(s) = k
        nx%vf(s) = avol(k, c)/vtot
        nx%mass(s) = amass(k, c)
        nx%e(s) = (aie(k, c) + ie(c)*amass(k, c)/mnew + iav(c)*share(aie(k, c), avail(c)))/amass(k, c)
        nx%rho(s) = amass(k, c)/(nx%vf(s)*h%vol(c))
        nx%xi(:, s) = hex_natural(xn, amom(:, k, c)/avol(k, c))
        s = s + 1
      end do
    end do
    if (wide) then
      do i = 1, size(visit)
        c = visit(i)
        if (.not. old%near(c) .and. counted(c)) call xsum_add(stats%change(5), h%mass(c)*h%e(c))
      end do
    end if
    call move_mixed(nx, mx)
    old%node(old%lnode) = .false.
    if (present(written)) call move_alloc(visit, written)

  contains

    !> Whether the stats count cell cc.
    logical function counted(cc)
      integer, intent(in) :: cc
      counted = .true.
      if (present(own)) counted = own(cc)
    end function counted

    !> Whether the stats count node nn.
    logical function node_counted(nn)
      integer, intent(in) :: nn
      node_counted = .true.
      if (present(own_node)) node_counted = own_node(nn)
    end function node_counted

    !> The visited cells beyond the near ones offer their energy above zero
    !> to the deficits' repair (`deficits_repair`), and their energies may
    !> change: out of the totals' change (back after the assembly).
    subroutine offer_far()
      integer :: ii, cc
      do ii = 1, size(visit)
        cc = visit(ii)
        if (old%near(cc)) cycle
        if (counted(cc)) call xsum_add(stats%change(5), -h%mass(cc)*h%e(cc))
        if (h%mat(cc) > 0) nmix(cc) = 0
        avail(cc) = cell_avail(cc)
        kdef(cc) = 0.0_wp
        ie(cc) = 0.0_wp
        iav(cc) = 0.0_wp
        rdef(cc) = 0.0_wp
      end do
    end subroutine offer_far

    !> donors: the window's own cells within the repair's rings of the
    !> deficit cells (every window's, `remap_zone_t`), with their residual
    !> deficits and energies before the repair (those beyond the near cells
    !> as `offer_far` sets them), in increasing order.
    subroutine give_donors()
      logical, allocatable :: pick(:)
      integer, allocatable :: list(:)
      integer :: ii, cc, q, ijk(3), lo(3), hi(3), i1, j1, k1
      allocate(pick(ncell), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'remap_euler', error_no_memory('the deficits'' donors'))
        return
      end if
      pick = .false.
      do q = 1, size(deficit_cells)
        ijk = [mod(deficit_cells(q) - 1, g%gn(1)), mod((deficit_cells(q) - 1)/g%gn(1), g%gn(2)), &
               (deficit_cells(q) - 1)/(g%gn(1)*g%gn(2))] + 1 - g%off
        lo = max(ijk - deficit_rings, [g%clo(1), g%clo(2), g%clo(3)])
        hi = min(ijk + deficit_rings, [g%chi(1), g%chi(2), g%chi(3)])
        do k1 = lo(3), hi(3)
          do j1 = lo(2), hi(2)
            do i1 = lo(1), hi(1)
              pick(g%cell(i1, j1, k1)) = own(g%cell(i1, j1, k1))
            end do
          end do
        end do
      end do
      list = pack([(ii, ii = 1, ncell)], pick)
      allocate(donors%id(size(list)), donors%v(4, size(list)), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'remap_euler', error_no_memory('the deficits'' donors'))
        return
      end if
      do ii = 1, size(list)
        cc = list(ii)
        donors%id(ii) = g%global_cell(cc)
        if (old%near(cc)) then
          donors%v(:, ii) = [rdef(cc), ie(cc), iav(cc), avail(cc)]
        else
          donors%v(:, ii) = [0.0_wp, 0.0_wp, 0.0_wp, cell_avail(cc)]
        end if
      end do
    end subroutine give_donors

    !> The deficits repaired over the patch (every window's donors) as the
    !> whole grid repairs them (`deficits_repair`, the stats counting the
    !> own cells' deficits), and the window's cells in it set from it: the
    !> visited cells widened to them (`offer_far`).
    subroutine repair_patch()
      real(wp), allocatable :: pv(:, :)
      integer, allocatable :: at(:), list(:)
      logical, allocatable :: mine(:)
      integer :: q, np, cc, ijk(3)
      np = size(patch%id)
      allocate(pv(4, np), at(np), mine(np), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'remap_euler', error_no_memory('the deficits'' patch'))
        return
      end if
      pv = patch%v
      do q = 1, np
        ijk = [mod(patch%id(q) - 1, g%gn(1)), mod((patch%id(q) - 1)/g%gn(1), g%gn(2)), &
               (patch%id(q) - 1)/(g%gn(1)*g%gn(2))] + 1 - g%off
        at(q) = 0
        if (all(ijk >= [g%clo(1), g%clo(2), g%clo(3)] .and. ijk <= [g%chi(1), g%chi(2), g%chi(3)])) &
          at(q) = g%cell(ijk(1), ijk(2), ijk(3))
        mine(q) = .false.
        if (at(q) > 0) mine(q) = own(at(q))
      end do
      call deficits_repair(g%gn, pv(1, :), pv(2, :), pv(3, :), pv(4, :), stats, mine, patch%id)
      call sorted_union(visit, pack(at, at > 0), list, err)
      if (allocated(err)) return
      call move_alloc(list, visit)
      wide = .true.
      call offer_far()
      do q = 1, np
        cc = at(q)
        if (cc == 0) cycle
        ie(cc) = pv(2, q)
        iav(cc) = pv(3, q)
        avail(cc) = pv(4, q)
      end do
    end subroutine repair_patch

    !> The internal energy above zero cell cc has to offer: its remapped
    !> materials' if it changed, else its own.
    real(wp) function cell_avail(cc) result(av)
      integer, intent(in) :: cc
      integer :: kc
      if (old%changed(cc)) then
        av = sum(max(aie(:, cc), 0.0_wp))
      else if (h%mat(cc) > 0) then
        av = h%mass(cc)*max(h%e(cc), 0.0_wp)
      else
        kc = -h%mat(cc)
        av = sum(mx%mass(mx%start(kc):mx%start(kc + 1) - 1)*max(mx%e(mx%start(kc):mx%start(kc + 1) - 1), 0.0_wp))
      end if
    end function cell_avail


    !> The share of a material with internal energy q in what its cell has
    !> available (total: only positive energies count).
    pure real(wp) function share(q, total)
      real(wp), intent(in) :: q, total
      share = 0.0_wp
      if (total > 0.0_wp) share = max(q, 0.0_wp)/total
    end function share
  end subroutine assemble

  !> The residual deficits rdef < 0 (kinetic energy the new nodal
  !> velocities hold beyond what the remap brought and the cells around
  !> their nodes could give) are taken back from the cells that hold them
  !> and taken instead from the energy the cells nearest to them still
  !> have above zero: ring after ring of cells around (index distance 0,
  !> 1, ... up to deficit_rings), each ring giving in proportion to what
  !> its cells have, until the deficit is paid. A cell gives first from
  !> the kinetic energy returned to it (ie > 0, shared by mass among its
  !> materials), then from its own internal energy above zero (avail + iav,
  !> shared in proportion to the materials' positive energies), never past
  !> zero. Cells are done in the whole grid's order, so the result depends
  !> neither on the thread count nor on the blocks; what no ring within
  !> reach can give is taken by mass. Total energy is unchanged: only
  !> where it sits moves. The arrays' entry q is the whole grid's cell q
  !> (gn cells a side), or with ids cell ids(q) (increasing; every cell
  !> within the rings of a deficit's is there); the stats count the
  !> deficits of the entries `counted` (absent: all).
  pure subroutine deficits_repair(gn, rdef, ie, iav, avail, stats, counted, ids)
    integer, intent(in) :: gn(3)
    real(wp), intent(in) :: rdef(:), avail(:)
    real(wp), intent(inout) :: ie(:), iav(:)
    type(remap_stats_t), intent(inout) :: stats
    logical, intent(in), optional :: counted(:)
    integer, intent(in), optional :: ids(:)
    integer :: q, ring, ijk(3), i, j, k, d, id
    real(wp) :: need, total, f, give, t1
    logical :: count_it

    do q = 1, size(rdef)
      if (.not. rdef(q) < 0.0_wp) cycle
      need = -rdef(q)
      ie(q) = ie(q) + need
      count_it = .true.
      if (present(counted)) count_it = counted(q)
      if (count_it) then
        stats%cells_deficit = stats%cells_deficit + 1
        stats%deficit_moved = stats%deficit_moved + need
      end if
      id = q
      if (present(ids)) id = ids(q)
      ijk = [mod(id - 1, gn(1)), mod((id - 1)/gn(1), gn(2)), (id - 1)/(gn(1)*gn(2))] + 1
      do ring = 0, deficit_rings
        total = 0.0_wp
        do k = max(1, ijk(3) - ring), min(gn(3), ijk(3) + ring)
          do j = max(1, ijk(2) - ring), min(gn(2), ijk(2) + ring)
            do i = max(1, ijk(1) - ring), min(gn(1), ijk(1) + ring)
              if (max(abs(i - ijk(1)), abs(j - ijk(2)), abs(k - ijk(3))) /= ring) cycle
              total = total + capacity(entry(i, j, k))
            end do
          end do
        end do
        if (.not. total > 0.0_wp) cycle
        f = min(1.0_wp, need/total)
        do k = max(1, ijk(3) - ring), min(gn(3), ijk(3) + ring)
          do j = max(1, ijk(2) - ring), min(gn(2), ijk(2) + ring)
            do i = max(1, ijk(1) - ring), min(gn(1), ijk(1) + ring)
              if (max(abs(i - ijk(1)), abs(j - ijk(2)), abs(k - ijk(3))) /= ring) cycle
              d = entry(i, j, k)
              give = f*capacity(d)
              t1 = min(give, max(ie(d), 0.0_wp))
              ie(d) = ie(d) - t1
              iav(d) = iav(d) - (give - t1)
            end do
          end do
        end do
        need = need - f*total
        if (f < 1.0_wp) then
          need = 0.0_wp
          exit
        end if
      end do
      ! what is left: by mass
      if (need > 0.0_wp) then
        ie(q) = ie(q) - need
        if (count_it) stats%deficit_by_mass = stats%deficit_by_mass + need
      end if
    end do

  contains

    !> The entry of the whole grid's cell (ii, jj, kk).
    pure integer function entry(ii, jj, kk)
      integer, intent(in) :: ii, jj, kk
      entry = ii + gn(1)*((jj - 1) + gn(2)*(kk - 1))
      if (present(ids)) entry = sorted_place(ids, entry)
    end function entry

    !> What entry dd can still give towards a deficit.
    pure real(wp) function capacity(dd)
      integer, intent(in) :: dd
      ! (never quite all of it: round-off must not take a donor below zero)
      capacity = (1.0_wp - 1.0e-12_wp)*(max(ie(dd), 0.0_wp) + max(avail(dd) + iav(dd), 0.0_wp))
    end function capacity
  end subroutine deficits_repair

  !> Replaces mx by nx.
  subroutine move_mixed(nx, mx)
    type(mixed_t), intent(inout) :: nx, mx
    mx%n = nx%n
    mx%nslot = nx%nslot
    call move_alloc(nx%cell, mx%cell)
    call move_alloc(nx%start, mx%start)
    call move_alloc(nx%mat, mx%mat)
    call move_alloc(nx%vf, mx%vf)
    call move_alloc(nx%mass, mx%mass)
    call move_alloc(nx%e, mx%e)
    call move_alloc(nx%rho, mx%rho)
    call move_alloc(nx%p, mx%p)
    call move_alloc(nx%cs, mx%cs)
    call move_alloc(nx%xi, mx%xi)
    call move_alloc(nx%vfn, mx%vfn)
    call move_alloc(nx%en, mx%en)
    call move_alloc(nx%pn, mx%pn)
    call move_alloc(nx%bn, mx%bn)
    call move_alloc(nx%voln, mx%voln)
  end subroutine move_mixed

  ! ------------------------------------------------------------ small kernels
end module remap_euler
