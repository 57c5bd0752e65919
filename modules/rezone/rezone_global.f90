!> The target grid of the global rezone (the paper's MMALE particle method,
!> Sect. 4: the grid is rezoned "to the initial one"), for blocks whose
!> boundary faces do not all stay where they started.
!>
!> A face of the block follows one of three rules:
!>   - GLOBAL_FACE_MOVE: a boundary that moves with the material (a piston,
!>     a `velocity` face; a free surface, a `pressure` face). Nothing may be
!>     remapped across it, so its nodes keep the positions the Lagrangian
!>     step gave them, bit for bit.
!>   - GLOBAL_FACE_SLIDE: a fixed plane the material may slide along or
!>     pass through (`symmetry`, and the open faces `inflow` and `outflow`,
!>     which by design keep the domain where it was): its nodes keep their
!>     initial normal coordinate and follow the interior tangentially.
!>   - GLOBAL_FACE_FIX: a wall; its nodes keep their initial positions.
!>
!> With no moving face the target is the initial grid x0 itself (bit for
!> bit). Otherwise the target is x0 plus a displacement D that is x - x0 on
!> the moving faces and is carried into the rest of the block by
!> transfinite interpolation (the TFI of Eq. (53), applied to the
!> displacement rather than to the positions), built up by dimension:
!>   1. corners: D = x - x0 on a moving face, else 0;
!>   2. edges not on a moving face: linear in the normalised arc length of
!>      the edge in x0 between its two corners;
!>   3. faces not moving: 2D TFI (Boolean sum of the two linear
!>      interpolations along the face's index lines, less their product)
!>      from the face's four edges;
!>   4. interior nodes: 3D TFI from the six faces, twelve edges and eight
!>      corners (as `rezone_smooth`'s smooth_tfi does for positions).
!> The parameters are the normalised arc lengths of x0 along each index
!> line through the node, so a piston that has moved by d compresses the
!> cells in front of it in proportion to their initial sizes: along a
!> straight line of initial length L each cell keeps (1 - d/L) of its
!> length, and every cell stays valid while d < L. Finally a SLIDE face's
!> nodes take back their initial normal coordinate and a FIX face's nodes
!> their initial position (a node on a moving face keeps its position
!> whatever other faces it lies on: the Lagrangian step already applied
!> their conditions to it).
module rezone_global
  use base_kinds, only: wp
  use base_errors, only: error_no_memory, error_t, error_set
  use base_strings, only: itoa, rtoa
  use mesh_grid, only: grid_index_t, grid_index, block_gather
  use mesh_geometry, only: hex_volume
  use mesh_boundary, only: BC_SYMMETRY, BC_WALL, BC_VELOCITY, BC_PRESSURE, BC_INFLOW, BC_OUTFLOW
  implicit none
  private
  public :: GLOBAL_FACE_SLIDE, GLOBAL_FACE_FIX, GLOBAL_FACE_MOVE
  public :: global_face_rule, global_target

  !> Rules for a face of the block in the global rezone (see the module header).
  integer, parameter :: GLOBAL_FACE_SLIDE = 1, GLOBAL_FACE_FIX = 2, GLOBAL_FACE_MOVE = 3
  !> Axis normal to each face (xlo, xhi, ylo, yhi, zlo, zhi).
  integer, parameter :: face_axis(6) = [1, 1, 2, 2, 3, 3]

contains

  !> The rule of a face with boundary condition kind `kind` (mesh_boundary's
  !> BC_*): velocity and pressure faces move with the material, walls are
  !> fixed, symmetry planes and open faces slide.
  pure integer function global_face_rule(kind) result(rule)
    integer, intent(in) :: kind
    select case (kind)
    case (BC_VELOCITY, BC_PRESSURE)
      rule = GLOBAL_FACE_MOVE
    case (BC_WALL)
      rule = GLOBAL_FACE_FIX
    case (BC_SYMMETRY, BC_INFLOW, BC_OUTFLOW)
      rule = GLOBAL_FACE_SLIDE
    case default
      rule = GLOBAL_FACE_SLIDE
    end select
  end function global_face_rule

  !> The global rezone's target xt for a block of ni x nj x nk cells whose
  !> initial nodes are x0 and current (Lagrangian) nodes x, faces following
  !> rule(6) (GLOBAL_FACE_*; order xlo, xhi, ylo, yhi, zlo, zhi). All
  !> positions (3, (ni+1)(nj+1)(nk+1)) in the deck's length unit, nodes
  !> numbered as in `mesh_grid`. Fails if a cell of the target is not
  !> valid (non-positive volume: a moving face has come too close to the
  !> opposite side for the block to hold it). nmove returns the number of
  !> nodes on moving faces (0: xt is x0).
  subroutine global_target(ni, nj, nk, rule, x0, x, xt, nmove, err)
    integer, intent(in) :: ni, nj, nk, rule(6)
    real(wp), intent(in) :: x(:, :)
    ! (contiguous: the copy of the initial grid, on every node at every
    ! Euler step of a run without moving faces, is then a block copy)
    real(wp), contiguous, intent(in) :: x0(:, :)
    real(wp), contiguous, intent(out) :: xt(:, :)
    integer, intent(out) :: nmove
    type(error_t), allocatable, intent(inout) :: err
    type(grid_index_t) :: ix
    real(wp), allocatable :: d(:, :), s(:, :)
    logical, allocatable :: mv(:)
    integer :: n, i, j, k, f, m, nmax(3), ijk(3), stat, c
    real(wp) :: xn(3, 8), v
    character(len=200) :: msg

    nmove = 0
    ix = grid_index(ni, nj, nk)
    if (size(x0, 2) /= ix%nnode .or. size(x, 2) /= ix%nnode .or. size(xt, 2) /= ix%nnode) then
      call error_set(err, 'global_target', 'the node arrays must hold every node of the block')
      return
    end if
    if (all(rule /= GLOBAL_FACE_MOVE)) then
      ! no moving face: the initial grid, bit for bit
      xt = x0
      return
    end if
    allocate(d(3, ix%nnode), s(3, ix%nnode), mv(ix%nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'global_target', error_no_memory('the work arrays'))
      return
    end if
    nmax = [ni, nj, nk]

    ! nodes on moving faces keep x; D = x - x0 there, 0 elsewhere for now
    do k = 0, nk
      do j = 0, nj
        do i = 0, ni
          n = ix%node(i, j, k)
          m = ix%node_faces(i, j, k)
          mv(n) = .false.
          do f = 1, 6
            if (btest(m, f - 1) .and. rule(f) == GLOBAL_FACE_MOVE) mv(n) = .true.
          end do
          if (mv(n)) then
            d(:, n) = x(:, n) - x0(:, n)
            nmove = nmove + 1
          else
            d(:, n) = 0.0_wp
          end if
        end do
      end do
    end do
    call line_parameters(ix, nmax, x0, s)

    ! edges (lines in direction a with both other indices at a block bound)
    do k = 0, nk
      do j = 0, nj
        do i = 0, ni
          n = ix%node(i, j, k)
          if (mv(n)) cycle
          ijk = [i, j, k]
          if (count(ijk == 0 .or. ijk == nmax) /= 2) cycle
          do m = 1, 3
            ! the edge's direction: the one index strictly inside
            if (ijk(m) > 0 .and. ijk(m) < nmax(m)) &
              d(:, n) = (1.0_wp - s(m, n))*d(:, along(ijk, m, 0)) + s(m, n)*d(:, along(ijk, m, nmax(m)))
          end do
        end do
      end do
    end do

    ! faces (nodes with exactly one index at a block bound): 2D TFI
    do k = 0, nk
      do j = 0, nj
        do i = 0, ni
          n = ix%node(i, j, k)
          if (mv(n)) cycle
          ijk = [i, j, k]
          if (count(ijk == 0 .or. ijk == nmax) /= 1) cycle
          call face_tfi(ijk, n)
        end do
      end do
    end do

    ! interior: 3D TFI
    do k = 1, nk - 1
      do j = 1, nj - 1
        do i = 1, ni - 1
          call interior_tfi([i, j, k], ix%node(i, j, k))
        end do
      end do
    end do

    ! the faces' own rules, then the target
    do k = 0, nk
      do j = 0, nj
        do i = 0, ni
          n = ix%node(i, j, k)
          if (mv(n)) then
            xt(:, n) = x(:, n)
            cycle
          end if
          m = ix%node_faces(i, j, k)
          do f = 1, 6
            if (.not. btest(m, f - 1)) cycle
            if (rule(f) == GLOBAL_FACE_SLIDE) d(face_axis(f), n) = 0.0_wp
            if (rule(f) == GLOBAL_FACE_FIX) d(:, n) = 0.0_wp
          end do
          xt(:, n) = x0(:, n) + d(:, n)
        end do
      end do
    end do

    do k = 1, nk
      do j = 1, nj
        do i = 1, ni
          call block_gather(ni, nj, i, j, k, xt, xn)
          v = hex_volume(xn)
          if (.not. v > 0.0_wp) then
            c = ix%cell(i, j, k)
            call error_set(err, 'global_target', 'the rezoned grid has a cell of volume '//rtoa(v)// &
                           ' (cell '//itoa(c)//' = ('//itoa(i)//','//itoa(j)//','//itoa(k)// &
                           ')): a moving face came too close to the other side of the block')
            return
          end if
        end do
      end do
    end do

  contains

    !> The node with index ijk except ijk(a) = val.
    pure integer function along(ijk, a, val) result(nn)
      integer, intent(in) :: ijk(3), a, val
      integer :: q(3)
      q = ijk
      q(a) = val
      nn = ix%node(q(1), q(2), q(3))
    end function along

    !> The node with index ijk except ijk(a) = va and ijk(b) = vb.
    pure integer function along2(ijk, a, va, b, vb) result(nn)
      integer, intent(in) :: ijk(3), a, va, b, vb
      integer :: q(3)
      q = ijk
      q(a) = va
      q(b) = vb
      nn = ix%node(q(1), q(2), q(3))
    end function along2

    !> 2D TFI at the face node n (index ijk) from the face's four edges.
    subroutine face_tfi(ijk, n)
      integer, intent(in) :: ijk(3), n
      integer :: a, b, m
      real(wp) :: u, w
      ! the two in-face directions a < b
      a = 0
      b = 0
      do m = 1, 3
        if (ijk(m) > 0 .and. ijk(m) < nmax(m)) then
          if (a == 0) then
            a = m
          else
            b = m
          end if
        end if
      end do
      u = s(a, n)
      w = s(b, n)
      d(:, n) = (1.0_wp - u)*d(:, along(ijk, a, 0)) + u*d(:, along(ijk, a, nmax(a))) &
                + (1.0_wp - w)*d(:, along(ijk, b, 0)) + w*d(:, along(ijk, b, nmax(b))) &
                - ((1.0_wp - u)*((1.0_wp - w)*d(:, along2(ijk, a, 0, b, 0)) + w*d(:, along2(ijk, a, 0, b, nmax(b)))) &
                   + u*((1.0_wp - w)*d(:, along2(ijk, a, nmax(a), b, 0)) + w*d(:, along2(ijk, a, nmax(a), b, nmax(b)))))
    end subroutine face_tfi

    !> 3D TFI at the interior node n (index ijk): faces - edges + corners.
    subroutine interior_tfi(ijk, n)
      integer, intent(in) :: ijk(3), n
      real(wp) :: u, v, w, p(3), e(3), cc(3)
      integer :: i0, i1, j0, j1, k0, k1
      u = s(1, n)
      v = s(2, n)
      w = s(3, n)
      i0 = 0; i1 = ni; j0 = 0; j1 = nj; k0 = 0; k1 = nk
      associate (i => ijk(1), j => ijk(2), k => ijk(3))
        p = (1.0_wp - u)*d(:, ix%node(i0, j, k)) + u*d(:, ix%node(i1, j, k)) &
            + (1.0_wp - v)*d(:, ix%node(i, j0, k)) + v*d(:, ix%node(i, j1, k)) &
            + (1.0_wp - w)*d(:, ix%node(i, j, k0)) + w*d(:, ix%node(i, j, k1))
        e = (1.0_wp - u)*((1.0_wp - v)*d(:, ix%node(i0, j0, k)) + v*d(:, ix%node(i0, j1, k))) &
            + u*((1.0_wp - v)*d(:, ix%node(i1, j0, k)) + v*d(:, ix%node(i1, j1, k))) &
            + (1.0_wp - u)*((1.0_wp - w)*d(:, ix%node(i0, j, k0)) + w*d(:, ix%node(i0, j, k1))) &
            + u*((1.0_wp - w)*d(:, ix%node(i1, j, k0)) + w*d(:, ix%node(i1, j, k1))) &
            + (1.0_wp - v)*((1.0_wp - w)*d(:, ix%node(i, j0, k0)) + w*d(:, ix%node(i, j0, k1))) &
            + v*((1.0_wp - w)*d(:, ix%node(i, j1, k0)) + w*d(:, ix%node(i, j1, k1)))
        cc = (1.0_wp - u)*((1.0_wp - v)*((1.0_wp - w)*d(:, ix%node(i0, j0, k0)) + w*d(:, ix%node(i0, j0, k1))) &
                           + v*((1.0_wp - w)*d(:, ix%node(i0, j1, k0)) + w*d(:, ix%node(i0, j1, k1)))) &
             + u*((1.0_wp - v)*((1.0_wp - w)*d(:, ix%node(i1, j0, k0)) + w*d(:, ix%node(i1, j0, k1))) &
                  + v*((1.0_wp - w)*d(:, ix%node(i1, j1, k0)) + w*d(:, ix%node(i1, j1, k1))))
      end associate
      d(:, n) = p - e + cc
    end subroutine interior_tfi
  end subroutine global_target

  !> s(a, n): the normalised arc length of x0 along the index line of
  !> direction a through node n (0 at index 0, 1 at the block's far side);
  !> index fractions on a line of no length.
  subroutine line_parameters(ix, nmax, x0, s)
    type(grid_index_t), intent(in) :: ix
    integer, intent(in) :: nmax(3)
    real(wp), intent(in) :: x0(:, :)
    real(wp), intent(out) :: s(:, :)
    integer :: a, p, q, m, ijk(3), n, nprev, b, c
    real(wp) :: total
    do a = 1, 3
      ! the other two directions b < c
      b = merge(2, 1, a == 1)
      c = merge(2, 3, a == 3)
      do q = 0, nmax(c)
        do p = 0, nmax(b)
          ijk(b) = p
          ijk(c) = q
          ijk(a) = 0
          n = ix%node(ijk(1), ijk(2), ijk(3))
          s(a, n) = 0.0_wp
          do m = 1, nmax(a)
            nprev = n
            ijk(a) = m
            n = ix%node(ijk(1), ijk(2), ijk(3))
            s(a, n) = s(a, nprev) + norm2(x0(:, n) - x0(:, nprev))
          end do
          total = s(a, n)
          do m = 0, nmax(a)
            ijk(a) = m
            n = ix%node(ijk(1), ijk(2), ijk(3))
            if (total > 0.0_wp) then
              s(a, n) = s(a, n)/total
            else
              s(a, n) = real(m, wp)/real(max(nmax(a), 1), wp)
            end if
          end do
          ! the far end exactly 1
          s(a, n) = 1.0_wp
        end do
      end do
    end do
  end subroutine line_parameters
end module rezone_global
