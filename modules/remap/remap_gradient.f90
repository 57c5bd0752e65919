!> Limited least-squares gradients of cell fields on a structured block, the
!> second-order part of the conservative remap (Sect. 5.4).
!>
!> The remap of Sect. 5.4 (Eqs. 54-57) integrates each old cell's field over
!> its intersection fragments with the new cells. The paper does not spell out
!> the reconstruction; we use the linear one q(x) = q_c + g.(x - pos_c) about
!> the point pos_c the mean q_c refers to (cell centroid, or a material's
!> centroid in a mixed cell), which integrates back to q_c over the cell when
!> pos_c is the centroid, so the remap stays conservative whatever g is.
!>
!> Gradient: weighted least squares over the up-to-26 cells of the 3x3x3
!> index neighbourhood that hold the quantity (`has`), minimising
!>   sum_n w_n (q_n - q_c - g.(pos_n - pos_c))^2,  w_n = 1/|pos_n - pos_c|^2,
!> so near neighbours count more and every row of the scaled system is a
!> unit direction (well scaled whatever the cell size). It reproduces a
!> linear field exactly on any grid. The geometry matrix is shared by all
!> fields (one LAPACK call, nrhs = nf). It is solved by SVD (`dgelss`) with a
!> relative singular-value cut: when the neighbours span fewer than three
!> directions (a 1-cell-thick grid, a lone cell, a thin material layer) the
!> minimum-norm solution gives zero gradient along the missing directions
!> instead of a NaN or a noise-driven slope. Where the neighbours span all
!> three directions well (nearly every cell) the 3 x 3 normal equations give
!> the same solution far more cheaply and are solved instead.
!>
!> Limiter (Barth-Jespersen), per field: g is scaled by the largest phi in
!> [0, 1] that keeps the reconstruction at the cell's 8 nodes within the
!> range [qmin, qmax] of q over the cell and its used neighbours. A linear
!> function's extremes over the cell (inside the convex hull of its nodes)
!> are at the nodes, so the remapped values stay inside the old neighbours'
!> bounds: no new extrema, no negative densities or energies from the
!> second-order term. Linear fields keep phi = 1 wherever the cell's nodes
!> lie within the hull of its neighbours' centroids (interior cells).
module remap_gradient
  use base_kinds, only: wp, tiny_wp
  use base_errors, only: error_no_memory, error_t, error_set
  use mesh_grid, only: block_gather, grid_index_t, grid_index
  use base_lapack, only: dgelss
  implicit none
  private
  public :: remap_limited_gradients

  !> Most neighbours a cell can have (its 3x3x3 index neighbourhood).
  integer, parameter :: max_nbr = 26
  !> Singular values below rcond times the largest are dropped: the rows are
  !> unit directions, so this cuts directions the neighbours do not span
  !> (their offsets there are round-off of the centroids, ~1e-16).
  real(wp), parameter :: rcond = 1.0e-10_wp
  !> The normal equations are solved directly (`normal_solve`) when their
  !> smallest eigenvalue is above this times their trace (condition below
  !> about 1/cond_min: round-off 1e-12 of the gradient at worst), by SVD
  !> otherwise.
  real(wp), parameter :: cond_min = 1.0e-4_wp
  !> Node deviations below this fraction of the field's magnitude are
  !> round-off and do not constrain the limiter (and never divide).
  real(wp), parameter :: dq_floor = 1.0e-15_wp

