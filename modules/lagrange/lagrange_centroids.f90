!> Material centroids of the mixed cells kept consistent with their volume
!> fractions through the Lagrangian phase, so that the MoF reconstruction of
!> the next remap (Sect. 5.4, Fig. 12) is given a reference it can match.
!>
!> What moves a material's centroid in a Lagrangian step. Its volume change
!> is dV_m = f_m dV + theta d_m (Tipton closure, `material_mixed`): the part
!> f_m dV follows the grid, and a material region carried by the cell's
!> trilinear map keeps its natural coordinates (exactly so for an affine
!> motion); the exchange theta d_m (sum zero) moves the interface against
!> the grid: one material grows into the space another gives up. Keeping xi
!> fixed (the state before this module) accounts for the first part only, so
!> the stored centroid drifts away from the volume fraction: for a sliver,
!> whose centroid the remap's MoF infers from the other material's through
!> sum_m V_m c_m = V c_cell, by 1/f_m times that drift (the remaps of the
!> triple point logged centroid errors of 1.4 cell sizes and hit the MoF
!> iteration cap in 70 cells per Euler step).
!>
!> The rule. Each material of a mixed cell is bounded by a plane of the
!> nested dissection the remap uses (slot order, `mof_reconstruct_nested`),
!> kept per slot in natural coordinates (`mixed_t%plane`, the cell's map
!> taken affine about its centre): a plane carried by an affine map stays a
!> plane, with the normal A^-T n_xi (A = dx/dxi), so the plane follows the
!> grid as the centroid does. When the fractions have changed, the planes
!> are moved along their normals until they cut the new volume fractions in
!> the cell as it is now (one volume root each, no search over normals:
!> `mof_nested_cut`), and each material's centroid is that of its region:
!> the interface moves by the closure's exchange and nothing else. Planes
!> are fitted by MoF to the fractions and centroids where they are not known
!> (`centroids_fit_planes`: the mixed cells of the initial scene, whose
!> centroids are exact for the region shapes, and those a remap has just
!> made, whose centroids are those of the remapped material): one fit per
!> cell per remap.
!>
!> When. The moved centroid depends only on the plane, the new fractions and
!> the cell's nodes, not on the steps in between (the plane for the final
!> fraction is the same however the change was split), so `centroids_refresh`
!> computes it where the centroids are read, before a remap and before a
!> restart dump, rather than after every step: the same numbers (to the
!> round-off of the volume roots), one cut per cell per remap instead of per
!> step (done after every step it made the triple point's Lagrangian phase
!> five times as long). The planes, the state that carries the interface,
!> are current at all times; mx%xi is current after a refresh.
!> A refresh leaves the centroids that one plane per material reproduces
!> exactly in the cell the remap is about to cut, whatever the fractions did:
!> MoF given them returns those planes, so the remap cuts the carried planes
!> of the cells it changes itself (`carried_cut`, the refresh's cut: no
!> search), and the refresh before it leaves those cells out.

module lagrange_centroids
  use base_kinds, only: wp
  use base_errors, only: error_t
  use mesh_grid, only: grid_t
  use mesh_geometry, only: hex_trilinear, hex_natural, hex_volume, cross
  use material_mixed, only: mixed_t, mixed_forget_planes
  use geometry_mof, only: mof_reconstruct_nested, mof_nested_cut, mof_max_iter_default
  use base_sort, only: sort_order, sorted_place
  implicit none
  private
  public :: centroid_stats_t, centroids_fit_planes, centroids_refresh, centre_axes, plane_normals, &
            plane_memory_t, centroids_remember, planes_known, carried_cut

  !> Most materials of one mixed cell handled (as in the remap).
  integer, parameter :: max_mat = 16

  !> What the centroid update did (accumulated over the steps it is given to).
  type :: centroid_stats_t
    integer :: fitted = 0             !< cells whose planes were fitted by MoF
    integer :: iterations = 0         !< the fits' Gauss-Newton iterations, all materials
    integer :: capped = 0             !< fits that hit the iteration cap or failed
    real(wp) :: err_max = 0.0_wp      !< largest centroid error of a fit / cell size
    integer :: moved = 0              !< cells whose centroids were refreshed from their planes
    integer :: failed = 0             !< cells not fitted or not refreshed (centroids kept)
  end type centroid_stats_t

  !> The interface planes of the mixed cells as they were before a remap
  !> (`centroids_remember`), cell by cell in increasing cell order: where
  !> the fits after it (`centroids_fit_planes`' memory) start their
  !> searches, a material's plane of the same cell (in natural coordinates:
  !> a global rezone gives back the cells the grid had, a localized one
  !> keeps most): a search that starts on the interface it is asked for
  !> needs one volume root instead of several Gauss-Newton iterations.
  type :: plane_memory_t
    integer :: n = 0
    integer, allocatable :: cell(:)        !< (n) the mixed cells, increasing
    integer, allocatable :: start(:)       !< (n + 1) their first entries
    integer, allocatable :: mat(:)         !< each entry's material
    real(wp), allocatable :: plane(:, :)   !< (4, entries) its plane (mixed_t%plane; n = 0: not known)
  end type plane_memory_t

