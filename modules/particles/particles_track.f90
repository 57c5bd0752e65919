!> Tracked particles (issue 14): which particles a deck's track points name,
!> where each of them is in the (re-sorted) arrays, and the values a
!> particle-history row reports for one of them.
!>
!> A track point names the particle nearest to it in the seeded state (t = 0),
!> by its seeding id `id`, which follows the particle through every sort
!> (`particles_order`, and the re-location of an Euler phase). Ties go to the
!> smallest id, so the choice depends only on the seeding, never on the
!> array order or the thread count; a restart, which seeds the same
!> particles before it reads the dump, names the same ones.
!>
!> At write time the index of an id is found through the inverse of the id
!> permutation (`particles_index_of_ids`, O(np) once per row for all tracked
!> particles together), not by a search per tracked particle.
module particles_track
  use base_kinds, only: wp
  use particles_state, only: particles_t
  use base_sort, only: sort_order
  implicit none
  private
  public :: particles_nearest_ids, particles_index_of_ids, particles_track_values, track_nfield, &
            track_field_names

  !> Values per tracked particle in a row (after its id), without the
  !> plastic strain; with history variables the plastic strain (hist(1)) is
  !> one more.
  integer, parameter :: track_nfield = 15
  !> Their column names (a tracked particle's columns end in _<track number>);
  !> the 16th, plastic_strain, only when the particles have history.
  character(len=*), parameter :: track_field_names(track_nfield + 1) = [character(len=14) :: &
    'x', 'y', 'z', 'velocity_x', 'velocity_y', 'velocity_z', 'stress_xx', 'stress_yy', 'stress_zz', &
    'stress_yz', 'stress_xz', 'stress_xy', 'pressure', 'von_mises', 'energy', 'plastic_strain']

contains

  !> ids(k): the id of the particle nearest to points(:, k) (length), ties to
  !> the smallest id; 0 when there are no particles. O(np x npoint), once.
  pure subroutine particles_nearest_ids(p, points, ids)
    type(particles_t), intent(in) :: p
    real(wp), intent(in) :: points(:, :)
    integer, intent(out) :: ids(:)
    integer :: k, q
    real(wp) :: d, dbest
    do k = 1, size(points, 2)
      ids(k) = 0
      dbest = huge(1.0_wp)
      do q = 1, p%np
        d = sum((p%x(:, q) - points(:, k))**2)
        if (d < dbest .or. (.not. d > dbest .and. p%id(q) < ids(k))) then   ! (a tie: the smaller id)
          dbest = d
          ids(k) = p%id(q)
        end if
      end do
    end do
  end subroutine particles_nearest_ids

  !> idx(k): the array index of the particle with id ids(k) (each
  !> particle's id searched among the few tracked ones: no array over all
  !> ids). An id that is not among p's particles (gone, or held by another
  !> block of a decomposed run) gives 0.
  pure subroutine particles_index_of_ids(p, ids, idx)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: ids(:)
    integer, intent(out) :: idx(:)
    integer :: order(size(ids)), q, lo, hi, mid, stat
    idx = 0
    if (size(ids) == 0) return
    ! (the ids in increasing order: each particle's id searched among them,
    ! every tracked point that names it given its index)
    call sort_order(ids, order, stat)
    if (stat /= 0) then   ! (no room to sort: one pass per id)
      do lo = 1, size(ids)
        idx(lo) = findloc(p%id(:p%np), ids(lo), 1)
      end do
      return
    end if
    do q = 1, p%np
      lo = 1
      hi = size(ids)
      do while (lo < hi)
        mid = (lo + hi)/2
        if (ids(order(mid)) < p%id(q)) then
          lo = mid + 1
        else
          hi = mid
        end if
      end do
      do while (lo <= size(ids))
        if (ids(order(lo)) /= p%id(q)) exit
        idx(order(lo)) = q
        lo = lo + 1
      end do
    end do
  end subroutine particles_index_of_ids

  !> The row values of particle q, in the order of `track_field_names`:
  !> position (length), velocity (length/time), Cauchy stress in Voigt order
  !> xx, yy, zz, yz, xz, xy (tension positive), pressure -trace/3 and von
  !> Mises stress sqrt(3/2 s:s) (stress units), specific internal energy e
  !> and, when the particles have history (nhist > 0), the plastic strain
  !> hist(1) as vals(track_nfield + 1).
  pure subroutine particles_track_values(p, q, vals)
    type(particles_t), intent(in) :: p
    integer, intent(in) :: q
    real(wp), intent(out) :: vals(:)
    real(wp) :: s(6), pr
    s = p%stress(:, q)
    pr = -(s(1) + s(2) + s(3))/3.0_wp
    vals(1:3) = p%x(:, q)
    vals(4:6) = p%v(:, q)
    vals(7:12) = s
    vals(13) = pr
    ! deviator s + p I; the shear components count twice in s:s
    vals(14) = sqrt(1.5_wp*((s(1) + pr)**2 + (s(2) + pr)**2 + (s(3) + pr)**2 + &
                            2.0_wp*(s(4)**2 + s(5)**2 + s(6)**2)))
    vals(15) = p%e(q)
    if (size(vals) > track_nfield .and. p%nhist > 0) vals(track_nfield + 1) = p%hist(1, q)
  end subroutine particles_track_values
end module particles_track
