!> Boundary conditions on the six faces of the structured block.
!>
!> Kinds: symmetry (reflective: the velocity component normal to the face is
!> zero), wall (fixed: velocity zero), velocity (prescribed velocity, a piston),
!> pressure (a prescribed external pressure; zero gives a free surface).
!> Inside the block, the nodes in boxes the deck gives (&boundary fixed_lo,
!> fixed_hi: a clamped support) are fixed as on a wall.
!> Faces are numbered xlo, xhi, ylo, yhi, zlo, zhi; face f is normal to axis
!> (f+1)/2. Kinematic conditions are applied after the unconstrained velocity
!> update; the impulse they add is accumulated as boundary work so that the
!> conservation report can balance total energy for open problems too.
module mesh_boundary
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_xsum, only: xsum_t, xsum_add, xsum_value
  use mesh_grid, only: grid_t, FACE_XLO, FACE_YLO, FACE_ZLO
  use mesh_geometry, only: cross
  implicit none
  private
  public :: bc_t, bc_init, bc_pressure_forces, bc_apply, bc_constrain, bc_constrain_nodes, bc_fixed_nodes, &
            BC_SYMMETRY, BC_WALL, BC_VELOCITY, BC_PRESSURE, BC_INFLOW, BC_OUTFLOW, bc_kind_from_name, &
            bc_kind_names

  integer, parameter :: BC_SYMMETRY = 1, BC_WALL = 2, BC_VELOCITY = 3, BC_PRESSURE = 4
  !> Open faces of a grid that the Euler phase brings back to its initial
  !> place: material enters through an inflow face (the face moves with the
  !> prescribed velocity in the Lagrangian phase; the remap fills the gap
  !> with the inflow state) and leaves through an outflow face (held by the
  !> pressure of the cell next to it, so it moves with the flow; the remap
  !> removes what lies beyond it and fills any gap with the next cell's state).
  integer, parameter :: BC_INFLOW = 5, BC_OUTFLOW = 6
  !> The bit of a node's mask (`bc_t%mask`) that says it is fixed by a box
  !> (`bc_t%fixed_box`); bits 0-5 are the faces it lies on.
  integer, parameter :: fixed_bit = 6
  !> The most fixed boxes (&boundary fixed_lo, fixed_hi).
  integer, parameter, public :: bc_max_fixed = 8
  !> Axis normal to each face.
  integer, parameter :: face_axis(6) = [1, 1, 2, 2, 3, 3]
  !> Names of the kinds as written in decks, in kind order.
  character(len=*), parameter :: bc_kind_names = 'symmetry, wall, velocity, pressure, inflow, outflow'

  !> Boundary conditions and the list of boundary nodes they act on.
  type :: bc_t
    integer :: kind(6) = BC_SYMMETRY
    real(wp) :: velocity(3, 6) = 0.0_wp   !< prescribed velocity per face
    real(wp) :: pressure(6) = 0.0_wp      !< external pressure per face
    ! inflow state per face (BC_INFLOW): material, density, specific energy
    integer :: inflow_mat(6) = 0
    real(wp) :: inflow_rho(6) = 0.0_wp, inflow_e(6) = 0.0_wp
    integer :: nb = 0                     !< number of boundary nodes
    integer, allocatable :: node(:)       !< boundary node indices (nb)
    integer, allocatable :: mask(:)       !< bit f-1 set if the node lies on face f
    logical, allocatable :: counted(:)    !< the node's work counts in this block's sum (`grid_counts_node`)
    integer, allocatable :: bindex(:)     !< node -> position in node(:), 0 inside (pressure only)
    logical :: any_pressure = .false.
    !> Boxes (lo(3), hi(3), length) whose nodes are fixed, as on a wall
    !> face: a node whose position when `bc_init` builds the lists (the
    !> grid as the deck made it) lies in one, bounds included
    integer :: nfixed = 0
    real(wp) :: fixed_box(6, bc_max_fixed) = 0.0_wp
    !> the nodes each box fixes that this block counts (`grid_counts_node`)
    integer :: fixed_count(bc_max_fixed) = 0
    !> (nnode, with fixed boxes) whether a stored node is fixed by one
    logical, allocatable :: fixed(:)
    real(wp), allocatable :: fext(:, :)   !< external pressure force on boundary nodes (3, nb)
  end type bc_t

contains

  !> Kind number of a deck name, or 0 if the name is unknown.
  pure integer function bc_kind_from_name(name)
    character(len=*), intent(in) :: name
    select case (trim(name))
    case ('symmetry'); bc_kind_from_name = BC_SYMMETRY
    case ('wall'); bc_kind_from_name = BC_WALL
    case ('velocity'); bc_kind_from_name = BC_VELOCITY
    case ('pressure'); bc_kind_from_name = BC_PRESSURE
    case ('inflow'); bc_kind_from_name = BC_INFLOW
    case ('outflow'); bc_kind_from_name = BC_OUTFLOW
    case default; bc_kind_from_name = 0
    end select
  end function bc_kind_from_name

  !> Builds the boundary node list of grid g for the kinds already set in bc.
  subroutine bc_init(bc, g, err)
    type(bc_t), intent(inout) :: bc
    type(grid_t), intent(in) :: g
    type(error_t), allocatable, intent(inout) :: err
    integer :: i, j, k, m, n, nb, stat, q
    character(len=200) :: msg

    if (bc%nfixed > 0) then
      allocate(bc%fixed(g%nnode), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'bc_init', error_no_memory('the fixed nodes'))
        return
      end if
      bc%fixed = .false.
      bc%fixed_count = 0
      do k = g%nlo(3), g%nhi(3)
        do j = g%nlo(2), g%nhi(2)
          do i = g%nlo(1), g%nhi(1)
            n = g%node(i, j, k)
            do q = 1, bc%nfixed
              if (any(g%x(:, n) < bc%fixed_box(1:3, q)) .or. any(g%x(:, n) > bc%fixed_box(4:6, q))) cycle
              bc%fixed(n) = .true.
              if (g%counts_node(i, j, k)) bc%fixed_count(q) = bc%fixed_count(q) + 1
            end do
          end do
        end do
      end do
    end if
    nb = 0
    do k = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        do i = g%nlo(1), g%nhi(1)
          if (node_mask(bc, g, i, j, k) /= 0) nb = nb + 1
        end do
      end do
    end do
    allocate(bc%node(nb), bc%mask(nb), bc%counted(nb), bc%fext(3, nb), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'bc_init', error_no_memory('boundary lists'))
      return
    end if
    bc%nb = 0
    do k = g%nlo(3), g%nhi(3)
      do j = g%nlo(2), g%nhi(2)
        do i = g%nlo(1), g%nhi(1)
          m = node_mask(bc, g, i, j, k)
          if (m == 0) cycle
          bc%nb = bc%nb + 1
          bc%node(bc%nb) = g%node(i, j, k)
          bc%mask(bc%nb) = m
          bc%counted(bc%nb) = g%counts_node(i, j, k)
        end do
      end do
    end do
    bc%fext = 0.0_wp
    bc%any_pressure = any(bc%kind == BC_PRESSURE .or. bc%kind == BC_OUTFLOW)
    if (bc%any_pressure) then
      allocate(bc%bindex(g%nnode), stat=stat, errmsg=msg)
      if (stat /= 0) then
        call error_set(err, 'bc_init', error_no_memory('boundary index'))
        return
      end if
      bc%bindex = 0
      do n = 1, bc%nb
        bc%bindex(bc%node(n)) = n
      end do
    end if
  end subroutine bc_init

  !> The faces node (i, j, k) of g lies on (bits 0-5) and whether a box
  !> fixes it (fixed_bit): the mask `constrain_node` takes.
  integer function node_mask(bc, g, i, j, k) result(m)
    type(bc_t), intent(in) :: bc
    type(grid_t), intent(in) :: g
    integer, intent(in) :: i, j, k
    m = g%node_faces(i, j, k)
    if (bc%nfixed > 0) then
      if (bc%fixed(g%node(i, j, k))) m = ibset(m, fixed_bit)
    end if
  end function node_mask

  !> The stored nodes that fixed boxes fix (`bc_t%fixed`; none without).
  function bc_fixed_nodes(bc) result(nodes)
    type(bc_t), intent(in) :: bc
    integer, allocatable :: nodes(:)
    integer :: b
    nodes = [integer ::]
    if (bc%nfixed == 0) return
    nodes = pack([(bc%node(b), b = 1, bc%nb)], [(btest(bc%mask(b), fixed_bit), b = 1, bc%nb)])
  end function bc_fixed_nodes

  !> External pressure forces on the nodes of pressure and outflow faces,
  !> from the node positions x at force time: each quad gives -p_ext A_out/4
  !> to its nodes; p_ext is the face's pressure, or on an outflow face the
  !> pressure p of the cell next to the quad (no pressure jump across it).
  subroutine bc_pressure_forces(bc, g, x, p)
    type(bc_t), intent(inout) :: bc
    type(grid_t), intent(in) :: g
    real(wp), intent(in) :: x(:, :), p(:)
    integer :: f, axis, i1, i2, d1, d2, nq(4), q, lo(3), hi(3)
    real(wp) :: a(3), sgn, pext

    if (.not. bc%any_pressure) return
    bc%fext = 0.0_wp
    do f = 1, 6
      if (bc%kind(f) /= BC_PRESSURE .and. bc%kind(f) /= BC_OUTFLOW) cycle
      axis = face_axis(f)
      sgn = merge(-1.0_wp, 1.0_wp, mod(f, 2) == 1)
      ! the face's quads, numbered by their lowest node (i1, i2) in the two
      ! other directions d1 < d2
      select case (axis)
      case (1); d1 = 2; d2 = 3
      case (2); d1 = 1; d2 = 3
      case default; d1 = 1; d2 = 2
      end select
      if (.not. on_face(g, f)) cycle
      ! the quads of the owned cells and of one ghost layer around them:
      ! every quad at an owned node
      call g%cells_around(1, lo, hi)
      do i2 = lo(d2) - 1, hi(d2) - 1
        do i1 = lo(d1) - 1, hi(d1) - 1
          nq = quad_nodes(g, f, i1, i2)
          a = 0.5_wp*cross(x(:, nq(3)) - x(:, nq(1)), x(:, nq(4)) - x(:, nq(2)))
          if (sgn*a(axis) < 0.0_wp) a = -a
          pext = bc%pressure(f)
          if (bc%kind(f) == BC_OUTFLOW) pext = p(quad_cell(g, f, i1, i2))
          do q = 1, 4
            associate (b => bc%bindex(nq(q)))
              if (b > 0) bc%fext(:, b) = bc%fext(:, b) - 0.25_wp*pext*a   ! (0: a ghost node)
            end associate
          end do
        end do
      end do
    end do
  end subroutine bc_pressure_forces

  !> True if the block of g lies on face f of the whole grid.
  pure logical function on_face(g, f)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: f
    integer :: d
    d = face_axis(f)
    if (mod(f, 2) == 1) then
      on_face = g%off(d) == 0
    else
      on_face = g%off(d) + g%nhi(d) == g%gn(d)
    end if
  end function on_face

  !> The four nodes (cyclic order) of boundary quad (i1,i2) on face f.
  pure function quad_nodes(g, f, i1, i2) result(nq)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: f, i1, i2
    integer :: nq(4)
    integer :: p
    select case (face_axis(f))
    case (1)
      p = merge(g%nlo(1), g%nhi(1), f == FACE_XLO)
      nq = [g%node(p, i1, i2), g%node(p, i1 + 1, i2), g%node(p, i1 + 1, i2 + 1), g%node(p, i1, i2 + 1)]
    case (2)
      p = merge(g%nlo(2), g%nhi(2), f == FACE_YLO)
      nq = [g%node(i1, p, i2), g%node(i1 + 1, p, i2), g%node(i1 + 1, p, i2 + 1), g%node(i1, p, i2 + 1)]
    case default
      p = merge(g%nlo(3), g%nhi(3), f == FACE_ZLO)
      nq = [g%node(i1, i2, p), g%node(i1 + 1, i2, p), g%node(i1 + 1, i2 + 1, p), g%node(i1, i2 + 1, p)]
    end select
  end function quad_nodes

  !> The cell next to boundary quad (i1,i2) of face f (the quad's lowest
  !> node is (i1,i2) in the face's two directions).
  pure integer function quad_cell(g, f, i1, i2) result(c)
    type(grid_t), intent(in) :: g
    integer, intent(in) :: f, i1, i2
    select case (face_axis(f))
    case (1)
      c = g%cell(merge(g%clo(1), g%chi(1), f == FACE_XLO), i1 + 1, i2 + 1)
    case (2)
      c = g%cell(i1 + 1, merge(g%clo(2), g%chi(2), f == FACE_YLO), i2 + 1)
    case default
      c = g%cell(i1 + 1, i2 + 1, merge(g%clo(3), g%chi(3), f == FACE_ZLO))
    end select
  end function quad_cell

  !> Applies the kinematic conditions to the velocities u(3, nnode) of all
  !> boundary nodes (used on the initial state).
  subroutine bc_constrain(bc, u)
    type(bc_t), intent(in) :: bc
    real(wp), intent(inout) :: u(:, :)
    integer :: b
    do b = 1, bc%nb
      call constrain_node(bc, bc%mask(b), u(:, bc%node(b)))
    end do
  end subroutine bc_constrain

  !> `bc_constrain` (bc built on grid g by `bc_init`, or without boundary
  !> nodes) on the nodes `nodes` only: those of them that g owns and that
  !> lie on the boundary.
  subroutine bc_constrain_nodes(bc, g, nodes, u)
    type(bc_t), intent(in) :: bc
    type(grid_t), intent(in) :: g
    integer, intent(in) :: nodes(:)
    real(wp), intent(inout) :: u(:, :)
    integer :: q, i, j, k, m
    if (bc%nb == 0) return
    do q = 1, size(nodes)
      call g%node_ijk(nodes(q), i, j, k)
      if (any([i, j, k] < g%nlo .or. [i, j, k] > g%nhi)) cycle
      m = node_mask(bc, g, i, j, k)
      if (m /= 0) call constrain_node(bc, m, u(:, nodes(q)))
    end do
  end subroutine bc_constrain_nodes

  !> Kinematic conditions of the faces in `mask` on one node velocity:
  !> prescribed velocities first, then symmetry and wall (so a piston sliding
  !> along a symmetry plane keeps zero normal velocity there); a node a box
  !> fixes (fixed_bit) is at rest, whatever faces it lies on.
  pure subroutine constrain_node(bc, mask, u)
    type(bc_t), intent(in) :: bc
    integer, intent(in) :: mask
    real(wp), intent(inout) :: u(3)
    integer :: f
    if (btest(mask, fixed_bit)) then
      u = 0.0_wp
      return
    end if
    do f = 1, 6
      if (btest(mask, f - 1) .and. (bc%kind(f) == BC_VELOCITY .or. bc%kind(f) == BC_INFLOW)) u = bc%velocity(:, f)
    end do
    do f = 1, 6
      if (.not. btest(mask, f - 1)) cycle
      select case (bc%kind(f))
      case (BC_SYMMETRY); u(face_axis(f)) = 0.0_wp
      case (BC_WALL); u = 0.0_wp
      end select
    end do
  end subroutine constrain_node

  !> Completes the node update on boundary nodes: adds the external pressure
  !> impulse, applies the kinematic conditions to u (new velocity), then
  !> recomputes the half-step velocity uh = (un+u)/2 and x = xn + dtx*uh.
  !> Returns in `work` the work done on the system by the boundary over dt
  !> (at the nodes this block counts, `bc%counted`), summed exactly
  !> (`base_xsum`; the sum itself in `work_acc` if present, for the blocks'
  !> total).
  !> A node's mass is mnode, plus m_ext if present (particle mass carried by
  !> the node, see `lagrange_step`).
  subroutine bc_apply(bc, dt, dtx, mnode, un, xn, u, uh, x, work, m_ext, work_acc)
    type(bc_t), intent(in) :: bc
    real(wp), intent(in) :: dt, dtx
    real(wp), intent(in) :: mnode(:), un(:, :), xn(:, :)
    real(wp), intent(inout) :: u(:, :), uh(:, :), x(:, :)
    real(wp), intent(out) :: work
    real(wp), intent(in), optional :: m_ext(:)
    type(xsum_t), intent(out), optional :: work_acc
    integer :: b, n
    real(wp) :: unc(3), imp(3), m
    logical :: has_m
    type(xsum_t) :: acc

    has_m = present(m_ext)
    do b = 1, bc%nb
      n = bc%node(b)
      m = mnode(n)
      if (has_m) m = m + m_ext(n)
      if (bc%any_pressure) u(:, n) = u(:, n) + dt*bc%fext(:, b)/m
      unc = u(:, n)
      call constrain_node(bc, bc%mask(b), u(:, n))
      imp = m*(u(:, n) - unc)
      uh(:, n) = 0.5_wp*(un(:, n) + u(:, n))
      x(:, n) = xn(:, n) + dtx*uh(:, n)
      if (bc%counted(b)) call xsum_add(acc, dot_product(imp + dt*bc%fext(:, b), uh(:, n)))
    end do
    work = xsum_value(acc)
    if (present(work_acc)) work_acc = acc
  end subroutine bc_apply
end module mesh_boundary
