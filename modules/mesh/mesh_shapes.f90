!> The shapes of a scene (deck: &region and &particles shape) as point
!> predicates: all, box [lo, hi], sphere (center, radius), half_space
!> n.(x - center) >= 0, cylinder (radius about the axis through center,
!> between lo and hi along it); a sphere or cylinder with inner_radius > 0
!> is hollow (a shell: inner_radius <= r <= radius). `shape_inside` says whether a point lies in
!> a shape, `shape_level` gives a 1-Lipschitz level function (<= 0 inside).
!> The volumes of shapes in cells (`geometry_shapes`) and particle seeding
!> (`particles_seed`) both build on these; they live in mesh so that both
!> packages can use them (ARCHITECTURE.md §2: particles come before remap).
module mesh_shapes
  use base_kinds, only: wp
  implicit none
  private
  public :: shape_t, shape_inside, shape_level, shape_kind, shape_inner_radius_problem
  public :: SHAPE_ALL, SHAPE_BOX, SHAPE_SPHERE, SHAPE_HALF_SPACE, SHAPE_CYLINDER

  integer, parameter :: SHAPE_ALL = 1, SHAPE_BOX = 2, SHAPE_SPHERE = 3, SHAPE_HALF_SPACE = 4, SHAPE_CYLINDER = 5

  !> One region's shape (lengths in the deck's units).
  type :: shape_t
    integer :: kind = SHAPE_ALL
    real(wp) :: lo(3) = -huge(1.0_wp), hi(3) = huge(1.0_wp)   !< box; cylinder's extent along its axis
    real(wp) :: center(3) = 0.0_wp, radius = 0.0_wp          !< sphere, cylinder, half-space point
    real(wp) :: inner_radius = 0.0_wp                        !< sphere, cylinder: hollow inside it
    real(wp) :: normal(3) = [1.0_wp, 0.0_wp, 0.0_wp]          !< half-space: inside is normal.(x - center) >= 0
    integer :: axis = 3                                       !< cylinder axis: 1 x, 2 y, 3 z
  end type shape_t

contains

  !> The kind of the shape named name as decks write it ('all', 'box',
  !> 'sphere', 'half_space', 'cylinder'), 0 if none of them.
  pure integer function shape_kind(name)
    character(len=*), intent(in) :: name
    select case (trim(name))
    case ('all')
      shape_kind = SHAPE_ALL
    case ('box')
      shape_kind = SHAPE_BOX
    case ('sphere')
      shape_kind = SHAPE_SPHERE
    case ('half_space')
      shape_kind = SHAPE_HALF_SPACE
    case ('cylinder')
      shape_kind = SHAPE_CYLINDER
    case default
      shape_kind = 0
    end select
  end function shape_kind

  !> True if the point p (length) lies in the shape (boundary included).
  pure logical function shape_inside(sh, p)
    type(shape_t), intent(in) :: sh
    real(wp), intent(in) :: p(3)
    real(wp) :: d(3)
    select case (sh%kind)
    case (SHAPE_ALL)
      shape_inside = .true.
    case (SHAPE_BOX)
      shape_inside = all(p >= sh%lo) .and. all(p <= sh%hi)
    case (SHAPE_SPHERE)
      shape_inside = sum((p - sh%center)**2) <= sh%radius**2 .and. sum((p - sh%center)**2) >= sh%inner_radius**2
    case (SHAPE_HALF_SPACE)
      shape_inside = dot_product(p - sh%center, sh%normal) >= 0.0_wp
    case (SHAPE_CYLINDER)
      d = p - sh%center
      d(sh%axis) = 0.0_wp
      shape_inside = sum(d**2) <= sh%radius**2 .and. sum(d**2) >= sh%inner_radius**2 .and. &
                     p(sh%axis) >= sh%lo(sh%axis) .and. p(sh%axis) <= sh%hi(sh%axis)
    case default
      shape_inside = .false.
    end select
  end function shape_inside

  !> The shape's level function at p (length): <= 0 inside, and
  !> |phi(p) - phi(q)| <= |p - q| (the distance to the surface, or a lower
  !> bound of it outside a box's or a cylinder's edges).
  pure real(wp) function shape_level(sh, p) result(phi)
    type(shape_t), intent(in) :: sh
    real(wp), intent(in) :: p(3)
    real(wp) :: d(3)
    integer :: a
    select case (sh%kind)
    case (SHAPE_ALL)
      phi = -huge(1.0_wp)
    case (SHAPE_BOX)
      phi = maxval(max(sh%lo - p, p - sh%hi))
    case (SHAPE_SPHERE)
      phi = sqrt(sum((p - sh%center)**2))
      phi = max(phi - sh%radius, sh%inner_radius - phi)
    case (SHAPE_HALF_SPACE)
      phi = -dot_product(p - sh%center, sh%normal)/norm2(sh%normal)
    case (SHAPE_CYLINDER)
      a = sh%axis
      d = p - sh%center
      d(a) = 0.0_wp
      phi = sqrt(sum(d**2))
      phi = max(phi - sh%radius, sh%inner_radius - phi, sh%lo(a) - p(a), p(a) - sh%hi(a))
    case default
      phi = huge(1.0_wp)
    end select
  end function shape_level

  !> What is wrong with a deck's inner_radius for the shape `name` of
  !> radius `radius` ('' if nothing): only a sphere or a cylinder is hollow,
  !> and 0 <= inner_radius < radius.
  pure function shape_inner_radius_problem(name, radius, inner_radius) result(msg)
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: radius, inner_radius
    character(len=64) :: msg
    msg = ''
    if (abs(inner_radius) > 0.0_wp .and. trim(name) /= 'sphere' .and. trim(name) /= 'cylinder') then
      msg = 'applies only to shape = ''sphere'' or ''cylinder'''
    else if (abs(inner_radius) > 0.0_wp .and. .not. (inner_radius > 0.0_wp .and. inner_radius < radius)) then
      msg = 'must be in [0, radius)'
    end if
  end function shape_inner_radius_problem
end module mesh_shapes