contains

  !> Limited least-squares gradients of nf cell fields on a block of
  !> ni x nj x nk cells (cells numbered by `grid_index_t` of `mesh_grid`).
  !>
  !> x(3, (ni+1)*(nj+1)*(nk+1)): node positions (numbering of `mesh_grid`).
  !> q(nf, ncell): mean of each field over the cell (or a material's part of
  !> it), any units. pos(3, ncell): the point q refers to (cell or material
  !> centroid), units of x. has(ncell): the cell holds the quantity; cells
  !> without it are never read (q and pos there may be anything) and get a
  !> zero gradient. need(ncell): gradient wanted here; other cells are left as they were.
  !> cells (optional): the cells to look at, in any order (only those with
  !> need are computed; absent: every cell of the block). A caller that
  !> knows the few cells it needs pays for those, not for the block.
  !> grad(3, nf, ncell): the limited gradients, units of q per unit of x.
  !> err (optional): set when the array sizes disagree (nothing is computed
  !> and grad is left undefined), the work arrays cannot be allocated (grad
  !> all zero), or the SVD fails to converge in some cell (those cells get a
  !> zero gradient, i.e. a first-order remap; the others are valid). So a
  !> caller with consistent sizes that omits err still gets a usable, at
  !> worst locally first-order, result.
  subroutine remap_limited_gradients(ni, nj, nk, x, q, pos, has, need, grad, err, cells)
    integer, intent(in) :: ni, nj, nk
    real(wp), intent(in) :: x(:, :), q(:, :), pos(:, :)
    logical, intent(in) :: has(:), need(:)
    real(wp), intent(inout) :: grad(:, :, :)
    type(error_t), allocatable, intent(inout), optional :: err
    integer, intent(in), optional :: cells(:)
    integer, allocatable :: list(:)
    integer :: nf, ncell, nnode, lwork, m, rank, info, stat, nfail, i
    integer :: c, ci, cj, ck, oi, oj, ok_, co, f, a, n, nbr(max_nbr), off(max_nbr), cand(max_nbr), ncand, jc
    type(grid_index_t) :: ix
    real(wp) :: amat(max_nbr, 3), at(3, max_nbr), sv(3), dx(3), d2, rinv, dxn(3, 8), xn(3, 8), g(3), &
                qc, qmin, qmax, qn, dq, eps, phi, w(max_nbr), wx(3), ata(3, 3), pc(3)
    real(wp), allocatable :: bmat(:, :), atb(:, :), work(:), qlo(:), qhi(:)
    character(len=200) :: msg

    nf = size(q, 1)
    ncell = ni*nj*nk
    nnode = (ni + 1)*(nj + 1)*(nk + 1)
    if (ni < 1 .or. nj < 1 .or. nk < 1 .or. size(x, 1) /= 3 .or. size(x, 2) /= nnode .or. &
        size(q, 2) /= ncell .or. size(pos, 1) /= 3 .or. size(pos, 2) /= ncell .or. &
        size(has) /= ncell .or. size(need) /= ncell .or. size(grad, 1) /= 3 .or. &
        size(grad, 2) /= nf .or. size(grad, 3) /= ncell) then
      write(msg, '(a,3(i0,1x),a)') 'array sizes do not match a block of ', ni, nj, nk, 'cells'
      call report(trim(msg))
      return
    end if
    if (nf == 0) return

    ! Work arrays once per call; the parallel loop gives each thread its own
    ! copy. The SVD's (work, lwork: the largest optimal size over all
    ! neighbour counts) only in a thread that meets a cell the normal
    ! equations do not solve (`svd_lwork`): most calls never do.
    allocate(bmat(max_nbr, nf), atb(3, nf), qlo(nf), qhi(nf), stat=stat, errmsg=msg)
    if (stat /= 0) then
      grad = 0.0_wp
      call report(error_no_memory('work arrays'))
      return
    end if
    amat = 0.0_wp
    bmat = 0.0_wp
    lwork = 0

    ix = grid_index(ni, nj, nk)
    if (present(cells)) then
      list = cells
    else
      allocate(list(ncell), stat=stat, errmsg=msg)
      if (stat /= 0) then
        grad = 0.0_wp
        call report(error_no_memory('work arrays'))
        return
      end if
      do c = 1, ncell
        list(c) = c
      end do
    end if
    ! the 26 neighbours' offsets, in the order of the loops over k, j, i
    n = 0
    do ok_ = -1, 1
      do oj = -1, 1
        do oi = -1, 1
          if (oi == 0 .and. oj == 0 .and. ok_ == 0) cycle
          n = n + 1
          off(n) = oi + ix%cx*oj + ix%cxy*ok_
        end do
      end do
    end do
    nfail = 0
    !$omp parallel do default(none) shared(ni, nj, nk, ix, nf, x, q, pos, has, need, grad, list, off) &
    !$omp private(i, c, ci, cj, ck, oi, oj, ok_, co, f, a, n, nbr, m, rank, info, amat, at, sv, dx, d2, rinv, &
    !$omp         cand, ncand, jc, &
    !$omp         dxn, xn, g, pc, qc, qmin, qmax, qn, dq, eps, phi, bmat, work, w, wx, ata, atb, qlo, qhi, stat) &
    !$omp firstprivate(lwork) reduction(+:nfail) schedule(static)
    do i = 1, size(list)
      c = list(i)
      if (.not. need(c)) cycle
      call ix%cell_ijk(c, ci, cj, ck)
      ! (a zero gradient where none is found: every other way sets all of it)
      if (.not. has(c)) then
        grad(:, :, c) = 0.0_wp
        cycle
      end if

      ! the rows (offsets and differences, unweighted) and the weighted
      ! normal equations A^T W A, A^T W b summed with them (w_n = 1/d2: no
      ! square root unless the SVD decides; the neighbour c + offset by the
      ! block's strides, no index call in the innermost loop); the offsets
      ! as the columns of at, contiguous for the sums (the SVD's rows amat
      ! made from them where it is needed)
      ! (the candidates in the loops' order, k then j then i: away from
      ! the block's faces all 26, by their offsets; else those within it)
      if (ci > ix%clo(1) .and. ci < ix%chi(1) .and. cj > ix%clo(2) .and. cj < ix%chi(2) .and. &
          ck > ix%clo(3) .and. ck < ix%chi(3)) then
        ncand = max_nbr
        cand = c + off
      else
        ncand = 0
        do ok_ = max(ix%clo(3), ck - 1), min(ix%chi(3), ck + 1)
          do oj = max(ix%clo(2), cj - 1), min(ix%chi(2), cj + 1)
            do oi = max(ix%clo(1), ci - 1), min(ix%chi(1), ci + 1)
              co = c + (oi - ci) + ix%cx*(oj - cj) + ix%cxy*(ok_ - ck)
              if (co == c) cycle
              ncand = ncand + 1
              cand(ncand) = co
            end do
          end do
        end do
      end if
      m = 0
      ata = 0.0_wp
      ! (the cell's point once, not reloaded through the descriptor per
      ! candidate)
      pc = pos(:, c)
      do jc = 1, ncand
        co = cand(jc)
        if (.not. has(co)) cycle
        dx = pos(:, co) - pc
        d2 = dx(1)**2 + dx(2)**2 + dx(3)**2
        if (.not. (d2 > tiny_wp)) cycle   ! coincident points carry no slope
        m = m + 1
        nbr(m) = co
        w(m) = 1.0_wp/d2
        at(:, m) = dx
        wx = w(m)*dx
        ata(1, 1) = ata(1, 1) + wx(1)*dx(1)
        ata(2, 1) = ata(2, 1) + wx(2)*dx(1)
        ata(3, 1) = ata(3, 1) + wx(3)*dx(1)
        ata(2, 2) = ata(2, 2) + wx(2)*dx(2)
        ata(3, 2) = ata(3, 2) + wx(3)*dx(2)
        ata(3, 3) = ata(3, 3) + wx(3)*dx(3)
      end do
      if (m == 0) then
        grad(:, :, c) = 0.0_wp
        cycle
      end if
      ! (with the neighbours' range of each field, for the limiter below)
      do f = 1, nf
        qc = q(f, c)
        qmin = qc
        qmax = qc
        wx = 0.0_wp
        do n = 1, m
          qn = q(f, nbr(n))
          qmin = min(qmin, qn)
          qmax = max(qmax, qn)
          bmat(n, f) = qn - qc
          wx = wx + (w(n)*bmat(n, f))*at(:, n)
        end do
        atb(:, f) = wx
        qlo(f) = qmin
        qhi(f) = qmax
      end do

      if (.not. normal_solve(nf, ata, atb, bmat)) then
        ! weighted rows: sqrt(w_n) = 1/|pos_n - pos_c|
        do n = 1, m
          rinv = sqrt(w(n))
          amat(n, :) = at(:, n)*rinv
          bmat(n, 1:nf) = bmat(n, 1:nf)*rinv
        end do
        if (lwork == 0) then
          lwork = svd_lwork(nf)
          allocate(work(lwork), stat=stat)
          if (stat /= 0) lwork = 0
        end if
        info = 1
        if (lwork > 0) call dgelss(m, 3, nf, amat, max_nbr, bmat, max_nbr, sv, rcond, rank, work, lwork, info)
        if (info /= 0) then
          nfail = nfail + 1
          grad(:, :, c) = 0.0_wp
          cycle
        end if
      end if

      ! Barth-Jespersen: keep the reconstruction at the 8 nodes in range
      call block_gather(ni, nj, ci, cj, ck, x, xn)
      do a = 1, 8
        dxn(:, a) = xn(:, a) - pc
      end do
      do f = 1, nf
        g = bmat(1:3, f)
        qc = q(f, c)
        qmin = qlo(f)
        qmax = qhi(f)
        ! qmax - qc and qc - qmin are at most 2*max(|qmin|,|qmax|), so with
        ! |dq| > eps the ratios stay below 2/dq_floor: no overflow
        eps = dq_floor*max(abs(qmin), abs(qmax))
        phi = 1.0_wp
        do a = 1, 8
          dq = g(1)*dxn(1, a) + g(2)*dxn(2, a) + g(3)*dxn(3, a)
          if (dq > eps) then
            phi = min(phi, (qmax - qc)/dq)
          else if (dq < -eps) then
            phi = min(phi, (qmin - qc)/dq)
          end if
        end do
        grad(:, f, c) = phi*g
      end do
    end do
    !$omp end parallel do

    if (nfail > 0) then
      write(msg, '(a,i0,a)') 'the SVD did not converge in ', nfail, ' cell(s); their gradients are zero'
      call report(trim(msg))
    end if

  contains

    !> The SVD's work size for nf fields (`dgelss`' own query): the largest
    !> optimal size over all neighbour counts.
    integer function svd_lwork(nf) result(lw)
      integer, intent(in) :: nf
      real(wp) :: aq(max_nbr, 3), bq(max_nbr, nf), sq(3), wq1(1)
      integer :: mq, rq, iq
      aq = 0.0_wp
      bq = 0.0_wp
      lw = 1
      do mq = 1, max_nbr
        call dgelss(mq, 3, nf, aq, max_nbr, bq, max_nbr, sq, rcond, rq, wq1, -1, iq)
        lw = max(lw, int(wq1(1)), 3*min(mq, 3) + max(2*min(mq, 3), mq, nf))
      end do
    end function svd_lwork

    !> The least-squares gradient from the weighted normal equations
    !> ata (lower triangle) and atb(:, 1:nf) into bmat(1:3, :) (3 x 3, by
    !> their adjugate), where they are well conditioned: their smallest
    !> eigenvalue above cond_min times the trace (the weighted rows are unit
    !> vectors, so the trace is the number of rows), i.e. the neighbours span
    !> all three directions well; then the solution is the SVD's, to
    !> round-off times at most 1/cond_min, at a small part of its cost.
    !> False (bmat untouched) otherwise: the SVD decides.
    !> (the arrays passed: the loop's private copies, which host
    !> association would not see)
    logical function normal_solve(nf, ata, atb, bmat) result(done)
      integer, intent(in) :: nf
      real(wp), intent(inout) :: ata(3, 3)
      real(wp), intent(in) :: atb(:, :)
      real(wp), intent(inout) :: bmat(:, :)
      real(wp) :: adj(3, 3), det, tr
      integer :: ff
      ata(1, 2) = ata(2, 1)
      ata(1, 3) = ata(3, 1)
      ata(2, 3) = ata(3, 2)
      adj(1, 1) = ata(2, 2)*ata(3, 3) - ata(2, 3)*ata(3, 2)
      adj(1, 2) = ata(1, 3)*ata(3, 2) - ata(1, 2)*ata(3, 3)
      adj(1, 3) = ata(1, 2)*ata(2, 3) - ata(1, 3)*ata(2, 2)
      adj(2, 2) = ata(1, 1)*ata(3, 3) - ata(1, 3)*ata(3, 1)
      adj(2, 3) = ata(1, 3)*ata(2, 1) - ata(1, 1)*ata(2, 3)
      adj(3, 3) = ata(1, 1)*ata(2, 2) - ata(1, 2)*ata(2, 1)
      adj(2, 1) = adj(1, 2)
      adj(3, 1) = adj(1, 3)
      adj(3, 2) = adj(2, 3)
      det = ata(1, 1)*adj(1, 1) + ata(1, 2)*adj(2, 1) + ata(1, 3)*adj(3, 1)
      tr = ata(1, 1) + ata(2, 2) + ata(3, 3)
      ! det <= lmax^2 lmin <= tr^2 lmin: det > cond_min tr^3 gives lmin > cond_min tr
      done = det > cond_min*tr**3
      if (.not. done) return
      do ff = 1, nf
        bmat(1:3, ff) = matmul(adj, atb(:, ff))/det
      end do
    end function normal_solve

    !> Sets err, when the caller passed one.
    subroutine report(what)
      character(len=*), intent(in) :: what
      if (present(err)) call error_set(err, 'remap_limited_gradients', what)
    end subroutine report
  end subroutine remap_limited_gradients
end module remap_gradient