contains

  !> The physical normals pn(3, :) of the planes n_xi.xi <= d_xi given in
  !> natural coordinates (planes(1:3, :), `mixed_t%plane`) in the cell xn
  !> (nodes a = 1 + i + 2j + 4k), each det A^-T n_xi (A = `centre_axes`:
  !> the columns of det A^-T are the cofactors a2 x a3, a3 x a1, a1 x a2),
  !> and det; a plane not known (n_xi = 0) gives 0.
  pure subroutine plane_normals(xn, planes, pn, det)
    real(wp), intent(in) :: xn(3, 8), planes(:, :)
    real(wp), intent(out) :: pn(:, :), det
    real(wp) :: a(3, 3), c(3, 3)
    integer :: j
    a = centre_axes(xn)
    c(:, 1) = cross(a(:, 2), a(:, 3))
    c(:, 2) = cross(a(:, 3), a(:, 1))
    c(:, 3) = cross(a(:, 1), a(:, 2))
    det = dot_product(a(:, 1), c(:, 1))
    do j = 1, size(planes, 2)
      pn(:, j) = planes(1, j)*c(:, 1) + planes(2, j)*c(:, 2) + planes(3, j)*c(:, 3)
    end do
  end subroutine plane_normals

  !> The planes of mx's mixed cells kept in mem (`plane_memory_t`); none
  !> if mx has no planes stored.
  subroutine centroids_remember(mx, mem)
    type(mixed_t), intent(in) :: mx
    type(plane_memory_t), intent(out) :: mem
    integer, allocatable :: order(:)
    integer :: i, k, s0, s1, m, stat
    logical :: stale
    stale = .not. allocated(mx%plane)
    if (.not. stale) stale = size(mx%plane, 2) /= mx%nslot
    if (mx%n == 0 .or. stale) return
    allocate(order(mx%n), mem%cell(mx%n), mem%start(mx%n + 1), mem%mat(mx%nslot), mem%plane(4, mx%nslot), &
             stat=stat)
    if (stat /= 0) return
    call sort_order(mx%cell(1:mx%n), order, stat)
    if (stat /= 0) return
    m = 0
    mem%start(1) = 1
    do i = 1, mx%n
      k = order(i)
      s0 = mx%start(k)
      s1 = mx%start(k + 1) - 1
      mem%cell(i) = mx%cell(k)
      mem%mat(m + 1:m + s1 - s0 + 1) = mx%mat(s0:s1)
      mem%plane(:, m + 1:m + s1 - s0 + 1) = mx%plane(:, s0:s1)
      m = m + s1 - s0 + 1
      mem%start(i + 1) = m + 1
    end do
    mem%n = mx%n
  end subroutine centroids_remember

  !> The cell's axes at its centre, A(:,i) = dx/dxi_i at xi = 0 (length per
  !> unit natural coordinate): a plane n_xi.xi = const of the natural cube
  !> is, through the affine part of the cell's map, the plane with normal
  !> A^-T n_xi, and a physical normal n is n_xi = A^T n.
  pure function centre_axes(xn) result(a)
    real(wp), intent(in) :: xn(3, 8)
    real(wp) :: a(3, 3)
    ! nodes a = 1 + i + 2j + 4k: the mean of the four high nodes minus the
    ! mean of the four low ones, halved (xi runs over [-1, 1])
    a(:, 1) = 0.125_wp*((xn(:, 2) + xn(:, 4) + xn(:, 6) + xn(:, 8)) - (xn(:, 1) + xn(:, 3) + xn(:, 5) + xn(:, 7)))
    a(:, 2) = 0.125_wp*((xn(:, 3) + xn(:, 4) + xn(:, 7) + xn(:, 8)) - (xn(:, 1) + xn(:, 2) + xn(:, 5) + xn(:, 6)))
    a(:, 3) = 0.125_wp*((xn(:, 5) + xn(:, 6) + xn(:, 7) + xn(:, 8)) - (xn(:, 1) + xn(:, 2) + xn(:, 3) + xn(:, 4)))
  end function centre_axes

  !> Fits the interface planes (mx%plane) of every mixed cell whose planes
  !> are not known, by nested MoF (`mof_reconstruct_nested`, at most max_iter
  !> iterations per material, default mof_max_iter_default) to its volume
  !> fractions mx%vf and centroids mx%xi in the cell as it is (g%x); the
  !> centroids are left as they are. stats accumulates (fits, iterations,
  !> capped, largest centroid error / cell size); a cell that cannot be fitted
  !> (volume not positive) keeps no planes (counted failed).
  subroutine centroids_fit_planes(g, mx, stats, max_iter, only, memory)
    type(grid_t), intent(in) :: g
    type(mixed_t), intent(inout) :: mx
    type(centroid_stats_t), intent(inout) :: stats
    integer, intent(in), optional :: max_iter
    !> (mx%n) the mixed cells fitted (absent: all)
    logical, intent(in), optional :: only(:)
    !> the planes the cells had (`plane_memory_t`): a material's plane of
    !> the same cell, where there was one, is where its search starts
    type(plane_memory_t), intent(in), optional :: memory
    real(wp) :: xn(3, 8), a(3, 3), vf(max_mat), cref(3, max_mat), pn(3, max_mat), pd(max_mat), &
                errc(max_mat), vol, errmax, m(3), xc(3), sc, guess(4, max_mat), start(3, max_mat), det
    integer :: k, c, s0, s1, nm, j, s, its(max_mat), mi, nfit, nits, ncap, nfail
    logical :: ok, remembered

    if (mx%n == 0) return
    call check_storage(mx, stats)
    mi = mof_max_iter_default
    if (present(max_iter)) mi = max_iter
    nfit = 0; nits = 0; ncap = 0; nfail = 0
    errmax = 0.0_wp
    !$omp parallel do default(none) shared(g, mx, mi, only, memory) &
    !$omp private(k, c, s0, s1, nm, j, s, its, ok, xn, a, vf, cref, pn, pd, errc, vol, m, xc, sc, guess, start, &
    !$omp det, remembered) reduction(+: nfit, nits, ncap, nfail) reduction(max: errmax) schedule(dynamic, 16)
    do k = 1, mx%n
      s0 = mx%start(k)
      s1 = mx%start(k + 1) - 1
      nm = s1 - s0 + 1
      if (nm < 2 .or. nm > max_mat) cycle
      if (planes_known(mx, s0, s1)) cycle
      if (present(only)) then
        if (.not. only(k)) cycle
      end if
      c = mx%cell(k)
      call g%gather(c, g%x, xn)
      vol = hex_volume(xn)
      if (.not. (vol > 0.0_wp .and. sum(mx%vf(s0:s1)) > 0.0_wp)) then
        nfail = nfail + 1
        cycle
      end if
      vf(1:nm) = mx%vf(s0:s1)/sum(mx%vf(s0:s1))
      do j = 1, nm
        cref(:, j) = hex_trilinear(xn, mx%xi(:, s0 + j - 1))
      end do
      remembered = .false.
      if (present(memory)) call recall(memory, c, mx%mat(s0:s1), guess(:, 1:nm), remembered)
      if (remembered) then
        call plane_normals(xn, guess(:, 1:nm), start(:, 1:nm), det)
        if (.not. det > 0.0_wp) start(:, 1:nm) = 0.0_wp
        call mof_reconstruct_nested(xn, vf(1:nm), cref(:, 1:nm), pn(:, 1:nm), pd(1:nm), errc(1:nm), &
                                    its(1:nm), ok, mi, guess=start(:, 1:nm))
      else
        call mof_reconstruct_nested(xn, vf(1:nm), cref(:, 1:nm), pn(:, 1:nm), pd(1:nm), errc(1:nm), &
                                    its(1:nm), ok, mi)
      end if
      nfit = nfit + 1
      nits = nits + sum(its(1:nm))
      if (.not. ok) ncap = ncap + 1
      errmax = max(errmax, maxval(errc(1:nm))/vol**(1.0_wp/3.0_wp))
      ! in natural coordinates, x = xc + A xi: n.x <= d is
      ! (A^T n).xi <= d - n.xc, scaled to a unit normal
      a = centre_axes(xn)
      xc = 0.125_wp*sum(xn, 2)
      do j = 1, nm
        s = s0 + j - 1
        m = matmul(pn(:, j), a)
        sc = norm2(m)
        mx%plane(:, s) = 0.0_wp
        if (sc > 0.0_wp) mx%plane(:, s) = [m/sc, (pd(j) - dot_product(pn(:, j), xc))/sc]
      end do
    end do
    !$omp end parallel do
    stats%fitted = stats%fitted + nfit
    stats%iterations = stats%iterations + nits
    stats%capped = stats%capped + ncap
    stats%err_max = max(stats%err_max, errmax)
    stats%failed = stats%failed + nfail
  end subroutine centroids_fit_planes

  !> The planes mem kept of cell c for the materials mats (in that order),
  !> planes(4, size(mats)); a material the cell did not hold, or held
  !> without a plane, gets 0. found: mem kept a plane of cell c.
  pure subroutine recall(mem, c, mats, planes, found)
    type(plane_memory_t), intent(in) :: mem
    integer, intent(in) :: c, mats(:)
    real(wp), intent(out) :: planes(:, :)
    logical, intent(out) :: found
    integer :: lo, hi, mid, j, e
    planes = 0.0_wp
    found = .false.
    lo = 1
    hi = mem%n
    do while (lo <= hi)
      mid = (lo + hi)/2
      if (mem%cell(mid) == c) then
        do j = 1, size(mats)
          do e = mem%start(mid), mem%start(mid + 1) - 1
            if (mem%mat(e) == mats(j)) planes(:, j) = mem%plane(:, e)
          end do
        end do
        found = any(abs(planes(1:3, :)) > 0.0_wp)
        return
      else if (mem%cell(mid) < c) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end subroutine recall

  !> Sets the centroids mx%xi of every mixed cell with known planes to those
  !> of its materials' regions when its planes, moved along their normals,
  !> cut the volume fractions mx%vf from the cell as it is (g%x) (module
  !> header). The stored planes are not changed (their offsets only start
  !> the volume roots), so a refresh changes nothing but mx%xi. stats
  !> accumulates (cells moved; failed: planes not known, cell volume not
  !> positive or a root that failed, centroids kept).
  subroutine centroids_refresh(g, mx, stats, skip)
    type(grid_t), intent(in) :: g
    type(mixed_t), intent(inout) :: mx
    type(centroid_stats_t), intent(inout) :: stats
    !> cells (increasing) left as they are: those a remap is about to
    !> change, whose centroids it does not read (it cuts their carried
    !> planes itself, `carried_cut`) and replaces; ignored if not sorted
    integer, intent(in), optional :: skip(:)
    real(wp) :: xn(3, 8), vreg(max_mat), cen(3, max_mat)
    integer :: k, c, s0, s1, nm, j, nmove, nfail, q, nskip
    integer, allocatable :: list(:)
    logical :: ok

    if (mx%n == 0) return
    call check_storage(mx, stats)
    ! (the list, where it is sorted; else none)
    nskip = 0
    if (present(skip)) then
      if (all(skip(2:) > skip(:size(skip) - 1))) nskip = size(skip)
    end if
    if (nskip > 0) then
      list = skip
    else
      list = [integer ::]
    end if
    nmove = 0; nfail = 0
    !$omp parallel do default(none) shared(g, mx, list, nskip) &
    !$omp private(k, c, s0, s1, nm, j, ok, xn, vreg, cen, q) &
    !$omp reduction(+: nmove, nfail) schedule(dynamic, 16)
    do k = 1, mx%n
      s0 = mx%start(k)
      s1 = mx%start(k + 1) - 1
      nm = s1 - s0 + 1
      if (nm < 2 .or. nm > max_mat) cycle
      c = mx%cell(k)
      if (nskip > 0) then
        q = sorted_place(list(1:nskip), c)
        if (q <= nskip) then
          if (list(q) == c) cycle
        end if
      end if
      if (.not. planes_known(mx, s0, s1)) then
        nfail = nfail + 1
        cycle
      end if
      call g%gather(c, g%x, xn)
      call carried_cut(xn, mx, s0, s1, vreg(1:nm), cen(:, 1:nm), ok)
      if (.not. ok) then
        nfail = nfail + 1
        cycle
      end if
      nmove = nmove + 1
      do j = 1, nm
        if (vreg(j) > 0.0_wp) mx%xi(:, s0 + j - 1) = hex_natural(xn, cen(:, j))
      end do
    end do
    !$omp end parallel do
    stats%moved = stats%moved + nmove
    stats%failed = stats%failed + nfail
  end subroutine centroids_refresh

  !> The carried planes of one mixed cell (slots s0..s1, planes known:
  !> `planes_known`) in the cell as it is (nodes xn), each moved along its
  !> normal until it cuts its material's current fraction (`mof_nested_cut`,
  !> started from the plane's carried offset): each material's region
  !> volume vreg and centroid cen (length), and, if asked, the planes in
  !> `mof_reconstruct_nested`'s convention (unit normal, offset; (0, 1) for
  !> the material that takes the rest, (0, -1) for an empty one). ok is
  !> false where the cell is inverted, has no fraction or a root failed.
  !> (`centroids_refresh`'s cut, and the remap's for the cells it changes:
  !> the same numbers for the same cell)
  pure subroutine carried_cut(xn, mx, s0, s1, vreg, cen, ok, planes)
    real(wp), intent(in) :: xn(3, 8)
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: s0, s1
    real(wp), intent(out) :: vreg(:), cen(:, :)
    logical, intent(out) :: ok
    real(wp), intent(out), optional :: planes(:, :)
    real(wp) :: vf(max_mat), pn(3, max_mat), pd(max_mat), dg(max_mat), xc(3), det
    integer :: nm, j

    nm = s1 - s0 + 1
    ! the planes in the cell: n_xi.A^-1 (x - xc) <= d_xi, i.e.
    ! pn.x <= det d_xi + pn.xc with pn = det A^-T n_xi (the columns of
    ! det A^-T are the cofactors a2 x a3, a3 x a1, a1 x a2; det A > 0)
    call plane_normals(xn, mx%plane(:, s0:s1), pn(:, 1:nm), det)
    ok = det > 0.0_wp .and. sum(mx%vf(s0:s1)) > 0.0_wp
    if (.not. ok) return
    xc = 0.125_wp*sum(xn, 2)
    do j = 1, nm
      dg(j) = det*mx%plane(4, s0 + j - 1) + dot_product(pn(:, j), xc)
    end do
    vf(1:nm) = mx%vf(s0:s1)/sum(mx%vf(s0:s1))
    call mof_nested_cut(xn, vf(1:nm), pn(:, 1:nm), pd(1:nm), vreg, cen, ok, dg(1:nm), planes)
  end subroutine carried_cut

  !> True if the planes of the slots s0..s1 of one mixed cell are known:
  !> every slot but the last has a normal.
  pure logical function planes_known(mx, s0, s1)
    type(mixed_t), intent(in) :: mx
    integer, intent(in) :: s0, s1
    integer :: s
    planes_known = .true.
    do s = s0, s1 - 1
      if (.not. any(abs(mx%plane(1:3, s)) > 0.0_wp)) planes_known = .false.
    end do
  end function planes_known

  !> Planes stored for other slots (storage not resized with the mixed
  !> cells) are not known: resized and cleared.
  subroutine check_storage(mx, stats)
    type(mixed_t), intent(inout) :: mx
    type(centroid_stats_t), intent(inout) :: stats
    type(error_t), allocatable :: err
    logical :: stale
    stale = .not. allocated(mx%plane)
    if (.not. stale) stale = size(mx%plane, 2) /= mx%nslot
    if (stale) call mixed_forget_planes(mx, err)
    if (allocated(err)) stats%failed = stats%failed + mx%n
  end subroutine check_storage
end module lagrange_centroids
