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
  use mesh_grid, only: grid_index_t, grid_index
  use mesh_geometry, only: hex_volume
  use mesh_boundary, only: BC_SYMMETRY, BC_WALL, BC_VELOCITY, BC_PRESSURE, BC_INFLOW, BC_OUTFLOW
  implicit none
  private
  public :: GLOBAL_FACE_SLIDE, GLOBAL_FACE_FIX, GLOBAL_FACE_MOVE
  public :: global_face_rule, global_target, global_surface_t, global_surface_init, global_face_box, &
            global_face_parameters, global_surface_solve, global_block_target, global_target_check, &
            global_line_sums, global_line_scale

  !> Rules for a face of the block in the global rezone (see the module header).
  integer, parameter :: GLOBAL_FACE_SLIDE = 1, GLOBAL_FACE_FIX = 2, GLOBAL_FACE_MOVE = 3
  !> Axis normal to each face (xlo, xhi, ylo, yhi, zlo, zhi).
  integer, parameter :: face_axis(6) = [1, 1, 2, 2, 3, 3]

  !> A face of the grid (`global_surface_t`): its nodes in the order of
  !> `face_node`, initial (x0) and current (x: read on moving faces only)
  !> positions, line parameters in its two directions (s(2, :)), the
  !> displacement D, and whether a node lies on a moving face (mv).
  type :: global_face_t
    real(wp), allocatable :: x0(:, :), x(:, :), s(:, :), d(:, :)
    logical, allocatable :: mv(:)
  end type global_face_t

  !> The grid's six faces for the global rezone's target: what the TFI of
  !> the displacement needs besides a node's own line parameters.
  type :: global_surface_t
    integer :: n(3) = 0                      !< the whole grid's cells
    integer :: rule(6) = GLOBAL_FACE_SLIDE
    integer :: nmove = 0                     !< nodes on moving faces
    type(global_face_t) :: f(6)
  end type global_surface_t

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
  !> nodes on moving faces (0: xt is x0). The displacement on the grid's
  !> faces comes from `global_surface_solve`, each node's target from
  !> `global_node_target`: a decomposed run computes the same values from
  !> the faces alone and each block's own nodes.
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
    type(global_surface_t) :: sf
    real(wp), allocatable :: s(:, :)
    integer :: n, i, j, k, f, stat, lo(3), hi(3)
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
    allocate(s(3, ix%nnode), stat=stat, errmsg=msg)
    if (stat /= 0) then
      call error_set(err, 'global_target', error_no_memory('the work arrays'))
      return
    end if
    call line_parameters(ix, x0, s)
    call global_surface_init(sf, [ni, nj, nk], rule, err)
    if (allocated(err)) return
    ! (each face's nodes, as a gather of its box would give them)
    do f = 1, 6
      call global_face_box(sf, f, lo, hi)
      associate (fc => sf%f(f))
        do k = lo(3) - 1, hi(3)
          do j = lo(2) - 1, hi(2)
            do i = lo(1) - 1, hi(1)
              n = ix%node(i, j, k)
              fc%x0(:, face_node(sf, f, [i, j, k])) = x0(:, n)
              fc%x(:, face_node(sf, f, [i, j, k])) = x(:, n)
            end do
          end do
        end do
      end associate
      call global_face_parameters(sf, f)
    end do
    call global_surface_solve(sf)
    nmove = sf%nmove
    call global_block_target(sf, ix, s, x0, x, xt)
    call global_target_check(ix, xt, [0, 0, 0], err)
  end subroutine global_target

  !> The targets xt of the block ix's owned nodes (`global_node_target`;
  !> its ghosts untouched), whose line parameters are s(3, :), initial
  !> positions x0 and current x. (One loop for the whole grid and for the
  !> blocks of a decomposed run: the same code, the same round-off.)
  subroutine global_block_target(sf, ix, s, x0, x, xt)
    type(global_surface_t), intent(in) :: sf
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: s(:, :), x0(:, :), x(:, :)
    real(wp), intent(inout) :: xt(:, :)
    integer :: i, j, k, n
    do k = 0, ix%nk
      do j = 0, ix%nj
        do i = 0, ix%ni
          n = ix%node(i, j, k)
          xt(:, n) = global_node_target(sf, [i, j, k] + ix%off, s(:, n), x0(:, n), x(:, n))
        end do
      end do
    end do
  end subroutine global_block_target

  !> Fails if a cell ni x nj x nk of the target xt (a block's stored nodes:
  !> ix) is not valid; off: the block's place in the whole grid (for the
  !> message).
  subroutine global_target_check(ix, xt, off, err)
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: xt(:, :)
    integer, intent(in) :: off(3)
    type(error_t), allocatable, intent(inout) :: err
    real(wp) :: xn(3, 8), v
    integer :: i, j, k, q(3)
    do k = 1, ix%nk
      do j = 1, ix%nj
        do i = 1, ix%ni
          call ix%gather(ix%cell(i, j, k), xt, xn)
          v = hex_volume(xn)
          if (.not. v > 0.0_wp) then
            q = [i, j, k] + off
            call error_set(err, 'global_target', 'the rezoned grid has a cell of volume '//rtoa(v)// &
                           ' (cell ('//itoa(q(1))//','//itoa(q(2))//','//itoa(q(3))// &
                           ')): a moving face came too close to the other side of the block')
            return
          end if
        end do
      end do
    end do
  end subroutine global_target_check

  !> sf ready for a grid of n(3) cells with faces following rule(6): the
  !> faces' arrays allocated (their nodes then set by the caller).
  subroutine global_surface_init(sf, n, rule, err)
    type(global_surface_t), intent(out) :: sf
    integer, intent(in) :: n(3), rule(6)
    type(error_t), allocatable, intent(inout) :: err
    integer :: f, m, stat
    sf%n = n
    sf%rule = rule
    do f = 1, 6
      m = face_count(sf, f)
      allocate(sf%f(f)%x0(3, m), sf%f(f)%x(3, m), sf%f(f)%s(2, m), sf%f(f)%d(3, m), sf%f(f)%mv(m), stat=stat)
      if (stat /= 0) then
        call error_set(err, 'global_surface_init', error_no_memory('the faces'' nodes'))
        return
      end if
      sf%f(f)%x = 0.0_wp
    end do
  end subroutine global_surface_init

  !> Face f's nodes as a box of cells lo..hi in whole-grid indices (`mesh_
  !> grid`: its nodes lo-1..hi), no cell thick across the face: the order of
  !> the box's nodes is the face's own.
  pure subroutine global_face_box(sf, f, lo, hi)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: f
    integer, intent(out) :: lo(3), hi(3)
    integer :: a
    a = face_axis(f)
    lo = 1
    hi = sf%n
    lo(a) = merge(sf%n(a) + 1, 1, mod(f, 2) == 0)
    hi(a) = lo(a) - 1
  end subroutine global_face_box

  !> Face f's line parameters in its two directions (`line_parameters` on
  !> its own nodes x0: the whole grid's, whose lines in those directions lie
  !> in the face).
  subroutine global_face_parameters(sf, f)
    type(global_surface_t), intent(inout) :: sf
    integer, intent(in) :: f
    type(grid_index_t) :: ix
    real(wp) :: s(3, face_count(sf, f))
    integer :: b, c
    call face_dirs(f, b, c)
    ix = grid_index(sf%n(b), sf%n(c), 0)
    call line_parameters(ix, sf%f(f)%x0, s)
    sf%f(f)%s = s(1:2, :)
  end subroutine global_face_parameters

  !> The displacement D on the grid's faces (sf's nodes x0 and, on moving
  !> faces, x; line parameters s): the module header's steps 1 to 3, before
  !> the faces' own rules; sf%nmove, the nodes on moving faces.
  subroutine global_surface_solve(sf)
    type(global_surface_t), intent(inout) :: sf
    integer :: f, p, g, gm, m, nb, ijk(3), nbound
    ! nodes on moving faces keep x; D = x - x0 there, 0 elsewhere for now
    sf%nmove = 0
    do f = 1, 6
      do p = 1, face_count(sf, f)
        ijk = face_ijk(sf, f, p)
        gm = 0
        do g = 1, 6
          if (on_face(sf, g, ijk) .and. sf%rule(g) == GLOBAL_FACE_MOVE) then
            gm = g
            exit
          end if
        end do
        sf%f(f)%mv(p) = gm > 0
        if (gm > 0) then
          nb = face_node(sf, gm, ijk)
          sf%f(f)%d(:, p) = sf%f(gm)%x(:, nb) - sf%f(gm)%x0(:, nb)
          if (canonical(sf, ijk) == f) sf%nmove = sf%nmove + 1
        else
          sf%f(f)%d(:, p) = 0.0_wp
        end if
      end do
    end do
    ! edges (two indices at a bound): linear between their corners; then
    ! the faces' other nodes (one index at a bound): 2D TFI from the edges
    do nbound = 2, 1, -1
      do f = 1, 6
        do p = 1, face_count(sf, f)
          if (sf%f(f)%mv(p)) cycle
          ijk = face_ijk(sf, f, p)
          if (count(ijk == 0 .or. ijk == sf%n) /= nbound) cycle
          if (nbound == 2) then
            do m = 1, 3
              ! the edge's direction: the one index strictly inside
              if (ijk(m) > 0 .and. ijk(m) < sf%n(m)) &
                sf%f(f)%d(:, p) = (1.0_wp - face_s(sf, f, p, m))*surface_d(sf, along(ijk, m, 0)) &
                                  + face_s(sf, f, p, m)*surface_d(sf, along(ijk, m, sf%n(m)))
            end do
          else
            sf%f(f)%d(:, p) = face_tfi(sf, f, p, ijk)
          end if
        end do
      end do
    end do
  end subroutine global_surface_solve

  !> The target of the node at whole-grid index ijk with line parameters
  !> s(3) (`line_parameters`), initial position x0n and current xn, from
  !> the faces' displacement (`global_surface_solve`): a node on a moving
  !> face keeps xn; any other is x0n plus D (the 3D TFI inside the grid),
  !> less what its faces' rules take back.
  pure function global_node_target(sf, ijk, s, x0n, xn) result(xt)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: ijk(3)
    real(wp), intent(in) :: s(3), x0n(3), xn(3)
    real(wp) :: xt(3)
    real(wp) :: d(3)
    integer :: f, p
    if (any(ijk == 0 .or. ijk == sf%n)) then
      f = canonical(sf, ijk)
      p = face_node(sf, f, ijk)
      if (sf%f(f)%mv(p)) then
        xt = xn
        return
      end if
      d = sf%f(f)%d(:, p)
      do f = 1, 6
        if (.not. on_face(sf, f, ijk)) cycle
        if (sf%rule(f) == GLOBAL_FACE_SLIDE) d(face_axis(f)) = 0.0_wp
        if (sf%rule(f) == GLOBAL_FACE_FIX) d = 0.0_wp
      end do
    else
      d = interior_tfi(sf, ijk, s)
    end if
    xt = x0n + d
  end function global_node_target

  !> The number of nodes of face f.
  pure integer function face_count(sf, f)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: f
    integer :: b, c
    call face_dirs(f, b, c)
    face_count = (sf%n(b) + 1)*(sf%n(c) + 1)
  end function face_count

  !> Face f's two directions b < c.
  pure subroutine face_dirs(f, b, c)
    integer, intent(in) :: f
    integer, intent(out) :: b, c
    b = merge(2, 1, face_axis(f) == 1)
    c = merge(2, 3, face_axis(f) == 3)
  end subroutine face_dirs

  !> Whether the node at whole-grid index ijk lies on face f.
  pure logical function on_face(sf, f, ijk)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: f, ijk(3)
    on_face = ijk(face_axis(f)) == merge(sf%n(face_axis(f)), 0, mod(f, 2) == 0)
  end function on_face

  !> The first face that the node at ijk (on the grid's surface) lies on:
  !> the one whose copy of it every reader takes.
  pure integer function canonical(sf, ijk)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: ijk(3)
    do canonical = 1, 6
      if (on_face(sf, canonical, ijk)) return
    end do
    canonical = 0
  end function canonical

  !> The index among face f's nodes of the node at ijk (on that face).
  pure integer function face_node(sf, f, ijk)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: f, ijk(3)
    integer :: b, c
    call face_dirs(f, b, c)
    face_node = 1 + ijk(b) + (sf%n(b) + 1)*ijk(c)
  end function face_node

  !> The whole-grid index of face f's node p.
  pure function face_ijk(sf, f, p) result(ijk)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: f, p
    integer :: ijk(3), b, c
    call face_dirs(f, b, c)
    ijk(face_axis(f)) = merge(sf%n(face_axis(f)), 0, mod(f, 2) == 0)
    ijk(b) = mod(p - 1, sf%n(b) + 1)
    ijk(c) = (p - 1)/(sf%n(b) + 1)
  end function face_ijk

  !> Face f's line parameter in direction m (one of its own) at its node p.
  pure real(wp) function face_s(sf, f, p, m)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: f, p, m
    integer :: b, c
    call face_dirs(f, b, c)
    face_s = sf%f(f)%s(merge(1, 2, m == b), p)
  end function face_s

  !> D at the surface node ijk.
  pure function surface_d(sf, ijk) result(d)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: ijk(3)
    real(wp) :: d(3)
    integer :: f
    f = canonical(sf, ijk)
    d = sf%f(f)%d(:, face_node(sf, f, ijk))
  end function surface_d

  !> The index ijk except ijk(a) = val.
  pure function along(ijk, a, val) result(q)
    integer, intent(in) :: ijk(3), a, val
    integer :: q(3)
    q = ijk
    q(a) = val
  end function along

  !> The index ijk except ijk(a) = va and ijk(b) = vb.
  pure function along2(ijk, a, va, b, vb) result(q)
    integer, intent(in) :: ijk(3), a, va, b, vb
    integer :: q(3)
    q = ijk
    q(a) = va
    q(b) = vb
  end function along2

  !> 2D TFI at face f's node p (index ijk, one index at a bound) from the
  !> face's four edges.
  pure function face_tfi(sf, f, p, ijk) result(d)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: f, p, ijk(3)
    real(wp) :: d(3)
    integer :: a, b, m
    real(wp) :: u, w
    associate (nmax => sf%n)
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
      u = face_s(sf, f, p, a)
      w = face_s(sf, f, p, b)
      d = (1.0_wp - u)*surface_d(sf, along(ijk, a, 0)) + u*surface_d(sf, along(ijk, a, nmax(a))) &
          + (1.0_wp - w)*surface_d(sf, along(ijk, b, 0)) + w*surface_d(sf, along(ijk, b, nmax(b))) &
          - ((1.0_wp - u)*((1.0_wp - w)*surface_d(sf, along2(ijk, a, 0, b, 0)) &
                           + w*surface_d(sf, along2(ijk, a, 0, b, nmax(b)))) &
             + u*((1.0_wp - w)*surface_d(sf, along2(ijk, a, nmax(a), b, 0)) &
                  + w*surface_d(sf, along2(ijk, a, nmax(a), b, nmax(b)))))
    end associate
  end function face_tfi

  !> 3D TFI at the interior node ijk with line parameters s(3): faces -
  !> edges + corners.
  pure function interior_tfi(sf, ijk, s) result(d)
    type(global_surface_t), intent(in) :: sf
    integer, intent(in) :: ijk(3)
    real(wp), intent(in) :: s(3)
    real(wp) :: d(3)
    real(wp) :: u, v, w, p(3), e(3), cc(3)
    integer :: i0, i1, j0, j1, k0, k1
    u = s(1)
    v = s(2)
    w = s(3)
    i0 = 0; i1 = sf%n(1); j0 = 0; j1 = sf%n(2); k0 = 0; k1 = sf%n(3)
    associate (i => ijk(1), j => ijk(2), k => ijk(3))
      p = (1.0_wp - u)*dd(i0, j, k) + u*dd(i1, j, k) &
          + (1.0_wp - v)*dd(i, j0, k) + v*dd(i, j1, k) &
          + (1.0_wp - w)*dd(i, j, k0) + w*dd(i, j, k1)
      e = (1.0_wp - u)*((1.0_wp - v)*dd(i0, j0, k) + v*dd(i0, j1, k)) &
          + u*((1.0_wp - v)*dd(i1, j0, k) + v*dd(i1, j1, k)) &
          + (1.0_wp - u)*((1.0_wp - w)*dd(i0, j, k0) + w*dd(i0, j, k1)) &
          + u*((1.0_wp - w)*dd(i1, j, k0) + w*dd(i1, j, k1)) &
          + (1.0_wp - v)*((1.0_wp - w)*dd(i, j0, k0) + w*dd(i, j0, k1)) &
          + v*((1.0_wp - w)*dd(i, j1, k0) + w*dd(i, j1, k1))
      cc = (1.0_wp - u)*((1.0_wp - v)*((1.0_wp - w)*dd(i0, j0, k0) + w*dd(i0, j0, k1)) &
                         + v*((1.0_wp - w)*dd(i0, j1, k0) + w*dd(i0, j1, k1))) &
           + u*((1.0_wp - v)*((1.0_wp - w)*dd(i1, j0, k0) + w*dd(i1, j0, k1)) &
                + v*((1.0_wp - w)*dd(i1, j1, k0) + w*dd(i1, j1, k1)))
    end associate
    d = p - e + cc
  contains
    pure function dd(ii, jj, kk)
      integer, intent(in) :: ii, jj, kk
      real(wp) :: dd(3)
      dd = surface_d(sf, [ii, jj, kk])
    end function dd
  end function interior_tfi

  !> The running arc length of x0 along the index lines of direction a
  !> through the block ix's owned nodes (0 .. n(a)), from start(line) at
  !> its node 0 (a line's number: its node's p + (n(b)+1) q over the other
  !> two directions b < c, from 0), into s(a, :); finish(line): at node
  !> n(a). Added one node after the other, as `line_parameters` does along
  !> the whole line: a block that starts from the one below's finish sums
  !> bit for bit as the whole grid does.
  subroutine global_line_sums(ix, a, x0, start, s, finish)
    type(grid_index_t), intent(in) :: ix
    integer, intent(in) :: a
    real(wp), intent(in) :: x0(:, :), start(:)
    real(wp), intent(inout) :: s(:, :)
    real(wp), intent(out) :: finish(:)
    integer :: n(3), b, c, p, q, m, ijk(3), nn, nprev
    n = [ix%ni, ix%nj, ix%nk]
    b = merge(2, 1, a == 1)
    c = merge(2, 3, a == 3)
    do q = 0, n(c)
      do p = 0, n(b)
        ijk(b) = p
        ijk(c) = q
        ijk(a) = 0
        nn = ix%node(ijk(1), ijk(2), ijk(3))
        s(a, nn) = start(1 + p + (n(b) + 1)*q)
        do m = 1, n(a)
          nprev = nn
          ijk(a) = m
          nn = ix%node(ijk(1), ijk(2), ijk(3))
          s(a, nn) = s(a, nprev) + norm2(x0(:, nn) - x0(:, nprev))
        end do
        finish(1 + p + (n(b) + 1)*q) = s(a, nn)
      end do
    end do
  end subroutine global_line_sums

  !> The line parameters of direction a at the block ix's owned nodes from
  !> their running arc lengths s(a, :) (`global_line_sums`) and the lines'
  !> totals (same numbering), as `line_parameters` normalises them: the
  !> block's node 0 is the whole grid's off(a), the grid has ntot(a) cells.
  subroutine global_line_scale(ix, a, total, ntot, s)
    type(grid_index_t), intent(in) :: ix
    integer, intent(in) :: a, ntot
    real(wp), intent(in) :: total(:)
    real(wp), intent(inout) :: s(:, :)
    integer :: n(3), b, c, p, q, m, ijk(3), nn
    n = [ix%ni, ix%nj, ix%nk]
    b = merge(2, 1, a == 1)
    c = merge(2, 3, a == 3)
    do q = 0, n(c)
      do p = 0, n(b)
        ijk(b) = p
        ijk(c) = q
        do m = 0, n(a)
          ijk(a) = m
          nn = ix%node(ijk(1), ijk(2), ijk(3))
          if (total(1 + p + (n(b) + 1)*q) > 0.0_wp) then
            s(a, nn) = s(a, nn)/total(1 + p + (n(b) + 1)*q)
          else
            s(a, nn) = real(m + ix%off(a), wp)/real(max(ntot, 1), wp)
          end if
          ! the far end exactly 1
          if (m + ix%off(a) == ntot) s(a, nn) = 1.0_wp
        end do
      end do
    end do
  end subroutine global_line_scale

  !> s(a, n): the normalised arc length of x0 along the index line of
  !> direction a through node n of the block ix (no ghosts, at no offset:
  !> 0 at index 0, 1 at the far side); index fractions on a line of no
  !> length.
  subroutine line_parameters(ix, x0, s)
    type(grid_index_t), intent(in) :: ix
    real(wp), intent(in) :: x0(:, :)
    real(wp), intent(out) :: s(:, :)
    ! (a line's start and total, for the most lines of a direction)
    real(wp) :: start(ix%nnode/(min(ix%ni, ix%nj, ix%nk) + 1)), total(size(start))
    integer :: a, n(3), m
    n = [ix%ni, ix%nj, ix%nk] + 1
    start = 0.0_wp
    do a = 1, 3
      m = product(n)/n(a)
      call global_line_sums(ix, a, x0, start(1:m), s, total(1:m))
      call global_line_scale(ix, a, total(1:m), n(a) - 1, s)
    end do
  end subroutine line_parameters
end module rezone_global
